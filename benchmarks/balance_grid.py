"""A grid of periodic motions as one compiled program (issue 30, item 5):
`balance_grid` over speed x cubic bearing stiffness on the scene of
benchmarks/harmonic_balance.py (ROSS's example rotor, 8 modes, cubic bearings at
nodes 0 and 6, unbalance at the disks), harmonic balance with H harmonics.

Along the speed (`p1`, 60..140 rad/s) each point's Newton starts from the previous
point's motion (a slow run-up: on the resonant branch up to its upper fold, then the
jump down); across the stiffness (`p2`, `--k3-range`) the columns are vmapped. One
call, compiled once; timed first (compiling) and warm (median of repeats).

Checked, on the column at the harmonic-balance benchmark's stiffness (3e12 N/m^3):
the run-up's amplitude at each speed equals that of the motion the branch
(`periodic_branch`, continued independently through the folds, each of its motions
at the grid's speeds solved there) has on the run-up's path (the largest one up to
the upper fold, the smallest after it), and the
jump lies between the two grid speeds around the branch's upper fold. Every grid
point's code (0: converged) and time-domain residual (the truncation estimate) are
reported, and a sample of points is re-solved one by one by `harmonic_balance`.

The peer for a grid of steady motions is a brute-force time sweep from rest: its cost
per point at 1e-4 amplitude error is read from benchmarks/results/harmonic_balance.json
(the same scene and machine, measured there against its own reference), and scaled
to the grid's points; it is not rerun here (10 000 points would take hours).

Run: python benchmarks/balance_grid.py [--n 100] [--harmonics 1] [--repeats 2] [--smoke]
Writes benchmarks/results/balance_grid.json (`--smoke`: a 6 x 3 grid, one call; prints,
writes nothing).
"""

import argparse
import json
import os
import sys
import time

import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, HERE)
sys.path.insert(0, os.path.dirname(HERE))

import jax  # noqa: E402
import jax.numpy as jnp  # noqa: E402

from rotorjax.analysis import balance_grid, harmonic_balance, orbit_amplitude, periodic_branch  # noqa: E402
from rotorjax.models import CubicBearing, RotorScene, Unbalance  # noqa: E402
from _common import CpuWatch, machine, timed_first, write_results  # noqa: E402
from harmonic_balance import K3, NODE, build, curve_from_branch  # noqa: E402


def scene_at2(rotor):
    def at(w, k3):
        parts = (Unbalance(2, 2e-3), Unbalance(4, 2e-3), CubicBearing(0, k3), CubicBearing(6, k3))
        return RotorScene(rotor, w, parts)
    return at


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--n", type=int, default=100, help="grid points along each axis")
    ap.add_argument("--harmonics", type=int, default=1)
    ap.add_argument("--k3-range", type=float, nargs=2, default=(1e12, 5e12))
    ap.add_argument("--repeats", type=int, default=2)
    ap.add_argument("--smoke", action="store_true", help="a 6 x 3 grid, one call; print, write nothing")
    args = ap.parse_args()
    n1, n2 = (6, 3) if args.smoke else (args.n, args.n)
    H = args.harmonics
    rotor, _ = build(8)
    at = scene_at2(rotor)
    speeds = jnp.linspace(60.0, 140.0, n1)
    k3s = jnp.linspace(*args.k3_range, n2)
    if not args.smoke:   # the checked column at the harmonic-balance benchmark's stiffness
        k3s = jnp.sort(jnp.concatenate([k3s[:-1], jnp.array([K3])]))
    guess = at(60.0, K3).rest_state()

    def run():
        out = balance_grid(at, speeds, k3s, guess, harmonics=H, node=NODE)
        return jax.block_until_ready(out)

    watch = CpuWatch()
    t_run, t_first, (co, code, tres, amp) = timed_first(run, 1 if args.smoke else args.repeats)
    busy = watch.report()["other_cores_busy"]
    code, tres, amp = np.asarray(code), np.asarray(tres), np.asarray(amp)
    points = n1 * n2
    res = {"grid": [n2, n1], "points": points, "harmonics": H, "first_call_s": t_first, "run_s": t_run,
           "ms_per_point": 1e3 * t_run / points, "not_converged": int(np.sum(code != 0)),
           "time_residual_max": float(np.max(np.where(code == 0, tres, 0.0))), "other_cores_busy": busy}
    print(json.dumps(res, indent=1), flush=True)

    # re-solved one by one at a sample of points, from the grid's own motion
    rng = np.random.default_rng(0)
    sample = [(int(i), int(j)) for i, j in zip(rng.integers(0, n2, 8), rng.integers(0, n1, 8))]
    dev = 0.0
    for i, j in sample:
        sc, T = at(speeds[j], k3s[i]), 2 * jnp.pi / speeds[j]
        s = harmonic_balance(sc, T, co[i, j], harmonics=H, tol=1e-12, stability=False)
        dev = max(dev, abs(float(orbit_amplitude(sc, s.coefficients, T, node=NODE)) / amp[i, j] - 1))
    res["resolved_sample_max_rel_diff"] = dev

    if not args.smoke:   # the column at K3 against the branch
        i = int(np.argmin(np.abs(np.asarray(k3s) - K3)))
        scene_at = lambda w: at(w, K3)  # noqa: E731
        br, cb = periodic_branch(scene_at, 60.0, guess, (60.0, 140.0), harmonics=H, name="speed", max_points=5000)
        fold_hi = max(e.p for e in br.events if e.kind == "fold")
        parts = (Unbalance(2, 2e-3), Unbalance(4, 2e-3), CubicBearing(0, K3), CubicBearing(6, K3))
        w = np.asarray(speeds)
        motions = curve_from_branch(rotor, parts, br, cb, w, H, 1e-12)   # every motion at every speed, solved
        worst = 0.0
        for j in range(n1):
            on = motions["amp"][motions["k"] == j]
            expect = on.max() if w[j] < fold_hi else on.min()
            worst = max(worst, abs(amp[i, j] / expect - 1))
        jump = int(np.argmax(np.abs(np.diff(amp[i]))))
        res["column_check"] = {"k3": float(k3s[i]), "max_rel_diff_to_branch": worst,
                               "branch_upper_fold": fold_hi, "jump_between": [float(w[jump]), float(w[jump + 1])],
                               "jump_brackets_fold": bool(w[jump] <= fold_hi <= w[jump + 1])}
        try:
            with open(os.path.join(HERE, "results", "harmonic_balance.json")) as f:
                hb = json.load(f)["matched"]
            per = hb["bf_s"] / 200
            res["brute_force_estimate"] = {"s_per_point": per, "rtol": hb["bf_rtol"], "t_end": hb["bf_t_end"],
                                           "error": hb["bf_error"], "s_for_grid": per * points,
                                           "ratio": per * points / t_run,
                                           "source": "benchmarks/results/harmonic_balance.json (matched)"}
        except (OSError, KeyError):
            pass
    print(json.dumps({k: v for k, v in res.items() if k in ("resolved_sample_max_rel_diff", "column_check",
                                                                "brute_force_estimate")}, indent=1), flush=True)
    if args.smoke:
        print("smoke run: nothing written")
        return
    write_results("balance_grid", {"benchmark": "balance_grid", "machine": machine(), "smoke": False,
                                   "versions": {"jax": jax.__version__},
                                   "settings": {"scene": "as benchmarks/harmonic_balance.py, cubic stiffness k3 "
                                                         "varied at both bearings", "modes": 8,
                                                "speeds": [60.0, 140.0, n1], "k3": [*args.k3_range, n2],
                                                "amplitude": f"node {NODE} orbit radius (m)",
                                                "repeats": args.repeats},
                                   "grid": res})


if __name__ == "__main__":
    main()
