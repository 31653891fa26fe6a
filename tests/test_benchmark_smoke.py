"""Every benchmark script runs: `python benchmarks/NAME.py --smoke` (tiny sizes, one
call per timing, every method's code path once, nothing written, no timing asserted), so that a
change that breaks a benchmark fails here and not at the next measurement. The
scripts run one after another in one fresh interpreter per group (`benchmark_smoke_runner.py`:
the imports and shared compilations paid once per group, with the workers' XLA flags, so that
the run's compilation cache serves both; those that split work over host devices in a second
one, `tests.helpers.SMOKE_HOST_DEVICES`), each reported by its own test; the
groups (`tests.helpers.SMOKE_GROUPS`) are this file's and test_benchmark_smoke_2.py's and _3's,
so that they run on different workers. A new script in `benchmarks/` must join a group (or the
helpers')."""

from pathlib import Path

import pytest

from tests.helpers import SMOKE_GROUPS, SMOKE_HOST_DEVICES, check_benchmark_smoke, run_benchmark_smokes

BENCH = Path(__file__).resolve().parent.parent / "benchmarks"
#: modules that are not benchmarks: shared helpers, and the results page (tests/test_benchmark_pages.py)
HELPERS = {"_common", "work_precision", "_ross_st_rotor"}


def test_every_script_has_a_smoke_run():
    scripts = [name for group in SMOKE_GROUPS for name in group]
    assert sorted(scripts) == sorted({p.stem for p in BENCH.glob("*.py")} - HELPERS)
    for name in scripts:
        assert "--smoke" in (BENCH / f"{name}.py").read_text(), name
    assert set(SMOKE_HOST_DEVICES) <= set(scripts)
    for name in SMOKE_HOST_DEVICES:   # a script given two host devices counts them
        assert "jax.local_devices()" in (BENCH / f"{name}.py").read_text(), name


@pytest.fixture(scope="module")
def smoke_runs(tmp_path_factory):
    return run_benchmark_smokes(tmp_path_factory.mktemp("smoke"), SMOKE_GROUPS[0])


@pytest.mark.parametrize("name", SMOKE_GROUPS[0])
def test_benchmark_smoke_run(name, smoke_runs):
    check_benchmark_smoke(name, smoke_runs)
