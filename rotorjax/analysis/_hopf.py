"""Hopf points of straight-line rotation: the speed where a pair of eigenvalues of
the linearised system crosses the imaginary axis (for model 004, the onset of
self-excited whirl from internal friction)."""

import dataclasses
from typing import Callable

import jax.numpy as jnp
import numpy as np

from ..models._contract import AbstractScene, require
from ._critical import critical_speeds
from ._roots import root_gradient


@dataclasses.dataclass(frozen=True)
class HopfPoint:
    """`speed` where the largest real part of the eigenvalues turns positive,
    `frequency` the crossing pair's `|Im lambda|` there (the whirl frequency, same
    units), `slope` `d(margin)/d(speed)`, `margin_at_speed` the residual."""

    speed: float
    frequency: float
    slope: float
    margin_at_speed: float

    def as_dict(self):
        return dataclasses.asdict(self)


def _margin(state_matrix):
    return lambda s: jnp.max(jnp.real(jnp.linalg.eigvals(state_matrix(s))))


def hopf_points(state_matrix: Callable, lo: float, hi: float, n_scan: int = 80,
                xtol: float = 1e-11, return_scan: bool = False, progress: bool = False):
    """All speeds in `[lo, hi]` where the system `x' = A(speed) x` loses stability
    as the speed grows (a complex pair crossing to the right: a Hopf point of the
    nonlinear system), from a scan of the margin `max Re lambda` and bisection.
    `state_matrix` is `A(speed)`, or a scene with `linear_matrices` (its reference
    motion's linearisation). With `return_scan`, returns `(points, (speeds, margins))`."""
    if isinstance(state_matrix, AbstractScene):
        scene = state_matrix
        require(scene, "linear_matrices", "hopf_points")
        state_matrix = lambda s: scene.linear_matrices(s).state_matrix()  # noqa: E731
    margin = _margin(state_matrix)
    out = []
    found, scan = critical_speeds(margin, lo, hi, n_scan=n_scan, xtol=xtol, chunk_size=8, return_scan=True,
                                  progress=progress)
    for c in found:
        if c.stable_side != "below":
            continue
        lam = np.asarray(jnp.linalg.eigvals(state_matrix(jnp.float64(c.speed))))
        k = np.argmax(lam.real)
        out.append(HopfPoint(speed=c.speed, frequency=float(abs(lam[k].imag)), slope=c.slope,
                             margin_at_speed=float(lam[k].real)))
    return (out, scan) if return_scan else out


def hopf_speed_gradient(state_matrix2: Callable, speed: float, param: float) -> float:
    """`d(Hopf speed)/d(param)` by the implicit function theorem on
    `max Re lambda(A(speed, param)) = 0` (autodiff through the eigenvalues;
    `rotorjax.analysis.root_gradient`)."""
    def m(s, p):
        return jnp.max(jnp.real(jnp.linalg.eigvals(state_matrix2(s, p))))

    return float(root_gradient(m, speed, param))
