"""Reference numbers from ROSS 2.3.0 for the shipped rotor file
`rotorjax/rotors/tapered_two_material.toml` (tapered elements, steel and titanium,
speed-dependent bearings): damped natural frequencies and log decrements of the
lateral modes at three speeds inside the bearings' table.

ROSS interpolates a bearing's table with `scipy.interpolate.UnivariateSpline` at its
default smoothing `s = len(speeds)` (in the coefficient's own units), so its curve
misses the tabulated values by up to ~sqrt(s) (N s/m on damping of ~1e3 N s/m:
1e-3 relative). rotorjax's spline passes through the table. The reference is
computed twice: "ross" (ROSS as shipped) and "ross_interpolating" (the same ROSS
model with each coefficient's spline replaced by scipy's not-a-knot
`CubicSpline` through the table: what the table says), and ROSS's spline values at
the table's own speeds are stored to show the smoothing.

Run with an interpreter that has ROSS (and rotorjax, for the built-in material
constants): `python tests/validation/ross_tapered_reference.py` rewrites
`tests/validation/data/ross_tapered.json`. ROSS 2.3.0 has 6 dofs per node
(x, y, z, alpha, beta, theta); its axial and torsional modes are dropped by their
shapes (lateral share of the eigenvector < 0.99).
"""

import json
import pathlib
import tomllib
import warnings

import numpy as np

HERE = pathlib.Path(__file__).parent
FILE = HERE.parents[1] / "rotorjax" / "rotors" / "tapered_two_material.toml"
SPEEDS = [100.0, 400.0, 850.0]


def _pair(v):
    return (v, v) if not isinstance(v, list) else tuple(v)


def compute():
    warnings.filterwarnings("ignore")
    import ross as rs

    from rotorjax.models._materials import MATERIALS

    doc = tomllib.loads(FILE.read_text())
    mats = {}
    for name in {s["material"] for s in doc["shaft"]}:
        m = MATERIALS[name]
        mats[name] = rs.Material(name=f"rj_{name}", rho=m.rho, E=m.E, G_s=m.G)
    shaft = []
    for s in doc["shaft"]:
        odl, odr = _pair(s["od"])
        idl, idr = _pair(s.get("id", 0.0))
        shaft.append(rs.ShaftElement(s["L"], idl, odl, idr=idr, odr=odr, material=mats[s["material"]],
                                     shear_effects=True, rotary_inertia=True, gyroscopic=True))
    disks = [rs.DiskElement(n=d["node"], m=d["m"], Id=d["Id"], Ip=d["Ip"]) for d in doc["disk"]]
    bearings = [rs.BearingElement(n=b["node"], kxx=b["kxx"], kyy=b["kyy"], cxx=b["cxx"], cyy=b["cyy"],
                                  frequency=b["speeds"]) for b in doc["bearing"]]
    out = {"ross_version": rs.__version__, "speeds": SPEEDS}
    b0 = bearings[0]
    out["ross_spline_at_table"] = {k: [float(getattr(b0, f"{k}_interpolated")(w)) for w in doc["bearing"][0]["speeds"]]
                                   for k in ("kxx", "cxx")}
    out["table"] = {k: doc["bearing"][0][k] for k in ("speeds", "kxx", "cxx")}
    out["ross"] = lateral_modes(rs, shaft, disks, bearings, SPEEDS)
    from scipy.interpolate import CubicSpline

    exact = []
    for b, spec in zip(bearings, doc["bearing"]):
        for k in ("kxx", "kyy", "cxx", "cyy"):
            setattr(b, f"{k}_interpolated", CubicSpline(spec["speeds"], spec[k]))
        exact.append(b)
    out["ross_interpolating"] = lateral_modes(rs, shaft, disks, exact, SPEEDS)
    return out


def lateral_modes(rs, shaft, disks, bearings, speeds, count=8):
    """ROSS's rotor of these elements: its `count` lowest lateral damped natural
    frequencies and log decrements at each speed (axial and torsional modes dropped by
    their shapes; `tests/models/ross_seal_reference.py` uses it too)."""
    rotor = rs.Rotor(shaft, disks, bearings)
    out = {"wd": [], "log_dec": []}
    n = rotor.ndof
    lateral = np.array([i % 6 in (0, 1, 3, 4) for i in range(n)])
    for w in speeds:
        modal = rotor.run_modal(speed=w, num_modes=2 * n, sparse=False)
        vec = np.asarray(modal.evectors)[:n, :len(modal.wd)]
        share = np.linalg.norm(vec[lateral], axis=0) / np.linalg.norm(vec, axis=0)
        keep = (share > 0.99) & (np.asarray(modal.wd) > 1.0)
        wd, ld = np.asarray(modal.wd)[keep], np.asarray(modal.log_dec)[keep]
        order = np.argsort(wd)[:count]
        out["wd"].append(wd[order].tolist())
        out["log_dec"].append(ld[order].tolist())
    return out


if __name__ == "__main__":
    data = compute()
    path = HERE / "data" / "ross_tapered.json"
    path.write_text(json.dumps(data, indent=1))
    print("wrote", path)
    print(json.dumps(data)[:800])
