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


def frequency_response_jvp(M, C, K, dM, dC, dK, F, w):
    """`Q` and its derivatives `dQ[..., k]` along the `p` parameter directions of
    `dM, dC, dK` (each `(n, n, p)`), with one LU factorisation: `Z dQ_k = -dZ_k Q`.
    (Forward-mode autodiff through `frequency_response` gives the same numbers, with
    a solve per direction.)"""
    import jax.scipy.linalg as jsl

    Z = dynamic_stiffness(M, C, K, w)
    lu = jsl.lu_factor(Z)
    F = jnp.asarray(F, dtype=jnp.complex128)
    Q = jsl.lu_solve(lu, F.reshape(F.shape[0], -1))
    dZ = dK - w**2 * dM + 1j * w * dC
    n, L, p = Q.shape[0], Q.shape[1], dZ.shape[2]
    rhs = -jnp.einsum("ijk,jl->ilk", dZ, Q).reshape(n, L * p)
    dQ = jsl.lu_solve(lu, rhs).reshape(n, L, p)
    return Q.reshape(F.shape), dQ.reshape(F.shape + (p,))
