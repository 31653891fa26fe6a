"""Continuation: (a) a shared equilibrium example with jaxcont (the Brusselator's
Hopf point, exact at b = 2 with frequency 1; the Duffing harmonic-balance folds,
exact from their closed form), rotorjax vs jaxcont in the same run, time (second
call, compiled) and error; (b) every stability boundary of model 001 in the
preset's box (n in [0.5, 10], mu_w in [0.05, 1]) by `trace_boundaries`: time
(first call, compiling; second call), points, and the accuracy of the dense curve
between the points against critical speeds bisected along n at the midpoints of
every interval (where a cubic Hermite piece is least accurate) and at the quarter
points of the least accurate ones, beside the accuracy of straight chords between
the same points; the peer: `critical_speeds` along n row by row, timed per row.

jaxcont is optional (`pip install jaxcont`, or `--jaxcont-path DIR` with a
`pip install --no-deps --target DIR jaxcont`). Writes
benchmarks/results/continuation.json; `--smoke`: a small box (one boundary),
one call of each, one interval checked, prints the results and writes nothing.
"""

import argparse
import json
import os
import sys
import time

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
from _common import machine, timed, write_results  # noqa: E402


def bisect_along_n(m, n0, mu, half=1e-4, xtol=1e-13):
    """The critical speed near `n0` at `mu`: plain bisection of the margin along n
    (the bracket widened until the margin changes sign)."""
    a, b = n0 - half, n0 + half
    fa, fb = float(m(a, mu)), float(m(b, mu))
    while np.sign(fa) == np.sign(fb):
        half *= 4
        a, b = n0 - half, n0 + half
        fa, fb = float(m(a, mu)), float(m(b, mu))
    while b - a > xtol:
        c = 0.5 * (a + b)
        fc = float(m(c, mu))
        if np.sign(fc) == np.sign(fa):
            a, fa = c, fc
        else:
            b = c
    return 0.5 * (a + b)


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--jaxcont-path", default=os.environ.get("ROTORJAX_JAXCONT_PATH"))
    ap.add_argument("--smoke", action="store_true", help="a small box, a few checks; print, write nothing")
    args = ap.parse_args()
    if args.jaxcont_path:
        sys.path.append(args.jaxcont_path)
    import jax
    import jax.numpy as jnp

    import rotorjax  # noqa: F401
    from rotorjax.analysis import continue_branch, critical_speeds, trace_boundaries
    from rotorjax.analysis._continuation import _hermite
    from rotorjax.presets import anisotropic_abb as ab
    from tests.analysis.test_continuation import brusselator, duffing, duffing_fold_forcing

    out = {"benchmark": "continuation", "machine": machine(), "smoke": args.smoke,
           "versions": {"jax": jax.__version__}}

    # (a) shared examples
    t_b, br = timed(lambda: continue_branch(brusselator, np.array([1.0, 1.0]), 1.0, p_bounds=(1.0, 3.0), ds=0.05,
                                            ds_max=0.1), repeats=0 if args.smoke else 3)
    hopf = [e for e in br.events if e.kind == "hopf"][0]
    f0 = 0.05
    from rotorjax._newton import newton
    u0, _ = newton(lambda u: duffing(u, 0.5, f0), jnp.array([0.0665, 0.0022]), 1e-12, 30, unit=1.0)
    u0 = np.asarray(u0)
    t_d, bd = timed(lambda: continue_branch(lambda u, om: duffing(u, om, f0), u0, 0.5, p_bounds=(0.5, 2.0),
                                            ds=0.02, ds_max=0.05, max_points=400), repeats=0 if args.smoke else 3)
    folds = [e.p for e in bd.events if e.kind == "fold"]
    fold_err = max(min(abs(f0 / v - 1) for v in duffing_fold_forcing(p)) for p in folds)
    out["shared"] = {"rotorjax": {"brusselator_s": t_b, "hopf_error": abs(hopf.p - 2.0),
                                  "hopf_frequency_error": abs(hopf.frequency - 1.0),
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

    # (b) every model 001 boundary in (n, mu_w)
    P = dict(ab.PRESET.defaults)
    G = {k: P[k] for k in ab.GROUPS}

    def margin(n, mu):
        return ab.main_motion_floquet(dict(G, mu_w=mu), n, P["K"]).margin

    box = ((4.5, 5.5), (0.4, 0.6)) if args.smoke else (ab.PRESET.box["n"], ab.PRESET.box["mu_w"])
    dense_tol = 1e-6

    def run():
        return trace_boundaries(margin, box, gradient="fd", names=("n", "mu_w"), dense_tol=dense_tol, ds=0.02,
                                ds_max=0.2)

    t0 = time.perf_counter()
    found = run()
    t_first = time.perf_counter() - t0
    t_second = t_first
    if not args.smoke:  # --smoke: one call
        t0 = time.perf_counter()
        run()
        t_second = time.perf_counter() - t0

    # the dense curve against bisection along n: every interval's midpoint, and the quarter points of the
    # five least accurate intervals of each boundary; the nodes; and straight chords between the nodes
    m = jax.jit(margin)
    branches = []
    for b in found:
        idx = np.arange(1, len(b.x))
        if args.smoke:
            idx = idx[np.argsort(b.errors[1:])[-1:]]
        worst = idx[np.argsort(b.errors[idx])[-5:]]
        mid, quarter, chord, ratio = [], [], [], []
        for i in idx:
            for s in ((0.25, 0.5, 0.75) if i in worst else (0.5,)):
                h = _hermite(b.x[i - 1], b.tangents[i - 1], b.x[i], b.tangents[i], [s])[0]
                e = abs(bisect_along_n(m, h[0], h[1]) - h[0])
                (mid if s == 0.5 else quarter).append(e)
                if s == 0.5:
                    if b.errors[i] > 1e-9:
                        ratio.append(e / b.errors[i])
                    c = b.x[i - 1] + 0.5 * (b.x[i] - b.x[i - 1])
                    chord.append(abs(bisect_along_n(m, c[0], c[1]) - c[0]))
        nodes = [abs(bisect_along_n(m, x[0], x[1]) - x[0]) for x in b.x[[0, len(b.x) // 2, -1]]]
        branches.append({"points": int(len(b.x)), "stops": list(b.stops),
                         "n_range": [float(b.x[:, 0].min()), float(b.x[:, 0].max())],
                         "error_estimate_max": float(b.errors.max()),
                         "intervals_checked": int(len(idx)),
                         "dense_error_at_midpoints_max": float(max(mid)),
                         "dense_error_at_quarter_points_max": float(max(quarter)) if quarter else None,
                         "node_error_max": float(max(nodes)),
                         "chord_error_at_midpoints_max": float(max(chord)),
                         "actual_over_estimate": [float(min(ratio)), float(max(ratio))] if ratio else None})
    dense_max = max(max(b["dense_error_at_midpoints_max"], b["dense_error_at_quarter_points_max"] or 0.0)
                    for b in branches)

    # the peer: critical speeds along n, one mu_w row at a time (scan over the whole range, bisection)
    rows = np.linspace(*box[1], 3 if not args.smoke else 1)
    t0 = time.perf_counter()
    for mu in rows:
        critical_speeds(lambda v: margin(v, mu), *box[0], n_scan=40, xtol=1e-10)
    t_row = (time.perf_counter() - t0) / len(rows)
    n_points = sum(b["points"] for b in branches)
    out["boundaries_001"] = {
        "box": {"n": list(box[0]), "mu_w": list(box[1])}, "dense_tol": dense_tol,
        "n_boundaries": len(found), "crossings_located": len(found.crossings),
        "trace_boundaries_first_call_s": t_first, "trace_boundaries_second_call_s": t_second,
        "branches": branches, "dense_error_max": dense_max,
        "critical_speeds_per_row_s": t_row,
        "rows_for_as_many_points_s": t_row * n_points,
        "ratio_rows_over_trace": t_row * n_points / t_second,
        "note": "errors are distances along n to plain bisection of the margin at fixed mu_w (to 1e-13); "
                "a critical_speeds row compiles its scan (as every call does), so it is timed as called"}
    print(json.dumps(out["boundaries_001"], indent=1))
    if args.smoke:
        print("smoke run: nothing written")
    else:
        write_results("continuation", out)


if __name__ == "__main__":
    main()
