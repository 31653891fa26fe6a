"""Where the suite's time goes: JAX's own compile-time events, summed per test file.

Enabled by `ROTORJAX_SUITE_PROFILE=DIR` (tests/conftest.py installs it; so do the subprocesses
the suite starts, `tests/benchmark_smoke_runner.py` and `tests/notebook_run.py`, which inherit the
variable). Each process writes `DIR/<pid>.json` when it ends: `{file: {event: seconds}}`, where
`file` is the test file that was running (`ROTORJAX_SUITE_PROFILE_FILE`, which the worker sets for
its subprocesses) and the events are JAX's monitoring durations:

- `trace`: `/jax/core/compile/jaxpr_trace_duration` (Python tracing to a jaxpr),
- `lower`: `/jax/core/compile/jaxpr_to_mlir_module_duration` (jaxpr to StableHLO),
- `compile`: `/jax/core/compile/backend_compile_duration` (XLA compiling, or a persistent-cache load: this
  includes `cache_load`),
- `cache_load`: `/jax/compilation_cache/cache_retrieval_time_sec` (the persistent cache's hits),
- `cache_saved`: `/jax/compilation_cache/compile_time_saved_sec` (the compile time those hits saved),
- `programs`: the number of backend compilations.

Each process also writes `DIR/programs-<pid>.json`, `{"program <- callers": [compilations, seconds]}`: the name
JAX gives the backend compile event (a jitted function's, or an eager operation's primitive), the innermost
function of rotorjax that called for it and that function's caller in another file (`_caller`).

`tools/suite_profile.py` joins these with a junit file into `benchmarks/results/suite_profile.json`."""

import atexit
import collections
import json
import os
import sys

EVENTS = {
    "/jax/core/compile/jaxpr_trace_duration": "trace",
    "/jax/core/compile/jaxpr_to_mlir_module_duration": "lower",
    "/jax/core/compile/backend_compile_duration": "compile",
    "/jax/compilation_cache/cache_retrieval_time_sec": "cache_load",
    "/jax/compilation_cache/compile_time_saved_sec": "cache_saved",
}
_FILE = "ROTORJAX_SUITE_PROFILE_FILE"
_totals = collections.defaultdict(lambda: collections.defaultdict(float))
_programs = collections.defaultdict(lambda: [0, 0.0])   # {program name: [backend compilations, seconds]}


def current_file(name):
    """Charge what follows to the test file `name` (this process and the subprocesses it starts)."""
    os.environ[_FILE] = name


def _listen(event, duration, **kwargs):
    key = EVENTS.get(event)
    if key is None:
        return
    where = _totals[os.environ.get(_FILE, "?")]
    where[key] += duration
    if key == "compile":
        where["programs"] += 1
        named = _programs[f'{kwargs.get("fun_name", "?")} <- {_caller()}']
        named[0] += 1
        named[1] += duration


def _where(path):
    """A frame's file as the profile names it: `rotorjax/...`, `tests/...` or `benchmarks/...`; None elsewhere."""
    path = path.replace(os.sep, "/")
    if "/site-packages/" in path:
        return None
    for root in ("rotorjax", "tests", "benchmarks"):
        if f"/{root}/" in path:
            return f"{root}/{path.rsplit(f'/{root}/', 1)[1]}"
    return None


def _caller():
    """Where a compile was asked for: the innermost frame of rotorjax's code (else of the tests' or
    benchmarks'), then the next frame in another of those files (its caller), as `file:function < file:function`."""
    frames, frame = [], sys._getframe(2)
    while frame is not None:
        where = _where(frame.f_code.co_filename)
        if where:
            frames.append((where, frame.f_code.co_name))
        frame = frame.f_back
    first = next((i for i, (w, _) in enumerate(frames) if w.startswith("rotorjax/")), 0)
    chain = frames[first:first + 1]
    chain += [f for f in frames[first + 1:] if chain and f[0] != chain[0][0]][:1]
    return " < ".join(f"{w}:{n}" for w, n in chain) or "?"


def write():
    """Write this process's totals now (`DIR/<pid>.json`, replaced by a later call); a no-op when off."""
    directory = os.environ.get("ROTORJAX_SUITE_PROFILE")
    if directory and _totals:
        with open(os.path.join(directory, f"{os.getpid()}.json"), "w") as f:
            json.dump({k: dict(v) for k, v in _totals.items()}, f)
        with open(os.path.join(directory, f"programs-{os.getpid()}.json"), "w") as f:
            json.dump(dict(_programs), f)


def install():
    """Listen to JAX's compile events when `ROTORJAX_SUITE_PROFILE` names a folder; a no-op otherwise."""
    directory = os.environ.get("ROTORJAX_SUITE_PROFILE")
    if not directory:
        return
    import jax.monitoring

    os.makedirs(directory, exist_ok=True)
    jax.monitoring.register_event_duration_secs_listener(_listen)
    atexit.register(write)
