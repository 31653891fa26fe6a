"""Model 000: Jeffcott rotor with a ball auto-balancer on an elliptic race.

Bykov & Kovachev, "Dynamics of a statically unbalanced rotor with an elliptic
automatic ball balancer", Vestnik SPbU Math. Mech. 2019 (seed 000).

A disk of mass `m` on a massless shaft of stiffness `k`, external damping `c_n`,
static eccentricity `s` at phase `alpha`; `n` balls of mass `m_b` in an elliptic race
with semi-axes `r1, r2` and drag `c_b` on their motion relative to the rotor.
Dimensionless groups (paper, after eq. 7), with `r = (r1 + r2)/2` and
`Omega = sqrt(k / (m + n m_b))`, time `tau = Omega t`, lengths over `r`:

    chi = m_b/m, eps = s/r, delta_n = c_n/((m + n m_b) Omega), delta_b = c_b/(m_b Omega),
    rho1 = r1/r, rho2 = r2/r, nu = theta_dot/Omega, nu_dot = theta_ddot/Omega^2.

The paper's eq. (7) divided by `m r Omega^2` is exactly the SI scene with `m = 1`,
`r = 1`, `Omega = 1`: `m_b = chi`, `s = eps`, `k = 1 + n chi`,
`c_n = delta_n (1 + n chi)`, `c_b = delta_b chi`, `r_i = rho_i`, which is what
`scene_from_groups` builds. The balls are point masses (`K = 1`) as in the paper;
each has one coordinate, the race's parametric angle (no constraint to drift).
"""

import jax.numpy as jnp
import numpy as np

from .._errors import InputError
from ..models import AutoBalancer, ConstantSpeed, Race, RigidRotor, RunUp, Scene, Supports, weights_at
from ._base import Preset, Setup
from ..models._validate import is_concrete

#: the reference motion of stability maps, critical speeds and boundaries
REGIME = "the balanced regime of a circular race (rotor on the axis)"

GROUPS = ("chi", "eps", "alpha", "rho1", "rho2", "delta_n", "delta_b")


def scene_si(disk_mass, stiffness, damping, eccentricity, phase, ball_mass, n_balls,
             r1, r2, ball_drag, speed, inertia_factor=1.0) -> Scene:
    """Model 000 in SI units; `speed` is a speed profile (rad/s)."""
    n_balls = _n_balls(n_balls)
    return Scene(
        RigidRotor(disk_mass, eccentricity, phase),
        speed,
        (
            Supports.isotropic(stiffness, damping),
            AutoBalancer(np.full(n_balls, float(ball_mass)), Race(r1, r2), ball_drag,
                         inertia_factor=inertia_factor),
        ),
    )


def groups_from_si(disk_mass, stiffness, damping, eccentricity, phase, ball_mass, n_balls,
                   r1, r2, ball_drag) -> dict:
    """The paper's dimensionless groups, plus the scales `Omega` (rad/s) and `r` (m)."""
    n_balls = _n_balls(n_balls)
    total = disk_mass + n_balls * ball_mass
    omega = np.sqrt(stiffness / total)
    r = 0.5 * (r1 + r2)
    return {
        "chi": ball_mass / disk_mass, "eps": eccentricity / r, "alpha": phase,
        "rho1": r1 / r, "rho2": r2 / r, "delta_n": damping / (total * omega),
        "delta_b": ball_drag / (ball_mass * omega), "Omega": omega, "r": r,
    }


def si_from_groups(groups, n_balls=2, disk_mass=1.0, Omega=1.0, r=None) -> dict:
    """SI parameters realising `groups` for a chosen disk mass, `Omega` and scale `r`
    (default `r = (rho1 + rho2)/2`, so that the race semi-axes are `rho1, rho2`)."""
    g = groups
    r = 0.5 * (g["rho1"] + g["rho2"]) if r is None else r
    ball_mass = g["chi"] * disk_mass
    total = disk_mass + n_balls * ball_mass
    return {
        "disk_mass": disk_mass, "stiffness": total * Omega**2,
        "damping": g["delta_n"] * total * Omega, "eccentricity": g["eps"] * r,
        "phase": g["alpha"], "ball_mass": ball_mass, "n_balls": n_balls,
        "r1": g["rho1"] * r, "r2": g["rho2"] * r, "ball_drag": g["delta_b"] * ball_mass * Omega,
    }


def scene_from_groups(chi, eps, alpha, rho1, rho2, delta_n, delta_b, nu=1.5, nu_dot=0.0,
                      nu0=0.0, n_balls=2, K=1.0, with_balancer=True) -> Scene:
    """Model 000 in the paper's dimensionless units (eq. 7). `nu_dot != 0` means a
    run-up `nu(tau) = nu0 + nu_dot tau`; otherwise constant speed `nu`.
    `with_balancer=False` is the same rotor (same shaft, damping, imbalance) with the
    balancer absent: the plain resonance of the paper's Fig. 3, curve 3."""
    n_balls = _n_balls(n_balls)
    speed = RunUp(nu0, nu_dot) if nu_dot != 0 else ConstantSpeed(nu)
    supports = Supports.isotropic(1.0 + n_balls * chi, delta_n * (1.0 + n_balls * chi))
    if not with_balancer:
        return Scene(RigidRotor(1.0, eps, alpha), speed, (supports,))
    balancer = AutoBalancer(jnp.full(n_balls, chi), Race(rho1, rho2), delta_b * chi,
                            inertia_factor=K)
    return Scene(RigidRotor(1.0, eps, alpha), speed, (supports, balancer))


def _n_balls(n):
    if int(n) != n or n < 1:
        raise InputError(f"n_balls must be a positive integer, got {n!r}")
    return int(n)


def balanced_reference(p):
    """The balanced regime of a circular race at constant speed `nu` as the preset's
    reference motion: Newton from the balanced configuration (eq. 14: the balls at
    `alpha + pi -+ arccos(eps / (n chi))` for two balls). Traceable in the
    parameters; an elliptic race (`rho1 != rho2`) or an imbalance beyond the balls'
    capacity has none (`NoReference`, with the reason)."""
    from ..analysis import NoReference, StationaryRegime
    from ..models import balancing_angles

    rho1, rho2 = p["rho1"], p["rho2"]
    n = int(p["n_balls"])
    c = p["eps"] / (n * p["chi"] * rho1)
    scene = scene_from_groups(p["chi"], p["eps"], p["alpha"], rho1, rho2, p["delta_n"],
                              p["delta_b"], nu=p["nu"], n_balls=n, K=p["K"])
    if is_concrete(rho1 - rho2) and rho1 != rho2:
        return NoReference(scene, "an elliptic race (rho1 != rho2) has no balanced regime (paper eqs. "
                                  "15-17); use `rotorjax steady` to list its regimes", label=REGIME)
    if is_concrete(c) and c > 1:
        return NoReference(scene, f"eps = {p['eps']} exceeds the balls' capacity n chi rho = "
                                  f"{n * p['chi'] * rho1}: there is no balanced regime", label=REGIME)
    psi = p["alpha"] + balancing_angles(n, c)
    return StationaryRegime(scene, jnp.concatenate([jnp.zeros(2), psi]), label=REGIME, balanced=True)


def balanced_regime(p):
    """The balanced regime of a circular race at speed `nu` (a `Regime`, traceable in
    the parameters; see `balanced_reference`)."""
    from ..analysis import regime

    return regime(balanced_reference(p))


def build(p) -> Setup:
    """The scene at `p` (a run-up where `nu_dot != 0`), the balls at rest relative to
    the rotor at `psi1 + j psi_spacing` from the imbalance, and the run's length (to
    `nu_end` for a run-up, else 200)."""
    # traced parameters (a map or a boundary sweeping them) build the reference only:
    # the run's initial state and length need concrete values
    run_up = is_concrete(p["nu_dot"]) and p["nu_dot"] != 0
    scene = scene_from_groups(
        p["chi"], p["eps"], p["alpha"], p["rho1"], p["rho2"], p["delta_n"], p["delta_b"],
        nu=p["nu"], nu_dot=p["nu_dot"] if run_up else 0.0, nu0=p["nu0"], n_balls=p["n_balls"], K=p["K"],
    )
    n = p["n_balls"]
    # Balls start at rest relative to the rotor at polar angles `psi1 + j psi_spacing`
    # measured from the imbalance direction `alpha` (default: near the opposite side).
    y0 = t_end = None
    race = scene.find(AutoBalancer).race
    if all(is_concrete(v) for v in (p["alpha"], p["psi1"], p["psi_spacing"], p["nu_end"], p["nu0"], race.r1,
                                    race.r2, race.center)):
        polar = p["alpha"] + p["psi1"] + np.arange(n) * p["psi_spacing"]
        y0 = scene.rest_state(weights_at(polar, race))
        t_end = 200.0
        if run_up:
            t_end = (p["nu_end"] - p["nu0"]) / p["nu_dot"]
            if t_end <= 0:
                raise InputError(
                    f"nu_end ({p['nu_end']}) must be beyond nu0 ({p['nu0']}) in the direction of nu_dot"
                )
    return Setup(scene, y0, t_end, reference=balanced_reference(p))


def _build(p):
    """`(scene, y0, t_end)` (the tuple `build` returned before `Setup`)."""
    return tuple(build(p))


PRESET = Preset(
    name="elliptic-abb",
    source="model 000: Bykov & Kovachev, Vestnik SPbU Math. Mech. 2019",
    defaults={
        "chi": 0.02, "eps": 0.04, "alpha": 0.6, "rho1": 1.28, "rho2": 1.2,
        "delta_n": 0.18, "delta_b": 40.0, "nu": 1.5, "nu_dot": 0.0, "nu0": 0.0,
        "nu_end": 4.0, "n_balls": 2, "K": 1.0, "psi1": np.pi - 0.1, "psi_spacing": 0.2,
    },
    build=build,
    describe_params={
        "chi": "ball mass / disk mass", "eps": "eccentricity / r", "alpha": "imbalance phase (rad)",
        "rho1": "race semi-axis 1 / r", "rho2": "race semi-axis 2 / r",
        "delta_n": "rotor damping c_n/((m+n m_b) Omega)", "delta_b": "ball drag c_b/(m_b Omega)",
        "nu": "speed / Omega (constant speed)", "nu_dot": "run-up rate (0: constant speed)",
        "nu0": "run-up start speed", "nu_end": "run-up end speed (sets t_end)",
        "n_balls": "number of balls", "K": "inertia factor (1: point masses, as the paper)",
        "psi1": "initial polar angle of ball 1 from the imbalance direction (rad)",
        "psi_spacing": "initial angular spacing of the balls (rad)",
    },
    units={"chi": "dimensionless", "eps": "dimensionless", "alpha": "rad", "rho1": "dimensionless",
           "rho2": "dimensionless", "delta_n": "dimensionless", "delta_b": "dimensionless",
           "nu": "dimensionless", "nu_dot": "dimensionless", "nu0": "dimensionless", "nu_end": "dimensionless",
           "n_balls": "count", "K": "dimensionless", "psi1": "rad", "psi_spacing": "rad"},
    domains={"chi": ">0", "eps": ">=0", "alpha": "any", "rho1": ">0", "rho2": ">0", "delta_n": ">=0",
             "delta_b": ">=0", "nu": ">0", "nu_dot": "any", "nu0": ">=0", "nu_end": ">0", "n_balls": "int[0,32]",
             "K": ">0", "psi1": "any", "psi_spacing": "any"},
    time_unit="1/Omega", length_unit="r = (r1+r2)/2",
    integer_keys=("n_balls",),
    speed_key="nu",
    steady_overrides={"nu_dot": 0.0},
    topology_keys=("n_balls",),
    # with rho2 = rho1: the balanced regime's boundary runs from nu = 1.001 (delta_n = 0.5) to delta_n -> 0
    box={"nu": (0.5, 4.0), "delta_n": (0.0, 0.5)},
)
