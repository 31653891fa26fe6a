"""Model 004 (preset `cantilever-limiters`): the whirl above the Hopf speed limited by
the contact limiters, as a periodic motion by harmonic balance and by shooting,
smoothed and exact (issue 30).

Above N_crit = 13.904 the straight shaft without unbalance (eps = 0: the field is
autonomous) whirls out until the limiters stop it. Where the long run settles (at
N = 22, 25 and 30 with the preset's defaults; at 15-18 it wanders among unstable
cycles, found and checked unstable by the same functions, so no cycle is its
attractor) the whirl is a periodic motion with contact: at N = 25 a forward whirl
with one contact a period, on one limiter (the first; the other two give its
symmetric copies), the disk's radius 0.0036 .. 0.0149 against the clearance chi =
0.0107.

- The long run (smoothed contact, regularisation length 1e-4, 3000 T*) settles: its
  last 100 whirl periods (between up-crossings of the disk's x, on a spline of the
  saves) agree to 1e-5.
- Harmonic balance (`limit_cycle`, 96 harmonics, from one period of the run's tail)
  finds that cycle: its period is the run's to 1e-6, its disk amplitude the run's
  largest radius to 1e-3, its precession index Lambda 2 pi / (N T) (one forward turn
  a period) and the run's over whole periods to 1e-3; stable by Floquet along its
  orbit, the trivial multiplier 1 to the truncation (1e-5).
- Shooting on the same smoothed field (`periodic_orbit(method="shooting",
  autonomous=True)`) gives the same period to 1e-7, the trivial multiplier 1 to 1e-8.
- The exact model (event-located contact, `periodic_orbit(..., events=True)`:
  Newton on the event-located map, the monodromy by its central differences) has
  the cycle too, stable with the trivial multiplier 1 to rtol / fd_step (1e-7, its
  central differences' error); the exact model's own
  long run (`simulate_events`) settles onto it (period 1e-6, amplitude 1e-3), and
  the smoothed cycles converge to it as the smoothing shrinks (1e-4, 1e-5, 1e-6:
  the period's errors 5.9e-4, 2.9e-6, 2.5e-7 and the amplitude's 1.7e-3, 6.9e-6,
  6.1e-7, asserted to fall and below 2e-6 and 1e-5 at 1e-6).
"""

import inspect

import jax
import jax.numpy as jnp
import numpy as np
import pytest
from scipy.interpolate import CubicSpline
from scipy.optimize import brentq

import rotorjax as rj
from rotorjax.analysis import coefficients_from_samples, limit_cycle, orbit_amplitude, periodic_orbit, precession
from rotorjax.analysis._event_shooting import floquet_events
from rotorjax.presets import cantilever_limiters as CL
from rotorjax.solve import simulate_events

P = CL.PRESET
N, SMOOTHING, H, NODE = 25.0, 1e-4, 96, 8        # NODE: the disk's shaft node
T_END, SAVES = 3000.0, 20                        # the long run (T*), saves per T*
EXACT = dict(rtol=1e-12, atol=1e-15)             # the event-located integrations
FD_STEP = inspect.signature(floquet_events).parameters["fd_step"].default   # its monodromy's difference step


def _scene(smoothing=SMOOTHING, events=0):
    st = P.build(dict(P.defaults, eps=0.0, N=N, smoothing=smoothing, events=events))
    sc = st.scene.without_work()
    return sc, jnp.asarray(st.y0[:sc.state_size])


def _disk(sc, ys):
    o = jax.vmap(lambda y: sc.outputs(0.0, y))(jnp.asarray(ys))
    return tuple(np.asarray(o[k]) for k in ("disk_x", "disk_y", "disk_vx", "disk_vy"))


def _up_crossings(ts, x):
    """The zero up-crossings of `x`, on a cubic spline of the samples."""
    cs = CubicSpline(ts, x)
    i = np.where((x[:-1] < 0) & (x[1:] >= 0))[0]
    return np.array([brentq(cs, ts[j], ts[j + 1], xtol=1e-14) for j in i])


def _largest_radius(sc, ts, ys):
    """The largest disk radius over the samples, on a spline near the largest sample."""
    x, y, _, _ = _disk(sc, ys)
    r = np.hypot(x, y)
    k = int(np.argmax(r))
    lo, hi = max(k - 4, 0), min(k + 5, r.size)
    fine = np.linspace(ts[lo], ts[hi - 1], 4001)
    return float(np.hypot(CubicSpline(ts[lo:hi], x[lo:hi])(fine), CubicSpline(ts[lo:hi], y[lo:hi])(fine)).max())


def _cycle_samples(sc, sol, events, n=4000):
    """`n + 1` states over one period of a shot cycle, from its exact start."""
    T, t0 = float(sol.period), float(sol.t0)
    ts = t0 + T * np.arange(n + 1) / n
    if events:
        r = simulate_events(sc, sol.initial_state(), (t0, t0 + T), saveat=n + 1, **EXACT)
    else:
        r = rj.simulate(sc, sol.initial_state(), (t0, t0 + T), saveat=ts, rtol=1e-12, atol=1e-15)
    assert int(r.code) == 0
    return ts, np.asarray(r.ys)


@pytest.fixture(scope="module")
def run():
    """The long run from the preset's state (straight running, kicked), smoothed contact."""
    sc, y0 = _scene()
    ts = np.linspace(0.0, T_END, int(T_END * SAVES) + 1)
    r = rj.simulate(sc, y0, (0.0, T_END), saveat=ts, rtol=1e-9, atol=1e-12, max_steps=2_000_000)
    assert int(r.code) == 0
    ys = np.asarray(r.ys)
    tail = ts >= T_END - 400
    tc = _up_crossings(ts[tail], _disk(sc, ys[tail])[0])
    return sc, ts[tail], ys[tail], tc


@pytest.fixture(scope="module")
def hb(run):
    """The cycle by harmonic balance from one period of the run's tail."""
    sc, ts, ys, tc = run
    spline = CubicSpline(ts, ys)
    period = tc[-1] - tc[-2]
    m = 4 * H + 4
    guess = coefficients_from_samples(spline(tc[-2] + period * np.arange(m) / m), H)
    return limit_cycle(sc, period, guess, H)


@pytest.fixture(scope="module")
def shot(hb):
    """The smoothed cycles by shooting at decreasing smoothing (each from the one
    before), and the exact one by event-located shooting."""
    out = {}
    start, T = hb.initial_state(), hb.period
    for s in (SMOOTHING, 1e-5, 1e-6):
        sc, _ = _scene(smoothing=s)
        sol = periodic_orbit(sc, start, T, method="shooting", autonomous=True, harmonics=16, rtol=1e-12,
                             atol=1e-15)
        assert int(sol.code) == 0, s
        out[s] = (sc, sol)
        start, T = sol.initial_state(), sol.period
    sc, _ = _scene(events=1)
    out["exact"] = (sc, periodic_orbit(sc, start, T, method="shooting", autonomous=True, events=True,
                                       harmonics=16, **EXACT))
    return out


def test_the_long_run_settles_to_a_whirl_with_contact(run):
    sc, ts, ys, tc = run
    periods = np.diff(tc)[-100:]
    assert np.ptp(periods) < 1e-5 * periods.mean()
    x, y, _, _ = _disk(sc, ys)
    assert np.hypot(x, y).max() > P.defaults["chi"]                   # at the limiter


def test_harmonic_balance_finds_the_run_s_cycle(run, hb):
    sc, ts, ys, tc = run
    assert int(hb.code) == 0 and float(hb.time_residual) < 1e-2
    T = float(hb.period)
    assert T == pytest.approx(np.diff(tc)[-100:].mean(), rel=1e-6)
    last = ts >= tc[-11]
    a_run = _largest_radius(sc, ts[last], ys[last])
    assert float(orbit_amplitude(sc, hb.coefficients, hb.period, hb.t0, node=NODE)) == pytest.approx(a_run, rel=1e-3)
    # Lambda: one forward turn a period, from the cycle's samples and from the run over 80 whole periods
    tt = float(hb.t0) + T * np.linspace(0.0, 1.0, 1601)
    lam = precession(tt, *_disk(sc, hb.state(tt)), N, window=(0.0, 1.0))
    assert lam.direction == "forward" and lam.mean == pytest.approx(2 * np.pi / (N * T), rel=1e-6)
    whole = (ts >= tc[-81]) & (ts <= tc[-1])
    lam_run = precession(ts[whole], *_disk(sc, ys[whole]), N, window=(0.0, 1.0)).mean
    assert lam_run == pytest.approx(lam.mean, rel=1e-3)
    assert bool(hb.stable) and abs(complex(hb.trivial_multiplier) - 1) < 1e-5


def test_shooting_the_smoothed_field_gives_the_same_cycle(hb, shot):
    _, sol = shot[SMOOTHING]
    assert float(sol.residual) < 1e-10
    assert float(sol.period) == pytest.approx(float(hb.period), rel=1e-7)
    assert abs(complex(sol.trivial_multiplier) - 1) < 1e-8 and bool(sol.stable)


def test_the_exact_cycle_by_event_located_shooting(shot):
    sc, ex = shot["exact"]
    assert int(ex.code) == 0 and float(ex.residual) < 1e-10
    # the trivial multiplier is 1 to the monodromy's central differences: two integrations, each to rtol, differenced
    # over fd_step of each state, err <= rtol / fd_step = 1e-7 (measured 1.8e-8, 5.3e-8 and below 1e-8 on three
    # machines; a missing saltation matrix would put it off by O(1))
    assert abs(complex(ex.trivial_multiplier) - 1) < EXACT["rtol"] / FD_STEP and bool(ex.stable)
    T = float(ex.period)
    ts, ys = _cycle_samples(sc, ex, events=True)
    lam = precession(ts, *_disk(sc, ys), N, window=(0.0, 1.0)).mean
    assert lam == pytest.approx(2 * np.pi / (N * T), rel=1e-6)
    # the exact model's own long run, from the smoothed run's start, settles onto it
    _, y0 = _scene()
    t_end = 300.0
    r = simulate_events(sc, y0, (0.0, t_end), saveat=int(t_end * SAVES) + 1, rtol=1e-10, atol=1e-13,
                        max_steps=200_000)
    assert int(r.code) == 0
    tr, yr = np.asarray(r.ts), np.asarray(r.ys)
    tail = tr >= t_end - 60
    tc = _up_crossings(tr[tail], _disk(sc, yr[tail])[0])
    assert np.diff(tc)[-10:].mean() == pytest.approx(T, rel=1e-6)
    a_exact = _largest_radius(sc, ts, ys)
    assert _largest_radius(sc, tr[tail], yr[tail]) == pytest.approx(a_exact, rel=1e-3)


def test_the_smoothed_cycles_converge_to_the_exact_one(shot):
    sc, ex = shot["exact"]
    T = float(ex.period)
    a = _largest_radius(sc, *_cycle_samples(sc, ex, events=True))
    errors = []
    for s in (SMOOTHING, 1e-5, 1e-6):
        scs, sol = shot[s]
        errors.append((abs(float(sol.period) / T - 1), abs(_largest_radius(scs, *_cycle_samples(scs, sol, False)) / a - 1)))
    errors = np.array(errors)
    assert np.all(np.diff(errors, axis=0) < 0)                        # both fall with the smoothing
    assert errors[-1, 0] < 2e-6 and errors[-1, 1] < 1e-5
