"""`rotorjax bench`: the headline comparisons run end to end at the smoke sizes (one
run, shared by the tests), the matched-error reading, the peers skipped with a note,
a numerical failure exiting 3. Bad input is in `test_cli_errors.py`'s table. No
timing is asserted: speed lives in `benchmarks/`."""

import json
import math
import os

import numpy as np
import pytest

from rotorjax import bench
from rotorjax.bench import _model001
from rotorjax.bench._campbell import nearest_relative_difference
from rotorjax.bench._matching import interpolate_cost
from rotorjax.cli import main
from rotorjax.cli._bench import table_lines


@pytest.fixture(scope="module")
def smoke(tmp_path_factory):
    out = tmp_path_factory.mktemp("bench")
    env = os.environ.pop("ROTORJAX_ROSS_PYTHON", None)
    try:
        with pytest.MonkeyPatch.context() as mp:  # ROSS absent, whatever this machine has
            mp.setattr("rotorjax.bench._campbell.ross_python", lambda explicit=None: None)
            rc = main(["bench", "--smoke", "--out", str(out)])
    finally:
        if env is not None:
            os.environ["ROTORJAX_ROSS_PYTHON"] = env
    with open(out / "bench.json") as f:
        return rc, json.load(f), out


def test_the_smoke_run_writes_the_report_and_the_diagram(smoke):
    rc, report, out = smoke
    assert rc == 0
    assert [c["name"] for c in report["comparisons"]] == ["model 001 sweep", "Floquet map", "Campbell diagram"]
    with open(out / "bench.png", "rb") as f:
        assert f.read(8) == b"\x89PNG\r\n\x1a\n"
    assert report["machine"]["device"].startswith("cpu")


def test_every_ratio_is_a_peer_cost_over_rotorjax_at_rotorjax_error(smoke):
    _, report, _ = smoke
    comps = {c["name"]: c for c in report["comparisons"]}
    assert report["table"]
    for row in report["table"]:
        if row["comparison"] == "Campbell diagram":
            continue
        c = comps[row["comparison"]]
        ladder = c["curves"][row["peer"]]
        cost, how = interpolate_cost([p["error"] for p in ladder], [p["cost"] for p in ladder], row["error"])
        assert row["peer_cost"] == pytest.approx(cost) and row["match"] == how
        assert row["ratio"] == pytest.approx(row["peer_cost"] / row["rotorjax_cost"])
        assert math.isfinite(row["ratio"]) and row["ratio"] > 0


def test_the_errors_are_those_of_the_tolerances(smoke):
    _, report, _ = smoke
    sweep, floquet, _ = report["comparisons"]
    rj = sweep["curves"][sweep["rotorjax"]]
    assert 0 < rj[0]["error"] < 1e-4          # rtol 1e-6 over tau in [0, 10]
    scipy = sweep["curves"]["scipy DOP853 loop, pure-Python rhs"]
    assert scipy[-1]["error"] < scipy[0]["error"]  # a tighter rtol, a smaller error
    assert floquet["checks"]["references_agree"] < 1e-9  # rotorjax and scipy at rtol 1e-12
    assert 0 <= floquet["curves"][floquet["rotorjax"]][0]["error"] < 1e-5


def test_the_peers_run_or_are_skipped_with_a_note(smoke):
    _, report, _ = smoke
    sweep, _, campbell = report["comparisons"]
    numba = [k for k in sweep["curves"] if k.startswith("numba RK4")]
    assert bool(numba) == bench.numba_available()
    assert campbell["skipped"] and campbell["skipped"][0]["peer"] == "ROSS"
    assert "not installed" in campbell["skipped"][0]["why"]
    lines = table_lines(report)
    assert any(line.startswith("skipped (Campbell diagram): ROSS: ROSS is not installed") for line in lines)


def test_numba_missing_is_skipped_with_a_note(monkeypatch):
    monkeypatch.setattr(_model001, "numba_available", lambda: False)
    comp = _model001.sweep_comparison(bench.SMOKE, lambda stage: None, 1)
    assert not any(k.startswith("numba") for k in comp.curves)
    assert comp.skipped[0][0] == "numba RK4" and "not installed" in comp.skipped[0][1]


@pytest.mark.skipif(bench.ross_python() is None, reason="ROSS is not installed (set ROTORJAX_ROSS_PYTHON)")
def test_campbell_agrees_with_ross():
    comp = bench._campbell.campbell_comparison(bench.SMOKE, lambda stage: None, 1)
    assert comp.peers and comp.checks["agreement_max_rel"] < 1e-8


def test_matched_cost_interpolates_in_log_log():
    cost, how = interpolate_cost([1e-4, 1e-8], [1.0, 100.0], 1e-6)
    assert how == "interpolated" and cost == pytest.approx(10.0)
    cost, how = interpolate_cost([1e-4, 1e-8, float("inf")], [1.0, 100.0, 0.1], 1e-10)
    assert how.startswith("extrapolated: peer never reached") and cost == pytest.approx(100.0)
    cost, how = interpolate_cost([1e-4, 1e-8], [1.0, 100.0], 1e-2)
    assert how.startswith("extrapolated: clamped") and cost == pytest.approx(1.0)
    assert math.isnan(interpolate_cost([float("nan")], [1.0], 1e-3)[0])


def test_nearest_relative_difference_ignores_the_peer_extra_modes():
    ours = np.array([[10.0, 20.0]])
    theirs = np.array([[10.0, 15.0, 20.0 * (1 + 1e-9)]])  # 15: a mode the lateral model has not
    assert nearest_relative_difference(ours, theirs) == pytest.approx(1e-9, rel=1e-6)


def test_a_numerical_failure_exits_3(monkeypatch, tmp_path, capsys):
    def fail(*args, **kwargs):
        raise FloatingPointError("model 001 sweep: the integration failed at 1 speed(s), first n = 7.5")

    monkeypatch.setattr(bench, "run_bench", fail)
    assert main(["bench", "--smoke", "--out", str(tmp_path)]) == 3
    err = capsys.readouterr().err
    assert "numerical failure: model 001 sweep: the integration failed" in err and "Traceback" not in err
