"""Model 003: a pinned-pinned shaft with distributed mass, expanded in its modes
`sin(k pi z / l)`, carrying a rigid disk (Kovachev, SPbU dissertation abstract).

Dimensionless (eq. 6): frequency unit `omega_1 = pi^2 sqrt(EJ / (rho S l^4))` (the
bare shaft's first frequency), mass unit `m_S = rho S l / 2` (the modal mass of
every mode), axial unit `l`, lateral unit `r0` (the imbalance radius). With
`a_k = sin(k pi z0)`, `b_k = k cos(k pi z0)` (deflection and scaled slope of mode k
at the disk) and `Lambda_k = k^4 - w^2 + i d w`, the synchronous response in the
rotating frame solves `(diag Lambda - w^2 (m a a^T + J b b^T)) W = m0 w^2 a`, whose
rank-2 structure gives the sums `S11 = sum a_k^2/Lambda_k`, `S12 = sum a_k b_k/Lambda_k`,
`S22 = sum b_k^2/Lambda_k` (eqs. 8-13); their `n -> infinity` limits have closed
forms (eqs. 14-16) and the critical speeds solve (eq. 17)

    G(nu) = (1 - S22 J nu^2) - m nu^2 [S11 (1 - S22 J nu^2) + S12^2 J nu^2] = 0.

`J` is the disk's effective rotary inertia in synchronous whirl. The paper's
equations give `J = Jt + 2 Jp`; a standard rigid-disk derivation gives `Jt - Jp`
(gyroscopic stiffening): `gyroscopic="paper"` (default, to reproduce the paper) or
`"standard"`.
"""

import equinox as eqx
import jax
import jax.numpy as jnp
import numpy as np

from ..models._validate import as_count, as_param, check, check_choice, check_span


class ModalShaft(eqx.Module):
    """Pinned-pinned modal shaft with a disk (model 003), dimensionless.

    **Arguments:** `n_modes` (static, >= 1), disk mass `m` (units `rho S l / 2`,
    disk plus imbalance mass), position `z0` in (0, 1), inertias `Jt`, `Jp`
    (units `l^2 m_S / pi^2`), external damping `d` (units `m_S omega_1`), imbalance
    mass `m0` (units `m_S`).
    """

    n_modes: int = eqx.field(static=True)
    m: jax.Array
    z0: jax.Array
    Jt: jax.Array
    Jp: jax.Array
    d: jax.Array
    m0: jax.Array
    gyroscopic: str = eqx.field(static=True)

    def __init__(self, n_modes, m, z0, Jt=0.0, Jp=0.0, d=0.0, m0=0.0, gyroscopic="paper"):
        self.n_modes = as_count("n_modes", n_modes, minimum=1)
        self.m = as_param("m (disk mass)", m, sign="nonnegative", shape=())
        self.z0 = as_param("z0 (disk position)", z0, shape=())
        check("z0 (disk position)", z0, lambda a: (0 < a) & (a < 1), "in (0, 1) (a fraction of the span)")
        self.Jt = as_param("Jt", Jt, sign="nonnegative", shape=())
        self.Jp = as_param("Jp", Jp, sign="nonnegative", shape=())
        self.d = as_param("d (external damping)", d, sign="nonnegative", shape=())
        self.m0 = as_param("m0 (imbalance mass)", m0, sign="nonnegative", shape=())
        check_choice("gyroscopic", gyroscopic, ("paper", "standard"))
        self.gyroscopic = gyroscopic

    @property
    def J(self):
        return self.Jt + 2 * self.Jp if self.gyroscopic == "paper" else self.Jt - self.Jp

    def mode_vectors(self):
        k = jnp.arange(1, self.n_modes + 1, dtype=jnp.float64)
        return jnp.sin(k * jnp.pi * self.z0), k * jnp.cos(k * jnp.pi * self.z0), k

    def sums(self, w):
        """Truncated `S11, S12, S22` at speed `w` (complex with damping)."""
        a, b, k = self.mode_vectors()
        lam = k**4 - w**2 + 1j * self.d * w
        return jnp.sum(a * a / lam), jnp.sum(a * b / lam), jnp.sum(b * b / lam)

    def natural_frequencies(self):
        """Undamped synchronous critical speeds of the modal model: the eigenvalues of
        `diag(k^4) W = nu^2 (I + m a a^T + J b b^T) W`, with a flag for the modes the
        disk's imbalance excites (non-zero disk deflection)."""
        a, b, k = self.mode_vectors()
        mass = jnp.eye(self.n_modes) + self.m * jnp.outer(a, a) + self.J * jnp.outer(b, b)
        # symmetric-definite: Cholesky of the mass, then a symmetric eigenproblem
        L = jnp.linalg.cholesky(mass)
        Linv = jnp.linalg.inv(L)
        nu2, v = jnp.linalg.eigh(Linv @ jnp.diag(k**4) @ Linv.T)
        w = Linv.T @ v
        excited = jnp.abs(a @ w) > 1e-9 * jnp.linalg.norm(w, axis=0)
        return jnp.sqrt(nu2), excited

    def response(self, w):
        """Synchronous response at speed `w` (eqs. 10-13): the complex disk-centre
        position in the rotating frame `W_disk` (units r0; `A = |W_disk|`, phase its
        angle) and the disk tilt `Phi` (physical angle `(pi r0 / l) Phi`)."""
        s11, s12, s22 = self.sums(w)
        return _response(s11, s12, s22, self.m, self.J, self.m0, w)


def _response(s11, s12, s22, m, J, m0, w):
    den = s11 * (1 - s22 * J * w**2) + s12**2 * J * w**2
    q = 1.0 / ((1 - s22 * J * w**2) / den - m * w**2)
    disk = m0 * w**2 * q
    tilt = s12 * m0 * w**2 / ((1 - s11 * m * w**2) * (1 - s22 * J * w**2) - s12**2 * m * J * w**4)
    return disk, tilt


def closed_form_sums(w, z0, d=0.0):
    """`S11, S12, S22` for `n -> infinity` (eqs. 14-16), `alpha^4 = w^2 - i d w`."""
    alpha = (w**2 - 1j * d * w + 0j) ** 0.25
    x = alpha * jnp.pi
    A, B = x * z0, x * (1 - z0)
    s11 = jnp.pi / (4 * alpha**3) * (jnp.sin(A) * jnp.sin(B) / jnp.sin(x) - jnp.sinh(A) * jnp.sinh(B) / jnp.sinh(x))
    s12 = jnp.pi / (4 * alpha**2) * (jnp.cos(A) * jnp.sin(B) / jnp.sin(x) - jnp.cosh(A) * jnp.sinh(B) / jnp.sinh(x))
    s22 = jnp.pi / (4 * alpha) * (-jnp.cos(A) * jnp.cos(B) / jnp.sin(x) + jnp.cosh(A) * jnp.cosh(B) / jnp.sinh(x))
    return s11, s12, s22


def critical_speed_function(nu, m, z0, J):
    """`G(nu)` of eq. (17) with the closed-form sums (undamped)."""
    s11, s12, s22 = (jnp.real(s) for s in closed_form_sums(nu, z0))
    return (1 - s22 * J * nu**2) - m * nu**2 * (s11 * (1 - s22 * J * nu**2) + s12**2 * J * nu**2)


def exact_critical_speeds(m, z0, J=0.0, lo=0.05, hi=30.0, n_scan=3000, xtol=1e-12):
    """Roots of eq. (17) in `[lo, hi]` (units of omega_1): scan + bisection, with the
    sign changes at the poles of the sums (the bare shaft's frequencies `k^2`)
    rejected by the size of `G` after refinement."""
    as_param("m (disk mass)", m, sign="nonnegative", shape=())
    as_param("z0 (disk position)", z0, shape=())
    check("z0 (disk position)", z0, lambda a: (0 < a) & (a < 1), "in (0, 1) (a fraction of the span)")
    as_param("J (disk rotary inertia)", J, shape=())
    lo, hi = check_span("lo", lo, "hi", hi)
    n_scan = as_count("n_scan", n_scan, minimum=2)
    as_param("xtol", xtol, sign="positive", shape=())
    g = jax.jit(lambda v: critical_speed_function(v, m, z0, J))
    nus = np.linspace(lo, hi, n_scan)
    vals = np.asarray(jax.vmap(g)(jnp.asarray(nus)))
    roots = []
    for i in range(n_scan - 1):
        a, b, ga = nus[i], nus[i + 1], vals[i]
        if not (np.isfinite(ga) and np.isfinite(vals[i + 1])) or np.sign(ga) == np.sign(vals[i + 1]):
            continue
        while b - a > xtol:
            c = 0.5 * (a + b)
            gc = float(g(c))
            a, b, ga = (c, b, gc) if np.sign(gc) == np.sign(ga) else (a, c, ga)
        root = 0.5 * (a + b)
        if abs(float(g(root))) < 1e-6 * (1 + abs(vals[i]) + abs(vals[i + 1])):
            roots.append(float(root))
    return roots
