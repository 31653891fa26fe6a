"""A fluid-film rotor's quantities (`journal_rig.toml`: ROSS's example rotor on two
short plain journal bearings), against the file read again with other film
viscosities: the `onset` design quantity (the oil-whirl threshold followed from the
nominal one) equals a fresh scan-and-bisect, and so does its gradient, and the stable
speed range (`stable-range`) is the range below it; and
uncertainty's critical speeds and log decrements are the linearised films'."""

import equinox as eqx
import jax
import jax.numpy as jnp
import numpy as np
import pytest

from rotorjax.analysis import critical_speeds_1x, linear_margin, modes
from rotorjax.design import rotor_problem
from rotorjax.io import read_rotor_file, shipped_rotor
from rotorjax.uncertainty import LogNormal, rotor_quantities

PATH = str(shipped_rotor("journal_rig"))
NAMES = ("bearing0.viscosity", "bearing1.viscosity")


_margin = eqx.filter_jit(linear_margin)   # one compilation for every file read (one layout)


def _scanned(values, lo=195.0, hi=225.0):
    """The threshold as the root of the largest real part on the file read again with
    `values`, by scipy's `brentq` to 1e-11 of the speed (an independent path: the
    file's reader, the margin, scipy's root finder; no secant)."""
    from scipy.optimize import brentq

    scene = read_rotor_file(PATH, dict(zip(NAMES, values))).scene
    margin = lambda w: float(_margin(scene, jnp.float64(w)))   # noqa: E731
    assert margin(lo) < 0 < margin(hi)
    return brentq(margin, lo, hi, xtol=1e-11 * lo, rtol=1e-15)


def test_the_onset_follows_the_scanned_threshold_and_its_gradient():
    file = read_rotor_file(PATH)
    p = rotor_problem(file, {n: (0.005, 0.05) for n in NAMES}, "onset", [("stable-range", ">=", 0.0)],
                      speed_range=(100.0, 400.0))
    x0 = p.nominal
    assert p.settings["onset"] == pytest.approx(_scanned(x0), rel=1e-9)
    # the stable range (the same threshold, followed by `StableSpeeds`): stable from 100 rad/s up to the onset
    assert p.settings["thresholds"] == [pytest.approx(p.settings["onset"], rel=1e-9)]
    assert p.settings["stable_between_thresholds"] == [True, False]
    x = x0 * np.array([1.3, 0.8])
    q = jax.jit(p.quantities)(jnp.asarray(x))
    assert float(q["onset"]) == pytest.approx(_scanned(x), rel=1e-8)
    assert float(q["stable-range"]) == pytest.approx(_scanned(x) - 100.0, rel=1e-8)
    g = np.asarray(jax.jit(jax.grad(lambda v: p.quantities(v)["onset"]))(jnp.asarray(x)))
    e = np.array([1e-3 * x[0], 0.0])
    fd = (_scanned(x + e) - _scanned(x - e)) / (2e-3 * x[0])
    assert g[0] == pytest.approx(fd, rel=1e-4)
    assert g[0] > 0 and g[1] > 0     # a thicker film raises the oil-whirl threshold


def test_uncertainty_takes_the_critical_speeds_and_log_decs_of_the_linearised_films():
    """`rotor_quantities` on a rotor whose bearings are fluid films: a sample's critical
    speeds and log decrement equal `critical_speeds_1x` and `modes` of the scene read
    again with its viscosity (the films linearised at their static equilibrium at
    each speed). It had taken the bare shaft's, which has no bearings (42 spurious
    critical speeds, not followed: the command refused)."""
    q = rotor_quantities(PATH, {NAMES[0]: LogNormal(0.03, 3e-4)}, lo=0.0, hi=20.6, n_modes=1)
    assert q.outputs == ("critical_speed_0", "log_dec_0")
    out = np.asarray(q.fn(jnp.array([0.031])))
    scene = read_rotor_file(PATH, {NAMES[0]: 0.031}).scene
    crit = [w for w, _ in critical_speeds_1x(scene, 0.0, 20.6, whirl="forward", xtol=1e-12)]
    np.testing.assert_allclose(out[:1], crit, rtol=1e-8)
    np.testing.assert_allclose(out[1:], np.asarray(modes(scene, q.speed, 1).log_dec), rtol=1e-9)
