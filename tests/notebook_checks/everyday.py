"""Checks of the numbers notebooks/everyday.py prints (see tests/test_notebooks.py).

Each against what is known without the notebook's code path: the rotor's mass from its
file (shaft volumes times density, plus the disks), the bearings carrying its weight,
the unbalance response's first peak at the first forward critical speed, API 684's
margins recomputed from its formula, and on isotropic bearings the amplification
factor from the mode's damping equal to the half-power bandwidth's of the response."""

import tomllib

import numpy as np

from rotorjax.io import shipped_rotor

REQUIRED = True


def check(claims):
    with open(shipped_rotor("flexible_rig"), "rb") as f:
        rotor = tomllib.load(f)
    rho = rotor["material"][0]["rho"]
    mass = sum(rho * np.pi / 4 * (e["od"] ** 2 - e["id"] ** 2) * e["L"] for e in rotor["shaft"])
    mass += sum(d["m"] for d in rotor["disk"])
    assert abs(claims["mass"] / mass - 1) < 1e-12
    assert abs(claims["weight"] / (9.80665 * mass) - 1) < 1e-12
    assert abs(sum(claims["reactions"]) / claims["weight"] - 1) < 1e-9
    # the first peak of the response at mid-span is the first forward critical speed (light damping: within 1 %)
    assert abs(claims["response"]["peaks"][0] / claims["critical_speeds"][0] - 1) < 0.01
    lo, hi = claims["operating"]
    assert [r["speed"] for r in claims["api684"]] == claims["critical_speeds"]
    for r in claims["api684"]:
        below = r["speed"] <= (lo + hi) / 2
        margin = 100 * ((lo - r["speed"]) / lo if below else (r["speed"] - hi) / hi)
        base = 17 * (1 - 1 / max(r["af"] - 1.5, 1.0))
        required = 0.0 if r["af"] < 2.5 else (min(16.0, base) if below else min(26.0, 10 + base))
        assert abs(r["margin"] - margin) < 1e-9 and abs(r["required"] - required) < 1e-9
        assert r["meets"] == (margin >= required)
    # anisotropic bearings widen the peak (the backward whirl responds too); isotropic ones do not
    assert claims["response"]["af_half_power"] < 0.8 * claims["api684"][0]["af"]
    iso = claims["isotropic"]
    assert abs(iso["af_half_power"] / iso["af"] - 1) < 0.03
    assert claims["level1"]["log_dec_0"] > 0 and claims["level1"]["q0"] > 0
