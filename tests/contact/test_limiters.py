"""Limiters (model 004, eq. 10): the exact force, its smoothing, friction, input checks."""

import jax.numpy as jnp
import numpy as np
import pytest

from rotorjax.contact import Limiters

ANGLES = np.pi / 3 + 2 * np.pi / 3 * np.arange(3)


def paper_force(pos, vel, N, radius, angles, chi, kappa, eta, f):
    """Eq. (10) transcribed per limiter in its local axes (x_k along the limiter,
    y_k tangential, positive with the spin), then rotated by T_k."""
    total = np.zeros(2)
    for a in angles:
        T = np.array([[np.cos(a), -np.sin(a)], [np.sin(a), np.cos(a)]])
        xl, vl = T.T @ pos, T.T @ vel
        r = kappa * (xl[0] - chi) + eta * vl[0]
        if xl[0] - chi > 0 and r > 0:
            V = N * radius + vl[1]
            total += T @ (-r * np.array([1.0, f * np.sign(V)]))
    return total


def test_exact_force_is_eq_10_at_random_states():
    rng = np.random.default_rng(0)
    lim = Limiters(ANGLES, 0.0107, 850.0, 0.06, 0.1)
    for _ in range(200):
        pos, vel = rng.normal(0, 0.012, 2), rng.normal(0, 0.05, 2)
        active = np.asarray(lim.indicator(jnp.asarray(pos), jnp.asarray(vel))) > 0
        ours = np.asarray(lim.force(jnp.asarray(pos), jnp.asarray(vel), 15.0, 0.1429, jnp.asarray(active))[0])
        np.testing.assert_allclose(ours, paper_force(pos, vel, 15.0, 0.1429, ANGLES, 0.0107, 850.0, 0.06, 0.1),
                                   rtol=1e-12, atol=1e-15)


def test_smoothed_force_converges_to_the_exact_one():
    rng = np.random.default_rng(1)
    states = [(rng.normal(0, 0.012, 2), rng.normal(0, 0.05, 2)) for _ in range(100)]
    errors = []
    for ell in (1e-5, 1e-6, 1e-7):
        lim = Limiters(ANGLES, 0.0107, 850.0, 0.06, 0.1, smoothing=ell)
        err = 0.0
        for pos, vel in states:
            g = np.asarray(lim.indicator(pos, vel))
            if np.min(np.abs(g)) < 1e-3 * 850 * 1e-4:  # too close to a switch to compare
                continue
            exact = np.asarray(lim.force(pos, vel, 15.0, 0.1429, jnp.asarray(g > 0))[0])
            err = max(err, float(np.max(np.abs(np.asarray(lim.force(pos, vel, 15.0, 0.1429)[0]) - exact))))
        errors.append(err)
    assert errors[0] > errors[1] > errors[2] and errors[2] < 1e-6


def test_no_force_out_of_contact_and_friction_opposes_slip():
    lim = Limiters([0.0], 0.01, 100.0, 0.0, 0.2)
    f, R = lim.force(jnp.array([0.005, 0.0]), jnp.zeros(2), 10.0, 0.1, jnp.array([False]))
    assert np.all(np.asarray(f) == 0) and float(R[0]) == 0
    f, R = lim.force(jnp.array([0.011, 0.0]), jnp.zeros(2), 10.0, 0.1, jnp.array([True]))
    # pushed back along -x; the rim at angle 0 moves along +y with the spin: friction along -y
    np.testing.assert_allclose(np.asarray(f), [-0.1, -0.02], rtol=1e-12)
    # a tensile "force" (disk leaving faster than the limiter relaxes) is no force
    f, R = Limiters([0.0], 0.01, 100.0, 10.0, 0.2).force(jnp.array([0.011, 0.0]), jnp.array([-1.0, 0.0]), 10.0,
                                                       0.1, jnp.array([True]))
    assert float(R[0]) < 0  # the exact force trusts the contact set given by the events ...
    assert float(Limiters([0.0], 0.01, 100.0, 10.0, 0.2).indicator(jnp.array([0.011, 0.0]),
                                                                 jnp.array([-1.0, 0.0]))[0]) < 0  # ... which ends it


@pytest.mark.parametrize("make,match", [
    (lambda: Limiters(ANGLES, 0.0, 850.0), "clearance .* must be > 0"),
    (lambda: Limiters(ANGLES, -0.01, 850.0), "clearance"),
    (lambda: Limiters(ANGLES, 0.01, -1.0), "stiffness .* must be >= 0"),
    (lambda: Limiters(ANGLES, 0.01, 850.0, friction=-0.1), "friction .* must be >= 0"),
    (lambda: Limiters(ANGLES, 0.01, 850.0, damping=-0.1), "damping"),
    (lambda: Limiters(ANGLES, [0.01, 0.01], 850.0), r"one value per limiter \(3\)"),
    (lambda: Limiters(ANGLES, 0.01, [850.0, 850.0]), "stiffness"),
    (lambda: Limiters([], 0.01, 850.0), "at least|>= 1"),
    (lambda: Limiters(ANGLES, 0.01, 850.0, smoothing=0.0), "smoothing"),
])
def test_bad_input(make, match):
    with pytest.raises(ValueError, match=match):
        make()
