"""Secondary bifurcations of periodic motions on `periodic_branch`: period
doubling, switching onto the doubled branch (`period_doubling_start`), and
Neimark-Sacker points, each against Floquet's multipliers from the integrated
variational equations (`rotorjax.analysis.floquet`), not Hill's method.

- A parametrically excited Duffing oscillator `x'' + C x' + (1 + EPS cos(om t)) x
  + BETA x^3 = 0`: its rest `x = 0` is a periodic motion of every period; it loses
  stability across the first Mathieu tongue near `om = 2` by period doubling (a
  multiplier through -1), where a motion of twice the period is born.
- A forced van der Pol oscillator `x'' - MU (1 - x^2) x' + x = F cos(om t)`: the
  entrained motion loses its stability on both sides of the locking band to a
  quasi-periodic motion, through a pair of complex multipliers leaving the unit
  circle (Neimark-Sacker)."""

import jax.numpy as jnp
import numpy as np
import pytest
from scipy.optimize import brentq

from rotorjax.analysis import floquet, harmonic_balance, hill_exponents, period_doubling_start, periodic_branch
from rotorjax.models import AbstractScene, ConstantSpeed

C, EPS, BETA = 0.05, 0.3, 1.0
MU, F = 0.2, 0.3


class Mathieu(AbstractScene):
    speed: ConstantSpeed

    def __init__(self, om):
        self.speed = ConstantSpeed(om)

    @property
    def state_size(self):
        return 2

    def vector_field(self, t, y, args=None):
        x, v = y
        return jnp.stack([v, -C * v - (1 + EPS * jnp.cos(self.speed.constant * t)) * x - BETA * x**3])

    def outputs(self, t, y):
        return {"x": y[0]}

    def describe(self):
        return "parametrically excited Duffing oscillator"


class ForcedVanDerPol(AbstractScene):
    speed: ConstantSpeed

    def __init__(self, om):
        self.speed = ConstantSpeed(om)

    @property
    def state_size(self):
        return 2

    def vector_field(self, t, y, args=None):
        x, v = y
        return jnp.stack([v, MU * (1 - x * x) * v - x + F * jnp.cos(self.speed.constant * t)])

    def outputs(self, t, y):
        return {"x": y[0]}

    def describe(self):
        return "forced van der Pol oscillator"


@pytest.fixture(scope="module")
def rest_branch():
    return periodic_branch(Mathieu, 1.5, jnp.zeros(2), (1.5, 2.5), harmonics=6, scale=1.0, ds=0.05, ds_max=0.1)


def rest_multiplier_plus_one(om):
    """The rest's (real) multiplier nearest -1, plus 1: linear Mathieu, integrated."""
    mu = np.asarray(floquet(Mathieu(om), jnp.zeros(2), 2 * np.pi / om, rtol=1e-12, atol=1e-14).multipliers)
    return float(mu[np.argmin(np.abs(mu + 1))].real + 1)


def test_period_doubling_points_are_floquets_multiplier_through_minus_one(rest_branch):
    br, _ = rest_branch
    assert [e.kind for e in br.events] == ["period-doubling", "period-doubling"]
    for e in br.events:
        exact = brentq(rest_multiplier_plus_one, e.p - 0.02, e.p + 0.02, xtol=1e-13)
        assert abs(e.p - exact) < 1e-6
        assert abs(e.frequency - e.p / 2) < 1e-8            # half the motion's frequency
    p = np.asarray(br.p)
    lo, hi = (e.p for e in br.events)
    assert np.array_equal(np.asarray(br.stable), (p < lo) | (p > hi))   # unstable inside the tongue


def test_switching_onto_the_doubled_branch(rest_branch):
    br, coefs = rest_branch
    pd = br.events[0]
    p, start = period_doubling_start(Mathieu, pd.p, np.asarray(pd.u).reshape(coefs.shape[1:]), 0.05)
    T = 2 * np.pi / float(p)
    assert abs(float(start.period) - 2 * T) < 1e-12 and float(start.floquet.closure) < 1e-9
    # a motion of period 2T, not T
    y0, yT = np.asarray(start.state(0.0)), np.asarray(start.state(T))
    assert np.max(np.abs(yT - y0)) > 1e-2
    br2, c2 = periodic_branch(Mathieu, float(p), start, (1.5, 1.95), harmonics=12, subharmonic=2, ds=0.05,
                              ds_max=0.2, max_points=60, switch=True)
    # one end falls back onto the rest at the period-doubling point: the doubled problem's branch point
    # (a pitchfork: the rest is a branch of the doubled problem too), where the tangent turns back in p
    # but the bordered determinant changes sign -- a branch point, not a fold; the other end grows
    back = [e for e in br2.events if e.kind in ("fold", "branch_point")]
    assert [e.kind for e in back] == ["branch_point"] and abs(back[0].p - pd.p) < 1e-8
    # switched there (switch=True): the branch crossing it is the rest, a motion of every period, traced over the
    # whole range, stable outside the tongue only (its multipliers over 2T the squares of those over T)
    rest, c_rest = back[0].switched
    assert rest.stops == ("box edge (p = 1.5)", "box edge (p = 1.95)")
    assert np.max(np.abs(c_rest)) < 1e-10 and c_rest.shape[1:] == c2.shape[1:]
    q = np.asarray(rest.p)
    np.testing.assert_array_equal(np.asarray(rest.stable)[np.abs(q - pd.p) > 1e-3], q[np.abs(q - pd.p) > 1e-3] < pd.p)
    far = int(np.argmax(np.asarray(br2.p)))
    s = harmonic_balance(Mathieu(float(br2.p[far])), 4 * np.pi / float(br2.p[far]), c2[far], harmonics=12)
    assert int(s.code) == 0 and float(s.floquet.closure) < 1e-8
    assert abs(float(br2.margin[far]) - float(s.floquet.margin)) < 1e-6
    assert bool(br2.stable[far]) == bool(s.stable)


def test_the_docs_state_the_switched_rest():
    from tests.helpers import documentation

    text = " ".join(documentation("docs/periodic.md").split())
    assert ("the branch switched onto there is the rest, zero to 1e-10 over the whole range, stable outside the "
            "Mathieu tongue only" in text)


@pytest.fixture(scope="module")
def entrained():
    guess = jnp.array([[0.0, 0.0], [1.5, 0.0], [0.0, -1.5]])
    s0 = harmonic_balance(ForcedVanDerPol(1.0), 2 * np.pi, guess, harmonics=12)
    br, coefs = periodic_branch(ForcedVanDerPol, 1.0, s0, (0.5, 1.5), harmonics=12, ds=0.05, ds_max=0.1)
    return s0, br, coefs


def test_neimark_sacker_points_are_floquets_pair_through_the_unit_circle(entrained):
    s0, br, coefs = entrained
    assert bool(s0.stable)
    ns = [e for e in br.events if e.kind == "neimark-sacker"]
    assert len(ns) == 2 and len(br.events) == 2
    for e in ns:
        i = int(np.argmin(np.abs(np.asarray(br.p) - e.p)))

        def orbit(om):
            return harmonic_balance(ForcedVanDerPol(om), 2 * np.pi / om, coefs[i], harmonics=12, rtol=1e-12,
                                    atol=1e-14)

        def modulus_minus_one(om):
            return float(np.max(np.abs(np.asarray(orbit(om).floquet.multipliers)))) - 1

        exact = brentq(modulus_minus_one, e.p - 0.01, e.p + 0.01, xtol=1e-13)
        assert abs(e.p - exact) < 1e-6
        mu = np.asarray(orbit(exact).floquet.multipliers)
        assert np.all(np.abs(mu.imag) > 0.1)                                 # a complex pair
        angle = np.abs(np.angle(mu[0]))
        assert abs(e.frequency - angle * exact / (2 * np.pi)) < 1e-6         # the pair's frequency
        # Hill's exponents at the refined point: the pair on the axis
        s = np.asarray(hill_exponents(ForcedVanDerPol(e.p), orbit(e.p)))
        assert np.max(np.abs(s.real)) < 1e-6
    p = np.asarray(br.p)
    lo, hi = sorted(e.p for e in ns)
    assert np.array_equal(np.asarray(br.stable), (p > lo) & (p < hi))        # stable inside the locking band


#: the whirl's frequency against the forcing's: within `PERIOD_DOUBLING_TOL` of a half, as oil whirl's is
NU = 0.4997


class HalfSpeedWhirl(AbstractScene):
    """A forced linear oscillator `x'' + C x' + x = F cos t` (the synchronous motion) and a whirl mode
    `y'' + (C - a) y' + NU^2 y = 0` whose damping the parameter `a` takes away: at `a = C` a complex pair of
    multipliers `exp(+-i 2 pi NU)`, near -1 but not real, leaves the unit circle."""

    speed: ConstantSpeed
    a: float

    def __init__(self, a):
        self.speed, self.a = ConstantSpeed(1.0), a

    @property
    def state_size(self):
        return 4

    def vector_field(self, t, y, args=None):
        x, v, z, w = y
        return jnp.stack([v, -C * v - x + F * jnp.cos(t), w, -(C - self.a) * w - NU**2 * z])

    def outputs(self, t, y):
        return {"x": y[0]}

    def describe(self):
        return "forced oscillator with a whirl mode at about half its frequency"


def test_a_pair_near_minus_one_is_a_neimark_sacker_point_not_a_period_doubling():
    """A whirl at about half the forcing frequency (oil whirl on a synchronous branch): two exponents cross,
    a Neimark-Sacker point at a = C with the whirl's frequency, however near half the forcing frequency
    (the former rule, the frequency alone within 1e-3 of a half, called it a period doubling)."""
    br, _ = periodic_branch(HalfSpeedWhirl, 0.013, jnp.zeros(4), (0.013, 0.1), harmonics=2, scale=1.0, ds=0.02,
                            ds_max=0.05)
    (e,) = br.events
    assert e.kind == "neimark-sacker" and e.crossing == 2 and e.as_dict()["crossing"] == 2
    assert abs(e.p - C) < 1e-8 and abs(e.frequency - NU) < 1e-8
    p = np.asarray(br.p)
    assert np.array_equal(np.asarray(br.stable), p < e.p)
