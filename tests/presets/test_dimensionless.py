"""SI and dimensionless forms map exactly onto each other, both ways."""

import numpy as np
import pytest

import rotorjax as rj
from rotorjax.models import ConstantSpeed
from rotorjax.presets import anisotropic_abb as A
from rotorjax.presets import jeffcott_abb as J


def _si_000(rng):
    return dict(disk_mass=rng.uniform(1, 20), stiffness=rng.uniform(1e4, 1e6),
                damping=rng.uniform(1, 100), eccentricity=rng.uniform(1e-5, 1e-3),
                phase=rng.uniform(-3, 3), ball_mass=rng.uniform(0.01, 0.2), n_balls=2,
                r1=rng.uniform(0.03, 0.05), r2=rng.uniform(0.03, 0.05), ball_drag=rng.uniform(0, 5))


def _si_001(rng):
    return dict(rotor_mass=rng.uniform(5, 20), imbalance_mass=rng.uniform(0.001, 0.05),
                radius=rng.uniform(0.02, 0.1), n_weights=3, weight_mass=rng.uniform(0.01, 0.1),
                kx=rng.uniform(1e4, 1e5), ky=rng.uniform(1e5, 1e6), bx=rng.uniform(1, 50),
                by=rng.uniform(1, 50), weight_drag=rng.uniform(0, 2), inertia_factor=1.4)


def _assert_rescaled(si_scene, dl_scene, scale, omega_unit, rng):
    """f_dimless(omega_unit t, y / scale) = f_SI(t, y) / (scale omega_unit) at random states."""
    for _ in range(5):
        y = rng.normal(size=scale.size) * scale
        t = rng.uniform(0, 1)
        f_si = np.asarray(si_scene.vector_field(t, y))
        f_dl = np.asarray(dl_scene.vector_field(t * omega_unit, y / scale))
        np.testing.assert_allclose(f_si / (scale * omega_unit), f_dl, rtol=1e-10,
                                   atol=1e-10 * np.abs(f_dl).max())


def test_000_groups_roundtrip():
    rng = np.random.default_rng(0)
    g = {k: v for k, v in J.groups_from_si(**_si_000(rng)).items() if k in J.GROUPS}
    for kw in ({}, {"disk_mass": 3.0, "Omega": 50.0, "r": 0.02}):
        back = J.groups_from_si(**J.si_from_groups(g, **kw))
        for k in J.GROUPS:
            assert back[k] == pytest.approx(g[k], rel=1e-13, abs=1e-15)


def test_001_groups_roundtrip():
    rng = np.random.default_rng(1)
    si = _si_001(rng)
    full = A.groups_from_si(**si)
    g = {k: full[k] for k in A.GROUPS}
    for kw in ({"K": 1.4}, {"K": 1.4, "Ms": 7.0, "wx": 30.0, "L": 1e-3}):
        back = A.groups_from_si(**A.si_from_groups(g, **kw))
        for k in A.GROUPS:
            assert back[k] == pytest.approx(g[k], rel=1e-12, abs=1e-15)
    with pytest.raises(ValueError, match="sigma"):
        A.si_from_groups(dict(g, sigma=0.4))


def test_000_si_scene_is_the_dimensionless_scene_rescaled():
    """f_dimless(tau, y~) = scaling of f_SI(t, y) at random states, and trajectories agree."""
    rng = np.random.default_rng(2)
    si = _si_000(rng)
    g = J.groups_from_si(**si)
    Om, r = g["Omega"], g["r"]
    omega = 1.3 * Om
    si_scene = J.scene_si(**si, speed=ConstantSpeed(omega))
    dl_scene = J.scene_from_groups(**{k: g[k] for k in J.GROUPS}, nu=omega / Om)
    scale = np.array([r, r, 1, 1, r * Om, r * Om, Om, Om])
    _assert_rescaled(si_scene, dl_scene, scale, Om, rng)
    y0 = si_scene.rest_state(np.array([0.3, 2.0]))
    T = 40.0 / Om
    a = rj.simulate(si_scene, y0, (0.0, T), rtol=1e-11, atol=1e-13 * r)
    b = rj.simulate(dl_scene, np.asarray(y0) / scale, (0.0, T * Om), rtol=1e-11, atol=1e-13)
    np.testing.assert_allclose(np.asarray(a.ys[-1]) / scale, np.asarray(b.ys[-1]), atol=1e-8)


def test_001_si_scene_is_the_dimensionless_scene_rescaled():
    rng = np.random.default_rng(3)
    si = _si_001(rng)
    g = A.groups_from_si(**si)
    wx, L = g["wx"], g["L"]
    omega = 2.5 * wx
    si_scene = A.scene_si(**si, speed=ConstantSpeed(omega))
    dl_scene = A.scene_from_groups(**{k: g[k] for k in A.GROUPS}, n=omega / wx, K=1.4)
    scale = np.array([L, L, 1, 1, 1, L * wx, L * wx, wx, wx, wx])
    _assert_rescaled(si_scene, dl_scene, scale, wx, rng)
