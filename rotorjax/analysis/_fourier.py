"""The truncated Fourier series of harmonic balance: `y(t) = c_0 + sum_k a_k cos(k
w t) + b_k sin(k w t)`, its coefficients `(2H + 1, n)` one row per term, evaluated
at instants, projected back from samples and differentiated in time."""

import jax.numpy as jnp
import numpy as np


def _basis_at(phase, H):
    """`[1, cos(phase), sin(phase), ..., cos(H phase), sin(H phase)]` along a new
    last axis."""
    k = jnp.arange(1, H + 1, dtype=jnp.float64).reshape((1,) * phase.ndim + (H,))
    kp = phase[..., None] * k
    cs = jnp.stack([jnp.cos(kp), jnp.sin(kp)], axis=-1).reshape(*phase.shape, 2 * H)
    return jnp.concatenate([jnp.ones(phase.shape + (1,)), cs], axis=-1)


def _collocation(H, N):
    """`B` (N, 2H+1): the series at the N instants; `P` (2H+1, N): the projection
    back (exact for N > 2H: `P B = I`)."""
    phase = 2 * np.pi * np.arange(N) / N
    k = np.arange(1, H + 1)
    B = np.ones((N, 2 * H + 1))
    B[:, 1::2] = np.cos(np.outer(phase, k))
    B[:, 2::2] = np.sin(np.outer(phase, k))
    weights = np.full(2 * H + 1, 2.0 / N)
    weights[0] = 1.0 / N
    return jnp.asarray(B), jnp.asarray(weights[:, None] * B.T)


def _derivative(Y, omega):
    """Coefficients of `y'` from those of `y`."""
    H = (Y.shape[0] - 1) // 2
    kw = (omega * jnp.arange(1, H + 1, dtype=jnp.float64))[:, None]
    a, b = Y[1::2], Y[2::2]
    d = jnp.stack([kw * b, -kw * a], axis=1).reshape(2 * H, -1)
    return jnp.concatenate([jnp.zeros_like(Y[:1]), d], axis=0)


def _samples(H, n_samples):
    """Default `N`: the smallest power of two above `4 (H + 1)` (a cubic term's
    harmonics up to `3H` fold back only above harmonic `H`)."""
    if n_samples is not None:
        return n_samples
    return int(2 ** np.ceil(np.log2(4 * (H + 1))))
