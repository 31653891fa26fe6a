"""Limit cycles of autonomous scenes by harmonic balance (`limit_cycle`,
`hopf_cycle`, `limit_cycle_branch`): the period unknown, closed by a phase
condition.

- The Hopf normal form in Cartesian coordinates, `r' = mu r + a r^3 - c r^5`,
  `theta' = om + b r^2`, has its cycles in closed form: `mu + a r^2 - c r^4 = 0`,
  period `2 pi / (om + b r^2)`, the non-trivial multiplier
  `exp((mu + 3 a r^2 - 5 c r^4) T)`. Supercritical (`a = -1, c = 0`): the branch
  born at the Hopf point `mu = 0` has `r = sqrt(mu)`. Subcritical (`a = 1, c = 1`):
  it bends back to a fold of cycles at `mu = -1/4`, `r^2 = 1/2`, unstable below,
  stable above.
- Van der Pol's oscillator at `mu = 1`, started from a time simulation: its period
  6.6632868593231301 (the literature value, e.g. Ellison & Sáenz's series; any
  high-accuracy shooting agrees), a closed orbit under time integration, and the
  trivial Floquet multiplier 1 to 1e-8.
- The derivative of a cycle's period with respect to a parameter by the implicit
  function theorem against the closed form and finite differences."""

import equinox as eqx
import jax
import jax.numpy as jnp
import numpy as np
import pytest

import rotorjax
from rotorjax.analysis import (HopfPoint, branch_amplitude, coefficients_from_samples, hill_exponents, hopf_cycle,
                               hopf_cycle_branch, limit_cycle,
                               limit_cycle_branch, periodic_orbit)
from rotorjax.models import AbstractScene, ConstantSpeed
from rotorjax.solve import RESULTS, code_of

OM, B = 1.3, 0.4


class NormalForm(AbstractScene):
    """The Hopf normal form; autonomous (the speed only carries `om`)."""

    speed: ConstantSpeed
    mu: jax.Array
    a: float = eqx.field(static=True)
    c: float = eqx.field(static=True)

    def __init__(self, mu, a=-1.0, c=0.0):
        self.speed = ConstantSpeed(OM)
        self.mu = jnp.asarray(mu, dtype=jnp.float64)
        self.a, self.c = a, c

    @property
    def state_size(self):
        return 2

    def vector_field(self, t, y, args=None):
        x, v = y
        r2 = x * x + v * v
        g = self.mu + self.a * r2 - self.c * r2 * r2
        h = self.speed.constant + B * r2
        return jnp.stack([g * x - h * v, h * x + g * v])

    def outputs(self, t, y):
        return {"whirl_amplitude": jnp.hypot(y[0], y[1])}

    def describe(self):
        return f"Hopf normal form at mu = {float(self.mu):g}"


class VanDerPol(AbstractScene):
    speed: ConstantSpeed
    mu: jax.Array

    def __init__(self, mu):
        self.speed = ConstantSpeed(0.0)
        self.mu = jnp.asarray(mu, dtype=jnp.float64)

    @property
    def state_size(self):
        return 2

    def vector_field(self, t, y, args=None):
        x, v = y
        return jnp.stack([v, self.mu * (1 - x * x) * v - x])

    def outputs(self, t, y):
        return {"x": y[0]}

    def describe(self):
        return f"van der Pol at mu = {float(self.mu):g}"


VDP_PERIOD = 6.6632868593231301896996820305


def radius(Y):
    return np.hypot(Y[..., 1, 0], Y[..., 2, 0])


@pytest.fixture(scope="module")
def supercritical():
    p, start = hopf_cycle(NormalForm, 0.0, jnp.zeros(2), 0.1, harmonics=4)
    br, coefs, periods = limit_cycle_branch(NormalForm, float(p), start, (0.0, 1.0), direction=1, ds=0.05)
    return p, start, br, coefs, periods


def test_hopf_start_is_the_closed_form_cycle(supercritical):
    p, start, *_ = supercritical
    assert int(start.code) == 0
    assert abs(float(p) - 0.01) < 1e-12                                  # r^2 = mu
    T = 2 * np.pi / (OM + B * 0.01)
    assert abs(float(start.period) - T) < 1e-12
    assert abs(complex(start.trivial_multiplier) - 1) < 1e-8
    other = np.sort(np.abs(np.asarray(start.floquet.multipliers)))[0]
    assert abs(other - np.exp(-2 * 0.01 * T)) < 1e-8
    assert bool(start.stable) and abs(float(start.margin) + 0.02) < 1e-8


def test_supercritical_branch_follows_sqrt_mu(supercritical):
    _, _, br, coefs, periods = supercritical
    mu = np.asarray(br.p)
    assert br.stops[-1] == "box edge (p = 1.0)"
    assert np.max(np.abs(radius(coefs) - np.sqrt(mu))) < 1e-8
    assert np.max(np.abs(periods - 2 * np.pi / (OM + B * mu))) < 1e-8
    assert np.max(np.abs(np.asarray(br.margin) + 2 * mu)) < 1e-6         # Hill's, the trivial exponent left out
    assert bool(np.all(br.stable)) and not br.events


def test_subcritical_branch_folds_where_the_closed_form_says():
    def scene_at(mu):
        return NormalForm(mu, a=1.0, c=1.0)

    p, start = hopf_cycle(scene_at, 0.0, jnp.zeros(2), 0.1, harmonics=3)
    r2 = 0.01
    assert abs(float(p) - (r2 * r2 - r2)) < 1e-12                       # mu = r^4 - r^2 < 0: subcritical
    assert not bool(start.stable)
    br, coefs, _ = limit_cycle_branch(scene_at, float(p), start, (-0.5, 0.2), direction=-1, ds=0.02)
    folds = [e for e in br.events if e.kind == "fold"]
    assert len(folds) == 1
    assert abs(folds[0].p + 0.25) < 1e-8
    Yf = np.asarray(folds[0].u).reshape(coefs.shape[1:])
    assert abs(radius(Yf) ** 2 - 0.5) < 1e-6
    r = radius(coefs)
    assert np.array_equal(np.asarray(br.stable), r ** 2 > 0.5)             # stable beyond the fold
    assert br.stops[-1] == "box edge (p = 0.2)"


@pytest.mark.parametrize("a, c", [(-1.0, 0.0), (1.0, 1.0)])
def test_hopf_cycle_branch_from_the_hopf_point_in_closed_form(a, c):
    """`hopf_cycle_branch` (what `rotorjax periodic --from-hopf` runs) on the normal
    form shifted to its Hopf point at p = 2 (mu = p - 2): supercritical, the cycles
    r^2 = mu above it to the range's top; subcritical, below it through the fold of
    cycles at mu = -1/4 (r^2 = 1/2) and back up to the range's top. The radii,
    periods and the fold against the closed forms; each cycle's amplitude
    (`branch_amplitude` at the branch's own periods) is its radius."""
    def scene_at(p):
        return NormalForm(p - 2.0, a=a, c=c)

    hopf = HopfPoint(speed=2.0, frequency=OM, slope=1.0, margin_at_speed=0.0)
    br, coefs, periods, p_first = hopf_cycle_branch(scene_at, hopf, jnp.zeros(2), (1.5, 2.5), harmonics=4,
                                                    amplitude=0.1, ds_max=0.2)
    mu, r = np.asarray(br.p) - 2.0, radius(coefs)
    assert abs(p_first - 2.0 - (-a * 0.1**2 + c * 0.1**4)) < 1e-12      # r = 0.1: mu = -a r^2 + c r^4
    assert (p_first > 2.0) == (a < 0)                                   # the side of the first cycle: criticality
    assert br.stops[0] == "start" and br.stops[1] == "box edge (p = 2.5)"
    assert np.max(np.abs(mu + a * r**2 - c * r**4)) < 1e-9
    assert np.max(np.abs(periods - 2 * np.pi / (OM + B * r**2))) < 1e-9
    folds = [e for e in br.events if e.kind == "fold"]
    if a > 0:
        assert len(folds) == 1 and abs(folds[0].p - 1.75) < 1e-8 and folds[0].note is None
        assert np.array_equal(np.asarray(br.stable), r**2 > 0.5)
    else:
        assert not folds and bool(np.all(br.stable))
    amp = branch_amplitude(scene_at, br.p, coefs, periods=periods)
    assert np.max(np.abs(amp - r)) < 1e-9


@pytest.fixture(scope="module")
def vdp():
    scene = VanDerPol(1.0)
    T_guess = 6.5
    ts = np.linspace(60.0, 60.0 + T_guess, 65)[:-1]
    res = rotorjax.simulate(scene, jnp.array([2.0, 0.0]), (0.0, ts[-1]), saveat=ts, rtol=1e-8, atol=1e-10)
    guess = coefficients_from_samples(res.ys, 8)
    return scene, limit_cycle(scene, T_guess, guess, harmonics=40, rtol=1e-12, atol=1e-12)


def test_van_der_pol_cycle_from_a_simulation(vdp):
    scene, sol = vdp
    assert int(sol.code) == 0 and float(sol.time_residual) < 1e-9
    assert abs(float(sol.period) - VDP_PERIOD) < 1e-9
    assert float(sol.floquet.closure) < 1e-8                             # closed under time integration
    assert abs(complex(sol.trivial_multiplier) - 1) < 1e-8
    assert bool(sol.stable)
    # Hill's non-trivial exponent equals Floquet's
    s = np.asarray(hill_exponents(scene, sol))
    s_other = s[np.argmax(np.abs(s))]
    mu = np.asarray(sol.floquet.multipliers)
    mu_other = mu[np.argmin(np.abs(mu))]
    assert abs(s_other.real - np.log(abs(mu_other)) / float(sol.period)) < 1e-6


def test_van_der_pol_cycle_by_shooting_with_unknown_period(vdp):
    """`periodic_orbit(..., method="shooting", autonomous=True)`: Newton on the
    closure and the period with a phase condition; the same cycle."""
    scene, hb = vdp
    sh = periodic_orbit(scene, jnp.array([2.0, 0.0]), 6.6, method="shooting", autonomous=True, harmonics=40,
                        rtol=1e-12, atol=1e-12)
    assert int(sh.code) == 0 and abs(float(sh.period) - VDP_PERIOD) < 1e-9
    assert abs(complex(sh.trivial_multiplier) - 1) < 1e-8 and bool(sh.stable)
    # the same orbit: the harmonic balance's passes through the shooting's start
    ts = np.linspace(0.0, float(hb.period), 100_001)
    d = np.min(np.linalg.norm(np.asarray(hb.state(ts)) - np.asarray(sh.initial_state()), axis=1))
    assert d < 2e-4   # the grid's resolution (speeds up to 2.7)


def test_a_guess_without_motion_is_refused():
    """From a cycle 1e3 times too small Newton falls onto the equilibrium (every
    period balances it): reported, not returned as a cycle."""
    scene = NormalForm(0.25)
    guess = jnp.zeros((3, 2)).at[1, 0].set(1e-3)
    sol = limit_cycle(scene, 2 * np.pi / OM, guess, harmonics=4, stability=False)
    if int(sol.code) == 0:   # Newton may also climb to the cycle: then it must be the cycle
        assert abs(radius(np.asarray(sol.coefficients)) - 0.5) < 1e-8
    else:
        assert int(sol.code) == code_of(RESULTS.root_not_converged)


def test_period_gradient_by_the_implicit_function_theorem(supercritical):
    _, _, br, coefs, periods = supercritical
    mu = 0.3
    i = int(np.argmin(np.abs(np.asarray(br.p) - mu)))
    guess = coefs[i]

    def solve(m):
        return limit_cycle(NormalForm(m), periods[i], guess, harmonics=4, stability=False)

    assert int(solve(mu).code) == 0

    def period(m):
        return solve(m).period

    d = float(jax.grad(period)(mu))
    closed = -2 * np.pi * B / (OM + B * mu) ** 2
    h = 1e-5
    fd = (float(period(mu + h)) - float(period(mu - h))) / (2 * h)
    assert abs(d - closed) < 1e-9 and abs(fd - closed) < 1e-7


def test_the_trivial_exponent_is_removed_and_a_split_pair_at_a_fold_merged():
    """`limit_cycle_branch`'s exponents less the trivial one: a real exponent at 0
    is removed; near a fold of cycles, where the trivial exponent and the crossing
    one are a complex pair `a +- i b` split by the truncation (no exponent at 0),
    the pair becomes their sum `2a` (real), not a Neimark-Sacker pair; a genuine
    pair away from 0 stays."""
    from rotorjax.analysis._limit_cycles import _nontrivial

    e = np.array([-3.0, 1e-12, 0.2 + 0.05j, 0.2 - 0.05j, -1.0 + 2.0j, -1.0 - 2.0j])
    np.testing.assert_array_equal(_nontrivial(e, 10.0), np.delete(e, 1))
    split = np.array([-3.0, 0.01 + 0.003j, 0.01 - 0.003j, -1.0 + 2.0j, -1.0 - 2.0j])
    np.testing.assert_allclose(_nontrivial(split, 10.0), [-3.0, 0.02, -1.0 + 2.0j, -1.0 - 2.0j])
    far = np.array([-5.0, 0.5 + 3.0j, 0.5 - 3.0j])       # nearest 0, but far from it: not merged
    assert len(_nontrivial(far, 10.0)) == 2 and np.iscomplex(_nontrivial(far, 10.0)).any()
