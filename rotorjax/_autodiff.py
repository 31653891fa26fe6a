"""A function's value and its Jacobian from one forward-mode pass.

`jax.jacfwd` computes the value on the way (each tangent column is a JVP, whose
primal is the value); calling `f` as well puts a second copy of `f` in the
compiled program, and XLA compiles every copy (for a rotor's field, a fluid film,
an ODE solve: most of a program's compile time)."""

import jax


def value_and_jacfwd(f, argnums=0):
    """`(*args) -> (f(*args), jax.jacfwd(f, argnums)(*args))`, `f` traced once."""

    def run(*args):
        jac, value = jax.jacfwd(lambda *a: _twice(f(*a)), argnums=argnums, has_aux=True)(*args)
        return value, jac

    return run


def _twice(y):
    return y, y
