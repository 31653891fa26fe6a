"""Model 002: influence coefficients, signals, balancing, ISO grades, identification."""

import jax
import jax.numpy as jnp
import numpy as np
import pytest

from rotorjax import identify as idf
from rotorjax.analysis import balancing_response
from rotorjax.identify._make_data import simulate_from
from rotorjax.models import ConstantSpeed
from rotorjax.presets import balancing_machine as bm
from tests.helpers import central_difference

P = dict(bm.PRESET.defaults)
MACHINE, PLANES, U = bm.build_machine(P), bm.planes(P), bm.unbalances(P)


def trial_runs(machine, w, trials=(1e-4, 1e-4j)):
    X0 = np.asarray(balancing_response(machine, w, PLANES, U))
    Xt = []
    for j, T in enumerate(trials):
        Uj = U.copy()
        Uj[j] += T
        Xt.append(np.asarray(balancing_response(machine, w, PLANES, Uj)))
    return X0, np.stack(Xt), np.asarray(trials)


@pytest.mark.parametrize("w", [60.0, 120.0, 210.0, 350.0])
def test_analytic_influence_coefficients_equal_trial_weight_estimates(w):
    K = np.asarray(MACHINE.influence_matrix(w, PLANES))
    # eq. (15) written out with the inverse of eq. (13)
    A, B, C = (np.asarray(a) for a in MACHINE.matrices())
    Linv = np.linalg.inv(C - w**2 * A + 1j * w * B)
    l = P["l"]
    np.testing.assert_allclose(K[:, 0], w**2 / l * Linv @ [l - PLANES[0], PLANES[0]], rtol=1e-12)
    np.testing.assert_allclose(idf.influence_from_trials(*trial_runs(MACHINE, w)), K, rtol=1e-10)


def test_influence_coefficients_from_simulated_signals():
    """The signal chain: time-domain runs (`BalancingScene` at constant speed, by
    `rotorjax.simulate`), tacho pulses, 1x phasors."""
    w, fs = 120.0, 4000.0
    t = np.arange(0.0, 1.0, 1 / fs)

    def run(Ur):
        x = simulate_from(idf.BalancingScene(MACHINE, PLANES, Ur, ConstantSpeed(w)), t, w)
        pulses = np.arange(0, 1.0, 2 * np.pi / w)
        return idf.phasors(t, x, pulses=pulses).X

    X0 = run(U)
    Xt = np.stack([run(U + np.array([1e-4, 0])), run(U + np.array([0, 1e-4j]))])
    K = idf.influence_from_trials(X0, Xt, np.array([1e-4, 1e-4j]))
    np.testing.assert_allclose(K, np.asarray(MACHINE.influence_matrix(w, PLANES)), rtol=1e-7)


def test_symmetric_case_only_gives_equal_coefficients():
    sym = bm.build_machine(dict(P, k2=P["k1"], c2=P["c1"]))
    planes = np.array([0.15, P["l"] - 0.15])                      # A = C
    K = np.asarray(sym.influence_matrix(150.0, planes))
    assert K[0, 0] == pytest.approx(K[1, 1], rel=1e-12) and K[0, 1] == pytest.approx(K[1, 0], rel=1e-12)
    K = np.asarray(MACHINE.influence_matrix(150.0, planes))        # k1 != k2
    assert abs(K[0, 0] / K[1, 1] - 1) > 1e-2


def test_one_correction_balances_noise_free_runs():
    w = 120.0
    K = idf.influence_from_trials(*trial_runs(MACHINE, w))
    X0 = np.asarray(balancing_response(MACHINE, w, PLANES, U))
    W = -idf.unbalance_from_vibration(K, X0)
    after = np.asarray(balancing_response(MACHINE, w, PLANES, U + W))
    assert np.max(np.abs(after)) < 1e-9 * np.max(np.abs(X0))


def test_vector_coefficients_need_fewer_runs_than_scalar_ones():
    """2 % sensor noise, tolerance from ISO G2.5 at the balancing speed; the paper:
    2 runs with vector coefficients, 5 with scalar ones."""
    w = 170.0
    tol = idf.permissible_unbalance(2.5, P["m"], w) / 2 * 1e-6   # kg m per plane
    vec = idf.simulate_balancing(MACHINE, PLANES, w, U, tol, method="vector", noise=0.02, seed=0)
    sca = idf.simulate_balancing(MACHINE, PLANES, w, U, tol, method="scalar", noise=0.02, seed=0)
    assert vec.balanced and vec.runs == 2
    assert sca.runs >= 4 and sca.runs > vec.runs


def test_goodman_least_squares_correction():
    """Two planes, three speeds, two sensors each: the weighted least-squares
    correction equals the normal equations' solution and zeroes the gradient."""
    speeds = [80.0, 150.0, 260.0]
    K = np.concatenate([np.asarray(MACHINE.influence_matrix(w, PLANES)) for w in speeds])
    rng = np.random.default_rng(0)
    X = K @ U + 1e-7 * (rng.normal(size=6) + 1j * rng.normal(size=6))
    q = np.array([1.0, 2.0, 1.0, 0.5, 1.0, 3.0])
    W = idf.least_squares_correction(K, X, q)
    Q = np.diag(q)
    normal = np.linalg.solve(K.conj().T @ Q @ K, -K.conj().T @ Q @ X)
    np.testing.assert_allclose(W, normal, rtol=1e-12)

    def cost(wr):
        r = jnp.asarray(X) + jnp.asarray(K) @ (wr[:2] + 1j * wr[2:])
        return jnp.sum(jnp.asarray(q) * jnp.abs(r) ** 2)
    g = jax.grad(cost)(jnp.concatenate([W.real, W.imag]))
    assert float(jnp.max(jnp.abs(g))) < 1e-12 * float(np.sum(q * np.abs(X) ** 2)) / float(np.max(np.abs(W)))


def test_iso_permissible_unbalance():
    assert idf.permissible_unbalance(6.3, 2.0, 10_000 * np.pi / 30) == pytest.approx(12.03, abs=5e-3)
    assert idf.grade_reached(10.0, 2.0, 10_000 * np.pi / 30) == 6.3
    with pytest.raises(ValueError, match="G must be > 0"):
        idf.permissible_unbalance(0.0, 2.0, 100.0)


def test_split_onto_holes():
    (ma, aa), (mb, ab) = idf.split_onto_holes(3.0 * np.exp(1j * 0.5), np.arange(8) * np.pi / 4)
    assert ma >= 0 and mb >= 0
    assert ma * np.exp(1j * aa) + mb * np.exp(1j * ab) == pytest.approx(3.0 * np.exp(1j * 0.5), rel=1e-12)


def test_identification_intervals_cover_the_truth():
    """1 % noise (of the peak), 60 speeds: the 95 % intervals hold k1, k2, c1, c2 in
    at least 90 of 100 seeded trials."""
    w = np.linspace(30.0, 400.0, 60)
    Xs = np.asarray(jax.vmap(lambda ww: balancing_response(MACHINE, ww, PLANES, U))(w))
    s = 0.01 * np.abs(Xs).max()
    start = bm.build_machine(dict(P, k1=1.5e5, k2=2.5e5, c1=100.0, c2=300.0))
    covered = {k: 0 for k in ("k1", "k2", "c1", "c2")}
    for seed in range(100):
        rng = np.random.default_rng(seed)
        Xn = Xs + s * (rng.normal(size=Xs.shape) + 1j * rng.normal(size=Xs.shape)) / np.sqrt(2)
        res = idf.identify(idf.BalancingScene(start, PLANES, U), (w, Xn))
        assert res.converged
        for k in covered:
            lo, hi = res.intervals[k]
            covered[k] += lo <= P[k] <= hi
    assert all(v >= 90 for v in covered.values()), covered


def test_identification_gradient_matches_finite_differences():
    w = np.linspace(30.0, 400.0, 40)
    Xs = np.asarray(jax.vmap(lambda ww: balancing_response(MACHINE, ww, PLANES, U))(w))
    r = idf.residual_fn(MACHINE, ("k1", "k2", "c1", "c2"), w, PLANES, Xs * 1.01, 1e-7, U)
    theta = jnp.log(jnp.array([1.8e5, 3.2e5, 140.0, 210.0]))
    g = np.asarray(jax.grad(lambda th: jnp.sum(r(th) ** 2))(theta))
    for i in range(4):
        fd = central_difference(lambda v: float(jnp.sum(r(theta.at[i].set(v)) ** 2)), float(theta[i]), 1e-5)
        assert g[i] == pytest.approx(fd, rel=1e-6)


def test_one_identify_for_every_scene():
    """`identify` is one entry with one result type: the machine from (speeds, X)
    and a rotor file from its phasors give an `Identification` alike (its JSON keys
    those of both former results); the machine's global stage (vmapped LM over a
    Latin hypercube) finds the local fit's optimum; the unbalances fitted on the
    machine come back with their planes and intervals."""
    from rotorjax.io import shipped_rotor

    w = np.linspace(30.0, 400.0, 40)
    Xs = np.asarray(jax.vmap(lambda ww: balancing_response(MACHINE, ww, PLANES, U))(w))
    rng = np.random.default_rng(2)
    Xn = Xs + 0.01 * np.abs(Xs).max() * (rng.normal(size=Xs.shape) + 1j * rng.normal(size=Xs.shape)) / np.sqrt(2)
    start = idf.BalancingScene(bm.build_machine(dict(P, k1=1.5e5, k2=2.5e5, c1=100.0, c2=300.0)), PLANES, U)
    local = idf.identify(start, (w, Xn), fit_unbalance=True)
    multi = idf.identify(start, (w, Xn), fit_unbalance=True, n_starts=6, spread=3.0)
    assert type(local) is idf.Identification and local.converged and multi.converged
    for k in ("k1", "k2", "c1", "c2"):
        assert multi.estimates[k] == pytest.approx(local.estimates[k], rel=1e-6)
    assert multi.n_starts == 6 and local.n_starts == 1
    table = local.unbalance_table
    assert [t["plane"] for t in table] == [float(a) for a in PLANES]
    for t, u in zip(table, U):
        assert t["magnitude_ci95"][0] <= t["magnitude"] <= t["magnitude_ci95"][1]
        assert abs(t["magnitude"] / abs(u) - 1) < 0.05
    rotor = idf.identify(str(shipped_rotor("flexible_rig")), "flexible-runup", ["bearing0.kxx"],
                         fit_unbalance=(2, 4), n_starts=1, critical_speeds=False)
    assert type(rotor) is idf.Identification
    keys = set(local.as_dict())
    assert keys == set(rotor.as_dict()) | {"residual_structure"}
    assert {"estimates", "intervals_95", "ci95", "rms_residual", "residual_rms", "unbalances", "correlation",
            "critical_speeds", "minima", "n_starts", "covariance_method"} <= keys
    assert [t["node"] for t in rotor.unbalance_table] == [2, 4]


def test_unidentifiable_parameter_is_flagged():
    """Above the resonances the response is mass-controlled: stiffness is invisible."""
    w = np.linspace(5000.0, 6000.0, 30)
    Xs = np.asarray(jax.vmap(lambda ww: balancing_response(MACHINE, ww, PLANES, U))(w))
    rng = np.random.default_rng(0)
    Xn = Xs + 0.01 * np.abs(Xs).max() * (rng.normal(size=Xs.shape) + 1j * rng.normal(size=Xs.shape))
    res = idf.identify(idf.BalancingScene(MACHINE, PLANES, U), (w, Xn), ("k1", "c1"))
    assert any("k1" in m or "rank" in m for m in res.warnings)


def test_shipped_dataset_round_trip():
    runs = idf.runs_from_signals(idf.read_signals(idf.BALANCING_RUNS))
    assert [r["trial"] is None for r in runs] == [True, False, False]
    X0 = runs[0]["X"]
    K = idf.influence_from_trials(X0, np.stack([r["X"] for r in runs[1:]]), np.array([r["trial"][1] for r in runs[1:]]))
    D = idf.unbalance_from_vibration(K, X0)
    np.testing.assert_allclose(D, U, rtol=0.02)   # 1 % sensor noise in the file


def test_machine_runs_go_through_the_one_engine():
    """Model 002's runs balanced by the engine every scene uses (`balance`): the
    corrections equal eq. 23's `-K^-1 X0` from the same runs (least squares and
    min-max alike: two sensors, two planes); the influence matrix from the model
    (the preset's machine) agrees with the trials' within the file's 1 % noise; the
    residual unbalance is the corrections' uncertainty from the baseline's noise."""
    data = idf.balancing_runs(idf.BALANCING_RUNS)
    K = idf.influence_from_trials(data.X0, data.X_trials, data.trial_unbalances)
    W = -np.linalg.solve(K, data.X0)
    scene = idf.BalancingScene(MACHINE, PLANES, U)
    ls = idf.balance(data, radius=0.01, holes=12)
    mm = idf.balance(data, method="minmax")
    both = idf.balance(data, influence="both", scene=scene)
    model = idf.balance(data, influence="model", scene=scene)
    np.testing.assert_allclose(ls.A, K, rtol=1e-12)
    np.testing.assert_allclose(ls.W, W, rtol=1e-10)
    np.testing.assert_allclose(mm.W, W, rtol=1e-6)
    assert both.warnings == () and np.max(both.influence_difference) < 0.03
    np.testing.assert_allclose(model.W, -U, rtol=0.02)        # the model's influence, the measured vibration
    assert ls.plane_key == "plane" and ls.sensor_names == ("x1", "x2") and ls.rotor_mass is None
    assert 0 < ls.noise_gmm and abs(ls.residual_gmm - ls.noise_gmm) < 1e-9 * ls.noise_gmm
    assert both.rotor_mass == MACHINE.m and both.grade_reached is not None
    c = ls.correction_table()
    assert [len(x["holes"]) for x in c] == [2, 2]
    np.testing.assert_allclose([x["mass_g"] for x in c], np.abs(W) / 0.01 * 1e3, rtol=1e-10)


def _write_csv(path, cols):
    names = list(cols)
    np.savetxt(path, np.stack([cols[k] for k in names], 1), delimiter=",", header=",".join(names), comments="")


@pytest.mark.parametrize("mutate,match", [
    (lambda c: c.pop("tacho"), "missing column.*tacho"),
    (lambda c: c["time"].__setitem__(5, c["time"][3]), "time is not strictly increasing"),
    (lambda c: c["x1"].__setitem__(7, np.nan), "'x1' has NaN"),
    (lambda c: c["tacho"].__setitem__(slice(None), 0.0), "tacho channel is constant"),
])
def test_malformed_files_get_clear_errors(tmp_path, mutate, match):
    t = np.arange(0, 0.5, 1e-3)
    cols = {"time": t.copy(), "tacho": (np.mod(t * 20, 1) < 0.01).astype(float),
            "x1": np.cos(2 * np.pi * 20 * t), "x2": np.sin(2 * np.pi * 20 * t)}
    mutate(cols)
    path = str(tmp_path / "bad.csv")
    _write_csv(path, cols)
    with pytest.raises(ValueError, match=match):
        idf.runs_from_signals(idf.read_signals(path))
    with pytest.raises(ValueError, match="no such file"):
        idf.read_signals(str(tmp_path / "missing.csv"))
