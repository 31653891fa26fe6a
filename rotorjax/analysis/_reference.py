"""The reference motion of a scene, as data, and what every stability analysis asks
of it: its margin, its branch as a root in the rotating frame, its Floquet analysis.

A preset's `build(params)` returns, beside the scene it simulates, the motion whose
stability its maps, critical speeds and boundaries are about (`Setup.reference`):

- `StationaryRegime`: a constant state in the frame spinning with the rotor (an
  `AbstractRotatingScene`), found by Newton from `guess`; its margin is the largest
  real part of its Jacobian's eigenvalues. `balanced`: the regime must have no whirl
  (an auto-balancer's balanced regime): elsewhere the margin is NaN.
- `PeriodicOrbit`: a periodic motion of period `period` through (or near) `y0`; its
  margin is the largest Floquet exponent.
- `StraightRunning`: the undeflected rotation of a linear scene at `speed`; its margin
  is the largest real part of the linear equations' eigenvalues.

Each holds the scene it refers to (a run-up's reference is the regime at a constant
speed), so that `stability_margin(reference)` needs nothing else: a function of the
preset's parameters is `lambda p: stability_margin(preset.build(p).reference)`,
traceable wherever the build is.
"""

import equinox as eqx
import jax
import jax.numpy as jnp
import numpy as np

from .._errors import InputError
from ..models._contract import AbstractScene, require


class AbstractReference(eqx.Module):
    """A scene's reference motion (see the module docstring)."""

    scene: eqx.AbstractVar[AbstractScene]
    label: eqx.AbstractVar[str]


class StationaryRegime(AbstractReference):
    """A stationary regime of a rotating-frame scene near `guess` (its generalised
    coordinates `q` in the rotating frame, velocities zero)."""

    scene: AbstractScene
    guess: jax.Array
    label: str = eqx.field(static=True, default="the stationary regime")
    balanced: bool = eqx.field(static=True, default=False)
    whirl_tol: float = eqx.field(static=True, default=1e-8)

    def __check_init__(self):
        require(self.scene, "to_rotating", "a stationary regime")


class PeriodicOrbit(AbstractReference):
    """A periodic motion of `scene` of period `period` from the state `y0`."""

    scene: AbstractScene
    y0: jax.Array
    period: jax.Array
    label: str = eqx.field(static=True, default="the periodic motion")
    rtol: float = eqx.field(static=True, default=1e-10)
    atol: float = eqx.field(static=True, default=1e-12)


class StraightRunning(AbstractReference):
    """The undeflected rotation of a linear scene at `speed`."""

    scene: AbstractScene
    speed: jax.Array
    label: str = eqx.field(static=True, default="straight-line rotation")

    def __check_init__(self):
        require(self.scene, "linear_matrices", "straight-line rotation")


class NoReference(AbstractReference):
    """A scene without the preset's reference motion at these parameters (an
    elliptic race has no balanced regime): every analysis of it raises `reason`."""

    scene: AbstractScene
    reason: str = eqx.field(static=True)
    label: str = eqx.field(static=True, default="no reference motion")


def _check(reference, what):
    if isinstance(reference, NoReference):
        raise InputError(reference.reason)
    if not isinstance(reference, AbstractReference):
        raise InputError(f"{what} needs a reference motion (StationaryRegime, PeriodicOrbit or StraightRunning), "
                         f"got {type(reference).__name__}")


def regime(reference: StationaryRegime):
    """The stationary regime (`rotorjax.analysis.Regime`) a `StationaryRegime` refers to."""
    from ._steady import steady_state

    _check(reference, "regime")
    if not isinstance(reference, StationaryRegime):
        raise InputError(f"regime needs a StationaryRegime, got {type(reference).__name__}")
    return steady_state(reference.scene, reference.guess)


def floquet_of(reference: PeriodicOrbit):
    """The Floquet analysis (`FloquetResult`) of a `PeriodicOrbit`."""
    from ._floquet import floquet

    _check(reference, "floquet_of")
    if not isinstance(reference, PeriodicOrbit):
        raise InputError(f"floquet_of needs a PeriodicOrbit, got {type(reference).__name__}")
    return floquet(reference.scene, reference.y0, reference.period, rtol=reference.rtol, atol=reference.atol)


def floquet_batch(orbits, lanes=None, steps_per_round=8, method="auto", shard=False,
                  max_steps=100_000):
    """`floquet_of` many periodic motions at once: `orbits` is a `PeriodicOrbit` whose
    array leaves carry a batch axis `N` in front (`eqx.filter_vmap(build)(points)`,
    with `build(point) -> PeriodicOrbit`). The variational equations of every orbit
    are integrated on `simulate_batch`'s kernel at the orbits' `rtol`/`atol`
    (`rotorjax.analysis._floquet.floquet_many`; `lanes`, `steps_per_round`, `method`,
    `shard`, `max_steps` as there). Each point's result equals `floquet_of`'s to the
    tolerance; a point that fails is marked by its `code`.

    **Returns:** a `FloquetResult` whose fields carry the batch axis in front."""
    from ._floquet import floquet_many

    if not isinstance(orbits, PeriodicOrbit):
        raise InputError(f"orbits must be a batch of PeriodicOrbit references (eqx.filter_vmap of a function "
                         f"returning one), got {type(orbits).__name__}")
    y0s = jnp.asarray(orbits.y0, dtype=jnp.float64)
    periods = jnp.asarray(orbits.period, dtype=jnp.float64)
    if y0s.ndim != 2 or periods.shape != y0s.shape[:1]:
        raise InputError(f"orbits must carry one batch axis in front (y0 of shape (N, state_size), period of "
                         f"shape (N,)), got y0 of shape {y0s.shape}, period of shape {periods.shape}")
    return floquet_many(orbits.scene, y0s, periods, orbits.rtol, orbits.atol, lanes, steps_per_round, method, shard,
                        max_steps)


def stability_margin(reference) -> jax.Array:
    """The stability margin of a reference motion (< 0: stable): the largest real
    part of the eigenvalues (a stationary regime, straight running) or the largest
    Floquet exponent (a periodic orbit). NaN where the regime is not found (a balanced
    regime that whirls counts as not found). Traceable in the scene's parameters."""
    from ._response import linear_margin

    _check(reference, "stability_margin")
    if isinstance(reference, StationaryRegime):
        r = regime(reference)
        ok = r.converged & (r.whirl_amplitude < reference.whirl_tol) if reference.balanced else r.converged
        return jnp.where(ok, r.margin, jnp.nan)
    if isinstance(reference, PeriodicOrbit):
        return floquet_of(reference).margin
    return linear_margin(reference.scene, reference.speed)


#: from this many points up, `stability_margins` takes periodic references through
#: `floquet_batch`. On a product grid (neighbouring points alike, so the vmapped
#: chunks waste little in lock-step) the two run about as fast with the same XLA
#: options (model 001's 200 x 50 map, one core: 3 570 and 3 390 points/s), and the
#: batch kernel's first call compiles for ~15 s against ~5 s (four copies of the
#: variational equations in its program); it pays back on large batches, and where the
#: points' step counts differ within a chunk (scattered designs)
FLOQUET_BATCH_FROM = 20_000


def stability_margins(reference_at, points: dict, chunk_size=None, progress=False) -> np.ndarray:
    """`stability_margin(reference_at(p))` at every point of a batch (`points`: a dict
    of equal-length 1-d arrays, one entry per point). Periodic references, from
    `FLOQUET_BATCH_FROM` points up, go through `floquet_batch` (the variational
    equations of all points in one queue of lanes, no point waiting for the slowest;
    the margin NaN where a point's integration failed); the others, and smaller
    batches, through `rotorjax.sweep` (vmapped, `chunk_size` points per compiled
    call; periodic references with `CPU_COMPILER_OPTIONS` on the CPU). Returns the
    margins, one per point."""
    from ..sweep import sweep
    from ._floquet import CPU_COMPILER_OPTIONS

    if not callable(reference_at):
        raise InputError(f"reference_at must be a function of one point returning a reference motion, got "
                         f"{reference_at!r}")
    flat = {k: jnp.asarray(np.asarray(v, dtype=np.float64).reshape(-1)) for k, v in points.items()}
    sizes = {v.shape[0] for v in flat.values()}
    if len(sizes) != 1 or 0 in sizes:
        raise InputError(f"points: every entry must hold the same number (> 0) of values, got sizes "
                         f"{ {k: int(v.shape[0]) for k, v in flat.items()} }")
    probe = eqx.filter_eval_shape(reference_at, {k: v[0] for k, v in flat.items()})
    periodic = isinstance(probe, PeriodicOrbit)
    if periodic and next(iter(sizes)) >= FLOQUET_BATCH_FROM:
        return np.asarray(floquet_batch(eqx.filter_vmap(reference_at)(flat)).checked_margin)
    options = CPU_COMPILER_OPTIONS if periodic and jax.default_backend() == "cpu" else None
    res = sweep(lambda p: stability_margin(reference_at(p)), flat, mode="zip", chunk_size=chunk_size,
                progress=progress, compiler_options=options)
    return np.asarray(res.values).reshape(-1)


def margin_gradient(reference) -> str:
    """How a boundary's tangent is differentiated for this kind of reference:
    `"autodiff"`, or `"fd"` (central differences) for Floquet margins, which come from
    an adaptive integration."""
    _check(reference, "margin_gradient")
    return "fd" if isinstance(reference, PeriodicOrbit) else "autodiff"


def branch_problem(reference_at, value):
    """`(F, u0)`: the stationary reference regime as a root `F(u, v) = 0` of the
    rotating-frame field of `reference_at(v).scene`, from the regime at `value`
    (`reference_at(v)` the `StationaryRegime` with the continued parameter at `v`),
    for one-parameter continuation."""
    from ._rotating import rotating_field

    start = reference_at(value)
    _check(start, "branch_problem")
    if not isinstance(start, StationaryRegime):
        raise InputError(f"a branch of stationary regimes needs a StationaryRegime reference; {start.label} is a "
                         f"{type(start).__name__}")
    r = regime(start)
    if not bool(r.converged):
        raise InputError(f"no {start.label} at the starting parameters (residual {float(r.residual):.2e})")
    if start.balanced and not float(r.whirl_amplitude) < start.whirl_tol:
        raise InputError(f"no {start.label} at the starting parameters (the regime found whirls with amplitude "
                         f"{float(r.whirl_amplitude):.2e})")

    def F(u, v):
        return rotating_field(reference_at(v).scene, 0.0, u)

    return F, np.asarray(r.z)


def floquet_family(reference_at):
    """`value -> FloquetResult`: the periodic reference motion's Floquet analysis with
    the continued parameter at `value` (`reference_at(v)` its `PeriodicOrbit`)."""

    def fl(v):
        ref = reference_at(v)
        _check(ref, "floquet_family")
        if not isinstance(ref, PeriodicOrbit):
            raise InputError(f"Floquet multipliers along a parameter need a PeriodicOrbit reference; {ref.label} "
                             f"is a {type(ref).__name__}")
        return floquet_of(ref)

    return fl
