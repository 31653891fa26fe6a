"""The CLI's pictures (`rotorjax.plot`) and the model band of an identification
(`rotorjax.identify.response_band`)."""

import inspect
import pathlib

import jax
import matplotlib
import numpy as np
import pytest

from rotorjax import identify as idf
from rotorjax import plot as rplot
from rotorjax.analysis import balancing_response
from rotorjax.cli._common import save_figure
from rotorjax.identify._fit import fit_covariance
from rotorjax.presets import balancing_machine as bm

matplotlib.use("Agg")   # as the CLI does: rotorjax.plot chooses no backend
import matplotlib.pyplot as plt  # noqa: E402


@pytest.fixture
def figures(monkeypatch):
    """The pyplot figures the plot functions make, in order, kept for inspection
    (and closed after the test)."""
    made, figure = [], plt.figure

    def keep(*args, **kwargs):
        fig = figure(*args, **kwargs)
        made.append(fig)
        return fig

    monkeypatch.setattr(plt, "figure", keep)
    yield made
    for fig in made:
        plt.close(fig)


def save(fig, path):
    """`fig` written as the CLI writes it (`save_figure`); the PNG's path."""
    return pathlib.Path(save_figure(fig, path))


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
    made = rplot.plot_steady_regimes(regimes=REGIMES, title="elliptic-abb, n = 1.5")
    check_png(save(made, tmp_path / "steady.png"))
    (fig,) = figures
    assert made is fig
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
        rplot.plot_steady_regimes(regimes=MODAL, title="flexible-abb")


def test_steady_regimes_without_weights_or_regimes(tmp_path, figures):
    rplot.plot_steady_regimes(regimes=[dict(REGIMES[1], weight_angles=[])], title="no balancer")
    empty = rplot.plot_steady_regimes(regimes=[], title="nothing found")
    assert legend_labels(figures[0]) == ["stable (no weights)"]
    check_png(save(empty, tmp_path / "b.png"))


def test_regime_amplitudes(tmp_path, figures):
    check_png(save(rplot.plot_regime_amplitudes(regimes=MODAL, title="flexible-abb, omega = 1.5"),
                   tmp_path / "modal.png"))
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
    made = rplot.plot_margin(None, s, m, np.array([1.0, 2.0]), "anisotropic-abb, mu_xi = 0.1",
                             "speed n (dimensionless)", "largest Re(lambda) (dimensionless)",
                             extra_roots=[1.05], extra_label="criterion p(n) = 0 (eq. 18)")
    check_png(save(made, tmp_path / "margin.png"))
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
    check_png(save(rplot.plot_campbell(s, f, fw, critical=[136.4, 166.7, 368.4], title="ross-compare"),
                   tmp_path / "c.png"))
    assert legend_labels(figures[0]) == ["forward", "backward", "1x", "critical speed (1x crossing)"]
    assert figures[0].axes[0].get_xlabel() == "speed (rad/s)"


def test_balance(tmp_path, figures):
    before = np.array([3e-5 * np.exp(1j * 0.4), 5e-5 * np.exp(-1j * 2.0)])
    after = np.array([2e-7 * np.exp(1j * 1.0), 1e-7 * np.exp(1j * 3.0)])
    corr = np.array([20.0 * np.exp(1j * np.radians(210.0)), 31.5 * np.exp(-1j * np.radians(20.0))])
    made = rplot.plot_balance(before=before, after=after, corrections=corr,
                              title="balancing at 170 rad/s, radius 10 mm", planes=[1, 2])
    check_png(save(made, tmp_path / "balance.png"))
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
    made = rplot.plot_identification(None, w, data, fit, 0.95 * np.abs(fit),
                                     1.05 * np.abs(fit), "balancing-machine: fit k1, k2, c1, c2", ["x1", "x2"])
    check_png(save(made, tmp_path / "ident.png"))
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
    Xs = np.asarray(jax.vmap(lambda ww: balancing_response(MACHINE, ww, PLANES, U))(SPEEDS))
    s = 0.01 * np.abs(Xs).max()
    rng = np.random.default_rng(3)
    Xn = Xs + s * (rng.normal(size=Xs.shape) + 1j * rng.normal(size=Xs.shape)) / np.sqrt(2)
    start = bm.build_machine(dict(P, k1=1.5e5, k2=2.5e5, c1=100.0, c2=300.0))
    known = U if request.param == "known unbalances" else None
    res = idf.identify(idf.BalancingScene(start, PLANES, U), (SPEEDS, Xn), fit_unbalance=known is None)
    assert res.converged
    return res, start, known


def test_band_is_a_point_without_uncertainty(fitted):
    res, start, known = fitted
    p = len(res.names) + (0 if known is not None else 2 * len(PLANES))
    X, lo, hi = idf.response_band(res, start, SPEEDS, PLANES, known, covariance=np.zeros((p, p)))
    m = bm.build_machine(dict(P, **res.estimates))
    D = U if known is not None else res.unbalances
    np.testing.assert_allclose(X, np.asarray(jax.vmap(lambda ww: balancing_response(m, ww, PLANES, D))(SPEEDS)),
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
        return jax.numpy.abs(jax.vmap(lambda ww: balancing_response(m, ww, PLANES, D))(SPEEDS))

    A = np.asarray(jax.jit(jax.vmap(amp))(draws))
    q_lo, q_hi = np.quantile(A, [0.025, 0.975], axis=0)
    width = q_hi - q_lo
    assert np.max(np.abs(lo - q_lo) / width) < 0.1
    assert np.max(np.abs(hi - q_hi) / width) < 0.1
    assert np.max(np.abs((hi - lo) / width - 1)) < 0.1


# --- issue 28, item 10: the FE analyses' pictures ------------------------------------------

def inside_figure(fig, text):
    """`text`'s drawn box lies inside the figure's (after the layout)."""
    from matplotlib.backends.backend_agg import FigureCanvasAgg

    box = text.get_window_extent(FigureCanvasAgg(fig).get_renderer())   # a closed figure's canvas has none
    return (box.x0 >= fig.bbox.x0 - 0.5 and box.x1 <= fig.bbox.x1 + 0.5
            and box.y0 >= fig.bbox.y0 - 0.5 and box.y1 <= fig.bbox.y1 + 0.5)


def test_campbell_tracked_legend_shows_line_styles(tmp_path, figures):
    """Forward and backward whirl in the legend as clean line-style entries (proxy
    lines without markers), apart from the log-decrement colours (a colorbar), the
    lines drawn over the dots, and no entry for a whirl that does not occur."""
    s = np.linspace(0.0, 400.0, 200)
    f = np.stack([150 - 0.1 * s, 150 + 0.1 * s, 350 + 0.05 * s], axis=1)
    whirl = np.array(["backward", "forward", "forward"])[None, :].repeat(200, 0)
    d = np.stack([0.1 + 0 * s, 0.2 - 1e-4 * s, 0.05 + 0 * s], axis=1)
    check_png(save(rplot.plot_campbell_tracked(s, f, whirl, d, critical=[136.4, 166.7], title="ross-compare"),
                   tmp_path / "c.png"))
    (fig,) = figures
    ax, cbar = fig.axes
    assert cbar.get_ylabel().startswith("logarithmic decrement")
    legend = ax.get_legend()
    entries = dict(zip((t.get_text() for t in legend.get_texts()), legend.legend_handles))
    assert list(entries) == ["forward whirl", "backward whirl", "1x", "1x crossing"]
    for name, ls in (("forward whirl", "-"), ("backward whirl", "--")):
        h = entries[name]
        assert h.get_linestyle() == ls and h.get_marker() in ("None", None, "")
        assert h not in ax.get_lines()          # a proxy, not a curve with the dots behind it
    (dots,) = ax.collections
    assert len(dots.get_offsets()) <= 3 * 40    # sparse enough for the dashes to show between them
    whirl_lines = [ln for ln in ax.get_lines() if ln.get_linestyle() in ("-", "--")]
    assert len(whirl_lines) == 6 and all(ln.get_zorder() > dots.get_zorder() for ln in whirl_lines)


CLI_TITLES = [
    "ross_compare: displacement at 2x / force at 2x, synchronous (speed = frequency)",
    "rotor-file-with-a-long-name: acceleration at 12y / force at 3x, at 1234.5 rad/s (a rotor read from "
    "/some/where/deep/in/a/project/rotors/compressor_rotor_with_tilting_pads.toml)",
]


@pytest.mark.parametrize("title", CLI_TITLES)
def test_frf_titles_fit_the_figures(tmp_path, figures, title):
    w = np.linspace(10.0, 600.0, 300)
    h = 1e-6 / (250.0**2 - w**2 + 2j * 0.05 * 250.0 * w)
    made = rplot.plot_frf(w, h, title=title)
    check_png(save(made[0], tmp_path / "bode.png"))
    check_png(save(made[1], tmp_path / "polar.png"))
    bode, polar = figures
    assert made == (bode, polar)
    assert inside_figure(bode, bode.axes[0].title)
    assert inside_figure(polar, polar.axes[0].title)
    # wrapped (a path too long for a line broken inside), nothing lost
    assert "".join(polar.axes[0].title.get_text().split()) == "".join((title + " (polar)").split())


@pytest.mark.parametrize("plot", ["ucs", "level1", "campbell", "modes", "stability_map", "simulation"])
def test_long_titles_fit_every_figure(tmp_path, figures, plot):
    """Every figure finishes in `_finish`, which wraps the titles to the figure."""
    title = CLI_TITLES[1]
    if plot == "ucs":
        rplot.plot_ucs(np.logspace(5, 9, 20), np.logspace(2, 3, 20)[:, None], title=title)
    elif plot == "level1":
        rplot.plot_level1(np.linspace(0, 5e7, 41), 0.3 - 1e-8 * np.linspace(0, 5e7, 41), q0=3e7, title=title)
    elif plot == "campbell":
        s = np.linspace(0, 100, 20)
        rplot.plot_campbell_tracked(s, 50 + 0 * s[:, None], np.full((20, 1), "forward"), 0.1 + 0 * s[:, None],
                                    title=title)
    elif plot == "modes":
        rplot.plot_mode_shapes(synthetic_modes(CIRCULAR, CIRCULAR), BEAM, title=title)
    elif plot == "stability_map":
        g = np.linspace(0, 1, 5)
        rplot.plot_stability_map(g, g, g[:, None] - g[None, :], None, "a", "b", title=title)
    else:
        rplot.plot_simulation(fake_run({"whirl_amplitude": np.ones(5)}), title=title)
    (fig,) = figures
    titles = [t for ax in fig.axes for t in (ax.title,) if t.get_text()]
    titles += [fig._suptitle] if fig._suptitle is not None else []
    assert titles and all(inside_figure(fig, t) for t in titles)


def test_frf_takes_a_refined_uneven_frequency_array(tmp_path, figures):
    """Points added near the resonance (uneven spacing, appended after the even
    grid): the curves run in order of frequency and the polar plot's ends are the
    lowest and highest frequency."""
    w = np.linspace(10.0, 600.0, 60)
    fine = 250.0 + np.linspace(-20.0, 20.0, 81)
    w_all = np.concatenate([w, fine])
    h = 1e-6 / (250.0**2 - w_all**2 + 2j * 0.02 * 250.0 * w_all)
    rplot.plot_frf(w_all, h, title="refined")
    bode, polar = figures
    order = np.argsort(w_all)
    (mag,) = bode.axes[0].get_lines()
    np.testing.assert_array_equal(mag.get_xdata(), w_all[order])
    np.testing.assert_array_equal(mag.get_ydata(), np.abs(h[order]))
    curve = polar.axes[0].get_lines()[0]
    np.testing.assert_array_equal(curve.get_xdata(), h.real[order])
    np.testing.assert_array_equal(curve.get_ydata(), h.imag[order])
    assert legend_labels(polar) == ["10 rad/s", "600 rad/s"]
    (phase,) = bode.axes[1].get_lines()
    deg = np.asarray(phase.get_ydata(), dtype=float)
    assert np.all(np.abs(np.diff(deg[np.isfinite(deg)])) < 180)     # no vertical line at a wrap


def test_level1_shows_q0(tmp_path, figures):
    """Q0 = 1e5 N/m on a 0 .. 5e7 N/m scan: inside the visible x range, clear of the
    axis's left end (not squeezed into the first 0.2 % of a linear axis), marked on
    the curve and annotated."""
    q = np.linspace(0.0, 5e7, 41)
    ld = 0.02 - 0.02 * q / 1e5 * np.exp(-q / 1e6)
    q0 = 1e5
    check_png(save(rplot.plot_level1(q, ld, q0=q0, title="ross-compare: API 684 level I"), tmp_path / "l1.png"))
    (fig,) = figures
    ax = fig.axes[0]
    lo, hi = ax.get_xlim()
    assert lo <= q0 <= hi and lo <= 0.0 and hi >= 5e7
    to_axes = ax.transAxes.inverted()
    x_frac = to_axes.transform(ax.transData.transform((q0, 0.0)))[0]
    assert 0.05 < x_frac < 0.95
    assert ax.get_xscale() == "symlog"
    notes = [t for t in ax.texts if t.get_text() == "Q0 = 1e+05 N/m"]
    assert len(notes) == 1 and tuple(notes[0].xy) == (q0, 0.0)
    # the curve passes through (Q0, 0)
    curve = ax.get_lines()[0]
    assert any(x == q0 and y == 0.0 for x, y in zip(curve.get_xdata(), curve.get_ydata()))


def test_level1_without_q0_stays_linear(tmp_path, figures):
    q = np.linspace(0.0, 5e7, 11)
    rplot.plot_level1(q, 0.1 + 0 * q, None, None, title="no crossing")
    (fig,) = figures
    assert fig.axes[0].get_xscale() == "linear" and not fig.axes[0].texts


class fake_run:
    """The parts of a `Solution` that `plot_simulation` reads."""

    def __init__(self, outputs, n=5):
        self.ts = np.linspace(0.0, 1.0, n)
        self.outputs = outputs
        self.success = True
        self.message = "ok"


def test_simulation_labels(tmp_path, figures):
    """The time axis says "time (s)" (not "time (time unit s)", as the CLI's label
    used to read), a run-up's speed axis "speed (rad/s)"; the amplitude axis names
    the node and the unit."""
    t = np.linspace(0.0, 1.0, 5)
    nx = np.outer(np.cos(t), [0.0, 1e-5, 3e-5, 1e-5])
    ny = np.outer(np.sin(t), [0.0, 1e-5, 3e-5, 1e-5])
    rotor_run = fake_run({"node_x": nx, "node_y": ny, "whirl_amplitude": np.hypot(nx, ny).max(1)})
    rplot.plot_simulation(rotor_run, title="rotor", x_label="time (time unit s)")
    rplot.plot_simulation(rotor_run, title="rotor", x_label="time", time_unit="s", node=2)
    rplot.plot_simulation(fake_run({"whirl_amplitude": np.ones(5)}), speed=t,
                          x_label="speed", time_unit="1/Omega", unit="r = (r1+r2)/2")
    rplot.plot_simulation(fake_run({"whirl_amplitude": np.ones(5)}))
    a, b, c, d = (fig.axes[0] for fig in figures)
    assert a.get_xlabel() == "time (s)"
    assert a.get_ylabel() == "whirl amplitude, largest over the nodes (m)"
    assert b.get_xlabel() == "time (s)" and b.get_ylabel() == "whirl amplitude at node 2 (m)"
    np.testing.assert_allclose(b.get_lines()[0].get_ydata(), 3e-5)
    assert c.get_xlabel() == "speed (rad per 1/Omega)" and c.get_ylabel() == "whirl amplitude (r = (r1+r2)/2)"
    assert d.get_xlabel() == "time" and d.get_ylabel() == "whirl amplitude"   # the old defaults
    with pytest.raises(ValueError, match="node"):
        rplot.plot_simulation(fake_run({"whirl_amplitude": np.ones(5)}), node=1)


def test_ucs_bearings_have_their_own_styles(tmp_path, figures):
    k = np.logspace(5, 9, 30)
    f = np.stack([30 * np.sqrt(k / 1e3), 90 * np.sqrt(k / 1e3)], axis=1)
    s = np.linspace(10.0, 2000.0, 20)
    kb = np.stack([np.stack([1e7 + 0 * s, 2e7 + 0 * s]), np.stack([3e7 + 0 * s, 4e7 + 1e3 * s])])
    two = rplot.plot_ucs(k, f, None, s, kb, [(1e7, 500.0)], title="two bearings")
    same = np.stack([np.stack([5e7 + 0 * s, 5e7 + 0 * s])] * 2)
    rplot.plot_ucs(k, f, None, s, same, title="two equal isotropic bearings")
    check_png(save(two, tmp_path / "u.png"))
    ax = figures[0].axes[0]
    bearing = {ln.get_label(): ln for ln in ax.get_lines() if ln.get_label().startswith("bearing")}
    assert list(bearing) == ["bearing 0 kxx", "bearing 0 kyy", "bearing 1 kxx", "bearing 1 kyy"]
    styles = {(ln.get_color(), ln.get_linestyle()) for ln in bearing.values()}
    assert len(styles) == 4
    assert bearing["bearing 0 kxx"].get_color() != bearing["bearing 1 kxx"].get_color()
    assert bearing["bearing 0 kxx"].get_linestyle() != bearing["bearing 0 kyy"].get_linestyle()
    # coinciding curves: one line, named for all of them
    labels = [ln.get_label() for ln in figures[1].axes[0].get_lines() if ln.get_label().startswith("bearing")]
    assert labels == ["bearings 0, 1 kxx = kyy"]


# a uniform beam of 10 elements on 11 nodes (4 dofs per node: x, y, theta_x, theta_y)
class _Beam:
    n_nodes = 11
    lengths = np.full(10, 0.1)
    node_positions = np.linspace(0.0, 1.0, 11)


BEAM = _Beam()
Z = BEAM.node_positions


def _shape(x, dx, y, dy):
    v = np.zeros(4 * BEAM.n_nodes, dtype=complex)
    v[0::4], v[1::4], v[2::4], v[3::4] = x, y, dx, dy
    return v


# forward circular whirl in the first bending mode: y lags x by 90 degrees
CIRCULAR = _shape(np.sin(np.pi * Z), np.pi * np.cos(np.pi * Z), -1j * np.sin(np.pi * Z),
                  -1j * np.pi * np.cos(np.pi * Z))
# the second bending mode, circular, with a phase of 90 degrees on the whole shape: x and y real
# parts vanish in turn
SECOND = 1j * _shape(np.sin(2 * np.pi * Z), 2 * np.pi * np.cos(2 * np.pi * Z), -1j * np.sin(2 * np.pi * Z),
                     -2j * np.pi * np.cos(2 * np.pi * Z))
# a planar mode (x only)
PLANAR = _shape(np.sin(np.pi * Z), np.pi * np.cos(np.pi * Z), 0 * Z, 0 * Z)


class synthetic_modes:
    def __init__(self, *shapes):
        self.shapes = np.stack(shapes, axis=1)
        self.frequencies = np.arange(1.0, len(shapes) + 1) * 100.0
        self.whirl = ["forward"] * len(shapes)
        self.log_dec = np.full(len(shapes), 0.1)


def test_mode_shapes_show_the_whirl(tmp_path, figures):
    """A circular orbit does not look planar: the plotted major semi-axis is the
    orbit's radius where a real part is zero, the minor semi-axis equals it
    (forward: positive), no curve is flat zero; a planar mode's minor axis is zero;
    the second bending mode's major axis changes sign at its nodal point."""
    check_png(save(rplot.plot_mode_shapes(synthetic_modes(CIRCULAR, SECOND, PLANAR), BEAM, title="synthetic"),
                   tmp_path / "m.png"))
    (fig,) = figures
    panels = fig.axes[:3]

    def curves(ax):
        return {ln.get_label(): (np.asarray(ln.get_xdata()), np.asarray(ln.get_ydata())) for ln in ax.get_lines()
                if not ln.get_label().startswith("_")}

    circ, second, planar = (curves(ax) for ax in panels)
    z, major = circ["major semi-axis"]
    np.testing.assert_allclose(major, np.sin(np.pi * z), atol=1e-3)
    _, minor = circ["minor semi-axis (+ forward, - backward)"]
    np.testing.assert_allclose(minor, major, atol=1e-3)
    for ax in panels:
        drawn = [ln for ln in ax.get_lines() if ln.get_linestyle() != "None" and len(ln.get_xdata()) > 2]
        assert drawn and all(np.max(np.abs(ln.get_ydata())) > 0.5 for ln in drawn if ax is not panels[2]
                             or not ln.get_label().startswith("minor"))
    # the second mode: the major axis is the orbit radius |sin(2 pi z)| (to the cubic interpolation's error
    # and normalisation), with the sign of the shape
    z2, major2 = second["major semi-axis"]
    np.testing.assert_allclose(np.abs(major2), np.abs(np.sin(2 * np.pi * z2)), atol=3e-3)
    assert major2[np.argmin(np.abs(z2 - 0.25))] * major2[np.argmin(np.abs(z2 - 0.75))] < 0
    _, minor_planar = planar["minor semi-axis (+ forward, - backward)"]
    np.testing.assert_allclose(minor_planar, 0.0, atol=1e-12)


# --- issue 29, item 6: plots you can use in a notebook ---------------------------------------

def _ns(**kw):
    import types

    return types.SimpleNamespace(**kw)


def _branch():
    x = np.column_stack([np.linspace(0.0, 1.0, 5), np.linspace(1.0, 2.0, 5)])
    return _ns(x=x, stop="box", dense=lambda n: x)


def _fe_identification():
    speed = np.repeat(np.linspace(100.0, 300.0, 6), 2)
    data = _ns(kind="runup", speed=speed, run=np.zeros(12, int), node=np.full(12, 2), direction=np.tile([0, 1], 6),
               X=1e-5 * np.exp(1j * speed / 100))
    return _ns(data=data, fitted=data.X * 1.01, sigma=np.full(12, 1e-7),
               critical_speeds=[{"ci95": [190.0, 210.0]}])


def _bench_report():
    pts = [{"error": 1e-3, "cost": 1e-2, "tol": "1e-6"}, {"error": 1e-6, "cost": 3e-2, "tol": "1e-9"}]
    comp = {"name": "campbell", "what": "Campbell diagram", "rotorjax": "rotorjax", "curves": {"rotorjax": pts},
            "cost_unit": "s per speed", "error_label": "relative error", "checks": {}, "skipped": []}
    return {"comparisons": [comp], "machine": {"device": "cpu", "cpu_count": 2, "platform": "linux", "jax": "0",
                                               "date": "2026-01-01"}}


S = np.linspace(0.0, 400.0, 30)
F3 = np.stack([150 - 0.1 * S, 150 + 0.1 * S, 350 + 0.05 * S], axis=1)
W = np.linspace(10.0, 600.0, 50)
H = 1e-6 / (250.0**2 - W**2 + 2j * 0.05 * 250.0 * W)
RUN = fake_run({"whirl_amplitude": np.ones(5), "weight_angles": np.zeros((5, 2)), "disk_x": np.ones(5),
                "disk_y": np.ones(5)})
PREC = _ns(ts=RUN.ts, strobe_x=np.ones(2), strobe_y=np.ones(2), Lambda=np.ones(5), mean=1.0,
           frequencies=np.arange(1.0, 6.0), spectrum=np.ones(5))
STATIC = _ns(axis="y", positions=Z, element_ends=np.stack([Z[:-1], Z[1:]], 1), displacement=np.ones((11, 2)),
             shear=np.ones((10, 2, 2)), moment=np.ones((10, 2, 2)))
FE_BALANCE = _ns(speeds=np.array([100.0, 200.0]), X0=np.array([1e-5, 2e-5]), predicted=np.array([1e-7, 2e-7]),
                 sensors=[(2, "x"), (2, "x")], corrections=[(3, 1e-3, 0.5)], method="ls")

PROPAGATION = _ns(outputs=("a", "b"), samples=np.random.default_rng(0).normal(size=(400, 2)),
                  finite=np.ones(400, bool), fosm_mean=np.zeros(2), fosm_std=np.ones(2),
                  quantiles={0.05: np.full(2, -1.64), 0.95: np.full(2, 1.64)})

DESIGN = _ns(optimum=_ns(steps=np.array([[-1.0, 0.1], [-2.0, 0.0]])),
             problem=_ns(sense=1, scales={"min-log-dec": 0.1}, objective="min-log-dec",
                         constraints=(("mass", "<=", 1),)))
_MODES = _ns(frequencies=np.tile([100.0, 300.0], (5, 1)))

#: every public drawing function of rotorjax.plot with arguments, and whether it draws on `ax=` or `fig=`
CALLS = {
    "plot_simulation": ("fig", lambda **kw: rplot.plot_simulation(RUN, title="run", **kw)),
    "plot_curves": ("ax", lambda **kw: rplot.plot_curves(S, {"a": S}, x_label="x", y_label="y", **kw)),
    "plot_periodic_branch": ("ax", lambda **kw: rplot.plot_periodic_branch(
        S, S, S < 100, [{"kind": "fold", "p": 100.0, "amplitude": 100.0}], **kw)),
    "plot_stability_map": ("ax", lambda **kw: rplot.plot_stability_map(W[:5], W[:4], np.ones((5, 4)) - 2, **kw)),
    "plot_campbell": ("ax", lambda **kw: rplot.plot_campbell(S, F3, np.ones((30, 3), bool), critical=[150.0], **kw)),
    "plot_response": ("fig", lambda **kw: rplot.plot_response(W, H, 2 * H, **kw)),
    "plot_precession": ("fig", lambda **kw: rplot.plot_precession(RUN, PREC, clearance=1.0, **kw)),
    "plot_bifurcation": ("fig", lambda **kw: rplot.plot_bifurcation([1.0, 2.0], [[0.1], [0.2]], [0.3, -0.1],
                                                                     param="n", **kw)),
    "plot_steady_regimes": ("ax", lambda **kw: rplot.plot_steady_regimes(regimes=REGIMES, title="t", **kw)),
    "plot_regime_amplitudes": ("ax", lambda **kw: rplot.plot_regime_amplitudes(regimes=MODAL, title="t", **kw)),
    "plot_margin": ("ax", lambda **kw: rplot.plot_margin(speeds=S, margin=S - 100, roots=[100.0], **kw)),
    "plot_balance": ("fig", lambda **kw: rplot.plot_balance(before=[1e-5], after=[1e-7], corrections=[2.0], **kw)),
    "plot_identification": ("fig", lambda **kw: rplot.plot_identification(speeds=W, data=H, fit=H, lo=0.9 * abs(H),
                                                                           hi=1.1 * abs(H), channels=["x1"], **kw)),
    "plot_fe_identification": ("fig", lambda **kw: rplot.plot_fe_identification(result=_fe_identification(), **kw)),
    "plot_boundaries": ("ax", lambda **kw: rplot.plot_boundaries([_branch()], [{"a": 0.5, "b": 1.5}], key="a",
                                                                 key2="b", **kw)),
    "plot_static": ("fig", lambda **kw: rplot.plot_static(STATIC, **kw)),
    "plot_mode_shapes": ("fig", lambda **kw: rplot.plot_mode_shapes(synthetic_modes(CIRCULAR, PLANAR), BEAM, **kw)),
    "plot_mode_shapes_3d": ("fig", lambda **kw: rplot.plot_mode_shapes_3d(synthetic_modes(CIRCULAR), BEAM, **kw)),
    "plot_campbell_tracked": ("ax", lambda **kw: rplot.plot_campbell_tracked(S, F3, np.full((30, 3), "forward"),
                                                                             0.1 + 0 * F3, **kw)),
    "plot_ucs": ("ax", lambda **kw: rplot.plot_ucs(np.logspace(5, 9, 20), np.logspace(2, 3, 20)[:, None], **kw)),
    "plot_bode": ("fig", lambda **kw: rplot.plot_bode(W, H, **kw)),
    "plot_nyquist": ("ax", lambda **kw: rplot.plot_nyquist(W, H, **kw)),
    "plot_deflected_shape": ("ax", lambda **kw: rplot.plot_deflected_shape(Z, Z, Z, Z, **kw)),
    "plot_level1": ("ax", lambda **kw: rplot.plot_level1(np.linspace(0, 5e7, 11), 0.3 - 1e-8 * np.linspace(0, 5e7, 11),
                                                         q0=3e7, **kw)),
    "plot_fe_balance": ("ax", lambda **kw: rplot.plot_fe_balance(result=FE_BALANCE, title="t", **kw)),
    "plot_bench": ("fig", lambda **kw: rplot.plot_bench(_bench_report(), **kw)),
    "plot_uncertainty": ("fig", lambda **kw: rplot.plot_uncertainty(result=PROPAGATION, title="t", **kw)),
    "plot_design": ("fig", lambda **kw: rplot.plot_design(design=DESIGN, title="t", **kw,
                                                          campbell=(np.linspace(0, 400, 5), _MODES, _MODES))),
    "work_precision_curve": ("ax", lambda ax: rplot.work_precision_curve(ax, [(1e-3, 1e-2, "1e-6")], "m", "o-")),
}


def _public_drawing_functions():
    return sorted(name for name, f in vars(rplot).items() if inspect.isfunction(f) and f.__module__ == rplot.__name__
                  and not name.startswith("_") and (name.startswith("plot_") or name.endswith("_curve")))


def test_an_output_the_same_in_every_sample_is_one_line(figures):
    """An undamped rotor's log decrements are 0 in every sample (`conservative`): one
    line at the value, no histogram and no first-order density (its width rounding)."""
    samples = np.column_stack([np.random.default_rng(1).normal(size=50), np.zeros(50)])
    res = _ns(outputs=("a", "log_dec_0"), samples=samples, finite=np.ones(50, bool), fosm_mean=np.zeros(2),
              fosm_std=np.array([1.0, 1e-17]), quantiles={0.05: np.zeros(2), 0.95: np.zeros(2)})
    fig = rplot.plot_uncertainty(result=res)
    figures.append(fig)
    spread, constant = fig.axes
    assert spread.patches and not constant.patches
    assert [t.get_text() for t in constant.get_legend().get_texts()] == ["every sample: 0"]
    assert constant.get_xlim() == (-1.0, 1.0)


def test_every_plot_function_is_covered():
    assert sorted(CALLS) == sorted(n for n in _public_drawing_functions() if n != "plot_frf")


@pytest.mark.parametrize("name", sorted(CALLS))
def test_draws_on_the_given_axes_or_figure(figures, name):
    """A notebook's axes (`ax=`) or figure (`fig=`): drawn on, returned, no other
    figure made; without them, a new figure is returned."""
    kind, call = CALLS[name]
    if kind == "ax":
        fig, (ax, other) = plt.subplots(1, 2, figsize=(12, 4))
        n = len(figures)
        got = call(ax=ax)
        assert got is fig and len(figures) == n
        assert ax.lines or ax.collections or ax.patches
        assert not (other.lines or other.collections or other.patches)    # the other panel left alone
    else:
        fig = plt.figure(figsize=(10, 7))
        n = len(figures)
        got = call(fig=fig)
        assert got is fig and len(figures) == n and fig.axes
    if name != "work_precision_curve":
        new = call()
        assert isinstance(new, matplotlib.figure.Figure) and new is not fig and new is figures[-1]


def test_frf_draws_on_the_given_figure_and_axes(figures):
    bode = plt.figure()
    polar_fig, polar = plt.subplots()
    n = len(figures)
    assert rplot.plot_frf(W, H, title="t", fig=bode, ax=polar) == (bode, polar_fig)
    assert len(figures) == n and len(bode.axes) == 2 and polar.lines
    made = rplot.plot_frf(W, H)
    assert made == tuple(figures[-2:])


def test_an_old_path_argument_is_not_written(tmp_path, figures):
    """The file-writing versions' calls still run: the path is ignored with a
    FutureWarning, the figure returned, nothing written."""
    with pytest.warns(FutureWarning, match="not written"):
        fig = rplot.plot_campbell(S, F3, np.ones((30, 3), bool), tmp_path / "c.png", title="old call")
    assert fig is figures[-1] and fig.axes[0].get_title() == "old call"
    with pytest.warns(FutureWarning):
        rplot.plot_steady_regimes(tmp_path / "s.png", REGIMES, "old call")
    with pytest.warns(FutureWarning):
        rplot.plot_frf(W, H, tmp_path / "b.png", tmp_path / "p.png")
    assert list(tmp_path.iterdir()) == []


def test_plot_module_chooses_no_backend_and_writes_no_file():
    """Only the CLI chooses matplotlib's backend (Agg) and saves figures."""
    source = pathlib.Path(rplot.__file__).read_text()
    for word in ("matplotlib.use", "savefig", "switch_backend", "open(", "print_figure"):
        assert word not in source, word
