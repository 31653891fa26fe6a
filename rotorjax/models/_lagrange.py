"""Equations of motion from energies by autodiff.

For generalised coordinates `q` with a prescribed, time-dependent spin, Lagrange's
equations of the second kind with a Rayleigh dissipation function `D` read

    d/dt (dL/dqd) - dL/dq = -dD/dqd,        L = T - V.

With `p(q, qd, t) = dL/dqd`, the time derivative is
`(dp/dq) qd + (dp/dqd) qdd + dp/dt`, so

    M qdd = dL/dq - dD/dqd - (dp/dq) qd - dp/dt,     M = d2T/dqd2.

`dp/dq qd + dp/dt` is one forward-mode product; `M` one Jacobian.
"""

from typing import Callable

import jax
import jax.numpy as jnp


def lagrange_terms(lagrangian: Callable, dissipation: Callable, q: jax.Array, qd: jax.Array, t):
    """`(M, f)` of Lagrange's equations `M qdd = f` for `lagrangian(q, qd, t)` and
    `dissipation(q, qd, t)` (both scalar-valued), unsolved (to be assembled into a
    larger system)."""
    t = jnp.asarray(t, dtype=q.dtype)
    momentum = jax.grad(lagrangian, argnums=1)
    mass = jax.jacfwd(momentum, argnums=1)(q, qd, t)
    _, dp_explicit = jax.jvp(
        momentum, (q, qd, t), (qd, jnp.zeros_like(qd), jnp.ones_like(t))
    )
    rhs = (
        jax.grad(lagrangian, argnums=0)(q, qd, t)
        - jax.grad(dissipation, argnums=1)(q, qd, t)
        - dp_explicit
    )
    return mass, rhs


def lagrange_accelerations(
    lagrangian: Callable, dissipation: Callable, q: jax.Array, qd: jax.Array, t, force=None
) -> jax.Array:
    """Generalised accelerations `qdd` from `lagrangian(q, qd, t)` and
    `dissipation(q, qd, t)` (both scalar-valued), plus a generalised `force`
    stated directly (forces with no energy: gyroscopic, circulatory, contact)."""
    mass, rhs = lagrange_terms(lagrangian, dissipation, q, qd, t)
    if force is not None:
        rhs = rhs + force
    return jnp.linalg.solve(mass, rhs)
