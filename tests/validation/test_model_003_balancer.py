"""Model 003 with the ball auto-balancer: regimes C / PS / NS1-3, stability, passage."""

import jax.numpy as jnp
import numpy as np
import pytest

import rotorjax as rj
from rotorjax.flexible import (ModalBalancerRotor, ModalShaft, balanced_regime, pseudo_balanced_speeds,
                               unbalanced_regimes)
from rotorjax.models import ConstantSpeed, RunUp

BALLS = jnp.array([0.02, 0.02])


def rotor(omega, d=0.05, drag=5.0, modes=6):
    shaft = ModalShaft(modes, 1.0 + float(jnp.sum(BALLS)), 0.5, d=d, m0=0.01)
    return ModalBalancerRotor(shaft, BALLS, 1.0, drag, ConstantSpeed(omega))


def test_regimes_satisfy_the_equations_and_table_1():
    """Every regime from eqs. (26), (28)-(30) is a rest point of the rotating-frame
    equations (24); below the first critical speed NS1 (sigma = 2 m_b r / m0 > 1) has
    two roots and NS2 none, above it the reverse (Table 1)."""
    for omega, present in ((0.5, {"NS1", "NS3"}), (1.2, {"NS2", "NS3"})):
        r = rotor(omega)
        regs = [balanced_regime(r)] + unbalanced_regimes(r)
        assert {g.kind for g in regs[1:]} == present
        assert sum(g.kind == ("NS1" if omega < 0.7 else "NS2") for g in regs) == 2
        for g in regs:
            assert float(g.residual) < 1e-12
        assert float(regs[0].disk_amplitude) == 0.0


def test_balanced_regime_stable_only_above_the_first_critical_speed():
    margins = {w: float(balanced_regime(rotor(w)).margin) for w in (0.5, 0.65, 0.8, 1.2, 3.0)}
    assert margins[0.5] > 0 and margins[0.65] > 0
    assert margins[0.8] < 0 and margins[1.2] < 0 and margins[3.0] < 0
    # below the critical speed the stable regime is NS1 (balls on the heavy side)
    assert any(g.kind == "NS1" and float(g.margin) < 0 for g in unbalanced_regimes(rotor(0.5)))


def test_pseudo_balanced_only_without_damping():
    shaft = ModalShaft(6, 1.04, 0.3, m0=0.01)
    speeds = pseudo_balanced_speeds(shaft, 0.1, 25.0)
    assert len(speeds) >= 2
    s = ModalShaft(2000, 1.04, 0.3, m0=0.01)
    for w in speeds:  # the disk centre does not move: a^T R^-1 a = 0, i.e. S11 = 0 for J = 0
        assert abs(complex(s.sums(w)[0])) < 1e-3
    with pytest.raises(ValueError, match="only without damping"):
        pseudo_balanced_speeds(ModalShaft(6, 1.04, 0.3, d=0.1, m0=0.01), 0.1, 25.0)


def test_passage_through_the_first_critical_speed():
    """Run-up 0.2 -> 1.2 omega_1 at 0.002 per unit time: the balancer lowers the
    resonance peak and balances above it (balls start co-rotating); with a weak ball
    drag the balls lock at the critical speed instead (non-synchronous ball lag)."""
    def run(balls, drag):
        shaft = ModalShaft(4, 1.0 + float(jnp.sum(balls)), 0.5, d=0.05, m0=0.01)
        r = ModalBalancerRotor(shaft, balls, 1.0, drag, RunUp(0.2, 0.002))
        y0 = r.state(jnp.zeros(4), jnp.array([2.0, 4.5])[: balls.shape[0]],
                     thetad=jnp.full(balls.shape[0], 0.2))
        res = rj.simulate(r, y0, (0.0, 500.0), saveat=501)
        assert bool(res.success), res.message
        return res, np.asarray(res.outputs["whirl_amplitude"])

    bare, amp_bare = run(jnp.zeros(0), 5.0)
    bal, amp_bal = run(BALLS, 5.0)
    assert 0.7 < 0.2 + 0.002 * float(bare.ts[np.argmax(amp_bare)]) < 0.85
    assert amp_bal.max() < 0.5 * amp_bare.max()
    assert amp_bal[-10:].max() < 0.3 * amp_bare[-10:].max()
    assert float(bal.outputs["residual_imbalance"][-1]) < 0.2 * 0.01
    lag, amp_lag = run(BALLS, 0.5)
    ball_speed = np.asarray(lag.ys[-1, -2:])
    np.testing.assert_allclose(ball_speed, 0.7, atol=0.05)   # locked near omega_1-ish, shaft at 1.2
    assert amp_lag[-1] > 10 * amp_bal[-1]
