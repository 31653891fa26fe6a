"""`rotorjax periodic` (issue 30, item 6): the branch of periodic forced motions of
the shipped rotor file `cubic_rig.toml` (ROSS's example rotor on cubic bearings)
continued in the speed by harmonic balance. One run, shared: its folds are those of
`synchronous_branch` (the rotating frame's rest points, computed here on the same
scene), its middle part is unstable, both ends stop on the range's edges, and a
node's amplitude is the largest radius of that node's orbit from `harmonic_balance`
at the start, sampled here from the solution's outputs."""

import json
import os
import re

import numpy as np
import pytest

import rotorjax
from rotorjax import presets
from rotorjax.cli import main

from .helpers import documentation

ROTOR = os.path.join(os.path.dirname(rotorjax.__file__), "rotors", "cubic_rig.toml")
#: docs/cli.md's command, at the defaults (tests/test_readme.py leaves it to this file: `RUN_ELSEWHERE`)
DOCS_COMMAND = "rotorjax periodic cubic_rig.toml --param speed --range 100 106"
ARGV = DOCS_COMMAND.split()[1:]
NODE = 1   # disk 1


@pytest.fixture(scope="module")
def run(tmp_path_factory):
    out = tmp_path_factory.mktemp("periodic")
    import io
    from contextlib import redirect_stderr, redirect_stdout

    stdout, stderr = io.StringIO(), io.StringIO()
    with redirect_stdout(stdout), redirect_stderr(stderr):
        rc = main(ARGV + ["--node", str(NODE), "--json", "--out", str(out), "--switch"])
    assert rc == 0, stderr.getvalue()
    return json.loads(stdout.getvalue()), out


@pytest.fixture(scope="module")
def scene():
    preset = presets.get(ROTOR)
    return preset.build(preset.params()).scene


def test_json_has_the_branch_and_its_bifurcations(run):
    d, _ = run
    assert {"param", "node", "amplitude_unit", "amplitude_of", "method", "harmonics", "subharmonic", "range",
            "branches", "bifurcations", "files"} <= set(d)
    assert (d["param"], d["node"], d["amplitude_unit"], d["method"], d["harmonics"], d["subharmonic"], d["range"]) \
        == ("speed", NODE, "m", "harmonic-balance", "auto", 1, [100.0, 106.0])
    assert d["amplitude_of"] == f"largest radius of node {NODE}'s orbit over the period"
    (b,) = d["branches"]
    n = len(b["speed"])
    assert n > 10 and len(b["amplitude"]) == n and len(b["stable"]) == n
    assert b["harmonics"] == [1] * n   # auto: a circular orbit needs one
    assert all(isinstance(s, bool) for s in b["stable"]) and min(b["amplitude"]) > 0
    # the defaults of --harmonics auto, as docs/cli.md states them, each point held to the target
    assert (d["truncation_tol"], d["max_harmonics"]) == (1e-6, 32)
    cli = re.sub(r"\s+", " ", documentation("docs/cli.md"))
    assert "`--max-harmonics` (32)" in cli and "`--truncation-tol` (1e-6)" in cli
    assert len(b["truncation"]) == n and max(b["truncation"]) <= d["truncation_tol"]
    for e in d["bifurcations"]:
        assert set(e) >= {"kind", "speed", "amplitude", "residual"}
        assert e["kind"] in ("fold", "branch-point", "period-doubling", "neimark-sacker", "hopf")
    # --switch: the synchronous branch of this rotor has no branch point (its folds only)
    assert d["switched"] == [] and "branch-point" not in {e["kind"] for e in d["bifurcations"]}
    assert "the CSV's `branch` column (0 the branch, 1, 2, ... the switched ones)" in cli


def test_folds_are_the_synchronous_branchs(run, scene):
    """Exactly two folds in (100, 106), equal to the rotating-frame branch's (a
    different problem: rest points of the rotating frame) to 1e-6."""
    from rotorjax.analysis import synchronous_branch

    d, _ = run
    folds = sorted(e["speed"] for e in d["bifurcations"] if e["kind"] == "fold")
    assert len(folds) == 2 and all(100.0 < f < 106.0 for f in folds)
    ref = sorted(e.p for e in synchronous_branch(scene, (100.0, 106.0)).events if e.kind == "fold")
    np.testing.assert_allclose(folds, ref, rtol=1e-6)


def test_middle_part_unstable_and_the_ends_on_the_range(run):
    d, _ = run
    (b,) = d["branches"]
    lo, hi = sorted(e["speed"] for e in d["bifurcations"] if e["kind"] == "fold")
    p, stable = np.array(b["speed"]), np.array(b["stable"])
    outside = (p < lo - 0.01) | (p > hi + 0.01)
    assert stable[outside].all() and not stable.all()
    # between the folds, three motions at a speed: the unstable one has the middle amplitude
    w = 0.5 * (lo + hi)
    amp = np.array(b["amplitude"])
    at_w = [(np.interp(w, p[i:i + 2], amp[i:i + 2]) if p[i] < p[i + 1] else
             np.interp(w, p[i:i + 2][::-1], amp[i:i + 2][::-1]), bool(stable[i] and stable[i + 1]))
            for i in range(len(p) - 1) if (p[i] - w) * (p[i + 1] - w) < 0]
    assert [s for _, s in sorted(at_w)] == [True, False, True]
    assert b["stops"] == ["box edge (speed = 100.0)", "box edge (speed = 106.0)"]
    assert b["stop"] == "box edge"


def test_node_amplitude_is_the_orbits_largest_radius(run, scene):
    """At the start (speed 100, one motion) the branch's amplitude is the largest
    radius of node 1's orbit, sampled densely from `harmonic_balance`'s solution
    through the scene's outputs."""
    import jax

    from rotorjax.analysis import harmonic_balance

    d, _ = run
    (b,) = d["branches"]
    i = int(np.argmin(np.abs(np.array(b["speed"]) - 100.0)))
    assert b["speed"][i] == 100.0
    T = 2 * np.pi / 100.0
    hb = harmonic_balance(scene, T, scene.rest_state(), harmonics=1, stability=False)
    assert int(hb.code) == 0
    ts = np.linspace(0.0, T, 2001)
    out = jax.vmap(lambda t: scene.outputs(t, hb.state(t)))(ts)
    radius = np.hypot(np.asarray(out["node_x"])[:, NODE], np.asarray(out["node_y"])[:, NODE]).max()
    np.testing.assert_allclose(b["amplitude"][i], radius, rtol=1e-6)


def test_files_are_written(run):
    d, out = run
    stem = os.path.join(str(out), "periodic_cubic_rig_speed")
    assert d["files"] == {"data": stem + ".csv", "summary": stem + ".json", "plot": stem + ".png"}
    assert all(os.path.getsize(f) > 0 for f in d["files"].values())
    with open(stem + ".json") as f:
        assert json.load(f) == d
    rows = np.loadtxt(stem + ".csv", delimiter=",", skiprows=1)
    with open(stem + ".csv") as f:
        assert f.readline().strip() == "speed,amplitude,stable,margin,branch"    # --switch: the branch column
    (b,) = d["branches"]
    np.testing.assert_array_equal(rows[:, -1], 0.0)
    np.testing.assert_allclose(rows[:, 0], b["speed"])
    np.testing.assert_array_equal(rows[:, 2].astype(bool), b["stable"])


def test_readme_states_the_folds(run):
    """The README's `periodic` entry: its command is this run's (without `--node`),
    and the fold speeds it states are this run's, to the digits stated."""
    d, _ = run
    cli = documentation("docs/cli.md")
    assert DOCS_COMMAND in re.sub(r"\s+", " ", cli)
    m = re.search(r"folds at ([\d.]+) and ([\d.]+) rad/s", re.sub(r"\s+", " ", cli))
    assert m, "the README's CLI section no longer states the folds of `periodic`"
    folds = sorted(e["speed"] for e in d["bifurcations"] if e["kind"] == "fold")
    np.testing.assert_allclose(folds, [float(g) for g in m.groups()], atol=0.006)


def test_a_range_without_the_files_speed_starts_at_its_nearest_end(run, tmp_path, capsys):
    """The human summary of a range given in rpm that leaves out the file's speed (100
    rad/s): the branch starts at the range's end nearest to it (960 rpm = 100.531 rad/s),
    says so, and reaches both ends through the same two folds as the module's run."""
    d, _ = run
    argv = ["periodic", "cubic_rig.toml", "--param", "speed", "--range", "960", "1010", "rpm", "--harmonics", "1"]
    rc = main(argv + ["--out", str(tmp_path)])
    cap = capsys.readouterr()
    assert rc == 0, cap.err
    lines = cap.out.splitlines()
    assert lines[0].endswith("wrote " + os.path.join(str(tmp_path), "periodic_cubic_rig_speed") + ".csv, .json, .png")
    lo, hi = 960 * np.pi / 30, 1010 * np.pi / 30
    assert f"speed in [{lo:g}, {hi:g}] from {lo:g} (the end of --range nearest to the preset's value 100)" in lines[1]
    with open(tmp_path / "periodic_cubic_rig_speed.json") as f:
        here = json.load(f)
    assert here["start"] == pytest.approx(lo, rel=1e-15) and here["start_source"].startswith("the end of --range")
    ends = [re.fullmatch(r"box edge \(speed = ([\d.]+)\)", stop) for stop in here["branches"][0]["stops"]]
    assert all(ends) and [float(m.group(1)) for m in ends] == pytest.approx([lo, hi], rel=1e-15)
    folds = [sorted(e["speed"] for e in x["bifurcations"] if e["kind"] == "fold") for x in (here, d)]
    np.testing.assert_allclose(folds[0], folds[1], rtol=1e-9)
    # the same start given as --from, in rpm: the same branch
    rc = main(argv + ["--from", "960rpm", "--out", str(tmp_path / "from")])
    assert rc == 0, capsys.readouterr().err
    with open(tmp_path / "from" / "periodic_cubic_rig_speed.json") as f:
        given = json.load(f)
    assert given["start_source"] == "--from" and given["start"] == here["start"]
    np.testing.assert_array_equal(given["branches"][0]["speed"], here["branches"][0]["speed"])


def test_a_branch_that_fails_inside_the_range_exits_3_after_writing(tmp_path, capsys, monkeypatch):
    """A branch end whose corrector failed inside the range is a numerical failure:
    the files are written first, then exit 3 with the reason (the library's branch,
    its end's stop reason replaced by a failure: none occurs on this rotor)."""
    import dataclasses

    import rotorjax.analysis

    real = rotorjax.analysis.periodic_branch

    def failing(*args, **kwargs):
        br, coefficients = real(*args, **kwargs)
        stops = (br.curve.stops[0], "corrector failed (step below ds_min) at speed = 100.1")
        return dataclasses.replace(br, curve=dataclasses.replace(br.curve, stops=stops)), coefficients

    monkeypatch.setattr(rotorjax.analysis, "periodic_branch", failing)
    rc = main(ARGV + ["--max-points", "2", "--out", str(tmp_path)])
    cap = capsys.readouterr()
    assert rc == 3
    last = cap.err.strip().splitlines()[-1]
    assert last.startswith("rotorjax: numerical failure: the branch stopped inside --range 100 106: corrector "
                           "failed (step below ds_min) at speed = 100.1")
    assert "Traceback" not in cap.err
    for ext in ("csv", "json", "png"):
        assert (tmp_path / f"periodic_cubic_rig_speed.{ext}").exists()


def test_a_rotor_file_entry_is_continued_where_the_scene_is_affine_in_it(tmp_path, capsys):
    """`--param` a rotor file's entry other than the speed (issue 62, item 5): the cubic stiffness of bearing 0
    at 103 rad/s. The branch folds in k3 (the jump boundary crossed at fixed speed), and both ends come back
    to the range's lower edge. Checked against independent builds of the file with that entry (not the traced
    scene): the amplitudes of the stable part equal harmonic balance's from rest, sampled densely as above;
    the fold's k3 is where the rotating frame's branch of the rebuilt file folds at 103 rad/s. An entry the
    scene is not affine in (a shaft diameter) is refused, exit 2, by name."""
    import jax

    from rotorjax.analysis import harmonic_balance, synchronous_branch

    key = "cubic_bearing0.k3"
    argv = ["periodic", "cubic_rig.toml", "--set", "speed=103", "--harmonics", "1", "--node", str(NODE), "--json",
            "--out", str(tmp_path), "--param"]
    assert main(argv + [key, "--range", "2e12", "4e12"]) == 0
    d = json.loads(capsys.readouterr().out)
    (b,) = d["branches"]
    assert d["start"] == 3e12 and d["start_source"] == "the preset's value"
    assert b["stops"] == [f"box edge ({key} = 2000000000000.0)"] * 2
    (fold,) = d["bifurcations"]
    assert fold["kind"] == "fold" and 3e12 < fold[key] < 4e12
    preset = presets.get(ROTOR)

    def rebuilt(k3):
        return preset.build(dict(preset.params(), speed=103.0, **{key: k3})).scene

    T = 2 * np.pi / 103.0
    ts = np.linspace(0.0, T, 2001)
    k3, stable = np.array(b[key]), np.array(b["stable"])
    for i in (0, int(np.argmin(np.abs(k3 - 3e12)))):     # the stable part, from the lower edge to the start
        assert stable[i]
        scene = rebuilt(k3[i])
        hb = harmonic_balance(scene, T, scene.rest_state(), harmonics=1, stability=False)
        out = jax.vmap(lambda t: scene.outputs(t, hb.state(t)))(ts)
        radius = np.hypot(np.asarray(out["node_x"])[:, NODE], np.asarray(out["node_y"])[:, NODE]).max()
        assert int(hb.code) == 0
        np.testing.assert_allclose(b["amplitude"][i], radius, rtol=1e-6)
    speeds = [e.p for e in synchronous_branch(rebuilt(fold[key]), (100.0, 106.0)).events if e.kind == "fold"]
    assert min(abs(s - 103.0) for s in speeds) < 1e-6 * 103.0
    assert main(argv + ["shaft0.od", "--range", "0.04", "0.06"]) == 2
    assert "--param shaft0.od: the scene's arrays do not depend affinely on shaft0.od" in capsys.readouterr().err


#: the jump boundary: the folds continued in (speed, a cubic stiffness), and the amplitude's derivative in it
K3, RANGE2 = "cubic_bearing0.k3", (1e12, 6e12)
#: docs/cli.md's command for it (run here only: tests/test_readme.py's `RUN_ELSEWHERE`)
JUMP_COMMAND = f"{DOCS_COMMAND} --node {NODE} --param2 {K3} --range2 1e12 6e12"


@pytest.fixture(scope="module")
def jump(tmp_path_factory):
    out = tmp_path_factory.mktemp("jump")
    import io
    from contextlib import redirect_stderr, redirect_stdout

    stdout, stderr = io.StringIO(), io.StringIO()
    with redirect_stdout(stdout), redirect_stderr(stderr):
        rc = main(JUMP_COMMAND.split()[1:] + ["--json", "--out", str(out)])
    assert rc == 0, stderr.getvalue()
    return json.loads(stdout.getvalue()), out


def _scene_with(k3):
    preset = presets.get(ROTOR)
    return preset.build(dict(preset.params(), **{K3: float(k3)})).scene


def test_the_jump_boundary_is_the_synchronous_branchs_folds(jump, run):
    """Each fold of the branch continued in (speed, k3) (issue 62, item 7): it starts
    at the branch's fold, spans the k3 range to its edges, and at two of its interior
    points the fold speed equals the rotating-frame branch's (`synchronous_branch`, a
    different problem, solved at that k3) to 1e-6."""
    from rotorjax.analysis import synchronous_branch

    d, _ = jump
    assert (d["param2"], d["range2"], d["param2_value"]) == (K3, list(RANGE2), 3e12)
    doc = " ".join(documentation("docs/cli.md").split())
    assert "both folds run to the edges of the `k3` range" in doc and "`synchronous_branch`, solved at that `k3`) to " \
        "1e-6, and the derivative equals central differences of harmonic balance to 1e-5" in doc
    folds = sorted(e["speed"] for e in run[0]["bifurcations"] if e["kind"] == "fold")
    curves = d["fold_curves"]
    assert [c["from"]["speed"] for c in curves] == pytest.approx(folds, rel=1e-12)
    for c in curves:
        speed, k3 = np.array(c["speed"]), np.array(c[K3])
        assert c["stop"] == "box edge" and c["stop_codes"] == [0, 0] and c["residual_max"] < 1e-9
        assert k3.min() == RANGE2[0] or k3.max() == RANGE2[1]
        for i in (len(k3) // 3, 2 * len(k3) // 3):
            ref = [e.p for e in synchronous_branch(_scene_with(k3[i]), (100.0, 106.0)).events
                   if e.kind == "fold"]
            assert min(abs(r / speed[i] - 1) for r in ref) < 1e-6


def test_the_amplitude_derivative_in_k3_equals_finite_differences(jump):
    """`d_amplitude_d_param2` at the range's ends (one motion each) equals central
    differences of `harmonic_balance` solved at k3 (1 -+ 1e-4) to 1e-5."""
    from rotorjax.analysis import harmonic_balance, orbit_amplitude

    d, _ = jump
    (b,) = d["branches"]
    for i in (0, len(b["speed"]) - 1):
        w = b["speed"][i]
        T = 2 * np.pi / w

        def amplitude(k3):
            import equinox as eqx

            sc = eqx.tree_at(lambda s: s.speed.constant, _scene_with(k3), w)
            hb = harmonic_balance(sc, T, sc.rest_state(), harmonics=1, stability=False)
            assert int(hb.code) == 0
            return float(orbit_amplitude(sc, hb.coefficients, T, node=NODE))

        h = 1e-4 * 3e12
        fd = (amplitude(3e12 + h) - amplitude(3e12 - h)) / (2 * h)
        np.testing.assert_allclose(b["d_amplitude_d_param2"][i], fd, rtol=1e-5)
        assert b["amplitude"][i] == pytest.approx(amplitude(3e12), rel=1e-8)


def test_the_jump_boundary_files(jump):
    d, out = jump
    stem = os.path.join(str(out), "periodic_cubic_rig_speed")
    assert d["files"]["fold_curves"] == stem + "_folds.csv" and d["files"]["fold_plot"] == stem + "_folds.png"
    assert all(os.path.getsize(f) > 0 for f in d["files"].values())
    with open(stem + ".csv") as f:
        assert f.readline().strip() == f"speed,amplitude,stable,margin,d_amplitude_d_{K3}"
    rows = np.loadtxt(stem + "_folds.csv", delimiter=",", skiprows=1)
    with open(stem + "_folds.csv") as f:
        assert f.readline().strip() == f"speed,{K3},fold_curve"
    for i, c in enumerate(d["fold_curves"]):
        np.testing.assert_allclose(rows[rows[:, 2] == i][:, :2], np.column_stack([c["speed"], c[K3]]))


def test_an_exit_3_names_every_reason():
    """A branch that ran out of points and missed its harmonics target says both (the
    first, the others after it), then the files written."""
    from rotorjax.cli._periodic import _failure

    assert _failure(["max_points reached", "harmonics insufficient"], "/out/periodic_rig_speed") == \
        "max_points reached; also: harmonics insufficient (files written: periodic_rig_speed.*)"
    assert _failure(["max_points reached"], "/out/periodic_rig_speed") == \
        "max_points reached (files written: periodic_rig_speed.*)"
