"""Harmonic balance: the periodic forced motion of any scene with a vector field.

A motion of period `T` (the forcing's, or `k` times it for a subharmonic) is
written as a truncated Fourier series of the state,

    y(t) = c_0 + sum_{k=1..H} a_k cos(k w (t - t0)) + b_k sin(k w (t - t0)),   w = 2 pi / T,

and the coefficients `Y = (c_0, a_1, b_1, ..., a_H, b_H)` (one row per term, one
column per state) solve the balance of the first `H` harmonics of `y' = f(t, y)`:

    R(Y) = D(w) Y - P f(t_j, B Y) = 0,

with the vector field evaluated at `N > 2H` equally spaced instants `t_j` of the
period (alternating frequency-time: `B` evaluates the series there, `P` projects
samples back onto the harmonics, exact for trigonometric polynomials of degree
`< N - H`), and `D(w)` the derivative in coefficient space (`a_k' = k w b_k`,
`b_k' = -k w a_k`). The state's first-order form makes it work for every scene
(any number of coordinates, components that own coordinates, smoothed contact)
without knowing its mass matrix. Newton's method with the exact Jacobian
`dR/dY` by autodiff (forward mode) solves it, in one compiled loop.

Self-checks returned with every solution: the balance residual `max |R|`, the
Newton step at exit, and the time-domain residual of the reconstructed orbit
`max_t |y'(t) - f(t, y(t))| / max_t |y'(t)|` on a grid four times finer than the
balance's: the truncation error of `H` harmonics, which the balance itself does
not see (it is the estimate a user raises `harmonics` against). Stability is
Floquet's, from the monodromy along the reconstructed orbit
(`rotorjax.analysis.floquet`, the variational equations integrated).
"""

import dataclasses

import equinox as eqx
import jax
import jax.numpy as jnp
import numpy as np

from .._errors import NumericalError
from ..models._contract import AbstractScene
from ..models._speed import ConstantSpeed
from ..models._validate import InputError, as_count, as_param, check_type, is_concrete
from ..solve._results import RESULTS, AbstractOutcome, code_of
from ..solve._simulate import simulate
from ._continuation import continue_branch, fold_curve, fold_gradient
from ._floquet import FloquetResult, floquet, flow_samples, periodic_orbit_by_shooting, shoot


class PeriodicSolution(AbstractOutcome):
    """A periodic motion by harmonic balance.

    - `coefficients`: `(2H + 1, n)`: `c_0`, then `a_k`, `b_k` of harmonic `k`
      (cosine, sine in `w (t - t0)`), one column per state.
    - `period`, `t0`: the motion's period and the phase origin.
    - `residual`: max |.| of the balance residual at exit (units of `y'`).
    - `step`: max |.| of the last Newton step, relative to max |Y|.
    - `time_residual`: `max_t |y' - f(t, y)| / max_t |y'|` of the reconstructed
      orbit on a grid four times finer: the truncation error estimate.
    - `iterations`: Newton iterations taken.
    - `code`: a `rotorjax.solve.RESULTS` index: `successful`, or
      `root_not_converged` (Newton did not reach its tolerance), `nonfinite`.
    - `floquet`: the `FloquetResult` along the orbit (None when not asked for).
    - `autonomous`, `phase`: a limit cycle of an autonomous scene (its period
      solved for), and the state whose first-harmonic sine part its phase
      condition holds at 0.
    """

    coefficients: jax.Array
    period: jax.Array
    t0: jax.Array
    residual: jax.Array
    step: jax.Array
    time_residual: jax.Array
    iterations: jax.Array
    code: jax.Array
    floquet: FloquetResult | None = None
    autonomous: bool = eqx.field(static=True, default=False)
    phase: int | None = eqx.field(static=True, default=None)

    @property
    def harmonics(self) -> int:
        return (self.coefficients.shape[-2] - 1) // 2

    def _checked_floquet(self, what):
        if self.floquet is None:
            raise InputError(f"{what}: this solution was computed with stability=False")
        return self.floquet

    @property
    def trivial_multiplier(self):
        """An autonomous cycle's multiplier along the orbit (the one nearest 1): it
        is exactly 1, so its distance from 1 is the Floquet computation's accuracy
        check."""
        mu = self._checked_floquet("trivial_multiplier").multipliers
        return mu[jnp.argmin(jnp.abs(mu - 1.0))]

    @property
    def margin(self):
        """The largest Floquet exponent `log|mu| / T` (1/time unit), an autonomous
        cycle's trivial multiplier left out (< 0: stable)."""
        fq = self._checked_floquet("margin")
        if not self.autonomous:
            return fq.margin
        mu = fq.multipliers
        others = jnp.where(jnp.arange(mu.shape[0]) == jnp.argmin(jnp.abs(mu - 1.0)), 0.0, jnp.abs(mu))
        return jnp.log(jnp.max(others)) / self.period

    @property
    def stable(self):
        """Floquet stability: every multiplier inside the unit circle (an
        autonomous cycle's trivial one left out)."""
        return self.margin < 0

    def state(self, t):
        """The state at time(s) `t`: shape `t.shape + (n,)`."""
        t = jnp.asarray(t, dtype=jnp.float64)
        phase = 2 * jnp.pi * (t - self.t0) / self.period
        return _basis_at(phase, self.harmonics) @ self.coefficients

    def initial_state(self):
        """`y(t0)`: the state to start a time integration on the orbit from."""
        return self.state(self.t0)

    def amplitude(self, rows):
        """Largest radius `max_t sqrt(y_i^2 + y_j^2)` of the orbit of the state pair
        `rows = (i, j)` (a node's x and y), on a grid of `16 (2H + 1)` instants."""
        return orbit_amplitude(None, self.coefficients, self.period, self.t0, rows=rows)


def forcing_period(scene, subharmonic=1):
    """The period of a forced motion of `scene`: `subharmonic` times `2 pi / speed`
    (the unbalance's, at the scene's constant speed, in its time unit)."""
    k = as_count("subharmonic", subharmonic, minimum=1)
    if not isinstance(scene.speed, ConstantSpeed):
        raise InputError(f"a forced periodic motion needs a constant speed; {scene.describe()} runs at a "
                         f"{type(scene.speed).__name__}")
    return k * 2 * jnp.pi / scene.speed.constant


def orbit_amplitude(scene, coefficients, period, t0=0.0, node=None, n_points=None, rows=None):
    """The amplitude of a periodic motion (coefficients `(2H + 1, n)` as in
    `PeriodicSolution`): the largest radius over the period of the orbit of `node`
    (the scene's outputs `node_x`, `node_y`: a shaft node, in the scene's length
    unit), or of the state pair `rows = (i, j)`, or, with neither, the largest of
    the scene's output `whirl_amplitude`. Sampled at `n_points` instants (default
    `16 (2H + 1)`). Traceable in the coefficients and the period; vmap over a
    branch's points."""
    Y = jnp.asarray(coefficients, dtype=jnp.float64)
    H = (Y.shape[-2] - 1) // 2
    m = n_points or 16 * (2 * H + 1)
    phase = 2 * jnp.pi * jnp.arange(m) / m
    ys = _basis_at(phase, H) @ Y
    if rows is not None:
        i, j = rows
        return jnp.sqrt(jnp.max(ys[:, i] ** 2 + ys[:, j] ** 2))
    ts = t0 + period * jnp.arange(m) / m
    probe = scene.outputs(ts[0], ys[0])
    if node is None:
        if "whirl_amplitude" not in probe:
            raise InputError(f"{scene.describe()}: no output 'whirl_amplitude'; name a node")
        return jnp.max(jax.vmap(lambda t, y: scene.outputs(t, y)["whirl_amplitude"])(ts, ys))
    if "node_x" not in probe or "node_y" not in probe:
        raise InputError(f"node {node}: {scene.describe()} has no nodes (no outputs 'node_x', 'node_y')")
    n_nodes = int(jnp.shape(probe["node_x"])[0])
    if isinstance(node, bool) or not isinstance(node, (int, np.integer)) or not 0 <= node < n_nodes:
        raise InputError(f"node {node!r}: the scene's nodes are 0..{n_nodes - 1}")

    def radius2(t, y):
        out = scene.outputs(t, y)
        return out["node_x"][node] ** 2 + out["node_y"][node] ** 2

    return jnp.sqrt(jnp.max(jax.vmap(radius2)(ts, ys)))


def _basis_at(phase, H):
    """`[1, cos(phase), sin(phase), ..., cos(H phase), sin(H phase)]` along a new
    last axis."""
    k = jnp.arange(1, H + 1, dtype=jnp.float64).reshape((1,) * phase.ndim + (H,))
    kp = phase[..., None] * k
    cs = jnp.stack([jnp.cos(kp), jnp.sin(kp)], axis=-1).reshape(*phase.shape, 2 * H)
    return jnp.concatenate([jnp.ones(phase.shape + (1,)), cs], axis=-1)


def _collocation(H, N):
    """`B` (N, 2H+1): the series at the N instants; `P` (2H+1, N): the projection
    back (exact for N > 2H: `P B = I`)."""
    phase = 2 * np.pi * np.arange(N) / N
    k = np.arange(1, H + 1)
    B = np.ones((N, 2 * H + 1))
    B[:, 1::2] = np.cos(np.outer(phase, k))
    B[:, 2::2] = np.sin(np.outer(phase, k))
    weights = np.full(2 * H + 1, 2.0 / N)
    weights[0] = 1.0 / N
    return jnp.asarray(B), jnp.asarray(weights[:, None] * B.T)


def _derivative(Y, omega):
    """Coefficients of `y'` from those of `y`."""
    H = (Y.shape[0] - 1) // 2
    kw = (omega * jnp.arange(1, H + 1, dtype=jnp.float64))[:, None]
    a, b = Y[1::2], Y[2::2]
    d = jnp.stack([kw * b, -kw * a], axis=1).reshape(2 * H, -1)
    return jnp.concatenate([jnp.zeros_like(Y[:1]), d], axis=0)


def balance_residual(scene, Y, period, t0=0.0, n_samples=None, args=None):
    """`R(Y) = D(w) Y - P f(t_j, B Y)` (shape of `Y`): the harmonic-balance residual
    of `scene`'s vector field for the coefficients `Y` (`(2H + 1, n)`)."""
    H = (Y.shape[0] - 1) // 2
    N = _samples(H, n_samples)
    B, P = _collocation(H, N)
    ts = t0 + period * jnp.arange(N) / N
    fs = jax.vmap(lambda t, y: scene.vector_field(t, y, args))(ts, B @ Y)
    return _derivative(Y, 2 * jnp.pi / period) - P @ fs


def _time_residual(scene, Y, period, t0, args):
    """`max_t |y' - f(t, y)| / max_t |y'|` on `4 N` instants."""
    H = (Y.shape[0] - 1) // 2
    M = 4 * _samples(H, None)
    B, _ = _collocation(H, M)
    ts = t0 + period * jnp.arange(M) / M
    ys, yds = B @ Y, B @ _derivative(Y, 2 * jnp.pi / period)
    fs = jax.vmap(lambda t, y: scene.vector_field(t, y, args))(ts, ys)
    return jnp.max(jnp.abs(yds - fs)) / jnp.maximum(jnp.max(jnp.abs(yds)), jnp.finfo(jnp.float64).tiny)


def _samples(H, n_samples):
    """Default `N`: the smallest power of two above `4 (H + 1)` (a cubic term's
    harmonics up to `3H` fold back only above harmonic `H`)."""
    if n_samples is not None:
        return n_samples
    return int(2 ** np.ceil(np.log2(4 * (H + 1))))


def _guess_coefficients(guess, H, n):
    """Coefficients `(2H + 1, n)` from a guess: a constant state `(n,)`, a
    coefficient array with any number of harmonics, or a `PeriodicSolution`."""
    if isinstance(guess, PeriodicSolution):
        guess = guess.coefficients
    g = jnp.asarray(guess, dtype=jnp.float64)
    if g.shape == (n,):
        return jnp.zeros((2 * H + 1, n)).at[0].set(g)
    if g.ndim != 2 or g.shape[1] != n or g.shape[0] % 2 != 1:
        raise InputError(f"guess must be a state of shape ({n},), coefficients of shape (2H + 1, {n}) or a "
                         f"PeriodicSolution, got shape {g.shape}")
    m = min(g.shape[0], 2 * H + 1)
    return jnp.zeros((2 * H + 1, n)).at[:m].set(g[:m])


def harmonic_balance(scene, period, guess, harmonics=8, *, t0=0.0, n_samples=None, tol=1e-10, max_iter=30,
                     stability=True, args=None, rtol=1e-10, atol=1e-12) -> PeriodicSolution:
    """The periodic motion of `scene` with period `period` (that of its forcing,
    `2 pi / speed` for an unbalance, or `k` times it for a subharmonic) near `guess`,
    by harmonic balance with `harmonics` harmonics (see the module docstring).

    **Arguments:**
    - `guess`: a state `(n,)` (the series starts constant there), coefficients
      `(2H' + 1, n)` (padded or truncated to `harmonics`), or a `PeriodicSolution`
      (for continuation, or to raise the harmonics).
    - `n_samples`: the instants per period of the frequency-time evaluation
      (default: the smallest power of two above `4 (harmonics + 1)`; must exceed
      `2 harmonics`).
    - `tol`: Newton stops when its step is below `tol` times max |Y| (and the
      residual is finite); `max_iter` bounds it (`root_not_converged` past it).
    - `stability`: also the Floquet multipliers along the reconstructed orbit
      (integrated at `rtol`, `atol`).

    Traceable in the scene's parameters and the period (`stability=False` to vmap
    over a grid without integrating); the harmonics and samples are sizes.
    """
    check_type("scene", scene, AbstractScene, "a scene (an AbstractScene: Scene, RotorScene, ...)")
    H = as_count("harmonics", harmonics, minimum=1)
    if n_samples is not None:
        n_samples = as_count("n_samples", n_samples, minimum=2 * H + 1)
    max_iter = as_count("max_iter", max_iter, minimum=1)
    period = as_param("period", period, sign="positive", shape=())
    t0 = as_param("t0", t0, shape=())
    if is_concrete(tol):
        as_param("tol", tol, sign="positive", shape=())
    n = scene.state_size
    Y0 = _guess_coefficients(guess, H, n)
    sol = _solve(scene, Y0, period, t0, n_samples, tol, max_iter, args)
    if stability:
        fq = floquet(scene, sol.initial_state(), period, t0, rtol=rtol, atol=atol)
        sol = eqx.tree_at(lambda s: s.floquet, sol, fq, is_leaf=lambda x: x is None)
    return sol


def _newton(residual, x0, tol, max_iter):
    """Newton's method with the exact Jacobian (forward mode), in one compiled
    loop, differentiable by the implicit function theorem (`lax.custom_root`: the
    derivative of the root with respect to anything `residual` closes over is
    `-R_x^{-1} R_theta`, one linear solve, not the iterations unrolled). Returns
    `(x, (step, iterations))`, `step` the last relative step."""

    def solve(f, x):
        def body(state):
            x, _, it = state
            r, jvp = jax.linearize(f, x)
            J = jax.vmap(jvp, in_axes=1, out_axes=1)(jnp.eye(x.shape[0]))
            dx = jnp.linalg.solve(J, r)
            x = x - dx
            step = jnp.max(jnp.abs(dx)) / jnp.maximum(jnp.max(jnp.abs(x)), jnp.finfo(jnp.float64).tiny)
            return x, step, it + 1

        def cond(state):
            _, step, it = state
            return (it < max_iter) & ~(step <= tol)

        x, step, it = jax.lax.while_loop(cond, body, (x, jnp.asarray(jnp.inf), 0))
        return x, (step, it.astype(jnp.float64))   # float aux: custom_root differentiates through it

    def tangent_solve(g, y):
        return jnp.linalg.solve(jax.jacfwd(g)(y), y)

    return jax.lax.custom_root(residual, x0, solve, tangent_solve, has_aux=True)


@eqx.filter_jit
def _solve(scene, Y0, period, t0, n_samples, tol, max_iter, args) -> PeriodicSolution:
    """One compiled Newton per scene structure and size (a new speed or guess
    reuses it)."""
    shape = Y0.shape

    def residual(x):
        return balance_residual(scene, x.reshape(shape), period, t0, n_samples, args).ravel()

    x, (step, it) = _newton(residual, Y0.ravel(), tol, max_iter)
    step, it = jax.lax.stop_gradient(step), jax.lax.stop_gradient(it).astype(jnp.int32)
    return _outcome(scene, x.reshape(shape), period, t0, jnp.max(jnp.abs(residual(x))), step, it, tol, args)


#: an autonomous "cycle" whose harmonics fell below this fraction of its guess's is an equilibrium
COLLAPSE_TOL = 1e-9


def _outcome(scene, Y, period, t0, r, step, it, tol, args, guess=None, phase=None) -> PeriodicSolution:
    """The solution with its code: `nonfinite`, `root_not_converged` (Newton's
    step above `tol`, or an autonomous cycle, `guess` its starting coefficients,
    collapsed onto an equilibrium: its harmonics vanish and its period is
    arbitrary), else `successful`."""
    autonomous = guess is not None
    finite = jnp.all(jnp.isfinite(Y)) & jnp.isfinite(r) & jnp.isfinite(period)
    converged = step <= tol
    if autonomous:
        converged &= jnp.max(jnp.abs(Y[1:])) > COLLAPSE_TOL * jnp.max(jnp.abs(guess[1:]))
    code = jnp.where(~finite, code_of(RESULTS.nonfinite),
                     jnp.where(converged, code_of(RESULTS.successful), code_of(RESULTS.root_not_converged)))
    return PeriodicSolution(coefficients=Y, period=period, t0=t0, residual=r, step=step,
                            time_residual=_time_residual(scene, Y, period, t0, args), iterations=it,
                            code=jnp.asarray(code, dtype=jnp.int32), autonomous=autonomous, phase=phase)


def _phase_state(Y, phase, guess=None):
    """The state whose first-harmonic sine coefficient the phase condition fixes at
    0: `phase`, else a guessed cycle's, else the one with the largest first-harmonic
    cosine part in `Y` (the nearest to holding it already)."""
    if phase is not None:
        return as_count("phase", phase, minimum=0)
    if isinstance(guess, PeriodicSolution) and guess.phase is not None:
        return guess.phase
    if not is_concrete(Y):
        raise InputError("phase: name the state of the phase condition when the guess is traced")
    return int(np.argmax(np.abs(np.asarray(Y[1]))))


def limit_cycle(scene, period, guess, harmonics=8, *, phase=None, t0=0.0, n_samples=None, tol=1e-10,
                max_iter=30, stability=True, args=None, rtol=1e-10, atol=1e-12) -> PeriodicSolution:
    """A limit cycle of an autonomous scene (a field that does not depend on
    time: a rotor at constant speed with no unbalance, self-excited by internal
    friction or a fluid film), its period unknown, by harmonic balance.

    The unknowns are the coefficients and the frequency `w = 2 pi / T`; the phase
    condition `b_1 = 0` of the state `phase` (the sine part of its first harmonic:
    the time origin at its first harmonic's maximum) closes the system. `period`
    is the guess of `T`; `guess` as in `harmonic_balance` (with harmonics: a
    constant state is a rest point, from which Newton cannot leave). Start from a
    Hopf point (`hopf_cycle`) or from a time simulation (`coefficients_from_samples`).
    `phase` defaults to the guess's own (a `PeriodicSolution`'s), else the state
    with the largest first-harmonic cosine part in the guess.

    Returns a `PeriodicSolution` with `autonomous=True`: its Floquet analysis has
    the trivial multiplier 1 (`trivial_multiplier`, the accuracy check) left out
    of `margin` and `stable`."""
    check_type("scene", scene, AbstractScene, "a scene (an AbstractScene: Scene, RotorScene, ...)")
    H = as_count("harmonics", harmonics, minimum=1)
    if n_samples is not None:
        n_samples = as_count("n_samples", n_samples, minimum=2 * H + 1)
    max_iter = as_count("max_iter", max_iter, minimum=1)
    period = as_param("period", period, sign="positive", shape=())
    t0 = as_param("t0", t0, shape=())
    n = scene.state_size
    Y0 = _guess_coefficients(guess, H, n)
    k = _phase_state(Y0, phase, guess)
    if k >= n:
        raise InputError(f"phase = {k}: the scene has {n} states")
    sol = _solve_cycle(scene, _aligned(Y0, k), period, t0, n_samples, tol, max_iter, args, k)
    if stability:
        fq = floquet(scene, sol.initial_state(), sol.period, t0, rtol=rtol, atol=atol)
        sol = eqx.tree_at(lambda s: s.floquet, sol, fq, is_leaf=lambda x: x is None)
    return sol


def _aligned(Y, k):
    """The coefficients of the same motion shifted in time so that state `k`'s
    first harmonic is a pure cosine (the phase condition holds at the guess:
    Newton need not find the time shift, which it does poorly when it is large)."""
    H = (Y.shape[0] - 1) // 2
    theta = jnp.arctan2(Y[2, k], Y[1, k])
    j = jnp.arange(1, H + 1, dtype=jnp.float64)[:, None]
    c, s = jnp.cos(j * theta), jnp.sin(j * theta)
    a, b = Y[1::2], Y[2::2]
    ab = jnp.stack([a * c + b * s, -a * s + b * c], axis=1).reshape(2 * H, -1)
    return jnp.concatenate([Y[:1], ab], axis=0)


@eqx.filter_jit
def _solve_cycle(scene, Y0, period, t0, n_samples, tol, max_iter, args, k) -> PeriodicSolution:
    shape, m = Y0.shape, Y0.size

    def residual(x):
        Y = x[:m].reshape(shape)
        r = balance_residual(scene, Y, 2 * jnp.pi / x[m], t0, n_samples, args).ravel()
        return jnp.concatenate([r, Y[2, k][None]])

    x0 = jnp.concatenate([Y0.ravel(), (2 * jnp.pi / period)[None]])
    x, (step, it) = _newton(residual, x0, tol, max_iter)
    step, it = jax.lax.stop_gradient(step), jax.lax.stop_gradient(it).astype(jnp.int32)
    return _outcome(scene, x[:m].reshape(shape), 2 * jnp.pi / x[m], t0, jnp.max(jnp.abs(residual(x))), step,
                    it, tol, args, guess=Y0, phase=k)


def coefficients_from_samples(ys, harmonics):
    """Fourier coefficients `(2H + 1, n)` (the layout of `PeriodicSolution`) of a
    motion sampled at `N > 2H` equally spaced instants over one period (`ys`:
    `(N, n)`, the last instant one step before the period closes): a time
    simulation's last period as the guess of `limit_cycle` or `harmonic_balance`."""
    ys = jnp.asarray(ys, dtype=jnp.float64)
    H = as_count("harmonics", harmonics, minimum=1)
    if ys.ndim != 2 or ys.shape[0] <= 2 * H:
        raise InputError(f"ys must be (N, n) samples with N > 2 harmonics = {2 * H}, got shape {ys.shape}")
    _, P = _collocation(H, ys.shape[0])
    return P @ ys


def hopf_cycle(scene_at, p, y_eq, amplitude, harmonics=8, *, frequency=None, tol=1e-10, max_iter=30,
               stability=True, args=None):
    """Onto the branch of limit cycles born at a Hopf point of an equilibrium:
    the cycle whose first harmonic has amplitude `amplitude` (in the state `k`
    where the critical eigenvector is largest), and the parameter where it lives.

    `scene_at(p)`: the autonomous scene at `p`; `p`, `y_eq`: the Hopf point and
    the equilibrium there (e.g. a `"hopf"` event of `continue_branch`);
    `frequency`: the crossing pair's `|Im lambda|` (default: the eigenvalue pair
    of the Jacobian at `y_eq` nearest the imaginary axis). The guess is the
    equilibrium plus the critical eigenvector at `amplitude`; Newton solves the
    balance for the coefficients, the frequency and the parameter, with the first
    harmonic's cosine part of state `k` fixed at `amplitude` and its sine part at
    0. Small amplitudes follow the Hopf normal form (the parameter moves as
    `amplitude^2`); its side gives the bifurcation's criticality.

    Returns `(p, solution)`: the parameter and the `PeriodicSolution` (autonomous)
    there; continue it with `limit_cycle_branch`."""
    H = as_count("harmonics", harmonics, minimum=1)
    p = as_param("p", p, shape=())
    amplitude = as_param("amplitude", amplitude, sign="positive", shape=())
    y_eq = jnp.asarray(y_eq, dtype=jnp.float64)
    scene = scene_at(p)
    n = scene.state_size
    if y_eq.shape != (n,):
        raise InputError(f"y_eq must be a state of shape ({n},), got {y_eq.shape}")
    J = jax.jacfwd(lambda y: scene.vector_field(0.0, y, args))(y_eq)
    lam, vecs = jnp.linalg.eig(J)
    cand = jnp.where(jnp.imag(lam) > 0, jnp.abs(jnp.real(lam)), jnp.inf)
    j = jnp.argmin(cand) if frequency is None else jnp.argmin(jnp.abs(lam - 1j * frequency))
    w0, v = jnp.abs(jnp.imag(lam[j])), vecs[:, j]
    k = int(jnp.argmax(jnp.abs(v)))
    v = v * jnp.conj(v[k]) / jnp.abs(v[k]) ** 2        # v[k] = 1: the cosine part of state k
    Y0 = jnp.zeros((2 * H + 1, n)).at[0].set(y_eq).at[1].set(amplitude * jnp.real(v)).at[2].set(
        -amplitude * jnp.imag(v))
    shape, m = Y0.shape, Y0.size

    def residual(x):
        Y = x[:m].reshape(shape)
        r = balance_residual(scene_at(x[m + 1]), Y, 2 * jnp.pi / x[m], 0.0, None, args).ravel()
        return jnp.concatenate([r, jnp.stack([Y[2, k], Y[1, k] - amplitude])])

    x0 = jnp.concatenate([Y0.ravel(), jnp.stack([w0, p])])
    x, (step, it) = _newton(residual, x0, tol, max_iter)
    step, it = jax.lax.stop_gradient(step), jax.lax.stop_gradient(it).astype(jnp.int32)
    pc = x[m + 1]
    sc = scene_at(pc)
    sol = _outcome(sc, x[:m].reshape(shape), 2 * jnp.pi / x[m], jnp.asarray(0.0), jnp.max(jnp.abs(residual(x))),
                   step, it, tol, args, guess=Y0, phase=k)
    if int(sol.code) != 0:
        raise NumericalError(f"hopf_cycle: no limit cycle of amplitude {float(amplitude):g} near the Hopf point "
                             f"p = {float(p):g} ({RESULTS[sol.result]}); try a smaller amplitude")
    if stability:
        fq = floquet(sc, sol.initial_state(), sol.period, 0.0)
        sol = eqx.tree_at(lambda s: s.floquet, sol, fq, is_leaf=lambda x: x is None)
    return pc, sol


#: the methods of `periodic_orbit`
METHODS = ("harmonic-balance", "shooting")


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
    fq = floquet(scene, y0, T, t0, rtol=rtol, atol=atol)
    return eqx.tree_at(lambda s: s.floquet, sol, fq, is_leaf=lambda x: x is None)


#: Hill's exponents within this fraction of `w / 2` of `-w / 2` are the copies of those at `+w / 2`
HALF_FREQUENCY_TOL = 1e-6


def _physical_exponents(jac, n, omega):
    """Hill's method: of the eigenvalues of the balance's linearisation `jac` (the
    exponents `s + i k w` of every retained harmonic `k`, and spurious ones from
    the truncation at the highest harmonics), the `n` with the smallest `|Im s|`:
    the representatives in `(-w/2, w/2]`, one per Floquet exponent. An exponent
    with `Im s = w/2` (a negative real multiplier) has two such copies, `s` and
    its conjugate at `-w/2`: the one at `-w/2` goes to the back, or a pair of
    multipliers on the negative axis would count one of them twice."""
    lam = jnp.linalg.eigvals(jac)
    im = jnp.imag(lam)
    key = jnp.abs(im) + jnp.where(im < -(0.5 - HALF_FREQUENCY_TOL) * omega, omega, 0.0)
    return lam[jnp.argsort(key)[:n]]


def hill_exponents(scene, solution, args=None):
    """Floquet exponents of a `PeriodicSolution` by Hill's method (the
    linearisation of the harmonic balance, no time integration): `n` complex
    exponents `s`, the multipliers being `exp(s T)`; their largest real part is the
    margin (< 0: stable). Agrees with `solution.floquet` as the harmonics converge."""
    check_type("solution", solution, PeriodicSolution, "a PeriodicSolution (from harmonic_balance)")
    Y = solution.coefficients
    n = Y.shape[1]

    def minus_residual(x):
        return -balance_residual(scene, x.reshape(Y.shape), solution.period, solution.t0, None, args).ravel()

    jac = jax.jacfwd(minus_residual)(Y.ravel())
    return _physical_exponents(jac, n, 2 * jnp.pi / solution.period)


def periodic_branch(scene_at, p0, guess, p_bounds, harmonics=8, *, period_at=None, subharmonic=1, scale=None,
                    name="p", ds=None, ds_max=None, max_points=300, tol=1e-11, gtol=1e-6, direction=None,
                    progress=False, method="harmonic-balance", steps=256):
    """A branch of periodic forced motions `Y(p)` by harmonic balance and
    pseudo-arclength continuation (`continue_branch`) in a parameter `p`, through
    folds.

    **Arguments:**
    - `scene_at(p)`: the scene at `p` (traceable in `p`).
    - `p0`, `guess`: the start (`guess` as in `harmonic_balance`: solved there first).
    - `p_bounds`: `(lo, hi)`; `harmonics`: `H`.
    - `period_at(p)`: the motion's period at `p` (default `forcing_period(scene_at(p),
      subharmonic)`: `subharmonic` times `2 pi / speed`).
    - `scale`: one length per state (default: each state's largest coefficient
      over a survey of the range, `SURVEY` points solved from the start's motion
      in one compiled batch, and at least 1e-3 of the largest of all). The
      unknowns are the coefficients over `scale`, times the range's length `L =
      hi - lo`, so that the arclength weighs a motion's growth from nothing to its
      largest and a walk across the range alike; time is scaled by the start's
      `2 pi / period`.
    - `ds`, `ds_max`: the first and the largest arclength step (default `L / 100`,
      `L / 10`).
    - `tol`, `gtol`: a point is accepted when Newton's last step is below `tol`
      (relative) and the scaled balance residual below `gtol` (its round-off floor
      grows with the stiffness: an FE rotor's highest modes).
    - `method`: `"harmonic-balance"`, or `"shooting"`: the unknowns are the state at
      the period's start and the equations its closure after one period, integrated
      in `steps` fixed steps of Dopri8 (exact derivatives of the discrete map; its
      truncation error is the user's to check, e.g. against harmonic balance);
      stability from the multipliers `eig(dF/du + I)` (the monodromy), exponents
      `log(mu) / T`; `coefficients` then `harmonics` harmonics of each orbit's
      samples.

    Returns `(branch, coefficients)`: the `Branch` (`p`; `margin` the largest real
    part of Hill's exponents in 1/s, see `hill_exponents`, and `stable` where it is
    negative; `u` the scaled unknowns) and the coefficients `(points, 2H + 1, n)`
    in physical units. `branch.events` (`u`: the coefficients there, flattened,
    physical units): `"fold"` (refined: Newton on the balance
    and `det dR/dY = 0`), `"branch_point"` (located to the step), and where a
    complex pair of Hill's exponents crosses, refined by bisection along the
    branch, `"period-doubling"` (its frequency half the motion's: a multiplier
    through -1) or `"neimark-sacker"` (a pair of multipliers `exp(+-i 2 pi f / w)`
    through the unit circle; `frequency` the exponent's `f` in (0, w/2), rad per
    time unit)."""
    if period_at is None:
        def period_at(p):
            return forcing_period(scene_at(p), subharmonic)
    try:
        lo, hi = p_bounds
    except (TypeError, ValueError):
        raise InputError(f"p_bounds must be a pair (lo, hi), got {p_bounds!r}") from None
    p0 = float(as_param("p0", p0, shape=()))
    if not (lo <= p0 <= hi):
        raise InputError(f"p0 = {p0} must lie in p_bounds = ({lo}, {hi})")
    if method not in METHODS:
        raise InputError(f"method {method!r}: one of {', '.join(map(repr, METHODS))}")
    L = _span(lo, hi, p0)
    options = dict(ds=L / 100 if ds is None else ds, ds_max=L / 10 if ds_max is None else ds_max,
                   max_points=max_points, tol=tol, direction=direction, name=name, progress=progress,
                   start_tol=gtol * L, gtol=gtol * L)
    if method == "shooting":
        return _shooting_branch(scene_at, p0, guess, (lo, hi), as_count("harmonics", harmonics, minimum=1),
                                period_at, scale, as_count("steps", steps, minimum=1), L, options)
    start = harmonic_balance(scene_at(p0), period_at(p0), guess, harmonics, stability=False)
    if int(start.code) != 0:
        raise NumericalError(f"periodic_branch: no periodic motion at {name} = {p0} from the guess "
                             f"({RESULTS[start.result]})")
    Y0 = start.coefficients
    shape = Y0.shape
    if scale is None:
        scale = _survey_scale(scene_at, period_at, Y0, lo, hi)
    scale = jnp.broadcast_to(jnp.asarray(scale, dtype=jnp.float64), (shape[1],))[None, :] / L
    w0 = float(2 * np.pi / period_at(p0))

    def F(u, p):   # a similarity transform (times L): Hill's exponents divided by w0
        Y = u.reshape(shape) * scale
        return -(balance_residual(scene_at(p), Y, period_at(p)) / (scale * w0)).ravel()

    br = continue_branch(F, np.asarray(Y0 / scale).ravel(), p0, p_bounds=(lo, hi), **options,
                         exponents=lambda J, u, p: _physical_exponents(jnp.asarray(J), shape[1],
                                                                       2 * np.pi / (w0 * period_at(p))))
    events = tuple(_physical(e, scale, w0, period_at) for e in br.events)
    br = dataclasses.replace(br, margin=br.margin * w0, events=events)
    coefficients = np.asarray(br.u).reshape((-1,) + shape) * np.asarray(scale)
    return br, coefficients


def limit_cycle_branch(scene_at, p0, start, p_bounds, *, phase=None, scale=None, name="p", ds=0.01, ds_max=0.2,
                       max_points=300, tol=1e-11, gtol=1e-6, direction=None, progress=False):
    """A branch of limit cycles of autonomous scenes `scene_at(p)` (their period
    unknown) by harmonic balance and pseudo-arclength continuation in `p`, through
    folds: the unknowns are the coefficients and the frequency, closed by the phase
    condition of `limit_cycle`.

    `start`: a `PeriodicSolution` of `scene_at(p0)` (from `limit_cycle` or
    `hopf_cycle`; its harmonics are the branch's). `scale`, `tol`, `gtol` and the
    rest as in `periodic_branch`.

    Returns `(branch, coefficients, periods)`: the `Branch` (`margin` the largest
    real part of Hill's exponents with the trivial one, nearest 0, left out;
    events folds, branch points, period doublings and Neimark-Sacker points as in
    `periodic_branch`), the coefficients `(points, 2H + 1, n)` and the periods."""
    check_type("start", start, PeriodicSolution, "a PeriodicSolution (from limit_cycle or hopf_cycle)")
    try:
        lo, hi = p_bounds
    except (TypeError, ValueError):
        raise InputError(f"p_bounds must be a pair (lo, hi), got {p_bounds!r}") from None
    p0 = float(as_param("p0", p0, shape=()))
    if not (lo <= p0 <= hi):
        raise InputError(f"p0 = {p0} must lie in p_bounds = ({lo}, {hi})")
    Y0 = start.coefficients
    shape, m = Y0.shape, Y0.size
    k = _phase_state(Y0, phase, start)
    if scale is None:
        top = jnp.max(jnp.abs(Y0), axis=0)
        scale = jnp.maximum(top, 1e-3 * jnp.max(top) + jnp.finfo(jnp.float64).tiny)
    scale = jnp.broadcast_to(jnp.asarray(scale, dtype=jnp.float64), (shape[1],))[None, :]
    w0 = float(2 * np.pi / start.period)

    def F(u, p):
        Y = u[:m].reshape(shape) * scale
        r = -(balance_residual(scene_at(p), Y, 2 * jnp.pi / (w0 * u[m])) / (scale * w0)).ravel()
        return jnp.concatenate([r, (Y[2, k] / scale[0, k])[None]])

    def exponents(J, u, p):
        e = _physical_exponents(jnp.asarray(J)[:m, :m], shape[1], u[m])
        return jnp.delete(e, jnp.argmin(jnp.abs(e)), assume_unique_indices=True)

    u0 = np.concatenate([np.asarray(Y0 / scale).ravel(), [1.0]])
    br = continue_branch(F, u0, p0, p_bounds=(lo, hi), ds=ds, ds_max=ds_max, max_points=max_points, tol=tol,
                         direction=direction, name=name, progress=progress, start_tol=gtol, gtol=gtol,
                         exponents=exponents)
    u = np.asarray(br.u)
    periods = 2 * np.pi / (w0 * u[:, m])
    events = []
    for e in br.events:
        e = dataclasses.replace(e, u=(np.asarray(e.u)[:m].reshape(shape) * np.asarray(scale)).ravel())
        if e.kind == "hopf":
            i = e.between[0]
            e = _secondary(e, w0, 2 * np.pi / periods[i])
        events.append(e)
    br = dataclasses.replace(br, margin=br.margin * w0, events=tuple(events))
    return br, u[:, :m].reshape((-1,) + shape) * np.asarray(scale), periods


def period_doubling_start(scene_at, p, coefficients, amplitude, *, period_at=None, subharmonic=1, tol=1e-10,
                          max_iter=30, stability=True):
    """Onto the branch of period-doubled motions born at a period-doubling point
    of a branch from `periodic_branch` (`p`, and the coefficients there: the
    event's `u` reshaped to `(2H + 1, n)`).

    The critical direction is the eigenvector of Hill's matrix whose exponent's
    frequency is half the motion's (a multiplier -1), made real as the
    perturbation `Re[e^{i w t / 2} z(t)]` and written with `2H` harmonics of the
    doubled period, as is the motion itself. Newton solves the doubled balance for
    the coefficients and the parameter with the component along that direction
    fixed at `amplitude` (the length of its coefficient vector).

    `period_at`, `subharmonic`: the motion's period as in `periodic_branch`.
    Returns `(p, solution)`: continue it with `periodic_branch(...,
    harmonics=2H, subharmonic=2 * subharmonic)` (or `period_at` doubled)."""
    if period_at is None:
        def period_at(v):
            return forcing_period(scene_at(v), subharmonic)
    p = as_param("p", p, shape=())
    amplitude = as_param("amplitude", amplitude, sign="positive", shape=())
    Y = jnp.asarray(coefficients, dtype=jnp.float64)
    scene = scene_at(p)
    n = scene.state_size
    if Y.ndim != 2 or Y.shape[1] != n or Y.shape[0] % 2 != 1:
        raise InputError(f"coefficients must be (2H + 1, {n}), got shape {Y.shape}")
    H = (Y.shape[0] - 1) // 2
    T = period_at(p)
    w = 2 * jnp.pi / T
    jac = jax.jacfwd(lambda x: -balance_residual(scene, x.reshape(Y.shape), T).ravel())(Y.ravel())
    lam, vecs = jnp.linalg.eig(jac)
    j = jnp.argmin(jnp.abs(jnp.real(lam)) + jnp.abs(jnp.abs(jnp.imag(lam)) - 0.5 * w))
    z = vecs[:, j].reshape(Y.shape)
    # the motion and the perturbation sampled over the doubled period
    N2 = 2 * _samples(2 * H, None)
    phase = 2 * jnp.pi * jnp.arange(N2) / N2 * 2            # w t over two periods
    B = _basis_at(phase, H)
    ys = B @ Y
    d = jnp.exp(0.5j * phase)[:, None] * (B @ z)
    d = jnp.where(jnp.linalg.norm(jnp.real(d)) >= jnp.linalg.norm(jnp.imag(d)), jnp.real(d), jnp.imag(d))
    Y2 = coefficients_from_samples(ys, 2 * H)
    D = coefficients_from_samples(d, 2 * H)
    D = D / jnp.linalg.norm(D)
    shape, m = Y2.shape, Y2.size

    def residual(x):
        Yd = x[:m].reshape(shape)
        r = balance_residual(scene_at(x[m]), Yd, 2 * period_at(x[m])).ravel()
        return jnp.concatenate([r, jnp.vdot(D, Yd - Y2)[None] - amplitude])

    x0 = jnp.concatenate([(Y2 + amplitude * D).ravel(), p[None]])
    x, (step, it) = _newton(residual, x0, tol, max_iter)
    step, it = jax.lax.stop_gradient(step), jax.lax.stop_gradient(it).astype(jnp.int32)
    pc = x[m]
    sc = scene_at(pc)
    T2 = 2 * period_at(pc)
    sol = _outcome(sc, x[:m].reshape(shape), T2, jnp.asarray(0.0), jnp.max(jnp.abs(residual(x))), step, it,
                   tol, None)
    if int(sol.code) != 0:
        raise NumericalError(f"period_doubling_start: no doubled motion of amplitude {float(amplitude):g} near "
                             f"p = {float(p):g} ({RESULTS[sol.result]}); try a smaller amplitude")
    if stability:
        fq = floquet(sc, sol.initial_state(), T2, 0.0)
        sol = eqx.tree_at(lambda s: s.floquet, sol, fq, is_leaf=lambda x: x is None)
    return pc, sol


def _start_state(guess, n):
    """A state at the period's start from a guess: a state, coefficients or a
    `PeriodicSolution`."""
    if isinstance(guess, PeriodicSolution):
        return guess.initial_state()
    g = jnp.asarray(guess, dtype=jnp.float64)
    if g.shape == (n,):
        return g
    if g.ndim == 2 and g.shape[1] == n and g.shape[0] % 2 == 1:
        return _basis_at(jnp.zeros(()), (g.shape[0] - 1) // 2) @ g
    raise InputError(f"guess must be a state of shape ({n},), coefficients of shape (2H + 1, {n}) or a "
                     f"PeriodicSolution, got shape {g.shape}")


def _shooting_branch(scene_at, p0, guess, bounds, H, period_at, scale, steps, L, options):
    """`periodic_branch(method="shooting")`: see there."""
    n = scene_at(p0).state_size
    N = _samples(H, None)
    steps = -(-max(steps, N) // N) * N          # a multiple of the samples

    def closure(y, p):
        return flow_samples(scene_at(p), y, period_at(p), steps=steps)[-1] - y

    @jax.jit
    def newton_direction(y):
        g, J = closure(y, p0), jax.jacfwd(closure)(y, p0)
        return jnp.linalg.solve(J, g), jnp.max(jnp.abs(g))

    gap = jax.jit(lambda y: jnp.max(jnp.abs(closure(y, p0))))
    y = _start_state(guess, n)
    for _ in range(40):            # Newton, the step halved until the closure shrinks
        dy, g = newton_direction(y)
        if not float(g) > 1e-12 * max(1.0, float(jnp.max(jnp.abs(y)))):
            break
        step = 1.0
        while step > 1e-3 and not float(gap(y - step * dy)) < float(g):
            step /= 2
        y = y - step * dy
    samples = flow_samples(scene_at(p0), y, period_at(p0), steps=steps, n_samples=N)
    if not bool(jnp.all(jnp.isfinite(samples))) or not float(jnp.max(jnp.abs(samples[-1] - y))) < 1e-8 * max(
            1.0, float(jnp.max(jnp.abs(samples)))):
        raise NumericalError(f"periodic_branch: shooting found no periodic motion at {options['name']} = {p0} from "
                             f"the guess (closure {float(jnp.max(jnp.abs(samples[-1] - y))):.2e})")
    if scale is None:
        top = jnp.max(jnp.abs(samples), axis=0)
        scale = jnp.maximum(top, 1e-3 * jnp.max(top) + jnp.finfo(jnp.float64).tiny)
    scale = jnp.broadcast_to(jnp.asarray(scale, dtype=jnp.float64), (n,)) / L
    w0 = float(2 * np.pi / period_at(p0))

    def F(u, p):
        return closure(u * scale, p) / scale

    def exponents(J, u, p):
        mu = jnp.linalg.eigvals(jnp.asarray(J) + jnp.eye(n))
        return jnp.log(mu.astype(jnp.complex128)) / (period_at(p) * w0)

    br = continue_branch(F, np.asarray(y / scale), p0, p_bounds=bounds, exponents=exponents, **options)
    events = []
    for e in br.events:
        e = dataclasses.replace(e, u=np.asarray(e.u) * np.asarray(scale))
        if e.kind == "hopf":
            e = _secondary(e, w0, float(2 * np.pi / period_at(e.p)))
        events.append(e)
    br = dataclasses.replace(br, margin=br.margin * w0, events=tuple(events))

    @jax.jit
    @jax.vmap
    def series(u, p):
        ys = flow_samples(scene_at(p), u, period_at(p), steps=steps, n_samples=N)
        return coefficients_from_samples(jnp.roll(ys, 1, axis=0), H)

    ys0 = np.asarray(br.u) * np.asarray(scale)
    coefficients = np.asarray(series(jnp.asarray(ys0), jnp.asarray(br.p)))
    ev = [dataclasses.replace(e, u=np.asarray(series(jnp.asarray(e.u)[None], jnp.asarray([e.p]))[0]).ravel())
          for e in events]
    return dataclasses.replace(br, events=tuple(ev)), coefficients


def _balance_in_two(scene_at2, Y0, period_at2, scale, w0):
    """`F(u, p1, p2)`: the balance of `scene_at2(p1, p2)`, scaled as in
    `periodic_branch` (u the coefficients over `scale`, Hill's exponents over w0)."""
    shape = Y0.shape

    def F(u, p1, p2):
        Y = u.reshape(shape) * scale
        return -(balance_residual(scene_at2(p1, p2), Y, period_at2(p1, p2)) / (scale * w0)).ravel()

    return F


def _two_parameter_setup(scene_at2, p, coefficients, period_at2, subharmonic):
    if period_at2 is None:
        def period_at2(a, b):
            return forcing_period(scene_at2(a, b), subharmonic)
    Y0 = jnp.asarray(coefficients, dtype=jnp.float64)
    top = jnp.max(jnp.abs(Y0), axis=0)
    scale = jnp.maximum(top, 1e-3 * jnp.max(top) + jnp.finfo(jnp.float64).tiny)[None, :]
    w0 = float(2 * np.pi / period_at2(*p))
    return _balance_in_two(scene_at2, Y0, period_at2, scale, w0), np.asarray(Y0 / scale).ravel(), scale


def periodic_fold_curve(scene_at2, p, coefficients, *, period_at2=None, subharmonic=1, bounds=None, ds=0.01,
                        ds_max=0.2, max_points=200, tol=1e-11, direction=None, names=("p1", "p2")):
    """Two-parameter continuation of a fold of periodic motions (the jump's
    boundary, e.g. in speed and cubic stiffness): the curve of `(p1, p2)` where the
    harmonic balance of `scene_at2(p1, p2)` folds, from a fold at `p = (p1, p2)`
    with its `coefficients` `(2H + 1, n)` (a `"fold"` event of `periodic_branch`
    with `p2` fixed: its `u` reshaped). `fold_curve` on the scaled balance; both
    ways from the start unless `direction`; `bounds` `((lo1, lo2), (hi1, hi2))`.
    Returns its `Curve` (rows `(u, p1, p2)`, the coefficients scaled)."""
    F, u0, _ = _two_parameter_setup(scene_at2, p, coefficients, period_at2, subharmonic)
    if bounds is not None:
        lo, hi = (np.asarray(b, dtype=float) for b in bounds)
        n = u0.size
        bounds = (np.concatenate([np.full(n, np.nan), lo]), np.concatenate([np.full(n, np.nan), hi]))
    return fold_curve(F, u0, p, ds=ds, ds_max=ds_max, max_points=max_points, tol=tol, bounds=bounds,
                      direction=direction, names=names)


def periodic_fold_gradient(scene_at2, p, coefficients, *, period_at2=None, subharmonic=1):
    """`dp1*/dp2`: how the fold of periodic motions at `p = (p1, p2)` (with its
    `coefficients`) moves in `p1` per unit of `p2`, by the implicit function
    theorem on the fold's defining system (`fold_gradient`)."""
    F, u0, _ = _two_parameter_setup(scene_at2, p, coefficients, period_at2, subharmonic)
    return fold_gradient(F, u0, p[0], p[1])


def balance_grid(scene_at2, p1, p2, guess, harmonics=8, *, period_at2=None, subharmonic=1, node=None, rows=None,
                 tol=1e-10, max_iter=30):
    """The periodic motions over a grid: along `p1` by natural continuation (each
    point's Newton starts from the previous point's motion, as a slow sweep: on a
    branch that folds it jumps where a run-up would), across `p2` vmapped, all in
    one compiled program (a `lax.scan` per column, the columns vmapped).

    `scene_at2(a, b)`: the scene at `p1 = a`, `p2 = b`; `guess` as in
    `harmonic_balance` (at `p1[0]`, every `p2`). Returns `(coefficients, code,
    time_residual, amplitude)`, each `(len(p2), len(p1), ...)`: the amplitude as
    `orbit_amplitude` (`node`, `rows`, or the scene's `whirl_amplitude`). Where
    Newton from the previous point fails (past a fold) it starts again from
    `guess`; a point that still does not converge keeps its code, and the next
    starts from the last converged one."""
    if period_at2 is None:
        def period_at2(a, b):
            return forcing_period(scene_at2(a, b), subharmonic)
    H = as_count("harmonics", harmonics, minimum=1)
    p1 = jnp.asarray(p1, dtype=jnp.float64)
    p2 = jnp.asarray(p2, dtype=jnp.float64)
    if p1.ndim != 1 or p2.ndim != 1:
        raise InputError(f"p1 and p2 must be 1-D grids, got shapes {p1.shape} and {p2.shape}")
    n = scene_at2(p1[0], p2[0]).state_size
    Y0 = _guess_coefficients(guess, H, n)

    def column(b):
        def step(Y, a):
            sc = scene_at2(a, b)
            T = period_at2(a, b)
            sol = _solve(sc, Y, T, jnp.asarray(0.0), None, tol, max_iter, None)
            # past a fold the branch swept ends: start again from the guess (the jump)
            sol = jax.lax.cond(sol.code == 0, lambda: sol,
                               lambda: _solve(sc, Y0, T, jnp.asarray(0.0), None, tol, max_iter, None))
            amp = orbit_amplitude(sc, sol.coefficients, T, node=node, rows=rows)
            return jnp.where(sol.code == 0, sol.coefficients, Y), (sol.coefficients, sol.code,
                                                                     sol.time_residual, amp)

        return jax.lax.scan(step, Y0, p1)[1]

    return jax.jit(jax.vmap(column))(p2)


#: parameter values at which `periodic_branch` surveys the motion's size before continuing
SURVEY = 9


def _span(lo, hi, p0):
    """The length `L` of the continued range (`max(|p0|, 1)` when unbounded)."""
    span = float(hi) - float(lo)
    return span if np.isfinite(span) and span > 0 else max(abs(float(p0)), 1.0)


def _survey_scale(scene_at, period_at, Y0, lo, hi):
    """Each state's largest coefficient over the start and the motions solved from
    it at `SURVEY` parameter values across a finite range (one vmapped Newton; the
    ones that do not converge are left out), at least 1e-3 of the largest of all."""
    top = jnp.max(jnp.abs(Y0), axis=0)
    if np.isfinite(lo) and np.isfinite(hi):
        def one(p):
            return _solve(scene_at(p), Y0, period_at(p), jnp.asarray(0.0), None, 1e-10, 30, None)

        sols = jax.jit(jax.vmap(one))(jnp.linspace(lo, hi, SURVEY))
        ok = (sols.code == 0)[:, None]
        top = jnp.maximum(top, jnp.max(jnp.where(ok, jnp.max(jnp.abs(sols.coefficients), axis=1), 0.0), axis=0))
    return jnp.maximum(top, 1e-3 * jnp.max(top) + jnp.finfo(jnp.float64).tiny)


#: a crossing pair whose frequency is within this fraction of `w / 2` is a period doubling
PERIOD_DOUBLING_TOL = 1e-3


def _physical(event, scale, w0, period_at):
    """An event of the scaled continuation in physical units, a crossing pair
    classified."""
    event = dataclasses.replace(event, u=(np.asarray(event.u).reshape((-1,) + scale.shape[1:])
                                          * np.asarray(scale)).ravel())
    if event.kind == "hopf":
        event = _secondary(event, w0, float(2 * np.pi / period_at(event.p)))
    return event


def _secondary(event, w0, w):
    """A crossing of a complex pair of Hill's exponents (continue_branch's "hopf",
    in units of `w0`) as a period doubling or a Neimark-Sacker bifurcation: the
    exponent's frequency reduced to `[0, w/2]` (each exponent recurs shifted by
    every `k w`)."""
    f = float(np.abs(np.mod(event.frequency * w0 + 0.5 * w, w) - 0.5 * w))
    kind = "period-doubling" if abs(f - 0.5 * w) < PERIOD_DOUBLING_TOL * w else "neimark-sacker"
    return dataclasses.replace(event, kind=kind, frequency=f)


def branch_amplitude(scene_at, p, coefficients, node=None, period_at=None, subharmonic=1, truncation=False):
    """`orbit_amplitude` at every point of a branch from `periodic_branch`
    (`p` its parameter values, `coefficients` `(points, 2H + 1, n)`), vmapped; with
    `truncation`, also each point's time-domain residual (`PeriodicSolution`'s
    `time_residual`: the truncation error of the harmonics) as a second array."""
    if period_at is None:
        def period_at(v):
            return forcing_period(scene_at(v), subharmonic)
    orbit_amplitude(scene_at(float(p[0])), coefficients[0], period_at(float(p[0])), node=node)   # checks node

    def one(v, Y):
        sc, T = scene_at(v), period_at(v)
        return orbit_amplitude(sc, Y, T, node=node), _time_residual(sc, Y, T, 0.0, None)

    amp, res = jax.jit(jax.vmap(one))(jnp.asarray(p), jnp.asarray(coefficients))
    return (np.asarray(amp), np.asarray(res)) if truncation else np.asarray(amp)
