"""Model 003's analyses (Kovachev, SPbU dissertation abstract): the natural
frequencies and synchronous response of the truncated modal model, and the
closed-form sums and critical speeds of the pinned-pinned shaft with a disk
(`rotorjax.models.ModalShaft`, whose docstring states the model and its units).

The response solves `(diag Lambda - w^2 (m a a^T + J b b^T)) W = m0 w^2 a`, whose
rank-2 structure gives the disk's deflection and tilt from the sums `S11, S12,
S22` alone (eqs. 10-13), O(n_modes).

The truncated sums' `n -> infinity` limits have closed forms (eqs. 14-16), and the
critical speeds solve (eq. 17)

    G(nu) = (1 - S22 J nu^2) - m nu^2 [S11 (1 - S22 J nu^2) + S12^2 J nu^2] = 0.
"""

import jax
import jax.numpy as jnp
import numpy as np

from ._roots import find_roots
from ..models._fe_reduction import undamped_modes
from ..models._modal import ModalShaft
from ..models._validate import as_count, as_param, check, check_span, check_type, is_concrete


def modal003_natural_frequencies(shaft):
    """Undamped synchronous critical speeds of model 003's modal model (units of
    omega_1, ascending): the eigenvalues `nu` of `diag(k^4) W = nu^2 (I + m a a^T +
    J b b^T) W` (`shaft.synchronous_matrices()`), with a flag per mode for those the
    disk's imbalance excites (non-zero disk deflection): `(frequencies, excited)`."""
    check_type("shaft", shaft, ModalShaft, "a rotorjax.models.ModalShaft")
    M, _, K = shaft.synchronous_matrices()
    nu2, w = undamped_modes(M, K)   # symmetric-definite: Cholesky of the mass, mass-normalised
    a = shaft.mode_vectors()[0]
    return jnp.sqrt(nu2), jnp.abs(a @ w) > 1e-9 * jnp.linalg.norm(w, axis=0)


def modal003_response(shaft, speed):
    """Synchronous response of model 003's shaft at `speed` (units of omega_1; the
    paper's `w`), eqs. 10-13: the complex disk-centre position in the rotating frame
    `W_disk` (units r0; `A = |W_disk|`, phase its angle) and the disk tilt `Phi`
    (physical angle `(pi r0 / l) Phi`): `(W_disk, Phi)`. The rank-2 form of
    `frequency_response` with `shaft.synchronous_matrices()`, O(n_modes); traceable
    in the speed and the shaft's parameters."""
    check_type("shaft", shaft, ModalShaft, "a rotorjax.models.ModalShaft")
    if is_concrete(speed):
        as_param("speed", speed, shape=())
    s11, s12, s22 = shaft.sums(speed)
    return _rank2_response(s11, s12, s22, shaft.m, shaft.J, shaft.m0, speed)


def _rank2_response(s11, s12, s22, m, J, m0, w):
    """Disk deflection and tilt from the sums (eqs. 10-13)."""
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
    """Roots of eq. (17) in `[lo, hi]` (units of omega_1): scan + bisection (the shared
    root finder, `rotorjax.analysis.find_roots`), with the sign changes at the poles
    of the sums (the bare shaft's frequencies `k^2`) rejected by the size of `G`
    after refinement."""
    as_param("m (disk mass)", m, sign="nonnegative", shape=())
    as_param("z0 (disk position)", z0, shape=())
    check("z0 (disk position)", z0, lambda a: (0 < a) & (a < 1), "in (0, 1) (a fraction of the span)")
    as_param("J (disk rotary inertia)", J, shape=())
    lo, hi = check_span("lo", lo, "hi", hi)
    n_scan = as_count("n_scan", n_scan, minimum=2)
    as_param("xtol", xtol, sign="positive", shape=())
    g = jax.jit(lambda v: critical_speed_function(v, m, z0, J))
    roots = find_roots(g, lo, hi, n_scan, xtol=xtol, pole_tol=1e-6,
                       values=lambda nus: jax.vmap(g)(jnp.asarray(nus)))
    return [r.x for r in roots]
