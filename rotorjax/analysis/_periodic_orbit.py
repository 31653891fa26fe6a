"""One periodic motion of a scene by the method asked for: harmonic balance
(forced, or an autonomous limit cycle) or shooting, a `PeriodicSolution` either way."""

import equinox as eqx
import jax.numpy as jnp

from ..models._contract import require
from ..models._validate import InputError, as_count, as_param
from ..solve._results import RESULTS, code_of
from ..solve._simulate import simulate
from ._event_shooting import event_orbit_samples, floquet_events, shoot_events
from ._floquet import periodic_orbit_by_shooting, shoot
from ._harmonic_balance import (METHODS, PeriodicSolution, _samples, _time_residual, _with_floquet,
                                coefficients_from_samples, forcing_period, harmonic_balance)
from ._limit_cycles import limit_cycle


def periodic_orbit(scene, y_guess, period=None, t0=0.0, max_iter=20, tol=1e-11, rtol=1e-11, atol=1e-13, *,
                   method=None, harmonics=8, subharmonic=1, autonomous=False, events=False):
    """The periodic motion of `scene` near `y_guess`, by `method`:

    - `"harmonic-balance"`: `harmonic_balance` (forced) or `limit_cycle`
      (`autonomous`, the period solved for) with `harmonics` harmonics;
    - `"shooting"`: Newton on the time integration's closure `y(t0 + T) = y(t0)`
      (`max_iter`, `tol` on the closure, the integration at `rtol`, `atol`; with
      `autonomous` the period is an unknown, closed by a phase condition), the
      orbit then written as `harmonics` harmonics of its integrated samples;
      with `events`, on the event-located contact (`simulate_events`: the exact,
      non-smooth model of a scene with contacts), the Jacobian and the monodromy
      by differences of the map (`shoot_events`, `floquet_events`).

    Both return a `PeriodicSolution` (its `residual` the balance's, or for shooting
    the closure; `time_residual` the truncation of the `harmonics`-term series)
    with its Floquet analysis. `period`: the forced motion's (default
    `forcing_period(scene, subharmonic)`), or an autonomous cycle's guess.
    `y_guess`: a state, or (harmonic balance) coefficients / a `PeriodicSolution`.

    Without `method`, the former call: shooting at the fixed period, returning
    `(y0, closure, converged)`."""
    if method is None:
        return periodic_orbit_by_shooting(scene, y_guess, period, t0, max_iter, tol, rtol, atol)
    if method not in METHODS:
        raise InputError(f"method {method!r}: one of {', '.join(map(repr, METHODS))}")
    if method != "shooting" and events:
        raise InputError("events: event-located contact is for method='shooting' (harmonic balance needs a "
                         "smooth field: smoothed contact)")
    if period is None:
        period = forcing_period(scene, subharmonic)
    if method == "harmonic-balance":
        kw = dict(t0=t0, tol=min(tol, 1e-10), max_iter=max(max_iter, 30), rtol=rtol, atol=atol)
        if autonomous:
            return limit_cycle(scene, period, y_guess, harmonics, **kw)
        return harmonic_balance(scene, period, y_guess, harmonics, **kw)
    H = as_count("harmonics", harmonics, minimum=1)
    y_guess = jnp.asarray(y_guess, dtype=jnp.float64)
    if y_guess.shape != (scene.state_size,):
        raise InputError(f"y_guess: shooting starts from a state of shape ({scene.state_size},), got {y_guess.shape}")
    args = (scene, y_guess, as_param("period", period, sign="positive", shape=()), t0,
            as_count("max_iter", max_iter, minimum=1), tol, rtol, atol, autonomous)
    if events:
        require(scene, "contact_indicator", "periodic_orbit(events=True)")
        y0, T, closure, it, ok = shoot_events(*args)
    else:
        y0, T, closure, it, ok = shoot(*args)
    N = 4 * _samples(H, None)
    if events:
        ys, success = jnp.asarray(event_orbit_samples(scene, y0, T, N, t0, rtol, atol)), True
    else:
        res = simulate(scene, y0, (t0, t0 + T), saveat=t0 + T * jnp.arange(N + 1) / N, rtol=rtol, atol=atol)
        ys, success = jnp.asarray(res.ys), bool(res.success)
    Y = coefficients_from_samples(ys[:-1], H)
    code = code_of(RESULTS.successful) if ok else code_of(RESULTS.root_not_converged)
    sol = PeriodicSolution(coefficients=Y, period=jnp.asarray(T, dtype=jnp.float64),
                           t0=jnp.asarray(t0, dtype=jnp.float64), residual=jnp.asarray(closure),
                           step=jnp.asarray(closure), time_residual=_time_residual(scene, Y, T, t0, None),
                           iterations=jnp.asarray(it),
                           code=jnp.asarray(code if success else code_of(RESULTS.nonfinite), dtype=jnp.int32),
                           autonomous=autonomous, start=jnp.asarray(y0, dtype=jnp.float64))
    if events:
        fq = floquet_events(scene, y0, T, t0, rtol, atol)
        return eqx.tree_at(lambda s: s.floquet, sol, fq, is_leaf=lambda x: x is None)
    return _with_floquet(scene, sol, rtol, atol, y0=y0)
