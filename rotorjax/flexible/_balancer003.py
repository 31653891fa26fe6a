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

In the rotating frame (`w = v e^{-i omega t}`, `alpha_j = theta_j - omega t`) the
stationary regimes are (eqs. 25-30): balanced C (`w = 0`, balls cancel the imbalance),
pseudo-balanced PS (`a^T w = 0` with a bent shaft, only for `d = 0`), and unbalanced
NS1/NS2/NS3 by the balancing coefficient `sigma = sum_j m_j r_j (-1)^{delta_j} / m0`.
"""

import itertools

import equinox as eqx
import jax
import jax.numpy as jnp
import numpy as np

from ..models._speed import AbstractSpeedProfile
from ..models._validate import InputError, as_count, as_param, check_span, check_type, is_concrete, per_item
from ._modal import ModalShaft


class ModalBalancerRotor(eqx.Module):
    """Model 003's shaft + disk (`shaft`, whose `m` must include the balls' mass)
    with balls of masses `ball_mass` (N,), radii `ball_radius` and drags `ball_drag`
    (units `m_S`, `r0`, `m_j r_j^2 omega_1`), spun by `speed`. Duck-types a scene for
    `rotorjax.simulate` (state `(Re v, Im v, theta, d/dt ...)`)."""

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

    # --- rotating frame (constant speed) -----------------------------------------------
    def _to_fixed(self, t, z, omega):
        v, al, wd, ald = self._split(z)
        e = jnp.exp(1j * omega * t)
        return self.state(v * e, al + omega * t, (wd + 1j * omega * v) * e, ald + omega)

    def rotating_field(self, z):
        """`dz/dt` in the rotating frame at constant speed (autonomous)."""
        omega = self.speed.speed(0.0)
        f = lambda zz, tt: self._to_fixed(tt, zz, omega)  # noqa: E731
        jz = jax.jacfwd(f, argnums=0)(z, 0.0)
        jt = jax.jacfwd(f, argnums=1)(z, 0.0)
        return jnp.linalg.solve(jz, self.vector_field(0.0, f(z, 0.0)) - jt)


class BalancerRegime(eqx.Module):
    """A stationary regime of model 003 with balls: `kind` in {"C", "PS", "NS1",
    "NS2", "NS3"}, the rotating-frame state, residual, eigenvalues, margin."""

    kind: str = eqx.field(static=True)
    sigma: float = eqx.field(static=True)
    z: jax.Array
    residual: jax.Array
    eigenvalues: jax.Array
    margin: jax.Array
    disk_amplitude: jax.Array


def _regime(rotor, kind, sigma, w, alpha):
    n = rotor.shaft.n_modes
    z = jnp.concatenate([jnp.real(w), jnp.imag(w), alpha, jnp.zeros(2 * n + rotor.n_balls)])
    res = jnp.max(jnp.abs(rotor.rotating_field(z)))
    eig = jnp.linalg.eigvals(jax.jacfwd(rotor.rotating_field)(z))
    a, _, _ = rotor.shaft.mode_vectors()
    return BalancerRegime(kind=kind, sigma=sigma, z=z, residual=res, eigenvalues=eig,
                          margin=jnp.max(jnp.real(eig)), disk_amplitude=jnp.abs(a @ w))


def _dynamic_matrix(rotor, omega):
    s = rotor.shaft
    a, b, k = s.mode_vectors()
    return (jnp.diag(k**4 + (1j * s.d - omega) * omega) - s.J * omega**2 * jnp.outer(b, b)
            - s.m * omega**2 * jnp.outer(a, a))


def balanced_regime(rotor):
    """Regime C: shaft straight, two (or more, fanned) balls cancelling the imbalance."""
    from ..models import balancing_angles

    check_type("rotor", rotor, ModalBalancerRotor, "a ModalBalancerRotor")
    mr = rotor.ball_mass * rotor.ball_radius
    if rotor.n_balls < 1:
        raise InputError("rotor: a rotor without balls has no balanced regime")
    c = rotor.shaft.m0 / (rotor.n_balls * mr[0])
    if not isinstance(c, jax.core.Tracer):
        if not np.allclose(np.asarray(mr), float(mr[0])):
            raise InputError("rotor: the balanced regime is built for identical balls")
        if c > 1:
            raise InputError(f"rotor: the balls cannot cancel the imbalance: m0 = {float(rotor.shaft.m0)} > "
                             f"sum m_j r_j = {rotor.n_balls * float(mr[0])}")
    alpha = balancing_angles(rotor.n_balls, c)
    return _regime(rotor, "C", float("nan"), jnp.zeros(rotor.shaft.n_modes, dtype=complex), alpha)


def unbalanced_regimes(rotor):
    """All NS regimes (eqs. 28-30): for every assignment `delta_j` of the balls to the
    disk-centre ray (0) or its opposite (1), `sigma = sum m_j r_j (-1)^delta_j / m0`, and
    the roots `rho > 0` of eq. (30)."""
    check_type("rotor", rotor, ModalBalancerRotor, "a ModalBalancerRotor")
    s = rotor.shaft
    if not is_concrete(s.m0) or not float(s.m0) > 0:
        raise InputError(f"rotor.shaft.m0 (imbalance mass) must be > 0 for the unbalanced regimes "
                         f"(sigma = sum m_j r_j (-1)^delta_j / m0), got {s.m0}")
    omega = float(rotor.speed.speed(0.0))
    R = _dynamic_matrix(rotor, omega)
    a, _, _ = s.mode_vectors()
    q = complex(a @ jnp.linalg.solve(R, a.astype(complex)))
    m0 = float(s.m0)
    mr = np.asarray(rotor.ball_mass * rotor.ball_radius)
    identical = np.allclose(mr, mr[0]) if mr.size else True
    deltas = (itertools.combinations_with_replacement((0, 1), rotor.n_balls) if identical
              else itertools.product((0, 1), repeat=rotor.n_balls))
    out = []
    for delta in deltas:
        sigma = float(np.sum(mr * (-1.0) ** np.array(delta)) / m0)
        disc = q.real**2 + (1 - sigma**2) * q.imag**2
        if disc < 0:
            continue
        for sign in (1.0, -1.0):
            rho = omega**2 * m0 * (sigma * q.real + sign * np.sqrt(disc))
            if rho <= 1e-14:
                continue
            e_beta = omega**2 * m0 * q / (rho - omega**2 * m0 * sigma * q)
            beta = float(np.angle(e_beta))
            w = jnp.linalg.solve(R, (omega**2 * m0 * (1 + sigma * np.exp(1j * beta))) * a.astype(complex))
            alpha = jnp.asarray(beta - np.pi * np.array(delta, dtype=float))
            kind = "NS3" if abs(sigma) < 1e-12 else ("NS1" if sigma > 0 else "NS2")
            out.append(_regime(rotor, kind, sigma, w, alpha))
    return out


def pseudo_balanced_speeds(shaft, lo, hi, n_scan=4000):
    """Speeds of the pseudo-balanced regime PS (eq. 27): the disk centre stays on the
    axis while the shaft is bent, where `S11 + S12^2 J w^2 / (1 - S22 J w^2) = 0`
    (closed-form sums). PS exists only without damping."""
    from ._modal import closed_form_sums

    check_type("shaft", shaft, ModalShaft, "a rotorjax.flexible.ModalShaft")
    lo, hi = check_span("lo", lo, "hi", hi)
    n_scan = as_count("n_scan", n_scan, minimum=2)
    if float(shaft.d) != 0:
        raise InputError("shaft: the pseudo-balanced regime PS exists only without damping (d = 0), "
                         f"got d = {float(shaft.d)}")
    z0, J = float(shaft.z0), float(shaft.J)

    def f(w):
        s11, s12, s22 = (np.real(complex(x)) for x in closed_form_sums(w, z0))
        return s11 + s12**2 * J * w**2 / (1 - s22 * J * w**2)

    ws = np.linspace(lo, hi, n_scan)
    vals = np.array([f(w) for w in ws])
    roots = []
    for i in range(n_scan - 1):
        if not (np.isfinite(vals[i]) and np.isfinite(vals[i + 1])) or np.sign(vals[i]) == np.sign(vals[i + 1]):
            continue
        a, b, fa = ws[i], ws[i + 1], vals[i]
        for _ in range(60):
            c = 0.5 * (a + b)
            fc = f(c)
            a, b, fa = (c, b, fc) if np.sign(fc) == np.sign(fa) else (a, c, fa)
        if abs(f(0.5 * (a + b))) < 1e-6 * (1 + abs(vals[i]) + abs(vals[i + 1])):
            roots.append(0.5 * (a + b))
    return roots
