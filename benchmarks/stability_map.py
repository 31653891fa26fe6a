"""Model 001 Floquet stability map: rotorjax vmapped vs a scipy loop.

The main motion's largest Floquet exponent over 200 speeds x 50 weight-damping
values `mu_w` (eps = 0.001, Table 1's other parameters). rotorjax integrates the
variational equations alongside the state (Dopri8, vmapped, chunks of 250), through
`rotorjax.sweep` on one device (and, with `--shard`, with `shard=True` over the two
host devices: XLA_FLAGS set below, before jax is imported; see the JSON's
`sharded_note`).
`sweep` compiles a function once (it keeps the compiled function for the next call); the
same vmapped computation compiled once (`jax.jit`, chunk by chunk, sharded alike) is
timed too. Every timing: a compiling call first, then the median of repeats.

`floquet_batch` (issue 32, item 4) integrates the same variational equations as a
scene on the batch kernel (all 10 000 points in one queue of lanes, the lanes stepped
together as arrays), with `CPU_COMPILER_OPTIONS`; the sweep is also timed with those
options (`compiler_options=`), as `stability_margins` runs it.

The compiled peer is Hairer's DOP853 in C (`numbalsoda`) over the same variational
equations, a numba `cfunc` right-hand side whose Jacobian is taken by complex step
(8 complex evaluations of the structured right-hand side), the points in a numba
`prange` loop on 1 and on 2 threads (`rotorjax.bench._dop853_001.floquet_loop`),
timed on the whole grid (target, issue 32: at least 1x).

The scipy peers are Python loops of scipy `solve_ivp` (DOP853) over the same augmented
system (state, monodromy matrix, trace integral), the Jacobian by complex step
(exact to rounding) of either right-hand side: the closed-form pure-Python one
(`peers_001.make_rhs_python(..., complex_step=True)`: scalar `cmath`, the 2x2 solve by
hand; the strongest peer) or the numpy one (a generic linear solve). A scipy loop is
timed on a random subset of grid points (it is linear in the number of points) and
reported as points per second. Target (issue 17): >= 100x the scipy loop on the CPU.

Accuracy: the critical speeds at mu_w = 0.25 located by each method (scan of the
200 speeds + bisection to 1e-9) against a tight reference (rotorjax, rtol 1e-12).

Run: python benchmarks/stability_map.py [--subset 60] [--repeats 3] [--smoke];
writes benchmarks/results/stability_map.json (`--smoke`: 8 speeds x 2 mu_w, rtol 1e-6 only,
the reference too, one call each; prints, writes nothing).
"""

import functools
import json
import os
import platform
import sys
import time

import numpy as np

# Two host devices, so that the sharded variant can use both cores (must precede jax).
os.environ.setdefault("XLA_FLAGS", "--xla_force_host_platform_device_count=2 --xla_cpu_multi_thread_eigen=false")
sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))

import jax  # noqa: E402
from scipy.integrate import solve_ivp  # noqa: E402

import equinox as eqx  # noqa: E402

import rotorjax as rj  # noqa: E402
from rotorjax.bench import _peers001  # noqa: E402
from rotorjax.bench._model001 import (FLOQUET_BASE, Y_MAIN as Y_MAIN_001, floquet_margin_fn,  # noqa: E402
                                      floquet_reference_fn)
from _common import CpuWatch, today  # noqa: E402
from rotorjax._distributed import on_each_device  # noqa: E402
from rotorjax.analysis import CPU_COMPILER_OPTIONS, critical_speeds, floquet_batch  # noqa: E402
from rotorjax.bench import _dop853_001  # noqa: E402
from rotorjax.presets import anisotropic_abb as A  # noqa: E402

BASE, Y_MAIN = FLOQUET_BASE, Y_MAIN_001  # model 001's Floquet study, as `rotorjax bench` runs it
SPEEDS = np.linspace(0.5, 10.0, 200)
MU_W = np.linspace(0.05, 1.0, 50)
margin_fn = floquet_margin_fn  # `point -> margin` at `rtol` (one function object per rtol)


def rotorjax_map(rtol, chunk=250, shard=False, options=None):
    """The map through `rotorjax.sweep` (with the XLA `options`) -> (margins (200, 50), seconds)."""
    t0 = time.perf_counter()
    res = rj.sweep(margin_fn(rtol), {"n": SPEEDS, "mu_w": MU_W}, chunk_size=chunk, progress=False, shard=shard,
                   compiler_options=options)
    return np.asarray(jax.block_until_ready(res.values)), time.perf_counter() - t0


def sweep_options_map(rtol, shard=False):
    """`rotorjax_map` with `CPU_COMPILER_OPTIONS` (as `stability_margins` sweeps)."""
    return rotorjax_map(rtol, shard=shard, options=CPU_COMPILER_OPTIONS)


def batch_map(rtol, shard=False):
    """The map through `floquet_batch`: the grid's orbits built (vmapped) and their
    variational equations integrated on the batch kernel -> (margins, seconds)."""
    n, mu = (jax.numpy.asarray(a.reshape(-1)) for a in np.meshgrid(SPEEDS, MU_W, indexing="ij"))
    t0 = time.perf_counter()
    res = floquet_batch(eqx.filter_vmap(floquet_reference_fn(rtol))({"n": n, "mu_w": mu}), shard=shard)
    margins = np.asarray(res.checked_margin)
    return margins.reshape(SPEEDS.size, MU_W.size), time.perf_counter() - t0


def c_dop853_map(rtol, threads):
    """The map by C DOP853 over the variational equations, `threads` threads ->
    (margins, seconds excluding numba's compilation, all succeeded)."""
    n, mu = (a.reshape(-1) for a in np.meshgrid(SPEEDS, MU_W, indexing="ij"))
    m, wall, ok = _dop853_001.floquet_loop(n, mu, Y_MAIN, BASE, rtol, rtol * 1e-2, threads=threads)
    return m.reshape(SPEEDS.size, MU_W.size), wall, ok


def c_dop853_margin(n, mu_w, rtol):
    return float(_dop853_001.floquet_loop(np.array([n]), mu_w, Y_MAIN, BASE, rtol, rtol * 1e-2)[0][0])


_COMPILED = {}


def compiled_map(rtol, chunk=250, shard=False):
    """The same vmapped computation, compiled once (`jax.jit`), chunk by chunk (each
    chunk split over the local devices when `shard`) -> (margins, seconds)."""
    if rtol not in _COMPILED:
        _COMPILED[rtol] = jax.jit(jax.vmap(margin_fn(rtol)))
    f = _COMPILED[rtol]
    n, mu = (a.reshape(-1) for a in np.meshgrid(SPEEDS, MU_W, indexing="ij"))
    nd = len(jax.local_devices()) if shard else 1
    t0 = time.perf_counter()
    outs = []
    for s in range(0, n.size, chunk):
        idx = np.minimum(np.arange(s, s + chunk), n.size - 1)
        part = {"n": n[idx], "mu_w": mu[idx]}
        if shard:  # each device its own share, as its own program (as `sweep(..., shard=True)`)
            per = -(-chunk // nd)
            shares = on_each_device(f, [({k: v[i * per:(i + 1) * per] for k, v in part.items()},)
                                        for i in range(nd)])
            outs.append(np.concatenate(shares))
        else:
            outs.append(np.asarray(jax.block_until_ready(f({k: jax.numpy.asarray(v) for k, v in part.items()}))))
    margins = np.concatenate(outs)[:n.size].reshape(SPEEDS.size, MU_W.size)
    return margins, time.perf_counter() - t0


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


def scipy_margin(n, mu_w, rtol, rhs="python"):
    """The largest Floquet exponent by a scipy DOP853 solve of the augmented system;
    `rhs`: "python" (closed-form pure-Python right-hand side in `cmath`: the package's
    peer, `rotorjax.bench._peers001.scipy_margin`) or "numpy"."""
    p = dict(BASE, mu_w=mu_w, n=n)
    if rhs == "python":
        return _peers001.scipy_margin(p, n, Y_MAIN, rtol)
    m = len(Y_MAIN)
    h = 1e-30

    def jac(t, y):
        return np.stack([np.imag(rhs_complex(t, y + 1j * h * e, p)) / h for e in np.eye(m)], axis=1)

    def aug(t, s):
        y, phi = s[:m], s[m:m + m * m].reshape(m, m)
        j = jac(t, y)
        return np.concatenate([rhs_complex(t, y, p), (j @ phi).ravel(), [np.trace(j)]])

    period = 2 * np.pi / n
    s0 = np.concatenate([Y_MAIN, np.eye(m).ravel(), [0.0]])
    sol = solve_ivp(aug, (0, period), s0, method="DOP853", rtol=rtol, atol=rtol * 1e-2)
    mono = sol.y[m:m + m * m, -1].reshape(m, m)
    return np.max(np.log(np.abs(np.linalg.eigvals(mono)))) / period


def scipy_critical(mu_w, rtol, margin=scipy_margin):
    """Critical speeds at `mu_w` by a scan of the 200 speeds and bisection to 1e-9,
    with `margin(n, mu_w, rtol)` (the scipy peer's, or the C DOP853 peer's)."""
    row = np.array([margin(n, mu_w, rtol) for n in SPEEDS])
    out = []
    for i in range(len(SPEEDS) - 1):
        a, b, ma = SPEEDS[i], SPEEDS[i + 1], row[i]
        if np.sign(row[i]) == np.sign(row[i + 1]):
            continue
        while b - a > 1e-9:
            c = 0.5 * (a + b)
            mc = margin(c, mu_w, rtol)
            a, b, ma = (c, b, mc) if np.sign(mc) == np.sign(ma) else (a, c, ma)
        out.append(0.5 * (a + b))
    return np.array(out)


@functools.lru_cache(maxsize=None)
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
    ap.add_argument("--shard", action="store_true", help="also time the variants split over the host devices")
    ap.add_argument("--smoke", action="store_true", help="a tiny grid, one rtol, one call each; write nothing")
    args = ap.parse_args()
    global SPEEDS, MU_W
    if args.smoke:
        SPEEDS, MU_W = np.linspace(0.5, 10.0, 8), np.linspace(0.05, 1.0, 2)
        args.subset, args.repeats = 3, 0
    rng = np.random.default_rng(0)
    whole = CpuWatch()
    n_dev = len(jax.local_devices())
    out = {"benchmark": "stability_map (model 001, Floquet, 200 speeds x 50 mu_w)",
           "machine": {"platform": platform.platform(), "cpu_count": os.cpu_count(),
                       "jax_backend": jax.default_backend(), "devices": [str(d) for d in jax.devices()],
                       "xla_flags": os.environ.get("XLA_FLAGS")},
           "gpu": "not available to this task",
           "versions": {"jax": jax.__version__, "numpy": np.__version__},
           "params": BASE, "grid": {"n": [0.5, 10.0, 200], "mu_w": [0.05, 1.0, 50]},
           "peers": {"python": "scipy DOP853 loop, closed-form pure-Python right-hand side (cmath), Jacobian by "
                               "complex step (8 evaluations): the strongest peer",
                     "numpy": "scipy DOP853 loop, numpy right-hand side (generic linear solve), Jacobian by "
                              "complex step"},
           "rows": []}

    ref_rtol = 1e-6 if args.smoke else 1e-12  # --smoke: the reference is the rtol-1e-6 run (computed once)
    ref = rotorjax_critical(0.25, ref_rtol)
    print(f"reference critical speeds (mu_w = 0.25, rotorjax rtol {ref_rtol:g}):", ref)
    out["reference_critical_speeds"] = ref.tolist()
    variants = {"sweep, 1 device": (rotorjax_map, False), "floquet_batch, 1 device": (batch_map, False)}
    if not args.smoke:  # --smoke: the public paths only (the compiled-once variant is the same vmapped function)
        variants["vmapped, compiled once, 1 device"] = (compiled_map, False)
        variants["sweep with CPU_COMPILER_OPTIONS, 1 device"] = (sweep_options_map, False)
        if n_dev >= 2:  # the batch kernel's own buffer on each host device (no hang, unlike the sweep's)
            variants[f"floquet_batch, shard=True over {n_dev} host devices"] = (batch_map, True)
    if args.shard:  # off by default: see the JSON's "sharded_note"
        variants.update({f"sweep, shard=True over {n_dev} host devices": (rotorjax_map, True),
                         f"vmapped, compiled once, sharded over {n_dev} host devices": (compiled_map, True)})
    out["sharded_note"] = (
        "floquet_batch's sharded variant (each host device its own buffer of lanes, the multipliers computed "
        "afterwards) runs by default; the sweep's sharded variants (--shard) are off by default: with both host "
        "devices running at once, XLA's CPU "
        "runtime hangs (every thread waiting) on this program; reproduced with the monodromy integration followed "
        "by eigvals, while each alone runs (with --xla_cpu_multi_thread_eigen on and off, OPENBLAS_NUM_THREADS=1 "
        "too). One such run finished before the cause was found: 825 points/s against 813 on one device.")
    for rtol in (1e-6,) if args.smoke else (1e-6, 1e-8):
        runs, first_map = {}, None
        for name, (fn, shard) in variants.items():
            watch = CpuWatch()
            m0, first = fn(rtol, shard=shard)
            times = [fn(rtol, shard=shard)[1] for _ in range(args.repeats)] or [first]  # --smoke: one call
            run = float(np.median(times))
            first_map = m0 if first_map is None else first_map
            runs[name] = {"points_per_s": MU_W.size * SPEEDS.size / run, "map_s": run, "first_call_s": first,
                          "repeats": times, "max_margin_difference_to_first_variant":
                          float(np.max(np.abs(m0 - first_map))),
                          "other_cores_busy": watch.report()["other_cores_busy"]}
            print(f"rtol {rtol:.0e} rotorjax [{name}]: {runs[name]['points_per_s']:.0f} points/s "
                  f"({run:.2f} s for the map, first call {first:.1f} s)", flush=True)
        rj_crit = rotorjax_critical(0.25, rtol)
        idx = rng.choice(SPEEDS.size * MU_W.size, size=args.subset, replace=False)
        peers = {}
        for rhs in ("python", "numpy"):
            watch = CpuWatch()
            t0 = time.perf_counter()
            sp = [scipy_margin(SPEEDS[i // MU_W.size], MU_W[i % MU_W.size], rtol, rhs) for i in idx]
            sp_time = time.perf_counter() - t0
            peers[rhs] = {"points_per_s": args.subset / sp_time,
                          "max_margin_difference_on_subset": float(np.max(np.abs(np.array(sp)
                                                                                - first_map.reshape(-1)[idx]))),
                          "other_cores_busy": watch.report()["other_cores_busy"]}
            print(f"  scipy DOP853 ({rhs} rhs): {peers[rhs]['points_per_s']:.1f} points/s", flush=True)
        t0 = time.perf_counter()
        sp_crit = scipy_critical(0.25, rtol)
        sp_crit_time = time.perf_counter() - t0
        c_peer = {}
        if _dop853_001.available():  # the compiled peer on the whole grid
            for th in (1, 2):
                watch = CpuWatch()
                c_dop853_map(rtol, th)  # warm
                walls, (cm, _, ok) = [], (None, None, None)
                for _ in range(max(args.repeats, 1)):
                    cm, wall, ok = c_dop853_map(rtol, th)
                    walls.append(wall)
                wall = float(np.median(walls))
                c_peer[f"{th} thread{'s' if th > 1 else ''}"] = {
                    "points_per_s": MU_W.size * SPEEDS.size / wall, "map_s": wall, "repeats": walls,
                    "all_succeeded": ok, "max_margin_difference_to_sweep": float(np.max(np.abs(cm - first_map))),
                    "other_cores_busy": watch.report()["other_cores_busy"]}
                print(f"  C DOP853 ({th} thread(s)): {c_peer[list(c_peer)[-1]]['points_per_s']:.0f} points/s",
                      flush=True)
            c_crit = scipy_critical(0.25, rtol, margin=c_dop853_margin)

        def err(c):
            return float(np.max(np.abs(c - ref))) if len(c) == len(ref) else float("inf")

        strongest = max(peers, key=lambda k: peers[k]["points_per_s"])
        if c_peer:
            one = "floquet_batch, 1 device"
            two = next((k for k in runs if k.startswith("floquet_batch, shard=True")), one)
            c_target = {"target": ">= 1x the C DOP853 (numbalsoda) on the variational system",
                        "rotorjax_vs_1_thread": one, "rotorjax_vs_2_threads": two,
                        "critical_error": err(c_crit), "critical_speeds": c_crit.tolist(),
                        "ratio_vs_1_thread": runs[one]["points_per_s"] / c_peer["1 thread"]["points_per_s"],
                        "ratio_vs_2_threads": runs[two]["points_per_s"] / c_peer["2 threads"]["points_per_s"]}
            c_target["met"] = c_target["ratio_vs_1_thread"] >= 1 and c_target["ratio_vs_2_threads"] >= 1
        best = max(runs, key=lambda k: runs[k]["points_per_s"])
        best_public = max((k for k in runs if k.startswith(("sweep", "floquet_batch"))),
                          key=lambda k: runs[k]["points_per_s"])
        base = runs["sweep, 1 device"]
        row = {"rtol": rtol, "rotorjax_points_per_s": base["points_per_s"], "rotorjax_map_s": base["map_s"],
               "rotorjax_first_call_s": base["first_call_s"], "variants": runs,
               "scipy_points_per_s": peers[strongest]["points_per_s"], "scipy_peer": strongest, "scipy": peers,
               "speedup": base["points_per_s"] / peers[strongest]["points_per_s"],
               "speedup_vs_numpy_peer": base["points_per_s"] / peers["numpy"]["points_per_s"],
               "max_margin_difference_on_subset": peers[strongest]["max_margin_difference_on_subset"],
               "rotorjax_critical_speeds": rj_crit.tolist(), "rotorjax_critical_error": err(rj_crit),
               "scipy_critical_speeds": sp_crit.tolist(), "scipy_critical_error": err(sp_crit),
               "scipy_critical_s": sp_crit_time, "stable_fraction": float(np.mean(first_map < 0)),
               "floquet_batch_points_per_s": runs["floquet_batch, 1 device"]["points_per_s"],
               "floquet_batch_speedup": runs["floquet_batch, 1 device"]["points_per_s"]
               / peers[strongest]["points_per_s"],
               "c_dop853": c_peer or "not run: numbalsoda missing (pip install numbalsoda)",
               "target_c_dop853": c_target if c_peer else None,
               "target": {"target": ">= 100x the scipy loop on the CPU", "peer": strongest,
                          "public_path": {"variant": best_public,
                                          "ratio": runs[best_public]["points_per_s"] / peers[strongest]["points_per_s"],
                                          "met": runs[best_public]["points_per_s"]
                                          / peers[strongest]["points_per_s"] >= 100},
                          "best_variant": {"variant": best,
                                           "ratio": runs[best]["points_per_s"] / peers[strongest]["points_per_s"],
                                           "met": runs[best]["points_per_s"] / peers[strongest]["points_per_s"] >= 100},
                          "vs_numpy_peer_best_variant": runs[best]["points_per_s"] / peers["numpy"]["points_per_s"]}}
        out["rows"].append(row)
        if c_peer:
            print(f"rtol {rtol:.0e}: floquet_batch {c_target['ratio_vs_1_thread']:.2f}x the C DOP853 loop on 1 "
                  f"thread, {c_target['ratio_vs_2_threads']:.2f}x on 2 [{c_target['rotorjax_vs_2_threads']}] (target "
                  f">= 1x: "
                  f"{'met' if c_target['met'] else 'NOT met'}); its critical-speed error {c_target['critical_error']:.1e}",
                  flush=True)
        tg = row["target"]
        print(f"rtol {rtol:.0e}: strongest scipy peer ({strongest} rhs) {row['scipy_points_per_s']:.1f} points/s; "
              f"public path [{best_public}] {tg['public_path']['ratio']:.1f}x, best [{best}] "
              f"{tg['best_variant']['ratio']:.1f}x (target >= 100x: "
              f"{'met' if tg['public_path']['met'] else 'NOT met'} by the public path); critical-speed error "
              f"rotorjax {row['rotorjax_critical_error']:.1e}, scipy {row['scipy_critical_error']:.1e}", flush=True)
    out["cpu_contention"] = {**whole.report(), "note": "other processes shared this 2-core machine; "
                             "other_cores_busy (per timing too) is their mean load in cores"}
    if args.smoke:
        print("smoke run: nothing written")
        return
    path = os.path.join(os.path.dirname(__file__), "results", "stability_map.json")
    with open(path, "w") as f:
        json.dump({**out, "date": today()}, f, indent=2)
    print(f"wrote {path}")


if __name__ == "__main__":
    main()
