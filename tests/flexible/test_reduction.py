"""Modal reduction and the roots of the synchronous determinant."""

import jax
import jax.numpy as jnp
import numpy as np
import pytest

from rotorjax.flexible import (FlexibleRotor, ReducedRotor, campbell, critical_speeds_1x, damped_frequencies,
                               synchronous_critical_speeds, unbalance_response)
from tests.helpers import central_difference


def two_disk(kb=1e6, kyy_ratio=0.8, cb=0.0):
    return FlexibleRotor(np.full(6, 0.25), 0.05, disks=((2, 32.6, 0.178, 0.33), (4, 32.6, 0.178, 0.33)),
                         bearings=((0, kb, kyy_ratio * kb, cb, cb), (6, kb, kyy_ratio * kb, cb, cb)))


def test_full_basis_reproduces_the_full_model():
    rotor = two_disk(cb=50.0)
    full = rotor.reduce(len(rotor.free_dofs))
    for speed in (0.0, 700.0):
        np.testing.assert_allclose(damped_frequencies(full, speed, 8), damped_frequencies(rotor, speed, 8),
                                   rtol=1e-10)
    w = jnp.linspace(50.0, 900.0, 9)
    np.testing.assert_allclose(unbalance_response(full, 2, 1e-3, 0.3, w)[0],
                               unbalance_response(rotor, 2, 1e-3, 0.3, w)[0], rtol=1e-8, atol=1e-14)


def test_reduction_error_falls_as_modes_are_added():
    rotor = two_disk()
    exact = np.asarray(campbell(rotor, jnp.array([0.0, 500.0, 1000.0]), 4).frequencies)
    errors = [np.max(np.abs(np.asarray(campbell(rotor.reduce(n), jnp.array([0.0, 500.0, 1000.0]), 4)
                                       .frequencies) / exact - 1)) for n in (8, 12, 20)]
    assert errors[0] > errors[1] > errors[2] and errors[2] < 1e-5


def test_reduced_mode_shapes_live_on_all_dofs():
    rotor = two_disk()
    m = campbell(rotor.reduce(12), jnp.array([300.0]), 4)
    assert m.shapes.shape == (1, rotor.n_dofs, 4)


def test_reduction_is_differentiable_at_repeated_frequencies():
    """An isotropic rotor has x/y pairs of equal frequency; the frozen basis keeps
    the gradient finite, and close to the full model's."""
    def f(kb, n=None):
        rotor = two_disk(kb, kyy_ratio=1.0)
        return damped_frequencies(rotor if n is None else rotor.reduce(n), 300.0, 1)[0]

    g_red = jax.grad(lambda k: f(k, 16))(1e6)
    assert np.isfinite(g_red)
    assert float(g_red) == pytest.approx(float(jax.grad(f)(1e6)), rel=1e-3)


def test_synchronous_determinant_roots_equal_campbell_intersections():
    rotor = two_disk()
    scan = [s for s, _ in critical_speeds_1x(rotor, 1.0, 1500.0, n_modes=12, whirl="all", xtol=1e-12)]
    roots = np.asarray(synchronous_critical_speeds(rotor))
    np.testing.assert_allclose(roots[: len(scan)], scan, rtol=1e-8)
    # each root makes the synchronous dynamic stiffness singular
    M, _, G1, K = (np.asarray(a) for a in rotor.reduced_matrices())
    for w in roots[:4]:
        s = np.linalg.svd(K - w**2 * M + 1j * w**2 * G1, compute_uv=False)
        assert s[-1] / s[0] < 1e-10


def test_synchronous_critical_speed_gradient_and_vmap():
    f = lambda kb: synchronous_critical_speeds(two_disk(kb), 1)[0]  # noqa: E731
    assert float(jax.grad(f)(1e6)) == pytest.approx(central_difference(f, 1e6, 1e2), rel=1e-6)
    kb = jnp.array([5e5, 1e6, 2e6])
    np.testing.assert_allclose(jax.vmap(f)(kb), [f(k) for k in kb], rtol=1e-12)


def test_gyroscopic_stiffening_leaves_no_critical_speed():
    """A thin disk (Ip = 2 It) at the free end of an overhung shaft: its
    conical forward mode stiffens faster than 1x, so one root is missing (inf)."""
    disk_only = FlexibleRotor(np.full(4, 0.1), 0.03, disks=((4, 5.0, 0.2, 0.4),),
                              bearings=((0, 1e8, 1e8, 0.0, 0.0), (2, 1e8, 1e8, 0.0, 0.0)))
    point = FlexibleRotor(np.full(4, 0.1), 0.03, disks=((4, 5.0, 0.2, 0.0),),
                          bearings=((0, 1e8, 1e8, 0.0, 0.0), (2, 1e8, 1e8, 0.0, 0.0)))
    n = len(disk_only.free_dofs)
    assert np.sum(np.isinf(np.asarray(synchronous_critical_speeds(disk_only)))) > 0
    assert np.sum(np.isinf(np.asarray(synchronous_critical_speeds(point)))) == 0
    assert synchronous_critical_speeds(point).shape == (n,)


@pytest.mark.parametrize("make,match", [
    (lambda: two_disk().reduce(0), "n_modes"),
    (lambda: ReducedRotor(two_disk(), 1000), "n_modes"),
    (lambda: synchronous_critical_speeds(two_disk(cb=10.0)), "undamped"),
])
def test_bad_input(make, match):
    with pytest.raises(ValueError, match=match):
        make()
