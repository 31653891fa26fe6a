"""`balancing-machine`: model 002 (Polushkin, Polushkin, Fofana 2016), a rigid
rotor on a two-support balancing machine. SI units (kg, m, N/m, N s/m, rad/s).

The defaults are a cardan-shaft-sized rotor (the paper gives no numbers):
10 kg, 0.5 kg m^2, supports 0.8 m apart with stiffness 2e5 / 3e5 N/m and damping
150 / 200 N s/m, correction planes 0.15 m and 0.65 m from support 1, unbalances
2e-4 kg m at 30 deg and 3e-4 kg m at 200 deg (20 and 30 g at 10 mm).
"""

import numpy as np

from ..identify._machine import BalancingMachine
from .._errors import InputError
from ._base import Preset


def build_machine(p) -> BalancingMachine:
    return BalancingMachine(p["m"], p["I"], p["l"], p["k1"], p["k2"], p["c1"], p["c2"])


def planes(p):
    a1, a2 = p["a1"], p["a2"]
    if not (0 <= a1 <= p["l"] and 0 <= a2 <= p["l"]) or a1 == a2:
        raise InputError(f"correction planes a1={a1}, a2={a2} must be distinct positions within the span "
                         f"[0, l={p['l']}] (distances from support 1)")
    return np.array([a1, a2])


def unbalances(p):
    return np.array([p["D1"] * np.exp(1j * np.radians(p["D1_angle"])),
                     p["D2"] * np.exp(1j * np.radians(p["D2_angle"]))])


def _build(p):
    return build_machine(p), planes(p), unbalances(p)


PRESET = Preset(
    name="balancing-machine",
    source="Polushkin, Polushkin, Fofana 2016: rigid rotor on a balancing machine, vector influence coefficients",
    defaults={"m": 10.0, "I": 0.5, "l": 0.8, "k1": 2e5, "k2": 3e5, "c1": 150.0, "c2": 200.0, "a1": 0.15,
              "a2": 0.65, "D1": 2e-4, "D1_angle": 30.0, "D2": 3e-4, "D2_angle": 200.0, "speed": 120.0},
    build=_build,
    describe_params={"m": "rotor mass", "I": "transverse inertia about the centre", "l": "support span",
                     "k1": "support 1 stiffness", "k2": "support 2 stiffness", "c1": "support 1 damping",
                     "c2": "support 2 damping", "a1": "plane 1, distance from support 1",
                     "a2": "plane 2, distance from support 1", "D1": "unbalance in plane 1",
                     "D1_angle": "its angle from the mark", "D2": "unbalance in plane 2",
                     "D2_angle": "its angle from the mark", "speed": "balancing speed"},
    units={"m": "kg", "I": "kg m^2", "l": "m", "k1": "N/m", "k2": "N/m", "c1": "N s/m", "c2": "N s/m",
           "a1": "m", "a2": "m", "D1": "kg m", "D1_angle": "deg", "D2": "kg m", "D2_angle": "deg",
           "speed": "rad/s"},
    domains={"m": ">0", "I": ">0", "l": ">0", "k1": ">0", "k2": ">0", "c1": ">=0", "c2": ">=0", "a1": ">=0",
             "a2": ">=0", "D1": ">=0", "D1_angle": "any", "D2": ">=0", "D2_angle": "any", "speed": ">0"},
    time_unit="s", length_unit="m", speed_key="speed", kind="machine",
)
