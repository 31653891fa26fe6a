"""Model 002's analysis (Polushkin et al. 2016): the steady support vibration of the
rigid rotor on its balancing machine (`rotorjax.models.BalancingMachine`, whose
docstring states the model, eqs. 8-17) under unbalances in its correction planes."""

import jax.numpy as jnp
import numpy as np

from ..models._balancing_machine import BalancingMachine, _check_planes
from ..models._validate import as_numpy, check_type, is_concrete


def balancing_response(machine, speed, planes, unbalances):
    """Complex support amplitudes `X = K(speed) D` (m; `x = Re(X e^{i speed t})`,
    shape `(2,)`) of `machine` at `speed` (rad/s) for the unbalances `D` (kg m,
    complex, angles from the mark) in the correction planes at `planes` (m from
    support 1): the influence matrix of eqs. (15), (17) times `D`. Traceable and
    vmappable in the speed, the machine's parameters and the unbalances."""
    check_type("machine", machine, BalancingMachine, "a rotorjax.models.BalancingMachine")
    n = _check_planes(planes)
    if is_concrete(unbalances):
        as_numpy("unbalances", unbalances, shape=(n,), dtype=np.complex128)
    return machine.influence_matrix(speed, planes) @ jnp.asarray(unbalances, dtype=jnp.complex128)
