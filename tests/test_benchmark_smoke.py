"""Every benchmark script runs: `python benchmarks/NAME.py --smoke` (tiny sizes, one
call per timing, every method's code path once, nothing written, no timing asserted), so that a
change that breaks a benchmark fails here and not at the next measurement. The
scripts run one after another in one fresh interpreter (`benchmark_smoke_runner.py`:
the imports and shared compilations paid once), each reported by its own test. A new
script in `benchmarks/` must join the list (or the helpers')."""

import json
import os
import subprocess
import sys
from pathlib import Path

import pytest

HERE = Path(__file__).resolve().parent
BENCH = HERE.parent / "benchmarks"
SCRIPTS = ("auto07p", "auto_balancing_range", "balance_grid", "continuation", "design", "fe_identification",
           "flexible", "gpu_batch", "harmonic_balance", "identification", "identification_coverage",
           "journal_bearings", "limiters", "peers_001", "periodic_jaxcont", "ross_parity", "rotor_scene",
           "solver_choice", "stability_map", "startup", "step_cost", "stiff_defaults", "sweep_throughput",
           "uncertainty")
#: modules that are not benchmarks: shared helpers, and the results page (tests/test_benchmark_pages.py)
HELPERS = {"_common", "work_precision", "_ross_st_rotor"}


def test_every_script_has_a_smoke_run():
    scripts = {p.stem for p in BENCH.glob("*.py")} - HELPERS
    assert scripts == set(SCRIPTS)
    for name in SCRIPTS:
        assert "--smoke" in (BENCH / f"{name}.py").read_text(), name


@pytest.fixture(scope="module")
def smoke_runs(tmp_path_factory):
    tmp = tmp_path_factory.mktemp("smoke")
    env = dict(os.environ, MPLBACKEND="Agg")
    # $ROTORJAX_ROSS_PYTHON passes through: the ROSS paths run where .ci/run installed ROSS
    results = BENCH / "results"
    before = {p.name: p.stat().st_mtime for p in results.iterdir()}
    report = tmp / "smoke.json"
    proc = subprocess.run([sys.executable, str(HERE / "benchmark_smoke_runner.py"), str(report), *SCRIPTS],
                          cwd=tmp, env=env, capture_output=True, text=True, timeout=1500)
    runs = json.loads(report.read_text()) if report.exists() else {}
    after = {p.name: p.stat().st_mtime for p in results.iterdir()}
    return runs, proc, before == after


@pytest.mark.parametrize("name", SCRIPTS)
def test_benchmark_smoke_run(name, smoke_runs):
    runs, proc, untouched = smoke_runs
    assert name in runs, f"the runner stopped before {name}: {proc.stdout[-1500:]}{proc.stderr[-1500:]}"
    assert runs[name]["ok"], runs[name]["tail"]
    assert untouched, "a smoke run wrote into benchmarks/results/"
