"""The rotor drawn: `layout(scene)` (what is where, as numbers) and `rotor(scene, ax=)`
(the drawing of it).

A shaft model (a rotor file's or a preset's finite-element rotor, reduced or not) is
drawn in its side view to scale along each axis (the radial axis magnified, as long
shafts need): each element's outline (a taper as it is), its bore, its material's
colour; the disks (their diameter and width those of the solid disk with the disk's
mass and inertias: `Ip = m r^2 / 2`, `Id = m r^2 / 4 + m w^2 / 12`); point masses;
bearings and seals under and over their nodes, pedestals under their bearings; the
nodes held fixed (a cantilever's clamp); every other component at its node, named by
its rotor-file table (fluid films, limiters, probes, unbalances, ...); the node
numbers. The other scenes are drawn as what they
are: a planar rotor (models 000, 001) in its end view (the disk, its eccentricity,
the supports' springs, the balls' race), the balancing machine's rigid rotor on its
two supports with the correction planes, the modal shaft (model 003) pinned at its
ends with its disk."""

import numpy as np

from ..models import AutoBalancer, BalancingScene, ModalBalancerRotor, RigidRotor, RotorScene, Scene, Supports
from ..models._contract import AbstractShaftModel
from ..models._registry import TABLES

#: colours of the materials, in the order they first appear along the shaft
MATERIAL_COLOURS = ("#8c9aa6", "#c9a66b", "#7fa37a", "#b57f7f", "#8d7fb5", "#6fa0b5")


def _table_entry(component):
    """`(table name, node or None)` of a component, as its rotor-file table writes it
    (a component without a table: its class's name, no node)."""
    for table in TABLES:
        if isinstance(component, table.builds):
            node = table.to_table(component).get("node")
            return table.name, None if node is None else int(node)
    return type(component).__name__, None


def _shaft_layout(scene):
    shaft = scene.full_rotor
    L = np.asarray(shaft.lengths, dtype=float)
    nodes = np.concatenate([[0.0], np.cumsum(L)])
    n_el = len(L)

    def pairs(d):
        d = np.broadcast_to(np.asarray(d, dtype=float), (n_el,) if np.ndim(d) < 2 else (n_el, 2))
        return np.stack([d, d], axis=1) if d.ndim == 1 else d

    od, bore = pairs(shaft.d_out), pairs(shaft.d_in)
    constants = np.stack([np.broadcast_to(np.asarray(v, dtype=float), (n_el,)) for v in (shaft.E, shaft.G, shaft.rho)],
                         axis=1)
    materials, which = [], []
    for row in constants:
        hit = [i for i, m in enumerate(materials) if np.array_equal(m, row)]
        if not hit:
            materials.append(row)
        which.append(hit[0] if hit else len(materials) - 1)
    # a linear taper's exact volume: the mean of d^2 along the element is (a^2 + a b + b^2) / 3
    mean_sq = lambda d: (d[:, 0]**2 + d[:, 0] * d[:, 1] + d[:, 1]**2) / 3   # noqa: E731
    shaft_mass = float(np.sum(constants[:, 2] * np.pi / 4 * (mean_sq(od) - mean_sq(bore)) * L))
    disks = []
    for node, (m, Id, Ip) in zip(shaft.disk_nodes, np.asarray(shaft.disk_params, dtype=float)):
        r = np.sqrt(2 * Ip / m) if Ip > 0 else 0.0
        width = np.sqrt(max(12 * (Id - m * r**2 / 4) / m, 0.0))
        disks.append({"node": int(node), "x": float(nodes[node]), "m": float(m), "Id": float(Id), "Ip": float(Ip),
                      "diameter": float(2 * r), "width": float(width)})
    masses = [{"node": int(n), "x": float(nodes[n]), "mx": float(p[0]), "my": float(p[1])}
              for n, p in zip(shaft.point_mass_nodes, np.asarray(shaft.point_mass_params, dtype=float))]
    bearings = [{"index": i, "node": int(n), "x": float(nodes[n]), "kind": kind}
                for i, (n, kind) in enumerate(zip(shaft.bearing_nodes, shaft.bearing_kinds))]
    supports = [{"bearing": int(b), "m": float(p[0])}
                for b, p in zip(shaft.support_bearings, np.asarray(shaft.support_params, dtype=float))]
    held = {}
    for index in shaft.fixed_dofs:      # global dof indices, 4 per node
        held.setdefault(int(index) // 4, []).append(("x", "y", "sx", "sy")[int(index) % 4])
    fixed = [{"node": n, "x": float(nodes[n]), "dofs": dofs} for n, dofs in sorted(held.items())]
    parts = []
    for c in scene.components if isinstance(scene, RotorScene) else ():
        table, node = _table_entry(c)
        parts.append({"table": table, "node": node, "x": None if node is None else float(nodes[node])})
    return {"kind": "shaft", "theory": shaft.theory, "length": float(nodes[-1]), "nodes": nodes.tolist(),
            "elements": [{"x": [float(nodes[i]), float(nodes[i + 1])], "od": od[i].tolist(), "id": bore[i].tolist(),
                          "material": which[i]} for i in range(n_el)],
            "materials": [{"E": float(E), "G": float(G), "rho": float(rho)} for E, G, rho in materials],
            "disks": disks, "point_masses": masses, "bearings": bearings, "supports": supports, "fixed": fixed,
            "components": parts,
            "mass": shaft_mass + sum(d["m"] for d in disks) + sum(p["mx"] for p in masses)}


def layout(scene) -> dict:
    """What `rotor` draws, as numbers: for a shaft model (`kind` "shaft") the node
    positions (m), the elements (ends, outer and inner diameters at each end, material
    index), the materials (`E`, `G`, `rho`), the disks (node, position, mass, inertias,
    and the solid disk's diameter and width), point masses, bearings and seals, pedestals,
    the other components with their table and node, the total mass (shaft, disks and
    point masses, kg); for the other scenes their kind and parameters."""
    if isinstance(scene, AbstractShaftModel):
        return _shaft_layout(scene)
    if isinstance(scene, BalancingScene):
        m = scene.machine
        return {"kind": "machine", "span": float(m.l), "m": float(m.m), "I": float(m.I),
                "supports": [{"x": 0.0, "k": float(m.k1), "c": float(m.c1)}, {"x": float(m.l), "k": float(m.k2),
                                                                             "c": float(m.c2)}],
                "planes": np.asarray(scene.planes, dtype=float).tolist()}
    if isinstance(scene, ModalBalancerRotor):
        s = scene.shaft
        return {"kind": "modal", "z0": float(s.z0), "m": float(s.m), "n_modes": int(s.n_modes),
                "balls": int(np.size(scene.ball_mass)),
                "ball_radius": np.asarray(scene.ball_radius, dtype=float).ravel().tolist()}
    if isinstance(scene, Scene) and isinstance(scene.rotor, RigidRotor):
        rotor = scene.rotor
        out = {"kind": "planar", "mass": float(rotor.mass), "eccentricity": float(rotor.eccentricity),
               "phase": float(rotor.phase), "supports": None, "race": None, "balls": 0}
        for c in scene.components:
            if isinstance(c, Supports):
                out["supports"] = {"kx": float(c.kx), "ky": float(c.ky), "cx": float(c.cx), "cy": float(c.cy)}
            if isinstance(c, AutoBalancer):
                out["race"] = {"r1": float(c.race.r1), "r2": float(c.race.r2),
                               "center": np.asarray(c.race.center, dtype=float).tolist()}
                out["balls"] = int(np.size(c.mass))
        return out
    raise TypeError(f"rotorjax.plot.rotor: cannot draw a {type(scene).__name__}")


def rotor(scene, *, ax=None, title="", labels=True):
    """Draw `scene` (see the module) on `ax` (or a new figure); returns the `Figure`.
    `labels`: the node numbers and the parts' names."""
    from . import _finish, _on_axes

    lay = layout(scene)
    fig, ax, own = _on_axes(ax, (10, 4.2) if lay["kind"] in ("shaft", "machine", "modal") else (6, 6))
    {"shaft": _draw_shaft, "machine": _draw_machine, "modal": _draw_modal, "planar": _draw_planar}[lay["kind"]](
        ax, lay, labels)
    ax.set_title(title or {"shaft": f"rotor: {len(lay.get('elements', ()))} elements, {lay.get('length', 0):.4g} m, "
                                    f"{lay.get('mass', 0):.4g} kg"}.get(lay["kind"], ""), fontsize=10)
    return _finish(fig, (), legend=False, layout=own)


def _draw_shaft(ax, lay, labels):
    from matplotlib.patches import Polygon, Rectangle

    r_max = max(max(e["od"]) for e in lay["elements"]) / 2
    disk_r = max([d["diameter"] / 2 for d in lay["disks"]] + [r_max])
    for e in lay["elements"]:
        (x0, x1), (a, b), (c, d) = e["x"], np.array(e["od"]) / 2, np.array(e["id"]) / 2
        colour = MATERIAL_COLOURS[e["material"] % len(MATERIAL_COLOURS)]
        ax.add_patch(Polygon([(x0, -a), (x1, -b), (x1, b), (x0, a)], closed=True, fc=colour, ec="#333", lw=0.8))
        if c > 0 or d > 0:
            ax.add_patch(Polygon([(x0, -c), (x1, -d), (x1, d), (x0, c)], closed=True, fc="white", ec="#555",
                                 lw=0.5, ls="--"))
    span = lay["length"]
    for d in lay["disks"]:
        w = max(d["width"], 0.004 * span)
        r = d["diameter"] / 2 or 1.5 * r_max
        ax.add_patch(Rectangle((d["x"] - w / 2, -r), w, 2 * r, fc="#b03a2e", ec="#5a1d17", lw=0.8, alpha=0.85))
    for p in lay["point_masses"]:
        ax.plot(p["x"], 0, "o", ms=8, mfc="#e0a060", mec="#6b4a25")
    size, base = 0.35 * disk_r, 1.15 * disk_r
    carried = {s["bearing"] for s in lay["supports"]}
    for b in lay["bearings"]:
        colour = "#2e5e8c" if b["kind"] == "bearing" else "#8c2e7a"
        for side in (-1, 1):
            y0 = side * max(r_max, 0.3 * disk_r)
            tri = [(b["x"], y0), (b["x"] - 0.012 * span, y0 + side * size), (b["x"] + 0.012 * span, y0 + side * size)]
            ax.add_patch(Polygon(tri, closed=True, fc=colour, ec="#222", lw=0.6, alpha=0.9))
        if b["index"] in carried:
            ax.add_patch(Rectangle((b["x"] - 0.02 * span, -(r_max + size) - 0.5 * size), 0.04 * span, 0.5 * size,
                                   fc="#999", ec="#222", lw=0.6, hatch="//"))
        if labels:
            ax.annotate(f"{b['kind'][0].upper()}{b['index']}", (b["x"], -base - 0.35 * size), ha="center",
                        va="top", fontsize=8, color=colour)
    for f in lay["fixed"]:
        side = -1 if f["x"] < span / 2 else 1
        ax.add_patch(Rectangle((f["x"] + (0 if side > 0 else -0.025 * span), -1.5 * r_max), 0.025 * span,
                               3 * r_max, fc="#bbb", ec="#222", lw=0.6, hatch="///"))
        if labels:
            ax.annotate("fixed " + ",".join(f["dofs"]), (f["x"], -1.6 * r_max), ha="center", va="top", fontsize=7)
    stacked = {}
    for part in lay["components"]:
        if part["x"] is None:
            continue
        k = stacked[part["node"]] = stacked.get(part["node"], 0) + 1
        y = base + 0.45 * size * k
        ax.plot(part["x"], y, "v", ms=6, color="#444")
        if labels:
            ax.annotate(part["table"], (part["x"], y), xytext=(4, 0), textcoords="offset points", fontsize=7,
                        va="center")
    if labels:
        for i, x in enumerate(lay["nodes"]):
            ax.annotate(str(i), (x, 0), xytext=(0, -2), textcoords="offset points", ha="center", va="top",
                        fontsize=7, color="#222")
    for i, m in enumerate(lay["materials"]):
        ax.plot([], [], "s", ms=9, color=MATERIAL_COLOURS[i % len(MATERIAL_COLOURS)],
                label=f"E {m['E'] / 1e9:.4g} GPa, rho {m['rho']:.5g} kg/m^3")
    ax.legend(fontsize=7, loc="lower right")
    ax.set_xlim(-0.04 * span, 1.04 * span)
    top = base + 0.45 * size * (1 + max(stacked.values(), default=0)) + 0.2 * disk_r
    ax.set_ylim(-top, top)
    ax.set_xlabel("axial position (m)")
    ax.set_ylabel("radius (m, magnified)")


def _spring(ax, a, b, n=6, width=0.04, **kw):
    a, b = np.asarray(a, dtype=float), np.asarray(b, dtype=float)
    t = np.linspace(0, 1, 2 * n + 3)
    d = b - a
    normal = np.array([-d[1], d[0]]) / np.linalg.norm(d)
    zig = np.r_[0, 0, [(-1) ** i for i in range(2 * n - 1)], 0, 0][: len(t)] * width
    pts = a + np.outer(t, d) + np.outer(zig, normal)
    ax.plot(pts[:, 0], pts[:, 1], **kw)


def _draw_machine(ax, lay, labels):
    from matplotlib.patches import Rectangle

    span = lay["span"]
    planes = lay["planes"]
    lo, hi = min([0.0] + planes) - 0.15 * span, max([span] + planes) + 0.15 * span
    ax.add_patch(Rectangle((lo, -0.04 * span), hi - lo, 0.08 * span, fc="#8c9aa6", ec="#333"))
    for i, s in enumerate(lay["supports"]):
        _spring(ax, (s["x"], -0.04 * span), (s["x"], -0.3 * span), width=0.02 * span, color="#2e5e8c")
        ax.plot([s["x"] - 0.04 * span, s["x"] + 0.04 * span], [-0.3 * span] * 2, color="#222", lw=2)
        if labels:
            ax.annotate(f"support {i + 1}: k {s['k']:.3g} N/m", (s["x"], -0.33 * span), ha="center", va="top",
                        fontsize=8)
    for j, p in enumerate(planes):
        ax.plot([p, p], [-0.1 * span, 0.1 * span], "--", color="#b03a2e")
        if labels:
            ax.annotate(f"plane {j + 1}", (p, 0.11 * span), ha="center", fontsize=8, color="#b03a2e")
    ax.set_xlim(lo - 0.05 * span, hi + 0.05 * span)
    ax.set_ylim(-0.45 * span, 0.25 * span)
    ax.set_aspect("equal")
    ax.set_xlabel("axial position from support 1 (m)")


def _draw_modal(ax, lay, labels):
    from matplotlib.patches import Rectangle

    ax.plot([0, 1], [0, 0], color="#333", lw=3)
    for x in (0, 1):
        ax.plot(x, -0.02, "^", ms=14, color="#2e5e8c")
    ax.add_patch(Rectangle((lay["z0"] - 0.01, -0.15), 0.02, 0.3, fc="#b03a2e", ec="#5a1d17"))
    if labels:
        ax.annotate(f"disk (mass {lay['m']:.3g}) with {lay['balls']} balls", (lay["z0"], 0.17), ha="center",
                    fontsize=8)
        ax.annotate(f"pinned-pinned shaft, {lay['n_modes']} modes", (0.5, -0.12), ha="center", fontsize=8)
    ax.set_xlim(-0.08, 1.08)
    ax.set_ylim(-0.3, 0.3)
    ax.set_xlabel("axial position / span")


def _draw_planar(ax, lay, labels):
    from matplotlib.patches import Circle, Ellipse

    race = lay["race"] or {"r1": 1.0, "r2": 1.0, "center": [0.0, 0.0]}
    R = 1.6 * max(race["r1"], race["r2"])
    ax.add_patch(Circle((0, 0), R, fc="#d7dde2", ec="#333"))
    cx, cy = race["center"]
    ax.add_patch(Ellipse((cx, cy), 2 * race["r1"], 2 * race["r2"], fill=False, ec="#2e5e8c", lw=1.5))
    for k in range(lay["balls"]):
        psi = np.pi / 2 + 2 * np.pi * k / max(lay["balls"], 1)
        ax.add_patch(Circle((cx + race["r1"] * np.cos(psi), cy + race["r2"] * np.sin(psi)), 0.08 * R, fc="#444"))
    e, phi = lay["eccentricity"], lay["phase"]
    ex, ey = (0.5 * R) * np.cos(phi), (0.5 * R) * np.sin(phi)
    ax.annotate("", (ex, ey), (0, 0), arrowprops=dict(arrowstyle="->", color="#b03a2e"))
    if labels:
        ax.annotate(f"eccentricity {e:.3g}", (ex, ey), fontsize=8, color="#b03a2e")
        ax.annotate(f"race {race['r1']:.3g} x {race['r2']:.3g}, {lay['balls']} balls", (0, -0.35 * R),
                    ha="center", fontsize=8, color="#2e5e8c")
    s = lay["supports"]
    if s is not None:
        _spring(ax, (R, 0), (2 * R, 0), width=0.08 * R, color="#2e5e8c")
        _spring(ax, (0, -R), (0, -2 * R), width=0.08 * R, color="#2e5e8c")
        ax.plot([2 * R] * 2, [-0.3 * R, 0.3 * R], color="#222", lw=2)
        ax.plot([-0.3 * R, 0.3 * R], [-2 * R] * 2, color="#222", lw=2)
        if labels:
            ax.annotate(f"kx {s['kx']:.3g}, cx {s['cx']:.3g}", (1.5 * R, 0.12 * R), ha="center", fontsize=8)
            ax.annotate(f"ky {s['ky']:.3g}, cy {s['cy']:.3g}", (0.12 * R, -1.5 * R), fontsize=8)
    ax.set_xlim(-2.3 * R, 2.3 * R)
    ax.set_ylim(-2.3 * R, 2.3 * R)
    ax.set_aspect("equal")
    ax.set_xlabel("x (rotor frame, model units)")
