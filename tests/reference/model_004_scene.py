"""Model 004's scene as it was hand-assembled before it became a `RotorScene`
composition of the shared components (`rotorjax.models.cantilever_scene`): the
independent reference the composition is tested against (equal vector fields,
outputs, linear matrices and unbalance loads at random states). Its weight load
omits the clamped node's share of the first element's consistent load, which
`Gravity` includes.

State `y = (q, q', W)`: the rotor's coordinates (the free FE dofs, or the amplitudes
of its lowest undamped modes with `n_modes`), their rates, and `W`, the work done
on the lateral motion by the non-conservative forces. Energy bookkeeping:
`E(t) - E(0) = W(t)` with `E = q'^T M q' / 2 + q^T K q / 2 - F_g^T q`.
"""

import equinox as eqx
import jax
import jax.numpy as jnp

from rotorjax.models._cantilever import CantileverRotor
from rotorjax.models._contract import AbstractContactScene, AbstractEnergyScene, AbstractLinearScene, LinearMatrices
from rotorjax.models._frequency import frequency_response
from rotorjax.models._limiters import Limiters
from rotorjax.models._speed import ConstantSpeed
from rotorjax.models._validate import InputError, as_param, check_type


class CantileverScene(AbstractLinearScene, AbstractContactScene, AbstractEnergyScene):
    """Model 004's hand-assembled scene (the reference of `cantilever_scene`).

    Model 004 at spin speed `N` (the paper's symbol for the speed; `scene.speed` is
    its `ConstantSpeed`) with mass eccentricity `eps` (phase `phase`), weight `gamma`
    (0: vertical axis or weight neglected, as in the paper), and `limiters`
    (`rotorjax.contact.Limiters`, or None). `n_modes`: simulate on the lowest
    undamped modes (None: all FE dofs).

    A scene with linear matrices (`linear_matrices`, `unbalance_load`, on its
    coordinates `q`), contacts (`contact_indicator`, `vector_field(t, y, active)`)
    and an energy balance (`energy`, the work state `W`)."""

    rotor: eqx.Module
    limiters: eqx.Module | None
    N: jax.Array
    eps: jax.Array
    phase: jax.Array
    gamma: jax.Array
    basis: jax.Array
    M: jax.Array
    Minv: jax.Array
    D: jax.Array          # C + Ci
    G1: jax.Array
    K: jax.Array
    CiJ: jax.Array
    unit_weight: jax.Array  # modal load of a unit weight along -x
    disk: jax.Array         # rows of the basis at the disk's x, y, sx, sy

    def __init__(self, rotor, N, eps=0.0, phase=0.0, gamma=0.0, limiters=None, n_modes=None):
        check_type("rotor", rotor, CantileverRotor, "a rotorjax.flexible.CantileverRotor")
        if limiters is not None and not isinstance(limiters, Limiters):
            raise InputError(f"limiters must be a rotorjax.contact.Limiters or None, got "
                             f"{type(limiters).__name__}")
        self.rotor, self.limiters = rotor, limiters
        self.N = as_param("N (spin speed)", N, shape=())
        self.eps = as_param("eps (eccentricity)", eps, sign="nonnegative", shape=())
        self.phase = as_param("phase", phase, shape=())
        self.gamma = as_param("gamma (weight)", gamma, sign="nonnegative", shape=())
        M, C, G1, K, Ci, J = rotor.matrices()
        P = jnp.eye(M.shape[0]) if n_modes is None else rotor.modal_basis(n_modes)
        self.basis = P
        self.M, self.G1, self.K = P.T @ M @ P, P.T @ G1 @ P, P.T @ K @ P
        self.D, self.CiJ = P.T @ (C + Ci) @ P, P.T @ Ci @ J @ P
        self.Minv = jnp.linalg.inv(self.M)
        ex = jnp.zeros(M.shape[0]).at[0::4].set(1.0)   # rigid unit x translation field
        self.unit_weight = -(P.T @ (M @ ex))
        self.disk = P[rotor.disk_dofs]

    @property
    def n_coords(self) -> int:
        return self.basis.shape[1]

    @property
    def state_size(self) -> int:
        return 2 * self.n_coords + 1

    @property
    def n_dof(self) -> int:
        return self.n_coords

    @property
    def n_contacts(self) -> int:
        return 0 if self.limiters is None else self.limiters.n

    @property
    def speed(self):
        """The speed profile: `ConstantSpeed(N)`."""
        return ConstantSpeed(self.N)

    @property
    def disk_radius(self):
        return self.rotor.beta**0.5 * 2  # eps_D / 2 = 2 sqrt(beta) for a thin disk

    def describe(self) -> str:
        lim = "no limiters" if self.limiters is None else self.limiters.describe()
        return (f"cantilever rotor, {self.rotor.n_elements} elements, {self.n_coords} coordinates, "
                f"{lim}")

    def split(self, y):
        n = self.n_coords
        return y[:n], y[n:2 * n], y[2 * n]

    def disk_state(self, y):
        q, qd, _ = self.split(y)
        return self.disk[:2] @ q, self.disk[:2] @ qd

    def unbalance(self, t):
        a = self.N * t + self.phase
        return self.eps * self.N**2 * jnp.stack([jnp.cos(a), jnp.sin(a)])

    def contact(self, t, y, active=None):
        """Force of the limiters on the disk and the normal forces."""
        if self.limiters is None:
            return jnp.zeros(2), jnp.zeros(0)
        pos, vel = self.disk_state(y)
        return self.limiters.force(pos, vel, self.N, self.disk_radius, active)

    def contact_indicator(self, t, y):
        if self.limiters is None:
            return jnp.zeros(0)
        pos, vel = self.disk_state(y)
        return self.limiters.indicator(pos, vel)

    def vector_field(self, t, y, active=None):
        """`active=None`: smoothed contact; else the exact force with that contact set."""
        q, qd, _ = self.split(y)
        f_disk = self.unbalance(t) + self.contact(t, y, active)[0]
        f_nc = self.disk[:2].T @ f_disk
        f = f_nc + self.gamma * self.unit_weight
        qdd = self.Minv @ (f - (self.D + self.N * self.G1) @ qd - (self.K + self.N * self.CiJ) @ q)
        power = qd @ f_nc - qd @ (self.D @ qd) - self.N * qd @ (self.CiJ @ q)
        return jnp.concatenate([qd, qdd, power[None]])

    def without_work(self):
        raise NotImplementedError("the reference formulation always keeps its work state")

    def energy(self, y):
        q, qd, _ = self.split(y)
        return 0.5 * qd @ (self.M @ qd) + 0.5 * q @ (self.K @ q) - self.gamma * self.unit_weight @ q

    def outputs(self, t, y):
        q, qd, work = self.split(y)
        pos, vel = self.disk[:2] @ q, self.disk[:2] @ qd
        # normal forces of the exact contact law at this state (for a smoothed run,
        # the applied ones differ by O(ell))
        active = None if self.limiters is None else self.contact_indicator(t, y) > 0
        _, normal = self.contact(t, y, active)
        return {"disk_x": pos[0], "disk_y": pos[1], "disk_vx": vel[0], "disk_vy": vel[1],
                "disk_tilt_x": self.disk[2] @ q, "disk_tilt_y": self.disk[3] @ q,
                "radius": jnp.sqrt(pos @ pos), "energy": self.energy(y), "work": work,
                "normal_forces": normal}

    def rest_state(self):
        """Straight-line rotation (with the static sag under weight)."""
        q = jnp.linalg.solve(self.K + self.N * self.CiJ, self.gamma * self.unit_weight)
        return jnp.concatenate([q, jnp.zeros(self.n_coords), jnp.zeros(1)])

    def linear_matrices(self, speed=None) -> LinearMatrices:
        """`M q'' + (D + speed G1) q' + (K + speed CiJ) q = f` on the scene's
        coordinates at `speed` (default: the scene's `N`), `D = C + Ci`."""
        speed = self.N if speed is None else speed
        return LinearMatrices(self.M, self.D, speed * self.G1, self.K + speed * self.CiJ)

    def unbalance_load(self, speed=None) -> jax.Array:
        """The unbalance's complex load on the coordinates at `speed` (default `N`):
        `eps speed^2 e^{i phase}` along x at the disk, `-i` times that along y."""
        speed = self.N if speed is None else speed
        fx = self.eps * speed**2 * jnp.exp(1j * self.phase)
        return self.disk[0] * fx + self.disk[1] * (-1j * fx)

    def synchronous_state(self):
        """The linear steady unbalance response at `t = 0` (no contact, no weight)."""
        N = self.N
        lin = self.linear_matrices(N)
        Q = frequency_response(lin.M, lin.C + lin.G, lin.K, self.unbalance_load(N), N)
        return jnp.concatenate([jnp.real(Q), jnp.real(1j * N * Q), jnp.zeros(1)])
