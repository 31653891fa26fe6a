"""The linear seal (`[[seal]]`, `rotorjax.models.Seal`; issue 33): the component added
through the rotor-file registry, touching only its module and one registry line.
Its law is a bearing's, tabulated against speed; checked against ROSS's
`SealElement` (its matrices and a rotor's damped modes, live in ROSS's interpreter),
against the same coefficients given as a `[[bearing]]`, through a round trip, and
identified: its cross-coupled stiffness fitted from a run-up's phasors."""

import pathlib

import numpy as np
import pytest

from rotorjax import flexible as fx
from rotorjax._errors import InputError
from rotorjax.identify import identify, make_phasors, rotor_model
from rotorjax.identify import _make_fe_data as rig
from rotorjax.io import load_rotor, read_rotor_file, save_rotor
from rotorjax.models import Bearing, FlexibleRotor, RotorScene, Seal
from tests.conftest import ross_compute

from .ross_seal_reference import MODAL_SPEEDS, SPEEDS, seal_coefficients
from .test_rotor_files import assert_identical

HERE = pathlib.Path(__file__).parent
FILE = HERE / "data" / "seal_rotor.toml"


@pytest.fixture(scope="module")
def scene():
    return load_rotor(FILE)


@pytest.fixture(scope="module")
def ross():
    return ross_compute(HERE / "ross_seal_reference.py")


def _seal_matrices(rotor, speed):
    c = np.asarray(rotor.bearing_coefficients(speed))[2]
    return tuple(np.array([[c[j], c[j + 2]], [c[j + 3], c[j + 1]]]) for j in (0, 4, 8))


def test_the_file_puts_a_seal_among_the_rotors_bearings(scene):
    r = scene.rotor
    assert r.bearing_kinds == ("bearing", "bearing", "seal") and r.bearing_nodes[2] == 3 and r.speed_dependent
    entry = read_rotor_file(FILE).raw["seal"][0][1]
    for w, row in zip(entry["speeds"], np.asarray(r.bearing_tables[2][1]).T):   # the table, exactly
        assert row[2] == seal_coefficients(entry)["kxy"][entry["speeds"].index(w)]


def test_seal_matrices_equal_ross_seal_element(scene, ross):
    """ROSS 2.3.0's `SealElement` with the file's coefficients: K, C, M at the table's speeds
    and between them (3 speeds: both interpolate with the quadratic through them)."""
    for i, w in enumerate(SPEEDS):
        K, C, M = _seal_matrices(scene.rotor, w)
        # measured (2026-11-27, ROSS 2.3.0): 5.7e-17, 1.9e-16 and 0 of the largest entry
        np.testing.assert_allclose(K, ross["K"][i], rtol=1e-12, atol=1e-9)
        np.testing.assert_allclose(C, ross["C"][i], rtol=1e-12, atol=1e-12)
        np.testing.assert_allclose(M, ross["M"][i], rtol=1e-12, atol=1e-15)


def test_rotor_with_the_seal_equals_ross(scene, ross):
    """The rotor's damped natural frequencies and log decrements with the seal, against
    ROSS's rotor with its `SealElement` (6 lowest lateral modes at two speeds). The seal's
    cross-coupled stiffness destabilises a mode (a negative log decrement at both speeds)."""
    c = fx.campbell(scene, np.asarray(MODAL_SPEEDS), 6)
    for k in range(len(MODAL_SPEEDS)):
        # measured (2026-11-27): 5.1e-13 and 9.0e-11 relative; tolerances 100x
        np.testing.assert_allclose(np.asarray(c.frequencies)[k], ross["wd"][k], rtol=5e-11)
        np.testing.assert_allclose(np.asarray(c.log_dec)[k], ross["log_dec"][k], rtol=1e-8)
    assert min(ross["log_dec"][0]) < 0 and min(ross["log_dec"][1]) < 0


def test_a_seal_acts_as_the_bearing_with_its_coefficients(scene, tmp_path):
    """The same entry as a `[[bearing]]`: the same linear equations at every speed (the
    law is the bearing's; only the table it is read from and written to differs). A
    bearing's direct stiffness is >= 0, so both get the seal's with its sign turned."""
    text = FILE.read_text().replace("= [-2.0e5, -1.5e5, -0.8e5]", "= [2.0e5, 1.5e5, 0.8e5]").replace(
        "= [-2.2e5, -1.6e5, -0.9e5]", "= [2.2e5, 1.6e5, 0.9e5]")
    scene = load_rotor(_write(tmp_path, "positive.toml", text))
    as_bearing = load_rotor(_write(tmp_path, "as_bearing.toml", text.replace("[[seal]]", "[[bearing]]")))
    assert scene.rotor.bearing_kinds[2] == "seal" and as_bearing.rotor.bearing_kinds == ("bearing",) * 3
    for w in (0.0, 120.0, 500.0, 650.0):
        a, b = scene.linear_matrices(w), as_bearing.linear_matrices(w)
        for x, y in zip(a, b):
            np.testing.assert_array_equal(np.asarray(x), np.asarray(y))


def test_seal_round_trips(scene, tmp_path):
    path = save_rotor(scene, tmp_path / "again.toml")
    assert "[[seal]]" in path.read_text()
    assert_identical(load_rotor(path), scene)
    # built in Python: a rotor with a Seal saves to a file that loads back equal, leaf for leaf
    built = RotorScene(FlexibleRotor([0.3] * 4, 0.04, bearings=(
        Bearing(0, kxx=1e7, cxx=300.0), Bearing(4, kxx=1e7, cxx=300.0),
        Seal(2, kxx=-5e4, kxy=[0.0, 2e5], kyx=[0.0, -2e5], cxx=40.0, speeds=[0.0, 600.0])), plausibility=False), 300.0)
    assert_identical(load_rotor(save_rotor(built, tmp_path / "built.toml")), built)
    # a bearing of a kind no table holds is refused, not dropped
    class Other(Bearing):
        kind = "other"

    with pytest.raises(InputError, match="bearings\\[0\\] is of kind 'other', which has no rotor-file table"):
        save_rotor(RotorScene(FlexibleRotor([0.3] * 2, 0.04, bearings=(Other(1, kxx=1e5),), plausibility=False)),
                   tmp_path / "other.toml")
    # a file lists its [[bearing]] entries before its [[seal]] entries
    with pytest.raises(InputError, match=r"bearings\[1\] \(a Bearing\) follows bearings\[0\] \(a seal\)"):
        save_rotor(RotorScene(FlexibleRotor([0.3] * 2, 0.04, bearings=(Seal(1, kxx=1e5), Bearing(0, kxx=1e7)),
                                            plausibility=False)), tmp_path / "bad.toml")


def test_seal_parameters_are_its_leaves(scene):
    f = read_rotor_file(FILE, {"seal0.kxy": 3.0e5})
    p = f.path("seal0.kxy")
    assert p.affine and not p.refusal and [t.leaf for t in p.targets] == [("rotor", "bearing_tables", 2, 1)]
    assert "tabulated against speed" in read_rotor_file(FILE).path("seal0.kxy").refusal
    assert f.path("seal0.kyy") is not None and f.path("seal0.node").refusal


def test_seal_cross_coupled_stiffness_identified(tmp_path):
    """Issue 33: a seal's cross-coupled stiffness fitted from noise-free run-up phasors of
    the rig with a seal (kxy 2.5e5 N/m at every speed, its direct coefficients tabulated),
    from a start 30 % off: recovered within 1e-6 (the data are exact)."""
    text = FILE.read_text().replace("kxy = [0.0, 1.5e5, 4.0e5]        # N/m: cross-coupled, from the leakage's swirl",
                                    "kxy = 2.5e5").replace("kyx = [0.0, -1.5e5, -4.0e5]", "kyx = -2.5e5")
    path = str(_write(tmp_path, "seal_fit.toml", text))
    truth = load_rotor(path).rotor
    speeds = rig.RUNUP_SPEEDS
    X = rig.clean_phasors(truth, rig.UNBALANCES, speeds, rig.SENSORS)
    n = len(speeds)
    data = make_phasors(np.repeat(speeds, len(rig.SENSORS)), np.tile([s[0] for s in rig.SENSORS], n),
                        np.tile([s[1] for s in rig.SENSORS], n), X.ravel())
    model = rotor_model(path, {"seal0.kxy": 2.5e5 * 1.3})
    res = identify(model, data, ["seal0.kxy"], fit_unbalance=(2, 4), n_starts=1, critical_speeds=False)
    assert abs(res.estimates["seal0.kxy"] / 2.5e5 - 1) < 1e-6, res.estimates


def _write(tmp_path, name, text):
    p = tmp_path / name
    p.write_text(text)
    return p
