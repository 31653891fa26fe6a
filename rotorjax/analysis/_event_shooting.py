"""Shooting on event-located contact: the periodic motions of the exact,
non-smooth contact model (model 004's limiters without smoothing).

The flow map `y(t0) -> y(t0 + T)` is integrated by `rotorjax.solve.simulate_events`
(every contact switch located, each smooth piece to the tolerance), and Newton runs
on its closure with a Jacobian by forward differences of the map: the jumps of the
map's derivative at the switches (the saltation) are in it without being written
out. For an autonomous cycle the period is an unknown, closed by the phase
condition `f(y_guess) . (y - y_guess) = 0` (as `shoot`). The Floquet multipliers are
the eigenvalues of the monodromy by central differences of the map at the solved
period."""

import jax.numpy as jnp
import numpy as np

from .._errors import NumericalError
from ..solve._events import simulate_events
from ..solve._results import RESULTS, code_of
from ._floquet import FloquetResult


def _flow(scene, t0, rtol, atol, max_steps):
    def flow(y, T, saves=2):
        r = simulate_events(scene, jnp.asarray(y), (t0, t0 + float(T)), saveat=saves, rtol=rtol, atol=atol,
                            max_steps=max_steps)
        if int(r.code) != 0 or not np.all(np.isfinite(np.asarray(r.ys[-1]))):
            raise NumericalError(f"event-located shooting: the integration over T = {float(T):.6g} ended with "
                                 f"{r.result} (code {int(r.code)})")
        return r if saves != 2 else np.asarray(r.ys[-1])
    return flow


def _steps(y, fd_step):
    """Difference steps per state: `fd_step` times the state's size (`y`: a state,
    or states along the orbit: the largest of each), at least 1e-3 of the largest
    (a state passing through zero)."""
    a = np.abs(np.asarray(y)).reshape(-1, np.shape(y)[-1]).max(axis=0)
    return fd_step * np.maximum(a, 1e-3 * max(float(a.max()), 1e-300))


def shoot_events(scene, y_guess, period, t0=0.0, max_iter=20, tol=1e-11, rtol=1e-12, atol=1e-15,
                 autonomous=False, fd_step=1e-7, max_steps=200_000):
    """Newton on the event-located closure (see the module docstring). Returns
    `(y0, period, closure, iterations, converged)` as `shoot`."""
    flow = _flow(scene, t0, rtol, atol, max_steps)
    y = np.asarray(y_guess, dtype=float)
    T = float(period)
    n = y.size
    y_guess = y.copy()
    normal = np.asarray(scene.vector_field(t0, jnp.asarray(y), scene.contact_indicator(t0, jnp.asarray(y)) > 0))

    def G(z):
        g = flow(z[:n], z[n] if autonomous else T) - z[:n]
        return np.concatenate([g, [normal @ (z[:n] - y_guess)]]) if autonomous else g

    z = np.concatenate([y, [T]]) if autonomous else y
    closure = np.inf
    for it in range(max_iter):
        g = G(z)
        closure = float(np.max(np.abs(g[:n])))
        if closure < tol and (not autonomous or abs(g[n]) < tol):
            return z[:n], (z[n] if autonomous else T), closure, it, True
        h = np.concatenate([_steps(z[:n], fd_step), [fd_step * z[n]]]) if autonomous else _steps(z, fd_step)
        J = np.empty((g.size, z.size))
        for i in range(z.size):
            e = np.zeros(z.size)
            e[i] = h[i]
            J[:, i] = (G(z + e) - g) / h[i]
        z = z - np.linalg.solve(J, g)
    return z[:n], (z[n] if autonomous else T), closure, max_iter, False


def floquet_events(scene, y0, period, t0=0.0, rtol=1e-12, atol=1e-15, fd_step=1e-5, max_steps=200_000):
    """The Floquet analysis of the event-located periodic motion through `y0`:
    the monodromy by central differences of the map (`fd_step` times each state's
    largest value along the orbit).
    `liouville_error` is NaN: across the contact switches `det M` is not the
    integral of the trace."""
    flow = _flow(scene, t0, rtol, atol, max_steps)
    y0 = np.asarray(y0, dtype=float)
    h = _steps(np.asarray(flow(y0, period, saves=65).ys), fd_step)   # sized by the orbit, not by y0
    M = np.empty((y0.size, y0.size))
    for i in range(y0.size):
        e = np.zeros(y0.size)
        e[i] = h[i]
        M[:, i] = (flow(y0 + e, period) - flow(y0 - e, period)) / (2 * h[i])
    mu = np.linalg.eigvals(M)
    exps = np.log(np.abs(mu)) / float(period)
    return FloquetResult(monodromy=jnp.asarray(M), multipliers=jnp.asarray(mu), exponents=jnp.asarray(exps),
                         margin=jnp.asarray(exps.max()), period=jnp.asarray(float(period)),
                         liouville_error=jnp.asarray(np.nan),
                         closure=jnp.asarray(float(np.max(np.abs(flow(y0, period) - y0)))),
                         code=jnp.asarray(code_of(RESULTS.successful), dtype=jnp.int32))


def event_orbit_samples(scene, y0, period, n, t0=0.0, rtol=1e-12, atol=1e-15, max_steps=200_000):
    """`n + 1` equally spaced states over one period of the event-located orbit from
    `y0` (the last after the whole period)."""
    r = _flow(scene, t0, rtol, atol, max_steps)(y0, period, saves=n + 1)
    return np.asarray(r.ys)
