"""Harmonic balance condensed to the coordinates the forces read.

A scene whose equations split into a linear part and forces at a few coordinates
(`AbstractLocalScene`, `LocalForces`: an FE rotor's nonlinear bearings at two
nodes),

    y' = A y + a0 + E g(t, S q, S q'),

has, for given force harmonics `G` (`(2H + 1, k)`), the linear response

    y_0 = -A^-1 (a0 + E G_0),     c_k = (i k w I - A)^-1 E (a_k - i b_k)_G,

(`c_k = a_k - i b_k` of the state), so the balance of all `(2H + 1) n` unknowns
reduces to the `(2H + 1) m` harmonics `Z` of the read coordinates:

    Z - S Y(G(Z)) = 0,    G(Z) = P g(t_j, B Z, B D(w) Z),

the forces evaluated at `N` instants as in the full balance (alternating
frequency-time). Newton's iterates on it are the full balance's (the equations
eliminated are linear in the unknowns eliminated), at the cost of `m` unknowns
a harmonic instead of `n` (4 instead of 32 for an FE rotor with two nonlinear
bearings: 80x faster at 32 harmonics). The velocities the forces read are the
series' derivative (`q' = dq/dt` holds in every harmonic of the linear part)."""

import jax
import jax.numpy as jnp
import numpy as np

from ..models._contract import AbstractLocalScene
from ..models._validate import is_concrete
from ._fourier import _collocation, _derivative

#: harmonic balance is condensed where the coordinates the forces read are at most this fraction of the states
CONDENSE_FRACTION = 0.5

#: ... and the linear part's condition number is below this (a shaft held by journal bearings alone has rigid-body
#: modes: no static response to the forces' constant part)
CONDENSE_COND = 1e12


def condensable(scene) -> bool:
    """Whether harmonic balance of `scene` is condensed: a local scene
    (`AbstractLocalScene`) split with few read coordinates and a regular linear
    part (checked on concrete values: a scene traced through, under `vmap` or
    `grad`, is balanced whole)."""
    if not isinstance(scene, AbstractLocalScene):
        return False
    local = scene.local_forces()
    if local is None or not local.S.shape[0] <= CONDENSE_FRACTION * scene.state_size or not is_concrete(local.A):
        return False
    return bool(np.linalg.cond(np.asarray(local.A)) < CONDENSE_COND)


def force_harmonics(local, Z, period, t0, N):
    """`G` (`(2H + 1, k)`): the harmonics of the forces along the read
    coordinates' series `Z` (`(2H + 1, m)`), from `N` instants."""
    H = (Z.shape[0] - 1) // 2
    B, P = _collocation(H, N)
    ts = t0 + period * jnp.arange(N) / N
    g = jax.vmap(local.force)(ts, B @ Z, B @ _derivative(Z, 2 * jnp.pi / period))
    return P @ g


def response(local, G, period):
    """The state's coefficients `Y` (`(2H + 1, n)`) of the linear part driven by
    the force harmonics `G` (`(2H + 1, k)`) and the constant `a0`."""
    A, E = local.A, local.E
    H, n, nq = (G.shape[0] - 1) // 2, A.shape[0], local.S.shape[1]
    # balanced: the velocities in units of the stiffest frequency (`A = [[0, I], [-M^-1 K, ...]]`'s blocks alike),
    # else an FE rotor's first-order matrix is conditioned as its frequencies squared (1e10) and the solves lose
    # four digits the full balance's Newton keeps
    top = jax.lax.stop_gradient(jnp.sqrt(jnp.max(jnp.abs(A[nq:, :nq])) + 1.0))
    d = jnp.concatenate([jnp.ones(nq), jnp.full(n - nq, top)])
    # E (a_k - i b_k), the constant term's `a0 + E G_0` first
    rhs = jnp.concatenate([(local.a0 + E @ G[0])[None], (G[1::2] - 1j * G[2::2]) @ E.T]) / d[None, :]
    c = _harmonic_solves(A * d[None, :] / d[:, None], 2 * jnp.pi / period, rhs) * d[None, :]
    ab = jnp.stack([jnp.real(c[1:]), -jnp.imag(c[1:])], axis=1).reshape(2 * H, n)
    return jnp.concatenate([jnp.real(c[:1]), ab], axis=0)


@jax.custom_jvp
def _harmonic_solves(A, w, rhs):
    """`c_k = (i k w I - A)^-1 rhs_k`, `k = 0..H` (`rhs` `(H + 1, n)`). Its
    derivative by the rule below, from the same factors: `dc_k = (i k w I - A)^-1
    (drhs_k - (i k dw I - dA) c_k)`; autodiff through the factorisation would carry
    a matrix per harmonic per tangent (a Jacobian of 260 unknowns at 32 harmonics:
    27 GB, and `n^3` work a tangent)."""
    return _solved(_factors(A, w, rhs.shape[0]), rhs)


def _factors(A, w, m):
    # LU, not jnp.linalg.solve: its custom_linear_solve rule would keep the program from being shared (_lift)
    eye = jnp.eye(A.shape[0])
    return jax.vmap(lambda k: jax.scipy.linalg.lu_factor(1j * k * w * eye - A))(jnp.arange(m, dtype=jnp.float64))


def _solved(factors, rhs):
    return jax.vmap(lambda lu, piv, r: jax.scipy.linalg.lu_solve((lu, piv), r))(*factors, rhs)


@_harmonic_solves.defjvp
def _harmonic_solves_jvp(primals, tangents):
    A, w, rhs = primals
    dA, dw, drhs = tangents
    factors = _factors(A, w, rhs.shape[0])
    c = _solved(factors, rhs)
    k = jnp.arange(rhs.shape[0], dtype=jnp.float64)[:, None]
    return c, _solved(factors, drhs - 1j * k * dw * c + c @ dA.T)


def expanded(local, Z, period, t0, N):
    """The whole motion's coefficients `Y` from the read coordinates' `Z`."""
    return response(local, force_harmonics(local, Z, period, t0, N), period)


def read(local, Y):
    """The read coordinates' coefficients `Z = Y_q S^T` of a motion `Y`."""
    return Y[..., :local.S.shape[1]] @ local.S.T


def condensed_residual(local, Z, period, t0, N):
    """`Z - S Y(G(Z))` (shape of `Z`, a length): the condensed balance."""
    return Z - read(local, expanded(local, Z, period, t0, N))
