"""Model 002's run-up model: the phasors a run-up actually produces. The machine's
response to the unbalance forcing along the measured speed profile (the tacho's
angle fit) is computed in the time domain, exactly for a linear machine (modal
coordinates, exponential integrator: `q_{n+1} = e^{lambda h} q_n + int e^{lambda (h
- s)} f(s) ds` with the forcing's envelope expanded to second order in the step),
and order-tracked with the same block operator as the data. The transient through
the resonances (a steady fit is biased by ~0.5 % in stiffness and damping at 19
rad/s^2) and the smoothing of a one-revolution block are then in the model, not in
the residuals.

The phase reference (`reference=True`): the angle comes from a tacho sampled with
the signals, so each pulse is timed to within half a sample and the fitted angle is
off by a smooth `dtheta(t)` (a few mrad at the ends of a 1 kHz run-up to 400 rad/s:
0.5 % of a phasor), the same for all sensors. Fitted as if exact, it biases the
damping by up to 1 % in an unknown direction. So the angle polynomial's error is
fitted too, with the tacho fit's covariance (`OrderTrack.angle_cov`) as its prior
(whitened prior rows in the residuals, counted in the bread and the meat of the
covariance): the data see most of it (the model's phase pattern over the run is
rigid), and the intervals include what they cannot see.
"""

import functools

import equinox as eqx
import jax
import jax.numpy as jnp
import numpy as np

from ..analysis._balancing002 import balancing_response
from ..models._balancing_machine import BalancingMachine
from ..models._parameters import with_values


def machine_with(base: BalancingMachine, names, logp):
    """`base` with the parameters `names` at `exp(logp)`, set through their paths (the
    one parameter mechanism: `rotorjax.models._parameters.with_values`)."""
    return with_values(base, [BalancingMachine.parameter_path(k) for k in names], jnp.exp(logp))


def _match_blocks(tracking, speeds):
    """The indices of `speeds` among `tracking.speeds` (exact: a selection of them)."""
    where = {float(w): i for i, w in enumerate(tracking.speeds)}
    idx = [where.get(float(w), -1) for w in speeds]
    if min(idx, default=-1) < 0 or len(set(idx)) != len(idx):
        raise ValueError("speeds must be a selection of tracking.speeds (the phasors the order tracking "
                         "returned), each at most once")
    return np.asarray(idx, dtype=int)


# --- the run-up model -----------------------------------------------------------

def _phi(z):
    """`phi_1, phi_2, phi_3` of the exponential integrators, `phi_k(z) = sum_j z^j / (j + k)!`,
    for complex `z` (Taylor near 0; double `where` so derivatives stay finite)."""
    small = jnp.abs(z) < 1e-2
    zs = jnp.where(small, 1.0, z)
    p1 = jnp.expm1(zs) / zs
    p2 = (p1 - 1.0) / zs
    p3 = (p2 - 0.5) / zs
    t1 = 1 + z / 2 + z**2 / 6 + z**3 / 24 + z**4 / 120
    t2 = 0.5 + z / 6 + z**2 / 24 + z**3 / 120 + z**4 / 720
    t3 = 1 / 6 + z / 24 + z**2 / 120 + z**3 / 720 + z**4 / 5040
    return jnp.where(small, t1, p1), jnp.where(small, t2, p2), jnp.where(small, t3, p3)


class RunupData(eqx.Module):
    """What the run-up model needs of an `OrderTrack`, padded to bucketed sizes so
    that data sets of one sampling share one compilation: the step `h`; at the
    start of each step the fitted angle and speed and the Taylor coefficients
    `g0, g1, g2` of the forcing envelope `(w^2 - i w') e^{i (theta - theta_n - w_n tau)}`;
    the start (`theta0`, `w0`); each sample's block basis (cos, sin, 1) and segment;
    the blocks' inverse normal matrices."""

    h: jax.Array
    theta_n: jax.Array
    w_n: jax.Array
    g0: jax.Array
    g1: jax.Array
    g2: jax.Array
    theta0: jax.Array
    w0: jax.Array
    basis: jax.Array
    segment: jax.Array
    normal_inv: jax.Array
    n_blocks: int = eqx.field(static=True)
    fft_size: int = eqx.field(static=True)

    @classmethod
    def from_tracking(cls, tracking):
        t = np.asarray(tracking.time, dtype=float)
        dt = np.diff(t)
        h = float(np.median(dt))
        if t.size < 3 or np.max(np.abs(dt - h)) > 1e-4 * h:
            raise ValueError("the run-up model needs uniformly sampled signals (constant time step)")
        d = [tracking.angle_derivatives(t[:-1], k) for k in range(5)]
        th, w, w1, w2, w3 = d
        s0 = w**2 - 1j * w1                                  # the forcing envelope per unit unbalance
        s1 = 2 * w * w1 - 1j * w2
        s2 = 2 * w1**2 + 2 * w * w2 - 1j * w3
        g2 = 0.5 * s2 + 0.5j * w1 * s0                       # with the chirp phase e^{i w' tau^2 / 2}
        nb = tracking.speeds.size
        nb_pad = _bucket(nb + 1)
        seg = np.where(tracking.block >= 0, tracking.block, nb_pad - 1)
        theta_all = tracking.angle_derivatives(t, 0)
        basis = np.stack([np.cos(theta_all), np.sin(theta_all), np.ones_like(t)], axis=1)
        Ginv = np.zeros((nb_pad, 3, 3))
        Ginv[:nb] = tracking.normal_inv
        return cls(jnp.asarray(h), jnp.asarray(th), jnp.asarray(w), jnp.asarray(s0), jnp.asarray(s1),
                   jnp.asarray(g2), jnp.asarray(float(theta_all[0])), jnp.asarray(float(
                       tracking.angle_derivatives(t[:1], 1)[0])), jnp.asarray(basis), jnp.asarray(seg),
                   jnp.asarray(Ginv), nb_pad, _fft_size(2 * t.size))


def _fft_size(n):
    """The smallest `2^a 3^b 5^c >= n` (a fast FFT length)."""
    best = 1 << int(np.ceil(np.log2(max(n, 1))))
    p5 = 1
    while p5 < best:
        p35 = p5
        while p35 < best:
            m = p35
            while m < n:
                m *= 2
            best = min(best, m)
            p35 *= 3
        p5 *= 5
    return best


def _bucket(n, q=64):
    return int(-(-n // q) * q)


def _mode_signals(lam, h, theta_n, w_n, g0, g1, g2, fft_size):
    """Per mode `j` (eigenvalue `lam_j`) and sample `n`: `u_j(n)`, the modal response
    to the unit forcing envelope `g e^{i theta}` from rest, and `e^{lam_j h n}`, the
    free decay of a unit initial state; both `(n_samples, 4)`.

    Over a step, `q_{n+1} = e^{lam h} q_n + e^{i (theta_n + w_n h)} h (g0 phi_1 +
    g1 h phi_2 + 2 g2 h^2 phi_3)((lam - i w_n) h)`, exact for the envelope's Taylor
    polynomial. The recurrence is a causal convolution with the decaying kernel
    `e^{lam h j}`, done by FFT (a sequential scan over 20 000 samples is far slower
    on a CPU, and slower still to differentiate)."""
    z = (lam[None, :] - 1j * w_n[:, None]) * h
    p1, p2, p3 = _phi(z)
    c = jnp.exp(1j * (theta_n + w_n * h))[:, None] * (g0[:, None] * h * p1 + g1[:, None] * h**2 * p2
                                                      + 2 * g2[:, None] * h**3 * p3)
    n_steps = c.shape[0]
    powers = jnp.exp(lam[None, :] * h * jnp.arange(n_steps + 1, dtype=jnp.float64)[:, None])   # (n + 1, 4)
    conv = jnp.fft.ifft(jnp.fft.fft(powers[:-1], fft_size, axis=0) * jnp.fft.fft(c, fft_size, axis=0),
                        axis=0)[:n_steps]
    return jnp.concatenate([jnp.zeros((1, lam.size), dtype=c.dtype), conv]), powers


def _blocks(y, basis, segment, normal_inv, n_blocks):
    """The order tracking of real signals `y` `(n_samples, k)`: the phasor `a - i b`
    of each block's least-squares fit `y ~ a cos + b sin + c`, `(n_blocks, k)`."""
    S = jax.ops.segment_sum(basis[:, :, None] * y[:, None, :], segment, num_segments=n_blocks)
    coef = jnp.einsum("bij,bjm->bim", normal_inv, S)
    return coef[:, 0, :] - 1j * coef[:, 1, :]


@functools.partial(jax.custom_jvp, nondiff_argnums=(10, 11))
def _mode_blocks(lam, h, theta_n, w_n, g0, g1, g2, basis, segment, normal_inv, n_blocks, fft_size):
    """The order-tracked real and imaginary parts of `_mode_signals`: `(Re u, Im u,
    Re e, Im e)` as block phasors, `(n_blocks, 4)` each. Each mode's signals depend
    on its own eigenvalue only, and holomorphically, so the JVP needs one complex
    derivative per mode whatever the number of parameters (the custom rule: 2
    evaluations instead of 1 + 2 x 4 for a Jacobian in 4 parameters and 2 unbalances)."""
    u, e = _mode_signals(lam, h, theta_n, w_n, g0, g1, g2, fft_size)
    parts = jnp.concatenate([u.real, u.imag, e.real, e.imag], axis=1)
    return tuple(jnp.split(_blocks(parts, basis, segment, normal_inv, n_blocks), 4, axis=1))


@_mode_blocks.defjvp
def _mode_blocks_jvp(n_blocks, fft_size, primals, tangents):
    lam, h, theta_n, w_n, g0, g1, g2, basis, segment, normal_inv = primals
    dlam = tangents[0]
    (u, e), (du, de) = jax.jvp(lambda l: _mode_signals(l, h, theta_n, w_n, g0, g1, g2, fft_size), (lam,),
                               (jnp.ones_like(lam),))
    parts = jnp.concatenate([u.real, u.imag, e.real, e.imag, du.real, du.imag, de.real, de.imag], axis=1)
    ur, ui, er, ei, dur, dui, der, dei = jnp.split(_blocks(parts, basis, segment, normal_inv, n_blocks), 8, axis=1)
    a, b = jnp.real(dlam)[None, :], jnp.imag(dlam)[None, :]
    # d Re(u) = Re(u' dlam) = a Re u' - b Im u';  d Im(u) = a Im u' + b Re u'
    return (ur, ui, er, ei), (a * dur - b * dui, a * dui + b * dur, a * der - b * dei, a * dei + b * der)


def runup_phasors(machine, planes, unbalances, data: RunupData):
    """The 1x phasors that order tracking extracts from the machine's run-up: the
    time response to the unbalances along the fitted speed profile (from the steady
    response at the first sample), projected block by block as the data were;
    `(n_blocks_padded, 2)` complex (padding rows are 0).

    In modal coordinates (`M = V diag(lam) V^-1`, the first-order form of eq. 9) the
    state is `q_j(n) = beta_j u_j(n) + q0_j e^{lam_j h n}`, `beta = V^-1 (0, A^-1 L D)`
    the modal forcing of the unbalances, and the support displacements are
    `x = Re(V_top q)`; order tracking is real-linear, so the phasors are
    `sum_j Re(w_j) P[Re u_j] - Im(w_j) P[Im u_j]` (and the same for the free part)."""
    A, B, C = machine.matrices()
    Ai = jnp.linalg.inv(A)
    M = jnp.block([[jnp.zeros((2, 2)), jnp.eye(2)], [-Ai @ C, -Ai @ B]])
    lam, V = jax.lax.linalg.eig(M, compute_left_eigenvectors=False, enable_eigvec_derivs=True)
    Vi = jnp.linalg.inv(V)
    planes = jnp.asarray(planes, dtype=jnp.float64)
    lever = jnp.stack([machine.l - planes, planes]) / machine.l                 # (2, n_planes)
    D = jnp.asarray(unbalances, dtype=jnp.complex128)
    beta = Vi[:, 2:] @ (Ai.astype(jnp.complex128) @ (lever.astype(jnp.complex128) @ D))   # (4,)
    X0 = balancing_response(machine, data.w0, planes, D)
    q0 = Vi @ (jnp.concatenate([X0, 1j * data.w0 * X0]) * jnp.exp(1j * data.theta0))
    ur, ui, er, ei = _mode_blocks(lam, data.h, data.theta_n, data.w_n, data.g0, data.g1, data.g2, data.basis,
                                  data.segment, data.normal_inv, data.n_blocks, data.fft_size)
    wu, we = V[:2] * beta[None, :], V[:2] * q0[None, :]                        # (sensor, mode)
    return ur @ wu.real.T - ui @ wu.imag.T + er @ we.real.T - ei @ we.imag.T


class _RunupResidual(eqx.Module):
    """`r(theta)` of the run-up model: as `Residual`, the model phasors from
    `runup_phasors`, padded to bucketed sizes (`rows`: the residuals that are data).

    With `reference`, theta ends with `eta`, the phase reference's error in whitened
    form: the tacho's angle fit is off by `dtheta(t) = V(t) L eta` (`L L^T` the
    covariance of its coefficients, `V` their sensitivities), which turns each
    measured phasor by `e^{-i dtheta}`; so the model is turned likewise and `eta`
    gets the prior rows `eta` (its prior `N(0, I)`: the tacho fit's own scatter)."""

    base: BalancingMachine
    names: tuple = eqx.field(static=True)
    planes: jax.Array
    X: jax.Array
    sigma: jax.Array
    mask: jax.Array
    select: jax.Array
    unbalances: jax.Array | None
    data: RunupData
    phase_basis: jax.Array | None
    n_points: int = eqx.field(static=True)
    n_padded: int = eqx.field(static=True)

    @property
    def n_reference(self):
        return 0 if self.phase_basis is None else self.phase_basis.shape[1]

    @property
    def rows(self):
        """The residuals that are data (the rest is padding and the prior's rows)."""
        n, n_pad = self.n_points, self.n_padded
        return np.concatenate([np.arange(2 * n), 2 * n_pad + np.arange(2 * n)])

    @property
    def prior_rows(self):
        return 4 * self.n_padded + np.arange(self.n_reference)

    @classmethod
    def build(cls, base, names, planes, X, sigma, unbalances, tracking, sel, reference=True):
        n = sel.size
        n_pad = _bucket(n)
        Xp = np.zeros((n_pad, 2), dtype=complex)
        Xp[:n] = X
        sp = np.ones((n_pad, 2))
        sp[:n] = sigma
        mask = np.zeros((n_pad, 2))
        mask[:n] = 1.0
        selp = np.zeros(n_pad, dtype=int)
        selp[:n] = sel
        basis = None
        if reference:
            Vth, _ = tracking.angle_sensitivity(tracking.block_time[sel])
            w, U = np.linalg.eigh(np.asarray(tracking.angle_cov))
            L = U * np.sqrt(np.maximum(w, 0.0))[None, :]          # L L^T = angle_cov
            basis = np.zeros((n_pad, L.shape[1]))
            basis[:n] = Vth @ L
            basis = jnp.asarray(basis)
        return cls(base, tuple(names), jnp.asarray(planes, dtype=jnp.float64), jnp.asarray(Xp), jnp.asarray(sp),
                   jnp.asarray(mask), jnp.asarray(selp),
                   None if unbalances is None else jnp.asarray(unbalances, dtype=jnp.complex128),
                   RunupData.from_tracking(tracking), basis, n, n_pad)

    def phase_error(self, theta):
        """The fitted error of the phase reference at each block (rad), `(n_points,)`."""
        if self.phase_basis is None:
            return np.zeros(self.n_points)
        eta = np.asarray(theta)[np.asarray(theta).size - self.n_reference:]
        return np.asarray(self.phase_basis)[:self.n_points] @ eta

    def __call__(self, theta):
        n, n_planes = len(self.names), self.planes.shape[0]
        machine = machine_with(self.base, self.names, theta[:n])
        D = theta[n:n + n_planes] + 1j * theta[n + n_planes:n + 2 * n_planes] if self.unbalances is None \
            else self.unbalances
        model = runup_phasors(machine, self.planes, D, self.data)[self.select]
        if self.phase_basis is not None:
            eta = theta[theta.size - self.n_reference:]
            model = model * jnp.exp(-1j * (self.phase_basis @ eta))[:, None]
        d = self.mask * (model - self.X) / self.sigma
        out = [jnp.real(d).ravel(), jnp.imag(d).ravel()]
        if self.phase_basis is not None:
            out.append(theta[theta.size - self.n_reference:])
        return jnp.concatenate(out)
