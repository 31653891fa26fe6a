"""Float64 for the whole package.

rotorjax enables JAX's 64-bit mode when it is imported (`jax_enable_x64`), because
the stability margins and balanced states it computes are below single precision.
Import rotorjax before creating any JAX arrays you will pass to it, or set the
environment variable `JAX_ENABLE_X64=1` yourself.

It also starts JAX's CPU backend with one intra-op thread (on Linux, where
the CPU backend is the default one), and turns off XLA's concurrency-optimised
scheduler on CPU (`--xla_cpu_enable_concurrency_optimized_scheduler=false`, added
to `XLA_FLAGS` unless that variable already names it). jaxlib 0.10.2 splits a
batched LAPACK call (a vmapped Cholesky, eigenvalue problem, linear solve) across
XLA's intra-op thread pool and blocks its thread until the parts are done; when
as many of them run at once as the pool has threads (two on a 2-core machine:
three critical speeds followed side by side over 128 samples, a gradient through
several eigenvalue solves), every thread waits for parts queued behind the
others, and the program never finishes, every thread idle. With one intra-op
thread the parts run in turn. XLA sizes that pool from the CPUs the process may
run on when the backend starts, so rotorjax starts it while its thread may run on
one CPU, then gives the threads it started every CPU again. The cost: XLA's CPU
kernels do not split work across cores within one program (a batched Cholesky of
4096 40x40 matrices took 2.1 s instead of 1.7 s on 2 cores); processes side by
side (the test suite's workers, `sweep`'s host devices) still use every core.
`ROTORJAX_CPU_THREADS=all` keeps XLA's own pool (and its risk). Import rotorjax
before running any JAX computation: a backend JAX has already started is left as
it is (XLA reads `XLA_FLAGS` then too).
"""

import importlib.metadata
import os
import pkgutil
import sys

import jax

#: the XLA option rotorjax sets, and its value (see the module)
CPU_SCHEDULER_FLAG = "--xla_cpu_enable_concurrency_optimized_scheduler=false"


def _add_xla_flag(flag: str) -> None:
    flags = os.environ.get("XLA_FLAGS", "")
    if flag.split("=")[0] not in flags:
        os.environ["XLA_FLAGS"] = f"{flags} {flag}".strip()


#: environment variable: "all" keeps XLA's CPU thread pool as XLA sizes it (see the module)
CPU_THREADS_VARIABLE = "ROTORJAX_CPU_THREADS"


def _accelerator_plugins() -> list:
    """The JAX plugins installed for other platforms (CUDA, ROCm, TPU): with one, the
    CPU backend is not the default, and its start is left to JAX."""
    names = [e.name for e in importlib.metadata.entry_points(group="jax_plugins")]
    try:
        import jax_plugins
        names += [m.name for m in pkgutil.iter_modules(jax_plugins.__path__)]
    except ImportError:
        pass
    try:
        importlib.metadata.version("libtpu")
        names.append("libtpu")
    except importlib.metadata.PackageNotFoundError:
        pass
    return names


def _start_cpu_backend_with_one_thread() -> bool:
    """Start JAX's CPU backend with one intra-op thread (see the module): the
    calling thread may run on one CPU while the backend starts (XLA sizes its pool
    from that), then every thread the start created gets back the CPUs the process
    had. Returns whether it did (not: asked not to, no thread affinity on this
    system (Linux only), a backend already started, another platform's plugin installed)."""
    if os.environ.get(CPU_THREADS_VARIABLE, "") == "all" or not sys.platform.startswith("linux"):
        return False
    from jax._src import xla_bridge
    platforms = (jax.config.jax_platforms or "").split(",")
    if xla_bridge._backends or (platforms[0] not in ("", "cpu")) or (platforms[0] == "" and _accelerator_plugins()):
        return False
    every = os.sched_getaffinity(0)
    before = set(os.listdir("/proc/self/task"))
    os.sched_setaffinity(0, {min(every)})
    try:
        jax.devices("cpu")
    finally:
        os.sched_setaffinity(0, every)
        for tid in set(os.listdir("/proc/self/task")) - before:
            try:
                os.sched_setaffinity(int(tid), every)
            except OSError:    # a thread that has ended since
                pass
    return True


_add_xla_flag(CPU_SCHEDULER_FLAG)
jax.config.update("jax_enable_x64", True)
_start_cpu_backend_with_one_thread()


#: environment variables: the cache folder, and the opt-out (any value but "" or "0")
CACHE_DIR_VARIABLE = "ROTORJAX_CACHE_DIR"
NO_CACHE_VARIABLE = "ROTORJAX_NO_COMPILATION_CACHE"


def default_cache_dir() -> str:
    """`$ROTORJAX_CACHE_DIR`, else `$XDG_CACHE_HOME/rotorjax/jax` (`~/.cache/rotorjax/jax`)."""
    given = os.environ.get(CACHE_DIR_VARIABLE)
    if given:
        return given
    base = os.environ.get("XDG_CACHE_HOME") or os.path.join(os.path.expanduser("~"), ".cache")
    return os.path.join(base, "rotorjax", "jax")


def enable_compilation_cache(path=None) -> str | None:
    """Turn on JAX's persistent compilation cache in `path` (default
    `default_cache_dir()`), so that a second run of a command loads its compiled
    programs from disk instead of compiling them again. Every compilation is kept
    (no minimum compile time or size). The `rotorjax` command calls this at start;
    `ROTORJAX_NO_COMPILATION_CACHE=1` turns it off; a folder JAX was already given
    (`JAX_COMPILATION_CACHE_DIR`, as the test suite does) is kept unless
    `ROTORJAX_CACHE_DIR` names another. Returns the folder used, or None
    when the cache is off or the folder cannot be created (nothing is cached then).

    Call it before the first compilation: JAX decides once per process whether it
    uses a cache."""
    if os.environ.get(NO_CACHE_VARIABLE, "") not in ("", "0"):
        return None
    if path is None and jax.config.jax_compilation_cache_dir and (
            not os.environ.get(CACHE_DIR_VARIABLE)
            or os.environ[CACHE_DIR_VARIABLE] == jax.config.jax_compilation_cache_dir):
        return jax.config.jax_compilation_cache_dir   # JAX's own setting (JAX_COMPILATION_CACHE_DIR) stands
    path = path or default_cache_dir()
    try:
        os.makedirs(path, exist_ok=True)
    except OSError:
        return None
    if not os.access(path, os.W_OK | os.X_OK):
        return None
    jax.config.update("jax_compilation_cache_dir", path)
    jax.config.update("jax_persistent_cache_min_compile_time_secs", 0.0)
    jax.config.update("jax_persistent_cache_min_entry_size_bytes", 0)
    return path
