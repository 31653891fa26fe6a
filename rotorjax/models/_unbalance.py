"""An unbalance at a node of a finite-element rotor."""

import equinox as eqx
import jax
import jax.numpy as jnp

from ._fe_rotor import DOFS_PER_NODE
from ._rotor_component import AbstractRotorComponent, node_index
from ._validate import as_param
from ._table import ComponentTable, Key, node_key


class Unbalance(AbstractRotorComponent):
    """A mass moment `magnitude` (kg m) at `node`, at angle `phase` (rad) from the
    rotor's reference mark. With the spin angle `theta(t)` and `a = theta + phase`,
    its force on the node is

        U (theta'^2 (cos a, sin a) + theta'' (sin a, -cos a)),

    the centrifugal and the tangential (run-up) parts: minus the mass times the
    acceleration of its offset `e (cos a, sin a)` (a run-up's tangential force lags the
    offset by 90 degrees, as the energy of a `RigidRotor`'s eccentric mass gives it); at constant speed `w` it is
    `Re(F e^{i w t})` with `F_x = U w^2 e^{i phase}`, `F_y = -i F_x`, the load of
    the linear unbalance response. (The unbalance mass's own inertia is neglected,
    as in every unbalance-response calculation.)"""

    node_index: int = eqx.field(static=True)
    magnitude: jax.Array
    phase: jax.Array

    def __init__(self, node, magnitude, phase=0.0):
        self.node_index = node_index(node)
        self.magnitude = as_param("unbalance magnitude", magnitude, sign="nonnegative", shape=())
        self.phase = as_param("unbalance phase", phase, shape=())

    @property
    def node(self):
        return self.node_index

    @property
    def reads_motion(self) -> bool:
        return False

    def force(self, s, q, qd, active=None):
        a = s.theta + self.phase
        f = self.magnitude * (s.theta_dot**2 * jnp.stack([jnp.cos(a), jnp.sin(a)])
                              + s.theta_ddot * jnp.stack([jnp.sin(a), -jnp.cos(a)]))
        return s.place(self.node, f)

    def unbalance_load(self, rotor, speed):
        fx = self.magnitude * speed**2 * jnp.exp(1j * self.phase)
        b = DOFS_PER_NODE * self.node
        return jnp.zeros(rotor.n_dofs, dtype=jnp.complex128).at[b].set(fx).at[b + 1].set(-1j * fx)

    def describe(self):
        return f"unbalance at node {self.node}"


#: its rotor-file table, `[[unbalance]]`
TABLE = ComponentTable(True, {
    "node": node_key("unbalance"),
    "magnitude": Key("number", "kg m", "unbalance (mass times eccentricity)", "nonnegative", True),
    "phase": Key("number", "rad", "angle from the reference mark", default=0.0),
}, "an unbalance", name="unbalance", builds=Unbalance,
    from_table=lambda u: Unbalance(u["node"], u["magnitude"], u["phase"]),
    to_table=lambda u: {"node": u.node, "magnitude": float(u.magnitude), "phase": float(u.phase)})
