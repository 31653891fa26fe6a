"""Time integration of a scene with diffrax."""

import diffrax
import equinox as eqx
import jax
import jax.numpy as jnp
import numpy as np

from ..models._contract import AbstractScene
from ..models._validate import InputError, as_count, as_numpy, is_concrete, show
from ._results import SimulationResult, result_code
from ._stiffness import choose_solver



def _field(t, y, scene):
    return scene.vector_field(t, y)


def _check_scene(scene):
    if not isinstance(scene, AbstractScene):
        raise InputError(f"scene must be a rotorjax scene (rotorjax.models.AbstractScene: Scene, RotorScene, "
                         f"BalancingScene, ModalBalancerRotor, ...); a {type(scene).__name__} has no state_size, "
                         "vector_field, outputs")


def _split_span(t_span):
    try:
        t0, t1 = t_span
    except (TypeError, ValueError):
        raise InputError(f"t_span must be a pair (t0, t1), got {show(t_span)}") from None
    return t0, t1


def _check_inputs(scene, y0, t0, t1, rtol, atol, max_steps):
    """Checks shared by `simulate` and `simulate_events` (concrete values only);
    returns `max_steps` as an int."""
    _check_scene(scene)
    if np.ndim(y0) != 1 or np.shape(y0)[0] != scene.state_size:
        raise InputError(
            f"y0 must have shape ({scene.state_size},) for this scene "
            f"({scene.describe()}), got shape {np.shape(y0)}"
        )
    if is_concrete(y0) and not np.all(np.isfinite(np.asarray(y0))):
        bad = int(np.flatnonzero(~np.isfinite(np.asarray(y0)))[0])
        raise InputError(f"y0 must be finite, got {float(np.asarray(y0)[bad])} at index {bad}")
    if is_concrete(y0):
        scene.check_state(y0)
    for name, v in (("t_span[0]", t0), ("t_span[1]", t1)):
        if is_concrete(v):
            as_numpy(name, v, shape=())
    if is_concrete((t0, t1)) and not float(t1) > float(t0):
        raise InputError(f"t_span must be increasing (t1 > t0), got ({show(t0)}, {show(t1)})")
    for name, v in (("rtol", rtol), ("atol", atol)):
        if is_concrete(v):
            as_numpy(name, v, sign="positive", shape=())
    return as_count("max_steps", max_steps, minimum=1)


def _y0(y0):
    if isinstance(y0, (str, bytes)) or y0 is None:
        raise InputError(f"y0 must be an array of numbers, got {y0!r}")
    try:
        return jnp.asarray(y0, dtype=jnp.float64)
    except (TypeError, ValueError):
        raise InputError(f"y0 must be an array of numbers, got {show(y0)}") from None


def _saveat(saveat, t0, t1):
    """`diffrax.SaveAt` from None, a count >= 2, or a 1-D array of times in `t_span`."""
    if saveat is None:
        return diffrax.SaveAt(t1=True)
    if isinstance(saveat, (bool, np.bool_)):
        raise InputError(f"saveat must be None, an integer count >= 2 or a 1-D array of times, got {saveat!r}")
    if isinstance(saveat, (int, np.integer)):
        if saveat < 2:
            raise InputError(f"saveat as a count must be >= 2, got {saveat}")
        return diffrax.SaveAt(ts=jnp.linspace(t0, t1, int(saveat)))
    if isinstance(saveat, (float, np.floating, str, bytes)):
        raise InputError(f"saveat must be None, an integer count >= 2 or a 1-D array of times, got {saveat!r}")
    if is_concrete(saveat):
        ts = as_numpy("saveat", saveat, ndim=1)
        if ts.size < 1:
            raise InputError("saveat times must hold at least one time, got an empty array")
        if np.any(np.diff(ts) < 0):
            i = int(np.flatnonzero(np.diff(ts) < 0)[0])
            raise InputError(f"saveat times must be non-decreasing, got {ts[i + 1]} after {ts[i]}")
        if is_concrete((t0, t1)) and (ts[0] < float(t0) or ts[-1] > float(t1)):
            raise InputError(f"saveat times must lie in t_span = ({show(t0)}, {show(t1)}), got "
                             f"[{ts[0]}, ..., {ts[-1]}]")
    ts = jnp.asarray(saveat, dtype=jnp.float64)
    if ts.ndim != 1:
        raise InputError(f"saveat times must be 1-D, got shape {ts.shape}")
    return diffrax.SaveAt(ts=ts)


def simulate(
    scene,
    y0,
    t_span,
    saveat=None,
    solver="auto",
    rtol: float = 1e-8,
    atol: float = 1e-10,
    max_steps: int = 200_000,
    dt0=None,
    adjoint=None,
    progress: bool = False,
) -> SimulationResult:
    """Integrate `scene` from `y0` over `t_span = (t0, t1)`.

    **Arguments:**
    - `scene`: a `rotorjax.Scene`.
    - `y0`: initial state `(q, qd)`, shape `(scene.state_size,)`.
    - `t_span`: `(t0, t1)`.
    - `saveat`: `None` (the final state only), an int `n` (n equally spaced times),
      or an array of times.
    - `solver`: "auto" (Dopri8, or Kvaerno5 for scenes stiff over this span at this
      tolerance and step budget; see `choose_solver`),
      a solver name, or any diffrax solver instance.
    - `rtol`, `atol`: PID step-size controller tolerances.
    - `max_steps`: reaching it is reported (`code == 1`), not raised.
    - `adjoint`: diffrax adjoint; default `RecursiveCheckpointAdjoint`. Do not use
      `BacksolveAdjoint` on damped rotors: integrating them backwards is unstable.
    - `progress`: a tqdm bar of the integrated time (diffrax's progress meter);
      for single runs, not under `vmap`.

    **Returns:** a `SimulationResult`; failures are marked in `code`, never returned
    as silent garbage. Pure and jit/vmap-able (batch scenes with `eqx.filter_vmap`).
    """
    t0, t1 = _split_span(t_span)
    y0 = _y0(y0)
    max_steps = _check_inputs(scene, y0, t0, t1, rtol, atol, max_steps)
    if dt0 is not None and is_concrete(dt0):
        as_numpy("dt0", dt0, sign="positive", shape=())
    if adjoint is not None and not isinstance(adjoint, diffrax.AbstractAdjoint):
        raise InputError(f"adjoint must be None or a diffrax adjoint, got {type(adjoint).__name__}")
    save = _saveat(saveat, t0, t1)
    solver = choose_solver(scene, y0, t0, solver, t1=t1, rtol=rtol, max_steps=max_steps)
    # Times and tolerances as arrays, so that new values do not recompile.
    f64 = lambda v: jnp.asarray(v, dtype=jnp.float64)  # noqa: E731
    dt0 = None if dt0 is None else f64(dt0)
    meter = diffrax.TqdmProgressMeter(refresh_steps=200) if progress else diffrax.NoProgressMeter()
    return _solve(scene, y0, f64(t0), f64(t1), save, solver, f64(rtol), f64(atol),
                  max_steps, dt0, adjoint, meter)


@eqx.filter_jit
def _solve(scene, y0, t0, t1, save, solver, rtol, atol, max_steps, dt0, adjoint, meter=diffrax.NoProgressMeter()):
    sol = diffrax.diffeqsolve(
        diffrax.ODETerm(_field),
        solver,
        t0=t0,
        t1=t1,
        dt0=dt0,
        y0=y0,
        args=scene,
        saveat=save,
        stepsize_controller=diffrax.PIDController(rtol=rtol, atol=atol),
        max_steps=max_steps,
        adjoint=adjoint if adjoint is not None else diffrax.RecursiveCheckpointAdjoint(),
        throw=False,
        progress_meter=meter,
    )
    outputs = jax.vmap(scene.outputs)(sol.ts, sol.ys)
    stats = {
        "num_steps": sol.stats["num_steps"],
        "num_accepted_steps": sol.stats["num_accepted_steps"],
        "num_rejected_steps": sol.stats["num_rejected_steps"],
    }
    return SimulationResult(
        ts=sol.ts, ys=sol.ys, outputs=outputs, code=result_code(sol.result, sol.ys),
        stats=stats, solver=type(solver).__name__,
    )
