"""Critical speeds: where the stability margin of a regime changes sign."""

import dataclasses
from typing import Callable

import equinox as eqx
import jax
import jax.numpy as jnp
import numpy as np

from ..sweep import sweep


@dataclasses.dataclass(frozen=True)
class CriticalSpeed:
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


def critical_speeds(margin: Callable, lo: float, hi: float, n_scan: int = 200,
                    xtol: float = 1e-10, chunk_size: int = 100, return_scan: bool = False,
                    progress: bool = False):
    """Scan `margin(speed)` (a JAX-traceable scalar function) over `[lo, hi]` with a
    vmapped sweep, then refine each sign change by bisection to `xtol`.

    A range with no sign change returns `[]`. Non-finite margins at scan points are
    skipped (and make the bracket around them unusable). With `return_scan`,
    returns `(found, (speeds, margins))`, the scan included (for plots). With
    `progress`, a bar shows the scan (in at least 8 chunks) and the bisections.
    """
    if not (np.isfinite(lo) and np.isfinite(hi) and hi > lo):
        raise ValueError(f"the speed range must be finite and increasing, got ({lo}, {hi})")
    if n_scan < 2:
        raise ValueError(f"n_scan must be >= 2, got {n_scan}")
    if progress:
        chunk_size = max(1, min(chunk_size, -(-n_scan // 8)))
    scan = sweep(lambda p: margin(p["speed"]), {"speed": np.linspace(lo, hi, n_scan)},
                 chunk_size=chunk_size, progress=progress)
    speeds, m = scan.axes["speed"], np.asarray(scan.values)
    one = eqx.filter_jit(margin)
    out = []
    brackets = [i for i in range(n_scan - 1) if np.isfinite(m[i]) and np.isfinite(m[i + 1])
                and np.sign(m[i]) != np.sign(m[i + 1]) and m[i] != 0]
    if progress and brackets:
        from tqdm.auto import tqdm

        brackets = tqdm(brackets, desc="bisection", unit="root", leave=False)
    for i in brackets:
        a, b, ma, mb = speeds[i], speeds[i + 1], m[i], m[i + 1]
        while b - a > xtol:
            c = 0.5 * (a + b)
            mc = float(one(jnp.float64(c)))
            if not np.isfinite(mc):
                break
            if np.sign(mc) == np.sign(ma):
                a, ma = c, mc
            else:
                b, mb = c, mc
        speed = 0.5 * (a + b)
        slope = (mb - ma) / (b - a) if b > a else float("nan")
        out.append(CriticalSpeed(speed=float(speed), stable_side="above" if mb < 0 else "below",
                                 slope=float(slope), bracket=(float(a), float(b))))
    return (out, (speeds, m)) if return_scan else out


def critical_speed_gradient(margin2: Callable, speed: float, param: float) -> float:
    """`d(critical speed)/d(param)` by the implicit function theorem on
    `margin2(speed, param) = 0`: `-(dm/dparam) / (dm/dspeed)`, both by autodiff."""
    g = jax.grad(margin2, argnums=(0, 1))(jnp.float64(speed), jnp.float64(param))
    return float(-g[1] / g[0])
