"""Issue 35 item 1: the rotor drawn (`rotorjax.plot.rotor`, `rotorjax.plot.rotor_layout`,
`rotorjax draw`). The layout's numbers against independent ones: the total mass
against the assembled mass matrix's rigid translation `u^T M u` (and the closed form
for ROSS's example rotor), each disk drawn as the solid disk that has its mass and
both inertias; the drawing against the layout (one outline per element at its
nodes, one rectangle per disk); every preset and shipped rotor file drawn by the
command."""

import json
import os

import jax
import matplotlib
import numpy as np
import pytest

from rotorjax import presets
from rotorjax.cli import main
from rotorjax.io import load_rotor
from rotorjax.plot import rotor, rotor_layout

matplotlib.use("Agg")

FILES = ("ross_compare.toml", "flexible_rig.toml", "rig_nonlinear.toml", "tapered_two_material.toml",
         "journal_rig.toml", "cubic_rig.toml")


def _shaft(scene):
    return scene.rotor.full_rotor if hasattr(scene.rotor, "full_rotor") else scene.rotor


@pytest.mark.parametrize("name", ["tapered_two_material.toml", "rig_nonlinear.toml"])
def test_the_mass_is_the_mass_matrix_s_rigid_translation(name):
    """`u^T M u` with `u` a unit translation of every shaft node (the shaft's elements,
    tapers and bores included, its disks and point masses; no pedestal moves) equals
    the layout's mass to 1e-12 (two materials, tapers, a bore)."""
    scene = load_rotor(name)
    shaft = _shaft(scene)
    M = np.asarray(jax.jit(lambda r: r.matrices(0.0)[0])(shaft))    # compiled: 3x faster than eager here
    u = np.zeros(M.shape[0])
    u[0:4 * shaft.n_nodes:4] = 1.0
    masses = np.asarray(shaft.bearing_mass, dtype=float)[:, 0] if len(shaft.bearing_nodes) else np.zeros(0)
    lay = rotor_layout(scene)
    assert u @ M @ u == pytest.approx(lay["mass"] + np.nansum(masses), rel=1e-12)


def test_ross_s_example_rotor_weighs_its_closed_form():
    lay = rotor_layout(load_rotor("ross_compare.toml"))
    shaft = 7810.0 * np.pi / 4 * 0.05**2 * 1.5
    assert lay["mass"] == pytest.approx(shaft + sum(d["m"] for d in lay["disks"]), rel=1e-14)
    assert lay["length"] == 1.5 and lay["nodes"] == pytest.approx(np.arange(7) * 0.25)
    assert [d["node"] for d in lay["disks"]] == [2, 4] and [b["node"] for b in lay["bearings"]] == [0, 6]


@pytest.mark.parametrize("name", FILES)
def test_each_disk_drawn_is_the_solid_disk_of_its_mass_and_inertias(name):
    """A solid disk of diameter D and width w: `Ip = m D^2 / 8`, `Id = m (D^2 / 16 + w^2
    / 12)`; a disk whose Id is below a thin disk's (`Id < Ip / 2`) is drawn thin."""
    for d in rotor_layout(load_rotor(name))["disks"]:
        assert d["m"] * d["diameter"] ** 2 / 8 == pytest.approx(d["Ip"], rel=1e-12)
        if d["Id"] >= d["Ip"] / 2:
            assert d["m"] * (d["diameter"] ** 2 / 16 + d["width"] ** 2 / 12) == pytest.approx(d["Id"], rel=1e-12)
        else:
            assert d["width"] == 0


def test_the_drawing_is_the_layout():
    """The tapered two-material rotor: an outline per element whose corners are the
    element's ends and radii (a bore drawn inside the hollow ones), a rectangle per
    disk centred on its node, the materials in the legend, the node numbers."""
    from matplotlib.patches import Polygon, Rectangle

    scene = load_rotor("tapered_two_material.toml")
    lay = rotor_layout(scene)
    ax = rotor(scene).axes[0]
    outlines = [p for p in ax.patches if isinstance(p, Polygon) and p.get_facecolor()[:3] != (1.0, 1.0, 1.0)
                and len(p.get_xy()) == 5 and p.get_xy()[0, 1] < 0 and p.get_xy()[0][0] != p.get_xy()[1][0]]
    assert len(outlines) == len(lay["elements"])
    for patch, e in zip(outlines, lay["elements"]):
        xy = patch.get_xy()[:4]
        np.testing.assert_allclose(xy[:, 0], [e["x"][0], e["x"][1], e["x"][1], e["x"][0]], rtol=1e-12)
        np.testing.assert_allclose(xy[:, 1], [-e["od"][0] / 2, -e["od"][1] / 2, e["od"][1] / 2, e["od"][0] / 2])
    bores = [e for e in lay["elements"] if max(e["id"]) > 0]
    white = [p for p in ax.patches if isinstance(p, Polygon) and p.get_facecolor()[:3] == (1.0, 1.0, 1.0)]
    assert len(white) == len(bores) > 0
    rects = [p for p in ax.patches if isinstance(p, Rectangle) and p.get_facecolor()[0] > 0.6]
    assert len(rects) == len(lay["disks"])
    for r, d in zip(rects, lay["disks"]):
        assert r.get_x() + r.get_width() / 2 == pytest.approx(d["x"])
    assert len(ax.get_legend().get_texts()) == len(lay["materials"]) == 2
    assert [t.get_text() for t in ax.texts if t.get_text().isdigit()] == [str(i) for i in range(len(lay["nodes"]))]


TARGETS = [*presets.PRESETS, "journal_rig.toml", "cubic_rig.toml"]


@pytest.mark.parametrize("target", TARGETS)
def test_every_preset_and_rotor_file_is_drawn(target, tmp_path, capsys):
    assert main(["draw", target, "--out", str(tmp_path), "--json"]) == 0
    out = json.loads(capsys.readouterr().out)
    assert os.path.getsize(out["files"]["plot"]) > 10_000
    assert json.load(open(out["files"]["json"]))["layout"] == out["layout"]
    kind = out["layout"]["kind"]
    expected = {"elliptic-abb": "planar", "anisotropic-abb": "planar", "flexible-abb": "modal",
                "balancing-machine": "machine"}.get(target, "shaft")
    assert kind == expected


def test_the_summary_names_the_parts(tmp_path, capsys):
    assert main(["draw", "rig_nonlinear.toml", "--out", str(tmp_path)]) == 0
    text = capsys.readouterr().out
    assert "6 elements (timoshenko), 0.68 m" in text and "2 materials; 1 disks; 2 bearings and seals" in text
    for part in ("cubic_bearing (node 0)", "clearance_bearing (node 6)", "limiters (node 3)",
                 "auto_balancer (node 3)", "unbalance (node 3)"):
        assert part in text
    assert main(["draw", "cantilever-limiters", "--out", str(tmp_path), "--json"]) == 0
    lay = json.loads(capsys.readouterr().out)["layout"]
    assert lay["fixed"] == [{"node": 0, "x": 0.0, "dofs": ["x", "y", "sx", "sy"]}]
