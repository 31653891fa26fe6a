"""Model 001 Floquet stability map: rotorjax vmapped vs a scipy loop.

The main motion's largest Floquet exponent over 200 speeds x 50 weight-damping
values `mu_w` (eps = 0.001, Table 1's other parameters). rotorjax integrates the
variational equations alongside the state (Dopri8, vmapped, chunked). The peer is
a Python loop of scipy `solve_ivp` (DOP853) over the same augmented system, with
the Jacobian of the numpy right-hand side by complex step (exact to rounding).
The scipy loop is timed on a random subset of grid points (it is linear in the
number of points) and reported as points per second.

Accuracy: the critical speeds at mu_w = 0.25 located by each method (scan of the
200 speeds + bisection to 1e-9) against a tight reference (rotorjax, rtol 1e-12).

Run: python benchmarks/stability_map.py; writes benchmarks/results/stability_map.json.
"""

import json
import os
import platform
import sys
import time

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))

import jax  # noqa: E402
from scipy.integrate import solve_ivp  # noqa: E402

import rotorjax as rj  # noqa: E402
from rotorjax.analysis import critical_speeds  # noqa: E402
from rotorjax.presets import anisotropic_abb as A  # noqa: E402

BASE = dict(n_eta=7.0, mu_xi=0.25, mu_eta=0.5, sigma=0.5, c=0.5, eps=0.001, mu_w=0.25)
SPEEDS = np.linspace(0.5, 10.0, 200)
MU_W = np.linspace(0.05, 1.0, 50)
Y_MAIN = np.concatenate([[0, 0], 2 * np.pi / 3 * np.array([1, 2]), np.zeros(4)])


def rotorjax_map(rtol, chunk=250):
    def one(p):
        g = dict(BASE, mu_w=p["mu_w"])
        return A.main_motion_floquet(g, p["n"], rtol=rtol, atol=rtol * 1e-2).margin

    t0 = time.perf_counter()
    res = rj.sweep(one, {"n": SPEEDS, "mu_w": MU_W}, chunk_size=chunk, progress=False)
    return np.asarray(res.values), time.perf_counter() - t0


def rhs_complex(t, y, p):
    """Model 001 right-hand side (as peers_001.rhs_numpy) that also accepts complex
    states, for complex-step Jacobians."""
    N = (len(y) - 4) // 2
    n, sigma, eps, mu_w = p["n"], p["sigma"], p["eps"], p["mu_w"]
    psi, psid = y[2:2 + N], y[4 + N:]
    phi, phid = psi + n * t, psid + n
    s, co = np.sin(phi), np.cos(phi)
    M = np.eye(N + 2, dtype=y.dtype)
    M[0, 2:], M[1, 2:], M[2:, 0], M[2:, 1] = -sigma * s, sigma * co, -eps * s, eps * co
    b = np.empty(N + 2, dtype=y.dtype)
    b[0] = -2 * p["mu_xi"] * y[2 + N] - y[0] + sigma * np.sum(phid**2 * co) + p["c"] * n**2 * np.cos(n * t)
    b[1] = (-2 * p["mu_eta"] * y[3 + N] - p["n_eta"] ** 2 * y[1] + sigma * np.sum(phid**2 * s)
            + p["c"] * n**2 * np.sin(n * t))
    b[2:] = -mu_w * psid
    return np.concatenate((y[2 + N:], np.linalg.solve(M, b)))


def scipy_margin(n, mu_w, rtol):
    p = dict(BASE, mu_w=mu_w, n=n)
    m = len(Y_MAIN)

    def jac(t, y):
        h = 1e-30
        return np.stack([np.imag(rhs_complex(t, y + 1j * h * e, p)) / h
                         for e in np.eye(m)], axis=1)

    def aug(t, s):
        y, phi = s[:m], s[m:m + m * m].reshape(m, m)
        j = jac(t, y)
        return np.concatenate([rhs_complex(t, y, p), (j @ phi).ravel(), [np.trace(j)]])

    period = 2 * np.pi / n
    s0 = np.concatenate([Y_MAIN, np.eye(m).ravel(), [0.0]])
    sol = solve_ivp(aug, (0, period), s0, method="DOP853", rtol=rtol, atol=rtol * 1e-2)
    mono = sol.y[m:m + m * m, -1].reshape(m, m)
    return np.max(np.log(np.abs(np.linalg.eigvals(mono)))) / period


def scipy_critical(mu_w, rtol):
    row = np.array([scipy_margin(n, mu_w, rtol) for n in SPEEDS])
    out = []
    for i in range(len(SPEEDS) - 1):
        a, b, ma = SPEEDS[i], SPEEDS[i + 1], row[i]
        if np.sign(row[i]) == np.sign(row[i + 1]):
            continue
        while b - a > 1e-9:
            c = 0.5 * (a + b)
            mc = scipy_margin(c, mu_w, rtol)
            a, b, ma = (c, b, mc) if np.sign(mc) == np.sign(ma) else (a, c, ma)
        out.append(0.5 * (a + b))
    return np.array(out)


def rotorjax_critical(mu_w, rtol):
    g = dict(BASE, mu_w=mu_w)
    cs = critical_speeds(lambda n: A.main_motion_floquet(g, n, rtol=rtol, atol=rtol * 1e-2).margin,
                         SPEEDS[0], SPEEDS[-1], n_scan=len(SPEEDS), xtol=1e-9)
    return np.array([c.speed for c in cs])


def main():
    import argparse

    ap = argparse.ArgumentParser()
    ap.add_argument("--subset", type=int, default=60)
    ap.add_argument("--repeats", type=int, default=3)
    args = ap.parse_args()
    rng = np.random.default_rng(0)
    out = {"benchmark": "stability_map (model 001, Floquet, 200 speeds x 50 mu_w)",
           "machine": {"platform": platform.platform(), "cpu_count": os.cpu_count(),
                       "jax_backend": jax.default_backend()},
           "versions": {"jax": jax.__version__, "numpy": np.__version__},
           "params": BASE, "grid": {"n": [0.5, 10.0, 200], "mu_w": [0.05, 1.0, 50]}, "rows": []}

    ref = rotorjax_critical(0.25, 1e-12)
    print("reference critical speeds (mu_w = 0.25, rotorjax rtol 1e-12):", ref)
    out["reference_critical_speeds"] = ref.tolist()
    for rtol in (1e-6, 1e-8):
        first_map, first = rotorjax_map(rtol)
        times = [rotorjax_map(rtol)[1] for _ in range(args.repeats)]
        run = float(np.median(times))
        rj_pts = MU_W.size * SPEEDS.size / run
        rj_crit = rotorjax_critical(0.25, rtol)
        idx = rng.choice(SPEEDS.size * MU_W.size, size=args.subset, replace=False)
        t0 = time.perf_counter()
        sp = [scipy_margin(SPEEDS[i // MU_W.size], MU_W[i % MU_W.size], rtol) for i in idx]
        sp_time = time.perf_counter() - t0
        sp_pts = args.subset / sp_time
        margin_diff = float(np.max(np.abs(np.array(sp) - first_map.reshape(-1)[idx])))
        t0 = time.perf_counter()
        sp_crit = scipy_critical(0.25, rtol)
        sp_crit_time = time.perf_counter() - t0

        def err(c):
            return float(np.max(np.abs(c - ref))) if len(c) == len(ref) else float("inf")

        row = {"rtol": rtol, "rotorjax_points_per_s": rj_pts, "rotorjax_map_s": run,
               "rotorjax_first_call_s": first, "scipy_points_per_s": sp_pts,
               "speedup": rj_pts / sp_pts, "max_margin_difference_on_subset": margin_diff,
               "rotorjax_critical_speeds": rj_crit.tolist(), "rotorjax_critical_error": err(rj_crit),
               "scipy_critical_speeds": sp_crit.tolist(), "scipy_critical_error": err(sp_crit),
               "scipy_critical_s": sp_crit_time, "stable_fraction": float(np.mean(first_map < 0))}
        out["rows"].append(row)
        print(f"rtol {rtol:.0e}: rotorjax {rj_pts:.0f} points/s ({run:.1f} s for the map, first call "
              f"{first:.1f} s), scipy {sp_pts:.1f} points/s -> {row['speedup']:.1f}x; "
              f"critical-speed error rotorjax {row['rotorjax_critical_error']:.1e}, "
              f"scipy {row['scipy_critical_error']:.1e}")
    path = os.path.join(os.path.dirname(__file__), "results", "stability_map.json")
    with open(path, "w") as f:
        json.dump(out, f, indent=2)
    print(f"wrote {path}")


if __name__ == "__main__":
    main()
