"""Floquet analysis, critical speeds and maps for model 001."""

import dataclasses

import equinox as eqx
import jax.numpy as jnp
import numpy as np
import pytest

import rotorjax as rj
from rotorjax.analysis import critical_speed_gradient, critical_speeds, floquet, periodic_orbit
from rotorjax.models import ConstantSpeed, RigidRotor, Scene, Supports
from rotorjax.presets import anisotropic_abb as A
from rotorjax.solve import RESULTS, code_of
from tests.helpers import central_difference

TABLE1 = dict(n_eta=7.0, mu_xi=0.25, mu_eta=0.5, sigma=0.5, c=0.5, eps=0.001, mu_w=0.25)


def test_floquet_of_a_damped_oscillator_matches_closed_form():
    """A non-rotating isotropic rotor: multipliers exp(lambda T) of
    x'' + 2 zeta w x' + w^2 x = 0, over any period."""
    m, k, c = 2.0, 50.0, 1.5
    scene = Scene(RigidRotor(m), ConstantSpeed(0.0), (Supports.isotropic(k, c),))
    period = 0.7
    r = floquet(scene, jnp.zeros(4), period)
    lam = np.roots([m, c, k])
    expected = np.sort_complex(np.exp(np.concatenate([lam, lam]) * period))
    np.testing.assert_allclose(np.sort_complex(np.asarray(r.multipliers)), expected, atol=1e-9)
    assert float(r.liouville_error) < 1e-8 and float(r.closure) == 0.0


def test_main_motion_self_checks():
    r = A.main_motion_floquet(TABLE1, 3.0)
    assert int(r.code) == code_of(RESULTS.successful) and bool(r.success)
    assert bool(r.result == RESULTS.successful)
    assert float(r.closure) < 1e-12           # the main motion is periodic (a constant state here)
    assert float(r.liouville_error) < 1e-7    # det M = exp(int tr J)
    assert bool(r.stable)


def test_a_failed_floquet_integration_carries_the_package_results_code():
    """The same `RESULTS` codes as `simulate`: a step budget too small is
    `max_steps_reached`, marked rather than raised; the result is immutable."""
    m, k, c = 2.0, 50.0, 1.5
    scene = Scene(RigidRotor(m), ConstantSpeed(0.0), (Supports.isotropic(k, c),))
    r = floquet(scene, jnp.ones(4), 0.7, max_steps=2)
    assert int(r.code) == code_of(RESULTS.max_steps_reached) and not bool(r.success)
    assert bool(r.result == RESULTS.max_steps_reached)
    with pytest.raises(dataclasses.FrozenInstanceError):
        r.code = jnp.int32(0)


def test_periodic_orbit_shooting_confirms_main_motion():
    scene = A.scene_from_groups(**TABLE1, n=3.0)
    y0 = scene.rest_state(A.main_motion_angles(2, 0.5))
    y, closure, ok = periodic_orbit(scene, y0 + 1e-3, 2 * np.pi / 3.0)
    assert ok and closure < 1e-11
    np.testing.assert_allclose(np.asarray(y), np.asarray(y0), atol=1e-9)


def test_floquet_critical_speeds_inside_paper_brackets():
    """eps = 0.001, mu_w = 0.25 (Table 1): inside 1.0-1.05, 5.0-5.05, 7.45-7.50, to 4
    significant digits across tolerances; stable between the first and second and
    above the third."""
    runs = []
    for rtol in (1e-8, 1e-10):
        cs = critical_speeds(lambda n: A.main_motion_floquet(TABLE1, n, rtol=rtol, atol=rtol * 1e-2).margin,
                             0.5, 10.0, n_scan=96)
        runs.append(cs)
    speeds = [np.array([c.speed for c in cs]) for cs in runs]
    assert len(speeds[0]) == 3
    np.testing.assert_allclose(speeds[0], speeds[1], rtol=5e-5)
    for s, (lo, hi) in zip(speeds[1], ((1.0, 1.05), (5.0, 5.05), (7.45, 7.50))):
        assert lo < s < hi
    assert [c.stable_side for c in runs[1]] == ["above", "below", "above"]


@pytest.mark.parametrize("n,stable", [(3.0, True), (6.0, False)])
def test_floquet_verdict_matches_long_simulation(n, stable):
    r = A.main_motion_floquet(TABLE1, n)
    assert bool(r.stable) == stable
    scene = A.scene_from_groups(**TABLE1, n=n)
    y0 = scene.rest_state(A.main_motion_angles(2, 0.5) + np.array([1e-4, -1e-4]))
    sim = rj.simulate(scene, y0, (0.0, 1500.0), rtol=1e-10, atol=1e-12)
    final = float(sim.outputs["residual_imbalance"][-1])
    assert (final < 1e-5) == stable


def test_criterion_roots_published():
    np.testing.assert_allclose(A.criterion_roots(7.0, 0.0, 0.0), [1.0, 5.0, 7.0], atol=1e-12)
    np.testing.assert_allclose(A.criterion_roots(7.0, 0.25, 0.5), [1.0026, 5.0407, 6.9254], atol=5e-5)


def test_no_bracket_returns_empty_list():
    assert critical_speeds(lambda n: A.main_motion_floquet(TABLE1, n).margin, 2.0, 4.0, n_scan=8) == []
    with pytest.raises(ValueError, match="increasing"):
        critical_speeds(lambda n: n, 3.0, 2.0)


def test_critical_speed_gradient_matches_finite_differences():
    """d(third critical speed)/d(mu_xi) by the implicit function theorem."""
    def margin2(n, mu_xi):
        return A.main_motion_floquet(dict(TABLE1, mu_xi=mu_xi), n).margin

    def margin_at(mu_xi, n):
        return margin2(n, mu_xi)

    def crit(mu_xi):
        # mu_xi an array leaf of the Partial: the three calls share one compilation
        cs = critical_speeds(eqx.Partial(margin_at, jnp.float64(mu_xi)), 7.3, 7.7, n_scan=5, xtol=1e-12)
        return cs[0].speed

    s = crit(0.25)
    g = critical_speed_gradient(margin2, s, 0.25)
    fd = central_difference(crit, 0.25, 1e-4)
    assert g == pytest.approx(fd, rel=1e-4)
