"""Time integration of a scene with diffrax."""

import diffrax
import equinox as eqx
import jax
import jax.numpy as jnp
import numpy as np

from ..models._validate import is_concrete
from ._results import SimulationResult, result_code
from ._stiffness import choose_solver


def _field(t, y, scene):
    return scene.vector_field(t, y)


def _check_inputs(scene, y0, t0, t1, rtol, atol, max_steps):
    if np.ndim(y0) != 1 or np.shape(y0)[0] != scene.state_size:
        raise ValueError(
            f"y0 must have shape ({scene.state_size},) for this scene "
            f"({scene.describe()}), got shape {np.shape(y0)}"
        )
    if is_concrete(y0) and not np.all(np.isfinite(np.asarray(y0))):
        raise ValueError("y0 must be finite")
    for name, v in (("t_span[0]", t0), ("t_span[1]", t1)):
        if is_concrete(v) and not np.isfinite(v):
            raise ValueError(f"{name} must be finite, got {v}")
    if is_concrete(t0) and is_concrete(t1) and not float(t1) > float(t0):
        raise ValueError(f"t_span must be increasing, got ({t0}, {t1})")
    if is_concrete(rtol) and is_concrete(atol) and not (rtol > 0 and atol > 0):
        raise ValueError(f"rtol and atol must be > 0, got rtol={rtol}, atol={atol}")
    if int(max_steps) < 1:
        raise ValueError(f"max_steps must be >= 1, got {max_steps}")


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
) -> SimulationResult:
    """Integrate `scene` from `y0` over `t_span = (t0, t1)`.

    **Arguments:**
    - `scene`: a `rotorjax.Scene`.
    - `y0`: initial state `(q, qd)`, shape `(scene.state_size,)`.
    - `t_span`: `(t0, t1)`.
    - `saveat`: `None` (the final state only), an int `n` (n equally spaced times),
      or an array of times.
    - `solver`: "auto" (Dopri8, or Kvaerno5 for stiff scenes; see `choose_solver`),
      a solver name, or any diffrax solver instance.
    - `rtol`, `atol`: PID step-size controller tolerances.
    - `max_steps`: reaching it is reported (`code == 1`), not raised.
    - `adjoint`: diffrax adjoint; default `RecursiveCheckpointAdjoint`. Do not use
      `BacksolveAdjoint` on damped rotors: integrating them backwards is unstable.

    **Returns:** a `SimulationResult`; failures are marked in `code`, never returned
    as silent garbage. Pure and jit/vmap-able (batch scenes with `eqx.filter_vmap`).
    """
    t0, t1 = t_span
    y0 = jnp.asarray(y0, dtype=jnp.float64)
    _check_inputs(scene, y0, t0, t1, rtol, atol, max_steps)
    solver = choose_solver(scene, y0, t0, solver)
    if saveat is None:
        save = diffrax.SaveAt(t1=True)
    elif isinstance(saveat, (int, np.integer)):
        if saveat < 2:
            raise ValueError(f"saveat as a count must be >= 2, got {saveat}")
        save = diffrax.SaveAt(ts=jnp.linspace(t0, t1, int(saveat)))
    else:
        ts = jnp.asarray(saveat, dtype=jnp.float64)
        if ts.ndim != 1:
            raise ValueError(f"saveat times must be 1-D, got shape {ts.shape}")
        save = diffrax.SaveAt(ts=ts)
    # Times and tolerances as arrays, so that new values do not recompile.
    f64 = lambda v: jnp.asarray(v, dtype=jnp.float64)  # noqa: E731
    dt0 = None if dt0 is None else f64(dt0)
    return _solve(scene, y0, f64(t0), f64(t1), save, solver, f64(rtol), f64(atol),
                  int(max_steps), dt0, adjoint)


@eqx.filter_jit
def _solve(scene, y0, t0, t1, save, solver, rtol, atol, max_steps, dt0, adjoint):
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
