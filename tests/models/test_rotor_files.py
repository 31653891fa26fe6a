"""Rotor files: ROSS's example rotor from its file equals the preset, round trips
are exact, per-element materials, and a rotor file as a preset (`--set` keys)."""

import jax
import numpy as np
import pytest

from rotorjax.flexible import campbell, critical_speeds_1x, synchronous_critical_speeds, unbalance_response
from rotorjax.models import (AutoBalancer, BalancerAt, ClearanceBearing, ConstantSpeed, CubicBearing, DiskDamping,
                             ExternalDamping, FlexibleRotor, Gravity, InternalDamping, Limiters, LimitersAt,
                             NodeProbe, Race, RotorScene, Seal, Unbalance)
from rotorjax.models._fe_elements import element_matrices
from rotorjax.models._fe_rotor import cowper_shear_coefficient
from rotorjax.models._frequency import frequency_response
from rotorjax.io import load_rotor, rotor_file_text, save_rotor, shipped_rotor
from rotorjax.presets import _ross_compare as ross
from rotorjax.presets._rotor_file import preset_from_file

ROSS = shipped_rotor("ross_compare")
RIG = shipped_rotor("rig_nonlinear")
SPEEDS = np.array([0.0, 150.0, 400.0, 800.0, 1000.0])


def _leaves(tree):
    return [np.asarray(a) for a in jax.tree_util.tree_leaves(tree)]


def assert_identical(a, b):
    """Same pytree structure (static fields included) and `==` on every leaf."""
    assert jax.tree_util.tree_structure(a) == jax.tree_util.tree_structure(b)
    for x, y in zip(_leaves(a), _leaves(b)):
        assert x.shape == y.shape and x.dtype == y.dtype
        assert np.array_equal(x, y, equal_nan=x.dtype.kind in "fc")  # tabulated bearings: NaN constants


def close(a, b, rtol=1e-10):
    a, b = np.asarray(a), np.asarray(b)
    return np.max(np.abs(a - b)) <= rtol * np.max(np.abs(b))


# --- ROSS's example rotor, from its file ---------------------------------------------------
@pytest.fixture(scope="module")
def ross_pair():
    return load_rotor(ROSS), ross.build_rotor(ross.PRESET.params())


def test_ross_file_is_the_preset_rotor(ross_pair):
    scene, rotor = ross_pair
    assert isinstance(scene.rotor, FlexibleRotor)
    assert_identical(scene.rotor, rotor)
    for a, b in zip(scene.rotor.matrices(), rotor.matrices()):
        assert np.array_equal(a, b)


def test_ross_file_campbell_and_critical_speeds(ross_pair):
    scene, rotor = ross_pair
    ca, cb = campbell(scene.rotor, SPEEDS, 8), campbell(rotor, SPEEDS, 8)
    assert close(ca.frequencies, cb.frequencies)
    assert np.allclose(ca.log_dec, cb.log_dec, rtol=1e-10, atol=1e-12)
    assert np.array_equal(ca.forward, cb.forward)
    crit_a = critical_speeds_1x(scene.rotor, 10.0, 1000.0, n_scan=100, n_modes=6)
    crit_b = critical_speeds_1x(rotor, 10.0, 1000.0, n_scan=100, n_modes=6)
    assert len(crit_a) == len(crit_b) >= 2
    assert [k for _, k in crit_a] == [k for _, k in crit_b]
    assert close([s for s, _ in crit_a], [s for s, _ in crit_b])
    sync_a, sync_b = synchronous_critical_speeds(scene.rotor, 6), synchronous_critical_speeds(rotor, 6)
    assert np.all(np.isfinite(sync_b)) and close(sync_a, sync_b)


def test_ross_file_unbalance_response(ross_pair):
    """The file's unbalance (1 g m at node 2) through the scene's own linear matrices
    and load (the one frequency-response solve) and through `unbalance_response`
    on the file's rotor both equal `unbalance_response` on the preset's rotor."""
    scene, rotor = ross_pair
    (u,) = scene.components
    w = np.linspace(10.0, 1200.0, 40)
    Xb, Yb = unbalance_response(rotor, 2, 1e-3, 0.0, w)
    Xa, Ya = unbalance_response(scene.rotor, u.node, u.magnitude, u.phase, w)
    assert close(Xa, Xb) and close(Ya, Yb)
    for i, s in enumerate(w):
        lm = scene.linear_matrices(s)
        Q = scene.expand(frequency_response(lm.M, lm.C + lm.G, lm.K, scene.unbalance_load(s), s))
        assert close(Q[0::4], Xb[i]) and close(Q[1::4], Yb[i])


# --- round trips ----------------------------------------------------------------------------
def _round_trip(scene, tmp_path, name="rotor"):
    first = tmp_path / "first.toml"
    save_rotor(scene, first, name=name)
    again = load_rotor(first)
    assert_identical(again, scene)
    second = tmp_path / "second.toml"
    save_rotor(again, second, name=name)
    assert second.read_text(encoding="utf-8") == first.read_text(encoding="utf-8")
    return again


@pytest.mark.parametrize("path", [ROSS, RIG])
def test_shipped_files_round_trip(path, tmp_path):
    _round_trip(load_rotor(path), tmp_path)


def every_component_scene(reduce=None):
    """A hand-built scene with every part a rotor file holds (components in the
    file's order, so the reloaded scene is the same tree)."""
    n = 5
    rotor = FlexibleRotor(
        [0.1, 0.12, 0.15, 0.12, 0.1], [0.05, 0.06, 0.06, 0.055, 0.05], [0.0, 0.01, 0.02, 0.0, 0.0],
        E=np.array([211e9, 211e9, 70e9, 211e9, 195e9]), G=np.array([81.2e9, 81.2e9, 26e9, 81.2e9, 75e9]),
        rho=np.array([7810.0, 7810.0, 2700.0, 7810.0, 7900.0]), nu=np.array([0.3, 0.3, 0.33, 0.3, 0.29]),
        disks=((2, 12.5, 0.07, 0.12), (4, 3.0, 0.01, 0.015)),
        bearings=((0, 1e7, 9e6, 300.0, 350.0, 1e5, -2e5, 1.5, -2.5), (n, 2e7, 2e7, 500.0, 500.0),
                  Seal(3, kxx=-4e4, kxy=[0.0, 1e5, 3e5], kyx=[0.0, -1e5, -3e5], cxx=[60.0, 55.0, 50.0], mxx=0.2,
                       speeds=[0.0, 200.0, 400.0])),
        theory="rayleigh", fixed_dofs=((0, 2), (0, 3)))
    if reduce:
        rotor = rotor.reduce(reduce)
    parts = (
        Unbalance(2, 2e-4, 0.3), Unbalance(4, 5e-5, -1.2),
        InternalDamping(3e-5),
        ExternalDamping(0.85),
        DiskDamping(2, 15.0, 0.02), DiskDamping(4, 3.5),
        Gravity(9.80665, -1.4),
        CubicBearing(1, 2e13, 1e5, 20.0),
        ClearanceBearing(n, 2e-4, 4e7, 300.0),
        LimitersAt(2, Limiters([0.1, 1.7, 3.3], [1e-3, 1.1e-3, 0.9e-3], 1e7, 200.0, 0.15, 2e-6), 0.12),
        BalancerAt(2, AutoBalancer(np.array([0.02, 0.025]), Race(0.08, 0.075, (1e-3, -2e-3)), 0.7,
                                   inertia_factor=1.2)),
        BalancerAt(4, AutoBalancer(np.full(3, 0.01), Race.circular(0.05), 0.3, kind="roller")),
        NodeProbe(2), NodeProbe(4, "outboard_disk"),
    )
    return RotorScene(rotor, ConstantSpeed(321.5), parts)


def test_every_component_round_trips_exactly(tmp_path):
    again = _round_trip(every_component_scene(), tmp_path, name='rig "A"\tα')
    assert [type(c).__name__ for c in again.components] == [
        "Unbalance", "Unbalance", "InternalDamping", "ExternalDamping", "DiskDamping", "DiskDamping", "Gravity",
        "CubicBearing", "ClearanceBearing", "LimitersAt", "BalancerAt", "BalancerAt", "NodeProbe", "NodeProbe"]


DAMPING_AND_PROBES = """
[external_damping]
coefficient = 0.75          # N s/m^2

[[disk_damping]]
node = 2
translational = 12.5        # N s/m
angular = 0.03              # N m s

[[disk_damping]]
node = 4
translational = 4.0

[[probe]]
node = 2

[[probe]]
node = 5
name = "bearing_b"
"""


def test_damping_and_probe_tables_build_their_components(tmp_path):
    """`[external_damping]`, `[[disk_damping]]`, `[[probe]]`: the loaded scene carries
    the components with the file's values (defaults filled in), in the documented
    order; the damping adds to the linear part exactly what the components do, and
    the probes' outputs are the nodes' motion."""
    path = tmp_path / "damped.toml"
    path.write_text(ROSS.read_text() + DAMPING_AND_PROBES)
    scene, plain = load_rotor(path), load_rotor(ROSS)
    kinds = [type(c) for c in scene.components]
    assert kinds == [type(c) for c in plain.components][:1] + [ExternalDamping, DiskDamping, DiskDamping,
                                                               NodeProbe, NodeProbe]
    ext, d2, d4, p2, p5 = scene.components[1:]
    assert float(ext.coefficient) == 0.75
    assert (d2.node, float(d2.translational), float(d2.angular)) == (2, 12.5, 0.03)
    assert (d4.node, float(d4.translational), float(d4.angular)) == (4, 4.0, 0.0)
    assert (p2.node, p2.name, p5.node, p5.name) == (2, "disk", 5, "bearing_b")
    by_hand = RotorScene(plain.rotor, plain.speed, plain.components + (
        ExternalDamping(0.75), DiskDamping(2, 12.5, 0.03), DiskDamping(4, 4.0), NodeProbe(2),
        NodeProbe(5, "bearing_b")))
    assert_identical(scene, by_hand)
    extra = np.asarray(scene.linear_matrices(300.0).C - plain.linear_matrices(300.0).C)
    assert np.max(np.abs(extra)) > 0
    y = scene.rest_state() + 1e-5 * np.random.default_rng(1).standard_normal(scene.state_size)
    out = scene.outputs(0.0, y)
    for name, node in (("disk", 2), ("bearing_b", 5)):
        assert float(out[f"{name}_x"]) == float(out["node_x"][node])
        assert float(out[f"{name}_y"]) == float(out["node_y"][node])
    # the damping values are --set keys like the other tables'
    changed = load_rotor(path, {"external_damping.coefficient": "1.5", "disk_damping1.angular": 0.2,
                                "probe1.node": 6})
    assert float(changed.components[1].coefficient) == 1.5 and float(changed.components[3].angular) == 0.2
    assert changed.components[5].node == 6


def test_damping_and_probe_tables_round_trip(tmp_path):
    """save_rotor then load_rotor: the same scene, so the same vector field and outputs."""
    path = tmp_path / "damped.toml"
    path.write_text(ROSS.read_text() + DAMPING_AND_PROBES)
    scene = load_rotor(path)
    again = _round_trip(scene, tmp_path)
    text = (tmp_path / "first.toml").read_text()
    for line in ("[external_damping]\ncoefficient = 0.75", "[[disk_damping]]\nnode = 4\ntranslational = 4.0\n"
                 "angular = 0.0", '[[probe]]\nnode = 5\nname = "bearing_b"'):
        assert line in text, line
    y = scene.rest_state() + 1e-5 * np.random.default_rng(2).standard_normal(scene.state_size)
    np.testing.assert_array_equal(np.asarray(again.vector_field(0.1, y)), np.asarray(scene.vector_field(0.1, y)))


def test_model_004_scene_saves_to_a_file_with_the_same_vector_field(tmp_path):
    """The cantilever-limiters preset's scene (a probe, internal, external and disk
    damping, limiters: model 004's parts) now fits a rotor file; reloaded (its
    components in the file's order) it has the same vector field and outputs."""
    import warnings

    from rotorjax.presets import cantilever_limiters as cl

    scene = cl.build_scene(cl.PRESET.params())
    assert {NodeProbe, ExternalDamping, DiskDamping} <= {type(c) for c in scene.components}
    save_rotor(scene, tmp_path / "m004.toml")
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")      # dimensionless units: implausible in SI, on purpose
        again = load_rotor(tmp_path / "m004.toml", track_work=scene.track_work)
    y = scene.rest_state() + 1e-3 * np.random.default_rng(3).standard_normal(scene.state_size)
    np.testing.assert_array_equal(np.asarray(again.vector_field(0.3, y)), np.asarray(scene.vector_field(0.3, y)))
    a, b = scene.outputs(0.3, y), again.outputs(0.3, y)
    assert sorted(a) == sorted(b) and all(np.array_equal(np.asarray(a[k]), np.asarray(b[k])) for k in a)


def issue15_scene():
    """Tapered elements, point masses, bearings with mass coefficients and speed
    tables, a pedestal support (issue 15's model-building parts)."""
    from rotorjax.models._fe_rotor import Bearing, Support

    rotor = FlexibleRotor(
        [0.1, 0.12, 0.15, 0.1], np.array([[0.04, 0.05], [0.05, 0.05], [0.05, 0.06], [0.06, 0.045]]),
        np.array([[0.0, 0.0], [0.0, 0.01], [0.01, 0.02], [0.0, 0.0]]),
        E=np.array([211e9, 211e9, 113.8e9, 211e9]), G=np.array([81.2e9, 81.2e9, 42.4e9, 81.2e9]),
        rho=np.array([7810.0, 7810.0, 4430.0, 7810.0]),
        disks=((2, 12.5, 0.07, 0.12),),
        bearings=(Bearing(0, kxx=1e7, kyy=9e6, cxx=300.0, mxx=0.5, myy=0.4, mxy=0.01),
                  Bearing(4, kxx=np.array([1e7, 1.2e7, 1.5e7]), cxx=np.array([200.0, 250.0, 320.0]),
                          kxy=np.array([0.0, 1e5, 3e5]), speeds=np.array([0.0, 300.0, 900.0]))),
        point_masses=((1, 2.0), (3, 1.5, 1.25)),
        supports=(Support(1, 40.0, 5e7, 4e7, 2e3, 2.5e3),))
    return RotorScene(rotor, ConstantSpeed(250.0), (Unbalance(2, 1e-4, 0.0),))


def test_tapered_point_masses_tables_supports_round_trip_exactly(tmp_path):
    again = _round_trip(issue15_scene(), tmp_path)
    text = (tmp_path / "first.toml").read_text()
    for line in ("od = [0.04, 0.05]", "[[point_mass]]", "mx = 1.5", "speeds = [0.0, 300.0, 900.0]",
                 "mxy = 0.01", "[[support]]", "bearing = 1"):
        assert line in text, line
    assert again.rotor.tapered and again.rotor.n_dofs == 4 * 5 + 2


def test_plain_journal_file_is_its_table(tmp_path):
    """A `type = "plain-journal"` bearing is the speed table of `PlainJournal`
    (short-bearing closed form) at the file's speeds."""
    from rotorjax.models._journal_bearing import PlainJournal

    text = ROSS.read_text().replace(
        "[[bearing]]\nnode = 0\nkxx = 1e6            # N/m\nkyy = 0.8e6\ncxx = 0.0            # N s/m\n",
        "[[bearing]]\nnode = 0\ntype = \"plain-journal\"\nload = 300.0\nviscosity = 0.02\nlength = 0.03\n"
        "diameter = 0.05\nclearance = 5e-5\nspeeds = [100.0, 300.0, 600.0, 1000.0]\n")
    assert "plain-journal" in text
    path = tmp_path / "journal.toml"
    path.write_text(text)
    rotor = load_rotor(path).rotor
    speeds, values = rotor.bearing_tables[0]
    expected = PlainJournal(300.0, 0.02, 0.03, 0.05, 5e-5).coefficients(np.asarray(speeds))
    np.testing.assert_allclose(np.asarray(values[0]), np.asarray(expected.k[:, 0, 0]), rtol=1e-12)
    np.testing.assert_allclose(np.asarray(values[2]), np.asarray(expected.k[:, 0, 1]), rtol=1e-12)
    np.testing.assert_allclose(np.asarray(values[5]), np.asarray(expected.c[:, 1, 1]), rtol=1e-12)


def test_built_in_material_by_name(tmp_path):
    from rotorjax.models._materials import MATERIALS

    text = ROSS.read_text().replace('material = "steel"', 'material = "titanium"', 1)
    path = tmp_path / "ti.toml"
    path.write_text(text.replace('name = "steel"', 'name = "steel"', 1))
    rotor = load_rotor(path).rotor
    ti = MATERIALS["titanium"]
    assert float(rotor.E[0]) == ti.E and float(rotor.rho[0]) == ti.rho and float(rotor.E[1]) == 211e9


def test_reduced_rotor_round_trips_exactly(tmp_path):
    again = _round_trip(every_component_scene(reduce=7), tmp_path)
    assert again.rotor.n_modes == 7
    assert "n_modes = 7" in (tmp_path / "first.toml").read_text()


def test_component_order_is_the_files(tmp_path):
    """Components come back in the documented table order, whatever the scene's
    (entries of one table keep their order)."""
    scene = every_component_scene()
    parts = scene.components
    shuffled = RotorScene(scene.rotor, scene.speed, parts[7:] + parts[2:7] + parts[:2])
    save_rotor(shuffled, tmp_path / "r.toml")
    assert_identical(load_rotor(tmp_path / "r.toml"), scene)


def test_save_refuses_what_a_file_cannot_hold(tmp_path):
    from rotorjax._errors import InputError
    from rotorjax.models import RunUp

    scene = every_component_scene()
    with pytest.raises(InputError, match="constant speed"):
        save_rotor(RotorScene(scene.rotor, RunUp(0.0, 10.0)), tmp_path / "r.toml")
    with pytest.raises(InputError, match="one \\[gravity\\]"):
        save_rotor(RotorScene(scene.rotor, 1.0, (Gravity(), Gravity())), tmp_path / "r.toml")
    with pytest.raises(InputError, match="one \\[external_damping\\]"):
        save_rotor(RotorScene(scene.rotor, 1.0, (ExternalDamping(1.0), ExternalDamping(2.0))), tmp_path / "r.toml")
    # the writer checks what it writes as the reader checks a file (the probe table's own check)
    with pytest.raises(InputError, match="save_rotor: probe\\[1\\].name = \"disk\": probe\\[0\\] has that name"):
        save_rotor(RotorScene(scene.rotor, 1.0, (NodeProbe(1), NodeProbe(2))), tmp_path / "r.toml")
    with pytest.raises(InputError, match="probe\\[0\\].name = \"left disk\": must be a word"):
        save_rotor(RotorScene(scene.rotor, 1.0, (NodeProbe(1, "left disk"),)), tmp_path / "r.toml")


def test_evenly_spaced_limiters_equal_their_angles(tmp_path):
    text = ROSS.read_text()
    even = text + ("\n[[limiters]]\nnode = 2\nn = 3\nfirst_angle = 0.25\nclearance = 1e-3\n"
                   "stiffness = 1e7\nradius = 0.1\n")
    angles = 0.25 + 2 * np.pi * np.arange(3) / 3
    listed = text + ("\n[[limiters]]\nnode = 2\nangles = [" + ", ".join(repr(float(a)) for a in angles)
                     + "]\nclearance = [1e-3, 1e-3, 1e-3]\nstiffness = 1e7\nradius = 0.1\n")
    (tmp_path / "even.toml").write_text(even)
    (tmp_path / "listed.toml").write_text(listed)
    assert_identical(load_rotor(tmp_path / "even.toml"), load_rotor(tmp_path / "listed.toml"))


# --- per-element materials --------------------------------------------------------------------
def _reference_matrices(lengths, d_out, d_in, E, G, rho, nu, theory):
    """`(M, G1, K)` of the bare shaft, element by element (no vmap)."""
    shear, rotary = theory == "timoshenko", theory in ("timoshenko", "rayleigh")
    n = 4 * (len(lengths) + 1)
    out = [np.zeros((n, n)) for _ in range(3)]
    for i in range(len(lengths)):
        kappa = cowper_shear_coefficient(nu[i], d_out[i], d_in[i])
        mats = element_matrices(E[i], G[i], rho[i], d_out[i], d_in[i], lengths[i], kappa, shear, rotary)
        for acc, m in zip(out, mats):
            acc[4 * i:4 * i + 8, 4 * i:4 * i + 8] += np.asarray(m)
    return out


@pytest.mark.parametrize("theory", ["timoshenko", "euler-bernoulli"])
def test_two_materials_equal_element_by_element_assembly(theory, tmp_path):
    """ROSS's rotor with two of its elements made hollow bronze: the loaded rotor's
    matrices equal element-by-element assembly with each element's constants."""
    text = ROSS.read_text().replace('theory = "timoshenko"', f'theory = "{theory}"')
    plain = '[[shaft]]\nL = 0.25\nod = 0.05\nid = 0.0\nmaterial = "steel"'
    assert text.count(plain) == 5  # shaft[1..5] (shaft[0] carries comments)
    text = text.replace(plain, plain.replace("id = 0.0", "id = 0.02").replace('"steel"', '"bronze"'), 2)
    text += '\n[[material]]\nname = "bronze"\nE = 110e9\nG = 41e9\nrho = 8800.0\nnu = 0.34\n'
    (tmp_path / "two.toml").write_text(text)
    rotor = load_rotor(tmp_path / "two.toml").rotor
    E, G, rho, d_in = np.full(6, 211e9), np.full(6, 81.2e9), np.full(6, 7810.0), np.zeros(6)
    nu = E / (2 * G) - 1
    for i in (1, 2):
        E[i], G[i], rho[i], nu[i], d_in[i] = 110e9, 41e9, 8800.0, 0.34, 0.02
    assert np.array_equal(rotor.E, E) and np.array_equal(rotor.nu, nu) and np.array_equal(rotor.d_in, d_in)
    M, G1, K = _reference_matrices(np.full(6, 0.25), np.full(6, 0.05), d_in, E, G, rho, nu, theory)
    m, it, ip = ross.PRESET.defaults["disk_mass"], ross.PRESET.defaults["disk_It"], ross.PRESET.defaults["disk_Ip"]
    for node in (2, 4):
        b = 4 * node
        M[b, b] += m
        M[b + 1, b + 1] += m
        M[b + 2, b + 2] += it
        M[b + 3, b + 3] += it
        G1[b + 2, b + 3] += ip
        G1[b + 3, b + 2] -= ip
    for node in (0, 6):
        K[4 * node, 4 * node] += 1e6
        K[4 * node + 1, 4 * node + 1] += 0.8e6
    Mr, Cr, G1r, Kr = (np.asarray(a) for a in rotor.matrices())
    for ours, ref in ((Mr, M), (G1r, G1), (Kr, K)):
        assert close(ours, ref, 1e-14)
    assert not np.any(Cr)


def test_two_material_reference_without_disks():
    """Element-by-element reference on a bare two-material shaft (no disks or bearings)."""
    L, do, di = np.array([0.2, 0.3, 0.25]), np.array([0.05, 0.06, 0.04]), np.array([0.0, 0.02, 0.0])
    E, G, rho = np.array([211e9, 70e9, 211e9]), np.array([81.2e9, 26e9, 81.2e9]), np.array([7810.0, 2700, 7810])
    nu = np.array([211e9 / (2 * 81.2e9) - 1, 0.33, 211e9 / (2 * 81.2e9) - 1])
    rotor = FlexibleRotor(L, do, di, E=E, G=G, rho=rho, nu=nu)
    ref = _reference_matrices(L, do, di, E, G, rho, nu, "timoshenko")
    M, C, G1, K = (np.asarray(a) for a in rotor.matrices())
    for ours, r in zip((M, G1, K), ref):
        assert close(ours, r, 1e-14)
    assert not np.any(C)


@pytest.mark.parametrize("theory", ["timoshenko", "rayleigh", "euler-bernoulli"])
def test_one_material_per_element_is_the_scalar_path_bit_for_bit(theory):
    n = 6
    common = dict(disks=((2, 30.0, 0.2, 0.3),), bearings=((0, 1e6, 8e5, 10.0, 10.0), (n, 1e6, 8e5, 10.0, 10.0)),
                  theory=theory)
    scalar = FlexibleRotor(np.full(n, 0.25), 0.05, 0.01, E=211e9, G=81.2e9, rho=7810.0, **common)
    each = FlexibleRotor(np.full(n, 0.25), 0.05, 0.01, E=np.full(n, 211e9), G=np.full(n, 81.2e9),
                         rho=np.full(n, 7810.0), **common)
    assert np.array_equal(scalar.kappa, each.kappa)
    for a, b in zip(scalar.matrices(), each.matrices()):
        assert np.array_equal(a, b)
    with_nu = FlexibleRotor(np.full(n, 0.25), 0.05, 0.01, E=211e9, G=81.2e9, rho=7810.0, nu=0.3, **common)
    each_nu = FlexibleRotor(np.full(n, 0.25), 0.05, 0.01, E=211e9, G=81.2e9, rho=7810.0, nu=np.full(n, 0.3),
                            **common)
    for a, b in zip(with_nu.matrices(), each_nu.matrices()):
        assert np.array_equal(a, b)


def test_per_element_constants_are_checked():
    from rotorjax._errors import InputError

    with pytest.raises(InputError, match="E .* one value per element \\(3\\)"):
        FlexibleRotor(np.full(3, 0.1), 0.05, E=np.full(2, 211e9))
    with pytest.raises(InputError, match="rho .* must be > 0"):
        FlexibleRotor(np.full(3, 0.1), 0.05, rho=np.array([7810.0, -1.0, 7810.0]))
    with pytest.raises(InputError, match="nu .* must be in"):
        FlexibleRotor(np.full(3, 0.1), 0.05, nu=np.array([0.3, 0.6, 0.3]))


# --- a rotor file as a preset -----------------------------------------------------------------
def test_preset_from_file_defaults_and_set_keys():
    preset = preset_from_file(str(ROSS))
    assert preset.kind == "rotor" and preset.name == str(ROSS) and preset.source == "ross-compare"
    assert preset.speed_key == "speed" and preset.defaults["speed"] == 0.0
    assert preset.defaults["bearing0.kxx"] == 1e6 and preset.units["bearing0.kxx"] == "N/m"
    assert preset.defaults["shaft3.od"] == 0.05 and preset.defaults["disk1.m"] == ross.PRESET.defaults["disk_mass"]
    assert preset.defaults["material0.E"] == 211e9 and preset.defaults["unbalance0.phase"] == 0.0
    assert preset.defaults["disk0.node"] == 2 and "disk0.node" in preset.topology_keys
    assert preset.domains["disk0.node"] == "int[0,6]"
    assert "shaft0.material" not in preset.defaults and "rotor.theory" not in preset.defaults

    params = preset.params({"bearing0.kxx": "2e7", "speed": "150"})
    assert params["bearing0.kxx"] == 2e7
    setup = preset.build(params)
    rotor = setup.scene.rotor
    kxx, kyy = np.asarray(rotor.bearing_params[:, 0]), np.asarray(rotor.bearing_params[:, 1])
    assert list(kxx) == [2e7, 1e6] and list(kyy) == [0.8e6, 0.8e6]
    assert float(setup.scene.speed.omega) == 150.0
    assert setup.t_end == pytest.approx(200 * 2 * np.pi / 150.0, rel=1e-15)
    assert np.array_equal(setup.y0, setup.scene.rest_state())
    # the same change written in the file
    base = preset.build(preset.params())
    assert base.t_end is None
    edited = load_rotor(ROSS, {"bearing0.kxx": 2e7, "speed": 150.0})
    assert_identical(setup.scene, edited)


def test_preset_from_file_nonlinear_keys():
    preset = preset_from_file(str(RIG))
    for key in ("limiters0.clearance", "internal_damping.relaxation_time", "gravity.g", "auto_balancer0.mass",
                "cubic_bearing0.k3", "clearance_bearing0.clearance", "material1.nu"):
        assert key in preset.defaults
    assert preset.defaults["speed"] == 300.0
    setup = preset.build(preset.params({"limiters0.clearance": "2e-3", "gravity.g": 0}))
    lim = next(c for c in setup.scene.components if isinstance(c, LimitersAt))
    assert np.all(np.asarray(lim.limiters.clearance) == 2e-3)
    assert float(next(c for c in setup.scene.components if isinstance(c, Gravity)).g) == 0.0
    assert setup.t_end == pytest.approx(200 * 2 * np.pi / 300.0)
    assert setup.y0.shape == (setup.scene.state_size,)


def test_presets_get_opens_rotor_files():
    from rotorjax.presets import get

    assert get(str(ROSS)).kind == "rotor"


def test_rig_file_components_in_the_documented_order():
    scene = load_rotor(RIG)
    assert [type(c).__name__ for c in scene.components] == [
        "Unbalance", "InternalDamping", "Gravity", "CubicBearing", "ClearanceBearing", "LimitersAt", "BalancerAt"]
    assert np.asarray(scene.rotor.E).shape == (6,)
    assert scene.n_dof == scene.n_shaft + 2


def test_text_is_readable_toml():
    import tomllib

    doc = tomllib.loads(rotor_file_text(load_rotor(RIG), "rig"))
    assert doc["rotor"]["name"] == "rig" and len(doc["shaft"]) == 6 and len(doc["material"]) == 2
