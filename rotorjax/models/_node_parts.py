"""Planar parts placed at a node of a finite-element rotor: the auto-balancer
and the limiters, each stated once (in `_balancer.py`, `_limiters.py`) and seen
here through the node's kinematics."""

import equinox as eqx
import jax
import jax.numpy as jnp
import numpy as np

from ._balancer import INERTIA_FACTORS, AutoBalancer, Race
from ._limiters import Limiters
from ._rotor_component import AbstractRotorComponent, node_index
from ._table import ComponentTable, Key, floats, node_key, one_or_each
from ._validate import InputError, as_param, check_type


class BalancerAt(AbstractRotorComponent):
    """An `AutoBalancer` (balls, rollers or pendulums in a race) on the rotor at
    `node`: the weights move with the node's centre and own one coordinate each
    (their race angle relative to the rotor). Its energies are the balancer's,
    evaluated at the node's kinematics."""

    node_index: int = eqx.field(static=True)
    balancer: AutoBalancer

    def __init__(self, node, balancer):
        self.node_index = node_index(node)
        check_type("balancer", balancer, AutoBalancer, "a rotorjax.models.AutoBalancer")
        self.balancer = balancer

    @property
    def node(self):
        return self.node_index

    @property
    def n_coords(self) -> int:
        return self.balancer.n_coords

    def kinetic(self, kin, q, qd):
        return self.balancer.kinetic(kin, q, qd)

    def potential(self, kin, q):
        return self.balancer.potential(kin, q)

    def dissipation(self, kin, q, qd):
        return self.balancer.dissipation(kin, q, qd)

    def mass_moment(self, q):
        """The weights' mass moment about the node's centre, rotor frame (kg m)."""
        return self.balancer.mass_moment(None, q)

    def outputs(self, s, q, qd):
        return self.balancer.outputs(s.at(self.node), q, qd)

    def rest_coords(self):
        return jnp.linspace(0.0, 2 * jnp.pi, self.n_coords, endpoint=False)

    def describe(self):
        return f"{self.balancer.describe()} at node {self.node}"


class LimitersAt(AbstractRotorComponent):
    """`Limiters` (discrete visco-elastic stops with friction) around the rim of
    radius `radius` (m) at `node`: the contact law of `rotorjax.models.Limiters`,
    exact with events or smoothed, on the node's centre; the rim's surface speed
    `speed * radius` sets the friction direction."""

    node_index: int = eqx.field(static=True)
    limiters: Limiters
    radius: jax.Array

    def __init__(self, node, limiters, radius):
        self.node_index = node_index(node)
        check_type("limiters", limiters, Limiters, "a rotorjax.models.Limiters")
        self.limiters = limiters
        self.radius = as_param("radius (rim radius at the limiters)", radius, sign="nonnegative", shape=())

    @property
    def node(self):
        return self.node_index

    @property
    def n_contacts(self) -> int:
        return self.limiters.n

    def contact_indicator(self, s, q, qd):
        return self.limiters.indicator(*s.motion(self.node), in_length=True)

    def force(self, s, q, qd, active=None):
        f, _ = self.limiters.force(*s.motion(self.node), s.theta_dot, self.radius, active)
        return s.place(self.node, f)

    def outputs(self, s, q, qd):
        pos, vel = s.motion(self.node)
        active = self.limiters.indicator(pos, vel) > 0
        return {"normal_forces": self.limiters.normal_forces(pos, vel, active)}

    def describe(self):
        return f"{self.limiters.describe()} at node {self.node}"


# --- their rotor-file tables, [[limiters]] and [[auto_balancer]] ------------------------
def _either(entry, where, i, first, second, words):
    """Exactly one of two ways to give a quantity (`first`: a key; `second`: keys)."""
    has_first, has_second = first in entry, any(k in entry for k in second)
    if has_first == has_second:
        where.fail(f"{where.loc(i)}: give either {words}{', not both' if has_first else '; got neither'}",
                   where.loc(i))
    return has_first


def _complete_limiters(entries, where):
    """`angles`, or `n` evenly spaced from `first_angle`; per-limiter lists as long as the angles."""
    for i, lim in enumerate(entries):
        _either(lim, where, i, "angles", ("n",), "angles = [...] or n (with first_angle)")
        if "angles" in lim and "first_angle" in lim:
            where.fail(f"{where.loc(i)}.first_angle goes with n (evenly spaced limiters), not with angles",
                       where.loc(i, "first_angle"))
        if "n" in lim:
            first, count = lim.pop("first_angle", 0.0), lim.pop("n")
            lim["angles"] = [float(a) for a in first + 2 * np.pi * np.arange(count) / count]
        n = len(lim["angles"])
        for key in ("clearance", "stiffness", "damping", "friction"):
            if isinstance(lim[key], list) and len(lim[key]) != n:
                where.fail(f"{where.loc(i, key)} must be a number or one value per limiter ({n}), "
                           f"got {len(lim[key])} values", where.loc(i, key))


def _limiters_entry(c):
    lim = c.limiters
    if lim.slip_regularisation != 1e-6:
        raise InputError(f"{c.describe()} has slip_regularisation = {lim.slip_regularisation!r}; rotor files "
                         f"hold the default 1e-6")
    return {"node": c.node, "angles": floats(lim.angles), "clearance": one_or_each(lim.clearance),
            "stiffness": one_or_each(lim.stiffness), "damping": one_or_each(lim.damping),
            "friction": one_or_each(lim.friction), "radius": float(c.radius), "smoothing": float(lim.smoothing)}


LIMITERS_TABLE = ComponentTable(True, {
    "node": node_key("limiters"),
    "angles": Key("numbers", "rad", "angles of the limiters"),
    "n": Key("count", "count", "number of evenly spaced limiters"),
    "first_angle": Key("number", "rad", "angle of the first of n evenly spaced limiters"),
    "clearance": Key("number_or_numbers", "m", "clearance to the rim", "positive", True),
    "stiffness": Key("number_or_numbers", "N/m", "contact stiffness", "nonnegative", True),
    "damping": Key("number_or_numbers", "N s/m", "contact damping", "nonnegative", default=0.0),
    "friction": Key("number_or_numbers", "dimensionless", "Coulomb friction coefficient", "nonnegative",
                    default=0.0),
    "radius": Key("number", "m", "rim radius (friction slip speed)", "nonnegative", True, plausible="radius"),
    "smoothing": Key("number", "m", "contact smoothing length", "positive", default=1e-6),
}, "visco-elastic limiters with friction around a node", name="limiters", builds=LimitersAt,
    from_table=lambda e: LimitersAt(e["node"], Limiters(
        np.array(e["angles"]), np.asarray(e["clearance"]), np.asarray(e["stiffness"]), np.asarray(e["damping"]),
        np.asarray(e["friction"]), e["smoothing"]), e["radius"]),
    to_table=_limiters_entry, complete=_complete_limiters,
    leaves={k: ("limiters", k) for k in ("clearance", "stiffness", "damping", "friction", "smoothing")},
    refused={"first_angle": "it places the limiters when the file is read (their angles are the leaves); not a "
                            "value that can be fitted"})


def _complete_balancer(entries, where):
    """`masses`, or `n_weights` of `mass`; `radius`, or the semi-axes `r1`, `r2`; `kind` or
    `inertia_factor`."""
    for i, ab in enumerate(entries):
        if not _either(ab, where, i, "masses", ("n_weights", "mass"), "masses = [...] or n_weights and mass"):
            for key in ("n_weights", "mass"):
                if key not in ab:
                    where.fail(f"{where.loc(i, key)} is missing (n_weights and mass go together)")
            ab["masses"] = [ab.pop("mass")] * ab.pop("n_weights")
        if _either(ab, where, i, "radius", ("r1", "r2"), "radius or r1 and r2 (an elliptic race)"):
            ab["r1"] = ab["r2"] = ab.pop("radius")
        for key in ("r1", "r2"):
            if key not in ab:
                where.fail(f"{where.loc(i, key)} is missing (r1 and r2 go together)")
        if len(ab["center"]) != 2:
            where.fail(f"{where.loc(i, 'center')} must be [x, y] (2 numbers), got {len(ab['center'])}",
                       where.loc(i, "center"))
        if "kind" in ab and "inertia_factor" in ab:
            where.fail(f"{where.loc(i)}: give kind or inertia_factor, not both", where.loc(i))


def _balancer_part(ab):
    race = Race(ab["r1"], ab["r2"], tuple(ab["center"]))
    if "inertia_factor" in ab:
        return BalancerAt(ab["node"], AutoBalancer(np.array(ab["masses"]), race, ab["drag"],
                                                   inertia_factor=ab["inertia_factor"]))
    return BalancerAt(ab["node"], AutoBalancer(np.array(ab["masses"]), race, ab["drag"], kind=ab.get("kind", "ball")))


def _balancer_entry(c):
    b = c.balancer
    masses = np.asarray(b.mass)
    out = {"node": c.node}
    out.update({"n_weights": masses.shape[0], "mass": float(masses[0])} if np.all(masses == masses[0]) else
               {"masses": floats(masses)})
    r1, r2 = float(b.race.r1), float(b.race.r2)
    out.update({"radius": r1} if r1 == r2 else {"r1": r1, "r2": r2})
    if np.any(np.asarray(b.race.center) != 0):
        out["center"] = floats(b.race.center)
    out["drag"] = float(b.drag)
    factor = float(b.inertia_factor)
    kind = next((k for k in INERTIA_FACTORS if INERTIA_FACTORS[k] == factor), None)
    out.update({"kind": kind} if kind else {"inertia_factor": factor})
    return out


BALANCER_TABLE = ComponentTable(True, {
    "node": node_key("auto-balancer"),
    "masses": Key("numbers", "kg", "mass of each weight", "positive"),
    "n_weights": Key("count", "count", "number of identical weights"),
    "mass": Key("number", "kg", "mass of each of n_weights weights", "positive"),
    "radius": Key("number", "m", "race radius", "positive", plausible="radius"),
    "r1": Key("number", "m", "race semi-axis along the rotor-frame x axis", "positive", plausible="radius"),
    "r2": Key("number", "m", "race semi-axis along the rotor-frame y axis", "positive", plausible="radius"),
    "center": Key("numbers", "m", "race centre in the rotor frame (x, y)", default=[0.0, 0.0]),
    "drag": Key("number", "N s/m", "viscous drag on the weights' relative motion", "nonnegative", default=0.0),
    "kind": Key("string", meaning="weight kind", choices=("ball", "roller", "pendulum")),
    "inertia_factor": Key("number", "dimensionless", "inertia factor (instead of kind)", domain=">=1"),
}, "a ball, roller or pendulum auto-balancer", name="auto_balancer", builds=BalancerAt,
    from_table=_balancer_part, to_table=_balancer_entry, complete=_complete_balancer,
    leaves={"mass": ("balancer", "mass"), "drag": ("balancer", "drag"),
            "inertia_factor": ("balancer", "inertia_factor"), "r1": ("balancer", "race", "r1"),
            "r2": ("balancer", "race", "r2")},
    spread={"radius": ("r1", "r2")})
