"""`rotorjax identify ROTOR.toml` and `rotorjax balance ROTOR.toml` on the shipped
flexible rig and its datasets (`flexible-runup`, `flexible-trials`): the as-built
bearing coefficients and the residual unbalances of `_make_fe_data` come back.

The legacy forms (no ROTOR: the balancing machine) are covered by tests/test_cli.py."""

import contextlib
import io
import json
import os

import numpy as np
import pytest

from rotorjax.cli import main
from rotorjax.identify._make_fe_data import TRUTH, UNBALANCES

RIG = "flexible_rig.toml"


def _run(argv):
    """`(exit code, stdout)` of `rotorjax ARGV`."""
    out = io.StringIO()
    with contextlib.redirect_stdout(out):
        rc = main(argv)
    return rc, out.getvalue()


@pytest.fixture(scope="module")
def identified(tmp_path_factory):
    """One identification (defaults: data flexible-runup, fit the 8 kxx, kyy, cxx, cyy)."""
    out = tmp_path_factory.mktemp("identify")
    rc, text = _run(["identify", RIG, "--fit-unbalance", "2,4", "--json", "--out", str(out)])
    assert rc == 0, text
    return out, json.loads(text)


def test_identify_rotor_file_finds_the_as_built_bearings(identified):
    out, res = identified
    for key in ("estimates", "ci95", "residual_rms", "warnings", "correlation", "critical_speeds", "unbalances"):
        assert key in res, key
    assert res["data"].endswith("flexible_runup.csv") or "flexible-runup" in res["data"]
    assert sorted(res["fit"]) == sorted(TRUTH)
    for name, true in TRUTH.items():
        assert abs(res["estimates"][name] / true - 1) < 0.02, (name, res["estimates"][name], true)
        lo, hi = res["ci95"][name]
        assert lo < res["estimates"][name] < hi
    found = {u["node"]: u for u in res["unbalances"]}
    assert sorted(found) == [2, 4]
    for node, mag, phase in UNBALANCES:
        assert abs(found[node]["magnitude"] / mag - 1) < 0.02
        assert abs(np.angle(np.exp(1j * (found[node]["phase"] - phase)))) < 0.02
    speeds = [c["speed"] for c in res["critical_speeds"]]
    assert any(abs(s - 108.6) < 1.0 for s in speeds) and any(abs(s - 355.6) < 2.0 for s in speeds)
    assert res["correlation"]["names"] == res["fit"]
    assert res["residual_rms"] > 0 and not res["warnings"]
    for f in ("identify_flexible_rig.png", "identify_flexible_rig.json"):
        assert (out / f).stat().st_size > 0
    assert json.loads((out / "identify_flexible_rig.json").read_text())["estimates"] == res["estimates"]


def test_identify_text_output_lists_estimates_and_critical_speeds(identified, tmp_path):
    rc, text = _run(["identify", RIG, "--fit-unbalance", "2,4", "--out", str(tmp_path)])
    assert rc == 0
    for name in TRUTH:
        assert f"  {name} = " in text and "95% [" in text
    assert "critical speed" in text and "unbalance at node 2" in text and "residual rms" in text
    assert os.path.exists(tmp_path / "identify_flexible_rig.png")


def _cancel(corrections):
    """|c + U| / |U| per plane: how far each correction is from cancelling the true unbalance."""
    true = {node: mag * np.exp(1j * phase) for node, mag, phase in UNBALANCES}
    return {c["node"]: abs(c["magnitude"] * np.exp(1j * np.radians(c["phase_deg"])) + true[c["node"]])
            / abs(true[c["node"]]) for c in corrections}


@pytest.mark.parametrize("method", ["ls", "minmax"])
def test_balance_rotor_file_cancels_the_true_unbalances(method, tmp_path):
    rc, text = _run(["balance", RIG, "--planes", "2,4", "--method", method, "--json", "--out", str(tmp_path)])
    assert rc == 0
    res = json.loads(text)
    assert [c["node"] for c in res["corrections"]] == [2, 4]
    for c in res["corrections"]:
        assert {"node", "magnitude", "phase_deg"} <= set(c)
    err = _cancel(res["corrections"])
    assert max(err.values()) < 0.03, err
    assert res["residual"]["after_max"] < 0.05 * res["residual"]["before_max"]
    assert (tmp_path / "balance_rotor.png").stat().st_size > 0


def test_balance_default_planes_are_the_trial_nodes(tmp_path):
    rc, text = _run(["balance", RIG, "--json", "--out", str(tmp_path)])
    assert rc == 0
    plain = json.loads(text)["corrections"]
    assert [c["node"] for c in plain] == [2, 4]
    # the balancing machine's presentation on a rotor file too: a mass at a radius, split onto holes
    rc, text = _run(["balance", RIG, "--radius", "0.05", "--holes", "8", "--out", str(tmp_path)])
    assert rc == 0
    for c in plain:
        grams = c["magnitude"] / 0.05 * 1e3
        assert f"node {c['node']}: add {grams:.3f} g at {c['angle_deg']:.1f} deg (radius 0.05 m" in text, text
    assert text.count("in the hole at") == 4


def test_balance_influence_both_warns_until_the_model_is_the_machine(tmp_path):
    rc, text = _run(["balance", RIG, "--planes", "2,4", "--influence", "both", "--json", "--out", str(tmp_path)])
    assert rc == 0
    warnings = json.loads(text)["warnings"]
    assert any("model's influence coefficients differ from the trial runs'" in w for w in warnings), warnings
    sets = [a for name, value in TRUTH.items() for a in ("--set", f"{name}={value:g}")]
    rc, text = _run(["balance", RIG, "--planes", "2,4", "--influence", "both", *sets, "--json",
                     "--out", str(tmp_path)])
    assert rc == 0
    res = json.loads(text)
    assert not any("influence coefficients differ" in w for w in res["warnings"]), res["warnings"]
    assert max(_cancel(res["corrections"]).values()) < 0.03
