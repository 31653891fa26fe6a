"""External (viscous) damping of a finite-element rotor: distributed along the
shaft (the surrounding medium), and concentrated at a node (a disk's damping by
the air or a squeeze film), as in model 004 (Azarov, Guskov, Panovko 2023, whose
`2 eta_e`, `2 eta_Dxi`, `2 eta_Dtheta` are these coefficients in its units).

Both are linear: they add a damping matrix to the scene's linear part and nothing
else (no force evaluated per step)."""

import equinox as eqx
import jax
import jax.numpy as jnp
import numpy as np

from ._fe_elements import conical_translational_mass
from ._fe_rotor import DOFS_PER_NODE
from ._rotor_component import AbstractRotorComponent, node_index
from ._validate import as_param
from ._table import ComponentTable, Key, node_key


def unit_line_mass(rotor):
    """`int N^T N dz` over the shaft on all dofs: the consistent translational mass
    matrix of a unit mass per unit length (cubic Euler-Bernoulli shape functions,
    the same in both planes; pedestal dofs zero)."""
    n = rotor.n_dofs
    lengths = rotor.lengths
    one = jnp.ones(())
    plane = jax.vmap(lambda L: conical_translational_mass(one, one, L, 0.0 * L, 0.0, 0.0))(lengths)
    ix, iy = np.array([0, 2, 4, 6]), np.array([1, 3, 5, 7])   # (w1, s1, w2, s2) of each plane
    me = jnp.zeros((lengths.shape[0], 8, 8))
    me = me.at[:, ix[:, None], ix[None, :]].set(plane).at[:, iy[:, None], iy[None, :]].set(plane)
    idx = np.arange(rotor.n_nodes - 1)[:, None] * DOFS_PER_NODE + np.arange(8)[None, :]
    rows = np.repeat(idx[:, :, None], 8, axis=2)
    cols = np.repeat(idx[:, None, :], 8, axis=1)
    return jnp.zeros((n, n)).at[rows, cols].add(me)


class ExternalDamping(AbstractRotorComponent):
    """Viscous damping of the shaft's lateral motion by its surroundings:
    `coefficient` (N s/m^2) per unit length, a force `-coefficient v(z)` per unit
    length opposing the local velocity in the fixed frame. Its damping matrix is
    `coefficient int N^T N dz` (`unit_line_mass`), the consistent discretisation
    (the shaft's rotary motion is not damped)."""

    coefficient: jax.Array

    def __init__(self, coefficient):
        self.coefficient = as_param("coefficient (external damping per unit length)", coefficient,
                                    sign="nonnegative", shape=())

    def linear_part(self, rotor):
        c = self.coefficient * unit_line_mass(rotor)
        return c, jnp.zeros_like(c), jnp.zeros_like(c)

    def describe(self):
        return f"external damping ({float(self.coefficient):g} per unit length)"


class DiskDamping(AbstractRotorComponent):
    """Viscous damping at `node` (a disk's): `translational` (N s/m) on the node's
    `x, y` velocity and `angular` (N m s) on its tilt rates `sx, sy`, in the fixed
    frame."""

    node_index: int = eqx.field(static=True)
    translational: jax.Array
    angular: jax.Array

    def __init__(self, node, translational, angular=0.0):
        self.node_index = node_index(node)
        self.translational = as_param("translational (disk damping)", translational, sign="nonnegative",
                                      shape=())
        self.angular = as_param("angular (disk angular damping)", angular, sign="nonnegative", shape=())

    @property
    def node(self):
        return self.node_index

    def linear_part(self, rotor):
        n = rotor.n_dofs
        b = DOFS_PER_NODE * self.node
        c = jnp.zeros((n, n))
        c = c.at[b, b].add(self.translational).at[b + 1, b + 1].add(self.translational)
        c = c.at[b + 2, b + 2].add(self.angular).at[b + 3, b + 3].add(self.angular)
        return c, jnp.zeros_like(c), jnp.zeros_like(c)

    def describe(self):
        return (f"disk damping at node {self.node} ({float(self.translational):g}, "
                f"angular {float(self.angular):g})")


#: the rotor-file tables, `[external_damping]` and `[[disk_damping]]`
TABLE = ComponentTable(False, {
    "coefficient": Key("number", "N s/m^2", "viscous damping of the shaft's lateral motion per unit length",
                       "nonnegative", True),
}, "viscous damping of the shaft by its surroundings", name="external_damping", builds=ExternalDamping,
    from_table=lambda d: ExternalDamping(d["coefficient"]),
    to_table=lambda d: {"coefficient": float(d.coefficient)})
DISK_TABLE = ComponentTable(True, {
    "node": node_key("disk damping"),
    "translational": Key("number", "N s/m", "viscous damping of the node's x, y motion", "nonnegative", True),
    "angular": Key("number", "N m s", "viscous damping of the node's tilts sx, sy", "nonnegative", default=0.0),
}, "viscous damping at a node (a disk's: air, squeeze film)", name="disk_damping", builds=DiskDamping,
    from_table=lambda d: DiskDamping(d["node"], d["translational"], d["angular"]),
    to_table=lambda d: {"node": d.node, "translational": float(d.translational), "angular": float(d.angular)})
