"""Components: validation at construction, invariants of the derived equations."""

import jax
import jax.numpy as jnp
import numpy as np
import pytest

import rotorjax as rj
from rotorjax.models import (AutoBalancer, ConstantSpeed, CustomSpeed, Race, RigidRotor, RunUp,
                             Scene, Supports)
from rotorjax.presets import jeffcott_abb


@pytest.mark.parametrize("make,match", [
    (lambda: RigidRotor(0.0), "mass must be > 0"),
    (lambda: RigidRotor(-1.0), "mass must be > 0"),
    (lambda: RigidRotor(float("nan")), "mass must be finite"),
    (lambda: RigidRotor(1.0, eccentricity=-1e-3), "eccentricity must be >= 0"),
    (lambda: Supports(1.0, 1.0, -0.1, 0.0), "cx must be >= 0"),
    (lambda: Supports(1.0, float("inf")), "ky must be finite"),
    (lambda: Supports(0.0, 1.0), "kx must be > 0"),
    (lambda: Race(0.0, 1.0), "r1 .* must be > 0"),
    (lambda: Race(1.0, -2.0), "r2 .* must be > 0"),
    (lambda: Race.circular(1.0).__class__(1.0, 1.0, center=(0.0, 0.0, 1.0)), "race center must have shape"),
    (lambda: AutoBalancer(np.array([0.1, -0.1]), Race.circular(1.0)), "weight mass must be > 0"),
    (lambda: AutoBalancer(np.array([0.1]), Race.circular(1.0), drag=-1.0), "weight drag must be >= 0"),
    (lambda: AutoBalancer(0.1, Race.circular(1.0)), "one entry per weight"),
    (lambda: AutoBalancer(np.array([0.1]), Race.circular(1.0), kind="cube"), "weight kind"),
    (lambda: AutoBalancer(np.array([0.1]), "circle"), "race must be"),
    (lambda: RigidRotor("heavy"), "mass must be a number"),
    (lambda: Scene(RigidRotor(1.0), 3.0), "speed must be a speed profile"),
    (lambda: CustomSpeed(3.0), "angle_fn must be callable"),
])
def test_bad_input_names_the_parameter(make, match):
    with pytest.raises(ValueError, match=match):
        make()


def _scene(rng, speed=None, damped=True):
    g = dict(chi=0.03, eps=0.02, alpha=0.4, rho1=1.1, rho2=0.9, delta_n=0.2 if damped else 0.0,
             delta_b=3.0 if damped else 0.0)
    s = jeffcott_abb.scene_from_groups(**g, nu=1.7, n_balls=3, K=1.4)
    if speed is not None:
        s = Scene(s.rotor, speed, s.components)
    return s


def test_mass_matrix_symmetric_positive_definite():
    rng = np.random.default_rng(0)
    scene = _scene(rng)
    for _ in range(5):
        q = rng.normal(size=scene.n_dof)
        m = np.asarray(scene.mass_matrix(q, rng.uniform(0, 5)))
        np.testing.assert_allclose(m, m.T, atol=1e-14)
        assert np.all(np.linalg.eigvalsh(m) > 0)


@pytest.mark.parametrize("speed", [ConstantSpeed(1.7), RunUp(0.3, 0.2),
                                   CustomSpeed(lambda t: 1.5 * t + 0.3 * jnp.sin(0.7 * t))])
def test_energy_balance_identity(speed):
    """Along the vector field, the energy function h = p.qd - L obeys
    dh/dt = -dL/dt|explicit - 2 D (Rayleigh), at random states."""
    rng = np.random.default_rng(1)
    scene = _scene(rng, speed)
    n = scene.n_dof

    def h(q, qd, t):
        p = jax.grad(scene.lagrangian, argnums=1)(q, qd, t)
        return p @ qd - scene.lagrangian(q, qd, t)

    for _ in range(4):
        y = rng.normal(size=2 * n)
        t = rng.uniform(0, 5)
        q, qd = jnp.asarray(y[:n]), jnp.asarray(y[n:])
        qdd = scene.accelerations(t, q, qd)
        _, dh = jax.jvp(h, (q, qd, jnp.float64(t)), (qd, qdd, jnp.float64(1.0)))
        _, dl_dt = jax.jvp(lambda tt: scene.lagrangian(q, qd, tt), (jnp.float64(t),), (jnp.float64(1.0),))
        expected = -dl_dt - 2 * scene.dissipation(q, qd, t)
        assert float(dh) == pytest.approx(float(expected), rel=1e-10, abs=1e-10)


def test_energy_conserved_without_spin_or_damping():
    """Not spinning and undamped: T + V is conserved along a trajectory."""
    rng = np.random.default_rng(2)
    scene = _scene(rng, ConstantSpeed(0.0), damped=False)
    y0 = jnp.asarray(rng.normal(size=scene.state_size) * 0.3)
    r = rj.simulate(scene, y0, (0.0, 30.0), saveat=7, rtol=1e-12, atol=1e-14)
    n = scene.n_dof
    e = np.array([scene.kinetic_energy(y[:n], y[n:], t) + scene.potential_energy(y[:n], t)
                  for t, y in zip(r.ts, r.ys)])
    assert np.ptp(e) < 1e-8 * abs(e[0])  # integrator drift at rtol 1e-12: ~4e-10


def test_isotropic_scene_is_rotation_invariant():
    """Rotating the initial state and the imbalance phase by the same angle rotates
    the whole trajectory (isotropic supports, circular race)."""
    g = dict(chi=0.02, eps=0.03, rho1=1.0, rho2=1.0, delta_n=0.1, delta_b=2.0)
    beta = 0.7
    a = jeffcott_abb.scene_from_groups(**g, alpha=0.2, nu=1.4)
    b = jeffcott_abb.scene_from_groups(**g, alpha=0.2 + beta, nu=1.4)
    ya = np.array([0.01, 0.02, 0.5, 2.0, 0.0, 0.0, 0.1, -0.1])
    yb = ya.copy()
    c, s = np.cos(beta), np.sin(beta)
    yb[0:2] = [c * ya[0] - s * ya[1], s * ya[0] + c * ya[1]]
    yb[4:6] = [c * ya[4] - s * ya[5], s * ya[4] + c * ya[5]]
    yb[2:4] += beta
    ra = rj.simulate(a, ya, (0.0, 20.0), rtol=1e-11, atol=1e-13)
    rb = rj.simulate(b, yb, (0.0, 20.0), rtol=1e-11, atol=1e-13)
    assert float(ra.outputs["whirl_amplitude"][-1]) == pytest.approx(float(rb.outputs["whirl_amplitude"][-1]), rel=1e-8)
    np.testing.assert_allclose(np.asarray(rb.ys[-1][2:4]) - beta, np.asarray(ra.ys[-1][2:4]), atol=1e-8)


def test_weight_inertia_factor_enters_as_model_001_states():
    """K m R^2 phi'' + b_w R^2 (phi' - w) = 0 when the rotor cannot move (a very
    heavy rotor): the weight's relative angular acceleration is -b_w psid / (K m)."""
    accs = []
    for K in (1.0, 1.4, 1.5):
        race = Race.circular(0.1)
        s = Scene(RigidRotor(1e15), ConstantSpeed(10.0),
                  (Supports(1e12, 1e12), AutoBalancer(np.array([0.05]), race, drag=0.3, inertia_factor=K)))
        y = np.array([0.0, 0.0, 0.4, 0.0, 0.0, 2.0])
        accs.append(float(s.vector_field(0.0, y)[-1]) * K)
    np.testing.assert_allclose(accs, -0.3 * 2.0 / 0.05, rtol=1e-10)


def test_absent_components_are_absent():
    s = jeffcott_abb.scene_from_groups(0.02, 0.04, 0.6, 1.28, 1.2, 0.18, 40.0, with_balancer=False)
    assert s.n_dof == 2 and s.find(AutoBalancer) is None
    assert "weight_angles" not in s.outputs(0.0, jnp.zeros(4))


@pytest.mark.parametrize("race", [Race.circular(1.0), Race.elliptic(1.28, 1.2),
                                  Race.eccentric(1.0, 0.05, 0.7)])
def test_weights_at_places_weights_at_polar_angles(race):
    from rotorjax.models import weights_at

    angles = np.array([-3.0, -1.0, 0.0, 0.5, 2.9])
    p = np.stack([np.asarray(race.position(psi)) for psi in weights_at(angles, race)])
    np.testing.assert_allclose(np.arctan2(p[:, 1], p[:, 0]), angles, atol=1e-12)


def test_eccentric_race_leaves_a_residual_imbalance():
    """A race offset by e from the rotor axis: two balls that would cancel the
    imbalance on a centred race leave a mass moment of 2 m_b e (model of the
    paper's reference [10]); the scene's residual_imbalance reports it."""
    m_b, e = 0.02, 0.01
    scene = Scene(RigidRotor(1.0, 0.03, 0.0), ConstantSpeed(1.5),
                  (Supports.isotropic(1.04, 0.1),
                   AutoBalancer(np.full(2, m_b), Race.eccentric(1.0, e, np.pi / 2), drag=1.0)))
    spread = np.arccos(0.03 / (2 * m_b))
    psi = np.pi + np.array([-spread, spread])  # on the centred circle these cancel
    y = scene.rest_state(psi)
    np.testing.assert_allclose(np.asarray(scene.imbalance(0.0, y)), [0.0, 2 * m_b * e], atol=1e-15)
    assert float(scene.outputs(0.0, y)["residual_imbalance"]) == pytest.approx(2 * m_b * e)


def test_custom_speed_equals_run_up():
    a = _scene(None, RunUp(0.4, 0.16))
    b = _scene(None, CustomSpeed(lambda t: 0.4 * t + 0.08 * t**2))
    y = np.random.default_rng(5).normal(size=a.state_size)
    np.testing.assert_allclose(np.asarray(a.vector_field(3.0, y)), np.asarray(b.vector_field(3.0, y)),
                               rtol=1e-13, atol=1e-13)
