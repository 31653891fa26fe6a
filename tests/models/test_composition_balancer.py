"""Composition (a): a ball auto-balancer on the disk node of ROSS's example rotor
(`ross-compare`, isotropic bearings with damping) balances it above the first
critical speed: the balanced regime (shaft straight, balls cancelling the
unbalance) is a rest point of the rotating frame, stable by the autodiff
Jacobian above the first forward critical speed and unstable below it, and a
simulation from displaced balls returns to it."""

import jax.numpy as jnp
import numpy as np
import pytest

import rotorjax
from rotorjax.analysis import steady_state
from rotorjax.flexible import critical_speeds_1x
from rotorjax.models import AutoBalancer, BalancerAt, Race, RotorScene, Unbalance, balancing_angles
from rotorjax.presets._ross_compare import PRESET, build_rotor

U, BALL, RADIUS, DRAG = 1e-3, 0.05, 0.05, 0.3   # kg m, kg, m, N s/m


@pytest.fixture(scope="module")
def rotor():
    return build_rotor(PRESET.params({"kyy": 1e6, "cxx": 2000.0, "cyy": 2000.0}))


def _scene(rotor, speed):
    parts = (Unbalance(2, U, 0.0), BalancerAt(2, AutoBalancer(jnp.full(2, BALL), Race.circular(RADIUS), DRAG)))
    return RotorScene(rotor, speed, parts)


def _balanced_angles():
    return np.asarray(balancing_angles(2, U / (2 * BALL * RADIUS)))


def test_balanced_regime_stable_above_the_first_critical_speed(rotor):
    first = critical_speeds_1x(rotor, 10.0, 600.0, whirl="forward")[0][0]
    assert abs(first - 96.9) < 0.05   # as the README says
    psi = _balanced_angles()
    verdicts = {}
    for w in (0.6 * first, 1.5 * first):
        sc = _scene(rotor, w)
        r = steady_state(sc, jnp.concatenate([jnp.zeros(sc.n_shaft), jnp.asarray(psi + 0.05)]), rtol=1e-11,
                         atol=1e-11)
        assert bool(r.converged) and float(r.residual) < 1e-10
        assert float(r.whirl_amplitude) < 1e-14          # the shaft is straight
        assert np.allclose(np.sort(np.asarray(r.weight_angles)), np.sort(np.angle(np.exp(1j * psi))), atol=1e-9)
        verdicts[w] = float(r.margin)
    assert verdicts[0.6 * first] > 1e-3    # below the first critical speed: unstable
    assert verdicts[1.5 * first] < -1e-3   # above: stable


def test_simulation_returns_to_the_balanced_regime(rotor):
    """Balls displaced by 0.5 and 0.3 rad at 150 rad/s (the rotor's lowest 8 modes):
    the whirl decays and the balls settle at the balancing angles."""
    sc = _scene(rotor.reduce(8), 150.0)
    psi = _balanced_angles()
    res = rotorjax.simulate(sc, sc.rest_state(psi + np.array([0.5, 0.3])), (0.0, 20.0), saveat=21,
                            solver="tsit5", rtol=1e-8, atol=1e-10, max_steps=500_000).raise_if_failed()
    whirl = np.asarray(res.outputs["whirl_amplitude"])
    assert whirl[-1] < 1e-2 * whirl.max() and np.all(np.diff(whirl[2:]) < 0)
    assert np.allclose(np.asarray(res.outputs["weight_angles"])[-1], np.angle(np.exp(1j * psi)), atol=5e-3)
