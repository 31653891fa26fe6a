"""Issue 29: one `modes`, one Campbell diagram for every linear system: the finite-element
rotor and its scene, and a linear scene without nodes (model 002's balancing machine),
against an independent eigen-solve (scipy), and a scene without linear equations refused
by its capability."""

import numpy as np
import pytest
import scipy.linalg

from rotorjax import analysis
from rotorjax.models import BalancingMachine, BalancingScene, ConstantSpeed, MissingCapability, Scene
from rotorjax.models import RigidRotor, Supports


@pytest.fixture(scope="module")
def machine():
    return BalancingMachine(m=20.0, I=0.9, l=0.6, k1=2e6, k2=3e6, c1=0.0, c2=0.0)


def _scene(machine):
    return BalancingScene(machine, np.array([0.1, 0.5]), np.array([1e-4 + 0j, 2e-4j]), ConstantSpeed(100.0))


def test_modes_of_a_linear_scene_without_nodes(machine):
    """Undamped: the frequencies are the generalised eigenvalues of (K, M) (scipy's eigh);
    the shapes are on the scene's coordinates and the whirl is undefined."""
    m = analysis.modes(_scene(machine), 100.0)
    A, _, C = (np.asarray(a) for a in machine.matrices())
    expected = np.sqrt(scipy.linalg.eigh(C, A, eigvals_only=True))
    np.testing.assert_allclose(np.asarray(m.frequencies), expected, rtol=1e-12)
    assert np.asarray(m.shapes).shape == (2, 2)
    assert list(m.whirl) == ["undefined", "undefined"] and not np.any(np.asarray(m.forward))
    camp = analysis.campbell(_scene(machine), np.array([0.0, 50.0, 100.0]), n_modes=2)
    np.testing.assert_allclose(np.asarray(camp.frequencies), np.tile(expected, (3, 1)), rtol=1e-12)


def test_damped_modes_of_a_linear_scene_against_scipy():
    damped = BalancingMachine(m=20.0, I=0.9, l=0.6, k1=2e6, k2=3e6, c1=800.0, c2=300.0)
    m = analysis.modes(_scene(damped), 100.0)
    A, B, C = (np.asarray(a) for a in damped.matrices())
    n = A.shape[0]
    state = np.block([[np.zeros((n, n)), np.eye(n)], [-np.linalg.solve(A, C), -np.linalg.solve(A, B)]])
    lam = scipy.linalg.eigvals(state)
    lam = np.sort_complex(lam[lam.imag > 0])
    np.testing.assert_allclose(np.sort_complex(np.asarray(m.eigenvalues)), lam, rtol=1e-12)


def test_a_scene_without_linear_equations_is_refused_by_capability():
    planar = Scene(RigidRotor(1.0, 1e-3, 0.0), ConstantSpeed(1.0), (Supports.isotropic(1.0, 0.1),))
    with pytest.raises(MissingCapability, match="modes needs a scene with `linear_system`; Scene .*"
                                                "AbstractLinearSystem"):
        analysis.modes(planar, 1.0)
    with pytest.raises(MissingCapability, match="static needs|finite-element shaft layout"):
        analysis.static(planar)
