"""Issue 34: a preset's stable speed range (an auto-balancer's auto-balancing range)
as a design quantity and an uncertain output (`rotorjax.analysis.StableSpeeds`,
`rotorjax.design.preset_problem`, `rotorjax.uncertainty.preset_quantities`).

One scene: model 000 (elliptic-abb) on a circular race (rho1 = rho2 = 1.2), whose
balanced regime is stationary in the rotating frame (its margin an eigenvalue
problem) and stable above one threshold near nu = 1. Checked against an independent
scan and bisection at a design away from the nominal (the thresholds followed by the
secant against found afresh), its gradient against finite differences, the optimum
against a vmapped brute-force grid, and the Monte Carlo's first-order moments against
the samples'."""

import jax
import numpy as np
import pytest

from rotorjax import presets
from rotorjax._errors import InputError
from rotorjax.analysis import stability_margin, stability_thresholds
from rotorjax.design import optimize_rotor, preset_problem
from rotorjax.uncertainty import LogNormal, preset_quantities, propagate

PRESET = presets.get("elliptic-abb")
PARAMS = PRESET.params({"rho1": 1.2})
VARY = {"delta_n": (0.05, 1.0), "delta_b": (5.0, 400.0)}
RANGE = (0.5, 6.0)


def margin_at(delta_n, delta_b, nu):
    return stability_margin(PRESET.build(dict(PARAMS, delta_n=delta_n, delta_b=delta_b, nu=nu)).reference)


#: docs/design.md's command, run here (`test_the_commands_present_the_design_and_the_distributions`) on this
#: file's problem and design, which are what the command builds (its arguments are checked there): the README test
#: does not run it again (tests/test_readme.py `RUN_ELSEWHERE`)
README_OPTIMIZE = ("rotorjax optimize elliptic-abb --set rho1=1.2 --vary delta_n=0.05:1 --vary delta_b=5:400 "
                   "--range 0.5 6 --starts 3")
#: the command's problem and search: its defaults (--n-scan 40, --seed 0) and --starts 3
PROBLEM_ARGS = dict(speed_range=RANGE, n_scan=40)
SEARCH_ARGS = dict(n_starts=3, seed=0)


@pytest.fixture(scope="module")
def problem():
    return preset_problem(PRESET, PARAMS, VARY, **PROBLEM_ARGS)


@pytest.fixture(scope="module")
def design(problem):
    return optimize_rotor(problem, **SEARCH_ARGS)


@pytest.fixture(scope="module")
def stable_range(problem, design):
    """The stable range at 3 designs at once, on the search's own compiled program
    (`minimize`'s evaluator: the objective is minus the range over its scale)."""
    from rotorjax.design._optimize import _ends, _evaluator, _to_u

    a, b = _ends(problem.lo, problem.hi, problem.log)
    evaluate = _evaluator(problem.fn, 0, a, b, problem.log)
    scale = problem.scales["stable-range"]

    def at(X):
        _, f, _, _ = evaluate(_to_u(np.asarray(X, dtype=float), a, b, problem.log), np.zeros((3, 0)), np.ones(3))
        return -f * scale

    return at


def test_the_followed_threshold_equals_a_fresh_scan_away_from_the_nominal(problem, stable_range):
    """At (delta_n, delta_b) = (0.05, 5), far from the nominal (0.18, 40): the stable
    range from the threshold followed by the secant equals the one from a fresh
    scan-and-bisection there (`stability_thresholds`, 60 speeds, to 1e-12)."""
    assert problem.settings["thresholds"] == [pytest.approx(1.00227011, abs=1e-7)]
    assert problem.settings["stable_between_thresholds"] == [False, True]
    value = stable_range([[0.05, 5.0], [0.18, 40.0], [1.0, 400.0]])
    fresh = stability_thresholds(lambda nu: margin_at(0.05, 5.0, nu), 0.25, 7.375, n_scan=60, xtol=1e-12)
    assert len(fresh) == 1 and fresh[0].stable_side == "above"
    assert value[0] == pytest.approx(RANGE[1] - fresh[0].speed, abs=1e-9)
    assert value[1] == pytest.approx(RANGE[1] - problem.settings["thresholds"][0], abs=1e-9)


def test_the_gradient_is_the_implicit_function_theorems(problem):
    """`minimize`'s gradient (in the scaled box) against central differences of the
    objective, both from its compiled program."""
    from rotorjax.design._optimize import _ends, _evaluator, _to_u

    a, b = _ends(problem.lo, problem.hi, problem.log)
    evaluate = _evaluator(problem.fn, 0, a, b, problem.log)
    u = _to_u(np.array([0.3, 20.0]), a, b, problem.log)
    for i in range(2):
        e = np.zeros(2)
        e[i] = 1e-5
        _, f, _, g = evaluate(np.stack([u, u + e, u - e]), np.zeros((3, 0)), np.ones(3))
        assert g[0, i] == pytest.approx((f[1] - f[2]) / 2e-5, rel=1e-4)
        assert g[0, i] < 0      # either damping lowers the threshold here: the range grows


def test_the_optimum_is_the_best_of_a_brute_force_grid(problem, design, stable_range):
    """The search (3 starts) against the stable range on a 12 x 12 grid (logarithmic,
    3 designs per call of the search's program): no grid design beats the optimum."""
    best = design.quantities_after["stable-range"]
    a = np.geomspace(*VARY["delta_n"], 12)
    b = np.geomspace(*VARY["delta_b"], 12)
    grid = np.stack(np.meshgrid(a, b, indexing="ij"), axis=-1).reshape(-1, 3, 2)
    values = np.concatenate([stable_range(rows) for rows in grid])
    assert np.all(np.isfinite(values))
    assert best >= values.max() - 1e-9
    assert design.optimum.converged
    assert design.rescan["agree"] and design.rescan["scanned"] == pytest.approx(best, abs=1e-8)
    np.testing.assert_allclose(design.optimum.x, [1.0, 400.0])      # the corner: the most damping of both
    assert design.as_dict()["objective"]["after"] == pytest.approx(best)
    speeds, before, after = design.margins(np.linspace(0.6, 1.4, 9))
    assert np.all(np.sign(after) == np.where(speeds > RANGE[1] - best, -1, 1))
    assert np.all(np.sign(before) == np.where(speeds > problem.settings["thresholds"][0], -1, 1))


def test_a_robust_design_sees_the_mean_less_k_sd_of_each_scattered_rotor():
    """Robust design on a preset (`--scatter chi=lognormal(0.02,0.002) --robust 1.5`,
    4 samples): the objective the search sees at (delta_n, delta_b) = (0.05, 5) is
    the mean less 1.5 sample standard deviations of the stable range of the 4
    scattered rotors, each found afresh (a scan of 60 speeds, then scipy's `brentq`),
    independent of the followed thresholds. A scatter wide
    enough that one sample has no balanced regime is refused (exit 3 at the CLI)."""
    from rotorjax._errors import NumericalError
    from rotorjax.uncertainty import draw

    # a wider scatter: at chi = 0.0151 (its second sample) the balls cannot balance eps (n chi rho < eps), so
    # that rotor has no balanced regime and no stable range: refused, not averaged
    with pytest.raises(InputError, match="no balanced regime"):
        stability_margin(PRESET.build(dict(PARAMS, chi=0.0151)).reference)
    with pytest.raises(NumericalError, match=r"stable-range not finite .* the 4 samples of --scatter: not finite in "
                                             r"at least one of them: .*give a narrower --scatter"):
        preset_problem(PRESET, PARAMS, VARY, speed_range=RANGE, n_scan=24, scatter={"chi": LogNormal(0.02, 0.004)},
                       robust_k=1.5, robust_samples=4, seed=5)
    scatter = {"chi": LogNormal(0.02, 0.002)}
    robust = preset_problem(PRESET, PARAMS, VARY, speed_range=RANGE, n_scan=24, scatter=scatter, robust_k=1.5,
                            robust_samples=4, seed=5)
    assert robust.robust == {"k": 1.5, "samples": 4, "seed": 5, "scatter": {"chi": "lognormal(0.02, 0.002)"}}
    chi = draw(scatter, 4, seed=5)[:, 0]
    assert np.ptp(chi) > 0.002          # the samples differ enough for the sd to matter

    from scipy.optimize import brentq

    margin = jax.jit(lambda c, nu: stability_margin(PRESET.build(dict(PARAMS, delta_n=0.05, delta_b=5.0, chi=c,
                                                                      nu=nu)).reference))
    scan = jax.jit(jax.vmap(margin, in_axes=(None, 0)))
    speeds = np.linspace(0.25, 7.375, 60)

    def fresh_range(c):
        m = np.asarray(scan(c, speeds))
        change = np.flatnonzero(np.sign(m[1:]) != np.sign(m[:-1]))
        assert len(change) == 1 and m[0] > 0 > m[-1]     # one threshold, stable above it
        i = change[0]
        return RANGE[1] - brentq(lambda nu: float(margin(c, nu)), speeds[i], speeds[i + 1], xtol=1e-13)

    ranges = np.array([fresh_range(c) for c in chi])
    q = jax.jit(robust.quantities)(np.array([0.05, 5.0]))
    assert float(q["stable-range"]) == pytest.approx(ranges.mean(), abs=1e-9)
    assert float(q["stable-range sd"]) == pytest.approx(ranges.std(ddof=1), rel=1e-6)
    seen = robust.value(q, "stable-range", -1)
    assert float(seen) == pytest.approx(ranges.mean() - 1.5 * ranges.std(ddof=1), abs=1e-9)


INPUTS = {"delta_n": LogNormal(0.18, 0.02), "delta_b": LogNormal(40.0, 4.0)}


@pytest.fixture(scope="module")
def quantities():
    return preset_quantities(PRESET, PARAMS, INPUTS, RANGE, n_scan=24)


def test_the_monte_carlo_of_the_threshold_against_first_order(quantities):
    """The threshold and the stable range under lognormal damping scatter: the sample
    mean and sd against the first-order moments (small scatter: they agree to a few
    standard errors), and the stable range is the range's top less the threshold."""
    q = quantities
    assert q.outputs == ("stable-range", "threshold_0")
    res = propagate(q.fn, INPUTS, samples=256, seed=3, names=q.outputs, chunk_size=16, reverse=True)
    assert res.n == 256
    np.testing.assert_allclose(res.samples[:, 0], RANGE[1] - res.samples[:, 1], atol=1e-12)
    assert abs(res.mean[1] - res.fosm_mean[1]) < 4 * res.sem[1] + 1e-9
    assert res.std[1] == pytest.approx(res.fosm_std[1], rel=0.15)


def test_the_commands_present_the_design_and_the_distributions(problem, design, quantities, monkeypatch, capsys,
                                                               tmp_path):
    """`optimize` and `uncertainty` on the preset: docs/design.md's `optimize` command as
    written, its problem and search the ones above (the command's arguments checked
    against theirs, so that nothing compiles again): the optimum as --set values, the
    rescan, the plot; the thresholds' statistics."""
    import json
    import shlex

    import rotorjax.design
    import rotorjax.uncertainty
    from rotorjax.cli import main

    from ..helpers import documentation

    def same_problem(preset, params, vary, objective, constraints, **kw):
        assert (preset.name, params, vary, objective, constraints) == (PRESET.name, PARAMS, VARY, "stable-range", [])
        assert list(kw["speed_range"]) == list(RANGE) and kw["n_scan"] == PROBLEM_ARGS["n_scan"]
        assert kw["scatter"] is None and kw["sense"] is None
        return problem

    def same_search(p, **kw):
        assert p is problem and {k: kw[k] for k in SEARCH_ARGS} == SEARCH_ARGS
        return design

    monkeypatch.setattr(rotorjax.design, "preset_problem", same_problem)
    monkeypatch.setattr(rotorjax.design, "optimize_rotor", same_search)
    monkeypatch.setattr(rotorjax.uncertainty, "preset_quantities", lambda *a, **k: quantities)
    assert README_OPTIMIZE in documentation()
    common = ["--set", "rho1=1.2", "--range", "0.5", "6", "--out", str(tmp_path)]
    assert main(shlex.split(README_OPTIMIZE)[1:] + ["--out", str(tmp_path)]) == 0
    text = capsys.readouterr().out
    assert "maximise stable-range: 4.99773 -> 4.99" in text and "checked by a fresh scan" in text
    assert "--set rho1=1.2 --set delta_n=1 --set delta_b=400" in text
    out = json.loads((tmp_path / "optimize_elliptic-abb.json").read_text())
    assert out["set"] == {"rho1": 1.2, "delta_n": 1.0, "delta_b": 400.0} and out["rescan"]["agree"]
    assert (tmp_path / "optimize_elliptic-abb.png").exists()
    assert main(["uncertainty", "elliptic-abb", "--dist", "delta_n=lognormal(0.18,0.02)", "--dist",
                 "delta_b=lognormal(40,4)", "--samples", "64", "--json", *common]) == 0
    out = json.loads(capsys.readouterr().out)
    stats = out["outputs"]
    assert list(stats) == ["stable-range", "threshold_0"] and out["settings"]["thresholds"]
    assert stats["stable-range"]["mean"] == pytest.approx(RANGE[1] - stats["threshold_0"]["mean"], abs=1e-12)


@pytest.mark.parametrize("vary, match", [
    ({"n_balls": (1, 3)}, r"--vary n_balls: sets the model's structure"),
    ({"nu": (1, 2)}, r"--vary nu: the speed"),
    ({"zeta": (1, 2)}, r"--vary zeta: not a parameter of elliptic-abb"),
    ({"delta_n": (-1, 1)}, r"--vary delta_n=-1:1: must be >= 0"),
    ({"delta_n": (1, 0.5)}, r"--vary delta_n=1:0.5: the bounds need LO < HI"),
])
def test_bad_input(vary, match):
    with pytest.raises(InputError, match=match):
        preset_problem(PRESET, PARAMS, vary, speed_range=RANGE)
