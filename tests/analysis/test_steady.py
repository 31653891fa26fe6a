"""Stationary regimes in the rotating frame: all of them, their stability, gradients."""

import jax
import jax.numpy as jnp
import numpy as np
import pytest

import rotorjax as rj
from rotorjax.analysis import check_autonomous, rotating_field, steady_state, steady_states, to_fixed, to_rotating
from rotorjax.presets import anisotropic_abb, jeffcott_abb
from tests.helpers import central_difference
from tests.reference.paper_models import stationary_residual_000

G000 = dict(chi=0.02, eps=0.04, alpha=0.6, rho1=1.28, rho2=1.2, delta_n=0.1, delta_b=40.0)


@pytest.fixture(scope="module")
def regimes_000():
    scene = jeffcott_abb.scene_from_groups(**G000, nu=1.5)
    return scene, steady_states(scene, n_angles=16)


def test_rotating_frame_roundtrip_and_autonomy():
    scene = jeffcott_abb.scene_from_groups(**G000, nu=1.5)
    z = jnp.asarray(np.random.default_rng(0).normal(size=8))
    np.testing.assert_allclose(np.asarray(to_rotating(scene, 2.3, to_fixed(scene, 2.3, z))), np.asarray(z),
                               atol=1e-14)
    check_autonomous(scene)
    a = np.asarray(rotating_field(scene, 0.0, z))
    b = np.asarray(rotating_field(scene, 7.1, z))
    np.testing.assert_allclose(a, b, atol=1e-12)


def test_all_regimes_of_model_000_at_nu_1_5(regimes_000):
    """The paper's two touching-ball regimes (0.039210, 0.141525) and the regimes
    with the balls apart, each satisfying eq. (11) to 1e-10."""
    scene, regimes = regimes_000
    amps = np.array([float(r.whirl_amplitude) for r in regimes])
    assert len(regimes) >= 4
    for published in (0.039210, 0.141525):
        assert np.min(np.abs(amps - published)) < 5e-7
    touching = [r for r in regimes if abs(np.angle(np.exp(1j * np.diff(np.asarray(r.weight_angles))[0]))) < 1e-8]
    apart = [r for r in regimes if r not in touching]
    assert len(touching) == 2 and len(apart) >= 2
    for r in regimes:
        q = np.asarray(r.z[:4])
        res = stationary_residual_000(q[0], q[1], 1.28 * np.cos(q[2:]), 1.2 * np.sin(q[2:]),
                                      dict(G000, nu0=1.5, nu_dot=0.0))
        assert np.max(np.abs(res)) < 1e-10
        assert bool(r.converged) and r.kind == "unbalanced"


def test_stability_verdicts_agree_with_long_simulations(regimes_000):
    """From a state near each regime, a long simulation stays (stable) or leaves
    (unstable); the rotating-frame state tells which."""
    scene, regimes = regimes_000
    rng = np.random.default_rng(1)
    for r in regimes:
        z0 = np.asarray(r.z) + 1e-4 * rng.normal(size=8) * np.array([1, 1, 10, 10, 0, 0, 0, 0])
        y0 = to_fixed(scene, 0.0, jnp.asarray(z0))
        t_end = 2500.0
        sim = rj.simulate(scene, y0, (0.0, t_end), rtol=1e-9, atol=1e-11)
        z_end = np.asarray(to_rotating(scene, t_end, sim.ys[-1]))
        dist = np.max(np.abs(np.angle(np.exp(1j * (z_end[:4] - np.asarray(r.z[:4]))))))
        if r.verdict == "stable":
            assert dist < 1e-5, (float(r.whirl_amplitude), dist)
        else:
            assert dist > 1e-2, (float(r.whirl_amplitude), dist)


def test_balanced_regime_of_circular_race():
    p = dict(jeffcott_abb.PRESET.defaults, rho1=1.0, rho2=1.0, eps=0.03, nu=1.5)
    r = jeffcott_abb.balanced_regime(p)
    assert bool(r.converged) and r.kind == "balanced" and r.verdict == "stable"
    spread = np.arccos(0.03 / 0.04)
    np.testing.assert_allclose(np.sort(np.mod(np.asarray(r.weight_angles), 2 * np.pi)),
                               np.sort(np.mod(0.6 + np.pi + np.array([-spread, spread]), 2 * np.pi)),
                               atol=1e-10)
    with pytest.raises(ValueError, match="elliptic race"):
        jeffcott_abb.balanced_regime(dict(p, rho1=1.28))
    with pytest.raises(ValueError, match="capacity"):
        jeffcott_abb.balanced_regime(dict(p, eps=0.05))


def test_steady_state_gradient_by_implicit_differentiation():
    """d(whirl amplitude of a regime)/d(delta_n) against central differences."""
    guess = jnp.array([0.0, 0.0, -3.0, -3.0])

    def amplitude(delta_n):
        scene = jeffcott_abb.scene_from_groups(**dict(G000, delta_n=delta_n), nu=1.5)
        return steady_state(scene, guess).whirl_amplitude

    g = float(jax.grad(amplitude)(jnp.float64(0.1)))
    fd = central_difference(lambda v: float(amplitude(jnp.float64(v))), 0.1, 1e-5)
    assert g == pytest.approx(fd, rel=1e-6)


def test_non_autonomous_scene_gets_a_clear_error():
    scene = anisotropic_abb.scene_from_groups(**{k: anisotropic_abb.PRESET.defaults[k]
                                                 for k in anisotropic_abb.GROUPS}, n=3.0)
    with pytest.raises(ValueError, match="not autonomous in the rotating frame.*Floquet"):
        steady_states(scene)
    run_up = jeffcott_abb.scene_from_groups(**G000, nu_dot=0.1)
    with pytest.raises(ValueError, match="Floquet"):
        steady_states(run_up)


def test_non_convergence_is_reported_with_the_residual():
    scene = jeffcott_abb.scene_from_groups(**G000, nu=1.5)
    r = steady_state(scene, jnp.array([0.3, -0.2, 1.0, 2.0]), max_steps=1)
    assert not bool(r.converged) and float(r.residual) > 1e-10
