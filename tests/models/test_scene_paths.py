"""Leaves of a scene addressed by path (data): what a preset's sweepable keys name."""

import jax.numpy as jnp
import pytest

from rotorjax._errors import InputError
from rotorjax.models import ConstantSpeed, FlexibleRotor, RotorScene, Unbalance, leaf_at, with_leaf


@pytest.fixture(scope="module")
def scene():
    rotor = FlexibleRotor([0.2] * 4, 0.04, bearings=[(0, 1e7, 1e7, 0, 0), (4, 1e7, 1e7, 0, 0)])
    return RotorScene(rotor, ConstantSpeed(100.0), (Unbalance(2, 1e-4, 0.3),))


def test_paths_read_and_set_leaves(scene):
    assert float(leaf_at(scene, "speed.constant")) == 100.0
    assert float(leaf_at(scene, "components[Unbalance].phase")) == pytest.approx(0.3)
    changed = with_leaf(scene, "components[Unbalance].magnitude", jnp.float64(2e-4))
    assert float(changed.components[0].magnitude) == 2e-4 and float(scene.components[0].magnitude) == 1e-4


def test_a_missing_component_is_named(scene):
    with pytest.raises(InputError, match=r"needs limiters \(no LimitersAt in the scene's components\)"):
        leaf_at(scene, "components[LimitersAt].limiters.clearance")
