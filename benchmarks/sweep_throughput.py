"""Model 001 sweep throughput: rotorjax vmapped sweep vs scipy loop vs numba RK4.

1000 speeds n in [0.5, 10], tau in [0, 200], from the preset's perturbed main motion.
Errors are max |final state - reference| over the well-conditioned speeds of an
evaluation subset (a speed is ill-conditioned when two tight references, rotorjax
Dopri8 at rtol 1e-13 and scipy DOP853 at rtol 1e-13, disagree by more than 1e-9:
shared/PERFORMANCE.md finds ~9% of speeds, near n = 7.2-8.2, so).

Peers are compared at matched error: scipy (DOP853, LSODA) and numba RK4 are run on
a ladder of tolerances / step counts, and their cost at rotorjax's error is
interpolated in log-log. scipy is timed on the evaluation subset (a Python loop is
linear in the number of speeds) and reported as throughput (speeds per second).

Run: python benchmarks/sweep_throughput.py [--n-speeds 1000] [--subset 40]
Writes benchmarks/results/sweep_throughput.json.
"""

import argparse
import json
import os
import platform
import sys
import time

import numpy as np

# Two host devices, so that the sharded variant can use both cores (must precede jax).
os.environ.setdefault("XLA_FLAGS", "--xla_force_host_platform_device_count=2")
sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))

import jax  # noqa: E402

import rotorjax as rj  # noqa: E402
from rotorjax.models import Scene  # noqa: E402
from rotorjax.presets import anisotropic_abb  # noqa: E402
import peers_001  # noqa: E402

P = dict(anisotropic_abb.PRESET.defaults)
GROUPS = {k: P[k] for k in anisotropic_abb.GROUPS}
T_END = 200.0


def initial_state():
    setup = anisotropic_abb.PRESET.build(P)
    scene, y0 = setup.scene, setup.y0
    return np.asarray(y0)


def rotorjax_sweep(speeds, y0, rtol, chunk_size, solver="dopri8", equations="auto", shard=False):
    def one(point):
        scene = anisotropic_abb.scene_from_groups(**GROUPS, n=point["n"], K=P["K"])
        if equations != "auto":
            scene = Scene(scene.rotor, scene.speed, scene.components, equations=equations)
        r = rj.simulate(scene, y0, (0.0, T_END), solver=solver, rtol=rtol, atol=rtol * 1e-3,
                        max_steps=1_000_000)
        return {"y": r.ys[-1], "code": r.code, "steps": r.stats["num_steps"]}

    t0 = time.perf_counter()
    res = rj.sweep(one, {"n": speeds}, chunk_size=chunk_size, progress=False, shard=shard)
    return res, time.perf_counter() - t0


def timed_rotorjax(speeds, y0, rtol, chunk_size, repeats, **kw):
    first, t_first = rotorjax_sweep(speeds, y0, rtol, chunk_size, **kw)
    times = [rotorjax_sweep(speeds, y0, rtol, chunk_size, **kw)[1] for _ in range(repeats)]
    run = float(np.median(times))
    return first, {"run_s": run, "first_call_s": t_first, "compile_s_estimate": t_first - run,
                   "repeats": times}


def error(final, ref, mask):
    return float(np.max(np.abs(final[mask] - ref[mask])))


def interpolate_cost(errors, costs, target):
    """Cost at `target` error by log-log interpolation over a ladder (monotone part)."""
    e, c = np.log(np.asarray(errors)), np.log(np.asarray(costs))
    order = np.argsort(e)
    e, c = e[order], c[order]
    t = np.log(target)
    if t <= e[0]:
        return float(np.exp(c[0])), "extrapolated: peer never reached this error"
    if t >= e[-1]:
        return float(np.exp(c[-1])), "clamped at loosest peer setting"
    return float(np.exp(np.interp(t, e, c))), "interpolated"


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--n-speeds", type=int, default=1000)
    ap.add_argument("--subset", type=int, default=40)
    ap.add_argument("--repeats", type=int, default=3)
    ap.add_argument("--chunk", type=int, default=50)
    ap.add_argument("--out", default=os.path.join(os.path.dirname(__file__), "results",
                                                  "sweep_throughput.json"))
    args = ap.parse_args()

    speeds = np.linspace(0.5, 10.0, args.n_speeds)
    y0 = initial_state()
    rng = np.random.default_rng(0)
    sub = np.sort(rng.choice(args.n_speeds, size=args.subset, replace=False))
    p = dict(GROUPS)

    print("reference on the subset: rotorjax Dopri8 rtol 1e-13 and scipy DOP853 rtol 1e-13")
    ref_res, _ = rotorjax_sweep(speeds[sub], y0, 1e-13, args.chunk)
    ref_sub = ref_res["y"]
    ref_scipy, _, _ = peers_001.scipy_loop(speeds[sub], y0, T_END, p, "DOP853", 1e-13, 1e-15)
    cond = np.max(np.abs(ref_sub - ref_scipy), axis=1) < 1e-9
    print(f"  well-conditioned: {cond.sum()} of {cond.size} subset speeds")

    results = {"rotorjax": {}, "scipy": {}, "numba": {}}
    # scipy ladders on the subset
    for method in ("DOP853", "LSODA"):
        ladder = []
        for rtol in (1e-5, 1e-6, 1e-7, 1e-8, 1e-9, 1e-10, 1e-11):
            fin, wall, failed = peers_001.scipy_loop(speeds[sub], y0, T_END, p, method, rtol,
                                                     rtol * 1e-3)
            ladder.append({"rtol": rtol, "error": error(fin, ref_sub, cond),
                           "s_per_speed": wall / len(sub), "failed": int(failed)})
            print(f"  scipy {method} rtol {rtol:.0e}: err {ladder[-1]['error']:.2e}, "
                  f"{ladder[-1]['s_per_speed'] * 1e3:.1f} ms/speed")
        results["scipy"][method] = ladder
    # numba ladder (all speeds, 1 and 2 threads); one untimed call first warms the
    # thread pool, whose start-up otherwise lands in the first timing.
    peers_001.numba_rk4(speeds, y0, T_END, p, 1000, threads=2)
    for threads in (1, 2):
        ladder = []
        for n_steps in (20_000, 40_000, 80_000, 160_000):
            fin, wall = peers_001.numba_rk4(speeds, y0, T_END, p, n_steps, threads=threads)
            walls = [wall] + [peers_001.numba_rk4(speeds, y0, T_END, p, n_steps, threads)[1]
                              for _ in range(args.repeats - 1)]
            ladder.append({"n_steps": n_steps, "error": error(fin[sub], ref_sub, cond),
                           "s_per_speed": float(np.median(walls)) / len(speeds)})
            print(f"  numba RK4 {threads} thr, {n_steps} steps: err {ladder[-1]['error']:.2e}, "
                  f"{ladder[-1]['s_per_speed'] * 1e3:.3f} ms/speed")
        results["numba"][f"{threads}_threads"] = ladder

    table = []
    variants = {
        "fast path": {},
        f"fast path, sharded over {len(jax.local_devices())} host devices": {"shard": True},
        "Lagrangian path (autodiff)": {"equations": "lagrange"},
    }
    for rtol in (1e-6, 1e-9):
        for vname, kw in variants.items():
            res, timing = timed_rotorjax(speeds, y0, rtol, args.chunk, args.repeats, **kw)
            err = error(res["y"][sub], ref_sub, cond)
            per = timing["run_s"] / len(speeds)
            row = {"variant": vname, "rtol": rtol, "error": err, "s_per_speed": per,
                   "failed": int(np.sum(res["code"] != 0)),
                   "steps_mean": float(np.mean(res["steps"])), "steps_max": int(np.max(res["steps"])),
                   **timing}
            results["rotorjax"][f"{vname} rtol {rtol:.0e}"] = row
            print(f"rotorjax Dopri8 [{vname}] rtol {rtol:.0e}: err {err:.2e}, {per * 1e3:.3f} ms/speed "
                  f"(first call {timing['first_call_s']:.1f} s incl. compile)")
            for name, ladder in [("scipy DOP853", results["scipy"]["DOP853"]),
                                 ("scipy LSODA", results["scipy"]["LSODA"]),
                                 ("numba RK4 1 thread", results["numba"]["1_threads"]),
                                 ("numba RK4 2 threads", results["numba"]["2_threads"])]:
                cost, how = interpolate_cost([r["error"] for r in ladder],
                                             [r["s_per_speed"] for r in ladder], err)
                table.append({"rotorjax_variant": vname, "rotorjax_rtol": rtol, "error": err,
                              "peer": name, "peer_s_per_speed": cost, "rotorjax_s_per_speed": per,
                              "rotorjax_speedup": cost / per, "match": how})

    print("\nspeed vs error (throughput ratio rotorjax / peer at rotorjax's error):")
    print(f"{'rotorjax variant':<42} {'rtol':>6} {'error':>9} {'peer':<22} {'peer ms/speed':>14} "
          f"{'rotorjax ms/speed':>18} {'ratio':>7}")
    for r in table:
        print(f"{r['rotorjax_variant']:<42} {r['rotorjax_rtol']:>6.0e} {r['error']:>9.2e} {r['peer']:<22} "
              f"{r['peer_s_per_speed'] * 1e3:>14.3f} {r['rotorjax_s_per_speed'] * 1e3:>18.3f} "
              f"{r['rotorjax_speedup']:>7.2f}  {r['match']}")

    out = {
        "benchmark": "sweep_throughput (model 001)",
        "machine": {"platform": platform.platform(), "processor": platform.processor(),
                    "cpu_count": os.cpu_count(), "jax_backend": jax.default_backend(),
                    "devices": [str(d) for d in jax.devices()]},
        "versions": {"jax": jax.__version__, "python": platform.python_version(),
                     "numpy": np.__version__, "numba": peers_001.numba.__version__},
        "sizes": {"n_speeds": args.n_speeds, "subset": args.subset, "t_end": T_END,
                  "chunk_size": args.chunk, "well_conditioned_in_subset": int(cond.sum())},
        "params": P,
        "rhs_ns_numba": peers_001.numba_rhs_ns(dict(p, n=5.0), y0),
        "results": results,
        "table": table,
    }
    os.makedirs(os.path.dirname(args.out), exist_ok=True)
    with open(args.out, "w") as f:
        json.dump(out, f, indent=2)
    print(f"wrote {args.out}")


if __name__ == "__main__":
    main()
