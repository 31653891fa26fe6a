"""Checks of the numbers notebooks/identification.py prints (see tests/test_notebooks.py).

Validation: the fitted parameters and unbalances against the truth the notebook's
synthetic data were made with (`truth`, `flex["truth"]`); the bands marked "regression pin"
bracket what the notebook printed, not an independent value."""

REQUIRED = True

NAMES = ("k1", "k2", "c1", "c2")


def check(claims):
    truth = claims["truth"]
    assert truth == {"k1": 2e5, "k2": 3e5, "c1": 150.0, "c2": 200.0}
    # regression pin: produced by `python notebooks/identification.py` (2026-11-25)
    assert claims["n_revolutions"] == 667

    # the steady fit as before: every 95 % interval misses, and nothing warned
    old = claims["old"]
    assert not any(old["covers"].values()), old["intervals"]
    assert all(abs(old["error_in_sd"][k]) > 2.5 for k in NAMES), old["error_in_sd"]
    # the bands around the steady fit's errors: regression pin: produced by
    # `python notebooks/identification.py` (2026-11-25)

    assert 0.5 < old["error_pct"]["k1"] < 1.0 and 1.0 < old["error_pct"]["c2"] < 2.0
    assert old["warnings"] == []

    # the diagnosis, each source alone (noise-free signals), in per cent
    d = claims["diagnosis"]
    # the bands below: regression pin: produced by `python notebooks/identification.py` (2026-11-25)
    model = d["model_error_pct"]
    assert 0.3 < model["k1"] < 0.5 and 0.1 < model["k2"] < 0.3 and 0.05 < model["c1"] < 0.2 \
        and 0.5 < model["c2"] < 0.8, model
    assert all(abs(v) < 0.1 for v in d["averaging_bias_pct"].values()), d["averaging_bias_pct"]
    ref = d["reference_bias_unweighted_pct"]
    # the tacho's phase reference; regression pin: produced by `python notebooks/identification.py` (2026-11-25)
    assert ref["c1"] > 0.8 and ref["k2"] > 0.3, ref
    weighted = d["reference_bias_pct"]
    assert all(abs(weighted[k]) < abs(ref[k]) for k in NAMES), (weighted, ref)
    # sources add up: transient + reference, as the steady fit saw them without noise
    both = d["transient_and_reference_bias_unweighted_pct"]
    for k in NAMES:
        assert abs(both[k] - (model[k] + ref[k])) < 0.25, (k, both[k], model[k], ref[k])
    # independent: a pulse time uniform within a 1 ms sample has sd 1/sqrt(12) ms = 0.289 ms
    assert 0.25 < d["pulse_jitter_ms"] < 0.33
    assert d["angle_error_max_mrad"] < 3 * max(d["angle_sd_ends_mrad"])
    # the residuals are nearly independent: correlation is not why the intervals missed
    assert all(abs(r) < 0.2 for r in d["residual_rho1"].values()), d["residual_rho1"]
    # regression pin: produced by `python notebooks/identification.py` (2026-11-25)
    assert all(n > 400 for n in d["residual_n_eff"].values()), d["residual_n_eff"]
    # regression pin: produced by `python notebooks/identification.py` (2026-11-25)
    assert all(1.0 <= r < 1.4 for r in d["hac_over_classical_sd"].values()), d["hac_over_classical_sd"]

    # the run-up model with the phase reference fitted jointly: intervals that cover
    new = claims["new"]
    assert new["model"] == "runup" and new["covariance_method"] == "hac"
    assert all(new["covers"].values()), new["intervals"]
    assert all(abs(new["error_pct"][k]) < 0.5 for k in NAMES), new["error_pct"]
    assert all(abs(new["error_in_sd"][k]) < 2.0 for k in NAMES), new["error_in_sd"]
    for k in NAMES:
        lo, hi = new["intervals"][k]
        old_lo, old_hi = old["intervals"][k]
        assert 0.3 < (hi - lo) / (old_hi - old_lo) < 3.0                 # honest, not blown up
    assert new["warnings"] == []
    assert all(abs(r) < 0.2 for r in new["residual_rho1"].values())
    rms = new["phase_correction_rms_mrad"]
    assert rms["difference"] < 0.6 * rms["actual"], rms                   # the fit sees most of the tacho's error
    assert all(abs(a) < 0.5 for a in new["unbalance_angle_error_deg"])

    # balancing from the steady runs: 20 g at 210 deg and 30 g at 20 deg (validation: the corrections that
    # cancel the unbalance the notebook's synthetic runs were made with)
    c = claims["balancing"]["corrections"]
    assert abs(c[0]["mass_g"] - 20) < 0.3 and abs(c[0]["angle_deg"] - 210) < 1.5
    assert abs(c[1]["mass_g"] - 30) < 0.3 and abs(c[1]["angle_deg"] - 20) < 1.5
    # regression pin: produced by `python notebooks/identification.py` (2026-11-25)
    assert claims["balancing"]["model_based_difference"] < 0.01

    # the flexible rig (issue 16): the 8 bearing coefficients and 2 unbalances from the run-up
    flex = claims["flexible"]
    assert set(flex["estimates"]) == set(flex["truth"]) and len(flex["truth"]) == 8
    assert all(abs(flex["error_pct"][k]) < 2.0 for k in flex["truth"]), flex["error_pct"]
    assert flex["warnings"] == [], flex["warnings"]
    assert [u["node"] for u in flex["unbalances"]] == [2, 4]
    assert all(u["relative_error"] < 0.02 for u in flex["unbalances"]), flex["unbalances"]
    assert len(flex["critical_speeds"]) == 2
    for c in flex["critical_speeds"]:                                    # the as-built, not the design, criticals
        assert abs(c["speed"] / c["true"] - 1) < 0.005 and abs(c["speed"] / c["design"] - 1) > 0.02, c
    # balancing from the trial runs, LS and min-max: each correction cancels the true unbalance within 3 %
    for method in ("ls", "minmax"):
        b = flex["balancing"][method]
        assert [c["node"] for c in b["corrections"]] == [2, 4]
        assert all(c["cancel_rel"] < 0.03 for c in b["corrections"]), (method, b["corrections"])
        # the run-up after balancing: below 5 % of before; the identified rotor predicts it within
        # 10 % of the before level
        r = flex["runup"][method]
        assert r["measured_after_max"] < 0.05 * flex["runup"]["before_max"], (method, r)
        assert r["difference_max"] < 0.10 * flex["runup"]["before_max"], (method, r)
