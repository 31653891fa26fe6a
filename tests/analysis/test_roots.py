"""The shared scan-and-bisect root finder and the implicit-function gradient."""

import jax
import jax.numpy as jnp
import numpy as np
import pytest

from rotorjax._errors import InputError
from rotorjax.analysis import critical_speeds, find_roots, root_gradient
from rotorjax.analysis._roots import bisect, sign_changes


def cubic(x):
    return (x - 1.0) * (x - 2.0) * (x - 3.5)


def test_polynomial_roots_to_xtol_with_slopes():
    roots = find_roots(cubic, 0.0, 5.0, n_scan=23, xtol=1e-12)
    np.testing.assert_allclose([r.x for r in roots], [1.0, 2.0, 3.5], atol=1e-12)
    for r in roots:
        a, b = r.bracket
        assert 0 < b - a <= 1e-12 and a <= r.x <= b
        assert np.sign(r.values[0]) != np.sign(r.values[1])
        slope = 3 * r.x**2 - 13 * r.x + 12.5          # d/dx of the cubic
        assert r.slope == pytest.approx(slope, rel=1e-3)
        assert np.isnan(r.residual)                     # no pole check asked for


def test_vectorised_scan_equals_the_per_point_scan():
    loop, (x, v) = find_roots(cubic, 0.0, 5.0, n_scan=23, return_scan=True)
    vmapped = find_roots(cubic, 0.0, 5.0, n_scan=23, values=lambda xs: jax.vmap(cubic)(jnp.asarray(xs)))
    given = find_roots(cubic, 0.0, 5.0, n_scan=23, values=v)
    np.testing.assert_array_equal(x, np.linspace(0.0, 5.0, 23))
    assert loop == vmapped == given


def test_relative_tolerance_and_iteration_cap():
    (r,) = find_roots(lambda x: x - 1000.0 * np.pi, 1000.0, 4000.0, n_scan=5, xtol=0.0, rtol=1e-9)
    assert r.bracket[1] - r.bracket[0] <= 1e-9 * r.bracket[1]
    assert r.x == pytest.approx(1000.0 * np.pi, rel=1e-9)
    (r,) = find_roots(lambda x: x - 1.3, 0.0, 2.0, n_scan=3, xtol=0.0, max_iter=10)
    assert r.bracket[1] - r.bracket[0] == pytest.approx(1.0 / 2**10)


def test_pole_rejected_by_the_residual_check():
    """`(x - 1) / (x - 2.55)` changes sign at its root 1 and through its pole 2.55."""
    def g(x):
        return (x - 1.0) / (x - 2.55)

    both = find_roots(g, 0.0, 4.0, n_scan=40, xtol=1e-12)
    np.testing.assert_allclose([r.x for r in both], [1.0, 2.55], atol=1e-12)
    (root,) = find_roots(g, 0.0, 4.0, n_scan=40, xtol=1e-12, pole_tol=1e-6)
    assert root.x == pytest.approx(1.0, abs=1e-12)
    assert root.residual < 1e-11


def test_non_finite_points_are_skipped():
    """Samples that are NaN or infinite bracket nothing: the roots next to them are
    not found (their brackets are unusable), the others are."""
    def g(x):
        if 2.1 < x < 2.5 or abs(x - 4.4) < 1e-9:
            return np.nan if x < 3 else np.inf
        return (x - 1.7) * (x - 2.3) * (x - 4.3)

    roots = find_roots(g, 0.0, 5.0, n_scan=26)     # samples every 0.2: NaN at 2.2 and 2.4, inf at 4.4
    np.testing.assert_allclose([r.x for r in roots], [1.7], atol=1e-10)
    assert sign_changes([1.0, np.nan, -1.0, -2.0, np.inf, 3.0, -3.0]).tolist() == [5]


def test_zero_on_a_sample_found_once_and_nan_midpoint_stops():
    roots = find_roots(lambda x: x - 2.0, 0.0, 4.0, n_scan=5, xtol=1e-12)
    assert len(roots) == 1 and roots[0].x == pytest.approx(2.0, abs=1e-12)
    r = bisect(lambda x: np.nan, 0.0, 1.0, -1.0, 1.0, xtol=1e-12)
    assert r.bracket == (0.0, 1.0) and r.x == 0.5


@pytest.mark.parametrize("g, root", [(lambda x: x**3 - 0.2, 0.2 ** (1 / 3)),
                                     (lambda x: np.exp(5 * x) - 2.0, np.log(2) / 5),
                                     (lambda x: np.tanh(40 * (x - 0.7)), 0.7)])
def test_secant_bisection_finds_the_root_in_a_few_calls(g, root):
    """`bisect(secant=True)` (Illinois): the same root as halving to 1e-14, in far
    fewer calls of `g` (a Hopf point's refinement corrects a point onto a branch per
    call), on a convex, an exponential and a near-step function."""
    calls = []

    def counted(x):
        calls.append(x)
        return g(x)

    r = bisect(counted, 0.0, 1.0, g(0.0), g(1.0), xtol=1e-14, max_iter=60, secant=True)
    assert abs(r.x - root) < 1e-13 and r.bracket[0] <= root <= r.bracket[1]
    halving = bisect(g, 0.0, 1.0, g(0.0), g(1.0), xtol=1e-14, max_iter=60)
    assert abs(halving.x - root) < 1e-13
    assert len(calls) <= 24 < 46


def test_critical_speeds_is_the_shared_finder():
    def margin(s):
        return jnp.sin(s) * jnp.exp(-0.1 * s) + 0.1

    found = critical_speeds(margin, 0.0, 20.0, n_scan=50, xtol=1e-12)
    roots = find_roots(jax.jit(margin), 0.0, 20.0, n_scan=50, xtol=1e-12)
    assert [c.speed for c in found] == [r.x for r in roots]
    assert [c.stable_side for c in found] == ["above" if r.values[1] < 0 else "below" for r in roots]
    # the scan point by point (the CPU's default) and vmapped: the same samples, so the same thresholds; the
    # closed form's roots (sin s = -0.1 exp(0.1 s)) to the bisection's tolerance
    (_, (x_p, v_p)), (vm, (x_v, v_v)) = (critical_speeds(margin, 0.0, 20.0, n_scan=50, xtol=1e-12, return_scan=True,
                                                         scan=m) for m in ("points", "vmap"))
    np.testing.assert_array_equal(x_p, x_v)
    np.testing.assert_allclose(v_p, v_v, rtol=1e-14, atol=1e-15)
    assert [c.speed for c in vm] == pytest.approx([c.speed for c in found], rel=1e-12)
    for c in found:
        assert abs(np.sin(c.speed) + 0.1 * np.exp(0.1 * c.speed)) < 1e-11
    with pytest.raises(InputError, match="scan must be one of auto, points, vmap, got 'chunks'"):
        critical_speeds(margin, 0.0, 20.0, scan="chunks")


def test_root_gradient_matches_the_closed_form():
    """`x^2 - p = 0`: `x = sqrt(p)`, `dx/dp = 1 / (2 sqrt(p))`; a pytree of parameters."""
    assert float(root_gradient(lambda x, p: x**2 - p, 3.0, 9.0)) == pytest.approx(1 / 6, rel=1e-14)

    def g2(x, p):
        return x**2 - p["a"] * p["b"]

    d = root_gradient(g2, 2.0, {"a": 2.0, "b": 2.0})
    assert float(d["a"]) == pytest.approx(0.5, rel=1e-14) and float(d["b"]) == pytest.approx(0.5, rel=1e-14)
    # traceable: vmapped over roots and parameters
    p = jnp.array([1.0, 4.0, 9.0])
    np.testing.assert_allclose(jax.vmap(lambda x, q: root_gradient(lambda u, v: u**2 - v, x, q))(jnp.sqrt(p), p),
                               0.5 / jnp.sqrt(p), rtol=1e-14)


@pytest.mark.parametrize("kw,match", [
    (dict(lo=1.0, hi=1.0), r"lo must be < hi"),
    (dict(lo=np.nan), r"lo must be finite"),
    (dict(n_scan=1), r"n_scan must be an integer >= 2, got 1"),
    (dict(xtol=-1e-3), r"xtol must be >= 0"),
    (dict(values=np.zeros(3)), r"values must hold one sample of g per scan point, shape \(10,\), got shape \(3,\)"),
    (dict(g="cubic"), r"g must be a function"),
    (dict(pole_tol=0.0), r"pole_tol must be > 0"),
])
def test_bad_input(kw, match):
    args = dict(g=cubic, lo=0.0, hi=5.0, n_scan=10)
    args.update(kw)
    with pytest.raises(InputError, match=match):
        find_roots(**args)
    with pytest.raises(InputError, match="x \\(the root\\) must be a scalar"):
        root_gradient(lambda x, p: x - p, jnp.zeros(2), 1.0)


def test_a_followed_root_stays_put_once_converged_on_a_noisy_function():
    """`secant_root` on a function with rounding noise (1e-15, a Floquet margin's) from
    a guess already at the root: a secant through two points 1e-14 apart is noise, and
    threw such a root to the wrong side of the range (a Floquet threshold of model
    001 from 1.0143 to -0.209, inside a vmapped design evaluation); it now stays."""
    from rotorjax.analysis._roots import secant_root

    def g(p, x):
        return p * (x - 1.0143481980647313) + 1e-15 * jnp.sin(1e9 * x)

    guesses = jnp.asarray(1.0143481980647313 + np.linspace(-1e-13, 1e-13, 41))
    x, res, step = jax.vmap(lambda s: secant_root(g, jnp.float64(0.0376), s, with_step=True))(guesses)
    np.testing.assert_allclose(np.asarray(x), 1.0143481980647313, atol=1e-12)
    assert np.all(np.asarray(step) < 1e-12)
    # far from the root the iterations still converge, and the derivative is the implicit function theorem's
    x, _ = secant_root(g, jnp.float64(0.0376), 1.3)
    assert float(x) == pytest.approx(1.0143481980647313, abs=1e-12)
    dx = jax.grad(lambda p: secant_root(lambda q, y: q * (y - 1.0) - 0.01, p, 1.3)[0])(jnp.float64(0.5))
    assert float(dx) == pytest.approx(-0.01 / 0.5**2, rel=1e-8)      # x* = 1 + 0.01 / p


def _copies(fn, *args, op="stablehlo.cbrt"):
    """How many copies of `op` a compiled program of `fn` holds (XLA compiles each)."""
    return jax.jit(fn).lower(*args).as_text().count(op)


def test_a_followed_root_calls_its_function_at_one_place():
    """`secant_root` puts two copies of `g` into a program (its loop's body, and the evaluation
    on the parameters as given that carries the derivative), where it had three (the first
    step's and the last step's vmapped pairs, and the loop): a fluid-film onset or a stationary
    regime's margin is most of a program, and XLA compiles each copy. The derivative is reverse
    mode's as well as forward mode's, of a `g` that allows only reverse mode too (a Floquet
    margin: an ODE solve whose adjoint is a `custom_vjp`)."""
    from rotorjax.analysis._roots import secant_root

    def g(p, x):       # a root at x = p^3 + 1; cbrt marks g's copies in the program
        return jnp.cbrt(x - 1.0) - p

    def root(p):
        return secant_root(g, p, 1.5, iters=30)[0]

    assert _copies(root, jnp.float64(0.9)) == 2
    assert float(root(jnp.float64(0.9))) == pytest.approx(0.9**3 + 1.0, rel=1e-12)
    assert float(jax.grad(root)(jnp.float64(0.9))) == pytest.approx(3 * 0.9**2, rel=1e-6)
    assert float(jax.jacfwd(root)(jnp.float64(0.9))) == pytest.approx(3 * 0.9**2, rel=1e-6)
    assert _copies(jax.grad(root), jnp.float64(0.9)) <= 2

    @jax.custom_vjp
    def shift(p):                   # reverse mode only
        return p

    shift.defvjp(lambda p: (p, None), lambda _, ct: (ct,))
    dx = jax.grad(lambda p: secant_root(lambda q, x: g(shift(q), x), p, 1.5, iters=30)[0])(jnp.float64(0.9))
    assert float(dx) == pytest.approx(3 * 0.9**2, rel=1e-6)


def test_a_value_and_its_jacobian_come_from_one_pass():
    """`value_and_jacfwd`: `f`'s value and `jax.jacfwd(f)`'s Jacobian, with one copy of `f` in the
    program (calling both puts two)."""
    from rotorjax._autodiff import value_and_jacfwd

    def f(x, y):
        return jnp.cbrt(x) * y[0] + jnp.stack([x[0] * y[1], x[1]])

    x, y = jnp.array([1.3, -0.7]), jnp.array([2.0, 0.5])
    v, (jx, jy) = value_and_jacfwd(f, argnums=(0, 1))(x, y)
    np.testing.assert_array_equal(v, f(x, y))
    for a, b in zip((jx, jy), jax.jacfwd(f, argnums=(0, 1))(x, y)):
        np.testing.assert_array_equal(a, b)
    assert _copies(value_and_jacfwd(f), x, y) == 1
    assert _copies(lambda x, y: (f(x, y), jax.jacfwd(f)(x, y)), x, y) == 2


def test_newton_with_a_unit_converges_on_a_root_at_zero():
    """`rotorjax._newton.newton(unit=)`: a step relative to `max(|x|, unit)`, so that a root at 0
    (a stationary regime on the axis) stops once the step is below `tol * unit`, its reported step
    measured so (relative to an |x| that vanishes with the root, it would be about 1 at every step)."""
    from rotorjax._newton import newton

    def r(x):
        return jnp.stack([x[0] + 0.1 * x[1] ** 2, x[1] - 0.2 * x[0] ** 3 + x[1] ** 3])

    x, (step, it) = newton(r, jnp.array([0.3, -0.2]), 1e-13, 50, unit=1.0)
    assert float(jnp.max(jnp.abs(x))) < 1e-13 and float(step) <= 1e-13 and float(it) < 12
