"""Reference numbers from ROSS 2.3.0 for the UCS map, the frequency response, the
unbalance response to several unbalances and the level I screening, on ROSS's
`rotor_example` (our `ross-compare`) and variants of it.

Run with an interpreter that has ROSS (no rotorjax or jax needed):
`/tmp/rossenv/bin/python tests/flexible/ross_ucs_frf_reference.py` rewrites
`tests/flexible/data/ross_ucs_frf.json`, which `test_ucs_frf.py` and
`test_level1.py` compare against. ROSS 2.3.0 has 6 dofs per node
(x, y, z, alpha, beta, theta): x of node n is dof 6 n, y is 6 n + 1.
"""

import json
import os
import warnings

import numpy as np

FREQS = [5.0, 50.0, 95.0, 150.0, 300.0, 600.0, 900.0]
PAIRS = [((2, "x"), (2, "x")), ((2, "x"), (4, "y")), ((0, "y"), (3, "x")), ((4, "y"), (4, "y"))]
DIR = {"x": 0, "y": 1}


def _bearings(rs, base, **kw):
    return [rs.BearingElement(b.n, **kw) for b in base.bearing_elements]


def _rotor_dict(rotor):
    return {"lengths": [e.L for e in rotor.shaft_elements], "d_out": rotor.shaft_elements[0].odl,
            "E": rotor.shaft_elements[0].material.E, "G": rotor.shaft_elements[0].material.G_s,
            "rho": rotor.shaft_elements[0].material.rho,
            "disks": [[d.n, d.m, d.Id, d.Ip] for d in rotor.disk_elements]}


def compute():
    warnings.filterwarnings("ignore")
    import ross as rs

    base = rs.rotor_example()
    out = {"ross_version": rs.__version__, "rotor": _rotor_dict(base)}

    # --- UCS map: every bearing isotropic k, speed 0 (and synchronous) ---
    ucs = {}
    for sync in (False, True):
        r = base.run_ucs(stiffness_range=(5, 10), num=30, num_modes=16, synchronous=sync)
        ucs["synchronous" if sync else "speed0"] = {"stiffness": np.asarray(r.stiffness_log).tolist(),
                                                    "wn": np.asarray(r.wn).tolist()}
    # speed-dependent bearings (linear in speed: ROSS's UnivariateSpline and our not-a-knot
    # spline both reproduce a line exactly); a fine map so that ROSS's polyline
    # intersection is accurate
    table = [0.0, 200.0, 400.0, 600.0, 800.0, 1000.0]
    kxx = [2e6 + 4e4 * w for w in table]
    kyy = [1e6 + 2e4 * w for w in table]
    brg = [rs.BearingElement(b.n, kxx=kxx, kyy=kyy, cxx=0, frequency=table) for b in base.bearing_elements]
    rot = rs.Rotor(base.shaft_elements, base.disk_elements, brg)
    r = rot.run_ucs(stiffness_range=(6, 8), num=1500, num_modes=16)
    ucs["speed_dependent"] = {"table": table, "kxx": kxx, "kyy": kyy,
                              "intersections_k": r.intersection_points["x"],
                              "intersections_speed": r.intersection_points["y"]}
    out["ucs"] = ucs

    # --- frequency response: synchronous (speed = frequency) and at a fixed speed ---
    damped = rs.Rotor(base.shaft_elements, base.disk_elements,
                      [rs.BearingElement(b.n, kxx=1e6, kyy=0.8e6, kxy=2e4, kyx=-1e4, cxx=300.0, cyy=200.0,
                                         cxy=10.0, cyx=-5.0) for b in base.bearing_elements])
    out["damped_bearing"] = [1e6, 0.8e6, 300.0, 200.0, 2e4, -1e4, 10.0, -5.0]  # kxx kyy cxx cyy kxy kyx cxy cyx
    frf = {}
    for name, rot in (("example", base), ("damped", damped)):
        resp = rot.run_freq_response(speed_range=FREQS)
        rows = []
        for (ni, di), (no, do) in PAIRS:
            i, o = 6 * ni + DIR[di], 6 * no + DIR[do]
            rows.append({"input": [ni, di], "output": [no, do],
                         "displacement": [[float(z.real), float(z.imag)] for z in resp.freq_resp[o, i, :]],
                         "velocity": [[float(z.real), float(z.imag)] for z in resp.velc_resp[o, i, :]],
                         "acceleration": [[float(z.real), float(z.imag)] for z in resp.accl_resp[o, i, :]]})
        fixed = []
        for f in FREQS:
            H = rot.transfer_matrix(speed=300.0, frequency=f)
            fixed.append([[float(H[6 * no + DIR[do], 6 * ni + DIR[di]].real),
                           float(H[6 * no + DIR[do], 6 * ni + DIR[di]].imag)] for (ni, di), (no, do) in PAIRS])
        frf[name] = {"pairs": rows, "fixed_speed_300": fixed}
    out["frf"] = {"frequencies": FREQS, "cases": frf}

    # --- unbalance response, two unbalances at once ---
    speeds = [50.0, 120.0, 400.0, 700.0]
    unb = [(2, 1e-3, 0.0), (4, 5e-4, 1.0)]
    resp = damped.run_unbalance_response(node=[u[0] for u in unb], unbalance_magnitude=[u[1] for u in unb],
                                         unbalance_phase=[u[2] for u in unb], frequency=speeds)
    n_nodes = len(base.nodes)
    X = resp.forced_resp[[6 * n for n in range(n_nodes)], :]
    Y = resp.forced_resp[[6 * n + 1 for n in range(n_nodes)], :]
    major = []
    for s in speeds:
        m = resp._calculate_major_axis_per_speed(s)
        major.append([float(abs(v)) for v in np.asarray(m[4 if m.shape[0] > 4 else 3, :])])
    out["unbalance"] = {"unbalances": unb, "speeds": speeds,
                        "x": [[[float(z.real), float(z.imag)] for z in row] for row in X],
                        "y": [[[float(z.real), float(z.imag)] for z in row] for row in Y],
                        "major_axis": major}

    # --- level I: cross-coupling kxy = Q, kyx = -Q at node 3, log dec of the first non-backward mode ---
    speed = 500.0
    lev_rotor = rs.Rotor(base.shaft_elements, base.disk_elements,
                         [rs.BearingElement(b.n, kxx=1e6, kyy=0.8e6, cxx=1500.0, cyy=1500.0)
                          for b in base.bearing_elements], rated_w=speed)
    lev = lev_rotor.run_level1(n=3, stiffness_range=(0.0, 4e5), num=9)
    out["level1"] = {"node": 3, "speed": speed, "bearing": [1e6, 0.8e6, 1500.0, 1500.0],
                     "Q": np.asarray(lev.stiffness_range).tolist(), "log_dec": np.asarray(lev.log_dec).tolist()}
    return out


if __name__ == "__main__":
    data = compute()
    path = os.path.join(os.path.dirname(__file__), "data", "ross_ucs_frf.json")
    with open(path, "w") as f:
        json.dump(data, f, indent=1)
    print("wrote", path)
