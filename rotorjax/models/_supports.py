"""Linear visco-elastic supports acting on the rotor centre."""

import jax

from ._base import AbstractComponent
from ._validate import as_param


class Supports(AbstractComponent):
    """Supports with stiffness `kx, ky` and viscous damping `cx, cy` along the
    fixed axes (anisotropic when `kx != ky`):

        V = (kx x^2 + ky y^2) / 2,      D = (cx xd^2 + cy yd^2) / 2.
    """

    kx: jax.Array
    ky: jax.Array
    cx: jax.Array
    cy: jax.Array

    def __init__(self, kx, ky, cx=0.0, cy=0.0):
        self.kx = as_param("kx", kx, sign="positive", shape=())
        self.ky = as_param("ky", ky, sign="positive", shape=())
        self.cx = as_param("cx", cx, sign="nonnegative", shape=())
        self.cy = as_param("cy", cy, sign="nonnegative", shape=())

    @classmethod
    def isotropic(cls, k, c=0.0) -> "Supports":
        k = as_param("k (support stiffness)", k, sign="positive", shape=())
        c = as_param("c (support damping)", c, sign="nonnegative", shape=())
        return cls(k, k, c, c)

    def potential(self, kin, q):
        return 0.5 * (self.kx * kin.x**2 + self.ky * kin.y**2)

    def dissipation(self, kin, q, qd):
        return 0.5 * (self.cx * kin.xd**2 + self.cy * kin.yd**2)

    def describe(self):
        return "supports"
