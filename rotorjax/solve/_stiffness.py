"""Choosing a solver: explicit unless the scene is stiff at the initial state."""

import diffrax
import jax
import numpy as np

from ..models._validate import InputError, is_concrete

#: Above this stiffness ratio "auto" picks an implicit solver (see `stiffness_ratio`).
#: Measured in benchmarks/solver_choice.py on model 000 (delta_b sweep): at
#: delta_b = 40 (ratio ~27) and 400 (~280) Dopri8 is faster than Kvaerno5; at
#: delta_b = 4000 (~2800) Dopri8 fails and Kvaerno5 takes ~2000 steps.
STIFFNESS_THRESHOLD = 1000.0


def stiffness_ratio(scene, y0, t0=0.0) -> float:
    """Ratio of the fastest decay rate of the linearised system at `(t0, y0)` to its
    fastest oscillation or the spin speed: how many times smaller than the dynamics
    of interest an explicit solver's step would have to be for stability alone."""
    jac = np.asarray(jax.jacfwd(lambda y: scene.vector_field(t0, y))(y0))
    lam = np.linalg.eigvals(jac)
    decay = max(float(np.max(-lam.real)), 0.0)
    spin = abs(float(scene.speed.speed(np.float64(t0))))
    scale = max(float(np.max(np.abs(lam.imag))), spin, 1e-300)
    return decay / scale


def choose_solver(scene, y0, t0=0.0, solver="auto"):
    """Resolve `solver`: a diffrax solver passes through; a name ("dopri8",
    "tsit5", "dopri5", "kvaerno5", "kvaerno3") is instantiated; "auto" picks Dopri8,
    or Kvaerno5 when `stiffness_ratio > STIFFNESS_THRESHOLD`. Inside jit/vmap the
    values are unknown and "auto" means Dopri8: pick once for a batch with
    `choose_solver` on a representative (the stiffest) point."""
    if isinstance(solver, diffrax.AbstractSolver):
        return solver
    names = {
        "dopri8": diffrax.Dopri8, "dopri5": diffrax.Dopri5, "tsit5": diffrax.Tsit5,
        "kvaerno5": diffrax.Kvaerno5, "kvaerno3": diffrax.Kvaerno3,
    }
    if solver == "auto":
        leaves = jax.tree_util.tree_leaves((scene, y0))
        if all(is_concrete(x) for x in leaves) and np.ndim(y0) == 1:
            stiff = stiffness_ratio(scene, y0, t0) > STIFFNESS_THRESHOLD
            return diffrax.Kvaerno5() if stiff else diffrax.Dopri8()
        return diffrax.Dopri8()
    if isinstance(solver, str) and solver.lower() in names:
        return names[solver.lower()]()
    raise InputError(
        f"solver must be 'auto', one of {', '.join(repr(n) for n in sorted(names))} or a diffrax "
        f"solver instance, got {solver!r}"
    )
