"""Modal (Ritz) reduction of a finite-element rotor.

The basis is the `n_modes` lowest undamped modes of the non-rotating rotor
(`K_s phi = w^2 M phi`, `K_s` the symmetric part of the stiffness, bearings
included), mass-normalised. The reduced rotor `Phi^T (M, C, G1, K) Phi` has the
same interface as the full one (`reduced_matrices`, `expand`, `project`), so every
linear analysis runs on either.

The basis is held fixed under differentiation (`stop_gradient`): gradients are
those of the reduced model in a frozen basis. This keeps them finite where the
rotor has repeated frequencies (an isotropic rotor's x/y pairs, where the
derivative of individual eigenvectors is undefined) and, because eigenvalues are
stationary with respect to the Ritz basis, differs from the full model's
derivative only at the order of the reduction error.
"""

import equinox as eqx
import jax
import jax.numpy as jnp

from ._contract import AbstractShaftModel, LinearMatrices
from ._validate import InputError, as_count


def undamped_modes(M, K):
    """Eigenpairs of the symmetric pencil `(K_s, M)`, ascending, mass-normalised."""
    Ks = 0.5 * (K + K.T)
    L = jnp.linalg.cholesky(M)
    Linv = jax.scipy.linalg.solve_triangular(L, jnp.eye(M.shape[0]), lower=True)
    w2, V = jnp.linalg.eigh(Linv @ Ks @ Linv.T)
    return w2, Linv.T @ V


class ReducedRotor(AbstractShaftModel):
    """A `FlexibleRotor` reduced to its `n_modes` lowest undamped modes (see the
    module docstring); `rotor.reduce(n_modes)` builds one."""

    rotor: eqx.Module
    basis: jax.Array  # (n_free_dofs, n_modes)

    def __init__(self, rotor, n_modes):
        if not (isinstance(rotor, AbstractShaftModel) and rotor.full_rotor is rotor):  # a FlexibleRotor
            raise InputError(f"rotor must be a FlexibleRotor, got {type(rotor).__name__}")
        n_free = len(rotor.free_dofs)
        n_modes = as_count("n_modes (reduction)", n_modes, minimum=1, maximum=n_free)
        M, _, _, K = rotor.reduced_matrices()
        _, phi = undamped_modes(M, K)
        self.rotor = rotor
        self.basis = jax.lax.stop_gradient(phi[:, :n_modes])

    @property
    def n_modes(self) -> int:
        return self.basis.shape[1]

    @property
    def full_rotor(self):
        return self.rotor

    @property
    def n_coordinates(self) -> int:
        return self.n_modes

    def linear_matrices(self, speed) -> LinearMatrices:
        """`Phi^T (M, C, speed G1, K) Phi`, bearings at `speed`."""
        M, C, G1, K = self.reduced_matrices(speed)
        return LinearMatrices(M=M, C=C, G=speed * G1, K=K)

    def reduced_matrices(self, speed=0.0):
        """`Phi^T (M, C, G1, K) Phi` in the modal coordinates (bearings at `speed`;
        the basis stays the one at speed 0)."""
        P = self.basis
        return tuple(P.T @ a @ P for a in self.rotor.reduced_matrices(speed))

    def expand(self, q):
        """Modal coordinates (vector or columns) to all dofs of the shaft."""
        return self.rotor.expand(self.basis @ q)

    def project(self, f):
        """A load on the free dofs to modal loads."""
        return self.basis.T @ f
