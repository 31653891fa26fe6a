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


def forcing_period(scene, subharmonic=1):
    """The period of a forced motion of `scene`: `subharmonic` times `2 pi / speed`
    (the unbalance's, at the scene's constant speed, in its time unit)."""
    k = as_count("subharmonic", subharmonic, minimum=1)
    if not isinstance(scene.speed, ConstantSpeed):
        raise InputError(f"a forced periodic motion needs a constant speed; {scene.describe()} runs at a "
                         f"{type(scene.speed).__name__}")
    return k * 2 * jnp.pi / scene.speed.constant


def orbit_amplitude(scene, coefficients, period, t0=0.0, node=None, n_points=None):
    """The amplitude of a periodic motion (coefficients `(2H + 1, n)` as in
    `PeriodicSolution`): the largest radius over the period of the orbit of `node`
    (the scene's outputs `node_x`, `node_y`: a shaft node, in the scene's length
    unit) or, with `node=None`, the largest of the scene's output `whirl_amplitude`.
    Sampled at `n_points` instants (default `16 (2H + 1)`). Traceable in the
    coefficients and the period; vmap over a branch's points."""
    Y = jnp.asarray(coefficients, dtype=jnp.float64)
    H = (Y.shape[-2] - 1) // 2
    m = n_points or 16 * (2 * H + 1)
    phase = 2 * jnp.pi * jnp.arange(m) / m
    ys = _basis_at(phase, H) @ Y
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


def periodic_branch(scene_at, p0, guess, p_bounds, harmonics=8, *, period_at=None, subharmonic=1, scale=None,
                    name="p", ds=0.01, ds_max=0.2, max_points=300, tol=1e-11, gtol=1e-6, direction=None,
                    progress=False):
    """A branch of periodic forced motions `Y(p)` by harmonic balance and
    pseudo-arclength continuation (`continue_branch`) in a parameter `p`, through
    folds.

    **Arguments:**
    - `scene_at(p)`: the scene at `p` (traceable in `p`).
    - `p0`, `guess`: the start (`guess` as in `harmonic_balance`: solved there first).
    - `p_bounds`: `(lo, hi)`; `harmonics`: `H`.
    - `period_at(p)`: the motion's period at `p` (default `forcing_period(scene_at(p),
      subharmonic)`: `subharmonic` times `2 pi / speed`).
    - `scale`: one length per state (default: each state's largest coefficient at
      the start, at least 1e-3 of the largest of all), so that the arclength
      weighs coefficients and `p` alike; time is scaled by the start's
      `2 pi / period`.
    - `tol`, `gtol`: a point is accepted when Newton's last step is below `tol`
      (relative) and the scaled balance residual below `gtol` (its round-off floor
      grows with the stiffness: an FE rotor's highest modes).

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
    events = tuple(_physical(e, scale, w0, period_at) for e in br.events)
    br = dataclasses.replace(br, margin=br.margin * w0, events=events)
    coefficients = np.asarray(br.u).reshape((-1,) + shape) * np.asarray(scale)
    return br, coefficients


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


def branch_amplitude(scene_at, p, coefficients, node=None, period_at=None, subharmonic=1):
    """`orbit_amplitude` at every point of a branch from `periodic_branch`
    (`p` its parameter values, `coefficients` `(points, 2H + 1, n)`), vmapped."""
    if period_at is None:
        def period_at(v):
            return forcing_period(scene_at(v), subharmonic)
    orbit_amplitude(scene_at(float(p[0])), coefficients[0], period_at(float(p[0])), node=node)   # checks node

    def one(v, Y):
        return orbit_amplitude(scene_at(v), Y, period_at(v), node=node)

    return np.asarray(jax.jit(jax.vmap(one))(jnp.asarray(p), jnp.asarray(coefficients)))
