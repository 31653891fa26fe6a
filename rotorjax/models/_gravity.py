"""Gravity on a finite-element rotor."""

import jax
import jax.numpy as jnp
import numpy as np

from ._rotor_component import AbstractRotorComponent
from ._validate import as_param
from ._table import ComponentTable, Key


class Gravity(AbstractRotorComponent):
    """Weight of the shaft and everything on it: acceleration `g` (m/s^2) along
    the direction at `angle` (rad) in the x-y plane (default `-pi/2`: along -y).
    The load is `g M e`, with `M` the full mass matrix and `e` the rigid unit
    translation along that direction (consistent element loads)."""

    g: jax.Array
    angle: jax.Array

    def __init__(self, g=9.81, angle=-np.pi / 2):
        self.g = as_param("g (gravity)", g, sign="nonnegative", shape=())
        self.angle = as_param("gravity angle", angle, shape=())

    def static_load(self, rotor):
        M = rotor.matrices()[0]
        e = rotor.translation(jnp.cos(self.angle), jnp.sin(self.angle))   # shaft nodes and pedestals
        return self.g * (M @ e)

    def describe(self):
        return "gravity"


#: its rotor-file table, `[gravity]`
TABLE = ComponentTable(False, {
    "g": Key("number", "m/s^2", "gravitational acceleration", "nonnegative", default=9.81),
    "angle": Key("number", "rad", "direction of gravity in the x-y plane", default=-np.pi / 2),
}, "gravity", name="gravity", builds=Gravity,
    from_table=lambda g: Gravity(g["g"], g["angle"]),
    to_table=lambda g: {"g": float(g.g), "angle": float(g.angle)})
