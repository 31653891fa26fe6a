"""Construction-time parameter checks (outside jit).

Values that are tracers (inside `jit`/`vmap`) cannot be inspected and pass through;
concrete values are checked for shape, finiteness and sign, and a failure raises
`ValueError` naming the parameter and the offending value.
"""

import jax
import jax.numpy as jnp
import numpy as np


def is_concrete(x) -> bool:
    return not isinstance(x, jax.core.Tracer)


def as_param(name: str, value, *, sign: str = "any", shape=None) -> jax.Array:
    """Convert `value` to a float64 array leaf and check it.

    **Arguments:**
    - `name`: the parameter's name, used in error messages.
    - `value`: scalar or array-like.
    - `sign`: `"positive"` (> 0), `"nonnegative"` (>= 0) or `"any"`.
    - `shape`: the required shape, or `None` for any.
    """
    if isinstance(value, (str, bytes)) or value is None:
        raise ValueError(f"{name} must be a number, got {value!r}")
    if is_concrete(value):
        try:
            arr = np.asarray(value, dtype=np.float64)
        except (TypeError, ValueError):
            raise ValueError(f"{name} must be a number, got {value!r}") from None
        if shape is not None and arr.shape != tuple(shape):
            raise ValueError(f"{name} must have shape {tuple(shape)}, got shape {arr.shape}")
        if not np.all(np.isfinite(arr)):
            raise ValueError(f"{name} must be finite, got {value!r}")
        if sign == "positive" and not np.all(arr > 0):
            raise ValueError(f"{name} must be > 0, got {value!r}")
        if sign == "nonnegative" and not np.all(arr >= 0):
            raise ValueError(f"{name} must be >= 0, got {value!r}")
        return jnp.asarray(arr)
    return jnp.asarray(value, dtype=jnp.float64)
