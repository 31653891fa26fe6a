"""Harmonic balance condensed to the coordinates the forces read
(`rotorjax.analysis._condensed`): on an FE rotor nobody tuned it on (the
anisotropic variant of `cubic_rig.toml`, bearing 0 stiffer in y, so its orbits are
ellipses with every harmonic), the condensed solve equals the whole balance's, the
derivative rule of its harmonic solves equals finite differences, and a scene
whose linear part is singular (a shaft on journal bearings alone) is balanced
whole."""

import os

import equinox as eqx
import jax
import jax.numpy as jnp
import numpy as np
import pytest
from jax.test_util import check_grads

from rotorjax import presets
from rotorjax.analysis import balance_residual, harmonic_balance
from rotorjax.analysis import _harmonic_balance, _condensed
from tests.validation.test_periodic_auto_harmonics import SHIPPED, variant_scene


@pytest.fixture(scope="module")
def scene(tmp_path_factory):
    return eqx.tree_at(lambda s: s.speed.constant, variant_scene(tmp_path_factory.mktemp("rotor")), 101.0)


def test_the_condensed_balance_equals_the_whole_one(scene, monkeypatch):
    """At 8 harmonics (the motion's truncation error 1e-5: every harmonic present)
    the condensed Newton takes the same iterations to the same coefficients (1e-10
    of the largest) as the whole balance's, whose residual the condensed motion
    meets to 1e-8 of the field's size; 4 unknowns a harmonic instead of 32."""
    local = scene.local_forces()
    assert _condensed.condensable(scene) and local.S.shape[0] == 4 and scene.state_size == 32
    T = 2 * np.pi / 101.0
    condensed = harmonic_balance(scene, T, jnp.zeros(scene.state_size), 8, stability=False)
    monkeypatch.setattr(_harmonic_balance, "condensable", lambda s: False)
    whole = harmonic_balance(scene, T, jnp.zeros(scene.state_size), 8, stability=False)
    assert int(condensed.code) == int(whole.code) == 0
    assert int(condensed.iterations) == int(whole.iterations)
    Y, Yw = np.asarray(condensed.coefficients), np.asarray(whole.coefficients)
    assert np.max(np.abs(Y - Yw)) < 1e-10 * np.max(np.abs(Yw))
    assert np.max(np.abs(Y[3:])) > 1e-4 * np.max(np.abs(Y))          # not a circle: higher harmonics
    field = np.max(np.abs(_harmonic_balance._derivative(Yw, 2 * np.pi / T)))
    assert float(np.max(np.abs(balance_residual(scene, Y, T)))) < 1e-8 * field
    assert float(condensed.time_residual) == pytest.approx(float(whole.time_residual), rel=1e-3)
    from tests.helpers import documentation

    text = " ".join(documentation("docs/periodic.md").split())
    assert (f"with {local.S.shape[0]} unknowns a harmonic instead of {scene.state_size} for the shipped rig" in text
            and "equal to the whole balance to 1e-10" in text)


def test_the_harmonic_solves_derivative_rule_equals_finite_differences():
    """`_harmonic_solves`' derivative rule (from the same factors, not through them)
    against central differences, forward and reverse, in the matrix, the frequency
    and the right-hand sides."""
    rng = np.random.default_rng(0)
    A = jnp.asarray(rng.normal(size=(6, 6))) - 3 * jnp.eye(6)
    rhs = jnp.asarray(rng.normal(size=(4, 6)) + 1j * rng.normal(size=(4, 6)))
    check_grads(_condensed._harmonic_solves, (A, 1.3, rhs), order=1, modes=["fwd", "rev"], atol=1e-7, rtol=1e-7)


def test_a_shaft_on_journal_bearings_alone_is_balanced_whole():
    """The shipped journal rig's linear part (no linear support: its journals' films
    are its forces) is singular: no condensation, the whole balance as before."""
    path = os.path.join(os.path.dirname(SHIPPED), "journal_rig.toml")
    preset = presets.get(path)
    sc = preset.build(preset.params()).scene
    local = sc.local_forces()
    assert local is not None and np.linalg.cond(np.asarray(local.A)) > _condensed.CONDENSE_COND
    assert not _condensed.condensable(sc)


def test_gradients_through_either_balance_equal_finite_differences(scene):
    """`jax.grad` of a motion's harmonic: in the cubic stiffness (the linear part
    concrete: the condensed balance, differentiated by the implicit function
    theorem) and in the speed (the linear part traced: it cannot be checked, so the
    whole balance runs), each against central differences of concrete (condensed)
    solves."""
    Y0 = harmonic_balance(scene, 2 * np.pi / 101.0, jnp.zeros(scene.state_size), 2, stability=False).coefficients
    condensed = []

    def amplitude(k3, w):
        sc = eqx.tree_at(lambda s: (s.components[-1].k3, s.speed.constant), scene, (k3, w))
        condensed.append(_condensed.condensable(sc))
        return harmonic_balance(sc, 2 * np.pi / w, Y0, 2, stability=False).coefficients[1, 0]

    k3, w = scene.components[-1].k3, jnp.asarray(101.0)
    for i, h in ((0, 1e-4 * k3), (1, 1e-4 * w)):
        g = jax.grad(amplitude, argnums=i)(k3, w)
        dx = [jnp.zeros(()), jnp.zeros(())]
        dx[i] = h
        fd = (amplitude(k3 + dx[0], w + dx[1]) - amplitude(k3 - dx[0], w - dx[1])) / (2 * h)
        assert float(g) == pytest.approx(float(fd), rel=1e-5)
    assert condensed == [True, True, True, False, True, True]
