"""Continuation: (a) a shared equilibrium example with jaxcont (the Brusselator's
Hopf point, exact at b = 2 with frequency 1; the Duffing harmonic-balance folds,
exact from their closed form), rotorjax vs jaxcont in the same run, time (second
call, compiled) and error; (b) the model 001 stability boundary in (n, mu_w),
traced by continuation vs the grid-map approach at equal boundary accuracy.

jaxcont is optional (`pip install jaxcont`, or `--jaxcont-path DIR` with a
`pip install --no-deps --target DIR jaxcont`). Writes
benchmarks/results/continuation.json.
"""

import argparse
import json
import os
import sys
import time

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
from _common import machine, timed, write_results  # noqa: E402


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--jaxcont-path", default=os.environ.get("ROTORJAX_JAXCONT_PATH"))
    args = ap.parse_args()
    if args.jaxcont_path:
        sys.path.append(args.jaxcont_path)
    import jax
    import jax.numpy as jnp

    import rotorjax  # noqa: F401
    from rotorjax.analysis import continue_branch, critical_speeds, trace_boundary
    from rotorjax.presets import anisotropic_abb as ab
    from rotorjax.sweep import sweep
    from tests.analysis.test_continuation import brusselator, duffing, duffing_fold_forcing

    out = {"benchmark": "continuation", "machine": machine(),
           "versions": {"jax": jax.__version__}}

    # (a) shared examples
    t_b, br = timed(lambda: continue_branch(brusselator, np.array([1.0, 1.0]), 1.0, p_bounds=(1.0, 3.0), ds=0.05,
                                            ds_max=0.1))
    hopf = [e for e in br.events if e["kind"] == "hopf"][0]
    f0 = 0.05
    from rotorjax.analysis._continuation import _newton
    u0, _ = _newton(lambda u: duffing(u, 0.5, f0), np.array([0.0665, 0.0022]))
    t_d, bd = timed(lambda: continue_branch(lambda u, om: duffing(u, om, f0), u0, 0.5, p_bounds=(0.5, 2.0),
                                            ds=0.02, ds_max=0.05, max_points=400))
    folds = [e["p"] for e in bd.events if e["kind"] == "fold"]
    fold_err = max(min(abs(f0 / v - 1) for v in duffing_fold_forcing(p)) for p in folds)
    out["shared"] = {"rotorjax": {"brusselator_s": t_b, "hopf_error": abs(hopf["p"] - 2.0),
                                  "hopf_frequency_error": abs(hopf["frequency"] - 1.0),
                                  "duffing_s": t_d, "folds": folds, "fold_error_rel": fold_err}}
    try:
        import jaxcont

        def f_b(u, p, _):
            return brusselator(u, p)

        def f_d(u, p, _):
            return duffing(u, p, f0)

        s = jaxcont.ContinuationPar(ds=0.05, ds_max=0.1, newton_tol=1e-12, max_steps=100)
        prob = jaxcont.bif_problem(f_b, jnp.array([1.0, 1.0]), 1.0)
        t_jb, rj = timed(lambda: jaxcont.continuation(prob, p_span=(1.0, 3.0), settings=s, events=[jaxcont.Hopf()]))
        hj = [e for e in rj.events if e.kind == "hopf"][0]
        sd = jaxcont.ContinuationPar(ds=0.02, ds_max=0.05, newton_tol=1e-12, max_steps=400)
        probd = jaxcont.bif_problem(f_d, jnp.asarray(u0), 0.5)
        t_jd, rd = timed(lambda: jaxcont.continuation(probd, p_span=(0.5, 2.0), settings=sd, events=[jaxcont.Fold()]))
        fj = [float(e.p) for e in rd.events if e.kind == "fold"]
        fj_err = max(min(abs(f0 / v - 1) for v in duffing_fold_forcing(p)) for p in fj) if fj else None
        out["shared"]["jaxcont"] = {"version": getattr(jaxcont, "__version__", "?"), "brusselator_s": t_jb,
                                    "hopf_error": abs(float(hj.p) - 2.0),
                                    "hopf_frequency_error": abs(float(hj.info.get("omega0", np.nan)) - 1.0),
                                    "duffing_s": t_jd, "folds": fj, "fold_error_rel": fj_err}
    except ImportError:
        out["shared"]["jaxcont"] = "not installed"
    print(json.dumps(out["shared"], indent=1), flush=True)

    # (b) model 001 boundary in (n, mu_w)
    P = dict(ab.PRESET.defaults)
    G = {k: P[k] for k in ab.GROUPS}

    def margin(n, mu):
        return ab.main_motion_floquet(dict(G, mu_w=mu), n, P["K"]).margin

    t0 = time.perf_counter()
    curve = trace_boundary(margin, (5.05, 0.3), bounds=(np.array([0.5, 0.3]), np.array([10.0, 1.0])), ds=0.05,
                           ds_max=0.1, gradient="fd", max_points=40, direction=(0.0, 1.0), tol=1e-10)
    t_trace = time.perf_counter() - t0
    # accuracy: bisection at three of the traced mu_w
    errs = []
    for n, mu in curve.x[[1, len(curve.x) // 2, -1]]:
        (c,) = critical_speeds(lambda v: margin(v, mu), n - 0.05, n + 0.05, n_scan=4, xtol=1e-12)
        errs.append(abs(c.speed - n))
    # grid map: 200 speeds over [0.5, 10] per mu_w row, the same rows as the trace
    rows = curve.x[:, 1]
    t0 = time.perf_counter()
    grid = sweep(lambda q: margin(q["n"], q["mu_w"]), {"n": np.linspace(0.5, 10.0, 200), "mu_w": rows},
                 chunk_size=200, progress=False)
    t_grid = time.perf_counter() - t0
    spacing = 9.5 / 199
    # the grid's boundary estimate in each row: the midpoint of the sign change
    # nearest the traced boundary
    gm, gn = np.asarray(grid.values), grid.axes["n"]
    grid_err = []
    for j, (n_tr, _) in enumerate(curve.x):
        k = [i for i in range(gn.size - 1) if np.sign(gm[i, j]) != np.sign(gm[i + 1, j])]
        if k:
            grid_err.append(min(abs(0.5 * (gn[i] + gn[i + 1]) - n_tr) for i in k))
    # equal accuracy (the trace's ~1e-12) needs bisection in each row: 2 scan points + ~35 steps
    t0 = time.perf_counter()
    for mu in rows[:3]:
        critical_speeds(lambda v: margin(v, mu), 4.9, 5.2, n_scan=4, xtol=1e-12)
    t_bisect_row = (time.perf_counter() - t0) / 3
    out["boundary_001"] = {"points": int(curve.x.shape[0]), "mu_w_range": [float(rows.min()), float(rows.max())],
                           "trace_s": t_trace, "trace_error_max": float(max(errs)), "stopped": curve.stopped,
                           "grid_map_200_per_row_s": t_grid, "grid_map_error_bound": spacing / 2,
                           "grid_map_error_max": float(max(grid_err)) if grid_err else None,
                           "map_plus_bisection_s": t_bisect_row * len(rows),
                           "ratio_map_plus_bisection_over_trace": t_bisect_row * len(rows) / t_trace,
                           "ratio_grid_over_trace": t_grid / t_trace}
    print(json.dumps(out["boundary_001"], indent=1))
    write_results("continuation", out)


if __name__ == "__main__":
    main()
