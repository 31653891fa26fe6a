"""A whole adaptive Runge-Kutta integration per trajectory in one Pallas kernel.

The design of DiffEqGPU.jl's `EnsembleGPUKernel`: one trajectory per lane, and the
whole adaptive loop (stages, error estimate, step-size control, accept/reject,
clipping to `t1`) inside ONE kernel launch, so that a batch of scenes costs one
launch instead of one host round trip (or one XLA while-loop iteration over the
whole batch) per step.

Layout: the batch (N scenes, padded to a multiple of `block` with copies of the last
lane) is cut into blocks of `block` lanes, one grid program per block. Per lane (axis
0 of every kernel array): the scene's parameters (every array leaf of the scene pytree
is its own kernel input), `t`, `tnext` (so `h = tnext - t`), `y`, the FSAL derivative,
the step counters, the result code and a done flag. Per block: one `lax.while_loop`
that runs while any lane of the block is not done (done lanes hold their values), and
two small inputs every program reads whole: the Butcher coefficients and the scalars
`t0, t1, rtol, atol, max_steps` (arrays, so new values do not recompile).

The numerics reproduce `diffrax.diffeqsolve(..., stepsize_controller=
diffrax.PIDController(rtol, atol))` with its defaults (I controller, safety 0.9,
factor in [0.2, 10], RMS norm of `err / (atol + rtol max(|y0|, |y1|))`, strict
`norm < 1` acceptance, its rounding of `tnext` to `t1` within 100 ULPs and halving
towards `t1` after a rejected clipped step), and the stage combinations are the same
XLA dot as diffrax's, so on model 001 the accepted and rejected step counts equal
those of `rotorjax.simulate` exactly (the error estimate of a smooth step is largely
rounding, so any other summation order shifts a few decisions). First step: diffrax
0.7.2's `diffeqsolve` never reaches `_select_initial_step`'s algorithm (its terms are
wrapped, so the `isinstance(terms, ODETerm)` check fails) and starts every ODE with
`dt0 = 0.01`; the kernel does what the installed diffrax does (a cached one-step probe,
`diffrax_selects_first_step`) and carries its own copy of the algorithm for diffrax
versions that use it. The tableau is read from the diffrax solver (any explicit RK
with an error estimate: Dopri5, Dopri8, Tsit5, ...). FSAL tableaus reuse the last
stage's derivative, as diffrax does.

Only Pallas interpret mode (`interpret=True`, the kernel run as ordinary JAX ops) has
been run and tested, on CPU. On a GPU the kernel would be compiled (Triton or Mosaic
GPU), which has NOT been tried. What would likely need to change there: the scene's
vector field must lower (elementwise float64 arithmetic and small reductions; no
`linalg.solve`, gathers or scatters); every block dimension must be a power of two
(the lane block, the state size and each parameter leaf's trailing shape: pad them);
the stage combinations would be unrolled multiply-adds instead of a dot over a
`(stages, block, n)` buffer (Triton dots want >= 16 x 16 tiles; the unrolled form no
longer matches diffrax's rounding bit for bit, only within a step or two); and float64
throughput on the device decides whether it pays.
"""

import functools
from typing import NamedTuple

import diffrax
import equinox as eqx
import jax
import jax.numpy as jnp
import jax.tree_util as jtu
import numpy as np
from jax import lax
from jax.experimental import pallas as pl

from ..models._contract import AbstractScene
from ..models._validate import InputError, as_count, as_numpy, is_concrete, show
from ._results import SimulationResult
from ._stiffness import choose_solver

# PIDController defaults (pcoeff=0, icoeff=1, dcoeff=0).
_SAFETY, _FACTORMIN, _FACTORMAX = 0.9, 0.2, 10.0
# A step proposal below this fraction of max(|t|, t1 - t0) counts as collapsed (code 3).
_COLLAPSE = 1e-14
# Order of the packed scalar parameters (one small kernel input shared by all blocks).
_T0, _T1, _T1_FLOOR, _RTOL, _ATOL, _MAX_STEPS = range(6)
_N_PARAMS = 8


class _Tableau(NamedTuple):
    """An explicit Butcher tableau as numpy data (compile-time constants), the lower
    triangle embedded in a square matrix as diffrax does."""

    a: np.ndarray  # (s, s): row i holds the coefficients of stages < i
    c: tuple  # c[i] for stage i (c[0] = c1 = 0)
    b_sol: np.ndarray
    b_error: np.ndarray
    ssal: bool
    fsal: bool

    @property
    def num_stages(self) -> int:
        return len(self.b_sol)


def explicit_tableau(solver) -> _Tableau:
    """The tableau of an explicit diffrax Runge-Kutta `solver` (diffrax's
    `ButcherTableau` layout: `c` and `a_lower` start at the second stage).

    **Arguments:**
    - `solver`: a diffrax solver instance.

    **Returns:** a `_Tableau`. Raises `InputError` naming `solver` for implicit or
    non-Runge-Kutta solvers and for tableaus without an error estimate.
    """
    tab = solver.tableau if isinstance(solver, diffrax.AbstractERK) else None
    name = type(solver).__name__
    if not isinstance(tab, diffrax.ButcherTableau):
        raise InputError(f"solver must be an explicit diffrax Runge-Kutta solver with a Butcher "
                         f"tableau (Dopri5, Dopri8, Tsit5, ...) for the Pallas kernel, got {name}")
    if tab.implicit or not isinstance(solver, diffrax.AbstractERK):
        raise InputError(f"solver must be an explicit Runge-Kutta solver (Dopri5, Dopri8, Tsit5, "
                         f"...) for the Pallas kernel, got the implicit {name}")
    if tab.b_error is None or not np.any(np.asarray(tab.b_error)):
        raise InputError(f"solver {name} has no error estimate: adaptive steps need one")
    s = tab.num_stages
    a = np.zeros((s, s))
    for i, row in enumerate(tab.a_lower):
        a[i + 1, : i + 1] = row
    return _Tableau(
        a=a,
        c=(float(tab.c1),) + tuple(float(x) for x in tab.c),
        b_sol=np.asarray(tab.b_sol, dtype=np.float64),
        b_error=np.asarray(tab.b_error, dtype=np.float64),
        ssal=bool(tab.ssal),
        fsal=bool(tab.fsal),
    )


def _rms(x):
    """Per-lane RMS norm over the last axis (optimistix.rms_norm on each lane)."""
    n = x.shape[-1]
    if n == 1:
        return jnp.abs(x[..., 0])
    return jnp.sqrt(jnp.sum(x * x, axis=-1)) / np.sqrt(n)


def _coefficients(tab) -> np.ndarray:
    """The tableau's coefficients as one `(s + 2, s)` array: rows `0..s-1` the embedded
    `a`, row `s` `b_sol`, row `s + 1` `b_error` (a kernel input: Pallas kernels may not
    capture array constants)."""
    return np.concatenate([tab.a, tab.b_sol[None], tab.b_error[None]], axis=0)


def _dot(coeffs, ks):
    """`sum_i coeffs[i] ks[i]` over the stage axis, as diffrax's `vector_tree_dot` (the
    same XLA dot, so the same rounding: the error estimate of a smooth step is mostly
    rounding, and the accept/reject decisions follow it)."""
    return jnp.tensordot(coeffs, ks, axes=1, precision=lax.Precision.HIGHEST)


@functools.cache
def diffrax_selects_first_step() -> bool:
    """Whether `diffrax.diffeqsolve(..., dt0=None)` chooses its first ODE step with
    `_select_initial_step`'s algorithm (True) or takes its fallback `dt0 = 0.01`
    (False). diffrax 0.7.2 wraps the terms (`WrapTerm`) before the controller's
    `isinstance(terms, ODETerm)` check, so it always takes 0.01; a one-step probe
    solve (cached) tells which, so that the kernel follows the installed diffrax."""
    with jax.ensure_compile_time_eval():  # concrete even when first asked under a trace
        sol = diffrax.diffeqsolve(
            diffrax.ODETerm(lambda t, y, args: -y), diffrax.Dopri5(), 0.0, 1.0, None,
            jnp.ones(1, dtype=jnp.float64), saveat=diffrax.SaveAt(steps=True),
            stepsize_controller=diffrax.PIDController(rtol=1e-3, atol=1e-6), max_steps=1,
            throw=False,
        )
        return float(sol.ts[0]) != 0.01


def _initial_step(field, t0, y0, f0, rtol, atol, error_order):
    """diffrax's `_select_initial_step` (Hairer, Norsett, Wanner II.4), per lane."""
    scale = atol + jnp.abs(y0) * rtol
    d0 = _rms(y0 / scale)
    d1 = _rms(f0 / scale)
    small = (d0 < 1e-5) | (d1 < 1e-5)
    h0 = jnp.where(small, 1e-6, 0.01 * (d0 / jnp.where(small, 1.0, d1)))
    f1 = field(t0 + h0, y0 + h0[:, None] * f0)
    d2 = _rms((f1 - f0) / scale) / h0
    max_d = jnp.maximum(d1, d2)
    h1 = jnp.where(max_d <= 1e-15, jnp.maximum(1e-6, h0 * 1e-3),
                   (0.01 / max_d) ** (1.0 / error_order))
    return jnp.minimum(100 * h0, h1)


def _rk_step(field, tab, coeffs, t, tnext, y, f_first):
    """One explicit RK step for every lane: `(y1, y_error, f_last)` as diffrax computes
    them (`k_i = f_i dt` in a zero-initialised stage buffer; stage time `t1` where
    `c_i == 1`; `y1` is the last stage's input for SSAL tableaus). `coeffs` is
    `_coefficients(tab)` as an array."""
    s = tab.num_stages
    dt = tnext - t
    ks = jnp.zeros((s,) + y.shape, y.dtype)
    yi, fi = y, f_first
    for i in range(s):
        if i > 0:
            yi = y + _dot(coeffs[i], ks)
            ti = tnext if tab.c[i] == 1.0 else t + tab.c[i] * dt
            fi = field(ti, yi)
        ks = ks.at[i].set(fi * dt[:, None])
    y1 = yi if tab.ssal else y + _dot(coeffs[s], ks)
    err = _dot(coeffs[s + 1], ks)
    err = jnp.where(jnp.isnan(err), jnp.inf, err)
    return y1, err, fi


def _integrate_block(field, tab, coeffs, error_order, select_first, params, y0):
    """The adaptive integration of one block of lanes (traced inside the kernel).

    **Arguments:**
    - `field`: `(t (B,), y (B, n)) -> dy/dt (B, n)`, the lanes' vector fields.
    - `tab`: the `_Tableau`; `coeffs`: `_coefficients(tab)` as an array;
      `error_order`: the solver's error order (a float).
    - `select_first`: choose the first step by `_initial_step` (else 0.01, see
      `diffrax_selects_first_step`).
    - `params`: the packed scalars (`t0, t1, t1_floor, rtol, atol, max_steps`; the
      last is the per-lane budget of accepted plus rejected steps).
    - `y0`: `(B, n)` initial states.

    **Returns:** `(t, y, code, num_steps, num_accepted, num_rejected)`, per lane.
    """
    t0, t1, t1_floor = params[_T0], params[_T1], params[_T1_FLOOR]
    rtol, atol, max_steps = params[_RTOL], params[_ATOL], params[_MAX_STEPS]
    lanes = y0.shape[0]
    t = jnp.full((lanes,), t0)
    f0 = field(t, y0)
    if select_first:
        dt0 = _initial_step(field, t, y0, f0, rtol, atol, error_order)
    else:
        dt0 = jnp.full((lanes,), 0.01)
    tnext = jnp.minimum(t0 + dt0, t1)
    zeros = jnp.zeros((lanes,), jnp.int32)
    done = jnp.zeros((lanes,), bool)
    state = (t, tnext, y0, f0, zeros, zeros, zeros, zeros, done)

    def cond(state):
        return jnp.any(~state[-1])

    def body(state):
        t, tnext, y, f, steps, acc, rej, code, done = state
        f_first = f if tab.fsal else field(t, y)
        bad_field = ~jnp.all(jnp.isfinite(f_first), axis=-1)
        y1, err, f_last = _rk_step(field, tab, coeffs, t, tnext, y, f_first)
        # diffrax's PIDController.adapt_step_size with its defaults.
        y1_scale = jnp.where(jnp.any(jnp.isnan(y1), axis=-1, keepdims=True), y, y1)
        norm = _rms(err / (atol + jnp.maximum(jnp.abs(y), jnp.abs(y1_scale)) * rtol))
        keep = norm < 1
        factor = jnp.clip(_SAFETY * (1 / norm) ** (1.0 / error_order),
                          jnp.where(keep, 1.0, _FACTORMIN), jnp.where(keep, _FACTORMAX, _SAFETY))
        dt = (tnext - t) * factor
        new_t = jnp.where(keep, tnext, t)
        new_tnext = new_t + dt
        # diffrax's book-keeping: clip to t1, round to t1 within 100 ULPs.
        new_t = jnp.minimum(new_t, t1)
        clip = new_tnext > t1_floor
        new_tnext = jnp.where(clip, jnp.where(keep, t1, new_t + 0.5 * (t1 - new_t)), new_tnext)
        new_y = jnp.where(keep[:, None], y1, y)
        new_f = jnp.where(keep[:, None], f_last, f) if tab.fsal else f
        # Lane outcomes (a lane stops with the first one that applies).
        live = ~done & ~bad_field
        new_steps = steps + live
        finished = new_t >= t1
        collapsed = ~(dt > _COLLAPSE * jnp.maximum(jnp.abs(new_t), t1 - t0))  # also NaN
        new_code = jnp.where(bad_field, 2, jnp.where(finished, 0, jnp.where(
            collapsed, 3, jnp.where(new_steps >= max_steps, 1, 0))))
        stop = bad_field | finished | collapsed | (new_steps >= max_steps)
        hold = lambda new, old: jnp.where(  # noqa: E731
            (live if new.ndim == 1 else live[:, None]), new, old)
        return (
            hold(new_t, t), hold(new_tnext, tnext), hold(new_y, y), hold(new_f, f),
            new_steps, acc + (live & keep), rej + (live & ~keep),
            jnp.where(done, code, new_code).astype(jnp.int32), done | stop,
        )

    t, _, y, _, steps, acc, rej, code, _ = lax.while_loop(cond, body, state)
    return t, y, code, steps, acc, rej


def _kernel(treedef, static, tab, error_order, select_first, n_leaves, params_ref, coeffs_ref,
            y0_ref, *refs):
    """The Pallas kernel: one grid program integrates one block of lanes."""
    leaf_refs, out_refs = refs[:n_leaves], refs[n_leaves:]
    scenes = eqx.combine(jtu.tree_unflatten(treedef, [r[...] for r in leaf_refs]), static)
    vf = eqx.filter_vmap(lambda sc, t, y: sc.vector_field(t, y))

    def field(t, y):
        return vf(scenes, t, y)

    outs = _integrate_block(field, tab, coeffs_ref[...], error_order, select_first,
                            params_ref[...], y0_ref[...])
    for ref, value in zip(out_refs, outs):
        ref[...] = value.astype(ref.dtype)


def _lane_spec(block, shape):
    """`block` lanes along axis 0, the whole of the other axes."""
    rest = len(shape) - 1
    return pl.BlockSpec((block,) + tuple(shape[1:]), lambda i: (i,) + (0,) * rest)


def _pad(x, n_pad):
    """Pad axis 0 by repeating the last lane (padded lanes integrate a real scene)."""
    if n_pad == 0:
        return x
    return jnp.concatenate([x, jnp.repeat(x[-1:], n_pad, axis=0)], axis=0)


@eqx.filter_jit
def _run(scenes, y0s, t0, t1, rtol, atol, max_steps, solver, block, interpret, select_first):
    tab = explicit_tableau(solver)
    error_order = float(solver.error_order(diffrax.ODETerm(lambda t, y, args: y)))
    dynamic, static = eqx.partition(scenes, eqx.is_array)
    leaves, treedef = jtu.tree_flatten(dynamic)
    n_lanes, n = y0s.shape
    n_pad = (-n_lanes) % block
    padded = [_pad(x, n_pad) for x in leaves]
    y0p = _pad(y0s, n_pad)
    total = n_lanes + n_pad
    t1_floor = t1
    for _ in range(100):  # diffrax rounds tnext to t1 within 100 ULPs
        t1_floor = jnp.nextafter(t1_floor, -jnp.inf)
    params = jnp.zeros(_N_PARAMS).at[:6].set(
        jnp.stack([t0, t1, t1_floor, rtol, atol, max_steps]))
    kernel = lambda *refs: _kernel(treedef, static, tab, error_order, select_first,  # noqa: E731
                                   len(leaves), *refs)
    coeffs = jnp.asarray(_coefficients(tab))
    lane = lambda dtype: jax.ShapeDtypeStruct((total,), dtype)  # noqa: E731
    t, y, code, steps, acc, rej = pl.pallas_call(
        kernel,
        grid=(total // block,),
        in_specs=[pl.BlockSpec((_N_PARAMS,), lambda i: (0,)),
                  pl.BlockSpec(coeffs.shape, lambda i: (0, 0)), _lane_spec(block, y0p.shape)]
        + [_lane_spec(block, x.shape) for x in padded],
        out_specs=[_lane_spec(block, (total,)), _lane_spec(block, (total, n))]
        + [_lane_spec(block, (total,))] * 4,
        out_shape=[lane(jnp.float64), jax.ShapeDtypeStruct((total, n), jnp.float64)]
        + [lane(jnp.int32)] * 4,
        interpret=interpret,
    )(params, coeffs, y0p, *padded)
    t, y, code = t[:n_lanes], y[:n_lanes], code[:n_lanes]
    code = jnp.where((code == 0) & ~jnp.all(jnp.isfinite(y), axis=-1), 2, code)
    ts, ys = t[:, None], y[:, None, :]
    outputs = eqx.filter_vmap(lambda sc, ti, yi: jax.vmap(sc.outputs)(ti, yi))(scenes, ts, ys)
    int_t = jnp.asarray(0).dtype  # the default integer type, as diffrax's counters
    stats = {
        "num_steps": steps[:n_lanes].astype(int_t),
        "num_accepted_steps": acc[:n_lanes].astype(int_t),
        "num_rejected_steps": rej[:n_lanes].astype(int_t),
    }
    return SimulationResult(ts=ts, ys=ys, outputs=outputs, code=code, stats=stats,
                            solver=type(solver).__name__ + "+pallas")


def _first_lane(scenes):
    """The scene of lane 0 (every array leaf indexed at 0 on its batch axis)."""
    return jtu.tree_map(lambda x: x[0] if eqx.is_array(x) else x, scenes)


def _check_batch(scenes, y0s):
    """`y0s` as a float64 (N, n) array; checks the scenes' leading batch axis."""
    if not isinstance(scenes, AbstractScene):
        raise InputError(f"scenes must be a batch of rotorjax scenes (an AbstractScene whose array "
                         f"leaves carry a leading batch axis, from eqx.filter_vmap(build)), got "
                         f"{type(scenes).__name__}")
    if isinstance(y0s, (str, bytes)) or y0s is None:
        raise InputError(f"y0s must be an (N, n) array of numbers, got {y0s!r}")
    try:
        y0s = jnp.asarray(y0s, dtype=jnp.float64)
    except (TypeError, ValueError):
        raise InputError(f"y0s must be an (N, n) array of numbers, got {show(y0s)}") from None
    n_lanes = y0s.shape[0] if y0s.ndim >= 1 else 0
    for leaf in jtu.tree_leaves(eqx.filter(scenes, eqx.is_array)):
        if np.ndim(leaf) < 1 or np.shape(leaf)[0] != n_lanes:
            raise InputError(f"scenes must carry a leading batch axis of length N = {n_lanes} "
                             f"(y0s.shape[0]) on every array leaf (build them with "
                             f"eqx.filter_vmap), found a leaf of shape {np.shape(leaf)}")
    n = _first_lane(scenes).state_size  # a batched scene may count its leaves' batch axis
    if y0s.ndim != 2 or y0s.shape[1] != n or y0s.shape[0] < 1:
        raise InputError(f"y0s must have shape (N, {n}) for these scenes, got shape {y0s.shape}")
    if is_concrete(y0s) and not np.all(np.isfinite(np.asarray(y0s))):
        lane, idx = (int(v[0]) for v in np.nonzero(~np.isfinite(np.asarray(y0s))))
        raise InputError(f"y0s must be finite, got {float(np.asarray(y0s)[lane, idx])} "
                         f"at lane {lane}, index {idx}")
    return y0s


def simulate_pallas(
    scenes,
    y0s,
    t_span,
    solver=diffrax.Dopri8(),
    rtol: float = 1e-8,
    atol: float = 1e-10,
    max_steps: int = 200_000,
    block: int = 64,
    interpret=None,
) -> SimulationResult:
    """Integrate a batch of scenes, one whole adaptive RK integration per lane inside
    one Pallas kernel (DiffEqGPU.jl's `EnsembleGPUKernel` design).

    **Arguments:**
    - `scenes`: a rotorjax scene whose array leaves carry a leading batch axis `N`
      (`eqx.filter_vmap(build)(points)`); all lanes share one topology.
    - `y0s`: `(N, n)` initial states (finite).
    - `t_span`: `(t0, t1)`, shared by all lanes.
    - `solver`: an explicit diffrax Runge-Kutta solver with a Butcher tableau (Dopri5,
      Dopri8, Tsit5, ...) or its name; implicit solvers raise `InputError`.
    - `rtol`, `atol`: tolerances of diffrax's default `PIDController`.
    - `max_steps`: the per-lane budget of steps (accepted plus rejected).
    - `block`: lanes per kernel program (the grid is `ceil(N / block)` programs; `N` is
      padded with copies of the last lane).
    - `interpret`: run the kernel in Pallas interpret mode (plain JAX ops). `None`:
      interpret unless `jax.default_backend() == "gpu"`. Only interpret mode has been
      tested; on a GPU the compiled kernel is untried and needs a vector field that
      Triton / Mosaic GPU can lower (elementwise float64 arithmetic, no linear solves
      or gathers) and power-of-two block shapes.

    **Returns:** a `SimulationResult` with the final state only: `ts` `(N, 1)` (`t1`,
    or where a failed lane stopped), `ys` `(N, 1, n)`, `outputs` at that instant
    (`(N, 1, ...)`), `code` `(N,)` (0 success, 1 `max_steps` reached, 2 non-finite
    vector field or state, 3 step size collapsed below `1e-14 max(|t|, t1 - t0)`),
    `stats` (`num_steps`, `num_accepted_steps`, `num_rejected_steps`, each `(N,)`) and
    `solver` (e.g. `"Dopri8+pallas"`). The step counts are those of
    `rotorjax.simulate` with the same solver and tolerances; codes 2 and 3 end a lane
    where diffrax would shrink the step until `max_steps` (code 1).
    """
    y0s = _check_batch(scenes, y0s)
    try:
        t0, t1 = t_span
    except (TypeError, ValueError):
        raise InputError(f"t_span must be a pair (t0, t1), got {show(t_span)}") from None
    for name, v in (("t_span[0]", t0), ("t_span[1]", t1)):
        if is_concrete(v):
            as_numpy(name, v, shape=())
    if is_concrete((t0, t1)) and not float(t1) > float(t0):
        raise InputError(f"t_span must be increasing (t1 > t0), got ({show(t0)}, {show(t1)})")
    for name, v in (("rtol", rtol), ("atol", atol)):
        if is_concrete(v):
            as_numpy(name, v, sign="positive", shape=())
    max_steps = as_count("max_steps", max_steps, minimum=1, maximum=np.iinfo(np.int32).max - 1)
    block = as_count("block", block, minimum=1)
    if isinstance(solver, str):
        solver = choose_solver(None, None, 0.0, solver) if solver != "auto" else diffrax.Dopri8()
    if not isinstance(solver, diffrax.AbstractSolver):
        raise InputError(f"solver must be a diffrax solver instance or a name ('dopri5', 'dopri8', "
                         f"'tsit5'), got {solver!r}")
    explicit_tableau(solver)  # raises InputError naming `solver` for implicit solvers
    if interpret is None:
        interpret = jax.default_backend() != "gpu"
    elif not isinstance(interpret, (bool, np.bool_)):
        raise InputError(f"interpret must be None, True or False, got {interpret!r}")
    f64 = lambda v: jnp.asarray(v, dtype=jnp.float64)  # noqa: E731
    # Times, tolerances and max_steps as arrays, so that new values do not recompile.
    return _run(scenes, y0s, f64(t0), f64(t1), f64(rtol), f64(atol), f64(max_steps), solver,
                block, bool(interpret), diffrax_selects_first_step())
