"""Plausibility warnings (issue 28): valid but implausible inputs, most often a unit
slip, are `PlausibilityWarning`s that name the value as the user gave it and the
likely slip; bearing tables used outside their speeds are named; `Bearing` takes its
coefficients by keyword only. Nothing here compiles more than a constructor."""

import copy
import functools
import warnings

import jax
import numpy as np
import pytest

from rotorjax._errors import InputError, PlausibilityWarning
from rotorjax.models import Bearing, FlexibleRotor, RotorScene, check_speeds
from rotorjax.io import load_rotor, shipped_rotor
from rotorjax.models._plausibility import judge
from rotorjax.presets import PRESETS
from tests.test_rotor_file_errors import BALANCER, BASE, toml


def _plausibility_warnings(fn, *args, **kwargs):
    """`fn(*args, **kwargs)` and the texts of the `PlausibilityWarning`s it issued."""
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        out = fn(*args, **kwargs)
    return out, [str(w.message) for w in caught if issubclass(w.category, PlausibilityWarning)]


# --- the ranges and the slips they name ----------------------------------------------
@pytest.mark.parametrize("quantity,value,expected", [
    ("E", 205.0, "did you mean GPa (205 GPa = 2.05e11 Pa)?"),
    ("E", 2.05e5, "did you mean MPa (205000 MPa = 2.05e11 Pa)?"),
    ("E", 30e6, "did you mean psi"),
    ("E", 2e14, "outside the plausible 1e9..1e12 Pa for a Young's modulus; check its units"),
    ("G", 79.5, "did you mean GPa"),
    ("rho", 7.85, "did you mean g/cm^3 (7.85 g/cm^3 = 7850 kg/m^3)?"),
    ("rho", 0.284, "did you mean lb/in^3"),
    ("rho", 7.85e-9, "did you mean t/mm^3"),
    ("rho", 1e6, "outside the plausible 500..25000 kg/m^3 for a density; check its units"),
    ("diameter", 60.0, "did you mean mm (60 mm = 0.06 m)?"),
    ("diameter", 1e-5, "outside the plausible 0.5 mm..5 m for a diameter; check its units"),
    ("length", 250.0, "did you mean mm (250 mm = 0.25 m)?"),
    ("bore", 20.0, "outside the plausible 0..5 m for a bore (inner diameter); did you mean mm"),
    ("slenderness", 0.01, "outside the plausible 0.05..50"),
])
def test_implausible_values_name_the_slip(quantity, value, expected):
    assert expected in judge(quantity, value)


@pytest.mark.parametrize("quantity,value", [
    ("E", 211e9), ("E", 1.2e9), ("E", 450e9), ("G", 26e9), ("rho", 7810.0), ("rho", 930.0), ("rho", 19300.0),
    ("diameter", 0.05), ("diameter", 0.001), ("bore", 1e-5), ("diameter", 3.0), ("length", 0.01),
    ("slenderness", 5.0),
    ("E", 0.0), ("rho", -1.0),  # signs are the validators' business
])
def test_plausible_values_pass(quantity, value):
    assert judge(quantity, value) is None


# --- rotor files ------------------------------------------------------------------------
def _all_shafts(key, value):
    def fn(doc):
        for s in doc["shaft"]:
            s[key] = value
    return fn


def _set(table, index, key, value):
    def fn(doc):
        (doc[table] if index is None else doc[table][index])[key] = value
    return fn


# (id, change to the test file, overrides, the one warning's phrases)
FILE_CASES = [
    ("E-in-GPa", _set("material", 0, "E", 205.0), None,
     ["rotor.toml: material[0].E = 205 Pa: outside the plausible 1e9..1e12 Pa", "did you mean GPa"]),
    ("E-in-MPa", _set("material", 0, "E", 2.05e5), None, ["material[0].E = 205000 Pa", "did you mean MPa"]),
    ("G-in-GPa", _set("material", 0, "G", 79.5), None, ["material[0].G = 79.5 Pa", "did you mean GPa"]),
    ("rho-in-g-cm3", _set("material", 0, "rho", 7.85), None,
     ["material[0].rho = 7.85 kg/m^3", "did you mean g/cm^3"]),
    ("od-in-mm", _all_shafts("od", 50.0), None,
     ["shaft[0].od = 50 m (and 5 more [[shaft]] entries): outside the plausible 0.5 mm..5 m for a diameter",
      "did you mean mm (50 mm = 0.05 m)?"]),
    ("one-od-in-mm", _set("shaft", 4, "od", 60.0), None, ["shaft[4].od = 60 m: ", "did you mean mm"]),
    ("L-in-mm", _all_shafts("L", 100.0), None, ["shaft[0].L = 100 m (and 5 more", "did you mean mm"]),
    ("taper-end-in-mm", _set("shaft", 2, "od", [0.05, 40.0]), None, ["shaft[2].od = 40 m", "did you mean mm"]),
    ("stubby-element", _set("shaft", 3, "od", 4.0), None,
     ["shaft[3]: L / od = 0.025 (L = 0.1 m, od = 4 m) is outside the plausible 0.05..50: a unit slip in L or od?"]),
    ("slender-element", _set("shaft", 0, "L", 3.0), None, ["shaft[0]: L / od = 60"]),
    ("inertia-in-kg-mm2", lambda d: d["disk"][0].update(Id=50000.0, Ip=80000.0), None,
     ["disk[0].Id = 50000 kg m^2 with m = 10 kg", "did you mean kg mm^2"]),
    ("balancer-radius-in-mm", lambda d: d.update(auto_balancer=[dict(BALANCER, radius=100.0)]), None,
     ["auto_balancer[0].radius = 100 m", "did you mean mm"]),
    ("override-E", lambda d: None, {"material0.E": 205},
     ["material[0].E = 205 Pa", "did you mean GPa", "(set by the override material0.E=205)"]),
]


@pytest.mark.parametrize("change,overrides,expected", [c[1:] for c in FILE_CASES], ids=[c[0] for c in FILE_CASES])
def test_rotor_file_warnings(tmp_path, change, overrides, expected):
    doc = copy.deepcopy(BASE)
    change(doc)
    path = tmp_path / "rotor.toml"
    path.write_text(toml(doc), encoding="utf-8")
    scene, texts = _plausibility_warnings(load_rotor, path, overrides)
    assert scene.rotor.n_nodes == 7  # a warning, not an error
    n = 2 if "kg mm^2" in expected[-1] else 1  # both inertias of a disk in kg mm^2 say so
    assert len(texts) == n, texts  # once, in the file's terms (the constructor stays quiet)
    assert texts[0].startswith(f"{path}: ")
    for phrase in expected:
        assert phrase in texts[0], texts[0]


def test_rotor_file_error_comes_without_warnings(tmp_path):
    doc = copy.deepcopy(BASE)
    doc["material"][0]["E"] = 205.0
    doc["disk"][0]["Ip"] = 1.0
    path = tmp_path / "rotor.toml"
    path.write_text(toml(doc), encoding="utf-8")
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        with pytest.raises(InputError, match=r"disk\[0\].Ip = 1.0 > 2 Id"):
            load_rotor(path)
    assert not [w for w in caught if issubclass(w.category, PlausibilityWarning)]


@functools.cache
def _shipped(name):
    """A shipped rotor file's scene and the plausibility warnings its loading issued."""
    return _plausibility_warnings(load_rotor, shipped_rotor(name))


@pytest.mark.parametrize("name", ["flexible_rig", "rig_nonlinear", "ross_compare", "tapered_two_material"])
def test_shipped_rotors_are_plausible(name):
    assert _shipped(name)[1] == []


@pytest.mark.parametrize("name", sorted(PRESETS))
def test_presets_are_plausible(name):
    preset = PRESETS[name]
    _, texts = _plausibility_warnings(preset.build, preset.params())
    assert texts == []


# --- Python constructors ------------------------------------------------------------------
SHAFT = dict(lengths=[0.25] * 4, d_out=0.05)

# (id, FlexibleRotor keyword arguments over SHAFT, the one warning's phrases)
PY_CASES = [
    ("E", dict(E=205.0), ["E (Young's modulus) = 205 Pa: outside", "did you mean GPa"]),
    ("G", dict(G=79.5), ["G (shear modulus) = 79.5 Pa", "did you mean GPa"]),
    ("rho", dict(rho=7.85), ["rho (density) = 7.85 kg/m^3", "did you mean g/cm^3"]),
    ("E-one-element", dict(E=[211e9, 211e9, 205.0, 211e9]), ["E[2] (Young's modulus) = 205 Pa"]),
    ("d_out", dict(d_out=60.0), ["d_out (outer diameter) = 60 m: ", "did you mean mm"]),
    ("d_out-two-elements", dict(d_out=[0.05, 60.0, 60.0, 0.05]),
     ["d_out[1] (outer diameter) (and 1 more element) = 60 m"]),
    ("taper", dict(d_out=[[0.05, 0.05], [0.05, 45.0], [0.05, 0.05], [0.05, 0.05]]),
     ["d_out[1] (outer diameter) = 45 m", "did you mean mm"]),
    ("lengths", dict(lengths=[250.0] * 4), ["lengths (element length) = 250 m", "did you mean mm"]),
    ("slenderness", dict(lengths=[0.1] * 4, d_out=4.0), ["element 0: L / od = 0.025 (L = 0.1 m, od = 4 m)"]),
    ("disk-ip", dict(disks=((2, 10.0, 0.05, 0.3),)),
     ["disks[0]: Ip = 0.3 > 2 It = 0.1 kg m^2: no rigid body"]),
    ("disk-kg-mm2", dict(disks=((2, 10.0, 5e4, 8e4),)), ["disks[0]: It = 50000 kg m^2 with mass = 10 kg"]),
]


@pytest.mark.parametrize("kwargs,expected", [c[1:] for c in PY_CASES], ids=[c[0] for c in PY_CASES])
def test_constructor_warnings(kwargs, expected):
    _, texts = _plausibility_warnings(FlexibleRotor, **dict(SHAFT, **kwargs))
    if kwargs.get("disks") and kwargs["disks"][0][2] > 1:  # kg mm^2: both inertias say so
        texts = texts[:1]
    assert len(texts) == 1, texts
    for phrase in expected:
        assert phrase in texts[0], texts[0]


def test_plausible_constructor_and_opt_out_are_quiet():
    _, texts = _plausibility_warnings(FlexibleRotor, **SHAFT, disks=((2, 10.0, 0.05, 0.1),),
                                      bearings=((0, 1e6, 1e6, 0.0, 0.0),))
    assert texts == []
    # a refined taper whose bore closes (tiny bores near its end) is plausible
    _, texts = _plausibility_warnings(FlexibleRotor, **SHAFT, d_in=[[0.02, 0.01], [0.01, 3e-4], [3e-4, 0.0],
                                                                    [0.0, 0.0]])
    assert texts == []
    # a nondimensional model (E I = 1) says so
    _, texts = _plausibility_warnings(FlexibleRotor, [0.25] * 4, 0.05, E=1.0, G=1.0, rho=1.0, plausibility=False)
    assert texts == []


def test_no_warning_under_jit_or_vmap():
    def build(E, rho):
        return FlexibleRotor(**SHAFT, E=E, rho=rho, disks=((2, 10.0, 0.05, 0.1),)).E

    out, texts = _plausibility_warnings(jax.jit(build), 205.0, 7.85)
    assert texts == [] and float(out) == 205.0
    out, texts = _plausibility_warnings(jax.vmap(build), np.array([205.0, 2e5]), np.array([7.85, 7.9]))
    assert texts == [] and out.shape == (2,)


# --- bearing tables used outside their speeds -----------------------------------------------
def _tabulated():
    table = Bearing(2, kxx=[1e7, 1.2e7, 1.5e7], cxx=[200.0, 250.0, 320.0], speeds=[10.0, 500.0, 1500.0])
    return FlexibleRotor(**SHAFT, bearings=((0, 1e7, 1e7, 100.0, 100.0), table))


@pytest.mark.parametrize("speeds,expected", [
    ([100.0, 3000.0], "bearing 1 (node 2): speeds up to 3000 rad/s are outside its table (10..1500 rad/s): "
                      "its coefficients are extrapolated"),
    (np.linspace(0.0, 1000.0, 5),
     "bearing 1 (node 2): speeds down to 0 rad/s are outside its table (10..1500 rad/s)"),
    ([5.0, 2000.0], "bearing 1 (node 2): speeds 5..2000 rad/s leave its table (10..1500 rad/s)"),
    (1600.0, "speeds up to 1600 rad/s"),
    ([10.0, 1500.0], None),
    (800.0, None),
])
def test_check_speeds(speeds, expected):
    rotor = _tabulated()
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        texts = check_speeds(rotor, speeds)
    issued = [str(w.message) for w in caught if issubclass(w.category, PlausibilityWarning)]
    assert issued == texts
    if expected is None:
        assert texts == []
    else:
        assert len(texts) == 1 and expected in texts[0], texts


def test_check_speeds_takes_scenes_and_reduced_rotors():
    scene = _shipped("tapered_two_material")[0]  # both bearings tabulated at 0..1000 rad/s
    assert isinstance(scene, RotorScene)
    texts, issued = _plausibility_warnings(check_speeds, scene, [20.0, 3000.0])
    assert texts == issued and len(texts) == 2
    assert texts[1] == ("bearing 1 (node 8): speeds up to 3000 rad/s are outside its table (0..1000 rad/s): "
                        "its coefficients are extrapolated")
    rotor = _tabulated()
    reduced = jax.jit(lambda r: r.reduce(4))(rotor)  # one compilation instead of op-by-op assembly
    with pytest.warns(PlausibilityWarning, match=r"bearing 1 \(node 2\)"):
        assert len(check_speeds(reduced, [10.0, 3000.0])) == 1
    # no tables, another kind of scene, traced speeds: nothing to say
    assert check_speeds(FlexibleRotor(**SHAFT, bearings=((0, 1e6, 1e6, 0.0, 0.0),)), [0.0, 1e5]) == []
    assert check_speeds(object(), [0.0, 1e5]) == []
    assert jax.jit(lambda s: len(check_speeds(rotor, s)) + s)(3000.0) == 3000.0


# --- keyword-only coefficients ---------------------------------------------------------------
def test_bearing_coefficients_are_keyword_only():
    with pytest.raises(TypeError):
        Bearing(0, 5e7, 5e7, 5e3, 5e3)
    with pytest.raises(TypeError):
        Bearing(0, 5e7)
    # the tuple form keeps its documented order: node, kxx, kyy, cxx, cyy
    as_tuple = FlexibleRotor(**SHAFT, bearings=((0, 5e7, 4e7, 5e3, 4e3),))
    named = FlexibleRotor(**SHAFT, bearings=(Bearing(0, kxx=5e7, kyy=4e7, cxx=5e3, cyy=4e3),))
    np.testing.assert_array_equal(as_tuple.bearing_params, named.bearing_params)
    np.testing.assert_array_equal(named.bearing_params[0], [5e7, 4e7, 0, 0, 5e3, 4e3, 0, 0])


@pytest.mark.parametrize("bearing,expected", [
    ((0, 5e7, 5e7, 5e3), "a tuple of 4 values is ambiguous"),
    ((0, 5e7, 5e7, 5e3, 5e3, 1e5), "a tuple of 6 values is ambiguous"),
    ((0, 5e7, 5e7, 5e3, 5e3, 1e5, 1e5, 0.0), "a tuple of 8 values is ambiguous"),
    ({"node": 0, "kxx": 5e7}, r"got a dict: name the coefficients with Bearing\(node, kxx=.*"
                              r"Bearing\(\*\*bearings\[0\]\)"),
])
def test_ambiguous_bearing_tuples(bearing, expected):
    with pytest.raises(InputError, match=r"bearings\[0\] must be (a Bearing or a tuple )?\(node, kxx, kyy, cxx, "
                                         r"cyy\) or \(node, kxx, kyy, cxx, cyy, kxy, kyx, cxy, cyx\).*" + expected):
        FlexibleRotor(**SHAFT, bearings=(bearing,))
