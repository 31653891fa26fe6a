"""The Lagrangian-by-autodiff equations equal the papers' published equations
(000 eq. 7 with the constraint eliminated; 001 eqs. 8 as reconstructed in the seeds'
README) at random states and parameters, and so does the hand-derived fast path. The reference is an independent numpy
implementation (tests/reference/paper_models.py)."""

import numpy as np
import pytest

from rotorjax.presets import anisotropic_abb, jeffcott_abb
from tests.reference.paper_models import rhs_000_paper, rhs_001_paper


@pytest.mark.parametrize("n_balls", [1, 2, 3])
@pytest.mark.parametrize("run_up", [False, True])
def test_model_000_equals_paper_eq7(n_balls, run_up):
    rng = np.random.default_rng(10 * n_balls + run_up)
    for _ in range(5):
        g = dict(chi=rng.uniform(0.005, 0.1), eps=rng.uniform(0, 0.1), alpha=rng.uniform(-3, 3),
                 rho1=rng.uniform(0.7, 1.3), rho2=rng.uniform(0.7, 1.3),
                 delta_n=rng.uniform(0, 0.5), delta_b=rng.uniform(0, 50))
        nu, nu_dot = rng.uniform(0.2, 3), (rng.uniform(0.01, 0.3) if run_up else 0.0)
        scene = jeffcott_abb.scene_from_groups(**g, nu=nu, nu_dot=nu_dot, nu0=nu, n_balls=n_balls)
        y = rng.normal(size=scene.state_size)
        t = rng.uniform(0, 20)
        p = dict(g, nu0=nu, nu_dot=nu_dot)
        ref = rhs_000_paper(t, y, p)
        for ours in (scene.lagrange_vector_field(t, y), scene.vector_field(t, y)):
            np.testing.assert_allclose(np.asarray(ours), ref, rtol=1e-11,
                                       atol=1e-11 * np.max(np.abs(ref)))


@pytest.mark.parametrize("sigma", [1.0, 0.5, 1 / 3])
def test_model_001_equals_paper_eq8(sigma):
    rng = np.random.default_rng(int(10 / sigma))
    for _ in range(5):
        g = dict(n_eta=rng.uniform(1, 8), mu_xi=rng.uniform(0, 1), mu_eta=rng.uniform(0, 1),
                 sigma=sigma, c=rng.uniform(0, 1), eps=rng.uniform(0.001, 0.2),
                 mu_w=rng.uniform(0, 2))
        n = rng.uniform(0.3, 10)
        scene = anisotropic_abb.scene_from_groups(**g, n=n, K=rng.choice([1.0, 1.4, 1.5]))
        y = rng.normal(size=scene.state_size)
        t = rng.uniform(0, 20)
        ref = rhs_001_paper(t, y, dict(g, n=n))
        for ours in (scene.lagrange_vector_field(t, y), scene.vector_field(t, y)):
            np.testing.assert_allclose(np.asarray(ours), ref, rtol=1e-11,
                                       atol=1e-11 * np.max(np.abs(ref)))


def test_criterion_roots_match_published():
    """Eq. (18) for n_eta = 7: roots 1, 5, 7 undamped; 1.003, 5.041, 6.925 damped."""
    n = np.linspace(0.5, 9, 200001)
    for (mx, me), expected, tol in (((0, 0), (1, 5, 7), 1e-4), ((0.25, 0.5), (1.003, 5.041, 6.925), 6e-4)):
        p = anisotropic_abb.criterion_polynomial(n, 7.0, mx, me)
        roots = n[:-1][np.sign(p[:-1]) != np.sign(p[1:])]
        np.testing.assert_allclose(roots, expected, atol=tol)
