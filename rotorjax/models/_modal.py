"""Model 003's shaft: a pinned-pinned shaft with distributed mass, expanded in its
modes `sin(k pi z / l)`, carrying a rigid disk (Kovachev, SPbU dissertation abstract).

Dimensionless (eq. 6): frequency unit `omega_1 = pi^2 sqrt(EJ / (rho S l^4))` (the
bare shaft's first frequency), mass unit `m_S = rho S l / 2` (the modal mass of
every mode), axial unit `l`, lateral unit `r0` (the imbalance radius). With
`a_k = sin(k pi z0)`, `b_k = k cos(k pi z0)` (deflection and scaled slope of mode k
at the disk) and `Lambda_k = k^4 - w^2 + i d w` at the speed `w` (the paper's
symbol; `speed` in the signatures, with `w` kept as an alias), the synchronous
response in the rotating frame solves

    (diag Lambda - w^2 (m a a^T + J b b^T)) W = m0 w^2 a,

i.e. `(K - w^2 M + i w C) W = F` with `M = I + m a a^T + J b b^T`, `C = d I`,
`K = diag k^4` (`ModalShaft.synchronous_matrices`), whose rank-2 structure gives
the sums `S11 = sum a_k^2/Lambda_k`, `S12 = sum a_k b_k/Lambda_k`,
`S22 = sum b_k^2/Lambda_k` (eqs. 8-13). Their `n -> infinity` limits and the
critical speeds (eqs. 14-17), the truncated model's natural frequencies and its
response are analyses: `rotorjax.analysis.closed_form_sums`, `exact_critical_speeds`,
`modal003_natural_frequencies`, `modal003_response`.

`J` is the disk's effective rotary inertia in synchronous whirl. The paper's
equations give `J = Jt + 2 Jp`; a standard rigid-disk derivation gives `Jt - Jp`
(gyroscopic stiffening): `gyroscopic="paper"` (default, to reproduce the paper) or
`"standard"`.
"""

import warnings

import equinox as eqx
import jax
import jax.numpy as jnp

from ._fe_reduction import undamped_modes
from ._frequency import frequency_response
from ._speed import speed_alias
from ._validate import as_count, as_param, check, check_choice


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

    def sums(self, speed=None, *, w=None):
        """Truncated `S11, S12, S22` at `speed` (the paper's `w`, accepted as an alias;
        complex with damping)."""
        w = speed_alias(speed, w, "w", "ModalShaft.sums")
        a, b, k = self.mode_vectors()
        lam = k**4 - w**2 + 1j * self.d * w
        return jnp.sum(a * a / lam), jnp.sum(a * b / lam), jnp.sum(b * b / lam)

    def natural_frequencies(self):
        """Deprecated: `rotorjax.analysis.modal003_natural_frequencies(shaft)`."""
        warnings.warn("ModalShaft.natural_frequencies is deprecated (analyses live in rotorjax.analysis): use "
                      "rotorjax.analysis.modal003_natural_frequencies(shaft)", DeprecationWarning, stacklevel=2)
        M, _, K = self.synchronous_matrices()
        nu2, w = undamped_modes(M, K)
        return jnp.sqrt(nu2), jnp.abs(self.mode_vectors()[0] @ w) > 1e-9 * jnp.linalg.norm(w, axis=0)

    def synchronous_matrices(self):
        """`(M, C, K)` of the synchronous whirl `v = W e^{i speed t}` in the complex
        modal amplitudes: `(K - speed^2 M + i speed C) W = m0 speed^2 a` (see the
        module docstring; the disk's gyroscopic moment is folded into `J`), for
        `rotorjax.models.frequency_response`."""
        a, b, k = self.mode_vectors()
        M = jnp.eye(self.n_modes) + self.J * jnp.outer(b, b) + self.m * jnp.outer(a, a)
        return M, self.d * jnp.eye(self.n_modes), jnp.diag(k**4)

    def response(self, speed=None, *, w=None):
        """Deprecated: `rotorjax.analysis.modal003_response(shaft, speed)` (the rank-2
        closed form, eqs. 10-13); here the same response by one `frequency_response`
        solve of `synchronous_matrices`."""
        w = speed_alias(speed, w, "w", "ModalShaft.response")
        warnings.warn("ModalShaft.response is deprecated (analyses live in rotorjax.analysis): use "
                      "rotorjax.analysis.modal003_response(shaft, speed)", DeprecationWarning, stacklevel=2)
        a, b, _ = self.mode_vectors()
        W = frequency_response(*self.synchronous_matrices(), self.m0 * w**2 * a, w)
        return a @ W, b @ W
