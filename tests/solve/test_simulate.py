"""simulate: result codes, solver choice, vmap, recompilation, gradients."""

import diffrax
import equinox as eqx
import jax
import jax.numpy as jnp
import numpy as np
import pytest

import rotorjax as rj
from rotorjax import presets
from rotorjax.models import _scene as scene_module
from rotorjax.presets import anisotropic_abb, jeffcott_abb
from rotorjax.solve._results import result_code
from tests.helpers import central_difference

P001 = presets.get("anisotropic-abb")
GROUPS_001 = {k: P001.defaults[k] for k in anisotropic_abb.GROUPS}


def _scene_001(n=3.0, **over):
    return anisotropic_abb.scene_from_groups(**dict(GROUPS_001, **over), n=n)


def _y0(scene):
    return scene.rest_state(np.array([2.2, 4.1]))


def test_max_steps_is_reported_not_raised():
    s = _scene_001()
    r = rj.simulate(s, _y0(s), (0.0, 100.0), saveat=5, max_steps=20)
    assert int(r.code) == 1 and not bool(r.success)
    assert "max_steps" in r.message
    with pytest.raises(RuntimeError, match="max_steps"):
        r.raise_if_failed()


def test_nonfinite_values_are_reported():
    ys = jnp.array([[0.0, 1.0], [jnp.nan, 0.0]])
    assert int(result_code(diffrax.RESULTS.successful, ys)) == 2
    assert int(result_code(diffrax.RESULTS.successful, jnp.ones((2, 2)))) == 0


def test_blow_up_is_marked_in_a_batch_without_raising():
    """A lane whose explicit solve cannot cope is marked; the others succeed."""
    g = {k: jeffcott_abb.PRESET.defaults[k] for k in jeffcott_abb.GROUPS}

    def one(delta_b):
        s = jeffcott_abb.scene_from_groups(**dict(g, delta_b=delta_b), nu=1.5)
        return rj.simulate(s, s.rest_state(np.array([0.5, 2.5])), (0.0, 30.0), solver="dopri8",
                           max_steps=3000).code

    codes = np.asarray(eqx.filter_vmap(one)(jnp.array([40.0, 4000.0])))
    assert codes[0] == 0 and codes[1] != 0


def test_auto_solver_switches_to_implicit_for_stiff_scenes():
    g = {k: jeffcott_abb.PRESET.defaults[k] for k in jeffcott_abb.GROUPS}
    for delta_b, expected in ((40.0, "Dopri8"), (4000.0, "Kvaerno5")):
        s = jeffcott_abb.scene_from_groups(**dict(g, delta_b=delta_b), nu=1.5)
        r = rj.simulate(s, s.rest_state(np.array([0.5, 2.5])), (0.0, 30.0), rtol=1e-6, atol=1e-8)
        assert r.solver == expected and bool(r.success)


def test_solver_names_and_bad_arguments():
    s = _scene_001()
    y0 = _y0(s)
    assert rj.simulate(s, y0, (0.0, 1.0), solver="tsit5").solver == "Tsit5"
    assert rj.simulate(s, y0, (0.0, 1.0), solver=diffrax.Dopri5()).solver == "Dopri5"
    with pytest.raises(ValueError, match="solver"):
        rj.simulate(s, y0, (0.0, 1.0), solver="euler-ish")
    with pytest.raises(ValueError, match=r"y0 must have shape \(8,\)"):
        rj.simulate(s, y0[:5], (0.0, 1.0))
    with pytest.raises(ValueError, match="t_span must be increasing"):
        rj.simulate(s, y0, (1.0, 0.0))
    with pytest.raises(ValueError, match="rtol"):
        rj.simulate(s, y0, (0.0, 1.0), rtol=0.0)
    with pytest.raises(ValueError, match="y0 must be finite"):
        rj.simulate(s, y0.at[0].set(jnp.nan), (0.0, 1.0))


def test_vmap_equals_loop():
    speeds = np.array([0.9, 3.0, 5.5])

    def one(n):
        s = _scene_001(n)
        return rj.simulate(s, _y0(s), (0.0, 20.0), solver="dopri8").ys[-1]

    batched = np.asarray(eqx.filter_vmap(one)(jnp.asarray(speeds)))
    looped = np.stack([np.asarray(one(n)) for n in speeds])
    np.testing.assert_allclose(batched, looped, rtol=1e-7, atol=1e-9)


def test_no_recompilation_on_second_call(monkeypatch):
    """The equations are traced once: new speeds, parameters, end times do not
    recompile (counted on both the fast and the Lagrangian path)."""
    jax.clear_caches()  # another test on this worker may have compiled the same call
    traces = []

    def counting(original):
        def wrapped(*args, **kwargs):
            traces.append(1)
            return original(*args, **kwargs)
        return wrapped

    monkeypatch.setattr(scene_module, "lagrange_accelerations", counting(scene_module.lagrange_accelerations))
    monkeypatch.setattr(scene_module, "planar_balancer_field", counting(scene_module.planar_balancer_field))
    for n in (2.0, 2.5, 4.0):
        s = _scene_001(n, mu_w=0.3 + n / 10)
        rj.simulate(s, _y0(s), (0.0, 3.0 + n), saveat=4, solver="dopri8")
        if n == 2.0:
            after_first = len(traces)
    assert after_first > 0 and len(traces) == after_first


def test_gradient_wrt_support_damping_matches_finite_differences():
    """d(final whirl amplitude)/d(mu_xi) by reverse mode through the solve."""

    def final_amplitude(mu_xi):
        s = _scene_001(3.0, mu_xi=mu_xi)
        r = rj.simulate(s, _y0(s), (0.0, 20.0), solver="dopri8", rtol=1e-12, atol=1e-14)
        return r.outputs["whirl_amplitude"][-1]

    x = 0.25
    g = float(jax.grad(final_amplitude)(jnp.float64(x)))
    fd = central_difference(lambda v: float(final_amplitude(jnp.float64(v))), x, 1e-4)
    assert g == pytest.approx(fd, rel=1e-6)
