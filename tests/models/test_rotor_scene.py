"""The finite-element rotor as a scene (`RotorScene`): its equations against an
independent numpy assembly at random states, its linear part against the
`FlexibleRotor` analyses, its rotating frame, and the FE rotor in time: at
constant speed the simulated orbit is the linear unbalance response at every
node."""

import jax
import jax.numpy as jnp
import numpy as np
import pytest

import rotorjax
from rotorjax.analysis import rotating_field, scene_unbalance_response
from rotorjax.flexible import unbalance_response
from rotorjax.models import (AbstractScene, BalancerAt, AutoBalancer, ClearanceBearing, CubicBearing, Gravity,
                             InternalDamping, JournalBearing, LimitersAt, Limiters, MissingCapability, Race,
                             RotorScene, RunUp, Unbalance, provides)
from rotorjax.presets._ross_compare import PRESET, build_rotor


def _rotor(**over):
    return build_rotor(PRESET.params({"kyy": 1e6, "cxx": 500.0, "cyy": 500.0, **over}))


def test_rotor_scene_is_a_scene_with_its_capabilities():
    sc = RotorScene(_rotor(), 100.0, (Unbalance(2, 1e-3),))
    assert isinstance(sc, AbstractScene)
    for cap in ("linear_matrices", "unbalance_load", "to_rotating", "to_fixed", "energy", "contact_indicator"):
        assert provides(sc, cap)
    with pytest.raises(MissingCapability, match="rotating frame needs the full FE rotor"):
        RotorScene(_rotor().reduce(6), 100.0).to_rotating(0.0, jnp.zeros(12))
    with pytest.raises(MissingCapability, match="no Unbalance"):
        RotorScene(_rotor(), 100.0).unbalance_load(100.0)


def _numpy_field(rotor, t, y, w0, alpha, U, node, phase, k3, k3_node, T_V, g):
    """Independent assembly: `M q'' + (C + T_V Ks + w G1) q' + (K + w T_V Ks J) q = F` on the
    free dofs, written with numpy from the rotor's matrices."""
    M, C, G1, K = (np.asarray(a) for a in rotor.matrices())
    bare = rotorjax.models.FlexibleRotor(rotor.lengths, rotor.d_out, E=rotor.E, G=rotor.G, rho=rotor.rho,
                                         disks=((2, 32.58972765304033, 0.17808928257067666, 0.32956362089137037),
                                                (4, 32.58972765304033, 0.17808928257067666, 0.32956362089137037)))
    Ks = np.asarray(bare.matrices()[3])
    n_nodes = rotor.n_nodes
    J = np.kron(np.eye(n_nodes), np.array([[0, 1, 0, 0], [-1, 0, 0, 0], [0, 0, 0, 1], [0, 0, -1, 0]]))
    theta, w, wd = w0 * t + 0.5 * alpha * t**2, w0 + alpha * t, alpha
    n = M.shape[0]
    q, qd = y[:n], y[n:]
    F = np.zeros(n)
    a = theta + phase
    F[4 * node:4 * node + 2] = U * (w**2 * np.array([np.cos(a), np.sin(a)]) + wd * np.array([np.sin(a), -np.cos(a)]))
    u = q[4 * k3_node:4 * k3_node + 2]
    F[4 * k3_node:4 * k3_node + 2] += -k3 * (u @ u) * u
    e = np.zeros(n)
    e[1::4] = -1.0
    F += g * M @ e
    qdd = np.linalg.solve(M, F - (C + T_V * Ks + w * G1) @ qd - (K + w * T_V * Ks @ J) @ q)
    return np.concatenate([qd, qdd])


def test_vector_field_equals_an_independent_assembly_at_random_states():
    rotor = _rotor()
    comps = (Unbalance(3, 2e-3, 0.4), CubicBearing(6, 5e11), InternalDamping(2e-4), Gravity(9.81))
    sc = RotorScene(rotor, RunUp(80.0, 3.0), comps)
    rng = np.random.default_rng(0)
    for _ in range(3):
        t = rng.uniform(0, 2)
        y = rng.normal(size=sc.state_size) * 1e-4
        got = np.asarray(sc.vector_field(t, jnp.asarray(y)))
        want = _numpy_field(rotor, t, y, 80.0, 3.0, 2e-3, 3, 0.4, 5e11, 6, 2e-4, 9.81)
        assert np.allclose(got, want, rtol=1e-10, atol=1e-10 * np.abs(want).max())


def test_local_forces_split_the_equations_at_random_states():
    """`local_forces()` (what harmonic balance condenses on): `y' = A y + a0 + E
    force(t, S q, S q')` at random states and times, with every kind of force at a
    node (cubic, clearance, journal film, limiters, unbalance) and whole-shaft linear
    parts (internal damping, gravity); the read coordinates are the nodes whose
    forces read the motion (not the unbalance's); no split where the equations are
    not of that form."""
    rotor = _rotor()
    comps = (Unbalance(3, 2e-3, 0.4), CubicBearing(6, 5e11, k=1e5), ClearanceBearing(2, 2e-4, 1e7, c=50.0),
             JournalBearing(0, 0.02, 0.02, 0.05, 1e-3),
             LimitersAt(4, Limiters(np.arange(3) * 2.1, 3e-4, stiffness=1e7, damping=2e3, friction=0.1), 0.1),
             InternalDamping(2e-4), Gravity(9.81))
    sc = RotorScene(rotor, 90.0, comps)
    local = sc.local_forces()
    ns = sc.n_dof
    assert local.S.shape == (8, ns) and local.E.shape == (2 * ns, 10) and local.A.shape == (2 * ns, 2 * ns)
    rng = np.random.default_rng(1)
    for _ in range(4):
        t = rng.uniform(0, 1)
        y = rng.normal(size=sc.state_size) * 3e-4
        want = np.asarray(sc.vector_field(t, jnp.asarray(y)))
        q, qd = y[:ns], y[ns:]
        got = np.asarray(local.A @ y + local.a0 + local.E @ local.force(t, local.S @ q, local.S @ qd))
        assert np.allclose(got, want, rtol=1e-11, atol=1e-11 * np.abs(want).max())
    assert RotorScene(rotor, RunUp(80.0, 3.0), comps).local_forces() is None
    assert RotorScene(rotor, 90.0, comps, track_work=True).local_forces() is None
    balancer = BalancerAt(2, AutoBalancer(jnp.full(2, 0.05), Race.circular(0.05), drag=0.3))
    assert RotorScene(rotor, 90.0, (balancer,)).local_forces() is None


def test_linear_part_and_unbalance_load_match_the_flexible_rotor_analyses():
    rotor = _rotor(kyy=0.8e6)
    sc = RotorScene(rotor, 0.0, (Unbalance(2, 1e-3, 0.7),))
    speeds = np.array([50.0, 97.0, 250.0])
    Q = np.asarray(scene_unbalance_response(sc, speeds))
    X, Y = (np.asarray(a) for a in unbalance_response(rotor, 2, 1e-3, 0.7, speeds))
    full = np.array([np.asarray(rotor.expand(q)) for q in Q])
    assert np.allclose(full[:, 0::4], X, rtol=1e-10, atol=1e-16)
    assert np.allclose(full[:, 1::4], Y, rtol=1e-10, atol=1e-16)
    M, C, G1, K = rotor.reduced_matrices()
    lin = sc.linear_matrices(120.0)
    for a, b in ((lin.M, M), (lin.C, C), (lin.G, 120.0 * G1), (lin.K, K)):
        # the scene assembles in one compiled program, the rotor op by op: equal up to rounding
        assert np.allclose(np.asarray(a), np.asarray(b), rtol=0, atol=1e-14 * np.abs(np.asarray(b)).max())


def test_rotating_frame_round_trip_and_autonomy():
    rotor = _rotor()
    comps = (Unbalance(2, 1e-3), CubicBearing(0, 1e12),
             BalancerAt(2, AutoBalancer(jnp.full(2, 0.05), Race.circular(0.05), drag=0.3)))
    sc = RotorScene(rotor, 150.0, comps)
    rng = np.random.default_rng(1)
    y = jnp.asarray(rng.normal(size=sc.state_size) * 1e-4)
    assert np.allclose(sc.to_fixed(0.3, sc.to_rotating(0.3, y)), y, rtol=1e-12, atol=1e-16)
    z = sc.to_rotating(0.0, y)
    a, b = rotating_field(sc, 0.0, z), rotating_field(sc, 0.77, z)
    assert np.allclose(a, b, rtol=1e-9, atol=1e-9 * float(jnp.max(jnp.abs(a))))


def test_fe_rotor_in_time_steady_orbit_equals_the_linear_unbalance_response():
    """`simulate` at constant speed. Full FE rotor, started on the linear unbalance
    response: it stays there (to the integration tolerance). Its lowest 8 modes
    (`rotor.reduce(8)`; the full rotor's high modes are almost undamped), started at
    rest: after the transient the orbit at every node is the (reduced) rotor's linear
    unbalance response to 1e-6 of its amplitude."""
    rotor = _rotor(cxx=3000.0, cyy=3000.0)
    w = 200.0
    parts = (Unbalance(2, 1e-3, 0.3), Unbalance(4, 5e-4, 2.0))
    period = 2 * np.pi / w
    sc = RotorScene(rotor, w, parts)
    Q = np.asarray(scene_unbalance_response(sc, np.array([w])))[0]
    res = rotorjax.simulate(sc, sc.state_from_response(Q, w), (0.0, 5 * period),
                            saveat=np.linspace(0, 5 * period, 6), rtol=1e-11, atol=1e-14).raise_if_failed()
    want = np.array([np.real(Q * np.exp(1j * w * t)) for t in np.asarray(res.ts)])
    assert np.max(np.abs(np.asarray(res.ys)[:, :sc.n_shaft] - want)) < 1e-8 * np.max(np.abs(want))

    sc = RotorScene(rotor.reduce(8), w, parts)
    Q = np.asarray(scene_unbalance_response(sc, np.array([w])))[0]
    decay = -float(np.max(np.real(np.linalg.eigvals(np.asarray(sc.linear_matrices(w).state_matrix())))))
    t_end = np.ceil(np.log(1e8) / decay / period) * period
    ts = t_end - period * np.linspace(0, 1, 9)[::-1]
    res = rotorjax.simulate(sc, sc.rest_state(), (0.0, t_end), saveat=ts, solver="tsit5", rtol=1e-10,
                            atol=1e-14, max_steps=1_000_000).raise_if_failed()
    full = np.asarray(sc.expand(Q))
    amp = np.max(np.abs(full[0::4]))
    for k, t in enumerate(np.asarray(res.ts)):
        e = np.exp(1j * w * t)
        assert np.max(np.abs(np.asarray(res.outputs["node_x"])[k] - np.real(full[0::4] * e))) < 1e-6 * amp
        assert np.max(np.abs(np.asarray(res.outputs["node_y"])[k] - np.real(full[1::4] * e))) < 1e-6 * amp


def test_balancer_equations_equal_the_global_lagrangian_at_random_states():
    """The scene assembles each balancer's Lagrange equations in its node's local
    coordinates; here they are derived instead from the whole system's Lagrangian
    `q'^T M q' / 2 + T_balls(P_k q, P_k q', psi, psi')` with the shaft's other
    forces added, by autodiff over all coordinates."""
    from rotorjax.models import Kinematics, lagrange_accelerations

    for rotor in (_rotor(), _rotor().reduce(6)):
        bal = AutoBalancer(jnp.array([0.05, 0.07]), Race(0.05, 0.04), drag=0.3)
        sc = RotorScene(rotor, RunUp(120.0, 5.0), (Unbalance(2, 1e-3), BalancerAt(2, bal)))
        ns, n = sc.n_shaft, sc.n_dof
        P = rotor.expand(jnp.eye(ns))[8:10]

        def kin(q, qd, t):
            x, xd = P @ q[:ns], P @ qd[:ns]
            return Kinematics(t=t, theta=sc.speed.angle(t), theta_dot=sc.speed.speed(t), x=x[0], y=x[1],
                              xd=xd[0], yd=xd[1])

        def lag(q, qd, t):
            return 0.5 * qd[:ns] @ sc.M @ qd[:ns] + bal.kinetic(kin(q, qd, t), q[ns:], qd[ns:])

        def dis(q, qd, t):
            return bal.dissipation(kin(q, qd, t), q[ns:], qd[ns:])

        @jax.jit
        def both(t, y):
            q, qd = y[:n], y[n:]
            f, _ = sc._forces(t, q, qd, None)
            want = lagrange_accelerations(lag, dis, q, qd, t, force=jnp.concatenate([f, jnp.zeros(2)]))
            return sc.vector_field(t, y)[n:], want

        rng = np.random.default_rng(2)
        for _ in range(2):
            t = rng.uniform(0, 1)
            y = jnp.asarray(np.concatenate([rng.normal(size=ns) * 1e-4, rng.uniform(0, 6, 2),
                                            rng.normal(size=ns) * 1e-2, rng.normal(size=2)]))
            got, want = both(t, y)
            assert np.allclose(got, want, rtol=1e-10, atol=1e-10 * float(jnp.max(jnp.abs(want))))


def test_linear_analyses_take_the_scene_and_say_when_they_cannot():
    """Campbell, 1x critical speeds, margins and Hopf points run on a `RotorScene`
    (its linear part: components included) and equal the rotor's own where the
    components add nothing linear; a scene without a linear part is refused by name."""
    from rotorjax.analysis import critical_speeds, hopf_points, linear_margin
    from rotorjax.flexible import campbell, critical_speeds_1x
    from rotorjax.presets import jeffcott_abb

    rotor = _rotor(kyy=0.8e6)
    sc = RotorScene(rotor, 0.0, (Unbalance(2, 1e-3),))
    speeds = np.array([0.0, 300.0])
    assert np.array_equal(np.asarray(campbell(sc, speeds).frequencies), np.asarray(campbell(rotor, speeds).frequencies))
    assert critical_speeds_1x(sc, 10.0, 400.0) == critical_speeds_1x(rotor, 10.0, 400.0)
    voigt = RotorScene(rotor, 0.0, (InternalDamping(1e-3),))
    (h,) = hopf_points(voigt, 50.0, 400.0, n_scan=40)
    (h2,) = hopf_points(lambda s: voigt.linear_matrices(s).state_matrix(), 50.0, 400.0, n_scan=40)
    assert h.speed == h2.speed
    (c,) = critical_speeds(voigt, 50.0, 400.0, n_scan=40)
    assert abs(c.speed - h.speed) < 1e-8 and abs(float(linear_margin(voigt, c.speed))) < 1e-6
    planar = jeffcott_abb.PRESET.build(jeffcott_abb.PRESET.params()).scene
    with pytest.raises(MissingCapability, match="hopf_points needs a scene with `linear_matrices`"):
        hopf_points(planar, 0.5, 2.0)



def test_unbalance_force_is_minus_the_offset_mass_times_its_acceleration():
    """The unbalance's force on its node during a run-up is `-U d^2/dt^2 (cos a, sin a)`
    with `a = theta(t) + phase` (differentiated by autodiff here), centrifugal and
    tangential parts alike; the tangential one lags the offset (it was once of the
    wrong sign)."""
    profile = RunUp(40.0, 25.0, theta0=0.3)
    u = Unbalance(1, 2e-3, phase=0.7)
    rotor = _rotor()
    sc = RotorScene(rotor, profile, (u,))
    for t in (0.0, 0.13, 0.71):
        offset = lambda tt: jnp.stack([jnp.cos(profile.angle(tt) + 0.7), jnp.sin(profile.angle(tt) + 0.7)])  # noqa
        expected = -2e-3 * jax.jacfwd(jax.jacfwd(offset))(jnp.float64(t))
        q = jnp.zeros(sc.n_dof)
        s = sc.shaft_state(jnp.float64(t), q, q)
        full = np.asarray(u.force(s, q, q).on_dofs(rotor.n_dofs))   # a NodeLoad, as an all-dof load
        np.testing.assert_allclose(full[4:6], np.asarray(expected), rtol=1e-12, atol=1e-18)
