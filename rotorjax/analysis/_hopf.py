"""Hopf points of straight-line rotation: the speed where a pair of eigenvalues of
the linearised system crosses the imaginary axis (for model 004, the onset of
self-excited whirl from internal friction)."""

import dataclasses
from typing import Callable

import equinox as eqx
import jax
import jax.numpy as jnp
import numpy as np

from .._errors import InputError
from ..models._contract import AbstractScene, require
from ._critical import stability_thresholds


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


def _margin_at(state_matrix, s):
    return jnp.max(jnp.real(jnp.linalg.eigvals(state_matrix(s))))


def _scene_state_matrix(scene, s):
    return scene.linear_matrices(s).state_matrix()


def _margin(state_matrix):
    # Partials, not closures: another scene of the same structure (other stiffness, viscosity, ...)
    # finds the scan compiled, its arrays the program's inputs
    return eqx.Partial(_margin_at, state_matrix)


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
        state_matrix = eqx.Partial(_scene_state_matrix, scene)
    margin = _margin(state_matrix)
    out = []
    found, scan = stability_thresholds(margin, lo, hi, n_scan=n_scan, xtol=xtol, chunk_size=8, return_scan=True,
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
    `max Re lambda(A(speed, param)) = 0`: `-Re(dlambda/dparam) / Re(dlambda/dspeed)`,
    each eigenvalue derivative `w^H (dA) v / (w^H v)` from the crossing eigenvalue's
    left and right eigenvectors `w`, `v` and the derivatives of `A` by forward-mode
    autodiff (through whatever `A` is built from: an equilibrium found by Newton, a
    table's spline)."""
    from scipy.linalg import eig

    s, p = jnp.float64(speed), jnp.float64(param)
    one = jnp.ones((), dtype=jnp.float64)
    A, dA_ds = jax.jvp(lambda x: state_matrix2(x, p), (s,), (one,))
    dA_dp = jax.jvp(lambda q: state_matrix2(s, q), (p,), (one,))[1]
    lam, w, v = eig(np.asarray(A), left=True, right=True)
    k = int(np.argmax(lam.real))
    wk, vk = w[:, k], v[:, k]

    def d(dA):
        return (wk.conj() @ np.asarray(dA) @ vk) / (wk.conj() @ vk)

    return float(-np.real(d(dA_dp)) / np.real(d(dA_ds)))


@dataclasses.dataclass(frozen=True)
class HopfReport:
    """What `reference_hopf_points` returns: the Hopf `points` of a reference motion in
    a speed range, the `whirl` of the crossing mode at each (`"forward"`,
    `"backward"`, or `"undefined"` for a scene without nodes), the derivative of each
    Hopf speed with respect to a parameter (`sensitivities`, None when not asked), and
    the scan of the margin (`speeds`, `margins`)."""

    points: tuple
    whirl: tuple
    sensitivities: tuple | None
    speeds: np.ndarray
    margins: np.ndarray

    def as_dict(self, speed_key="speed", sensitivity_key=None) -> dict:
        """JSON rows: each point's fields, its speed again as `{speed_key}_crit`, its
        whirl, and its sensitivity as `d{speed_key}_crit_d_{sensitivity_key}`; the
        first point's speed and frequency on top."""
        rows = []
        for i, h in enumerate(self.points):
            d = h.as_dict()
            d.update({f"{speed_key}_crit": h.speed, "whirl_frequency": h.frequency,
                      "whirl_frequency_ratio": h.frequency / h.speed, "whirl": self.whirl[i]})
            if self.sensitivities is not None and sensitivity_key:
                d[f"d{speed_key}_crit_d_{sensitivity_key}"] = self.sensitivities[i]
            rows.append(d)
        out = {"hopf_points": rows}
        if self.points:
            out[f"{speed_key}_crit"], out["whirl_frequency"] = self.points[0].speed, self.points[0].frequency
        return out


def _crossing_whirl(scene, speed, lam):
    """The whirl of the mode whose eigenvalue is `lam` at `speed`."""
    from ..models._contract import AbstractShaftModel
    from ._linear import modes

    if not isinstance(scene, AbstractShaftModel):
        return "undefined"
    m = modes(scene, speed)
    k = int(np.argmin(np.abs(np.asarray(m.eigenvalues) - (lam.real + 1j * abs(lam.imag)))))
    return "forward" if bool(np.asarray(m.forward)[k]) else "backward"


def reference_hopf_points(reference, lo: float, hi: float, n_scan: int = 80, sensitivity=None,
                          progress: bool = False) -> HopfReport:
    """The Hopf points of a reference motion with linear equations (a
    `StraightRunning`: its scene's `linear_matrices(speed)`) in `[lo, hi]`
    (`hopf_points`), the whirl of each crossing mode, and with `sensitivity = (value,
    reference_at)` the derivative of each Hopf speed with respect to a parameter at
    `value` (`reference_at(v)` the reference with the parameter at `v`; the implicit
    function theorem, `hopf_speed_gradient`)."""
    from ._reference import StraightRunning, _check

    _check(reference, "reference_hopf_points")
    if not isinstance(reference, StraightRunning):
        raise InputError(f"Hopf points need a reference motion with linear equations (StraightRunning); "
                         f"{reference.label} is a {type(reference).__name__}")
    scene = reference.scene

    a = eqx.Partial(_scene_state_matrix, scene)

    points, (speeds, margins) = hopf_points(a, lo, hi, n_scan=n_scan, return_scan=True, progress=progress)
    whirl = []
    for h in points:
        lam = np.asarray(jnp.linalg.eigvals(a(jnp.float64(h.speed))))
        whirl.append(_crossing_whirl(scene, h.speed, lam[np.argmax(lam.real)]))
    sens = None
    if sensitivity is not None:
        value, reference_at = sensitivity
        sens = tuple(hopf_speed_gradient(lambda s, v: reference_at(v).scene.linear_matrices(s).state_matrix(),
                                         h.speed, value) for h in points)
    return HopfReport(tuple(points), tuple(whirl), sens, np.asarray(speeds), np.asarray(margins))
