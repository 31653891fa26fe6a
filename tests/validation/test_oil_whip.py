"""Validation: oil whirl and oil whip in time, on a small flexible rotor in two short
(Ocvirk, pi-film) journal bearings.

**The rotor** (one layout for the whole file): a steel shaft (d = 30 mm) of two
Euler-Bernoulli elements of 0.4 m, a 10 kg disk at mid-span with light viscous
damping (`DiskDamping`, 50 N s/m: ~1 % of critical in the first bending mode),
5 kg journal masses at both ends, in short journal bearings (D = 50 mm, L = 15 mm,
c = 150 um, mu = 0.1 Pa s), gravity along -y. The journal masses slow the
fastest decay (the film's squeeze damping over the journal's mass), which sets the
explicit integrator's step; the disk damping bounds the whip's orbit (without it
the orbit was still growing after 2 s at 2.5 W_C, the journals past eps 0.94, the
steps ever shorter).

Its first critical speed on rigid supports (journals pinned), `W_C` = 254.45 rad/s,
gives the classic picture:
- the oil-whirl onset `w_th` (`hopf_points`, ~1.76 W_C) is below 2 W_C, the
  whirl there at 0.484 times the speed (just under half, the film-supported first
  mode at ~0.85 W_C: the films are soft at the equilibrium, eps ~ 0.49);
- the Hopf point is subcritical (the cycles born there exist below it, unstable):
  above it the whirl jumps to a large orbit;
- above ~2 W_C the whirl is whip: its frequency stays near the first natural
  frequency, not at half the speed.

Each test is described in its docstring; measured values are in the comments next to
the tolerances.

The cycle born at the onset (`hopf_cycle`, subcritical) and the whip cycle
(`limit_cycle` from the run) are joined by `limit_cycle_branch` (6 harmonics):
down from the onset to a fold at 0.962 w_th, then up, stable, to the whip speed,
where it ends on the run's cycle; runs on either side of the fold show the
hysteresis it predicts.

Runtime ~80 s on a 2-core machine (no compilation cache): every run is one
compiled program (`simulate` with the speed, the end time and the initial state as
arrays, the same number of saves and the same scene layout with `track_work=True`),
so runs cost their steps only.
"""

import jax.numpy as jnp
import numpy as np
import pytest
import scipy.linalg
from scipy.interpolate import CubicSpline

import rotorjax as rj
from rotorjax.analysis import (coefficients_from_samples, hill_exponents, hopf_cycle, hopf_points, limit_cycle,
                               limit_cycle_branch, orbit_amplitude)
from rotorjax.models import DiskDamping, FlexibleRotor, Gravity, JournalBearing, RotorScene, static_equilibrium

# ------------------------------------------------------------------------------- the rotor
G_ACC = 9.81
VISCOSITY, LENGTH, DIAMETER, CLEARANCE = 0.1, 0.015, 0.05, 1.5e-4     # each bearing: L/D = 0.3
DISK, DISK_DAMPING = 1, 50.0
_SHAFT = dict(lengths=[0.4, 0.4], d_out=0.03, theory="euler-bernoulli", disks=((DISK, 10.0, 0.01, 0.02),),
              point_masses=((0, 5.0), (2, 5.0)))
ROTOR = FlexibleRotor(**_SHAFT)
COMPONENTS = (Gravity(G_ACC), JournalBearing(0, VISCOSITY, LENGTH, DIAMETER, CLEARANCE),
              JournalBearing(2, VISCOSITY, LENGTH, DIAMETER, CLEARANCE), DiskDamping(DISK, DISK_DAMPING))


def _first_critical_on_rigid_supports():
    """The lowest natural frequency with the journals' x, y held (the shaft's bending
    on pinned supports; the disk at mid-span has no gyroscopic coupling in it)."""
    rig = FlexibleRotor(**_SHAFT, fixed_dofs=((0, 0), (0, 1), (2, 0), (2, 1)))
    M, _, _, K = (np.asarray(a) for a in rig.reduced_matrices(0.0))
    return float(np.sqrt(scipy.linalg.eigh(K, M, eigvals_only=True)[0]))


W_C = _first_critical_on_rigid_supports()
#: every run saves this many states (one compiled program for all of them)
N_SAVE = 12001
RUN = dict(solver="dopri8", rtol=1e-9, atol=1e-14, max_steps=500_000)


def _scene(speed, track_work=True, components=COMPONENTS):
    """The rotor at constant `speed` (an array: one compiled program for all speeds)."""
    return RotorScene(ROTOR, jnp.asarray(speed, dtype=jnp.float64), components, track_work=track_work)


def _equilibrium_state(scene, speed):
    eq = static_equilibrium(scene, jnp.asarray(speed, dtype=jnp.float64))
    assert bool(eq.converged)
    return jnp.zeros(scene.state_size).at[:scene.n_dof].set(eq.q)


def _run(speed, t_end, kick=0.01 * CLEARANCE, y0=None, components=COMPONENTS):
    """A constant-speed run from the equilibrium with the disk displaced by `kick`
    along x (or from `y0`)."""
    sc = _scene(speed, components=components)
    if y0 is None:
        y0 = _equilibrium_state(sc, speed).at[4 * DISK].add(kick)
    ts = jnp.linspace(0.0, t_end, N_SAVE)
    res = rj.simulate(sc, y0, (jnp.float64(0.0), jnp.asarray(t_end, dtype=jnp.float64)), saveat=ts, **RUN)
    assert int(res.code) == 0, res.stats
    return sc, np.asarray(ts), res


def _disk(res):
    return np.asarray(res.outputs["node_x"])[:, DISK], np.asarray(res.outputs["node_y"])[:, DISK]


def _up_crossings(ts, x):
    """Zero up-crossings of `x` (linear interpolation between samples)."""
    i = np.where((x[:-1] < 0) & (x[1:] >= 0))[0]
    return ts[i] - x[i] * (ts[i + 1] - ts[i]) / (x[i + 1] - x[i])


def _whirl_frequency(ts, x):
    """The whirl frequency (rad/s) of `x` about its mean, from its zero up-crossings."""
    tc = _up_crossings(ts, x - x.mean())
    return 2 * np.pi * (len(tc) - 1) / (tc[-1] - tc[0])


@pytest.fixture(scope="module")
def onset():
    """The oil-whirl onset: one Hopf point between 1.6 and 1.9 W_C."""
    (p,) = hopf_points(_scene(0.0, track_work=False), 1.6 * W_C, 1.9 * W_C, n_scan=4)
    return p


# --------------------------------------------------------------------------------- the tests
def test_the_classic_picture(onset):
    """The onset is below 2 W_C (measured 1.759 W_C = 447.61 rad/s, W_C = 254.45
    rad/s) and whirls at just under half the speed (measured 0.4840)."""
    assert 1.6 * W_C < onset.speed < 1.9 * W_C
    assert 0.45 < onset.frequency / onset.speed < 0.5


#: the growth is measured over this many whirl periods (of the onset's frequency),
#: between windows of WINDOW periods at the start (after the kick's other modes have
#: decayed) and at the end
N_PERIODS, WINDOW, SKIP = 40, 4, 6


def _orbit_growth(onset, ratio):
    """`(measured, linear)`: the growth factor of the disk's orbit about the
    equilibrium from the first window to the last, and `exp(Re lambda dt)` of the
    linearisation at that speed."""
    speed = ratio * onset.speed
    period = 2 * np.pi / onset.frequency
    sc, ts, res = _run(speed, N_PERIODS * period)
    eq = np.asarray(sc.expand(static_equilibrium(sc, jnp.float64(speed)).q))[4 * DISK:4 * DISK + 2]
    x, y = _disk(res)
    r = np.hypot(x - eq[0], y - eq[1])
    first = (ts >= SKIP * period) & (ts < (SKIP + WINDOW) * period)
    last = ts >= (N_PERIODS - WINDOW) * period
    lam = np.linalg.eigvals(np.asarray(sc.linear_matrices(jnp.float64(speed)).state_matrix()))
    return r[last].max() / r[first].max(), np.exp(lam.real.max() * (N_PERIODS - WINDOW - SKIP) * period)


@pytest.mark.parametrize("ratio", [0.98, 1.02])
def test_whirl_starts_at_the_computed_onset(onset, ratio):
    """Constant-speed runs from the equilibrium (the disk kicked by 1 % of the
    clearance) at 2 % below and above the onset: over 30 whirl periods (between
    windows of 4) the orbit about the equilibrium shrinks below (measured factor
    0.6241) and grows above (1.5781), at the linearisation's rate (`exp(Re lambda
    t)`: 0.6216 and 1.5832; the logarithms agree to 0.9 % and 0.7 %)."""
    growth, linear = _orbit_growth(onset, ratio)
    assert (growth < 1) if ratio < 1 else (growth > 1)
    assert np.log(growth) == pytest.approx(np.log(linear), rel=0.02)


WHIP = (2.5, 3.0)            # speeds / W_C
#: run lengths (s): the one at 2.5 W_C settles onto the cycle (its Floquet margin -2.4 / s)
WHIP_T = {2.5: 5.0, 3.0: 2.0}


@pytest.fixture(scope="module")
def whip():
    """Runs at 2.5 and 3 W_C (1.42 and 1.71 w_th) from the equilibrium, the disk
    kicked by one clearance, 5 s and 2 s: the whirl grows and settles on the whip
    orbit (journals at eps 0.89..0.91 and 0.87..0.88, the disk at ~22 clearances)."""
    out = {}
    for r in WHIP:
        speed = r * W_C
        out[r] = _run(speed, WHIP_T[r], kick=CLEARANCE)
    return out


def _tail(ts, frac=0.75):
    return ts >= frac * ts[-1]


def test_whip_locks_near_the_first_natural_frequency(whip):
    """Above 2 W_C the settled whirl's frequency (zero crossings of the disk's x over
    the last quarter of the run) stays near the first natural frequency instead of
    following half the speed: measured 0.9788 W_C at 2.5 W_C and 0.9819 W_C at 3 W_C
    (whirl ratios 0.392 and 0.327; half the speed would be 1.25 and 1.5 W_C). The
    natural frequency it locks to is the first mode's with the journals at the whip
    orbit's eccentricity (~0.9): there the films
    are far stiffer than at the equilibrium (where the linearised whirl mode is at
    0.85 W_C), nearly rigid supports, so the whip runs just under W_C."""
    freq = {}
    for r, (sc, ts, res) in whip.items():
        tail = _tail(ts)
        x, _ = _disk(res)
        f = _whirl_frequency(ts[tail], x[tail])
        freq[r] = f
        assert f == pytest.approx(W_C, rel=0.05)
        assert f / (r * W_C) < 0.42                    # clearly not half the speed
        eps = np.asarray(res.outputs["journal0_eccentricity"])[tail]
    # locked: the speed moves by 20 %, the whirl frequency by 0.3 %
    assert freq[3.0] == pytest.approx(freq[2.5], rel=0.01)


def test_energy_balance_through_the_whip(whip):
    """`track_work`: over the run at 2.5 W_C (from the equilibrium through the growth
    into whip) `energy(y(t)) - energy(y(0)) - W(t)` stays at the integration's
    tolerance relative to the energy scale (measured 2.1e-10 at rtol 1e-9; the energy
    scale 7.6 J)."""
    sc, ts, res = whip[2.5]
    e, w = np.asarray(res.outputs["energy"]), np.asarray(res.outputs["work"])
    resid = np.max(np.abs(e - e[0] - w)) / np.max(np.abs(e))
    assert resid < 1e-8


def test_drop_into_the_bearing_reaches_high_eccentricity():
    """A low-speed drop: the rotor released from the bearings' centres at 0.05 W_C
    falls under its weight into the films; the journals reach eps ~ 0.95 (measured
    0.9637 after 0.5 s, still sinking slowly: the squeeze film) and the run stays
    finite."""
    speed = 0.003 * W_C
    sc = _scene(speed)
    _, ts, res = _run(speed, 0.5, y0=jnp.zeros(sc.state_size))
    eps = np.asarray(res.outputs["journal0_eccentricity"])
    assert np.all(np.isfinite(np.asarray(res.ys)))
    assert 0.94 < eps.max() < 1.0


HARMONICS = 8


def _run_period_and_amplitude(ts, ys, n_last=10):
    """The run's whirl period (mean of its last `n_last` periods between up-crossings
    of the disk's x, on a spline of the saves) and the disk's largest radius over
    them (the spline sampled densely)."""
    x_spline = CubicSpline(ts, ys[:, 4 * DISK])
    y_spline = CubicSpline(ts, ys[:, 4 * DISK + 1])
    x = ys[:, 4 * DISK]
    tc = _up_crossings(ts, x - x.mean())[-(n_last + 1):]
    fine = np.linspace(tc[0], tc[-1], 200 * n_last + 1)
    return (tc[-1] - tc[0]) / n_last, float(np.hypot(x_spline(fine), y_spline(fine)).max()), tc


@pytest.fixture(scope="module")
def cycle(whip):
    """The whip cycle at 2.5 W_C by harmonic balance (`limit_cycle`, 8 harmonics),
    from one period of the run's tail."""
    sc, ts, res = whip[2.5]
    tail = _tail(ts, 0.5)
    ts, ys = ts[tail], np.asarray(res.ys)[tail, :-1]          # the work state left out
    period, _, tc = _run_period_and_amplitude(ts, ys)
    m = 4 * HARMONICS + 4
    guess = coefficients_from_samples(CubicSpline(ts, ys)(tc[-2] + period * np.arange(m) / m), HARMONICS)
    return limit_cycle(sc.without_work(), period, guess, HARMONICS), (ts, ys)


def test_whip_cycle_by_harmonic_balance_is_the_run_s_orbit(cycle):
    """The cycle's period and disk amplitude (its largest radius, 3.28 mm = 21.9 c)
    equal the run's settled orbit (the last 10 whirl periods of the 5 s run: measured
    5.3e-7 and 8.1e-6 relative), and it is stable (Floquet: margin -2.43 / s, the
    trivial multiplier 1 to 3e-11)."""
    sol, (ts, ys) = cycle
    assert int(sol.code) == 0
    period, amp, _ = _run_period_and_amplitude(ts, ys)
    sc = _scene(2.5 * W_C, track_work=False)
    a = float(orbit_amplitude(sc, sol.coefficients, sol.period, sol.t0, node=DISK))
    assert float(sol.period) == pytest.approx(period, rel=5e-6)
    assert a == pytest.approx(amp, rel=1e-4)
    assert bool(sol.stable) and abs(complex(sol.trivial_multiplier) - 1) < 1e-8


def _scene_at(speed):
    return RotorScene(ROTOR, speed, COMPONENTS)


@pytest.fixture(scope="module")
def hopf(onset):
    """`hopf_cycle` at the onset, in the speed relative to it (6 harmonics, a
    small cycle: first-harmonic amplitude 1e-3 m/s in the largest state of the
    critical eigenvector, ~1e-3 of the whip's)."""
    sc = _scene(onset.speed, track_work=False)
    y_eq = _equilibrium_state(sc, onset.speed)
    return hopf_cycle(lambda r: _scene_at(r * onset.speed), 1.0, y_eq, 1e-3, harmonics=6, stability=False)


def test_the_onset_is_a_subcritical_hopf_point(onset, hopf):
    """The cycle at the onset lives below it (subcritical: the speed falls as the
    amplitude squared, measured -3.4e-6 relative) at the critical eigenvalue's
    period. So above the onset there is no small whirl: the runs above jump to the
    large orbit."""
    p, sol = hopf
    shift = float(p) - 1
    assert -1e-5 < shift < -1e-6
    assert float(sol.period) == pytest.approx(2 * np.pi / onset.frequency, rel=1e-5)


@pytest.fixture(scope="module")
def whirl_branch(onset, hopf):
    """The limit cycles from the onset to the whip speed (2.5 W_C = 1.4212 w_th),
    by `limit_cycle_branch` from `hopf`, downwards first (154 points, ~25 s)."""
    p, sol = hopf
    top = 2.5 * W_C / onset.speed
    br, coefs, periods = limit_cycle_branch(lambda r: _scene_at(r * onset.speed), float(p), sol, (0.9, top),
                                            direction=-1, ds=0.02, ds_max=100.0, max_points=400)
    return br, coefs, periods, top


def test_the_whirl_branch_joins_the_onset_to_the_whip_cycle(onset, whirl_branch, cycle):
    """From the Hopf point the branch runs down in speed, unstable (the subcritical
    cycles: the margin between equilibrium and whip), to a fold at 0.9624 w_th
    (= 1.692 W_C); there it turns and rises, stable, to the whip speed, where it
    lands and ends on the whip cycle found from the 5 s run (period and disk
    amplitude: measured 6e-15 and 2.8e-7 relative, 6 harmonics against 8), with the
    run's cycle's Floquet margin (Hill's exponents along the branch: -2.4332 / s,
    the time-domain Floquet margin of the cycle: equal to 5e-10). Near 0.9886 w_th the branch has
    a narrow S (two more folds 1.6e-4 apart) whose place moves with the
    harmonics (0.9896 with 8): not asserted."""
    br, coefs, periods, top = whirl_branch
    sol, _ = cycle
    assert br.stops == ("start", f"box edge (p = {top!r})")
    folds = sorted(e.p for e in br.events if e.kind == "fold")
    assert 0.95 < folds[0] < 0.975 and all(f > 0.985 for f in folds[1:])
    assert not [e for e in br.events if e.kind not in ("fold",)]
    turn = int(np.argmin(br.p))
    assert not br.stable[1:turn - 1].any()                 # the cycles born at the onset: unstable
    upper = np.arange(br.p.size) > turn
    assert br.stable[upper & ((br.p < 0.985) | (br.p > 0.995))].all()
    sc = _scene(2.5 * W_C, track_work=False)
    assert periods[-1] == pytest.approx(float(sol.period), rel=1e-10)
    amp = float(orbit_amplitude(sc, coefs[-1], periods[-1], 0.0, node=DISK))
    assert amp == pytest.approx(float(orbit_amplitude(sc, sol.coefficients, sol.period, sol.t0, node=DISK)),
                                rel=1e-5)
    assert float(br.margin[-1]) == pytest.approx(float(sol.margin), rel=1e-7)


def test_hill_exponents_of_the_whip_cycle_are_floquet_s(cycle):
    """Hill's exponents of the whip cycle (8 harmonics, 24 states: the flexible
    rotor's higher modes lie above (H + 1/2) w, and the journals' film damping at
    eps 0.9 is stiff and strongly modulated) equal the time-domain Floquet
    exponents: the six least damped to 1e-7 relative (measured 4.7e-10; the trivial
    one 5e-13 and 1e-9)."""
    sol, _ = cycle
    sc = _scene(2.5 * W_C, track_work=False)
    hill = np.sort(np.asarray(hill_exponents(sc, sol)).real)[::-1][:6]
    flo = np.sort(np.asarray(sol.floquet.exponents).real)[::-1][:6]
    np.testing.assert_allclose(hill[1:], flo[1:], rtol=1e-7)
    assert abs(hill[0]) < 1e-6 and abs(flo[0]) < 1e-6               # the trivial one


def _cycle_state(coefs):
    """The state at t = 0 of a cycle's coefficients, with the work state 0."""
    return jnp.asarray(np.concatenate([coefs[0] + coefs[1::2].sum(axis=0), [0.0]]))


def _radius(sc, speed, res):
    """The disk's distance from its equilibrium, in clearances."""
    eq = np.asarray(sc.expand(static_equilibrium(sc, jnp.float64(speed)).q))[4 * DISK:4 * DISK + 2]
    x, y = _disk(res)
    return np.hypot(x - eq[0], y - eq[1]) / CLEARANCE


def test_hysteresis_the_whirl_persists_down_to_the_fold(onset, whirl_branch):
    """Runs from the branch's cycles: on the stable upper part at 0.972 w_th (below
    the onset, where the equilibrium is stable too) the orbit stays for 0.5 s
    (about 17 whirl periods) at its amplitude (the largest distance from the
    equilibrium over the first and the last tenth of the run: 2.226 and 2.220
    clearances); below the fold, at 0.95 w_th, started from the fold's cycle, there
    is no cycle to hold it and the orbit decays (1.80 to 0.72 clearances in 1.5 s,
    every tenth of the run smaller than the one before)."""
    br, coefs, periods, _ = whirl_branch
    turn = int(np.argmin(br.p))
    i = turn + int(np.argmin(np.abs(br.p[turn:] - 0.972)))
    speed = br.p[i] * onset.speed
    sc, ts, res = _run(speed, 0.5, y0=_cycle_state(coefs[i]))
    r = _radius(sc, speed, res)
    n = r.size // 10
    assert r[:n].max() > 2 and r[-n:].max() == pytest.approx(r[:n].max(), rel=1e-2)
    speed = 0.95 * onset.speed
    sc, ts, res = _run(speed, 1.5, y0=_cycle_state(coefs[turn]))
    peaks = _radius(sc, speed, res)[:10 * n].reshape(10, n).max(axis=1)
    assert np.all(np.diff(peaks) < 0) and peaks[-1] < 0.5 * peaks[0]
