"""The validation files' stored reference runs (`tests.helpers.stored_reference`)
say how they were made, and the command they name makes them again: the module it
runs exists and has the `reference()` that computes them."""

import importlib
import json
from pathlib import Path

import pytest

from tests.helpers import REFERENCE_DATA

STORED = sorted(p for p in (Path(__file__).resolve().parents[1] / REFERENCE_DATA).glob("*.json")
                if "made" in json.loads(p.read_text()))


def test_there_are_stored_runs():
    assert len(STORED) >= 4


@pytest.mark.parametrize("path", STORED, ids=lambda p: p.stem)
def test_a_stored_run_names_the_command_that_makes_it(path):
    made = json.loads(path.read_text())["made"]
    assert set(made) == {"command", "commit", "date", "jax", "diffrax"}
    program, flag, module = made["command"].split()
    assert (program, flag) == ("python", "-m") and module.startswith("tests.validation.")
    source = importlib.import_module(module)
    assert callable(source.reference)
    assert f'REFERENCE = "{path.stem}"' in Path(source.__file__).read_text()
