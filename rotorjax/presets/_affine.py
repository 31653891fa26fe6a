"""A scene as a traceable function of one rotor-file parameter it depends on
affinely.

A rotor file's scene is assembled from numbers read from the file (NumPy, Python
floats): it cannot be built from a traced value, so a continuation, a gradient or
a grid in one of its entries has no function to trace. But many entries an
engineer varies enter the scene's arrays affinely: a bearing's coefficients, a
cubic bearing's stiffness, an unbalance's magnitude and phase (kept as an angle,
its sine taken in the field). For those the scene at `p` is the scene built at
`p0` plus `(p - p0) / h` times the difference to the one built at `p0 + h`,
exactly; `affine_scene` checks that at a third value and refuses the others by
name (on `cubic_rig.toml`: a shaft's diameter, a disk's mass, the modulus E, which
reach the arrays through the reduced model)."""

import equinox as eqx
import jax
import jax.numpy as jnp
import numpy as np

#: the largest second difference of a leaf across the three builds, relative to the leaf's size, still affine
AFFINE_RTOL = 1e-9


def affine_scene(build, p0, key):
    """`p -> build(p)` (a scene) as a JAX function of `p`, for a parameter `key`
    (named in the errors) the scene's arrays depend on affinely; `build(p)` builds
    it from a number. Raises `ValueError` where the dependence is not affine or
    changes the scene's structure."""
    p0 = float(p0)
    h = 0.25 * abs(p0) if p0 != 0 else 1.0
    scenes = [build(p) for p in (p0, p0 + h, p0 + 2 * h)]
    parts = [eqx.partition(s, eqx.is_inexact_array) for s in scenes]
    (d0, static), (d1, static1), (d2, static2) = parts
    same = [jax.tree_util.tree_structure(d) == jax.tree_util.tree_structure(d0) for d in (d1, d2)]
    if not (all(same) and eqx.tree_equal(static, static1, static2) is True):
        raise ValueError(f"{key} changes the scene's structure (not only its arrays): it cannot be traced")
    for a, b, c in zip(*(jax.tree_util.tree_leaves(d) for d in (d0, d1, d2))):
        a, b, c = (np.asarray(x) for x in (a, b, c))
        if a.shape != b.shape or a.shape != c.shape:
            raise ValueError(f"{key} changes the shape of the scene's arrays: it cannot be traced")
        size = max(np.max(np.abs(a), initial=0.0), np.max(np.abs(b), initial=0.0), np.max(np.abs(c), initial=0.0))
        if np.max(np.abs(c - 2 * b + a), initial=0.0) > AFFINE_RTOL * size:
            raise ValueError(f"the scene's arrays do not depend affinely on {key} (as they do on a bearing's "
                             "coefficients, a cubic stiffness, an unbalance): it cannot be traced in it")

    def at(p):
        s = (jnp.asarray(p, dtype=jnp.float64) - p0) / h
        return eqx.combine(jax.tree_util.tree_map(lambda a, b: a + s * (b - a), d0, d1), static)

    return at
