"""`flexible-abb`: model 003, the pinned-pinned shaft with distributed mass and a
disk (Kovachev), dimensionless (see `rotorjax.flexible.ModalShaft` for the units).

Defaults: the published critical-speed case, a point-mass disk (`Jt = Jp = 0`) with
`m = 1` (half the shaft's mass) at mid-span, 20 modes.
"""

import jax.numpy as jnp
import numpy as np

from ..models import ConstantSpeed, ModalBalancerRotor, ModalShaft
from ..models._validate import is_concrete
from ._base import Preset, Setup

#: the reference motion of stability maps, critical speeds and boundaries
REGIME = "the balanced regime C (straight shaft, balls cancel the imbalance)"


def build_shaft(p) -> ModalShaft:
    """The shaft + disk; its mass `m` includes the balls (`m + n_balls ball_mass`)."""
    return ModalShaft(int(p["modes"]), p["m"] + p["n_balls"] * p["ball_mass"], p["z0"], p["Jt"],
                      p["Jp"], p["d"], p["m0"],
                      gyroscopic="paper" if p["paper_gyroscopics"] else "standard")


def build_balancer_rotor(p, speed=None) -> ModalBalancerRotor:
    n = int(p["n_balls"])
    return ModalBalancerRotor(build_shaft(p), jnp.full(n, p["ball_mass"]), p["ball_radius"],
                              p["ball_drag"], ConstantSpeed(p["omega"]) if speed is None else speed)


def build(p) -> Setup:
    """The rotor as a scene: the shaft + disk with `n_balls` balls (0: none; the
    shaft is `scene.shaft`) at the constant speed `omega`; the imbalance and the
    balls are the shared `RigidRotor` and `AutoBalancer` components
    (`scene.components`), their equations from their energies. Not simulated from
    the CLI: no initial state."""
    rotor = build_balancer_rotor(p)
    return Setup(rotor, reference=balanced_reference(p, rotor))


def balanced_reference(p, rotor=None):
    """The balanced regime C at `omega` as the preset's reference motion: the shaft
    straight, the balls at the angles that cancel the imbalance (exact: Newton starts
    on it); none without balls or where the balls cannot cancel the imbalance."""
    from ..analysis import NoReference, StationaryRegime
    from ..models import balancing_angles

    rotor = build_balancer_rotor(p) if rotor is None else rotor
    n = int(p["n_balls"])
    if n < 1:
        return NoReference(rotor, "the balanced regime needs balls: --set n_balls=2", label=REGIME)
    c = rotor.shaft.m0 / (n * rotor.ball_mass[0] * rotor.ball_radius[0])
    if is_concrete(c) and c > 1:
        return NoReference(rotor, f"rotor: the balls cannot cancel the imbalance: m0 = {float(rotor.shaft.m0)} > "
                                  f"sum m_j r_j = {n * float(rotor.ball_mass[0] * rotor.ball_radius[0])}",
                           label=REGIME)
    guess = jnp.concatenate([jnp.zeros(2 * rotor.shaft.n_modes), balancing_angles(n, c)])
    return StationaryRegime(rotor, guess, label=REGIME, balanced=True)


PRESET = Preset(
    name="flexible-abb",
    source="model 003: Kovachev, SPbU dissertation abstract (pinned-pinned modal shaft + disk)",
    defaults={"m": 1.0, "z0": 0.5, "Jt": 0.0, "Jp": 0.0, "d": 0.0, "m0": 0.01, "modes": 20,
              "paper_gyroscopics": 1, "n_balls": 0, "ball_mass": 0.02, "ball_radius": 1.0,
              "ball_drag": 5.0, "omega": 1.2},
    build=build,
    describe_params={
        "m": "disk (+ imbalance) mass / (rho S l / 2)", "z0": "disk position / l",
        "Jt": "transverse inertia / (l^2 m_S / pi^2)", "Jp": "polar inertia / (l^2 m_S / pi^2)",
        "d": "external damping / (m_S omega_1)", "m0": "imbalance mass / m_S", "modes": "shaft modes",
        "paper_gyroscopics": "1: J = Jt + 2 Jp as the paper; 0: J = Jt - Jp (standard)",
        "n_balls": "balls of the auto-balancer (0: none)", "ball_mass": "each ball / m_S",
        "ball_radius": "ball circle radius / r0", "ball_drag": "d_j / (m_j r_j^2 omega_1)",
        "omega": "speed / omega_1 (regimes, maps)",
    },
    units={"m": "dimensionless", "z0": "dimensionless", "Jt": "dimensionless", "Jp": "dimensionless",
           "d": "dimensionless", "m0": "dimensionless", "modes": "count", "paper_gyroscopics": "flag",
           "n_balls": "count", "ball_mass": "dimensionless", "ball_radius": "dimensionless",
           "ball_drag": "dimensionless", "omega": "dimensionless"},
    domains={"m": ">0", "z0": "(0,1)", "Jt": ">=0", "Jp": ">=0", "d": ">=0", "m0": ">=0", "modes": "int[1,200]",
             "paper_gyroscopics": "{0,1}", "n_balls": "int[0,32]", "ball_mass": ">0", "ball_radius": ">0",
             "ball_drag": ">=0", "omega": ">0"},
    time_unit="1/omega_1", length_unit="r0 (lateral), l (axial)",
    integer_keys=("modes", "paper_gyroscopics", "n_balls"),
    speed_key="omega",
    topology_keys=("modes", "n_balls", "paper_gyroscopics"),
    kind="modal",
    # the balanced regime's boundary (with balls) runs from omega = 0.70 (d = 0.5) to d -> 0 at high speed
    box={"omega": (0.3, 3.0), "d": (0.0, 0.5)},
)
