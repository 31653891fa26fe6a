import os
import tempfile

import jax
import pytest

jax.config.update("jax_enable_x64", True)
jax.config.update("jax_numpy_rank_promotion", "raise")

# One compilation cache for the subprocesses of the run (the notebooks, the benchmarks' smoke runs): the
# same computations are compiled by many of them. Fresh per run, so a test never sees a compilation from
# an older tree. The test workers keep their compilations in memory only (and the CLI commands they call
# in-process, `ROTORJAX_NO_COMPILATION_CACHE`): a worker's memory mappings are the limit that matters
# (`_free_compiled_programs` below), and writing thousands of small programs to disk buys little there.
_CACHE = os.environ.setdefault("JAX_COMPILATION_CACHE_DIR", tempfile.mkdtemp(prefix="rotorjax-jax-cache-"))
os.environ.setdefault("JAX_PERSISTENT_CACHE_MIN_COMPILE_TIME_SECS", "0")
os.environ.setdefault("JAX_PERSISTENT_CACHE_MIN_ENTRY_SIZE_BYTES", "0")
os.environ["ROTORJAX_NO_COMPILATION_CACHE"] = "1"
jax.config.update("jax_compilation_cache_dir", None)


@pytest.fixture(autouse=True, scope="module")
def _free_compiled_programs():
    """Drop JAX's compiled programs after each test file. Each compiled CPU program keeps
    memory mappings of its code; a worker that ran hundreds of files reached 34 000 of
    the kernel's default 65 530 (`vm.max_map_count`) and then died inside XLA, compiling
    (measured 2026-11-25, five of six full runs). A file's own programs are kept while it runs."""
    yield
    jax.clear_caches()


#: the longest test files (a few minutes each on the 2-core CI machine), started first: pytest-xdist
#: (`--dist loadfile`) hands files to its workers in collection order, so a long file collected last
#: would keep one worker busy alone at the end
LONGEST_FIRST = ("test_benchmark_smoke.py", "test_cli.py", "test_readme.py", "test_notebooks.py")


def pytest_collection_modifyitems(config, items):
    rank = {name: i for i, name in enumerate(LONGEST_FIRST)}
    items.sort(key=lambda item: rank.get(item.path.name, len(LONGEST_FIRST)))  # stable: the rest keep their order


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
