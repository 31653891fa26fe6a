import collections
import os
import tempfile

# XLA's CPU code generation is left at its defaults (what users run). Measured 2026-12-02, full runs on the 2-core
# machine: with `--xla_cpu_use_fusion_emitters=false --xla_backend_optimization_level=0` the suite took 35 min
# instead of 48, but results moved beyond rounding (a NaN gradient of the minimum log decrement; a batch's lanes
# no longer equal to 1e-12); with the emitters flag alone it took 50 min. (The secant fallback of
# tests/uncertainty/test_rank_change.py that ran for more than 10 minutes then, and hung CI at 20 with XLA's
# defaults, was jaxlib's batched LAPACK calls deadlocking XLA's CPU thread pool: `rotorjax._config`.)
import jax
import pytest

import rotorjax  # noqa: F401  (first: it starts JAX's CPU backend, with one intra-op thread)

from tests import suite_profile

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
# The workers share that cache for every program, however small: the same Floquet, continuation, FE and CLI
# programs recur across files, and so do the eager operations' small programs (a third of the compile time of the
# model and FE files). Measured on the CLI and README files (2 workers, 445 tests, 2026-11-27, runs alternated):
# 308 and 313 s with programs of 0.05 s or more, 344 and 331 s with 1 s or more; on tests/models, tests/flexible
# and two validation files (2026-12-02): 370 s with every program (565 tests), 385 s with 0.05 s or more (the three
# live-ROSS tests skipped).
jax.config.update("jax_compilation_cache_dir", _CACHE)
jax.config.update("jax_persistent_cache_min_compile_time_secs", 0.0)
jax.config.update("jax_persistent_cache_min_entry_size_bytes", 0)

# `ROTORJAX_SUITE_PROFILE=DIR`: JAX's compile-time events summed per test file (tests/suite_profile.py)
suite_profile.install()


def pytest_sessionfinish(session):
    suite_profile.write()   # a worker ends without running atexit


def pytest_runtest_setup(item):
    suite_profile.current_file(os.path.relpath(str(item.path), os.path.dirname(os.path.abspath(__file__))))


def _mapped_regions():
    """The number of memory mappings of this process and the kernel's limit on it (None where
    /proc does not tell), and the process's resident memory in bytes."""
    try:
        with open("/proc/self/maps") as f:
            maps = sum(1 for _ in f)
        with open("/proc/sys/vm/max_map_count") as f:
            limit = int(f.read())
        with open("/proc/self/statm") as f:
            rss = int(f.read().split()[1]) * os.sysconf("SC_PAGE_SIZE")
    except (OSError, ValueError):
        return None, None, None
    return maps, limit, rss


#: free the compiled programs once a worker holds this share of the kernel's memory mappings, or this much memory
MAPS_SHARE, RSS_LIMIT = 0.4, 6 * 2**30


@pytest.fixture(autouse=True, scope="module")
def _free_compiled_programs():
    """Drop JAX's compiled programs after a test file when the worker holds many of them. Each
    compiled CPU program keeps memory mappings of its code; a worker that ran hundreds of files
    reached 34 000 of the kernel's default 65 530 (`vm.max_map_count`) and then died inside XLA,
    compiling (measured 2026-11-25, five of six full runs). Clearing after every file made each
    file compile again what an earlier file of its worker had compiled: the eager operations'
    small programs and every jitted function of the same shapes (on four tests/flexible files in
    one process, 1 535 compilations and 177 s of compiling, against 1 215 and 141 s kept, 2026-12-02).
    So the programs are kept until the worker holds `MAPS_SHARE` of the limit or `RSS_LIMIT`
    bytes (where /proc does not tell, after every file, as before)."""
    yield
    maps, limit, rss = _mapped_regions()
    if maps is None or maps > MAPS_SHARE * limit or rss > RSS_LIMIT:
        jax.clear_caches()


#: the longest test files, longest first (seconds: the sums of their tests' durations in a full run on the 2-core
#: CI machine, 2 workers, 2026-12-02, compiled with XLA's classic emitters at -O0, which the suite no longer uses:
#: the order, not the seconds, is what counts; (*): measured 2026-12-07 in a run of those files on this machine's
#: 2 workers, with XLA's defaults), started first, so that no long file
#: starts last and keeps one worker busy alone at the end. A new file of more than about 40 s joins the list. The
#: other files follow, those with more tests first (pytest-xdist's own order).
LONGEST_FIRST = (
    "validation/test_periodic_anisotropic_jumps.py",  # 289 (*)
    "test_readme.py",                               # 269
    "validation/test_periodic_rub.py",              # 262 (*)
    "validation/test_periodic_sfd.py",              # 246 (*)
    "test_notebooks.py",                            # 228 (seven kernels)
    "test_cli_periodic.py",                         # 204 (*)
    "test_benchmark_smoke_3.py",                    # 196 (a third of the benchmarks' --smoke runs)
    "solve/test_batch.py",                          # 167
    "validation/test_oil_whip_finite.py",           # 166 (*)
    "test_cli_from_hopf.py",                        # 164 (*)
    "test_cli.py",                                  # 163
    "validation/test_oil_whip.py",                  # 160
    "test_benchmark_smoke.py",                      # 156
    "validation/test_periodic_auto_harmonics.py",   # 148 (*)
    "design/test_stable_range.py",                  # 127
    "test_benchmark_smoke_2.py",                    # 121
    "test_right_or_refused.py",                     # 96
    "design/test_onset.py",                         # 94
    "test_bench.py",                                # 89
    "analysis/test_floquet.py",                     # 78
    "models/test_composition_cubic.py",             # 73
    "uncertainty/test_quantities.py",               # 66
    "identify/test_fe_identify.py",                 # 64
    "validation/test_model_004.py",                 # 62
    "design/test_design.py",                        # 62
    "models/test_film_rotor.py",                    # 55
    "validation/test_ross_suite.py",                # 54
    "validation/test_model004_whirl_cycle.py",      # 53
    "analysis/test_harmonic_balance.py",            # 53
    "test_simulate_defaults.py",                    # 53
    "test_cli_errors.py",                           # 51
    "analysis/test_continuation.py",                # 47
    "flexible/test_ross.py",                        # 46
    "models/test_fe_building.py",                   # 45
    "test_report.py",                               # 42
    "models/test_rotor_files.py",                   # 41
)


def pytest_configure(config):
    # pytest-xdist (--dist loadfile) hands the files out in the order of their numbers of tests unless told
    # not to (--loadscope-reorder, its default): the order below would be lost, and a long file with few tests
    # (the notebooks: 3 tests, 105 s) started near the end
    if getattr(config.option, "loadscopereorder", False):
        config.option.loadscopereorder = False


#: the quick tier (`python3 -m pytest -m "not slow"`, docs/developing.md): per subsystem, the test files that run in
#: it, each with at least one check against an independent reference (named here); every other test is marked
#: `slow`. Chosen from benchmarks/results/suite_profile.json: the cheapest files that still check each subsystem
#: against something outside its own code path. tests/test_suite_tiers.py checks the table.
QUICK_TIER = {
    "seed models": (
        ("validation/test_model_003.py", "model 003's closed-form sums and eq. (17) of the paper"),
        ("validation/test_paper_equations.py", "the papers' equations of motion, an independent numpy implementation"),
    ),
    "finite elements against ROSS": (
        ("validation/test_ross_tapered.py", "ROSS 2.3.0 live and its stored reference, tapered two-material rotor"),
        ("flexible/test_fe.py", "closed forms of beams, convergence order"),
    ),
    "identification and balancing": (
        ("identify/test_fe_balance.py", "influence coefficients against the FE rotor's own response"),
    ),
    "continuation": (
        ("validation/test_auto07p.py", "AUTO-07p's branches, folds and two-parameter curves"),
    ),
    "periodic motions": (
        ("analysis/test_periodic_two_parameters.py", "closed-form fold curves of the Duffing oscillator"),
    ),
    "fluid films": (
        ("models/test_fluid_film.py", "the short-bearing pressure integrated by scipy quad, Ocvirk's closed forms"),
    ),
    "design and uncertainty": (
        ("design/test_positions.py", "the analyses of the rotor file with the bearing moved by hand"),
        ("uncertainty/test_propagate.py", "Monte Carlo against closed forms, first-order moments against exact"),
    ),
    "CLI errors": (
        ("test_cli_errors.py", "every command's bad input: exit 2 naming the option, key, file, column or row"),
        ("test_rotor_file_errors.py", "every bad rotor file named by file, table, index and key"),
    ),
}


@pytest.hookimpl(tryfirst=True)   # before pytest's own hook deselects by mark (`-m "not slow"`)
def pytest_collection_modifyitems(config, items):
    here = os.path.dirname(os.path.abspath(__file__))
    rank = {name: i for i, name in enumerate(LONGEST_FIRST)}
    files = {item: os.path.relpath(str(item.path), here).replace(os.sep, "/") for item in items}
    count = collections.Counter(files.values())
    quick = {f for entries in QUICK_TIER.values() for f, _ in entries}
    for item, f in files.items():
        if f not in quick:
            item.add_marker(pytest.mark.slow)

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
