"""Issue 62, validation: oil whip in finite journal bearings (Reynolds' equation in
full, `JournalBearing(model="finite")`, L/D = 0.3), by harmonic balance against a
time run: the rotor of `test_oil_whip.py` (its short films replaced, nothing else),
on which no periodic analysis was built.

- The onset (`hopf_points`) lies below 2 W_C and whirls at just under half the
  speed, as with the short films, a little higher: measured 1.787 W_C against the
  short films' 1.759 W_C (the short model's pressure, exact only as L/D -> 0,
  differs at L/D = 0.3).
- At 2.5 W_C the run (5 s from the equilibrium, the disk kicked by one clearance;
  stored in `tests/validation/data/`, made by `reference()`) settles on the whip
  cycle; `limit_cycle` (8 harmonics) from one period of its tail gives its period
  and the disk's amplitude to 1e-5 and 1e-4 (measured 6.9e-7 and 6.1e-6), stable."""

import numpy as np
import pytest
from scipy.interpolate import CubicSpline

from rotorjax.analysis import coefficients_from_samples, hopf_points, limit_cycle, orbit_amplitude
from rotorjax.models import DiskDamping, Gravity, JournalBearing

from tests.helpers import store_reference, stored_reference

from .test_oil_whip import (CLEARANCE, DIAMETER, DISK, DISK_DAMPING, G_ACC, LENGTH, VISCOSITY, W_C,
                            _run, _run_period_and_amplitude, _scene, _tail)

pytestmark = pytest.mark.slow

FINITE = (Gravity(G_ACC), JournalBearing(0, VISCOSITY, LENGTH, DIAMETER, CLEARANCE, model="finite"),
          JournalBearing(2, VISCOSITY, LENGTH, DIAMETER, CLEARANCE, model="finite"), DiskDamping(DISK, DISK_DAMPING))
SHORT_ONSET = 1.759        # W_C: test_oil_whip.py's measured onset in the short films
ONSET = 1.787              # W_C: measured here
HARMONICS = 8
REFERENCE = "oil_whip_finite_run"     # tests/validation/data/, made by `reference()`


def test_the_onset_is_later_than_the_short_films():
    """One Hopf point between 1.4 and 2.2 W_C, above the short films' (measured
    1.787 W_C), whirling at just under half the speed (measured 0.4748)."""
    (p,) = hopf_points(_scene(0.0, track_work=False, components=FINITE), 1.4 * W_C, 2.2 * W_C, n_scan=6)
    assert SHORT_ONSET * W_C < p.speed < 2.0 * W_C
    assert p.speed / W_C == pytest.approx(ONSET, abs=5e-4)          # as docs/fluid-films.md gives it
    assert 0.45 < p.frequency / p.speed < 0.5


def reference():
    """The time run (independent of harmonic balance): 5 s at 2.5 W_C from the
    equilibrium, the disk kicked by one clearance; its settled whirl's period and
    disk amplitude (the last 10 whirl periods), the journals' eccentricities over
    its last quarter, and one period of its tail as `HARMONICS` harmonics (the
    start of `limit_cycle`). Stored (`python -m tests.validation.test_oil_whip_finite`):
    the run takes about a minute."""
    sc, ts, res = _run(2.5 * W_C, 5.0, kick=CLEARANCE, components=FINITE)
    eps = np.asarray(res.outputs["journal0_eccentricity"])[_tail(ts)]
    tail = _tail(ts, 0.5)
    ts, ys = ts[tail], np.asarray(res.ys)[tail, :-1]            # the work state left out
    period, amp, tc = _run_period_and_amplitude(ts, ys)
    m = 4 * HARMONICS + 4
    guess = coefficients_from_samples(CubicSpline(ts, ys)(tc[-2] + period * np.arange(m) / m), HARMONICS)
    return dict(period=period, amplitude=amp, guess=np.asarray(guess), eps_min=eps.min(), eps_max=eps.max())


def test_the_whip_cycle_by_harmonic_balance_is_the_run_s_orbit():
    """The cycle's period and disk amplitude (~21 clearances) equal the run's settled
    orbit (`reference`: the last 10 whirl periods) to 1e-5 and 1e-4; it is stable, the trivial
    multiplier 1 to 1e-8; the journals whip at eps 0.91..0.94 (inside the finite
    film's interpolated range)."""
    speed = 2.5 * W_C
    run = stored_reference(REFERENCE)
    sc = _scene(speed, track_work=False, components=FINITE)
    sol = limit_cycle(sc, run["period"], run["guess"], HARMONICS)
    assert int(sol.code) == 0
    a = float(orbit_amplitude(sc, sol.coefficients, sol.period, sol.t0, node=DISK))
    assert float(sol.period) == pytest.approx(run["period"], rel=1e-5)
    assert a == pytest.approx(run["amplitude"], rel=1e-4) and a > 10 * CLEARANCE
    assert bool(sol.stable) and abs(complex(sol.trivial_multiplier) - 1) < 1e-8
    assert 0.9 < run["eps_min"] and run["eps_max"] < 0.95


def test_the_docs_state_these_checks():
    from tests.helpers import documentation

    text = " ".join(documentation("docs/fluid-films.md").split())
    assert "The same rotor in **finite** bearings" in text
    assert f"whirls from {ONSET} `W_C` (the short films' {SHORT_ONSET})" in text
    assert ("equals the 5 s run's settled orbit: period within 1e-5, disk amplitude within 1e-4 (measured 6.9e-7 and "
            "6.1e-6), stable, the journals at eps 0.91 to 0.94" in text)


if __name__ == "__main__":
    import jax

    jax.config.update("jax_enable_x64", True)
    store_reference(REFERENCE, reference(), "python -m tests.validation.test_oil_whip_finite")
