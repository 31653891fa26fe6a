"""The batch kernels on an accelerator, in one command (issue 32, item 5).

    python benchmarks/gpu_batch.py            # on the machine's default JAX device

Model 001's sweep scene (`benchmarks/sweep_throughput.py`: speeds 0.5..10, tau in
[0, T_END], Dopri8, rtol 1e-9, atol rtol * 1e-3), as many points as lanes (1e3, 1e4,
1e5 on a GPU; 1e3 on a CPU unless `--lanes` says otherwise), through `simulate_batch`
with each of the two kernels `sweep(batch=...)` selects for an accelerator:
- "vectorised": every lane stepped together as arrays of lanes (all lanes in one
  buffer, 8 steps per round);
- "pallas": the whole adaptive loop of a block of lanes in one Pallas kernel
  (compiled on a GPU; interpret mode elsewhere, where it is a correctness path, not
  a fast one).
Per kernel and size: the wall time (a compiling call first, then the best of
`--repeats`), trajectories per second, lane-steps taken, flops (lane-steps x the
flops of a lane-step, counted as `benchmarks/step_cost.py` counts them: XLA's cost
analysis of the right-hand side, the stage sums from the tableau), the achieved
GFLOP/s and its fraction of the device's double-precision peak: a GPU's from the
table `FP64_PEAK` (vector units, not tensor cores: the kernels are elementwise),
matched on the device's name (`null` where the name is not in it); a CPU's, all its
cores, as step_cost's `peak`. The two kernels' final states are compared point by
point (median, 90th percentile and largest difference, each relative to the point's
largest state component). A kernel that fails to compile
or run is recorded with its error, not fatal: the Pallas kernel has not been
compiled for a GPU before.

Writes benchmarks/results/gpu_batch_<backend>.json (`--smoke`: 8 lanes, a short
span, one call each; prints, writes nothing). No GPU figure exists until this runs on
one; the JSON says which device measured it.
"""

import argparse
import os
import sys

os.environ.setdefault("XLA_FLAGS", "")  # the device's defaults (step_cost pins one CPU thread)
sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))

import numpy as np  # noqa: E402

from _common import machine, today, write_results  # noqa: E402

T_END, RTOL = 200.0, 1e-9
GPU_LANES, CPU_LANES = (1_000, 10_000, 100_000), (1_000,)
SPR = 8
METHODS = ("vectorised", "pallas")
#: double-precision peaks of the vector units, FLOP/s, by a piece of the device's name
#: (vendors' data sheets; H100 SXM, the PCIe card 26 TFLOP/s)
FP64_PEAK = (("H100 PCIe", 25.6e12), ("H200", 34e12), ("H100", 34e12), ("A100", 9.7e12), ("V100", 7.8e12),
             ("L40", 1.4e12), ("A10", 0.98e12), ("T4", 0.25e12))


def device_peak(device):
    """`(FLOP/s or None, basis)` for `device` (a JAX device)."""
    if device.platform == "cpu":
        import step_cost

        pk = step_cost.peak()
        if pk is None:
            return None, "unknown CPU"
        cores = os.cpu_count() or 1
        return pk["gflops_per_core"] * 1e9 * cores, f"{cores} cores x {pk['gflops_per_core']:.1f} GFLOP/s ({pk['basis']})"
    name = getattr(device, "device_kind", "")
    for key, flops in FP64_PEAK:
        if key in name:
            return flops, f"{key}: FP64 vector units, data sheet"
    return None, f"{name}: not in the table"


def flops_per_lane_step(scenes, y0):
    import diffrax
    import jax.numpy as jnp
    import step_cost
    from rotorjax.solve._vectorised import Tableau

    lanes = 4
    field, scene_t = step_cost.lanes_kernel(scenes, lanes)
    Y = jnp.tile(jnp.asarray(y0), (lanes, 1))
    return step_cost.count_flops(field, scene_t, jnp.zeros((lanes,)), Y, Tableau(diffrax.Dopri8()))[1]


def run_kernel(method, scenes, y0s, t_end, repeats):
    import jax

    from rotorjax.solve import simulate_batch

    def once():
        kw = dict(lanes=y0s.shape[0], steps_per_round=SPR) if method == "vectorised" else {}
        r = simulate_batch(scenes, y0s, (0.0, t_end), solver="dopri8", rtol=RTOL, atol=RTOL * 1e-3,
                           max_steps=1_000_000, method=method, **kw)
        return jax.block_until_ready((r.ys[:, -1], r.code, r.stats["num_steps"]))

    import step_cost

    s, first, out = step_cost.timed(once, repeats)
    return s, first, [np.asarray(x) for x in out]


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--smoke", action="store_true", help="8 lanes, a short span, one call each; write nothing")
    ap.add_argument("--lanes", type=int, nargs="+", help="lane counts (default: 1e3 1e4 1e5 on a GPU, 1e3 on a CPU)")
    ap.add_argument("--repeats", type=int, default=3)
    args = ap.parse_args()
    import jax

    jax.config.update("jax_enable_x64", True)
    import step_cost

    device = jax.devices()[0]
    backend = device.platform
    lanes_list = [8] if args.smoke else args.lanes or (GPU_LANES if backend == "gpu" else CPU_LANES)
    t_end = 2.0 if args.smoke else T_END
    repeats = 0 if args.smoke else args.repeats
    peak, basis = device_peak(device)
    out = {"benchmark": "gpu_batch: the batch kernels over lanes", "date": today(), "machine": machine(),
           "device": {"platform": backend, "kind": getattr(device, "device_kind", ""), "fp64_peak_flops": peak,
                      "peak_basis": basis},
           "setup": {"scene": "model 001 (anisotropic_abb), speeds 0.5..10", "t_end": t_end, "rtol": RTOL,
                     "atol": RTOL * 1e-3, "solver": "dopri8", "steps_per_round": SPR, "repeats": repeats},
           "gpu_figure": ("measured here" if backend == "gpu" else
                          "none: no GPU measured this; these are the CPU's numbers"),
           "runs": []}
    for lanes in lanes_list:
        case = step_cost.model001(lanes, lanes, t_end)
        y0s = np.tile(case["y0"], (lanes, 1))
        fl = flops_per_lane_step(case["scenes"], case["y0"])
        finals = {}
        for method in METHODS:
            row = {"lanes": lanes, "method": method}
            try:
                s, first, (y, code, steps) = run_kernel(method, case["scenes"], y0s, t_end, repeats)
            except Exception as e:  # noqa: BLE001 - a kernel that does not compile here is recorded
                row["failed"] = f"{type(e).__name__}: {str(e)[:800]}"
                print(f"{lanes} lanes, {method}: FAILED {row['failed'][:200]}", flush=True)
                out["runs"].append(row)
                continue
            lane_steps = int(steps.sum())
            achieved = lane_steps * fl / s
            row.update({"s": s, "first_call_s": first, "trajectories_per_s": lanes / s, "lane_steps": lane_steps,
                        "points_failed": int(np.sum(code != 0)), "flops_per_lane_step": fl,
                        "achieved_gflops": achieved / 1e9,
                        "fraction_of_peak": None if peak is None else achieved / peak})
            finals[method] = y
            out["runs"].append(row)
            print(f"{lanes} lanes, {method}: {s:.3f} s, {lanes / s:.0f} trajectories/s, {achieved / 1e9:.2f} GFLOP/s"
                  + ("" if peak is None else f" ({100 * achieved / peak:.2f}% of the peak)"), flush=True)
        if len(finals) == 2:
            # per point: the largest difference over its largest state component
            d = (np.max(np.abs(finals["vectorised"] - finals["pallas"]), axis=1)
                 / np.max(np.abs(finals["pallas"]), axis=1))
            diff = {"median": float(np.median(d)), "p90": float(np.quantile(d, 0.9)), "max": float(np.max(d)),
                    "note": "per point, relative to its largest state component; model 001's ill-conditioned "
                            "speeds amplify a step's rounding over the span (shared/PERFORMANCE.md), so the "
                            "largest differences are theirs"}
            for row in out["runs"][-2:]:
                row["kernels_differ_by"] = diff
    if args.smoke:
        print("smoke run: nothing written")
        return
    write_results(f"gpu_batch_{backend}", out)


if __name__ == "__main__":
    main()
