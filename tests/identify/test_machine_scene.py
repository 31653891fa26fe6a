"""Model 002 as a scene: `BalancingScene` (machine + planes + unbalances + speed) gives
the machine's influence coefficients through the one frequency-response solve and
its time response under the rotating unbalance force."""

import jax.numpy as jnp
import numpy as np
import pytest

import rotorjax
from rotorjax.analysis import balancing_response
from rotorjax.identify import RIG, BalancingMachine, BalancingScene, rig_scene
from rotorjax.models import ConstantSpeed, RunUp, provides
from rotorjax.models._frequency import frequency_response


def test_the_scene_contract():
    scene = rig_scene()
    assert isinstance(scene, rotorjax.models.AbstractScene) and scene.state_size == 4 and scene.n_dof == 2
    for capability in ("linear_matrices", "unbalance_load"):
        assert provides(scene, capability)
    assert not provides(scene, "to_rotating")
    lm = scene.linear_matrices(100.0)
    A, B, C = scene.machine.matrices()
    np.testing.assert_array_equal(lm.M, A)
    np.testing.assert_array_equal(lm.C, B)
    np.testing.assert_array_equal(lm.K, C)
    assert not np.any(lm.G)


@pytest.mark.parametrize("w", [20.0, 120.0, 150.0, 400.0])
def test_frequency_response_of_the_scene_is_the_machine_response(w):
    scene = rig_scene()
    lm = scene.linear_matrices(w)
    X = frequency_response(lm.M, lm.C + lm.G, lm.K, scene.unbalance_load(w), w)
    np.testing.assert_allclose(X, balancing_response(scene.machine, w, scene.planes, scene.unbalances), rtol=1e-12)


def test_influence_is_unchanged_by_the_shared_solve():
    """Eqs. (15), (17) as written before the frequency-response solve was shared, bit for bit
    (the shipped datasets were generated with them)."""
    m = rig_scene().machine
    A, B, C = m.matrices()
    for w in (20.0, 120.0, 400.0):
        for a in (0.15, 0.65):
            load = jnp.stack([m.l - a, a]).astype(jnp.complex128)
            old = w**2 / m.l * jnp.linalg.solve(C - w**2 * A + 1j * w * B, load)
            np.testing.assert_array_equal(m.influence(w, a), old)


def test_steady_orbit_in_time_equals_the_frequency_response():
    w = 120.0
    scene = rig_scene()
    X = np.asarray(balancing_response(scene.machine, w, scene.planes, scene.unbalances))
    period = 2 * np.pi / w
    ts = np.linspace(0.0, 5 * period, 101)
    r = rotorjax.simulate(scene, scene.steady_state(w), (0.0, ts[-1]), saveat=ts, rtol=1e-11, atol=1e-14)
    assert r.success
    expect = np.real(X[None, :] * np.exp(1j * w * ts)[:, None])
    got = np.stack([r.outputs["x1"], r.outputs["x2"]], axis=1)
    np.testing.assert_allclose(got, expect, atol=1e-6 * np.abs(X).max())


def test_vector_field_follows_the_speed_profile():
    """The scene's field is eq. (8) with the machine's unbalance force under `theta(t)` of
    its profile (run-up included)."""
    m = rig_scene().machine
    scene = BalancingScene(m, [0.15, 0.65], [2e-4 + 1e-4j, -3e-4j], RunUp(20.0, 19.0))
    y = jnp.array([1e-5, -2e-5, 3e-4, 1e-4])
    t = 1.3
    theta, w, alpha = 20.0 * t + 0.5 * 19.0 * t**2, 20.0 + 19.0 * t, 19.0
    A, B, C = m.matrices()
    f = m.unbalance_force(theta, w, alpha, scene.planes, scene.unbalances)
    np.testing.assert_allclose(scene.vector_field(t, y, None),
                               jnp.concatenate([y[2:], jnp.linalg.solve(A, f - B @ y[2:] - C @ y[:2])]),
                               rtol=1e-13)
    assert isinstance(BalancingScene(m, [0.2], [1e-4], 50.0).speed, ConstantSpeed)


@pytest.mark.parametrize("args,match", [
    (dict(planes=[0.2, 0.2]), r"must be distinct positions within the span"),
    (dict(planes=[0.2, 1.2]), r"within the span \[0, l=0.8\]"),
    (dict(unbalances=[1e-4]), r"unbalances"),
    (dict(machine="m"), r"machine must be a BalancingMachine"),
])
def test_bad_scenes_are_named(args, match):
    kw = dict(machine=BalancingMachine(**{k: RIG[k] for k in ("m", "I", "l", "k1", "k2", "c1", "c2")}),
              planes=[0.15, 0.65], unbalances=[1e-4, 2e-4])
    kw.update(args)
    with pytest.raises(rotorjax._errors.InputError, match=match):
        BalancingScene(**kw)
