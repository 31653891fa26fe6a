"""Checks of the numbers notebooks/design_uncertainty.py prints (see tests/test_notebooks.py).

Uncertainty: two samples recomputed from the rotor file read again with their values
(the analyses' own solvers) equal the vmapped function's; the first-order moments
near the Monte Carlo ones; the horizontal stiffnesses set the first critical speed,
the vertical ones the first mode's damping; the violation probability's 95 % Wilson
interval holds a 4000-sample estimate drawn afresh, and so do at least 36 of the 40
intervals of 100 samples (coverage: a true 95 % interval holds it 35 times or fewer
with probability 0.05). Design: the optimum no worse than the best of a vmapped
grid, both dampers at their bound, and the least log decrements before and after the
ones the documentation's design page states for the same problem."""

import re

import numpy as np

from tests.helpers import documentation

REQUIRED = True


def check(claims):
    mean, std = np.array(claims["mean"]), np.array(claims["std"])
    assert claims["recomputed"] < 1e-8
    assert np.all(np.abs(mean - np.array(claims["fosm_mean"])) < 0.3 * std)
    assert np.all(np.abs(np.array(claims["fosm_std"]) / std - 1) < 0.1)
    shares = np.array(claims["shares"])
    assert np.allclose(shares.sum(axis=1), 1.0)
    kxx = [claims["inputs"].index(f"bearing{i}.kxx") for i in (0, 1)]
    assert shares[claims["outputs"].index("critical_speed_0"), kxx].sum() > 0.95
    kyy = [claims["inputs"].index(f"bearing{i}.kyy") for i in (0, 1)]
    assert shares[claims["outputs"].index("log_dec_0"), kyy].sum() > 0.95
    p, lo, hi = claims["probability"]
    assert 0.2 < p < 0.8 and lo <= claims["pooled"] <= hi
    assert claims["held"] >= 36
    before, after = claims["design"]
    assert claims["converged"] and after >= claims["grid_best"] - 1e-9 and after > before
    assert all(v == 3000.0 for v in claims["after"].values())
    stated = re.search(r"from ([\d.]+) to ([\d.]+), both dampers at their 3000", " ".join(
        documentation("docs/design.md").split()))
    assert abs(before - float(stated.group(1))) < 5e-4 and abs(after - float(stated.group(2))) < 5e-4
