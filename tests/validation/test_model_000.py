"""Model 000 (Bykov & Kovachev 2019): published behaviour, reproduced by simulation."""

import numpy as np
import pytest
from scipy.integrate import solve_ivp

import rotorjax as rj
from rotorjax import presets
from rotorjax.demo import runup_000
from tests.reference.paper_models import rhs_000_paper, stationary_residual_000

PRESET = presets.get("elliptic-abb")
# A generic start: balls at 1.0 and 3.5 rad from the imbalance direction.
START = {"psi1": 1.0, "psi_spacing": 2.5}


def _run(overrides, t_end, n_save=8, rtol=1e-9):
    p = PRESET.params(dict(START, **overrides))
    setup = PRESET.build(p)
    scene, y0 = setup.scene, setup.y0
    r = rj.simulate(scene, y0, (0.0, t_end), saveat=n_save, rtol=rtol, atol=rtol * 1e-2)
    assert bool(r.success), r.message
    return p, scene, r


def test_circular_race_within_capacity_balances_fully():
    """eps = 0.03 < 2 chi: the rotor whirl is driven below 1e-6 (paper eq. 14)."""
    p, _, r = _run({"rho1": 1.0, "rho2": 1.0, "eps": 0.03}, 7000.0)
    amp = np.asarray(r.outputs["whirl_amplitude"])
    assert amp[-1] < 1e-6
    # The balls sit at the balanced position of eq. (14): +-acos(eps/(2 chi)) off the
    # side opposite the imbalance.
    spread = np.arccos(p["eps"] / (2 * p["chi"]))
    expected = np.sort(np.angle(np.exp(1j * (p["alpha"] + np.pi + np.array([-1, 1]) * spread))))
    np.testing.assert_allclose(np.sort(np.asarray(r.outputs["weight_angles"][-1])), expected,
                               atol=1e-4)


def test_circular_race_at_capacity_is_approached_only_slowly():
    """eps = 0.04 = 2 chi: the balanced state (both balls opposite the imbalance) is
    degenerate. The whirl keeps decreasing, but algebraically, not exponentially:
    after 8000 time units it is still above 1e-4 (the eps = 0.03 case is at 6e-8)."""
    _, _, r = _run({"rho1": 1.0, "rho2": 1.0}, 8000.0)
    amp = np.asarray(r.outputs["whirl_amplitude"])[2:]
    assert np.all(np.diff(amp) < 0)
    assert 1e-4 < amp[-1] < 5e-3
    # Algebraic decay: successive ratios approach 1 instead of staying constant.
    ratios = amp[1:] / amp[:-1]
    assert ratios[-1] > ratios[0] > 0.3


def test_elliptic_race_settles_on_paper_stationary_regime():
    """rho1 = 1.28, rho2 = 1.2: a non-zero residual whirl whose rotating-frame state
    satisfies the paper's stationary equations (11) to 1e-8."""
    p, _, r = _run({}, 4500.0, rtol=1e-10)
    t, y = float(r.ts[-1]), np.asarray(r.ys[-1])
    z = (y[0] + 1j * y[1]) * np.exp(-1j * p["nu"] * t)
    psi = y[2:4]
    res = stationary_residual_000(z.real, z.imag, p["rho1"] * np.cos(psi), p["rho2"] * np.sin(psi),
                                  dict(p, nu0=p["nu"], nu_dot=0.0))
    assert np.max(np.abs(res)) < 1e-8
    assert abs(z) > 0.01  # the elliptic race cannot balance
    # The two balls touch (paper eq. 19).
    assert abs(np.angle(np.exp(1j * (psi[0] - psi[1])))) < 1e-6


def test_runup_through_resonance_reproduces_fig3():
    """nu = 0.16 tau: the circular race keeps the rotor balanced through and above
    resonance, the elliptic race leaves a residual whirl, and without a balancer the
    plain resonance peak appears near nu = 1."""
    speed, curves, info = runup_000()
    assert all(i["success"] for i in info.values())
    none, circ, ell = (info[k] for k in ("no balancer", "circular race", "elliptic race"))
    assert none["peak_amplitude"] > 0.1 and 1.0 < none["speed_at_peak"] < 2.2
    assert circ["max_amplitude_above_nu_2.5"] < 0.01
    assert ell["max_amplitude_above_nu_2.5"] > 3 * circ["max_amplitude_above_nu_2.5"]
    assert none["max_amplitude_above_nu_2.5"] > 3 * ell["max_amplitude_above_nu_2.5"]


@pytest.mark.parametrize("overrides,t_end", [({}, 60.0), ({"nu_dot": 0.16}, 25.0),
                                             ({"rho1": 1.0, "rho2": 1.0, "delta_b": 2.0}, 60.0)])
def test_trajectory_matches_scipy_dop853(overrides, t_end):
    """Against scipy DOP853 at rtol 1e-11 on the independent paper equations."""
    p = PRESET.params(dict(START, **overrides))
    setup = PRESET.build(p)
    scene, y0 = setup.scene, setup.y0
    ts = np.linspace(0.0, t_end, 7)
    r = rj.simulate(scene, y0, (0.0, t_end), saveat=ts, rtol=1e-12, atol=1e-14)
    ref = solve_ivp(rhs_000_paper, (0.0, t_end), np.asarray(y0), method="DOP853", t_eval=ts,
                    rtol=1e-11, atol=1e-13, args=(dict(p, nu0=p["nu0"] if p["nu_dot"] else p["nu"]),))
    assert ref.success
    assert np.max(np.abs(np.asarray(r.ys) - ref.y.T)) < 1e-7
