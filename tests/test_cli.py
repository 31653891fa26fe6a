"""The rotorjax command."""

import json
import subprocess
import sys

import numpy as np
import pytest

from rotorjax.cli import main


def test_simulate_json_summary(tmp_path, capsys):
    rc = main(["simulate", "anisotropic-abb", "--set", "n=3", "--set", "eps=0.01", "--t-end", "40",
               "--out", str(tmp_path), "--json", "--n-save", "400"])
    assert rc == 0
    summary = json.loads(capsys.readouterr().out)
    for key in ("final_whirl_amplitude", "max_whirl_amplitude_last_revolutions",
                "weight_angles_final", "residual_imbalance_final", "success", "solver", "stats"):
        assert key in summary
    assert summary["success"] and len(summary["weight_angles_final"]) == 2
    assert summary["params"]["n"] == 3.0
    for f in ("anisotropic-abb.png", "anisotropic-abb.npz", "anisotropic-abb.json"):
        assert (tmp_path / f).stat().st_size > 0


def test_simulate_runup_plots_against_speed(tmp_path, capsys):
    rc = main(["simulate", "elliptic-abb", "--set", "nu_dot=0.16", "--set", "nu_end=1.0",
               "--out", str(tmp_path), "--n-save", "200"])
    assert rc == 0
    assert "final whirl amplitude" in capsys.readouterr().out
    assert (tmp_path / "elliptic-abb.png").exists()


def test_failure_is_reported_with_nonzero_exit(tmp_path, capsys):
    rc = main(["simulate", "anisotropic-abb", "--t-end", "50", "--max-steps", "10",
               "--out", str(tmp_path), "--json"])
    summary = json.loads(capsys.readouterr().out)
    assert rc == 3 and not summary["success"] and "max_steps" in summary["message"]


@pytest.mark.parametrize("argv,match", [
    (["simulate", "no-such-rotor"], "unknown preset 'no-such-rotor'"),
    (["simulate", "elliptic-abb", "--set", "zeta=1"], "unknown parameter 'zeta'"),
    (["simulate", "elliptic-abb", "--set", "chi"], "KEY=VALUE"),
    (["simulate", "elliptic-abb", "--set", "chi=abc"], "chi=abc: must be a number"),
    (["simulate", "elliptic-abb", "--set", "rho1=-1"], "rho1=-1: must be > 0"),
    (["simulate", "elliptic-abb", "--set", "chi=-0.1"], "chi=-0.1: must be > 0"),
    (["simulate", "anisotropic-abb", "--set", "sigma=0.4"], "sigma must be 1/N"),
    (["simulate", "elliptic-abb", "--set", "n_balls=1.5"], "n_balls=1.5: must be an integer"),
    (["simulate", "elliptic-abb", "--t-end", "-3"], "--t-end: must be > 0"),
])
def test_bad_input_gets_a_clear_error(argv, match, capsys, tmp_path):
    rc = main(argv + ["--out", str(tmp_path)])
    assert rc == 2
    import re
    assert re.search(match, capsys.readouterr().err)


def test_presets_listing(capsys):
    assert main(["presets"]) == 0
    out = capsys.readouterr().out
    for key in ("chi", "eps", "alpha", "rho1", "rho2", "delta_n", "delta_b", "nu", "nu_dot",
                "n_eta", "mu_xi", "mu_eta", "sigma", "c", "mu_w"):
        assert f"  {key} = " in out


def test_demo_runs_and_writes_plots(tmp_path):
    out = subprocess.run([sys.executable, "-m", "rotorjax.cli", "demo", "--out", str(tmp_path)],
                         capture_output=True, text=True, timeout=600)
    assert out.returncode == 0, out.stderr
    for f in ("runup_000.png", "sweep_001.png", "demo_summary.json"):
        assert (tmp_path / f).stat().st_size > 0
    summary = json.loads((tmp_path / "demo_summary.json").read_text())
    assert summary["sweep_001"]["failed_points"] == 0


def test_steady_lists_all_regimes(capsys):
    rc = main(["steady", "elliptic-abb", "--set", "delta_n=0.1", "--speed", "1.5", "--json"])
    assert rc == 0
    out = json.loads(capsys.readouterr().out)
    amps = sorted(r["whirl_amplitude"] for r in out["regimes"])
    # regression pin: produced by `rotorjax steady elliptic-abb --set delta_n=0.1 --speed 1.5 --json` (2026-11-25)
    assert any(abs(a - 0.039210) < 1e-6 for a in amps) and any(abs(a - 0.141525) < 1e-6 for a in amps)
    assert {"verdict", "weight_angles", "max_eigenvalue_real_part", "kind"} <= set(out["regimes"][0])


def test_steady_on_a_periodic_scene_suggests_floquet(capsys):
    assert main(["steady", "anisotropic-abb", "--speed", "3"]) == 2
    assert "Floquet" in capsys.readouterr().err


def test_critical_speeds_anisotropic_with_criterion(capsys):
    rc = main(["critical-speeds", "anisotropic-abb", "--set", "eps=0.001", "--set", "mu_w=0.25",
               "--range", "4.5", "5.5", "--n-scan", "6", "--json"])
    assert rc == 0
    out = json.loads(capsys.readouterr().out)
    (c,) = out["critical_speeds"]
    assert 5.0 < c["speed"] < 5.05 and c["stable_side"] == "below"
    # regression pin: produced by `rotorjax critical-speeds anisotropic-abb --set eps=0.001 --set mu_w=0.25
    # --range 4.5 5.5 --n-scan 6 --json` (2026-11-25)
    assert out["criterion_roots"] == pytest.approx([5.040672901949166])


def test_stability_map_writes_png(tmp_path, capsys):
    rc = main(["stability-map", "anisotropic-abb", "--x", "n", "2", "8", "4", "--y", "mu_w", "0.2", "0.6",
               "2", "--out", str(tmp_path), "--json"])
    assert rc == 0
    out = json.loads(capsys.readouterr().out)
    assert 0 < out["stable_fraction"] < 1 and out["failed_points"] == 0
    assert (tmp_path / "stability_map_anisotropic-abb.png").stat().st_size > 0
    assert main(["stability-map", "anisotropic-abb", "--x", "sigma", "0.2", "0.5", "3", "--y", "n", "1", "2",
                 "2", "--out", str(tmp_path)]) == 2


def test_flexible_commands(tmp_path, capsys):
    assert main(["campbell", "ross-compare", "--range", "0", "1000", "--n-speeds", "20",
                 "--out", str(tmp_path)]) == 0
    assert (tmp_path / "campbell_ross-compare.png").stat().st_size > 0
    capsys.readouterr()
    assert main(["critical-speeds", "ross-compare", "--range", "10", "200", "--n-scan", "40", "--json"]) == 0
    out = json.loads(capsys.readouterr().out)
    # external reference: ROSS 2.3.0's run_critical_speed (tests/flexible/data/ross_rotor_example.json)
    assert [round(c["speed"], 3) for c in out["critical_speeds"]] == [91.788, 96.296]
    assert [c["whirl"] for c in out["critical_speeds"]] == ["backward", "forward"]
    np.testing.assert_allclose(out["synchronous_determinant_roots"],
                               [c["speed"] for c in out["critical_speeds"]], rtol=1e-8)
    assert main(["campbell", "ross-compare", "--range", "0", "1000", "--n-speeds", "5", "--reduce", "20",
                 "--out", str(tmp_path), "--json"]) == 0
    # external reference: ROSS 2.3.0's first damped frequency at speed 0, 91.79655 (ross_rotor_example.json)
    assert abs(json.loads(capsys.readouterr().out)["frequencies"][0][0] / 91.797 - 1) < 1e-4
    assert main(["campbell", "ross-compare", "--range", "0", "1000", "--reduce", "0",
                 "--out", str(tmp_path)]) == 2
    assert "n_modes (reduction)" in capsys.readouterr().err
    assert main(["response", "ross-compare", "--range", "10", "400", "--n", "400", "--set", "cxx=100",
                 "--set", "cyy=100", "--out", str(tmp_path), "--json"]) == 0
    out = json.loads(capsys.readouterr().out)
    assert abs(out["peaks"][0] - 91.8) < 2 and (tmp_path / "response_ross-compare.png").exists()
    assert main(["response", "ross-compare", "--range", "10", "400", "--node", "9", "--out", str(tmp_path)]) == 2
    assert main(["simulate", "ross-compare", "--out", str(tmp_path)]) == 2


def test_flexible_abb_critical_speeds(capsys):
    assert main(["critical-speeds", "flexible-abb", "--range", "0.1", "25", "--exact", "--json"]) == 0
    out = json.loads(capsys.readouterr().out)
    # external reference: the published roots of eq. (17) (model 003's paper, to 6 decimals)
    assert out["critical_speeds"] == pytest.approx([0.705801, 7.276434, 21.484371], abs=1e-6)
    assert main(["critical-speeds", "flexible-abb", "--range", "0.1", "25", "--modes", "20", "--json"]) == 0
    out = json.loads(capsys.readouterr().out)
    assert out["critical_speeds"][0] == pytest.approx(0.705801, abs=1e-5)


def test_hopf_command(capsys):
    assert main(["hopf", "cantilever-limiters", "--range", "5", "25", "--n-scan", "20", "--json"]) == 0
    out = json.loads(capsys.readouterr().out)
    assert abs(out["N_crit"] / out["paper_fit"]["N_crit"] - 1) < 0.01
    assert out["hopf_points"][0]["whirl"] == "forward" and out["hopf_points"][0]["dN_crit_d_eta_e"] > 0
    assert main(["hopf", "ross-compare"]) == 2


def test_contact_simulate_and_bifurcation(tmp_path, capsys):
    assert main(["simulate", "cantilever-limiters", "--set", "revolutions=60", "--set", "perturbation=0.05",
                 "--out", str(tmp_path), "--json"]) == 0
    out = json.loads(capsys.readouterr().out)
    assert out["success"] and out["energy_residual"] < 1e-5 and out["max_normal_force"] > 0
    assert {"mean_Lambda", "direction", "spectrum_peaks", "max_disk_x"} <= set(out)
    assert (tmp_path / "cantilever-limiters.png").stat().st_size > 0
    assert main(["simulate", "cantilever-limiters", "--set", "revolutions=30", "--set", "events=1",
                 "--set", "perturbation=0.05", "--out", str(tmp_path), "--json"]) == 0
    assert json.loads(capsys.readouterr().out)["stats"]["num_events"] > 0
    assert main(["bifurcation", "cantilever-limiters", "--param", "eps", "0", "0.001", "2", "--set",
                 "revolutions=20", "--out", str(tmp_path), "--json"]) == 0
    out = json.loads(capsys.readouterr().out)
    assert len(out["points"]) == 2 and all(p["code"] == 0 for p in out["points"])
    assert out["batch"]["method"] == "vectorised" and out["batch"]["steps_max"] >= out["batch"]["steps_mean"] > 0
    assert (tmp_path / "bifurcation_cantilever-limiters_eps.png").exists()
    # the speed swept, with event-located contact: a span (10 revolutions) per point
    assert main(["bifurcation", "cantilever-limiters", "--param", "N", "14", "16", "2", "--set",
                 "revolutions=10", "--set", "events=1", "--set", "perturbation=0.05", "--out", str(tmp_path),
                 "--json"]) == 0
    out = json.loads(capsys.readouterr().out)
    assert all(p["code"] == 0 for p in out["points"]) and sum(out["batch"]["events"]) > 0
    assert main(["bifurcation", "cantilever-limiters", "--param", "mu_R", "0", "1", "2"]) == 2
    assert main(["simulate", "cantilever-limiters", "--set", "chi=0"]) == 2
    assert "clearance" in capsys.readouterr().err


def test_balance_and_identify_on_the_shipped_data(tmp_path, capsys):
    assert main(["balance", "--holes", "12", "--json"]) == 0
    out = json.loads(capsys.readouterr().out)
    got = {c["plane"]: (c["mass_g"], c["angle_deg"]) for c in out["corrections"]}
    # the preset's unbalances: 20 g at 30 deg and 30 g at 200 deg (radius 10 mm)
    assert abs(got[0][0] - 20) < 0.3 and abs(got[0][1] - 210) < 1.5
    assert abs(got[1][0] - 30) < 0.3 and abs(got[1][1] - 20) < 1.5
    assert out["iso_grade_reached"] <= 1.0 and len(out["corrections"][0]["holes"]) == 2
    # one engine: min-max and the model's influence coefficients for the machine too (its preset the model)
    assert main(["balance", "--method", "minmax", "--influence", "both", "--json"]) == 0
    both = json.loads(capsys.readouterr().out)
    assert both["method"] == "minmax" and both["warnings"] == []
    assert [round(c["mass_g"], 2) for c in both["corrections"]] == [round(c["mass_g"], 2) for c in out["corrections"]]
    assert main(["identify", "balancing-machine", "--set", "k1=1.5e5", "--set", "c1=100", "--json"]) == 0
    out = json.loads(capsys.readouterr().out)
    for k, true in (("k1", 2e5), ("k2", 3e5), ("c1", 150.0), ("c2", 200.0)):
        assert abs(out["estimates"][k] / true - 1) < 0.03
    bad = tmp_path / "bad.csv"
    bad.write_text("time,x1\n0,1\n")
    assert main(["balance", "--runs", str(bad)]) == 2
    assert "missing column" in capsys.readouterr().err
    assert main(["identify", "balancing-machine", "--fit", "k1,zz"]) == 2
    assert main(["balance", "--planes", "5"]) == 2
    single = tmp_path / "single.csv"
    t = np.arange(0, 0.5, 1e-3)
    np.savetxt(single, np.stack([t, (np.mod(t * 20, 1) < 0.01).astype(float), np.cos(40 * np.pi * t),
                                 np.sin(40 * np.pi * t)], 1), delimiter=",", header="time,tacho,x1,x2", comments="")
    assert main(["balance", "--runs", str(single)]) == 2
    assert "no runs with a trial weight" in capsys.readouterr().err
    assert main(["simulate", "balancing-machine"]) == 2
    assert "use `balance`, `identify`" in capsys.readouterr().err


def test_continue_command(tmp_path, capsys):
    assert main(["continue", "anisotropic-abb", "--param", "n", "--to", "4", "6", "--max-points", "6",
                 "--out", str(tmp_path), "--json"]) == 0
    out = json.loads(capsys.readouterr().out)
    # regression pin: produced by `rotorjax continue anisotropic-abb --param n --to 4 6 --max-points 6 --json` (2026-11-25)
    assert len(out["crossings"]) == 1 and abs(out["crossings"][0]["p"] - 5.0499297) < 1e-6
    assert main(["continue", "cantilever-limiters", "--param", "N", "--param2", "eta_e", "--from", "13.9", "0.025",
                 "--box", "1", "40", "0", "0.03", "--ds", "0.002", "--max-points", "6", "--out", str(tmp_path),
                 "--json"]) == 0
    out = json.loads(capsys.readouterr().out)
    # traced both ways from the corrected start (N = 13.904126 at eta_e = 0.025; regression pin: produced by
    # `rotorjax continue cantilever-limiters --param N --param2 eta_e --from 13.9 0.025 --box 1 40 0 0.03
    # --ds 0.002 --max-points 6 --json`, 2026-11-25)
    start = out["stops"] and np.argmin(np.abs(np.asarray(out["eta_e"]) - 0.025))
    assert abs(out["N"][start] - 13.904126) < 1e-5 and max(out["residuals"]) < 1e-8
    assert min(out["eta_e"]) < 0.025 < max(out["eta_e"])
    assert (tmp_path / "continue_cantilever-limiters_N_eta_e.csv").exists()
    # the same as the one branch, with its dense curve (8 samples per interval) within 1e-6 along N
    (br,) = out["branches"]
    assert br["N"] == out["N"] and br["stops"] == out["stops"] and out["box_source"] == "--box"
    assert br["dense"]["N"][::8] == br["N"] and br["interpolation_error_max"] <= 1e-6 == out["dense_tol"]
    # without --box: the preset's default box
    assert main(["continue", "cantilever-limiters", "--param", "N", "--param2", "eta_e", "--from", "13.9", "0.025",
                 "--max-points", "4", "--out", str(tmp_path), "--json"]) == 0
    out = json.loads(capsys.readouterr().out)
    assert out["box"] == [1.0, 40.0, 0.0, 0.06] and out["box_source"] == "the preset's default box"
    # a box without a boundary, and one way without a start
    base = ["continue", "cantilever-limiters", "--param", "N", "--param2", "eta_e", "--out", str(tmp_path)]
    assert main(base + ["--box", "1", "5", "0", "0.06"]) == 2
    assert "no stability boundary meets the edge of the box N in [1, 5]" in capsys.readouterr().err
    assert main(base + ["--direction", "up"]) == 2
    assert main(["continue", "elliptic-abb", "--param", "nu", "--set", "eps=0.03", "--set", "rho2=1.28",
                 "--to", "1.4", "1.8", "--ds", "0.05", "--out", str(tmp_path), "--json"]) == 0
    out = json.loads(capsys.readouterr().out)
    assert out["residual_max"] < 1e-10 and all(out["stable"])
    assert main(["continue", "anisotropic-abb", "--param", "zz"]) == 2
    assert main(["continue", "anisotropic-abb", "--param", "n", "--param2", "mu_w", "--from", "5"]) == 2
    assert main(["continue", "ross-compare", "--param", "kxx"]) == 2


def test_continue_traces_the_boundary_that_turns_in_mu_w(tmp_path, capsys):
    """Model 001 in (n, mu_w) over a box round the second boundary (every other setting the default): the
    boundary from mu_w = 0.05 to 1, turning at n = 5.0534715, mu_w = 0.816, and between its points as
    accurate as critical speeds bisected along n to 1e-6. The whole default box (three boundaries, the
    same pins) is traced by notebooks/stability_boundaries.py, whose claims tests/test_notebooks.py checks;
    the CLI's choice of the preset's box by test_continue_command."""
    from rotorjax.analysis import Curve, critical_speeds
    from rotorjax.presets import anisotropic_abb as ab

    assert main(["continue", "anisotropic-abb", "--param", "n", "--param2", "mu_w", "--box", "4", "6", "0.05", "1",
                 "--out", str(tmp_path), "--json"]) == 0
    out = json.loads(capsys.readouterr().out)
    assert out["box"] == [4.0, 6.0, 0.05, 1.0] and out["n_branches"] == 1
    (br,) = out["branches"]
    assert br["stops"] == ["box edge (mu_w = 0.05)", "box edge (mu_w = 1.0)"] and br["stop"] == "box edge"
    # regression pins, as the notebook's (the turn: the largest n of the dense curve)
    assert abs(min(br["dense"]["n"]) - 4.6071146) < 1e-6 and abs(max(br["dense"]["n"]) - 5.0534715) < 1e-6
    assert max(br["residuals"]) < 1e-9 and br["interpolation_error_max"] <= 1e-6
    assert all(c["branch"] is not None for c in out["crossings"])
    curve = Curve(x=np.column_stack([br["n"], br["mu_w"]]), residuals=np.asarray(br["residuals"]),
                  steps=np.asarray(br["steps"]), iterations=np.zeros(len(br["n"])), stopped=br["stopped"],
                  tangents=np.asarray(br["tangents"]))
    # at the midpoint of its least accurate interval, against critical speeds bisected along n
    # (independently of the continuation); below the turn the boundary meets that mu_w twice
    i = int(np.argmax(br["interpolation_errors"]))
    mu = br["dense"]["mu_w"][8 * (i - 1) + 4]
    n_dense = np.sort(curve.meets(1, mu)[:, 0])
    p = dict(ab.PRESET.defaults, mu_w=mu)
    found = critical_speeds(lambda n: ab.PRESET.margin(dict(p, n=n)), 4.0, 6.0, n_scan=20, xtol=1e-12)
    assert len(found) == n_dense.size >= 1
    np.testing.assert_allclose([c.speed for c in found], n_dense, rtol=0, atol=1e-6)


def test_rotor_files_take_the_place_of_presets(tmp_path, capsys):
    """A rotor file (`.toml`) in place of a preset: its scalar entries are `--set` keys
    (with dots), `simulate --speed W` integrates the FE rotor with its unbalance, and the
    linear commands read ROSS's example rotor as the `ross-compare` preset does."""
    import os

    import rotorjax

    rotor = os.path.join(os.path.dirname(rotorjax.__file__), "rotors", "ross_compare.toml")
    assert main(["critical-speeds", rotor, "--range", "10", "200", "--n-scan", "40", "--out", str(tmp_path),
                 "--json"]) == 0
    out = json.loads(capsys.readouterr().out)
    # external reference: ROSS 2.3.0's run_critical_speed (tests/flexible/data/ross_rotor_example.json)
    assert [round(c["speed"], 3) for c in out["critical_speeds"]] == [91.788, 96.296]
    assert (tmp_path / "critical_speeds_ross_compare.png").stat().st_size > 0
    assert main(["critical-speeds", rotor, "--range", "10", "200", "--n-scan", "40", "--set", "bearing0.kxx=2e6",
                 "--set", "bearing1.kxx=2e6", "--out", str(tmp_path), "--json"]) == 0
    out = json.loads(capsys.readouterr().out)
    assert out["params"]["bearing0.kxx"] == 2e6 and out["critical_speeds"][1]["speed"] > 97.0  # stiffer in x
    assert main(["simulate", rotor, "--speed", "50", "--t-end", "0.2", "--n-save", "100", "--out", str(tmp_path),
                 "--json"]) == 0
    out = json.loads(capsys.readouterr().out)
    assert out["success"] and out["final_speed"] == 50.0 and out["params"]["speed"] == 50.0
    assert out["final_whirl_amplitude"] > 0 and len(out["node_x_final"]) == 7
    assert (tmp_path / "ross_compare.npz").stat().st_size > 0


def test_static_modes_and_tracked_campbell(tmp_path, capsys):
    """`static` (reactions W/2 on ROSS's symmetric example rotor, plot of deflection,
    shear, moment), `modes` (table as JSON, 2-D and 3-D shape plots) and `campbell`'s
    tracked branches; on a rotor file with components (cubic bearings, internal
    damping) `campbell` and `critical-speeds` use the scene's linear part."""
    import os

    import rotorjax
    from rotorjax import presets
    from rotorjax.flexible import campbell

    assert main(["static", "ross-compare", "--out", str(tmp_path), "--json"]) == 0
    out = json.loads(capsys.readouterr().out)
    w = -out["weight"][1]
    np.testing.assert_allclose([r["y"] for r in out["bearing_reactions"]], [w / 2, w / 2], rtol=1e-10)
    assert out["max_deflection"]["node"] == 3 and out["max_moment"] > 0
    assert (tmp_path / "static_ross-compare.png").stat().st_size > 0
    assert main(["modes", "ross-compare", "--speed", "1000", "--n-modes", "4", "--out", str(tmp_path),
                 "--json"]) == 0
    out = json.loads(capsys.readouterr().out)
    assert [m["whirl"] for m in out["modes"]] == ["backward", "forward", "backward", "forward"]
    np.testing.assert_allclose(out["modes"][0]["damped_frequency_hz"] * 2 * np.pi,
                               out["modes"][0]["damped_frequency"], rtol=1e-12)
    for f in out["files"].values():
        assert os.path.getsize(f) > 0
    assert main(["campbell", "ross-compare", "--range", "0", "4000", "--n-speeds", "41", "--out", str(tmp_path),
                 "--json"]) == 0
    out = json.loads(capsys.readouterr().out)
    tracked = out["tracked"]
    assert min(tracked["min_mac"]) > 0.8
    assert all(len({w for w in col[1:] if w != "mixed"}) == 1 for col in zip(*tracked["whirl"]))
    rig = os.path.join(os.path.dirname(rotorjax.__file__), "rotors", "rig_nonlinear.toml")
    assert main(["campbell", rig, "--range", "0", "300", "--n-speeds", "3", "--modes", "4", "--out",
                 str(tmp_path), "--json"]) == 0
    out = json.loads(capsys.readouterr().out)
    p = presets.get(rig)
    scene = p.build(dict(p.defaults)).scene
    np.testing.assert_allclose(out["frequencies"], np.asarray(campbell(scene, [0.0, 150.0, 300.0], 4).frequencies),
                               rtol=1e-10)
    bare = np.asarray(campbell(scene.rotor, [0.0, 150.0, 300.0], 4).frequencies)
    assert np.abs(np.asarray(out["frequencies"]) / bare - 1).max() > 1e-3


def test_ucs_frf_level1_and_several_unbalances(tmp_path, capsys):
    """The UCS map, FRF and level I commands print what the library computes, and
    `response` takes several unbalances and a deflected shape."""
    from rotorjax.flexible import deflected_shape, frf, level1, ucs, unbalance_response_many
    from rotorjax.presets import get

    rotor = get("ross-compare").build(dict(get("ross-compare").defaults)).scene.rotor
    assert main(["ucs", "ross-compare", "--n", "12", "--out", str(tmp_path), "--json"]) == 0
    out = json.loads(capsys.readouterr().out)
    ref = ucs(rotor, (1e5, 1e10), 12, 4)
    np.testing.assert_allclose(out["critical_speeds"], np.asarray(ref.frequencies), rtol=1e-12)
    np.testing.assert_allclose([i["speed"] for i in out["intersections"]][:2], [91.79655318, 96.28899977], rtol=1e-8)
    assert (tmp_path / "ucs_ross-compare.png").stat().st_size > 0

    assert main(["frf", "ross-compare", "--input", "2,x", "--output", "4,y", "--range", "10", "1000", "--n", "50",
                 "--kind", "velocity", "--speed", "300", "--set", "cxx=100", "--out", str(tmp_path), "--json"]) == 0
    out = json.loads(capsys.readouterr().out)
    damped = get("ross-compare").build(dict(get("ross-compare").defaults, cxx=100.0)).scene.rotor
    w = np.asarray(out["frequencies"])   # the grid, with points added around each peak
    assert np.all(np.diff(w) > 0) and np.all(np.isin(np.linspace(10, 1000, 50), w))
    h = np.asarray(frf(damped, (2, "x"), (4, "y"), w, "velocity", speed=300.0).values)
    # the command solves on the scene (assembled in one compiled program), the reference on the bare rotor:
    # the same numbers up to rounding near the resonances (measured 1.1e-11)
    np.testing.assert_allclose(out["magnitude"], np.abs(h), rtol=1e-9)
    np.testing.assert_allclose(out["phase"], np.angle(h), atol=1e-9)
    for f in ("frf_ross-compare_bode.png", "frf_ross-compare_polar.png"):
        assert (tmp_path / f).stat().st_size > 0

    assert main(["level1", "ross-compare", "--speed", "500", "--set", "cxx=1500", "--set", "cyy=1500", "--n", "9",
                 "--q-max", "4e5", "--out", str(tmp_path), "--json"]) == 0
    out = json.loads(capsys.readouterr().out)
    lev = get("ross-compare").build(dict(get("ross-compare").defaults, cxx=1500.0, cyy=1500.0)).scene
    ref = level1(lev, 500.0, q_max=4e5, n=9)
    assert out["node"] == 3 and out["q0"] == pytest.approx(float(ref.q0), rel=1e-12)
    assert abs(out["check_at_q0"]["max_real_part"]) < 1e-6
    np.testing.assert_allclose(out["log_dec"], np.asarray(ref.log_dec), rtol=1e-12)

    unb = [(2, 1e-3, 0.0), (4, 5e-4, 1.0)]
    assert main(["response", "ross-compare", "--range", "10", "400", "--n", "40", "--set", "cxx=100", "--probe", "3",
                 "--unbalance", "2,1e-3,0", "--unbalance", "4,5e-4,1", "--shape-at", "250", "--out", str(tmp_path),
                 "--json"]) == 0
    out = json.loads(capsys.readouterr().out)
    X, Y = unbalance_response_many(damped, unb, np.linspace(10, 400, 40), probe_nodes=[3])
    amp = np.sqrt(np.abs(np.asarray(X[:, 0])) ** 2 + np.abs(np.asarray(Y[:, 0])) ** 2)
    # the peak located between the grid's points: above the grid's largest value, and the library's value there
    X, Y = unbalance_response_many(damped, unb, np.array([out["speed_at_max"]]), probe_nodes=[3])
    at_max = float(np.sqrt(np.abs(np.asarray(X[0, 0])) ** 2 + np.abs(np.asarray(Y[0, 0])) ** 2))
    assert out["max_amplitude"] >= amp.max() and out["max_amplitude"] == pytest.approx(at_max, rel=1e-12)
    assert [u["node"] for u in out["unbalances"]] == [2, 4] and out["unbalance"] is None
    np.testing.assert_allclose(out["deflected_shape"]["major"], np.asarray(deflected_shape(damped, unb, 250.0).major),
                               rtol=1e-12)
    assert (tmp_path / "response_ross-compare_shape.png").stat().st_size > 0


def test_the_cli_imports_no_heavy_library_it_does_not_use():
    """A command's start-up pays for its imports: scipy (scipy.stats alone was a quarter of
    `import rotorjax.cli`, measured 2026-12-02), matplotlib, numba, tqdm and optax are
    imported by the functions that use them, not when the CLI loads."""
    heavy = ("scipy", "matplotlib", "numba", "tqdm", "optax")
    code = ("import sys; import rotorjax.cli; "
            f"print(sorted({{m.split('.')[0] for m in sys.modules}} & set({heavy!r})))")
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True)
    assert out.stdout.strip() == "[]", out.stdout
