"""Balancing flexible FE rotors from 1x phasors (the one engine, rotorjax.identify._balance)."""

import json

import numpy as np
import pytest

import rotorjax  # noqa: F401  (x64)
from rotorjax._errors import InputError
from rotorjax.flexible import FlexibleRotor, unbalance_response_many
from rotorjax.identify import (balance, influence_from_phasor_runs, least_squares_balance, minmax_balance,
                               model_influence)
from rotorjax.identify._iso import total_mass
from rotorjax.identify._phasor_file import make_phasors

SPEEDS = np.array([60.0, 96.0, 200.0, 400.0])   # below, near, between and above the first two criticals
SENSORS = (2, 4)
UNBALANCES = [(2, 2e-3, 0.7), (4, 1.5e-3, 2.9)]
TRIALS = {1: (2, 2e-3, 0.0), 2: (4, 2e-3, 1.0)}


def make_rotor(kfac=1.0):
    """ROSS's example rotor with damped bearings (critical speeds ~96, 302, 855 rad/s)."""
    return FlexibleRotor([0.25] * 6, 0.05, disks=((2, 32.59, 0.178, 0.3296), (4, 32.59, 0.178, 0.3296)),
                         bearings=((0, 1e6 * kfac, 0.8e6 * kfac, 800.0, 800.0),
                                   (6, 1e6 * kfac, 0.8e6 * kfac, 800.0, 800.0)))


ROTOR = make_rotor()


def respond(unbalances, speeds=SPEEDS, rotor=ROTOR):
    """Rows (speed, node, direction, X) sorted as the balancing orders them."""
    X, Y = unbalance_response_many(rotor, unbalances, speeds, list(SENSORS))
    X, Y = np.asarray(X), np.asarray(Y)
    rows = []
    for k, s in enumerate(speeds):
        for j, n in enumerate(SENSORS):
            rows += [(s, n, "x", X[k, j]), (s, n, "y", Y[k, j])]
    return rows


def trial_data(unbalances=UNBALANCES, noise=0.0, seed=0, trials=TRIALS, drop=None, speeds=SPEEDS):
    rng = np.random.default_rng(seed)
    cols = {"speed": [], "node": [], "direction": [], "X": [], "run": []}
    runs = {0: list(unbalances)}
    runs.update({r: list(unbalances) + [t] for r, t in trials.items()})
    for r, ub in runs.items():
        for s, n, d, x in respond(ub, speeds):
            if drop is not None and drop == (r, s, n, d):
                continue
            x = x + noise * abs(x) * (rng.normal() + 1j * rng.normal()) / np.sqrt(2)
            for k, v in zip(cols, (s, n, d, x, r)):
                cols[k].append(v)
    return make_phasors(cols["speed"], cols["node"], cols["direction"], np.array(cols["X"]), run=cols["run"],
                        trial=dict(trials), path="trials.csv")


def true_W():
    return np.array([-m * np.exp(1j * p) for _, m, p in UNBALANCES])


@pytest.fixture(scope="module")
def clean():
    return trial_data()


def test_influence_from_runs_matches_model(clean):
    sp, sensors, X0, A = influence_from_phasor_runs(clean, [2, 4])
    assert X0.shape == (16,) and A.shape == (16, 2) and len(sensors) == 16
    assert list(sp[:4]) == [60.0] * 4 and sensors[:4] == ((2, "x"), (2, "y"), (4, "x"), (4, "y"))
    A_model = model_influence(ROTOR, sp, sensors, [2, 4])
    np.testing.assert_allclose(A, A_model, rtol=1e-7, atol=1e-9 * np.max(np.abs(A)))
    # a subset of speeds
    sp2, _, X02, A2 = influence_from_phasor_runs(clean, [2, 4], speeds=[400.0, 96.0])
    assert sorted(set(sp2)) == [96.0, 400.0] and A2.shape == (8, 2)


@pytest.mark.parametrize("method", ["ls", "minmax"])
def test_two_planes_cancel_the_unbalances(clean, method):
    res = balance(clean, [2, 4], method=method, scene=ROTOR)
    np.testing.assert_allclose(res.W, true_W(), rtol=0.03, atol=0.03 * np.max(np.abs(true_W())))
    assert res.after_max < 1e-6 * res.before_max
    # the predicted residual is what the machine does with the corrections added
    corr = [(n, m, p) for n, m, p in res.corrections]
    sim = np.array([x for *_, x in respond(UNBALANCES + corr)])
    np.testing.assert_allclose(res.predicted, sim, rtol=0, atol=1e-9 * np.max(np.abs(res.X0)))
    assert not res.warnings


def test_predicted_residual_equals_simulation_with_a_third_unbalance():
    ub = UNBALANCES + [(3, 1e-3, 4.0)]     # not at a plane: cannot be cancelled exactly
    data = trial_data(ub)
    for method in ("ls", "minmax"):
        res = balance(data, [2, 4], method=method)
        sim = np.array([x for *_, x in respond(ub + list(res.corrections))])
        np.testing.assert_allclose(res.predicted, sim, rtol=0, atol=1e-9 * np.max(np.abs(res.X0)))
        assert res.after_max < res.before_max


def test_minmax_is_optimal():
    from scipy.optimize import minimize

    data = trial_data(UNBALANCES + [(3, 1e-3, 4.0)], noise=0.01)
    _, _, X0, A = influence_from_phasor_runs(data, [2, 4])
    W, t = minmax_balance(A, X0)
    assert t == pytest.approx(np.max(np.abs(X0 + A @ W)), rel=1e-12)
    W_ls = least_squares_balance(A, X0)
    assert t <= np.max(np.abs(X0 + A @ W_ls)) * (1 + 1e-9)
    # an independent solve: SLSQP on the epigraph (scaled W, t)
    sx, sw = np.max(np.abs(X0)), np.max(np.abs(W_ls))

    def res(z):
        Wz = (z[0:2] + 1j * z[2:4]) * sw
        return np.abs(X0 + A @ Wz) / sx

    z0 = np.concatenate([W_ls.real, W_ls.imag]) / sw
    z0 = np.append(z0, np.max(res(z0)))
    opt = minimize(lambda z: z[4], z0, method="SLSQP", options={"ftol": 1e-12, "maxiter": 500},
                   constraints=[{"type": "ineq", "fun": lambda z: z[4] - res(z)}])
    assert np.max(res(opt.x)) <= opt.x[4] + 1e-9          # feasible
    assert t / sx <= np.max(res(opt.x)) * (1 + 1e-9)      # Clarabel's is no worse
    assert t / sx == pytest.approx(np.max(res(opt.x)), rel=1e-5)
    # no perturbation of W lowers the worst residual
    rng = np.random.default_rng(1)
    for scale in (1e-2, 1e-4, 1e-6):
        for _ in range(200):
            dW = scale * np.max(np.abs(W)) * (rng.normal(size=2) + 1j * rng.normal(size=2))
            assert np.max(np.abs(X0 + A @ (W + dW))) >= t * (1 - 1e-8)


def test_weighted_balancing():
    data = trial_data(UNBALANCES + [(3, 1e-3, 4.0)])
    _, _, X0, A = influence_from_phasor_runs(data, [2, 4])
    w = np.ones(X0.size)
    w[:4] = 100.0   # the lowest speed matters most
    for method in ("ls", "minmax"):
        plain = balance(data, [2, 4], method=method)
        weighted = balance(data, [2, 4], method=method, weights=w)
        assert np.max(np.abs(weighted.predicted[:4])) < np.max(np.abs(plain.predicted[:4]))
    W, t = minmax_balance(A, X0, w)
    assert t == pytest.approx(np.max(w * np.abs(X0 + A @ W)), rel=1e-12)


@pytest.mark.parametrize("method,tol", [("ls", 0.05), ("minmax", 0.25)])
def test_noise_one_percent(method, tol):
    """1 % noise on every phasor: the machine's true vibration after the corrections is
    within a few % of the before. Least squares also finds the unbalances to a few %;
    min-max follows the noise of the worst point (1 % of the resonance peak), so its
    corrections move more while leaving as little vibration."""
    res = balance(trial_data(noise=0.01, seed=3), [2, 4], method=method)
    np.testing.assert_allclose(res.W, true_W(), rtol=0, atol=tol * np.max(np.abs(true_W())))
    after = np.array([x for *_, x in respond(UNBALANCES + list(res.corrections))])
    assert np.max(np.abs(after)) < 0.04 * res.before_max
    assert res.after_max < 0.04 * res.before_max


def test_model_influence_alone_and_both(clean):
    res = balance(clean, [2, 4], influence="model", scene=ROTOR)
    np.testing.assert_allclose(res.W, true_W(), rtol=1e-6)
    base_only = trial_data(trials={})
    res2 = balance(base_only, [2, 4], influence="model", scene=ROTOR, method="minmax")
    np.testing.assert_allclose(res2.W, true_W(), rtol=1e-5)
    both = balance(clean, [2, 4], influence="both", scene=ROTOR)
    assert not both.warnings and np.max(both.influence_difference) < 1e-6
    wrong = balance(clean, [2, 4], influence="both", scene=make_rotor(3.0))
    assert wrong.warnings and "differ from the trial runs'" in wrong.warnings[0]
    assert np.max(wrong.influence_difference) > 0.2
    np.testing.assert_allclose(wrong.W, true_W(), rtol=1e-6)   # the trials' coefficients are used


def test_iso_report_and_json(clean):
    res = balance(trial_data(noise=0.01, seed=5), [2, 4], scene=ROTOR, service_speed=400.0)
    m = total_mass(ROTOR)
    shaft = 7810.0 * np.pi / 4 * 0.05**2 * 1.5
    assert m == pytest.approx(shaft + 2 * 32.59, rel=1e-12)
    assert res.rotor_mass == pytest.approx(m)
    assert len(res.criticals) == 2 and res.criticals[0] == pytest.approx(96.35, rel=1e-3)
    assert res.permissible_gmm == pytest.approx(1000 * 2.5 * m / 400.0)
    assert res.grade_reached is not None and res.grade_before is not None
    assert res.grade_reached <= res.grade_before and res.residual_gmm < res.initial_gmm
    text = " ".join(res.explanation)
    assert "2 forward critical speed(s)" in text and "N+2-plane method 4" in text
    assert "2 too few for the N+2-plane method" in text
    d = json.loads(json.dumps(res.as_dict()))
    assert set(d) >= {"corrections", "residual", "method", "influence", "iso", "warnings"}
    assert [c["node"] for c in d["corrections"]] == [2, 4]
    assert d["corrections"][0]["magnitude"] == pytest.approx(abs(res.W[0]))
    assert set(d["residual"]) == {"before_max", "after_max", "before_rms", "after_rms", "per_point"}
    assert len(d["residual"]["per_point"]) == 16
    assert set(d["residual"]["per_point"][0]) == {"speed", "node", "direction", "before", "after"}
    assert d["iso"]["n_criticals"] == 2 and d["iso"]["planes_needed_n_plus_2"] == 4
    # no rotor: no mass, no criticals, a sentence says so
    bare = balance(clean, [2, 4])
    assert bare.rotor_mass is None and bare.criticals is None and bare.grade_reached is None
    assert any("No rotor model" in t for t in bare.explanation)
    given = balance(clean, [2, 4], rotor_mass=80.0, grade=6.3)
    assert given.permissible_gmm == pytest.approx(1000 * 6.3 * 80.0 / 400.0)


def test_plot(tmp_path, clean):
    from rotorjax.plot import plot_fe_balance

    res = balance(trial_data(UNBALANCES + [(3, 1e-3, 4.0)]), [2, 4])
    from rotorjax.cli._common import save_figure

    fig = plot_fe_balance(result=res, title="test")
    assert fig.axes[0].get_title().startswith("test")
    path = save_figure(fig, str(tmp_path / "b.png"))
    assert (tmp_path / "b.png").stat().st_size > 1000 and path.endswith("b.png")


def _dup_trial():
    t = dict(TRIALS)
    t[3] = (2, 1e-3, 0.5)
    return trial_data(trials=t)


BAD = [
    ("plane not a node", lambda: balance(trial_data(), [2, 9], scene=ROTOR),
     "planes: node 9 is not a node of the rotor (nodes 0..6)"),
    ("no baseline", lambda: balance(trial_data(trials={0: (2, 1e-3, 0.0), **TRIALS}), [2, 4]),
     "trials.csv: no baseline run"),
    ("plane without trial", lambda: balance(trial_data(), [2, 3]), "plane 3 has no trial run"),
    ("duplicate trial", lambda: balance(_dup_trial(), [2, 4]), "plane 2 has 2 trial runs (1, 3)"),
    ("missing measurement", lambda: balance(trial_data(drop=(2, 200.0, 4, "y")), [2, 4]),
     "run 2 (trial weight at node 4) has no measurement at speed 200 rad/s, node 4, direction y"),
    ("underdetermined", lambda: balance(trial_data(speeds=np.array([96.0]), trials={
        1: (2, 1e-3, 0.0), 2: (4, 1e-3, 0.0), 3: (3, 1e-3, 0.0), 4: (1, 1e-3, 0.0), 5: (5, 1e-3, 0.0)}),
        [1, 2, 3, 4, 5]), "4 measurement(s) at the chosen speeds cannot determine 5 plane corrections"),
    ("weights not positive", lambda: balance(trial_data(), [2, 4], weights=[1.0] * 15 + [0.0]),
     "weights must be finite and > 0; weight 15"),
    ("weights wrong length", lambda: least_squares_balance(np.ones((3, 2)), np.ones(3), [1.0, 2.0]),
     "weights must be one number per measurement (3)"),
    ("unknown speed", lambda: balance(trial_data(), [2, 4], speeds=[96.0, 150.0]),
     "speeds: 150 rad/s is not a speed of the baseline run of trials.csv"),
    ("model without rotor", lambda: balance(trial_data(), [2, 4], influence="model"),
     "influence='model' needs the scene's model"),
    ("bad method", lambda: balance(trial_data(), [2, 4], method="l2"), "method must be one of"),
    ("bad influence", lambda: balance(trial_data(), [2, 4], influence="x"), "influence must be one of"),
    ("repeated plane", lambda: balance(trial_data(), [2, 2]), "planes: node 2 is given twice"),
    ("negative grade", lambda: balance(trial_data(), [2, 4], grade=-1.0), "grade"),
    ("frf data", lambda: balance(make_phasors([0.0], [2], ["x"], [1e-7 + 0j], frequency=[50.0],
                                                    input_node=[2], input_direction=["x"], path="impact.csv"),
                                       [2]), "impact.csv: an impact-test (FRF) file"),
    ("ls underdetermined", lambda: least_squares_balance(np.ones((1, 2)), np.ones(1)),
     "1 measurement(s) cannot determine 2 plane corrections"),
]


@pytest.mark.parametrize("name,call,message", BAD, ids=[b[0] for b in BAD])
def test_bad_input(name, call, message):
    with pytest.raises(InputError) as e:
        call()
    assert message in str(e.value)
