"""Every benchmark script runs: `python benchmarks/NAME.py --smoke` (tiny sizes, one
repeat, every method's code path once, nothing written, no timing asserted), so that a
change that breaks a benchmark fails here and not at the next measurement. A new
script in `benchmarks/` must join the list (or the list of helpers)."""

import os
import subprocess
import sys
from pathlib import Path

import pytest

BENCH = Path(__file__).resolve().parents[1] / "benchmarks"
#: the scripts and the extra arguments of their smoke runs
SCRIPTS = {
    "auto07p": (), "continuation": (), "fe_identification": (), "flexible": (), "identification": (),
    "identification_coverage": (), "limiters": (), "peers_001": (), "ross_parity": (), "rotor_scene": (),
    "solver_choice": (), "stability_map": (), "sweep_throughput": (),
}
#: modules that are not benchmarks: shared helpers, and the results page (tests/test_benchmark_pages.py)
HELPERS = {"_common", "work_precision"}


def test_every_script_has_a_smoke_run():
    scripts = {p.stem for p in BENCH.glob("*.py")} - HELPERS
    assert scripts == set(SCRIPTS)
    for name in SCRIPTS:
        assert "--smoke" in (BENCH / f"{name}.py").read_text(), name


@pytest.mark.parametrize("name", sorted(SCRIPTS))
def test_benchmark_smoke_run(name, tmp_path):
    env = dict(os.environ, MPLBACKEND="Agg")
    env.pop("ROTORJAX_ROSS_PYTHON", None)  # the ROSS parts are skipped, as on a machine without ROSS
    results = BENCH / "results"
    before = {p.name: p.stat().st_mtime for p in results.iterdir()}
    proc = subprocess.run([sys.executable, str(BENCH / f"{name}.py"), "--smoke", *SCRIPTS[name]], cwd=tmp_path,
                          env=env, capture_output=True, text=True, timeout=900)
    assert proc.returncode == 0, proc.stdout[-2000:] + proc.stderr[-3000:]
    assert "smoke run: nothing written" in proc.stdout, proc.stdout[-2000:]
    assert {p.name: p.stat().st_mtime for p in results.iterdir()} == before  # nothing written
