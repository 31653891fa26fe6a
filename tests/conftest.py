import os
import tempfile

import jax

jax.config.update("jax_enable_x64", True)
jax.config.update("jax_numpy_rank_promotion", "raise")

# One compilation cache for the whole run (this process and the notebooks and CLI
# subprocesses it starts): the same computations are compiled by many tests, often
# from new closures that the in-memory cache cannot match. Fresh per run, so a test
# never sees a compilation from an older tree.
_CACHE = os.environ.setdefault("JAX_COMPILATION_CACHE_DIR", tempfile.mkdtemp(prefix="rotorjax-jax-cache-"))
os.environ.setdefault("JAX_PERSISTENT_CACHE_MIN_COMPILE_TIME_SECS", "0")
os.environ.setdefault("JAX_PERSISTENT_CACHE_MIN_ENTRY_SIZE_BYTES", "0")
jax.config.update("jax_compilation_cache_dir", _CACHE)
jax.config.update("jax_persistent_cache_min_compile_time_secs", 0)
jax.config.update("jax_persistent_cache_min_entry_size_bytes", 0)


#: the longest test files (a few minutes each on the 2-core CI machine), started first: pytest-xdist
#: (`--dist loadfile`) hands files to its workers in collection order, so a long file collected last
#: would keep one worker busy alone at the end
LONGEST_FIRST = ("test_benchmark_smoke.py", "test_cli.py", "test_readme.py", "test_notebooks.py")


def pytest_collection_modifyitems(config, items):
    rank = {name: i for i, name in enumerate(LONGEST_FIRST)}
    items.sort(key=lambda item: rank.get(item.path.name, len(LONGEST_FIRST)))  # stable: the rest keep their order
