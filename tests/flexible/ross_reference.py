"""Reference numbers from ROSS for the `ross-compare` rotor (ROSS's `rotor_example`).

Run with an interpreter that has ROSS (`pip install "ross-rotordynamics==2.3.0"
"plotly<7"`): `python tests/flexible/ross_reference.py` rewrites
`tests/flexible/data/ross_rotor_example.json`, which the tests compare against
(and, when ROSS imports in the test environment, recompute live).
"""

import json
import os
import warnings

import numpy as np


def compute():
    warnings.filterwarnings("ignore")
    import ross as rs

    out = {"ross_version": rs.__version__, "speeds": [0.0, 500.0, 1000.0], "cases": {}}
    for name, shear in (("timoshenko", True), ("euler-bernoulli", False)):
        base = rs.rotor_example()
        if shear:
            rotor = base
        else:
            steel = base.shaft_elements[0].material
            shaft = [rs.ShaftElement(0.25, 0.0, 0.05, material=steel, shear_effects=False,
                                     rotary_inertia=False, gyroscopic=True) for _ in range(6)]
            rotor = rs.Rotor(shaft, base.disk_elements, base.bearing_elements)
        freqs = []
        for s in out["speeds"]:
            modal = rotor.run_modal(speed=s, num_modes=16)
            freqs.append([float(w) for w in np.sort(modal.wd)[:4]])
        crit = rotor.run_critical_speed(num_modes=16)
        wn = np.sort(np.asarray(crit.wn()))[:2] if callable(getattr(crit, "wn", None)) else None
        resp = rotor.run_unbalance_response(node=2, unbalance_magnitude=0.001, unbalance_phase=0.0,
                                            frequency=np.linspace(10.0, 1200.0, 2000))
        mag = np.abs(resp.forced_resp[rotor.number_dof * 2, :])  # x at node 2
        peaks = [float(resp.speed_range[i]) for i in range(1, len(mag) - 1)
                 if mag[i] > mag[i - 1] and mag[i] > mag[i + 1]]
        out["cases"][name] = {"damped_frequencies": freqs,
                              "critical_speeds": None if wn is None else [float(w) for w in wn],
                              "unbalance_peaks_node2_x": peaks}
    base = rs.rotor_example()
    out["rotor"] = {
        "lengths": [e.L for e in base.shaft_elements], "d_out": base.shaft_elements[0].odl,
        "E": base.shaft_elements[0].material.E, "G": base.shaft_elements[0].material.G_s,
        "rho": base.shaft_elements[0].material.rho,
        "disks": [[d.n, d.m, d.Id, d.Ip] for d in base.disk_elements],
        "bearings": [[b.n, float(np.ravel(b.kxx)[0]), float(np.ravel(b.kyy)[0]),
                      float(np.ravel(b.cxx)[0]), float(np.ravel(b.cyy)[0])] for b in base.bearing_elements],
    }
    return out


if __name__ == "__main__":
    data = compute()
    path = os.path.join(os.path.dirname(__file__), "data", "ross_rotor_example.json")
    with open(path, "w") as f:
        json.dump(data, f, indent=2)
    print(json.dumps(data, indent=2))
