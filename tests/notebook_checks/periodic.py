"""Checks of the numbers notebooks/periodic.py prints (see tests/test_notebooks.py).

The folds of the harmonic-balance branch equal those of the rotating frame's rest
points (`synchronous_branch`: no Fourier series, no time), and the documentation's
(the CLI page states them for the same command); between the folds three motions, the
middle one unstable; the branch stable at both ends of the range."""

import re

from tests.helpers import documentation

REQUIRED = True


def check(claims):
    folds, sync = claims["folds"], claims["sync_folds"]
    assert len(folds) == len(sync) == 2
    assert all(abs(a - b) < 1e-6 * b for a, b in zip(folds, sync)), (folds, sync)
    stated = re.search(r"folds at ([\d.]+) and ([\d.]+)", " ".join(documentation("docs/cli.md").split()))
    assert all(abs(f - float(s)) < 0.006 for f, s in zip(folds, stated.groups()))
    assert [s for _, s in claims["three"]] == [True, False, True]
    assert claims["stable_ends"] == [True, True]
