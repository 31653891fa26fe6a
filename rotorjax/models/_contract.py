"""The scene contract: what `solve/` and `analysis/` may rely on.

Every model in rotorjax is an `AbstractScene`. The required part is what time
integration needs; the optional parts are capabilities an analysis asks for and
a scene provides only where they make sense:

| capability              | methods                                  | used by                              |
|-------------------------|------------------------------------------|--------------------------------------|
| time integration        | `state_size`, `vector_field`, `outputs`, | `simulate`, `sweep`, Floquet         |
|                         | `describe`, `speed`                      |                                      |
| linear(ised) matrices   | `linear_matrices(speed)`                 | modes, Campbell, critical speeds,    |
|                         |                                          | Hopf points, stability margins       |
| unbalance response      | `unbalance_load(speed)`, `linear_matrices`| frequency response                   |
| rotating frame          | `n_dof`, `to_rotating`, `to_fixed`       | stationary regimes, their stability, |
|                         |                                          | continuation                         |
| contacts                | `n_contacts`, `contact_indicator`,       | `simulate_events`                    |
|                         | `vector_field(t, y, active)`             |                                      |
| energy                  | `energy(y)` (+ a work state)             | energy-balance checks                |

A missing capability raises `MissingCapability` (an `InputError`) naming the
scene and what the analysis needed, never an `AttributeError` deep inside.
The speed is called `speed` everywhere (rad/s in SI scenes; the paper's
dimensionless `nu`, `n`, `N`, `omega` in the published ones, kept as aliases).
"""

import abc
from typing import NamedTuple

import equinox as eqx
import jax
import jax.numpy as jnp

from .._errors import InputError
from ._speed import AbstractSpeedProfile


class MissingCapability(InputError):
    """The scene does not provide what an analysis needs."""


class LinearMatrices(NamedTuple):
    """The linear(ised) equations about a scene's reference motion at one speed,
    `M q'' + (C + G) q' + K q = f`: mass, damping, gyroscopic (already times the
    speed) and stiffness (with any circulatory terms) matrices."""

    M: jax.Array
    C: jax.Array
    G: jax.Array
    K: jax.Array

    def state_matrix(self) -> jax.Array:
        """First-order matrix `A` of `(q, q')' = A (q, q')`."""
        n = self.M.shape[0]
        minv = jnp.linalg.inv(self.M)
        return jnp.block([[jnp.zeros((n, n)), jnp.eye(n)],
                          [-minv @ self.K, -minv @ (self.C + self.G)]])


class AbstractScene(eqx.Module):
    """A rotor model: its state, equations, outputs and prescribed speed (see the
    module docstring for the optional capabilities)."""

    speed: eqx.AbstractVar[AbstractSpeedProfile]

    # --- required -------------------------------------------------------------------
    @property
    @abc.abstractmethod
    def state_size(self) -> int:
        """Length of the state vector `y`."""

    @abc.abstractmethod
    def vector_field(self, t, y, args=None) -> jax.Array:
        """`dy/dt` (pure, unbatched). `args` is the contact set for scenes with contacts."""

    @abc.abstractmethod
    def outputs(self, t, y) -> dict:
        """Named outputs at one instant (scalars or small arrays)."""

    @abc.abstractmethod
    def describe(self) -> str:
        """One line for logs and reports."""

    # --- optional capabilities ---------------------------------------------------------
    def linear_matrices(self, speed) -> LinearMatrices:
        """The linear(ised) equations about the reference motion at `speed`."""
        raise _missing(self, "linear_matrices", "a linear or linearisable part")

    def unbalance_load(self, speed) -> jax.Array:
        """Complex load `F` of the scene's unbalance at `speed` on the coordinates of
        `linear_matrices`: the synchronous force is `Re(F e^{i speed t})`."""
        raise _missing(self, "unbalance_load", "an unbalance on a linear part")

    @property
    def n_dof(self) -> int:
        """Number of generalised coordinates `q` (the state starts `(q, q')`)."""
        raise _missing(self, "n_dof", "a rotating-frame state layout")

    def to_rotating(self, t, y) -> jax.Array:
        """The state seen in the frame spinning with the rotor."""
        raise _missing(self, "to_rotating", "a rotating frame")

    def to_fixed(self, t, z) -> jax.Array:
        """Inverse of `to_rotating`."""
        raise _missing(self, "to_fixed", "a rotating frame")

    def weight_coordinates(self):
        """`(indices, identical)`: the positions in `q` of coordinates that are
        angles of balancing weights (periodic, 2 pi), and whether the weights are
        interchangeable (identical masses). None here."""
        import numpy as np

        return np.zeros(0, dtype=int), True

    @property
    def n_contacts(self) -> int:
        return 0

    def contact_indicator(self, t, y) -> jax.Array:
        """One value per contact, positive exactly where it acts."""
        raise _missing(self, "contact_indicator", "contacts")

    def energy(self, y) -> jax.Array:
        """Mechanical energy of state `y` (its change equals the work state's)."""
        raise _missing(self, "energy", "an energy balance")


def rotating_field(scene, t, z):
    """`dz/dt` of the rotating-frame state `z` of `scene` at time `t`, by the chain
    rule through `to_rotating` (one forward-mode product):
    `z' = (d to_rotating / dy) f(t, y) + d to_rotating / dt`, `y = to_fixed(t, z)`.
    Autonomous (independent of `t`) for a constantly spinning isotropic scene."""
    t = jnp.asarray(t, dtype=jnp.float64)
    y = scene.to_fixed(t, z)
    return jax.jvp(scene.to_rotating, (t, y), (jnp.ones_like(t), scene.vector_field(t, y)))[1]


def _missing(scene, name, what):
    return MissingCapability(f"{type(scene).__name__} ({scene.describe()}) has no {what} "
                             f"(`{name}`)")


_OPTIONAL = ("linear_matrices", "unbalance_load", "to_rotating", "to_fixed", "contact_indicator", "energy")


def provides(scene, capability: str) -> bool:
    """Whether `scene` implements the optional method `capability` (one of
    `linear_matrices`, `unbalance_load`, `to_rotating`, `to_fixed`,
    `contact_indicator`, `energy`)."""
    if capability not in _OPTIONAL:
        raise ValueError(f"unknown capability {capability!r}")
    method = getattr(type(scene), capability, None)
    return method is not None and method is not getattr(AbstractScene, capability)


def require(scene, capability: str, needed_by: str):
    """Raise `MissingCapability` unless `scene` is a scene that provides `capability`."""
    if not isinstance(scene, AbstractScene):
        raise InputError(f"{needed_by} needs a rotorjax scene (rotorjax.models.AbstractScene), got "
                         f"{type(scene).__name__}")
    if not provides(scene, capability):
        raise MissingCapability(f"{needed_by} needs a scene with `{capability}`; {type(scene).__name__} "
                                f"({scene.describe()}) does not provide it")
