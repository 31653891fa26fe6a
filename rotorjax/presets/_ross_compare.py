"""`ross-compare`: ROSS's example rotor (`ross.rotor_example()`), built here too.

A steel shaft of six 0.25 m Timoshenko elements, 0.05 m diameter; two disks
(32.59 kg, It = 0.1781, Ip = 0.3296 kg m^2) at nodes 2 and 4; bearings at nodes 0
and 6 with kxx = 1e6, kyy = 0.8e6 N/m, no damping. SI units (rad/s, m).
"""

import numpy as np

from ..models import FlexibleRotor, RotorScene
from .._errors import InputError
from ._base import Preset, Setup


def build_rotor(p) -> FlexibleRotor:
    n_el = int(p["n_elements"])
    for key in ("disk1_node", "disk2_node"):
        if not 0 <= int(p[key]) <= n_el:
            raise InputError(f"{key}={p[key]}: the shaft has nodes 0..{n_el} (n_elements={n_el})")
    disk = (p["disk_mass"], p["disk_It"], p["disk_Ip"])
    return FlexibleRotor(
        np.full(n_el, p["shaft_length"] / n_el), p["shaft_diameter"], E=p["E"], G=p["G"],
        rho=p["rho"],
        disks=((int(p["disk1_node"]),) + disk, (int(p["disk2_node"]),) + disk),
        bearings=((0, p["kxx"], p["kyy"], p["cxx"], p["cyy"]),
                  (n_el, p["kxx"], p["kyy"], p["cxx"], p["cyy"])),
        theory="timoshenko" if p["timoshenko"] else "euler-bernoulli",
    )


#: the unbalance of ROSS's unbalance-response example (kg m), at disk 1's node
UNBALANCE = 1e-3


def build(p) -> Setup:
    """The rotor as a scene (at rest, no initial state: the preset is analysed
    linearly, not simulated), with the unbalance of ROSS's unbalance-response
    example (`UNBALANCE` at disk 1's node, as `rotors/ross_compare.toml` has it)."""
    from ..models import Unbalance

    return Setup(RotorScene(build_rotor(p), components=(Unbalance(int(p["disk1_node"]), UNBALANCE),)))


def _build(p):
    """`(rotor, None, None)` (the tuple `build` returned before `Setup`)."""
    return build_rotor(p), None, None


PRESET = Preset(
    name="ross-compare",
    source="ROSS rotor_example: steel shaft, two disks, two bearings (also built in ROSS)",
    defaults={
        "shaft_length": 1.5, "n_elements": 6, "shaft_diameter": 0.05, "E": 211e9, "G": 81.2e9,
        "rho": 7810.0, "disk_mass": 32.58972765304033, "disk_It": 0.17808928257067666,
        "disk_Ip": 0.32956362089137037, "disk1_node": 2, "disk2_node": 4,
        "kxx": 1e6, "kyy": 0.8e6, "cxx": 0.0, "cyy": 0.0, "timoshenko": 1,
    },
    build=build,
    describe_params={
        "shaft_length": "shaft length", "n_elements": "shaft elements (equal lengths)",
        "shaft_diameter": "shaft outer diameter", "E": "Young's modulus", "G": "shear modulus",
        "rho": "density", "disk_mass": "mass of each disk", "disk_It": "transverse inertia of each disk",
        "disk_Ip": "polar inertia of each disk", "disk1_node": "node of disk 1 (0..n_elements)",
        "disk2_node": "node of disk 2 (0..n_elements)", "kxx": "bearing stiffness, x (both bearings)",
        "kyy": "bearing stiffness, y", "cxx": "bearing damping, x", "cyy": "bearing damping, y",
        "timoshenko": "1: Timoshenko, 0: Euler-Bernoulli",
    },
    units={"shaft_length": "m", "n_elements": "count", "shaft_diameter": "m", "E": "Pa", "G": "Pa",
           "rho": "kg/m^3", "disk_mass": "kg", "disk_It": "kg m^2", "disk_Ip": "kg m^2", "disk1_node": "node",
           "disk2_node": "node", "kxx": "N/m", "kyy": "N/m", "cxx": "N s/m", "cyy": "N s/m",
           "timoshenko": "flag"},
    domains={"shaft_length": ">0", "n_elements": "int[1,500]", "shaft_diameter": ">0", "E": ">0", "G": ">0",
             "rho": ">0", "disk_mass": ">=0", "disk_It": ">=0", "disk_Ip": ">=0", "disk1_node": "int[0,500]",
             "disk2_node": "int[0,500]", "kxx": ">=0", "kyy": ">=0", "cxx": ">=0", "cyy": ">=0",
             "timoshenko": "{0,1}"},
    time_unit="s", length_unit="m",
    integer_keys=("n_elements", "disk1_node", "disk2_node"),
    speed_key="speed",
    topology_keys=("n_elements", "disk1_node", "disk2_node", "timoshenko"),
    kind="flexible",
)
