"""Model 003 with a ball auto-balancer: the modal shaft of `ModalShaft` with N balls
running on circles in the disk plane (Kovachev, eq. 24), dimensionless.

Fixed-frame coordinates: the complex modal amplitudes `v` (n) and the balls'
absolute angles `theta_j`; the disk spins at the prescribed `theta0(t)`, the
imbalance `m0` sits at radius 1 and angle `theta0`. With `V = a^T v` the disk centre,

    (E + Jt B + m A) v'' + (d E + i g Jp theta0' B) v' + (diag k^4 + i (g/2) Jp theta0'' B) v
        = m0 (theta0'^2 - i theta0'') e^{i theta0} a + sum_j m_j r_j (theta_j'^2 - i theta_j'') e^{i theta_j} a
    theta_j'' + Im[V'' e^{-i theta_j}] / r_j + d_j (theta_j' - theta0') = 0

(`m` is disk + imbalance + balls, `g = 2` reproduces the paper's `J = Jt + 2 Jp`,
`g = -1` the standard `Jt - Jp`). The accelerations enter linearly; they are found
from the residual's Jacobian (autodiff) and one linear solve.

In the rotating frame (`w = v e^{-i theta0}`, `alpha_j = theta_j - theta0`; at constant
speed `theta0 = omega t`) the stationary regimes are (eqs. 25-30; analyses in
`rotorjax.flexible`): balanced C (`w = 0`, balls cancel the imbalance),
pseudo-balanced PS (`a^T w = 0` with a bent shaft, only for `d = 0`), and unbalanced
NS1/NS2/NS3 by the balancing coefficient `sigma = sum_j m_j r_j (-1)^{delta_j} / m0`.
"""

import jax
import jax.numpy as jnp

from ._contract import AbstractScene, rotating_field
from ._modal import ModalShaft
from ._rotation import to_fixed_pair, to_rotating_pair
from ._speed import AbstractSpeedProfile
from ._validate import InputError, as_param, check_type, per_item


class ModalBalancerRotor(AbstractScene):
    """Model 003's shaft + disk (`shaft`, whose `m` must include the balls' mass)
    with balls of masses `ball_mass` (N,), radii `ball_radius` and drags `ball_drag`
    (units `m_S`, `r0`, `m_j r_j^2 omega_1`), spun by `speed` (a speed profile). A
    scene (state `(Re v, Im v, theta, d/dt ...)`) with a rotating frame
    (`to_rotating`, `to_fixed`)."""

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

    def _residual(self, t, y, acc):
        s = self.shaft
        n = s.n_modes
        v, th, vd, thd = self._split(y)
        vdd, thdd = acc[:n] + 1j * acc[n:2 * n], acc[2 * n:]
        a, b, k = s.mode_vectors()
        th0, th0d, th0dd = self.speed.angle(t), self.speed.speed(t), self.speed.acceleration(t)
        g = self._g()
        B = jnp.outer(b, b)
        shaft = (vdd + s.Jt * b * (b @ vdd) + s.m * a * (a @ vdd) + s.d * vd
                 + 1j * g * s.Jp * th0d * (B @ vd) + k**4 * v + 1j * 0.5 * g * s.Jp * th0dd * (B @ v)
                 - s.m0 * (th0d**2 - 1j * th0dd) * jnp.exp(1j * th0) * a
                 - jnp.sum(self.ball_mass * self.ball_radius * (thd**2 - 1j * thdd) * jnp.exp(1j * th)) * a)
        ball = thdd + jnp.imag((a @ vdd) * jnp.exp(-1j * th)) / self.ball_radius + self.ball_drag * (thd - th0d)
        return jnp.concatenate([jnp.real(shaft), jnp.imag(shaft), ball])

    def vector_field(self, t, y, args=None):
        t = jnp.asarray(t, dtype=jnp.float64)
        zero = jnp.zeros(2 * self.shaft.n_modes + self.n_balls)
        r0 = self._residual(t, y, zero)
        jac = jax.jacfwd(lambda acc: self._residual(t, y, acc))(zero)
        acc = -jnp.linalg.solve(jac, r0)
        half = y.shape[0] // 2
        return jnp.concatenate([y[half:], acc])

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
