"""The notebooks (jupytext percent-format scripts in notebooks/) run end to end,
writing their figures and `<name>_claims.json`: every number a notebook prints as a
finding is written there too and asserted by `tests/notebook_checks/<name>.py`
(`check(claims)`). How long they take is not asserted here (a shared CI machine's
load decides it; speed lives in benchmarks/): a run past the subprocess's limit fails."""

import importlib
import json
import os
import subprocess
import sys

import pytest

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))


@pytest.mark.parametrize("name,figures", [
    ("parameter_study", ["parameter_study.png"]),
    ("identification", ["identification.png", "identification_flexible.png"]),
    ("stability_boundaries", ["boundary_001.png", "boundary_003.png"]),
])
def test_notebook_runs(name, figures, tmp_path):
    env = dict(os.environ, ROTORJAX_NOTEBOOK_OUT=str(tmp_path), MPLBACKEND="Agg")
    proc = subprocess.run([sys.executable, os.path.join(ROOT, "notebooks", f"{name}.py")], env=env,
                          capture_output=True, text=True, timeout=400, cwd=str(tmp_path))
    assert proc.returncode == 0, proc.stderr[-3000:]
    for f in figures:
        assert (tmp_path / f).stat().st_size > 0
    claims_file = tmp_path / f"{name}_claims.json"
    check = importlib.import_module(f"tests.notebook_checks.{name}")
    if getattr(check, "REQUIRED", False) or claims_file.exists():
        check.check(json.loads(claims_file.read_text()))
