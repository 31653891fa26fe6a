"""Floquet analysis, critical speeds and maps for model 001."""

import dataclasses

import equinox as eqx
import jax
import jax.numpy as jnp
import numpy as np
import pytest

import rotorjax as rj
from rotorjax.analysis import (Variational, critical_speed_gradient, critical_speeds, floquet, floquet_batch,
                               floquet_of, periodic_orbit, stability_margins)
from rotorjax.analysis import _reference
from rotorjax.analysis._floquet import _augmented
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
                             0.5, 10.0, n_scan=40)
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


# --- many periodic motions at once: the variational equations as a scene, on the batch kernel (issue 32, item 4)

BATCH_SPEEDS = np.array([1.5, 3.0, 6.0, 8.0, 9.5])


def _orbit(n):
    return A.main_motion_reference(TABLE1, n, 1.0, 1e-8, 1e-10)


@pytest.fixture(scope="module")
def batch():
    orbits = eqx.filter_vmap(_orbit)(jnp.asarray(BATCH_SPEEDS))
    return orbits, floquet_batch(orbits)


def test_the_variational_scene_is_the_augmented_field():
    """The flat state (y, Phi row by row, int tr J) and its field are `monodromy`'s
    tuple state and field, element for element."""
    scene = A.scene_from_groups(**TABLE1, n=3.0)
    rng = np.random.default_rng(3)
    y, phi = jnp.asarray(rng.normal(size=8)), jnp.asarray(rng.normal(size=(8, 8)))
    var = Variational(scene)
    s = jnp.concatenate([y, phi.reshape(-1), jnp.array([0.4])])
    dy, dphi, tr = _augmented(1.3, (y, phi, None), scene)
    np.testing.assert_array_equal(var.vector_field(1.3, s), jnp.concatenate([dy, dphi.reshape(-1), tr[None]]))
    assert var.state_size == 73 and var.speed is scene.speed
    np.testing.assert_array_equal(Variational.initial_state(y), jnp.concatenate([y, jnp.eye(8).reshape(-1), jnp.zeros(1)]))
    for a, b in zip(Variational.split(s), (y, phi, 0.4)):
        np.testing.assert_array_equal(a, b)


def test_floquet_batch_equals_floquet_point_by_point(batch):
    """Each point's monodromy, margin and self-checks are `floquet`'s to the
    tolerance, the verdicts the same (stable and unstable points both present)."""
    _, r = batch
    one = jax.vmap(lambda n: floquet_of(_orbit(n)))(jnp.asarray(BATCH_SPEEDS))
    assert np.all(np.asarray(r.code) == 0) and np.all(np.asarray(one.code) == 0)
    np.testing.assert_allclose(np.asarray(r.monodromy), np.asarray(one.monodromy), atol=1e-6)
    np.testing.assert_allclose(np.asarray(r.margin), np.asarray(one.margin), atol=1e-7)
    assert np.array_equal(np.asarray(r.stable), np.asarray(one.stable))
    assert 0 < int(np.sum(np.asarray(r.stable))) < BATCH_SPEEDS.size
    assert float(np.max(r.liouville_error)) < 1e-6 and float(np.max(r.closure)) < 1e-12
    np.testing.assert_allclose(np.asarray(r.period), 2 * np.pi / BATCH_SPEEDS, rtol=1e-15)


def test_a_failed_point_of_a_batch_is_marked_and_its_margin_refused(batch, monkeypatch):
    """A step budget too small marks every point `max_steps_reached` (the same codes as
    `simulate`); `stability_margins` turns a failed point's margin into NaN, and
    equals `floquet_batch` where the points succeed."""
    orbits, r = batch
    bad = floquet_batch(orbits, max_steps=3)
    assert np.all(np.asarray(bad.code) == code_of(RESULTS.max_steps_reached))
    monkeypatch.setattr(_reference, "FLOQUET_BATCH_FROM", 1)
    m = stability_margins(lambda p: _orbit(p["n"]), {"n": BATCH_SPEEDS})
    np.testing.assert_allclose(m, np.asarray(r.margin), atol=1e-7)
    failed = jnp.array([0, 0, 1, 0, 2], dtype=jnp.int32)  # a point out of steps, one non-finite
    monkeypatch.setattr(_reference, "floquet_batch", lambda orbits: eqx.tree_at(lambda x: x.code, r, failed))
    m = stability_margins(lambda p: _orbit(p["n"]), {"n": BATCH_SPEEDS})
    assert np.array_equal(np.isnan(m), np.asarray(failed) != 0)


def test_the_c_dop853_peer_computes_the_same_margins(batch):
    """The benchmark's compiled peer (Hairer's DOP853 in C over the variational
    equations, Jacobian by complex step) gives `floquet_batch`'s margins: the two
    solve the same equations (`benchmarks/stability_map.py` times them)."""
    pytest.importorskip("numbalsoda")
    from rotorjax.bench._dop853_001 import floquet_loop
    from rotorjax.bench._model001 import Y_MAIN

    _, r = batch
    m, _, ok = floquet_loop(BATCH_SPEEDS, TABLE1["mu_w"], Y_MAIN, TABLE1, 1e-8, 1e-10)
    assert ok
    np.testing.assert_allclose(m, np.asarray(r.margin), atol=1e-7)
