"""Reference numbers from ROSS 2.3.0 for the model-building tests (`test_fe_building.py`).

Run with an interpreter that has ROSS (no rotorjax or jax needed):
`/tmp/rossenv/bin/python tests/models/ross_fe_building_reference.py` rewrites
`tests/models/data/ross_fe_building.json`:

- `elements`: ROSS `ShaftElement.M()`, `.K()`, `.G()` (12 x 12, dofs
  `x, y, z, alpha, beta, theta` per node) of tapered hollow and solid elements
  under the Timoshenko, Rayleigh and Euler-Bernoulli options;
- `rotors`: two rotors, each stated once here as plain data (the test builds
  our `FlexibleRotor` from the same data) and built in ROSS below, with the
  damped natural frequencies and logarithmic decrements of their lateral modes
  at speeds inside the bearing tables (`Rotor.run_modal(speed, sparse=False)`).
  ROSS's modes also include axial and torsional ones (6 dofs per node, uncoupled
  from bending): they are told apart by where the eigenvector lives.

  * `tapered_supported`: 8 tapered hollow elements of two materials (steel,
    Ti-6Al-4V), a disk, a point mass on the shaft (in ROSS a disk without inertia), a bearing with 4-speed tables
    of all 8 stiffness and damping coefficients at node 0, and at node 8 a
    tabulated bearing that stands on a pedestal (ROSS: a bearing with `n_link` to
    a `PointMass` node, plus a bearing from that node to ground).
  * `bearing_mass`: a cylindrical/tapered shaft on bearings with mass
    coefficients (`mxx, myy, mxy, myx`), one of them tabulated.

Tables have 4 speeds: ROSS interpolates with `UnivariateSpline` (cubic,
smoothing `s = n`), which for 4 points is the cubic through them, the same
curve as our not-a-knot spline. With more points ROSS's curve is a smoothing
spline that misses the table's own points by residuals of order 1 in the
coefficient's units (`table_5_speeds` records it).
"""

import json
import os
import warnings

import numpy as np

STEEL = {"name": "steel", "rho": 7810.0, "E": 211e9, "G_s": 81.2e9}
TITANIUM = {"name": "titanium", "rho": 4430.0, "E": 113.8e9, "Poisson": 0.342}

ELEMENTS = [
    dict(L=0.12, idl=0.02, odl=0.06, idr=0.03, odr=0.09, material=STEEL, shear_effects=True, rotary_inertia=True),
    dict(L=0.12, idl=0.02, odl=0.06, idr=0.03, odr=0.09, material=STEEL, shear_effects=False,
         rotary_inertia=False),
    dict(L=0.08, idl=0.0, odl=0.10, idr=0.0, odr=0.05, material=TITANIUM, shear_effects=True,
         rotary_inertia=True),
    dict(L=0.08, idl=0.0, odl=0.10, idr=0.0, odr=0.05, material=TITANIUM, shear_effects=False,
         rotary_inertia=True),
    dict(L=0.30, idl=0.04, odl=0.05, idr=0.01, odr=0.07, material=STEEL, shear_effects=True, rotary_inertia=True),
    dict(L=0.25, idl=0.01, odl=0.05, idr=0.01, odr=0.05, material=STEEL, shear_effects=True, rotary_inertia=True),
]

SPEEDS_TABLE = [0.0, 400.0, 800.0, 1200.0]

TAPERED_SUPPORTED = {
    "lengths": [0.10, 0.12, 0.15, 0.15, 0.12, 0.12, 0.10, 0.10],
    "d_out": [[0.05, 0.06], [0.06, 0.08], [0.08, 0.09], [0.09, 0.09], [0.09, 0.07], [0.07, 0.06],
              [0.06, 0.05], [0.05, 0.05]],
    "d_in": [[0.01, 0.01], [0.01, 0.02], [0.02, 0.02], [0.02, 0.03], [0.03, 0.02], [0.02, 0.02],
             [0.02, 0.01], [0.01, 0.01]],
    "materials": ["steel", "steel", "steel", "steel", "titanium", "titanium", "titanium", "titanium"],
    "disks": [[3, 12.0, 0.05, 0.09]],
    "point_masses": [[5, 3.5]],
    "bearings": [
        {"node": 0, "speeds": SPEEDS_TABLE,
         "kxx": [2.0e7, 2.4e7, 3.1e7, 3.5e7], "kyy": [1.5e7, 1.9e7, 2.2e7, 2.9e7],
         "kxy": [0.0, 2.0e6, 5.0e6, 6.0e6], "kyx": [0.0, -3.0e6, -4.5e6, -8.0e6],
         "cxx": [3.0e3, 2.6e3, 2.3e3, 2.2e3], "cyy": [4.0e3, 3.1e3, 2.9e3, 2.5e3],
         "cxy": [0.0, 1.0e2, 3.0e2, 2.0e2], "cyx": [0.0, 1.5e2, 1.0e2, 4.0e2]},
        {"node": 8, "speeds": SPEEDS_TABLE,
         "kxx": [1.0e7, 1.3e7, 1.5e7, 2.1e7], "kyy": [1.2e7, 1.4e7, 1.9e7, 2.0e7],
         "kxy": 0.0, "kyx": 0.0,
         "cxx": [1.5e3, 1.2e3, 1.0e3, 1.1e3], "cyy": [1.5e3, 1.4e3, 1.3e3, 1.2e3],
         "cxy": 0.0, "cyx": 0.0},
    ],
    # the pedestal under bearing 1: mass (kg), stiffness and damping to ground
    "supports": [{"bearing": 1, "m": 25.0, "kxx": 5.0e7, "kyy": 8.0e7, "cxx": 2.0e3, "cyy": 3.0e3}],
    "speeds": [200.0, 500.0, 1000.0],
    "n_modes": 8,
}

BEARING_MASS = {
    "lengths": [0.2, 0.2, 0.2, 0.2, 0.2, 0.2],
    "d_out": [[0.06, 0.06], [0.06, 0.08], [0.08, 0.08], [0.08, 0.08], [0.08, 0.06], [0.06, 0.06]],
    "d_in": [[0.0, 0.0]] * 6,
    "materials": ["steel"] * 6,
    "disks": [[2, 20.0, 0.12, 0.2], [4, 15.0, 0.08, 0.14]],
    "point_masses": [],
    "bearings": [
        {"node": 0, "kxx": 2.0e7, "kyy": 3.0e7, "kxy": 1.0e6, "kyx": -1.0e6, "cxx": 2.0e3, "cyy": 2.5e3,
         "cxy": 0.0, "cyx": 0.0, "mxx": 4.0, "myy": 6.0, "mxy": 0.5, "myx": -0.8},
        {"node": 6, "speeds": SPEEDS_TABLE,
         "kxx": [1.0e7, 1.2e7, 1.6e7, 1.7e7], "kyy": [1.1e7, 1.3e7, 1.5e7, 1.9e7], "kxy": 0.0, "kyx": 0.0,
         "cxx": [1.0e3, 1.1e3, 1.3e3, 1.2e3], "cyy": 1.0e3, "cxy": 0.0, "cyx": 0.0,
         "mxx": [2.0, 2.5, 3.5, 3.0], "myy": [1.0, 1.5, 2.0, 2.2], "mxy": 0.0, "myx": [0.0, 0.1, 0.3, 0.2]},
    ],
    "supports": [],
    "speeds": [100.0, 600.0, 1100.0],
    "n_modes": 8,
}

COEFFS = ("kxx", "kyy", "kxy", "kyx", "cxx", "cyy", "cxy", "cyx", "mxx", "myy", "mxy", "myx")


def _material(rs, spec):
    return rs.Material(**spec)


def ross_rotor(rs, data):
    """The ROSS rotor of `data` (see the module docstring)."""
    mats = {"steel": _material(rs, STEEL), "titanium": _material(rs, TITANIUM)}
    shaft = [rs.ShaftElement(L=L, idl=di[0], odl=do[0], idr=di[1], odr=do[1], material=mats[m],
                             shear_effects=True, rotary_inertia=True, gyroscopic=True)
             for L, do, di, m in zip(data["lengths"], data["d_out"], data["d_in"], data["materials"])]
    n_nodes = len(shaft) + 1
    disks = [rs.DiskElement(n=n, m=m, Id=it, Ip=ip) for n, m, it, ip in data["disks"]]
    # a mass on a shaft node: ROSS places `PointMass`es only at bearing nodes, so a
    # disk without inertia (the same lateral mass matrix)
    disks += [rs.DiskElement(n=n, m=m, Id=0.0, Ip=0.0) for n, m in data["point_masses"]]
    point_masses = []
    supported = {s["bearing"]: (j, s) for j, s in enumerate(data["supports"])}
    bearings = []
    for i, b in enumerate(data["bearings"]):
        kw = {k: b.get(k, 0.0) for k in COEFFS}
        if "speeds" in b:
            n = len(b["speeds"])
            kw = {k: (list(v) if isinstance(v, list) else [float(v)] * n) for k, v in kw.items()}
            kw["frequency"] = b["speeds"]
        if i in supported:
            j, s = supported[i]
            ped = n_nodes + j
            kw["n_link"] = ped
            point_masses.append(rs.PointMass(n=ped, mx=s["m"], my=s["m"], mz=s["m"]))
            bearings.append(rs.BearingElement(n=ped, kxx=s["kxx"], kyy=s["kyy"], cxx=s["cxx"], cyy=s["cyy"],
                                              tag=f"pedestal{j}"))
        bearings.append(rs.BearingElement(n=b["node"], tag=f"bearing{i}", **kw))
    return rs.Rotor(shaft, disks, bearings, point_mass_elements=point_masses)


def lateral_modes(rotor, speed, n_modes, n_shaft_nodes, n_pedestals):
    """ROSS's damped frequencies and log decrements of the first `n_modes`
    lateral modes (upper half-plane, ascending), and the largest share of a kept
    mode's eigenvector outside the lateral dofs (a check that they separate)."""
    modal = rotor.run_modal(speed=speed, num_modes=2 * rotor.ndof, sparse=False)
    ev, vec = modal.evalues, modal.evectors
    nd = rotor.ndof
    lateral = np.zeros(nd, dtype=bool)
    for n in range(n_shaft_nodes):
        lateral[[6 * n, 6 * n + 1, 6 * n + 3, 6 * n + 4]] = True
    for j in range(n_pedestals):
        p = 6 * n_shaft_nodes + 3 * j
        lateral[[p, p + 1]] = True
    wd, logdec, leak = [], [], 0.0
    for k in range(len(ev)):
        if ev[k].imag <= 0:
            continue
        v = np.abs(vec[:nd, k]) ** 2
        share = v[lateral].sum() / v.sum()
        if share < 0.5:
            continue
        leak = max(leak, 1 - share)
        wd.append(float(modal.wd[k]) if k < len(modal.wd) else float(ev[k].imag))
        logdec.append(float(modal.log_dec[k]) if k < len(modal.log_dec) else None)
    order = np.argsort(wd)[:n_modes]
    return [wd[i] for i in order], [logdec[i] for i in order], leak


def compute():
    warnings.filterwarnings("ignore")
    import ross as rs

    out = {"ross_version": rs.__version__, "elements": [], "rotors": {}}
    for spec in ELEMENTS:
        el = rs.ShaftElement(L=spec["L"], idl=spec["idl"], odl=spec["odl"], idr=spec["idr"], odr=spec["odr"],
                             material=_material(rs, spec["material"]), shear_effects=spec["shear_effects"],
                             rotary_inertia=spec["rotary_inertia"], gyroscopic=True)
        mat = el.material
        out["elements"].append({
            **{k: spec[k] for k in ("L", "idl", "odl", "idr", "odr", "shear_effects", "rotary_inertia")},
            "E": mat.E, "G": mat.G_s, "rho": mat.rho, "nu": mat.Poisson,
            "kappa": getattr(el, "kappa", None), "phi": float(el.phi),
            "M": el.M().tolist(), "K": el.K().tolist(), "G_matrix": el.G().tolist()})
    for name, data in (("tapered_supported", TAPERED_SUPPORTED), ("bearing_mass", BEARING_MASS)):
        rotor = ross_rotor(rs, data)
        wd, logdec, leaks = [], [], []
        for s in data["speeds"]:
            f, d, leak = lateral_modes(rotor, s, data["n_modes"], len(data["lengths"]) + 1, len(data["supports"]))
            wd.append(f)
            logdec.append(d)
            leaks.append(leak)
        out["rotors"][name] = {"data": data, "damped_frequencies": wd, "log_dec": logdec,
                               "largest_nonlateral_share": max(leaks),
                               "materials": {"steel": {"E": STEEL["E"], "G": STEEL["G_s"], "rho": STEEL["rho"],
                                                       "nu": rs.Material(**STEEL).Poisson},
                                             "titanium": {"E": TITANIUM["E"], "G": rs.Material(**TITANIUM).G_s,
                                                          "rho": TITANIUM["rho"], "nu": TITANIUM["Poisson"]}}}
    # a 5-speed table: ROSS's smoothing spline (s = 5, in the coefficient's units)
    # misses its own points; ours interpolates them
    speeds, table = [0.0, 100.0, 250.0, 400.0, 700.0], {"cxx": [100.0, 120.0, 90.0, 150.0, 130.0],
                                                          "mxx": [2.0, 2.5, 3.5, 3.0, 4.0]}
    b = rs.BearingElement(n=0, kxx=1e7, cxx=table["cxx"], mxx=table["mxx"], frequency=speeds)
    out["table_5_speeds"] = {"speeds": speeds, "values": table,
                             "ross_at_speeds": {k: getattr(b, f"{k}_interpolated")(speeds).tolist() for k in table}}
    return out


if __name__ == "__main__":
    data = compute()
    path = os.path.join(os.path.dirname(__file__), "data", "ross_fe_building.json")
    os.makedirs(os.path.dirname(path), exist_ok=True)
    with open(path, "w") as f:
        json.dump(data, f, indent=1)
    for name, r in data["rotors"].items():
        print(name, np.round(r["damped_frequencies"], 3).tolist(), r["largest_nonlateral_share"])
