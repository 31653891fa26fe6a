"""Linear analyses of any scene with the linear capability: its unbalance
response and the stability margin of its reference motion."""

import equinox as eqx
import jax
import jax.numpy as jnp

from ..models._contract import require
from ..models._frequency import frequency_response
from ..models._validate import as_numpy, is_concrete
from ._linear import system_eigenvalues


def scene_unbalance_response(scene, speeds):
    """Complex amplitudes `Q` (rows: speeds) of the synchronous response of the
    scene's coordinates to its unbalance, `q = Re(Q e^{i speed t})`, from
    `linear_matrices(speed)` and `unbalance_load(speed)` (vmapped over speeds)."""
    require(scene, "linear_matrices", "an unbalance response")
    require(scene, "unbalance_load", "an unbalance response")
    if is_concrete(speeds):
        as_numpy("speeds", speeds, ndim=1)
    return _responses(scene, jnp.asarray(speeds, dtype=jnp.float64))


@eqx.filter_jit
def _responses(scene, speeds):
    def one(w):
        lin = scene.linear_matrices(w)
        return frequency_response(lin.M, lin.C + lin.G, lin.K, scene.unbalance_load(w), w)

    return jax.vmap(one)(speeds)


def linear_margin(scene, speed):
    """Largest real part of the eigenvalues of the scene's linear(ised) equations
    about its reference motion at `speed` (< 0: stable): of any linear system (a
    linear scene, a finite-element rotor, model 004's `CantileverRotor`). Traceable in
    the speed and the scene's parameters."""
    require(scene, "linear_system", "a linear stability margin")
    return jnp.max(jnp.real(system_eigenvalues(scene, speed)))
