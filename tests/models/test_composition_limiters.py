"""Composition (c): limiters at a node of the FE rotor with a large unbalance give
bounded rubbing motion, and the energy balance closes.

ROSS's example rotor (`ross-compare`) with isotropic damped bearings runs at its
first critical speed with an unbalance whose free response at the disk (node 2)
is three times the limiters' clearance. Four visco-elastic stops with friction
around the disk's rim keep it near the clearance. The linear part is reduced to
the rotor's 8 lowest modes (`rotor.reduce(8)`), the contact acts at the physical
dofs of node 2: the full FE rotor's highest frequencies (~1e5 rad/s) would make an
explicit integration 20 times slower and add nothing at this speed.
"""

import jax
import jax.numpy as jnp
import numpy as np
import pytest

import rotorjax as rj
from rotorjax.models import Limiters, LimitersAt, RotorScene, Unbalance
from rotorjax.presets import ross_compare
from rotorjax.solve import simulate_events

SPEED = 96.5             # rad/s: the first forward critical speed
UNBALANCE = 3e-3         # kg m at node 2
CLEARANCE = 3e-4         # m
T_END = 3.0              # s: 46 revolutions
N_SAVE = 3001
TOLS = dict(rtol=1e-10, atol=1e-13)


def _scene(smoothing=1e-6, limiters=True):
    rotor = ross_compare.build_rotor(ross_compare.PRESET.params(
        {"kxx": 1e6, "kyy": 1e6, "cxx": 1e3, "cyy": 1e3})).reduce(8)
    parts = [Unbalance(2, UNBALANCE)]
    if limiters:
        stops = Limiters(np.pi / 4 + np.arange(4) * np.pi / 2, CLEARANCE, stiffness=1e7, damping=2e3,
                         friction=0.1, smoothing=smoothing)
        parts.append(LimitersAt(2, stops, radius=0.1))
    return RotorScene(rotor, SPEED, tuple(parts), track_work=True)


def _smoothed(scene):
    y0 = jnp.zeros(scene.state_size)
    return rj.simulate(scene, y0, (0.0, T_END), saveat=jnp.linspace(0.0, T_END, N_SAVE), max_steps=10**6,
                       **TOLS)


def _events(scene, **tols):
    y0 = jnp.zeros(scene.state_size)
    return simulate_events(scene, y0, (0.0, T_END), saveat=N_SAVE, **(tols or TOLS))


@pytest.fixture(scope="module")
def smoothed():
    return _smoothed(_scene())


@pytest.fixture(scope="module")
def events():
    return _events(_scene())


def _radius(res, node=2):
    return np.hypot(np.asarray(res.outputs["node_x"])[:, node], np.asarray(res.outputs["node_y"])[:, node])


def _free_amplitude():
    """Largest radius of the linear (limiter-free) unbalance orbit at node 2."""
    scene = _scene(limiters=False)
    m = scene.linear_matrices(SPEED)
    Q = np.linalg.solve(np.asarray(m.K - SPEED**2 * m.M + 1j * SPEED * (m.C + m.G)),
                        np.asarray(scene.unbalance_load(SPEED)))
    X = np.asarray(scene.expand(jnp.asarray(Q)))[8:10]
    phase = np.exp(1j * np.linspace(0, 2 * np.pi, 721))
    return np.max(np.hypot((X[0] * phase).real, (X[1] * phase).real))


def _check_rubbing(res):
    assert int(res.code) == 0, res.message
    ts, r = np.asarray(res.ts), _radius(res)
    free = _free_amplitude()
    assert free > 3 * CLEARANCE                      # without the stops the disk would hit them
    R = np.asarray(res.outputs["normal_forces"])
    assert np.any(R > 0) and np.all(R >= 0)
    period = 2 * np.pi / SPEED
    last, before = ts > T_END - 10 * period, (ts > T_END - 20 * period) & (ts <= T_END - 10 * period)
    assert np.any(R[last] > 0)                       # still rubbing at the end
    # bounded: near the clearance (penetration < 25 %), far below the free orbit
    assert r.max() < 1.25 * CLEARANCE
    assert r.max() < 0.4 * free
    # a settled regime: the last ten revolutions' orbit matches the ten before
    assert abs(r[last].max() - r[before].max()) < 0.01 * r[last].max()
    assert r[last].min() > 0.9 * CLEARANCE
    E, W = np.asarray(res.outputs["energy"]), np.asarray(res.outputs["work"])
    closure = np.max(np.abs(E - E[0] - W)) / np.max(np.abs(E))
    assert closure < 1e-6
    return closure


def test_rubbing_is_bounded_and_energy_closes_smoothed(smoothed):
    _check_rubbing(smoothed)


def test_rubbing_is_bounded_and_energy_closes_with_events(events):
    _check_rubbing(events)
    assert int(events.stats["num_events"]) > 100


def test_event_located_run_converges_with_tolerance(events):
    # Every switch located to rounding: tightening the tolerances moves the orbit
    # by integration error only (with a badly scaled indicator the root find
    # failed at releases and the contact was held up to 0.2 ms too long: 1e-6 m).
    tight = _events(_scene(), rtol=1e-12, atol=1e-15)
    assert int(tight.code) == 0
    x, xt = np.asarray(events.outputs["node_x"])[:, 2], np.asarray(tight.outputs["node_x"])[:, 2]
    assert np.max(np.abs(x - xt)) < 1e-9


def test_smoothed_contact_converges_to_event_located(events):
    # The smoothed law's error is O(ell) in the force; along the orbit it falls at
    # least as fast as ell (faster where contacts are firm).
    x_events = np.asarray(events.outputs["node_x"])[:, 2]
    ells = (1.6e-5, 4e-6, 1e-6)
    errors = [np.max(np.abs(np.asarray(_smoothed(_scene(ell)).outputs["node_x"])[:, 2] - x_events))
              for ell in ells]
    assert all(a > b for a, b in zip(errors, errors[1:]))
    assert all(e < 3 * ell for e, ell in zip(errors, ells))
    assert errors[0] / errors[-1] > ells[0] / ells[-1]     # at least first order overall
