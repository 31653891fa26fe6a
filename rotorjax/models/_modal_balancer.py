"""Model 003 with a ball auto-balancer: the modal shaft of `ModalShaft` with N balls
running on circles in the disk plane (Kovachev, eq. 24), dimensionless.

Fixed-frame coordinates: the complex modal amplitudes `v` (n) and the balls'
absolute angles `theta_j`; the disk spins at the prescribed `theta0(t)`, the
imbalance `m0` sits at radius 1 and angle `theta0`. With `V = a^T v` the disk centre,

    (E + Jt B + m A) v'' + (d E + i g Jp theta0' B) v' + (diag k^4 + i (g/2) Jp theta0'' B) v
        = m0 (theta0'^2 - i theta0'') e^{i theta0} a + sum_j m_j r_j (theta_j'^2 - i theta_j'') e^{i theta_j} a
    theta_j'' + Im[V'' e^{-i theta_j}] / r_j + d_j (theta_j' - theta0') = 0

(`m` is disk + imbalance + balls, `g = 2` reproduces the paper's `J = Jt + 2 Jp`,
`g = -1` the standard `Jt - Jp`).

These equations are not coded by hand: the disk's parts are the shared planar
components, seen at the disk centre `V = a^T v` (`ModalBalancerRotor.components`):
the imbalance is a `RigidRotor` of mass `m0` with eccentricity 1, each ball an
`AutoBalancer` with one pendulum-type weight (`K = 1`) on a circular race of radius
`r_j` and drag `d_j m_j` (its coordinate `psi_j = theta_j - theta0`). Their energies
give, by Lagrange's equations (autodiff, `lagrange_terms`), the balls' equations and
their and the imbalance's forces and inertia on the shaft; the modal shaft adds its
own linear part (the disk's mass less the imbalance and the balls, `Jt`, damping,
gyroscopic terms, `diag k^4`), and one linear solve gives the accelerations. A test
(`tests/models/test_model003_composition.py`) checks this against the hand-written
eq. (24) above at random states.

In the rotating frame (`w = v e^{-i theta0}`, `alpha_j = theta_j - theta0`; at constant
speed `theta0 = omega t`) the stationary regimes are (eqs. 25-30; analyses in
`rotorjax.analysis`): balanced C (`w = 0`, balls cancel the imbalance),
pseudo-balanced PS (`a^T w = 0` with a bent shaft, only for `d = 0`), and unbalanced
NS1/NS2/NS3 by the balancing coefficient `sigma = sum_j m_j r_j (-1)^{delta_j} / m0`.
"""

import jax
import jax.numpy as jnp

from ._balancer import AutoBalancer, Race
from ._base import Kinematics
from ._contract import AbstractRotatingScene, rotating_field
from ._lagrange import lagrange_terms
from ._modal import ModalShaft
from ._rotor import RigidRotor
from ._rotation import to_fixed_pair, to_rotating_pair
from ._speed import AbstractSpeedProfile
from ._validate import InputError, as_param, check_type, is_concrete, per_item


class ModalBalancerRotor(AbstractRotatingScene):
    """Model 003's shaft + disk (`shaft`, whose `m` must include the balls' mass)
    with balls of masses `ball_mass` (N,), radii `ball_radius` and drags `ball_drag`
    (units `m_S`, `r0`, `m_j r_j^2 omega_1`), spun by `speed` (a speed profile). A
    scene (state `(Re v, Im v, theta, d/dt ...)`) with a rotating frame
    (`to_rotating`, `to_fixed`). The imbalance and the balls are the shared
    components `RigidRotor` and `AutoBalancer` (`components`); their energies give
    their equations (see the module docstring)."""

    shaft: ModalShaft
    ball_mass: jax.Array
    ball_radius: jax.Array
    ball_drag: jax.Array
    speed: AbstractSpeedProfile

    def __init__(self, shaft, ball_mass, ball_radius, ball_drag, speed):
        check_type("shaft", shaft, ModalShaft, "a rotorjax.flexible.ModalShaft")
        self.shaft = shaft
        self.ball_mass = as_param("ball_mass", ball_mass, sign="positive")
        if self.ball_mass.ndim != 1:
            raise InputError(f"ball_mass must be a 1-D array with one entry per ball (empty: the shaft "
                             f"without a balancer), got shape {self.ball_mass.shape}")
        n = self.ball_mass.shape[0]
        self.ball_radius = per_item("ball_radius", ball_radius, n, sign="positive", what="ball")
        self.ball_drag = per_item("ball_drag", ball_drag, n, sign="nonnegative", what="ball")
        check_type("speed", speed, AbstractSpeedProfile, "a speed profile (ConstantSpeed, RunUp, ...)")
        self.speed = speed

    @property
    def n_balls(self):
        return self.ball_mass.shape[0]

    @property
    def state_size(self):
        return 2 * (2 * self.shaft.n_modes + self.n_balls)

    def describe(self):
        return f"modal shaft ({self.shaft.n_modes} modes) with {self.n_balls} balls"

    def _g(self):
        return 2.0 if self.shaft.gyroscopic == "paper" else -1.0

    def _split(self, y):
        n, N = self.shaft.n_modes, self.n_balls
        q, qd = y[: 2 * n + N], y[2 * n + N:]
        return q[:n] + 1j * q[n:2 * n], q[2 * n:], qd[:n] + 1j * qd[n:2 * n], qd[2 * n:]

    @property
    def components(self):
        """The disk's parts, as the shared planar components (`rotorjax.models`) seen at
        the disk centre: the imbalance, `RigidRotor(m0, eccentricity=1)` (absent when
        `m0` is a concrete 0), then one `AutoBalancer` per ball (one pendulum-type
        weight of mass `m_j` on a circular `Race` of radius `r_j`, drag `d_j m_j`, so
        that its torque is `d_j m_j r_j^2 (theta_j' - theta0')`). Built from the
        rotor's fields, so they follow any change of them (`eqx.tree_at`, tracing)."""
        parts = []
        m0 = self.shaft.m0
        if not (is_concrete(m0) and float(m0) == 0.0):
            parts.append(RigidRotor(m0, 1.0))
        for j in range(self.n_balls):
            parts.append(AutoBalancer(self.ball_mass[j:j + 1], Race.circular(self.ball_radius[j]),
                                      self.ball_drag[j] * self.ball_mass[j], kind="pendulum"))
        return tuple(parts)

    def _shaft_terms(self, t, q, qd):
        """The modal shaft's own part, `(M, f)` with `M q'' = f` over all coordinates:
        the disk's mass without the imbalance and the balls (their inertia comes with
        their energies), `Jt`, the external damping, the gyroscopic terms and the
        stiffness `diag k^4`."""
        s = self.shaft
        n, N = s.n_modes, self.n_balls
        a, b, k = s.mode_vectors()
        g = self._g()
        th0d, th0dd = self.speed.speed(t), self.speed.acceleration(t)
        B = jnp.outer(b, b)
        own_mass = s.m - s.m0 - jnp.sum(self.ball_mass)
        Mc = jnp.eye(n) + s.Jt * B + own_mass * jnp.outer(a, a)
        v, vd = q[:n] + 1j * q[n:2 * n], qd[:n] + 1j * qd[n:2 * n]
        f = -(s.d * vd + 1j * g * s.Jp * th0d * (B @ vd) + k**4 * v + 0.5j * g * s.Jp * th0dd * (B @ v))
        mass = jnp.zeros((self.n_dof, self.n_dof)).at[:n, :n].set(Mc).at[n:2 * n, n:2 * n].set(Mc)
        return mass, jnp.concatenate([jnp.real(f), jnp.imag(f), jnp.zeros(N)])

    def _disk_terms(self, t, q, qd, parts):
        """The disk's parts by Lagrange's equations of their summed energies in the
        local coordinates `r = (Re V, Im V, psi)`, `V = a^T v`, `psi = theta - theta0(t)`
        (as `RotorScene` does at a node), carried to `(v, theta)` by `r = A q - e theta0`:
        `M += A^T M_r A`, `f += A^T (f_r + M_r e theta0'')`."""
        n, N = self.shaft.n_modes, self.n_balls
        a, _, _ = self.shaft.mode_vectors()
        A = jnp.zeros((2 + N, self.n_dof)).at[0, :n].set(a).at[1, n:2 * n].set(a)
        A = A.at[2:, 2 * n:].set(jnp.eye(N))
        e = jnp.zeros(2 + N).at[2:].set(1.0)
        r, rd = A @ q - e * self.speed.angle(t), A @ qd - e * self.speed.speed(t)
        slices, start = [], 2
        for c in parts:
            slices.append(slice(start, start + c.n_coords))
            start += c.n_coords

        def kinematics(r, rd, tt):
            return Kinematics(t=tt, theta=self.speed.angle(tt), theta_dot=self.speed.speed(tt), x=r[0], y=r[1],
                              xd=rd[0], yd=rd[1])

        def lagrangian(r, rd, tt):
            kin = kinematics(r, rd, tt)
            return sum(c.kinetic(kin, r[sl], rd[sl]) - c.potential(kin, r[sl]) for c, sl in zip(parts, slices))

        def dissipation(r, rd, tt):
            kin = kinematics(r, rd, tt)
            return sum(c.dissipation(kin, r[sl], rd[sl]) for c, sl in zip(parts, slices))

        m_r, f_r = lagrange_terms(lagrangian, dissipation, r, rd, t)
        return A.T @ m_r @ A, A.T @ (f_r + (m_r @ e) * self.speed.acceleration(t))

    def vector_field(self, t, y, args=None):
        t = jnp.asarray(t, dtype=jnp.float64)
        q, qd = y[: self.n_dof], y[self.n_dof:]
        mass, rhs = self._shaft_terms(t, q, qd)
        parts = self.components
        if parts:
            m_d, f_d = self._disk_terms(t, q, qd, parts)
            mass, rhs = mass + m_d, rhs + f_d
        return jnp.concatenate([qd, jnp.linalg.solve(mass, rhs)])

    def outputs(self, t, y):
        v, th, _, _ = self._split(y)
        a, _, _ = self.shaft.mode_vectors()
        th0 = self.speed.angle(t)
        rel = th - th0
        imbalance = self.shaft.m0 + jnp.sum(self.ball_mass * self.ball_radius * jnp.exp(1j * rel))
        return {"whirl_amplitude": jnp.abs(a @ v), "weight_angles": jnp.angle(jnp.exp(1j * rel)),
                "residual_imbalance": jnp.abs(imbalance)}

    def state(self, v, theta, vd=None, thetad=None):
        v = jnp.asarray(v, dtype=jnp.complex128)
        vd = jnp.zeros_like(v) if vd is None else jnp.asarray(vd, dtype=jnp.complex128)
        theta = jnp.asarray(theta, dtype=jnp.float64)
        thetad = jnp.zeros_like(theta) if thetad is None else jnp.asarray(thetad, dtype=jnp.float64)
        return jnp.concatenate([jnp.real(v), jnp.imag(v), theta, jnp.real(vd), jnp.imag(vd), thetad])

    # --- rotating frame -----------------------------------------------------------------
    @property
    def n_dof(self):
        return 2 * self.shaft.n_modes + self.n_balls

    def to_rotating(self, t, y):
        """`z = (Re w, Im w, alpha, d/dt ...)`: the modal amplitudes seen from the
        frame spinning with the disk, `w = v e^{-i theta0(t)}`, and the balls' angles
        relative to the imbalance, `alpha_j = theta_j - theta0(t)`."""
        n = self.shaft.n_modes
        th0, th0d = self.speed.angle(t), self.speed.speed(t)
        q, qd = y[: self.n_dof], y[self.n_dof:]
        w, wd = to_rotating_pair(th0, th0d, jnp.stack([q[:n], q[n:2 * n]]), jnp.stack([qd[:n], qd[n:2 * n]]))
        return jnp.concatenate([w[0], w[1], q[2 * n:] - th0, wd[0], wd[1], qd[2 * n:] - th0d])

    def to_fixed(self, t, z):
        """Inverse of `to_rotating`: `v = w e^{i theta0}`, `v' = (w' + i theta0' w) e^{i theta0}`,
        `theta_j = alpha_j + theta0`."""
        n = self.shaft.n_modes
        th0, th0d = self.speed.angle(t), self.speed.speed(t)
        p, pd = z[: self.n_dof], z[self.n_dof:]
        v, vd = to_fixed_pair(th0, th0d, jnp.stack([p[:n], p[n:2 * n]]), jnp.stack([pd[:n], pd[n:2 * n]]))
        return jnp.concatenate([v[0], v[1], p[2 * n:] + th0, vd[0], vd[1], pd[2 * n:] + th0d])

    def rotating_field(self, z):
        """`dz/dt` in the rotating frame at `t = 0` (autonomous at constant speed):
        the scene contract's chain rule through `to_rotating`."""
        return rotating_field(self, 0.0, z)
