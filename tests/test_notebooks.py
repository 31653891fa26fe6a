"""The notebooks (issue 35): each `notebooks/NAME.py` (jupytext percent format) is paired
with the `notebooks/NAME.ipynb` a repository page shows, committed with its outputs.
Each is executed here as Jupyter runs it (a `python3` kernel, nbclient:
`tests.notebook_run`), writing its figures and `<name>_claims.json`: every number a
notebook prints as a finding is written there too and asserted by
`tests/notebook_checks/<name>.py` (`check(claims)`). The committed `.ipynb` has the
`.py`'s cells, in order, with their outputs (its figures inline, no errors). How long
they take is not asserted here (speed lives in benchmarks/)."""

import importlib
import json
import os

import pytest

from tests.notebook_run import NOTEBOOKS, execute, source

@pytest.mark.parametrize("name,figures", [
    ("parameter_study", ["parameter_study.png"]),
    ("identification", ["identification.png", "identification_flexible.png"]),
    ("stability_boundaries", ["boundary_001.png", "boundary_003.png"]),
    ("everyday", ["everyday_rotor.png", "everyday_campbell.png", "everyday_response.png"]),
    ("fluid_films", ["fluid_films_locus.png", "fluid_films_onset.png"]),
    ("periodic", ["periodic_branch.png"]),
    ("design_uncertainty", ["design_uncertainty_scatter.png", "design_uncertainty_design.png"]),
])
def test_notebook_runs(name, figures, tmp_path):
    nb = execute(name, tmp_path)
    assert not [o for c in nb.cells for o in c.get("outputs", []) if o.output_type == "error"]
    shown = sum("image/png" in o.get("data", {}) for c in nb.cells for o in c.get("outputs", []))
    assert shown >= len(figures)          # each figure inline, not only written
    for f in figures:
        assert (tmp_path / f).stat().st_size > 0
    claims_file = tmp_path / f"{name}_claims.json"
    check = importlib.import_module(f"tests.notebook_checks.{name}")
    if getattr(check, "REQUIRED", False) or claims_file.exists():
        check.check(json.loads(claims_file.read_text()))


@pytest.mark.parametrize("name", ["parameter_study", "identification", "stability_boundaries", "everyday",
                                  "fluid_films", "periodic", "design_uncertainty"])
def test_the_committed_notebook_is_its_script_with_outputs(name):
    """The `.ipynb` holds the `.py`'s cells (sources equal, in order) and their outputs:
    figures inline, no error; refresh it with `python -m tests.notebook_run NAME`."""
    import nbformat

    committed = nbformat.read(os.path.join(NOTEBOOKS, f"{name}.ipynb"), as_version=4)
    script = source(name)
    assert [(c.cell_type, c.source) for c in committed.cells] == [(c.cell_type, c.source) for c in script.cells]
    outputs = [o for c in committed.cells for o in c.get("outputs", [])]
    assert any("image/png" in o.get("data", {}) for o in outputs)
    assert not [o for o in outputs if o.output_type == "error"]
