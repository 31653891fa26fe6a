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

On a scene whose forces act at a few coordinates (`AbstractLocalScene`: an FE
rotor's nonlinear bearings), Newton runs on those coordinates' harmonics alone, the
rest of the motion their linear response (`_condensed`: the same iterates, a
fraction of the unknowns).

Self-checks returned with every solution: the balance residual `max |R|`, the
Newton step at exit, and the time-domain residual of the reconstructed orbit
`max_t |y'(t) - f(t, y(t))| / max_t |y'(t)|` on a grid four times finer than the
balance's: the truncation error of `H` harmonics, which the balance itself does
not see (it is the estimate a user raises `harmonics` against). Stability is
Floquet's, from the monodromy along the reconstructed orbit
(`rotorjax.analysis.floquet`, the variational equations integrated).
"""

import equinox as eqx
import jax
import jax.numpy as jnp
import numpy as np

from .._newton import newton as _newton
from ..models._contract import AbstractScene
from ..models._speed import ConstantSpeed
from ..models._validate import InputError, as_count, as_param, check_type, is_concrete
from ..solve._results import RESULTS, AbstractOutcome, code_of
from ._condensed import condensable, condensed_residual, expanded, read
from ._fourier import _basis_at, _collocation, _derivative, _samples
from ._floquet import FloquetResult, floquet


class PeriodicSolution(AbstractOutcome):
    """A periodic motion by harmonic balance.

    - `coefficients`: `(2H + 1, n)`: `c_0`, then `a_k`, `b_k` of harmonic `k`
      (cosine, sine in `w (t - t0)`), one column per state.
    - `period`, `t0`: the motion's period and the phase origin.
    - `residual`: max |.| of the balance residual at exit (units of `y'`).
    - `step`: max |.| of the last Newton step, relative to max |Y|.
    - `time_residual`: `max_t |y' - f(t, y)| / max(max_t |y'|, w max_t |y|)` of
      the reconstructed orbit on a grid four times finer: the truncation error
      estimate.
    - `iterations`: Newton iterations taken.
    - `code`: a `rotorjax.solve.RESULTS` index: `successful`, or
      `root_not_converged` (Newton did not reach its tolerance), `nonfinite`.
    - `floquet`: the `FloquetResult` along the orbit (None when not asked for).
    - `autonomous`, `phase`: a limit cycle of an autonomous scene (its period
      solved for), and the state whose first-harmonic sine part its phase
      condition holds at 0.
    - `start`: shooting's state at `t0` (exact to the closure; None for harmonic
      balance), what `initial_state` returns.
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
    start: jax.Array | None = None

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
        """`y(t0)`: the state to start a time integration on the orbit from (the
        shooting's own state where it has one, `start`; else the series' at `t0`,
        off the orbit by the truncation)."""
        return self.state(self.t0) if self.start is None else self.start

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
    """`max_t |y' - f(t, y)| / max(max_t |y'|, w max_t |y|)` on `4 N` instants (the
    second term: the derivative's scale at the motion's size, for a motion that is
    (nearly) constant, such as an auto-balanced rotor's, whose `y'` is round-off)."""
    H = (Y.shape[0] - 1) // 2
    M = 4 * _samples(H, None)
    B, _ = _collocation(H, M)
    ts = t0 + period * jnp.arange(M) / M
    ys, yds = B @ Y, B @ _derivative(Y, 2 * jnp.pi / period)
    fs = jax.vmap(lambda t, y: scene.vector_field(t, y, args))(ts, ys)
    scale = jnp.maximum(jnp.max(jnp.abs(yds)), 2 * jnp.pi / period * jnp.max(jnp.abs(ys)))
    return jnp.max(jnp.abs(yds - fs)) / jnp.maximum(scale, jnp.finfo(jnp.float64).tiny)


def truncation_error(scene, Y, period, t0=0.0, args=None):
    """The truncation error estimate of the coefficients `Y` (`(2H + 1, n)`): the
    correction the left-out harmonics would bring, relative to the motion. The
    residual `y' - f(t, y)` of the reconstructed orbit (on `4 N` instants) holds
    only harmonics above `H` (the balance removes the others); each is mapped to
    the state's correction `(i k w I - A)^-1 r_k`, `A` the field's Jacobian
    averaged over the orbit (one linearized Newton step on the harmonics above
    `H`), and the result is `||dY / s|| / ||Y / s||`, each state weighed by its
    size `s` (its largest coefficient, at least 1e-3 of the largest of all), so a
    stiff rotor's large accelerations of tiny motions do not count as error, as
    they do in the time-domain residual."""
    e2, size2 = _truncation_terms(scene, Y, period, t0, args)
    return jnp.sqrt(jnp.sum(e2) / size2)


def truncation_profile(scene, Y, period, t0=0.0, args=None):
    """`truncation_error`'s estimate had the series kept more harmonics, predicted
    from these coefficients: entry `j` leaves out only the corrections above
    harmonic `H + j` (entry 0 is `truncation_error`; the last, `j = 2 N - 2 - H`,
    only that of harmonic `2 N - 1`, the highest the `4 N` instants resolve). Where
    the series is short of harmonics, the count that meets a target is read off it
    (`next_harmonics`) instead of climbing the ladder one count at a time."""
    e2, size2 = _truncation_terms(scene, Y, period, t0, args)
    return jnp.sqrt(jnp.cumsum(e2[::-1])[::-1] / size2)


def _truncation_terms(scene, Y, period, t0, args):
    """`truncation_error`'s squared corrections per left-out harmonic `H + 1 ..
    2 N - 1` (summed over the states, weighed) and the weighed series' squared size."""
    H = (Y.shape[0] - 1) // 2
    M = 4 * _samples(H, None)
    B, _ = _collocation(H, M)
    w = 2 * jnp.pi / period
    ts = t0 + period * jnp.arange(M) / M

    def f(t, y):
        return scene.vector_field(t, y, args)

    ys = B @ Y
    r = B @ _derivative(Y, w) - jax.vmap(f)(ts, ys)
    eye = jnp.eye(Y.shape[1])

    def jac(t, y):   # columns by forward products (jacfwd's basis would carry a sharding: no shared program)
        return jax.vmap(lambda v: jax.jvp(lambda z: f(t, z), (y,), (v,))[1], out_axes=1)(eye)

    A = jnp.mean(jax.vmap(jac)(ts, ys), axis=0)
    ks = jnp.arange(H + 1, M // 2)
    R = jnp.fft.rfft(r, axis=0)[H + 1:M // 2] * (2.0 / M)
    # LU, not jnp.linalg.solve: its custom_linear_solve rule would keep the program from being shared (_lift)
    dY = jax.vmap(lambda k, Rk: jax.scipy.linalg.lu_solve(jax.scipy.linalg.lu_factor(1j * k * w * eye - A), Rk))(ks, R)
    s = jnp.max(jnp.abs(Y), axis=0, keepdims=True)
    s = jnp.maximum(s, 1e-3 * jnp.max(s) + jnp.finfo(jnp.float64).tiny)
    return (jnp.sum(jnp.abs(dY / s) ** 2, axis=1),
            jnp.maximum(jnp.sum((Y / s) ** 2), jnp.finfo(jnp.float64).tiny))


def next_harmonics(profile, H, counts, target):
    """The count of `counts` (ascending, all above `H`) to solve with next, from the
    `truncation_profile` `profile` of a solution with `H` harmonics that missed
    `target`: the fewest whose predicted estimate meets it; where none that the
    profile sees does, the first it does not see (beyond what these coefficients
    tell); the last count where every count is seen and none meets it."""
    profile = np.asarray(profile)
    for h in counts:
        if h - H >= profile.size or profile[h - H] <= target:
            return h
    return counts[-1]


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


def _checked(scene, period, guess, harmonics, t0, n_samples, tol, max_iter):
    """The arguments of a balance, checked by name: `(Y0, period, t0, n_samples,
    max_iter)`, `Y0` the guess's coefficients with `harmonics` harmonics."""
    check_type("scene", scene, AbstractScene, "a scene (an AbstractScene: Scene, RotorScene, ...)")
    H = as_count("harmonics", harmonics, minimum=1)
    if n_samples is not None:
        n_samples = as_count("n_samples", n_samples, minimum=2 * H + 1)
    max_iter = as_count("max_iter", max_iter, minimum=1)
    period = as_param("period", period, sign="positive", shape=())
    t0 = as_param("t0", t0, shape=())
    if is_concrete(tol):
        as_param("tol", tol, sign="positive", shape=())
    return _guess_coefficients(guess, H, scene.state_size), period, t0, n_samples, max_iter


#: `harmonics="auto"`: the harmonics tried, in turn
AUTO_HARMONICS = (4, 8, 16, 32, 64)


def harmonic_ladder(max_harmonics, ladder=AUTO_HARMONICS, above=0):
    """The harmonics `"auto"` tries in turn: `ladder`'s counts above `above` and
    below `max_harmonics`, then `max_harmonics`."""
    return tuple(h for h in ladder if above < h < max_harmonics) + (max_harmonics,)


def harmonic_balance(scene, period, guess, harmonics=8, *, t0=0.0, n_samples=None, tol=1e-10, max_iter=30,
                     stability=True, args=None, rtol=1e-10, atol=1e-12, truncation_tol=1e-6,
                     max_harmonics=64) -> PeriodicSolution:
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
    - `harmonics="auto"`: adapted to the motion: 4, 8, 16, ... up to
      `max_harmonics`, each solve started from the last, until the time-domain
      residual (the truncation error estimate, reported) is below `truncation_tol`;
      where it never is, the code is `harmonics_insufficient`.

    Traceable in the scene's parameters and the period (`stability=False` to vmap
    over a grid without integrating); the harmonics and samples are sizes.
    """
    check_type("scene", scene, AbstractScene, "a scene (an AbstractScene: Scene, RotorScene, ...)")
    if isinstance(harmonics, str) and harmonics == "auto":
        return _adapted(scene, period, guess, t0=t0, tol=tol, max_iter=max_iter, stability=stability, args=args,
                        rtol=rtol, atol=atol, truncation_tol=truncation_tol, max_harmonics=max_harmonics)
    Y0, period, t0, n_samples, max_iter = _checked(scene, period, guess, harmonics, t0, n_samples, tol, max_iter)
    sol = _solve(scene, Y0, period, t0, n_samples, tol, max_iter, args, args is None and condensable(scene))
    return _with_floquet(scene, sol, rtol, atol) if stability else sol


def _adapted(scene, period, guess, *, truncation_tol, max_harmonics, stability, ladder=AUTO_HARMONICS, above=0,
             measure=None, profile=None, **kw):
    """`harmonic_balance(harmonics="auto")`: see there (`ladder`, `above`: as in
    `harmonic_ladder`). `measure(solution)`, where given, is a `truncation_profile`:
    its first entry is held below `truncation_tol`, and where it is not, the next
    count is read off it (`next_harmonics`) rather than the ladder's next; `profile`
    the one of the solution with `above` harmonics that `guess` is, to choose the
    first count by. Without `measure`, the time-domain residual is held below it,
    count by count."""
    max_harmonics = as_count("max_harmonics", max_harmonics, minimum=1)
    as_param("truncation_tol", truncation_tol, sign="positive", shape=())
    counts = harmonic_ladder(max_harmonics, ladder, above)
    H = counts[0] if profile is None else next_harmonics(profile, above, counts, truncation_tol)
    sol = None
    while True:
        sol = harmonic_balance(scene, period, guess if sol is None else sol, H, stability=False, **kw)
        if int(sol.code) != 0:
            return sol
        seen = None if measure is None else np.asarray(measure(sol))
        if float(sol.time_residual if seen is None else seen[0]) <= truncation_tol:
            break
        later = tuple(h for h in counts if h > H)
        if not later:
            sol = eqx.tree_at(lambda s: s.code, sol, jnp.asarray(code_of(RESULTS.harmonics_insufficient), jnp.int32))
            break
        H = later[0] if seen is None else next_harmonics(seen, H, later, truncation_tol)
    return _with_floquet(scene, sol, kw["rtol"], kw["atol"]) if stability else sol


def _with_floquet(scene, sol, rtol=1e-10, atol=1e-12, y0=None) -> PeriodicSolution:
    """`sol` with its Floquet analysis along the orbit from `y0` (default: the
    series' state at `t0`), integrated at `rtol`, `atol`."""
    y0 = sol.initial_state() if y0 is None else y0
    fq = floquet(scene, y0, sol.period, sol.t0, rtol=rtol, atol=atol)
    return eqx.tree_at(lambda s: s.floquet, sol, fq, is_leaf=lambda x: x is None)


@eqx.filter_jit
def _solve(scene, Y0, period, t0, n_samples, tol, max_iter, args, condense=False) -> PeriodicSolution:
    """One compiled Newton per scene structure and size (a new speed or guess
    reuses it). `condense` (a `condensable` scene, `args` None): Newton on the read
    coordinates' harmonics alone (`_condensed`), the motion their linear
    response."""
    shape = Y0.shape

    def residual(x):
        return balance_residual(scene, x.reshape(shape), period, t0, n_samples, args).ravel()

    if condense:
        local = scene.local_forces()
        N = _samples((shape[0] - 1) // 2, n_samples)
        Z0 = read(local, Y0)
        def reduced(x):
            return condensed_residual(local, x.reshape(Z0.shape), period, t0, N).ravel()

        z, (step, it) = _newton(reduced, Z0.ravel(), tol, max_iter, limit=_finite_step(reduced))
        x = expanded(local, z.reshape(Z0.shape), period, t0, N).ravel()
    else:
        x, (step, it) = _newton(residual, Y0.ravel(), tol, max_iter, limit=_finite_step(residual))
    step, it = jax.lax.stop_gradient(step), jax.lax.stop_gradient(it).astype(jnp.int32)
    return _outcome(scene, x.reshape(shape), period, t0, jnp.max(jnp.abs(residual(x))), step, it, tol, args)


#: `_finite_step`: the most halvings of a Newton step whose end the forces are not defined at
MAX_HALVINGS = 40


def _finite_step(residual):
    """Newton's `limit`: the step halved until the residual at its end is finite (a
    film's journal kept inside its clearance, where the full step from a guess far
    off, such as the rest, would leave it), at most `MAX_HALVINGS` times."""
    def limit(x, dx):
        def short(c):
            return (c[1] < MAX_HALVINGS) & ~jnp.all(jnp.isfinite(residual(x - c[0])))

        return jax.lax.while_loop(short, lambda c: (0.5 * c[0], c[1] + 1), (dx, 0))[0]

    return limit


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


#: the methods of `periodic_orbit`
METHODS = ("harmonic-balance", "shooting")


#: Hill's exponents within this fraction of `w / 2` of `+-w / 2` (a negative real multiplier, or two
#: near it) are told apart by the side their eigenvector leans to
HALF_FREQUENCY_TOL = 1e-6


def _harmonic_mean(vecs, n):
    """The mean harmonic index of each eigenvector of Hill's matrix (columns of
    `vecs`, the coefficients `(2H + 1) n` in the layout of `Y`), in the complex
    Fourier basis (`a_k cos + b_k sin = p_k e^{ikwt} + p_-k e^{-ikwt}`, `p_+-k =
    (a_k -+ i b_k) / 2`) weighted by `|p_k|^2`."""
    V = vecs.reshape(-1, n, vecs.shape[-1])
    H = (V.shape[0] - 1) // 2
    a, b = V[1::2], V[2::2]
    plus = jnp.sum(jnp.abs(a - 1j * b) ** 2, axis=1) / 4
    minus = jnp.sum(jnp.abs(a + 1j * b) ** 2, axis=1) / 4
    k = jnp.arange(1, H + 1, dtype=jnp.float64)[:, None]
    total = jnp.sum(jnp.abs(V[0]) ** 2, axis=0) + jnp.sum(plus + minus, axis=0)
    return jnp.sum(k * (plus - minus), axis=0) / total


def _physical_exponents(jac, n, omega):
    """Hill's method: of the eigenvalues of Hill's matrix `jac` (the balance's
    linearisation `-dR/dY`: the copies `s + i k w` of every Floquet exponent `s`
    for every retained harmonic shift `k`, and spurious ones from the truncation),
    one per exponent, `n` in all, returned with `Im s` folded into `[-w/2, w/2]`
    (the multiplier `exp(sT)` unchanged).

    The copy taken is the one whose eigenvector is centred on the constant term
    (Lazarus & Thomas 2010): an eigenvector's mean harmonic index
    (`_harmonic_mean`) moves by `k` with the copy, so one copy of each exponent has
    `|mean| <= 1/2`, and the truncation's spurious ones lean to the highest
    harmonics. (The usual choice, the smallest `|Im s|`, fails once a mode's
    frequency passes `(H + 1/2) w`, as a flexible rotor's higher modes do: their
    copies cannot reach `|Im s| < w/2`, and copies of the low exponents take their
    places, counted twice.) Of the centred ones the least damped are kept: a real
    eigenvalue has a real eigenvector, mean 0, and a stiff, strongly modulated
    damping (a journal at high eccentricity) gives more real ones than there are
    places (spurious, or exponents so damped that they do not matter). An exponent with
    `Im s = w/2` (a negative real multiplier) has two centred copies, `s` and `s -
    i w` (means -1/2 and 1/2): the one leaning to positive harmonics goes to the
    back, or a multiplier on the negative axis would count twice (two distinct
    ones near it keep a copy each)."""
    lam, vecs = jnp.linalg.eig(jac)
    mean = _harmonic_mean(vecs, n)
    im = jnp.imag(lam)
    folded = im - omega * jnp.round(im / omega)
    half = jnp.abs(folded) > (0.5 - HALF_FREQUENCY_TOL) * omega
    centred = (jnp.abs(mean) <= 0.5 + HALF_FREQUENCY_TOL) & ~(half & (mean > 0))
    # the centred ones first, the least damped first; then the nearest to centred
    chosen = jnp.lexsort((jnp.where(centred, -jnp.real(lam), jnp.abs(mean)), ~centred))[:n]
    return jnp.real(lam[chosen]) + 1j * folded[chosen]


def magnus_exponents(scene, Y, period, t0=0.0, args=None):
    """Floquet exponents of the orbit of the coefficients `Y` (`(2H + 1, n)`) from
    its monodromy: the product of the fourth-order Magnus propagators
    `expm(h/2 (A1 + A2) + sqrt(3) h^2/12 [A2, A1])` over `2 N` steps `h` of the
    period (`A1`, `A2` the field's Jacobian at the step's two Gauss points on the
    reconstructed orbit; `N` the balance's instants). `n` exponents `log(mu) / T`,
    `Im s` in `(-w/2, w/2]`, as `hill_exponents`' (the exponential keeps a stiff
    rotor's fast modes stable at any step). Where Hill's matrix is large, far
    cheaper than its eigenvalues (`benchmarks/periodic_defaults.py`, section
    `exponents`), at a fourth-order error in the step. Damped modes whose
    multipliers underflow get `-inf`."""
    H, n = (Y.shape[0] - 1) // 2, Y.shape[1]
    M = 2 * _samples(H, None)
    h = period / M
    gauss = jnp.asarray([0.5 - np.sqrt(3) / 6, 0.5 + np.sqrt(3) / 6])
    ts = t0 + h * (jnp.arange(M, dtype=jnp.float64)[:, None] + gauss[None, :])
    ys = _basis_at(2 * jnp.pi * (ts - t0) / period, H) @ Y
    eye = jnp.eye(n)

    def jac(t, y):   # columns by forward products, as in truncation_error
        return jax.vmap(lambda v: jax.jvp(lambda z: scene.vector_field(t, z, args), (y,), (v,))[1], out_axes=1)(eye)

    A = jax.vmap(jax.vmap(jac))(ts, ys)
    A1, A2 = A[:, 0], A[:, 1]
    steps = jax.vmap(jax.scipy.linalg.expm)(0.5 * h * (A1 + A2) + (np.sqrt(3) / 12) * h * h * (A2 @ A1 - A1 @ A2))
    monodromy = jax.lax.scan(lambda P, E: (E @ P, None), eye, steps)[0]
    return jnp.log(jnp.linalg.eigvals(monodromy).astype(jnp.complex128)) / period


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
