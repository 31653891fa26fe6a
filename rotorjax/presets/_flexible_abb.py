"""`flexible-abb`: model 003, the pinned-pinned shaft with distributed mass and a
disk (Kovachev), dimensionless (see `rotorjax.flexible.ModalShaft` for the units).

Defaults: the published critical-speed case, a point-mass disk (`Jt = Jp = 0`) with
`m = 1` (half the shaft's mass) at mid-span, 20 modes.
"""

from ..flexible import ModalShaft
from ._base import Preset


def build_shaft(p) -> ModalShaft:
    return ModalShaft(int(p["modes"]), p["m"], p["z0"], p["Jt"], p["Jp"], p["d"], p["m0"],
                      gyroscopic="paper" if p["paper_gyroscopics"] else "standard")


PRESET = Preset(
    name="flexible-abb",
    source="model 003: Kovachev, SPbU dissertation abstract (pinned-pinned modal shaft + disk)",
    defaults={"m": 1.0, "z0": 0.5, "Jt": 0.0, "Jp": 0.0, "d": 0.0, "m0": 0.01, "modes": 20,
              "paper_gyroscopics": 1},
    build=lambda p: (build_shaft(p), None, None),
    describe_params={
        "m": "disk (+ imbalance) mass / (rho S l / 2)", "z0": "disk position / l",
        "Jt": "transverse inertia / (l^2 m_S / pi^2)", "Jp": "polar inertia / (l^2 m_S / pi^2)",
        "d": "external damping / (m_S omega_1)", "m0": "imbalance mass / m_S", "modes": "shaft modes",
        "paper_gyroscopics": "1: J = Jt + 2 Jp as the paper; 0: J = Jt - Jp (standard)",
    },
    time_unit="1/omega_1", length_unit="r0 (lateral), l (axial)",
    integer_keys=("modes", "paper_gyroscopics"),
    speed_key="omega",
    topology_keys=("modes",),
    kind="modal",
)
