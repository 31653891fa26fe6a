"""Checks of the numbers notebooks/fluid_films.py prints (see tests/test_notebooks.py).

The equilibrium against the short bearing's closed forms, solved here: each journal
carries half the weight (the file's masses; the rig is symmetric), Ocvirk's load
equation gives the eccentricity at that load and speed (scipy's brentq), and the
attitude angle is `tan phi = pi sqrt(1 - eps^2) / (4 eps)`. The onset of oil whirl:
the largest real part of the eigenvalues (scipy, in the notebook) changes sign across
it, and the whirl is forward, below the running speed, near half of it."""

import tomllib

import numpy as np
from scipy.optimize import brentq

from rotorjax.io import shipped_rotor

REQUIRED = True


def check(claims):
    with open(shipped_rotor("journal_rig"), "rb") as f:
        rotor = tomllib.load(f)
    steel = rotor["material"][0]
    mass = sum(steel["rho"] * np.pi / 4 * e["od"] ** 2 * e["L"] for e in rotor["shaft"])
    mass += sum(d["m"] for d in rotor["disk"])
    b = rotor["bearing"][0]
    load = 9.81 * mass / 2
    loc = claims["locus"]
    for w, e, a, f in zip(loc["speeds"], loc["eccentricity"], loc["attitude"], loc["load"]):
        assert abs(f / load - 1) < 1e-9
        ss = b["viscosity"] * w * b["diameter"] * b["length"] ** 3 / (8 * b["clearance"] ** 2 * load)
        eps = brentq(lambda x: ss * x * np.sqrt(np.pi ** 2 * (1 - x * x) + 16 * x * x) / (1 - x * x) ** 2 - 1,
                     1e-12, 1 - 1e-12, xtol=1e-15)
        assert abs(e - eps) < 1e-9, (w, e, eps)
        assert abs(np.tan(a) - np.pi * np.sqrt(1 - eps ** 2) / (4 * eps)) < 1e-7 * np.tan(a), (w, a)
    assert np.all(np.diff(loc["eccentricity"]) < 0)          # faster, nearer the centre
    on = claims["onset"]
    assert on["margin_below"] < 0 < on["margin_above"]
    assert 0.4 < on["ratio"] < 0.65
    scan, margin = np.asarray(on["scan"]), np.asarray(on["margin"])
    assert np.all(margin[scan < 0.99 * on["speed"]] < 0) and np.all(margin[scan > 1.01 * on["speed"]] > 0)
