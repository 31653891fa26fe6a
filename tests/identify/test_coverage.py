"""Identification from a run-up: the run-up model, the phase reference, honest
intervals (issue 13, item 3). A small Monte Carlo on a cheap run-up (10 s instead
of the shipped 20 s, so twice the sweep rate: 38 rad/s^2), and the covariance
estimators on residuals of known structure."""

import jax
import jax.numpy as jnp
import numpy as np
import pytest

from rotorjax import identify as idf
from rotorjax.analysis import balancing_response
from rotorjax.identify import _covariance, _runup_model
from rotorjax.identify import _make_data as md
from rotorjax.presets import balancing_machine as bm

P = dict(bm.PRESET.defaults)
MACHINE, PLANES, U = bm.build_machine(P), bm.planes(P), bm.unbalances(P)
NAMES = ("k1", "k2", "c1", "c2")
TRUTH = np.array([P[k] for k in NAMES])
START = bm.build_machine(dict(P, k1=1.5e5, k2=3.75e5, c1=100.0, c2=266.0))
#: the start with its unbalances fitted (the scene's are not used)
FITTED = idf.BalancingScene(START, PLANES, np.zeros(len(PLANES), dtype=complex))
CHEAP = dict(duration=10.0, fs=1000.0, w0=20.0, w1=400.0)
ALPHA = (CHEAP["w1"] - CHEAP["w0"]) / CHEAP["duration"]
N_MC = 40


def true_angle(d, t):
    return d["phi"] + CHEAP["w0"] * t + 0.5 * ALPHA * t**2


def exact_pulses(d):
    """The instants the mark passes (theta = 2 pi k), without the tacho's sampling."""
    k = np.arange(1, 2000) * 2 * np.pi - d["phi"]
    k = k[k > 0]
    t = (-CHEAP["w0"] + np.sqrt(CHEAP["w0"] ** 2 + 2 * ALPHA * k)) / ALPHA
    return t[t < d["time"][-1]]


def clean(d):
    """The noise-free signal of data set `d` (the generator's cached simulations)."""
    _, xD, xiD = md._runup_clean(tuple(sorted(P.items())), *(float(CHEAP[k]) for k in ("fs", "duration", "w0",
                                                                                          "w1")))
    return np.cos(d["phi"]) * xD + np.sin(d["phi"]) * xiD


@pytest.fixture(scope="module")
def monte_carlo():
    """40 cheap run-ups: the old fit (steady model, classical covariance) and the new
    one (run-up model, phase reference fitted jointly, HAC), the phasors' noise and
    the angle's error against what `OrderTrack` states."""
    out = {"old": [], "new": [], "z": [], "angle_z": []}
    for seed in range(N_MC):
        d = md.runup_dataset(seed, **CHEAP)
        x = np.stack([d["x1"], d["x2"]], axis=1)
        tr = idf.order_track(d["time"], x, tacho=d["tacho"], full=True)
        old = idf.identify(FITTED, (tr.speeds, tr.X), NAMES, fit_unbalance=True)
        new = idf.identify(FITTED, tr, NAMES, fit_unbalance=True)
        assert new.converged and new.model == "runup" and new.covariance_method == "hac"
        for key, r in (("old", old), ("new", new)):
            out[key].append([[r.estimates[k], *r.intervals[k], r.std[k]] for k in NAMES])
        # the phasors' noise: the same blocks of the noise-free signal
        _, X0 = idf.order_track(d["time"], clean(d), tacho=d["tacho"])
        z = (tr.X - X0) / tr.sigma
        out["z"].append(np.concatenate([z.real.ravel(), z.imag.ravel()]))
        V, _ = tr.angle_sensitivity(tr.block_time)
        err = tr.angle_derivatives(tr.block_time) - true_angle(d, tr.block_time)
        err -= 2 * np.pi * np.round(err / (2 * np.pi))
        out["angle_z"].append(err / np.sqrt(np.einsum("ij,jk,ik->i", V, tr.angle_cov, V)))
    return {k: np.asarray(v) if k in ("old", "new") else np.concatenate(v) for k, v in out.items()}


def test_new_intervals_cover_the_truth(monte_carlo):
    """Coverage within the binomial range of 95 % intervals (>= 33 of 40: P(X <= 32) = 0.5 %
    for a true 95 %), bias below a third of the reported standard deviation, and the
    reported standard deviation equal to the scatter across data sets to 35 %."""
    a = monte_carlo["new"]                                   # (data set, parameter, est/lo/hi/sd)
    covered = np.sum((a[..., 1] <= TRUTH) & (TRUTH <= a[..., 2]), axis=0)
    assert np.all(covered >= 33), dict(zip(NAMES, covered))
    rel = a[..., 0] / TRUTH - 1
    sd = np.mean(a[..., 3] / a[..., 0], axis=0)
    assert np.all(np.abs(rel.mean(axis=0)) < sd / 3), (rel.mean(axis=0), sd)
    ratio = rel.std(axis=0, ddof=1) / sd
    assert np.all((ratio > 0.65) & (ratio < 1.35)), dict(zip(NAMES, ratio))


def test_old_intervals_miss_the_truth(monte_carlo):
    """The steady fit of a run-up: the transient and the tacho's phase error bias it
    by several of its standard deviations, so its intervals miss (the failure the
    new estimator fixes)."""
    a = monte_carlo["old"]
    covered = np.mean((a[..., 1] <= TRUTH) & (TRUTH <= a[..., 2]), axis=0)
    assert np.min(covered) < 0.5, dict(zip(NAMES, covered))


def test_phasor_noise_and_angle_error_are_as_stated(monte_carlo):
    """`OrderTrack.sigma` is the phasors' noise, and `angle_cov` the angle fit's error
    (the tacho pulses timed to half a sample): both scaled errors have unit variance."""
    z = monte_carlo["z"]
    assert np.std(z) == pytest.approx(1.0, abs=0.03)
    assert np.sqrt(np.mean(monte_carlo["angle_z"] ** 2)) == pytest.approx(1.0, abs=0.25)


def test_runup_model_equals_the_time_simulation():
    """The run-up model (modal exponential integrator, FFT convolution) order-tracked
    equals the generator's diffrax simulation order-tracked the same way, with the
    exact angle: to 1e-7 of the peak."""
    d = md.runup_dataset(0, **CHEAP)
    tr = idf.order_track(d["time"], clean(d), pulses=exact_pulses(d), full=True)
    data = _runup_model.RunupData.from_tracking(tr)
    Xm = np.asarray(_runup_model.runup_phasors(MACHINE, PLANES, U, data))[:tr.speeds.size]
    assert np.max(np.abs(Xm - tr.X)) < 1e-7 * np.max(np.abs(tr.X))
    assert np.all(np.asarray(_runup_model.runup_phasors(MACHINE, PLANES, U, data))[tr.speeds.size:] == 0)


def test_runup_model_derivatives_match_finite_differences():
    """The custom JVP (one complex derivative per mode) against central differences,
    in a damping, a stiffness and an unbalance."""
    d = md.runup_dataset(1, **CHEAP)
    tr = idf.order_track(d["time"], clean(d), tacho=d["tacho"], full=True)
    data = _runup_model.RunupData.from_tracking(tr)

    @jax.jit
    def f(v):
        m = bm.build_machine(dict(P, c1=v[0], k2=v[1]))
        return _runup_model.runup_phasors(m, PLANES, U * jnp.array([v[2], 1.0]), data)

    v0 = jnp.array([150.0, 3e5, 1.0])
    for i, h in enumerate((1e-3, 1.0, 1e-6)):
        e = jnp.zeros(3).at[i].set(1.0)
        jvp = np.asarray(jax.jvp(f, (v0,), (e,))[1])
        fd = np.asarray(f(v0 + h * e) - f(v0 - h * e)) / (2 * h)
        assert np.max(np.abs(jvp - fd)) < 1e-6 * np.max(np.abs(fd))


def _regression(n):
    """A smooth 3-parameter design over `n` speed points, rows stacked as `identify`
    stacks residuals: `(part Re/Im, point, sensor)` row-major."""
    s = np.linspace(-1, 1, n)
    base = np.stack([np.ones(n), s, s**2], axis=1)                          # (n, 3)
    gain = np.array([[1.0, 0.7], [0.4, -0.9]])                              # (part, sensor)
    return (gain[:, None, :, None] * base[None, :, None, :]).reshape(-1, 3)


def test_hac_equals_classical_on_independent_residuals_and_exceeds_it_on_ar1():
    rng = np.random.default_rng(0)
    n = 20000
    J = _regression(n)
    white = rng.normal(size=4 * n)
    sd = {m: np.sqrt(np.diag(_covariance.theta_covariance(J, white, m, n_points=n))) for m in ("classical", "sandwich",
                                                                                           "hac")}
    np.testing.assert_allclose(sd["sandwich"], sd["classical"], rtol=0.05)
    np.testing.assert_allclose(sd["hac"], sd["classical"], rtol=0.05)
    # AR(1) along the speed points (rho 0.8), the same for each of the 4 residual channels
    e = np.empty((n, 4))
    e[0] = rng.normal(size=4)
    for i in range(1, n):
        e[i] = 0.8 * e[i - 1] + 0.6 * rng.normal(size=4)
    ar1 = np.concatenate([e[:, :2].ravel(), e[:, 2:].ravel()])
    sd_c = np.sqrt(np.diag(_covariance.theta_covariance(J, ar1, "classical", n_points=n)))
    sd_h = np.sqrt(np.diag(_covariance.theta_covariance(J, ar1, "hac", n_points=n, lags=30)))
    # the long-run variance of AR(1) is (1 + rho) / (1 - rho) = 9 times the variance: sd x 3
    assert np.all(sd_h > 2.0 * sd_c) and np.all(sd_h < 3.3 * sd_c), sd_h / sd_c


@pytest.mark.parametrize("rho,warns", [(0.0, False), (0.8, True)])
def test_structure_warning(rho, warns):
    """A steady sweep with white noise: no warning; with AR(1) noise along the sweep:
    the structure warning, naming the lag-1 autocorrelation."""
    w = np.linspace(30.0, 400.0, 300)
    Xs = np.asarray(jax.vmap(lambda ww: balancing_response(MACHINE, ww, PLANES, U))(w))
    s = 0.01 * np.abs(Xs).max()
    rng = np.random.default_rng(5)
    e = rng.normal(size=(300, 4))
    for i in range(1, 300):
        e[i] = rho * e[i - 1] + np.sqrt(1 - rho**2) * e[i]
    Xn = Xs + s * (e[:, :2] + 1j * e[:, 2:]) / np.sqrt(2)
    res = idf.identify(idf.BalancingScene(START, PLANES, U), (w, Xn), NAMES)
    found = [m for m in res.warnings if "structure" in m]
    assert bool(found) == warns, res.warnings
    if warns:
        assert "lag-1 autocorrelation" in found[0] and "covariance='hac'" in found[0]
        assert all(v["rho1"] > 0.5 for v in res.residual_structure.values())
    else:
        assert all(abs(v["rho1"]) < 0.2 for v in res.residual_structure.values())
