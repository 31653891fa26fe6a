"""`rotorjax periodic --from-hopf` (issue 62, item 5): the limit cycles born at the oil-whirl
onset of the shipped rotor file `journal_rig.toml` (ROSS's example rotor on two short journal
bearings), its unbalance set to zero (an autonomous scene), continued in the speed by harmonic
balance at the command's defaults. One run, shared:

- the Hopf point is the reference motion's (`reference_hopf_points`, the same scan `rotorjax hopf`
  runs), and the first cycle's period is the crossing pair's 2 pi / |Im lambda| to 1e-6;
- the branch runs from the Hopf point to the range's top (supercritical: the cycles live above the
  onset, stable), every cycle within the harmonics' truncation check;
- independent of harmonic balance: each checked cycle's state at phase 0, integrated over its period
  by `rotorjax.simulate` (Dopri8 at rtol 1e-10), comes back to itself, and the node's largest radius
  over the run is the command's amplitude to 1e-4 of the whirl's size."""

import io
import json
import re
from contextlib import redirect_stderr, redirect_stdout

import jax.numpy as jnp
import numpy as np
import pytest

import rotorjax
from rotorjax import presets
from rotorjax.analysis import reference_hopf_points
from rotorjax.cli import main
from rotorjax.io import shipped_rotor

from .helpers import documentation

#: docs/cli.md's command (tests/test_readme.py leaves it to this file: `RUN_ELSEWHERE`)
DOCS_COMMAND = ("rotorjax periodic journal_rig.toml --param speed --range 200 210 --from-hopf --set "
                "unbalance0.magnitude=0 --node 2")
ARGV = DOCS_COMMAND.split()[1:]


@pytest.fixture(scope="module")
def preset():
    return presets.get(shipped_rotor("journal_rig"))


@pytest.fixture(scope="module")
def run(tmp_path_factory):
    out = tmp_path_factory.mktemp("from_hopf")
    stdout, stderr = io.StringIO(), io.StringIO()
    with redirect_stdout(stdout), redirect_stderr(stderr):
        rc = main(ARGV + ["--json", "--out", str(out)])
    assert rc == 0, stderr.getvalue()
    return json.loads(stdout.getvalue()), out


def _params(preset, speed):
    return dict(preset.params(), **{"unbalance0.magnitude": 0.0, "speed": speed})


def test_the_cycles_start_at_the_reference_motions_hopf_point(run, preset):
    out, _ = run
    setup = preset.build(_params(preset, 200.0))
    (hopf,) = reference_hopf_points(setup.reference, 200.0, 210.0).points
    assert out["hopf"]["speed"] == pytest.approx(hopf.speed, rel=1e-12)
    assert out["hopf"]["frequency"] == pytest.approx(hopf.frequency, rel=1e-12)
    first = out["hopf"]["first_cycle"]
    assert first["period"] == pytest.approx(2 * np.pi / hopf.frequency, rel=1e-6)
    assert abs(first["speed"] / hopf.speed - 1) < 1e-6 and out["start"] == first["speed"]
    assert out["start_source"] == "--from-hopf" and out["method"] == "harmonic-balance" and out["harmonics"] == 8


def test_supercritical_stable_cycles_from_the_onset_to_the_range_top(run):
    out, _ = run
    (br,) = out["branches"]
    speed, amp = np.array(br["speed"]), np.array(br["amplitude"])
    assert out["hopf"]["criticality"] == "supercritical" and speed[0] > out["hopf"]["speed"]
    assert br["stops"][0] == "start" and br["stops"][1].startswith("box edge")
    assert speed[-1] == pytest.approx(210.0, rel=1e-12) and np.all(np.diff(speed) > 0)
    assert np.all(np.diff(amp) > 0) and all(br["stable"]) and not out["bifurcations"]
    assert max(br["time_residual"]) < 1e-3 and br["n_points"] == speed.size
    assert len(br["state_at_phase_0"]) == speed.size


def test_each_cycle_is_the_integrators_orbit(run, preset):
    """Harmonic balance against the integrator: from a cycle's state at phase 0, one
    period of `rotorjax.simulate` comes back to it, and node 2's largest radius over
    that period is the command's amplitude (the middle of the branch and the range's
    top; to 1e-4 of the whirl's own size, the radius above the first cycle's)."""
    out, _ = run
    (br,) = out["branches"]
    scene = preset.build(_params(preset, 200.0)).scene
    amp = np.array(br["amplitude"])
    for i in (len(br["speed"]) // 2, len(br["speed"]) - 1):
        y0, T = jnp.asarray(br["state_at_phase_0"][i]), br["period"][i]
        res = rotorjax.simulate(_at(scene, br["speed"][i]), y0, (0.0, T), saveat=jnp.linspace(0.0, T, 2001),
                                rtol=1e-10, atol=1e-14, solver="dopri8")
        assert int(res.code) == 0
        assert np.max(np.abs(np.asarray(res.ys)[-1] - np.asarray(y0))) < 1e-6 * np.max(np.abs(y0))
        radius = np.max(np.hypot(np.asarray(res.outputs["node_x"])[:, 2], np.asarray(res.outputs["node_y"])[:, 2]))
        assert abs(radius - amp[i]) < 1e-4 * (amp[i] - amp[0]), i     # measured 2.5e-5, 3.3e-5


def _at(scene, speed):
    import equinox as eqx

    return eqx.tree_at(lambda s: s.speed.constant, scene, jnp.float64(speed))


def test_the_docs_state_it(run):
    """docs/cli.md's `--from-hopf` paragraph: its command is this run's, and the onset,
    its criticality and the radii it states are this run's, to the digits stated."""
    out, _ = run
    cli = re.sub(r"\s+", " ", documentation("docs/cli.md"))
    assert DOCS_COMMAND in cli
    m = re.search(r"the onset at ([\d.]+) rad/s is (\w+): stable cycles grow above it, node 2's largest radius "
                  r"\(static sag included\) from ([\d.]+) mm to ([\d.]+) mm at ([\d.]+) rad/s", cli)
    assert m, "docs/cli.md no longer states the journal rig's cycles"
    (br,) = out["branches"]
    assert float(m[1]) == round(out["hopf"]["speed"], 2) and m[2] == out["hopf"]["criticality"]
    assert all(br["stable"])
    assert (float(m[3]), float(m[4])) == (round(1e3 * br["amplitude"][0], 3), round(1e3 * br["amplitude"][-1], 3))
    assert float(m[5]) == round(br["speed"][-1], 2)


def test_files_are_written(run):
    out, d = run
    for f in out["files"].values():
        assert (d / f.split("/")[-1]).exists()
