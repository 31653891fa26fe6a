"""Writes the rotors of `tests/io/data/ross/` with ROSS itself (`Rotor.save`, TOML and
JSON) and ROSS's modes of them (`ross_modes.json`): run in ROSS's own interpreter,
`$ROTORJAX_ROSS_PYTHON tests/io/ross_saved.py OUT_DIR`. ROSS 2.3.0 wrote the files in
`data/ross/` (`test_import_ross.py` runs it again when ROSS is there, and imports what
it writes); ROSS 3.1.0 those in `data/ross/v3/`. ROSS 3.x needs Python 3.13, which
this project's machines lack, so it ran in a Debian 13 chroot:

    debootstrap --variant=minbase --include=python3,python3-venv trixie /tmp/trixie
    chroot /tmp/trixie python3 -m venv /opt/ross3
    chroot /tmp/trixie /opt/ross3/bin/pip install ross-rotordynamics==3.1.0
    chroot /tmp/trixie /opt/ross3/bin/python /work/ross_saved.py /work/out   # this file copied in

- `rotor_example`: ROSS's example rotor (`ross.rotor_example()`), TOML and JSON;
- `tapered_rig`: tapered and hollow elements of two materials, two disks, a bearing
  tabulated over the rotor speed (2.x's `frequency`, 3.x's `speed` axis) with
  cross-coupled stiffness, and a constant one;
- `linked`: a bearing linked (`n_link`) to a pedestal (a node of its own, a point mass
  there, and a bearing from it to the ground); 3.x: TOML and JSON;
- `axial_force`: a shaft under axial force (refused on import);
- 3.x: `frequency_table`: `tapered_rig` with its table over the excitation frequency
  (3.x's `frequency` axis; refused on import).

The modes: each rotor's damped natural frequencies and log decrements at 0 and 400
rad/s (a speed of `tapered_rig`'s table, where the two tools' interpolations agree)."""

import json
import sys
import warnings

import numpy as np

warnings.filterwarnings("ignore")
import ross as rs  # noqa: E402

MAJOR = int(rs.__version__.split(".")[0])
#: the bearing table's axis of the rotor speed: `frequency` in 2.x, `speed` in 3.x
SPEED_AXIS = "speed" if MAJOR >= 3 else "frequency"


def rotors():
    steel = rs.Material(name="steel", rho=7810, E=211e9, G_s=81.2e9)
    alu = rs.Material(name="aluminium", rho=2700, E=70e9, G_s=26e9)
    geometry = [(0.2, 0.0, 0.06, 0.0, 0.06, steel), (0.2, 0.02, 0.06, 0.02, 0.08, steel),
                (0.25, 0.02, 0.08, 0.02, 0.08, steel), (0.25, 0.0, 0.07, 0.0, 0.07, alu),
                (0.2, 0.0, 0.07, 0.0, 0.05, alu), (0.2, 0.0, 0.05, 0.0, 0.05, alu)]
    shaft = [rs.ShaftElement(L=L, idl=idl, odl=odl, idr=idr, odr=odr, material=m, n=i)
             for i, (L, idl, odl, idr, odr, m) in enumerate(geometry)]
    disks = [rs.DiskElement(n=2, m=15.0, Id=0.08, Ip=0.15), rs.DiskElement(n=4, m=8.0, Id=0.03, Ip=0.05)]
    def table(axis):
        return rs.BearingElement(n=0, kxx=[1e7, 1.1e7, 1.3e7, 1.6e7], kyy=[8e6, 9e6, 1.1e7, 1.4e7],
                                 kxy=[0, 2e5, 4e5, 6e5], kyx=[0, -2e5, -4e5, -6e5], cxx=[800, 900, 1000, 1100],
                                 cyy=[700, 800, 900, 1000], **{axis: np.array([0.0, 200.0, 400.0, 800.0])})

    def tapered(axis):
        return rs.Rotor(shaft, disks, [table(axis), rs.BearingElement(n=6, kxx=2e7, kyy=1.5e7, cxx=1500, cyy=1200)])

    plain = [rs.ShaftElement(L=0.25, idl=0, odl=0.05, material=steel, n=i) for i in range(4)]
    linked = rs.Rotor(plain, [], [rs.BearingElement(n=0, kxx=1e6, cxx=0, n_link=5),
                                  rs.BearingElement(n=5, kxx=1e8, cxx=0), rs.BearingElement(n=4, kxx=1e6, cxx=0)],
                      [rs.PointMass(n=5, m=10.0)])
    axial = rs.Rotor([rs.ShaftElement(L=0.25, idl=0, odl=0.05, material=steel, n=i, axial_force=1000.0)
                      for i in range(4)], [], [rs.BearingElement(n=0, kxx=1e6, cxx=0),
                                               rs.BearingElement(n=4, kxx=1e6, cxx=0)])
    made = {"rotor_example": rs.rotor_example(), "tapered_rig": tapered(SPEED_AXIS), "linked": linked,
            "axial_force": axial}
    if MAJOR >= 3:
        made["frequency_table"] = tapered("frequency")     # 3.x: over the excitation frequency (refused)
    return made


def main(out):
    made = rotors()
    for name, rotor in made.items():
        rotor.save(f"{out}/{name}.toml")
        if name in ("rotor_example", "tapered_rig") or (MAJOR >= 3 and name == "linked"):
            rotor.save(f"{out}/{name}.json")
    ref = {"ross_version": rs.__version__}
    for name in ("rotor_example", "tapered_rig", "linked"):
        ref[name] = {}
        for speed in (0.0, 400.0):
            m = made[name].run_modal(speed, num_modes=40)
            ref[name][str(speed)] = {"wd": m.wd.tolist(), "log_dec": m.log_dec.tolist()}
    with open(f"{out}/ross_modes.json", "w") as f:
        json.dump(ref, f, indent=1)


if __name__ == "__main__":
    main(sys.argv[1])
