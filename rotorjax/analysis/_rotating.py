"""The rotating frame: where a constantly spinning, isotropic scene is autonomous.

A scene with the rotating-frame capability maps its state both ways
(`scene.to_rotating(t, y)`, `scene.to_fixed(t, z)`; see
`rotorjax.models.AbstractScene`). The rotating-frame equations follow from the
fixed-frame ones by the chain rule, for any scene:

    z' = d/dt to_rotating(t, y(t)) = (d to_rotating / dy) f(t, y) + d to_rotating / dt,

one forward-mode product. For the planar rotor (`u = R^T C`) this is
`u' = v, v' = R^T C'' - 2 thd J v + thd^2 u - thdd J u`.
"""

import jax
import jax.numpy as jnp
import numpy as np

from ..models._contract import require
from ..models._contract import rotating_field as _rotating_field


def to_fixed(scene, t, z):
    """Fixed-frame state `y` of rotating-frame state `z` at time `t`."""
    return scene.to_fixed(t, z)


def to_rotating(scene, t, y):
    """Rotating-frame state `z` of fixed-frame state `y` at time `t`."""
    return scene.to_rotating(t, y)


def rotating_field(scene, t, z):
    """`dz/dt` of the rotating-frame state (depends on `t` unless the scene is
    autonomous in the rotating frame); `rotorjax.models._contract.rotating_field`."""
    return _rotating_field(scene, t, z)


def check_autonomous(scene, rtol=1e-9, seed=0):
    """Raise `ValueError` unless the scene is autonomous in the rotating frame
    (constant speed and isotropic supports): tested at random states and times."""
    require(scene, "to_rotating", "a rotating-frame analysis")
    rng = np.random.default_rng(seed)
    for _ in range(3):
        z = jnp.asarray(rng.normal(size=scene.state_size) * 0.3)
        a = np.asarray(rotating_field(scene, 0.0, z))
        b = np.asarray(rotating_field(scene, rng.uniform(0.3, 3.0), z))
        if not np.allclose(a, b, rtol=rtol, atol=rtol * (1 + np.abs(a).max())):
            raise ValueError(
                "this scene is not autonomous in the rotating frame (anisotropic supports "
                "or a varying speed), so it has no stationary regimes there: use Floquet "
                "analysis (rotorjax.analysis.floquet) for its periodic motions"
            )
