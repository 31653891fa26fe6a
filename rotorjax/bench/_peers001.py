"""The peers of model 001 (anisotropic supports, N correction weights) that are not
JAX: the closed-form pure-Python right-hand side (the strongest scipy peer: scalar
`math`, the weights' accelerations eliminated by hand so that only the 2x2 system for
xi'', eta'' is solved), a scipy `solve_ivp` loop over speeds, and the largest Floquet
exponent of the main motion by scipy (augmented system, complex-step Jacobian).

Dimensionless equations:

  xi''  + 2 mu_xi  xi'  + xi          - sigma sum_j (phi_j'' sin phi_j + phi_j'^2 cos phi_j) - c n^2 cos(n t) = 0
  eta'' + 2 mu_eta eta' + n_eta^2 eta + sigma sum_j (phi_j'' cos phi_j - phi_j'^2 sin phi_j) - c n^2 sin(n t) = 0
  phi_j'' + mu_w (phi_j' - n) + eps (-xi'' sin phi_j + eta'' cos phi_j) = 0

State y = [xi, eta, psi_1..psi_N, xid, etad, psid_1..psid_N], psi_j = phi_j - n t.
Parameters `p`: a dict with n_eta, mu_xi, mu_eta, sigma, c, eps, mu_w (and n).
Used by `rotorjax bench` and the scripts in `benchmarks/`.
"""

import cmath
import math
import time

import numpy as np


def make_rhs_python(p, complex_step=False):
    """`rhs(t, y)` for the parameters `p` (with `p["n"]`): closed form in scalar Python
    (`math.sin/cos`, the weights' accelerations eliminated by hand so that only the
    2x2 system for xi'', eta'' is solved, as in the numba kernel). Returns a list.
    `complex_step=True`: `cmath.sin/cos`, for complex states (complex-step Jacobians)."""
    n = float(p["n"])
    n_eta2 = float(p["n_eta"]) ** 2
    two_mu_xi, two_mu_eta = 2.0 * float(p["mu_xi"]), 2.0 * float(p["mu_eta"])
    sigma, eps, mu_w = float(p["sigma"]), float(p["eps"]), float(p["mu_w"])
    cn2 = float(p["c"]) * n * n
    se = sigma * eps
    sin, cos = (cmath.sin, cmath.cos) if complex_step else (math.sin, math.cos)

    def rhs(t, y):
        y = y.tolist()
        N = (len(y) - 4) >> 1
        m = N + 2
        nt = n * t
        sss = scc = ssc = ssg = scg = sc2 = ss2 = 0.0
        ss, cc = [], []
        for j in range(N):
            phi = y[2 + j] + nt
            s = sin(phi)
            co = cos(phi)
            ss.append(s)
            cc.append(co)
            psid = y[m + 2 + j]
            g = -mu_w * psid
            w2 = (psid + n) * (psid + n)
            sss += s * s
            scc += co * co
            ssc += s * co
            ssg += s * g
            scg += co * g
            sc2 += w2 * co
            ss2 += w2 * s
        b1 = -two_mu_xi * y[m] - y[0] + sigma * sc2 + cn2 * cos(nt) + sigma * ssg
        b2 = -two_mu_eta * y[m + 1] - n_eta2 * y[1] + sigma * ss2 + cn2 * sin(nt) - sigma * scg
        a11 = 1.0 - se * sss
        a12 = se * ssc
        a22 = 1.0 - se * scc
        det = a11 * a22 - a12 * a12
        X = (b1 * a22 - a12 * b2) / det
        E = (a11 * b2 - a12 * b1) / det
        out = y[m:]
        out.append(X)
        out.append(E)
        for j in range(N):
            out.append(-mu_w * y[m + 2 + j] + eps * (ss[j] * X - cc[j] * E))
        return out

    return rhs


def rhs_python(t, y, p):
    """Pure-Python closed-form right-hand side (see `make_rhs_python`), as an array."""
    return np.asarray(make_rhs_python(p)(float(t), np.asarray(y, dtype=np.float64)))


def scipy_loop(speeds, y0, t_end, p, method="DOP853", rtol=1e-6, atol=1e-9, rhs="python"):
    """Plain Python loop of solve_ivp over speeds, with the pure-Python right-hand side
    (`rhs="python"`, the strongest scipy peer) or a numpy one (`rhs`: a function
    `rhs(t, y, p)`, e.g. `benchmarks/peers_001.rhs_numpy`).
    -> (final_states, wall_s, n_failed)."""
    from scipy.integrate import solve_ivp

    speeds = np.asarray(speeds, dtype=np.float64)
    y0 = np.asarray(y0, dtype=np.float64)
    out = np.empty((len(speeds), len(y0)))
    n_failed = 0
    t0 = time.perf_counter()
    for i, n in enumerate(speeds):
        pp = dict(p)
        pp["n"] = float(n)
        if rhs == "python":
            fun, args = make_rhs_python(pp), None
        else:
            fun, args = rhs, (pp,)
        sol = solve_ivp(fun, (0.0, float(t_end)), y0, method=method,
                        rtol=rtol, atol=atol, args=args)
        if not sol.success:
            n_failed += 1
        out[i] = sol.y[:, -1]
    return out, time.perf_counter() - t0, n_failed


# --------------------------------------------------------------------------- Floquet
def scipy_margin(p, n, y_main, rtol):
    """The largest Floquet exponent of the periodic motion through `y_main` at speed `n`
    (period 2 pi / n): a scipy DOP853 solve of the state, the monodromy matrix and the
    Jacobian's trace integral, the Jacobian by complex step of the pure-Python
    right-hand side (exact to rounding)."""
    from scipy.integrate import solve_ivp

    p = dict(p, n=float(n))
    m = len(y_main)
    h = 1e-30
    f_c = make_rhs_python(p, complex_step=True)
    f_r = make_rhs_python(p)
    steps = [[1j * h if i == k else 0.0 for i in range(m)] for k in range(m)]

    def jac(t, y):
        yl = y.tolist()
        cols = [f_c(t, np.array([a + b for a, b in zip(yl, e)])) for e in steps]
        return np.imag(np.array(cols)).T / h

    def aug(t, s):
        y, phi = s[:m], s[m:m + m * m].reshape(m, m)
        j = jac(t, y)
        return np.concatenate([f_r(t, y), (j @ phi).ravel(), [np.trace(j)]])

    period = 2 * np.pi / float(n)
    s0 = np.concatenate([np.asarray(y_main, dtype=np.float64), np.eye(m).ravel(), [0.0]])
    sol = solve_ivp(aug, (0, period), s0, method="DOP853", rtol=rtol, atol=rtol * 1e-2)
    mono = sol.y[m:m + m * m, -1].reshape(m, m)
    return float(np.max(np.log(np.abs(np.linalg.eigvals(mono)))) / period)
