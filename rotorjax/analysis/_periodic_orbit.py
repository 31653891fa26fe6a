"""One periodic motion of a scene by the method asked for: harmonic balance
(forced, or an autonomous limit cycle) or shooting, a `PeriodicSolution` either way."""

import jax.numpy as jnp

from ..models._validate import InputError, as_count, as_param
from ..solve._results import RESULTS, code_of
from ..solve._simulate import simulate
from ._floquet import periodic_orbit_by_shooting, shoot
from ._harmonic_balance import (METHODS, PeriodicSolution, _samples, _time_residual, _with_floquet,
                                coefficients_from_samples, forcing_period, harmonic_balance)
from ._limit_cycles import limit_cycle


def periodic_orbit(scene, y_guess, period=None, t0=0.0, max_iter=20, tol=1e-11, rtol=1e-11, atol=1e-13, *,
                   method=None, harmonics=8, subharmonic=1, autonomous=False):
    """The periodic motion of `scene` near `y_guess`, by `method`:

    - `"harmonic-balance"`: `harmonic_balance` (forced) or `limit_cycle`
      (`autonomous`, the period solved for) with `harmonics` harmonics;
    - `"shooting"`: Newton on the time integration's closure `y(t0 + T) = y(t0)`
      (`max_iter`, `tol` on the closure, the integration at `rtol`, `atol`; with
      `autonomous` the period is an unknown, closed by a phase condition), the
      orbit then written as `harmonics` harmonics of its integrated samples.

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
    y0, T, closure, it, ok = shoot(scene, y_guess, as_param("period", period, sign="positive", shape=()), t0,
                                   as_count("max_iter", max_iter, minimum=1), tol, rtol, atol, autonomous)
    N = 4 * _samples(H, None)
    ts = t0 + T * jnp.arange(N + 1) / N
    res = simulate(scene, y0, (t0, t0 + T), saveat=ts, rtol=rtol, atol=atol)
    Y = coefficients_from_samples(jnp.asarray(res.ys)[:-1], H)
    code = code_of(RESULTS.successful) if ok else code_of(RESULTS.root_not_converged)
    sol = PeriodicSolution(coefficients=Y, period=T, t0=jnp.asarray(t0, dtype=jnp.float64),
                           residual=jnp.asarray(closure), step=jnp.asarray(closure),
                           time_residual=_time_residual(scene, Y, T, t0, None), iterations=jnp.asarray(it),
                           code=jnp.asarray(code if bool(res.success) else code_of(RESULTS.nonfinite),
                                            dtype=jnp.int32),
                           autonomous=autonomous)
    return _with_floquet(scene, sol, rtol, atol, y0=y0)
