"""`Preset.build` returns the same thing for every preset: a `Setup` whose scene is a
`rotorjax.models.AbstractScene`; the hooks that replaced the CLI's per-preset code."""

import os

import numpy as np
import pytest

import rotorjax
from rotorjax import presets
from rotorjax.flexible import ModalBalancerRotor
from rotorjax.identify import BalancingScene
from rotorjax.models import AbstractScene, RotorScene
from rotorjax.presets import Setup

ROTOR_FILE = os.path.join(os.path.dirname(rotorjax.__file__), "rotors", "ross_compare.toml")


@pytest.mark.parametrize("name", sorted(presets.PRESETS))
def test_every_preset_builds_a_setup_of_a_scene(name):
    p = presets.get(name)
    setup = p.build(p.params())
    assert isinstance(setup, Setup) and isinstance(setup.scene, AbstractScene)
    assert isinstance(setup.extras, dict)
    if setup.y0 is not None:
        assert np.shape(setup.y0) == (setup.scene.state_size,) and setup.t_end > 0
        assert np.all(np.isfinite(np.asarray(setup.scene.vector_field(0.0, setup.y0))))


def test_scenes_of_the_linear_presets():
    rc = presets.get("ross-compare")
    scene = rc.build(rc.params()).scene
    assert isinstance(scene, RotorScene)
    ref = presets.ross_compare.build_rotor(rc.params())
    for a, b in zip(scene.rotor.reduced_matrices(), ref.reduced_matrices()):
        np.testing.assert_array_equal(np.asarray(a), np.asarray(b))
    fa = presets.get("flexible-abb")
    scene = fa.build(fa.params()).scene                     # 0 balls: the bare shaft + disk
    assert isinstance(scene, ModalBalancerRotor) and scene.n_balls == 0
    assert scene.shaft.n_modes == fa.defaults["modes"]
    assert fa.build(fa.params({"n_balls": 2})).scene.n_balls == 2
    bm = presets.get("balancing-machine")
    scene = bm.build(bm.params()).scene
    assert isinstance(scene, BalancingScene)
    np.testing.assert_array_equal(np.asarray(scene.planes), [bm.defaults["a1"], bm.defaults["a2"]])
    assert bm.defaults == rotorjax.identify.RIG


def test_contact_extras():
    cl = presets.get("cantilever-limiters")
    setup = cl.build(cl.params({"events": 1, "revolutions": 10}))
    assert setup.extras["events"] is True and setup.extras["revolutions"] == 10
    assert setup.t_end == pytest.approx(2 * np.pi / cl.defaults["N"] * 10)
    bm = presets.balancing_machine
    scene = bm.build(bm.PRESET.defaults).scene
    assert isinstance(scene.machine, rotorjax.identify.BalancingMachine)
    assert scene.planes.shape == scene.unbalances.shape == (2,)


def test_default_boxes_and_ranges():
    cl = presets.get("cantilever-limiters")
    assert cl.boundary_box("N", "eta_e", (13.9, 0.025)) == ([1.0, 40.0, 0.0, 0.06], "the preset's default box")
    box, source = cl.boundary_box("N", "eta_i", (13.9, 0.005))
    assert box == [1.0, 40.0, 0.0025, 0.01] and source == "N: the preset's default box; eta_i: the start halved " \
                                                          "and doubled"
    box, source = cl.boundary_box("eps", "phase", (0.0, -1.0))
    assert box == [0.0, 1.0, -2.0, 0.0] and source == "default (start halved and doubled)"
    assert presets.Preset.continuation_range(-2.0) == (-4.0, -1.0) and presets.Preset.continuation_range(0) == (-1, 1)


def test_hooks_say_what_each_preset_offers():
    by = presets.PRESETS
    assert by["anisotropic-abb"].margin_gradient == "fd" and by["elliptic-abb"].margin_gradient == "autodiff"
    assert by["elliptic-abb"].branch_problem is not None and by["anisotropic-abb"].floquet_family is not None
    assert by["anisotropic-abb"].criterion_roots(by["anisotropic-abb"].params(), 4.5, 5.5) == \
        pytest.approx([5.040672901949166])
    assert set(by["cantilever-limiters"].sweepable) == {"eps", "N", "phase", "f_S", "chi", "kappa", "eta_S"}
    assert by["ross-compare"].critical_speeds is not None and by["cantilever-limiters"].hopf is not None
    for name in ("ross-compare", "balancing-machine"):
        assert by[name].regimes is None and by[name].hopf is None


def test_ross_compare_critical_speeds_hook():
    rc = presets.get("ross-compare")
    out = rc.critical_speeds(rc.params(), 10.0, 200.0, n_scan=40)
    assert [round(c["speed"], 3) for c in out["critical_speeds"]] == [91.788, 96.296]
    np.testing.assert_allclose(out["synchronous_determinant_roots"], [91.788, 96.296], atol=1e-3)


def test_get_opens_rotor_files_and_names_unknown_presets():
    from rotorjax._errors import InputError

    p = presets.get(ROTOR_FILE)
    assert p.kind == "rotor" and "bearing0.kxx" in p.defaults
    params = p.params({"bearing0.kxx": "2e6", "speed": "50"})
    assert params["bearing0.kxx"] == 2e6
    setup = p.build(params)
    assert isinstance(setup.scene, RotorScene) and setup.t_end > 0
    with pytest.raises(InputError, match="unknown preset 'nosuch'"):
        presets.get("nosuch")
    with pytest.raises(InputError, match="nosuch.toml"):
        presets.get("nosuch.toml")


def test_presets_are_data_and_analyses_are_library_functions():
    """Issue 29: a preset's reference motion comes with the `Setup`, and the library's
    functions of it give what the preset hooks gave (the deprecated attributes above
    are computed from them; that a preset holds nothing callable but `build` is
    `tests/test_layering.py`'s)."""
    from rotorjax import analysis

    ab, ea = presets.get("anisotropic-abb"), presets.get("elliptic-abb")
    setup = ab.build(ab.params())
    assert isinstance(setup.reference, analysis.PeriodicOrbit) and analysis.margin_gradient(setup.reference) == "fd"
    assert setup.published[0].within(4.5, 5.5) == pytest.approx([5.040672901949166])
    circular = ea.params({"rho2": 1.28})
    ref = ea.build(circular).reference
    assert isinstance(ref, analysis.StationaryRegime) and ref.balanced
    assert float(analysis.stability_margin(ref)) == pytest.approx(float(ea.margin(circular)), abs=0.0)
    from rotorjax._errors import InputError

    with pytest.raises(InputError, match="an elliptic race .* has no balanced regime"):
        analysis.stability_margin(ea.build(ea.params()).reference)
