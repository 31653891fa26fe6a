"""The shipped flexible-rotor datasets (`flexible-runup`, `flexible-trials`): they are
what the seeded script `rotorjax.identify._make_fe_data` writes, the true machine's
forward critical speeds lie inside the run-up, and the noise is the documented 1 %."""

import csv

import numpy as np
import pytest

import rotorjax  # noqa: F401  (float64)
from rotorjax.flexible import critical_speeds_1x
from rotorjax.identify import _make_fe_data as fe
from rotorjax.identify._datasets import ALIASES, DATASETS, dataset_path


def _read(name):
    """The CSV as (header, rows of strings)."""
    with open(dataset_path(name), newline="", encoding="utf-8") as f:
        table = list(csv.reader(f))
    return table[0], table[1:]


def _phasors(rows):
    return np.array([complex(float(r[3]), float(r[4])) for r in rows])


def _regenerated(rows):
    return np.array([complex(r[3], r[4]) for r in rows])


@pytest.fixture(scope="module")
def truth():
    return fe.true_rotor()


def test_registered():
    for name, file in (("flexible-runup", "flexible_runup.csv"), ("flexible-trials", "flexible_trials.csv")):
        assert DATASETS[name][0] == file
        assert ALIASES[name.replace("-", "_")] == name


def test_runup_file_is_the_regeneration():
    header, rows = _read("flexible-runup")
    assert tuple(header) == fe.RUNUP_COLUMNS
    assert len(rows) == 200
    new = fe.runup_rows(fe.RUNUP_SEED)
    assert len(new) == len(rows)
    np.testing.assert_array_equal([float(r[0]) for r in rows], [r[0] for r in new])
    assert [(int(r[1]), r[2], int(r[5])) for r in rows] == [(r[1], r[2], r[5]) for r in new]
    X, Xn = _phasors(rows), _regenerated(new)
    # the file was written when scenes were assembled op by op; now they are assembled in one compiled
    # program, which rounds differently: measured 6.0e-13 (runup) and 2.3e-13 (trials), 2026-11-25
    assert np.max(np.abs(X - Xn) / np.abs(Xn)) <= 1e-11
    assert sorted({float(r[0]) for r in rows}) == list(fe.RUNUP_SPEEDS)


def test_trials_file_is_the_regeneration():
    header, rows = _read("flexible-trials")
    assert tuple(header) == fe.TRIALS_COLUMNS
    assert len(rows) == 3 * len(fe.TRIAL_SPEEDS) * len(fe.SENSORS)
    new = fe.trial_rows(fe.TRIALS_SEED)
    assert len(new) == len(rows)
    np.testing.assert_array_equal([float(r[0]) for r in rows], [r[0] for r in new])
    assert [(int(r[1]), r[2], int(r[5])) for r in rows] == [(r[1], r[2], r[5]) for r in new]
    for r, n in zip(rows, new):
        if n[5] == 0:
            assert r[6:] == ["", "", ""]
        else:
            assert (int(r[6]), float(r[7]), float(r[8])) == n[6:] == fe.TRIALS[n[5]]
    X, Xn = _phasors(rows), _regenerated(new)
    # the file was written when scenes were assembled op by op; now they are assembled in one compiled
    # program, which rounds differently: measured 6.0e-13 (runup) and 2.3e-13 (trials), 2026-11-25
    assert np.max(np.abs(X - Xn) / np.abs(Xn)) <= 1e-11


def test_criticals_inside_the_runup(truth):
    lo, hi = float(fe.RUNUP_SPEEDS[0]), float(fe.RUNUP_SPEEDS[-1])
    crit = [s for s, _ in critical_speeds_1x(truth, lo, hi, whirl="forward")]
    assert len(crit) == 2
    assert lo < 0.5 * crit[0] and crit[1] < hi / 1.2 and crit[1] > 2 * crit[0]
    w = fe.TRIAL_SPEEDS  # below the 1st, near it, between, near the 2nd
    assert w[0] < 0.8 * crit[0] < w[1] < crit[0] < w[2] < 0.8 * crit[1] < w[3] < 1.05 * crit[1]


def test_runup_noise_level(truth):
    _, rows = _read("flexible-runup")
    clean = fe.clean_phasors(truth, fe.UNBALANCES, fe.RUNUP_SPEEDS, fe.SENSORS).ravel()
    rel = np.abs(_phasors(rows) - clean) / np.abs(clean)
    rms = np.sqrt(np.mean(rel**2))
    assert 0.75 * fe.NOISE < rms < 1.25 * fe.NOISE
