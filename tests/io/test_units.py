"""Issue 35 item 2 (the input side): values with units in rotor files and `--set`
(`rotorjax._units.to_si`, pint). A file written with units builds the same scene as
the file in SI, bit for bit where the conversion is exact; a unit of the wrong
dimension, an unknown unit or a unit without a number is refused naming the file,
table, index and key. Conversions against their definitions (NIST SP 811):
1 in = 0.0254 m, 1 lbf = 4.4482216152605 N, 1 lb = 0.45359237 kg, 1 rpm = 2 pi/60
rad/s, 1 mil = 2.54e-5 m, and Hz as cycles per second."""

import math

import numpy as np
import pytest

from rotorjax._errors import InputError
from rotorjax._units import to_si
from rotorjax.io import read_rotor_file

LBF, LB, IN = 4.4482216152605, 0.45359237, 0.0254

CONVERSIONS = [
    ("1.5e7 N/m", "N/m", 1.5e7),
    ("3600 rpm", "rad/s", 3600 * 2 * math.pi / 60),
    ("3600rpm", "rad/s", 3600 * 2 * math.pi / 60),
    ("50 Hz", "rad/s", 100 * math.pi),
    ("2 in", "m", 2 * IN),
    ("3 mils", "m", 3e-3 * IN),
    ("25 g*mm", "kg m", 25e-6),
    ("1000 lbf/in", "N/m", 1000 * LBF / IN),
    ("10 lbf*s/in", "N s/m", 10 * LBF / IN),
    ("70 lb", "kg", 70 * LB),
    ("5 µm", "m", 5e-6),
    ("211 GPa", "Pa", 211e9),
    ("7.81 g/cm^3", "kg/m^3", 7810.0),
    ("12 cP", "Pa s", 0.012),
    ("1 lb*in^2", "kg m^2", LB * IN**2),
    ("0.25", "m", 0.25),
]


@pytest.mark.parametrize("text, unit, si", CONVERSIONS, ids=[c[0] for c in CONVERSIONS])
def test_each_unit_converts_to_its_definition(text, unit, si):
    assert to_si(text, unit, "x") == pytest.approx(si, rel=1e-14)


REFUSED = [
    ("1 N", "N/m", r"x = '1 N': a force \(N\), and this value is a stiffness, in N/m"),
    ("3 furlongs", "m", None),   # a length pint knows: accepted (checked below)
    ("3 foo", "m", r"x = '3 foo': not a quantity \(unknown unit 'foo'\)"),
    ("rpm", "rad/s", r"x must be a number, or a number and a unit .*got 'rpm'"),
    ("1 m", "dimensionless", r"x = '1 m': a length \(m\); this value has no unit"),
    ("2 kg", "rad/s", r"x = '2 kg': a mass \(kg\), and this value is a speed, in rad/s"),
]


@pytest.mark.parametrize("text, unit, match", REFUSED, ids=[r[0] for r in REFUSED])
def test_a_wrong_unit_is_refused_by_name(text, unit, match):
    if match is None:
        assert to_si(text, unit, "x") == pytest.approx(3 * 201.168, rel=1e-5)   # 660 survey feet
        return
    with pytest.raises(InputError, match=match):
        to_si(text, unit, "x")


SI = """[rotor]
theory = "timoshenko"
speed = {speed}

[[material]]
name = "steel"
E = {E}
G = 81.2e9
rho = 7810.0

[[shaft]]
L = {L}
od = {od}
material = "steel"

[[shaft]]
L = 0.25
od = 0.05
material = "steel"

[[disk]]
node = 1
m = {m}
Id = 0.178
Ip = 0.329

[[bearing]]
node = 0
kxx = {kxx}
cxx = {cxx}

[[bearing]]
node = 2
kxx = 1e6
speeds = {speeds}
kyy = [8e5, 9e5]

[[unbalance]]
node = 1
magnitude = {u}
"""
WITH_UNITS = dict(speed='"3600 rpm"', E='"211 GPa"', L='"250 mm"', od='"2 in"', m='"70 lb"', kxx='"1.5e7 N/m"',
                  cxx='"10 lbf*s/in"', speeds='["0 rpm", "3000 rpm"]', u='"25 g*mm"')
IN_SI = dict(speed=repr(3600 * 2 * math.pi / 60), E="211e9", L="0.25", od=repr(2 * IN), m=repr(70 * LB), kxx="1.5e7",
             cxx=repr(10 * LBF / IN), speeds=f"[0.0, {3000 * 2 * math.pi / 60!r}]", u="25e-6")


def test_a_file_with_units_is_the_file_in_si(tmp_path):
    a, b = tmp_path / "units.toml", tmp_path / "si.toml"
    a.write_text(SI.format(**WITH_UNITS))
    b.write_text(SI.format(**IN_SI))
    fa, fb = read_rotor_file(str(a)), read_rotor_file(str(b))
    for name, p in fb.entries.items():
        assert fa.entries[name].value == pytest.approx(p.value, rel=1e-15), name
    ra, rb = fa.scene.rotor, fb.scene.rotor
    for leaf in ("lengths", "d_out", "E", "disk_params", "bearing_params"):
        np.testing.assert_allclose(np.asarray(getattr(ra, leaf)), np.asarray(getattr(rb, leaf)), rtol=1e-15)
    # --set takes a unit too
    f = read_rotor_file(str(b), {"bearing0.kyy": "2e7 N/m", "speed": "50 Hz"})
    assert f.entries["bearing0.kyy"].value == 2e7 and f.entries["speed"].value == pytest.approx(100 * math.pi)


@pytest.mark.parametrize("edit, match", [
    (dict(kxx='"1.5e7 N"'), r"units.toml: bearing\[0\].kxx = '1.5e7 N': a force \(N\), and this value is a "
                            r"stiffness, in N/m"),
    (dict(od='"2 inches per second"'), r"units.toml: shaft\[0\].od = '2 inches per second': .* and this value is "
                                       r"a length, in m"),
    (dict(speeds='["0 rpm", "3000 kg"]'), r"bearing\[1\].speeds\[1\] = '3000 kg': a mass"),
    (dict(m='"seventy lb"'), r"disk\[0\].m must be a number, or a number and a unit .*got 'seventy lb'"),
])
def test_a_file_value_in_the_wrong_unit_names_its_table_index_and_key(edit, match, tmp_path):
    path = tmp_path / "units.toml"
    path.write_text(SI.format(**{**WITH_UNITS, **edit}))
    with pytest.raises(InputError, match=match):
        read_rotor_file(str(path))


def test_a_set_value_in_the_wrong_unit_names_the_key(tmp_path):
    path = tmp_path / "si.toml"
    path.write_text(SI.format(**IN_SI))
    with pytest.raises(InputError, match=r"override bearing0.kyy = '2e7 N': a force"):
        read_rotor_file(str(path), {"bearing0.kyy": "2e7 N"})
