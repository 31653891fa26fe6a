"""`cantilever-limiters`: model 004 (Azarov, Guskov, Panovko 2023), a cantilever
flexible rotor with a heavy disk, Voigt internal friction and three visco-elastic
limiters with Coulomb friction around the disk.

Units (eq. 7): length `l = 0.7 m`, mass the disk's `M = 2.45 kg`, time
`T* = sqrt(M l^3 / EI) = 0.0226 s`. Defaults are the paper's base parameters; the
groups `mu_R`, `beta`, `d_ratio` come from its geometry (`groups_from_si`).

The scene is a `RotorScene` composition (`rotorjax.models.cantilever_scene`): the
cantilever's FE shaft reduced to `n_modes` modes, with `Unbalance`,
`InternalDamping`, `ExternalDamping`, `DiskDamping`, `Gravity` (when `gamma` is not
0), `LimitersAt` and a `NodeProbe` (the disk outputs) at the disk.
"""

import jax.numpy as jnp
import numpy as np

from .._errors import InputError
from ..models import Limiters, LimitersAt, RotorScene, Unbalance, cantilever_scene
from ..models import DOFS_PER_NODE
from ..models._cantilever import PAPER_SI, CantileverRotor, groups_from_si
from ..models._validate import is_concrete
from ._base import Preset, PublishedSpeeds, Setup

#: the reference motion of stability maps, Hopf points and boundaries
REGIME = "straight-line rotation (no contact)"
#: the paper's fit of the Hopf speed, drawn and reported beside the computed one
FIT = "paper's fit 2.47 eta_e/eta_i + 1.64"
FORMULA = "N_crit = 2.47 eta_e/eta_i + 1.64"

_G = groups_from_si(**{k: PAPER_SI[k] for k in ("l", "d", "D", "a", "E", "rho")})


def build_rotor(p) -> CantileverRotor:
    return CantileverRotor(p["mu_R"], p["beta"], p["d_ratio"], p["eta_i"], p["eta_e"], p["eta_Dxi"],
                           p["eta_Dtheta"], n_elements=p["n_elements"])


def build_limiters(p):
    n = p["n_limiters"]
    if n == 0:
        return None
    angles = p["alpha1"] + 2 * np.pi / n * np.arange(n)
    return Limiters(angles, p["chi"], p["kappa"], p["eta_S"], p["f_S"], smoothing=p["smoothing"])


def build_scene(p, rotor=None) -> RotorScene:
    """The simulated scene: the composition reduced to `n_modes` modes, with the limiters."""
    rotor = build_rotor(p) if rotor is None else rotor
    return cantilever_scene(rotor, p["N"], eps=p["eps"], phase=p["phase"], gamma=p["gamma"],
                            limiters=build_limiters(p), n_modes=p["n_modes"] or None)


def disk_rows(scene):
    """The disk's `(x, y)` as a linear map of the scene's shaft coordinates."""
    node = _component(scene, Unbalance).node
    n = scene.n_shaft
    return scene.expand(jnp.eye(n))[DOFS_PER_NODE * node:DOFS_PER_NODE * node + 2]


def initial_state(scene, p):
    """Straight-line rotation (static sag under weight) plus a lateral kick of
    `perturbation` (dimensionless velocity of the disk along y)."""
    y0 = scene.rest_state()
    n = scene.n_shaft
    lin = scene.linear_matrices(scene.speed.speed(0.0))
    sag = jnp.linalg.solve(lin.K, scene.F0)
    return y0.at[:n].set(sag).at[n:2 * n].add(p["perturbation"] * disk_rows(scene)[1])


def build(p) -> Setup:
    """The scene, straight-line rotation with a kick, `revolutions` turns; extras:
    `events` (locate the contacts exactly), `revolutions`, `saves_per_revolution`
    (40), `analysis_revolutions` (the paper's window: the last 300 turns) and the
    limiters' `clearance`."""
    if is_concrete(p["N"]) and not p["N"] > 0:
        raise InputError(f"N (spin speed) must be > 0: runs are measured in revolutions; got {p['N']}")
    if p["revolutions"] < 1:
        raise InputError(f"revolutions must be >= 1, got {p['revolutions']}")
    rotor = build_rotor(p)
    scene = build_scene(p, rotor)
    published = ()
    if is_concrete(p["eta_e"]) and is_concrete(p["eta_i"]) and paper_fit(p["eta_e"], p["eta_i"]) is not None:
        published = (PublishedSpeeds(FIT, (paper_fit(p["eta_e"], p["eta_i"]),), formula=FORMULA,
                                     details={"eta_e_over_eta_i": p["eta_e"] / p["eta_i"]}),)
    y0 = initial_state(scene, p) if is_concrete(p["N"]) else None
    t_end = 2 * np.pi / p["N"] * p["revolutions"] if is_concrete(p["N"]) else None
    return Setup(scene, y0, t_end,
                 extras={"events": bool(p["events"]), "revolutions": int(p["revolutions"]),
                         "saves_per_revolution": 40, "analysis_revolutions": 300, "clearance": p["chi"]},
                 reference=straight_running(p, rotor), published=published)


def _build(p):
    """`(scene, y0, t_end)` (the tuple `build` returned before `Setup`)."""
    return tuple(build(p))


def straight_running(p, rotor=None):
    """Straight-line rotation at `N` as the preset's reference motion: the linear
    equations of the full finite-element composition (all dofs: the Hopf point
    N_crit = 13.904 of the paper's base case; the limiters do not touch a straight
    shaft)."""
    from ..analysis import StraightRunning

    rotor = build_rotor(p) if rotor is None else rotor
    scene = cantilever_scene(rotor, p["N"], eps=p["eps"], phase=p["phase"], gamma=p["gamma"])
    return StraightRunning(scene, scene.speed.constant, label=REGIME)


def paper_fit(eta_e, eta_i):
    """Azarov, Guskov, Panovko's fit of the Hopf speed of straight-line rotation,
    `N_crit = 2.47 eta_e/eta_i + 1.64` (None without internal friction)."""
    return None if not eta_i > 0 else 2.47 * eta_e / eta_i + 1.64


def _component(scene, kind):
    """The scene's component of type `kind` (None if absent)."""
    return next((c for c in scene.components if isinstance(c, kind)), None)


def limiters_of(scene):
    """The scene's `Limiters` (inside its `LimitersAt`), or None."""
    part = _component(scene, LimitersAt)
    return None if part is None else part.limiters


#: the keys `bifurcation` sweeps, and the path of the scene's leaf each one sets
#: (`rotorjax.models.leaf_at`: data, into the composition's components)
SWEEPABLE = {"eps": "components[Unbalance].magnitude", "N": "speed.constant",
             "phase": "components[Unbalance].phase", "f_S": "components[LimitersAt].limiters.friction",
             "chi": "components[LimitersAt].limiters.clearance",
             "kappa": "components[LimitersAt].limiters.stiffness",
             "eta_S": "components[LimitersAt].limiters.damping"}


PRESET = Preset(
    name="cantilever-limiters",
    source="Azarov, Guskov, Panovko 2023: cantilever rotor, internal friction, discrete limiters",
    defaults={
        "N": 15.0, "eps": 0.00142, "phase": 0.0, "eta_i": 0.005, "eta_e": 0.025, "eta_Dxi": 0.0025,
        "eta_Dtheta": 0.05, "mu_R": _G["mu_R"], "beta": _G["beta"], "d_ratio": _G["d_ratio"], "gamma": 0.0,
        "chi": 0.0107, "kappa": 850.0, "eta_S": 0.06, "f_S": 0.1, "n_limiters": 3, "alpha1": np.pi / 3,
        "n_elements": 8, "n_modes": 6, "events": 0, "smoothing": 1e-6, "revolutions": 600,
        "perturbation": 1e-3,
    },
    build=build,
    describe_params={
        "N": "spin speed (units 1/T*)", "eps": "eccentricity e/l", "phase": "unbalance phase (rad)",
        "eta_i": "internal (Voigt) damping", "eta_e": "external shaft damping",
        "eta_Dxi": "disk damping", "eta_Dtheta": "disk angular damping", "mu_R": "shaft/disk mass",
        "beta": "disk inertia B/(M l^2)", "d_ratio": "shaft diameter / length",
        "gamma": "weight M g l^2/EI (0: neglected, as in the paper)", "chi": "limiter clearance h/l",
        "kappa": "limiter stiffness k l^3/EI", "eta_S": "limiter damping", "f_S": "limiter friction",
        "n_limiters": "limiters, equally spaced (0: none)", "alpha1": "angle of the first limiter (rad)",
        "n_elements": "shaft elements", "n_modes": "modes kept in simulations (0: all dofs)",
        "events": "1: event-located exact contact, 0: smoothed contact",
        "smoothing": "regularisation length of the smoothed contact (units l)",
        "revolutions": "run length in revolutions", "perturbation": "initial disk velocity kick",
    },
    units={"N": "dimensionless", "eps": "dimensionless", "phase": "rad", "eta_i": "dimensionless",
           "eta_e": "dimensionless", "eta_Dxi": "dimensionless", "eta_Dtheta": "dimensionless",
           "mu_R": "dimensionless", "beta": "dimensionless", "d_ratio": "dimensionless",
           "gamma": "dimensionless", "chi": "dimensionless", "kappa": "dimensionless",
           "eta_S": "dimensionless", "f_S": "dimensionless", "n_limiters": "count", "alpha1": "rad",
           "n_elements": "count", "n_modes": "count", "events": "flag", "smoothing": "dimensionless",
           "revolutions": "count", "perturbation": "dimensionless"},
    domains={"N": ">0", "eps": ">=0", "phase": "any", "eta_i": ">=0", "eta_e": ">=0", "eta_Dxi": ">=0",
             "eta_Dtheta": ">=0", "mu_R": ">=0", "beta": ">=0", "d_ratio": ">0", "gamma": "any", "chi": ">0",
             "kappa": ">0", "eta_S": ">=0", "f_S": ">=0", "n_limiters": "int[0,64]", "alpha1": "any",
             "n_elements": "int[1,200]", "n_modes": "int[0,800]", "events": "{0,1}", "smoothing": ">0",
             "revolutions": "int[1,1000000]", "perturbation": "any"},
    time_unit="T* = sqrt(M l^3 / EI) (0.0226 s)", length_unit="l (0.7 m)",
    integer_keys=("n_limiters", "n_elements", "n_modes", "events", "revolutions"),
    speed_key="N",
    topology_keys=("n_limiters", "n_elements", "n_modes", "events"),
    kind="contact",
    # the Hopf curve of straight-line rotation runs from N = 13.2 (eta_e = 0) to 14.8 (eta_e = 0.06)
    box={"N": (1.0, 40.0), "eta_e": (0.0, 0.06)},
    sweepable=SWEEPABLE,
    hopf_sensitivity="eta_e",
)
