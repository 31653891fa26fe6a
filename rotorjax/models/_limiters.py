"""Discrete visco-elastic limiters around a disk (model 004, eq. 10).

Limiter `k` sits at angle `alpha_k` with clearance `chi_k` to the disk's rim. With
the disk centre's displacement along the limiter's axis `e_k = (cos a, sin a)`,
`u_k = e_k . r`, the penetration is `delta_k = u_k - chi_k` and the normal force
`R_k = kappa_k delta_k + eta_k delta_k'`. The limiter pushes only while the disk
penetrates and the force is compressive: `R_k H(delta_k) H(R_k)`. Coulomb friction
`f_k R_k` opposes the slip of the disk's surface, whose speed along the tangent
`t_k = (-sin a, cos a)` is `V_k = N rho_D + t_k . r'` (`rho_D = eps_D / 2` the
disk's radius; the paper writes the same with its local axes). The force on the
disk is `-R_k (e_k + f_k sgn(V_k) t_k)`.

Two ways to evaluate the switch (`Limiters.force`):
- exact, given the set of limiters in contact (`active`), for event-located
  integration (`rotorjax.solve.simulate_events` finds where `min(delta_k, R_k)`
  changes sign);
- smoothed, with regularisation length `ell`: `delta -> ell softplus(delta / ell)`,
  the damping switched by `sigmoid(delta / ell)`, and the compressive clip
  `R -> R sigmoid(R / (ell kappa))` (zero at `R = 0`, so nothing leaks out of
  contact). The force converges to the exact one at first order in `ell` (tested);
  `ell` is in the units of the clearance.
`sgn(V)` is `tanh(V / v_reg)` with `v_reg = 1e-6`: in model 004 the rim speed
`N rho_D` (about 2 at `N = 15`) dwarfs the whirl velocities, so `V` never changes
sign in practice (its minimum is an output of the scene).
"""

import equinox as eqx
import jax
import jax.numpy as jnp
import numpy as np

from ._validate import as_param, as_vector, per_item


class Limiters(eqx.Module):
    """`N_S` massless visco-elastic limiters (see the module docstring).

    **Arguments:** `angles` (rad, one per limiter), and per limiter or shared:
    `clearance` (> 0), `stiffness` (>= 0), `damping` (>= 0), `friction` (>= 0).
    `smoothing`: the regularisation length `ell` (> 0) of the smoothed contact.
    """

    angles: jax.Array
    clearance: jax.Array
    stiffness: jax.Array
    damping: jax.Array
    friction: jax.Array
    smoothing: jax.Array
    slip_regularisation: float = eqx.field(static=True, default=1e-6)

    def __init__(self, angles, clearance, stiffness, damping=0.0, friction=0.0, smoothing=1e-6):
        angles = as_vector("limiter angles", angles, what="angles (at least one limiter)")
        n = angles.shape[0]
        self.angles = angles
        self.clearance = per_item("limiter clearance chi", clearance, n, sign="positive", what="limiter")
        self.stiffness = per_item("limiter stiffness kappa", stiffness, n, sign="nonnegative", what="limiter")
        self.damping = per_item("limiter damping eta", damping, n, sign="nonnegative", what="limiter")
        self.friction = per_item("limiter friction f_S", friction, n, sign="nonnegative", what="limiter")
        self.smoothing = as_param("smoothing (contact regularisation length)", smoothing, sign="positive",
                                  shape=())

    @property
    def n(self) -> int:
        return self.angles.shape[0]

    def axes(self):
        e = jnp.stack([jnp.cos(self.angles), jnp.sin(self.angles)], axis=-1)
        t = jnp.stack([-jnp.sin(self.angles), jnp.cos(self.angles)], axis=-1)
        return e, t

    def kinematics(self, pos, vel, N, radius):
        """Penetrations `delta`, their rates, and the slip speeds `V`, per limiter."""
        e, t = self.axes()
        delta = e @ pos - self.clearance
        return delta, e @ vel, N * radius + t @ vel

    def indicator(self, pos, vel, in_length=False):
        """`min(delta_k, R_k)`: positive exactly where limiter `k` pushes. With
        `in_length`, `min(delta_k, R_k / kappa_k)` (same sign, both branches lengths):
        in SI units `R` is ~1e7 `delta`, the kink `R = delta` sits a micro-newton from
        the release `R = 0`, and an event root find cycles across it (tested on the
        FE rotor's limiters, `LimitersAt`)."""
        e, _ = self.axes()
        delta = e @ pos - self.clearance
        force = self.stiffness * delta + self.damping * (e @ vel)
        if in_length:
            force = force / jnp.where(self.stiffness > 0, self.stiffness, 1.0)
        return jnp.minimum(delta, force)

    def normal_forces(self, pos, vel, active=None):
        """Normal forces `R_k H(delta_k) H(R_k)` (exact, `active` the contact set) or
        their smoothed version (`active=None`)."""
        e, _ = self.axes()
        delta, rate = e @ pos - self.clearance, e @ vel
        if active is not None:
            return jnp.where(active, self.stiffness * delta + self.damping * rate, 0.0)
        ell = self.smoothing
        r = self.stiffness * ell * jax.nn.softplus(delta / ell) + self.damping * rate * jax.nn.sigmoid(delta / ell)
        scale = ell * jnp.maximum(self.stiffness, 1e-300)
        return r * jax.nn.sigmoid(r / scale)

    def force(self, pos, vel, N, radius, active=None):
        """Total force on the disk centre, and the normal forces per limiter."""
        e, t = self.axes()
        R = self.normal_forces(pos, vel, active)
        V = N * radius + t @ vel
        sgn = jnp.tanh(V / self.slip_regularisation)
        per = -R[:, None] * (e + (self.friction * sgn)[:, None] * t)
        return jnp.sum(per, axis=0), R

    def describe(self) -> str:
        a = ", ".join(f"{np.degrees(float(x)):.0f}" for x in np.asarray(self.angles))
        return f"{self.n} limiters at {a} deg"
