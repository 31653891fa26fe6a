"""Planar parts placed at a node of a finite-element rotor: the auto-balancer
and the limiters, each stated once (in `_balancer.py`, `_limiters.py`) and seen
here through the node's kinematics."""

import equinox as eqx
import jax
import jax.numpy as jnp

from ._balancer import AutoBalancer
from ._limiters import Limiters
from ._rotor_component import AbstractRotorComponent, node_index
from ._validate import as_param, check_type


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
