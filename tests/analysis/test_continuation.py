"""Continuation: branches with folds and Hopf points, fold curves, stability
boundaries of models 001 and 004, batched boundary solves, bad input."""

import jax.numpy as jnp
import numpy as np
import pytest

from rotorjax.analysis import (boundary_points, boundary_sensitivity, continue_branch, critical_speeds,
                               floquet_crossings, fold_curve, hopf_points, trace_boundary)
from rotorjax.presets import anisotropic_abb as ab
from rotorjax.presets import cantilever_limiters as cl

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
    from rotorjax.analysis._continuation import _newton
    u0, r = _newton(lambda u: duffing(u, 0.5, f0), u0)
    br = continue_branch(lambda u, om: duffing(u, om, f0), u0, 0.5, p_bounds=(0.5, 2.0), ds=0.02, ds_max=0.05,
                         max_points=400)
    folds = [e for e in br.events if e["kind"] == "fold"]
    assert len(folds) == 2 and br.curve.stopped == "left the parameter box"
    for e in folds:
        assert e["residual"] < 1e-12
        assert min(abs(f0 / v - 1) for v in duffing_fold_forcing(e["p"])) < 1e-9
    fc = fold_curve(duffing, folds[0]["u"], (folds[0]["p"], f0), ds=0.01, ds_max=0.05, max_points=60,
                    bounds=(np.array([np.nan, np.nan, 0.8, 0.005]), np.array([np.nan, np.nan, 2.0, 0.2])))
    assert fc.x.shape[0] > 20 and fc.residuals.max() < 1e-12
    err = max(min(abs(x[3] / v - 1) for v in duffing_fold_forcing(x[2])) for x in fc.x)
    assert err < 1e-8


def brusselator(u, b, a=1.0):
    x, y = u[0], u[1]
    return jnp.stack([a - (b + 1) * x + x * x * y, b * x - x * x * y])


def test_hopf_point_of_the_brusselator():
    """Equilibrium (a, b/a); Hopf at b = 1 + a^2 with frequency a."""
    br = continue_branch(brusselator, np.array([1.0, 1.0]), 1.0, p_bounds=(1.0, 3.0), ds=0.05, ds_max=0.1)
    (h,) = [e for e in br.events if e["kind"] == "hopf"]
    assert h["p"] == pytest.approx(2.0, abs=1e-9) and h["frequency"] == pytest.approx(1.0, abs=1e-8)
    assert bool(br.stable[0]) and not bool(br.stable[-1])
    np.testing.assert_allclose(br.u[:, 1], br.p, rtol=1e-10)      # the branch is (1, b)


BASE = dict(cl.PRESET.defaults)


def rotor(ratio, mu=BASE["mu_R"]):
    return cl.build_rotor(dict(BASE, eta_i=BASE["eta_e"] / ratio, mu_R=mu))


def test_model_004_hopf_curve_matches_pointwise_solves_and_its_sensitivity():
    curve = trace_boundary(lambda N, r: rotor(r).stability_margin(N), (4.0, 1.0),
                           bounds=(np.array([0.5, 0.5]), np.array([30.0, 4.0])), ds=0.2, ds_max=1.0,
                           direction=(0.0, 1.0), tol=1e-10)
    assert curve.stopped == "left the parameter box" and curve.x.shape[0] >= 8
    for N, r in curve.x[::3]:
        h = hopf_points(rotor(r).state_matrix, N - 0.5, N + 0.5, n_scan=5, xtol=1e-13)[0]
        assert abs(h.speed - N) < 1e-8 * N
    # sensitivity of the boundary (N at fixed ratio) to the shaft/disk mass ratio,
    # i.e. to the disk mass M through mu_R = m_R l / M
    N, r = curve.x[4]
    s = boundary_sensitivity(lambda N, r, mu: rotor(r, mu).stability_margin(N), (N, r), BASE["mu_R"])

    def n_crit(mu):
        return hopf_points(rotor(r, mu).state_matrix, N - 0.5, N + 0.5, n_scan=5, xtol=1e-13)[0].speed
    h = 1e-3
    assert s == pytest.approx((n_crit(BASE["mu_R"] + h) - n_crit(BASE["mu_R"] - h)) / (2 * h), rel=1e-6)


def test_batched_boundary_points_equal_the_traced_curve():
    ratios = jnp.array([1.0, 2.0, 3.0, 4.0])
    sigma = lambda N, r: rotor(r).stability_margin(N)  # noqa: E731
    N, res = boundary_points(sigma, 2.47 * ratios + 1.8, ratios)
    assert float(jnp.max(res)) < 1e-9
    for n, r in zip(np.asarray(N), np.asarray(ratios)):
        assert abs(hopf_points(rotor(r).state_matrix, n - 0.5, n + 0.5, n_scan=5, xtol=1e-13)[0].speed - n) < 1e-8 * n


P001 = dict(ab.PRESET.defaults)
G001 = {k: P001[k] for k in ab.GROUPS}


def margin_001(n, mu):
    return ab.main_motion_floquet(dict(G001, mu_w=mu), n, P001["K"]).margin


def test_model_001_floquet_crossings_and_boundary_through_the_critical_speeds():
    found = floquet_crossings(lambda n: ab.main_motion_floquet(G001, n, P001["K"]), 4.0, 6.0, n_scan=6)
    (c,) = found
    assert c["kind"] == "complex pair" and c["residual"] < 1e-9 and c["closure"] < 1e-10
    curve = trace_boundary(margin_001, (c["p"], G001["mu_w"]), bounds=(np.array([0.5, 0.3]), np.array([10.0, 0.8])),
                           ds=0.05, ds_max=0.1, gradient="fd", max_points=8, direction=(0.0, 1.0), tol=1e-10)
    assert curve.residuals.max() < 1e-9
    for n, mu in curve.x[[1, -1]]:
        (cs,) = critical_speeds(lambda v: margin_001(v, mu), n - 0.05, n + 0.05, n_scan=4, xtol=1e-12)
        assert abs(cs.speed - n) < 1e-6


def test_bad_starts_and_boxes():
    with pytest.raises(ValueError, match=r"not on the curve: residual 2.000e\+00"):
        continue_branch(brusselator, np.array([2.0, 1.0]), 1.0)
    with pytest.raises(ValueError, match="outside the bounds"):
        continue_branch(brusselator, np.array([1.0, 1.0]), 1.0, p_bounds=(1.5, 3.0))
    br = continue_branch(brusselator, np.array([1.0, 1.0]), 1.0, p_bounds=(0.5, 1.3), ds=0.05)
    assert br.curve.stopped == "left the parameter box" and br.p.max() <= 1.3
