"""What a component on a finite-element rotor states, and what it sees.

A component of a `RotorScene` sits at a node (or acts on the whole shaft) and
states, once, only what it adds:

- `linear_part(rotor)`: its contribution to the linear equations about the
  straight, resting shaft, as full-dof matrices `(C, K, K_speed)` (the last times
  the speed: circulatory terms) or `None`;
- `force(s, q, qd, active)`: the rest of its force, a `NodeLoad` at its node
  (`s.place(node, f)`) or an all-dof load (`s` the shaft's state, `q, qd` the component's own coordinates, `active` its
  contact set for event-located integration, or `None` for a smooth law);
- `static_load(rotor)`: a constant load (weight), or `None`;
- `kinetic`, `potential`, `dissipation`: energies, for components with
  coordinates of their own at a node (an auto-balancer's weights), as functions
  of the node's kinematics (`Kinematics`) and those coordinates, through
  Lagrange's equations of the node's two displacements and the own coordinates
  (assembled into the shaft's equations by the node's rows of the basis);
- `unbalance_load(rotor, speed)`: the complex synchronous load, for unbalances.

The scene sums what is present; nothing absent is evaluated.
"""

import equinox as eqx
import jax
import jax.numpy as jnp

from ._base import Kinematics
from ._fe_rotor import DOFS_PER_NODE
from ._validate import InputError, is_concrete, show


class NodeLoad(eqx.Module):
    """A force `f = (f_x, f_y)` at `node` (what `ShaftState.place` returns): the scene
    maps it onto its coordinates through the node's rows, without an all-dof vector."""

    node: int = eqx.field(static=True)
    f: jax.Array

    def on_dofs(self, n_dofs: int) -> jax.Array:
        """The load as an all-dof vector."""
        b = DOFS_PER_NODE * self.node
        return jnp.zeros(n_dofs, dtype=self.f.dtype).at[b:b + 2].set(self.f)


class ShaftState(eqx.Module):
    """The shaft at one instant: the shaft coordinates `q`, `qd` and the map `E` from
    them to all dofs (node order `(x, y, sx, sy)`), the spin angle, speed and
    acceleration. `x`, `v` are the all-dof displacements and velocities; a node's
    are read through its rows of `E` alone (two rows, not the whole shaft)."""

    t: jax.Array
    theta: jax.Array
    theta_dot: jax.Array
    theta_ddot: jax.Array
    q: jax.Array
    qd: jax.Array
    E: jax.Array

    @property
    def x(self) -> jax.Array:
        return self.E @ self.q

    @property
    def v(self) -> jax.Array:
        return self.E @ self.qd

    def _rows(self, node, n=2):
        b = DOFS_PER_NODE * node
        return self.E[b:b + n]

    def at(self, node: int) -> Kinematics:
        """The kinematic context of `node`'s centre (for planar components)."""
        x, v = self._rows(node) @ self.q, self._rows(node) @ self.qd
        return Kinematics(t=self.t, theta=self.theta, theta_dot=self.theta_dot, x=x[0], y=x[1], xd=v[0], yd=v[1])

    def position(self, node: int) -> jax.Array:
        return self._rows(node) @ self.q

    def velocity(self, node: int) -> jax.Array:
        return self._rows(node) @ self.qd

    def displacements(self, node: int) -> jax.Array:
        """`node`'s four dofs `(x, y, sx, sy)` (its rows of `E` alone)."""
        return self._rows(node, DOFS_PER_NODE) @ self.q

    def motion(self, node: int):
        """`(position, velocity)` of `node`'s centre, from one product."""
        pv = self._rows(node) @ jnp.stack([self.q, self.qd], axis=1)
        return pv[:, 0], pv[:, 1]

    def place(self, node: int, f2) -> NodeLoad:
        """A force `f2 = (f_x, f_y)` at `node` (a `NodeLoad`)."""
        return NodeLoad(node, jnp.asarray(f2))


class AbstractRotorComponent(eqx.Module):
    """A component of a `RotorScene` (see the module docstring). `node` is the
    node it acts at (None for whole-shaft components)."""

    @property
    def node(self):
        return None

    @property
    def n_coords(self) -> int:
        return 0

    @property
    def n_contacts(self) -> int:
        return 0

    @property
    def reads_motion(self) -> bool:
        """Whether its force depends on the shaft's motion (not only on time and the
        spin: an unbalance's does not)."""
        return True

    @property
    def in_equilibrium(self) -> bool:
        """Whether its force acts at rest and is part of the static equilibrium (a
        function of the shaft's state and speed alone: bearings, fluid films)."""
        return False

    def linear_part(self, rotor):
        return None

    def static_load(self, rotor):
        return None

    def unbalance_load(self, rotor, speed):
        return None

    def force(self, s: ShaftState, q, qd, active=None):
        return None

    def kinetic(self, kin: Kinematics, q, qd):
        return jnp.zeros(())

    def potential(self, kin: Kinematics, q):
        return jnp.zeros(())

    def dissipation(self, kin: Kinematics, q, qd):
        return jnp.zeros(())

    def contact_indicator(self, s: ShaftState, q, qd):
        return jnp.zeros(0)

    def outputs(self, s: ShaftState, q, qd) -> dict:
        return {}

    def rest_coords(self):
        """Own coordinates of the reference state (weights spread evenly)."""
        return jnp.zeros(self.n_coords)

    def describe(self) -> str:
        return type(self).__name__


class AbstractBearingAt(AbstractRotorComponent):
    """A bearing-like component at one shaft node (`node_index`) whose force acts at
    rest and is part of the static equilibrium (cubic and clearance bearings, fluid
    films)."""

    node_index: eqx.AbstractVar[int]

    @property
    def node(self):
        return self.node_index

    @property
    def in_equilibrium(self) -> bool:
        return True


def node_index(node) -> int:
    """A component's node: a non-negative integer (the scene checks it exists)."""
    if isinstance(node, (bool, str, bytes)) or not is_concrete(node):
        raise InputError(f"node must be a non-negative integer node index, got {show(node)}")
    try:
        f = float(node)
    except (TypeError, ValueError):
        raise InputError(f"node must be a non-negative integer node index, got {show(node)}") from None
    if not (f >= 0 and f == int(f)):
        raise InputError(f"node must be a non-negative integer node index, got {show(node)}")
    return int(f)
