"""The CLI's pictures (`rotorjax.plot`) and the model band of an identification
(`rotorjax.identify.response_band`)."""

import jax
import numpy as np
import pytest

from rotorjax import identify as idf
from rotorjax import plot as rplot
from rotorjax.identify._fit import fit_covariance
from rotorjax.presets import balancing_machine as bm


@pytest.fixture
def figures(monkeypatch):
    """The figures the plot functions close, kept for inspection."""
    plt = rplot._plt()
    closed, close = [], plt.close

    def keep(fig=None):
        closed.append(fig)
        close(fig)

    monkeypatch.setattr(plt, "close", keep)
    return closed


def legend_labels(fig):
    return [t.get_text() for ax in fig.axes if ax.get_legend() for t in ax.get_legend().get_texts()]


def check_png(path):
    with open(path, "rb") as f:
        head = f.read(8)
    assert head == b"\x89PNG\r\n\x1a\n"
    assert path.stat().st_size > 10_000


# stationary regimes of elliptic-abb at n = 1.5 (`rotorjax steady --json`) and a
# flexible-abb run (model 003)
REGIMES = [
    {"whirl_amplitude": 0.0177, "weight_angles": [-3.1348, -1.4483], "verdict": "unstable", "kind": "unbalanced"},
    {"whirl_amplitude": 0.0396, "weight_angles": [-3.0005, -3.0005], "verdict": "stable", "kind": "unbalanced"},
    {"whirl_amplitude": 0.0583, "weight_angles": [-3.0046, -0.2729], "verdict": "stable", "kind": "unbalanced"},
    {"whirl_amplitude": 0.1371, "weight_angles": [1.4077, 1.4077], "verdict": "unstable", "kind": "unbalanced"},
    {"whirl_amplitude": 0.0, "weight_angles": [0.3, 2.9], "verdict": "marginal", "kind": "balanced"},
]
MODAL = [
    {"kind": "C", "sigma": None, "disk_amplitude": 0.0, "verdict": "unstable"},
    {"kind": "NS3", "sigma": 0.0, "disk_amplitude": 0.0062, "verdict": "stable"},
    {"kind": "NS2", "sigma": -4.0, "disk_amplitude": 0.0311, "verdict": "unstable"},
    {"kind": "NS2", "sigma": -4.0, "disk_amplitude": 0.0187, "verdict": "unstable"},
]


def test_steady_regimes(tmp_path, figures):
    path = tmp_path / "steady.png"
    assert rplot.plot_steady_regimes(path, REGIMES, "elliptic-abb, n = 1.5") == path
    check_png(path)
    (fig,) = figures
    ax = fig.axes[0]
    assert sorted(legend_labels(fig)) == ["marginal", "stable", "unstable"]
    assert ax.get_xlabel() == "weight angle relative to the rotor (rad)"
    assert ax.get_ylabel() == "whirl amplitude (dimensionless)"
    assert "n = 1.5" in ax.get_title()
    # one marker per weight: 2 weights x 5 regimes, filled only for the stable ones
    markers = [ln for ln in ax.get_lines() if ln.get_marker() not in ("None", None, "")]
    assert sum(len(ln.get_xdata()) for ln in markers) == 10
    assert {ln.get_label(): ln.get_markerfacecolor() != "none" for ln in markers
            if not ln.get_label().startswith("_")} == {"stable": True, "unstable": False, "marginal": False}
    with pytest.raises(ValueError, match="plot_regime_amplitudes"):
        rplot.plot_steady_regimes(tmp_path / "x.png", MODAL, "flexible-abb")


def test_steady_regimes_without_weights_or_regimes(tmp_path, figures):
    rplot.plot_steady_regimes(tmp_path / "a.png", [dict(REGIMES[1], weight_angles=[])], "no balancer")
    rplot.plot_steady_regimes(tmp_path / "b.png", [], "nothing found")
    assert legend_labels(figures[0]) == ["stable (no weights)"]
    check_png(tmp_path / "b.png")


def test_regime_amplitudes(tmp_path, figures):
    path = rplot.plot_regime_amplitudes(tmp_path / "modal.png", MODAL, "flexible-abb, omega = 1.5")
    check_png(path)
    (fig,) = figures
    ax = fig.axes[0]
    assert sorted(legend_labels(fig)) == ["stable", "unstable"]
    assert [t.get_text() for t in ax.get_xticklabels()] == ["C", "NS3", "NS2"]
    assert ax.get_ylabel() == "disk amplitude (dimensionless)" and ax.get_xlabel() == "regime kind"
    xs = sorted(float(ln.get_xdata()[0]) for ln in ax.get_lines())
    assert xs[0] == 0 and xs[1] == 1 and 1.5 < xs[2] < 2 < xs[3] < 2.5     # the two NS2 side by side


def test_margin(tmp_path, figures):
    s = np.linspace(0.0, 3.0, 301)
    m = 0.1 * (s - 1.0) * (s - 2.0)
    m[50] = np.nan
    path = rplot.plot_margin(tmp_path / "margin.png", s, m, np.array([1.0, 2.0]), "anisotropic-abb, mu_xi = 0.1",
                             "speed n (dimensionless)", "largest Re(lambda) (dimensionless)",
                             extra_roots=[1.05], extra_label="criterion p(n) = 0 (eq. 18)")
    check_png(path)
    (fig,) = figures
    ax = fig.axes[0]
    assert legend_labels(fig) == ["stable (margin < 0)", "margin", "critical speed: 1, 2",
                                  "criterion p(n) = 0 (eq. 18): 1.05"]
    assert ax.get_xlabel() == "speed n (dimensionless)"
    assert ax.get_ylabel() == "largest Re(lambda) (dimensionless)"
    assert ax.get_title() == "anisotropic-abb, mu_xi = 0.1"


def test_campbell_marks_the_crossings(tmp_path, figures):
    """The flexible rotor's 1x crossings: `plot_campbell` already draws them."""
    s = np.linspace(0.0, 400.0, 50)
    f = np.stack([150 - 0.1 * s, 150 + 0.1 * s, 350 + 0.05 * s], axis=1)
    fw = np.array([False, True, True])[None, :].repeat(50, 0)
    rplot.plot_campbell(s, f, fw, tmp_path / "c.png", critical=[136.4, 166.7, 368.4], title="ross-compare")
    check_png(tmp_path / "c.png")
    assert legend_labels(figures[0]) == ["forward", "backward", "1x", "critical speed (1x crossing)"]
    assert figures[0].axes[0].get_xlabel() == "speed (rad/s)"


def test_balance(tmp_path, figures):
    before = np.array([3e-5 * np.exp(1j * 0.4), 5e-5 * np.exp(-1j * 2.0)])
    after = np.array([2e-7 * np.exp(1j * 1.0), 1e-7 * np.exp(1j * 3.0)])
    corr = np.array([20.0 * np.exp(1j * np.radians(210.0)), 31.5 * np.exp(-1j * np.radians(20.0))])
    path = rplot.plot_balance(tmp_path / "balance.png", before, after, corr,
                              "balancing at 170 rad/s, radius 10 mm", planes=[1, 2])
    check_png(path)
    (fig,) = figures
    labels = legend_labels(fig)
    assert labels[:2] == ["measured before: 3e-05, 5e-05 m", "predicted after: 2e-07, 1e-07 m"]
    assert labels[2:] == ["plane 1: 20.0 g at 210 deg", "plane 2: 31.5 g at 340 deg"]
    assert "once-per-revolution mark" in fig._suptitle.get_text()
    assert "170 rad/s" in fig._suptitle.get_text()
    assert all("(deg)" in ax.get_xlabel() for ax in fig.axes)
    assert "(radius: amplitude, 1e-5 m)" in fig.axes[0].get_title()
    assert "(radius: mass, g)" in fig.axes[1].get_title()


def test_identification_plot(tmp_path, figures):
    w = np.linspace(30.0, 400.0, 40)
    fit = np.stack([1e-5 * w**2 / (200.0**2 - w**2 + 40j * w), 2e-5 * w**2 / (260.0**2 - w**2 + 30j * w)], 1)
    data = fit * (1 + 0.02 * np.random.default_rng(0).normal(size=fit.shape))
    path = rplot.plot_identification(tmp_path / "ident.png", w, data, fit, 0.95 * np.abs(fit),
                                     1.05 * np.abs(fit), "balancing-machine: fit k1, k2, c1, c2", ["x1", "x2"])
    check_png(path)
    (fig,) = figures
    a1, a2 = fig.axes
    assert legend_labels(fig) == ["x1 model 95 % band", "x1 measured", "x1 model",
                                  "x2 model 95 % band", "x2 measured", "x2 model",
                                  "x1 measured", "x1 model", "x2 measured", "x2 model"]
    assert a1.get_yscale() == "log" and a1.get_ylabel() == "1x amplitude (m)"
    assert a2.get_ylabel().startswith("phase (deg") and a2.get_xlabel() == "speed (rad/s)"


# --- the band of the identified model ------------------------------------------------

P = dict(bm.PRESET.defaults)
MACHINE, PLANES, U = bm.build_machine(P), bm.planes(P), bm.unbalances(P)
SPEEDS = np.linspace(30.0, 400.0, 60)


@pytest.fixture(scope="module", params=["known unbalances", "fitted unbalances"])
def fitted(request):
    """A fit of k1, k2, c1, c2 to 60 speeds with 1 % noise (of the peak)."""
    Xs = np.asarray(jax.vmap(lambda ww: MACHINE.response(ww, PLANES, U))(SPEEDS))
    s = 0.01 * np.abs(Xs).max()
    rng = np.random.default_rng(3)
    Xn = Xs + s * (rng.normal(size=Xs.shape) + 1j * rng.normal(size=Xs.shape)) / np.sqrt(2)
    start = bm.build_machine(dict(P, k1=1.5e5, k2=2.5e5, c1=100.0, c2=300.0))
    known = U if request.param == "known unbalances" else None
    res = idf.identify(start, SPEEDS, Xn, PLANES, unbalances=known)
    assert res.converged
    return res, start, known


def test_band_is_a_point_without_uncertainty(fitted):
    res, start, known = fitted
    p = len(res.names) + (0 if known is not None else 2 * len(PLANES))
    X, lo, hi = idf.response_band(res, start, SPEEDS, PLANES, known, covariance=np.zeros((p, p)))
    m = bm.build_machine(dict(P, **res.estimates))
    D = U if known is not None else res.unbalances
    np.testing.assert_allclose(X, np.asarray(jax.vmap(lambda ww: m.response(ww, PLANES, D))(SPEEDS)),
                               rtol=1e-12)
    np.testing.assert_array_equal(lo, np.abs(X))
    np.testing.assert_array_equal(hi, np.abs(X))


def test_rebuilt_covariance_is_identifys(fitted):
    res, start, known = fitted
    cov = fit_covariance(res, start, SPEEDS, PLANES, known)
    sd_log = np.sqrt(np.diag(cov))[:len(res.names)]
    np.testing.assert_allclose(sd_log, [res.std[k] / res.estimates[k] for k in res.names], rtol=1e-6)


def test_band_equals_monte_carlo(fitted):
    """2000 parameter sets drawn from the fit's covariance: the 2.5 % and 97.5 %
    quantiles of |X| at each speed equal the delta-method band's edges to 10 % of
    the band's width."""
    res, start, known = fitted
    X, lo, hi = idf.response_band(res, start, SPEEDS, PLANES, known)
    assert np.all(hi > lo)
    cov = fit_covariance(res, start, SPEEDS, PLANES, known)
    logp = np.log([res.estimates[k] for k in res.names])
    theta = logp if known is not None else np.concatenate([logp, res.unbalances.real, res.unbalances.imag])
    draws = np.random.default_rng(0).multivariate_normal(theta, cov, size=2000)
    n = len(res.names)

    def amp(th):
        m = bm.build_machine(dict(P, **{k: jax.numpy.exp(th[i]) for i, k in enumerate(res.names)}))
        D = known if known is not None else th[n:n + 2] + 1j * th[n + 2:]
        return jax.numpy.abs(jax.vmap(lambda ww: m.response(ww, PLANES, D))(SPEEDS))

    A = np.asarray(jax.jit(jax.vmap(amp))(draws))
    q_lo, q_hi = np.quantile(A, [0.025, 0.975], axis=0)
    width = q_hi - q_lo
    assert np.max(np.abs(lo - q_lo) / width) < 0.1
    assert np.max(np.abs(hi - q_hi) / width) < 0.1
    assert np.max(np.abs((hi - lo) / width - 1)) < 0.1
