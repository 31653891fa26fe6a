"""Stability thresholds: the speeds where the stability margin of a reference motion
changes sign (onset, or end, of an instability). The other "critical speeds", where a
Campbell diagram's branch meets the 1x line, are `campbell_critical_speeds`."""

import dataclasses
from typing import Callable

import equinox as eqx
import jax
import jax.numpy as jnp
import numpy as np

from ..models._validate import InputError
from ..models._contract import AbstractScene, require
from ..sweep import sweep
from ._response import linear_margin
from ._roots import find_roots, root_gradient


@dataclasses.dataclass(frozen=True)
class StabilityThreshold:
    """A speed where the margin (largest real part of the eigenvalues, or largest
    Floquet exponent) crosses zero; `stable_side` is "above" or "below"; `slope` is
    d(margin)/d(speed) there; `bracket` the final bisection bracket."""

    speed: float
    stable_side: str
    slope: float
    bracket: tuple

    def as_dict(self):
        return {"speed": self.speed, "stable_side": self.stable_side, "slope": self.slope,
                "bracket": list(self.bracket)}


#: how `stability_thresholds` scans
SCANS = ("auto", "points", "vmap")


def stability_thresholds(margin: Callable, lo: float, hi: float, n_scan: int = 200,
                    xtol: float = 1e-10, chunk_size: int = 100, return_scan: bool = False,
                    progress: bool = False, scan: str = "auto"):
    """Scan `margin(speed)` (a JAX-traceable scalar function) over `[lo, hi]`, then refine
    each sign change by bisection to `xtol` (the shared root finder,
    `rotorjax.analysis.find_roots`).

    A range with no sign change returns `[]`. Non-finite margins at scan points are
    skipped (and make the bracket around them unusable). With `return_scan`,
    returns `(found, (speeds, margins))`, the scan included (for plots). With
    `progress`, a bar shows the scan (per speed; vmapped, in at least 8 chunks) and the
    bisections.
    `margin` may be a scene with `linear_matrices`: the margin of its reference
    motion's linearisation (`linear_margin`). `scan`: "points" (the bisection's compiled
    program, point by point: one compilation of the margin), "vmap" (a vmapped sweep in
    chunks of `chunk_size`: a second compilation, the points at once on an accelerator)
    or "auto" ("points" on a CPU: benchmarks/threshold_scan.py).
    """
    if isinstance(margin, AbstractScene):
        scene = margin
        require(scene, "linear_matrices", "stability_thresholds")
        margin = lambda s: linear_margin(scene, s)  # noqa: E731
    if not (np.isfinite(lo) and np.isfinite(hi) and hi > lo):
        raise InputError(f"the speed range must be finite and increasing, got ({lo}, {hi})")
    if n_scan < 2:
        raise InputError(f"n_scan must be >= 2, got {n_scan}")
    if scan not in SCANS:
        raise InputError(f"scan must be one of {', '.join(SCANS)}, got {scan!r}")
    if scan == "auto":
        scan = "points" if jax.default_backend() == "cpu" else "vmap"
    if progress:
        chunk_size = max(1, min(chunk_size, -(-n_scan // 8)))

    one = eqx.filter_jit(margin)

    def point(c):
        return one(jnp.float64(c))

    def scanned(speeds):
        if scan == "points":
            # the bisection's program: one compilation of the margin, not two (on a CPU a first call 0.7-3 s
            # sooner; a repeated call of a linear margin ~0.3 ms a point slower, of a Floquet margin faster:
            # vmapped lanes integrate in lock-step; benchmarks/results/threshold_scan.json)
            from tqdm.auto import tqdm      # here: the CLI's start imports no library it does not use

            bar = tqdm(speeds, desc="scan", unit="speed", leave=False, disable=not progress)
            return np.array([float(point(c)) for c in bar])
        # a Partial, not a fresh lambda: another call with the same margin (or an `eqx.Partial` of the same
        # function, its arrays other values) finds the vmapped scan compiled
        return sweep(eqx.Partial(_at_speed, margin), {"speed": speeds}, chunk_size=chunk_size,
                     progress=progress).values

    roots, found_scan = find_roots(point, lo, hi, n_scan, values=scanned, xtol=xtol, progress=progress,
                                   return_scan=True)
    out = [StabilityThreshold(speed=r.x, stable_side="above" if r.values[1] < 0 else "below", slope=r.slope,
                         bracket=r.bracket) for r in roots]
    return (out, found_scan) if return_scan else out


def _at_speed(margin, point):
    return margin(point["speed"])


def threshold_gradient(margin2: Callable, speed: float, param: float) -> float:
    """`d(critical speed)/d(param)` by the implicit function theorem on
    `margin2(speed, param) = 0`: `-(dm/dparam) / (dm/dspeed)`, both by autodiff
    (`rotorjax.analysis.root_gradient`)."""
    return float(root_gradient(margin2, speed, param))


#: deprecated names (one release): the speeds where a margin changes sign were called critical speeds
CriticalSpeed = StabilityThreshold
critical_speeds = stability_thresholds
critical_speed_gradient = threshold_gradient
