"""Work-precision diagrams and the results page, from the benchmarks' JSON.

Reads `benchmarks/results/*.json` (what the benchmark scripts last measured) and
writes, next to each, a PNG:
- `sweep_throughput`, `limiters`, `stability_map`: log error against log time per
  trajectory (or per point), one curve per method and variant, markers labelled
  with the tolerance;
- `ross_parity`, `identification`, `fe_identification` (no tolerance ladder): time per analysis against
  the peer, the ratio above each pair, the agreement in the reading;
- `harmonic_balance`: max relative amplitude error against the time for all speeds,
  harmonic balance (one marker per harmonic count) and the brute-force sweep (one per
  tolerance and integration length), the target error as a line;
- `step_cost`: microseconds per lane-step split into right-hand sides, stage sums
  and the rest, the arithmetic bound and the peer's right-hand sides marked;
- `bench_quick` (the report of `rotorjax bench --quick`): its three panels
  (`rotorjax.plot.plot_bench`).
Captions carry the machine and the JSON's `date` (else the file's time). Then writes
`benchmarks/README.md`: each diagram with its reading, every number in it taken from
the JSON. Measures nothing; run it after a benchmark.

Run: python benchmarks/work_precision.py [--results DIR] [--page FILE]
"""

import argparse
import datetime
import json
import os

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

from rotorjax.plot import work_precision_curve  # noqa: E402

HERE = os.path.dirname(os.path.abspath(__file__))


def _load(results, name):
    path = os.path.join(results, f"{name}.json")
    with open(path) as f:
        data = json.load(f)
    if "date" in data:  # written by the benchmark; else the file's time (a fresh clone's checkout time)
        return data, data["date"]
    when = datetime.datetime.fromtimestamp(os.path.getmtime(path), datetime.timezone.utc)
    return data, when.strftime("%Y-%m-%d") + " (file time)"


def _caption(ax, data, date, what):
    m = data.get("machine", {})
    ax.set_title(f"{what}\n{m.get('cpu_count', '?')}-core {m.get('jax_backend', 'cpu')}, "
                 f"{m.get('platform', '')[:40]}, measured {date}", fontsize=8)


def _save(fig, ax, path, xlabel, ylabel):
    ax.set_xlabel(xlabel)
    ax.set_ylabel(ylabel)
    ax.grid(True, which="both", alpha=0.3)
    ax.legend(fontsize=6, loc="upper left", bbox_to_anchor=(1.01, 1.0))
    fig.tight_layout()
    fig.savefig(path, dpi=130)
    plt.close(fig)


def sweep_throughput(results):
    d, date = _load(results, "sweep_throughput")
    fig, ax = plt.subplots(figsize=(9.0, 4.4))
    rj = d["results"]["rotorjax"]
    ladder = {}
    for row in rj.values():
        ladder.setdefault(row["variant"], []).append((row["error"], row["s_per_speed"], f"{row['rtol']:.0e}"))
    for i, (name, pts) in enumerate(ladder.items()):
        work_precision_curve(ax, pts, f"rotorjax: {name}",
                             "o-" if len(pts) > 1 else ["s", "^", "v", "<"][i % 4])
    for threads, rows in d["results"].get("dop853", {}).items():
        work_precision_curve(ax, [(r["error"], r["s_per_speed"], f"{r['rtol']:.0e}") for r in rows],
                             f"C DOP853 (numbalsoda), {threads}", "*-.")
    for threads, rows in d["results"]["numba"].items():
        work_precision_curve(ax, [(r["error"], r["s_per_speed"], f"h={r['h']:g}") for r in rows],
                             f"numba RK4, {threads}", "x--")
    for method, rows in d["results"]["scipy"].items():
        if isinstance(rows, list):
            work_precision_curve(ax, [(r["error"], r["s_per_speed"], f"{r['rtol']:.0e}") for r in rows],
                   f"scipy {method}, pure-Python rhs", "d:")
    _caption(ax, d, date, "model 001: 1000 speeds, tau in [0, 200]")
    _save(fig, ax, os.path.join(results, "sweep_throughput_wp.png"), "seconds per speed", "max error")
    a = d["targets"]["a"]
    per = d["targets"]["b"]["per_rung"]
    text = (f"At rotorjax's rtol-1e-6 error ({a['error']:.1e}) the buffered sweep over both cores is "
            f"{a['ratio']:.2f}x numba RK4 on 2 threads; the lead grows with accuracy, to {per[-1]['ratio']:.1f}x at "
            f"{per[-1]['error']:.1e}. Lanes here differ little in cost, so the buffer removes little lock-step "
            f"waste.")
    if "c" in d["targets"]:
        c = d["targets"]["c"]["per_rtol"]
        text += (" Against Hairer's DOP853 in C on 2 threads (numbalsoda, numba right-hand side) it is "
                 + " and ".join(f"{r['ratio']:.2f}x at {r['error']:.1e}" for r in c)
                 + f" (target 2x: {'met' if d['targets']['c']['met'] else 'not met'}).")
    return "sweep_throughput_wp.png", text


def limiters(results):
    d, date = _load(results, "limiters")
    fig, ax = plt.subplots(figsize=(9.0, 4.4))
    groups = {}
    for key, row in d["single_run"].items():
        name, tol = key.rsplit("_rtol", 1)
        groups.setdefault(name, []).append((row["error_after_5_revolutions"], row["seconds"], tol))
    for name, pts in groups.items():
        work_precision_curve(ax, pts, name.replace("_", " "), "o-" if name.startswith("rotorjax") else "d:")
    _caption(ax, d, date, "model 004 with limiters: one run of 300 revolutions")
    _save(fig, ax, os.path.join(results, "limiters_wp.png"), "seconds per run",
          "disk-position error after 5 revolutions")
    t = d["sweep"]["target"]
    m = d["matched_accuracy"]["rotorjax_smooth_dopri8_rtol1e-07"]
    return ("limiters_wp.png",
            f"One run at matched accuracy: rotorjax Dopri8 (smoothed contact, rtol 1e-7) is "
            f"{m['LSODA']['ratio']:.0f}x scipy LSODA and {m['Radau']['ratio']:.0f}x Radau. The 64-point "
            f"eccentricity sweep: {t['ratio']:.0f}x the LSODA loop at matched accuracy ({t['variant']}); "
            f"smoothed contact {t['smoothed_contact_best']['ratio']:.0f}x.")


def stability_map(results):
    d, date = _load(results, "stability_map")
    fig, ax = plt.subplots(figsize=(9.0, 4.4))
    rows = d["rows"]
    names = list(rows[0]["variants"])
    for name in names:
        work_precision_curve(ax, [(r["rotorjax_critical_error"], 1.0 / r["variants"][name]["points_per_s"],
                                   f"{r['rtol']:.0e}")
                                  for r in rows], f"rotorjax: {name}", "o-")
    for peer in rows[0]["scipy"]:
        work_precision_curve(ax, [(r["scipy_critical_error"], 1.0 / r["scipy"][peer]["points_per_s"],
                                   f"{r['rtol']:.0e}")
                                  for r in rows], f"scipy DOP853 loop, {peer} rhs", "d:")
    c_rows = [r for r in rows if isinstance(r.get("c_dop853"), dict)]
    for peer in (c_rows[0]["c_dop853"] if c_rows else []):
        work_precision_curve(ax, [(r["target_c_dop853"]["critical_error"], 1.0 / r["c_dop853"][peer]["points_per_s"],
                                   f"{r['rtol']:.0e}") for r in c_rows], f"C DOP853 (numbalsoda) loop, {peer}", "s--")
    _caption(ax, d, date, "model 001 Floquet map, 200 x 50 points")
    _save(fig, ax, os.path.join(results, "stability_map_wp.png"), "seconds per point",
          "critical-speed error (mu_w = 0.25)")
    r0 = rows[0]
    return ("stability_map_wp.png",
            f"At rtol {r0['rtol']:.0e} the vmapped margin through `sweep` (XLA's default options) maps "
            f"{r0['rotorjax_points_per_s']:.0f} points/s, "
            f"{r0['speedup']:.0f}x the strongest scipy loop ({r0['scipy_peer']} right-hand side) and "
            f"{r0['speedup_vs_numpy_peer']:.0f}x the numpy one, at the same critical-speed accuracy "
            f"(the scipy curves use scipy's own critical-speed error)."
            + "".join(f" At rtol {r['rtol']:.0e} `floquet_batch` maps {r['floquet_batch_points_per_s']:.0f} points/s, "
                      f"{r['target_c_dop853']['ratio_vs_1_thread']:.2f}x the C DOP853 loop over the same variational "
                      f"equations on 1 thread; over the 2 host devices {r['target_c_dop853']['ratio_vs_2_threads']:.2f}x its 2 threads."
                      for r in rows if r.get("target_c_dop853")))


def _bar_chart(path, data, date, what, ylabel, labels, ours, theirs, peer):
    """Time per analysis, rotorjax against `peer`, grouped by analysis (log axis), the
    ratio peer / rotorjax above each pair."""
    fig, ax = plt.subplots(figsize=(9.0, 4.4))
    x = range(len(labels))
    ax.bar([i - 0.2 for i in x], ours, 0.4, label="rotorjax")
    ax.bar([i + 0.2 for i in x], theirs, 0.4, label=peer)
    ax.set_yscale("log")
    ax.set_xticks(list(x))
    ax.set_xticklabels(labels, fontsize=7, rotation=15)
    for i, (a, b) in enumerate(zip(ours, theirs)):
        ax.annotate(f"{b / a:.0f}x", (i, max(a, b)), ha="center", fontsize=7, xytext=(0, 3),
                    textcoords="offset points")
    _caption(ax, data, date, what)
    ax.set_ylabel(ylabel)
    ax.grid(True, which="both", axis="y", alpha=0.3)
    ax.legend(fontsize=7)
    fig.tight_layout()
    fig.savefig(path, dpi=130)
    plt.close(fig)


def ross_parity(results):
    d, date = _load(results, "ross_parity")
    r, ross, agree = d["rotorjax"], d["ross"], d["agreement"]
    rows = [("damped modes", r["modes_s"], ross["modes_s"]),
            ("Campbell, 50 speeds", r["campbell_s"], ross["campbell_s"]),
            ("FRF, 200 freq.", r["frf_s"], ross["frf_s"]), ("static", r["static_s"], ross["static_s"])]
    per_design = {"critical": "critical speeds / design", "ucs": "UCS map / design", "level1": "API level I / design"}
    for key, label in per_design.items():  # rotorjax: 1000 designs in one vmapped call
        rows.append((label, r[key]["s_per_design"], ross[f"{key}_s_per_design"]))
    ratios = d["ratios_ross_over_rotorjax"]
    lo, hi = min(ratios, key=ratios.get), max(ratios, key=ratios.get)
    _bar_chart(os.path.join(results, "ross_parity_bars.png"), d, date,
               "ROSS's rotor_example: linear analyses (ROSS time / rotorjax time above each pair)", "seconds",
               *zip(*rows), f"ROSS {ross['version']}")
    return ("ross_parity_bars.png",
            f"rotorjax against ROSS: from {ratios[lo]:.0f}x ({lo}) to {ratios[hi]:.0f}x ({hi}; 1000 designs in "
            f"one vmapped call){'' if ratios[lo] > 1 else ' (below 1: ROSS faster)'}, agreeing with ROSS to "
            f"{agree['frf_max_rel']:.0e} (FRF) and {agree['critical_max_rel']:.0e} (critical speeds), "
            f"relative.")


def identification(results):
    d, date = _load(results, "identification")
    sw, ru = d["sweep"], d["runup"]
    _bar_chart(os.path.join(results, "identification_bars.png"), d, date,
               "model 002: supports' k1, k2, c1, c2 from 1x phasors (peer time / rotorjax time)", "seconds per fit",
               [f"{sw['n_speeds']}-speed sweep", f"run-up, {ru['samples']} samples"],
               [sw["rotorjax_lm_s"], ru["rotorjax_track_and_lm_s"]],
               [sw["scipy_lm_fd_s"], ru["scipy_lm_fd_s_plus_tracking"]], "scipy least_squares (LM, finite differences)")
    return ("identification_bars.png",
            f"Levenberg-Marquardt with the autodiff Jacobian: {sw['scipy_lm_fd_s'] / sw['rotorjax_lm_s']:.0f}x "
            f"scipy on the sweep and {ru['scipy_lm_fd_s_plus_tracking'] / ru['rotorjax_track_and_lm_s']:.0f}x on "
            f"the run-up, the same estimates to {max(sw['estimates_agree_rel'], ru['estimates_agree_rel']):.0e} "
            f"relative.")


def fe_identification(results):
    d, date = _load(results, "fe_identification")
    fit, sp, rj = d["rotorjax_fit_only"], d["scipy"], d["rotorjax"]
    rows = [("residual + Jacobian", d["res_jac"]["rotorjax_s"], d["res_jac"]["numpy_fd_s"]),
            ("fit, 1 start (LM)", fit["n_starts_1"]["s"], sp["lm"]["s"]),
            ("fit, 32 starts (LM)", fit["n_starts_32"]["s"], sp["lm_32_starts"]["s"])]
    _bar_chart(os.path.join(results, "fe_identification_bars.png"), d, date,
               f"flexible rig ({d['n_dofs']} dofs): {len(d['fit'])} bearing coefficients + unbalances from "
               f"{d['n_rows']} phasors (peer time / rotorjax time)", "seconds", *zip(*rows),
               "scipy least_squares, finite differences, numpy model")
    worst = max(r["max_rel_error"] for r in sp["lm"]["runs"] + fit["n_starts_1"]["runs"])
    return ("fe_identification_bars.png",
            f"Equal work: the fit alone is {sp['lm']['s'] / fit['n_starts_1']['s']:.1f}x scipy from one start and "
            f"{sp['lm_32_starts']['s'] / fit['n_starts_32']['s']:.0f}x from 32 (residual and Jacobian "
            f"{d['res_jac']['numpy_fd_s'] / d['res_jac']['rotorjax_s']:.0f}x), both ending within "
            f"{worst:.1e} (relative) of the true coefficients, the limit the data's noise sets. The whole "
            f"`identify` call (rotor file, set-up, fit, intervals, critical speeds with intervals) takes "
            f"{rj['n_starts_1']['s']:.2f} s from one start, {rj['n_starts_32']['s']:.2f} s from 32.")


def harmonic_balance(results):
    d, date = _load(results, "harmonic_balance")
    hb, bf, m, ref = d["harmonic_balance"], d["brute_force"], d["matched"], d["reference"]
    n = d["settings"]["speeds"][2]
    fig, ax = plt.subplots(figsize=(9.0, 4.4))
    work_precision_curve(ax, [(r["error_stable"], r["run_s"], f"H={h}") for h, r in hb.items()],
                         "rotorjax: periodic_branch + harmonic_balance", "o-")
    work_precision_curve(ax, [(r["error"], r["s_for_all_speeds"], f"{r['rtol']:.0e}, {r['t_end']:g} s")
                              for r in bf["rungs"]], "rotorjax: brute-force sweep (Dopri8 from rest)", "d:")
    ax.axhline(m["target"], color="0.5", lw=0.8, ls="--", label=f"target {m['target']:.0e}")
    _caption(ax, d, date, f"cubic bearings through the jump: {n} speeds over {d['settings']['speeds'][0]:g}.."
                          f"{d['settings']['speeds'][1]:g} rad/s")
    _save(fig, ax, os.path.join(results, "harmonic_balance_wp.png"), f"seconds for {n} speeds",
          "max relative amplitude error")
    h = hb[str(m["hb_harmonics"])]
    if m.get("ratio_is_lower_bound"):
        peer = (f"no brute-force rung reached {m['target']:.0e}; the costliest ({m['bf_s_lower_bound']:.0f} s) "
                f"bounds the ratio from below: harmonic balance at least {m['ratio']:.1f}x faster")
    else:
        peer = (f"the cheapest brute-force sweep within it (rtol {m['bf_rtol']:.0e}, {m['bf_t_end']:g} s from rest "
                f"at every speed, error {m['bf_error']:.1e}) {m['bf_s']:.0f} s (timed on "
                f"{bf['rungs'][0]['speeds_run']} speeds, scaled to {n}): harmonic balance {m['ratio']:.1f}x "
                f"faster at matched error")
    on = max(c["rel_diff"] for c in ref["checks"] if c["start"] != "rest")
    rest = max(c["rel_diff"] for c in ref["checks"] if c["start"] == "rest")
    busy = [r["other_cores_busy"] for r in list(hb.values()) + bf["rungs"] if r.get("other_cores_busy") is not None]
    return ("harmonic_balance_wp.png",
            f"ROSS's example rotor on cubic bearings, the unbalance response at {n} constant speeds through the "
            f"jump. Target error {m['target']:.0e} (max relative amplitude error over the speeds): harmonic "
            f"balance with H = {m['hb_harmonics']} (a branch of {h['points']} points with the library's default "
            f"steps, then every coexisting motion, {h['motions']} in all, solved at each speed) takes "
            f"{m['hb_s']:.1f} s at error {m['hb_error']:.1e}; {peer}. The sweep finds one motion per speed, and "
            f"not the unstable one. Errors against {ref['harmonics']}-harmonic references, which tight time "
            f"integrations started on them keep to {on:.0e} (one from rest, {rest:.0e}). Both measured in the "
            f"same run" + (f", other processes keeping {min(busy):.1f}-{max(busy):.1f} cores busy" if busy else "")
            + ": the ratio is the robust number.")


def journal_bearings(results):
    """The journal-bearing rotor (`journal_bearings.json`): error against time, the
    8-mode reduction at constant speed and in the run-up; the full rotor's summary in
    the reading."""
    d, date = _load(results, "journal_bearings")
    cases = d["cases"]
    reduced = {k: c for k, c in cases.items() if c.get("n_modes")}
    full = {k: c for k, c in cases.items() if not c.get("n_modes")}
    ok = lambda r: r.get("success", True) and r.get("code", 0) == 0  # noqa: E731
    fig, axes = plt.subplots(1, 2, figsize=(11.0, 4.4), sharey=True)
    for ax, (label, c) in zip(axes, reduced.items()):
        for name, v in c["runs"].items():
            style = "o-" if name.startswith("rotorjax") else ("x--" if "numba" in name else "d:")
            work_precision_curve(ax, [(r["error"], r["s"], f"{r['rtol']:.0e}") for r in v["ladder"] if ok(r)],
                                 name, style)
        ax.set_title(label, fontsize=8)
        ax.xaxis.set_minor_formatter(matplotlib.ticker.NullFormatter())
        ax.set_xlabel("seconds per run")
        ax.grid(True, which="both", alpha=0.3)
    axes[0].set_ylabel("final-state error (clearances)")
    n = next(iter(reduced.values()))["n_modes"]
    fig.suptitle(f"journal-bearing rotor, {n}-mode reduction: final state against the same model's reference "
                 f"(failed runs left out)\n{d['machine'].get('cpu_count', '?')}-core "
                 f"{d['machine'].get('jax_backend', 'cpu')}, {d['machine'].get('platform', '')[:40]}, measured {date}",
                 fontsize=8)
    axes[-1].legend(fontsize=6, loc="upper left", bbox_to_anchor=(1.01, 1.0))
    fig.tight_layout()
    fig.savefig(os.path.join(results, "journal_bearings_wp.png"), dpi=130)
    plt.close(fig)

    def matched(c):
        """Peer / rotorjax Dopri8 at rotorjax's error, over the rungs the peer's ladder brackets."""
        parts = []
        for peer in (p for p in c["runs"] if not p.startswith("rotorjax")):
            rs = [r for r in c["ratios"] if r["rotorjax"] == "rotorjax Dopri8" and r["peer"] == peer
                  and r["match"] == "interpolated"]
            if not rs:
                parts.append(f"{peer} never brackets it")
                continue
            lo, hi = min(rs, key=lambda r: r["matched_error"]), max(rs, key=lambda r: r["matched_error"])
            span = (f"{lo['matched_error']:.2f}x" if lo is hi else
                    f"{lo['matched_error']:.2f}x (at {lo['rotorjax_error']:.0e}) to {hi['matched_error']:.2f}x "
                    f"(at {hi['rotorjax_error']:.0e})")
            parts.append(f"{peer} {span}, {len(rs)} rungs")
        failed = sorted({f"{r['rtol']:.0e}" for v in c["runs"].values() for r in v["ladder"] if not ok(r)})
        return "; ".join(parts) + (f" (runs that stopped short, left out: rtol {', '.join(failed)})" if failed else "")

    red_text = " ".join(
        f"{label.split(': ', 1)[1].capitalize()}: rotorjax Dopri8's errors "
        f"{min(r['error'] for r in c['runs']['rotorjax Dopri8']['ladder']):.0e}.."
        f"{max(r['error'] for r in c['runs']['rotorjax Dopri8']['ladder']):.0e} clearances in "
        f"{min(r['s'] for r in c['runs']['rotorjax Dopri8']['ladder']):.2f}.."
        f"{max(r['s'] for r in c['runs']['rotorjax Dopri8']['ladder']):.2f} s; peer time / rotorjax time at "
        f"rotorjax's error: {matched(c)}." for label, c in reduced.items())
    red_err = " ".join(
        f"{scen.capitalize()}: {e['final_nodes_max_abs_diff_clearances']:.2f} clearances at the end "
        f"({e['final_nodes_diff_relative_to_largest_full_displacement']:.0%} of the largest displacement)."
        for scen, e in d.get("reduction_error", {}).items())
    eq_err = max((e["equilibrium_nodes_max_abs_diff_clearances"] for e in d.get("reduction_error", {}).values()),
                 default=None)
    full_text = []
    for label, c in full.items():
        sm = d["summary"][label]["at_noise_floor"]
        rj_row = c["runs"]["rotorjax Dopri8"]["ladder"][0]
        rat = ", ".join(f"{p} {v:.2f}x" for p, v in sm["ratio_peer_over_rotorjax_dopri8"].items())
        when = f", carried over from the run of {c['carried_over']['date']}" if "carried_over" in c else ""
        full_text.append(f"{label.split(': ', 1)[1]} ({c['t_end_s'] / rj_row['steps']:.0e} s steps at rtol "
                         f"{rj_row['rtol']:.0e}{when}): {rat}")
    busy = [(c.get("cpu") or (c.get("carried_over") or {}).get("cpu_of_that_run") or {}).get("other_cores_busy")
            for c in cases.values()]
    busy = [b for b in busy if b is not None]
    caveat = (f" Other processes kept {min(busy):.1f}-{max(busy):.1f} of the "
              f"{d['machine'].get('cpu_count', '?')} cores busy while the cases ran: absolute times are slowed, "
              f"the ratios within a case are the robust numbers." if busy else "")
    return ("journal_bearings_wp.png",
            f"ROSS's example rotor on two short journal bearings (`{d['setup'].get('rotor_file', 'journal_rig')}`: "
            f"nonlinear film forces, gravity, unbalance), from the static equilibrium: the final state after "
            f"{'; '.join(label.split(': ', 1)[1] for label in reduced)}, with the {n}-mode reduction an engineer "
            f"would run (`[rotor] n_modes = {n}`, the films still at the journal nodes). The peers (numba-compiled "
            f"DOP853; scipy `solve_ivp` DOP853 and Hairer's Fortran dop853, both with a numba right-hand side) "
            f"integrate the scene's own matrices. {red_text} Reduction error against the full "
            f"{d['setup']['full']['n_shaft'] if 'full' in d['setup'] else 28}-dof rotor (the two references' node "
            f"positions): {red_err}" + (f" At the equilibrium {eq_err:.2f} clearances." if eq_err is not None else "")
            + " The full rotor (not drawn): its highest shaft modes bound every explicit solver's steps, every rtol "
            f"lands at the error floor and matched error only extrapolates; the cheapest run of each within "
            f"{d['summary'][next(iter(full))]['at_noise_floor']['error_limit'] / d['summary'][next(iter(full))]['error_floor_reference_disagreement']:.0f}x "
            f"the references' disagreement, peer / rotorjax Dopri8: " + "; ".join(full_text) + "." + caveat)


def step_cost(results):
    """Where a lane-step's time goes (`benchmarks/step_cost.py`): per case, the
    lane-step split into right-hand sides, stage sums and the rest, beside the
    arithmetic bound and the peer's right-hand sides."""
    d, date = _load(results, "step_cost")
    cases = d["cases"]
    fig, ax = plt.subplots(figsize=(9.0, 4.4))
    labels = list(cases)
    parts = (("step", "the step: 13 right-hand sides and the stage sums"),
             ("control_dense_output_and_buffer", "step control, dense output, buffer"))
    left = [0.0] * len(labels)
    for key, name in parts:
        widths = [cases[k]["split_us"][key] for k in labels]
        ax.barh(range(len(labels)), widths, left=left, label=name)
        left = [a + b for a, b in zip(left, widths)]
    marks = (([cases[k]["rhs_alone_per_step_us"] for k in labels], "o", "w",
              "13 right-hand sides alone, over the same lanes"),
             ([13 * cases[k]["peer"]["numba_rhs_us"] for k in labels], "x", "r",
              "13 numba right-hand sides (the C loop's)"),
             ([cases[k]["arithmetic_bound_us"] for k in labels], "|", "k", "arithmetic bound (flops / one core's peak)"))
    for xs, marker, color, name in marks:
        ax.scatter(xs, range(len(labels)), marker=marker, s=120, color=color, edgecolors="k", label=name, zorder=3)
    ax.set_xscale("log")
    ax.set_yticks(range(len(labels)))
    ax.set_yticklabels(labels, fontsize=7)
    _caption(ax, d, date, "microseconds per lane-step, Dopri8, one core")
    _save(fig, ax, os.path.join(results, "step_cost_bars.png"), "microseconds per lane-step", "")
    said = "; ".join(
        f"{k} ({c['lanes']} lanes): {c['lane_step_us']:.2f} us a lane-step, "
        f"{100 * c['split_us']['step'] / c['lane_step_us']:.0f}% of it the step itself (13 right-hand sides alone: "
        f"{c['rhs_alone_per_step_us']:.2f} us, {c['rhs_us'] * 1e3:.0f} ns each against the numba peer's "
        f"{c['peer']['numba_rhs_us'] * 1e3:.0f} ns; over 512 lanes {c['rhs_us_by_lanes']['512'] * 1e3:.0f} ns), "
        f"{100 * c['fraction_of_peak']:.1f}% of the core's peak (bound {c['arithmetic_bound_us']:.2f} us)"
        + (f"; numba DOP853 {c['peer']['numba_dop853_step_us']:.2f} us a step" if "numba_dop853_step_us"
           in c["peer"] else "")
        for k, c in cases.items())
    pk = d["peak"]
    return ("step_cost_bars.png",
            f"The batch path's cost per lane-step against its right-hand side and the arithmetic bound "
            f"({pk['gflops_per_core']:.1f} GFLOP/s a core: {pk['clock_ghz']:.2f} GHz x {pk['flops_per_cycle']} "
            f"flops a cycle, {pk['basis']}). {said}.")


def bench_quick(results):
    """`rotorjax bench --quick` on this machine (its report copied to bench_quick.json)."""
    from rotorjax.plot import plot_bench

    d, _ = _load(results, "bench_quick")
    fig = plot_bench(d)
    fig.savefig(os.path.join(results, "bench_quick.png"), dpi=120)
    plt.close(fig)
    pairs = {}
    for r in d["table"]:
        if r["match"] == "interpolated" or r["match"].startswith("same"):
            pairs.setdefault((r["comparison"], r["peer"]), []).append(f"{r['ratio']:.3g}x at {r['error']:.1e}")
    said = "; ".join(f"{c} vs {p}: {', '.join(v)}" for (c, p), v in pairs.items())
    skipped = [f"{s['peer']} ({c['name']})" for c in d["comparisons"] for s in c["skipped"]]
    return ("bench_quick.png",
            f"`rotorjax bench --quick` ({d['machine']['device']}, {d['machine']['date']}), rotorjax on one device, "
            f"ratios at matched error (where the peer's ladder brackets rotorjax's error; below 1: the peer is "
            f"faster), "
            f"at rotorjax's error (Campbell: agreement with ROSS): {said}."
            + (f" Skipped: {', '.join(skipped)}." if skipped else "")
            + " Smaller sizes than the studies above: the ratios are the command's, not the benchmarks'.")


def page(entries, path):
    lines = ["# Benchmark results", "",
             "Generated by `python benchmarks/work_precision.py` from `benchmarks/results/*.json`, the last "
             "measured state; do not edit by hand. Each diagram: log error against log time, one curve per "
             "method, markers labelled with the tolerance (or step). Lower left wins.", ""]
    for title, (png, reading) in entries:
        lines += [f"## {title}", "", f"![{title}](results/{png})", "", reading, ""]
    with open(path, "w") as f:
        f.write("\n".join(lines))


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--results", default=os.path.join(HERE, "results"))
    ap.add_argument("--page", default=os.path.join(HERE, "README.md"))
    args = ap.parse_args()
    entries = [("Model 001 speed sweep", sweep_throughput(args.results)),
               ("Model 004 with limiters", limiters(args.results)),
               ("Floquet stability map", stability_map(args.results)),
               ("Linear analyses against ROSS", ross_parity(args.results)),
               ("Identification of support stiffness and damping", identification(args.results)),
               ("Identification of a flexible rotor's bearings", fe_identification(args.results)),
               ("Harmonic balance against brute-force sweeps", harmonic_balance(args.results)),
               ("Journal bearings: time integration against CPU peers", journal_bearings(args.results)),
               ("Where a lane-step's time goes", step_cost(args.results)),
               ("`rotorjax bench --quick`", bench_quick(args.results))]
    page(entries, args.page)
    print(f"wrote {len(entries)} diagrams and {args.page}")


if __name__ == "__main__":
    main()
