"""The finite plain journal's film-force interpolant (rotorjax.models._finite_film)
against the Reynolds solver it tabulates (`finite_bearing_state`, same 240 x 16 mesh),
the finite bearing's static equilibrium and eight coefficients (`PlainJournal(...,
method="finite")`), the short-bearing limit; smoothness, transforms, bad input."""

import jax
import jax.numpy as jnp
import numpy as np
import pytest

from rotorjax._errors import InputError
from rotorjax.models._finite_film import finite_film_force, short_film_force
from rotorjax.models._journal_bearing import PlainJournal, finite_bearing_state

FORCE = jax.jit(finite_film_force)
JAC = jax.jit(jax.jacfwd(finite_film_force, argnums=(0, 1, 2)))
VFORCE = jax.jit(jax.vmap(finite_film_force))
SHORT = jax.jit(short_film_force)
# dimensional operating geometry for the equilibrium checks (the results are dimensionless)
MU, D, C_RAD, W = 0.02, 0.1, 1e-4, 1000.0
R = D / 2


def solver_fhat(eps, delta, ratio):
    """`Fhat` by its definition through the solver (omega = 1, c = 1, rho = 1)."""
    return finite_bearing_state(eps, 0.0, vx=-np.sin(delta) / 2, vy=(eps - np.cos(delta)) / 2,
                                ratio=ratio, n_theta=240, n_z=16)[0]


# --- 20 random off-grid points: interpolant vs the solver --------------------------------
_RNG = np.random.default_rng(20261126)
POINTS = np.column_stack([_RNG.uniform(0.1, 0.9, 20), _RNG.uniform(-np.pi, np.pi, 20),
                          _RNG.uniform(0.25, 1.0, 20)])


@pytest.fixture(scope="module")
def solved():
    return np.array([solver_fhat(*p) for p in POINTS])


def test_force_matches_solver_off_grid(solved):
    got = np.array([FORCE(*p) for p in POINTS])
    rel = np.linalg.norm(got - solved, axis=1) / np.linalg.norm(solved, axis=1)
    # measured max 9e-5 (the solver's own grid-scale cavitation-boundary noise); aim 1 %
    assert rel.max() < 2e-3, rel.max()


def test_definition_homogeneity():
    """`rho Fhat(eps, delta)` is the solver's force for any (a, b) right side: a journal
    at eps whirling at v_t and moving out at v_r (omega = c = 1)."""
    eps, ratio, v_r, v_t = 0.55, 0.6, 0.07, -0.11
    a, b = eps - 2 * v_t, -2 * v_r
    want = finite_bearing_state(eps, 0.0, v_r, v_t, ratio=ratio)[0]
    got = np.hypot(a, b) * np.asarray(FORCE(eps, np.arctan2(b, a), ratio))
    np.testing.assert_allclose(got, want, rtol=2e-3, atol=1e-3 * np.linalg.norm(want))


# --- static equilibrium and coefficients vs method="finite" --------------------------------
CASES = [(0.25, 0.1), (0.25, 0.85), (0.5, 0.5), (1.0, 0.15), (1.0, 0.9)]  # (L/D, eps target)


def _speed_for(eps, ratio):
    """The speed at which the interpolant puts the equilibrium near `eps` (pure rotation:
    rho = e omega, W = 12 mu R^4 omega eps |Fhat(eps, 0)| / c^2)."""
    fhat = np.linalg.norm(np.asarray(FORCE(eps, 0.0, ratio)))
    return W * C_RAD ** 2 / (12 * MU * R ** 4 * eps * fhat)


@pytest.fixture(scope="module")
def finite():
    """`PlainJournal(method="finite")` at one speed per case (the equilibrium near the
    target eps)."""
    return [PlainJournal(W, MU, ratio * D, D, C_RAD, method="finite").coefficients(_speed_for(eps, ratio))
            for ratio, eps in CASES]


def global_force(q, v, ratio):
    """Dimensionless global film force (units 12 mu R^4 omega / c^2 with c = omega = 1)
    on a journal at q = (x, y) moving at v = (vx, vy), from `Fhat` and the rotation to the
    line of centres."""
    e = jnp.hypot(q[0], q[1])
    psi = jnp.arctan2(q[1], q[0])
    cs, sn = jnp.cos(psi), jnp.sin(psi)
    v_r = v[0] * cs + v[1] * sn
    v_t = -v[0] * sn + v[1] * cs
    a, b = e - 2 * v_t, -2 * v_r
    f = jnp.hypot(a, b) * finite_film_force(e, jnp.arctan2(b, a), ratio)
    return jnp.stack([cs * f[0] - sn * f[1], sn * f[0] + cs * f[1]])


@jax.jit
def linearised(q0, ratio):
    """`k c / W`, `c c omega / W` and `W` (dimensionless) by autodiff about q0 at rest."""
    state = jnp.concatenate([q0, jnp.zeros(2)])
    load = jnp.linalg.norm(global_force(q0, state[2:], ratio))
    jac = -jax.jacfwd(lambda s: global_force(s[:2], s[2:], ratio))(state) / load
    return jac[:, :2], jac[:, 2:], load


@pytest.mark.parametrize("case", range(len(CASES)))
def test_static_load_and_attitude(finite, case):
    ratio = CASES[case][0]
    r = finite[case]
    eps, phi = float(r.eccentricity[0]), float(r.attitude[0])
    fhat = np.asarray(FORCE(eps, 0.0, ratio))
    load = 12 * MU * R ** 4 * float(r.speeds[0]) * eps / C_RAD ** 2 * np.linalg.norm(fhat)
    attitude = np.pi - np.arctan2(fhat[1], fhat[0])
    # measured: load within 1.1e-4, attitude within 1.3e-4 (relative)
    assert abs(load / W - 1) < 0.02
    assert abs(attitude / phi - 1) < 0.02


@pytest.mark.parametrize("case", range(len(CASES)))
def test_coefficients_by_autodiff(finite, case):
    ratio = CASES[case][0]
    r = finite[case]
    k, c, _ = linearised(jnp.asarray(np.asarray(r.position[0]) / C_RAD), ratio)
    k_ref = np.asarray(r.k[0]) * C_RAD / W
    c_ref = np.asarray(r.c[0]) * C_RAD * float(r.speeds[0]) / W
    # measured: max 0.05 % (stiffness) / 0.1 % (damping) of the matrix norm
    assert np.abs(k - k_ref).max() < 0.05 * np.linalg.norm(k_ref)
    assert np.abs(c - c_ref).max() < 0.05 * np.linalg.norm(c_ref)


# --- short-bearing limit ---------------------------------------------------------------------
def test_short_bearing_limit():
    """At L/D = 0.25 and eps 0.1-0.4 the finite force is within a few % of Ocvirk's
    over every delta (measured max 4.8 %; 2.5-4.2 % under pure rotation, delta = 0); the
    difference shrinks about as (L/D)^2 (measured ratio 3.3 between L/D = 0.5 and 0.25)."""
    eps = jnp.linspace(0.1, 0.4, 4)
    delta = jnp.linspace(-np.pi, np.pi, 16, endpoint=False)
    e, d, r = (a.ravel() for a in jnp.meshgrid(eps, delta, jnp.array([0.25, 0.5]), indexing="ij"))
    fe, sh = VFORCE(e, d, r), jax.vmap(short_film_force)(e, d, r)
    gap = (jnp.linalg.norm(fe - sh, axis=1) / jnp.linalg.norm(sh, axis=1)).reshape(-1, 2)
    g25, g50 = (float(x) for x in gap.max(axis=0))
    assert g25 < 0.06, g25
    assert 2.5 < g50 / g25 < 4.5, g50 / g25
    # the short formula itself against the solver at a small L/D
    np.testing.assert_allclose(np.asarray(SHORT(0.6, 1.0, 0.05)), solver_fhat(0.6, 1.0, 0.05), rtol=4e-3)


# --- smoothness, extrapolation, transforms ------------------------------------------------
def test_beyond_the_table():
    """Above the table (eps 0.98) the force stays finite, its eps-derivative continuous,
    and under pure rotation its magnitude grows to eps 0.995."""
    eps = jnp.linspace(0.9, 0.995, 32)
    for ratio in (0.25, 1.0):
        f = np.asarray(VFORCE(eps, jnp.zeros(32), jnp.full(32, ratio)))
        assert np.all(np.isfinite(f))
        assert np.all(np.diff(np.linalg.norm(f, axis=1)) > 0)
        below, above = JAC(0.98 - 1e-9, 0.0, ratio)[0], JAC(0.98 + 1e-9, 0.0, ratio)[0]
        np.testing.assert_allclose(np.asarray(above), np.asarray(below), rtol=1e-4)
    # and stays near the solver just past the table (measured 1 %)
    np.testing.assert_allclose(np.asarray(FORCE(0.985, 0.0, 0.5)), solver_fhat(0.985, 0.0, 0.5), rtol=0.03)


def test_gradients_match_finite_differences():
    args = (0.63, 2.1, 0.41)
    jac = JAC(*args)
    h = 1e-6
    for i in range(3):
        up = list(args)
        dn = list(args)
        up[i] += h
        dn[i] -= h
        fd = (np.asarray(FORCE(*up)) - np.asarray(FORCE(*dn))) / (2 * h)
        np.testing.assert_allclose(np.asarray(jac[i]), fd, rtol=1e-6, atol=1e-9)
    # at the concentric position (a one-sided difference)
    fd0 = (np.asarray(FORCE(1e-6, 0.3, 0.5)) - np.asarray(FORCE(0.0, 0.3, 0.5))) / 1e-6
    np.testing.assert_allclose(np.asarray(JAC(0.0, 0.3, 0.5)[0]), fd0, rtol=1e-4)
    # periodic in delta, including its derivative
    np.testing.assert_allclose(np.asarray(JAC(0.7, -3.0, 0.8)[1]), np.asarray(JAC(0.7, -3.0 + 2 * np.pi, 0.8)[1]),
                               rtol=1e-9)


def test_vmap_equals_loop():
    batched = VFORCE(*jnp.asarray(POINTS.T))
    loop = np.array([FORCE(*p) for p in POINTS])
    np.testing.assert_allclose(np.asarray(batched), loop, rtol=1e-12)


@pytest.mark.parametrize("ratio", [0.2, 1.2])
def test_bad_ratio(ratio):
    with pytest.raises(InputError, match="L/D"):
        finite_film_force(0.5, 0.0, ratio)


def test_bad_eps():
    with pytest.raises(InputError, match="eps"):
        finite_film_force(1.0, 0.0, 0.5)
