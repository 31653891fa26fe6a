"""Issue 62, validation: the jump of an anisotropic cubic rotor, whose synchronous
orbit is no rest point of any rotating frame (its orbits are ellipses, so the
cubic bearings' force has every odd harmonic), by `periodic_branch` with its
defaults, on a rotor it was not built on: the shipped `cubic_rig.toml` with bearing
0 stiffer in y (kyy = 1.1 kxx), continued in speed through its jump.

Independent reference: the rotor's equations integrated in time (diffrax's Dopri8
through `rotorjax.simulate`, nothing of harmonic balance; stored in
`tests/validation/data/`, made by `reference()`):
- settled motions at three speeds, four orbits (both coexisting ones in the jump's
  hysteresis) equal the branch's orbits at node 1 to 1e-3 of their amplitude;
- slow run-up and run-down sweeps (0.1 rad/s^2) follow the branch's stable parts
  and jump within 1 % past its folds: down after the highest fold on the way up, up
  below the lowest on the way down (a sweep lags the quasi-static jump, never leads
  it)."""

import re
import tempfile
from pathlib import Path

import equinox as eqx
import numpy as np
import pytest

import rotorjax
from rotorjax.analysis import harmonic_balance
from rotorjax.models import RunUp
from tests.helpers import cubic_rig_variant, orbits_of, settled_orbit, speed_branch, store_reference, stored_reference

pytestmark = pytest.mark.slow

RANGE = (101.0, 106.0)    # rad/s, through the jump
NODE = 1                  # the first disk
RATE = 0.1                # rad/s^2, the sweeps
PHASES = np.linspace(0.0, 2 * np.pi, 128, endpoint=False)
#: as docs/periodic.md gives them (rad/s): the lowest and highest fold, the run-down's and the run-up's jump
FOLDS, JUMPS = (103.18, 104.29), (102.77, 104.84)
REFERENCE = "periodic_anisotropic_jumps_runs"    # tests/validation/data/, made by `reference()`


def anisotropic(text):
    """cubic_rig.toml with bearing 0 at kyy = 1.1e6 (kxx = 1e6)."""
    text, n = re.subn(r"(?m)^kxx = 1e6( .*)?$", "kxx = 1e6\nkyy = 1.1e6", text, count=1)
    assert n == 1
    return text


@pytest.fixture(scope="module")
def rig(tmp_path_factory):
    scene = cubic_rig_variant(tmp_path_factory.mktemp("rotor"), "anisotropic_jump.toml", anisotropic)
    scene_at, br, coefficients, orbits = speed_branch(scene, RANGE, PHASES)
    radius = np.hypot(orbits[..., 2 * 2 * NODE], orbits[..., 2 * 2 * NODE + 1])     # 4 dofs a node: x, y first
    folds = sorted(e.p for e in br.events if e.kind == "fold")
    return scene_at, br, coefficients, radius.max(axis=1), folds


def _sheets(br, amplitude, w):
    """The branch's stable points nearest `w` on each crossing of it, lowest
    amplitude first: `[(index, amplitude)]`."""
    found = []
    for i in range(br.p.size - 1):
        if (br.p[i] - w) * (br.p[i + 1] - w) <= 0 and br.stable[i] and br.stable[i + 1]:
            j = i if abs(br.p[i] - w) < abs(br.p[i + 1] - w) else i + 1
            found.append((j, amplitude[j]))
    return sorted(found, key=lambda f: f[1])


def test_the_branch_crosses_its_jump_with_the_defaults(rig):
    """Both range ends reached, every point within the truncation target, and a
    hysteresis: two stable orbits between the lowest and highest fold."""
    _, br, _, amplitude, folds = rig
    assert br.stops == ("box edge (speed = 101.0)", "box edge (speed = 106.0)")
    assert np.all(np.asarray(br.truncation) <= 1e-6)
    assert len(folds) >= 2 and folds[-1] - folds[0] > 0.5
    np.testing.assert_allclose([folds[0], folds[-1]], FOLDS, atol=0.02)
    assert (min(br.harmonics), max(br.harmonics)) == (16, 32)
    assert len(_sheets(br, amplitude, 0.5 * (folds[0] + folds[-1]))) == 2


def _sweep(scene, w0, w1):
    """Node 1's orbit radius, its largest over each revolution, along a sweep from
    rest at `w0` to `w1` at `RATE`: `(speeds, envelope)`."""
    rate = RATE if w1 > w0 else -RATE
    t1 = (w1 - w0) / rate
    per_rev = 24
    ts = np.linspace(0.0, t1, int(t1 * w0 / (2 * np.pi)) * per_rev + 1)
    res = rotorjax.simulate(eqx.tree_at(lambda s: s.speed, scene, RunUp(w0, rate)), np.zeros(scene.state_size),
                            (0.0, t1), saveat=ts, solver="dopri8", rtol=1e-8, atol=1e-12,
                            max_steps=2_000_000).raise_if_failed()
    ys = np.asarray(res.ys)
    r = np.hypot(ys[:, 2 * 2 * NODE], ys[:, 2 * 2 * NODE + 1])[:-1].reshape(-1, per_rev).max(axis=1)
    return w0 + rate * ts[:-1:per_rev], r


def reference():
    """The time simulations (independent of harmonic balance), stored
    (`python -m tests.validation.test_periodic_anisotropic_jumps`: they take a few
    minutes): the motions settled over 400 revolutions below, inside (both sheets)
    and above the hysteresis, from rest or from the branch's orbit 3 % off (a start
    in the sheet's basin; the branch is solved here for that only), node 1's x and y
    over the last revolution; the run-up's and the run-down's envelopes (`_sweep`)."""
    scene = cubic_rig_variant(Path(tempfile.mkdtemp()), "anisotropic_jump.toml", anisotropic)
    _, br, _, orbits = speed_branch(scene, RANGE, PHASES)
    radius = np.hypot(orbits[..., 2 * 2 * NODE], orbits[..., 2 * 2 * NODE + 1]).max(axis=1)
    folds = sorted(e.p for e in br.events if e.kind == "fold")
    mid = 0.5 * (folds[0] + folds[-1])
    (below, _), = _sheets(br, radius, folds[0] - 1.5)
    (above, _), = _sheets(br, radius, folds[-1] + 1.0)
    (lower, _), (upper, _) = _sheets(br, radius, mid)
    speeds, orbits_settled = [], []
    for i, start in ((below, None), (lower, 1.03), (upper, 0.97), (above, None)):
        y0 = np.zeros(scene.state_size) if start is None else start * orbits[i, 0]
        speeds.append(float(br.p[i]))
        orbits_settled.append(settled_orbit(scene, speeds[-1], y0, 400, PHASES)[:, 2 * 2 * NODE:2 * 2 * NODE + 2])
    up, down = _sweep(scene, *RANGE), _sweep(scene, *RANGE[::-1])
    return dict(speeds=np.asarray(speeds), settled=np.asarray(orbits_settled), up_w=up[0], up_r=up[1], down_w=down[0],
                down_r=down[1])


@pytest.fixture(scope="module")
def runs():
    return stored_reference(REFERENCE)


def test_settled_motions_are_the_branch_s_orbits(rig, runs):
    """Below, inside (both sheets) and above the hysteresis: the motion settled over
    400 revolutions (`reference`), from rest or from the orbit's state 3 % off, equals the
    branch's at node 1 (the point of its sheet nearest that speed, solved again there)
    to 1e-3 of its amplitude (measured: 5e-6 to 3e-5)."""
    scene_at, br, coefficients, amplitude, _ = rig
    for w, settled in zip(runs["speeds"], runs["settled"]):
        reached = np.hypot(settled[:, 0], settled[:, 1]).max()
        (i, _), = sorted(_sheets(br, amplitude, w), key=lambda f: abs(f[1] - reached))[:1]
        H = int(br.harmonics[i])
        sol = harmonic_balance(scene_at(w), 2 * np.pi / w, coefficients[i, :2 * H + 1], H, stability=False)
        assert int(sol.code) == 0
        orbit = orbits_of(sol.coefficients, PHASES)[:, 2 * 2 * NODE:2 * 2 * NODE + 2]
        err = np.abs(settled - orbit).max() / amplitude[i]
        assert err < 1e-3, (w, err)


def test_slow_sweeps_jump_past_the_folds_within_one_percent(rig, runs):
    """The run-up drops after the highest fold and within 1 % of it, the run-down
    jumps up below the lowest fold and within 1 % of it; away from the jumps both
    follow the branch's stable sheets to 2 % (the sweep's lag)."""
    _, br, _, amplitude, folds = rig
    mid = 0.5 * (folds[0] + folds[-1])
    (_, lower), (_, upper) = _sheets(br, amplitude, mid)
    for (w0, w1), w, r in (((RANGE[0], RANGE[1]), runs["up_w"], runs["up_r"]),
                           ((RANGE[1], RANGE[0]), runs["down_w"], runs["down_r"])):
        settled = np.abs(w - w0) > 1.0                       # past the start's transient
        jumps = np.diff(r) * np.sign(w1 - w0)                # the run-up falls, the run-down rises
        k = int(np.argmin(np.where(settled[1:], jumps, np.inf)))
        jump = 0.5 * (w[k] + w[k + 1])
        if w1 > w0:
            assert folds[-1] < jump < 1.01 * folds[-1], (jump, folds)
        else:
            assert 0.99 * folds[0] < jump < folds[0], (jump, folds)
        assert abs(jump - JUMPS[w1 > w0]) < 0.03, jump
        at_mid = r[np.argmin(np.abs(w - mid))]
        assert abs(at_mid - (upper if w1 > w0 else lower)) < 0.02 * at_mid
        for beside in (folds[0] - 1.5, folds[-1] + 1.0):
            (_, a), = _sheets(br, amplitude, beside)
            assert abs(r[np.argmin(np.abs(w - beside))] - a) < 0.02 * a


def test_the_docs_state_these_checks():
    from tests.helpers import documentation

    text = " ".join(documentation("docs/periodic.md").split())
    assert ("the shipped `cubic_rig.toml` with bearing 0 at kyy = 1.1 kxx, continued over 101..106 rad/s with the "
            "defaults" in text)
    assert f"{RANGE[0]:g}..{RANGE[1]:g} rad/s" in text
    assert "equal the branch's orbits at the first disk to 1e-3 of their amplitude" in text
    assert f"Sweeps at {RATE:g} rad/s^2 jump within 1 % past the folds" in text
    assert "The branch crosses its jump with 16 to 32 harmonics" in text
    assert (f"({JUMPS[1]:.2f} against {FOLDS[1]:.2f} rad/s), the run-down up below the lowest ({JUMPS[0]:.2f} against "
            f"{FOLDS[0]:.2f})" in text)


if __name__ == "__main__":
    import jax

    jax.config.update("jax_enable_x64", True)
    store_reference(REFERENCE, reference(), "python -m tests.validation.test_periodic_anisotropic_jumps")
