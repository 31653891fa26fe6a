"""Limit cycles of autonomous scenes by harmonic balance: the period an unknown,
closed by a phase condition; from a Hopf point of an equilibrium or from a time
simulation; continued in a parameter through folds of cycles."""

import dataclasses

import equinox as eqx
import jax
import jax.numpy as jnp
import numpy as np

from .._errors import NumericalError
from ..models._validate import InputError, as_count, as_param, check_type, is_concrete
from ..solve._results import RESULTS
from ._continuation import continue_branch, physical_stops
from ._harmonic_balance import (PeriodicSolution, _checked, _newton, _outcome, _physical_exponents, _with_floquet,
                                balance_residual, forcing_period)
from ._periodic_branch import _checked_range, _secondary


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
    Y0, period, t0, n_samples, max_iter = _checked(scene, period, guess, harmonics, t0, n_samples, tol, max_iter)
    n = scene.state_size
    k = _phase_state(Y0, phase, guess)
    if k >= n:
        raise InputError(f"phase = {k}: the scene has {n} states")
    sol = _solve_cycle(scene, _aligned(Y0, k), period, t0, n_samples, tol, max_iter, args, k)
    return _with_floquet(scene, sol, rtol, atol) if stability else sol


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
    return pc, (_with_floquet(sc, sol) if stability else sol)


def _nontrivial(e, w):
    """Hill's exponents of a limit cycle (`w` its frequency) less the trivial one,
    the one nearest 0. Near a fold of cycles the trivial exponent and the one
    crossing there form a near-Jordan block, which the truncation and aliasing
    split into a complex pair `a +- i b` (`b` ~ the square root of the error) with
    no exponent at 0: then the trivial one is removed from the pair and the other is
    their sum `2a` (a sum of eigenvalues moves as the error, not its square root),
    or the fold would be reported as a Neimark-Sacker point."""
    i = int(np.argmin(np.abs(e)))
    rest = np.delete(e, i)
    if abs(e[i].imag) > 1e-9 * max(abs(e[i]), 1e-300) and abs(e[i]) < 0.1 * abs(w):
        j = int(np.argmin(np.abs(rest - np.conj(e[i]))))
        if abs(rest[j] - np.conj(e[i])) <= 1e-6 * abs(e[i]):
            rest[j] = (e[i] + rest[j]).real
    return rest


def limit_cycle_branch(scene_at, p0, start, p_bounds, *, phase=None, scale=None, name="p", ds=0.01, ds_max=0.2,
                       max_points=300, tol=1e-11, gtol=1e-6, direction=None, progress=False):
    """A branch of limit cycles of autonomous scenes `scene_at(p)` (their period
    unknown) by harmonic balance and pseudo-arclength continuation in `p`, through
    folds: the unknowns are the coefficients and the frequency, closed by the phase
    condition of `limit_cycle`.

    `start`: a `PeriodicSolution` of `scene_at(p0)` (from `limit_cycle` or
    `hopf_cycle`; its harmonics are the branch's). `scale`, `tol`, `gtol` and the
    rest as in `periodic_branch`: the steps `ds`, `ds_max` are in the unknowns
    divided by `scale`, by default each state's largest coefficient at the start.
    From a small cycle at a Hopf point the amplitude grows by orders of magnitude
    (oil whip: 1e-3 to 22 clearances), so give a large `ds_max` (e.g. 100); the
    steps still shrink where the corrector works hard or the branch turns.

    Returns `(branch, coefficients, periods)`: the `Branch` (`margin` the largest
    real part of Hill's exponents with the trivial one, nearest 0, left out;
    events folds, branch points, period doublings and Neimark-Sacker points as in
    `periodic_branch`), the coefficients `(points, 2H + 1, n)` and the periods."""
    check_type("start", start, PeriodicSolution, "a PeriodicSolution (from limit_cycle or hopf_cycle)")
    (lo, hi), p0 = _checked_range(p_bounds, p0)
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
        return _nontrivial(np.asarray(_physical_exponents(jnp.asarray(J)[:m, :m], shape[1], u[m])), u[m])

    u0 = np.concatenate([np.asarray(Y0 / scale).ravel(), [1.0]])
    br = continue_branch(F, u0, p0, p_bounds=(lo, hi), ds=ds, ds_max=ds_max, max_points=max_points, tol=tol,
                         direction=direction, name=name, progress=progress, start_tol=gtol, gtol=gtol,
                         exponents=exponents)
    u = np.asarray(br.u)
    periods = 2 * np.pi / (w0 * u[:, m])
    events = []
    for e in br.events:
        e = dataclasses.replace(e, u=(np.asarray(e.u)[:m].reshape(shape) * np.asarray(scale)).ravel(),
                                tangent=None)   # in the scaled unknowns, as in `_periodic_branch._physical`
        if e.kind == "hopf":
            i = e.between[0]
            e = _secondary(e, w0, 2 * np.pi / periods[i])
        events.append(e)
    br = dataclasses.replace(br, margin=br.margin * w0, events=tuple(events))
    return br, u[:, :m].reshape((-1,) + shape) * np.asarray(scale), periods


def is_autonomous(scene, y) -> bool:
    """Whether `scene`'s equations do not depend on time (no forcing, such as an
    unbalance): its field at the state `y` equal (to 1e-12 relative) at two instants
    of its forcing period (`forcing_period`). Limit cycles (`limit_cycle`,
    `hopf_cycle_branch`) need an autonomous scene. (`check_autonomous` asks the same
    of the rotating frame, where stationary regimes live.)"""
    f0, f1 = (scene.vector_field(t, jnp.asarray(y), None) for t in (0.0, 0.37 * forcing_period(scene)))
    return float(jnp.max(jnp.abs(f1 - f0))) <= 1e-12 * float(jnp.max(jnp.abs(f0))) + 1e-300


def hopf_cycle_branch(scene_at, hopf, y_eq, p_bounds, harmonics=8, *, amplitude=None, name="p", ds=0.02,
                      ds_max=100.0, max_points=300, progress=False):
    """The branch of limit cycles born at a Hopf point, continued away from it
    through `p_bounds`: `hopf_cycle` at a small amplitude, then `limit_cycle_branch`
    in `p` relative to the Hopf point's (the steps `ds`, `ds_max` are in that ratio
    and in the unknowns divided by the first cycle's largest coefficient: from a
    small cycle the amplitude grows by orders of magnitude, hence the large `ds_max`).

    `scene_at(p)`: the autonomous scene at `p`; `hopf`: a `HopfPoint` (its `speed`
    the parameter, its `frequency` the crossing pair's); `y_eq`: the equilibrium
    there (a guess: harmonic balance solves the cycle's mean with it);
    `amplitude`: the first cycle's first-harmonic amplitude in the state where the
    critical eigenvector is largest (default: 1e-2 of the equilibrium's largest
    state, or 1e-6 where the equilibrium is the origin). The branch runs to the side
    of the Hopf point on which the first cycle lives (its criticality), through folds.

    Returns `(branch, coefficients, periods, p_start)`: the `Branch` in `p` itself,
    its coefficients `(points, 2H + 1, n)`, the periods, and the first cycle's `p`
    (below the Hopf point's: subcritical; above: supercritical)."""
    p_h = as_param("hopf.speed", hopf.speed, sign="positive", shape=())
    (lo, hi), _ = _checked_range(p_bounds, float(p_h))
    y_eq = jnp.asarray(y_eq, dtype=jnp.float64)
    if amplitude is None:
        top = float(jnp.max(jnp.abs(y_eq)))
        amplitude = 1e-2 * top if top > 0 else 1e-6

    def at(r):
        return scene_at(r * p_h)

    r0, start = hopf_cycle(at, 1.0, y_eq, amplitude, harmonics, frequency=hopf.frequency, stability=False)
    r0 = float(r0)
    direction = -1 if r0 < 1.0 else 1
    # continued in the ratio to the Hopf point's parameter (named so while it runs: the progress bar); the
    # branch, its events and its stops are given back in the parameter itself
    ratio = f"{name}/{float(p_h):.8g}"
    # every unknown scaled by the first cycle's largest coefficient (the equilibrium's size, where it is not the
    # origin), not each state by its own: the cycle's harmonics start tiny and grow by orders, and scaled by their
    # own start they rule the arclength (the journal rig's oil whirl, 8 harmonics: 300 points to 212 rad/s per
    # state, 24 to 215 rad/s so)
    scale = jnp.max(jnp.abs(start.coefficients))
    br, coefficients, periods = limit_cycle_branch(at, r0, start, (lo / float(p_h), hi / float(p_h)), name=ratio,
                                                   scale=scale, ds=ds, ds_max=ds_max, max_points=max_points,
                                                   direction=direction, progress=progress)
    p = float(p_h)
    events = tuple(dataclasses.replace(e, p=e.p * p) for e in br.events)

    def back(texts):
        return physical_stops(texts, ratio, lambda v: v * p, lo, hi, as_name=name)

    curve = dataclasses.replace(br.curve, stops=back(br.curve.stops), stopped=back((br.curve.stopped,))[0])
    br = dataclasses.replace(br, p=np.asarray(br.p) * p, events=events, curve=curve)
    return br, coefficients, periods, r0 * p
