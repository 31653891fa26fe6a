"""Model 003 with balls is composed from the shared components: `ModalBalancerRotor`
takes the imbalance's and the balls' equations from the energies of `RigidRotor` and
`AutoBalancer` (Lagrange by autodiff), not from a hand derivation. The hand-written
equations (24) of Kovachev's dissertation abstract are kept here only, as the
reference the composed vector field must reproduce."""

import equinox as eqx
import jax
import jax.numpy as jnp
import numpy as np
import pytest

from rotorjax.models import AutoBalancer, ConstantSpeed, ModalBalancerRotor, RigidRotor, RunUp
from rotorjax.models._modal import ModalShaft


def kovachev_eq24_field(rotor, t, y):
    """`dy/dt` of eq. (24), written by hand: with `V = a^T v`, `B = b b^T`,

        (E + Jt B + m A) v'' + (d E + i g Jp theta0' B) v' + (diag k^4 + i (g/2) Jp theta0'' B) v
            = m0 (theta0'^2 - i theta0'') e^{i theta0} a + sum_j m_j r_j (theta_j'^2 - i theta_j'') e^{i theta_j} a,
        theta_j'' + Im[V'' e^{-i theta_j}] / r_j + d_j (theta_j' - theta0') = 0,

    accelerations from the residual's Jacobian (linear in them) and one solve."""
    s = rotor.shaft
    n, N = s.n_modes, rotor.n_balls
    g = 2.0 if s.gyroscopic == "paper" else -1.0
    a, b, k = s.mode_vectors()
    B = jnp.outer(b, b)
    th0, th0d, th0dd = rotor.speed.angle(t), rotor.speed.speed(t), rotor.speed.acceleration(t)
    q, qd = y[: 2 * n + N], y[2 * n + N:]
    v, th, vd, thd = q[:n] + 1j * q[n:2 * n], q[2 * n:], qd[:n] + 1j * qd[n:2 * n], qd[2 * n:]
    mr = rotor.ball_mass * rotor.ball_radius

    def residual(acc):
        vdd, thdd = acc[:n] + 1j * acc[n:2 * n], acc[2 * n:]
        shaft = (vdd + s.Jt * b * (b @ vdd) + s.m * a * (a @ vdd) + s.d * vd
                 + 1j * g * s.Jp * th0d * (B @ vd) + k**4 * v + 0.5j * g * s.Jp * th0dd * (B @ v)
                 - s.m0 * (th0d**2 - 1j * th0dd) * jnp.exp(1j * th0) * a
                 - jnp.sum(mr * (thd**2 - 1j * thdd) * jnp.exp(1j * th)) * a)
        ball = thdd + jnp.imag((a @ vdd) * jnp.exp(-1j * th)) / rotor.ball_radius + rotor.ball_drag * (thd - th0d)
        return jnp.concatenate([jnp.real(shaft), jnp.imag(shaft), ball])

    zero = jnp.zeros(2 * n + N)
    acc = -jnp.linalg.solve(jax.jacfwd(residual)(zero), residual(zero))
    return jnp.concatenate([qd, acc])


CASES = [
    # modes, balls, radii, drags, m0, Jt, Jp, d, gyroscopic, speed
    (6, [0.02, 0.02], 1.0, 5.0, 0.01, 0.0, 0.0, 0.05, "paper", ConstantSpeed(1.2)),
    (4, [0.02, 0.03, 0.05], [1.0, 0.8, 1.3], [5.0, 0.5, 2.0], 0.02, 0.3, 0.2, 0.1, "paper", RunUp(0.2, 0.3)),
    (5, [0.01], 0.7, 0.0, 0.0, 0.1, 0.4, 0.0, "standard", RunUp(0.5, -0.05, theta0=0.3)),
    (3, [], 1.0, 1.0, 0.01, 0.2, 0.1, 0.02, "paper", RunUp(0.2, 0.002)),
]


def _rotor(modes, balls, radii, drags, m0, Jt, Jp, d, gyroscopic, speed):
    balls = jnp.asarray(balls, dtype=jnp.float64)
    shaft = ModalShaft(modes, 1.0 + float(jnp.sum(balls)) + m0, 0.37, Jt, Jp, d, m0, gyroscopic=gyroscopic)
    return ModalBalancerRotor(shaft, balls, radii, drags, speed)


@pytest.mark.parametrize("case", range(len(CASES)))
def test_composed_field_equals_eq24_at_random_states(case):
    rotor = _rotor(*CASES[case])
    rng = np.random.default_rng(case)
    field, reference = eqx.filter_jit(rotor.vector_field), eqx.filter_jit(kovachev_eq24_field)
    for _ in range(8):
        y = jnp.asarray(rng.normal(size=rotor.state_size))
        t = jnp.asarray(rng.uniform(0.0, 10.0))   # an array: a float would be static to filter_jit
        got, ref = np.asarray(field(t, y)), np.asarray(reference(rotor, t, y))
        assert np.linalg.norm(got - ref) <= 1e-12 * np.linalg.norm(ref)
        assert np.allclose(got, ref, rtol=1e-12, atol=1e-12 * np.abs(ref).max())


def test_balls_and_imbalance_are_the_shared_components():
    rotor = _rotor(*CASES[1])
    parts = rotor.components
    balls = [c for c in parts if isinstance(c, AutoBalancer)]
    assert [type(c) for c in parts] == [RigidRotor] + [AutoBalancer] * 3
    assert len(balls) == rotor.n_balls
    np.testing.assert_array_equal(np.concatenate([np.asarray(c.mass) for c in balls]), np.asarray(rotor.ball_mass))
    np.testing.assert_allclose([float(c.race.r1) for c in balls], [1.0, 0.8, 1.3])
    np.testing.assert_allclose([float(c.drag) for c in balls], np.array([5.0, 0.5, 2.0]) * np.array([0.02, 0.03, 0.05]))
    assert all(float(c.inertia_factor) == 1.0 for c in balls)   # point masses, as eq. (24)
    assert float(parts[0].mass) == float(rotor.shaft.m0) and float(parts[0].eccentricity) == 1.0
    # without balls or imbalance those parts are absent, not zero-mass
    assert _rotor(*CASES[2]).components[0].__class__ is AutoBalancer
    assert [type(c) for c in _rotor(*CASES[3]).components] == [RigidRotor]


def test_the_balls_enter_through_their_energies(monkeypatch):
    """The balls' terms come from `AutoBalancer.kinetic` (called once per ball), not
    from a copy of it: scaling the shared component's kinetic energy changes the field."""
    rotor = _rotor(*CASES[0])
    y = jnp.asarray(np.random.default_rng(7).normal(size=rotor.state_size))
    base = np.asarray(jax.jit(lambda y: rotor.vector_field(0.3, y))(y))   # a fresh function: traced anew
    calls = []
    original = AutoBalancer.kinetic

    def doubled(self, kin, q, qd):
        calls.append(1)
        return 2.0 * original(self, kin, q, qd)

    monkeypatch.setattr(AutoBalancer, "kinetic", doubled)
    changed = np.asarray(jax.jit(lambda y: rotor.vector_field(0.3, y))(y))
    assert len(calls) >= rotor.n_balls
    assert not np.allclose(changed[rotor.n_dof:], base[rotor.n_dof:])
