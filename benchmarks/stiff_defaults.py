"""Default settings on stiff rotors: what `rotorjax simulate` does with a shipped rotor
file whose full finite-element model is stiff for an explicit solver, and how far the
chosen path is from a tight reference of the full model (issue 32, item 6).

For each case, 200 revolutions at the CLI's defaults (rtol 1e-8, atol 1e-10, 500 000
steps): the plan (`rotorjax.analysis.plan_run`: the modes kept, Dopri8's estimated
steps with all of them), the run on the planned model with the solver "auto" takes
(steps, time), Dopri8 on the full model at the same tolerance with the budget it
needs (`--modes all --solver dopri8 --max-steps 5000000`), and the error of each
against the full model at rtol 1e-11 (Dopri8), over the saved node displacements,
relative to their largest value. The first call compiles; a time is a second run's,
except where the first took over a minute (then the first's, compilation included:
`run_includes_compile`).

Run: python benchmarks/stiff_defaults.py [--smoke]; writes benchmarks/results/stiff_defaults.json
(`--smoke`: one case, 2 revolutions with the step budget scaled alike (the same
decisions), one call each; prints, writes nothing).
"""

import argparse
import json
import os
import platform
import sys
import time

import jax
import numpy as np

from rotorjax import presets
from rotorjax.analysis import plan_run
from rotorjax.solve import simulate

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from _common import timed_first  # noqa: E402

LONG_S = 60.0

ROTORS = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "rotorjax", "rotors")
CASES = (("ross_compare.toml", 50.0), ("tapered_two_material.toml", 50.0), ("journal_rig.toml", None))
REVOLUTIONS, RTOL, ATOL, MAX_STEPS, SAVES = 200, 1e-8, 1e-10, 500_000, 400


def _displacements(result):
    return np.concatenate([np.asarray(result.outputs["node_x"]), np.asarray(result.outputs["node_y"])], axis=-1)


def _error(result, ref):
    scale = float(np.max(np.abs(ref)))
    return float(np.max(np.abs(_displacements(result) - ref)) / scale) if result.success else None


def _timed(fn, repeats):
    """`(run seconds, first-call seconds, whether the run time includes compilation, result)`."""
    run_s, first, result = timed_first(fn, 0)
    if repeats and first < LONG_S:
        run_s, _, result = timed_first(fn, 0)
        return run_s, first, False, result
    return run_s, first, True, result


def _row(run_s, first, with_compile, result, ref_x):
    return {"solver": result.solver, "success": bool(result.success), "message": result.message,
            "steps": int(result.stats["num_steps"]), "run_s": run_s, "first_call_s": first,
            "run_includes_compile": with_compile, "error": _error(result, ref_x)}


def case(name, speed, scale, repeats):
    preset = presets.get(os.path.join(ROTORS, name))
    params = preset.params({} if speed is None else {"speed": speed})
    setup = preset.build(params)
    w = float(params["speed"])
    t_end = scale * REVOLUTIONS * 2 * np.pi / w
    max_steps = int(round(scale * MAX_STEPS))
    t0 = time.perf_counter()
    plan = plan_run(setup.scene, setup.y0, t_end, RTOL, max_steps)
    plan_s = time.perf_counter() - t0
    solver = "kvaerno5" if plan.implicit else "dopri8"
    run = lambda scene, y0, rtol, atol, steps, solver=solver: simulate(  # noqa: E731
        scene, y0, (0.0, t_end), saveat=SAVES, solver=solver, rtol=rtol, atol=atol, max_steps=steps)
    ref = run(setup.scene, setup.y0, 1e-11, 1e-13, 20 * MAX_STEPS, "dopri8")
    if not ref.success:
        raise RuntimeError(f"{name}: the reference run failed: {ref.message}")
    ref_x = _displacements(ref)
    auto = _timed(lambda: run(plan.scene, plan.y0, RTOL, ATOL, max_steps), repeats)
    full = _timed(lambda: run(setup.scene, setup.y0, RTOL, ATOL, 10 * max_steps, "dopri8"), repeats)
    row = {"rotor": name, "speed_rad_s": w, "t_end_s": t_end, "revolutions": scale * REVOLUTIONS,
           "max_steps": max_steps, "plan": dict(plan.as_dict(), plan_s=plan_s),
           "auto": _row(*auto, ref_x), "dopri8_full_model": _row(*full, ref_x),
           "reference": {"solver": ref.solver, "rtol": 1e-11, "steps": int(ref.stats["num_steps"])}}
    a, f = row["auto"], row["dopri8_full_model"]
    print(f"{name} at {w:g} rad/s, {scale * REVOLUTIONS:g} rev: plan {plan.modes or 'all'} of {plan.coordinates} "
          f"modes (full model: ~{plan.estimate_full.explicit_steps:.3g} Dopri8 steps), {a['solver']}: "
          f"{a['steps']} steps {a['run_s']:.2f} s, error {a['error']}; full model at rtol {RTOL:g}: "
          f"{f['steps']} steps {f['run_s']:.2f} s, error {f['error']}", flush=True)
    return row


def _err(e):
    return "failed" if e is None else f"{e:.1e}"


def table(out) -> str:
    """The README's table (markdown) from the results."""
    lines = ["| rotor file, 200 revolutions | what `simulate` chose | steps, time | error | Dopri8 on the full "
             "model: steps, time | error |", "|---|---|---|---|---|---|"]
    for c in out["cases"]:
        p, a, f = c["plan"], c["auto"], c["dopri8_full_model"]
        chose = (f"{p['modes']} of {p['coordinates']} modes (to {p['cutoff_frequency']:.0f} rad/s), {a['solver']}"
                 if p["modes"] else f"all {p['coordinates']} dofs, {a['solver']}")
        lines.append(f"| `{c['rotor']}` at {c['speed_rad_s']:g} rad/s | {chose} | {a['steps']}, {a['run_s']:.1f} s | "
                     f"{_err(a['error'])} | {f['steps']}, {f['run_s']:.1f} s | {_err(f['error'])} |")
    return "\n".join(lines)


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--smoke", action="store_true", help="one case, 2 revolutions, one call each; print, write nothing")
    ap.add_argument("--table", action="store_true", help="print the README's table from the stored results")
    args = ap.parse_args()
    path = os.path.join(os.path.dirname(os.path.abspath(__file__)), "results", "stiff_defaults.json")
    if args.table:
        with open(path) as f:
            print(table(json.load(f)))
        return
    cases = CASES[:1] if args.smoke else CASES
    rows = [case(name, speed, 0.01 if args.smoke else 1.0, 0 if args.smoke else 1) for name, speed in cases]
    if args.smoke:
        print("smoke run: nothing written")
        return
    out = {"benchmark": "stiff_defaults (rotorjax simulate's defaults on stiff shipped rotor files)",
           "machine": {"platform": platform.platform(), "cpu_count": os.cpu_count()},
           "versions": {"jax": jax.__version__}, "settings": {"rtol": RTOL, "atol": ATOL, "max_steps": MAX_STEPS,
                                                              "revolutions": REVOLUTIONS, "saves": SAVES},
           "cases": rows}
    with open(path, "w") as f:
        json.dump(out, f, indent=2)
    print("wrote", path)


if __name__ == "__main__":
    main()
