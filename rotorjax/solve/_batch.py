"""Batched integration without lock-step: a buffer of lanes refilled from a queue.

`vmap` over `diffeqsolve` runs every lane until the slowest one is done: a batch of
adaptive solves costs `max(steps)` per lane instead of `mean(steps)` (model 001:
1 900 against 1 180; model 004's contact sweep: 17 700 against 6 000). Here a fixed
number of lanes is advanced instead, each by its own adaptive steps, through
diffrax's public step API (`solver.init/step`, `PIDController.init/adapt_step_size`,
`solver.interpolation_cls` for the saved times): the same solver, controller and
dense output that `simulate` uses, so each point's trajectory is `simulate`'s to the
tolerance (the first step differs: `diffeqsolve` starts at 0.01 whenever `dt0` is
None, as it wraps its terms before the controller's initial-step rule looks at
them; the buffer applies that rule). A round
makes `steps_per_round` steps on every lane, then the lanes whose point is done are
retired (their results written at the point's index) and refilled from the queue of
pending points. Everything, rounds included, is one compiled `lax.while_loop`: a
GPU pays its kernel launches per round, not per step, and a lane waits at most one
round for a new point.
"""

import dataclasses
import functools

import diffrax
import equinox as eqx
import jax
import jax.numpy as jnp
import numpy as np

from .._distributed import on_each_device
from ..models._contract import require
from ..models._validate import InputError, as_count, check_choice
from ._results import MAX_STEPS_REACHED, NONFINITE, SOLVER_FAILURE, SUCCESSFUL, SimulationResult
from ._simulate import _check_inputs, _check_scene, _saveat, _split_span
from ._stiffness import choose_solver
from ._vectorised import Tableau, field_over_lanes, stages, vectorises

#: The batch methods: "auto" ("vectorised" for an explicit Runge-Kutta solver without
#: events, else "buffered"), "vectorised" (this module's buffer, its lanes stepped
#: together as arrays of lanes: `_vectorised.py`), "buffered" (this module's buffer,
#: diffrax's step vmapped over the lanes: any solver, events), "pallas" (one kernel
#: per block of lanes, `_pallas.py`), "vmap" (`simulate` vmapped: lanes in lock-step).
METHODS = ("auto", "vectorised", "buffered", "pallas", "vmap")


class IVP(eqx.Module):
    """An initial-value problem at one grid point: what a function swept by
    `rotorjax.sweep` returns to have the sweep integrate it.

    `scene`, `y0` and `t_span` may vary over the grid (a span per point: a number
    of revolutions at each speed); the output times (None or a count of states
    over each span), solver and tolerances (static fields) are the same for every
    point. `sweep` integrates the whole grid in one buffered batch
    (`simulate_batch`) and returns the batched `SimulationResult`. `events=True`:
    event-located contact switching, as `simulate_events` (scenes with contacts).
    """

    scene: eqx.Module
    y0: jax.Array
    t_span: tuple
    saveat: object = eqx.field(static=True, default=None)
    solver: object = eqx.field(static=True, default="auto")
    rtol: float = eqx.field(static=True, default=1e-8)
    atol: float = eqx.field(static=True, default=1e-10)
    max_steps: int = eqx.field(static=True, default=200_000)
    events: bool = eqx.field(static=True, default=False)


def simulate_batch(scenes, y0s, t_span, saveat=None, solver="auto", rtol: float = 1e-8,
                   atol: float = 1e-10, max_steps: int = 200_000, lanes: int | None = None,
                   steps_per_round: int = 8, method: str = "auto", shard: bool = False,
                   events: bool = False, compiler_options: dict | None = None) -> SimulationResult:
    """Integrate a batch of scenes, each from its own initial state.

    **Arguments:**
    - `scenes`: one scene whose array leaves carry a leading batch axis `N`
      (`eqx.filter_vmap(build)(points)`).
    - `y0s`: initial states, shape `(N, scene.state_size)`.
    - `t_span`, `saveat`, `solver`, `rtol`, `atol`, `max_steps`: as `simulate`, the
      same for every point (`solver="auto"` decides on the first point).
    - `lanes`: how many points are integrated at once (default `min(N, 128)`).
    - `steps_per_round`: steps each lane makes between retirements and refills.
    - `shard`: with several local devices (GPUs, or host CPUs under
      `XLA_FLAGS=--xla_force_host_platform_device_count=K`), give each its own
      buffer of `lanes / devices` lanes and every device-th point ("buffered" only);
      each device runs its own program (see `rotorjax._distributed.on_each_device`).
    - `events`: locate contact switches (scenes with `contact_indicator` and
      `vector_field(t, y, active)`, such as model 004 with limiters): a step that
      crosses one is cut at the crossing (bisection on the dense output), the
      contact set switched and the solver restarted; `stats["num_events"]` counts
      them ("buffered" only).
    - `method`: "vectorised" (lanes refilled from the queue, stepped together as
      arrays of lanes: explicit Runge-Kutta solvers, no events; see
      `_vectorised.py`), "buffered" (lanes refilled from the queue, diffrax's step
      vmapped over them: any solver, events), "auto" (the default: "vectorised"
      where it applies, else "buffered"), "pallas" (the whole adaptive loop of a
      block of lanes in one Pallas kernel; explicit Runge-Kutta, final state only),
      "vmap" (`simulate` vmapped: lanes in lock-step).
    - `compiler_options`: XLA options for the compiled loop ("vectorised" and
      "buffered"), e.g. `{"xla_cpu_use_fusion_emitters": False}`, which
      `floquet_batch` passes on the CPU (see there); each set compiles its own program.

    Array leaves equal at every point (a speed sweep's matrices) enter the compiled
    loop once, without the batch axis ("vectorised" and "buffered"): the lanes'
    vector field applies them to every lane at once.

    **Returns:** a `SimulationResult` whose fields carry the batch axis in front, in
    the order of the points; a failed point is marked by its `code` (see `RESULTS`).
    """
    check_choice("method", method, METHODS)
    program = _program(compiler_option_pairs(compiler_options))
    y0s = _batch_states(scenes, y0s)
    n = y0s.shape[0]
    t0s, t1s = _spans(t_span, n)
    t0, t1 = t0s[0], t1s[0]
    uniform = bool(np.all(t0s == t0) and np.all(t1s == t1))
    scene0 = jax.tree_util.tree_map(lambda a: a[0] if eqx.is_array(a) else a, scenes)
    _check_scene(scene0)
    if y0s.shape[1] != scene0.state_size:
        raise InputError(f"y0s must have shape (N, {scene0.state_size}) for this scene ({scene0.describe()}), "
                         f"got shape {y0s.shape}")
    max_steps = _check_inputs(scene0, y0s[0], t0, t1, rtol, atol, max_steps)
    solver = choose_solver(scene0, y0s[0], t0, solver, t1=t1, rtol=rtol, max_steps=max_steps)
    steps_per_round = as_count("steps_per_round", steps_per_round, minimum=1)
    lanes = min(n, 128) if lanes is None else min(as_count("lanes", lanes, minimum=1), n)
    f64 = lambda v: jnp.asarray(v, dtype=jnp.float64)  # noqa: E731
    if events:
        require(scene0, "contact_indicator", "simulate_batch(events=True)")
        if scene0.n_contacts < 1:
            raise InputError("events: the scene has no contacts (limiters); use events=False")
        if method not in ("auto", "buffered"):
            raise InputError(f"events=True needs method='buffered' (or 'auto'), got method={method!r}")
    if method == "auto":
        method = "vectorised" if vectorises(solver) and not events else "buffered"
    if method == "vectorised" and not vectorises(solver):
        raise InputError(f"method='vectorised' needs an explicit Runge-Kutta solver (dopri8, dopri5, tsit5, ...), "
                         f"got {type(solver).__name__}; use method='buffered'")
    if not uniform and not (saveat is None or isinstance(saveat, (int, np.integer))):
        raise InputError("saveat: with a time span per point give a count of saved states (or None), not times")
    if method == "pallas":
        if not uniform:
            raise InputError("t_span: method='pallas' takes one time span for all points")
        if saveat is not None:
            raise InputError("saveat: method='pallas' returns the final state only; use saveat=None, or "
                             "method='buffered' for saved times")
        from ._pallas import simulate_pallas

        return simulate_pallas(scenes, y0s, (t0, t1), solver=solver, rtol=rtol, atol=atol,
                               max_steps=max_steps)
    if method == "vmap":
        from ._simulate import _solve

        return eqx.filter_vmap(
            lambda sc, y, a, b: _solve(sc, y, a, b, _saveat(saveat, a, b), solver, f64(rtol), f64(atol),
                                       max_steps, None, None))(scenes, y0s, f64(t0s), f64(t1s))
    _saveat(saveat, t0, t1)  # checks
    relative = isinstance(saveat, (int, np.integer)) and not isinstance(saveat, bool)
    final_only = saveat is None
    # output times: absolute, or fractions of each point's span (a count of saved states)
    ts = jnp.ones((1,)) if final_only else jnp.linspace(0.0, 1.0, int(saveat)) if relative else f64(saveat)
    rest = (ts, solver, f64(rtol), f64(atol), jnp.asarray(max_steps))
    static = (steps_per_round, final_only, relative, events, method == "vectorised")
    scenes, shared = _split_shared(scenes)
    devices = jax.local_devices() if shard else []
    if len(devices) < 2 or n < 2:
        return program(scenes, shared, y0s, f64(t0s), f64(t1s), *rest, lanes, *static)
    return _over_devices(program, scenes, shared, y0s, f64(t0s), f64(t1s), rest, lanes, static, devices)


def compiler_option_pairs(compiler_options):
    """`compiler_options` as a sorted tuple of pairs (hashable), checked."""
    if compiler_options is None:
        return ()
    if not isinstance(compiler_options, dict) or not all(
            isinstance(k, str) and isinstance(v, (bool, int, float, str)) for k, v in compiler_options.items()):
        raise InputError(f"compiler_options must be a dict of XLA option names to values (bool, number or "
                         f"string), e.g. {{'xla_cpu_use_fusion_emitters': False}}; got {compiler_options!r}")
    return tuple(sorted(compiler_options.items()))


@functools.lru_cache(maxsize=None)
def _program(options: tuple):
    """The compiled batch loop, with these XLA options (one jitted function per set)."""
    return eqx.filter_jit(_buffered_impl, compiler_options=dict(options)) if options else _buffered


def _split_shared(scenes):
    """`(varying, shared)`: the scene's array leaves that are equal at every point
    (a speed sweep's mass, stiffness and gyroscopic matrices) pass once, without the
    batch axis, so that the lanes' vector field applies them to every lane at once
    (a matrix-matrix product over the lanes, not one matrix-vector product per
    lane); the others keep their batch axis. Leaves being traced stay batched."""
    def same(a):
        if not eqx.is_array(a) or isinstance(a, jax.core.Tracer) or np.ndim(a) == 0:
            return False
        v = np.asarray(a)
        return bool(np.all(v == v[:1]))

    mask = jax.tree_util.tree_map(same, scenes)
    shared, varying = eqx.partition(scenes, mask)
    return varying, jax.tree_util.tree_map(lambda a: a[0], shared)


def _spans(t_span, n):
    """`(t0s, t1s)`, one per point, from a pair of scalars or of length-`n` arrays."""
    t0, t1 = _split_span(t_span)
    out = []
    for name, v in (("t_span[0]", t0), ("t_span[1]", t1)):
        try:
            a = np.asarray(v, dtype=np.float64)
        except (TypeError, ValueError):
            raise InputError(f"{name} must be a number or an array of one per point, got {v!r}") from None
        if a.ndim > 1 or (a.ndim == 1 and a.shape[0] != n):
            raise InputError(f"{name} must be a number or an array of {n} (one per point), got shape {a.shape}")
        if not np.all(np.isfinite(a)):
            raise InputError(f"{name} must be finite, got {a}")
        out.append(np.broadcast_to(a, (n,)))
    bad = np.flatnonzero(~(out[1] > out[0]))
    if bad.size:
        i = int(bad[0])
        raise InputError(f"t_span must be increasing (t1 > t0), got ({out[0][i]}, {out[1][i]}) at point {i}")
    return out


def _over_devices(program, scenes, shared, y0s, t0s, t1s, rest, lanes, static, devices):
    """`run` on each local device with its own buffer, as its own program (see
    `on_each_device`): point `i` goes to device `i mod D` (neighbouring points cost
    alike, so the devices share the work evenly); padded with the last point, results
    put back in order."""
    n, d = y0s.shape[0], min(len(devices), y0s.shape[0])
    per = -(-n // d)
    order = np.minimum(np.arange(per * d).reshape(per, d).T.reshape(-1), n - 1)
    share = lambda a, i: a[order[i * per:(i + 1) * per]] if eqx.is_array(a) else a  # noqa: E731
    parts = [(jax.tree_util.tree_map(lambda a: share(a, i), scenes), shared, share(y0s, i), share(t0s, i),
              share(t1s, i), *rest, min(-(-lanes // d), per), *static) for i in range(d)]
    outs = on_each_device(program, parts)
    back = np.argsort(order, kind="stable")[:n]  # the first copy of each point
    return jax.tree_util.tree_map(lambda *xs: jnp.asarray(np.concatenate(xs, axis=0)[back]), *outs)


def _batch_states(scenes, y0s):
    try:
        y0s = jnp.asarray(y0s, dtype=jnp.float64)
    except (TypeError, ValueError):
        raise InputError("y0s must be an array of initial states, shape (N, state_size)") from None
    if y0s.ndim != 2:
        raise InputError(f"y0s must have shape (N, state_size), got shape {y0s.shape}")
    sizes = {np.shape(a)[0] if np.ndim(a) else None for a in jax.tree_util.tree_leaves(scenes)
             if eqx.is_array(a)}
    if sizes != {y0s.shape[0]}:
        raise InputError(f"scenes must carry the batch axis N = {y0s.shape[0]} (len(y0s)) in front of every "
                         f"array (build them with eqx.filter_vmap), got leading sizes {sorted(map(str, sizes))}")
    return y0s


def _with_tolerances(solver, controller):
    """An implicit solver's root finder takes the step-size controller's tolerances
    where it asks for them, as in `diffeqsolve`."""
    if not isinstance(solver, diffrax.AbstractImplicitSolver):
        return solver
    from diffrax._root_finder import use_stepsize_tol

    names = [a for a in ("rtol", "atol", "norm") if getattr(solver.root_finder, a) is use_stepsize_tol]
    return eqx.tree_at(lambda s: [getattr(s.root_finder, a) for a in names], solver,
                       [getattr(controller, a) for a in names])


class _Lanes(eqx.Module):
    """The buffer: one row per lane (`idx == N` marks an empty lane)."""

    idx: jax.Array
    scene: eqx.Module
    active: jax.Array
    t0: jax.Array
    t1: jax.Array
    t: jax.Array
    tnext: jax.Array
    y: jax.Array
    solver_state: object
    controller_state: object
    made_jump: jax.Array
    save_i: jax.Array
    steps: jax.Array
    accepted: jax.Array
    rejected: jax.Array
    result: jax.Array
    events: jax.Array


def _lane_field(t, y, args):
    scene, active = args
    return scene.vector_field(t, y, active) if active.shape[0] else scene.vector_field(t, y)


def _buffered_impl(scenes, shared, y0s, t0s, t1s, ts, solver, rtol, atol, max_steps, lanes, steps_per_round,
                   final_only, relative, events, vectorised):
    n, n_save = y0s.shape[0], ts.shape[0]
    term = diffrax.ODETerm(_lane_field)
    controller = diffrax.PIDController(rtol=rtol, atol=atol)
    solver = _with_tolerances(solver, controller)
    order = solver.error_order(term)
    arrays, static = eqx.partition(scenes, eqx.is_array)
    ok = diffrax.RESULTS.successful
    whole = lambda scene_arrays: eqx.combine(scene_arrays, shared, static)  # noqa: E731
    if vectorised:
        tableau = Tableau(solver)
        lanes_field = field_over_lanes(lambda a, t, y: whole(a).vector_field(t, y))

    def signed(scene_arrays, active, t, y):
        """+g while a contact is open, -g while closed: a switch is an up-crossing."""
        g = whole(scene_arrays).contact_indicator(t, y)
        return jnp.where(active, -1.0, 1.0) * g

    def start(scene_arrays, y0, t0, t1):
        scene = whole(scene_arrays)
        active = scene.contact_indicator(t0, y0) > 0 if events else jnp.zeros((0,), bool)
        tnext, cstate = controller.init(term, t0, t1, y0, None, (scene, active), solver.func, order)
        tnext = jnp.minimum(tnext, t1)
        if vectorised:  # the carried first stage (first-same-as-last), or nothing
            sstate = scene.vector_field(t0, y0) if tableau.fsal else jnp.zeros((0,))
        else:
            sstate = solver.init(term, t0, tnext, y0, (scene, active))
        return tnext, sstate, cstate, active

    def control(t1, t, tnext, y, y1, yerr, cstate):
        """The controller's verdict on a step from `t` to `tnext`, its next step clipped
        to end at `t1`."""
        yerr = jnp.where(jnp.isnan(yerr), jnp.inf, yerr)
        keep, tprev, tn, mj, cstate1, cres = controller.adapt_step_size(t, tnext, y, y1, None, yerr, order, cstate)
        tprev = jnp.minimum(tprev, t1)
        clip = tn > jnp.nextafter(t1, -jnp.inf)
        tn = jnp.where(clip, jnp.where(keep, t1, tprev + 0.5 * (t1 - tprev)), tn)
        return keep, tprev, tn, mj, cstate1, cres

    def step(scene_arrays, active, t1, t, tnext, y, sstate, cstate, made_jump):
        args = (whole(scene_arrays), active)
        y1, yerr, dense, sstate1, sres = solver.step(term, t, tnext, y, args, sstate, made_jump)
        keep, tprev, tn, mj, cstate1, cres = control(t1, t, tnext, y, y1, yerr, cstate)
        pick = lambda a, b: jnp.where(keep, a, b)  # noqa: E731
        # 0: fine, 1: the step-size controller's failure, 2: the solver's (not `code`)
        result = jnp.where(keep & (sres != ok), 2, jnp.where(cres != ok, 1, 0))
        return (tprev, tn, pick(y1, y), jax.tree_util.tree_map(pick, sstate1, sstate), cstate1,
                pick(mj, made_jump), keep, dense, y1, result)

    def step_lanes(lanes_):
        """Every lane's step: diffrax's, vmapped, or the vectorised stepper's."""
        if not vectorised:
            return jax.vmap(step)(lanes_.scene, lanes_.active, lanes_.t1, lanes_.t, lanes_.tnext, lanes_.y,
                                  lanes_.solver_state, lanes_.controller_state, lanes_.made_jump)
        scene_t = jax.tree_util.tree_map(lambda a: jnp.moveaxis(a, 0, -1), lanes_.scene)
        f0 = lanes_.solver_state if tableau.fsal else None
        y1, yerr, k, f1 = stages(tableau, lanes_field, scene_t, lanes_.t, lanes_.tnext - lanes_.t, lanes_.y, f0)

        def finish(t1, t, tnext, y, y1, yerr, f0, f1, cstate, made_jump):
            keep, tprev, tn, mj, cstate1, cres = control(t1, t, tnext, y, y1, yerr, cstate)
            pick = lambda a, b: jnp.where(keep, a, b)  # noqa: E731
            return tprev, tn, pick(y1, y), pick(f1, f0), cstate1, pick(mj, made_jump), keep, jnp.where(cres != ok, 1, 0)

        f1 = lanes_.solver_state if f1 is None else f1
        t, tn, y, ss, cs, mj, keep, result = jax.vmap(finish)(
            lanes_.t1, lanes_.t, lanes_.tnext, lanes_.y, y1, yerr, lanes_.solver_state, f1, lanes_.controller_state,
            lanes_.made_jump)
        return t, tn, y, ss, cs, mj, keep, dict(y0=lanes_.y, y1=y1, k=k), y1, result

    def evaluate(t_a, t_b, dense, y_b, t):
        y_t = solver.interpolation_cls(t0=t_a, t1=t_b, **dense).evaluate(t)
        return jnp.where(t == t_b, y_b, y_t)

    def switch(lanes_, accepted, t_a, t_b, dense, y_b):
        """Lanes whose accepted step crossed a contact switch: cut the step at the
        first crossing (bisection on the dense output, to rounding), switch the
        contact set there and restart the solver (`made_jump`) with the same step."""
        crossed = accepted & jnp.any(jax.vmap(signed)(lanes_.scene, lanes_.active, lanes_.t, lanes_.y) > 0,
                                     axis=1)

        def locate(scene_arrays, active, t_a, t_b, dense, y_b):
            h = lambda t: jnp.max(signed(scene_arrays, active, t, evaluate(t_a, t_b, dense, y_b, t)))  # noqa: E731

            def halve(_, c):
                lo, hi = c
                mid = 0.5 * (lo + hi)
                up = h(mid) > 0
                return jnp.where(up, lo, mid), jnp.where(up, mid, hi)

            _, hit = jax.lax.fori_loop(0, 64, halve, (t_a, t_b))
            y_hit = evaluate(t_a, t_b, dense, y_b, hit)
            return hit, y_hit, active ^ (signed(scene_arrays, active, hit, y_hit) > 0)

        t_hit, y_hit, active = jax.lax.cond(  # located only when some lane crossed
            jnp.any(crossed), lambda: jax.vmap(locate)(lanes_.scene, lanes_.active, t_a, t_b, dense, y_b),
            lambda: (lanes_.t, lanes_.y, lanes_.active))
        c1 = crossed[:, None]
        # the next step's size: the controller's proposal, or (when the crossed step
        # ended at t1, where the proposal is clipped to nothing) the crossed step's size
        dt = jnp.where(lanes_.tnext > lanes_.t, lanes_.tnext - lanes_.t, t_b - t_a)
        return dataclasses.replace(
            lanes_, t=jnp.where(crossed, t_hit, lanes_.t), y=jnp.where(c1, y_hit, lanes_.y),
            active=jnp.where(c1, active, lanes_.active), made_jump=lanes_.made_jump | crossed,
            tnext=jnp.where(crossed, jnp.minimum(t_hit + dt, lanes_.t1), lanes_.tnext),
            events=lanes_.events + jnp.where(crossed, 1, 0))

    def time(lanes_, k):
        """The lanes' `k`-th output times (`k` one per lane)."""
        if not relative:
            return ts[k]
        a, b = lanes_.t0, lanes_.t1
        return jnp.where(k == n_save - 1, b, a + (b - a) * ts[k])

    def running(lanes_):
        return ((lanes_.idx < n) & (lanes_.t < lanes_.t1) & (lanes_.steps < max_steps)
                & (lanes_.result == 0))

    def save_due(ys, lanes_, reached, value):
        """Write every output time `<= reached` not yet saved; `value(k)` gives the
        lanes' states at their output times `k`."""
        def due(save_i):
            return (lanes_.idx < n) & (save_i < n_save) & (time(lanes_, jnp.minimum(save_i, n_save - 1)) <= reached)

        def body(c):
            ys, save_i = c
            d = due(save_i)
            k = jnp.minimum(save_i, n_save - 1)
            ys = ys.at[jnp.where(d, lanes_.idx, n), k].set(value(k))
            return ys, save_i + d

        return jax.lax.while_loop(lambda c: jnp.any(due(c[1])), body, (ys, lanes_.save_i))

    def advance(_, c):
        lanes_, ys = c
        live = running(lanes_)
        t_old, tnext_old = lanes_.t, lanes_.tnext
        (t, tn, y, ss, cs, mj, keep, dense, y1, result) = step_lanes(lanes_)
        sel = lambda a, b: jnp.where(live.reshape(live.shape + (1,) * (a.ndim - 1)), a, b)  # noqa: E731
        new = dataclasses.replace(
            lanes_, t=t, tnext=tn, y=y, solver_state=ss, controller_state=cs, made_jump=mj,
            steps=lanes_.steps + 1, accepted=lanes_.accepted + jnp.where(keep, 1, 0),
            rejected=lanes_.rejected + jnp.where(keep, 0, 1), result=result)
        new = jax.tree_util.tree_map(sel, new, lanes_)
        if events:
            new = switch(new, live & keep, t_old, tnext_old, dense, y1)
        if final_only:  # written at retirement
            return new, ys
        reached = jnp.where(live & keep, new.t, -jnp.inf)
        value = lambda k: jax.vmap(evaluate)(t_old, tnext_old, dense, y1, time(new, k))  # noqa: E731
        ys, save_i = save_due(ys, new, reached, value)
        return dataclasses.replace(new, save_i=save_i), ys

    def refill(c):
        lanes_, ys, out, next_point, retired = c
        finished = (lanes_.idx < n) & ~running(lanes_)
        target = jnp.where(finished, lanes_.idx, n)
        finite = jnp.all(jnp.isfinite(lanes_.y), axis=1)
        code = jnp.where(lanes_.result == 0, jnp.where(lanes_.t < lanes_.t1, MAX_STEPS_REACHED,
                                                     jnp.where(finite, SUCCESSFUL, NONFINITE)),
                         SOLVER_FAILURE).astype(jnp.int32)
        values = {"code": code, "num_steps": lanes_.steps, "num_accepted_steps": lanes_.accepted,
                  "num_rejected_steps": lanes_.rejected, "num_events": lanes_.events}
        out = {k: v.at[target].set(values[k]) for k, v in out.items()}  # the dump row n for the others
        if final_only:
            ys = ys.at[target, 0].set(jnp.where((lanes_.t >= lanes_.t1)[:, None], lanes_.y, jnp.inf))
        free = finished | (lanes_.idx >= n)
        new_idx = next_point + jnp.cumsum(free) - 1
        take = free & (new_idx < n)
        idx = jnp.where(take, new_idx, jnp.where(finished, n, lanes_.idx))
        fresh = _fresh(take, jnp.minimum(new_idx, n - 1), lanes_, idx)
        if not final_only:
            ys, save_i = save_due(ys, fresh, jnp.where(take, fresh.t0, -jnp.inf), lambda k: fresh.y)
            fresh = dataclasses.replace(fresh, save_i=save_i)
        return fresh, ys, out, next_point + jnp.sum(take), retired + jnp.sum(finished)

    def _fresh(take, points, lanes_, idx):
        scene_arrays = jax.tree_util.tree_map(lambda a: a[points], arrays)
        y0 = y0s[points]
        t0, t1 = t0s[points], t1s[points]
        tnext, ss, cs, active = jax.vmap(start)(scene_arrays, y0, t0, t1)
        zeros = jnp.zeros_like(lanes_.steps)
        started = _Lanes(idx=idx, scene=scene_arrays, active=active, t0=t0, t1=t1, t=t0,
                         tnext=tnext, y=y0, solver_state=ss, controller_state=cs,
                         made_jump=jnp.zeros_like(lanes_.made_jump), save_i=zeros, steps=zeros, accepted=zeros,
                         rejected=zeros, result=jnp.zeros_like(lanes_.result), events=zeros)
        sel = lambda a, b: jnp.where(take.reshape(take.shape + (1,) * (a.ndim - 1)), a, b)  # noqa: E731
        merged = jax.tree_util.tree_map(sel, started, lanes_)
        return dataclasses.replace(merged, idx=idx)

    def round_(c):
        lanes_, ys, out, next_point, retired = c
        lanes_, ys = jax.lax.fori_loop(0, steps_per_round, advance, (lanes_, ys))
        return refill((lanes_, ys, out, next_point, retired))

    # An empty buffer (every lane "finished" at point n), then the first fill.
    first = jnp.zeros((lanes,), dtype=jnp.int32)
    tnext, ss, cs, active = jax.vmap(start)(jax.tree_util.tree_map(lambda a: a[first], arrays), y0s[first],
                                            t0s[first], t1s[first])
    zeros = jnp.zeros((lanes,), dtype=jnp.int32)
    empty = _Lanes(idx=jnp.full((lanes,), n, dtype=jnp.int32), scene=jax.tree_util.tree_map(lambda a: a[first], arrays),
                   active=active, t0=t0s[first], t1=t1s[first], t=t0s[first], tnext=tnext, y=y0s[first], solver_state=ss,
                   controller_state=cs, made_jump=jnp.zeros((lanes,), bool), save_i=zeros, steps=zeros,
                   accepted=zeros, rejected=zeros, result=zeros, events=zeros)
    ys = jnp.full((n + 1, n_save, y0s.shape[1]), jnp.inf)
    counts = ("num_steps", "num_accepted_steps", "num_rejected_steps") + (("num_events",) if events else ())
    out = {k: jnp.zeros((n + 1,), dtype=jnp.int32) for k in ("code",) + counts}
    c = refill((empty, ys, out, jnp.asarray(0), jnp.asarray(0)))
    _, ys, out, _, _ = jax.lax.while_loop(lambda c: c[4] < n, round_, c)
    ys = ys[:n]
    if final_only:
        ts_all = t1s[:, None]
    elif relative:  # the times `time` saved at
        last = jnp.arange(n_save) == n_save - 1
        ts_all = jnp.where(last, t1s[:, None], t0s[:, None] + (t1s - t0s)[:, None] * ts[None, :])
    else:
        ts_all = jnp.broadcast_to(ts, (n, n_save))
    outputs = jax.vmap(lambda a, t, y: jax.vmap(whole(a).outputs)(t, y))(arrays, ts_all, ys)
    stats = {k: out[k][:n] for k in counts}
    return SimulationResult(ts=ts_all, ys=ys, outputs=outputs, code=out["code"][:n], stats=stats,
                            solver=type(solver).__name__ + ("+vectorised" if vectorised else "+buffered"))


_buffered = eqx.filter_jit(_buffered_impl)
