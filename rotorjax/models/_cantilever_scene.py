"""Model 004's scene: the cantilever rotor (`rotorjax.models.CantileverRotor`),
its unbalance and weight, and (when present) the limiters around the disk, as a
`RotorScene` composition of the shared components (the cantilever's FE shaft,
optionally reduced to its lowest modes, with `Unbalance`, `InternalDamping`,
`ExternalDamping`, `DiskDamping`, `Gravity`, `LimitersAt` and a `NodeProbe` for the
disk outputs; the work state `W` keeps the energy balance, `energy_residual` checks
it). The `cantilever-limiters` preset uses it."""

import warnings

import jax
import jax.numpy as jnp
import numpy as np

from ._cantilever import CantileverRotor
from ._limiters import Limiters
from ._speed import ConstantSpeed
from ._validate import InputError, as_param, check_type, is_concrete


def CantileverScene(rotor, N, eps=0.0, phase=0.0, gamma=0.0, limiters=None, n_modes=None):
    """Deprecated: `cantilever_scene` (model 004 as a `RotorScene` composition; the
    hand-assembled class of earlier releases is the tests' reference,
    `tests/reference/model_004_scene.py`)."""
    warnings.warn("CantileverScene is deprecated: use rotorjax.models.cantilever_scene (a RotorScene)",
                  DeprecationWarning, stacklevel=2)
    return cantilever_scene(rotor, N, eps=eps, phase=phase, gamma=gamma, limiters=limiters, n_modes=n_modes)


def cantilever_scene(rotor, N, eps=0.0, phase=0.0, gamma=0.0, limiters=None, n_modes=None):
    """Model 004 as a `RotorScene` (the arguments of `CantileverScene`): the shaft
    `rotor.scene_rotor(n_modes)` at `ConstantSpeed(N)` with, at the disk (node
    `rotor.disk_node`), `NodeProbe` (outputs `disk_x`, `disk_y`, `disk_vx`,
    `disk_vy`, `disk_tilt_x`, `disk_tilt_y`, `disk_radius`), `Unbalance(eps, phase)`,
    the rotor's damping (`rotor.damping_components()`), `Gravity(gamma)` along -x
    when `gamma` is not 0, and `LimitersAt(limiters, radius = eps_D / 2)`. The work
    state is kept (`track_work`): `energy_residual` checks a run.

    The equations are those of `CantileverScene` (tested); the limiters'
    `contact_indicator` is `LimitersAt`'s (the same sign, its force branch in
    length units); the work state also holds the weight's work (`CantileverScene`
    puts the weight's potential in the energy)."""
    from ._gravity import Gravity
    from ._node_parts import LimitersAt
    from ._node_probe import NodeProbe
    from ._rotor_scene import RotorScene
    from ._unbalance import Unbalance

    check_type("rotor", rotor, CantileverRotor, "a rotorjax.flexible.CantileverRotor")
    if limiters is not None and not isinstance(limiters, Limiters):
        raise InputError(f"limiters must be a rotorjax.contact.Limiters or None, got "
                         f"{type(limiters).__name__}")
    N = as_param("N (spin speed)", N, shape=())
    eps = as_param("eps (eccentricity)", eps, sign="nonnegative", shape=())
    phase = as_param("phase", phase, shape=())
    gamma = as_param("gamma (weight)", gamma, sign="nonnegative", shape=())
    node = rotor.disk_node
    parts = [NodeProbe(node, "disk"), Unbalance(node, eps, phase), *rotor.damping_components()]
    if not is_concrete(gamma) or float(gamma) != 0.0:
        parts.append(Gravity(gamma, angle=jnp.pi))
    if limiters is not None:
        parts.append(LimitersAt(node, limiters, radius=2 * rotor.beta**0.5))  # eps_D / 2 = 2 sqrt(beta)
    return RotorScene(rotor.scene_rotor(n_modes), ConstantSpeed(N), tuple(parts), track_work=True)


def energy_residual(scene, ys):
    """`max |E(t) - E(0) - W(t)| / max |E|` over saved states (one run)."""
    e = jax.vmap(scene.energy)(ys)
    w = ys[:, -1]
    return float(np.max(np.abs(np.asarray(e - e[0] - w))) / max(float(np.max(np.abs(np.asarray(e)))), 1e-300))
