"""What the benchmark scripts share: timing (compile first, median of repeats,
JAX results waited for) and writing `benchmarks/results/<name>.json`."""

import json
import os
import platform
import time

import numpy as np


def _ready(r):
    try:
        import jax

        return jax.block_until_ready(r)
    except (ImportError, TypeError):
        return r


def timed_first(fn, repeats=3):
    """`(median seconds, first-call seconds, result)`: the first call compiles."""
    t0 = time.perf_counter()
    r = _ready(fn())
    first = time.perf_counter() - t0
    ts = []
    for _ in range(repeats):
        t0 = time.perf_counter()
        r = _ready(fn())
        ts.append(time.perf_counter() - t0)
    return float(np.median(ts)), first, r


def timed(fn, repeats=3):
    """`(median seconds after a first, compiling call, result)`."""
    t, _, r = timed_first(fn, repeats)
    return t, r


def machine():
    return {"platform": platform.platform(), "cpu_count": os.cpu_count()}


def write_results(name, out):
    """Write `out` to `benchmarks/results/<name>.json` and say so."""
    path = os.path.join(os.path.dirname(os.path.abspath(__file__)), "results", f"{name}.json")
    with open(path, "w") as f:
        json.dump(out, f, indent=2)
    print(f"wrote {path}")
    return path
