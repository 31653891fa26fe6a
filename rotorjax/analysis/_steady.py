"""Stationary regimes in the rotating frame, their stability, and finding them all."""

import itertools

import equinox as eqx
import jax
import jax.numpy as jnp
import numpy as np

from .._autodiff import value_and_jacfwd
from .._newton import newton
from ..models._contract import require
from ._rotating import check_autonomous, rotating_field


class Regime(eqx.Module):
    """A stationary regime (a steady state in the rotating frame).

    - `z`: the rotating-frame state `(u, psi, 0, 0)`.
    - `residual`: max-norm of `dz/dt` at `z`; `converged`: the root finder's verdict
      and `residual < tol`.
    - `eigenvalues`: of the rotating-frame Jacobian (`jax.jacfwd`).
    - `margin`: the largest real part; `stable`: `margin < -stability_tol`.
    - `whirl_amplitude`: the scene's `whirl_amplitude` output (`|u|` for a planar
      rotor, the largest node orbit of an FE rotor); `weight_angles`: polar angles
      of the weights relative to the rotor; `kind`: "balanced" (rotor on the axis)
      or "unbalanced".
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

    def as_dict(self) -> dict:
        """The regime as a JSON row (one unbatched regime)."""
        return {
            "whirl_amplitude": float(self.whirl_amplitude),
            "weight_angles": [float(a) for a in np.asarray(self.weight_angles)],
            "max_eigenvalue_real_part": float(self.margin),
            "verdict": self.verdict,
            "kind": self.kind,
            "residual": float(self.residual),
            "state_rotating_frame": [float(v) for v in np.asarray(self.z)],
        }


def _accel_residual(q, scene):
    n = scene.n_dof
    z = jnp.concatenate([q, jnp.zeros(n)])
    return rotating_field(scene, 0.0, z)[n:]


def _observed(scene, z):
    """`(whirl_amplitude, weight_angles)` of rotating-frame state `z` (at t = 0,
    where both frames coincide), from the scene's own outputs."""
    out = scene.outputs(0.0, scene.to_fixed(0.0, z))
    return out["whirl_amplitude"], out.get("weight_angles", jnp.zeros(0))


def stability(scene, z):
    """Eigenvalues of the rotating-frame Jacobian at `z` (autodiff)."""
    require(scene, "to_rotating", "stability of a stationary regime")
    return _eigenvalues(scene, jnp.asarray(z, dtype=jnp.float64))


@eqx.filter_jit
def _eigenvalues(scene, z):
    jac = jax.jacfwd(lambda zz: rotating_field(scene, 0.0, zz))(z)
    return jnp.linalg.eigvals(jac)


def steady_state(scene, q_guess, rtol=1e-13, atol=1e-13, max_steps=100, tol=1e-10) -> Regime:
    """Newton's method from `q_guess = (u, psi)` for a stationary regime (the
    package's Newton, `rotorjax._newton`: until the step is <= `atol + rtol |q|`, or
    is at the rounding floor, at most `max_steps` steps).

    Pure and differentiable: `d(regime)/d(scene parameters)` comes from the implicit
    function theorem. Batch guesses with `vmap`. A failure is marked (`converged ==
    False`, with the residual), not raised. Compiled once per scene structure (the
    Newton solve, the Jacobian's eigenvalues and the outputs together, not op by op).
    """
    require(scene, "to_rotating", "steady_state")
    return _steady_state(scene, jnp.asarray(q_guess, dtype=jnp.float64), rtol, atol, max_steps, tol)


#: Newton stops at a relative step this small that no longer halves (the rounding floor of an ill-conditioned
#: Jacobian), and a regime counts as found only once its steps are this small (and its residual below `tol`)
STEP_FLOOR = 1e-8


@eqx.filter_jit
def _steady_state(scene, q_guess, rtol, atol, max_steps, tol) -> Regime:
    q, (step, _) = newton(lambda v: _accel_residual(v, scene), q_guess, rtol, max_steps, floor=STEP_FLOOR,
                         unit=atol / rtol)
    n = scene.n_dof
    z = jnp.concatenate([q, jnp.zeros(n)])
    # the field and its Jacobian from one forward-mode pass (one copy of the field in the program)
    field, jac = value_and_jacfwd(lambda zz: rotating_field(scene, 0.0, zz))(z)
    residual = jnp.max(jnp.abs(field))
    eig = jnp.linalg.eigvals(jac)
    ok = (step <= STEP_FLOOR) & (residual < tol) & jnp.all(jnp.isfinite(q))
    whirl, angles = _observed(scene, z)
    return Regime(z=z, residual=residual, converged=ok, eigenvalues=eig,
                  margin=jnp.max(jnp.real(eig)), whirl_amplitude=whirl, weight_angles=angles)


def steady_states(scene, n_angles=16, u_starts=None, tol=1e-10, dedupe_tol=1e-6):
    """All stationary regimes found by Newton from a grid of starts: `n_angles` per
    balancing weight over [0, 2 pi) (all combinations; the scene's
    `weight_coordinates`), times the starts `u_starts` of the other coordinates
    (default: the rotor on the axis). Converged roots are de-duplicated (angles
    mod 2 pi; identical weights are interchangeable). Returns a list of `Regime`s
    sorted by whirl amplitude. Raises `ValueError` for a scene that is not
    autonomous in the rotating frame.
    """
    check_autonomous(scene)
    n = scene.n_dof
    angle_idx, same_masses = scene.weight_coordinates()
    other = np.setdiff1d(np.arange(n), angle_idx)
    if u_starts is None:
        u_starts = (np.zeros(other.size),)
    grid = np.linspace(0.0, 2 * np.pi, n_angles, endpoint=False) + 0.1
    starts = []
    for u in u_starts:
        u = np.asarray(u, dtype=float)
        if u.shape != (other.size,):
            raise ValueError(f"u_starts entries must have {other.size} values (the coordinates that are not "
                             f"weight angles), got shape {u.shape}")
        for psi in itertools.product(grid, repeat=angle_idx.size):
            start = np.zeros(n)
            start[other], start[angle_idx] = u, psi
            starts.append(start)
    starts = jnp.asarray(np.array(starts))
    batch = eqx.filter_jit(eqx.filter_vmap(lambda q: steady_state(scene, q, tol=tol)))(starts)
    found, keys = [], []
    conv = np.asarray(batch.converged)
    for i in np.nonzero(conv)[0]:
        regime = jax.tree_util.tree_map(lambda x: x[i], batch)
        q = np.asarray(regime.z[:n])
        psi = np.mod(q[angle_idx], 2 * np.pi)
        psi = np.where(psi > 2 * np.pi - dedupe_tol, 0.0, psi)
        if same_masses:
            psi = np.sort(psi)
        key = np.concatenate([q[other], psi])
        if any(np.max(np.abs(key - k)) < dedupe_tol for k in keys):
            continue
        keys.append(key)
        found.append(regime)
    return sorted(found, key=lambda r: float(r.whirl_amplitude))
