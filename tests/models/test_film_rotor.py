"""A finite-element rotor on fluid films (one rotor layout for the file): its static
equilibrium in the journals against the short bearing's closed form, the journal
interchangeable with its coefficient table on the same node, rotor files with
`type = "journal"` / `"sfd"` (round trip), and the CLI (`static`, `modes`, `hopf`,
`simulate`) on them, bad input included."""

import json
import math

import jax.numpy as jnp
import numpy as np
import pytest

from rotorjax.analysis import bearing_equilibrium, hopf_points
from rotorjax.cli import main
from rotorjax.models import static_equilibrium
from rotorjax.io import load_rotor
from rotorjax.models._journal_bearing import short_bearing_coefficients, short_bearing_eccentricity
from rotorjax.io import rotor_file_text
from rotorjax.models._validate import InputError

MU, LEN, DIA, CLR, SPEED = 0.02, 0.02, 0.05, 5e-5, 300.0

HEAD = """
[rotor]
name = "film-test"
theory = "timoshenko"
speed = 300.0

[[shaft]]
L = 0.2
od = 0.05
material = "steel"

[[shaft]]
L = 0.2
od = 0.05
material = "steel"

[[disk]]
node = 1
m = 10.0
Id = 0.03
Ip = 0.05

[gravity]
"""


def _journal(node, model="short"):
    return (f'\n[[bearing]]\nnode = {node}\ntype = "journal"\nmodel = "{model}"\nviscosity = {MU}\n'
            f"length = {LEN}\ndiameter = {DIA}\nclearance = {CLR}\n")


def _table(node, load, speeds):
    return (f'\n[[bearing]]\nnode = {node}\ntype = "plain-journal"\nload = {load!r}\nviscosity = {MU}\n'
            f"length = {LEN}\ndiameter = {DIA}\nclearance = {CLR}\nspeeds = {list(speeds)!r}\n")


@pytest.fixture(scope="module")
def files(tmp_path_factory):
    d = tmp_path_factory.mktemp("films")
    journal = d / "journal.toml"
    journal.write_text(HEAD + _journal(0) + _journal(2))
    return d, journal


@pytest.fixture(scope="module")
def scene(files):
    return load_rotor(files[1])


@pytest.fixture(scope="module")
def weight(scene):
    """The rotor's weight, N (the static load's total along -y)."""
    n = scene.full_rotor.n_nodes
    F = np.asarray(scene.E.T @ scene.F0) if False else np.asarray(scene.rotor.expand(scene.F0))
    return -float(np.sum(F[1:4 * n:4]))


def test_equilibrium_matches_the_short_bearing_closed_form(scene, weight):
    res = bearing_equilibrium(scene, SPEED)
    w = weight / 2   # a symmetric rotor: each journal carries half
    ss = MU * SPEED * DIA * LEN ** 3 / (8 * CLR ** 2 * w)
    eps = float(short_bearing_eccentricity(ss))
    phi = math.atan2(math.pi * math.sqrt(1 - eps ** 2), 4 * eps)
    for f in res.films:
        assert abs(f.eccentricity - eps) <= 1e-9
        assert abs(f.attitude - phi) <= 1e-8
        assert abs(f.min_film - CLR * (1 - eps)) <= 1e-9 * CLR
        assert abs(f.load - w) <= 1e-8 * w
    assert res.residual < 1e-10


def test_journal_and_its_coefficient_table_are_interchangeable(files, scene, weight):
    """The same node as a nonlinear journal (linearised about the equilibrium) or as
    `type = "plain-journal"` coefficients at the load it carries: the same modes."""
    d, _ = files
    table = d / "table.toml"
    table.write_text(HEAD.replace("[gravity]\n", "") + _table(0, weight / 2, [200.0, 300.0, 400.0])
                     + _table(2, weight / 2, [200.0, 300.0, 400.0]))
    lam_j = np.sort_complex(np.linalg.eigvals(np.asarray(scene.linear_matrices(SPEED).state_matrix())))
    lam_t = np.sort_complex(np.linalg.eigvals(np.asarray(load_rotor(table).linear_matrices(SPEED).state_matrix())))
    low = np.abs(lam_j) < 1e4     # the film-borne modes (the shaft's own are far above)
    np.testing.assert_allclose(lam_j[low], lam_t[low], rtol=1e-7)


def test_coefficients_from_the_equilibrium_are_the_short_bearings(scene, weight):
    """The films' linearisation inside `linear_matrices`, at the journal's dofs."""
    eq = static_equilibrium(scene, SPEED)
    lin, rest = scene.linear_matrices(SPEED), scene._linear_about_rest(SPEED)
    w = weight / 2
    eps = float(short_bearing_eccentricity(MU * SPEED * DIA * LEN ** 3 / (8 * CLR ** 2 * w)))
    _, a, b = short_bearing_coefficients(eps)
    rows = np.asarray(scene._node_rows(0))
    pick = [int(np.argmax(np.abs(r))) for r in rows]     # free coordinates of node 0's x, y
    k = np.asarray(lin.K - rest.K)[np.ix_(pick, pick)]
    c = np.asarray(lin.C - rest.C)[np.ix_(pick, pick)]
    np.testing.assert_allclose(k, w / CLR * np.asarray(a), rtol=1e-9, atol=1e-9 * w / CLR)
    np.testing.assert_allclose(c, w / (CLR * SPEED) * np.asarray(b), rtol=1e-9, atol=1e-9 * w / (CLR * SPEED))
    assert bool(eq.converged)


def test_round_trip_through_a_rotor_file(files, scene, tmp_path):
    text = rotor_file_text(scene)
    assert text.count('type = "journal"') == 2
    path = tmp_path / "again.toml"
    path.write_text(text)
    again = load_rotor(path)
    for a, b in zip(scene.components, again.components):
        assert type(a) is type(b) and a.describe() == b.describe()
    np.testing.assert_allclose(np.asarray(static_equilibrium(again, SPEED).q),
                               np.asarray(static_equilibrium(scene, SPEED).q), rtol=1e-12, atol=1e-18)


def test_squeeze_film_damper_file_and_its_refusals(files):
    d, _ = files
    sfd = d / "sfd.toml"
    sfd.write_text(HEAD + _journal(0) + _journal(2) + '\n[[bearing]]\nnode = 1\ntype = "sfd"\nfilm = "2pi"\n'
                   f"viscosity = {MU}\nlength = {LEN}\ndiameter = 0.1\nclearance = {CLR}\n")
    sc = load_rotor(sfd)
    assert "squeeze-film damper (2pi film) at node 1" in sc.describe()
    # a 2 pi film at the centre is linear: C = pi mu R L^3 / c^3 on the node's x, y
    eq = static_equilibrium(sc, SPEED)
    assert bool(eq.converged)
    uncentred = d / "sfd_alone.toml"
    uncentred.write_text(HEAD + '\n[[bearing]]\nnode = 1\ntype = "sfd"\n'
                         f"viscosity = {MU}\nlength = {LEN}\ndiameter = 0.1\nclearance = {CLR}\n")
    with pytest.raises(InputError, match="squeeze-film damper .pi film. at node 1 has no centring spring"):
        static_equilibrium(load_rotor(uncentred), SPEED)


def test_sfd_linearisation_at_the_centre(files):
    d, _ = files
    path = d / "sfd_spring.toml"
    path.write_text(HEAD.replace("[gravity]\n", "") + '\n[[bearing]]\nnode = 0\nkxx = 1e7\n\n[[bearing]]\nnode = 2\n'
                    'kxx = 1e7\n\n[[bearing]]\nnode = 1\ntype = "sfd"\nfilm = "2pi"\nkxx = 1e5\n'
                    f"viscosity = {MU}\nlength = {LEN}\ndiameter = 0.1\nclearance = {CLR}\n")
    sc = load_rotor(path)
    lin, rest = sc.linear_matrices(SPEED), sc._linear_about_rest(SPEED)
    rows = np.asarray(sc._node_rows(1))
    pick = [int(np.argmax(np.abs(r))) for r in rows]
    c = np.asarray(lin.C - rest.C)[np.ix_(pick, pick)]
    c0 = math.pi * MU * 0.05 * LEN ** 3 / CLR ** 3
    np.testing.assert_allclose(c, c0 * np.eye(2), rtol=1e-9, atol=1e-9 * c0)
    # the centring spring is the damper's linear part
    k = np.asarray(rest.K)[np.ix_(pick, pick)] - np.asarray(load_rotor(path, {"bearing2.kxx": 0.0})
                                                            ._linear_about_rest(SPEED).K)[np.ix_(pick, pick)]
    np.testing.assert_allclose(k, 1e5 * np.eye(2), rtol=1e-12)


# ---- the CLI ---------------------------------------------------------------------------------

def test_cli_static_reports_each_bearing(files, scene, tmp_path, capsys):
    _, journal = files
    assert main(["static", str(journal), "--json", "--out", str(tmp_path)]) == 0
    out = json.loads(capsys.readouterr().out)
    res = bearing_equilibrium(scene, SPEED)
    assert out["speed"] == SPEED and len(out["bearings"]) == 2
    for row, f in zip(out["bearings"], res.films):
        assert row["node"] == f.node and row["eccentricity"] == pytest.approx(f.eccentricity, rel=1e-12)
        assert row["attitude_deg"] == pytest.approx(math.degrees(f.attitude), rel=1e-12)
    assert (tmp_path / "static_journal.json").exists()


def test_cli_hopf_reports_the_oil_whirl_onset(files, scene, tmp_path, capsys):
    _, journal = files
    assert main(["hopf", str(journal), "--range", "100", "3000", "--n-scan", "12", "--json",
                 "--out", str(tmp_path)]) == 0
    out = json.loads(capsys.readouterr().out)
    ref = hopf_points(scene, 100.0, 3000.0, n_scan=12)   # the same compiled scan
    assert len(out["hopf_points"]) == len(ref) >= 1
    h = out["hopf_points"][0]
    for key in ("speed", "frequency", "whirl_frequency", "whirl_frequency_ratio", "whirl", "speed_crit"):
        assert key in h
    assert h["speed"] == pytest.approx(ref[0].speed, rel=1e-9)
    assert h["whirl_frequency_ratio"] == pytest.approx(ref[0].frequency / ref[0].speed, rel=1e-9)
    assert 0.3 < h["whirl_frequency_ratio"] < 0.55 and h["whirl"] == "forward"   # near 1/2: a light load
    assert out["unit"] == "speed speed and whirl frequency in rad/s"
    # below the onset: none, and the text says so
    assert main(["hopf", str(journal), "--range", "20", str(0.9 * ref[0].speed), "--n-scan", "12",
                 "--out", str(tmp_path)]) == 0
    assert "keeps its stability" in capsys.readouterr().out


def test_cli_modes_at_the_equilibrium(files, scene, tmp_path, capsys):
    _, journal = files
    assert main(["modes", str(journal), "--json", "--n-modes", "2", "--out", str(tmp_path)]) == 0
    out = json.loads(capsys.readouterr().out)
    lam = np.linalg.eigvals(np.asarray(scene.linear_matrices(SPEED).state_matrix()))
    wd = np.sort(lam.imag[lam.imag > 1e-6])
    assert out["modes"][0]["damped_frequency"] == pytest.approx(wd[0], rel=1e-8)


def test_cli_simulate_starts_from_the_equilibrium(files, scene, tmp_path, capsys):
    _, journal = files
    assert main(["simulate", str(journal), "--set", "speed=150", "--t-end", "0.02", "--n-save", "20", "--json",
                 "--out", str(tmp_path)]) == 0
    out = json.loads(capsys.readouterr().out)
    eps0 = bearing_equilibrium(scene, 150.0).films[0].eccentricity
    assert out["success"] and out["journal0_eccentricity_final"] == pytest.approx(eps0, rel=1e-6)


def test_cli_run_into_the_wall_fails_naming_the_bearing(files, tmp_path, capsys):
    d, _ = files
    path = d / "heavy.toml"     # a heavy unbalance drives the journals into their walls
    path.write_text(HEAD + _journal(0) + _journal(2) + "\n[[unbalance]]\nnode = 1\nmagnitude = 0.05\n")
    rc = main(["simulate", str(path), "--t-end", "0.2", "--n-save", "400", "--max-steps", "20000",
               "--out", str(tmp_path)])
    text = capsys.readouterr().out
    assert rc == 3
    assert "the journal bearing at node" in text and "had eccentricity" in text and "t = " in text


@pytest.mark.parametrize("argv, words", [
    (["hopf", "{journal}"], "--range LO HI is required for a rotor file"),
    (["static", "{journal}", "--gravity", "3"], "--gravity: a rotor on fluid-film bearings is loaded by its file"),
    (["static", "{journal}", "--set", "speed=0"], "a journal bearing carries its load only while the shaft spins"),
    (["static", "{journal}", "--set", "bearing0.clearance=0.03"], "bearing[0].clearance must be < diameter / 2"),
    (["static", "{journal}", "--set", "bearing1.viscosity=-1"], "bearing1.viscosity"),
    (["modes", "{journal}", "--speed", "0"], "the rotor's linear equations at 0 rad/s: a journal bearing carries"),
    (["campbell", "{journal}", "--range", "0", "300"], "speed 0 rad/s: a rotor on journal bearings has linear"),
])
def test_cli_bad_input_on_film_rotors(files, tmp_path, capsys, argv, words):
    _, journal = files
    rc = main([a.format(journal=journal) for a in argv] + ["--out", str(tmp_path)])
    assert rc == 2
    assert words in capsys.readouterr().err


def test_a_batch_of_designs_runs_like_each_design(scene):
    """Viscosity swept in one batch (`simulate_batch` over scenes built by
    `eqx.filter_vmap`): each lane equals its own run, from its own equilibrium."""
    import equinox as eqx

    from rotorjax import simulate
    from rotorjax.models import JournalBearing, RotorScene
    from rotorjax.solve import simulate_batch

    def build(mu):
        parts = tuple(JournalBearing(c.node, mu, LEN, DIA, CLR) if type(c) is JournalBearing else c
                      for c in scene.components)
        return RotorScene(scene.rotor, SPEED, parts)

    mus = jnp.array([0.015, 0.02, 0.03])
    scenes = eqx.filter_vmap(build)(mus)
    y0s = jnp.stack([build(m).rest_state().at[:scene.n_shaft].set(static_equilibrium(build(m), SPEED).q)
                     for m in mus])
    y0s = y0s.at[:, scene.n_shaft + 1].add(1e-3)      # a kick: the films whirl or settle
    res = simulate_batch(scenes, y0s, (0.0, 0.01), saveat=5, rtol=1e-9, atol=1e-13)
    one = simulate(build(mus[2]), y0s[2], (0.0, 0.01), saveat=5, rtol=1e-9, atol=1e-13)
    assert not np.any(np.asarray(res.code))
    np.testing.assert_allclose(np.asarray(res.ys[2, -1]), np.asarray(one.ys[-1]), rtol=1e-6, atol=1e-12)
