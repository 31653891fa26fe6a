"""A scene: the rotor, its prescribed spin, and only the components present."""

import equinox as eqx
import jax
import jax.numpy as jnp
import numpy as np

from ._balancer import AutoBalancer
from ._base import AbstractComponent, Kinematics
from ._contract import AbstractRotatingScene
from ._fastpath import planar_balancer_field
from ._lagrange import lagrange_accelerations
from ._rotation import to_fixed_pair, to_rotating_pair
from ._rotor import RigidRotor
from ._speed import AbstractSpeedProfile
from ._supports import Supports
from ._validate import InputError, as_components, as_numpy, check_choice, is_concrete


class Scene(AbstractRotatingScene):
    """A planar rotor scene.

    Generalised coordinates `q = (x, y, <each component's own coordinates>)`, in
    the order the components are given; the state is `y = (q, qd)`. The equations
    of motion are Lagrange's equations of the summed energies (`vector_field`),
    derived by autodiff: a new component only states its energies.

    Components absent from `components` are absent from the equations: there is
    no zero-mass balancer. Each topology (which components, how many weights)
    compiles once; parameter values are array leaves and may be batched with vmap.

    **Arguments:**
    - `rotor`: the `RigidRotor`.
    - `speed`: an `AbstractSpeedProfile` (the prescribed spin).
    - `components`: further components (`Supports`, `AutoBalancer`, ...).
    - `equations`: "auto" uses the hand-derived fast path of `_fastpath.py` for the
      planar balancer rotor (rotor + supports + one balancer, tested equal to the
      Lagrangian path) and the Lagrangian path otherwise; "lagrange" always derives
      the equations from the energies by autodiff.
    """

    rotor: RigidRotor
    speed: AbstractSpeedProfile
    components: tuple
    equations: str = eqx.field(static=True)

    def __init__(self, rotor, speed, components=(), equations="auto"):
        if not isinstance(rotor, RigidRotor):
            raise InputError(f"rotor must be a RigidRotor, got {type(rotor).__name__}")
        if not isinstance(speed, AbstractSpeedProfile):
            raise InputError(f"speed must be a speed profile (ConstantSpeed, RunUp, CustomSpeed), "
                             f"got {type(speed).__name__}")
        components = as_components(components, AbstractComponent, "rotorjax component",
                                   "Supports, AutoBalancer, ...")
        check_choice("equations", equations, ("auto", "lagrange"))
        self.rotor = rotor
        self.speed = speed
        self.components = components
        self.equations = equations

    # --- layout -----------------------------------------------------------------
    @property
    def n_dof(self) -> int:
        return 2 + sum(c.n_coords for c in self.components)

    @property
    def state_size(self) -> int:
        return 2 * self.n_dof

    def _slices(self):
        start, out = 2, []
        for c in self.components:
            out.append(slice(start, start + c.n_coords))
            start += c.n_coords
        return out

    def find(self, cls):
        """The first component of type `cls`, or `None` if the scene has none."""
        for c in self.components:
            if isinstance(c, cls):
                return c
        return None

    def coords_of(self, component, y):
        """`(q, qd)` of one component's own coordinates in state `y`."""
        for c, sl in zip(self.components, self._slices()):
            if c is component:
                n = self.n_dof
                return y[sl], y[n:][sl]
        raise InputError(f"component ({component.describe()}) is not part of this scene")

    # --- energies -----------------------------------------------------------------
    def kinematics(self, q, qd, t) -> Kinematics:
        t = jnp.asarray(t, dtype=jnp.float64)
        return Kinematics(
            t=t,
            theta=self.speed.angle(t),
            theta_dot=self.speed.speed(t),
            x=q[0], y=q[1], xd=qd[0], yd=qd[1],
        )

    def _parts(self):
        return ((self.rotor, slice(0, 0)),) + tuple(zip(self.components, self._slices()))

    def kinetic_energy(self, q, qd, t):
        kin = self.kinematics(q, qd, t)
        return sum(c.kinetic(kin, q[sl], qd[sl]) for c, sl in self._parts())

    def potential_energy(self, q, t=0.0):
        kin = self.kinematics(q, jnp.zeros_like(q), t)
        return sum(c.potential(kin, q[sl]) for c, sl in self._parts())

    def lagrangian(self, q, qd, t):
        return self.kinetic_energy(q, qd, t) - self.potential_energy(q, t)

    def dissipation(self, q, qd, t):
        kin = self.kinematics(q, qd, t)
        return sum(c.dissipation(kin, q[sl], qd[sl]) for c, sl in self._parts())

    # --- dynamics -----------------------------------------------------------------
    def accelerations(self, t, q, qd):
        return lagrange_accelerations(self.lagrangian, self.dissipation, q, qd, t)

    def _fast_path_parts(self):
        """`(supports, balancer)` when the hand-derived equations apply, else None."""
        if self.equations != "auto" or len(self.components) != 2:
            return None
        sup, bal = self.components
        if type(sup) is Supports and type(bal) is AutoBalancer:
            return sup, bal
        return None

    def vector_field(self, t, y, args=None):
        """`dy/dt` for one state and this scene's parameters (pure, unbatched)."""
        parts = self._fast_path_parts()
        if parts is not None:
            t = jnp.asarray(t, dtype=jnp.float64)
            return planar_balancer_field(self.rotor, parts[0], parts[1], self.speed, t, y)
        return self.lagrange_vector_field(t, y)

    def lagrange_vector_field(self, t, y, args=None):
        """`dy/dt` from Lagrange's equations of the components' energies (autodiff)."""
        n = self.n_dof
        q, qd = y[:n], y[n:]
        return jnp.concatenate([qd, self.accelerations(t, q, qd)])

    def mass_matrix(self, q, t=0.0):
        qd = jnp.zeros_like(q)
        return jax.hessian(self.kinetic_energy, argnums=1)(q, qd, t)

    # --- outputs -------------------------------------------------------------------
    def imbalance(self, t, y):
        """Residual imbalance of rotor + weights about C, in the rotor frame (kg m)."""
        n = self.n_dof
        q, qd = y[:n], y[n:]
        kin = self.kinematics(q, qd, t)
        return sum(c.mass_moment(kin, q[sl]) for c, sl in self._parts())

    def outputs(self, t, y) -> dict:
        """Named outputs at one instant: `whirl_amplitude`, `residual_imbalance`,
        and each component's own (e.g. `weight_angles`, rotor frame, radians)."""
        n = self.n_dof
        q, qd = y[:n], y[n:]
        kin = self.kinematics(q, qd, t)
        out = {}
        for c, sl in self._parts():
            out.update(c.outputs(kin, q[sl], qd[sl]))
        out["residual_imbalance"] = jnp.linalg.norm(self.imbalance(t, y))
        return out

    def weight_coordinates(self):
        bal = self.find(AutoBalancer)
        if bal is None:
            return np.zeros(0, dtype=int), True
        sl = next(sl for c, sl in zip(self.components, self._slices()) if c is bal)
        m = np.asarray(bal.mass) if is_concrete(bal.mass) else None
        same = m is not None and bool(np.all(m == m[0]))
        return np.arange(sl.start, sl.stop), same

    # --- rotating frame ---------------------------------------------------------------
    def to_rotating(self, t, y):
        """`z = (u, psi, u', psi')`: the rotor centre in the frame spinning with the
        rotor (the weights' coordinates are already relative to it)."""
        n = self.n_dof
        u, ud = to_rotating_pair(self.speed.angle(t), self.speed.speed(t), y[0:2], y[n:n + 2])
        return jnp.concatenate([u, y[2:n], ud, y[n + 2:]])

    def to_fixed(self, t, z):
        n = self.n_dof
        c, cd = to_fixed_pair(self.speed.angle(t), self.speed.speed(t), z[0:2], z[n:n + 2])
        return jnp.concatenate([c, z[2:n], cd, z[n + 2:]])

    def rest_state(self, angles=None) -> jax.Array:
        """A state with the rotor centred and at rest, weights at `angles` (race
        parameters, relative to the rotor) and at rest relative to the rotor."""
        q = [jnp.zeros(2)]
        for c, sl in zip(self.components, self._slices()):
            if c.n_coords:
                if angles is None:
                    q.append(jnp.linspace(0.0, 2 * np.pi, c.n_coords, endpoint=False))
                else:
                    if is_concrete(angles):
                        as_numpy("angles", angles, shape=(c.n_coords,))
                    a = jnp.asarray(angles, dtype=jnp.float64)
                    if a.shape != (c.n_coords,):
                        raise InputError(
                            f"angles must have shape ({c.n_coords},), got {a.shape}"
                        )
                    q.append(a)
        q = jnp.concatenate(q)
        return jnp.concatenate([q, jnp.zeros_like(q)])

    def describe(self) -> str:
        return ", ".join([self.rotor.describe()] + [c.describe() for c in self.components])
