"""Issue 35 item 5: rotors saved by ROSS (`Rotor.save`) brought over as rotor files
(`rotorjax.io.import_ross`, `rotorjax import-ross`).

The files in `data/ross/` were written by ROSS 2.3.0 itself, those in `data/ross/v3/`
by ROSS 3.1.0 (`ross_saved.py`, run in ROSS's interpreter; 3.x in a Python 3.13
chroot, as its docstring shows), with ROSS's modes of each (`ross_modes.json`): its
example rotor (TOML and JSON), a tapered hollow two-material rotor with a
speed-tabulated cross-coupled bearing, and a bearing on a pedestal (`n_link`); and
one form derived by hand: `rotor_example_v1.toml` (1.x's: no version, no axial terms,
1.x's tags).
Checked: every imported rotor's damped natural frequencies equal ROSS's (the version
that wrote it) to 1e-8 and its log decrements to 1e-9 (at 0 and 400 rad/s: a speed of
the table, where the two interpolations agree); the forms and versions of one rotor
give one rotor file; what a rotor file cannot hold is refused by the section's name;
live ROSS 2.3 writes the committed files."""

import copy
import json
import os
import subprocess

import numpy as np
import pytest

from rotorjax._errors import InputError
from rotorjax.analysis import modes
from rotorjax.cli import main
from rotorjax.io import import_ross, load_rotor, ross_rotor_text

HERE = os.path.dirname(os.path.abspath(__file__))
DATA = os.path.join(HERE, "data", "ross")
REF = json.load(open(os.path.join(DATA, "ross_modes.json")))
REF3 = json.load(open(os.path.join(DATA, "v3", "ross_modes.json")))


def data(name):
    return os.path.join(DATA, name)


def _body(text):
    """The rotor file without its comments (the source and the elements' tags) and its
    name: what the forms of one rotor share."""
    return "\n".join(line.split("#")[0].rstrip() for line in text.splitlines() if not line.startswith("name = "))


@pytest.mark.parametrize("version, name", [(v, n) for v in (2, 3) for n in ("rotor_example", "tapered_rig", "linked")])
def test_the_imported_rotor_has_ross_s_modes(version, name, tmp_path):
    """The first 10 modes at 0 and 400 rad/s: each rotorjax frequency is one of ROSS's
    (ROSS's 6-dof rotor also has axial and torsional modes, so each is matched to the
    nearest) to 1e-8, with its log decrement to 1e-9; ROSS 2.3.0's and 3.1.0's."""
    ref = {2: REF, 3: REF3}[version]
    assert ref["ross_version"] == {2: "2.3.0", 3: "3.1.0"}[version]
    out = import_ross(data(f"{'v3/' if version == 3 else ''}{name}.toml"), tmp_path / "r.toml")
    scene = load_rotor(str(tmp_path / "r.toml"))
    for speed in ("0.0", "400.0"):
        lam = np.asarray(modes(scene, float(speed), 10).eigenvalues)
        wd, log_dec = np.imag(lam), -2 * np.pi * np.real(lam) / np.imag(lam)
        ross_wd, ross_ld = np.array(ref[name][speed]["wd"]), np.array(ref[name][speed]["log_dec"])
        nearest = np.array([np.argmin(np.abs(ross_wd - w)) for w in wd])
        np.testing.assert_allclose(ross_wd[nearest], wd, rtol=1e-8)
        np.testing.assert_allclose(ross_ld[nearest], log_dec, atol=1e-9)
    assert out["version"] == version and out["theory"] == "timoshenko"


def test_what_each_rotor_file_holds(tmp_path):
    """The tapered rotor: taper as `[left, right]`, the bore, two materials, the table
    over speeds with its cross-coupling and the note on interpolation; the pedestal: a
    [[support]] on the linked bearing."""
    text, summary = ross_rotor_text(data("tapered_rig.toml"))
    assert "od = [0.06, 0.08]\nid = 0.02" in text and "od = [0.07, 0.05]" in text
    assert 'name = "aluminium"\nE = 70000000000.0\nG = 26000000000.0\nrho = 2700.0' in text
    assert "speeds = [0.0, 200.0, 400.0, 800.0]" in text and "kyx = [0.0, -200000.0, -400000.0, -600000.0]" in text
    assert summary["elements"] == {"shaft": 6, "material": 2, "disk": 2, "point_mass": 0, "bearing": 2, "support": 0}
    assert "smoothing spline" in summary["notes"][0]
    text, summary = ross_rotor_text(data("linked.toml"))
    assert "[[support]]\nbearing = 1\nm = 10.0\nkxx = 100000000.0\nkyy = 100000000.0" in text
    assert summary["elements"]["support"] == 1 and summary["elements"]["bearing"] == 2


def test_each_form_of_a_rotor_gives_the_same_rotor_file():
    """TOML and JSON of ROSS 2.3 and of 3.1, and the 1.x TOML form; 3.x's notes name its
    PCHIP."""
    example = _body(ross_rotor_text(data("rotor_example.toml"))[0])
    assert _body(ross_rotor_text(data("rotor_example.json"))[0]) == example
    text, summary = ross_rotor_text(data("rotor_example_v1.toml"))
    assert _body(text) == example and summary["version"] == 1
    tapered = _body(ross_rotor_text(data("tapered_rig.toml"))[0])
    assert _body(ross_rotor_text(data("tapered_rig.json"))[0]) == tapered
    for form in ("toml", "json"):
        assert _body(ross_rotor_text(data(f"v3/rotor_example.{form}"))[0]) == example
        text, summary = ross_rotor_text(data(f"v3/tapered_rig.{form}"))
        assert _body(text) == tapered and summary["version"] == 3 and "pchip" in summary["notes"][0]
    assert _body(ross_rotor_text(data("v3/linked.json"))[0]) == _body(ross_rotor_text(data("linked.toml"))[0])


def _edited(tmp_path, edit, source="rotor_example.json"):
    d = json.load(open(data(source)))
    edit(d)
    path = tmp_path / "edited.json"
    path.write_text(json.dumps(d))
    return str(path)


def _set(section, key, value):
    def edit(d):
        d[section][key] = value
    return edit


def _add(section, values):
    def edit(d):
        d[section] = values
    return edit


SHAFT0, BEARING0 = "ShaftElement_Shaft Element 0", "BearingElement_Bearing 0"


def _layer(d):
    d["ShaftElement_Sleeve"] = copy.deepcopy(d[SHAFT0])


def _mixed(d):
    d["ShaftElement_Shaft Element 3"]["shear_effects"] = False


REFUSED = [
    (_set(BEARING0, "kzz", [1e6]), rf"\[{BEARING0}\]: kzz = \[1000000.0\]: an axial coefficient"),
    (_set(SHAFT0, "alpha", 0.1), rf"\[{SHAFT0}\]: alpha = 0.1: proportional damping"),
    (_set(SHAFT0, "torque", 50.0), rf"\[{SHAFT0}\]: torque = 50.0: a shaft torque"),
    (_set(SHAFT0, "gyroscopic", False), rf"\[{SHAFT0}\]: gyroscopic = false"),
    (_set(SHAFT0, "shear_method_calc", "hutchinson"), r"shear_method_calc = 'hutchinson': rotorjax uses Cowper's"),
    (_layer, r"\[ShaftElement_Sleeve\]: n = 0 is also .*concentric shaft layers"),
    (_mixed, r"the shaft elements mix theories \(rayleigh, timoshenko"),
    (_add("CouplingElement_Coupling 0", {"n": 2, "L": 0.1}), r"\[CouplingElement_Coupling 0\]: a CouplingElement"),
    (_add("GearElement_Gear 0", {"n": 2}), r"\[GearElement_Gear 0\]: a GearElement"),
    (_set(BEARING0, "n_link", 4), rf"\[{BEARING0}\]: n_link = 4: a bearing between nodes 0 and 4"),
    (_add("PointMass_Point Mass 0", {"n": 9, "m": 5.0}), r"node 9 \(beyond the shaft's nodes 0..6\) carries 0 "
                                                         r"linked bearing\(s\), 0 .* and 1 point mass"),
    (lambda d: d[BEARING0].update(speed=[0.0, 100.0], kxx=[1e6, 2e6, 3e6]),
     rf"\[{BEARING0}\] kxx: 3 values for 2 speeds"),
    (_set(BEARING0, "kxx", [1e6, 2e6]), rf"\[{BEARING0}\] kxx: 2 values and no speeds"),
    (_set(BEARING0, "kxx", [[1e6, 1e6], [2e6, 2e6]]), rf"\[{BEARING0}\] kxx: a table over speed and frequency"),
    (_set(SHAFT0, "L", "long"), rf"\[{SHAFT0}\] L = 'long': expected a finite number"),
    (_set(SHAFT0, "material", None), rf"\[{SHAFT0}\] material: missing"),
    (lambda d: [d.pop(k) for k in list(d) if k.startswith("ShaftElement")], r"no ShaftElement sections"),
]


@pytest.mark.parametrize("edit, match", REFUSED, ids=[m[:40] for _, m in REFUSED])
def test_what_a_rotor_file_cannot_hold_is_refused_by_name(edit, match, tmp_path):
    with pytest.raises(InputError, match=match):
        ross_rotor_text(_edited(tmp_path, edit))


def test_a_3x_table_over_the_excitation_frequency_is_refused():
    """ROSS 3.1 wrote `tapered_rig` with its table over the excitation frequency."""
    with pytest.raises(InputError, match=r"frequency_table.toml: \[BearingElement_Bearing 0\]: coefficients over the "
                                         r"excitation frequency \(ROSS 3.x"):
        ross_rotor_text(data("v3/frequency_table.toml"))


def _parameters(key, value):
    def edit(d):
        d["parameters"][key] = value
    return edit


REFUSED_3X = [
    (_parameters("alpha", 0.5), r"\[parameters\]: alpha = 0.5: proportional damping of the whole rotor \(alpha M\)"),
    (_parameters("beta", 1e-5), r"\[parameters\]: beta = 1e-05: proportional damping of the whole rotor \(beta K\)"),
    (_parameters("default_damping_ratio", 0.02), r"default_damping_ratio = 0.02: modal damping of the whole rotor"),
    (_parameters("modal_damping_ratio", [0.01, 0.02]), r"modal_damping_ratio = \[0.01, 0.02\]: modal damping of"),
    (_parameters("alpha", "x"), r"\[parameters\] alpha = 'x': expected a finite number"),
]


@pytest.mark.parametrize("edit, match", REFUSED_3X, ids=[m[:40] for _, m in REFUSED_3X])
def test_the_whole_rotor_s_damping_of_3x_is_refused_by_name(edit, match, tmp_path):
    """ROSS 3.x saves the rotor's own damping in `[parameters]` (zero in the files it
    wrote here, which import); any of it not zero is refused, not dropped."""
    assert ross_rotor_text(data("v3/rotor_example.json"))[1]["version"] == 3
    with pytest.raises(InputError, match=match):
        ross_rotor_text(_edited(tmp_path, edit, "v3/rotor_example.json"))


def test_the_command_writes_the_file_and_says_what_it_holds(tmp_path, capsys):
    out = tmp_path / "tapered.toml"
    assert main(["import-ross", data("tapered_rig.toml"), "--out", str(out), "--name", "rig"]) == 0
    text = capsys.readouterr().out
    assert f"(ROSS 2.x) -> {out}: 6 shaft elements (timoshenko, 2 materials), 2 disks, 2 bearings" in text
    assert "note: ROSS 2.x evaluates a bearing table with a smoothing spline" in text
    assert 'name = "rig"' in out.read_text()
    assert main(["import-ross", data("linked.toml"), "--out", str(tmp_path / "l.toml"), "--json"]) == 0
    summary = json.loads(capsys.readouterr().out)
    assert summary["elements"]["support"] == 1 and summary["out"] == str(tmp_path / "l.toml")


def test_live_ross_writes_the_committed_files(tmp_path):
    """ROSS itself, now (skipped without it): `ross_saved.py` writes the same files, and
    the same modes."""
    from rotorjax.bench import ross_python

    python = ross_python()
    if python is None:
        pytest.skip("ROSS is not installed here: run .ci/install-ross and set ROTORJAX_ROSS_PYTHON")
    proc = subprocess.run([python, os.path.join(HERE, "ross_saved.py"), str(tmp_path)], capture_output=True,
                          text=True, timeout=600, cwd=str(tmp_path))
    assert proc.returncode == 0, proc.stderr[-2000:]
    live = json.load(open(tmp_path / "ross_modes.json"))
    assert live["ross_version"] == REF["ross_version"]
    for name in ("rotor_example.toml", "rotor_example.json", "tapered_rig.toml", "tapered_rig.json", "linked.toml",
                 "axial_force.toml"):
        assert (tmp_path / name).read_text() == open(data(name)).read(), name
    for name in ("rotor_example", "tapered_rig", "linked"):
        for speed in ("0.0", "400.0"):
            # ROSS's sparse eigensolver (ARPACK) moves its high modes by ~1e-8 from run to run
            np.testing.assert_allclose(live[name][speed]["wd"], REF[name][speed]["wd"], rtol=1e-7)
