"""Model 001: planar rotor on anisotropic visco-elastic supports with a passive
auto-balancer.

Filimonikhina, Gutsul, Dumenko, Nevdakha, EEJET 2017 (seed 001).

Rotor mass `M`, point imbalance `m0` at radius `R`, `N` weights of mass `m` (inertia
factor `K`) on a circle of radius `R` about the rotor axis, drag `b_w` on their
relative motion, supports `kx < ky`, `bx, by`. With `Ms = M + N m + m0`,
`wx = sqrt(kx/Ms)`, `L = N m R / Ms`, `tau = wx t`, `xi = x/L`, `eta = y/L`:

    n = w/wx, n_eta = wy/wx, mu_xi = bx/(2 Ms wx), mu_eta = by/(2 Ms wx),
    sigma = 1/N, c = m0/(N m), eps = N m/(K Ms), mu_w = b_w/(K m wx),

    xi'' + 2 mu_xi xi' + xi - sigma sum(phi'' sin phi + phi'^2 cos phi) - c n^2 cos n tau = 0
    eta'' + 2 mu_eta eta' + n_eta^2 eta + sigma sum(phi'' cos phi - phi'^2 sin phi) - c n^2 sin n tau = 0
    phi'' + mu_w (phi' - n) + eps(-xi'' sin phi + eta'' cos phi) = 0.

The SI scene with `Ms = 1, wx = 1, L = 1` is exactly these equations:
`m = K eps/N`, `R = 1/(K eps)`, `m0 = c K eps`, `kx = 1`, `ky = n_eta^2`,
`bx = 2 mu_xi`, `by = 2 mu_eta`, `b_w = mu_w K m`. The imbalance `m0` at `R` is the
rotor body's eccentricity: mass `M + m0`, eccentricity `m0 R/(M + m0)`. The weights'
coordinates are their angles relative to the rotor, `psi_j = phi_j - n tau`.
"""

import jax
import numpy as np

from .._errors import InputError
from ..models import AutoBalancer, ConstantSpeed, Race, RigidRotor, RunUp, Scene, Supports
from ..models import balancing_angles
from ._base import Preset, PublishedSpeeds, Setup
from ..models._validate import is_concrete

GROUPS = ("n_eta", "mu_xi", "mu_eta", "sigma", "c", "eps", "mu_w")


#: the reference motion of stability maps, critical speeds and boundaries
REGIME = "the main motion (largest Floquet exponent)"
#: the paper's own estimate, drawn beside the computed critical speeds
CRITERION = "paper's criterion p(n) = 0 (eq. 18)"


def scene_si(rotor_mass, imbalance_mass, radius, n_weights, weight_mass, kx, ky, bx, by,
             weight_drag, speed, inertia_factor=1.0) -> Scene:
    """Model 001 in SI units (`radius` is both the imbalance's and the race's)."""
    body = rotor_mass + imbalance_mass
    return Scene(
        RigidRotor(body, imbalance_mass * radius / body, 0.0),
        speed,
        (
            Supports(kx, ky, bx, by),
            AutoBalancer(np.full(int(n_weights), float(weight_mass)), Race.circular(radius),
                         weight_drag, inertia_factor=inertia_factor),
        ),
    )


def groups_from_si(rotor_mass, imbalance_mass, radius, n_weights, weight_mass, kx, ky, bx, by,
                   weight_drag, inertia_factor=1.0) -> dict:
    """The paper's groups (eq. 7), plus the scales `wx` (rad/s) and `L` (m)."""
    K, N, m = inertia_factor, n_weights, weight_mass
    ms = rotor_mass + N * m + imbalance_mass
    wx = np.sqrt(kx / ms)
    return {
        "n_eta": np.sqrt(ky / ms) / wx, "mu_xi": bx / (2 * ms * wx), "mu_eta": by / (2 * ms * wx),
        "sigma": 1.0 / N, "c": imbalance_mass / (N * m), "eps": N * m / (K * ms),
        "mu_w": weight_drag / (K * m * wx), "wx": wx, "L": N * m * radius / ms,
    }


def n_weights_from_sigma(sigma) -> int:
    if isinstance(sigma, jax.core.Tracer):
        raise InputError("sigma = 1/N sets the number of weights (the topology): it cannot be "
                         "swept or differentiated; build one scene per N")
    n = int(round(1.0 / sigma)) if sigma > 0 else 0
    if n < 1 or abs(1.0 / sigma - n) > 1e-9:
        raise InputError(f"sigma must be 1/N for an integer number of weights N, got {sigma!r}")
    return n


def si_from_groups(groups, K=1.0, Ms=1.0, wx=1.0, L=1.0) -> dict:
    """SI parameters realising `groups` for chosen `Ms` (kg), `wx` (rad/s), `L` (m)."""
    g = groups
    N = n_weights_from_sigma(g["sigma"])
    if not isinstance(g["eps"], jax.core.Tracer) and not 0 < g["eps"] < 1:
        raise InputError(f"eps = N m/(K Ms) must be in (0, 1), got {g['eps']}")
    nm = K * g["eps"] * Ms
    m = nm / N
    m0 = g["c"] * nm
    M = Ms - nm - m0
    if not isinstance(M, jax.core.Tracer) and M <= 0:
        raise InputError(
            f"eps={g['eps']}, c={g['c']}, K={K} leave no rotor mass: need K eps (1 + c) < 1"
        )
    return {
        "rotor_mass": M, "imbalance_mass": m0, "radius": L * Ms / nm, "n_weights": N,
        "weight_mass": m, "kx": Ms * wx**2, "ky": Ms * (g["n_eta"] * wx) ** 2,
        "bx": 2 * g["mu_xi"] * Ms * wx, "by": 2 * g["mu_eta"] * Ms * wx,
        "weight_drag": g["mu_w"] * K * m * wx, "inertia_factor": K,
    }


def scene_from_groups(n_eta, mu_xi, mu_eta, sigma, c, eps, mu_w, n=3.0, n_dot=0.0, n0=0.0,
                      K=1.0) -> Scene:
    """Model 001 in the paper's dimensionless units; `n_dot != 0` is a run-up
    `n(tau) = n0 + n_dot tau` (the paper studies constant speed)."""
    groups = dict(n_eta=n_eta, mu_xi=mu_xi, mu_eta=mu_eta, sigma=sigma, c=c, eps=eps, mu_w=mu_w)
    si = si_from_groups(groups, K=K)
    speed = RunUp(n0, n_dot) if n_dot != 0 else ConstantSpeed(n)
    si.pop("inertia_factor")
    return scene_si(**si, speed=speed, inertia_factor=K)


def main_motion_angles(N: int, c: float):
    """Weight angles (relative to the rotor) of a main motion: the weights cancel the
    imbalance `c` (`sigma sum e^{i psi} + c = 0`); see `models.balancing_angles`."""
    return balancing_angles(N, c)


def criterion_polynomial(n, n_eta, mu_xi, mu_eta):
    """The paper's empirical auto-balancing criterion, eq. (18): balancing where
    `p(n) < 0`. Fast and approximate: it ignores `eps` and `mu_w`."""
    n2 = np.asarray(n, dtype=np.float64) ** 2
    e2 = n_eta**2
    return (1 - n2) * (e2 - n2) * (1 + e2 - 2 * n2) + 4 * n2 * (
        (1 - n2) * mu_eta**2 + (e2 - n2) * mu_xi**2
    )


def main_motion_reference(groups, n, K=1.0, rtol=1e-10, atol=1e-12):
    """The main motion at constant speed `n` as the preset's reference motion (a
    `PeriodicOrbit`, traceable in `n` and in the groups). In the fixed frame with the
    weights' angles relative to the rotor, the main motion is a constant state of a
    system with period `2 pi / n`."""
    from ..analysis import PeriodicOrbit

    scene = scene_from_groups(**groups, n=n, K=K)
    N = n_weights_from_sigma(groups["sigma"])
    y0 = scene.rest_state(main_motion_angles(N, groups["c"]))
    return PeriodicOrbit(scene, y0, 2 * np.pi / n, label=REGIME, rtol=rtol, atol=atol)


def main_motion_floquet(groups, n, K=1.0, rtol=1e-10, atol=1e-12):
    """Floquet analysis of the main motion at speed `n` (pure, traceable in `n` and
    in the groups; see `main_motion_reference`)."""
    from ..analysis import floquet_of

    return floquet_of(main_motion_reference(groups, n, K, rtol, atol))


def criterion_roots(n_eta, mu_xi, mu_eta, lo=0.0, hi=None):
    """Positive roots of the criterion polynomial in `n` (a cubic in `n^2`)."""
    e2 = n_eta**2
    # p as a polynomial in s = n^2: (1-s)(e2-s)(1+e2-2s) + 4s[(1-s) me^2 + (e2-s) mx^2]
    one_minus = np.poly1d([-1.0, 1.0])
    e2_minus = np.poly1d([-1.0, e2])
    poly = one_minus * e2_minus * np.poly1d([-2.0, 1 + e2]) + np.poly1d([4.0, 0.0]) * (
        one_minus * mu_eta**2 + e2_minus * mu_xi**2)
    s = poly.roots
    s = np.real(s[(np.abs(np.imag(s)) < 1e-12) & (np.real(s) > 0)])
    n = np.sort(np.sqrt(s))
    hi = np.inf if hi is None else hi
    return [float(x) for x in n if lo <= x <= hi]


def build(p) -> Setup:
    """The scene at `p` (a run-up where `n_dot != 0`), the weights near the main
    motion (deviated by `perturbation`), and the run's length (to `n_end` for a
    run-up, else 200)."""
    N = n_weights_from_sigma(p["sigma"])
    # traced parameters (a map or a boundary sweeping them) build the reference only
    run_up = is_concrete(p["n_dot"]) and p["n_dot"] != 0
    scene = scene_from_groups(
        p["n_eta"], p["mu_xi"], p["mu_eta"], p["sigma"], p["c"], p["eps"], p["mu_w"],
        n=p["n"], n_dot=p["n_dot"] if run_up else 0.0, n0=p["n0"], K=p["K"],
    )
    angles = main_motion_angles(N, p["c"]) + p["perturbation"] * np.cos(np.arange(N) + 1.0)
    y0 = scene.rest_state(angles)
    t_end = None
    if all(is_concrete(p[k]) for k in ("n_end", "n0")):
        t_end = 200.0
        if run_up:
            t_end = (p["n_end"] - p["n0"]) / p["n_dot"]
            if t_end <= 0:
                raise InputError(f"n_end ({p['n_end']}) must be beyond n0 ({p['n0']}) along n_dot")
    published = ()
    if all(is_concrete(p[k]) for k in ("n_eta", "mu_xi", "mu_eta")):
        published = (PublishedSpeeds(CRITERION, tuple(criterion_roots(p["n_eta"], p["mu_xi"], p["mu_eta"]))),)
    return Setup(scene, y0, t_end, reference=main_motion_reference({k: p[k] for k in GROUPS}, p["n"], p["K"]),
                 published=published)


def _build(p):
    """`(scene, y0, t_end)` (the tuple `build` returned before `Setup`)."""
    return tuple(build(p))


PRESET = Preset(
    name="anisotropic-abb",
    source="model 001: Filimonikhina, Gutsul, Dumenko, Nevdakha, EEJET 2017",
    defaults={
        "n_eta": 7.0, "mu_xi": 0.25, "mu_eta": 0.5, "sigma": 0.5, "c": 0.5, "eps": 0.01,
        "mu_w": 0.5, "n": 3.0, "n_dot": 0.0, "n0": 0.0, "n_end": 10.0, "K": 1.0,
        "perturbation": 0.1,
    },
    build=build,
    describe_params={
        "n_eta": "wy/wx (support anisotropy)", "mu_xi": "bx/(2 Ms wx)", "mu_eta": "by/(2 Ms wx)",
        "sigma": "1/N (N weights)", "c": "m0/(N m) imbalance ratio", "eps": "N m/(K Ms)",
        "mu_w": "b_w/(K m wx) weight drag", "n": "speed / wx", "n_dot": "run-up rate (0: constant)",
        "n0": "run-up start speed", "n_end": "run-up end speed (sets t_end)",
        "K": "inertia factor (1 pendulum, 1.4 ball, 1.5 roller)",
        "perturbation": "initial deviation of the weights from the main motion (rad)",
    },
    units={"n_eta": "dimensionless", "mu_xi": "dimensionless", "mu_eta": "dimensionless",
           "sigma": "dimensionless", "c": "dimensionless", "eps": "dimensionless", "mu_w": "dimensionless",
           "n": "dimensionless", "n_dot": "dimensionless", "n0": "dimensionless", "n_end": "dimensionless",
           "K": "dimensionless", "perturbation": "rad"},
    domains={"n_eta": ">0", "mu_xi": ">=0", "mu_eta": ">=0", "sigma": "(0,1]", "c": ">=0", "eps": "(0,1)",
             "mu_w": ">=0", "n": ">0", "n_dot": "any", "n0": ">=0", "n_end": ">0", "K": ">0",
             "perturbation": "any"},
    time_unit="1/wx", length_unit="L = N m R / Ms",
    speed_key="n",
    topology_keys=("sigma",),
    # the paper's speed range and weight damping from nearly none to twice the default: three boundaries
    box={"n": (0.5, 10.0), "mu_w": (0.05, 1.0)},
    steady_overrides={"n_dot": 0.0},
)
