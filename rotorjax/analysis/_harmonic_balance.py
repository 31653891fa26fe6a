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
from ..models._validate import InputError, as_count, as_param, check_type, is_concrete
from ..solve._results import RESULTS, AbstractOutcome, code_of
from ._continuation import continue_branch
from ._floquet import FloquetResult, floquet


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

    @property
    def harmonics(self) -> int:
        return (self.coefficients.shape[-2] - 1) // 2

    @property
    def stable(self):
        """Floquet stability (all multipliers inside the unit circle)."""
        if self.floquet is None:
            raise InputError("stable: this solution was computed with stability=False")
        return self.floquet.stable

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
        i, j = rows
        n = 16 * (2 * self.harmonics + 1)
        ys = self.state(self.t0 + self.period * jnp.arange(n) / n)
        return jnp.sqrt(jnp.max(ys[:, i] ** 2 + ys[:, j] ** 2))


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


def _solve(scene, Y0, period, t0, n_samples, tol, max_iter, args) -> PeriodicSolution:
    shape = Y0.shape

    def residual(x):
        return balance_residual(scene, x.reshape(shape), period, t0, n_samples, args).ravel()

    def body(state):
        x, _, _, it = state
        r, jvp = jax.linearize(residual, x)
        J = jax.vmap(jvp, in_axes=1, out_axes=1)(jnp.eye(x.shape[0]))
        dx = jnp.linalg.solve(J, r)
        x = x - dx
        step = jnp.max(jnp.abs(dx)) / jnp.maximum(jnp.max(jnp.abs(x)), jnp.finfo(jnp.float64).tiny)
        return x, step, jnp.max(jnp.abs(r)), it + 1

    def cond(state):
        _, step, _, it = state
        return (it < max_iter) & ~(step <= tol)

    x0 = Y0.ravel()
    x, step, _, it = jax.lax.while_loop(cond, body, (x0, jnp.inf, jnp.inf, 0))
    r = jnp.max(jnp.abs(residual(x)))
    Y = x.reshape(shape)
    finite = jnp.all(jnp.isfinite(x)) & jnp.isfinite(r)
    code = jnp.where(~finite, code_of(RESULTS.nonfinite),
                     jnp.where(step <= tol, code_of(RESULTS.successful), code_of(RESULTS.root_not_converged)))
    return PeriodicSolution(coefficients=Y, period=period, t0=t0, residual=r, step=step,
                            time_residual=_time_residual(scene, Y, period, t0, args), iterations=it,
                            code=jnp.asarray(code, dtype=jnp.int32))


def _physical_exponents(jac, n, omega):
    """Hill's method: of the eigenvalues of the balance's linearisation `jac` (the
    exponents `s + i k w` of every retained harmonic `k`, and spurious ones from
    the truncation at the highest harmonics), the `n` with the smallest `|Im s|`:
    the representatives in `(-w/2, w/2]`, one per Floquet exponent."""
    lam = jnp.linalg.eigvals(jac)
    return lam[jnp.argsort(jnp.abs(jnp.imag(lam)))[:n]]


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


def periodic_branch(scene_at, p0, guess, p_bounds, harmonics=8, *, period_at=None, scale=None, name="p", ds=0.01,
                    ds_max=0.2, max_points=300, tol=1e-11, gtol=1e-6, direction=None, progress=False):
    """A branch of periodic forced motions `Y(p)` by harmonic balance and
    pseudo-arclength continuation (`continue_branch`) in a parameter `p`, through
    folds.

    **Arguments:**
    - `scene_at(p)`: the scene at `p` (traceable in `p`).
    - `p0`, `guess`: the start (`guess` as in `harmonic_balance`: solved there first).
    - `p_bounds`: `(lo, hi)`; `harmonics`: `H`.
    - `period_at(p)`: the motion's period at `p` (default `2 pi / p`: `p` is the
      speed or forcing frequency in rad/s).
    - `scale`: one length per state (default: each state's largest coefficient at
      the start, at least 1e-3 of the largest of all), so that the arclength
      weighs coefficients and `p` alike; time is scaled by the start's
      `2 pi / period`.
    - `tol`, `gtol`: a point is accepted when Newton's last step is below `tol`
      (relative) and the scaled balance residual below `gtol` (its round-off floor
      grows with the stiffness: an FE rotor's highest modes).

    Returns `(branch, coefficients)`: the `Branch` (`p`; `margin` the largest real
    part of Hill's exponents in 1/s, see `hill_exponents`, and `stable` where it is
    negative; `events`: folds, refined, and branch points; `u` the scaled
    unknowns) and the coefficients `(points, 2H + 1, n)` in physical units.
    Secondary bifurcations (period doubling, Neimark-Sacker) are not yet
    classified: Hill's exponents crossing elsewhere than at folds are not reported
    as events (the margin and `stable` show them)."""
    if period_at is None:
        def period_at(p):
            return 2 * jnp.pi / p
    try:
        lo, hi = p_bounds
    except (TypeError, ValueError):
        raise InputError(f"p_bounds must be a pair (lo, hi), got {p_bounds!r}") from None
    p0 = float(as_param("p0", p0, shape=()))
    if not (lo <= p0 <= hi):
        raise InputError(f"p0 = {p0} must lie in p_bounds = ({lo}, {hi})")
    start = harmonic_balance(scene_at(p0), period_at(p0), guess, harmonics, stability=False)
    if int(start.code) != 0:
        raise NumericalError(f"periodic_branch: no periodic motion at {name} = {p0} from the guess "
                             f"({RESULTS[start.result]})")
    Y0 = start.coefficients
    shape = Y0.shape
    if scale is None:
        top = jnp.max(jnp.abs(Y0), axis=0)
        scale = jnp.maximum(top, 1e-3 * jnp.max(top) + jnp.finfo(jnp.float64).tiny)
    scale = jnp.broadcast_to(jnp.asarray(scale, dtype=jnp.float64), (shape[1],))[None, :]
    w0 = float(2 * np.pi / period_at(p0))

    def F(u, p):   # a similarity transform: Hill's exponents divided by w0
        Y = u.reshape(shape) * scale
        return -(balance_residual(scene_at(p), Y, period_at(p)) / (scale * w0)).ravel()

    br = continue_branch(F, np.asarray(Y0 / scale).ravel(), p0, p_bounds=(lo, hi), ds=ds, ds_max=ds_max,
                         max_points=max_points, tol=tol, direction=direction, name=name, progress=progress,
                         start_tol=gtol, gtol=gtol,
                         exponents=lambda J: _physical_exponents(jnp.asarray(J), shape[1], 1.0))
    events = tuple(e for e in br.events if e.kind in ("fold", "branch_point"))
    br = dataclasses.replace(br, margin=br.margin * w0, events=events)
    coefficients = np.asarray(br.u).reshape((-1,) + shape) * np.asarray(scale)
    return br, coefficients
