"""Voigt internal (material) damping of a rotating shaft."""

import jax
import jax.numpy as jnp

from ._rotation import quarter_turn_matrix
from ._rotor_component import AbstractRotorComponent
from ._validate import as_param
from ._table import ComponentTable, Key


class InternalDamping(AbstractRotorComponent):
    """Voigt (Kelvin-Voigt) internal damping of the shaft material: the stress has
    a part `T_V E eps'` with `eps'` the strain rate seen in the rotating shaft, so
    the shaft's internal damping matrix is `C_i = T_V K_shaft` (the shaft elements'
    stiffness, bearings excluded) and, written in the fixed frame,

        force = -C_i q' - speed C_i J q,

    a damping term and a circulatory one (`J` the quarter turn of every node). The
    circulatory term feeds whirl above a threshold speed: for a Jeffcott rotor
    `w_n (1 + c_e / c_i)` (tested). `relaxation_time` is `T_V` (s; the loss factor
    at frequency `w` is `w T_V`)."""

    relaxation_time: jax.Array

    def __init__(self, relaxation_time):
        self.relaxation_time = as_param("relaxation_time (Voigt T_V)", relaxation_time, sign="nonnegative",
                                        shape=())

    def linear_part(self, rotor):
        ci = self.relaxation_time * rotor.shaft_matrices()[2]
        n = ci.shape[0]   # supports' pedestal dofs (after the shaft's) are not turned: C_i is zero there
        J = jnp.zeros((n, n)).at[:4 * rotor.n_nodes, :4 * rotor.n_nodes].set(quarter_turn_matrix(rotor.n_nodes))
        return ci, jnp.zeros_like(ci), ci @ J

    def describe(self):
        return f"internal damping (T_V = {float(self.relaxation_time):g} s)"


#: its rotor-file table, `[internal_damping]`
TABLE = ComponentTable(False, {
    "relaxation_time": Key("number", "s", "Voigt relaxation time T_V", "nonnegative", True),
}, "Voigt internal damping of the shaft", name="internal_damping", builds=InternalDamping,
    from_table=lambda d: InternalDamping(d["relaxation_time"]),
    to_table=lambda d: {"relaxation_time": float(d.relaxation_time)})
