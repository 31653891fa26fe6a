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


def numba_dop853(rhs_into):
    """scipy's DOP853 (`solve_ivp`: the same tableau, error estimate, step controller
    and initial step) compiled whole with numba around `rhs_into(t, y, out, args)`,
    `args` a tuple of the right-hand side's arrays: `dop853(y0, t0, t1, rtol, atol,
    args, max_steps)` returns `(y(t1), steps, fevals, ok)`. No Python per step or
    stage; a non-finite error estimate shrinks the step."""
    import math

    import numba
    from scipy.integrate._ivp import dop853_coefficients as dc

    A = np.ascontiguousarray(dc.A[:12, :12])
    B, Cc = np.ascontiguousarray(dc.B), np.ascontiguousarray(dc.C[:12])
    E3, E5 = np.ascontiguousarray(dc.E3), np.ascontiguousarray(dc.E5)

    @numba.njit
    def _rms(v):
        s = 0.0
        for x in v:
            s += x * x
        return math.sqrt(s / v.shape[0])

    @numba.njit
    def dop853(y0, t0, t1, rtol, atol, args, max_steps):
        """scipy's DOP853 (`solve_ivp`), compiled: returns (y(t1), steps, fevals, ok)."""
        n = y0.shape[0]
        K = np.zeros((13, n))
        y = y0.copy()
        t = t0
        f = np.empty(n)
        rhs_into(t, y, f, args)
        scale = atol + np.abs(y) * rtol
        d0, d1 = _rms(y / scale), _rms(f / scale)
        h0 = 1e-6 if (d0 < 1e-5 or d1 < 1e-5) else 0.01 * d0 / d1
        h0 = min(h0, t1 - t0)
        f1 = np.empty(n)
        rhs_into(t0 + h0, y + h0 * f, f1, args)
        d2 = _rms((f1 - f) / scale) / h0
        if d1 <= 1e-15 and d2 <= 1e-15:
            h1 = max(1e-6, h0 * 1e-3)
        else:
            h1 = (0.01 / max(d1, d2)) ** (1.0 / 8.0)
        h_abs = min(100 * h0, h1, t1 - t0)
        nfev, steps = 2, 0
        ys = np.empty(n)
        y_new = np.empty(n)
        a5 = np.empty(n)
        a3 = np.empty(n)
        while t < t1:
            if steps >= max_steps:
                return y, steps, nfev, False
            min_step = 10 * max(abs(t) * 2.220446049250313e-16, 5e-324)
            h_abs = max(h_abs, min_step)
            rejected = False
            while True:
                if h_abs < min_step:
                    return y, steps, nfev, False
                t_new = min(t + h_abs, t1)
                h = t_new - t
                K[0] = f
                for s in range(1, 12):
                    ys[:] = y
                    for j in range(s):
                        cf = h * A[s, j]
                        if cf != 0.0:
                            for i in range(n):
                                ys[i] += cf * K[j, i]
                    rhs_into(t + Cc[s] * h, ys, K[s], args)
                y_new[:] = y
                for j in range(12):
                    cf = h * B[j]
                    if cf != 0.0:
                        for i in range(n):
                            y_new[i] += cf * K[j, i]
                rhs_into(t_new, y_new, K[12], args)
                nfev += 12
                steps += 1
                a5[:] = 0.0
                a3[:] = 0.0
                for j in range(13):
                    c5, c3 = E5[j], E3[j]
                    for i in range(n):
                        a5[i] += c5 * K[j, i]
                        a3[i] += c3 * K[j, i]
                e5, e3 = 0.0, 0.0
                for i in range(n):
                    sc = atol + max(abs(y[i]), abs(y_new[i])) * rtol
                    e5 += (a5[i] / sc) ** 2
                    e3 += (a3[i] / sc) ** 2
                if e5 == 0.0 and e3 == 0.0:
                    err = 0.0
                else:
                    err = abs(h) * e5 / math.sqrt((e5 + 0.01 * e3) * n)
                if not err < 1.0 and not math.isfinite(err):   # a NaN force (past the wall): shrink
                    err = 1e10
                if err < 1.0:
                    factor = 10.0 if err == 0.0 else min(10.0, 0.9 * err ** (-1.0 / 8.0))
                    if rejected:
                        factor = min(1.0, factor)
                    h_abs *= factor
                    break
                h_abs *= max(0.2, 0.9 * err ** (-1.0 / 8.0))
                rejected = True
            t = t_new
            y[:] = y_new
            f[:] = K[12]
        return y, steps, nfev, True

    return dop853
