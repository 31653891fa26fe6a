"""Identification of a finite-element rotor file from phasors (issue 16): the model
against independent solves, the shipped flexible rig identified from starts 2-5x
off, interval coverage over noise replicates, identifiability warnings, receptance
(impact-test) data, gradients of the estimates against re-fits, bad input."""

import pathlib

import equinox as eqx
import jax
import jax.numpy as jnp
import numpy as np
import pytest

from rotorjax._errors import InputError
from rotorjax.flexible import critical_speeds_1x, frf, unbalance_response_many
from rotorjax.identify import estimates_jacobian, identify, make_phasors, read_phasors, rotor_model
from rotorjax.identify import _make_fe_data as rig
from rotorjax.identify._fe_identify import problem
from rotorjax.identify._lm import res_jac as _res_jac
from rotorjax.identify._lm import levenberg_marquardt
from rotorjax.io import load_rotor, shipped_rotor

from ..models.test_rotor_files import assert_identical

PATH = str(shipped_rotor("flexible_rig"))
TRUTH = rig.TRUTH
FIT = list(TRUTH)


def _phasors(rotor, speeds, sensors=rig.SENSORS, unbalances=rig.UNBALANCES, noise=0.0, seed=0, sigma=None):
    X = rig.clean_phasors(rotor, unbalances, speeds, sensors)
    if noise:
        e = np.random.default_rng(seed).standard_normal(X.shape + (2,))
        X = X + noise * np.abs(X) / np.sqrt(2) * (e[..., 0] + 1j * e[..., 1])
    n = len(speeds)
    return make_phasors(np.repeat(speeds, len(sensors)), np.tile([s[0] for s in sensors], n),
                        np.tile([s[1] for s in sensors], n), X.ravel(),
                        sigma=None if sigma is None else np.full(X.size, sigma))


def _starts(seed, n):
    rng = np.random.default_rng(seed)
    for _ in range(n):
        f = np.exp(rng.uniform(np.log(2), np.log(5), len(FIT))) ** rng.choice([-1, 1], len(FIT))
        yield {k: TRUTH[k] * fk for k, fk in zip(FIT, f)}


@pytest.fixture(scope="module")
def truth_rotor():
    return rig.true_rotor()


# --- the model: three ways -----------------------------------------------------------

def test_model_equals_unbalance_response(truth_rotor):
    """The fitted model's phasors at the truth equal `unbalance_response_many` (an
    independent assembly of the same solve), on every row."""
    data = _phasors(truth_rotor, rig.RUNUP_SPEEDS)
    res = identify(rotor_model(PATH, TRUTH), data, FIT, fit_unbalance=(2, 4), n_starts=1,
                         critical_speeds=False)
    assert np.max(np.abs(res.fitted - data.X)) < 1e-9 * np.max(np.abs(data.X))


@pytest.mark.parametrize("coupled", [True, False])
def test_jacobian_equals_autodiff(coupled):
    """The residual's Jacobian (receptance coupling, or direct solves with one LU per
    point) equals forward-mode autodiff through the plain solves."""
    _, _, r, center = problem(PATH, "flexible-runup", FIT, (2, 4), coupling=coupled)
    _, _, plain, _ = problem(PATH, "flexible-runup", FIT, (2, 4), coupling=False)
    for shift in (0.0, 1.1, -1.7):
        th = jnp.asarray(center + shift * np.linspace(-1, 1, len(FIT)))
        res, J = eqx.filter_jit(_res_jac)(r, th)
        ref = eqx.filter_jit(lambda m, t: (m(t), jax.jacfwd(m)(t)))(plain, th)
        assert float(jnp.max(jnp.abs(res - ref[0]))) < 1e-9 * float(jnp.max(jnp.abs(ref[0])))
        assert float(jnp.max(jnp.abs(J - ref[1]))) < 1e-9 * float(jnp.max(jnp.abs(ref[1])))


def test_coupling_exact_for_disks_and_supports(tmp_path):
    """The Woodbury coupling is exact for every kind of local parameter: a disk's mass
    and inertia, a pedestal's stiffness, a bearing's mass coefficient."""
    text = pathlib.Path(PATH).read_text() + """
[[support]]
bearing = 1
m = 20.0
kxx = 5e7
cxx = 2e3
"""
    f = tmp_path / "rig_support.toml"
    f.write_text(text)
    names = ["disk0.m", "disk1.Id", "support0.kxx", "support0.cxx", "bearing0.kxx"]
    _, _, r, center = problem(str(f), "flexible-runup", names, (2, 4))
    _, _, plain, _ = problem(str(f), "flexible-runup", names, (2, 4), coupling=False)
    assert r.coupling is not None
    th = jnp.asarray(center + 0.7)
    a, b = eqx.filter_jit(lambda m, t: m(t))(r, th), eqx.filter_jit(lambda m, t: m(t))(plain, th)
    assert float(jnp.max(jnp.abs(a - b))) < 1e-9 * float(jnp.max(jnp.abs(b)))


# --- the shipped flexible rig -----------------------------------------------------------

@pytest.fixture(scope="module")
def shipped_fits():
    """The shipped run-up (1 % noise) identified from three starts 2-5x off the truth."""
    data = read_phasors("flexible-runup")
    return [identify(rotor_model(PATH, s), data, FIT, fit_unbalance=(2, 4)) for s in _starts(16, 3)]


def test_shipped_runup_identified(shipped_fits, truth_rotor):
    for res in shipped_fits:
        assert res.converged and res.warnings == [], res.warnings
        for k in FIT:
            assert abs(res.estimates[k] / TRUTH[k] - 1) < 0.02, (k, res.estimates[k])
            lo, hi = res.intervals[k]
            z = np.log(res.estimates[k] / TRUTH[k]) / (res.std[k] / res.estimates[k])
            assert abs(z) < 3.0, (k, z)           # inside the 99.7 % interval
        covered = sum(res.intervals[k][0] <= TRUTH[k] <= res.intervals[k][1] for k in FIT)
        assert covered >= 6, covered              # 95 % each: 8 of 8 only two times in three
        for u, (node, mag, phase) in zip(res.unbalance_table, rig.UNBALANCES):
            assert u["node"] == node and abs(u["magnitude"] / mag - 1) < 0.02 and abs(u["phase"] - phase) < 0.02
    # every start finds the same optimum
    best = shipped_fits[0]
    for res in shipped_fits[1:]:
        assert all(abs(res.estimates[k] / best.estimates[k] - 1) < 1e-6 for k in FIT)
    # the fitted critical speeds' intervals hold the true machine's
    true = [w for w, _ in critical_speeds_1x(truth_rotor, 30.0, 460.0, whirl="forward")]
    assert len(best.critical_speeds) == len(true) == 2
    for c, w in zip(best.critical_speeds, true):
        assert c["ci95"][0] <= w <= c["ci95"][1], (c, w)


def test_local_fit_also_converges_with_projected_unbalances():
    """With the unbalances projected out (variable projection) one start 2-5x off
    reaches the same optimum as the global search (recorded: the global search is
    the safeguard, not the only reason it works)."""
    data = read_phasors("flexible-runup")
    start = next(_starts(5, 1))
    local = identify(rotor_model(PATH, start), data, FIT, fit_unbalance=(2, 4), n_starts=1,
                           critical_speeds=False)
    assert all(abs(local.estimates[k] / TRUTH[k] - 1) < 0.02 for k in FIT)


def test_known_unbalance(tmp_path, truth_rotor):
    """The unbalances given in the rotor file (known): the bearings alone fitted."""
    text = pathlib.Path(PATH).read_text() + "".join(
        f"\n[[unbalance]]\nnode = {n}\nmagnitude = {m!r}\nphase = {p!r}\n" for n, m, p in rig.UNBALANCES)
    f = tmp_path / "rig_unbalanced.toml"
    f.write_text(text)
    data = _phasors(truth_rotor, rig.RUNUP_SPEEDS, noise=0.01, seed=3)
    res = identify(rotor_model(str(f), next(_starts(7, 1))), data, FIT, n_starts=1, critical_speeds=False)
    assert all(abs(res.estimates[k] / TRUTH[k] - 1) < 0.02 for k in FIT), res.estimates
    assert res.unbalances is None and res.unbalance_table == []


def test_interval_coverage(truth_rotor):
    """The 95 % intervals cover the truth at the nominal rate: 40 noise replicates of
    the run-up (1 %), each fitted (bearings and unbalances)."""
    model = rotor_model(PATH, TRUTH)
    hits = np.zeros(len(FIT))
    n = 40
    for seed in range(n):
        data = _phasors(truth_rotor, rig.RUNUP_SPEEDS, noise=0.01, seed=100 + seed)
        res = identify(model, data, FIT, fit_unbalance=(2, 4), n_starts=1, critical_speeds=False)
        hits += [res.intervals[k][0] <= TRUTH[k] <= res.intervals[k][1] for k in FIT]
    rate = hits / n
    # binomial(40, 0.95): below 0.8 has probability < 1 %; the mean over 8 parameters is tighter
    assert np.all(rate >= 0.8), dict(zip(FIT, rate))
    assert 0.89 <= rate.mean() <= 1.0, rate.mean()


# --- identifiability -------------------------------------------------------------------

def test_not_identifiable_far_below_resonance(truth_rotor):
    """Far below the first critical speed the response is quasi-static, `U W^2 / k` at
    the bearings: with the unbalance unknown, its size and the bearing stiffness
    trade off, and the damping barely shows. The fit flags every coefficient."""
    data = _phasors(truth_rotor, np.linspace(2.0, 6.0, 20), noise=0.01, seed=1)
    res = identify(rotor_model(PATH, TRUTH), data, FIT, fit_unbalance=(2, 4), n_starts=1,
                         critical_speeds=False)
    flagged = [k for k in FIT if any(w.startswith(f"{k} is poorly determined") for w in res.warnings)]
    assert flagged == FIT, res.warnings


def test_gyroscopic_inertia_invisible_at_rest(truth_rotor):
    """An impact test at rest cannot see a disk's polar inertia (it acts through the
    spin only): the fit names it."""
    data = _receptances(truth_rotor, speed=0.0)
    res = identify(rotor_model(PATH, TRUTH), data, ["bearing0.kxx", "disk0.Ip"], n_starts=1,
                         critical_speeds=False)
    assert any(w.startswith("the data cannot see disk0.Ip") for w in res.warnings), res.warnings


def test_other_minima_reported():
    """Distinct minima within the chi-square margin are reported; the same minimum
    reached twice, and minima far worse, are not."""
    from rotorjax.identify._engine import Parameter, other_minima

    params = (Parameter("bearing0.kxx", None, True, 1.0, 1e6),)
    best = np.array([np.log(1e6)])
    ths = np.log(np.array([[1e6], [1e6 * (1 + 1e-4)], [3e6], [9e6]]))
    out = other_minima(params, ths, np.array([1.0, 1.0, 1.05, 50.0]), best, 1.0, np.array([0.01]), 0.2)
    assert len(out) == 1 and abs(out[0]["estimates"]["bearing0.kxx"] / 3e6 - 1) < 1e-12


# --- impact tests (receptances) ----------------------------------------------------------

def _receptances(rotor, speed, noise=0.0, seed=0):
    w = np.linspace(40.0, 450.0, 40)
    rows = {"speed": [], "frequency": [], "node": [], "direction": [], "input_node": [], "input_direction": [],
            "X": []}
    for inp, out in [(i, o) for i in ((2, "x"), (2, "y")) for o in ((0, "x"), (0, "y"), (6, "x"), (6, "y"))]:
        H = np.asarray(frf(rotor, inp, out, w, speed=speed).values)
        for wi, h in zip(w, H):
            rows["speed"].append(speed)
            rows["frequency"].append(wi)
            rows["node"].append(out[0])
            rows["direction"].append(out[1])
            rows["input_node"].append(inp[0])
            rows["input_direction"].append(inp[1])
            rows["X"].append(h)
    X = np.asarray(rows.pop("X"))
    if noise:
        e = np.random.default_rng(seed).standard_normal(X.shape + (2,))
        X = X + noise * np.abs(X) / np.sqrt(2) * (e[..., 0] + 1j * e[..., 1])
    return make_phasors(np.asarray(rows["speed"]), np.asarray(rows["node"]), rows["direction"], X,
                        frequency=np.asarray(rows["frequency"]), input_node=np.asarray(rows["input_node"]),
                        input_direction=rows["input_direction"])


@pytest.mark.parametrize("speed", [0.0, 200.0])
def test_identify_from_receptances(truth_rotor, speed):
    """Impact-test receptances (hammer at node 2 in x and in y, probes at the
    bearings; rotor at rest, or running), noise-free: the bearing coefficients come
    back exactly from starts 2-5x off. (At rest an x impact alone cannot see the y
    coefficients: nothing couples the planes.)"""
    data = _receptances(truth_rotor, speed)
    assert data.kind == "frf"
    res = identify(rotor_model(PATH, next(_starts(11, 1))), data, FIT, critical_speeds=False)
    for k in FIT:
        assert abs(res.estimates[k] / TRUTH[k] - 1) < 1e-6, (k, res.estimates[k])


# --- gradients through the whole chain -------------------------------------------------

def test_estimates_gradient_against_refits(truth_rotor):
    """d estimates / d phasors by the implicit function theorem equals central
    differences of re-fits of perturbed data, each fitted to rounding (sigma held
    fixed: a sigma column)."""
    base = _phasors(truth_rotor, rig.RUNUP_SPEEDS, noise=0.01, seed=2, sigma=1e-5)
    model = rotor_model(PATH, TRUTH)
    res = identify(model, base, FIT, fit_unbalance=(2, 4), n_starts=1, critical_speeds=False)
    G = estimates_jacobian(res)
    n = base.n
    assert G.shape == (len(FIT), 2 * n)
    for j in (3, n + 117):
        i = j % n
        h = 0.05 * abs(base.X[i])
        vals = []
        for sgn in (1, -1):
            X = base.X.copy()
            X[i] += sgn * h * (1 if j < n else 1j)
            d = make_phasors(base.speed, base.node, base.direction, X, sigma=base.sigma)
            r = problem(model, d, FIT, (2, 4))[2]
            theta, _, info = levenberg_marquardt(r, res.theta, max_iter=50, tol=0.0)
            vals.append(np.exp(np.asarray(theta)))
        fd = (vals[0] - vals[1]) / (2 * h)
        assert np.allclose(G[:, j], fd, rtol=1e-3, atol=1e-3 * np.abs(fd).max()), (G[:, j], fd)


# --- optax as the gradient-descent option --------------------------------------------------

def test_optax_option_lowers_the_cost():
    data = read_phasors("flexible-runup")
    near = {k: v * 1.05 for k, v in TRUTH.items()}
    lm = identify(rotor_model(PATH, near), data, FIT, fit_unbalance=(2, 4), n_starts=1,
                        critical_speeds=False)
    adam = identify(rotor_model(PATH, near), data, FIT, fit_unbalance=(2, 4), n_starts=1, method="optax",
                          max_iter=50, critical_speeds=False)
    start_cost = float(np.sum(np.asarray(problem(PATH, data, FIT, (2, 4), overrides=near)[2](
        jnp.asarray(problem(PATH, data, FIT, (2, 4), overrides=near)[3]))) ** 2))
    assert lm.cost <= adam.cost * (1 + 1e-9) and adam.cost < start_cost


# --- bad input ---------------------------------------------------------------------------

BAD = [
    (dict(fit=["bearing7.kxx"]), "--fit bearing7.kxx: not a parameter of this rotor file"),
    (dict(fit=["bearing0.kzz"]), "a bearing's coefficients are kxx"),
    (dict(fit=["bearing0.kxx", "bearing0.kxx"]), "--fit: bearing0.kxx is named twice"),
    (dict(fit=["bearing0.mxx"]), "--fit bearing0.mxx: its start value is 0"),
    (dict(fit=[], fit_unbalance=()), "--fit: name at least one parameter"),
    (dict(fit_unbalance=(9,)), "--fit-unbalance 9: not a node of the rotor (0..6)"),
    (dict(fit_unbalance=(2, 2)), "--fit-unbalance 2,2: a node is named twice"),
    (dict(fit_unbalance=()), "has no excitation; give --fit-unbalance NODES"),
    (dict(covariance="hac"), "--covariance hac: expected classical or sandwich"),
    (dict(method="bfgs"), "--method bfgs: expected lm or optax"),
    (dict(n_starts=0), "--starts 0: at least 1"),
    (dict(spread=1.0), "--spread 1.0: must be > 1"),
    (dict(weights="log"), "--weights log: expected one of relative, uniform"),
]


@pytest.mark.parametrize("kwargs, message", BAD)
def test_bad_input(kwargs, message):
    args = dict(fit=["bearing0.kxx"], fit_unbalance=(2, 4), n_starts=1, critical_speeds=False)
    args.update(kwargs)
    fit = args.pop("fit")
    if message is None:
        identify(PATH, "flexible-runup", fit, **args)
        return
    with pytest.raises(InputError) as e:
        identify(PATH, "flexible-runup", fit, **args)
    assert message in str(e.value)


def test_material_and_diameter_identified():
    """Issue 33: the shaft's Young's modulus (`material0.E`) and one element's outer
    diameter (`shaft2.od`) are parameters like any other: from noise-free phasors of
    the rig with E = 205 GPa and od = 52 mm, a fit started 30 % off (E high, od low)
    recovers both within 1 %. The matrices are not affine in them, so the fit solves
    the rotor directly (no receptance coupling), and the fitted rotor is the file's
    with those values (`--set`)."""
    truth = dict(TRUTH, **{"material0.E": 2.05e11, "shaft2.od": 0.052})
    data = _phasors(load_rotor(PATH, truth).rotor, rig.RUNUP_SPEEDS)
    start = dict(TRUTH, **{"material0.E": 2.05e11 * 1.3, "shaft2.od": 0.052 * 0.7})
    model = rotor_model(PATH, start)
    _, params, r, _ = problem(model, data, ["material0.E", "shaft2.od"], (2, 4))
    assert r.coupling is None and not any(q.path.affine for q in params)
    res = identify(model, data, ["material0.E", "shaft2.od"], fit_unbalance=(2, 4), n_starts=1,
                         critical_speeds=False)
    for k in ("material0.E", "shaft2.od"):
        assert abs(res.estimates[k] / truth[k] - 1) < 1e-2, res.estimates
    fitted = r._rotor(jnp.asarray(res.theta))[0]
    assert_identical(fitted, load_rotor(PATH, dict(start, **res.estimates)).rotor)


def test_signed_parameter_with_zero_start():
    """A cross-coupled coefficient may start at 0: fitted linearly, scaled by 1."""
    _, params, _, center = problem(PATH, "flexible-runup", ["bearing0.kxy"], (2, 4))
    assert not params[0].log and params[0].scale == 1.0 and center.tolist() == [0.0]


def test_bad_rows_and_tables(tmp_path):
    d = make_phasors([100.0, 100.0], [3, 9], ["x", "x"], [1e-5, 1e-5])
    with pytest.raises(InputError, match=r"entry 1 .*node 9 is not a node of the rotor \(0\.\.6\)"):
        identify(PATH, d, ["bearing0.kxx"], fit_unbalance=(2,), n_starts=1)
    frf_data = make_phasors([0.0], [0], ["x"], [1e-7], frequency=[50.0], input_node=[2], input_direction=["x"])
    with pytest.raises(InputError, match="holds receptances"):
        identify(PATH, frf_data, ["bearing0.kxx"], fit_unbalance=(2,), n_starts=1)
    tapered = str(shipped_rotor("tapered_two_material"))
    with pytest.raises(InputError, match="tabulated against speed"):
        identify(tapered, d, ["bearing0.kxx"], fit_unbalance=(2,), n_starts=1)
