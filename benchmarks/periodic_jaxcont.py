"""JaxCont side by side on part (c) of benchmarks/auto07p.py: the forced periodic
motions of the anisotropic Jeffcott rotor with cubic bearings
(tests/validation/test_auto07p_periodic.py), continued in the speed `Om` over
`OM_RANGE` through its four folds, by rotorjax's harmonic balance
(`rotorjax_branch()`, `H` harmonics) and by JaxCont's (PyPI `jaxcont`) collocation
continuation of periodic orbits, in the same run.

JaxCont continues autonomous periodic orbits only, so it gets the same autonomous
extension as AUTO (tests/reference/auto07p/jeffcott_forced.f90): the state `(x, y,
x', y', u, v)` with the forcing oscillator `u' = u + Om v - u (u^2 + v^2)`, `v' =
-Om u + v - v (u^2 + v^2)` and the forcing `ECC Om^2 (v, u)`. Its start is
rotorjax's harmonic-balance orbit at `Om = 0.5` sampled over one period
(`start_orbit()`, as AUTO's data), which `periodic_orbit_problem` resamples onto a
fixed, uniform Gauss-Legendre collocation mesh `Collocation(ntst, ncol)` and
corrects; then `continuation(..., PseudoArclength, events=[Fold()])` in float64
(rotorjax turns x64 on) with `newton_tol` NEWTON_TOL (JaxCont's default 1e-6 is
meant for float32). Several meshes are run; each one's folds (sorted) are compared
with rotorjax's, relatively.

Settings, and why: the first step `ds` also sets JaxCont's merge window for
events (two folds closer than `2 ds` in the parameter are reported as one); the
folds come in pairs 0.021 and 0.027 apart, so `ds` = DS (with `ds = 0.05` only
two of the four folds are reported). The arclength is the plain Euclidean norm
of all collocation unknowns and the period, hence the large `ds_max`. The fold
refinement (JaxCont's extended system, `2 n + 1` unknowns with the collocation
Jacobian's own derivatives, its tolerance fixed at 1e-6) is where most of the
time of the finer meshes goes.

Times: `timed_first` (first call with tracing and compilation, then the median of
`--repeats`), for rotorjax's `rotorjax_branch()` (from rest at `Om = 0.5`; its
median again after the meshes, `after_meshes`, as the machine's load may change) and for
each JaxCont mesh (building the problem from the sampled start orbit, its
correction, the continuation, the Floquet multipliers of every point and the fold
refinement: everything `continuation` does with `events=[Fold()]`). JaxCont passes
the right-hand side to its jitted engine as a fresh closure on every call, so its
repeated calls trace and compile again: its "warm" time includes that.

Without jaxcont installed (CI) it says so and exits 0, writing nothing.
`--smoke`: the coarsest mesh, one call each, prints, writes nothing. Otherwise
writes benchmarks/results/periodic_jaxcont.json.
"""

import argparse
import json
import os
import sys
import traceback

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from _common import CpuWatch, machine, timed_first, write_results  # noqa: E402

#: (ntst, ncol): a coarse mesh, a middle and a fine one (the smoke run: the first only)
MESHES = ((5, 4), (10, 4), (20, 4))
DS, DS_MIN, DS_MAX = 0.005, 1e-7, 0.5
NEWTON_TOL = 1e-10
MAX_STEPS = 2000
#: the fold speeds must agree with rotorjax's to this (relative), as AUTO's do (test_auto07p_periodic.TOL)
FOLD_TOL = 1e-6


def import_jaxcont():
    """The jaxcont package (this script is named apart from it: a script named
    `jaxcont.py` in benchmarks/, which the scripts put on the path, would shadow it)."""
    import importlib

    return importlib.import_module("jaxcont")


def vector_field(ex):
    """The extended, autonomous right-hand side `f(U, Om, args)` (JaxCont's convention)."""
    import jax.numpy as jnp

    def f(U, om, args):
        x, y, xd, yd, u, v = U
        r2 = x * x + y * y
        s2 = u * u + v * v
        return jnp.stack([xd, yd,
                          ex.ECC * om * om * v - ex.C * xd - ex.KX * x - ex.BETA * x * r2,
                          ex.ECC * om * om * u - ex.C * yd - ex.KY * y - ex.BETA * y * r2,
                          u + om * v - u * s2,
                          -om * u + v - v * s2])

    return f


def jaxcont_run(jc, ex, data, ntst, ncol):
    """`fn()` that builds the periodic problem on the mesh from the sampled start
    orbit `data` (rows `(t, x, y, x', y', u, v)`) and continues it over `OM_RANGE`."""
    import jax.numpy as jnp
    from jaxcont.core.collocation import Collocation
    from jaxcont.problems.periodic import periodic_orbit_problem

    f = vector_field(ex)
    om0 = ex.OM_RANGE[0]
    settings = jc.ContinuationPar(ds=DS, ds_min=DS_MIN, ds_max=DS_MAX, max_steps=MAX_STEPS, newton_tol=NEWTON_TOL)

    def fn():
        prob = periodic_orbit_problem(f, jnp.asarray(data[:, 1:]), jnp.asarray(data[:, 0]), ex.period(om0), om0,
                                      Collocation(ntst=ntst, ncol=ncol))
        return jc.continuation(prob, jc.PseudoArclength(), p_span=ex.OM_RANGE, settings=settings,
                               events=[jc.Fold()])

    return fn


def summarize(res, folds_rj, om_end, ntst, ncol):
    """One mesh's numbers, and why it failed (None if it did not)."""
    b = res.branch
    folds = [e for e in res.events if e.kind == "fold"]
    fp = np.sort([e.p for e in folds])
    n_unknowns = int(b.states.shape[1])
    stable = np.asarray(b.stable) if b.stable is not None else None
    out = {"ntst": ntst, "ncol": ncol, "unknowns": n_unknowns, "branch_points": int(b.params.size),
           "converged_steps": int(res.stats.get("converged_steps", -1)), "end_Om": float(b.params[-1]),
           "folds": fp.tolist(), "folds_converged": [bool(e.info.get("converged")) for e in folds],
           "stability_changes": int(np.sum(stable[1:] != stable[:-1])) if stable is not None else None}
    why = []
    if float(b.params[-1]) < om_end:
        why.append(f"stopped at Om = {float(b.params[-1])} before {om_end}")
    if fp.size != folds_rj.size:
        why.append(f"{fp.size} folds, not {folds_rj.size}")
    else:
        dev = np.abs(fp / folds_rj - 1)
        out["folds_rel"] = dev.tolist()
        out["folds_rel_max"] = float(np.max(dev))
    if not all(out["folds_converged"]):
        why.append("a fold's refinement did not converge")
    return out, "; ".join(why) or None


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--smoke", action="store_true", help="the coarse mesh only, one call each; print, write nothing")
    ap.add_argument("--repeats", type=int, default=3)
    args = ap.parse_args()
    repeats = 0 if args.smoke else args.repeats  # --smoke: the first call only

    try:
        jc = import_jaxcont()
    except ImportError as e:
        print(f"jaxcont is not installed ({e}): nothing to compare "
              "(python3 -m pip install --no-deps jaxcont==0.4.0)")
        print("smoke run: nothing written" if args.smoke else "nothing written")
        return

    import jax

    import rotorjax  # noqa: F401  (float64 on, before any array is made)
    from tests.validation import test_auto07p_periodic as ex

    jax_version = jax.__version__
    try:
        from importlib.metadata import version

        jc_version = version("jaxcont")
    except Exception:  # noqa: BLE001
        jc_version = getattr(jc, "__version__", "unknown")

    out = {"benchmark": "periodic_jaxcont", "machine": machine(), "smoke": args.smoke, "repeats": repeats,
           "versions": {"jax": jax_version, "jaxcont": jc_version, "x64": bool(jax.config.jax_enable_x64)},
           "problem": {"test": "tests/validation/test_auto07p_periodic.py", "KX": ex.KX, "KY": ex.KY, "C": ex.C,
                       "BETA": ex.BETA, "ECC": ex.ECC, "OM_RANGE": list(ex.OM_RANGE),
                       "extension": "tests/reference/auto07p/jeffcott_forced.f90 (6 states)"},
           "settings": {"algorithm": "PseudoArclength", "events": ["Fold"], "ds": DS, "ds_min": DS_MIN,
                        "ds_max": DS_MAX, "newton_tol": NEWTON_TOL, "max_steps": MAX_STEPS,
                        "start": "rotorjax's harmonic-balance orbit at Om = 0.5, 401 samples (start_orbit())",
                        "fold_refinement_tolerance": "1e-6 (fixed by jaxcont's detect_events)",
                        "fold_tol": FOLD_TOL,
                        "note": "ds also sets jaxcont's event merge window (2 ds in Om); the folds come in "
                                "pairs 0.021 and 0.027 apart, so ds = 0.05 reports two folds of four"},
           "load_average_at_start": list(os.getloadavg())}

    watch = CpuWatch()
    t_rj, t_rj_first, (br, _) = timed_first(ex.rotorjax_branch, repeats)
    folds_rj_branch = [e.p for e in br.events if e.kind == "fold"]
    folds_rj = np.sort(folds_rj_branch)
    out["rotorjax"] = {"first_call_s": t_rj_first, "median_s": t_rj, "branch_points": int(br.p.size),
                       "harmonics": ex.H, "folds": folds_rj.tolist(), "folds_in_branch_order": folds_rj_branch,
                       "cpu": watch.report()}
    print(json.dumps(out["rotorjax"], indent=1, default=float), flush=True)

    data = ex.start_orbit()
    meshes = MESHES[:1] if args.smoke else MESHES
    out["meshes"] = []
    for ntst, ncol in meshes:
        watch.start()
        try:
            t, t_first, res = timed_first(jaxcont_run(jc, ex, data, ntst, ncol), repeats)
            m, why = summarize(res, folds_rj, ex.OM_RANGE[1], ntst, ncol)
            m.update({"first_call_s": t_first, "median_s": t})
            if why:
                m["failed"] = why
        except Exception as e:  # noqa: BLE001 - a peer's failure is a result: recorded, not hidden
            m = {"ntst": ntst, "ncol": ncol, "failed": f"{type(e).__name__}: {e}",
                 "traceback": traceback.format_exc()[-2000:]}
        m["cpu"] = watch.report()
        out["meshes"].append(m)
        print(json.dumps(m, indent=1, default=float), flush=True)

    # rotorjax again after the meshes: the machine is shared, and its load may have changed meanwhile
    watch.start()
    t_rj_end, _, _ = timed_first(ex.rotorjax_branch, max(repeats, 1))
    out["rotorjax"]["after_meshes"] = {"median_s": t_rj_end, "cpu": watch.report()}

    ok = [m for m in out["meshes"] if "failed" not in m]
    if ok:
        best = min(ok, key=lambda m: m["folds_rel_max"])
        out["best_mesh"] = {"ntst": best["ntst"], "ncol": best["ncol"], "folds_rel_max": best["folds_rel_max"],
                            "within_fold_tol": best["folds_rel_max"] < FOLD_TOL,
                            "ratio_jaxcont_median_over_rotorjax_median": best["median_s"] / t_rj,
                            "ratio_jaxcont_first_over_rotorjax_first": best["first_call_s"] / t_rj_first}
        within = [m for m in ok if m["folds_rel_max"] < FOLD_TOL]
        if within:      # the cheapest mesh that meets the tolerance
            c = min(within, key=lambda m: m["median_s"])
            out["cheapest_mesh_within_fold_tol"] = {
                "ntst": c["ntst"], "ncol": c["ncol"], "folds_rel_max": c["folds_rel_max"],
                "ratio_jaxcont_median_over_rotorjax_median": c["median_s"] / t_rj,
                "ratio_jaxcont_first_over_rotorjax_first": c["first_call_s"] / t_rj_first}
        print(json.dumps({k: out[k] for k in ("best_mesh", "cheapest_mesh_within_fold_tol") if k in out},
                         indent=1, default=float), flush=True)
    else:
        out["failed"] = "no mesh gave four converged folds over the whole range"
        print(out["failed"], flush=True)

    out["load_average_at_end"] = list(os.getloadavg())  # a shared machine: times are only as good as its load
    if args.smoke:
        print("smoke run: nothing written")
    else:
        write_results("periodic_jaxcont", out)


if __name__ == "__main__":
    main()
