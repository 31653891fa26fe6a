"""Issue 62, item 4: the harmonics of a periodic branch adapted point by point
(`periodic_branch`'s default, `harmonics="auto"`), on a rotor it was not built on:
the shipped `cubic_rig.toml` made anisotropic (bearing 0 stiffer in y, kyy = 1.4
kxx: elliptic orbits, so the radial cubic force has odd harmonics) with a tenth of
the cubic stiffness and a quarter of the unbalance, continued through its first
resonance with the library's defaults.

Independent reference: the rotor's equations integrated over one period by scipy's
DOP853 at rtol 1e-12 from each checked point's state: the harmonic series equals
the integrated orbit to the truncation target's order."""

import os
import re

import jax
import jax.numpy as jnp
import numpy as np
import pytest
from scipy.integrate import solve_ivp

import rotorjax
from rotorjax import presets
from rotorjax.analysis._harmonic_balance import _basis_at
from tests.helpers import speed_branch

pytestmark = pytest.mark.slow

SHIPPED = os.path.join(os.path.dirname(rotorjax.__file__), "rotors", "cubic_rig.toml")
RANGE = (90.0, 110.0)     # rad/s, through the first resonance
TARGET = 1e-6             # the default truncation_tol


def variant(text):
    """cubic_rig.toml, anisotropic, its cubic stiffness / 10, its unbalance / 4."""
    text, n1 = re.subn(r"(?m)^kxx = 1e6( .*)?$", "kxx = 1e6\nkyy = 1.4e6", text, count=1)
    text, n2 = re.subn(r"(?m)^k3 = 3e12", "k3 = 3e11", text)
    text, n3 = re.subn(r"(?m)^magnitude = 2e-3", "magnitude = 5e-4", text)
    assert (n1, n2, n3) == (1, 2, 2)
    return text


def variant_scene(folder):
    """The variant's scene (its rotor file written in `folder`)."""
    path = folder / "anisotropic_cubic.toml"
    with open(SHIPPED) as f:
        path.write_text(variant(f.read()))
    preset = presets.get(str(path))
    return preset.build(preset.params()).scene


@pytest.fixture(scope="module")
def branch(tmp_path_factory):
    scene_at, br, coefficients, _ = speed_branch(variant_scene(tmp_path_factory.mktemp("rotor")), RANGE, [0.0])
    return scene_at, br, coefficients


def test_the_harmonics_follow_the_motion(branch):
    """Both ends on the range's edges; every point within the target; more harmonics
    at the resonance than at the ends."""
    _, br, coefficients = branch
    H = np.asarray(br.harmonics)
    assert br.stops == ("box edge (speed = 90.0)", "box edge (speed = 110.0)")
    assert np.all(np.asarray(br.truncation) <= TARGET)
    peak = int(np.argmax(np.max(np.abs(coefficients), axis=(1, 2))))
    assert H[peak] > H[0] and H[peak] > H[-1]
    assert coefficients.shape[1] == 2 * H.max() + 1


def _integrated(scene, y0, period, ts):
    """The orbit from `y0` at the instants `ts` of one period, by scipy's DOP853."""
    field = jax.jit(lambda t, y: scene.vector_field(t, y, None))
    sol = solve_ivp(lambda t, y: np.asarray(field(t, jnp.asarray(y))), (0.0, period), np.asarray(y0),
                    method="DOP853", rtol=1e-12, atol=1e-15, t_eval=ts)
    assert sol.success
    return sol.y.T


def test_the_series_is_the_integrated_orbit(branch):
    """At the start, the largest motion and the end: the series at 16 instants
    equals scipy's integration from its own initial state to 1e-5 of each state's
    size (the truncation target 1e-6, plus the closure of a stable orbit integrated
    once)."""
    scene_at, br, coefficients = branch
    peak = int(np.argmax(np.max(np.abs(coefficients), axis=(1, 2))))
    for i in (0, peak, len(br.p) - 1):
        w = float(br.p[i])
        scene, T = scene_at(w), 2 * np.pi / w
        Y = jnp.asarray(coefficients[i, :2 * int(br.harmonics[i]) + 1])
        H = (Y.shape[0] - 1) // 2
        ts = np.linspace(0.0, T, 17)[:-1]
        series = np.stack([np.asarray(_basis_at(jnp.asarray(2 * np.pi * t / T), H) @ Y) for t in ts])
        orbit = _integrated(scene, series[0], T, ts)
        size = np.max(np.abs(orbit), axis=0)
        size = np.maximum(size, 1e-3 * size.max())
        err = np.max(np.abs(series - orbit) / size)
        assert err < 10 * TARGET, (w, H, err)
