"""Fluid films as nonlinear forces: the plain journal bearing (short, finite, long)
and the squeeze-film damper, each a pure, differentiable function of the journal's
position and velocity and the shaft's speed.

**Frame** (as `rotorjax.models.PlainJournal`): `x` horizontal, `y` vertical, the
journal spinning counter-clockwise about `+z` at `speed`; `(x, y)` is the journal
centre's displacement from the bearing centre, `e = |(x, y)|`, `eps = e / c`. In
the frame of the line of centres (`e_r` along `(x, y)`, `e_t` a quarter turn
ahead) the film is `h = c (1 - eps cos(beta))`, `beta` from `e_r`, and the
Reynolds right side is `6 mu (speed dh/dtheta + 2 dh/dt) = 6 mu (a sin(beta) +
b cos(beta))`, with `a = e speed - 2 v_t`, `b = -2 v_r` (m/s; `v_r`, `v_t` the
journal's radial and tangential velocity). Write `rho = |(a, b)|` and `delta` the
direction of `(a, b)`: the film is converging (pressure positive) where
`sin(beta + delta) < 0`.

**Short bearing** (Ocvirk, `L/D -> 0`): `p = 3 mu (z^2 - L^2/4) (a sin + b cos) /
h^3`; half-Sommerfeld (pi-film) cavitation keeps the positive half,
`beta in (pi - delta, 2 pi - delta)`, so

    (F_r, F_t) = (mu R L^3 / (2 c^3)) int (a sin(beta) + b cos(beta)) (cos(beta), sin(beta))
                 / (1 - eps cos(beta))^3 dbeta

in closed form: with the Sommerfeld substitution `cos(g) = (cos(beta) - eps) / (1 -
eps cos(beta))` (`g = beta + 2 atan(eps' sin(beta) / (1 - eps' cos(beta)))`, `eps' =
eps / (1 + sqrt(1 - eps^2))`, continuous in `beta`) each integrand is a trigonometric
polynomial in `g`. The integrand vanishes at both ends of the arc, so the force is
continuously differentiable in the state and its linearisation at the static
equilibrium is exactly the short bearing's eight coefficients (Friswell et al.,
2010, sec. 5.5; `PlainJournal(method="short")`). The uncavitated (2 pi) film
integrates over the whole circle.

**Finite bearing**: Reynolds' equation in full is positively homogeneous in its right
side, so the force is `(12 mu R^4 rho / c^3) Fhat(eps, delta; L/D)`; `Fhat` is a
smooth interpolation of the project's finite-difference Reynolds solution with
Swift-Stieber cavitation (`rotorjax.models._finite_film`), valid for
`0.25 <= L/D <= 1`.

**Long bearing** (Sommerfeld, `L/D -> inf`, Gümbel cavitation): `d/dbeta(h^3 dp/dbeta)
= 6 mu R^2 (a sin + b cos)`, the pressure periodic and zero at the widest gap
(`beta = pi`) as in Sommerfeld's solution, negative pressures set to zero; the
pressure is in closed form, its positive part integrated by the trapezoid rule on
`n_long` points of the Sommerfeld angle (relative error ~1e-5: the pressure's kink
at the film's rupture).

**Squeeze-film damper**: the short film of a journal that does not spin (`speed =
0`: an orbiting, non-rotating ring), pi-film (cavitated) or 2 pi-film, with an
optional centring spring (a linear part).

The forces are finite for `eps < 1` and NaN at or beyond the wall: a run that
reaches it ends with an error naming the bearing and the time (`rotorjax.simulate`
callers; `film_eccentricity` reports the state).
"""

import math
import warnings

import equinox as eqx
import jax
import jax.numpy as jnp

from .._errors import PlausibilityWarning
from ._fe_rotor import DOFS_PER_NODE, follow
from ._rotor_component import AbstractBearingAt, node_index
from ._table import ComponentTable
from ._validate import InputError, as_param, check_choice, is_concrete, show

__all__ = ["JOURNAL_MODELS", "SFD_FILMS", "JournalBearing", "SqueezeFilmDamper", "film_force"]

JOURNAL_MODELS = ("short", "finite", "long")
SFD_FILMS = ("pi", "2pi")
#: the finite model's table covers these L/D
FINITE_RATIOS = (0.25, 1.0)
#: the short model is refused above this L/D, and warned about above SHORT_WARN
SHORT_MAX, SHORT_WARN = 1.0, 0.5
#: trapezoid points of the long bearing's pressure integral
N_LONG = 720


def _safe_unit(px, py, s0):
    """`(|p'|, p' / |p'|)` of `p' = p + (s, 0)`, `s = s0^3 / (s0^2 + |p|^2)`: the
    journal moved by at most `s0` (1e-9 c) near the centre, so that its centred
    position has a direction and the right derivatives (the film's cross-coupling
    there, a damper's damping; `ds/dp = 0` at the centre), and by `s0^3 / |p|^2`
    elsewhere (1e-25 c at eps = 0.1: nothing)."""
    px = px + s0 ** 3 / (s0 * s0 + px * px + py * py)
    r = jnp.sqrt(px * px + py * py)
    return r, px / r, py / r


def _direction(a, b):
    """`(rho, cos(delta), sin(delta))` of `(a, b)`; `delta = 0` where `(a, b) = 0`."""
    rho2 = a * a + b * b
    nz = rho2 > 0.0
    rho = jnp.sqrt(jnp.where(nz, rho2, 1.0))
    return jnp.where(nz, rho, 0.0), jnp.where(nz, a / rho, 1.0), jnp.where(nz, b / rho, 0.0)


def _sommerfeld_angle(eps, cb, sb):
    """`(cos g, sin g)` of the Sommerfeld angle of `beta` (given by its cos, sin)."""
    d = 1.0 - eps * cb
    return (cb - eps) / d, jnp.sqrt(1.0 - eps * eps) * sb / d


def _unwrap(eps, cb, sb):
    """`g - beta`, continuous in `beta`."""
    ep = eps / (1.0 + jnp.sqrt(1.0 - eps * eps))
    return 2.0 * jnp.arctan2(ep * sb, 1.0 - ep * cb)


def _short_integrals(eps, cd, sd, full):
    """`(I_sc, I_cc, I_ss)`: the integrals of `(sin cos, cos^2, sin^2) / (1 - eps
    cos)^3` over the converging arc `(pi - delta, 2 pi - delta)` (or the whole circle)."""
    s = 1.0 - eps * eps
    if full:
        return jnp.zeros_like(eps), math.pi * (1.0 + 2.0 * eps * eps) / s ** 2.5, math.pi / s ** 1.5
    # arc ends: beta1 = pi - delta (cos = -cos d, sin = sin d), beta2 = beta1 + pi
    c1, s1 = -cd, sd
    c2, s2 = cd, -sd
    cg1, sg1 = _sommerfeld_angle(eps, c1, s1)
    cg2, sg2 = _sommerfeld_angle(eps, c2, s2)
    dg = math.pi + _unwrap(eps, c2, s2) - _unwrap(eps, c1, s1)   # g2 - g1
    # antiderivatives in g: sin(2g) = 2 sin cos
    i_cc = (0.5 + eps * eps) * dg + 0.5 * (sg2 * cg2 - sg1 * cg1) + 2.0 * eps * (sg2 - sg1)
    i_ss = 0.5 * dg - 0.5 * (sg2 * cg2 - sg1 * cg1)
    i_sc = 0.5 * (sg2 * sg2 - sg1 * sg1) - eps * (cg2 - cg1)
    return i_sc / s ** 2, i_cc / s ** 2.5, i_ss / s ** 1.5


def _short_local(eps, a, b, viscosity, length, radius, clearance, full):
    _, cd, sd = _direction(a, b)
    i_sc, i_cc, i_ss = _short_integrals(eps, cd, sd, full)
    k0 = viscosity * radius * length ** 3 / (2.0 * clearance ** 3)
    return k0 * (a * i_sc + b * i_cc), k0 * (a * i_ss + b * i_sc)


def _long_local(eps, a, b, viscosity, length, radius, clearance, n):
    """The long bearing's film force `(F_r, F_t)` (module docstring)."""
    s = 1.0 - eps * eps
    g = jnp.linspace(0.0, 2.0 * math.pi, n, endpoint=False)   # Sommerfeld angle, g = 0 at the thinnest film
    cg, sg = jnp.cos(g), jnp.sin(g)
    # beta from g (the inverse map), and h / c = s / (1 + eps cos g)
    cb, sb = (cg + eps) / (1.0 + eps * cg), jnp.sqrt(s) * sg / (1.0 + eps * cg)
    # h^3 p' = 6 mu R^2 (-a cos + b sin + C1) / c^3 ... p' over beta; in g, dbeta = sqrt(s) / (1 + eps cos g) dg
    # and 1 / (1 - eps cos beta)^3 = (1 + eps cos g)^3 / s^3: p'(g) = 6 mu R^2 / c^3 (.) (1 + eps cos g)^2 / s^2.5
    w = (1.0 + eps * cg) ** 2 / s ** 2.5
    # C1 from periodicity: int (-a cos beta + b sin beta + C1) w dg = 0 (the sin beta term is odd in g)
    c1 = a * jnp.mean(cb * w) / jnp.mean(w)
    dp = (-a * cb + b * sb + c1) * w
    # p(g) = int_pi^g p' dg: cumulative trapezoid on the periodic grid, shifted to 0 at g = pi
    step = 2.0 * math.pi / n
    cum = jnp.concatenate([jnp.zeros(1), jnp.cumsum(0.5 * (dp[1:] + dp[:-1]) * step)])
    p = cum - cum[n // 2]
    p = 6.0 * viscosity * radius ** 2 / clearance ** 3 * jnp.maximum(p, 0.0)
    # F = -R L int p (cos beta, sin beta) dbeta, dbeta = sqrt(s) / (1 + eps cos g) dg
    jac = jnp.sqrt(s) / (1.0 + eps * cg)
    fr = -radius * length * jnp.sum(p * cb * jac) * step
    ft = -radius * length * jnp.sum(p * sb * jac) * step
    return fr, ft


def _finite_local(eps, a, b, viscosity, length, radius, clearance):
    from ._finite_film import finite_film_force  # noqa: PLC0415 (its table is loaded when first used)

    rho, cd, sd = _direction(a, b)
    delta = jnp.arctan2(sd, cd)
    fhat = finite_film_force(eps, delta, length / (2.0 * radius))
    scale = 12.0 * viscosity * radius ** 4 * rho / clearance ** 3
    return scale * fhat[0], scale * fhat[1]


def film_force(u, v, speed, viscosity, length, diameter, clearance, model="short"):
    """The film force on the journal (N, global `(x, y)`) at displacement `u` (m,
    (2,)) and velocity `v` (m/s, (2,)) from the bearing centre, the journal spinning
    at `speed` (rad/s). `model`: "short" (pi-film), "short-2pi" (uncavitated),
    "finite", "long" (module docstring). NaN where `|u| >= clearance`."""
    radius = 0.5 * diameter
    e, cr, sr = _safe_unit(u[0], u[1], 1e-9 * clearance)
    eps = e / clearance
    v_r = cr * v[0] + sr * v[1]
    v_t = -sr * v[0] + cr * v[1]
    a, b = e * speed - 2.0 * v_t, -2.0 * v_r
    if model in ("short", "short-2pi"):
        fr, ft = _short_local(eps, a, b, viscosity, length, radius, clearance, model == "short-2pi")
    elif model == "finite":
        fr, ft = _finite_local(eps, a, b, viscosity, length, radius, clearance)
    elif model == "long":
        fr, ft = _long_local(eps, a, b, viscosity, length, radius, clearance, N_LONG)
    else:
        raise InputError(f"model must be one of short, short-2pi, finite, long, got {model!r}")
    return jnp.stack([fr * cr - ft * sr, fr * sr + ft * cr])


def _film_geometry(owner, viscosity, length, diameter, clearance):
    out = (as_param(f"{owner}: viscosity (Pa s)", viscosity, sign="positive", shape=()),
           as_param(f"{owner}: length (m)", length, sign="positive", shape=()),
           as_param(f"{owner}: diameter (m)", diameter, sign="positive", shape=()),
           as_param(f"{owner}: clearance (m)", clearance, sign="positive", shape=()))
    if is_concrete(out) and not float(out[3]) < float(out[2]) / 2:
        raise InputError(f"{owner}: clearance must be < diameter / 2 (the journal's radius), got clearance = "
                         f"{show(clearance)}, diameter = {show(diameter)}")
    return out


class _Film(AbstractBearingAt):
    """What a fluid film at a node shares: its node, geometry and the state it sees."""

    node_index: int = eqx.field(static=True)
    viscosity: jax.Array
    length: jax.Array
    diameter: jax.Array
    clearance: jax.Array

    #: whether the journal spins with the shaft (a journal bearing) or only orbits (a damper)
    spins: bool = eqx.field(static=True, default=True)

    @property
    def centred(self) -> bool:
        """Whether something of its own holds the journal at rest (a damper's centring
        spring); a journal bearing's film does while it spins."""
        return True

    def eccentricity(self, s):
        """`|u| / c` of the journal in the shaft state `s`."""
        u = s.position(self.node)
        return jnp.sqrt(u @ u) / self.clearance

    @property
    def label(self) -> str:
        return f"{self.kind} at node {self.node}"

    def outputs(self, s, q, qd) -> dict:
        return {f"{self.output_prefix}_eccentricity": self.eccentricity(s)}

    @property
    def output_prefix(self) -> str:
        return f"{self.short_name}{self.node}"


class JournalBearing(_Film):
    """A plain cylindrical fluid-film journal bearing at shaft node `node`, a
    nonlinear force (module docstring): the journal's position and velocity and the
    shaft's speed give the film force; the static load (the rotor's weight, any
    given force) sets where it runs.

    **Arguments:**
    - `node`: the shaft node of the journal.
    - `viscosity` (Pa s), `length` (m), `diameter` (m, the journal's), `clearance`
      (m, radial, < diameter / 2): all > 0.
    - `model`: "short" (Ocvirk, half-Sommerfeld; `L/D <= 1`, warned above 0.5),
      "finite" (the interpolated Reynolds solution, `0.25 <= L/D <= 1`), "long"
      (Sommerfeld with Gümbel cavitation).
    """

    model: str = eqx.field(static=True)

    def __init__(self, node, viscosity, length, diameter, clearance, model="short"):
        self.node_index = node_index(node)
        check_choice("model", model, JOURNAL_MODELS)
        self.model = model
        owner = f"journal bearing at node {self.node_index}"
        self.viscosity, self.length, self.diameter, self.clearance = _film_geometry(
            owner, viscosity, length, diameter, clearance)
        if is_concrete((self.length, self.diameter)):
            ratio = float(self.length) / float(self.diameter)
            if model == "short" and ratio > SHORT_MAX:
                raise InputError(f"{owner}: the short-bearing model needs L/D <= {SHORT_MAX:g}, got L/D = "
                                 f"{ratio:.4g} (length {show(length)}, diameter {show(diameter)}); use "
                                 f"model = \"finite\"")
            if model == "short" and ratio > SHORT_WARN:
                warnings.warn(f"{owner}: L/D = {ratio:.4g} > {SHORT_WARN:g}: the short-bearing model "
                              f"overestimates the load capacity (use model = \"finite\")", PlausibilityWarning,
                              stacklevel=2)
            if model == "finite" and not FINITE_RATIOS[0] <= ratio <= FINITE_RATIOS[1]:
                raise InputError(f"{owner}: the finite-bearing model covers {FINITE_RATIOS[0]:g} <= L/D <= "
                                 f"{FINITE_RATIOS[1]:g}, got L/D = {ratio:.4g}")

    kind = property(lambda self: f"{self.model} journal bearing")
    short_name = "journal"

    def force(self, s, q, qd, active=None):
        u, v = s.motion(self.node)
        return s.place(self.node, film_force(u, v, s.theta_dot, self.viscosity, self.length, self.diameter,
                                             self.clearance, self.model))

    def describe(self):
        return self.label


#: a damper's centring spring: `kyy` left out is `kxx`
SFD_FOLLOWS = {"kyy": "kxx"}


class SqueezeFilmDamper(_Film):
    """A squeeze-film damper at shaft node `node`: a short film round a ring that
    orbits with the node but does not spin (module docstring), with an optional
    centring spring `kxx`, `kyy` (N/m, linear).

    **Arguments:** `viscosity` (Pa s), `length`, `diameter`, `clearance` (m, < diameter
    / 2), `film`: "pi" (cavitated: half the film carries pressure) or "2pi"
    (uncavitated), `kxx` (N/m, = 0), `kyy` (N/m, = kxx).
    """

    film: str = eqx.field(static=True)
    kxx: jax.Array
    kyy: jax.Array

    def __init__(self, node, viscosity, length, diameter, clearance, film="pi", kxx=0.0, kyy=None):
        self.node_index = node_index(node)
        self.spins = False
        check_choice("film", film, SFD_FILMS)
        self.film = film
        owner = f"squeeze-film damper at node {self.node_index}"
        self.viscosity, self.length, self.diameter, self.clearance = _film_geometry(
            owner, viscosity, length, diameter, clearance)
        spring = follow(dict(kxx=kxx, kyy=kyy), SFD_FOLLOWS)
        self.kxx, self.kyy = (as_param(f"{owner}: {k} (centring spring, N/m)", spring[k], sign="nonnegative",
                                       shape=()) for k in ("kxx", "kyy"))

    kind = property(lambda self: f"squeeze-film damper ({self.film} film)")
    short_name = "sfd"

    @property
    def centred(self) -> bool:
        """Whether a centring spring holds it (both directions)."""
        return not (is_concrete((self.kxx, self.kyy)) and (float(self.kxx) == 0.0 or float(self.kyy) == 0.0))

    def linear_part(self, rotor):
        b = DOFS_PER_NODE * self.node
        z = jnp.zeros((rotor.n_dofs, rotor.n_dofs))
        return z, z.at[b, b].set(self.kxx).at[b + 1, b + 1].set(self.kyy), z

    def force(self, s, q, qd, active=None):
        u, v = s.motion(self.node)
        model = "short" if self.film == "pi" else "short-2pi"
        return s.place(self.node, film_force(u, v, jnp.zeros(()), self.viscosity, self.length, self.diameter,
                                             self.clearance, model))

    def describe(self):
        return self.label


def _film_part(b):
    geometry = (b["viscosity"], b["length"], b["diameter"], b["clearance"])
    if b["type"] == "journal":
        return JournalBearing(b["node"], *geometry, model=b["model"])
    return SqueezeFilmDamper(b["node"], *geometry, film=b["film"], kxx=b["kxx"], kyy=b["kyy"])


def _film_entry(c):
    out = {"node": c.node}
    if isinstance(c, JournalBearing):
        out.update(type="journal", model=c.model)
    else:
        out.update(type="sfd", film=c.film, kxx=float(c.kxx), kyy=float(c.kyy))
    out.update(viscosity=float(c.viscosity), length=float(c.length), diameter=float(c.diameter),
               clearance=float(c.clearance))
    return out


#: the fluid films' rotor-file entries: `[[bearing]]` entries of type "journal" and "sfd" (the rotor file's
#: bearing table declares and checks their keys; `rotorjax.io`)
FILM_TABLE = ComponentTable(True, {}, "a fluid film (journal bearing, squeeze-film damper) as a nonlinear force",
                            name="bearing", builds=(JournalBearing, SqueezeFilmDamper), from_table=_film_part,
                            to_table=_film_entry, part="film",
                            followers={lead: ((f, "value"),) for f, lead in SFD_FOLLOWS.items()})
