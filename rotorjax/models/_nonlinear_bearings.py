"""Nonlinear bearings at a node: cubic hardening, and a clearance (dead band)."""

import equinox as eqx
import jax
import jax.numpy as jnp

from ._fe_rotor import DOFS_PER_NODE
from ._rotor_component import AbstractBearingAt, node_index
from ._validate import as_param
from ._table import ComponentTable, Key, node_key


def _radial(p):
    r = jnp.sqrt(p @ p + 1e-300)
    return r, p / r


class CubicBearing(AbstractBearingAt):
    """An isotropic bearing with hardening stiffness at `node`:

        f = -(k + k3 |u|^2) u - c u',

    `u` the node's displacement. `k` (N/m) and `c` (N s/m) are its linear part (in
    every linear analysis), `k3` (N/m^3) the cubic hardening (a Duffing bearing:
    the unbalance response bends over and jumps). Being isotropic, it keeps the
    synchronous orbit a rest point of the rotating frame."""

    node_index: int = eqx.field(static=True)
    k: jax.Array
    k3: jax.Array
    c: jax.Array

    def __init__(self, node, k3, k=0.0, c=0.0):
        self.node_index = node_index(node)
        self.k3 = as_param("k3 (cubic stiffness)", k3, sign="nonnegative", shape=())
        self.k = as_param("k (bearing stiffness)", k, sign="nonnegative", shape=())
        self.c = as_param("c (bearing damping)", c, sign="nonnegative", shape=())

    def linear_part(self, rotor):
        b = DOFS_PER_NODE * self.node
        z = jnp.zeros((rotor.n_dofs, rotor.n_dofs))
        K = z.at[b, b].set(self.k).at[b + 1, b + 1].set(self.k)
        C = z.at[b, b].set(self.c).at[b + 1, b + 1].set(self.c)
        return C, K, z

    def force(self, s, q, qd, active=None):
        u = s.position(self.node)
        return s.place(self.node, -self.k3 * (u @ u) * u)

    def potential_energy(self, u):
        """Energy of the cubic part, `k3 |u|^4 / 4` (the linear part is in `K`)."""
        return 0.25 * self.k3 * (u @ u) ** 2

    def describe(self):
        return f"cubic bearing at node {self.node}"


class ClearanceBearing(AbstractBearingAt):
    """A bearing with a radial clearance (dead band) `clearance` (m) at `node`: no
    force while `|u| < clearance`, then a stiffness `k` (N/m) and damping `c`
    (N s/m) on the penetration `d = |u| - clearance`,

        f = -(k d + c d') e_r   in contact, 0 outside,

    exactly, with the contact set located by events (`simulate_events`), or
    smoothed over `smoothing` (m: `d -> smoothing softplus(d / smoothing)`)."""

    node_index: int = eqx.field(static=True)
    clearance: jax.Array
    k: jax.Array
    c: jax.Array
    smoothing: jax.Array

    def __init__(self, node, clearance, k, c=0.0, smoothing=None):
        self.node_index = node_index(node)
        self.clearance = as_param("clearance", clearance, sign="positive", shape=())
        self.k = as_param("k (bearing stiffness)", k, sign="positive", shape=())
        self.c = as_param("c (bearing damping)", c, sign="nonnegative", shape=())
        smoothing = self.default_smoothing(self.clearance) if smoothing is None else smoothing
        self.smoothing = as_param("smoothing", smoothing, sign="positive", shape=())

    @staticmethod
    def default_smoothing(clearance):
        """The smoothing length when none is given: `clearance / 1000`."""
        return 1e-3 * clearance

    @property
    def n_contacts(self) -> int:
        return 1

    def contact_indicator(self, s, q, qd):
        r, _ = _radial(s.position(self.node))
        return (r - self.clearance)[None]

    def force(self, s, q, qd, active=None):
        r, e = _radial(s.position(self.node))
        d, rate = r - self.clearance, e @ s.velocity(self.node)
        if active is None:
            ell = self.smoothing
            mag = self.k * ell * jax.nn.softplus(d / ell) + self.c * rate * jax.nn.sigmoid(d / ell)
        else:
            mag = jnp.where(active[0], self.k * d + self.c * rate, 0.0)
        return s.place(self.node, -mag * e)

    def describe(self):
        return f"clearance bearing at node {self.node}"


#: the rotor-file tables, `[[cubic_bearing]]` and `[[clearance_bearing]]`
CUBIC_TABLE = ComponentTable(True, {
    "node": node_key("cubic bearing"),
    "k3": Key("number", "N/m^3", "cubic (hardening) stiffness", "nonnegative", True),
    "k": Key("number", "N/m", "linear stiffness", "nonnegative", default=0.0),
    "c": Key("number", "N s/m", "damping", "nonnegative", default=0.0),
}, "an isotropic bearing with cubic stiffness", name="cubic_bearing", builds=CubicBearing,
    from_table=lambda c: CubicBearing(c["node"], c["k3"], c["k"], c["c"]),
    to_table=lambda c: {"node": c.node, "k3": float(c.k3), "k": float(c.k), "c": float(c.c)})
CLEARANCE_TABLE = ComponentTable(True, {
    "node": node_key("clearance bearing"),
    "clearance": Key("number", "m", "radial clearance", "positive", True),
    "k": Key("number", "N/m", "contact stiffness", "positive", True),
    "c": Key("number", "N s/m", "contact damping", "nonnegative", default=0.0),
    "smoothing": Key("number", "m", "contact smoothing length", "positive", default=None),
}, "a bearing with a radial clearance", name="clearance_bearing", builds=ClearanceBearing,
    from_table=lambda c: ClearanceBearing(c["node"], c["clearance"], c["k"], c["c"], c["smoothing"]),
    to_table=lambda c: {"node": c.node, "clearance": float(c.clearance), "k": float(c.k), "c": float(c.c),
                        "smoothing": float(c.smoothing)},
    followers={"clearance": (("smoothing", "smoothing"),)})
