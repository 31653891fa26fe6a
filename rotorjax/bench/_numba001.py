"""The numba peer of model 001: fixed-step classical RK4 over speeds (`prange`), with
the structured right-hand side (the weights' accelerations eliminated by hand, a 2x2
solve), as a fast compiled CPU code would be written. Needs numba (an optional
dependency, `pip install rotorjax[bench]`): import this module only when
`importlib.util.find_spec("numba")` finds it. Parameters as in `_peers001`."""

import time

import numba
import numpy as np

_KEYS = ("n_eta", "mu_xi", "mu_eta", "sigma", "c", "eps", "mu_w")


@numba.njit(fastmath=False, cache=False, inline="always")
def _rhs_nb(t, y, out, n, n_eta, mu_xi, mu_eta, sigma, c, eps, mu_w, N):
    """Structured RHS: phi_j'' = g_j + eps (s_j X - c_j E), g_j = -mu_w psid_j, -> 2x2 solve.
    Generic in the state's type (`np.sin`, not `math.sin`): with complex `y` and `out`
    it is the complex-step derivative's right-hand side (the Floquet peer's Jacobian)."""
    nt = n * t
    z = y[0] * 0.0  # a zero of the state's type
    Sss = z
    Scc = z
    Ssc = z
    Ssg = z
    Scg = z
    Sc2 = z  # sum phid^2 cos
    Ss2 = z  # sum phid^2 sin
    for j in range(N):
        phi = y[2 + j] + nt
        s = np.sin(phi)
        co = np.cos(phi)
        psid = y[4 + N + j]
        phid = psid + n
        g = -mu_w * psid
        Sss += s * s
        Scc += co * co
        Ssc += s * co
        Ssg += s * g
        Scg += co * g
        w2 = phid * phid
        Sc2 += w2 * co
        Ss2 += w2 * s
    cn2 = c * n * n
    r1 = -2.0 * mu_xi * y[2 + N] - y[0] + sigma * Sc2 + cn2 * np.cos(nt)
    r2 = -2.0 * mu_eta * y[3 + N] - n_eta * n_eta * y[1] + sigma * Ss2 + cn2 * np.sin(nt)
    se = sigma * eps
    a11 = 1.0 - se * Sss
    a12 = se * Ssc
    a22 = 1.0 - se * Scc
    b1 = r1 + sigma * Ssg
    b2 = r2 - sigma * Scg
    det = a11 * a22 - a12 * a12
    X = (b1 * a22 - a12 * b2) / det
    E = (a11 * b2 - a12 * b1) / det
    m = 2 + N
    for k in range(m):
        out[k] = y[m + k]
    out[m] = X
    out[m + 1] = E
    for j in range(N):
        phi = y[2 + j] + nt
        out[m + 2 + j] = -mu_w * y[4 + N + j] + eps * (np.sin(phi) * X - np.cos(phi) * E)


@numba.njit(parallel=True, fastmath=False, cache=True)  # cached: its compilation takes ~20 s
def _rk4_kernel(speeds, y0, t_end, n_steps, pars):
    n_eta, mu_xi, mu_eta, sigma, c, eps, mu_w = (pars[0], pars[1], pars[2], pars[3],
                                                 pars[4], pars[5], pars[6])
    ns = speeds.shape[0]
    d = y0.shape[0]
    N = (d - 4) // 2
    out = np.empty((ns, d))
    h = t_end / n_steps
    for i in numba.prange(ns):
        n = speeds[i]
        y = y0.copy()
        yt = np.empty(d)
        k1 = np.empty(d)
        k2 = np.empty(d)
        k3 = np.empty(d)
        k4 = np.empty(d)
        for step in range(n_steps):
            t = step * h
            _rhs_nb(t, y, k1, n, n_eta, mu_xi, mu_eta, sigma, c, eps, mu_w, N)
            for k in range(d):
                yt[k] = y[k] + 0.5 * h * k1[k]
            _rhs_nb(t + 0.5 * h, yt, k2, n, n_eta, mu_xi, mu_eta, sigma, c, eps, mu_w, N)
            for k in range(d):
                yt[k] = y[k] + 0.5 * h * k2[k]
            _rhs_nb(t + 0.5 * h, yt, k3, n, n_eta, mu_xi, mu_eta, sigma, c, eps, mu_w, N)
            for k in range(d):
                yt[k] = y[k] + h * k3[k]
            _rhs_nb(t + h, yt, k4, n, n_eta, mu_xi, mu_eta, sigma, c, eps, mu_w, N)
            for k in range(d):
                y[k] += (h / 6.0) * (k1[k] + 2.0 * k2[k] + 2.0 * k3[k] + k4[k])
        for k in range(d):
            out[i, k] = y[k]
    return out


def _pars(p):
    return np.array([float(p[k]) for k in _KEYS], dtype=np.float64)


_compiled = False


def _warmup(d):
    global _compiled
    y = np.zeros(d)
    _rk4_kernel(np.array([1.0, 2.0]), y, 0.01, 2, np.ones(7))
    _compiled = True


def numba_rk4(speeds, y0, t_end, p, n_steps, threads=1):
    """Fixed-step classical RK4 over speeds (prange). -> (final_states, wall_s excl. compile)."""
    speeds = np.ascontiguousarray(speeds, dtype=np.float64)
    y0 = np.ascontiguousarray(y0, dtype=np.float64)
    numba.set_num_threads(int(threads))
    _warmup(len(y0))
    t0 = time.perf_counter()
    out = _rk4_kernel(speeds, y0, float(t_end), int(n_steps), _pars(p))
    return out, time.perf_counter() - t0


@numba.njit(fastmath=False, cache=False)
def _rhs_once(t, y, n, pars):
    out = np.empty(y.shape[0])
    _rhs_nb(t, y, out, n, pars[0], pars[1], pars[2], pars[3], pars[4], pars[5], pars[6],
            (y.shape[0] - 4) // 2)
    return out


def numba_rhs(t, y, p):
    """Numba RHS (structured 2x2 solve), returns a new array; for checks."""
    return _rhs_once(float(t), np.ascontiguousarray(y, dtype=np.float64), float(p["n"]), _pars(p))


@numba.njit(fastmath=False, cache=False)
def _rhs_loop(y, n, pars, n_calls):
    d = y.shape[0]
    N = (d - 4) // 2
    out = np.empty(d)
    acc = 0.0
    for i in range(n_calls):
        _rhs_nb(1e-6 * i, y, out, n, pars[0], pars[1], pars[2], pars[3], pars[4],
                pars[5], pars[6], N)
        acc += out[d - 1]
    return acc


def numba_rhs_ns(p, y0, n_calls=2_000_000, repeats=5):
    """Nanoseconds per numba RHS evaluation (best of `repeats`)."""
    y = np.ascontiguousarray(y0, dtype=np.float64)
    pars = _pars(p)
    n = float(p.get("n", 5.0))
    _rhs_loop(y, n, pars, 10)
    best = np.inf
    for _ in range(repeats):
        t0 = time.perf_counter()
        _rhs_loop(y, n, pars, n_calls)
        best = min(best, time.perf_counter() - t0)
    return best / n_calls * 1e9
