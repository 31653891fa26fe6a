"""`rotorjax._sincos`: float64 sine and cosine in `jnp` (issue 32, item 1), against
numpy (the C library) on 1e7 random arguments over every range the reduction
covers, exact values, derivatives, and NaN (not garbage) beyond its limit."""

import jax
import jax.numpy as jnp
import numpy as np
import pytest

from rotorjax._sincos import REDUCTION_LIMIT, cos, sin, sincos

_PAIR = jax.jit(sincos)


def _ulps(got, want):
    return np.max(np.abs(got - want) / np.spacing(np.maximum(np.abs(want), np.finfo(float).tiny)))


@pytest.mark.parametrize("scale, max_ulp", [(np.pi / 4, 1), (10.0, 1), (1e4, 1), (1e6, 1), (REDUCTION_LIMIT, 2)])
def test_within_two_ulp_of_numpy_on_two_million_arguments(scale, max_ulp):
    """2e6 uniform arguments in [-scale, scale] per range (1e7 in all): within 1
    ulp of numpy up to 1e6 rad (the models' `n tau`, speed times time), 2 ulp up
    to the reduction's limit (measured: 1, 1, 1, 1, 2)."""
    x = np.random.default_rng(int(np.log10(scale) * 10) + 7).uniform(-scale, scale, 2_000_000)
    s, c = (np.asarray(v) for v in _PAIR(jnp.asarray(x)))
    assert _ulps(s, np.sin(x)) <= max_ulp and _ulps(c, np.cos(x)) <= max_ulp


def test_exact_values_near_the_multiples_of_a_quarter_turn():
    """At 0, and next to k pi/2 (where the reduction cancels most digits), as numpy."""
    k = np.arange(-2000, 2001)
    x = np.concatenate([k * (np.pi / 2), np.nextafter(k * (np.pi / 2), np.inf), [0.0, -0.0, 1e-300]])
    s, c = (np.asarray(v) for v in _PAIR(jnp.asarray(x)))
    np.testing.assert_allclose(s, np.sin(x), rtol=3e-16, atol=1e-300 + 2 * np.spacing(np.abs(np.sin(x))).max())
    np.testing.assert_allclose(c, np.cos(x), rtol=3e-16, atol=2 * np.spacing(np.abs(np.cos(x))).max())
    assert float(sin(0.0)) == 0.0 and float(cos(0.0)) == 1.0


def test_derivatives_are_the_pair_itself():
    """`custom_jvp`: d sin = cos, d cos = -sin, exactly the computed pair (forward
    and reverse mode); a second derivative, through the polynomials (the rule does
    not call `sincos` itself, so that programs holding it are shared: `solve._lift`),
    within 1e-15 of it (measured: 7.8e-16)."""
    x = jnp.linspace(-50.0, 50.0, 101)
    s, c = sincos(x)
    np.testing.assert_array_equal(jax.vmap(jax.grad(sin))(x), c)
    np.testing.assert_array_equal(jax.vmap(jax.grad(cos))(x), -s)
    np.testing.assert_allclose(jax.vmap(jax.grad(jax.grad(sin)))(x), -s, rtol=0, atol=1e-15)
    _, (ds, dc) = jax.jvp(sincos, (x,), (jnp.ones_like(x),))
    np.testing.assert_array_equal(ds, c)


def test_beyond_the_limit_nan_not_garbage():
    """Past `REDUCTION_LIMIT` (and for inf, NaN) the result is NaN: a run reports it
    as non-finite; it never returns a wrong number."""
    x = jnp.asarray([1.01 * REDUCTION_LIMIT, -1e12, jnp.inf, jnp.nan, REDUCTION_LIMIT])
    s, c = (np.asarray(v) for v in _PAIR(x))
    assert np.isnan(s[:4]).all() and np.isnan(c[:4]).all()
    assert s[4] == pytest.approx(np.sin(REDUCTION_LIMIT), abs=4 * np.spacing(1.0))
