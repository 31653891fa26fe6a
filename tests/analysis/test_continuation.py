"""Continuation: branches with folds and Hopf points, fold curves, stability
boundaries of models 001 and 004, batched boundary solves, bad input; curves in
closed form traced both ways to the box edges, closed loops, and every stop reason;
every boundary in a box, and the dense curve between points against the exact one."""

import dataclasses
import functools

import equinox as eqx
import jax
import jax.numpy as jnp
import numpy as np
import pytest

from rotorjax.analysis import (Boundaries, BoundaryCrossing, Branch, BranchEvent, Curve, FloquetCrossing,
                               boundary_points, boundary_sensitivity, continue_branch, critical_speeds,
                               floquet_crossings, fold_curve, hopf_points, trace_boundaries, trace_boundary,
                               trace_curve)
from rotorjax.solve import RESULTS, code_of
from rotorjax.presets import anisotropic_abb as ab
from rotorjax.presets import cantilever_limiters as cl
from rotorjax.analysis import linear_margin, state_matrix

W0, C, BETA = 1.0, 0.05, 0.2


def duffing(u, om, f):
    """Harmonic balance of x'' + c x' + w0^2 x + beta x^3 = f cos(om t), x = p cos + q sin."""
    p, q = u[0], u[1]
    A = p * p + q * q
    d = W0**2 - om**2
    return jnp.stack([d * p + C * om * q + 0.75 * BETA * A * p - f, d * q - C * om * p + 0.75 * BETA * A * q])


def duffing_fold_forcing(om):
    """The fold curve in closed form: with y = d + 3/4 beta A, folds of
    A[(d + 3/4 beta A)^2 + c^2 om^2] = f^2 satisfy 3 y^2 - 2 d y + c^2 om^2 = 0."""
    d = W0**2 - om**2
    out = []
    for s in (1, -1):
        y = (d + s * np.sqrt(d * d - 3 * C * C * om * om)) / 3
        A = (y - d) / (0.75 * BETA)
        if A > 0:
            out.append(np.sqrt(A * (y * y + C * C * om * om)))
    return out


def test_duffing_branch_folds_and_fold_curve_match_the_closed_form():
    f0 = 0.05
    u0 = np.array([0.06653383, 0.00221583])
    from rotorjax._newton import newton
    u0, _ = newton(lambda u: duffing(u, 0.5, f0), jnp.asarray(u0), 1e-12, 30, unit=1.0)
    br = continue_branch(lambda u, om: duffing(u, om, f0), u0, 0.5, p_bounds=(0.5, 2.0), ds=0.02, ds_max=0.05,
                         max_points=400)
    folds = [e for e in br.events if e.kind == "fold"]
    # traced both ways from the box's lower edge: that end stops at once, the other lands on p = 2
    assert len(folds) == 2 and br.stops == ("box edge (p = 0.5)", "box edge (p = 2.0)")
    assert br.curve.start == 0 and br.p[-1] == 2.0
    assert all(list(e.as_dict()) == ["kind", "p", "u", "residual", "between"] for e in folds)
    for e in folds:
        assert e.residual < 1e-12
        assert min(abs(f0 / v - 1) for v in duffing_fold_forcing(e.p)) < 1e-9
    fc = fold_curve(duffing, folds[0].u, (folds[0].p, f0), ds=0.01, ds_max=0.05, max_points=60,
                    bounds=(np.array([np.nan, np.nan, 0.8, 0.005]), np.array([np.nan, np.nan, 2.0, 0.2])))
    assert fc.x.shape[0] > 20 and fc.residuals.max() < 1e-12
    err = max(min(abs(x[3] / v - 1) for v in duffing_fold_forcing(x[2])) for x in fc.x)
    assert err < 1e-8


@pytest.mark.parametrize("z, r, why", [
    (np.array([np.nan, 1.2]), np.nan, "a non-finite iterate"),
    (np.array([0.5, 1.2]), 3e-2, "residual 3.0e-02 > 1e-08"),
    (np.array([0.5, 9.0]), 1e-14, "it left the step"),
    (np.array([0.9, 1.05]), 1e-14, "it left the step"),
])
def test_a_fold_whose_refinement_fails_is_located_to_the_step_never_nan(z, r, why):
    """A fold's Newton on its defining system that diverges (non-finite), stalls
    (residual above the branch's gtol) or runs off the step is not reported as
    refined: the fold is placed at the step's midpoint with the points' residual and
    a note (it was printed as `fold at speed = nan` before; issue 62)."""
    from rotorjax.analysis._continuation import _refined_event

    a, b = np.array([0.4, 1.0]), np.array([0.6, 1.1])
    e = _refined_event(z, r, a, b, 1, (3, 4), 1e-8, 2e-10)
    assert (e.kind, e.p, e.residual, e.between) == ("fold", 1.05, 2e-10, (3, 4))
    assert np.allclose(e.u, [0.5]) and np.all(np.isfinite(e.u))
    assert e.note == f"located to the step; not refined (Newton on the fold's defining system: {why})"
    assert e.as_dict()["note"] == e.note
    refined = _refined_event(np.array([0.51, 1.04]), 1e-14, a, b, 1, (3, 4), 1e-8, 2e-10)
    assert (refined.p, refined.residual, refined.note) == (1.04, 1e-14, None)


def test_fold_system_jacobian_equals_differentiating_the_jacobian():
    """The fold refinement's Jacobian (`G`'s and the bordered test function's
    gradient `-w^T (G_u)_z v`, by n + 1 directional derivatives) equals forward
    differentiation of the whole fold system (the (n + 1)^2-evaluation way it
    replaced), on a random nonlinear G at a random point (measured 1.4e-14); its
    value is `[G; bordered_fold(G_u)]`."""
    from rotorjax.analysis._continuation import _fold_system, bordered_fold

    rng = np.random.default_rng(0)
    M = jnp.asarray(rng.normal(size=(5, 6)))

    def G(z):
        return jnp.tanh(M @ z) + 0.3 * z[:5] ** 3 * z[5]

    z, b, c = (jnp.asarray(rng.normal(size=k)) for k in (6, 5, 5))
    value, jacobian = _fold_system(G, z, b, c)
    want = jax.jacfwd(lambda x: _fold_system(G, x, b, c)[0])(z)
    np.testing.assert_allclose(jacobian, want, atol=1e-12 * float(jnp.max(jnp.abs(want))))
    np.testing.assert_allclose(value, jnp.concatenate([G(z), bordered_fold(jax.jacfwd(G)(z)[:, :5], b, c)[None]]),
                               rtol=1e-13, atol=1e-15)


def test_corrector_accepts_at_the_rounding_floor_of_a_noisy_system():
    """A curve whose second equation is a difference of terms of 1e12 (rounding
    noise ~5e-11 in it, as a balance of a stiff flexible rotor's first-order form
    has, condition ~1e12): Newton's steps stall at that floor, above `tol`. The
    corrector accepts a step that stops contracting within 1e3 tol, so the steps
    grow to `ds_max` (before: every point took all 8 iterations and halved the
    step, and the branch crept to a standstill)."""
    def G(x):
        big = 1e6 + x[2]
        return jnp.stack([x[0] ** 2 + x[1] ** 2 - 1.0, (big * big - 1e12 - 2e6 * x[0]) / 2e6])

    x0 = np.array([1.0, 0.0, 1.0 - 0.5e-6])
    cv = trace_curve(G, x0, ds=0.01, ds_max=0.1, max_points=30, tol=1e-13, direction=np.array([0.0, 1.0, 0.0]),
                     start_tol=1e-8, gtol=1e-8)
    assert cv.steps.max() == pytest.approx(0.1) and np.median(cv.iterations[1:]) <= 4


def brusselator(u, b, a=1.0):
    x, y = u[0], u[1]
    return jnp.stack([a - (b + 1) * x + x * x * y, b * x - x * x * y])


def test_hopf_point_of_the_brusselator():
    """Equilibrium (a, b/a); Hopf at b = 1 + a^2 with frequency a."""
    br = continue_branch(brusselator, np.array([1.0, 1.0]), 1.0, p_bounds=(1.0, 3.0), ds=0.05, ds_max=0.1)
    (h,) = [e for e in br.events if e.kind == "hopf"]
    assert h.p == pytest.approx(2.0, abs=1e-9) and h.frequency == pytest.approx(1.0, abs=1e-8)
    # an event is a frozen row; its JSON row keeps the former dict's keys, in their order, and then how many
    # eigenvalues cross (a pair)
    assert isinstance(h, BranchEvent) and h.note is None and h.between[1] == h.between[0] + 1
    row = h.as_dict()
    assert list(row) == ["kind", "p", "u", "frequency", "residual", "between", "crossing"] and h.crossing == 2
    assert row["u"] == h.u.tolist() and row["between"] == list(h.between) and row["p"] == h.p
    assert br.as_dict()["events"] == [e.as_dict() for e in br.events]
    with pytest.raises(dataclasses.FrozenInstanceError):
        h.p = 0.0
    with pytest.warns(DeprecationWarning, match=r"BranchEvent\['kind'\]"):
        assert h["kind"] == "hopf" and h["u"] is h.u
    assert "frequency" in h and "note" not in h
    assert bool(br.stable[0]) and not bool(br.stable[-1])
    np.testing.assert_allclose(br.u[:, 1], br.p, rtol=1e-10)      # the branch is (1, b)
    # results are frozen data: a changed branch is a new one
    assert isinstance(br, Branch) and isinstance(br.curve, Curve) and isinstance(br.events, tuple)
    with pytest.raises(dataclasses.FrozenInstanceError):
        br.p = br.p * 2
    with pytest.raises(dataclasses.FrozenInstanceError):
        br.curve.stopped = "changed"
    moved = dataclasses.replace(br, p=br.p * 2)
    np.testing.assert_array_equal(moved.p, 2 * br.p)
    assert moved.events is br.events and moved.curve is br.curve


BASE = dict(cl.PRESET.defaults)


def rotor(ratio, mu=BASE["mu_R"]):
    return cl.build_rotor(dict(BASE, eta_i=BASE["eta_e"] / ratio, mu_R=mu))


def state_matrix_of(ratio, mu=BASE["mu_R"]):
    """`A(N)` of straight-line rotation of `rotor(ratio, mu)`."""
    return functools.partial(state_matrix, rotor(ratio, mu))


def test_model_004_hopf_curve_matches_pointwise_solves_and_its_sensitivity():
    curve = trace_boundary(lambda N, r: linear_margin(rotor(r), N), (4.0, 1.0),
                           bounds=(np.array([0.5, 0.5]), np.array([30.0, 4.0])), ds=0.2, ds_max=1.0,
                           direction=(0.0, 1.0), tol=1e-10)
    assert curve.stopped == "box edge (p2 = 4.0)" and curve.x.shape[0] >= 8 and curve.x[-1, 1] == 4.0
    assert curve.stops[0] == "start" and np.all(curve.x[0] == curve.x[curve.start])
    for N, r in curve.x[::3]:
        h = hopf_points(state_matrix_of(r), N - 0.5, N + 0.5, n_scan=5, xtol=1e-13)[0]
        assert abs(h.speed - N) < 1e-8 * N
    # sensitivity of the boundary (N at fixed ratio) to the shaft/disk mass ratio,
    # i.e. to the disk mass M through mu_R = m_R l / M
    N, r = curve.x[4]
    s = boundary_sensitivity(lambda N, r, mu: linear_margin(rotor(r, mu), N), (N, r), BASE["mu_R"])

    def n_crit(mu):
        return hopf_points(state_matrix_of(r, mu), N - 0.5, N + 0.5, n_scan=5, xtol=1e-13)[0].speed
    h = 1e-3
    assert s == pytest.approx((n_crit(BASE["mu_R"] + h) - n_crit(BASE["mu_R"] - h)) / (2 * h), rel=1e-6)


def test_batched_boundary_points_equal_the_traced_curve():
    ratios = jnp.array([1.0, 2.0, 3.0, 4.0])
    sigma = lambda N, r: linear_margin(rotor(r), N)  # noqa: E731
    N, res = boundary_points(sigma, 2.47 * ratios + 1.8, ratios)
    assert float(jnp.max(res)) < 1e-9
    for n, r in zip(np.asarray(N), np.asarray(ratios)):
        assert abs(hopf_points(state_matrix_of(r), n - 0.5, n + 0.5, n_scan=5, xtol=1e-13)[0].speed - n) < 1e-8 * n


P001 = dict(ab.PRESET.defaults)
G001 = {k: P001[k] for k in ab.GROUPS}


def margin_001(n, mu):
    return ab.main_motion_floquet(dict(G001, mu_w=mu), n, P001["K"]).margin


def margin_001_at(mu, n):
    return margin_001(n, mu)


def test_model_001_floquet_crossings_and_boundary_through_the_critical_speeds():
    found = floquet_crossings(lambda n: ab.main_motion_floquet(G001, n, P001["K"]), 4.0, 6.0, n_scan=6)
    assert isinstance(found, tuple)
    (c,) = found
    assert isinstance(c, FloquetCrossing)
    assert c.kind == "complex pair" and c.residual < 1e-9 and c.closure < 1e-10
    assert c.code == code_of(RESULTS.successful) and c.stable_side in ("above", "below")
    assert abs(np.hypot(*c.multiplier) - 1) < 1e-9
    # the JSON row (the CLI's): the former dict's keys, the code added; and read-only
    row = c.as_dict()
    assert set(row) == {"p", "kind", "multiplier", "residual", "closure", "liouville_error", "stable_side", "code"}
    assert row["multiplier"] == list(c.multiplier) and c["p"] == c.p
    with pytest.raises(dataclasses.FrozenInstanceError):
        c.p = 0.0
    curve = trace_boundary(margin_001, (c.p, G001["mu_w"]), bounds=(np.array([0.5, 0.3]), np.array([10.0, 0.8])),
                           ds=0.05, ds_max=0.1, gradient="fd", max_points=8, direction=(0.0, 1.0), tol=1e-10)
    assert curve.residuals.max() < 1e-9
    for n, mu in curve.x[[1, -1]]:
        # mu an array leaf of the Partial: the scan and the bisection compile once for both points
        (cs,) = critical_speeds(eqx.Partial(margin_001_at, jnp.float64(mu)), n - 0.05, n + 0.05, n_scan=4,
                                xtol=1e-12)
        assert abs(cs.speed - n) < 1e-6


def test_bad_starts_and_boxes():
    with pytest.raises(ValueError, match=r"not on the curve: residual 2.000e\+00"):
        continue_branch(brusselator, np.array([2.0, 1.0]), 1.0)
    with pytest.raises(ValueError, match="outside the bounds"):
        continue_branch(brusselator, np.array([1.0, 1.0]), 1.0, p_bounds=(1.5, 3.0))
    br = continue_branch(brusselator, np.array([1.0, 1.0]), 1.0, p_bounds=(0.5, 1.3), ds=0.05)
    assert br.stopped == "low end: box edge (p = 0.5); high end: box edge (p = 1.3)"
    assert br.p[0] == 0.5 and br.p[-1] == 1.3 and np.all(np.diff(br.p) > 0)
    with pytest.raises(ValueError, match="empty box"):
        trace_curve(circle, [1.0, 0.0], bounds=([0.0, 0.5], [2.0, -0.5]))


# curves in closed form


def circle(x):
    return jnp.atleast_1d(x[0] ** 2 + x[1] ** 2 - 1.0)


def parabola(x):            # x = y^2: a turning point in x at the origin, curvature 2 there
    return jnp.atleast_1d(x[0] - x[1] ** 2)


def chord_turns(x):
    d = np.diff(x, axis=0)
    d /= np.linalg.norm(d, axis=1, keepdims=True)
    return np.arccos(np.clip(np.sum(d[1:] * d[:-1], axis=1), -1.0, 1.0))


def test_circle_traced_both_ways_lands_on_both_box_edges():
    """From (1, 0) inside the box y in [-0.5, 0.8]: the arc from (sqrt(3)/2, -0.5) to (0.6, 0.8), in order,
    the start once; with a lower bound on x instead, the upper end lands on x = 0.3."""
    c = trace_curve(circle, [1.0, 0.0], bounds=(np.array([np.nan, -0.5]), np.array([np.nan, 0.8])), ds=0.05,
                    names=("x", "y"))
    assert c.stops == ("box edge (y = -0.5)", "box edge (y = 0.8)")
    assert c.stopped == "low end: box edge (y = -0.5); high end: box edge (y = 0.8)"
    np.testing.assert_allclose(c.x[0], [np.sqrt(0.75), -0.5], atol=1e-8)
    np.testing.assert_allclose(c.x[-1], [0.6, 0.8], atol=1e-8)
    np.testing.assert_array_equal(c.x[c.start], [1.0, 0.0])
    angle = np.arctan2(c.x[:, 1], c.x[:, 0])
    assert np.all(np.diff(angle) > 0) and c.residuals.max() < 1e-12
    assert c.steps[0] == 0 and np.all(c.steps[1:] > 0) and c.x.shape[0] == c.steps.size
    c = trace_curve(circle, [1.0, 0.0], bounds=(np.array([0.3, -0.5]), np.array([np.nan, np.nan])), ds=0.05,
                    ds_max=0.5, names=("x", "y"))
    assert c.stops == ("box edge (y = -0.5)", "box edge (x = 0.3)")
    np.testing.assert_allclose(c.x[-1], [0.3, np.sqrt(1 - 0.09)], atol=1e-8)
    # one way: the start is the first point, the old behaviour
    c = trace_curve(circle, [1.0, 0.0], bounds=(np.array([np.nan, -0.5]), np.array([np.nan, 0.8])), ds=0.05,
                    direction=(0.0, -1.0), names=("x", "y"))
    assert c.stops == ("start", "box edge (y = -0.5)") and c.stopped == "box edge (y = -0.5)"
    assert c.start == 0 and c.x[-1, 1] == -0.5


def test_parabola_through_its_turning_point_to_both_edges_without_kinks():
    """x = y^2 from (1, 1) in x <= 2: both ends on x = 2 (y = -+sqrt 2); through the turning point the
    chord turns at most about max_turn per point although ds_max allows 0.4 rad there."""
    c = trace_curve(parabola, [1.0, 1.0], bounds=(np.array([np.nan, np.nan]), np.array([2.0, np.nan])),
                    ds=0.1, ds_max=0.2, names=("x", "y"))
    assert c.stops == ("box edge (x = 2.0)", "box edge (x = 2.0)")
    np.testing.assert_allclose(c.x[[0, -1]], [[2.0, -np.sqrt(2)], [2.0, np.sqrt(2)]], atol=1e-8)
    assert np.all(np.diff(c.x[:, 1]) > 0) and c.residuals.max() < 1e-12
    assert chord_turns(c.x).max() < 0.25
    assert c.steps[np.argmin(np.abs(c.x[:, 1]))] < 0.15      # shorter steps at the turning point


def test_compiled_core_runs_a_branch_without_python_per_point_and_matches_the_driver(monkeypatch):
    """The compiled core (`_arclength.march`) traces a curve in calls of up to CHUNK points, not one per
    point, and gives the NumPy driver's curve (gradient="fd", the loop it replaces for JAX functions): the
    same stops, points on the circle to the same tolerance, as many of them, the same error estimates."""
    from rotorjax.analysis import _arclength

    calls = []
    march = _arclength.march

    def counted(*a):
        calls.append(1)
        return march(*a)

    monkeypatch.setattr(_arclength, "march", counted)
    box = (np.array([-0.5, -2.0]), np.array([2.0, 2.0]))
    fast = trace_curve(circle, [1.0, 0.0], bounds=box, ds=0.002, ds_max=0.01, max_points=2000)
    assert fast.x.shape[0] > 3 * _arclength.CHUNK
    assert len(calls) <= 2 * (fast.x.shape[0] // _arclength.CHUNK + 2)       # calls per chunk, not per point
    slow = trace_curve(circle, [1.0, 0.0], bounds=box, ds=0.002, ds_max=0.01, max_points=2000, gradient="fd")
    assert fast.stops == slow.stops == ("box edge (x[0] = -0.5)", "box edge (x[0] = -0.5)")
    for c in (fast, slow):
        assert np.abs(np.hypot(c.x[:, 0], c.x[:, 1]) - 1.0).max() < 1e-10
        np.testing.assert_allclose(np.abs(c.x[[0, -1], 1]), np.sqrt(0.75), rtol=1e-10)
    assert abs(fast.x.shape[0] - slow.x.shape[0]) <= 0.02 * slow.x.shape[0]     # measured: 425 both
    # the interpolation error estimates (the dense curve's distance from the circle at each midpoint) agree
    np.testing.assert_allclose(np.median(fast.errors[1:]), np.median(slow.errors[1:]), rtol=1e-2)


def test_closed_loop_inside_the_box_and_max_points():
    c = trace_curve(circle, [1.0, 0.0], bounds=(np.array([-2.0, -2.0]), np.array([2.0, 2.0])), ds=0.05)
    assert c.stopped == "closed loop" and c.stops == ("closed loop", "closed loop")
    np.testing.assert_array_equal(c.x[0], c.x[-1])
    angle = np.unwrap(np.arctan2(c.x[:, 1], c.x[:, 0]))
    assert angle[-1] - angle[0] == pytest.approx(2 * np.pi, abs=1e-12) and np.all(np.diff(angle) > 0)
    assert c.residuals.max() < 1e-12 and chord_turns(c.x).max() < 0.25
    c = trace_curve(circle, [1.0, 0.0], ds=0.05, direction=(0.0, 1.0))
    assert c.stops == ("start", "closed loop") and np.all(c.x[-1] == c.x[0])
    c = trace_curve(circle, [1.0, 0.0], ds=0.05, max_points=15)
    assert c.x.shape[0] == 15 and c.start == 7
    assert c.stops == ("max_points reached (no parameter box given)",) * 2
    c = trace_curve(circle, [1.0, 0.0], bounds=(np.array([-2.0, -2.0]), np.array([2.0, 2.0])), ds=0.05,
                    max_points=15)
    assert c.x.shape[0] == 15 and c.stops == ("max_points reached",) * 2


def test_stops_inside_the_box_say_why():
    """A function undefined above y = 0.6, and a cusp (y^2 = x^3, where the corrector cannot converge)."""
    def undefined_above(x):
        return jnp.atleast_1d(jnp.where(x[1] > 0.6, jnp.nan, x[0] ** 2 + x[1] ** 2 - 1.0))

    c = trace_curve(undefined_above, [1.0, 0.0], bounds=(np.array([np.nan, -0.5]), np.array([np.nan, 0.9])),
                    ds=0.05, names=("x", "y"))
    assert c.stops[0] == "box edge (y = -0.5)" and c.stops[1].startswith("non-finite G at (x = ")
    assert 0.55 < c.x[-1, 1] <= 0.6 and c.x.shape[0] < 30

    def cusp(x):
        return jnp.atleast_1d(x[1] ** 2 - x[0] ** 3)

    c = trace_curve(cusp, [1.0, 1.0], bounds=(np.array([np.nan, np.nan]), np.array([2.0, np.nan])), ds=0.05,
                    names=("x", "y"))
    assert c.stops[0].startswith("corrector failed (step below ds_min) at (x = ")
    assert c.stops[1] == "box edge (x = 2.0)" and np.abs(c.x[0]).max() < 1e-3
    np.testing.assert_allclose(c.x[-1], [2.0, np.sqrt(8.0)], atol=1e-8)


def test_branch_with_two_folds_traced_both_ways():
    """p = u^3 - u from the middle (unstable) equilibrium u = 0, p in [-1, 1]: folds at u = -+1/sqrt 3,
    p = +-2/(3 sqrt 3); towards increasing p at the start the branch turns at the upper fold and ends on
    p = -1 (u = -1.3247..., the plastic number), the other way on p = 1."""
    def F(u, p):
        return jnp.atleast_1d(p + u[0] - u[0] ** 3)

    br = continue_branch(F, np.array([0.0]), 0.0, p_bounds=(-1.0, 1.0), ds=0.05, name="p")
    assert br.stops == ("box edge (p = 1.0)", "box edge (p = -1.0)")
    plastic = 1.324717957244746
    np.testing.assert_allclose(br.u[[0, -1], 0], [plastic, -plastic], atol=1e-8)
    assert br.p[0] == 1.0 and br.p[-1] == -1.0 and br.u[br.curve.start, 0] == 0.0
    assert np.all(np.diff(br.u[:, 0]) < 0)                      # one ordered curve, the start once
    folds = sorted(e.p for e in br.events if e.kind == "fold")
    np.testing.assert_allclose(folds, [-2 / (3 * np.sqrt(3)), 2 / (3 * np.sqrt(3))], atol=1e-12)
    assert list(br.stable[[0, br.curve.start, -1]]) == [True, False, True]
    assert chord_turns(np.column_stack([br.u, br.p])).max() < 0.25
    d = br.as_dict()
    assert d["stops"] == list(br.stops) and d["start"] == br.curve.start
    one = continue_branch(F, np.array([0.0]), 0.0, p_bounds=(-1.0, 1.0), ds=0.05, direction=1.0)
    assert one.stops == ("start", "box edge (p = -1.0)") and one.p[0] == 0.0


# every boundary in a box, and the dense curve


def three_curves(x, y):
    """Three disjoint zero sets in the box x in [-2, 6], y in [-1.8, 1.8]: the unit circle (a closed loop that
    only the middle line y = 0 crosses), the parabola x = 3 + y^2 / 2 (turning in x at y = 0, from the bottom
    edge to the top), and an arc of the circle of radius 0.35 about (-2.2, 0.6) that enters and leaves through
    the left side and crosses no line."""
    return [x**2 + y**2 - 1.0, x - 3.0 - 0.5 * y**2, (x + 2.2) ** 2 + (y - 0.6) ** 2 - 0.35**2]


@functools.partial(jax.jit, static_argnums=0)
def value_and_gradient(k, points):
    """Curve `k` of `three_curves` and its gradient at each point (row)."""
    return jax.vmap(jax.value_and_grad(lambda p: three_curves(p[0], p[1])[k]))(points)


def product_margin(x, y):
    f = three_curves(x, y)
    return f[0] * f[1] * f[2]


def test_every_boundary_in_a_box_once_with_its_dense_curve_to_tolerance():
    box = ((-2.0, 6.0), (-1.8, 1.8))
    found = trace_boundaries(product_margin, box, names=("x", "y"), ds=0.05, ds_max=0.5)
    assert len(found) == 3 and np.allclose(found.lines, [-1.2, 0.0, 1.2])
    # each crossing the scan met (edge, lines, sides) lies on a branch; each branch was traced once
    assert all(c.branch is not None for c in found.crossings) and len(found.crossings) >= 9
    assert sorted({c.branch for c in found.crossings}) == [0, 1, 2]
    assert all(isinstance(c, BoundaryCrossing) and c.error is None for c in found.crossings)
    c0 = found.crossings[0]
    assert c0.as_dict(names=("x", "y")) == {"x": c0.p1, "y": c0.p2, "along": c0.along,
                                           "stable_side": c0.stable_side, "branch": c0.branch}
    assert list(c0.as_dict()) == ["p1", "p2", "along", "stable_side", "branch"]
    with pytest.warns(DeprecationWarning):
        assert c0["p1"] == c0.p1 and "error" not in c0
    assert isinstance(found, Boundaries) and isinstance(found.branches, tuple) and isinstance(found.crossings, tuple)
    with pytest.raises(dataclasses.FrozenInstanceError):
        found.branches = ()
    which = {}
    for k, c in enumerate(found):
        f = np.array([np.abs(three_curves(*p)) for p in c.x])
        (which[k],) = set(np.argmin(f, axis=1))
        assert c.residuals.max() < 1e-12 and c.dense_tol == 1e-6
    by_curve = {v: found[k] for k, v in which.items()}
    assert sorted(by_curve) == [0, 1, 2]
    assert by_curve[0].stop == "closed loop" and np.all(by_curve[0].x[0] == by_curve[0].x[-1])
    assert by_curve[1].stops == ("box edge (y = -1.8)", "box edge (y = 1.8)")
    assert by_curve[2].stops == ("box edge (x = -2.0)", "box edge (x = -2.0)")
    np.testing.assert_allclose(by_curve[1].x[[0, -1]], [[4.62, -1.8], [4.62, 1.8]], atol=1e-12)
    # the dense curve, 16 points per interval (between the points), against the exact curves: its distance
    # along x (at fixed y) within dense_tol wherever the curve is not within 3 degrees of horizontal, and
    # its distance to the curve within dense_tol everywhere
    for k, c in by_curve.items():
        d = c.dense(16)
        assert np.array_equal(d[::16], c.x)
        f, g = value_and_gradient(k, d)
        normal, along_x, slope = np.abs(f) / np.linalg.norm(g, axis=1), np.abs(f / g[:, 0]), \
            np.abs(g[:, 0]) / np.linalg.norm(g, axis=1)
        assert normal.max() < 1e-6 and along_x[slope >= 0.05].max() < 1e-6
        assert along_x[slope >= 0.05].max() > 1e-8              # the steps were long, not needlessly short
        # the estimates are the midpoints' errors (where the curve is not near horizontal)
        mid = slice(8, None, 16)
        ok = slope[mid] > 0.2
        np.testing.assert_allclose(c.errors[1:][ok], along_x[mid][ok], rtol=0.05, atol=1e-10)
    # the parabola's critical x at y = 0 read off the dense curve
    np.testing.assert_allclose(by_curve[1].meets(1, 0.0), [[3.0, 0.0]], atol=1e-6)
    # nothing in a box without a boundary
    assert len(trace_boundaries(product_margin, ((-1.9, -1.5), (-1.7, -1.2)))) == 0


def test_dense_curve_of_a_boundary_traced_with_a_tolerance():
    """trace_boundary with dense_tol: the parabola x = 3 + y^2/2 from one start, both ways; Curve.meets and
    as_dict give the dense curve; with a tenfold tolerance the steps are about 10^(1/4) longer."""
    def sigma(x, y):
        return three_curves(x, y)[1]

    kw = dict(bounds=(np.array([-2.0, -1.8]), np.array([6.0, 1.8])), names=("x", "y"), ds=0.05, ds_max=1.0)
    fine = trace_boundary(sigma, (3.2, 0.5), dense_tol=1e-7, **kw)
    coarse = trace_boundary(sigma, (3.2, 0.5), dense_tol=1e-6, **kw)
    free = trace_boundary(sigma, (3.2, 0.5), **kw)
    assert fine.x[fine.start, 0] == pytest.approx(3.125, abs=1e-12)
    for c, tol in ((fine, 1e-7), (coarse, 1e-6)):
        d = c.dense(8)
        assert np.abs(d[:, 0] - 3.0 - 0.5 * d[:, 1] ** 2).max() < tol
        assert c.errors.max() <= 0.8 * tol
    assert 1.4 < len(fine.x) / len(coarse.x) < 2.2
    assert free.dense_tol is None and free.errors.max() > 1e-6        # not controlled, only estimated
    for y in (-1.0, 0.3, 1.7):
        np.testing.assert_allclose(coarse.meets(1, y), [[3.0 + 0.5 * y * y, y]], atol=1e-6)
    js = coarse.as_dict(names=("x", "y"), dense=4)
    assert js["stop"] == "box edge" and js["interpolation_error_max"] <= 0.8e-6
    assert len(js["dense"]["x"]) == 4 * (len(js["x"]) - 1) + 1 and len(js["tangents"]) == len(js["x"])
    assert js["error_measured"] == "along x at fixed other coordinates"
    # a start from which Newton along x would leave the box fails at once, naming it
    with pytest.raises(ValueError, match=r"no stability boundary near the start x = 1: Newton along x leaves the box"):
        trace_boundary(sigma, (1.0, 0.5), bounds=(np.array([0.0, -1.0]), np.array([2.0, 1.0])), names=("x", "y"))
    np.testing.assert_allclose(np.linalg.norm(coarse.tangents, axis=1), 1.0)
    assert np.all(np.sum(np.diff(coarse.x, axis=0) * coarse.tangents[1:], axis=1) > 0)     # along the curve


def test_boundary_crossing_without_a_branch_carries_its_error_in_the_row():
    c = BoundaryCrossing(p1=1.0, p2=2.0, along="x", stable_side="above", error="no stability boundary near")
    assert c.as_dict(names=("n", "mu_w")) == {"n": 1.0, "mu_w": 2.0, "along": "x", "stable_side": "above",
                                              "branch": None, "error": "no stability boundary near"}
    with pytest.warns(DeprecationWarning):
        assert c["error"] == c.error and "error" in c
    with pytest.raises(dataclasses.FrozenInstanceError):
        c.branch = 0


@pytest.mark.parametrize("reason, result", [
    ("box edge (p = 2.0)", "successful"),
    ("closed loop", "successful"),
    ("start", "successful"),
    ("max_points reached", "max_points_reached"),
    ("max_points reached (no parameter box given)", "max_points_reached"),
    ("corrector failed (step below ds_min) at p = 1.5", "solver_failure"),
    ("non-finite F at p = 1.5", "nonfinite"),
    ("no periodic motion with more harmonics than 3 at speed = 210 (Newton iteration ...)", "root_not_converged"),
    ("harmonics raised", "solver_failure"),
])
def test_each_way_a_curve_ends_is_a_results_item(reason, result):
    """Stops are `RESULTS` items (issue 62): `Curve.results` per end, `complete`
    where both are `successful`, and the JSON's `stop_codes`; an end for a reason of
    the caller's own (a watch that was not handled) counts as a failure."""
    from rotorjax.analysis._continuation import stop_result

    assert stop_result(reason) == getattr(RESULTS, result)
    curve = Curve(x=np.zeros((2, 2)), residuals=np.zeros(2), steps=np.zeros(2), iterations=np.zeros(2, int),
                  stopped="", stops=("box edge (p = 0.0)", reason))
    assert curve.complete == (result == "successful")
    assert curve.as_dict()["stop_codes"] == [0, code_of(getattr(RESULTS, result))]
