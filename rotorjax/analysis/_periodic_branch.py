"""Branches of periodic forced motions: harmonic balance (or shooting) continued
by pseudo-arclength in a parameter through folds, with Hill's (or the monodromy's)
stability at every point and its events (folds, branch points, period doublings,
Neimark-Sacker points); switching onto a period-doubled branch; a fold continued in
two parameters and its gradient; a grid of motions in one compiled program."""

import dataclasses
import functools

import jax
import jax.numpy as jnp
import numpy as np

from .._autodiff import value_and_jacfwd
from .._errors import NumericalError
from ..models._validate import InputError, as_count, as_param
from ..solve._lift import batched, call, lift, vmapped
from ..solve._results import RESULTS, code_of
from ._branch_harmonics import (BRANCH_HARMONICS, PeriodicBranch, _adaptive, _fields, _measure, _rows,
                                _series_harmonics, _series_tail, _truncated, _truncations, _watch)
from ._condensed import condensable, condensed_residual, expanded, read
from ._continuation import continue_branch, fold_curve, fold_gradient, physical_stops, switch_branch
from ._floquet import flow_samples
from ._harmonic_balance import (METHODS, PeriodicSolution, _adapted, _basis_at, _guess_coefficients, _newton, _outcome,
                                _physical_exponents, _samples, _solve, _time_residual, _with_floquet, balance_residual,
                                coefficients_from_samples, forcing_period, harmonic_balance, harmonic_ladder,
                                magnus_exponents, orbit_amplitude)


def periodic_branch(scene_at, p0, guess, p_bounds, harmonics="auto", *, period_at=None, subharmonic=1, scale=None,
                    name="p", ds=None, ds_max=None, max_points=300, tol=1e-11, gtol=1e-6, direction=None,
                    progress=False, method="harmonic-balance", steps=256, truncation_tol=1e-6, max_harmonics=32,
                    switch=False):
    """A branch of periodic forced motions `Y(p)` by harmonic balance and
    pseudo-arclength continuation (`continue_branch`) in a parameter `p`, through
    folds.

    **Arguments:**
    - `scene_at(p)`: the scene at `p` (traceable in `p`).
    - `p0`, `guess`: the start (`guess` as in `harmonic_balance`: solved there first).
    - `p_bounds`: `(lo, hi)`; `harmonics`: `H`, or `"auto"` (the default): each
      point's harmonics adapted to the motion (`BRANCH_HARMONICS`: 1, 2, 4, ... up
      to `max_harmonics`), so that the truncation error estimate
      (`truncation_error`) stays below `truncation_tol`: the start takes the fewest
      that reach it (the counts that the estimate's `truncation_profile` shows short
      skipped); a point past it ends the piece of branch there, and the next piece
      goes on from that point solved again with more harmonics (in the direction
      the branch went; the count read off that point's profile likewise); where the
      series cut to the next lower count keeps the residual below `LOWER_MARGIN`
      times `truncation_tol`, with fewer (kept only where the motion solved with
      them meets the target). With shooting, each point's series keeps the fewest
      harmonics (of `max_harmonics`) whose left-out ones hold less than
      `truncation_tol` of its size.
    - `period_at(p)`: the motion's period at `p` (default `forcing_period(scene_at(p),
      subharmonic)`: `subharmonic` times `2 pi / speed`).
    - `scale`: one length per state (default: each state's largest coefficient
      over a survey of the range, `SURVEY` points solved from the start's motion
      in one compiled batch, and at least 1e-3 of the largest of all, times the
      square root of the number of states: the whole block of unknowns, not each
      state, spans about one length). The unknowns are the coefficients over
      `scale`, times the range's length `L = hi - lo`, so that the arclength weighs
      a motion's growth from nothing to its largest and a walk across the range
      alike (an FE rotor's 32 states each grown to their largest would make the
      arclength of the motion's growth sqrt(32) times that of the range's walk);
      time is scaled by the start's `2 pi / period`.
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

    Returns `(branch, coefficients)`: the `PeriodicBranch` (`harmonics`: each
    point's count; `p`; `margin` the largest real
    part of Hill's exponents in 1/s, see `hill_exponents` (above `HILL_MAX`
    unknowns the reconstructed orbit's monodromy's, `magnus_exponents`), and
    `stable` where it is negative; `u` the scaled unknowns: the coefficients,
    or on a scene with local forces the read coordinates' (`_condensed`)) and the coefficients `(points, 2H + 1, n)`
    in physical units (`H` the most any point has; zeros above a point's own).
    `branch.events` (`u`: the coefficients there, flattened, physical units):
    `"fold"` (refined: Newton on the balance and `det dR/dY = 0`), `"branch_point"` (refined on Moore and
    Keller's extended system, as in `continue_branch`), and where a
    complex pair of Hill's exponents crosses, refined by bisection along the
    branch, `"period-doubling"` (its frequency half the motion's: a multiplier
    through -1) or `"neimark-sacker"` (a pair of multipliers `exp(+-i 2 pi f / w)`
    through the unit circle; `frequency` the exponent's `f` in (0, w/2), rad per
    time unit)."""
    scene_at = _array_parameter(scene_at)
    if period_at is None:
        def period_at(p):
            return forcing_period(scene_at(p), subharmonic)
    (lo, hi), p0 = _checked_range(p_bounds, p0)
    if method not in METHODS:
        raise InputError(f"method {method!r}: one of {', '.join(map(repr, METHODS))}")
    auto = isinstance(harmonics, str) and harmonics == "auto"
    if isinstance(harmonics, str) and not auto:
        raise InputError(f"harmonics must be an integer >= 1 or 'auto', got {harmonics!r}")
    target = float(as_param("truncation_tol", truncation_tol, sign="positive", shape=()))
    top = as_count("max_harmonics", max_harmonics, minimum=1) if auto else as_count("harmonics", harmonics,
                                                                                     minimum=1)
    L = _span(lo, hi, p0)
    options = dict(ds=L / 100 if ds is None else ds, ds_max=L / 10 if ds_max is None else ds_max,
                   max_points=max_points, tol=tol, direction=direction, name=name, progress=progress,
                   start_tol=gtol * L, gtol=gtol * L)
    if switch and method == "shooting":
        raise InputError("switch: branch points are switched at on harmonic-balance branches; give "
                         "method='harmonic-balance'")
    if method == "shooting":
        br, coefficients = _shooting_branch(scene_at, p0, guess, (lo, hi), top, period_at, scale,
                                            as_count("steps", steps, minimum=1), L, options)
        kept = _series_harmonics(coefficients, target) if auto else np.full(br.p.size, top)
        return (PeriodicBranch(**_fields(br), harmonics=kept, truncation=_series_tail(coefficients, kept)),
                _truncated(coefficients, kept))
    if auto:
        start = _adapted(scene_at(p0), period_at(p0), guess, truncation_tol=target, max_harmonics=top,
                         stability=False, ladder=BRANCH_HARMONICS, measure=_measure(scene_at, period_at, p0), t0=0.0,
                         tol=1e-10, max_iter=30, args=None)
    else:
        start = harmonic_balance(scene_at(p0), period_at(p0), guess, top, stability=False)
    if int(start.code) not in (0, code_of(RESULTS.harmonics_insufficient)):
        raise NumericalError(f"periodic_branch: no periodic motion at {name} = {p0} from the guess "
                             f"({RESULTS[start.result]})")
    Y0 = start.coefficients
    condense = condensable(scene_at(p0))
    reads = _reads(scene_at(p0), Y0.shape[1]) if condense else None
    if scale is None:
        scale = _survey_scale(scene_at, period_at, Y0, lo, hi, condense) * np.sqrt(Y0.shape[1])
    scale = jnp.broadcast_to(jnp.asarray(scale, dtype=jnp.float64), (Y0.shape[1],))[None, :] / L
    # condensed: the unknowns are the read coordinates' harmonics, each over its largest (that of the states'
    # scales it reads), the block spanning about one length as the states' do
    zscale = None if reads is None else (np.max(np.abs(reads) * np.asarray(scale).T, axis=0)
                                         * np.sqrt(reads.shape[1] / Y0.shape[1]))[None, :]
    piece = functools.partial(_piece, scene_at, period_at, (lo, hi), (scale, zscale), float(2 * np.pi / period_at(p0)),
                              switch=bool(switch))
    if not auto:
        br, coefficients = piece(Y0, p0, options)
        return (PeriodicBranch(**_fields(br), harmonics=np.full(br.p.size, top),
                               truncation=_truncations(scene_at, period_at, br.p, coefficients)[:, 0]), coefficients)
    return _adaptive(piece, Y0, p0, options, target, harmonic_ladder(top, BRANCH_HARMONICS))


def _reads(scene, n):
    """`(n, m)`: the read coordinates of a condensed balance from a motion's
    coefficients, `Z = Y @ reads` (`_condensed.read`)."""
    S = np.asarray(scene.local_forces().S)
    return np.concatenate([S.T, np.zeros((n - S.shape[1], S.shape[0]))])


def _piece(scene_at, period_at, bounds, scales, w0, Y0, p0, options, watch=None, switch=False):
    """The branch by harmonic balance with `Y0`'s harmonics from `(Y0, p0)` (see
    `periodic_branch`; `w0` the start's forcing frequency, the unit of the scaled
    equations' exponents; `scales`: the states' and, for a condensed balance, the
    read coordinates'; `watch`: `(target, higher, lower)` of `_watch`; `switch`:
    each refined branch point's crossing branch too, in its event's `switched`):
    `(branch, coefficients)`."""
    shape = Y0.shape
    scale, zscale = scales
    w0_ = jnp.asarray(w0)   # an array, not a literal: a branch of other values reuses the compilation

    def whole(v, p):   # a similarity transform (times L): Hill's exponents divided by w0
        Y = v.reshape(shape) * scale
        return -(balance_residual(scene_at(p), Y, period_at(p)) / (scale * w0_)).ravel()

    if zscale is None:
        F, u0 = whole, np.asarray(Y0 / scale).ravel()

        def coefficients(u, p):
            return u.reshape(shape) * scale
    else:
        N, zshape = _samples((shape[0] - 1) // 2, None), (shape[0], zscale.shape[1])

        def F(u, p):
            return (condensed_residual(scene_at(p).local_forces(), u.reshape(zshape) * zscale, period_at(p), 0.0, N)
                    / zscale).ravel()

        def coefficients(u, p):
            return expanded(scene_at(p).local_forces(), u.reshape(zshape) * zscale, period_at(p), 0.0, N)

        u0 = np.asarray(read(scene_at(p0).local_forces(), Y0) / zscale).ravel()
    at = (jnp.asarray(u0), jnp.asarray(p0))
    if Y0.size <= HILL_MAX:
        ratio = lift(lambda p: 2 * jnp.pi / (w0_ * period_at(p)), at[1])   # w / w0 at p
        if zscale is None:
            def exponents(J, u, p):
                return _hill(jnp.asarray(J), shape[1], call(ratio, jnp.asarray(p)))
        else:
            hill = lift(lambda u, p: jax.jacfwd(whole)((coefficients(u, p) / scale).ravel(), p), *at)

            def exponents(J, u, p):
                return _hill(call(hill, jnp.asarray(u), jnp.asarray(p)), shape[1], call(ratio, jnp.asarray(p)))
    else:
        magnus = lift(lambda u, p: magnus_exponents(scene_at(p), coefficients(u, p), period_at(p)) / w0_, *at)

        def exponents(J, u, p):
            return call(magnus, jnp.asarray(u), jnp.asarray(p))
    if watch is not None:
        watch = _watch(scene_at, period_at, coefficients, shape, *watch)
    br = continue_branch(F, u0, p0, p_bounds=bounds, **options, watch=watch, exponents=exponents)
    if zscale is None:
        physical = functools.partial(_scaled, scale)
    else:
        physical = functools.partial(_expand_rows, lift(lambda p, u: coefficients(u, p), at[1], at[0]))
    events = []
    for e in br.events:
        crossing = _crossing(F, e, bounds, options, exponents, physical, w0, (scene_at, period_at), shape) \
            if switch else {}
        events.append(dataclasses.replace(_physical(e, physical, w0, period_at), **crossing))
    br = dataclasses.replace(br, margin=br.margin * w0, events=tuple(events))
    return br, physical(np.asarray(br.p), np.asarray(br.u)).reshape((-1,) + shape)


def _crossing(F, event, bounds, options, exponents, physical, w0, at, shape):
    """`periodic_branch(switch=True)`: the fields of a refined branch point's event
    (`F`'s scaled unknowns) that hold the branch crossing there, `{"switched":
    (PeriodicBranch, coefficients)}` with `shape`'s harmonics, or `{"note": why}`
    where it does not start; `{}` for the other events (`at`: `(scene_at,
    period_at)`)."""
    if event.kind != "branch_point" or event.tangent is None:
        return {}
    opts = {k: v for k, v in options.items() if k not in ("direction", "start_tol")}
    try:
        other = switch_branch(F, event, p_bounds=bounds, start_tol=options["start_tol"], exponents=exponents, **opts)
    except ValueError as err:
        return {"note": f"not switched at: {err}"}
    H, period_at = (shape[0] - 1) // 2, at[1]
    coefficients = physical(np.asarray(other.p), np.asarray(other.u)).reshape((-1,) + shape)
    other = dataclasses.replace(other, margin=other.margin * w0,
                                events=tuple(_physical(e, physical, w0, period_at) for e in other.events))
    return {"switched": (PeriodicBranch(**_fields(other), harmonics=np.full(other.p.size, H),
                                        truncation=_truncations(*at, other.p, coefficients)[:, 0]), coefficients)}


def _scaled(scale, p, u):
    """Coefficients `(points, 2H + 1, n)` from unknowns `u` over `scale`."""
    return np.asarray(u).reshape((len(p), -1, scale.shape[1])) * np.asarray(scale)


def _expand_rows(coefficients, p, u):
    """Coefficients `(points, 2H + 1, n)` of a condensed balance's unknowns `u`
    (`coefficients` lifted: compiled once per structure)."""
    return batched(_rows, coefficients, (np.asarray(p, dtype=float), np.asarray(u, dtype=float)))[0]


#: a branch's stability exponents by Hill's method (the eigenvalues of the balance's Jacobian) up to this many
#: unknowns `(2H + 1) n`; above, by the monodromy of the reconstructed orbit (`magnus_exponents`: 15x faster at 1056
#: unknowns, the margin within 1e-7 of the integrated monodromy's; benchmarks/periodic_defaults.py, `exponents`)
HILL_MAX = 1024


def _checked_range(p_bounds, p0):
    """`((lo, hi), p0)` checked: a pair, and the start inside it."""
    try:
        lo, hi = p_bounds
    except (TypeError, ValueError):
        raise InputError(f"p_bounds must be a pair (lo, hi), got {p_bounds!r}") from None
    p0 = float(as_param("p0", p0, shape=()))
    if not (lo <= p0 <= hi):
        raise InputError(f"p0 = {p0} must lie in p_bounds = ({lo}, {hi})")
    return (lo, hi), p0


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

    y = _start_state(guess, n)
    # the user's functions lifted: the start's Newton and the series below are compiled once per
    # structure of the scene (another branch of this layout reuses them)
    at = jnp.asarray(p0, dtype=jnp.float64)
    flow = (lift(scene_at, at), lift(period_at, at), steps)
    for _ in range(40):            # Newton, the step halved until the closure shrinks
        dy, g = _shooting_newton(*flow, y, at)
        if not float(g) > 1e-12 * max(1.0, float(jnp.max(jnp.abs(y)))):
            break
        step = 1.0
        while step > 1e-3 and not float(_shooting_gap(*flow, y - step * dy, at)) < float(g):
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
        return _closure(*flow, u * scale, p) / scale

    def exponents(J, u, p):
        mu = jnp.linalg.eigvals(jnp.asarray(J) + jnp.eye(n))
        return jnp.log(mu.astype(jnp.complex128)) / (period_at(p) * w0)

    br = continue_branch(F, np.asarray(y / scale), p0, p_bounds=bounds, exponents=exponents, **options)
    events = []
    for e in br.events:
        e = dataclasses.replace(e, u=np.asarray(e.u) * np.asarray(scale), tangent=None)   # as `_physical`
        if e.kind == "hopf":
            e = _secondary(e, w0, float(2 * np.pi / period_at(e.p)))
        events.append(e)
    br = dataclasses.replace(br, margin=br.margin * w0, events=tuple(events))

    def series(u, p):
        return _shooting_series(*flow, N, H, jnp.asarray(u, dtype=jnp.float64), jnp.asarray(p, dtype=jnp.float64))

    ys0 = np.asarray(br.u) * np.asarray(scale)
    coefficients = np.asarray(series(ys0, br.p))
    ev = [dataclasses.replace(e, u=np.asarray(series(np.asarray(e.u)[None], [e.p])[0]).ravel())
          for e in events]
    return dataclasses.replace(br, events=tuple(ev)), coefficients


def _closure(scene_at, period_at, steps, y, p):
    return flow_samples(scene_at(p), y, period_at(p), steps=steps)[-1] - y


@functools.partial(jax.jit, static_argnums=2)
def _shooting_newton(scene_at, period_at, steps, y, p):
    """Newton's direction on the closure after one period, and the closure's size."""
    args = (scene_at, period_at, steps, y, p)
    g, J = value_and_jacfwd(_closure, argnums=3)(*args)
    return jnp.linalg.solve(J, g), jnp.max(jnp.abs(g))


@functools.partial(jax.jit, static_argnums=2)
def _shooting_gap(scene_at, period_at, steps, y, p):
    return jnp.max(jnp.abs(_closure(scene_at, period_at, steps, y, p)))


@functools.partial(jax.jit, static_argnums=(2, 3, 4))
def _shooting_series(scene_at, period_at, steps, N, H, u, p):
    """The harmonics of the orbits from the states `u` at `p` (vmapped)."""
    def one(u, p):
        ys = flow_samples(scene_at(p), u, period_at(p), steps=steps, n_samples=N)
        return coefficients_from_samples(jnp.roll(ys, 1, axis=0), H)

    return jax.vmap(one)(u, p)


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
    return pc, (_with_floquet(sc, sol) if stability else sol)


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
    ways from the start unless `direction`; `bounds` `((lo1, lo2), (hi1, hi2))`:
    then each parameter is continued relative to its side of the box (`(p - lo) /
    (hi - lo)`: the steps `ds`, `ds_max` are fractions of the box, so that a speed in
    rad/s and a cubic stiffness in N/m^3 weigh alike in the arclength), the points
    and stops given back in the parameters' own units. Returns its `Curve` (rows
    `(u, p1, p2)`, the coefficients scaled)."""
    if period_at2 is None:
        def period_at2(a, b):
            return forcing_period(scene_at2(a, b), subharmonic)
    if bounds is None:
        F, u0, _ = _two_parameter_setup(scene_at2, p, coefficients, period_at2, subharmonic)
        return fold_curve(F, u0, p, ds=ds, ds_max=ds_max, max_points=max_points, tol=tol, direction=direction,
                          names=names)
    lo, hi = (np.asarray(b, dtype=float) for b in bounds)
    side = hi - lo
    if not (lo.shape == hi.shape == (2,) and np.all(np.isfinite(side)) and np.all(side > 0)):
        raise InputError(f"bounds must be ((lo1, lo2), (hi1, hi2)), finite, lo < hi; got {bounds!r}")

    def scaled(f):
        return lambda a, b: f(lo[0] + side[0] * a, lo[1] + side[1] * b)

    x0 = (np.asarray(p, dtype=float) - lo) / side
    F, u0, _ = _two_parameter_setup(scaled(scene_at2), x0, coefficients, scaled(period_at2), subharmonic)
    n = u0.size
    box = (np.concatenate([np.full(n, np.nan), [0.0, 0.0]]), np.concatenate([np.full(n, np.nan), [1.0, 1.0]]))
    c = fold_curve(F, u0, x0, ds=ds, ds_max=ds_max, max_points=max_points, tol=tol, bounds=box,
                   direction=direction, names=names)
    x = np.concatenate([c.x[:, :n], lo + side * c.x[:, n:]], axis=1)
    x[:, n:] = np.where(np.abs(c.x[:, n:]) < 1e-12, lo, np.where(np.abs(c.x[:, n:] - 1) < 1e-12, hi, x[:, n:]))
    t = np.concatenate([c.tangents[:, :n], side * c.tangents[:, n:]], axis=1)
    stops = c.stops
    for k in (0, 1):
        stops = physical_stops(stops, names[k], lambda v, k=k: lo[k] + side[k] * v, lo[k], hi[k])
    stopped = physical_stops((c.stopped,), names[0], lambda v: lo[0] + side[0] * v, lo[0], hi[0])
    stopped = physical_stops(stopped, names[1], lambda v: lo[1] + side[1] * v, lo[1], hi[1])[0]
    return dataclasses.replace(c, x=x, tangents=t / np.linalg.norm(t, axis=1, keepdims=True), stops=stops,
                               stopped=stopped)


def periodic_fold_gradient(scene_at2, p, coefficients, *, period_at2=None, subharmonic=1):
    """`dp1*/dp2`: how the fold of periodic motions at `p = (p1, p2)` (with its
    `coefficients`) moves in `p1` per unit of `p2`, by the implicit function
    theorem on the fold's defining system (`fold_gradient`)."""
    F, u0, _ = _two_parameter_setup(scene_at2, p, coefficients, period_at2, subharmonic)
    return fold_gradient(F, u0, p[0], p[1])


def branch_amplitude_gradient(scene_at2, p, q, coefficients, node=None, *, period_at2=None, subharmonic=1):
    """`d(amplitude)/dq` at every point of a branch of periodic motions in `p`
    (`p` its parameter values, `coefficients` `(points, 2H + 1, n)` as
    `periodic_branch` returns them) at the second parameter's value `q`: how the
    motion's `orbit_amplitude` (of `node`) changes per unit of `q` at fixed `p`, by
    the implicit function theorem on the balance, `dY/dq = -R_Y^{-1} R_q`, one
    linear solve a point, vmapped (compiled once per structure of the scene). It
    grows without bound towards a fold, where `R_Y` is singular. `scene_at2(p, q)`:
    the scene; `period_at2(p, q)`: the period (default the forcing's times
    `subharmonic`)."""
    if period_at2 is None:
        def period_at2(a, b):
            return forcing_period(scene_at2(a, b), subharmonic)
    p, coefficients = jnp.asarray(p, dtype=jnp.float64), jnp.asarray(coefficients, dtype=jnp.float64)
    q = jnp.asarray(q, dtype=jnp.float64)
    shape = coefficients.shape[1:]
    orbit_amplitude(scene_at2(float(p[0]), float(q)), coefficients[0], period_at2(float(p[0]), float(q)),
                    node=node)   # checks node

    def one(a, Y, b):
        def R(y, c):
            return balance_residual(scene_at2(a, c), y.reshape(shape), period_at2(a, c)).ravel()

        def A(y, c):
            return orbit_amplitude(scene_at2(a, c), y.reshape(shape), period_at2(a, c), node=node)

        RY, Rq = jax.jacfwd(R, argnums=(0, 1))(Y.ravel(), b)
        gY, gq = jax.grad(A, argnums=(0, 1))(Y.ravel(), b)
        return gq - gY @ jnp.linalg.solve(RY, Rq)

    qs = jnp.full(p.shape, q)
    return np.asarray(vmapped(lift(one, p[0], coefficients[0], qs[0]), p, coefficients, qs))


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
    # the user's functions lifted (their arrays as arguments): the grid's program is compiled once per
    # structure of the scene, not once per call
    scene_at2, period_at2 = (lift(f, p1[0], p2[0]) for f in (scene_at2, period_at2))
    return _grid(scene_at2, period_at2, Y0, p1, p2, node, None if rows is None else tuple(rows), tol, max_iter)


@functools.partial(jax.jit, static_argnums=(5, 6, 7, 8))
def _grid(scene_at2, period_at2, Y0, p1, p2, node, rows, tol, max_iter):
    """`balance_grid`'s compiled program: a `lax.scan` along `p1` per column, the
    columns vmapped."""
    def column(b):
        def step(Y, a):
            sc = scene_at2(a, b)
            T = period_at2(a, b)
            sol = _solve(sc, Y, T, jnp.asarray(0.0), None, tol, max_iter, None)
            # past a fold the branch swept ends: start again from the guess (the jump). A second
            # solve, from the motion where the first converged (one step there): vmapped, a
            # `lax.cond` would run the restart from the guess at every point
            sol = _solve(sc, jnp.where(sol.code == 0, sol.coefficients, Y0), T, jnp.asarray(0.0), None, tol,
                         max_iter, None)
            amp = orbit_amplitude(sc, sol.coefficients, T, node=node, rows=rows)
            return jnp.where(sol.code == 0, sol.coefficients, Y), (sol.coefficients, sol.code,
                                                                     sol.time_residual, amp)

        return jax.lax.scan(step, Y0, p1)[1]

    return jax.vmap(column)(p2)


#: Hill's physical exponents, compiled once per size
_hill = jax.jit(_physical_exponents, static_argnums=1)


#: parameter values at which `periodic_branch` surveys the motion's size before continuing
SURVEY = 9


def _array_parameter(scene_at):
    """`scene_at` given its parameter as a float64 array: a Python number set into a
    scene is a static leaf of it (`eqx.filter_jit`), and each value that a branch
    solves at alone (its start, each change of harmonics) would compile `_solve`
    again."""
    def at(p):
        return scene_at(jnp.asarray(p, dtype=jnp.float64))

    return at


def _span(lo, hi, p0):
    """The length `L` of the continued range (`max(|p0|, 1)` when unbounded)."""
    span = float(hi) - float(lo)
    return span if np.isfinite(span) and span > 0 else max(abs(float(p0)), 1.0)


#: the survey of a branch's scales solves its motions with at most this many harmonics (the scales are the largest
#: coefficients, the low harmonics'; a start with 16 or 32 would take half a minute)
SURVEY_HARMONICS = 4


def _survey_scale(scene_at, period_at, Y0, lo, hi, condense=False):
    """Each state's largest coefficient over the start and the motions solved from
    it (cut to `SURVEY_HARMONICS`; `condense`: by the condensed balance) at `SURVEY`
    parameter values across a finite range (one vmapped Newton; the ones that do
    not converge are left out), at least 1e-3 of the largest of all."""
    top = jnp.max(jnp.abs(Y0), axis=0)
    if np.isfinite(lo) and np.isfinite(hi):
        ps = jnp.linspace(lo, hi, SURVEY)
        sols = _survey(lift(scene_at, ps[0]), lift(period_at, ps[0]), Y0[:2 * SURVEY_HARMONICS + 1], ps, condense)
        ok = (sols.code == 0)[:, None]
        top = jnp.maximum(top, jnp.max(jnp.where(ok, jnp.max(jnp.abs(sols.coefficients), axis=1), 0.0), axis=0))
    return jnp.maximum(top, 1e-3 * jnp.max(top) + jnp.finfo(jnp.float64).tiny)


@functools.partial(jax.jit, static_argnums=4)
def _survey(scene_at, period_at, Y0, ps, condense):
    """The motions at `ps` from `Y0` (`scene_at`, `period_at` lifted: compiled once
    per structure)."""
    def one(p):
        return _solve(scene_at(p), Y0, period_at(p), jnp.asarray(0.0), None, 1e-10, 30, None, condense)

    return jax.vmap(one)(ps)


#: a crossing pair whose frequency is within this fraction of `w / 2` is a period doubling
PERIOD_DOUBLING_TOL = 1e-3


def _physical(event, physical, w0, period_at):
    """An event of the scaled continuation in physical units (`physical(p, u)`:
    points' coefficients from their unknowns), a crossing pair classified."""
    # a branch point's crossing tangent is in the continuation's scaled unknowns: not carried over
    event = dataclasses.replace(event, u=physical(np.asarray([event.p]), np.asarray(event.u)[None]).ravel(),
                                tangent=None)
    if event.kind == "hopf":
        event = _secondary(event, w0, float(2 * np.pi / period_at(event.p)))
    return event


def _secondary(event, w0, w):
    """A crossing of a complex pair of Hill's exponents (continue_branch's "hopf",
    in units of `w0`) as a period doubling or a Neimark-Sacker bifurcation: the
    exponent's frequency reduced to `[0, w/2]` (each exponent recurs shifted by
    every `k w`). A period doubling is one real multiplier through -1: one exponent
    of frequency `w/2` crosses. Where two cross (`event.crossing`), it is a pair, a
    Neimark-Sacker point, however near `w/2` (a whirl at about half speed on a
    synchronous branch, as oil whirl is)."""
    f = float(np.abs(np.mod(event.frequency * w0 + 0.5 * w, w) - 0.5 * w))
    single = event.crossing is None or event.crossing % 2 == 1
    kind = "period-doubling" if abs(f - 0.5 * w) < PERIOD_DOUBLING_TOL * w and single else "neimark-sacker"
    return dataclasses.replace(event, kind=kind, frequency=f)


def branch_amplitude(scene_at, p, coefficients, node=None, period_at=None, subharmonic=1, truncation=False,
                     periods=None):
    """`orbit_amplitude` at every point of a branch from `periodic_branch`
    (`p` its parameter values, `coefficients` `(points, 2H + 1, n)`), vmapped; with
    `truncation`, also each point's time-domain residual (`PeriodicSolution`'s
    `time_residual`: the truncation error of the harmonics) as a second array.
    `periods`: each point's period (a branch of limit cycles, `limit_cycle_branch`),
    instead of the forcing's (`period_at(p)`, by default the scene's forcing period
    times `subharmonic`)."""
    if period_at is None:
        def period_at(v):
            return forcing_period(scene_at(v), subharmonic)
    p, coefficients = jnp.asarray(p, dtype=jnp.float64), jnp.asarray(coefficients, dtype=jnp.float64)
    if periods is not None:
        periods = jnp.asarray(periods, dtype=jnp.float64)
    orbit_amplitude(scene_at(float(p[0])), coefficients[0], period_at(float(p[0])) if periods is None else periods[0],
                    node=node)   # checks node

    def one(v, Y, *period):
        sc = scene_at(v)
        T = period[0] if period else period_at(v)
        return orbit_amplitude(sc, Y, T, node=node), _time_residual(sc, Y, T, 0.0, None)

    given = () if periods is None else (periods,)
    amp, res = vmapped(lift(one, p[0], coefficients[0], *(g[0] for g in given)), p, coefficients, *given)
    return (np.asarray(amp), np.asarray(res)) if truncation else np.asarray(amp)
