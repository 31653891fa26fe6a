"""Uncertainty propagation (`rotorjax.uncertainty`): Monte Carlo against closed forms,
first-order moments against exact ones, and a rotor file's sampled quantities
against the analyses run on the rotor file with the sample's values `--set`."""

import jax.numpy as jnp
import numpy as np
import pytest
from scipy.stats import lognorm, norm

from rotorjax._errors import InputError
from rotorjax.analysis import critical_speeds_1x, modes
from rotorjax.io import read_rotor_file, shipped_rotor
from rotorjax.uncertainty import (LogNormal, Normal, Uniform, distribution, parse_distribution, propagate,
                                  rotor_quantities, support, wilson)

M = 2.0
K = LogNormal(1e6, 1e5)
N_MC = 40_000


@pytest.fixture(scope="module")
def jeffcott():
    """A Jeffcott rotor's critical speed `sqrt(k / m)` with a lognormal `k`."""
    return propagate(lambda v: jnp.sqrt(v[0] / M), {"k": K}, samples=N_MC, seed=3, names=("w",))


def test_monte_carlo_equals_the_closed_form(jeffcott):
    """`sqrt(k / m)` of a lognormal `k` is lognormal (`s_w = s_k / 2`, `mu_w = (mu_k -
    log m) / 2`): the sample mean, standard deviation and 5/50/95 % quantiles agree
    with the exact ones within 4 of their standard errors."""
    r = jeffcott
    s, mu = K.s / 2, (K.mu - np.log(M)) / 2
    exact = lognorm(s, scale=np.exp(mu))
    assert abs(r.mean[0] - exact.mean()) < 4 * r.sem[0]
    assert abs(r.std[0] / exact.std() - 1) < 4 / np.sqrt(2 * N_MC)
    for q in (0.05, 0.5, 0.95):
        x = exact.ppf(q)
        se = np.sqrt(q * (1 - q) / N_MC) / exact.pdf(x)     # an order statistic's standard error
        assert abs(r.quantiles[q][0] - x) < 4 * se, (q, r.quantiles[q][0], x)
    assert r.n == N_MC and r.finite.all()


def test_first_order_moments(jeffcott):
    """FOSM: `f(E k)` and `|f'(E k)| sd_k` against the exact lognormal moments, to their
    second-order error (`s^2 / 8` and `s^2 / 2` relative; `s = 0.1`); exact for a
    linear function of correlated normal inputs."""
    r = jeffcott
    s, mu = K.s / 2, (K.mu - np.log(M)) / 2
    exact = lognorm(s, scale=np.exp(mu))
    assert r.fosm_mean[0] == pytest.approx(np.sqrt(K.mean / M), rel=1e-12)
    assert abs(r.fosm_mean[0] / exact.mean() - 1) < K.s**2 / 4
    assert abs(r.fosm_std[0] / exact.std() - 1) < K.s**2
    a, b = Normal(1.0, 0.3), Normal(-2.0, 0.5)
    lin = propagate(lambda v: jnp.stack([2 * v[0] + 3 * v[1], v[0]]), {"a": a, "b": b}, samples=20_000,
                    correlation={("a", "b"): 0.6}, names=("y", "a"))
    sd = np.sqrt(4 * 0.09 + 9 * 0.25 + 2 * 2 * 3 * 0.6 * 0.3 * 0.5)
    assert lin.fosm_mean[0] == pytest.approx(-4.0, abs=1e-12) and lin.fosm_std[0] == pytest.approx(sd, rel=1e-12)
    assert abs(lin.mean[0] + 4.0) < 4 * lin.sem[0] and abs(lin.std[0] / sd - 1) < 4 / np.sqrt(2 * 20_000)
    rho = np.corrcoef(lin.input_samples.T)[0, 1]
    assert abs(rho - 0.6) < 4 * (1 - 0.36) / np.sqrt(20_000)
    assert lin.shares[0] == pytest.approx([4 * 0.09 / (4 * 0.09 + 9 * 0.25), 9 * 0.25 / (4 * 0.09 + 9 * 0.25)])


def test_uniform_and_a_violation_probability(capsys):
    """A uniform parameter's probability of exceeding a level: `k / n` with a Wilson
    interval that holds the exact value; the interval itself against its formula.
    (With `progress`, a bar over the chunks on stderr.)"""
    u = Uniform(0.0, 2.0)
    r = propagate(lambda v: v[0], {"u": u}, samples=4000, seed=1, names=("u",), chunk_size=1000, progress=True)
    assert "sweep" in capsys.readouterr().err
    p, (lo, hi) = r.probability("u", above=1.5)
    assert lo <= 0.25 <= hi and abs(p - 0.25) < 0.03
    assert wilson(0, 100)[1][0] == 0.0 and wilson(100, 100)[1][1] == 1.0
    p, (lo, hi) = wilson(20, 100)
    z = norm.ppf(0.975)
    c = (0.2 + z**2 / 200) / (1 + z**2 / 100)
    h = z * np.sqrt(0.2 * 0.8 / 100 + z**2 / 40000) / (1 + z**2 / 100)
    assert (lo, hi) == pytest.approx((c - h, c + h), rel=1e-12)


@pytest.mark.parametrize("call,match", [
    (lambda: parse_distribution("bearing0.kxx=normal(1e6)"), r"--dist 'bearing0\.kxx=normal\(1e6\)': expected"),
    (lambda: parse_distribution("k=gamma(1,2)"), r"unknown distribution 'gamma'"),
    (lambda: parse_distribution("k=normal(1,0)"), r"k=normal\(1,0\): normal\(1, 0\): the standard deviation must"),
    (lambda: parse_distribution("k=uniform(2,1)"), r"uniform\(2, 1\) needs LO < HI"),
    (lambda: parse_distribution("k=lognormal(-1,1)"), r"lognormal quantity's mean must be > 0"),
    (lambda: parse_distribution("k=normal(a,1)"), r"'a' and '1' must be numbers"),
    (lambda: distribution("normal", 1.0, float("nan")), r"needs finite numbers"),
    (lambda: propagate(lambda v: v, {"k": K}, samples=1), r"samples must be an integer >= 2, got 1"),
    (lambda: propagate(lambda v: v, {}, samples=10), r"inputs: give at least one"),
    (lambda: propagate(lambda v: v, {"a": K, "b": K}, samples=10, correlation=[[1, 2], [2, 1]]),
     r"correlation must be symmetric .* entries in \[-1, 1\]"),
    (lambda: propagate(lambda v: v, {"a": K, "b": K}, samples=10, correlation={("a", "c"): 0.5}),
     r"correlation: 'c' is not one of the distributed parameters"),
])
def test_bad_input_names_the_item(call, match):
    with pytest.raises(InputError, match=match):
        call()


# --- a rotor file ---------------------------------------------------------------------------------------

PATH = str(shipped_rotor("flexible_rig"))
NAMES = ("bearing0.kxx", "bearing1.kyy", "disk0.m")


@pytest.fixture(scope="module")
def rig():
    inputs = {"bearing0.kxx": LogNormal(1.2e6, 1.2e4), "bearing1.kyy": Normal(8e5, 8e3),
              "disk0.m": Uniform(9.9, 10.1)}
    q = rotor_quantities(PATH, inputs, hi=500.0, n_modes=2)
    return q, inputs, propagate(q.fn, inputs, samples=400, seed=5, names=q.outputs)


def test_samples_equal_the_analyses_of_the_file_with_the_values_set(rig):
    """Each sample's critical speeds and log decrements equal `critical_speeds_1x` and
    `modes` run on the rotor file read again with the sample's values as `--set`
    overrides (an independent path: the file's reader, the analyses' own solvers)."""
    q, _, r = rig
    assert q.outputs == ("critical_speed_0", "critical_speed_1", "log_dec_0", "log_dec_1")
    for i in (0, 17, 399):
        values = dict(zip(NAMES, r.input_samples[i]))
        rotor = read_rotor_file(PATH, values).scene.full_rotor
        crit = [w for w, _ in critical_speeds_1x(rotor, 0.0, 500.0, whirl="forward")]
        np.testing.assert_allclose(r.samples[i, :2], crit, rtol=1e-8)
        np.testing.assert_allclose(r.samples[i, 2:], np.asarray(modes(rotor, q.speed, 2).log_dec), rtol=1e-9)


def test_first_order_agrees_with_monte_carlo_for_small_scatter(rig):
    """With 1 % scatter the quantities are nearly linear in the parameters: the
    first-order mean and standard deviation agree with the Monte Carlo ones within
    4 standard errors (and 10 % for the standard deviation)."""
    _, _, r = rig
    assert r.n == 400
    assert np.all(np.abs(r.mean - r.fosm_mean) < 4 * r.sem)
    assert np.all(np.abs(r.std / r.fosm_std - 1) < 0.1)
    assert np.allclose(r.shares.sum(axis=1), 1.0)


@pytest.mark.parametrize("path", ["secant", "newton"])
def test_each_critical_speed_is_solved_and_differentiated_exactly(path):
    """`critical_speed` each way, checked against the scan-and-bisect
    `critical_speeds_1x` of the file read again with the sample's values (the speed,
    and its gradient against central differences of the bisection); the residual at
    roundoff.

    - `secant`: from 30 % off each nominal critical speed, on a sample 20 % stiffer
      and 20 % heavier. (A plain fixed point needs `|d omega / d Omega|^n` small:
      with 6 iterations it left the highest one unconverged, and a Monte Carlo at
      10 % scatter dropped the samples far from the nominal.)
    - `newton` (`pair=`, the Monte Carlo's path): 4 Newton steps from the nominal
      rotor's eigenpair at its critical speed (`critical_pair`), on a sample 10 % off
      in all three parameters; it also equals the secant path's to 1e-11.
    """
    import jax

    from rotorjax.analysis import critical_pair, critical_speed
    from rotorjax.models._parameters import parts_of, with_values

    file = read_rotor_file(PATH)
    nominal = critical_speeds_1x(file.scene.full_rotor, 0.0, 900.0, whirl="forward")
    assert len(nominal) == 3   # the third's |d omega / d Omega| is 0.08
    parts, paths = parts_of(file.scene), [file.path(n) for n in NAMES]
    off = 0.2 if path == "secant" else 0.1
    values = np.array([(1 + off) * 1.2e6, (1 - off) * 8e5, (1 + off) * 10.0])

    def scan(v):
        rotor = read_rotor_file(PATH, dict(zip(NAMES, v))).scene.full_rotor
        return np.array([w for w, _ in critical_speeds_1x(rotor, 0.0, 900.0, whirl="forward", xtol=1e-12)])

    ref = scan(values)
    steps = [np.eye(3)[i] * 1e-3 * values[i] for i in range(3)]
    fd = np.stack([(scan(values + e) - scan(values - e)) / (2 * e.sum()) for e in steps], axis=1)
    for j, (W, k) in enumerate(nominal):
        pair = critical_pair(file.scene.full_rotor, k, W)

        def solve(v, k=k, W=W, pair=pair):
            rotor = with_values(parts, paths, v).rotor
            if path == "secant":
                return critical_speed(rotor, k, 0.7 * W)
            return critical_speed(rotor, k, W, iters=4, pair=pair)

        w, res = solve(jnp.asarray(values))
        grad = np.asarray(jax.grad(lambda v: solve(v)[0])(jnp.asarray(values)))
        assert abs(float(res)) < 1e-10 * float(w)
        assert float(w) == pytest.approx(ref[j], rel=1e-9)
        for i in range(3):
            assert grad[i] == pytest.approx(fd[j, i], rel=1e-4, abs=1e-8 * abs(float(w)) / values[i])
        if path == "newton":
            secant = critical_speed(with_values(parts, paths, jnp.asarray(values)).rotor, k, W)[0]
            assert float(w) == pytest.approx(float(secant), rel=1e-11)
    with pytest.raises(InputError, match=r"k \(mode index\) must be"):
        critical_pair(file.scene.full_rotor, 99, 100.0)


def test_samples_fn_leaves_are_evaluated_again_by_the_fallback():
    """`propagate(..., fallback=)`: the samples (and the first-order point) where `fn`
    is not finite are the fallback's, counted in `retried`; without a fallback they
    are left out."""
    u = Uniform(0.0, 1.0)
    fn = lambda v: jnp.where(v[0] < 0.5, v[0] ** 2, jnp.nan)   # noqa: E731
    again = propagate(fn, {"u": u}, samples=200, seed=2, fallback=lambda v: v[0] ** 2)
    np.testing.assert_allclose(again.samples[:, 0], again.input_samples[:, 0] ** 2, rtol=1e-15)
    assert again.retried == int(np.sum(again.input_samples[:, 0] >= 0.5)) > 50 and again.n == 200
    assert again.fosm_mean[0] == pytest.approx(0.25) and again.gradient[0, 0] == pytest.approx(1.0)
    assert again.as_dict()["retried_samples"] == again.retried
    alone = propagate(fn, {"u": u}, samples=200, seed=2)
    assert alone.retried == 0 and alone.n == 200 - again.retried


def test_support_is_the_five_sigma_quantiles():
    """What a distribution draws, checked against a key's domain (`--dist`, `--scatter`): scipy's quantiles at
    5 standard deviations of the normal behind it (lognormal: scipy's `lognorm(s, scale=exp(mu))`)."""
    p = norm.cdf([-5.0, 5.0])
    d = LogNormal(0.3, 0.05)
    np.testing.assert_allclose(support(d), lognorm(d.s, scale=np.exp(d.mu)).ppf(p), rtol=1e-9)
    np.testing.assert_allclose(support(Normal(0.6, 0.1)), norm(0.6, 0.1).ppf(p), rtol=1e-9)
    assert support(Uniform(0.2, 0.7)) == (0.2, 0.7)
    draws = np.asarray(d.from_normal(np.random.default_rng(0).standard_normal(100_000)))
    assert support(d)[0] < draws.min() and draws.max() < support(d)[1]


def test_a_positive_parameter_needs_a_positive_distribution():
    with pytest.raises(InputError, match=r"--dist bearing0\.kxx=normal\(1e\+06, 300000\): bearing0\.kxx is a "
                                         r"positive quantity"):
        rotor_quantities(PATH, {"bearing0.kxx": Normal(1e6, 3e5)}, hi=500.0)
    with pytest.raises(InputError, match=r"--dist bearing9\.kxx: not a parameter of"):
        rotor_quantities(PATH, {"bearing9.kxx": LogNormal(1e6, 1e5)}, hi=500.0)


def test_the_command(tmp_path, capsys):
    """`rotorjax uncertainty`: the JSON's statistics are the API's for the same seed,
    with the instability probabilities and the files."""
    from rotorjax.cli import main

    dist = "bearing0.kxx=lognormal(1.2e6,1.2e5)"
    assert main(["uncertainty", "flexible_rig.toml", "--dist", dist, "--samples", "64", "--range", "0", "500",
                 "--modes", "1", "--json", "--out", str(tmp_path)]) == 0
    out = __import__("json").loads(capsys.readouterr().out)
    inputs = {"bearing0.kxx": LogNormal(1.2e6, 1.2e5)}
    q = rotor_quantities(PATH, inputs, hi=500.0, n_modes=1)
    r = propagate(q.fn, inputs, samples=64, names=q.outputs)
    for j, name in enumerate(q.outputs):
        assert out["outputs"][name]["mean"] == pytest.approx(r.mean[j], rel=1e-12)
        assert out["outputs"][name]["first_order"]["std"] == pytest.approx(r.fosm_std[j], rel=1e-12)
    u = out["probability_unstable"]
    assert list(u) == ["log_dec_0"] and u["log_dec_0"]["p"] == 0.0 and u["log_dec_0"]["ci95"][0] == 0.0
    assert u["log_dec_0"]["ci95"][1] == pytest.approx(wilson(0, 64)[1][1], rel=1e-12)
    assert (tmp_path / "uncertainty_flexible_rig.png").stat().st_size > 0
