"""Regenerate `journal_ross.json`: ROSS 2.3.0's plain journal bearings at one
operating point, for `tests/models/test_journal_bearing.py::test_ross_reference`.

Run with the ROSS venv (ROSS, NumPy, SciPy; no rotorjax needed):

    /tmp/rossenv/bin/python tests/models/data/make_journal_ross.py

ROSS functions used:
- `ross.CylindricalBearing` (ross/bearing_seal_element.py): the short-bearing closed
  form of Friswell et al. (2010) p. 177 — eccentricity, Sommerfeld numbers, K, C.
- `ross.BearingFluidFlow` (same file; deprecated in 2.x): finite-difference Reynolds
  solution (ross/bearings/fluid_flow.py) with its equilibrium search and coefficients
  fitted to small harmonic journal motions
  (ross/bearings/fluid_flow_coefficients.py::calculate_stiffness_and_damping_coefficients).
  Its pressure is the full-film solution clipped at zero (half-Sommerfeld:
  `np.clip(P, a_min=0)` in `FluidFlow.calculate_pressure_matrix_numerical`); stored at
  ROSS's test mesh (nz=30, ntheta=20) and on finer ones (ntheta up to 320).
The operating point is the one in ROSS's own tests (test_cylindrical_hydrodynamic,
test_bearing_fluid_flow): W = 525 N, mu = 0.1 Pa s, L = 30 mm, D = 100 mm,
c = 0.1 mm, 1500 rpm.
"""

import json
import pathlib
import warnings

import numpy as np
import ross as rs

W, MU, L, D, C = 525.0, 0.1, 0.03, 0.1, 1e-4
SPEED = 1500 * np.pi / 30  # rad/s

cyl = rs.CylindricalBearing(n=0, speed=[SPEED, 2 * SPEED], weight=W, bearing_length=L, journal_diameter=D,
                            radial_clearance=C, oil_viscosity=MU)
with warnings.catch_warnings():
    warnings.simplefilter("ignore", DeprecationWarning)
    ff = rs.BearingFluidFlow(0, nz=30, ntheta=20, length=L, omega=[SPEED], p_in=0.0, p_out=0.0,
                             radius_rotor=D / 2 - C, radius_stator=D / 2, visc=MU, rho=860.0, load=W)


def mats(b, speed):
    k = np.asarray(b.K(speed))[:2, :2]
    c = np.asarray(b.C(speed))[:2, :2]
    return k.tolist(), c.tolist()


k_cyl, c_cyl = mats(cyl, SPEED)
k_ff, c_ff = mats(ff, SPEED)
# the same solver on finer meshes (circumferential cells halved each time; about 4 min in
# all): its coefficients converge at first order in 1/ntheta, to a limit that differs
# from a Swift-Stieber solution by the half-Sommerfeld clipping (see the test)
refinement = []
for ntheta in (20, 40, 80, 160, 320):
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", DeprecationWarning)
        b = rs.BearingFluidFlow(0, nz=30, ntheta=ntheta, length=L, omega=[SPEED], p_in=0.0, p_out=0.0,
                                radius_rotor=D / 2 - C, radius_stator=D / 2, visc=MU, rho=860.0, load=W)
    k, c = mats(b, SPEED)
    refinement.append({"nz": 30, "ntheta": ntheta, "K": k, "C": c})
out = {
    "ross_version": rs.__version__,
    "script": "tests/models/data/make_journal_ross.py",
    "operating_point": {"load": W, "viscosity": MU, "length": L, "diameter": D, "clearance": C, "speed": SPEED},
    "frame": "ROSS: x horizontal, y vertical, load along -y; K = [[kxx, kxy], [kyx, kyy]] (N/m), C (N s/m)",
    "CylindricalBearing": {
        "eccentricity": float(cyl.eccentricity[0]),
        "attitude_angle": float(cyl.attitude_angle[0]),
        "sommerfeld": float(cyl.sommerfeld[0]),
        "modified_sommerfeld": float(cyl.modified_sommerfeld[0]),
        "K": k_cyl,
        "C": c_cyl,
    },
    "BearingFluidFlow": {"nz": 30, "ntheta": 20, "K": k_ff, "C": c_ff},
    "BearingFluidFlow_refinement": refinement,
}
path = pathlib.Path(__file__).with_name("journal_ross.json")
path.write_text(json.dumps(out, indent=2) + "\n")
print(json.dumps(out, indent=2))
