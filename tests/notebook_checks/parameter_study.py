"""Checks of the numbers notebooks/parameter_study.py prints (see tests/test_notebooks.py).

Each printed count is recounted from the stored per-point values, and the values are
checked against what is known independently of the notebook's code path: the
boundaries of model 001's main motion (critical speeds near n = 1.01-1.02 and
5.04-5.05 at mu_w = 0.5, a third one that moves down with mu_w: 8.29 at mu_w = 0.53,
7.99 at 0.85), the paper's criterion polynomial (eq. 18) written out here, and the
rotor's forced response to the perturbation's residual imbalance, also written out
here, which must predict exactly which points the whirl threshold gets wrong."""

import numpy as np

REQUIRED = True


def _criterion(n, n_eta, mu_xi, mu_eta):
    """Eq. (18) of Filimonikhina et al. 2017, balancing where < 0."""
    s, e2 = n**2, n_eta**2
    return (1 - s) * (e2 - s) * (1 + e2 - 2 * s) + 4 * s * ((1 - s) * mu_eta**2 + (e2 - s) * mu_xi**2)


def _semi_major_axis(n, n_eta, mu_xi, mu_eta):
    """Steady orbit of the rotor (units of L) under a unit imbalance (units of Ms L)
    rotating at speed n: xi = Re(X e^{i n tau}), eta = Re(Y e^{i n tau}); the ellipse's
    semi-major axis in closed form."""
    X = n**2 / (1 - n**2 + 2j * mu_xi * n)
    Y = -1j * n**2 / (n_eta**2 - n**2 + 2j * mu_eta * n)
    return np.sqrt((abs(X) ** 2 + abs(Y) ** 2 + abs(X**2 + Y**2)) / 2)


def check(claims):
    g = claims["groups"]
    n = np.asarray(claims["grid_n"])
    mu = np.asarray(claims["grid_mu_w"])
    assert np.allclose(n, np.linspace(0.5, 9.5, 24)) and np.allclose(mu, [0.25, 0.5, 1.0])
    assert claims["n_points"] == n.size * mu.size == 72

    # --- Floquet verdict: self-checks and recounts -------------------------------
    m = np.asarray(claims["margin"], dtype=float)
    assert m.shape == (n.size, mu.size) and np.all(np.isfinite(m))
    assert claims["floquet_failed"] == 0
    assert claims["liouville_error_max"] < 1e-7 and claims["closure_max"] < 1e-10
    stable = m < 0
    # the Floquet count; regression pin: produced by `python notebooks/parameter_study.py` (2026-11-25)
    assert claims["stable_count"] == int(stable.sum()) == 42
    assert claims["stable_count_per_mu_w"] == stable.sum(axis=0).tolist()

    # --- boundaries: the known ones, and the grid verdict they imply ---------------
    b = [np.asarray(x) for x in claims["floquet_boundaries"]]
    assert all(x.size == 3 for x in b), b
    assert claims["boundary_bracket_width"] < 1e-4
    for x in b:
        assert 1.0 < x[0] < 1.05 and 5.0 < x[1] < 5.06, x
    j05 = int(np.argmin(abs(mu - 0.5)))
    # regression pins: the boundary values below were produced by `python notebooks/parameter_study.py`
    # (2026-11-25) and are stated in the notebook's text; no published table gives them (the paper's
    # criterion, eq. 18, is checked against the same boundaries further down)
    assert 1.01 <= b[j05][0] <= 1.02 and 5.04 <= b[j05][1] <= 5.05, b[j05]
    third = np.array([x[2] for x in b])
    assert np.all(np.diff(third) < 0), third  # moves down as mu_w grows
    assert 8.29 <= third[j05] <= 8.35, third  # 8.29 at mu_w = 0.53, above it at 0.5
    assert third[-1] < 7.99  # 7.99 at mu_w = 0.85, below it at 1.0
    for j, x in enumerate(b):
        expect = ((n > x[0]) & (n < x[1])) | (n > x[2])
        assert np.array_equal(stable[:, j], expect), (mu[j], x, m[:, j])

    # --- whirl threshold: recounts, and the decay-time explanation -----------------
    thr, (t_a, t_b) = claims["threshold"], claims["window"]
    assert thr == 1e-3 and (t_a, t_b) == (140.0, 150.0)
    assert claims["sim_failed"] == 0
    w = np.asarray(claims["whirl_window_max"])
    kept = w < thr
    # regression pin: produced by `python notebooks/parameter_study.py` (2026-11-25)
    assert claims["kept_count"] == int(kept.sum()) == 22
    mis_lost, mis_kept = stable & ~kept, ~stable & kept
    assert claims["misclassified_stable_as_lost"] == int(mis_lost.sum())
    assert claims["misclassified_unstable_as_kept"] == int(mis_kept.sum()) == 0
    # regression pin: produced by `python notebooks/parameter_study.py` (2026-11-25)
    assert claims["misclassified_count"] == int(mis_lost.sum() + mis_kept.sum()) == 20

    # residual imbalance of the perturbed main motion: the scene's own value at tau = 0,
    # and the first-order estimate sigma |sum delta_j i e^{i psi_j}| about the main motion
    # psi = pi -+ a, where sigma |e^{i psi_1} + e^{i psi_2}| = c
    U0 = claims["residual_imbalance0"]
    assert np.allclose(claims["residual_imbalance0_simulated"], U0, rtol=1e-9, atol=0)
    a = np.arccos(g["c"] / (2 * g["sigma"]))
    psi = np.pi + np.array([-a, a])
    assert abs(abs(g["c"] + g["sigma"] * np.exp(1j * psi).sum())) < 1e-12
    delta = 0.05 * np.cos(np.arange(2))
    U0_lin = g["sigma"] * abs(np.sum(1j * delta * np.exp(1j * psi)))
    assert abs(U0 / U0_lin - 1) < 0.05, (U0, U0_lin)   # first order: the 5 % is the tolerance of that estimate

    A0 = U0 * _semi_major_axis(n, g["n_eta"], g["mu_xi"], g["mu_eta"])[:, None] * np.ones_like(m)
    assert np.allclose(claims["forced_amplitude"], A0, rtol=1e-4)
    td = np.where(stable, np.log(A0 / thr) / np.abs(m), np.inf)
    stored = np.array([[np.inf if x is None else x for x in row] for row in claims["decay_time"]])
    assert np.allclose(stored[stable], td[stable], rtol=1e-4) and np.all(np.isinf(stored[~stable]))
    # the threshold reports a stable point lost exactly when its transient outlasts the window's start
    predicted = stable & (td > t_a)
    assert np.array_equal(predicted, mis_lost), np.argwhere(predicted != mis_lost)
    assert claims["predicted_misclassified_count"] == int(predicted.sum())
    assert claims["prediction_mismatch_count"] == 0
    assert np.isclose(claims["misclassified_decay_time_min"], td[mis_lost].min(), rtol=1e-4)
    assert np.isclose(claims["misclassified_decay_time_max"], td[mis_lost].max(), rtol=1e-4)
    assert claims["misclassified_decay_time_min"] > t_a
    sp = claims["slowest_point"]
    i, j = int(np.argmin(abs(n - sp["n"]))), int(np.argmin(abs(mu - sp["mu_w"])))
    assert (i, j) == np.unravel_index(np.argmax(np.where(mis_lost, td, -np.inf)), m.shape)
    assert sp["margin"] == m[i, j] and np.isclose(sp["decay_time"], td[i, j], rtol=1e-4)

    # --- the paper's criterion against the Floquet verdict ----------------------------
    p = lambda x: _criterion(x, g["n_eta"], g["mu_xi"], g["mu_eta"])  # noqa: E731
    roots = np.asarray(claims["criterion_roots"])
    fine = np.linspace(0.5, 9.5, 90001)
    flips = fine[:-1][np.sign(p(fine[1:])) != np.sign(p(fine[:-1]))]
    assert roots.size == flips.size == 3 and np.allclose(roots, flips, atol=2e-4), (roots, flips)
    crit = np.broadcast_to((p(n) < 0)[:, None], m.shape)
    assert claims["criterion_stable_count"] == int(crit.sum())
    disagree = crit != stable
    # regression pin: produced by `python notebooks/parameter_study.py` (2026-11-25)
    assert claims["criterion_disagree_count"] == int(disagree.sum()) == 9
    pts = [[float(n[i]), float(mu[j])] for i, j in zip(*np.nonzero(disagree))]
    assert np.allclose(claims["criterion_disagree_points"], pts)
    # the criterion ignores mu_w: it errs between its third root and the mu_w-dependent boundary
    for i, j in zip(*np.nonzero(disagree)):
        assert roots[2] < n[i] < third[j] and crit[i, j] and not stable[i, j]
