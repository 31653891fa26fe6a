"""Finite-element shafts: closed forms, convergence, invariants, gyroscopics, gradients."""

import jax
import jax.numpy as jnp
import numpy as np
import pytest

from rotorjax.flexible import (FlexibleRotor, campbell, critical_speeds_1x, damped_frequencies, modes,
                               unbalance_response)
from tests.helpers import central_difference

E, RHO, L, D = 211e9, 7810.0, 1.0, 0.05


def pinned(n_el, theory="euler-bernoulli", length=L, d=D):
    return FlexibleRotor(np.full(n_el, length / n_el), d, E=E, rho=RHO, theory=theory,
                         fixed_dofs=((0, 0), (0, 1), (n_el, 0), (n_el, 1)))


def exact_pinned(k, length=L, d=D):
    A, I = np.pi * d**2 / 4, np.pi * d**4 / 64
    return (k * np.pi / length) ** 2 * np.sqrt(E * I / (RHO * A))


def test_pinned_pinned_euler_bernoulli_converges_at_fourth_order():
    errors = []
    for n_el in (4, 8, 16):
        f = np.asarray(modes(pinned(n_el), 0.0).frequencies)[::2][:3]  # x and y planes pair up
        errors.append(np.abs(f / np.array([exact_pinned(k) for k in (1, 2, 3)]) - 1))
    errors = np.array(errors)
    assert errors[-1, 0] < 2e-6
    order = np.log2(errors[:-1] / errors[1:])
    assert np.all(order > 3.8)


def test_timoshenko_approaches_euler_bernoulli_with_slenderness():
    """The gap closes as (d/L)^2, as the Rayleigh-Timoshenko correction
    1 - w_T/w_EB ~ (pi r_g/L)^2 (1 + E/(kappa G)) / 2 (r_g = d/4) says."""
    gaps, predicted = [], []
    for length in (0.25, 0.5, 1.0, 2.0):
        rotor = pinned(16, "timoshenko", length)
        t = float(modes(rotor, 0.0).frequencies[0])
        e = float(modes(pinned(16, "euler-bernoulli", length), 0.0).frequencies[0])
        gaps.append(1 - t / e)
        kappa = float(rotor.kappa[0])
        predicted.append(0.5 * (np.pi * D / 4 / length) ** 2 * (1 + E / (kappa * float(rotor.G))))
    gaps, predicted = np.array(gaps), np.array(predicted)
    assert np.all(np.diff(gaps) < 0) and gaps[-1] < 1e-3
    np.testing.assert_allclose(gaps[1:], predicted[1:], rtol=0.1)


def overhung():
    return FlexibleRotor(np.full(6, 0.1), 0.03, disks=((6, 5.0, 0.05, 0.1),),
                         bearings=((0, 1e7, 1e7, 100.0, 100.0), (3, 1e7, 1e7, 100.0, 100.0)))


def test_matrix_invariants():
    M, C, G1, K = overhung().matrices()
    M, C, G1, K = (np.asarray(a) for a in (M, C, G1, K))
    np.testing.assert_allclose(M, M.T, atol=1e-14)
    np.testing.assert_allclose(K, K.T, rtol=0, atol=1e-6 * np.abs(K).max() * 1e-9)
    np.testing.assert_allclose(G1, -G1.T, atol=1e-16)
    assert np.linalg.eigvalsh(M).min() > 0 and np.linalg.eigvalsh(K).min() > 0


def test_gyroscopic_forward_stiffens_backward_softens():
    camp = campbell(overhung(), jnp.array([0.0, 500.0, 1000.0]), n_modes=4)
    f, fwd = np.asarray(camp.frequencies), np.asarray(camp.forward)
    assert f[0, 0] == pytest.approx(f[0, 1], rel=1e-9)  # a pair at rest
    for i in (1, 2):
        forward = f[i][fwd[i]][0]
        backward = f[i][~fwd[i]][0]
        assert forward > f[i - 1][0] and backward < f[i - 1][0]
    assert f[2][fwd[2]][0] > f[1][fwd[1]][0] and f[2][~fwd[2]][0] < f[1][~fwd[1]][0]


def test_critical_speed_is_where_forward_branch_meets_1x():
    rotor = overhung()
    (speed, k), *_ = critical_speeds_1x(rotor, 10.0, 600.0, n_scan=60, n_modes=4, whirl="forward")
    m = modes(rotor, speed, 4)
    assert bool(m.forward[k]) and float(m.frequencies[k]) == pytest.approx(speed, rel=1e-8)


def test_critical_speed_gradient_wrt_bearing_stiffness():
    """Implicit function theorem on omega_k(Omega; k_b) - Omega = 0 vs finite differences."""
    def rotor_with(kb):
        return FlexibleRotor(np.full(6, 0.1), 0.03, disks=((6, 5.0, 0.05, 0.1),),
                             bearings=((0, kb, kb, 0.0, 0.0), (3, kb, kb, 0.0, 0.0)))

    def crit(kb):
        return critical_speeds_1x(rotor_with(kb), 10.0, 600.0, n_scan=60, n_modes=4, xtol=1e-13,
                                  whirl="forward")[0]

    kb = 1e7
    speed, k = crit(kb)
    g = jax.grad(lambda s, b: damped_frequencies(rotor_with(b), s, 4)[k] - s, argnums=(0, 1))(
        jnp.float64(speed), jnp.float64(kb))
    ift = float(-g[1] / g[0])
    fd = central_difference(lambda b: crit(b)[0], kb, kb * 1e-4)
    assert ift == pytest.approx(fd, rel=1e-5)


def test_unbalance_response_of_a_single_mode_rotor_matches_closed_form():
    """A short stiff shaft on soft damped bearings behaves as a rigid Jeffcott rotor:
    |X| = U w^2 / |k_tot - m_tot w^2 + i c_tot w| in the cylindrical mode."""
    kb, cb = 1e5, 50.0
    rotor = FlexibleRotor(np.full(2, 0.05), 0.1, disks=((1, 10.0, 0.0, 0.0),),
                          bearings=((0, kb, kb, cb, cb), (2, kb, kb, cb, cb)), theory="euler-bernoulli")
    M, _, _, _ = rotor.matrices()
    m_tot = float(np.asarray(M)[0::4, 0::4].sum())
    w = jnp.linspace(20.0, 200.0, 7)
    X, Y = unbalance_response(rotor, 1, 1e-3, 0.0, w, probe_nodes=[1])
    expected = 1e-3 * w**2 / np.abs(2 * kb - m_tot * w**2 + 1j * 2 * cb * w)
    np.testing.assert_allclose(np.abs(np.asarray(X[:, 0])), expected, rtol=2e-3)
    np.testing.assert_allclose(np.asarray(Y[:, 0]), -1j * np.asarray(X[:, 0]), rtol=1e-6, atol=1e-15)


@pytest.mark.parametrize("make,match", [
    (lambda: FlexibleRotor(np.array([0.1, -0.1]), 0.03), "element lengths must be > 0"),
    (lambda: FlexibleRotor(np.array([0.1]), 0.0), "d_out .* must be > 0"),
    (lambda: FlexibleRotor(np.array([0.1]), 0.03, rho=0.0), "rho .* must be > 0"),
    (lambda: FlexibleRotor(np.array([0.1]), 0.03, E=-1.0), "E .* must be > 0"),
    (lambda: FlexibleRotor(np.array([0.1]), 0.03, disks=((5, 1.0, 0.1, 0.1),)), "disk at node 5"),
    (lambda: FlexibleRotor(np.array([0.1]), 0.03, bearings=((2, 1e6, 1e6, 0, 0),)), "bearing at node 2"),
    (lambda: FlexibleRotor(np.array([0.1]), 0.03, d_in=0.04), "d_in"),
    (lambda: FlexibleRotor(np.array([0.1]), 0.03, theory="shear-only"), "theory"),
])
def test_bad_input(make, match):
    with pytest.raises(ValueError, match=match):
        make()
