"""The scene contract: what `solve/` and `analysis/` may rely on.

Every model in rotorjax is an `AbstractScene`: the required part is what time
integration needs. What else a scene can do it declares by type, subclassing the
abstract capability classes (equinox's abstract/final pattern; nothing is probed
by attribute):

| capability class        | methods                                  | used by                              |
|-------------------------|------------------------------------------|--------------------------------------|
| `AbstractScene`         | `state_size`, `vector_field`, `outputs`, | `simulate`, `sweep`, Floquet         |
|                         | `describe`, `speed`                      |                                      |
| `AbstractLinearScene`   | `linear_matrices(speed)`,                | modes, Campbell, critical speeds,    |
|                         | `unbalance_load(speed)`                  | Hopf points, margins, responses      |
| `AbstractShaftModel`    | nodes, `expand`, `project`, `full_rotor` | mode shapes, responses at nodes, UCS,|
|                         | (also `FlexibleRotor`, `ReducedRotor`)   | level I, static deflection           |
| `AbstractRotatingScene` | `n_dof`, `to_rotating`, `to_fixed`       | stationary regimes, their stability, |
|                         |                                          | continuation                         |
| `AbstractContactScene`  | `contact_indicator`,                     | `simulate_events`                    |
|                         | `vector_field(t, y, active)`             |                                      |
| `AbstractEnergyScene`   | `energy(y)` (+ a work state)             | energy-balance checks                |
| `AbstractLocalScene`    | `local_forces()`: the linear part and    | harmonic balance condensed to the    |
|                         | the forces at a few coordinates          | coordinates the forces read          |

A missing capability raises `MissingCapability` (an `InputError`) naming the
scene and what the analysis needed, never an `AttributeError` deep inside.
The speed is called `speed` everywhere (rad/s in SI scenes; the paper's
dimensionless `nu`, `n`, `N`, `omega` in the published ones, kept as aliases).
"""

import abc
from typing import Callable, NamedTuple

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
    """A rotor model: its state, equations, outputs and prescribed speed. What it can
    do beyond time integration it declares by subclassing the capability classes
    below (`AbstractLinearScene`, `AbstractRotatingScene`, `AbstractContactScene`,
    `AbstractEnergyScene`); an analysis names the capability it needs and
    `require` refuses a scene that is not one with `MissingCapability`."""

    speed: eqx.AbstractVar[AbstractSpeedProfile]

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

    @property
    def n_contacts(self) -> int:
        """Number of contacts (`AbstractContactScene`); none here."""
        return 0

    def check_state(self, y) -> None:
        """Refuse (`InputError`) a concrete state outside the scene's domain (a journal
        outside its clearance); every state is in it here."""
        return None

    def weight_coordinates(self):
        """`(indices, identical)`: the positions in `q` of coordinates that are
        angles of balancing weights (periodic, 2 pi), and whether the weights are
        interchangeable (identical masses). None here."""
        import numpy as np

        return np.zeros(0, dtype=int), True


# --- capabilities -----------------------------------------------------------------------

class AbstractLinearSystem(eqx.Module):
    """Anything with linear(ised) equations `M q'' + (C + G) q' + K q = f` at each
    speed: a finite-element rotor, a reduced one, a linear scene."""

    @abc.abstractmethod
    def linear_matrices(self, speed) -> LinearMatrices:
        """The linear(ised) equations about the reference motion at `speed`."""

    @property
    def n_coordinates(self) -> int:
        """Length of `q` in `linear_matrices`."""
        return self.linear_matrices(0.0).M.shape[0]


class SpinMatrices(AbstractLinearSystem):
    """A linear system given by its matrices, the speed entering through the
    gyroscopic matrix alone: `(M, C, speed G1, K)`. A rotor whose bearings do not
    depend on speed, assembled once (`FlexibleRotor.reduced_matrices`) for analyses
    that evaluate it at many speeds (a critical speed's iterations)."""

    M: jax.Array
    C: jax.Array
    G1: jax.Array
    K: jax.Array

    def linear_matrices(self, speed) -> LinearMatrices:
        return LinearMatrices(M=self.M, C=self.C, G=speed * self.G1, K=self.K)


class AbstractShaftModel(AbstractLinearSystem):
    """A finite-element shaft layout: `n_nodes` nodes of four dofs `(x, y, sx, sy)`
    (then the supports' pedestals), the free dofs, and the coordinates the linear
    matrices are written in (the free dofs, or modal amplitudes). `FlexibleRotor`,
    `ReducedRotor` and `RotorScene` are shaft models: the node-based analyses
    (mode shapes, whirl, responses at nodes, UCS, level I, static deflection) need
    this capability."""

    @property
    @abc.abstractmethod
    def full_rotor(self):
        """The `FlexibleRotor` behind the coordinates (nodes, bearings, supports)."""

    @property
    @abc.abstractmethod
    def n_coordinates(self) -> int:
        """Length of `q` in `linear_matrices` (free dofs, or modes)."""

    @abc.abstractmethod
    def reduced_matrices(self, speed=0.0):
        """The bare shaft's `(M, C, G1, K)` in the coordinates (bearings at `speed`)."""

    @abc.abstractmethod
    def expand(self, q):
        """Coordinates (vector or columns) to all dofs, fixed dofs zero."""

    @abc.abstractmethod
    def project(self, f):
        """A load on the free dofs to a load on the coordinates."""

    @property
    def n_nodes(self) -> int:
        return self.full_rotor.n_nodes

    @property
    def n_dofs(self) -> int:
        return self.full_rotor.n_dofs

    @property
    def free_dofs(self):
        return self.full_rotor.free_dofs

    @property
    def speed_dependent(self) -> bool:
        """Whether any bearing's coefficients are tabulated against speed."""
        return self.full_rotor.speed_dependent


class AbstractLinearScene(AbstractScene, AbstractLinearSystem):
    """A scene with linear(ised) equations and an unbalance load on them: modes,
    Campbell diagrams, critical speeds, Hopf points, stability margins, unbalance
    and frequency responses."""

    @abc.abstractmethod
    def unbalance_load(self, speed) -> jax.Array:
        """Complex load `F` of the scene's unbalance at `speed` on the coordinates of
        `linear_matrices`: the synchronous force is `Re(F e^{i speed t})`."""


class AbstractRotatingScene(AbstractScene):
    """A scene whose state can be seen in the frame spinning with the rotor:
    stationary regimes, their stability, continuation."""

    @property
    @abc.abstractmethod
    def n_dof(self) -> int:
        """Number of generalised coordinates `q` (the state starts `(q, q')`)."""

    @abc.abstractmethod
    def to_rotating(self, t, y) -> jax.Array:
        """The state seen in the frame spinning with the rotor."""

    @abc.abstractmethod
    def to_fixed(self, t, z) -> jax.Array:
        """Inverse of `to_rotating`."""


class AbstractContactScene(AbstractScene):
    """A scene with contacts: `vector_field(t, y, active)` smooth for a fixed contact
    set, and `contact_indicator` (event-located runs, `simulate_events`)."""

    @abc.abstractmethod
    def contact_indicator(self, t, y) -> jax.Array:
        """One value per contact, positive exactly where it acts."""


class AbstractEnergyScene(AbstractScene):
    """A scene with an energy balance: `energy(y)`, whose change equals the work
    state's."""

    @abc.abstractmethod
    def energy(self, y) -> jax.Array:
        """Mechanical energy of state `y`."""

    @abc.abstractmethod
    def without_work(self) -> "AbstractScene":
        """The same scene without the work state (which grows along a periodic
        motion: harmonic balance and shooting need a state that returns), its state
        the first `state_size` entries of this one's."""


class AbstractReducibleScene(AbstractScene):
    """A scene whose shaft can be reduced to its lowest modes (a finite-element
    rotor's): what a time run's plan uses to model only what the run reaches."""

    @property
    @abc.abstractmethod
    def reducible(self) -> bool:
        """Whether the shaft is whole (a reduced one is not reduced again)."""

    @abc.abstractmethod
    def reduction_basis(self):
        """`(w, Phi)`: the Ritz basis `reduce` draws on, the shaft's undamped modes
        at rest, ascending by frequency `w` (rad per time unit), mass-normalised."""

    @abc.abstractmethod
    def reduce(self, n_modes) -> "AbstractReducibleScene":
        """The scene with its shaft reduced to the `n_modes` lowest modes."""

    @abc.abstractmethod
    def reduction_maps(self, n_modes):
        """`(E, P)`: `y = E y_r` expands a state of `reduce(n_modes)`, `y_r = P y`
        projects one of this scene on it, `P E = I`."""


class LocalForces(eqx.Module):
    """A scene's equations split into a linear part and forces that read a few
    coordinates: with `y = (q, q')` (`q` the first `n_q = S.shape[1]` states),

        y' = A y + a0 + E force(t, S q, S q'),

    `A` `(n, n)`, `a0` `(n,)`, `S` `(m, n_q)` (the `m` read coordinates, a node's
    displacements), `E` `(n, k)` and `force(t, x, v)` `(k,)` (the forces, at the read
    coordinates and at others they do not depend on: an unbalance's). Harmonic
    balance then solves for the `m` read coordinates' harmonics alone, the rest of the
    motion a linear response to the forces (`rotorjax.analysis`, `_condensed`)."""

    A: jax.Array
    a0: jax.Array
    S: jax.Array
    E: jax.Array
    force: Callable


class AbstractLocalScene(AbstractScene):
    """A scene whose nonlinear and time-dependent forces act at a few coordinates
    (a finite-element rotor's bearings and unbalances at its nodes)."""

    @abc.abstractmethod
    def local_forces(self) -> LocalForces | None:
        """The split of the equations (`LocalForces`), or None where this scene is
        not of that form (components with coordinates of their own, a work state, a
        speed that varies)."""


def rotating_field(scene, t, z):
    """`dz/dt` of the rotating-frame state `z` of `scene` at time `t`, by the chain
    rule through `to_rotating` (one forward-mode product):
    `z' = (d to_rotating / dy) f(t, y) + d to_rotating / dt`, `y = to_fixed(t, z)`.
    Autonomous (independent of `t`) for a constantly spinning isotropic scene."""
    t = jnp.asarray(t, dtype=jnp.float64)
    y = scene.to_fixed(t, z)
    return jax.jvp(scene.to_rotating, (t, y), (jnp.ones_like(t), scene.vector_field(t, y)))[1]


#: each capability (by the method an analysis calls) and the class that declares it
CAPABILITIES = {
    "linear_matrices": AbstractLinearScene, "unbalance_load": AbstractLinearScene,
    "n_dof": AbstractRotatingScene, "to_rotating": AbstractRotatingScene, "to_fixed": AbstractRotatingScene,
    "contact_indicator": AbstractContactScene, "energy": AbstractEnergyScene, "without_work": AbstractEnergyScene,
    "shaft": AbstractShaftModel, "linear_system": AbstractLinearSystem, "reduce": AbstractReducibleScene,
    "local_forces": AbstractLocalScene,
}

_WHAT = {AbstractLinearScene: "no linear or linearisable part (it is not an AbstractLinearScene)",
         AbstractRotatingScene: "no rotating frame (it is not an AbstractRotatingScene)",
         AbstractContactScene: "no contacts (it is not an AbstractContactScene)",
         AbstractEnergyScene: "no energy balance (it is not an AbstractEnergyScene)",
         AbstractLinearSystem: "no linear equations (it is not an AbstractLinearSystem: a linear scene, a "
                               "FlexibleRotor, a ReducedRotor or a CantileverRotor)",
         AbstractShaftModel: "no finite-element shaft layout (it is not an AbstractShaftModel: a FlexibleRotor, "
                             "ReducedRotor or RotorScene)",
         AbstractReducibleScene: "no shaft to reduce (it is not an AbstractReducibleScene: a RotorScene)",
         AbstractLocalScene: "no split into a linear part and local forces (it is not an AbstractLocalScene: a "
                             "RotorScene)"}


def provides(scene, capability: str) -> bool:
    """Whether `scene` is an instance of the class that declares `capability` (one
    of `CAPABILITIES`'s keys)."""
    if capability not in CAPABILITIES:
        raise ValueError(f"unknown capability {capability!r}")
    return isinstance(scene, CAPABILITIES[capability])


def _name(obj) -> str:
    try:
        return f"{type(obj).__name__} ({obj.describe()})"
    except Exception:  # not a scene: its type names it
        return type(obj).__name__


def require(scene, capability: str, needed_by: str):
    """Raise `MissingCapability` unless `scene` provides `capability`: the message
    names the scene, the analysis and the capability class it needs."""
    if capability not in ("shaft", "linear_system") and not isinstance(scene, AbstractScene):
        raise InputError(f"{needed_by} needs a rotorjax scene (rotorjax.models.AbstractScene), got "
                         f"{type(scene).__name__}")
    if not provides(scene, capability):
        raise MissingCapability(f"{needed_by} needs a scene with `{capability}`; {_name(scene)} has "
                                f"{_WHAT[CAPABILITIES[capability]]}")
