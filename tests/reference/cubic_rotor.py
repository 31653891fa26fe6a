"""ROSS's example rotor (`ross-compare`: two disks, dampers at them) on isotropic
bearings with cubic hardening at nodes 0 and 6, unbalanced at the disks: the scene of
tests/models/test_composition_cubic.py and benchmarks/harmonic_balance.py."""

import numpy as np

from rotorjax.models import CubicBearing, FlexibleRotor, Unbalance
from rotorjax.presets._ross_compare import PRESET

K3 = 3e12   # N/m^3


def cubic_rotor(k3=K3):
    """`(rotor, parts)`: the full FE rotor and its components (unbalance 2e-3 kg m at
    nodes 2 and 4, cubic bearings `k3` at nodes 0 and 6)."""
    p = PRESET.params()
    disk = (p["disk_mass"], p["disk_It"], p["disk_Ip"])
    rotor = FlexibleRotor(np.full(6, 0.25), p["shaft_diameter"], E=p["E"], G=p["G"], rho=p["rho"],
                          disks=((2,) + disk, (4,) + disk),
                          bearings=((0, 1e6, 1e6, 0.0, 0.0), (6, 1e6, 1e6, 0.0, 0.0),
                                    (2, 0.0, 0.0, 150.0, 150.0), (4, 0.0, 0.0, 150.0, 150.0)))
    return rotor, (Unbalance(2, 2e-3), Unbalance(4, 2e-3), CubicBearing(0, k3), CubicBearing(6, k3))
