"""Lateral (4-dof) reference numbers from ROSS 2.3.0 for `test_ross_suite.py`, where the
numbers typed in ROSS's tests cannot be used as they are.

Run with an interpreter that has ROSS 2.3.0 (e.g. `/tmp/rossenv/bin/python
tests/validation/ross_suite_reference.py`); it rewrites `data/ross_suite.json`.
"""

import json
import os
import warnings

import numpy as np


def compute():
    warnings.filterwarnings("ignore")
    import ross as rs
    from ross.materials import steel
    from ross.rotor_assembly import convert_6dof_to_4dof

    out = {"ross_version": rs.__version__}

    def rotor3(n=6, kx=1e6, ky=0.8e6, c=0.0):
        sh = [rs.ShaftElement(1.5 / n, 0, 0.05, material=steel, shear_effects=True, rotary_inertia=True,
                              gyroscopic=True) for _ in range(n)]
        disks = [rs.DiskElement.from_geometry(n // 3, steel, 0.07, 0.05, 0.28),
                 rs.DiskElement.from_geometry(2 * n // 3, steel, 0.07, 0.05, 0.35)]
        brg = [rs.BearingElement(0, kxx=kx, kyy=ky, cxx=c, cyy=c), rs.BearingElement(n, kxx=kx, kyy=ky, cxx=c, cyy=c)]
        return rs.Rotor(sh, disks, brg)

    # test_mesh_convergence: the 96-element rotor3 (ROSS's refinement), full eigensolver, 4 dof
    r96 = convert_6dof_to_4dof(rotor3(96))
    out["mesh_convergence"] = {"wn0_96_elements": float(np.sort(r96.run_modal(0, sparse=False).wn)[0])}

    # test_bearing_seal_element.py::test_plot: ROSS's coefficient curve of bearing0 (kxx, cxx)
    kxx = [8.5e07, 1.1e08, 1.3e08, 1.6e08, 1.8e08, 2.0e08, 2.3e08, 2.5e08, 2.6e08]
    kyy = [9.2e07, 1.1e08, 1.4e08, 1.6e08, 1.9e08, 2.1e08, 2.3e08, 2.5e08, 2.6e08]
    cxx = [226837, 211247, 197996, 185523, 174610, 163697, 153563, 144209, 137973]
    cyy = [235837, 211247, 197996, 185523, 174610, 163697, 153563, 144209, 137973]
    wb = [314.2, 418.9, 523.6, 628.3, 733.0, 837.8, 942.5, 1047.2, 1151.9]
    b0 = rs.BearingElement(4, kxx=kxx, kyy=kyy, cxx=cxx, cyy=cyy, frequency=wb)
    w = np.linspace(314.2, 1151.9, 30)
    out["bearing0"] = {"speeds": w.tolist(), "kxx": b0.kxx_interpolated(w).tolist(),
                       "cxx": b0.cxx_interpolated(w).tolist()}

    # test_bearing_len_2 / _3: interp1d (linear, quadratic) between the table's speeds
    f2, f3 = [115.19, 345.575], [115.19, 345.575, 691.15]
    b2 = rs.BearingElement(n=0, kxx=[481, 4810], cxx=[3.13, 10.81], kyy=[481, 4810], kxy=[194, 2078],
                           kyx=[-194, -2078], cyy=[3.13, 10.81], cxy=[0.276, 0.69], cyx=[-0.276, -0.69],
                           frequency=f2)
    b3 = rs.BearingElement(n=0, kxx=[481, 4810, 18810], cxx=[3.13, 10.81, 22.99], kyy=[481, 4810, 18810],
                           kxy=[194, 2078, 8776], kyx=[-194, -2078, -8776], cyy=[3.13, 10.81, 22.99],
                           cxy=[0.276, 0.69, 1.19], cyx=[-0.276, -0.69, -1.19], frequency=f3)
    w2, w3 = np.linspace(115.19, 345.575, 7), np.linspace(115.19, 691.15, 9)
    out["bearing_len_2"] = {"speeds": w2.tolist(),
                            **{c: getattr(b2, f"{c}_interpolated")(w2).tolist() for c in ("kxx", "kxy", "kyx", "cxy")}}
    out["bearing_len_3"] = {"speeds": w3.tolist(),
                            **{c: getattr(b3, f"{c}_interpolated")(w3).tolist() for c in ("kxx", "kxy", "kyx", "cxx")}}

    # test_run_critical_speed: rotor5 and rotor6 on the 4-dof model with a tight Newton tolerance
    def rotor5(disk_nodes):
        sh = [rs.ShaftElement(0.25, 0, 0.05, material=steel, shear_effects=True, rotary_inertia=True,
                              gyroscopic=True) for _ in range(10)]
        disks = [rs.DiskElement.from_geometry(disk_nodes[0], steel, 0.07, 0.05, 0.28),
                 rs.DiskElement.from_geometry(disk_nodes[1], steel, 0.07, 0.05, 0.35)]
        brg = [rs.BearingElement(2, kxx=1e6, kyy=1e6, cxx=0), rs.BearingElement(8, kxx=1e6, kyy=1e6, cxx=0)]
        return rs.Rotor(sh, disks, brg)

    out["critical_speeds_4dof"] = {}
    for name, nodes in (("rotor5", (4, 6)), ("rotor6", (5, 10))):
        res = convert_6dof_to_4dof(rotor5(nodes)).run_critical_speed(num_modes=12, rtol=1e-12)
        out["critical_speeds_4dof"][name] = [float(v) for v in np.sort(res._wn)[:6]]
    return out


if __name__ == "__main__":
    data = compute()
    path = os.path.join(os.path.dirname(__file__), "data", "ross_suite.json")
    os.makedirs(os.path.dirname(path), exist_ok=True)
    with open(path, "w") as f:
        json.dump(data, f, indent=1)
    print(json.dumps(data, indent=1)[:3000])
