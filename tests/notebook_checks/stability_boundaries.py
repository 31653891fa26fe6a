"""Checks of the numbers notebooks/stability_boundaries.py prints (see tests/test_notebooks.py)."""

import numpy as np

REQUIRED = True


def check(claims):
    # model 001, multipliers along n at mu_w = 0.5: complex pairs entering, leaving, entering the unit circle
    fc = claims["floquet_crossings"]
    # regression pin: produced by `python notebooks/stability_boundaries.py` (its printed claims; tests/test_notebooks.py), 2026-11-25
    np.testing.assert_allclose([c["n"] for c in fc], [1.014348, 5.049930, 8.322286], atol=1e-5)
    assert [c["kind"] for c in fc] == ["complex pair"] * 3
    assert [c["direction"] for c in fc] == ["enters", "leaves", "enters"]
    for c in fc:
        below, above = c["max_abs_multiplier_below"], c["max_abs_multiplier_above"]
        assert (below > 1 > above) if c["direction"] == "enters" else (below < 1 < above)
        assert c["stable_side"] == ("above" if c["direction"] == "enters" else "below")
        assert f"{c['direction']} the unit circle as n increases" in c["wording"]
        assert ("stable above" if c["direction"] == "enters" else "unstable above") in c["wording"]

    # model 001: three boundaries over the whole speed range, from mu_w = 0.05 to 1
    m = claims["model_001"]
    assert m["box"] == {"n": [0.5, 10.0], "mu_w": [0.05, 1.0]} and m["n_boundaries"] == 3
    ranges = [(1.0076027, 1.3451642), (4.6071146, 5.0534715), (7.8630886, 9.6322835)]  # regression pins (as above)
    for b, r in zip(m["boundaries"], ranges):
        np.testing.assert_allclose(b["n_range"], r, atol=1e-6)
        assert b["mu_w_range"] == [0.05, 1.0] and b["stops"] == ["box edge (mu_w = 0.05)", "box edge (mu_w = 1.0)"]
        assert b["interpolation_error_max"] <= 1e-6 and b["residual_max"] < 1e-9
    third = m["boundaries"][2]["n_at_mu_w"]
    assert abs(third["0.53"][0] - 8.2895) < 1e-3  # regression pins (as above), both and abs(third["0.85"][0] - 7.9885) < 1e-3
    # the first two barely move for mu_w >= 0.2, the third one does (and by 1.77 over the box)
    moves = m["n_moves_for_mu_w_from_0.2"]
    assert moves[0] < 0.05 and moves[1] < 0.08 and moves[2] > 0.9
    assert m["boundaries"][2]["n_range"][1] - m["boundaries"][2]["n_range"][0] > 1.7

    # against critical speeds bisected independently: three per mu_w, within 1e-6 of the dense curves
    bis = m["bisection"]
    assert bis["crossings_per_mu_w"] == 3 and len(bis["points"]) == 3 * len(bis["mu_w"]) >= 9
    assert bis["distance_max"] < 1e-6
    assert max(p["distance"] for p in bis["points"]) == bis["distance_max"]
    for p in bis["points"]:
        assert any(b["n_range"][0] <= p["bisected_n"] <= b["n_range"][1] for b in m["boundaries"])

    # the paper's criterion: right for the first two boundaries, wrong by 1.1-1.4 for the third
    np.testing.assert_allclose(m["criterion_roots"], [1.0026138, 5.0406729, 6.9254157], atol=1e-6)  # regression pins
    err = m["criterion_error"]
    assert abs(err[0]["at_preset_mu_w"]) < 0.02 and abs(err[1]["at_preset_mu_w"]) < 0.02
    assert 1.1 < err[2]["at_preset_mu_w"] < 1.45
    assert 1.0 < min(err[2]["over_mu_w_0.53_0.85"]) and max(err[2]["over_mu_w_0.53_0.85"]) < 1.4
    assert err[2]["over_box"][0] > 0.9 and err[2]["over_box"][1] > 2.5

    # model 003: one boundary across the box, both ends on its edge, stable above it in omega
    m3 = claims["model_003"]
    assert m3["n_boundaries"] == 1
    (b,) = m3["boundaries"]
    assert all(s.startswith("box edge") for s in b["stops"]) and b["interpolation_error_max"] <= 1e-6
    assert abs(b["omega_range"][0] - 0.7001) < 1e-3  # regression pin (as above) and b["omega_range"][1] == 3.0
    assert b["d_range"][0] < 1e-3 and b["d_range"][1] == 0.5
    assert b["stable_side_in_omega"] == "above"
    assert b["omega_at_d"]["0.5"][0] < b["omega_at_d"]["0.1"][0] < b["omega_at_d"]["0.01"][0]
