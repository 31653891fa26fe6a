"""Model 003's balancer rotor and model 004's cantilever scene on the scene contract:
what they provide, their rotating frame, linear matrices and unbalance response
against the formulas they replaced."""

import ast
import pathlib

import jax
import jax.numpy as jnp
import numpy as np
import pytest

import rotorjax
from rotorjax._errors import InputError
from rotorjax.analysis import (balancing_response, least_stable_whirl, linear_margin, modal003_natural_frequencies,
                               modal003_response, rotating_field, scene_unbalance_response, state_matrix)
from rotorjax.flexible import ModalBalancerRotor, ModalShaft
from rotorjax.models import BalancingMachine, CantileverRotor, ConstantSpeed, RunUp
from tests.reference.model_004_scene import CantileverScene
from rotorjax.models._contract import AbstractScene, MissingCapability, provides
from rotorjax.models._frequency import frequency_response

CAPABILITIES = ("linear_matrices", "unbalance_load", "to_rotating", "to_fixed", "contact_indicator", "energy")


def balancer(speed=ConstantSpeed(1.2), modes=4):
    shaft = ModalShaft(modes, 1.04, 0.4, Jt=0.02, Jp=0.01, d=0.05, m0=0.01)
    return ModalBalancerRotor(shaft, jnp.array([0.02, 0.02]), 1.0, 5.0, speed)


def cantilever():
    return CantileverRotor(0.7, 0.005, 0.03, 0.005, 0.025, eta_Dxi=0.01, n_elements=3)


def test_both_models_are_scenes_that_say_what_they_provide():
    scene, rotor = CantileverScene(cantilever(), 5.0, eps=1e-3), balancer()
    assert isinstance(scene, AbstractScene) and isinstance(rotor, AbstractScene)
    assert {c for c in CAPABILITIES if provides(scene, c)} == {"linear_matrices", "unbalance_load",
                                                               "contact_indicator", "energy"}
    assert {c for c in CAPABILITIES if provides(rotor, c)} == {"to_rotating", "to_fixed"}
    assert scene.n_dof == scene.n_coords and rotor.n_dof == 2 * 4 + 2
    assert isinstance(scene.speed, ConstantSpeed) and float(scene.speed.speed(3.0)) == 5.0
    with pytest.raises(MissingCapability, match="ModalBalancerRotor .* linear"):
        rotorjax.analysis.linear_margin(rotor, 1.2)
    with pytest.raises(MissingCapability, match="modes needs a scene with `linear_system`; ModalBalancerRotor .*AbstractLinearSystem"):
        rotorjax.analysis.modes(rotor, 1.2)


def _old_rotating_field(rotor, z):
    """The rotating-frame field before the contract: the inverse map at constant
    speed and `solve(jz, f - jt)`."""
    omega = rotor.speed.speed(0.0)
    n, nb = rotor.shaft.n_modes, rotor.n_balls

    def to_fixed(t, zz):
        q, qd = zz[: 2 * n + nb], zz[2 * n + nb:]
        v, al, wd, ald = q[:n] + 1j * q[n:2 * n], q[2 * n:], qd[:n] + 1j * qd[n:2 * n], qd[2 * n:]
        e = jnp.exp(1j * omega * t)
        return rotor.state(v * e, al + omega * t, (wd + 1j * omega * v) * e, ald + omega)

    f = lambda zz, tt: to_fixed(tt, zz)  # noqa: E731
    jz = jax.jacfwd(f, argnums=0)(z, 0.0)
    jt = jax.jacfwd(f, argnums=1)(z, 0.0)
    return jnp.linalg.solve(jz, rotor.vector_field(0.0, f(z, 0.0)) - jt)


def test_generic_rotating_field_equals_the_old_one():
    rotor = balancer()
    old_field = jax.jit(lambda z: _old_rotating_field(rotor, z))
    generic = jax.jit(lambda t, z: rotating_field(rotor, t, z))
    method = jax.jit(lambda z: rotor.rotating_field(z))
    rng = np.random.default_rng(3)
    for _ in range(4):
        z = jnp.asarray(rng.normal(size=rotor.state_size) * 0.2)
        old = np.asarray(old_field(z))
        np.testing.assert_allclose(np.asarray(generic(0.0, z)), old, rtol=1e-12, atol=1e-12)
        np.testing.assert_allclose(np.asarray(method(z)), old, rtol=1e-12, atol=1e-12)
        # autonomous at constant speed
        np.testing.assert_allclose(np.asarray(generic(2.3, z)), old, rtol=1e-10, atol=1e-12)


def test_rotating_frame_round_trip_on_a_run_up():
    rotor = balancer(RunUp(0.3, 0.05, theta0=0.4))
    rng = np.random.default_rng(4)
    y = jnp.asarray(rng.normal(size=rotor.state_size))
    for t in (0.0, 1.7, 12.0):
        z = rotor.to_rotating(t, y)
        np.testing.assert_allclose(np.asarray(rotor.to_fixed(t, z)), np.asarray(y), rtol=1e-13, atol=1e-13)
        # the balls' angles are relative to the imbalance, the disk centre's modulus is frame-free
        th0 = float(rotor.speed.angle(t))
        np.testing.assert_allclose(np.asarray(z[8:10]), np.asarray(y[8:10]) - th0, rtol=1e-13)
        n = 4
        np.testing.assert_allclose(np.hypot(z[:n], z[n:2 * n]), np.hypot(y[:n], y[n:2 * n]), rtol=1e-13)


def test_cantilever_scene_linear_matrices_are_the_rotors():
    rotor = cantilever()
    scene = CantileverScene(rotor, 7.0, eps=1e-3, phase=0.4)
    for N in (0.0, 3.0, 7.0):
        np.testing.assert_allclose(np.asarray(scene.linear_matrices(N).state_matrix()),
                                   np.asarray(state_matrix(rotor, N)), rtol=1e-14, atol=1e-14)
    lin = scene.linear_matrices()
    assert np.array_equal(np.asarray(lin.G), np.asarray(7.0 * scene.G1))
    # reduced scenes: the same matrices projected on the modes
    reduced = CantileverScene(rotor, 7.0, n_modes=5)
    P = reduced.basis
    full = rotor.linear_matrices(7.0)
    np.testing.assert_allclose(np.asarray(reduced.linear_matrices(7.0).K), np.asarray(P.T @ full.K @ P),
                               rtol=1e-12, atol=1e-12)


def test_unbalance_responses_equal_the_old_formulas():
    rotor = cantilever()
    M, C, G1, K, Ci, J = rotor.matrices()
    d = rotor.disk_dofs
    for N, eps, phase in ((3.0, 1e-3, 0.0), (8.0, 5e-4, 0.7)):
        fx = eps * N**2 * jnp.exp(1j * phase)
        F = jnp.zeros(M.shape[0], dtype=jnp.complex128).at[d[0]].set(fx).at[d[1]].set(-1j * fx)
        old = jnp.linalg.solve(K + N * Ci @ J - N**2 * M + 1j * N * (C + Ci + N * G1), F)
        composed = rotorjax.models.cantilever_scene(rotor, N, eps=eps, phase=phase)
        np.testing.assert_allclose(np.asarray(scene_unbalance_response(composed, jnp.array([N]))[0]),
                                   np.asarray(old), rtol=1e-13, atol=1e-20)
        scene = CantileverScene(rotor, N, eps=eps, phase=phase)
        y = scene.synchronous_state()
        n = scene.n_coords
        np.testing.assert_allclose(np.asarray(y[:n]), np.asarray(jnp.real(old)), rtol=1e-13, atol=1e-20)
        np.testing.assert_allclose(np.asarray(y[n:2 * n]), np.asarray(jnp.real(1j * N * old)), rtol=1e-13,
                                   atol=1e-20)
        np.testing.assert_allclose(np.asarray(scene.unbalance_load(N)), np.asarray(F), rtol=0, atol=0)
    # model 003: the rank-2 response is the frequency response of the synchronous matrices
    shaft = ModalShaft(10, 0.8, 0.3, Jt=0.02, Jp=0.01, d=0.05, m0=0.01)
    a, b, _ = shaft.mode_vectors()
    for w in (0.4, 2.0, 7.5):
        W = frequency_response(*shaft.synchronous_matrices(), shaft.m0 * w**2 * a, w)
        disk, tilt = modal003_response(shaft, w)
        np.testing.assert_allclose(complex(disk), complex(a @ W), rtol=1e-10)
        np.testing.assert_allclose(complex(tilt), complex(b @ W), rtol=1e-10)


def test_speed_is_the_name_and_the_paper_symbols_are_aliases():
    assert ConstantSpeed(2.0) == ConstantSpeed(speed=2.0) == ConstantSpeed(omega=2.0)
    assert float(ConstantSpeed(speed=2.0, theta0=0.5).omega) == 2.0
    assert RunUp(0.2, 0.1) == RunUp(speed0=0.2, acceleration=0.1) == RunUp(omega0=0.2, acceleration=0.1)
    rotor = cantilever()
    with pytest.deprecated_call():   # the deprecated analysis methods keep the paper's N as well
        for method in ("state_matrix", "eigenvalues", "stability_margin"):
            np.testing.assert_array_equal(np.asarray(getattr(rotor, method)(4.0)),
                                          np.asarray(getattr(rotor, method)(N=4.0)))
        np.testing.assert_array_equal(np.asarray(rotor.unbalance_response(4.0, 1e-3)),
                                      np.asarray(rotor.unbalance_response(N=4.0, eps=1e-3)))
    shaft = ModalShaft(6, 1.0, 0.5, d=0.1, m0=0.01)
    assert complex(shaft.sums(2.0)[0]) == complex(shaft.sums(w=2.0)[0])
    with pytest.deprecated_call():
        assert complex(shaft.response(speed=2.0)[0]) == complex(shaft.response(w=2.0)[0])
    with pytest.raises(InputError, match="as speed or as omega"):
        ConstantSpeed(1.0, omega=2.0)
    with pytest.raises(InputError, match="as speed or as N"):
        rotor.state_matrix(1.0, N=2.0)


def test_deprecated_analysis_methods_warn_and_equal_the_analyses():
    """Issue 29: the analyses of models 002-004 live in `rotorjax.analysis`; the old
    methods stay one release, each warning with the function to call instead."""
    rotor, N = cantilever(), 6.0

    def old(obj, method, *args, **kw):
        with pytest.warns(DeprecationWarning, match=f"{type(obj).__name__}.{method} is deprecated.*rotorjax.analysis"):
            return getattr(obj, method)(*args, **kw)

    np.testing.assert_array_equal(np.asarray(old(rotor, "state_matrix", N)), np.asarray(state_matrix(rotor, N)))
    lam = np.asarray(old(rotor, "eigenvalues", N))
    new = np.linalg.eigvals(np.asarray(state_matrix(rotor, N)))
    np.testing.assert_allclose(np.sort_complex(lam), np.sort_complex(new), rtol=1e-12)
    assert float(old(rotor, "stability_margin", N)) == pytest.approx(float(linear_margin(rotor, N)), rel=1e-12)
    lam_old, fwd_old = old(rotor, "whirl_direction", N)
    lam_new, fwd_new = least_stable_whirl(rotor, N, rotor.disk_dofs[:2])
    assert complex(lam_old) == pytest.approx(complex(lam_new), rel=1e-12) and bool(fwd_old) == bool(fwd_new)
    composed = rotorjax.models.cantilever_scene(rotor, N, eps=1e-3, phase=0.3)
    np.testing.assert_allclose(np.asarray(old(rotor, "unbalance_response", N, 1e-3, 0.3)),
                               np.asarray(scene_unbalance_response(composed, jnp.array([N]))[0]), rtol=1e-12,
                               atol=1e-20)
    shaft = ModalShaft(10, 0.8, 0.3, Jt=0.02, Jp=0.01, d=0.05, m0=0.01)
    for a, b in zip(old(shaft, "natural_frequencies"), modal003_natural_frequencies(shaft)):
        np.testing.assert_array_equal(np.asarray(a), np.asarray(b))
    for a, b in zip(old(shaft, "response", 2.0), modal003_response(shaft, 2.0)):
        np.testing.assert_allclose(complex(a), complex(b), rtol=1e-10)
    machine = BalancingMachine(10.0, 0.5, 0.8, 2e5, 3e5, 150.0, 200.0)
    planes, D = jnp.array([0.15, 0.65]), jnp.array([2e-4j, -3e-4 + 1e-4j])
    np.testing.assert_array_equal(np.asarray(old(machine, "response", 120.0, planes, D)),
                                  np.asarray(balancing_response(machine, 120.0, planes, D)))


@pytest.mark.parametrize("name", ["_modal", "_modal_balancer", "_cantilever", "_cantilever_scene", "_speed"])
def test_model_modules_import_no_analysis(name):
    source = pathlib.Path(rotorjax.__file__).parent / "models" / f"{name}.py"
    banned = ("analysis", "flexible", "identify", "presets", "cli", "solve")
    for node in ast.walk(ast.parse(source.read_text())):
        if isinstance(node, ast.ImportFrom):
            parts = (node.module or "").split(".")
            assert not (node.level >= 2 and parts[0] in banned), f"{name} imports {node.module}"
            assert not (parts[0] == "rotorjax" and len(parts) > 1 and parts[1] in banned)
