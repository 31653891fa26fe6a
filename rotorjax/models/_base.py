"""The abstract component and the per-evaluation kinematic context."""

import abc

import equinox as eqx
import jax
import jax.numpy as jnp

from ._rotation import quarter_turn, rotate


class Kinematics(eqx.Module):
    """What every component may see at one instant.

    `x, y` locate the rotor's geometric centre C in the fixed frame, `xd, yd` are
    its velocity, and `theta, theta_dot` the prescribed spin angle and speed.
    """

    t: jax.Array
    theta: jax.Array
    theta_dot: jax.Array
    x: jax.Array
    y: jax.Array
    xd: jax.Array
    yd: jax.Array

    def to_fixed(self, p: jax.Array) -> jax.Array:
        """Rotate a rotor-frame vector into the fixed frame."""
        return rotate(self.theta, p)

    def velocity_of(self, p: jax.Array, p_dot: jax.Array) -> jax.Array:
        """Fixed-frame velocity of a point at rotor-frame position `p` moving at
        rotor-frame velocity `p_dot` (transport + spin + relative)."""
        spin = self.theta_dot * quarter_turn(p)
        return jnp.stack([self.xd, self.yd]) + self.to_fixed(p_dot + spin)


class AbstractComponent(eqx.Module):
    """A physical component of a planar rotor scene.

    A component states its energies; the equations of motion come from Lagrange's
    equations by autodiff (`rotorjax.models.lagrange_accelerations`). It may own
    generalised coordinates of its own (`n_coords`, static); it always sees the
    rotor centre and the prescribed spin through `Kinematics`.
    """

    @property
    def n_coords(self) -> int:
        return 0

    def kinetic(self, kin: Kinematics, q: jax.Array, qd: jax.Array) -> jax.Array:
        return jnp.zeros(())

    def potential(self, kin: Kinematics, q: jax.Array) -> jax.Array:
        return jnp.zeros(())

    def dissipation(self, kin: Kinematics, q: jax.Array, qd: jax.Array) -> jax.Array:
        """Rayleigh dissipation function (half the dissipated power)."""
        return jnp.zeros(())

    def mass_moment(self, kin: Kinematics, q: jax.Array) -> jax.Array:
        """Static mass moment (kg m) about C in the rotor frame: its imbalance."""
        return jnp.zeros(2)

    def outputs(self, kin: Kinematics, q: jax.Array, qd: jax.Array) -> dict:
        return {}

    @abc.abstractmethod
    def describe(self) -> str:
        """One line for logs and reports."""
