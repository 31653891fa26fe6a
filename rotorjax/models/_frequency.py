"""The one frequency-response solve.

A linear(ised) rotor `M q'' + C q' + K q = Re(F e^{i w t})` (with `C` holding the
damping and the speed-scaled gyroscopic matrix, `K` the stiffness and any
circulatory terms) answers with `q = Re(Q e^{i w t})`,

    (K - w^2 M + i w C) Q = F.

Every unbalance response, influence coefficient and synchronous state in
rotorjax is this solve.
"""

import jax.numpy as jnp


def dynamic_stiffness(M, C, K, w):
    """`K - w^2 M + i w C` at the excitation frequency `w` (rad/s or the scene's unit)."""
    return K - w**2 * M + 1j * w * C


def frequency_response(M, C, K, F, w):
    """Complex amplitudes `Q` of the steady response to `Re(F e^{i w t})`; `F` may
    be a vector or a matrix of load columns."""
    return jnp.linalg.solve(dynamic_stiffness(M, C, K, w), jnp.asarray(F, dtype=jnp.complex128))
