"""Composition (d): model 004 (the `cantilever-limiters` preset) is a `RotorScene` of
the shared components, with the equations of the hand-assembled `CantileverScene`
it replaced (kept, deprecated, as the reference: `M q'' + (C + Ci + N G1) q' +
(K + N Ci J) q = P^T (unbalance + limiters at the disk) - gamma M e_x`, with the
work of the non-conservative forces as the last state)."""

import equinox as eqx
import jax
import jax.numpy as jnp
import numpy as np
import pytest

from rotorjax import models
from rotorjax.models import (DiskDamping, ExternalDamping, Gravity, InternalDamping, LimitersAt,
                             NodeProbe, RotorScene, Unbalance, leaf_at, with_leaf)
from rotorjax.presets import cantilever_limiters as cl
from tests.reference.model_004_scene import CantileverScene

BASE = dict(cl.PRESET.defaults, smoothing=1e-5)


def _old(p):
    return CantileverScene(cl.build_rotor(p), p["N"], eps=p["eps"], phase=p["phase"], gamma=p["gamma"],
                           limiters=cl.build_limiters(p), n_modes=p["n_modes"] or None)


def _states(old, rng, n=25):
    """States whose disk sits near the limiters (in and out of contact), other modes
    excited a little."""
    disk_pinv = np.linalg.pinv(np.asarray(old.disk[:2]))
    for _ in range(n):
        q = disk_pinv @ rng.normal(0, 0.011, 2) + rng.normal(0, 1e-4, old.n_coords)
        qd = disk_pinv @ rng.normal(0, 0.05, 2) + rng.normal(0, 1e-3, old.n_coords)
        yield rng.uniform(0, 10), jnp.asarray(np.concatenate([q, qd, [0.0]]))


def test_preset_scene_is_a_rotor_scene_of_the_shared_components():
    scene = cl.build_scene(BASE)
    assert isinstance(scene, RotorScene) and scene.track_work
    kinds = [type(c) for c in scene.components]
    assert kinds == [NodeProbe, Unbalance, InternalDamping, ExternalDamping, DiskDamping, LimitersAt]
    for kind in kinds:   # the shared component set, exported
        assert getattr(models, kind.__name__) is kind
    node = BASE["n_elements"]
    assert all(c.node == node for c in scene.components if c.node is not None)
    assert isinstance(scene.rotor, models.ReducedRotor) and scene.n_shaft == BASE["n_modes"]
    assert isinstance(cl.build_scene(dict(BASE, n_modes=0)).rotor, models.FlexibleRotor)
    assert Gravity in [type(c) for c in cl.build_scene(dict(BASE, gamma=0.3)).components]
    assert LimitersAt not in [type(c) for c in cl.build_scene(dict(BASE, n_limiters=0)).components]
    # the sweepable keys point into the components
    lim = scene.components[-1].limiters
    for key, leaf in (("eps", scene.components[1].magnitude), ("phase", scene.components[1].phase),
                      ("f_S", lim.friction), ("chi", lim.clearance)):
        assert leaf_at(scene, cl.PRESET.sweepable[key]) is leaf
    assert float(leaf_at(scene, cl.PRESET.sweepable["N"])) == BASE["N"] == float(scene.speed.speed(0.0))


@pytest.mark.parametrize("n_modes", [6, 0])
def test_vector_field_equals_the_old_formulation_at_random_states(n_modes):
    p = dict(BASE, n_modes=n_modes)
    old, new = _old(p), cl.build_scene(p)
    assert new.state_size == old.state_size
    f_old = jax.jit(lambda t, y, a: old.vector_field(t, y, a))
    f_new = jax.jit(lambda t, y, a: new.vector_field(t, y, a))
    rng = np.random.default_rng(7)
    checked_contact = False
    for t, y in _states(old, rng):
        for active in (None, jnp.asarray(old.contact_indicator(t, y) > 0)):
            a, b = np.asarray(f_old(t, y, active)), np.asarray(f_new(t, y, active))
            np.testing.assert_allclose(b, a, rtol=0, atol=1e-12 * np.max(np.abs(a)))
            checked_contact |= active is not None and bool(np.any(active))
        # the same contact set (the indicators differ in scale, not in sign)
        np.testing.assert_array_equal(np.asarray(new.contact_indicator(t, y)) > 0,
                                      np.asarray(old.contact_indicator(t, y)) > 0)
        o_old, o_new = old.outputs(t, y), new.outputs(t, y)
        for k in ("disk_x", "disk_y", "disk_vx", "disk_vy", "disk_tilt_x", "disk_tilt_y"):
            np.testing.assert_allclose(float(o_new[k]), float(o_old[k]), rtol=1e-12, atol=1e-15)
        np.testing.assert_allclose(float(o_new["disk_radius"]), float(o_old["radius"]), rtol=1e-12)
        np.testing.assert_allclose(np.asarray(o_new["normal_forces"]), np.asarray(o_old["normal_forces"]),
                                   rtol=1e-12, atol=1e-12)
    assert checked_contact
    for speed in (0.0, 7.0, 15.0):
        lo, ln = old.linear_matrices(speed), new.linear_matrices(speed)
        for a, b in zip(lo, ln):
            np.testing.assert_allclose(np.asarray(b), np.asarray(a), rtol=0, atol=1e-12 * np.max(np.abs(a)))
    np.testing.assert_allclose(np.asarray(new.unbalance_load(9.0)), np.asarray(old.unbalance_load(9.0)),
                               rtol=1e-13, atol=1e-18)
    # the preset's initial state: the same kick along the disk's y
    n = old.n_coords
    y0_old = old.rest_state().at[n:2 * n].add(p["perturbation"] * old.disk[1])
    np.testing.assert_allclose(np.asarray(cl.initial_state(new, p)), np.asarray(y0_old), rtol=1e-13, atol=1e-18)


def test_swept_leaves_change_the_composition_like_the_old_fields():
    old, new = _old(BASE), cl.build_scene(BASE)
    rng = np.random.default_rng(8)
    for key, value in (("eps", 0.0009), ("phase", 0.8), ("N", 13.0), ("kappa", 600.0), ("f_S", 0.3)):
        o = _old(dict(BASE, **{key: value}))
        path = cl.PRESET.sweepable[key]
        n = with_leaf(new, path, jnp.broadcast_to(jnp.float64(value), jnp.shape(leaf_at(new, path))))
        for t, y in _states(old, rng, 3):
            a, b = np.asarray(o.vector_field(t, y)), np.asarray(n.vector_field(t, y))
            np.testing.assert_allclose(b, a, rtol=0, atol=1e-12 * np.max(np.abs(a)))


def test_weight_is_the_gravity_component_with_the_clamped_nodes_share():
    """`Gravity` loads every node's consistent share of the weight; the old scene left
    out the clamped node's coupling to the first element (`M[free, clamped]`), a
    difference in the load only (the preset's default `gamma = 0`: no weight)."""
    p = dict(BASE, gamma=0.3)
    old, new = _old(p), cl.build_scene(p)
    rotor = cl.build_rotor(p).shaft()
    M = np.asarray(rotor.matrices()[0])
    free, fixed = rotor.free_dofs, np.asarray(rotor.fixed_dofs)
    e = np.zeros(rotor.n_dofs)
    e[0::4] = -1.0
    share = np.asarray(new.rotor.basis).T @ (M[np.ix_(free, fixed)] @ e[fixed])
    np.testing.assert_allclose(np.asarray(new.F0), np.asarray(old.gamma * old.unit_weight) + 0.3 * share,
                               rtol=1e-12, atol=1e-15)
    # with the old load the vector fields agree
    patched = eqx.tree_at(lambda s: s.F0, new, old.gamma * old.unit_weight)
    for t, y in _states(old, np.random.default_rng(9), 5):
        a, b = np.asarray(old.vector_field(t, y)), np.asarray(patched.vector_field(t, y))
        np.testing.assert_allclose(b[:-1], a[:-1], rtol=0, atol=1e-12 * np.max(np.abs(a)))


def test_hopf_speed_of_the_composition_is_the_published_one():
    """Straight-line rotation of the full-dof composition loses stability at the
    rotor's `N_crit = 13.904` (the `hopf` command's number, from `CantileverRotor`)."""
    from rotorjax.analysis import hopf_points, state_matrix

    scene = cl.build_scene(dict(BASE, n_modes=0))
    (h,) = hopf_points(lambda s: scene.linear_matrices(s).state_matrix(), 5.0, 25.0, n_scan=20)
    rotor = cl.build_rotor(BASE)
    (ref,) = hopf_points(lambda s: state_matrix(rotor, s), 5.0, 25.0, n_scan=20)
    assert h.speed == pytest.approx(ref.speed, rel=1e-9)
    assert h.speed == pytest.approx(13.904126, abs=1e-5)
