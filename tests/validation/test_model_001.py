"""Model 001 (Filimonikhina et al. 2017): the main motion, its stability, scipy."""

import numpy as np
import pytest
from scipy.integrate import solve_ivp

import rotorjax as rj
from rotorjax import presets
from rotorjax.presets import anisotropic_abb
from tests.reference.paper_models import rhs_001_paper

PRESET = presets.get("anisotropic-abb")


def test_main_motion_is_an_exact_solution():
    """Weights at 2pi/3, 4pi/3 moving with the shaft, c = sigma = 0.5: the rotor stays
    at rest for any speed, to rounding (which grows where the main motion is unstable,
    as at n = 6)."""
    for n, tol in ((0.7, 1e-11), (3.0, 1e-11), (6.0, 1e-8)):
        p = PRESET.params({"n": n, "perturbation": 0.0})
        setup = PRESET.build(p)
        scene, y0 = setup.scene, setup.y0
        np.testing.assert_allclose(np.asarray(y0[2:4]), [2 * np.pi / 3, 4 * np.pi / 3], atol=1e-15)
        r = rj.simulate(scene, y0, (0.0, 50.0), saveat=11, rtol=1e-10, atol=1e-12)
        assert bool(r.success)
        assert float(np.max(r.outputs["whirl_amplitude"])) < tol
        assert float(np.max(r.outputs["residual_imbalance"])) < tol


@pytest.mark.parametrize("n,returns", [(3.0, True), (6.0, False)])
def test_perturbed_main_motion(n, returns):
    """eps = 0.01, mu_w = 0.5, n_eta = 7, mu_xi = 0.25, mu_eta = 0.5: from a perturbed
    main motion the rotor returns to it at n = 3 and does not at n = 6."""
    p = PRESET.params({"n": n, "eps": 0.01, "mu_w": 0.5})
    setup = PRESET.build(p)
    scene, y0, t_end = setup.scene, setup.y0, setup.t_end
    r = rj.simulate(scene, y0, (0.0, t_end), saveat=np.linspace(t_end - 10, t_end, 50))
    assert bool(r.success)
    amp = float(np.max(r.outputs["whirl_amplitude"]))
    angles = np.sort(np.mod(np.asarray(r.outputs["weight_angles"][-1]), 2 * np.pi))
    if returns:
        assert amp < 1e-3
        np.testing.assert_allclose(angles, [2 * np.pi / 3, 4 * np.pi / 3], atol=1e-3)
    else:
        assert amp > 0.1
        assert float(np.min(r.outputs["residual_imbalance"])) > 0.1


@pytest.mark.parametrize("n", [0.8, 3.0, 5.5, 9.0])
def test_trajectory_matches_scipy_dop853(n):
    """Against scipy DOP853 at rtol 1e-11 on the independent paper equations; speeds
    chosen away from the ill-conditioned band n = 7.2-8.2 (shared/PERFORMANCE.md)."""
    p = PRESET.params({"n": n})
    setup = PRESET.build(p)
    scene, y0 = setup.scene, setup.y0
    t_end = 50.0
    ts = np.linspace(0.0, t_end, 6)
    r = rj.simulate(scene, y0, (0.0, t_end), saveat=ts, rtol=1e-12, atol=1e-14)
    ref = solve_ivp(rhs_001_paper, (0.0, t_end), np.asarray(y0), method="DOP853", t_eval=ts,
                    rtol=1e-11, atol=1e-13, args=(p,))
    assert ref.success
    assert np.max(np.abs(np.asarray(r.ys) - ref.y.T)) < 1e-7


def test_main_motion_angles_cancel_imbalance():
    for N, c in ((2, 0.5), (3, 0.3), (4, 0.9), (2, 0.0)):
        a = anisotropic_abb.main_motion_angles(N, c)
        assert abs(np.sum(np.exp(1j * a)) / N + c) < 1e-12
