"""Stationary regimes in the rotating frame, their stability, and finding them all."""

import itertools

import equinox as eqx
import jax
import jax.numpy as jnp
import numpy as np
import optimistix as optx

from ..models import AutoBalancer
from ._rotating import check_autonomous, rotating_field


class Regime(eqx.Module):
    """A stationary regime (a steady state in the rotating frame).

    - `z`: the rotating-frame state `(u, psi, 0, 0)`.
    - `residual`: max-norm of `dz/dt` at `z`; `converged`: the root finder's verdict
      and `residual < tol`.
    - `eigenvalues`: of the rotating-frame Jacobian (`jax.jacfwd`).
    - `margin`: the largest real part; `stable`: `margin < -stability_tol`.
    - `whirl_amplitude`: `|u|`; `weight_angles`: polar angles of the weights
      relative to the rotor; `kind`: "balanced" (rotor on the axis) or "unbalanced".
    """

    z: jax.Array
    residual: jax.Array
    converged: jax.Array
    eigenvalues: jax.Array
    margin: jax.Array
    whirl_amplitude: jax.Array
    weight_angles: jax.Array

    @property
    def stable(self):
        return self.margin < -1e-9

    @property
    def verdict(self) -> str:
        m = float(self.margin)
        return "stable" if m < -1e-9 else ("unstable" if m > 1e-9 else "marginal")

    @property
    def kind(self) -> str:
        return "balanced" if float(self.whirl_amplitude) < 1e-8 else "unbalanced"


def _accel_residual(q, scene):
    n = scene.n_dof
    z = jnp.concatenate([q, jnp.zeros(n)])
    return rotating_field(scene, 0.0, z)[n:]


def _weight_angles(scene, q):
    bal = scene.find(AutoBalancer)
    if bal is None:
        return jnp.zeros(0)
    psi, _ = scene.coords_of(bal, jnp.concatenate([q, q]))
    p = jax.vmap(bal.race.position)(psi)
    return jnp.arctan2(p[:, 1], p[:, 0])


def stability(scene, z):
    """Eigenvalues of the rotating-frame Jacobian at `z` (autodiff)."""
    jac = jax.jacfwd(lambda zz: rotating_field(scene, 0.0, zz))(z)
    return jnp.linalg.eigvals(jac)


def steady_state(scene, q_guess, rtol=1e-13, atol=1e-13, max_steps=100, tol=1e-10) -> Regime:
    """Newton's method from `q_guess = (u, psi)` for a stationary regime.

    Pure and differentiable: `d(regime)/d(scene parameters)` comes from the implicit
    function theorem (optimistix's implicit adjoint). Batch guesses with `vmap`.
    A failure is marked (`converged == False`, with the residual), not raised.
    """
    q_guess = jnp.asarray(q_guess, dtype=jnp.float64)
    sol = optx.root_find(_accel_residual, optx.Newton(rtol=rtol, atol=atol), q_guess, args=scene,
                         max_steps=max_steps, throw=False)
    q = sol.value
    n = scene.n_dof
    z = jnp.concatenate([q, jnp.zeros(n)])
    residual = jnp.max(jnp.abs(rotating_field(scene, 0.0, z)))
    eig = stability(scene, z)
    ok = (sol.result == optx.RESULTS.successful) & (residual < tol) & jnp.all(jnp.isfinite(q))
    return Regime(z=z, residual=residual, converged=ok, eigenvalues=eig,
                  margin=jnp.max(jnp.real(eig)), whirl_amplitude=jnp.linalg.norm(q[:2]),
                  weight_angles=_weight_angles(scene, q))


def steady_states(scene, n_angles=16, u_starts=((0.0, 0.0),), tol=1e-10, dedupe_tol=1e-6):
    """All stationary regimes found by Newton from a grid of starts: `n_angles` per
    weight over [0, 2 pi) (all combinations), times the rotor-centre starts
    `u_starts`. Converged roots are de-duplicated (angles mod 2 pi; identical weights
    are interchangeable). Returns a list of `Regime`s sorted by whirl amplitude.
    Raises `ValueError` for a scene that is not autonomous in the rotating frame.
    """
    check_autonomous(scene)
    bal = scene.find(AutoBalancer)
    n_w = 0 if bal is None else bal.n_weights
    grid = np.linspace(0.0, 2 * np.pi, n_angles, endpoint=False) + 0.1
    starts = []
    for u in u_starts:
        for psi in itertools.product(grid, repeat=n_w):
            starts.append(np.concatenate([np.asarray(u, dtype=float), np.asarray(psi)]))
    starts = jnp.asarray(np.array(starts))
    batch = eqx.filter_jit(eqx.filter_vmap(lambda q: steady_state(scene, q, tol=tol)))(starts)
    same_masses = bal is not None and bool(np.all(np.asarray(bal.mass) == np.asarray(bal.mass)[0]))
    found, keys = [], []
    conv = np.asarray(batch.converged)
    for i in np.nonzero(conv)[0]:
        regime = jax.tree_util.tree_map(lambda x: x[i], batch)
        q = np.asarray(regime.z[:scene.n_dof])
        psi = np.mod(q[2:2 + n_w], 2 * np.pi)
        psi = np.where(psi > 2 * np.pi - dedupe_tol, 0.0, psi)
        if same_masses:
            psi = np.sort(psi)
        key = np.concatenate([q[:2], psi])
        if any(np.max(np.abs(key - k)) < dedupe_tol for k in keys):
            continue
        keys.append(key)
        found.append(regime)
    return sorted(found, key=lambda r: float(r.whirl_amplitude))
