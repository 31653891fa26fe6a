"""Reference numbers from ROSS 2.3.0 for the static analysis and the damped modes.

Run with an interpreter that has ROSS (no rotorjax or JAX needed):
`/tmp/rossenv/bin/python tests/flexible/ross_static_reference.py` rewrites
`tests/flexible/data/ross_static.json` (`run_static` on ROSS's `rotor_example` and
on a rotor with an overhung disk) and `tests/flexible/data/ross_modal.json`
(`run_modal` on `rotor_example`, the same with damped bearings, and a rotor with a
gyroscopically strong overhung disk). `tests/flexible/test_static.py` and
`tests/flexible/test_modes_tracking.py` compare against them.

ROSS 2.3.0 has 6 dofs per node (x, y, z, alpha, beta, theta); its axial and
torsional modes are dropped here (rotorjax's elements are lateral only).
"""

import json
import os
import warnings

import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
G = 9.8065   # ROSS's run_static gravity


def _steel():
    import ross as rs

    return rs.rotor_example().shaft_elements[0].material


def _rotor(spec):
    """A ROSS rotor from the plain description the tests rebuild in rotorjax."""
    import ross as rs

    steel = _steel()
    shaft = [rs.ShaftElement(L, 0.0, spec["d_out"], material=steel, shear_effects=True, rotary_inertia=True,
                             gyroscopic=True) for L in spec["lengths"]]
    disks = [rs.DiskElement(n=n, m=m, Id=it, Ip=ip) for n, m, it, ip in spec["disks"]]
    bearings = [rs.BearingElement(n=n, kxx=kxx, kyy=kyy, cxx=cxx, cyy=cyy) for n, kxx, kyy, cxx, cyy in
                spec["bearings"]]
    return rs.Rotor(shaft, disks, bearings)


def _example_spec(c=0.0):
    import ross as rs

    base = rs.rotor_example()
    steel = base.shaft_elements[0].material
    return {"lengths": [float(e.L) for e in base.shaft_elements], "d_out": float(base.shaft_elements[0].odl),
            "E": float(steel.E), "G": float(steel.G_s), "rho": float(steel.rho),
            "disks": [[int(d.n), float(d.m), float(d.Id), float(d.Ip)] for d in base.disk_elements],
            "bearings": [[int(b.n), float(np.ravel(b.kxx)[0]), float(np.ravel(b.kyy)[0]), c, c]
                         for b in base.bearing_elements]}


def _overhung_spec():
    """Bearings at nodes 0 and 4, a disk hanging at node 6 (free end), one at 2."""
    s = _example_spec()
    s["disks"] = [[2, 10.0, 0.05, 0.1], [6, 25.0, 0.15, 0.3]]
    s["bearings"] = [[0, 2e6, 2e6, 0.0, 0.0], [4, 3e6, 3e6, 0.0, 0.0]]
    return s


def _gyroscopic_spec():
    """A short shaft with a heavy, flat overhung disk (Ip >> It) at the free end,
    damped anisotropic bearings: strongly speed-dependent frequencies."""
    s = _example_spec()
    s["lengths"] = [0.2] * 5
    s["disks"] = [[5, 20.0, 0.08, 0.6]]
    s["bearings"] = [[0, 5e6, 4e6, 300.0, 300.0], [3, 8e6, 6e6, 500.0, 500.0]]
    return s


def static_reference():
    cases = {}
    for name, spec in (("rotor_example", _example_spec()), ("overhung_disk", _overhung_spec())):
        st = _rotor(spec).run_static()
        cases[name] = {"rotor": spec,
                       "deformation_y": [float(v) for v in st.deformation],
                       "shear": [float(v) for v in st.Vx], "moment": [float(v) for v in st.Bm],
                       "shear_positions": [float(v) for v in st.Vx_axis],
                       "bearing_forces": {k: float(v) for k, v in st.bearing_forces.items()},
                       "disk_forces": {k: float(v) for k, v in st.disk_forces.items()},
                       "shaft_weight": float(st.w_shaft), "nodes_pos": [float(v) for v in st.nodes_pos]}
    return {"gravity": G, "cases": cases}


def modal_reference(n_keep=8):
    cases = {}
    specs = (("rotor_example", _example_spec(), [0.0, 500.0, 1000.0]),
             ("rotor_example_damped", _example_spec(c=200.0), [0.0, 500.0, 1000.0]),
             ("gyroscopic", _gyroscopic_spec(), [0.0, 1000.0, 3000.0]))
    for name, spec, speeds in specs:
        rotor = _rotor(spec)
        rows = []
        for s in speeds:
            modal = rotor.run_modal(speed=s, num_modes=40)
            whirl = modal.whirl_direction()
            lateral = [i for i in range(len(modal.wd)) if modal.shapes[i].mode_type == "Lateral"]
            lateral = sorted(lateral, key=lambda i: modal.wd[i])[:n_keep]
            rows.append({"speed": s, "wn": [float(modal.wn[i]) for i in lateral],
                         "wd": [float(modal.wd[i]) for i in lateral],
                         "log_dec": [float(modal.log_dec[i]) for i in lateral],
                         "damping_ratio": [float(modal.damping_ratio[i]) for i in lateral],
                         "whirl": [str(whirl[i]).lower() for i in lateral]})
        cases[name] = {"rotor": spec, "modes": rows}
    return {"cases": cases}


def compute():
    warnings.filterwarnings("ignore")
    import ross as rs

    out_static = dict(static_reference(), ross_version=rs.__version__)
    out_modal = dict(modal_reference(), ross_version=rs.__version__)
    return out_static, out_modal


if __name__ == "__main__":
    st, md = compute()
    os.makedirs(os.path.join(HERE, "data"), exist_ok=True)
    for fname, data in (("ross_static.json", st), ("ross_modal.json", md)):
        with open(os.path.join(HERE, "data", fname), "w") as f:
            json.dump(data, f, indent=1)
    print(json.dumps({k: v["deformation_y"] for k, v in st["cases"].items()}))
    for k, v in md["cases"].items():
        print(k, [r["whirl"] for r in v["modes"]])
