"""The results page and work-precision diagrams (`benchmarks/work_precision.py`) are
generated from the benchmarks' JSON: every number on the page is the JSON's."""

import json
import shutil
import subprocess
import sys
from pathlib import Path

import pytest

from .helpers import documentation

BENCH = Path(__file__).resolve().parents[1] / "benchmarks"
NAMES = ("sweep_throughput", "limiters", "stability_map", "ross_parity", "identification", "fe_identification",
         "harmonic_balance", "journal_bearings", "step_cost", "bench_quick")
PNGS = ("sweep_throughput_wp", "limiters_wp", "stability_map_wp", "ross_parity_bars", "identification_bars",
        "fe_identification_bars", "harmonic_balance_wp", "journal_bearings_wp", "step_cost_bars", "bench_quick")


def _bench_module(name):
    """A benchmark script imported as a module (for its `table`), `benchmarks/` on the path meanwhile."""
    import importlib

    sys.path.insert(0, str(BENCH))
    try:
        return importlib.import_module(name)
    finally:
        sys.path.remove(str(BENCH))


def test_page_and_diagrams_from_the_json(tmp_path):
    for name in NAMES:
        shutil.copy(BENCH / "results" / f"{name}.json", tmp_path)
    page = tmp_path / "README.md"
    subprocess.run([sys.executable, str(BENCH / "work_precision.py"), "--results", str(tmp_path),
                    "--page", str(page)], check=True, capture_output=True, text=True)
    for name in PNGS:
        png = tmp_path / f"{name}.png"
        assert png.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    text = page.read_text()
    sweep = json.loads((tmp_path / "sweep_throughput.json").read_text())
    assert f"{sweep['targets']['a']['ratio']:.2f}x numba RK4 on 2 threads" in text
    for row in sweep["targets"].get("c", {}).get("per_rtol", []):  # the C DOP853 peer, where it ran
        assert f"{row['ratio']:.2f}x at {row['error']:.1e}" in text
    lim = json.loads((tmp_path / "limiters.json").read_text())["sweep"]["target"]
    assert f"{lim['ratio']:.0f}x the LSODA loop" in text
    stab = json.loads((tmp_path / "stability_map.json").read_text())["rows"][0]
    assert f"{stab['rotorjax_points_per_s']:.0f} points/s, {stab['speedup']:.0f}x" in text
    ross = json.loads((tmp_path / "ross_parity.json").read_text())["ratios_ross_over_rotorjax"]
    assert f"from {min(ross.values()):.0f}x" in text and f"to {max(ross.values()):.0f}x" in text
    ident = json.loads((tmp_path / "identification.json").read_text())["sweep"]
    assert f"{ident['scipy_lm_fd_s'] / ident['rotorjax_lm_s']:.0f}x scipy on the sweep" in text
    fe = json.loads((tmp_path / "fe_identification.json").read_text())
    assert f"{fe['scipy']['lm_32_starts']['s'] / fe['rotorjax_fit_only']['n_starts_32']['s']:.0f}x from 32" in text
    hb = json.loads((tmp_path / "harmonic_balance.json").read_text())["matched"]
    assert f"takes {hb['hb_s']:.1f} s at error {hb['hb_error']:.1e}" in text
    assert f"{hb['ratio']:.1f}x faster" in text
    cost = json.loads((tmp_path / "step_cost.json").read_text())
    for label, c in cost["cases"].items():
        assert f"{label} ({c['lanes']} lanes): {c['lane_step_us']:.2f} us a lane-step" in text
        assert f"{100 * c['fraction_of_peak']:.1f}% of the core's peak" in text
    quick = json.loads((tmp_path / "bench_quick.json").read_text())
    for row in quick["table"]:  # every bracketed ratio is quoted with its error
        if row["match"] == "interpolated":
            assert f"{row['ratio']:.3g}x at {row['error']:.1e}" in text
    # the committed page is the generated one
    assert (BENCH / "README.md").read_text() == text.replace(str(tmp_path), str(BENCH / "results"))


def test_readme_startup_table_is_the_json():
    """The README's start-up table (first and cached runs of the everyday commands) is
    `benchmarks/results/startup.json`'s, as `python benchmarks/startup.py --table` prints it."""
    startup = _bench_module("startup")
    out = json.loads((BENCH / "results" / "startup.json").read_text())
    readme = documentation()
    assert startup.table(out) in readme
    readme = " ".join(readme.split())
    cached = [r["cached_s"] for r in out["commands"] if r["command"].split()[0] in out["targets"]["cached_commands"]]
    assert f"cached runs of `modes`, `campbell`, `critical-speeds` and `response`: {min(cached):.1f}-" \
           f"{max(cached):.1f} s" in readme
    first = [r["first_s"] for r in out["commands"]]
    assert f"first runs {min(first):.1f}-{max(first):.1f} s." in readme
    # issue 61's targets on the 36-dof rotor, and whether the runs meet them, as the JSON's rows say
    v = out["targets"]
    assert v == startup.verdict(out["commands"])
    assert (f"The goal on the 36-dof rotor: a cached run under {v['cached_s']:g} s "
            f"({'met' if v['cached_met'] else 'not met'}: {v['slowest_cached_s']:.1f} s at the slowest) and a "
            f"first run under {v['first_s']:g} s ({'met' if v['first_met'] else 'not met'}: "
            f"{v['slowest_first_s']:.1f} s).") in readme
    sp = v["cached_split_median"]
    assert (f"interpreter start {sp['start_s']:.1f} s, imports {sp['import_s']:.1f} s, tracing and lowering "
            f"{sp['trace_s'] + sp['lower_s']:.1f} s, cache loads {sp['cache_load_s']:.1f} s, and the rest "
            f"{sp['execute_other_s']:.1f} s") in readme
    if sp["import_s"] >= v["cached_s"]:
        assert f"the imports alone take longer than the {v['cached_s']:g} s goal" in readme


def test_readme_stiff_defaults_table_is_the_json():
    """The README's table of `simulate`'s defaults on stiff rotor files, and the ratios
    quoted under it, are `benchmarks/results/stiff_defaults.json`'s."""
    stiff_defaults = _bench_module("stiff_defaults")
    out = json.loads((BENCH / "results" / "stiff_defaults.json").read_text())
    readme = " ".join(documentation().split())
    assert " ".join(stiff_defaults.table(out).split()) in readme
    cases = {c["rotor"]: c for c in out["cases"]}
    reduced = [c for c in out["cases"] if c["plan"]["modes"]]
    speedups = [c["dopri8_full_model"]["run_s"] / c["auto"]["run_s"] for c in reduced]
    assert f"they run {min(speedups):.0f}-{max(speedups):.0f}x faster than Dopri8" in readme
    assert " and ".join(f"{c['auto']['error']:.1e}".replace("e-0", "e-") for c in reduced) in readme
    over = [c["plan"]["estimated_explicit_steps_full"] / c["dopri8_full_model"]["steps"] for c in out["cases"]]
    over += [c["plan"]["estimated_explicit_steps"] / c["auto"]["steps"] for c in reduced]
    assert f"{min(over):.2f}-{max(over):.1f}x the steps taken" in readme
    journal = cases["journal_rig.toml"]
    assert journal["auto"]["solver"] == "Kvaerno5" and journal["auto"]["success"]
    assert f"is {journal['auto']['run_s'] / journal['dopri8_full_model']['run_s']:.1f}x faster there" in readme
    # every default run succeeded within the budget; the full FE rotors would not have
    assert all(c["auto"]["success"] and c["auto"]["steps"] <= c["max_steps"] for c in out["cases"])
    assert all(c["dopri8_full_model"]["steps"] > c["max_steps"] for c in out["cases"])


def test_readme_step_cost_table_and_fe_batch_are_the_json():
    """The README's table of where a lane-step's time goes is `step_cost.json`'s, and the
    readings under it hold there; the FE rotor's batch ratios are `rotor_scene.json`'s."""
    step_cost = _bench_module("step_cost")
    out = json.loads((BENCH / "results" / "step_cost.json").read_text())
    readme = " ".join(documentation().split())
    assert " ".join(step_cost.table(out).split()) in readme
    c = out["cases"]
    small = [c["model 001"], c["FE rotor, 8 modes"]]
    full = c["FE rotor, full (28 dofs)"]
    # "a quarter to a third of a lane-step" in control and the buffer; "16-19% of the peak"; "45%"
    assert all(0.25 <= x["split_us"]["control_dense_output_and_buffer"] / x["lane_step_us"] <= 1 / 3 + 0.01
               for x in small)
    assert all(0.155 <= x["fraction_of_peak"] <= 0.195 for x in small) and round(100 * full["fraction_of_peak"]) == 45
    ns = lambda x, k: f"{x['rhs_us_by_lanes'][k] * 1e3:.0f}"  # noqa: E731
    m, r = small
    assert (f"falls from {ns(m, '8')} to {ns(m, '512')} ns (model 001) and from {ns(r, '8')} to {ns(r, '512')} ns "
            f"(8 modes)") in readme
    assert all(x["rhs_us_by_lanes"]["8"] > x["rhs_us_by_lanes"]["512"] for x in small)
    assert f"({ns(full, '128')} ns at 128 lanes, {ns(full, '512')} ns at 512)" in readme
    assert full["rhs_us_by_lanes"]["512"] > full["rhs_us_by_lanes"]["128"] < full["rhs_us_by_lanes"]["8"]
    assert all(x["rhs_us_by_lanes"]["512"] < x["peer"]["numba_rhs_us"] for x in small)
    assert (f"({ns(m, '512')} and {ns(r, '512')} ns against {m['peer']['numba_rhs_us'] * 1e3:.0f} and "
            f"{r['peer']['numba_rhs_us'] * 1e3:.0f} ns)") in readme
    # the full rotor's right-hand side "about 3x cheaper" than numba's
    assert 2.5 < full["peer"]["numba_rhs_us"] / full["rhs_us"] < 3.5
    batch = json.loads((BENCH / "results" / "rotor_scene.json").read_text())["batch"]
    f, r, big = batch["full (28 dofs)"], batch["reduced (8 modes)"], batch["reduced (8 modes), 512 speeds"]
    one, two = "numba_loop_over_rotorjax_batch", "numba_prange_2_threads_over_rotorjax_batch_2_devices"
    x = lambda v: f"{v:.2f}x"  # noqa: E731
    assert (f"On one core, `simulate_batch` takes {f['rotorjax_batch']['s']:.2f} s for the full rotor: "
            f"{x(f['ratios'][one])} the numba-compiled DOP853 loop on one thread. With `shard=True` over the two "
            f"host devices it takes {f['rotorjax_batch_2_devices']['s']:.2f} s: {x(f['ratios'][two])} the loop's "
            f"`prange` over 2 threads. The 8-mode rotor's batch takes {r['rotorjax_batch']['s'] * 1e3:.0f} ms on one "
            f"core: {x(r['ratios'][one])} the one-thread loop. On two devices it is {x(r['ratios'][two])} the "
            f"2-thread loop: 64 speeds leave each device 32 lanes, where the 8-mode right-hand side costs "
            f"{ns(c['FE rotor, 8 modes'], '32')} ns a lane against {ns(c['FE rotor, 8 modes'], '64')} ns "
            f"at 64") in readme
    # "a device's half takes as long as the whole batch on one": two devices no faster than one (within 25 %)
    assert r["rotorjax_batch_2_devices"]["s"] > 0.8 * r["rotorjax_batch"]["s"]
    assert (f"At 512 speeds the lanes fill: {x(big['ratios'][one])} the one-thread loop on one core, "
            f"{x(big['ratios'][two])} the 2-thread loop on two devices. Errors are "
            f"{f['rotorjax_batch_error_max']:.1e} (full) and {r['rotorjax_batch_error_max']:.1e} (8 modes)") in readme
    assert (f"64 speeds, one core against one thread / two devices against 2 threads: {x(f['ratios'][one])} / "
            f"{x(f['ratios'][two])} (full), {x(r['ratios'][one])} / {x(r['ratios'][two])} (8 modes); 512 speeds "
            f"(8 modes): {x(big['ratios'][one])} / {x(big['ratios'][two])} |") in readme
    v = [b["rotorjax_vmap_one_call"] for b in (f, r)]
    assert (f"| full: {v[0]['s']:.1f} s; 8 modes: {v[1]['s']:.2f} s | numba loop "
            f"{f['numba_dop853_loop_1_thread']['s']:.1f} s / {r['numba_dop853_loop_1_thread']['s']:.2f} s; scipy loop "
            f"{f['scipy_solve_ivp_dop853_numba_rhs_loop']['s']:.0f} s / "
            f"{r['scipy_solve_ivp_dop853_numba_rhs_loop']['s']:.1f} s | "
            f"{x(f['ratios']['numba_loop_over_rotorjax_one_call'])} / "
            f"{x(r['ratios']['numba_loop_over_rotorjax_one_call'])} numba") in readme
    assert all(b[k]["failed"] == 0 for b in (f, r, big) for k in ("rotorjax_batch", "rotorjax_batch_2_devices"))
    # the table row's single runs: Dopri8's time at rtol 1e-8, and each peer's range of ratios at matched error
    wp = json.loads((BENCH / "results" / "rotor_scene.json").read_text())["work_precision"]
    wf, wr = wp["full (28 dofs)"], wp["reduced (8 modes)"]

    def ranges(w):
        by_peer = {}
        for row in w["ratios"]:
            if row["rotorjax"] == "rotorjax Dopri8":
                by_peer.setdefault(row["peer"], []).append(row["matched_error"])
        g = lambda v: f"{v:.1f}" if v >= 0.5 else f"{v:.2f}"  # noqa: E731
        return " / ".join(f"{g(min(v))}-{g(max(v))}x" for v in by_peer.values())

    at_1e8 = lambda w: next(x["s"] for x in w["runs"]["rotorjax Dopri8"]["ladder"] if x["rtol"] == 1e-8)  # noqa: E731
    assert f"full 28 dofs: {at_1e8(wf):.2f} s at rtol 1e-8; 8 modes: {at_1e8(wr) * 1e3:.0f} ms; 64 speeds" in readme
    assert f"one run: {ranges(wf)} (full); {ranges(wr)} (8 modes" in readme
    assert f["rotorjax_batch"]["method"] == "Dopri8+vectorised" and f["rotorjax_batch"]["failed"] == 0


def test_readme_gpu_batch_numbers_are_the_json():
    """The accelerator benchmark's README numbers are `gpu_batch_cpu.json`'s, and no GPU
    figure is quoted: no `gpu_batch_gpu.json` has been measured."""
    out = json.loads((BENCH / "results" / "gpu_batch_cpu.json").read_text())
    readme = " ".join(documentation().split())
    v, p = out["runs"]
    assert out["device"]["platform"] == "cpu" and out["gpu_figure"].startswith("none")
    assert not (BENCH / "results" / "gpu_batch_gpu.json").exists() and "No GPU figure exists yet" in readme
    assert (f"`vectorised`: {v['trajectories_per_s']:.0f} trajectories/s, {100 * v['fraction_of_peak']:.1f}% of the "
            f"CPU's peak") in readme
    assert f"`pallas` (interpret mode): {p['trajectories_per_s']:.0f} trajectories/s" in readme
    d = v["kernels_differ_by"]
    assert f"differ by {d['median']:.0e} (median over the points, relative) and {d['p90']:.0e}" in readme
    assert d["median"] < 1e-9 and all(r["points_failed"] == 0 for r in out["runs"])


def test_readme_floquet_map_numbers_are_the_json():
    """The README's Floquet-map table (issue 32, item 4) quotes `stability_map.json`:
    `floquet_batch` and the C DOP853 loop over the same variational equations, on 1 and
    2 cores, the vmapped margin with and without the XLA option, the scipy loop; and
    the measured target holds as stated (at least 1x the C loop on one core)."""
    out = json.loads((BENCH / "results" / "stability_map.json").read_text())
    readme = " ".join(documentation().split())
    for r in out["rows"]:
        t, c, v = r["target_c_dop853"], r["c_dop853"], r["variants"]
        row = (f"| {r['rtol']:.0e} | {v['floquet_batch, 1 device']['points_per_s']:.0f} points/s | "
               f"{c['1 thread']['points_per_s']:.0f} (**{t['ratio_vs_1_thread']:.2f}x**) | "
               f"{v[t['rotorjax_vs_2_threads']]['points_per_s']:.0f} | {c['2 threads']['points_per_s']:.0f} "
               f"(**{t['ratio_vs_2_threads']:.2f}x**) | "
               f"{v['sweep with CPU_COMPILER_OPTIONS, 1 device']['points_per_s']:.0f} / "
               f"{v['sweep, 1 device']['points_per_s']:.0f} | {r['scipy_points_per_s']:.0f} "
               f"({r['floquet_batch_speedup']:.0f}x) |")
        assert row in readme, row
        assert t["ratio_vs_1_thread"] >= 1
    r6 = out["rows"][0]
    assert (f"error {r6['rotorjax_critical_error']:.1e} (rotorjax) and {r6['target_c_dop853']['critical_error']:.1e} "
            "(C DOP853)") in readme


def test_readme_fe_identification_row_is_the_json():
    """The README's FE-identification rows quote `fe_identification.json`: the fit
    alone from 1 and 32 starts against scipy's LM (one start, and from the same 32
    starts), the ratios, and the whole `identify` call."""
    fe = json.loads((BENCH / "results" / "fe_identification.json").read_text())
    readme = " ".join(documentation().split())
    fit, sp, ratio = fe["rotorjax_fit_only"], fe["scipy"], fe["time_ratios_scipy_over_rotorjax"]
    eq = ratio["equal_work_fit_only"]
    assert (f"| {1e3 * fit['n_starts_1']['s']:.2g} ms / {fit['n_starts_32']['s']:.2g} s (LM, receptance coupling) | "
            f"scipy `least_squares` LM with finite differences, numpy model: {1e3 * sp['lm']['s']:.2g} ms / "
            f"{sp['lm_32_starts']['s']:.2g} s | {eq['scipy_lm_over_rotorjax_fit_only_1_start']:.2g}x / "
            f"{eq['scipy_lm_32_starts_over_rotorjax_fit_only_32_starts']:.2g}x (same optimum to 1e-6; residual + "
            f"Jacobian {ratio['res_jac']:.2g}x) |") in readme
    whole = fe["rotorjax"]["n_starts_32"]
    assert f"| {whole['s']:.2g} s (first, compiling, call {whole['first_call_s']:.2g} s) |" in readme


def test_readme_uncertainty_and_design_numbers_are_the_json():
    """The README's Monte Carlo and design benchmark sentences quote `uncertainty.json`
    and `design.json`."""
    readme = " ".join(documentation().split())
    u = json.loads((BENCH / "results" / "uncertainty.json").read_text())
    assert (f"rotorjax {u['rotorjax_per_sample_ms']:.3g} ms a sample; a numpy/scipy loop doing the same fixed points "
            f"{u['peer_per_sample_ms']:.2g} ms ({u['ratio_peer_over_rotorjax']:.2f}x") in readme
    assert f"(a close pair: {u['retried_samples']} of {u['samples']} samples on ROSS's example rotor below)" in readme
    minutes = u["rotorjax_per_sample_ms"] * 1e5 / 6e4
    assert f"At that rate 10^5 samples take {minutes:.2g} minutes on this 2-core machine" in readme
    r = u["ross"]
    assert (f"`ST_Rotor.run_campbell` ({r['scan_speeds_a']} speeds) {r['ross_a_per_sample_s']:.3g} s a sample "
            f"({r['ratio_ross_a_over_rotorjax']:.0f}x), a loop of its `run_critical_speed` and `run_modal` "
            f"{r['ross_b_per_sample_s']:.2g} s ({r['ratio_ross_b_over_rotorjax']:.0f}x)") in readme
    d = json.loads((BENCH / "results" / "design.json").read_text())
    assert (f"rotorjax converges in {d['rotorjax']['seconds']:.2g} s ({d['rotorjax']['evaluations']} evaluations, "
            f"compiled), scipy's SLSQP on the same compiled objective with finite-difference gradients in "
            f"{d['slsqp_fd']['seconds']:.2g} s ({d['ratios']['slsqp_fd_over_rotorjax']:.2g}x), with rotorjax's "
            f"exact gradient in {d['slsqp_exact']['seconds']:.2g} s") in readme
    assert f"(one gradient {d['gradient_eval_ms'] / d['objective_eval_ms']:.2g} objective evaluations" in readme


def test_readme_auto_balancing_range_numbers_are_the_json():
    """The README's auto-balancing-range design sentence quotes `auto_balancing_range.json`."""
    readme = " ".join(documentation().split())
    d = json.loads((BENCH / "results" / "auto_balancing_range.json").read_text())
    r, peer = d["rotorjax"], d["lbfgsb_fd"]
    t = r["rescan"]["thresholds"]
    assert (f"the stable range grows from {r['before']:.4g} to {r['after']:.4g} (`mu_xi` {r['x']['mu_xi']:.3g}, "
            f"`mu_eta` at its bound {r['x']['mu_eta']:g}; thresholds {t[0]:.4g}, {t[1]:.4g} and {t[2]:.4g}, the "
            f"fresh scan agreeing to {abs(r['rescan']['scanned'] - r['rescan']['followed']):.2g}) in "
            f"{r['evaluations']} evaluations and {r['seconds']:.2g} s, the rescan included (the first call "
            f"{r['first_call_s']:.3g} s, compiling); scipy's L-BFGS-B on the same compiled objective with "
            f"finite-difference gradients reaches the same optimum in {peer['evaluations']} evaluations and "
            f"{peer['seconds']:.2g} s ({d['ratio_lbfgsb_fd_over_rotorjax']:.2g}x)") in readme
    assert r["rescan"]["agree"] and abs(peer["after"] - r["after"]) < 1e-6 * r["after"]


def test_continuation_auto07p_times_are_the_json():
    """docs/continuation.md's times against AUTO-07p (the compiled continuation core, issue 62) are
    `auto07p.json`'s: the Duffing fold curve, the forced Jeffcott branch with its points and harmonics, the
    Hopf curve."""
    out = json.loads((BENCH / "results" / "auto07p.json").read_text())
    docs = " ".join(documentation().split())
    a, b, c = (out[k] for k in ("duffing_fold_curve", "jeffcott_hopf_curve", "jeffcott_forced_branch"))
    assert (f"the Duffing fold curve {a['rotorjax']['median_s']:.3f} s against AUTO's {a['auto']['run_s']:.3f} s "
            f"run after a {a['auto']['compile_s']:.3f} s compile ({a['ratio_rotorjax_median_over_auto_run']:.1f}x "
            f"the run, {a['ratio_rotorjax_median_over_auto_compile_plus_run']:.1f}x compile and run)") in docs
    assert (f"(part (c), {c['rotorjax']['branch_points']} points with {c['rotorjax']['harmonics']} harmonics, "
            f"four folds) {c['rotorjax']['median_s']:.2f} s against AUTO's {c['auto']['run_s']:.2f} s, "
            f"{c['ratio_rotorjax_median_over_auto_run']:.1f}x") in docs
    assert len(c["rotorjax"]["folds"]) == 4
    assert (f"still {b['rotorjax']['median_s']:.1f} s against {b['auto']['run_s']:.3f} s") in docs


def test_the_speed_page_states_the_threshold_scan():
    """docs/speed.md's row of benchmarks/threshold_scan.py is its JSON's."""
    rows = {r["case"]: r for r in json.loads((BENCH / "results" / "threshold_scan.json").read_text())["cases"]}
    order = ("journal_rig", "tapered_36", "model_001_floquet")

    def joined(key, fmt):
        return " / ".join(format(rows[c][key], fmt) for c in order)

    page = documentation("docs/speed.md")
    assert (f"first call {joined('points_cold_s', '.2f')} s; repeated {joined('points_warm_s', '.3f')} s "
            f"| the vmapped scan (the margin compiled twice): {joined('vmap_cold_s', '.2f')} s; "
            f"{joined('vmap_warm_s', '.3f')} s | first call {joined('cold_ratio_vmap_over_points', '.1f')}x sooner; "
            f"repeated {joined('warm_ratio_vmap_over_points', '.2f')}x |") in page
    # what was scanned: the journal rig's oil whirl (~207.6 rad/s, benchmarks/journal_bearings.py), model 001's
    # three crossings at the paper's weight damping (notebooks/stability_boundaries.py), the tapered rotor stable
    assert rows["journal_rig"]["thresholds"] == pytest.approx([207.55], abs=0.01)
    assert rows["model_001_floquet"]["thresholds"] == pytest.approx([1.014348, 5.049930, 8.322286], abs=1e-5)
    assert rows["tapered_36"]["thresholds"] == [] and {r["n_scan"] for r in rows.values()} == {200}


def test_continuation_times_are_the_json():
    """docs/speed.md's row of benchmarks/continuation.py (against jaxcont) and docs/continuation.md's
    time for model 001's boundaries are `continuation.json`'s."""
    d = json.loads((BENCH / "results" / "continuation.json").read_text())
    b, r, j = d["boundaries_001"], d["shared"]["rotorjax"], d["shared"]["jaxcont"]
    speed = (BENCH.parent / "docs" / "speed.md").read_text()
    assert (f"| {r['brusselator_s']:.3f} s (error {max(r['hopf_error'], r['hopf_frequency_error']):.0e}) / "
            f"{r['duffing_s']:.3f} s (both folds, {r['fold_error_rel']:.0e}) | jaxcont {j['version']}: "
            f"{j['brusselator_s']:.2f} s ({max(j['hopf_error'], j['hopf_frequency_error']):.0e}) / "
            f"{j['duffing_s']:.2f} s (one fold of two, {j['fold_error_rel']:.0e}) | "
            f"{j['brusselator_s'] / r['brusselator_s']:.0f}x / {j['duffing_s'] / r['duffing_s']:.0f}x |") in speed
    docs = " ".join((BENCH.parent / "docs" / "continuation.md").read_text().split())
    assert (f"in {b['trace_boundaries_first_call_s']:.0f} s on 2 cores (a second call "
            f"{b['trace_boundaries_second_call_s']:.0f} s)") in docs
