"""Model 001 (preset `anisotropic-abb`): the auto-balancing main motion loses its
stability at n = 1.01434820 by a Neimark-Sacker bifurcation (issue 30).

The main motion (the rotor at rest on its supports, the two weights fixed at the
balancing angles relative to the rotor) is a constant state of the preset's scene,
so the harmonic balance of `periodic_branch` is exact for it at any number of
harmonics, and its stability from Hill's exponents must agree with the Floquet
multipliers of the preset's own reference (`floquet_of` of the `PeriodicOrbit`,
the variational equations integrated over the forcing period 2 pi / n). Checked:

(a) the branch over n in (0.9, 1.2) has exactly one event, a Neimark-Sacker point,
    at the speed where the largest multiplier of the reference leaves the unit
    circle (bisected here with brentq, to 1e-8), with the frequency of the
    crossing pair (its angle over the period), stable exactly above it;
(b) a time simulation started near the main motion (the preset's y0: the weights
    0.1 rad off) converges to it at n = 1.05, and at n = 0.95 does not: the
    weights leave the balancing angles, lock together, and slip backwards round the rotor
    together (relative rates between -0.024 and -0.005: a second, slow
    frequency), the rotor whirling at a steady amplitude near 2: a quasi-periodic
    motion whose stroboscopic samples (the state every forcing period) trace a
    closed curve that keeps its spread. The bifurcation is not a soft one here: the
    invariant curve the samples settle on is far from the main motion (the weights
    going all the way round), not a small one born at the point;
(c) `rotorjax periodic` reports the point and what it means (the branch of (a)
    shared: the CLI's call to `periodic_branch` is checked and answered with it).
"""

import equinox as eqx
import jax
import numpy as np
import pytest
import scipy.optimize

import rotorjax as rj
import rotorjax.analysis
from rotorjax.analysis import floquet_of, periodic_branch
from rotorjax.cli import main
from rotorjax.presets import anisotropic_abb as A

P = A.PRESET
LO, HI, START, H = 0.9, 1.2, 1.1, 4
GROUPS = {k: P.defaults[k] for k in A.GROUPS}
#: the simulations' speeds (below and above the Neimark-Sacker point) and length in forcing periods
BELOW, ABOVE, PERIODS = 0.95, 1.05, 500


@pytest.fixture(scope="module")
def start():
    setup = P.build(dict(P.defaults, n=START))
    scene = setup.scene

    def scene_at(n):   # as the CLI's `_scene_at` builds it for the speed key
        return eqx.tree_at(lambda s: s.speed.constant, scene, n)

    return setup, scene_at


@pytest.fixture(scope="module")
def branch(start):
    setup, scene_at = start
    # setup.y0: the rest state with the weights at the balancing angles deviated by
    # 0.1 rad (a constant guess; Newton removes the deviation at n = 1.1)
    return periodic_branch(scene_at, START, setup.y0, (LO, HI), H, name="n")


@pytest.fixture(scope="module")
def crossing():
    """The Neimark-Sacker point from the reference's Floquet multipliers: the speed
    where the largest modulus is 1, and the crossing multiplier there."""
    multipliers = jax.jit(lambda n: floquet_of(A.main_motion_reference(GROUPS, n)).multipliers)

    def excess(n):
        return float(np.max(np.abs(np.asarray(multipliers(n))))) - 1.0

    assert excess(0.99) > 0 > excess(1.04)
    n_ns = scipy.optimize.brentq(excess, 0.99, 1.04, xtol=1e-13, rtol=1e-14)
    mu = np.asarray(multipliers(n_ns))
    return n_ns, mu[np.argmax(np.abs(mu))]


def test_the_branch_has_one_neimark_sacker_point_at_the_floquet_crossing(branch, crossing):
    br, coefficients = branch
    n_ns, mu = crossing
    assert br.p.min() == pytest.approx(LO) and br.p.max() == pytest.approx(HI)
    assert [e.kind for e in br.events] == ["neimark-sacker"]
    e = br.events[0]
    assert float(e.p) == pytest.approx(1.0143482, abs=1e-7)
    assert abs(float(e.p) - n_ns) < 1e-8
    # a complex pair, not +-1: the second frequency is the pair's angle over the period 2 pi / n
    angle = abs(np.angle(mu))
    assert 0.01 < angle < np.pi - 0.01
    assert float(e.frequency) == pytest.approx(angle * n_ns / (2 * np.pi), rel=1e-6)
    assert float(e.frequency) == pytest.approx(0.0087686, rel=1e-4)
    # stable exactly above the point, unstable below
    far = np.abs(br.p - float(e.p)) > 1e-9
    np.testing.assert_array_equal(np.asarray(br.stable)[far], (br.p > float(e.p))[far])
    assert np.all(np.sign(np.asarray(br.margin))[far] == np.where(br.p[far] > float(e.p), -1, 1))
    # the main motion is a constant state: the harmonics vanish, the rotor is at rest
    Y = np.asarray(coefficients)
    assert np.max(np.abs(Y[:, 1:, :])) < 1e-8
    assert np.max(np.abs(Y[:, 0, :2])) < 1e-8


def _strobe(n, periods):
    """The preset's run at speed `n` (its y0: near the main motion) sampled once per
    forcing period, and the main motion's state."""
    setup = P.build(dict(P.defaults, n=n))
    ts = 2 * np.pi / n * np.arange(periods + 1)
    r = rj.simulate(setup.scene, setup.y0, (0.0, ts[-1]), saveat=ts, rtol=1e-9, atol=1e-11, max_steps=1_000_000)
    assert int(r.code) == 0
    return np.asarray(r.ys), np.asarray(setup.reference.y0)


@pytest.fixture(scope="module")
def strobes():
    return {n: _strobe(n, PERIODS) for n in (BELOW, ABOVE)}


def _deviation(ys, main):
    """Per sample: max |.| of the state's deviation from the main motion, the weights'
    angles taken modulo 2 pi."""
    d = ys - main
    d[:, 2:4] = (d[:, 2:4] + np.pi) % (2 * np.pi) - np.pi
    return np.max(np.abs(d), axis=1)


def test_above_the_point_the_motion_converges_to_the_main_motion(strobes):
    ys, main = strobes[ABOVE]
    dev = _deviation(ys, main)
    assert dev[:50].max() > 0.05
    windows = [dev[k:k + 100].max() for k in range(100, PERIODS, 100)]
    assert all(b < 0.6 * a for a, b in zip(windows, windows[1:]))     # a steady decay
    assert dev[-1] < 2e-3


def test_below_the_point_the_motion_leaves_it_for_a_quasi_periodic_one(strobes):
    ys, main = strobes[BELOW]
    assert _deviation(ys, main)[:20].max() < 0.2                  # started near the main motion
    before, last = ys[-200:-100], ys[-100:]
    # the weights have locked together (a fixed angle between them) ...
    assert np.ptp(last[:, 3] - last[:, 2]) < 0.05
    for block in (before, last):
        # ... and go all the way round the rotor (their angles relative to it sweep
        # the circle in every window: the spread does not decay) ...
        assert np.ptp(np.cos(block[:, 2])) > 1.9 and np.ptp(np.sin(block[:, 2])) > 1.9
        # ... always backwards, slower than the rotor (a second, slow frequency)
        assert np.max(block[:, 6:8]) < -0.003 and np.min(block[:, 6:8]) > -0.05
    # the rotor whirls at a steady amplitude (the main motion's rotor is at rest)
    amp_before, amp_last = (np.hypot(b[:, 0], b[:, 1]).max() for b in (before, last))
    assert amp_last > 1.0 and amp_last == pytest.approx(amp_before, rel=1e-2)
    # the stroboscopic samples lie on a closed curve parametrised by the weights'
    # angle: ordered by it, the rest of the state moves in small steps
    both = ys[-200:]
    angle = both[:, 2] % (2 * np.pi)
    order = np.argsort(angle)
    assert np.max(np.diff(angle[order])) < 0.3
    rest = both[order][:, [0, 1, 4, 5, 6, 7]]
    assert np.all(np.max(np.abs(np.diff(rest, axis=0)), axis=0) < 0.15 * np.ptp(rest, axis=0))


def test_the_cli_names_the_neimark_sacker_point_and_the_quasi_periodic_motion(start, branch, tmp_path, capsys,
                                                                              monkeypatch):
    setup, scene_at = start
    calls = []

    def shared(cli_scene_at, p0, guess, p_bounds, harmonics, **kw):
        # the CLI asks for this test's branch: the same start, guess, range, harmonics and scene
        calls.append(kw)
        assert p0 == START and tuple(p_bounds) == (LO, HI) and harmonics == H
        np.testing.assert_array_equal(np.asarray(guess), np.asarray(setup.y0))
        for v in (0.95, 1.15):
            np.testing.assert_allclose(cli_scene_at(v).vector_field(0.3, setup.y0, None),
                                       scene_at(v).vector_field(0.3, setup.y0, None), rtol=0, atol=1e-14)
        assert kw.get("method", "harmonic-balance") == "harmonic-balance" and kw.get("subharmonic", 1) == 1
        return branch

    monkeypatch.setattr(rotorjax.analysis, "periodic_branch", shared)
    rc = main(["periodic", "anisotropic-abb", "--param", "n", "--range", str(LO), str(HI), "--from", str(START),
               "--harmonics", str(H), "--out", str(tmp_path)])
    cap = capsys.readouterr()
    out = cap.out
    assert rc == 0 and len(calls) == 1, cap.err
    lines = [line for line in out.splitlines() if "neimark-sacker" in line]
    assert len(lines) == 1, out
    assert "neimark-sacker at n = 1.0143482" in lines[0]
    assert "quasi-periodic" in lines[0]
    assert "0.00876863 rad per time unit" in lines[0]
