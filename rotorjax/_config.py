"""Float64 for the whole package.

rotorjax enables JAX's 64-bit mode when it is imported (`jax_enable_x64`), because
the stability margins and balanced states it computes are below single precision.
Import rotorjax before creating any JAX arrays you will pass to it, or set the
environment variable `JAX_ENABLE_X64=1` yourself.

It also turns off XLA's concurrency-optimised scheduler on CPU
(`--xla_cpu_enable_concurrency_optimized_scheduler=false`, added to `XLA_FLAGS`
unless that variable already names it). With it on, a vmapped program with many
independent eigenvalue calls (the gradient of a separation margin over several
designs, on 2 cores) deadlocked about every run: every XLA thread idle, the
result never ready. XLA reads `XLA_FLAGS` when JAX starts its first backend, so
import rotorjax before running any JAX computation (or set the flag yourself).
A compiled loop (`lax.while_loop`) around such a gradient deadlocked even with the
option off (and with Eigen's threads and XNNPACK off too), so `rotorjax.design`
keeps its loops on the host.
"""

import os

import jax

#: the XLA option rotorjax sets, and its value (see the module)
CPU_SCHEDULER_FLAG = "--xla_cpu_enable_concurrency_optimized_scheduler=false"


def _add_xla_flag(flag: str) -> None:
    flags = os.environ.get("XLA_FLAGS", "")
    if flag.split("=")[0] not in flags:
        os.environ["XLA_FLAGS"] = f"{flags} {flag}".strip()


_add_xla_flag(CPU_SCHEDULER_FLAG)
jax.config.update("jax_enable_x64", True)


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
