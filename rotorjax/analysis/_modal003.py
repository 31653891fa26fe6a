"""Model 003's analyses (Kovachev, SPbU dissertation abstract): the closed-form
sums and critical speeds of the pinned-pinned shaft with a disk
(`rotorjax.models.ModalShaft`, whose docstring states the model and its units).

The truncated sums' `n -> infinity` limits have closed forms (eqs. 14-16), and the
critical speeds solve (eq. 17)

    G(nu) = (1 - S22 J nu^2) - m nu^2 [S11 (1 - S22 J nu^2) + S12^2 J nu^2] = 0.
"""

import jax
import jax.numpy as jnp
import numpy as np

from ._roots import find_roots
from ..models._validate import as_count, as_param, check, check_span


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
