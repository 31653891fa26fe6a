"""Where a lane-step's time goes: the batch path's cost per lane-step against the
right-hand side's own cost and the machine's arithmetic bound (issue 32, item 3).

Cases, Dopri8, on one core (one host device, XLA's Eigen threads off):
- model 001, the sweep's scene (`benchmarks/sweep_throughput.py`: speeds 0.5..10,
  tau in [0, T_001], rtol 1e-9, atol rtol * 1e-3), 256 speeds, 128 lanes (the sweep's tuned
  buffer on each of its two devices), 8 steps per round;
- the FE rotor of `benchmarks/rotor_scene.py` (ROSS's rotor, an unbalance, two cubic
  bearings, from rest; speeds 100..200 rad/s, [0, T_FE] s, rtol 1e-8, atol rtol *
  1e-4) reduced to 8 modes, and full (28 dofs), 64 lanes.

Per case:
- `lane_step_us`: `simulate_batch`'s wall time (its default method, the vectorised
  stepper; compiled first, the best of repeats, as every timing here) over the
  lane-steps taken (accepted and rejected);
- `step_us`: the vectorised stepper's `stages` alone (one Dopri8 step of every lane:
  13 right-hand sides, the 14th stage carried, and the stage sums, which XLA fuses
  with them) in a compiled loop, per lane; the rest of a lane-step (`lane_step_us -
  step_us`) is step-size control, dense output, retiring and refilling lanes;
- `rhs_us_by_lanes`: one evaluation of the vector field over 8, 32, 128 and 512 lanes,
  as the stepper calls it (structure of arrays, the matrices equal at every point
  applied to all lanes at once), in a compiled loop, per lane: what a call costs
  whatever its width (XLA's CPU runtime runs each fused kernel as its own call) shows
  as the per-lane cost falling with the lanes;
- `flops_per_lane_step`: XLA's cost analysis of one right-hand side over the lanes
  (per lane) times 13, plus the stage sums counted from the tableau (2 s n per
  stage, s = 14 stages, n states; the solution and error sums); the arithmetic bound:
  those flops over one core's double-precision peak (`peak`: the clock times the
  flops per cycle of its vector FMA units, the basis recorded);
- the peer: the numba right-hand side's cost per evaluation (the one the C DOP853 loop
  calls: model 001's `numba_rhs_ns`; the FE rotor's `rotor_scene` peer), and, for the
  FE rotor, the numba-compiled DOP853's cost per step (time over its steps, one
  thread; numbalsoda does not return model 001's step count).

Run: python benchmarks/step_cost.py [--smoke] [--repeats 5]
Writes benchmarks/results/step_cost.json (`--smoke`: model 001 only, 4 lanes, a short
span, one call per timing; prints, writes nothing).
"""

import argparse
import os
import re
import sys
import time

os.environ.setdefault("XLA_FLAGS", "--xla_cpu_multi_thread_eigen=false intra_op_parallelism_threads=1")
sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))

import numpy as np  # noqa: E402

from _common import machine, today, write_results  # noqa: E402

T_001, RTOL_001, LANES_001, SPR = 200.0, 1e-9, 128, 8
T_FE, RTOL_FE, LANES_FE = 0.5, 1e-8, 64
N_001, N_FE = 256, 64
LOOP = 50          # evaluations (steps) per compiled timing loop
RHS_LANES = (8, 32, 128, 512)  # the right-hand side alone over this many lanes: its fixed cost per call


def peak():
    """One core's double-precision peak from /proc/cpuinfo: clock x flops per cycle.
    AVX-512 or AVX2 with FMA: two 256-bit FMA pipes (4 doubles x 2 flops x 2 pipes = 16
    flops a cycle: AMD Zen 2-4, which runs AVX-512 on 256-bit units, and Intel client
    cores since Haswell; Intel's server cores with two 512-bit pipes reach 32, not
    assumed); otherwise SSE2, 4."""
    try:
        text = open("/proc/cpuinfo").read()
    except OSError:
        return None
    mhz = [float(m) for m in re.findall(r"cpu MHz\s*:\s*([0-9.]+)", text)]
    m = re.search(r"^flags\s*:\s*(.*)$", text, re.M)
    flags = set(m.group(1).split()) if m else set()
    m = re.search(r"^model name\s*:\s*(.*)$", text, re.M)
    name = m.group(1).strip() if m else "unknown"
    if not mhz:
        return None
    per_cycle, basis = ((16, "two 256-bit FMA pipes (AVX2/AVX-512 with FMA)") if "fma" in flags and "avx2" in flags
                        else (4, "SSE2: one add and one multiply of 2 doubles"))
    ghz = max(mhz) / 1e3
    return {"cpu": name, "clock_ghz": ghz, "flops_per_cycle": per_cycle, "basis": basis,
            "gflops_per_core": ghz * per_cycle}


def timed(fn, repeats):
    """`(best s, first-call s, output)`: the fastest of `repeats` calls after a first,
    compiling one (a cost breakdown on a shared machine: the least disturbed call)."""
    import jax

    t0 = time.perf_counter()
    out = jax.block_until_ready(fn())
    first = time.perf_counter() - t0
    ts = []
    for _ in range(repeats):
        t0 = time.perf_counter()
        out = jax.block_until_ready(fn())
        ts.append(time.perf_counter() - t0)
    return float(min(ts or [first])), first, out


# ----------------------------------------------------------------------------- cases
def model001(n_points, lanes, t_end):
    import equinox as eqx
    import jax.numpy as jnp

    from rotorjax.bench._model001 import _sweep_problem
    from rotorjax.presets import anisotropic_abb as ab

    _, groups, y0 = _sweep_problem(RTOL_001, t_end)
    k = dict(ab.PRESET.defaults)["K"]
    speeds = np.linspace(0.5, 10.0, n_points)
    scenes = eqx.filter_vmap(lambda n: ab.scene_from_groups(**groups, n=n, K=k))(jnp.asarray(speeds))
    return {"scenes": scenes, "n": n_points, "y0": np.asarray(y0), "span": (0.0, t_end), "rtol": RTOL_001,
            "atol": RTOL_001 * 1e-3, "lanes": lanes, "points": f"{n_points} speeds 0.5..10"}


def fe_rotor(n_modes, n_points, lanes, t_end):
    import equinox as eqx
    import jax.numpy as jnp

    from rotor_scene import ATOL_PER_RTOL, build_scene

    scene = build_scene(n_modes)
    speeds = np.linspace(100.0, 200.0, n_points)
    scenes = eqx.filter_vmap(lambda w: eqx.tree_at(lambda sc: sc.speed.constant, scene, w))(jnp.asarray(speeds))
    return {"scenes": scenes, "n": n_points, "y0": np.asarray(scene.rest_state()), "span": (0.0, t_end), "rtol": RTOL_FE,
            "atol": RTOL_FE * ATOL_PER_RTOL, "lanes": lanes, "points": f"{n_points} speeds 100..200 rad/s"}


# ----------------------------------------------------------------------------- measures
def lanes_kernel(scenes, lanes):
    """`(field, scene_t)`: the vector field over lanes as the vectorised stepper calls
    it (`field(scene_t, t, Y)`, `Y[state, lane]`, the leaves equal at every point
    unbatched) and the first `lanes` points' varying leaves, lanes last."""
    import equinox as eqx
    import jax
    import jax.numpy as jnp

    from rotorjax.solve._batch import _split_shared
    from rotorjax.solve._vectorised import field_over_lanes

    varying, shared = _split_shared(scenes)
    arrays, static = eqx.partition(varying, eqx.is_array)
    scene_t = jax.tree_util.tree_map(lambda a: jnp.moveaxis(a[:lanes], 0, -1), arrays)
    return field_over_lanes(lambda a, t, y: eqx.combine(a, shared, static).vector_field(t, y)), scene_t


def count_flops(field, scene_t, T, Y, tab):
    """`(right-hand side flops, step flops, transcendentals)` per lane: XLA's cost
    analysis of one right-hand side over the lanes (`Y[lane, state]`), times the
    evaluations a step makes, plus the stage sums counted from the tableau (a
    stage's sum over all `s` stages, 2 s n, and its update, 2 n; the solution and
    error sums). XLA counts a while loop's body once, so the step's own analysis
    would undercount."""
    import jax

    lanes, n_state = Y.shape
    ca = jax.jit(lambda Y: field(scene_t, T, Y)).lower(Y.T).compile().cost_analysis()
    ca = ca[0] if isinstance(ca, list) else ca
    evals = tab.stages - 1 if tab.fsal else tab.stages
    rhs = float(ca["flops"]) / lanes
    sums = (evals * (2 * tab.stages + 2) + 2 * (2 * tab.stages + 2)) * n_state
    return rhs, evals * rhs + sums, float(ca.get("transcendentals", 0.0)) / lanes


def measure(case, repeats):
    """The lane-step, the step alone, the right-hand side alone, their flops."""
    import diffrax
    import jax
    import jax.numpy as jnp

    from rotorjax.solve import simulate_batch
    from rotorjax.solve._vectorised import Tableau, stages

    scenes, lanes = case["scenes"], case["lanes"]
    n = case["n"]
    y0s = jnp.tile(jnp.asarray(case["y0"]), (n, 1))

    def run():
        r = simulate_batch(scenes, y0s, case["span"], solver="dopri8", rtol=case["rtol"], atol=case["atol"],
                           lanes=lanes, steps_per_round=SPR, max_steps=1_000_000)
        return r.ys, r.stats["num_steps"], r.code, r.solver
    t_batch, first, (ys, steps, code, how) = timed(run, repeats)
    if np.any(np.asarray(code) != 0):
        raise FloatingPointError(f"{case['points']}: {int(np.sum(np.asarray(code) != 0))} point(s) failed")
    lane_steps = int(np.sum(np.asarray(steps)))

    # the kernel's pieces on the first `lanes` points, at their final states
    field, scene_t = lanes_kernel(scenes, lanes)
    tab = Tableau(diffrax.Dopri8())
    Y = jnp.asarray(ys)[:lanes, -1]                       # [lanes, state]
    T = jnp.full((lanes,), case["span"][1])
    H = jnp.full((lanes,), (case["span"][1] - case["span"][0]) / (lane_steps / n))  # the mean step
    F0 = field(scene_t, T, Y.T).T

    def rhs_per_lane(k):
        """One right-hand side over `k` lanes (the first lanes repeated), per lane, us."""
        idx = np.arange(k) % lanes
        sk = jax.tree_util.tree_map(lambda a: a[..., idx], scene_t)
        Yk, Tk = Y.T[:, idx], T[idx]
        loop = jax.jit(lambda Y: jax.lax.fori_loop(0, LOOP, lambda i, Y: Y + 1e-12 * field(sk, Tk, Y), Y))
        return timed(lambda: loop(Yk), max(repeats, 1))[0] / LOOP / k * 1e6

    step_loop = jax.jit(lambda y: jax.lax.fori_loop(0, LOOP, lambda i, y: stages(tab, field, scene_t, T, H, y,
                                                                                   F0)[0], y))
    t_step, _, _ = timed(lambda: step_loop(Y), max(repeats, 1))
    evals = tab.stages - 1 if tab.fsal else tab.stages
    n_state = Y.shape[1]
    rhs_flops, step_flops, transcendentals = count_flops(field, scene_t, T, Y, tab)
    by_lanes = {str(k): rhs_per_lane(k) for k in sorted(set(RHS_LANES) | {lanes})}
    out = {"points": case["points"], "state_size": int(n_state), "lanes": lanes, "steps_per_round": SPR,
           "span": list(case["span"]), "rtol": case["rtol"], "atol": case["atol"], "method": how,
           "lane_steps": lane_steps, "batch_s": t_batch, "first_call_s": first,
           "lane_step_us": t_batch / lane_steps * 1e6, "step_us": t_step / LOOP / lanes * 1e6,
           "rhs_us": by_lanes[str(lanes)], "rhs_us_by_lanes": by_lanes,
           "rhs_evals_per_step": evals, "rhs_flops": rhs_flops,
           "rhs_transcendentals": transcendentals, "flops_per_lane_step": step_flops}
    # the step (right-hand sides and stage sums, not separable: XLA fuses a stage's sum
    # into its right-hand side) and the rest of the lane-step; the right-hand sides
    # alone for comparison
    out["split_us"] = {"step": out["step_us"],
                       "control_dense_output_and_buffer": max(out["lane_step_us"] - out["step_us"], 0.0)}
    out["rhs_alone_per_step_us"] = evals * out["rhs_us"]
    return out


def bound(out, pk):
    if pk is not None:
        out["arithmetic_bound_us"] = out["flops_per_lane_step"] / (pk["gflops_per_core"] * 1e3)
        out["fraction_of_peak"] = out["arithmetic_bound_us"] / out["lane_step_us"]
        out["rhs_fraction_of_peak"] = out["rhs_flops"] / (pk["gflops_per_core"] * 1e3) / out["rhs_us"]
    return out


def peer_001(case):
    from rotorjax.bench._numba001 import numba_rhs_ns
    from rotorjax.presets import anisotropic_abb as ab

    p = dict(ab.PRESET.defaults)
    return {"numba_rhs_us": numba_rhs_ns(p, case["y0"]) / 1e3,
            "note": "the numba right-hand side the C DOP853 loop (numbalsoda) calls, per evaluation"}


def peer_fe(n_modes, t_end, nb=None):
    """The rotor_scene peer: its numba right-hand side per evaluation, and its
    numba-compiled DOP853 per step (one thread, 8 speeds)."""
    import rotor_scene as rs

    nb = nb or rs.make_numba()
    pm = rs.PeerModel(rs.build_scene(n_modes))
    y0 = np.zeros(2 * pm.ns)
    L, W, E6, g0, coef = pm.params(150.0)
    k = 20_000
    nb["rhs_loop"](y0, 10, L, W, E6, g0, coef)
    t0 = time.perf_counter()
    nb["rhs_loop"](y0, k, L, W, E6, g0, coef)
    rhs_us = (time.perf_counter() - t0) / k * 1e6
    nb["dop853"](y0, 0.0, 1e-3, RTOL_FE, RTOL_FE * rs.ATOL_PER_RTOL, L, W, E6, g0, coef, 10**7)
    t0, steps = time.perf_counter(), 0
    for w in np.linspace(100.0, 200.0, 8):
        L, _, _, _, coef = pm.params(w)
        _, st, _, _ = nb["dop853"](y0, 0.0, t_end, RTOL_FE, RTOL_FE * rs.ATOL_PER_RTOL, L, W, E6, g0, coef, 10**7)
        steps += int(st)
    return {"numba_rhs_us": rhs_us, "numba_dop853_step_us": (time.perf_counter() - t0) / steps * 1e6,
            "note": "the rotor_scene peer: its numba right-hand side per evaluation (the matrices formed per "
                    "speed, M^-1 applied before the run), scipy's DOP853 compiled whole with numba, per step"}


def table(out):
    rows = ["| case (lanes) | lane-step | the step: stages and sums | control, dense output, buffer | "
            "one right-hand side per lane: 8 / 32 / 128 / 512 lanes (numba) | flops / lane-step | "
            "arithmetic bound | of peak |",
            "|---|---|---|---|---|---|---|---|"]
    for label, c in out["cases"].items():
        s = c["split_us"]
        by = " / ".join(f"{c['rhs_us_by_lanes'][str(k)] * 1e3:.0f}" for k in RHS_LANES)
        rows.append(f"| {label} ({c['lanes']}) | {c['lane_step_us']:.2f} us | {s['step']:.2f} us | "
                    f"{s['control_dense_output_and_buffer']:.2f} us | {by} ns ({c['peer']['numba_rhs_us'] * 1e3:.0f} "
                    f"ns) | {c['flops_per_lane_step']:.3g} | {c['arithmetic_bound_us']:.2f} us | "
                    f"{100 * c['fraction_of_peak']:.1f}% |")
    return "\n".join(rows)


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--smoke", action="store_true", help="model 001 only, 4 lanes, a short span; write nothing")
    ap.add_argument("--repeats", type=int, default=5)
    ap.add_argument("--table", action="store_true", help="print the README's table from the stored JSON")
    args = ap.parse_args()
    if args.table:
        import json

        with open(os.path.join(os.path.dirname(os.path.abspath(__file__)), "results", "step_cost.json")) as f:
            print(table(json.load(f)))
        return
    import jax

    jax.config.update("jax_enable_x64", True)
    t_start = time.perf_counter()
    pk = peak()
    repeats = 0 if args.smoke else args.repeats
    out = {"benchmark": "step_cost: where a lane-step's time goes", "date": today(), "machine": machine(),
           "peak": pk, "loop_evaluations": LOOP, "cases": {}}
    if args.smoke:
        cases = {"model 001": (model001(8, 4, 2.0), peer_001)}
    else:
        cases = {"model 001": (model001(N_001, LANES_001, T_001), peer_001),
                 "FE rotor, 8 modes": (fe_rotor(8, N_FE, LANES_FE, T_FE), lambda c: peer_fe(8, T_FE)),
                 "FE rotor, full (28 dofs)": (fe_rotor(None, N_FE, LANES_FE, T_FE), lambda c: peer_fe(None, T_FE))}
    for label, (case, peer) in cases.items():
        res = bound(measure(case, repeats), pk)
        res["peer"] = peer(case)
        out["cases"][label] = res
        print(f"{label}: {res['lane_step_us']:.2f} us per lane-step = step {res['split_us']['step']:.2f} + rest "
              f"{res['split_us']['control_dense_output_and_buffer']:.2f} (13 right-hand sides alone "
              f"{res['rhs_alone_per_step_us']:.2f}); one RHS per lane by lanes {res['rhs_us_by_lanes']} us "
              f"(numba {res['peer']['numba_rhs_us'] * 1e3:.0f} ns); bound "
              f"{res.get('arithmetic_bound_us', float('nan')):.3f} us "
              f"({100 * res.get('fraction_of_peak', float('nan')):.1f}% of peak)", flush=True)
    out["total_wall_s"] = time.perf_counter() - t_start
    if args.smoke:
        print("smoke run: nothing written")
        return
    print(table(out))
    write_results("step_cost", out)


if __name__ == "__main__":
    main()
