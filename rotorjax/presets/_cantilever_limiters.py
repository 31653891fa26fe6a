"""`cantilever-limiters`: model 004 (Azarov, Guskov, Panovko 2023), a cantilever
flexible rotor with a heavy disk, Voigt internal friction and three visco-elastic
limiters with Coulomb friction around the disk.

Units (eq. 7): length `l = 0.7 m`, mass the disk's `M = 2.45 kg`, time
`T* = sqrt(M l^3 / EI) = 0.0226 s`. Defaults are the paper's base parameters; the
groups `mu_R`, `beta`, `d_ratio` come from its geometry (`groups_from_si`).
"""

import numpy as np

from .._errors import InputError
from ..models import CantileverScene, Limiters
from ..models._cantilever import PAPER_SI, CantileverRotor, groups_from_si
from ._base import Preset, Setup

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


def build_scene(p) -> CantileverScene:
    return CantileverScene(build_rotor(p), p["N"], eps=p["eps"], phase=p["phase"], gamma=p["gamma"],
                           limiters=build_limiters(p), n_modes=p["n_modes"] or None)


def initial_state(scene, p):
    """Straight-line rotation (static sag under weight) plus a lateral kick of
    `perturbation` (dimensionless velocity of the disk along y)."""
    y0 = scene.rest_state()
    n = scene.n_coords
    return y0.at[n:2 * n].add(p["perturbation"] * scene.disk[1])


def build(p) -> Setup:
    """The scene, straight-line rotation with a kick, `revolutions` turns; extras:
    `events` (locate the contacts exactly), `revolutions`, `saves_per_revolution`
    (40), `analysis_revolutions` (the paper's window: the last 300 turns) and the
    limiters' `clearance`."""
    if not p["N"] > 0:
        raise InputError(f"N (spin speed) must be > 0: runs are measured in revolutions; got {p['N']}")
    if p["revolutions"] < 1:
        raise InputError(f"revolutions must be >= 1, got {p['revolutions']}")
    scene = build_scene(p)
    return Setup(scene, initial_state(scene, p), 2 * np.pi / p["N"] * p["revolutions"],
                 extras={"events": bool(p["events"]), "revolutions": int(p["revolutions"]),
                         "saves_per_revolution": 40, "analysis_revolutions": 300, "clearance": p["chi"]})


def _build(p):
    """`(scene, y0, t_end)` (the tuple `build` returned before `Setup`)."""
    return tuple(build(p))


def hopf(p, lo, hi, n_scan=80, progress=True) -> dict:
    """Hopf points of straight-line rotation for `N` in `[lo, hi]` (the linearised
    rotor's eigenvalues, scan and bisection), each with its whirl direction and
    `dN_crit/d eta_e` (implicit function theorem), and the paper's fit
    `N_crit = 2.47 eta_e/eta_i + 1.64`; `"scan"` holds the margin scanned and
    `"present"` the plot's labels."""
    from ..analysis import hopf_points, hopf_speed_gradient

    rotor = build_rotor(p)
    points, scan = hopf_points(rotor.state_matrix, lo, hi, n_scan=n_scan, return_scan=True, progress=progress)

    def a_of(s, eta_e):
        return build_rotor(dict(p, eta_e=eta_e)).state_matrix(s)

    out = {"unit": "speed N and whirl frequency in 1/T*", "hopf_points": []}
    for h in points:
        _, fwd = rotor.whirl_direction(h.speed)
        d = h.as_dict()
        d.update({"N_crit": h.speed, "whirl_frequency": h.frequency,
                  "whirl": "forward" if bool(fwd) else "backward",
                  "dN_crit_d_eta_e": hopf_speed_gradient(a_of, h.speed, p["eta_e"])})
        out["hopf_points"].append(d)
    if points:
        out["N_crit"], out["whirl_frequency"] = points[0].speed, points[0].frequency
        ratio = p["eta_e"] / p["eta_i"] if p["eta_i"] > 0 else None
        out["eta_e_over_eta_i"] = ratio
        if ratio is not None:
            out["paper_fit"] = {"N_crit": 2.47 * ratio + 1.64, "formula": "N_crit = 2.47 eta_e/eta_i + 1.64"}
    out["scan"] = scan
    out["present"] = {
        "title": f"straight-line rotation, eta_i = {p['eta_i']:g}, eta_e = {p['eta_e']:g}",
        "speed_label": "spin speed N (units 1/T*)", "margin_label": "largest Re(lambda) (units 1/T*)",
        "extra_roots": [out["paper_fit"]["N_crit"]] if "paper_fit" in out else None,
        "extra_label": "paper's fit 2.47 eta_e/eta_i + 1.64",
        "sensitivity": ("dN_crit_d_eta_e", "dN/d eta_e"),
    }
    return out


def _limiter_part(attr):
    def where(scene):
        if scene.limiters is None:
            raise InputError("needs limiters (--set n_limiters=0 removed them)")
        return getattr(scene.limiters, attr)

    return where


#: the keys `bifurcation` sweeps, and the scene's leaf each one sets
SWEEPABLE = {"eps": lambda s: s.eps, "N": lambda s: s.N, "phase": lambda s: s.phase,
             "f_S": _limiter_part("friction"), "chi": _limiter_part("clearance"),
             "kappa": _limiter_part("stiffness"), "eta_S": _limiter_part("damping")}


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
    margin=lambda p: build_rotor(p).stability_margin(p["N"]),
    regime="straight-line rotation (no contact)",
    topology_keys=("n_limiters", "n_elements", "n_modes", "events"),
    kind="contact",
    # the Hopf curve of straight-line rotation runs from N = 13.2 (eta_e = 0) to 14.8 (eta_e = 0.06)
    box={"N": (1.0, 40.0), "eta_e": (0.0, 0.06)},
    hopf=hopf,
    sweepable=SWEEPABLE,
)
