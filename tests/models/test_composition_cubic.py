"""Composition (d): ROSS's example rotor (`ross-compare`, dampers at its disks) on
isotropic bearings with cubic hardening. The synchronous orbit is a rest point of
the rotating frame, so the unbalance response is a branch of rest points: traced
by continuation in the speed it bends over and folds twice (the jump), the middle
part unstable; a run-up follows the upper branch past the lower fold and drops,
a run-down follows the lower branch and jumps up below it."""

import numpy as np
import pytest

import rotorjax
from rotorjax.analysis import synchronous_branch
from rotorjax.models import RotorScene, RunUp
from tests.reference.cubic_rotor import cubic_rotor



@pytest.fixture(scope="module")
def setup():
    rotor, parts = cubic_rotor()
    branch = synchronous_branch(RotorScene(rotor, 60.0, parts), (60.0, 140.0))
    return rotor, parts, branch


def _bearing_radius(u):
    return np.hypot(u[..., 0], u[..., 1])


def test_branch_folds_twice_with_an_unstable_middle(setup):
    _, _, br = setup
    folds = sorted(e.p for e in br.events if e.kind == "fold")
    assert len(folds) == 2
    lo, hi = folds
    assert abs(lo - 102.79) < 0.01 and abs(hi - 104.12) < 0.01   # as the README says
    # the refined folds are the branch's turning points in speed
    turns = sorted([br.p[i] for i in range(1, len(br.p) - 1)
                    if (br.p[i] - br.p[i - 1]) * (br.p[i + 1] - br.p[i]) < 0])
    assert len(turns) == 2
    assert np.allclose(turns, folds, rtol=2e-3)
    # three solutions between the folds, the middle one unstable; one outside
    w = 0.5 * (lo + hi)
    crossings = [i for i in range(len(br.p) - 1) if (br.p[i] - w) * (br.p[i + 1] - w) < 0]
    assert len(crossings) == 3
    amps = [_bearing_radius(br.u[i]) for i in crossings]
    stab = [bool(br.stable[i] and br.stable[i + 1]) for i in crossings]
    order = np.argsort(amps)
    assert [stab[i] for i in order] == [True, False, True]
    assert br.stable[0] and br.stable[-1]
    assert br.stops == ("box edge (speed = 60.0)", "box edge (speed = 140.0)")


def _envelope(rotor, parts, w0, alpha, t_end):
    sc = RotorScene(rotor.reduce(8), RunUp(w0, alpha), parts)
    ts = np.linspace(0.0, t_end, 3001)
    res = rotorjax.simulate(sc, sc.rest_state(), (0.0, t_end), saveat=ts, solver="tsit5", rtol=1e-8, atol=1e-12,
                            max_steps=1_000_000).raise_if_failed()
    r = np.hypot(np.asarray(res.outputs["node_x"])[:, 0], np.asarray(res.outputs["node_y"])[:, 0])
    return w0 + alpha * ts, r


def _branch_at(br, w, upper):
    """Bearing orbit radius on the stable upper or lower part of the branch at speed `w`."""
    amps = []
    for i in range(len(br.p) - 1):
        if (br.p[i] - w) * (br.p[i + 1] - w) <= 0 and br.stable[i] and br.stable[i + 1]:
            s = (w - br.p[i]) / (br.p[i + 1] - br.p[i])
            amps.append((1 - s) * _bearing_radius(br.u[i]) + s * _bearing_radius(br.u[i + 1]))
    return max(amps) if upper else min(amps)


def test_run_up_and_run_down_jump_where_the_continuation_folds(setup):
    """Sweeps at +-0.5 rad/s^2 (quasi-static away from the folds; the run-up
    overshoots the fold by the sweep's lag, about 1.5 rad/s)."""
    rotor, parts, br = setup
    lo, hi = sorted(e.p for e in br.events if e.kind == "fold")
    w, r = _envelope(rotor, parts, 96.0, 0.5, 30.0)
    for speed in (100.0, hi - 0.3):
        i = np.argmin(np.abs(w - speed))
        assert abs(r[i] - _branch_at(br, speed, upper=True)) < 0.03 * r[i]     # on the upper branch
    i = np.argmin(np.abs(w - (hi + 4.0)))
    assert abs(r[i] - _branch_at(br, hi + 4.0, upper=False)) < 0.1 * r[i]      # dropped to the lower one
    w, r = _envelope(rotor, parts, 111.0, -0.5, 30.0)
    for speed in (hi - 0.3, 0.5 * (lo + hi)):   # (the lower branch steepens towards its fold)
        i = np.argmin(np.abs(w - speed))
        assert abs(r[i] - _branch_at(br, speed, upper=False)) < 0.05 * r[i]    # on the lower branch
    i = np.argmin(np.abs(w - (lo - 2.5)))
    assert abs(r[i] - _branch_at(br, lo - 2.5, upper=True)) < 0.05 * r[i]      # jumped up


def test_harmonic_balance_equals_the_synchronous_branch(setup):
    """Harmonic balance (any scene, in the fixed frame) against the branch of
    rotating-frame rest points, at the three coexisting orbits between the folds:
    the orbit is a rest point of the rotating frame (its equations, those the
    branch continues, vanish there to 1e-8), it is the branch's point at that
    speed, it has no higher harmonics (circular, so the cubic bearings' force on it
    is purely 1x), and the middle one is Floquet-unstable as the branch says."""
    from rotorjax.analysis import harmonic_balance, rotating_field

    rotor, parts, br = setup
    folds = sorted(e.p for e in br.events if e.kind == "fold")
    w = 0.5 * sum(folds)
    crossings = [i for i in range(len(br.p) - 1) if (br.p[i] - w) * (br.p[i + 1] - w) < 0]
    scene = RotorScene(rotor, w, parts)
    n, T = scene.n_dof, 2 * np.pi / w
    ts = np.linspace(0.0, T, 5)
    found = []
    for i in crossings:
        s = (w - br.p[i]) / (br.p[i + 1] - br.p[i])
        u = (1 - s) * br.u[i] + s * br.u[i + 1]       # on the branch at w, to the step's accuracy
        guess = np.stack([np.zeros_like(u), scene.to_fixed(0.0, u), scene.to_fixed(T / 4, u)])
        hb = harmonic_balance(scene, T, guess, harmonics=3, stability=(i == crossings[1]))
        assert int(hb.code) == 0 and float(hb.time_residual) < 1e-8
        z = np.asarray(scene.to_rotating(0.0, hb.initial_state()))
        for t in ts:   # a rest point of the rotating frame
            np.testing.assert_allclose(np.asarray(scene.to_rotating(t, hb.state(t))), z, atol=1e-10 * np.abs(z).max())
        acc = np.asarray(rotating_field(scene, 0.0, z))
        assert np.abs(acc[:n]).max() < 1e-8 * w * np.abs(z[:n]).max()
        assert np.abs(acc[n:]).max() < 1e-8 * w**2 * np.abs(z[:n]).max()
        assert np.abs(z - u).max() < 5e-2 * np.abs(u).max()   # the branch's point (interpolated near a fold)
        found.append(z)
        c = np.asarray(hb.coefficients)
        assert np.max(np.abs(c[3:])) < 1e-10 * np.max(np.abs(c[1:3]))
        if i == crossings[1]:
            assert not bool(br.stable[i]) and not bool(hb.stable)
    radii = sorted(float(np.hypot(z[0], z[1])) for z in found)   # three distinct orbits
    assert radii[1] > 1.1 * radii[0] and radii[2] > 1.1 * radii[1]


def test_periodic_branch_folds_where_the_synchronous_branch_does(setup):
    """Harmonic balance continued in the speed (fixed frame, one harmonic) folds at
    the speeds where the rotating-frame branch folds, and is unstable between
    them on its middle part, as that branch is."""
    from rotorjax.analysis import periodic_branch

    rotor, parts, br = setup
    folds = sorted(e.p for e in br.events if e.kind == "fold")
    w0 = 101.5
    i = int(np.searchsorted(br.p, w0))   # below both folds: one orbit
    s = (w0 - br.p[i - 1]) / (br.p[i] - br.p[i - 1])
    u = (1 - s) * br.u[i - 1] + s * br.u[i]
    scene = RotorScene(rotor, w0, parts)
    T = 2 * np.pi / w0
    guess = np.stack([np.zeros_like(u), scene.to_fixed(0.0, u), scene.to_fixed(T / 4, u)])
    hb, _ = periodic_branch(lambda w: RotorScene(rotor, w, parts), w0, guess, (w0, 105.0), harmonics=1,
                            name="speed", ds=0.05, ds_max=0.5, direction=1)
    got = sorted(e.p for e in hb.events if e.kind == "fold")
    np.testing.assert_allclose(got, folds, rtol=1e-8)
    outside = (hb.p < folds[0] - 0.01) | (hb.p > folds[1] + 0.01)
    assert np.all(hb.stable[outside]) and not np.all(hb.stable[~outside])
