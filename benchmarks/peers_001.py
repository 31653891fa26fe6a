"""Peer (non-JAX) implementations for benchmark 001.

Dimensionless rotor with N correction weights on anisotropic supports:

  xi''  + 2 mu_xi  xi'  + xi          - sigma sum_j (phi_j'' sin phi_j + phi_j'^2 cos phi_j) - c n^2 cos(n t) = 0
  eta'' + 2 mu_eta eta' + n_eta^2 eta + sigma sum_j (phi_j'' cos phi_j - phi_j'^2 sin phi_j) - c n^2 sin(n t) = 0
  phi_j'' + mu_w (phi_j' - n) + eps (-xi'' sin phi_j + eta'' cos phi_j) = 0

State y = [xi, eta, psi_1..psi_N, xid, etad, psid_1..psid_N], psi_j = phi_j - n t,
psid_j = phid_j - n, psidd_j = phidd_j.  float64 throughout.

Contents: rhs_numpy (generic (N+2)x(N+2) solve, here: the check of the others);
from the package (`rotorjax.bench`, which `rotorjax bench` runs): rhs_python /
make_rhs_python (closed-form, pure Python: scalar `math`, the structured 2x2 solve by
hand; the strongest scipy peer), scipy_loop (solve_ivp per speed, either right-hand
side), numba_rk4 (fixed-step classical RK4, prange over speeds, structured 2x2 solve),
numba_rhs_ns (ns per RHS evaluation), dop853_loop (Hairer's DOP853 in C, `numbalsoda`,
the numba right-hand side as a `cfunc`, prange over speeds; `dop853_available()`).
"""
import math

import numpy as np
import numba  # noqa: F401  (its version goes into the results)

from rotorjax.bench import _peers001
from rotorjax.bench._numba001 import numba_rhs, numba_rhs_ns, numba_rk4  # noqa: F401
from rotorjax.bench._peers001 import make_rhs_python, rhs_python  # noqa: F401
from rotorjax.bench._dop853_001 import available as dop853_available  # noqa: F401


def dop853_loop(speeds, y0, t_end, p, rtol, atol, threads=1):
    """C DOP853 over the speeds -> (final states, wall s, all succeeded); see
    `rotorjax.bench._dop853_001` (needs numbalsoda)."""
    from rotorjax.bench._dop853_001 import dop853_loop as run

    return run(speeds, y0, t_end, p, rtol, atol, threads)


# --------------------------------------------------------------------------- numpy
def rhs_numpy(t, y, p):
    """RHS via a generic (N+2)x(N+2) linear solve for [xi'', eta'', phi_1''..phi_N'']."""
    y = np.asarray(y, dtype=np.float64)
    N = (len(y) - 4) // 2
    n = float(p["n"])
    sigma, eps, mu_w = float(p["sigma"]), float(p["eps"]), float(p["mu_w"])
    xi, eta = y[0], y[1]
    psi = y[2:2 + N]
    xid, etad = y[2 + N], y[3 + N]
    psid = y[4 + N:]
    phi = psi + n * t
    phid = psid + n
    s, co = np.sin(phi), np.cos(phi)

    M = np.eye(N + 2)
    M[0, 2:] = -sigma * s
    M[1, 2:] = sigma * co
    M[2:, 0] = -eps * s
    M[2:, 1] = eps * co
    b = np.empty(N + 2)
    b[0] = (-2.0 * p["mu_xi"] * xid - xi + sigma * np.sum(phid**2 * co)
            + p["c"] * n * n * math.cos(n * t))
    b[1] = (-2.0 * p["mu_eta"] * etad - p["n_eta"] ** 2 * eta
            + sigma * np.sum(phid**2 * s) + p["c"] * n * n * math.sin(n * t))
    b[2:] = -mu_w * psid
    acc = np.linalg.solve(M, b)
    return np.concatenate((y[2 + N:], acc))


def scipy_loop(speeds, y0, t_end, p, method="DOP853", rtol=1e-6, atol=1e-9, rhs="python"):
    """`rotorjax.bench._peers001.scipy_loop`, with `rhs="numpy"` naming `rhs_numpy`."""
    return _peers001.scipy_loop(speeds, y0, t_end, p, method, rtol, atol, rhs_numpy if rhs == "numpy" else rhs)


# --------------------------------------------------------------------------- checks
def _checks():
    p = dict(n_eta=7.0, mu_xi=0.25, mu_eta=0.5, sigma=0.5, c=0.5, eps=0.01, mu_w=0.5)
    # main motion is an exact solution
    y = np.array([0, 0, 2 * np.pi / 3, 4 * np.pi / 3, 0, 0, 0, 0], dtype=np.float64)
    mm = 0.0
    for n in (0.5, 3.0, 10.0):
        for t in (0.0, 1.3, 17.0):
            q = dict(p, n=n)
            mm = max(mm, np.abs(rhs_numpy(t, y, q)).max(), np.abs(numba_rhs(t, y, q)).max(),
                     np.abs(rhs_python(t, y, q)).max())
    # numpy (generic solve) vs numba and pure Python (structured 2x2) at random states
    rng = np.random.default_rng(0)
    md = 0.0
    for N in (1, 2, 3, 5):
        for _ in range(200):
            yy = rng.normal(size=2 * N + 4)
            q = dict(p, n=rng.uniform(0.5, 10), eps=rng.uniform(0, 0.3))
            t = rng.uniform(0, 50)
            a = rhs_numpy(t, yy, q)
            for b in (numba_rhs(t, yy, q), rhs_python(t, yy, q),
                      np.real(make_rhs_python(q, complex_step=True)(t, yy.astype(complex)))):
                md = max(md, np.abs(a - b).max() / max(1.0, np.abs(a).max()))
    return mm, md


if __name__ == "__main__":
    import argparse

    ap = argparse.ArgumentParser(description="checks of the peers, then their speed on 20 speeds")
    ap.add_argument("--smoke", action="store_true", help="the checks, then 3 speeds over tau in [0, 20]")
    args = ap.parse_args()
    mm, md = _checks()
    print(f"check main motion: max|rhs| = {mm:.3e}  (rounding level; sigma=c, psi=2pi/3,4pi/3)")
    print(f"check numpy vs numba and pure-Python rhs: max rel diff = {md:.3e}")
    assert mm < 1e-12 and md < 1e-13

    p = dict(n_eta=7.0, mu_xi=0.25, mu_eta=0.5, sigma=0.5, c=0.5, eps=0.01, mu_w=0.5)
    y0 = np.array([0, 0, 2 * np.pi / 3 + 0.1, 4 * np.pi / 3 - 0.05, 0, 0, 0, 0])
    speeds = np.linspace(0.5, 10.0, 3 if args.smoke else 20)
    t_end = 20.0 if args.smoke else 200.0

    # note: n=8.0 is sensitive (slipping weights); scipy itself disagrees with rtol=1e-12
    # there by O(10), so the max diff is reported with and without the worst speed.
    ref, t_sp, nf = scipy_loop(speeds, y0, t_end, p, method="DOP853", rtol=1e-10, atol=1e-12)
    print(f"scipy DOP853 rtol=1e-10 atol=1e-12: {t_sp:.2f} s, failed={nf}")
    for dt in (0.002, 0.005):
        ns = int(round(t_end / dt))
        for th in (1, 2):
            res, t_nb = numba_rk4(speeds, y0, t_end, p, ns, threads=th)
            dv = np.abs(res - ref).max(axis=1)
            w = int(np.argmax(dv))
            print(f"numba RK4 dt={dt} threads={th}: {t_nb:.3f} s, max|diff| vs scipy = "
                  f"{dv.max():.3e} (at n={speeds[w]:.2f}); excluding that speed: "
                  f"{np.delete(dv, w).max():.3e}")
    print(f"numba rhs: {numba_rhs_ns(p, y0, n_calls=1000 if args.smoke else 2_000_000):.1f} ns/eval")
    if args.smoke:
        print("smoke run: nothing written")
