"""Model 004 (preset `cantilever-limiters`): the whirl above the Hopf speed limited by
the three contact limiters, as periodic motions by harmonic balance (issue 30).

Above N_crit = 13.904 the straight shaft without unbalance (eps = 0: the field is
autonomous) whirls out until the limiters stop it. At N = 15 (smoothed contact,
regularisation length 1e-4) the long time simulation from the preset's state does
not settle: its whirl periods (between zero up-crossings of the disk's x) keep
spreading over 3.43 .. 3.56 and its radius over 0.0088 .. 0.01098 (runs to 2400 T*),
a forward whirl at the limiters. Harmonic balance (`limit_cycle`, 48 harmonics,
from one period of the run's tail) finds a whirl cycle near each such period, and
every one found is unstable: e.g.

- period 3.5213756, disk amplitude 0.0111381, a complex pair of Floquet
  multipliers |mu| = 1.2922 (angle 0.845 rad);
- period 3.5084813, amplitude 0.0109555, a real multiplier 2.244;
- period 3.4924120, amplitude 0.0106410 (grazing: within the smoothing length).

So no cycle is the attractor: the motion wanders among unstable cycles. Which one
the tail leads to depends on the tail (on the platform's round-off, over 1000 T* of
a wandering motion), so the checks hold for whichever is found:

- the balance converged with a small truncation residual; the same cycle by
  shooting (`periodic_orbit(method="shooting", autonomous=True)`) agrees (period
  1e-6, amplitude 1e-5), and its Floquet analysis along the exact orbit has the
  trivial multiplier 1 to 1e-8 (along the harmonic-balance orbit only to the
  truncation, ~7e-5 at H = 48) and a multiplier outside the unit circle;
- runs started on the cycle, moved along the unstable Floquet direction, leave it
  at the Floquet rate (their difference grows by |mu| a period);
- the precession index Lambda (`rotorjax.analysis.precession`, what the preset's
  `simulate` reports) of the cycle is 2 pi / (N T), a forward whirl of one turn a
  period, from the shooting and the harmonic-balance orbits' samples alike; the
  run's mean Lambda over its last 300 T* is forward and within 2 % of it, the
  cycle's amplitude within the run's range of radii, and the run's periods spread
  (> 0.05) about the cycle's.

The smoothing's limit (1e-5 and below, or the event-located contact) is not checked:
it needs many more harmonics, for cycles that are not the attractor.
"""

import jax
import jax.numpy as jnp
import numpy as np
import pytest
from scipy.interpolate import CubicSpline

import rotorjax as rj
from rotorjax.analysis import coefficients_from_samples, limit_cycle, orbit_amplitude, periodic_orbit, precession
from rotorjax.presets import cantilever_limiters as CL

P = CL.PRESET
N, SMOOTHING, H, NODE = 15.0, 1e-4, 48, 8        # NODE: the disk's shaft node
T_END, SAVES = 1000.0, 20                        # the long run (T*), saves per T*


@pytest.fixture(scope="module")
def scene():
    st = P.build(dict(P.defaults, eps=0.0, N=N, smoothing=SMOOTHING))
    sc = st.scene.without_work()
    return sc, jnp.asarray(st.y0[:sc.state_size])


def _disk(sc, ys):
    o = jax.vmap(lambda y: sc.outputs(0.0, y))(jnp.asarray(ys))
    return tuple(np.asarray(o[k]) for k in ("disk_x", "disk_y", "disk_vx", "disk_vy"))


def _up_crossings(ts, x):
    i = np.where((x[:-1] < 0) & (x[1:] >= 0))[0]
    return ts[i] - x[i] * (ts[i + 1] - ts[i]) / (x[i + 1] - x[i])


@pytest.fixture(scope="module")
def run(scene):
    """The long run from the preset's state (straight running, kicked)."""
    sc, y0 = scene
    ts = np.linspace(0.0, T_END, int(T_END * SAVES) + 1)
    r = rj.simulate(sc, y0, (0.0, T_END), saveat=ts, rtol=1e-9, atol=1e-12, max_steps=2_000_000)
    assert int(r.code) == 0
    return ts, np.asarray(r.ys)


@pytest.fixture(scope="module")
def cycle(scene, run):
    """The cycle by harmonic balance from a period of the run's tail (the periods
    whose end states come back closest first), and the same cycle by shooting."""
    sc, _ = scene
    ts, ys = run
    tail = ts >= T_END - 100
    tc = _up_crossings(ts[tail], _disk(sc, ys[tail])[0])
    spline = CubicSpline(ts[tail], ys[tail])
    ends = spline(tc)
    closure = np.max(np.abs(np.diff(ends, axis=0)), axis=1)
    m = 4 * H + 4
    for j in np.argsort(closure)[:8]:
        period = tc[j + 1] - tc[j]
        guess = coefficients_from_samples(spline(tc[j] + period * np.arange(m) / m), H)
        hb = limit_cycle(sc, period, guess, H, stability=False)
        if not (int(hb.code) == 0 and float(hb.time_residual) < 2e-3 and 3.4 < float(hb.period) < 3.6):
            continue
        sh = periodic_orbit(sc, hb.initial_state(), hb.period, method="shooting", autonomous=True, harmonics=H)
        if int(sh.code) == 0:
            break
    else:
        pytest.fail("no period of the run's tail led harmonic balance and shooting to a cycle")
    return hb, sh


def test_the_cycle_by_harmonic_balance_and_by_shooting(scene, cycle):
    sc, _ = scene
    hb, sh = cycle
    assert int(hb.code) == 0 and float(hb.time_residual) < 1e-3
    assert int(sh.code) == 0 and float(sh.residual) < 1e-9           # the shooting closure
    assert float(sh.period) == pytest.approx(float(hb.period), rel=1e-6)
    a_hb = float(orbit_amplitude(sc, hb.coefficients, hb.period, hb.t0, node=NODE))
    a_sh = float(orbit_amplitude(sc, sh.coefficients, sh.period, sh.t0, node=NODE))
    assert a_sh == pytest.approx(a_hb, rel=1e-5)
    assert 3.4 < float(hb.period) < 3.6                               # near 2 pi / 1.732, the whirl's
    # at the limiters (the smoothed contact acts within its regularisation length of the clearance)
    assert a_hb > P.defaults["chi"] - 2 * SMOOTHING
    # Floquet along the exact orbit: the trivial multiplier is 1, the cycle unstable
    assert abs(complex(sh.trivial_multiplier) - 1) < 1e-8
    assert not bool(sh.stable) and float(sh.margin) > 0.05


def test_a_run_started_on_the_cycle_leaves_it_at_the_floquet_rate(scene, cycle):
    """Two runs from the cycle's state moved by +-1e-9 along the unstable Floquet
    direction: their difference grows by the largest multiplier a period (the
    central difference; the state from the shooting orbit's series is itself off
    the orbit by its truncation, so the runs are compared with each other)."""
    sc, _ = scene
    _, sh = cycle
    T = float(sh.period)
    w, v = np.linalg.eig(np.asarray(sh.floquet.monodromy))
    k = int(np.argmax(np.abs(w)))
    y_star = np.asarray(sh.initial_state())
    direction = np.real(v[:, k]) / np.max(np.abs(np.real(v[:, k])))
    periods = 40
    ts = float(sh.t0) + T * np.arange(periods + 1)
    ys = [np.asarray(rj.simulate(sc, jnp.asarray(y_star + s * 1e-9 * direction), (ts[0], ts[-1]), saveat=ts,
                                 rtol=1e-11, atol=1e-14, max_steps=1_000_000).ys) for s in (1.0, -1.0)]
    diff = np.max(np.abs(ys[0] - ys[1]), axis=1)
    near = np.max(np.abs(ys[1] - y_star), axis=1)
    assert near[-1] > 1e-3                                            # both have left the cycle
    linear = (near < 1e-4) & (np.arange(ts.size) > 0)
    assert linear.sum() >= 4
    kk = np.arange(ts.size)[linear]
    rate = np.polyfit(kk, np.log(diff[linear]), 1)[0]
    assert rate == pytest.approx(np.log(abs(w[k])), rel=0.1)


def test_the_attractor_is_a_wandering_forward_whirl_around_the_cycle(scene, run, cycle):
    sc, _ = scene
    ts, ys = run
    hb, sh = cycle
    T = float(sh.period)
    # the cycle's precession index from its samples: one forward turn a period
    tt = float(sh.t0) + T * np.linspace(0.0, 1.0, 1601)
    lam_cycle = precession(tt, *_disk(sc, sh.state(tt)), N, window=(0.0, 1.0)).mean
    assert lam_cycle == pytest.approx(2 * np.pi / (N * T), rel=1e-6)
    lam_hb = precession(tt, *_disk(sc, hb.state(tt)), N, window=(0.0, 1.0)).mean
    assert lam_hb == pytest.approx(lam_cycle, rel=1e-6)
    # the run over its last 300 T*: in contact, forward, of the cycle's mean precession
    # speed and size to 2 %, but not periodic: its whirl periods spread about the cycle's
    last = ts >= T_END - 300
    x, y, vx, vy = _disk(sc, ys[last])
    prec = precession(ts[last], x, y, vx, vy, N, window=(0.0, 1.0))
    assert prec.direction == "forward"
    assert prec.mean == pytest.approx(lam_cycle, rel=0.02)
    amplitude = float(orbit_amplitude(sc, sh.coefficients, sh.period, sh.t0, node=NODE))
    radius = np.hypot(x, y)
    assert radius.min() < amplitude < 1.02 * radius.max()
    assert radius.max() > P.defaults["chi"]
    periods = np.diff(_up_crossings(ts[last], x))
    assert np.ptp(periods) > 0.05
    assert periods.min() < T < periods.max()
