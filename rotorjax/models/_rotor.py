"""The rigid rotor body (disk) on which the other components act."""

import jax
import jax.numpy as jnp

from ._base import AbstractComponent, Kinematics
from ._validate import as_param


class RigidRotor(AbstractComponent):
    """A rigid rotor body translating in the plane with a prescribed spin.

    Its geometric centre C is at `(x, y)`; the centre of mass is offset by the
    static eccentricity `eccentricity` at phase `phase` in the rotor frame, so

        T = m/2 |d/dt (C + s e^{i(theta + phase)})|^2 + I_p theta_dot^2 / 2.

    `polar_inertia` enters only the (prescribed) spin energy; `transverse_inertia`
    is kept for tilting scenes and plays no role in a planar (Jeffcott) scene.
    The rotor owns the two coordinates `x, y` of C.
    """

    mass: jax.Array
    eccentricity: jax.Array
    phase: jax.Array
    polar_inertia: jax.Array
    transverse_inertia: jax.Array

    def __init__(self, mass, eccentricity=0.0, phase=0.0, polar_inertia=0.0,
                 transverse_inertia=0.0):
        self.mass = as_param("mass", mass, sign="positive", shape=())
        self.eccentricity = as_param("eccentricity", eccentricity, sign="nonnegative", shape=())
        self.phase = as_param("phase", phase, shape=())
        self.polar_inertia = as_param("polar_inertia", polar_inertia, sign="nonnegative", shape=())
        self.transverse_inertia = as_param(
            "transverse_inertia", transverse_inertia, sign="nonnegative", shape=()
        )

    def _offset(self):
        return self.eccentricity * jnp.stack([jnp.cos(self.phase), jnp.sin(self.phase)])

    def kinetic(self, kin: Kinematics, q, qd):
        v = kin.velocity_of(self._offset(), jnp.zeros(2))
        return 0.5 * self.mass * (v @ v) + 0.5 * self.polar_inertia * kin.theta_dot**2

    def mass_moment(self, kin, q):
        return self.mass * self._offset()

    def outputs(self, kin, q, qd):
        return {"whirl_amplitude": jnp.hypot(kin.x, kin.y)}

    def describe(self):
        return "rigid rotor"
