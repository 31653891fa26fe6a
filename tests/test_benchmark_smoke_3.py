"""The benchmarks' smoke runs, group 3 (see test_benchmark_smoke.py)."""

import pytest

from tests.helpers import SMOKE_GROUPS, check_benchmark_smoke, run_benchmark_smokes


@pytest.fixture(scope="module")
def smoke_runs(tmp_path_factory):
    return run_benchmark_smokes(tmp_path_factory.mktemp("smoke"), SMOKE_GROUPS[2])


@pytest.mark.parametrize("name", SMOKE_GROUPS[2])
def test_benchmark_smoke_run(name, smoke_runs):
    check_benchmark_smoke(name, smoke_runs)
