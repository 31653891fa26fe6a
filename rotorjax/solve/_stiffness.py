"""Choosing a solver: explicit unless the scene is stiff at the initial state.

Two measures of stiffness, both from the eigenvalues of the linearisation at the
initial state:

- `stiffness_ratio`: the fastest decay over the dynamics of interest. Above
  `STIFFNESS_THRESHOLD` an implicit solver is cheaper (measured).
- `estimate_stiffness(...).explicit_steps`: the steps Dopri8 is expected to take
  over the span at the tolerance, each eigenvalue's step bounded by Dopri8's
  stability region along its direction and, for an oscillation, by the accuracy
  the tolerance asks (a mode that rings must be followed). Where the span makes
  this pass the step budget, an explicit run cannot finish: "auto" takes the
  implicit solver when that fastest eigenvalue decays, and the analysis layer
  (`rotorjax.analysis.plan_run`) reduces a finite-element rotor to its lower modes
  when it oscillates (an implicit solver must follow a ringing mode as closely).
"""

import functools
from typing import NamedTuple

import diffrax
import equinox as eqx
import jax
import jax.numpy as jnp
import numpy as np

from ..models._validate import InputError, is_concrete

#: Above this stiffness ratio "auto" picks an implicit solver (see `stiffness_ratio`).
#: Measured in benchmarks/solver_choice.py on model 000 (delta_b sweep): at
#: delta_b = 40 (ratio ~27) and 400 (~280) Dopri8 is faster than Kvaerno5; at
#: delta_b = 4000 (~2800) Dopri8 fails and Kvaerno5 takes ~2000 steps.
STIFFNESS_THRESHOLD = 1000.0

#: Dopri8's accepted step times the frequency of the fastest mode that rings, as
#: `ACCURACY_SCALE * rtol ** (1/8)` (capped by the stability region). Fitted to the
#: full FE rotors ross_compare.toml (50 rad/s) and tapered_two_material.toml started
#: from rest: h * |lambda| = 3.6 and 3.6 at rtol 1e-6, 1.8 and 3.0 at 1e-8, 1.0 and 1.1
#: at 1e-10 (the fit: 3.2, 1.8, 1.0; it errs towards more steps).
ACCURACY_SCALE = 17.8

#: Steps tried per step accepted in the estimate (the same runs: 1.15-1.3).
TRIES_PER_STEP = 1.3

#: An eigenvalue closer to the imaginary axis than this angle from it is counted at
#: it: DOP853's stability region hugs the imaginary axis and is open on it only to
#: |h lambda| = 0.36, yet an undamped mode's growth there is below any tolerance.
_AXIS_MARGIN = 0.01 * np.pi


class StiffnessEstimate(NamedTuple):
    """What the linearisation at the initial state says of an explicit run."""

    spectral_radius: float    # max |lambda| (1/time unit)
    fastest_decay: float      # max -Re(lambda)
    fastest_oscillation: float  # max |Im(lambda)|
    ratio: float              # `stiffness_ratio`
    explicit_steps: float     # Dopri8's expected steps (tried) over the span at rtol
    limiting: str             # "decay" or "oscillation": the eigenvalue that bounds Dopri8's step


@functools.cache
def _dopri8_stability_coefficients() -> np.ndarray:
    """Coefficients of Dopri8's stability polynomial `R(z) = sum_k c_k z^k`
    (`c_k = b^T A^(k-1) 1`), from diffrax's tableau."""
    tab = diffrax.Dopri8().tableau
    n = len(tab.a_lower) + 1
    A = np.zeros((n, n))
    for i, row in enumerate(tab.a_lower):
        A[i + 1, :len(row)] = np.asarray(row)
    b, v, c = np.asarray(tab.b_sol), np.ones(n), [1.0]
    for _ in range(n):
        c.append(float(b @ v))
        v = A @ v
    return np.asarray(c)


def dopri8_stability_radius(angle) -> np.ndarray:
    """Largest `|h lambda|` with `h lambda` in Dopri8's stability region along the
    ray at `angle` (radians from the positive real axis, pi/2..pi; nearer the
    imaginary axis than 1% of pi counts as that margin), vectorised."""
    angle = np.clip(np.abs(np.asarray(angle, dtype=np.float64)), np.pi / 2 + _AXIS_MARGIN, np.pi)
    s = np.linspace(0.0, 8.0, 1601)[1:]
    z = s[None, :] * np.exp(1j * angle.reshape(-1))[:, None]
    unstable = np.abs(np.polyval(_dopri8_stability_coefficients()[::-1], z)) > 1.0
    first = np.where(unstable.any(axis=1), np.argmax(unstable, axis=1), s.size)
    return np.where(first > 0, s[np.maximum(first - 1, 0)], 0.0).reshape(angle.shape)


def _eigenvalues(scene, y0, t0):
    return np.linalg.eigvals(jacobian_at(scene, y0, t0))


def _ratio(lam, spin):
    decay = max(float(np.max(-lam.real)), 0.0)
    scale = max(float(np.max(np.abs(lam.imag))), spin, 1e-300)
    return decay / scale


def stiffness_ratio(scene, y0, t0=0.0) -> float:
    """Ratio of the fastest decay rate of the linearised system at `(t0, y0)` to its
    fastest oscillation or the spin speed: how many times smaller than the dynamics
    of interest an explicit solver's step would have to be for stability alone."""
    return _ratio(_eigenvalues(scene, y0, t0), abs(float(scene.speed.speed(np.float64(t0)))))


def jacobian_at(scene, y0, t0=0.0) -> np.ndarray:
    """The vector field's Jacobian at `(t0, y0)`, as a numpy array (one compiled
    program per scene layout)."""
    return np.asarray(_jacobian(scene, jnp.asarray(y0, dtype=jnp.float64), jnp.asarray(t0, dtype=jnp.float64)))


@eqx.filter_jit
def _jacobian(scene, y0, t0):
    return jax.jacfwd(lambda y: scene.vector_field(t0, y))(y0)


def estimate_stiffness(scene, y0, t0, t1, rtol, eigenvalues=None) -> StiffnessEstimate:
    """Dopri8's expected step count over `(t0, t1)` at `rtol` from the linearisation
    at `(t0, y0)` (see the module docstring): each eigenvalue bounds the step by
    Dopri8's stability radius along its direction over `|lambda|` and, where it
    oscillates (`|Im| > |Re|`), by `ACCURACY_SCALE * rtol ** (1/8) / |lambda|`; the
    count is `TRIES_PER_STEP * (t1 - t0) / h`. It counts every mode as excited: a
    scene that leaves its fast modes at rest takes fewer steps. `eigenvalues`: the
    linearisation's, where known (else computed)."""
    lam = _eigenvalues(scene, y0, t0) if eigenvalues is None else np.asarray(eigenvalues)
    spin = abs(float(scene.speed.speed(np.float64(t0))))
    mag = np.abs(lam)
    live = mag > 0
    if not np.any(live):
        return StiffnessEstimate(0.0, 0.0, 0.0, 0.0, 0.0, "decay")
    lam, mag = lam[live], mag[live]
    h = dopri8_stability_radius(np.angle(lam)) / mag
    rings = np.abs(lam.imag) > np.abs(lam.real)
    h = np.where(rings, np.minimum(h, ACCURACY_SCALE * float(rtol) ** 0.125 / mag), h)
    i = int(np.argmin(h))
    return StiffnessEstimate(
        spectral_radius=float(np.max(mag)), fastest_decay=max(float(np.max(-lam.real)), 0.0),
        fastest_oscillation=float(np.max(np.abs(lam.imag))), ratio=_ratio(lam, spin),
        explicit_steps=TRIES_PER_STEP * float(t1 - t0) / float(h[i]),
        limiting="oscillation" if rings[i] else "decay")


#: The budget rule of `is_stiff` asks the decay to be at least this many times the
#: fastest oscillation: an implicit solver's step, bounded by the oscillations, is then
#: that much longer than Dopri8's (journal_rig.toml: 17).
BUDGET_RATIO = 10.0


def is_stiff(estimate: StiffnessEstimate, max_steps=None) -> bool:
    """Whether "auto" takes the implicit solver: a decay faster than
    `STIFFNESS_THRESHOLD` times the dynamics of interest, or (with `max_steps`) a
    decay faster than `BUDGET_RATIO` times them that would hold Dopri8 to more steps
    than the budget."""
    over_budget = max_steps is not None and estimate.explicit_steps > max_steps
    return estimate.ratio > STIFFNESS_THRESHOLD or (over_budget and estimate.limiting == "decay"
                                                    and estimate.ratio > BUDGET_RATIO)


def choose_solver(scene, y0, t0=0.0, solver="auto", t1=None, rtol=None, max_steps=None):
    """Resolve `solver`: a diffrax solver passes through; a name ("dopri8",
    "tsit5", "dopri5", "kvaerno5", "kvaerno3") is instantiated; "auto" picks Dopri8,
    or Kvaerno5 where `is_stiff`: `stiffness_ratio > STIFFNESS_THRESHOLD`, or, given
    the span's end `t1`, `rtol` and `max_steps`, a decaying eigenvalue that would
    hold Dopri8 to more than `max_steps` steps (`estimate_stiffness`). Inside
    jit/vmap the values are unknown and "auto" means Dopri8: pick once for a batch
    with `choose_solver` on a representative (the stiffest) point."""
    if isinstance(solver, diffrax.AbstractSolver):
        return solver
    names = {
        "dopri8": diffrax.Dopri8, "dopri5": diffrax.Dopri5, "tsit5": diffrax.Tsit5,
        "kvaerno5": diffrax.Kvaerno5, "kvaerno3": diffrax.Kvaerno3,
    }
    if solver == "auto":
        leaves = jax.tree_util.tree_leaves((scene, y0))
        if all(is_concrete(x) for x in leaves) and np.ndim(y0) == 1:
            spanned = all(v is not None and is_concrete(v) for v in (t0, t1, rtol))
            if spanned:
                stiff = is_stiff(estimate_stiffness(scene, y0, t0, t1, rtol), max_steps)
            else:
                stiff = stiffness_ratio(scene, y0, t0) > STIFFNESS_THRESHOLD
            return diffrax.Kvaerno5() if stiff else diffrax.Dopri8()
        return diffrax.Dopri8()
    if isinstance(solver, str) and solver.lower() in names:
        return names[solver.lower()]()
    raise InputError(
        f"solver must be 'auto', one of {', '.join(repr(n) for n in sorted(names))} or a diffrax "
        f"solver instance, got {solver!r}"
    )
