"""One adaptive explicit Runge-Kutta step of every lane at once, as arrays of lanes.

The buffered batch (`_batch.py`) advances a buffer of lanes by their own adaptive
steps. Its general stepper is diffrax's `solver.step`, vmapped over the lanes. For
an explicit Runge-Kutta solver (`diffrax.AbstractERK`: Dopri5, Dopri8, Tsit5,
Bosh3, ...) this module is the vectorised stepper: the stages are written over
structure-of-arrays states, `Y[state, lane]` (lanes the innermost, contiguous
dimension; the vector field is vmapped over the last axis), so every line of a
right-hand side is one elementwise operation over contiguous lanes, which XLA fuses
and vectorises; the stage sums are one `tensordot` against the Butcher tableau,
under a `fori_loop` over the stages (one copy of the right-hand side in the compiled
program, not one per stage: Dopri8's 14 stages unrolled compiled 9x longer, 4.5 s
against 0.5 s on model 001, for at most 10% at run time).

It is the same method as diffrax's step: the same tableau (`solver.tableau`), the
first-same-as-last stage carried between steps, the same error estimate
(`b_error`), the same dense output (`solver.interpolation_cls` from the stages'
increments), and the step size from the same controller (`_batch.py` passes both
through `PIDController.adapt_step_size`); one step from the same state equals
diffrax's to rounding. The error estimate is a difference of nearly equal sums,
which here are taken in another order: its rounding moves the next step's size
(by ~1e-4 relative on model 001 at rtol 1e-9), so a point's trajectory equals the
diffrax stepper's to the tolerance, its step count within a few
(`tests/solve/test_batch.py`).
"""

import diffrax
import jax
import jax.numpy as jnp
import numpy as np


def vectorises(solver) -> bool:
    """Whether `solver` is an explicit Runge-Kutta method this stepper runs."""
    return isinstance(solver, diffrax.AbstractERK) and isinstance(solver.tableau, diffrax.ButcherTableau)


class Tableau:
    """A Butcher tableau as dense float64 arrays: stage times `c` (`s`), the stage
    matrix `a` (`s x s`, strictly lower), the solution and error weights."""

    def __init__(self, solver):
        tab = solver.tableau
        c = np.concatenate([[0.0], np.asarray(tab.c, dtype=np.float64)])
        s = c.size
        a = np.zeros((s, s))
        for i, row in enumerate(tab.a_lower):
            a[i + 1, :i + 1] = np.asarray(row, dtype=np.float64)
        self.stages = s
        self.c, self.a = c, a
        self.b_sol = np.asarray(tab.b_sol, dtype=np.float64)
        self.b_error = np.asarray(tab.b_error, dtype=np.float64)
        #: the last stage is f(t1, y1): carried to the next step as its first stage
        self.fsal = bool(tab.fsal)


def field_over_lanes(field):
    """`field(scene_arrays, t, y)` of one lane -> the same over lanes: `scene_arrays`
    leaves, `t` and `Y` with the lanes as their last axis (`Y[state, lane]`)."""
    return jax.vmap(field, in_axes=(-1, -1, -1), out_axes=-1)


def _combine(weights, fs):
    """`sum_j weights[j] fs[j]` over the stages (a dot: 8x faster on the CPU than the
    same sum written term by term, whose slices XLA materialises)."""
    return jnp.tensordot(weights, fs, axes=1)


def stages(tableau: Tableau, lanes_field, scene_t, t, h, y, f0):
    """One step of size `h` (per lane) from `(t, y)` on every lane.

    **Arguments:**
    - `lanes_field`: `field_over_lanes(...)`; `scene_t`: the lanes' scene arrays,
      lanes last.
    - `t`, `h`: `[lanes]`; `y`: `[lanes, state]`.
    - `f0`: the vector field at `(t, y)`, `[lanes, state]` (first-same-as-last), or
      None to evaluate it here.

    **Returns:** `(y1, y_error, k, f1)`, `[lanes, ...]`: the new state, its error
    estimate, the stages' increments `k[lane, stage, state]` (dense output) and the
    vector field at `(t + h, y1)` when the tableau carries it (else None).
    """
    s = tableau.stages
    a, c = jnp.asarray(tableau.a), jnp.asarray(tableau.c)
    Y, hl = y.T, h[None, :]
    F0 = lanes_field(scene_t, t, Y) if f0 is None else f0.T
    fs = jnp.zeros((s,) + Y.shape, Y.dtype).at[0].set(F0)

    def stage(i, fs):
        Yi = Y + hl * _combine(a[i], fs)
        return fs.at[i].set(lanes_field(scene_t, t + c[i] * h, Yi))

    fs = jax.lax.fori_loop(1, s, stage, fs)
    Y1 = Y + hl * _combine(jnp.asarray(tableau.b_sol), fs)
    err = hl * _combine(jnp.asarray(tableau.b_error), fs)
    k = jnp.transpose(hl[None] * fs, (2, 0, 1))
    f1 = fs[s - 1].T if tableau.fsal else None
    return Y1.T, err.T, k, f1
