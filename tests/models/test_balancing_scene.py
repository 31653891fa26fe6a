"""Model 002 integrated as a scene: `BalancingScene.vector_field` is `f(t, y, args)`
(the diffrax convention), takes the shaft's angle, speed and acceleration from its
speed profile, and `rotorjax.simulate` of it at constant speed settles on the
closed-form steady response (`BalancingMachine.response`, `scene.steady_state`)."""

import diffrax
import jax
import jax.numpy as jnp
import numpy as np
import pytest

import rotorjax
from rotorjax._errors import NumericalError
from rotorjax.analysis import balancing_response
from rotorjax.identify import BalancingMachine, BalancingScene, rig_scene
from rotorjax.identify import _make_data as md
from rotorjax.models import ConstantSpeed, CustomSpeed, RunUp


def eq8(machine, planes, unbalances, theta, w, alpha, y):
    """Eq. (8) written out: `A x'' + B x' + C x = sum_j Re(D_j (w^2 - i alpha) e^{i theta}) (l - a_j, a_j) / l`."""
    A, B, C = (np.asarray(a) for a in machine.matrices())
    planes, l = np.asarray(planes), float(machine.l)
    F = np.stack([l - planes, planes]) / l @ np.real(np.asarray(unbalances) * (w**2 - 1j * alpha) * np.exp(1j * theta))
    y = np.asarray(y)
    return np.concatenate([y[2:], np.linalg.solve(A, F - B @ y[2:] - C @ y[:2])])


@pytest.mark.parametrize("w", [120.0, 400.0])
def test_constant_speed_settles_on_the_closed_form_response(w):
    """From rest, the slowest transient (decay rate 17 /s) is below 1e-14 after 2 s;
    then the simulated orbit is `Re(X e^{i w t})` with `X = balancing_response(machine, w, ...)` and
    the state at whole turns is `scene.steady_state(w)`, both to 1e-8."""
    scene = rig_scene(speed=ConstantSpeed(w))
    X = np.asarray(balancing_response(scene.machine, w, scene.planes, scene.unbalances))
    turn = 2 * np.pi / w
    n0 = int(np.ceil(2.0 / turn))
    ts = np.concatenate([[0.0], (n0 + np.linspace(0.0, 3.0, 61)) * turn])
    r = rotorjax.simulate(scene, jnp.zeros(4), (0.0, ts[-1]), saveat=ts, solver="dopri8", rtol=1e-12,
                          atol=1e-18, max_steps=10**6)
    assert r.success
    got = np.stack([r.outputs["x1"], r.outputs["x2"]], axis=1)[1:]
    expect = np.real(X[None, :] * np.exp(1j * w * ts[1:])[:, None])
    assert np.max(np.abs(got - expect)) < 1e-8 * np.max(np.abs(X))
    ss = np.asarray(scene.steady_state(w))
    whole = np.asarray(r.ys)[1::20]                                    # n0, n0 + 1, n0 + 2, n0 + 3 turns
    assert whole.shape == (4, 4)
    for y in whole:
        assert np.max(np.abs(y[:2] - ss[:2])) < 1e-8 * np.max(np.abs(ss[:2]))
        assert np.max(np.abs(y[2:] - ss[2:])) < 1e-8 * np.max(np.abs(ss[2:]))
    # the transient was there to decay: at t = 0 the rotor is at rest, far from the steady state
    assert np.max(np.abs(ss[:2])) > 1e-2 * np.max(np.abs(X))


@pytest.mark.parametrize("profile,angle", [
    (ConstantSpeed(120.0, theta0=0.4), lambda t: (0.4 + 120.0 * t, 120.0, 0.0)),
    (RunUp(20.0, 19.0), lambda t: (20.0 * t + 9.5 * t**2, 20.0 + 19.0 * t, 19.0)),
    (CustomSpeed(lambda t: 50.0 * t + 3.0 * jnp.sin(2.0 * t)),
     lambda t: (50.0 * t + 3.0 * np.sin(2.0 * t), 50.0 + 6.0 * np.cos(2.0 * t), -12.0 * np.sin(2.0 * t))),
])
def test_vector_field_is_f_of_t_y_args_under_the_speed_profile(profile, angle):
    """`f(t, y, args)`: `args` is accepted and ignored (positionally and by keyword),
    and the field is eq. (8) at the profile's angle, speed and acceleration."""
    m = rig_scene().machine
    scene = BalancingScene(m, [0.15, 0.65], [2e-4 + 1e-4j, -3e-4j], profile)
    y = jnp.array([1e-5, -2e-5, 3e-4, 1e-4])
    t = 1.3
    expect = eq8(m, scene.planes, scene.unbalances, *angle(t), y)
    for f in (scene.vector_field(t, y, None), scene.vector_field(t, y, {"anything": 1.0}),
              scene.vector_field(t, y, args=()), scene.vector_field(t, y)):
        np.testing.assert_allclose(f, expect, rtol=1e-12, atol=1e-12 * np.max(np.abs(expect)))
    assert not hasattr(BalancingMachine, "vector_field")


def test_vector_field_is_a_diffrax_term_and_batches_with_vmap():
    """The bound method is a diffrax `ODETerm` as it stands (`rotorjax.simulate` gives the
    same orbit), and is pure: vmapped over states it equals the loop."""
    scene = rig_scene(speed=RunUp(20.0, 19.0))
    y0 = scene.steady_state(20.0)
    ts = jnp.linspace(0.0, 0.5, 11)
    sol = diffrax.diffeqsolve(diffrax.ODETerm(scene.vector_field), diffrax.Dopri8(), 0.0, 0.5, None, y0,
                              args=object(), saveat=diffrax.SaveAt(ts=ts),
                              stepsize_controller=diffrax.PIDController(rtol=1e-11, atol=1e-16))
    r = rotorjax.simulate(scene, y0, (0.0, 0.5), saveat=ts, solver="dopri8", rtol=1e-11, atol=1e-16)
    assert r.success
    np.testing.assert_allclose(r.ys, sol.ys, rtol=0, atol=1e-9 * float(jnp.max(jnp.abs(sol.ys))))
    ys = jnp.stack([y0, 2 * y0, -y0 + 1e-6])
    batched = jax.vmap(lambda y: scene.vector_field(0.3, y, None))(ys)
    for y, fy in zip(ys, batched):
        np.testing.assert_allclose(fy, scene.vector_field(0.3, y, None), rtol=1e-13)


def test_synthetic_data_come_from_simulate(monkeypatch):
    """`_make_data.simulate` is `rotorjax.simulate` of the scene with the generator's
    tolerances (`SOLVER`); `simulate_from` starts on the steady response at the start
    speed; a failed integration raises instead of writing garbage."""
    scene = rig_scene(speed=RunUp(20.0, 38.0))
    t = np.arange(0.0, 0.05, 1e-3)
    x = md.simulate_from(scene, t, 20.0)
    r = rotorjax.simulate(scene, scene.steady_state(20.0), (t[0], t[-1]), saveat=t, **md.SOLVER)
    np.testing.assert_array_equal(x, np.stack([r.outputs["x1"], r.outputs["x2"]], axis=1))
    X = np.asarray(balancing_response(scene.machine, 20.0, scene.planes, scene.unbalances))
    np.testing.assert_allclose(x[0], X.real, rtol=1e-12)
    monkeypatch.setitem(md.SOLVER, "max_steps", 2)
    with pytest.raises(NumericalError, match="balancing machine, 2 correction plane"):
        md.simulate(scene, t)
