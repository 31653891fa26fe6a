"""`balancing-machine`: model 002 (Polushkin, Polushkin, Fofana 2016), a rigid
rotor on a two-support balancing machine. SI units (kg, m, N/m, N s/m, rad/s).

The defaults are the rig the shipped datasets simulate (`rotorjax.identify.RIG`;
the paper gives no numbers): a cardan-shaft-sized rotor, 10 kg, 0.5 kg m^2,
supports 0.8 m apart with stiffness 2e5 / 3e5 N/m and damping 150 / 200 N s/m,
correction planes 0.15 m and 0.65 m from support 1, unbalances 2e-4 kg m at 30 deg
and 3e-4 kg m at 200 deg (20 and 30 g at 10 mm).
"""

from ..identify._datasets import RIG, machine_from, planes_from, unbalances_from
from ..models._balancing_machine import BalancingMachine, BalancingScene
from ..models._speed import ConstantSpeed
from ._base import Preset, Setup


def build_machine(p) -> BalancingMachine:
    return machine_from(p)


def planes(p):
    return planes_from(p)


def unbalances(p):
    return unbalances_from(p)


def build(p) -> Setup:
    """The machine with its planes and unbalances at the balancing speed, as a scene
    (`BalancingScene`: `scene.machine`, `scene.planes`, `scene.unbalances`, and the
    speed profile `scene.speed`, a `ConstantSpeed`). `rotorjax.simulate` integrates
    it (from rest, or from `scene.steady_state(p["speed"])`; the shipped signals are
    made that way, `rotorjax.identify._make_data`), but the CLI does not simulate it
    (`balance`, `identify`): no initial state."""
    return Setup(BalancingScene(build_machine(p), planes(p), unbalances(p), ConstantSpeed(p["speed"])))


PRESET = Preset(
    name="balancing-machine",
    source="Polushkin, Polushkin, Fofana 2016: rigid rotor on a balancing machine, vector influence coefficients",
    defaults=dict(RIG),
    build=build,
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
