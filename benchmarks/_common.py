"""What the benchmark scripts share: timing (compile first, median of repeats,
JAX results waited for) and writing `benchmarks/results/<name>.json`."""

import datetime
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
    """`(median seconds, first-call seconds, result)`: the first call compiles.
    `repeats=0` (smoke runs): the first call only, its time in both places."""
    t0 = time.perf_counter()
    r = _ready(fn())
    first = time.perf_counter() - t0
    ts = []
    for _ in range(repeats):
        t0 = time.perf_counter()
        r = _ready(fn())
        ts.append(time.perf_counter() - t0)
    return float(np.median(ts)) if ts else first, first, r


def timed(fn, repeats=3):
    """`(median seconds after a first, compiling call, result)`."""
    t, _, r = timed_first(fn, repeats)
    return t, r


def machine():
    return {"platform": platform.platform(), "cpu_count": os.cpu_count()}


def today():
    """The date a result was measured, for its JSON (`date`) and diagram captions."""
    return datetime.datetime.now(datetime.timezone.utc).strftime("%Y-%m-%d")


def write_results(name, out):
    """Write `out` to `benchmarks/results/<name>.json`, dated (UTC), and say so."""
    out = {**out, "date": today()}
    path = os.path.join(os.path.dirname(os.path.abspath(__file__)), "results", f"{name}.json")
    with open(path, "w") as f:
        json.dump(out, f, indent=2)
    print(f"wrote {path}")
    return path


def _busy_ticks():
    with open("/proc/stat") as f:
        v = [int(x) for x in f.readline().split()[1:]]
    return v[0] + v[1] + v[2] + v[5] + v[6] + v[7]  # user nice system irq softirq steal


class CpuWatch:
    """How busy the machine was with other processes while a benchmark ran: cores
    busy in all (`/proc/stat`, Linux) minus this process's own CPU time, over the wall
    time. On a shared machine, timings taken while `other_cores_busy` is large are
    slowed; ratios measured in the same run are more robust than absolute times."""

    def __init__(self):
        self.start()

    def start(self):
        self._t, self._cpu, self._ticks = time.perf_counter(), sum(os.times()[:4]), self._read()
        return self

    @staticmethod
    def _read():
        try:
            return _busy_ticks()
        except (OSError, ValueError, IndexError):
            return None

    def report(self):
        wall = time.perf_counter() - self._t
        own = sum(os.times()[:4]) - self._cpu
        ticks = self._read()
        if ticks is None or self._ticks is None or wall <= 0:
            return {"wall_s": wall, "own_cpu_s": own, "other_cores_busy": None}
        busy = (ticks - self._ticks) / os.sysconf("SC_CLK_TCK")
        return {"wall_s": wall, "own_cpu_s": own, "all_cpu_s": busy,
                "other_cores_busy": max(busy - own, 0.0) / wall, "cpu_count": os.cpu_count()}
