"""The rotorjax command."""

import json
import os
import subprocess
import sys

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
    (["simulate", "elliptic-abb", "--set", "chi"], "key=value"),
    (["simulate", "elliptic-abb", "--set", "chi=abc"], "'chi' must be a number"),
    (["simulate", "elliptic-abb", "--set", "rho1=-1"], "r1 .* must be > 0"),
    (["simulate", "elliptic-abb", "--set", "chi=-0.1"], "weight mass must be > 0"),
    (["simulate", "anisotropic-abb", "--set", "sigma=0.4"], "sigma must be 1/N"),
    (["simulate", "elliptic-abb", "--set", "n_balls=1.5"], "non-negative integer"),
    (["simulate", "elliptic-abb", "--t-end", "-3"], "--t-end must be > 0"),
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
