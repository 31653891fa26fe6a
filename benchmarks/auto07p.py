"""AUTO-07p side by side: the two shared examples of tests/validation/test_auto07p.py
((a) the Duffing harmonic-balance branch, its folds and the fold curve in (om, f);
(b) the Jeffcott rotor's synchronous-whirl branch in the speed, its Hopf point and the
Hopf curve in (Om, c_ext)) and the one of tests/validation/test_auto07p_periodic.py
((c) the forced periodic motions of an anisotropic Jeffcott rotor with cubic
bearings: the branch in the speed with its four folds, by harmonic balance in
rotorjax and by collocation of periodic orbits in AUTO), each solved by AUTO-07p and
by rotorjax in the same run.

Times: AUTO's compile-and-link of the equation file (gfortran) apart from its runs
(the one-parameter branch plus the two-parameter curve both ways; wall time of the
executables, and AUTO's own "Total Time"); rotorjax's first call (tracing and
compiling included) apart from the median of the repeats. Deviations: the largest
distance of an AUTO point from rotorjax's curve (rotorjax's corrector from AUTO's
point, and a spline through rotorjax's points), the special points, the curves' ends.

In (c) AUTO's time is one run (no two-parameter curve), and the deviation's own time
(rotorjax's corrector at every AUTO point, its Floquet multipliers at seven) is apart
from both; the deviations are the fold speeds, the points' distance in the
(Om, L2-norm) plane and the Floquet multipliers.

AUTO-07p comes from `.ci/install-auto07p` (Debian's `auto-07p` and gfortran); without it
only rotorjax is timed. `--smoke`: one call each, AUTO in (a) and (c) only, prints the
results, writes no file. `--only a|b|c`: that part alone, printed, no file written.
Otherwise writes benchmarks/results/auto07p.json.
"""

import argparse
import json
import os
import subprocess
import sys
import tempfile
import time

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from _common import machine, timed_first, write_results  # noqa: E402


def _gfortran_version(fc):
    try:
        return subprocess.run([fc, "--version"], capture_output=True, text=True, timeout=10).stdout.splitlines()[0]
    except (OSError, subprocess.SubprocessError, IndexError):
        return "unknown"


def time_auto(run_example, inst, repeats, curve):
    """Median compile seconds and run seconds (wall, and AUTO's own) over `repeats`
    fresh directories, and the last result (`curve`: its two-parameter runs' key)."""
    comp, wall, own, res = [], [], [], None
    for _ in range(max(1, repeats)):
        with tempfile.TemporaryDirectory() as d:
            res = run_example(d, inst)
        runs = [res["branch"], *res[curve]]
        comp.append(res["equation"].compile_seconds)
        wall.append(sum(r.seconds for r in runs))
        own.append(sum(r.auto_seconds for r in runs))
    return {"compile_s": float(np.median(comp)), "run_s": float(np.median(wall)),
            "run_auto_total_time_s": float(np.median(own)), "runs_ok": all(r.ok for r in runs),
            "points": [int(sum(len(b.data) for b in r.branches)) for r in runs]}, res


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--smoke", action="store_true",
                    help="one call each, AUTO in (a) and (c) only; print, write nothing")
    ap.add_argument("--only", choices=("a", "b", "c"), help="one part only; print, write nothing")
    ap.add_argument("--repeats", type=int, default=3)
    args = ap.parse_args()
    repeats = 0 if args.smoke else args.repeats  # --smoke: the first call only

    import jax

    import rotorjax  # noqa: F401
    from tests.reference.auto07p import driver
    from tests.validation import test_auto07p as ex
    from tests.validation import test_auto07p_periodic as exc

    inst, why = driver.find_auto()
    out = {"benchmark": "auto07p", "machine": machine(), "smoke": args.smoke, "repeats": repeats,
           "versions": {"jax": jax.__version__,
                        "auto-07p": inst.version if inst else None,
                        "gfortran": _gfortran_version(inst.fc) if inst else None},
           "tolerance": ex.TOL, "load_average_at_start": list(os.getloadavg())}
    if inst is None:
        print(why, flush=True)
        out["auto"] = why

    if args.only in (None, "a"):
        part_a(args, ex, inst, repeats, out)
    if args.only in (None, "b"):
        part_b(args, ex, inst, repeats, out)
    if args.only in (None, "c"):
        part_c(exc, inst, repeats, out)

    out["load_average_at_end"] = list(os.getloadavg())    # a shared machine: times are only as good as its load
    if args.smoke:
        print("smoke run: nothing written")
    elif args.only:
        print("one part: nothing written")
    else:
        write_results("auto07p", out)


def part_a(args, ex, inst, repeats, out):
    """(a) Duffing fold curve."""
    t_rj, t_rj_first, rj = timed_first(ex.rotorjax_duffing, repeats)
    a = {"rotorjax": {"first_call_s": t_rj_first, "median_s": t_rj, "fold_curve_points": int(rj[1].x.shape[0]),
                      "branch_points": int(rj[0].p.size), "stopped": rj[1].stopped}}
    if inst is not None:
        a["auto"], res = time_auto(ex.auto_duffing, inst, repeats, "folds")
        a["deviation"] = ex.duffing_deviation(res, rj)
        a["ratio_rotorjax_median_over_auto_run"] = t_rj / a["auto"]["run_s"]
        a["ratio_rotorjax_median_over_auto_compile_plus_run"] = t_rj / (a["auto"]["compile_s"] + a["auto"]["run_s"])
    out["duffing_fold_curve"] = a
    print(json.dumps(a, indent=1, default=float), flush=True)


def part_b(args, ex, inst, repeats, out):
    """(b) Jeffcott Hopf curve."""
    t_rj, t_rj_first, rj = timed_first(ex.rotorjax_jeffcott, repeats)
    b = {"rotorjax": {"first_call_s": t_rj_first, "median_s": t_rj, "hopf_curve_points": int(rj[1].x.shape[0]),
                      "branch_points": int(rj[0].p.size), "stopped": rj[1].stopped}}
    if inst is not None and not args.smoke:  # --smoke: AUTO in (a) and (c) only (the same glue)
        b["auto"], res = time_auto(ex.auto_jeffcott, inst, repeats, "hopf")
        t0 = time.perf_counter()
        b["deviation"] = ex.jeffcott_deviation(res, rj)
        b["deviation"]["seconds"] = time.perf_counter() - t0
        b["ratio_rotorjax_median_over_auto_run"] = t_rj / b["auto"]["run_s"]
        b["ratio_rotorjax_median_over_auto_compile_plus_run"] = t_rj / (b["auto"]["compile_s"] + b["auto"]["run_s"])
        with tempfile.TemporaryDirectory() as d:
            lin = ex.auto_jeffcott(d, inst, ecc=0.0)
        pts = ex.auto_curve(lin["hopf"], ["PAR(1)", "PAR(2)"])
        b["auto_closed_form_without_eccentricity"] = float(np.max(np.abs(pts[:, 0] - (1 + pts[:, 1] / ex.C_INT))))
    out["jeffcott_hopf_curve"] = b
    print(json.dumps(b, indent=1, default=float), flush=True)


def part_c(exc, inst, repeats, out):
    """(c) Forced periodic motions of the anisotropic Jeffcott rotor: the branch
    in the speed with its folds (AUTO also in --smoke: one run, about a second)."""
    t_rj, t_rj_first, rj = timed_first(exc.rotorjax_branch, repeats)
    br = rj[0]
    c = {"rotorjax": {"first_call_s": t_rj_first, "median_s": t_rj, "branch_points": int(br.p.size),
                      "harmonics": exc.H, "folds": [e.p for e in br.events if e.kind == "fold"]}}
    if inst is not None:
        c["auto"], res = time_auto(exc.auto_forced, inst, repeats, "runs")
        t0 = time.perf_counter()
        c["deviation"] = exc.deviation(res, rj)
        c["deviation"]["seconds"] = time.perf_counter() - t0
        c["ratio_rotorjax_median_over_auto_run"] = t_rj / c["auto"]["run_s"]
        c["ratio_rotorjax_median_over_auto_compile_plus_run"] = t_rj / (c["auto"]["compile_s"] + c["auto"]["run_s"])
    out["jeffcott_forced_branch"] = c
    print(json.dumps(c, indent=1, default=float), flush=True)


if __name__ == "__main__":
    main()
