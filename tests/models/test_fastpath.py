"""The hand-derived planar balancer equations equal the Lagrangian (autodiff) path."""

import jax.numpy as jnp
import numpy as np
import pytest

from rotorjax.models import (AutoBalancer, ConstantSpeed, CustomSpeed, Race, RigidRotor, RunUp,
                             Scene, Supports)


def _random_scene(rng, race_kind, speed_kind, n_weights):
    race = {
        "circular": lambda: Race.circular(rng.uniform(0.5, 2)),
        "elliptic": lambda: Race.elliptic(rng.uniform(0.5, 2), rng.uniform(0.5, 2)),
        "eccentric": lambda: Race.eccentric(rng.uniform(0.5, 2), rng.uniform(0, 0.3), rng.uniform(-3, 3)),
    }[race_kind]()
    speed = {
        "constant": lambda: ConstantSpeed(rng.uniform(-3, 3), rng.uniform(-3, 3)),
        "run-up": lambda: RunUp(rng.uniform(0, 2), rng.uniform(-0.5, 0.5), rng.uniform(-1, 1)),
        "custom": lambda: CustomSpeed(lambda t: 1.3 * t + 0.2 * jnp.sin(2.0 * t)),
    }[speed_kind]()
    return Scene(
        RigidRotor(rng.uniform(0.5, 5), rng.uniform(0, 0.2), rng.uniform(-3, 3)),
        speed,
        (Supports(rng.uniform(0.5, 50), rng.uniform(0.5, 50), rng.uniform(0, 2), rng.uniform(0, 2)),
         AutoBalancer(rng.uniform(0.01, 0.3, size=n_weights), race, rng.uniform(0, 5),
                      inertia_factor=rng.choice([1.0, 1.4, 1.5]))),
    )


@pytest.mark.parametrize("race_kind", ["circular", "elliptic", "eccentric"])
@pytest.mark.parametrize("speed_kind", ["constant", "run-up", "custom"])
@pytest.mark.parametrize("n_weights", [1, 3])
def test_fast_path_equals_lagrangian_path(race_kind, speed_kind, n_weights):
    rng = np.random.default_rng(hash((race_kind, speed_kind, n_weights)) % 2**32)
    scene = _random_scene(rng, race_kind, speed_kind, n_weights)
    assert scene._fast_path_parts() is not None
    for _ in range(4):
        y = rng.normal(size=scene.state_size)
        t = rng.uniform(0, 10)
        fast = np.asarray(scene.vector_field(t, y))
        slow = np.asarray(scene.lagrange_vector_field(t, y))
        np.testing.assert_allclose(fast, slow, rtol=1e-11, atol=1e-12 * np.abs(slow).max())


def test_lagrange_option_and_scenes_outside_the_fast_path():
    rng = np.random.default_rng(0)
    s = _random_scene(rng, "circular", "constant", 2)
    forced = Scene(s.rotor, s.speed, s.components, equations="lagrange")
    assert forced._fast_path_parts() is None
    no_balancer = Scene(s.rotor, s.speed, (s.components[0],))
    assert no_balancer._fast_path_parts() is None
    reordered = Scene(s.rotor, s.speed, (s.components[1], s.components[0]))
    assert reordered._fast_path_parts() is None
    with pytest.raises(ValueError, match="equations"):
        Scene(s.rotor, s.speed, s.components, equations="newton")
