"""The rotating frame: where a constantly spinning, isotropic scene is autonomous.

With `R = R(theta)` the rotation by the spin angle and `J` the rotation by pi/2, the
rotor centre in the rotating frame is `u = R^T C`, with velocity `v = R^T C' - thd J u`.
The rotating-frame state is `z = (u, psi, v, psid)` (the weights' coordinates are
already relative to the rotor) and

    u' = v,    v' = R^T C'' - 2 thd J v + thd^2 u - thdd J u,

with `C''` and `psi''` from the scene's fixed-frame equations at the same instant.
"""

import jax.numpy as jnp
import numpy as np


def _rot(theta, v):
    c, s = jnp.cos(theta), jnp.sin(theta)
    return jnp.stack([c * v[0] - s * v[1], s * v[0] + c * v[1]])


def _j(v):
    return jnp.stack([-v[1], v[0]])


def to_fixed(scene, t, z):
    """Fixed-frame state `y` of rotating-frame state `z` at time `t`."""
    n = scene.n_dof
    th, thd = scene.speed.angle(t), scene.speed.speed(t)
    u, v = z[0:2], z[n:n + 2]
    c = _rot(th, u)
    cd = _rot(th, v + thd * _j(u))
    return jnp.concatenate([c, z[2:n], cd, z[n + 2:]])


def to_rotating(scene, t, y):
    """Rotating-frame state `z` of fixed-frame state `y` at time `t`."""
    n = scene.n_dof
    th, thd = scene.speed.angle(t), scene.speed.speed(t)
    u = _rot(-th, y[0:2])
    v = _rot(-th, y[n:n + 2]) - thd * _j(u)
    return jnp.concatenate([u, y[2:n], v, y[n + 2:]])


def rotating_field(scene, t, z):
    """`dz/dt` of the rotating-frame state (depends on `t` unless the scene is
    autonomous in the rotating frame)."""
    t = jnp.asarray(t, dtype=jnp.float64)
    n = scene.n_dof
    th, thd, thdd = scene.speed.angle(t), scene.speed.speed(t), scene.speed.acceleration(t)
    f = scene.vector_field(t, to_fixed(scene, t, z))
    u, v = z[0:2], z[n:n + 2]
    vd = _rot(-th, f[n:n + 2]) - 2 * thd * _j(v) + thd**2 * u - thdd * _j(u)
    return jnp.concatenate([v, z[n + 2:], vd, f[n + 2:]])


def check_autonomous(scene, rtol=1e-9, seed=0):
    """Raise `ValueError` unless the scene is autonomous in the rotating frame
    (constant speed and isotropic supports): tested at random states and times."""
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
