"""The one Newton iteration: the exact Jacobian (forward mode), in one compiled
loop, differentiable by the implicit function theorem (`lax.custom_root`: the
derivative of the root with respect to anything `residual` closes over is
`-R_x^{-1} R_theta`, one linear solve, not the iterations unrolled).

Used by harmonic balance, shooting, limit cycles, stationary regimes and the
continuation core (`rotorjax.analysis`) and by a rotor's static equilibrium in its
bearings (`rotorjax.models`)."""

import jax
import jax.numpy as jnp


def newton(residual, x0, tol, max_iter, limit=None, floor=None, unit=None, value_and_jacobian=None, final=False):
    """The root of `residual` from `x0`: iterate until the relative step is <= `tol`
    or `max_iter` steps, or a step is not finite. The step is relative to the largest
    `|x|`, or to `unit` where that is larger (given: a root at or near 0 converges
    too, as with an absolute tolerance `tol * unit`). `limit(x, dx)`, if given, returns
    the step to take (a damped one: keeps the iterate where `residual` is defined).
    `floor`, if given: also stop at a step <= `floor` that no longer halves (the
    rounding floor of an ill-conditioned system: more iterations only stir the
    noise). `value_and_jacobian(x)`, if given, returns the residual and its Jacobian
    by the caller's cheaper rule (a fold's defining system: its second derivatives by
    directional derivatives, not a Jacobian of a Jacobian); `residual` is then
    `value_and_jacobian`'s first output (None: made from it). Returns `(x, (step,
    iterations))`, `step` the last relative step (check the residual too); with
    `final`, `(x, (step, iterations, r, J))`, `r` and `J` the residual and its
    Jacobian at `x` (one more evaluation, made by the loop's own copy of the
    residual: a caller that needs them has no second copy in its program)."""

    if value_and_jacobian is not None and residual is None:
        def residual(x):
            return value_and_jacobian(x)[0]

    def evaluated(f, x):
        if value_and_jacobian is None:
            r, jvp = jax.linearize(f, x)
            return r, jax.vmap(jvp, in_axes=1, out_axes=1)(jnp.eye(x.shape[0]))
        return value_and_jacobian(x)

    def update(x, r, J):
        dx = jnp.linalg.solve(J, r)
        if limit is not None:
            dx = limit(x, dx)
        x = x - dx
        size = jnp.maximum(jnp.max(jnp.abs(x)), jnp.finfo(jnp.float64).tiny if unit is None else unit)
        return x, jnp.max(jnp.abs(dx)) / size

    def going(last, step, it):
        on = (it < max_iter) & ~(step <= tol) & ~jnp.isnan(step)
        if floor is not None:
            on = on & ~((step <= floor) & (step > 0.5 * last))
        return on

    def solve(f, x):
        def body(state):
            x, _, prev, it = state
            x, step = update(x, *evaluated(f, x))
            return x, prev, step, it + 1

        inf = jnp.asarray(jnp.inf)
        x, _, step, it = jax.lax.while_loop(lambda s: going(*s[1:]), body, (x, inf, inf, 0))
        return x, (step, it.astype(jnp.float64))   # float aux: custom_root differentiates through it

    def solve_final(f, x):
        # each pass evaluates at its iterate first: the pass that finds the iteration over keeps that evaluation
        def body(state):
            x, _, _, last, step, it, _ = state
            r, J = evaluated(f, x)
            on = going(last, step, it)
            xn, stepn = jax.lax.cond(on, lambda: update(x, r, J), lambda: (x, step))
            return xn, r, J, jnp.where(on, step, last), stepn, it + on, ~on

        inf, m = jnp.asarray(jnp.inf), x.shape[0]
        r0 = jax.eval_shape(f, x)
        state = (x, jnp.zeros(r0.shape, r0.dtype), jnp.zeros(r0.shape + (m,), r0.dtype), inf, inf, 0,
                 jnp.asarray(False))
        x, r, J, _, step, it, _ = jax.lax.while_loop(lambda s: ~s[-1], body, state)
        return x, (step, it.astype(jnp.float64), r, J)

    def tangent_solve(g, y):
        return jnp.linalg.solve(jax.jacfwd(g)(y), y)

    return jax.lax.custom_root(residual, x0, solve_final if final else solve, tangent_solve, has_aux=True)
