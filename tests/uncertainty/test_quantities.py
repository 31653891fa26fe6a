"""`uncertainty`'s design quantities (`rotor_quantities(..., quantities=)`, `--output`)
on ROSS's example rotor (`ross_compare.toml`, 500 N s/m bearing damping `cxx`, its
unbalance), each sample against the rotor file read again with the sample's values
`--set`: the largest unbalance response at a probe against the largest on a dense
grid of speeds, the separation margin against API 684's formula at the critical
speeds and amplification factors found by scanning, the mass against the rotor's;
and the first-order moments against Monte Carlo."""

import json

import numpy as np
import pytest

from rotorjax.analysis import (amplification_factor, critical_speeds_1x, damped_eigenvalues,
                               required_separation_margin, scene_unbalance_response)
from rotorjax.io import read_rotor_file, shipped_rotor
from rotorjax.uncertainty import LogNormal, draw, propagate, rotor_quantities

PATH = str(shipped_rotor("ross_compare"))
SETS = {"bearing0.cxx": 500.0, "bearing1.cxx": 500.0}
INPUTS = {"bearing0.kxx": LogNormal(1e6, 1e5), "disk0.m": LogNormal(32.6, 1.0)}
OPERATING = (400.0, 600.0)


@pytest.fixture(scope="module")
def sampled():
    q = rotor_quantities(PATH, INPUTS, lo=0.0, hi=600.0, n_modes=0, overrides=SETS,
                         quantities=("response", "separation-margin", "mass"), operating=OPERATING, probes=(2,))
    # chunks of 16: the 64 samples in one vmapped program hung XLA's CPU runtime in 3 runs of 4 (every thread
    # idle; the deadlock `rotorjax._config` describes, here with its scheduler option off); 16 at a time ran
    return q, propagate(q.fn, INPUTS, samples=64, seed=1, names=q.outputs, chunk_size=16)


def _independent(values):
    """The three quantities of the file read again with `values` (the reader, the
    analyses' own solvers): the largest amplitude at node 2 on 20 001 speeds, API
    684's least slack over the forward 1x critical speeds below 1200 rad/s, the mass."""
    scene = read_rotor_file(PATH, {**SETS, **dict(zip(INPUTS, values))}).scene
    speeds = np.linspace(0.6, 600.0, 20_001)
    full = np.asarray(scene.expand(scene_unbalance_response(scene, speeds).T))
    response = float(np.max(np.hypot(np.abs(full[8]), np.abs(full[9]))))
    slacks = []
    for w, k in critical_speeds_1x(scene, 0.0, 2 * OPERATING[1], whirl="forward", xtol=1e-12):
        af = float(amplification_factor(damped_eigenvalues(scene, w, k + 1)[k]))
        below = w <= 0.5 * sum(OPERATING)    # nearer the range's bottom (a speed inside: negative)
        margin = 100 * ((OPERATING[0] - w) / OPERATING[0] if below else (w - OPERATING[1]) / OPERATING[1])
        slacks.append(margin - float(required_separation_margin(af, below)))
    return response, min(slacks), float(scene.full_rotor.mass())


def test_each_sample_equals_the_file_read_again(sampled):
    """The response is the peak between grid speeds (within the dense grid's own
    spacing, 2e-4, and not below its largest value but for the parabola's error,
    1e-5); the separation margin is within the soft
    minimum's 0.05 percent of the least slack; the mass is the rotor's."""
    q, r = sampled
    assert q.outputs == ("critical_speed_0", "critical_speed_1", "response", "separation-margin", "mass")
    for i in (0, 5, 63):
        response, slack, mass = _independent(r.input_samples[i])
        assert r.samples[i, 2] == pytest.approx(response, rel=2e-4) and r.samples[i, 2] >= response * (1 - 1e-5)
        assert slack - 0.05 <= r.samples[i, 3] <= slack + 1e-9
        assert r.samples[i, 4] == pytest.approx(mass, rel=1e-12)


def test_first_order_moments_agree_with_monte_carlo(sampled):
    """The response's peak is smooth in the parameters (no wobble as the resonance
    slides across the grid, which made its gradient, and so its first-order standard
    deviation, 6 times the sampled one): first-order mean and standard deviation
    within 4 standard errors and 30 % of Monte Carlo's, for every output."""
    _, r = sampled
    assert r.n == 64
    assert np.all(np.abs(r.mean - r.fosm_mean) < 4 * r.sem + 1e-12 * np.abs(r.mean))
    assert np.all(np.abs(r.std / r.fosm_std - 1) < 0.3)


def test_the_command_reports_the_quantities_and_the_margin_shortfall(tmp_path, capsys):
    """`rotorjax uncertainty --output ...`: the JSON's means equal the means of the
    independent quantities of the same samples, and the probability that the margin
    falls short is the fraction of them below API 684's requirement."""
    from rotorjax.cli import main

    sets = [a for k, v in SETS.items() for a in ("--set", f"{k}={v}")]
    dists = [a for t in ("bearing0.kxx=lognormal(1e6,1e5)", "disk0.m=lognormal(32.6,1)") for a in ("--dist", t)]
    assert main(["uncertainty", "ross_compare.toml", *sets, *dists, "--samples", "6", "--seed", "2", "--range", "0",
                 "600", "--modes", "0", "--output", "response", "--output", "separation-margin", "--operating",
                 "400", "600", "--probe", "2", "--json", "--out", str(tmp_path)]) == 0
    out = json.loads(capsys.readouterr().out)
    ref = np.array([_independent(v)[:2] for v in draw(INPUTS, 6, seed=2)])
    assert out["outputs"]["response"]["mean"] == pytest.approx(ref[:, 0].mean(), rel=2e-4)
    assert out["outputs"]["separation-margin"]["mean"] == pytest.approx(ref[:, 1].mean(), abs=0.05)
    short = out["probability_separation_short"]["separation-margin"]
    assert short["p"] == pytest.approx(np.mean(ref[:, 1] < 0))
    assert out["settings"]["operating"] == [400.0, 600.0] and out["settings"]["probes"] == [2]
