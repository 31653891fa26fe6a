"""Damped modes (natural frequency, damping ratio, whirl) against ROSS 2.3.0's
`run_modal` (reference numbers from `ross_static_reference.py`, stored in
`data/ross_modal.json`), and mode tracking along a Campbell diagram by the modal
assurance criterion."""

import json
import os

import numpy as np
import pytest

from rotorjax.flexible import FlexibleRotor, campbell, mac, modes, track_modes, track_order, whirl_labels

DATA = os.path.join(os.path.dirname(__file__), "data", "ross_modal.json")


@pytest.fixture(scope="module")
def reference():
    with open(DATA) as f:
        return json.load(f)


def _rotor(spec):
    return FlexibleRotor(np.array(spec["lengths"]), spec["d_out"], E=spec["E"], G=spec["G"], rho=spec["rho"],
                         disks=[tuple(d) for d in spec["disks"]], bearings=[tuple(b) for b in spec["bearings"]])


@pytest.mark.parametrize("case", ["rotor_example", "rotor_example_damped", "gyroscopic"])
def test_modes_match_ross(reference, case):
    """wn, wd, damping ratio and log dec of the first 8 lateral modes at three speeds:
    within 1e-9 relative (the damping of the undamped rotor: round-off, 1e-11 absolute)."""
    c = reference["cases"][case]
    rotor = _rotor(c["rotor"])
    for row in c["modes"]:
        m = modes(rotor, row["speed"], 8)
        np.testing.assert_allclose(np.asarray(m.frequencies), row["wd"], rtol=1e-9)
        np.testing.assert_allclose(np.asarray(m.natural_frequencies), row["wn"], rtol=1e-9)
        np.testing.assert_allclose(np.asarray(m.damping_ratio), row["damping_ratio"], rtol=1e-8, atol=1e-11)
        np.testing.assert_allclose(np.asarray(m.log_dec), row["log_dec"], rtol=1e-8, atol=1e-10)
        zeta = np.asarray(m.damping_ratio)
        np.testing.assert_allclose(np.asarray(m.log_dec), 2 * np.pi * zeta / np.sqrt(1 - zeta**2), rtol=1e-10,
                                   atol=1e-12)


@pytest.mark.parametrize("case", ["rotor_example", "rotor_example_damped", "gyroscopic"])
def test_whirl_matches_ross_except_round_off_nodes(reference, case):
    """At speed > 0 the whirl labels equal ROSS's, except where ROSS says "mixed"
    because one node's orbit is of round-off size (a node of the mode shape, whose
    phase is noise; ROSS counts it, we do not): there our label is checked to hold
    at every other node. At speed 0 (planar modes of anisotropic bearings) ROSS's
    labels come from round-off phases; ours are "mixed"."""
    c = reference["cases"][case]
    rotor = _rotor(c["rotor"])
    agree = 0
    for row in c["modes"]:
        m = modes(rotor, row["speed"], 8)
        ours = list(m.whirl)
        if row["speed"] == 0:
            assert ours == ["mixed"] * 8
            continue
        sh = np.asarray(m.shapes)
        for k, (a, b) in enumerate(zip(ours, row["whirl"])):
            if a == b:
                agree += 1
                continue
            assert b == "mixed" and a in ("forward", "backward"), (row["speed"], k, a, b)
            x, y = sh[0::4, k], sh[1::4, k]
            amp = np.abs(x) ** 2 + np.abs(y) ** 2
            tiny = amp < 1e-12 * amp.max()
            assert tiny.any()
            s = np.imag(np.conj(x) * y)[~tiny]
            assert np.all(s < 0) if a == "forward" else np.all(s > 0)
    assert agree >= 12


def test_whirl_labels_and_mac_of_a_mode_with_itself():
    assert list(whirl_labels([0.0, 0.5, 1.0])) == ["forward", "mixed", "backward"]
    rotor = FlexibleRotor([0.25] * 6, 0.05, disks=[(2, 30.0, 0.2, 0.3)], bearings=[(0, 1e6, 1e6, 0, 0),
                                                                                   (6, 1e6, 1e6, 0, 0)])
    m = modes(rotor, 300.0, 6)
    sh = np.asarray(m.shapes)
    c = np.asarray(mac(sh, sh))
    np.testing.assert_allclose(np.diag(c), 1.0, rtol=1e-12)
    np.testing.assert_allclose(np.asarray(mac(sh[:, 0], (2 - 3j) * sh[:, 0])), [[1.0]], rtol=1e-12)
    assert np.all((c >= 0) & (c <= 1 + 1e-12))
    # isotropic bearings: the forward and backward modes of one pair are orthogonal in the MAC sense
    assert c[0, 1] < 1e-6


def test_tracked_branches_follow_crossings():
    """ROSS's example rotor from 0 to 4000 rad/s: its second forward branch (rising)
    crosses the third backward one (falling) near 2700 rad/s, and more cross above.
    Sorted by frequency, four columns switch between forward and backward whirl and
    a column's shape changes at a crossing (its MAC with the previous speed's drops
    below 0.5); tracked, every branch keeps its whirl, its shape (MAC between
    successive speeds above 0.9) and a continuous slope (second differences of the
    second forward branch below 0.5 rad/s at 50 rad/s steps, against 3 rad/s for
    the sorted column's kink)."""
    ref_spec = json.load(open(DATA))["cases"]["rotor_example"]["rotor"]
    rotor = _rotor(ref_spec)
    speeds = np.linspace(0.0, 4000.0, 81)
    camp = campbell(rotor, speeds, 10)
    tracked = track_modes(camp)
    _, step = track_order(camp)
    sorted_step = np.array([[float(np.asarray(mac(np.asarray(camp.shapes)[i - 1][:, k],
                                                      np.asarray(camp.shapes)[i][:, k]))[0, 0])
                             for k in range(8)] for i in range(1, len(speeds))])
    assert sorted_step.min() < 0.5
    assert step[:, :8].min() > 0.9

    def swaps(m):
        w = np.asarray(m.whirl_value)[1:, :8]
        return [bool((w == 0).any(axis=0)[k] and (w == 1).any(axis=0)[k]) for k in range(8)]

    assert sum(swaps(camp)) >= 2
    assert not any(swaps(tracked))
    d2_sorted = np.abs(np.diff(np.asarray(camp.frequencies)[:, 3], 2)).max()
    d2_tracked = np.abs(np.diff(np.asarray(tracked.frequencies)[:, 3], 2)).max()
    assert d2_tracked < 0.5 < 3.0 < d2_sorted
    # the tracked set is the sorted one re-ordered at every speed
    np.testing.assert_allclose(np.sort(np.asarray(tracked.frequencies), axis=1), np.asarray(camp.frequencies))
    assert list(np.asarray(tracked.whirl)[-1, :2]) == ["backward", "forward"]
