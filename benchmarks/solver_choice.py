"""Explicit vs implicit on model 000 as the balls' drag delta_b grows: where does
Kvaerno5 start to pay? Sets rotorjax.solve.STIFFNESS_THRESHOLD.

Run: python benchmarks/solver_choice.py [--smoke]; writes benchmarks/results/solver_choice.json
(`--smoke`: the mildest and stiffest drag, t = 10, 20 000 steps at most, one call each; prints, writes nothing).
"""

import argparse
import json
import os
import platform
import sys

import jax
import numpy as np

import rotorjax as rj
from rotorjax import presets

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from _common import timed_first  # noqa: E402

T_END = 300.0


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--smoke", action="store_true", help="two drags, t = 10, one call each; print, write nothing")
    args = ap.parse_args()
    t_end = 10.0 if args.smoke else T_END
    max_steps = 20_000 if args.smoke else 200_000
    repeats = 0 if args.smoke else 3  # --smoke: the first call only
    preset = presets.get("elliptic-abb")
    rows = []
    for delta_b in (40.0, 40000.0) if args.smoke else (40.0, 400.0, 4000.0, 40000.0):
        p = preset.params({"rho1": 1.0, "rho2": 1.0, "eps": 0.03, "psi1": 1.0,
                           "psi_spacing": 2.5, "delta_b": delta_b})
        setup = preset.build(p)
        scene, y0 = setup.scene, setup.y0
        ratio = rj.solve.stiffness_ratio(scene, y0)
        # --smoke: the runs' step budget (max_steps is static: the reference then shares their compilation)
        ref = rj.simulate(scene, y0, (0.0, t_end), solver="kvaerno5", rtol=1e-11, atol=1e-13,
                          max_steps=max_steps if args.smoke else 2_000_000)
        for solver in ("dopri8", "kvaerno5"):
            for rtol in (1e-6,) if args.smoke else (1e-6, 1e-8):
                run = lambda: rj.simulate(scene, y0, (0.0, t_end), solver=solver, rtol=rtol,  # noqa
                                          atol=rtol * 1e-2, max_steps=max_steps)
                run_s, first, r = timed_first(run, repeats)
                err = float(np.max(np.abs(np.asarray(r.ys[-1]) - np.asarray(ref.ys[-1]))))
                rows.append({"delta_b": delta_b, "stiffness_ratio": ratio, "solver": solver,
                             "rtol": rtol, "success": bool(r.success), "message": r.message,
                             "steps": int(r.stats["num_steps"]), "error": err,
                             "run_s": run_s, "first_call_s": first,
                             "auto_picks": rj.solve.choose_solver(scene, y0).__class__.__name__})
                print(f"delta_b {delta_b:>7.0f} ratio {ratio:>8.1f} {solver:>8} rtol {rtol:.0e}: "
                      f"{r.message[:30]:30s} steps {rows[-1]['steps']:>7} err {err:.1e} "
                      f"{rows[-1]['run_s']:.2f} s (auto: {rows[-1]['auto_picks']})")
    out = {"benchmark": "solver_choice (model 000, circular race, nu = 1.5, t = 300)",
           "machine": {"platform": platform.platform(), "cpu_count": os.cpu_count()},
           "versions": {"jax": jax.__version__}, "threshold": rj.solve.STIFFNESS_THRESHOLD,
           "rows": rows}
    if args.smoke:
        print("smoke run: nothing written")
        return
    path = os.path.join(os.path.dirname(__file__), "results", "solver_choice.json")
    os.makedirs(os.path.dirname(path), exist_ok=True)
    with open(path, "w") as f:
        json.dump(out, f, indent=2)
    print(f"wrote {path}")


if __name__ == "__main__":
    main()
