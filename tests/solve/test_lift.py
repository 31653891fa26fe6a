"""`lift`: one compilation per program structure, and never one shared by two
programs that compute different things."""

import jax
import jax.numpy as jnp
import numpy as np
import pytest

from rotorjax.solve._lift import call, jacobian, lift, vmapped


def _closure(A, c=2.0):
    return lambda x, p: jnp.tanh(A @ x) * p + c


X = jnp.array([0.3, -0.2, 0.5])


def test_closures_over_other_arrays_share_one_compilation():
    rng = np.random.default_rng(0)
    A1, A2 = (jnp.asarray(rng.normal(size=(3, 3))) for _ in range(2))
    f1, f2 = lift(_closure(A1), X, 1.0), lift(_closure(A2), X, 1.0)
    assert f1.structure is f2.structure
    np.testing.assert_allclose(call(f1, X, 1.5), _closure(A1)(X, 1.5), rtol=1e-14)
    np.testing.assert_allclose(call(f2, X, 1.5), _closure(A2)(X, 1.5), rtol=1e-14)
    (compiled_call,) = [j for j in f1.structure.compiled.values()]
    assert compiled_call._cache_size() == 1
    np.testing.assert_allclose(jacobian(f2, X, 1.5), jax.jacfwd(_closure(A2))(X, 1.5), rtol=1e-13)


def test_the_package_s_sine_and_cosine_share_their_programs():
    # `_sincos`' derivative rule once called `sincos` itself: every trace held a new rule object, so no
    # program of a rotating model's Jacobian was ever shared (a second branch of the same auto-balancer
    # compiled for 25 s again; found by `tests/analysis/test_balancer_pitchfork.py`)
    from rotorjax._sincos import cos, sin

    def make(A):
        return lambda x: jax.jacfwd(lambda y: sin(A @ y) * cos(y))(x) @ x

    A1, A2 = jnp.eye(3), 2.0 * jnp.ones((3, 3))
    f1, f2 = lift(make(A1), X), lift(make(A2), X)
    assert f1.structure is f2.structure
    np.testing.assert_allclose(call(f2, X), make(A2)(X), rtol=1e-14)


def test_a_jacobian_inside_shares_one_compilation():
    # jacfwd inside the program (a fold's test function, a bordered system) stages a conversion whose
    # sharding parameter is a new object per trace: compared by value, not identity (found when every
    # fold curve of the same equations compiled the continuation core again, 2 s a call)
    def make(A):
        return lambda x: jax.jacfwd(lambda y: jnp.outer(A @ y, y))(x).sum(axis=0) @ x

    A1, A2 = jnp.eye(3), 2.0 * jnp.ones((3, 3))
    f1, f2 = lift(make(A1), X), lift(make(A2), X)
    assert f1.structure is f2.structure
    np.testing.assert_allclose(call(f2, X), make(A2)(X), rtol=1e-14)


def test_a_python_number_is_part_of_the_program():
    A = jnp.eye(3)
    f1, f2 = lift(_closure(A, 2.0), X, 1.0), lift(_closure(A, 3.0), X, 1.0)
    assert f1.structure is not f2.structure
    np.testing.assert_allclose(call(f2, X, 1.0) - call(f1, X, 1.0), 1.0, rtol=1e-14)


def test_arrays_of_an_inner_compiled_call_are_arguments_not_the_program():
    # a jitted helper closing over an array: its array lives inside the traced program
    def make(B):
        inner = jax.jit(lambda x: B @ x)
        return lambda x: jnp.sin(inner(x))

    B1, B2 = jnp.eye(3), 2.0 * jnp.ones((3, 3))
    f1, f2 = lift(make(B1), X), lift(make(B2), X)
    assert f1.structure is f2.structure
    np.testing.assert_allclose(call(f1, X), make(B1)(X), rtol=1e-14)
    np.testing.assert_allclose(call(f2, X), make(B2)(X), rtol=1e-14)


def test_a_program_with_a_python_rule_is_never_shared():
    def make(c):
        @jax.custom_jvp
        def f(x):
            return jnp.sin(x)

        @f.defjvp
        def f_jvp(primals, tangents):
            return f(primals[0]), c * tangents[0]   # the rule differs, the forward program does not

        return f

    f1, f2 = lift(make(1.0), X), lift(make(5.0), X)
    assert f1.structure is not f2.structure
    np.testing.assert_allclose(jacobian(f1, X), np.eye(3), rtol=1e-14)
    np.testing.assert_allclose(jacobian(f2, X), 5.0 * np.eye(3), rtol=1e-14)


def test_pytrees_in_and_out_and_a_vmapped_call():
    A = jnp.asarray(np.random.default_rng(1).normal(size=(3, 3)))

    def f(d):
        return {"y": A @ d["x"], "s": jnp.sum(d["x"]) * d["k"]}

    lf = lift(f, {"x": X, "k": jnp.float64(2.0)})
    out = call(lf, {"x": X, "k": jnp.float64(3.0)})
    np.testing.assert_allclose(out["y"], A @ X, rtol=1e-14)
    np.testing.assert_allclose(out["s"], 3.0 * float(jnp.sum(X)), rtol=1e-14)
    xs = jnp.stack([X, 2 * X])
    out = vmapped(lf, {"x": xs, "k": jnp.array([1.0, 2.0])})
    np.testing.assert_allclose(out["y"], xs @ A.T, rtol=1e-14)
    with pytest.raises(TypeError, match="traced with"):
        call(lf, X)
