"""`flexible-abb`: model 003, the pinned-pinned shaft with distributed mass and a
disk (Kovachev), dimensionless (see `rotorjax.flexible.ModalShaft` for the units).

Defaults: the published critical-speed case, a point-mass disk (`Jt = Jp = 0`) with
`m = 1` (half the shaft's mass) at mid-span, 20 modes.
"""

import jax.numpy as jnp
import numpy as np

from .._errors import InputError
from ..flexible import ModalBalancerRotor, ModalShaft
from ..models import ConstantSpeed
from ._base import Preset, Setup


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
    shaft is `scene.shaft`) at the constant speed `omega`. Not simulated from the
    CLI: no initial state."""
    return Setup(build_balancer_rotor(p))


def regimes(p, n_angles=16, stage=None):
    """The stationary regimes at `omega` (needs balls): the balanced regime C (when
    the balls can cancel the imbalance) and the unbalanced ones (closed forms, eqs.
    25-30), as JSON rows; a note where C does not exist."""
    from ..flexible import balanced_regime, unbalanced_regimes

    if p["n_balls"] < 1:
        raise InputError("--set n_balls=0: flexible-abb regimes need balls, e.g. --set n_balls=2")
    stage = stage or (lambda text: None)
    stage("building the rotor")
    rotor = build(p).scene
    stage("balanced and unbalanced regimes")
    found, notes = [], []
    try:
        found.append(balanced_regime(rotor))
    except ValueError as e:
        notes.append(f"(no balanced regime: {e})")
    found += unbalanced_regimes(rotor)
    rows = [{"kind": r.kind, "sigma": None if r.kind == "C" else r.sigma,
             "disk_amplitude": float(r.disk_amplitude), "max_eigenvalue_real_part": float(r.margin),
             "verdict": "stable" if float(r.margin) < -1e-9 else "unstable",
             "residual": float(r.residual)} for r in found]
    return rows, notes


def critical_speeds(p, lo, hi, n_scan=200, n_modes=None, exact=False, progress=True) -> dict:
    """Critical speeds in `[lo, hi]` (units omega_1): the natural frequencies the
    disk's unbalance excites (`n_modes` shaft modes, default the preset's `modes`),
    or with `exact` the roots of the closed-form equation (17); `"campbell"` holds
    the excited frequencies to plot (constant in the speed), `"present"` its unit and
    title, `"params"` the parameters used."""
    from ..flexible import exact_critical_speeds

    if n_modes is not None:
        try:
            p = dict(p, modes=PRESET.check("modes", n_modes))
        except InputError as e:
            raise InputError(f"--modes {n_modes}: {str(e).split(': ', 1)[1]}") from None
    shaft = build(p).scene.shaft
    f, excited = (np.asarray(v) for v in shaft.natural_frequencies())
    if exact:
        speeds = exact_critical_speeds(float(shaft.m), float(shaft.z0), float(shaft.J), lo, hi)
        method = "closed form, eq. (17)"
    else:
        speeds = [float(v) for v, e in zip(f, excited) if e and lo <= v <= hi]
        method = f"modal model, {shaft.n_modes} modes"
    excited_f = f[excited.astype(bool)]
    shown = excited_f[excited_f <= 1.2 * hi] if np.any(excited_f <= 1.2 * hi) else excited_f[:1]
    return {"params": p, "method": method, "unit": "omega_1 (first pinned-pinned frequency of the bare shaft)",
            "critical_speeds": speeds,
            "campbell": (np.linspace(lo, hi, 2), np.tile(shown, (2, 1)), np.ones((2, shown.size), bool)),
            "present": {"unit": "omega_1 (dimensionless)",
                        "title": f"natural frequencies excited by the disk's unbalance, critical speeds ({method})"}}


def _balanced_margin(p):
    from ..flexible import balanced_regime

    if int(p["n_balls"]) < 1:
        raise InputError("the balanced regime needs balls: --set n_balls=2")
    return balanced_regime(build_balancer_rotor(p)).margin


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
    margin=_balanced_margin,
    regime="the balanced regime C (straight shaft, balls cancel the imbalance)",
    topology_keys=("modes", "n_balls", "paper_gyroscopics"),
    kind="modal",
    # the balanced regime's boundary (with balls) runs from omega = 0.70 (d = 0.5) to d -> 0 at high speed
    box={"omega": (0.3, 3.0), "d": (0.0, 0.5)},
    regimes=regimes,
    critical_speeds=critical_speeds,
)
