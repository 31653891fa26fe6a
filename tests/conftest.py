import collections
import os
import tempfile

import jax
import pytest

jax.config.update("jax_enable_x64", True)
jax.config.update("jax_numpy_rank_promotion", "raise")

# One compilation cache for the subprocesses of the run (the notebooks, the benchmarks' smoke runs): the
# same computations are compiled by many of them. Fresh per run, so a test never sees a compilation from
# an older tree. The CLI commands the workers call in-process do not set up their own
# (`ROTORJAX_NO_COMPILATION_CACHE`).
_CACHE = os.environ.setdefault("JAX_COMPILATION_CACHE_DIR", tempfile.mkdtemp(prefix="rotorjax-jax-cache-"))
os.environ.setdefault("JAX_PERSISTENT_CACHE_MIN_COMPILE_TIME_SECS", "0")
os.environ.setdefault("JAX_PERSISTENT_CACHE_MIN_ENTRY_SIZE_BYTES", "0")
os.environ["ROTORJAX_NO_COMPILATION_CACHE"] = "1"
# The workers share that cache for every program that takes 0.05 s or more to compile: the same Floquet,
# continuation, FE and CLI programs recur across files, and each file's programs are freed after it
# (`_free_compiled_programs`). Measured on the CLI and README files (2 workers, 445 tests, 2026-11-27, runs
# alternated): 308 and 313 s with 0.05 s, 344 and 331 s with the 1 s this had before.
jax.config.update("jax_compilation_cache_dir", _CACHE)
jax.config.update("jax_persistent_cache_min_compile_time_secs", 0.05)
jax.config.update("jax_persistent_cache_min_entry_size_bytes", 0)


@pytest.fixture(autouse=True, scope="module")
def _free_compiled_programs():
    """Drop JAX's compiled programs after each test file. Each compiled CPU program keeps
    memory mappings of its code; a worker that ran hundreds of files reached 34 000 of
    the kernel's default 65 530 (`vm.max_map_count`) and then died inside XLA, compiling
    (measured 2026-11-25, five of six full runs). A file's own programs are kept while it runs."""
    yield
    jax.clear_caches()


#: the longest test files, longest first (seconds on the 2-core CI machine, 2 workers, 2026-11-25: the sums of
#: their tests' durations; ">=" where only their slowest tests were measured, "~" scaled from a run on a loaded
#: machine), started first, so that no long file starts last and keeps one worker busy alone at the end. A new
#: file of more than about 20 s joins the list. The other files follow, those with more tests first (pytest-xdist's
#: own order).
LONGEST_FIRST = (
    "test_benchmark_smoke_3.py",               # ~ 330 locally, 2026-11-28 (a third of the benchmarks' --smoke runs,
    "test_benchmark_smoke.py",                 # ~ 320                    one subprocess each; more in CI, with ROSS
    "test_benchmark_smoke_2.py",               # ~ 300                    and AUTO-07p installed)
    "test_cli.py",                             # >= 108
    "test_readme.py",                          # ~ 110
    "test_notebooks.py",                       # 105 (three subprocesses)
    "analysis/test_floquet.py",                # ~ 260 (these seven: one file alone on a loaded machine, 2026-11-27)
    "identify/test_fe_identify.py",            # ~ 260
    "models/test_composition_voigt.py",        # ~ 200
    "models/test_composition_balancer.py",     # ~ 200
    "design/test_stable_range.py",             # ~ 180
    "design/test_onset.py",                    # ~ 150
    "design/test_design.py",                   # ~ 140
    "design/test_positions.py",                # ~ 35
    "analysis/test_continuation.py",           # >= 57
    "solve/test_batch.py",                     # >= 50
    "validation/test_model004_whirl_cycle.py",  # >= 46
    "models/test_fe_building.py",              # ~ 48
    "validation/test_ross_suite.py",           # ~ 46
    "test_right_or_refused.py",                # >= 43
    "validation/test_oil_whip.py",             # ~ 55
    "models/test_film_rotor.py",               # ~ 45
    "validation/test_oil_whirl_onset.py",      # ~ 40
    "models/test_composition_cubic.py",        # >= 37
    "analysis/test_conservative.py",           # ~ 35 (alone, 2026-11-29)
    "analysis/test_harmonic_balance.py",       # >= 23
    "models/test_seal.py",                     # 41 (ROSS live, once; the seal's cross coupling fitted)
    "validation/test_model_004.py",            # >= 22
    "identify/test_coverage.py",               # >= 22
    "validation/test_model_003_balancer.py",   # >= 22
    "test_distributed.py",                     # >= 18
    "identify/test_fe_cli.py",                 # >= 18
    "validation/test_model001_neimark_sacker.py",  # >= 17
    "test_bench.py",                           # >= 17
    "test_cli_periodic.py",                    # >= 16
    "test_cli_errors.py",                      # ~ 15
)


def pytest_configure(config):
    # pytest-xdist (--dist loadfile) hands the files out in the order of their numbers of tests unless told
    # not to (--loadscope-reorder, its default): the order below would be lost, and a long file with few tests
    # (the notebooks: 3 tests, 105 s) started near the end
    if getattr(config.option, "loadscopereorder", False):
        config.option.loadscopereorder = False


def pytest_collection_modifyitems(config, items):
    here = os.path.dirname(os.path.abspath(__file__))
    rank = {name: i for i, name in enumerate(LONGEST_FIRST)}
    files = {item: os.path.relpath(str(item.path), here).replace(os.sep, "/") for item in items}
    count = collections.Counter(files.values())

    def key(item):
        f = files[item]
        return (rank[f], 0) if f in rank else (len(LONGEST_FIRST), -count[f])

    items.sort(key=key)  # stable: a file's tests keep their order


# --- ROSS, live: the reference scripts (tests/**/ross_*reference.py) run in the interpreter that has it --
_ROSS_WORKER = r"""
import importlib.util, json, sys, types, warnings
warnings.filterwarnings("ignore")
path, function, stubs = sys.argv[1], sys.argv[2], json.loads(sys.argv[3])
if importlib.util.find_spec("rotorjax") is None:  # ROSS's own venv: only the constants the script reads
    for name, attrs in stubs.items():
        for i in range(1, name.count(".") + 2):
            sys.modules.setdefault(".".join(name.split(".")[:i]), types.ModuleType(".".join(name.split(".")[:i])))
        for key, value in attrs.items():  # {"NAME": {"key": {"field": ...}}}: a dict of attribute namespaces
            setattr(sys.modules[name], key, {k: types.SimpleNamespace(**v) for k, v in value.items()})
spec = importlib.util.spec_from_file_location("ross_reference", path)
module = importlib.util.module_from_spec(spec)
spec.loader.exec_module(module)
print(json.dumps(getattr(module, function)(), default=lambda o: o.tolist()))
"""


def ross_compute(script, function="compute", stubs=None, timeout=900):
    """`function()` of the reference script `script` (a path), computed live by ROSS and
    returned as JSON data. ROSS runs in a subprocess of `rotorjax.bench.ross_python()`:
    `$ROTORJAX_ROSS_PYTHON` (the virtual environment `.ci/install-ross` makes; `.ci/run`
    exports it), else this interpreter when `ross` imports here. Skips, with the reason,
    only when neither has ROSS; a ROSS that is there but fails fails the test. `stubs`
    (`{"module": {"NAME": {"key": {"field": value}}}}`) stand in for the rotorjax modules the
    script imports when ROSS's interpreter has no rotorjax: `module.NAME[key].field`."""
    import json
    import subprocess

    import pytest

    from rotorjax.bench import ross_python

    python = ross_python()
    if python is None:
        pytest.skip("ROSS is not installed here: run .ci/install-ross and set ROTORJAX_ROSS_PYTHON to the "
                    "interpreter it prints")
    proc = subprocess.run([python, "-c", _ROSS_WORKER, str(script), function, json.dumps(stubs or {})],
                          capture_output=True, text=True, timeout=timeout,
                          cwd=tempfile.gettempdir())  # not the checkout: its rotorjax/ would shadow the stubs
    assert proc.returncode == 0, f"ROSS ({python}) failed on {script}: {proc.stderr[-2000:]}"
    return json.loads(proc.stdout.strip().splitlines()[-1])
