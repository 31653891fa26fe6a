"""Construction-time parameter checks (outside jit).

Every public constructor and function checks its arguments here, before any
tracing, and a failure raises `rotorjax._errors.InputError` (a `ValueError`) whose
message names the parameter as the caller passed it, the offending value and what
would be valid.

Values that are tracers (inside `jit`/`vmap`) cannot be inspected: their *values*
pass through unchecked (only their static shapes are checked), and no check ever
calls `float()` or `bool()` on one. Counts that fix a topology (elements, modes,
weights) are static and must be concrete.
"""

import jax
import jax.numpy as jnp
import numpy as np

from .._errors import InputError

__all__ = [
    "InputError", "is_concrete", "show", "as_param", "as_numpy", "as_vector", "per_item",
    "as_count", "check", "check_choice", "check_type", "check_node", "check_span",
]

_SIGNS = {
    "positive": (lambda a: a > 0, "> 0"),
    "nonnegative": (lambda a: a >= 0, ">= 0"),
    "any": (None, None),
}


def is_concrete(x) -> bool:
    """True when no leaf of `x` is a tracer (its values can be inspected)."""
    return not any(isinstance(leaf, jax.core.Tracer) for leaf in jax.tree_util.tree_leaves(x))


def show(value) -> str:
    """A short rendering of a caller's value for an error message."""
    if isinstance(value, (np.ndarray, jax.Array, list, tuple)) and is_concrete(value):
        try:
            arr = np.asarray(value)
        except (TypeError, ValueError):
            return repr(value)
        if arr.dtype.kind in "biufc":
            if arr.ndim == 0:
                return repr(arr.item())
            return np.array2string(arr, threshold=12, edgeitems=3, separator=", ")
    if isinstance(value, np.generic):
        return repr(value.item())
    return repr(value)


def as_numpy(name: str, value, *, sign: str = "any", shape=None, ndim=None, dtype=np.float64,
             finite: bool = True) -> np.ndarray:
    """`value` as a concrete numpy array, checked (see `as_param`). For functions
    that compute with numpy (not traceable anyway)."""
    if sign not in _SIGNS:
        raise ValueError(f"unknown sign requirement {sign!r}")  # a bug in rotorjax, not bad input
    if isinstance(value, (str, bytes)) or value is None:
        raise InputError(f"{name} must be a number, got {value!r}")
    if not is_concrete(value):
        raise InputError(f"{name} must be a concrete value here (this function is not traceable), "
                         f"got a traced value")
    try:
        arr = np.asarray(value, dtype=dtype)
    except (TypeError, ValueError):
        raise InputError(f"{name} must be a number or an array of numbers, got {value!r}") from None
    _check_array(name, value, arr, sign=sign, shape=shape, ndim=ndim, finite=finite)
    return arr


def _check_array(name, value, arr, *, sign, shape, ndim, finite):
    if shape is not None and arr.shape != tuple(shape):
        raise InputError(f"{name} must have shape {tuple(shape)}, got shape {arr.shape}: {show(value)}")
    if ndim is not None and arr.ndim != ndim:
        raise InputError(f"{name} must be a {ndim}-D array, got shape {arr.shape}: {show(value)}")
    if finite and not np.all(np.isfinite(arr)):
        raise InputError(f"{name} must be finite, got {show(value)}")
    test, text = _SIGNS[sign]
    if test is not None and not np.all(test(arr)):
        raise InputError(f"{name} must be {text}, got {show(value)}")


def as_param(name: str, value, *, sign: str = "any", shape=None, ndim=None) -> jax.Array:
    """Convert `value` to a float64 array leaf and check it.

    **Arguments:**
    - `name`: the parameter's name as the caller passed it (with a gloss), used in
      error messages.
    - `value`: scalar or array-like; a tracer passes (only its shape is checked).
    - `sign`: `"positive"` (> 0), `"nonnegative"` (>= 0) or `"any"`; always finite.
    - `shape`, `ndim`: the required shape or number of dimensions, or `None` for any.
    """
    if sign not in _SIGNS:
        raise ValueError(f"unknown sign requirement {sign!r}")
    if isinstance(value, (str, bytes)) or value is None:
        raise InputError(f"{name} must be a number, got {value!r}")
    if is_concrete(value):
        return jnp.asarray(as_numpy(name, value, sign=sign, shape=shape, ndim=ndim))
    out = jnp.asarray(value, dtype=jnp.float64)
    if shape is not None and out.shape != tuple(shape):
        raise InputError(f"{name} must have shape {tuple(shape)}, got a traced value of shape {out.shape}")
    if ndim is not None and out.ndim != ndim:
        raise InputError(f"{name} must be a {ndim}-D array, got a traced value of shape {out.shape}")
    return out


def as_vector(name: str, value, *, sign: str = "any", min_size: int = 1, what: str = "entries"):
    """A 1-D float64 array leaf of at least `min_size` entries (see `as_param`)."""
    arr = as_param(name, value, sign=sign)
    if arr.ndim != 1 or arr.shape[0] < min_size:
        raise InputError(f"{name} must be a 1-D array of >= {min_size} {what}, got shape {arr.shape}"
                         + (f": {show(value)}" if is_concrete(value) else ""))
    return arr


def per_item(name: str, value, n: int, *, sign: str = "any", what: str = "item") -> jax.Array:
    """A scalar (broadcast) or one value per item: a float64 array of shape `(n,)`."""
    v = as_param(name, value, sign=sign)
    if v.ndim == 0:
        return jnp.full(n, v)
    if v.shape != (n,):
        raise InputError(f"{name} must be a scalar or one value per {what} ({n}), got shape {v.shape}"
                         + (f": {show(value)}" if is_concrete(value) else ""))
    return v


def as_count(name: str, value, *, minimum: int = 1, maximum: int | None = None) -> int:
    """A concrete integer count (elements, modes, weights, steps) in
    `minimum..maximum`. Integral floats (`8.0`) are accepted; booleans, strings,
    fractions, non-finite values and tracers are not."""
    rng = f"an integer >= {minimum}" if maximum is None else f"an integer in {minimum}..{maximum}"
    if isinstance(value, jax.core.Tracer):
        raise InputError(f"{name} sets the model's size or a loop count: it must be a concrete "
                         f"integer ({rng}), not a traced value")
    if isinstance(value, (bool, np.bool_, str, bytes)) or value is None:
        raise InputError(f"{name} must be {rng}, got {value!r}")
    try:
        f = float(value)
    except (TypeError, ValueError):
        raise InputError(f"{name} must be {rng}, got {value!r}") from None
    if not np.isfinite(f) or f != int(f):
        raise InputError(f"{name} must be {rng}, got {show(value)}")
    n = int(f)
    if n < minimum or (maximum is not None and n > maximum):
        raise InputError(f"{name} must be {rng}, got {n}")
    return n


def check(name: str, value, ok, requirement: str) -> None:
    """Raise unless `ok(np.asarray(value))` holds everywhere; skipped for tracers."""
    if is_concrete(value) and not np.all(ok(np.asarray(value))):
        raise InputError(f"{name} must be {requirement}, got {show(value)}")


def check_choice(name: str, value, choices) -> None:
    """`value` must be one of `choices` (strings)."""
    if not isinstance(value, str) or value not in choices:
        valid = ", ".join(repr(c) for c in choices)
        raise InputError(f"{name} must be one of {valid}; got {value!r}")


def check_type(name: str, value, cls, what: str) -> None:
    if not isinstance(value, cls):
        raise InputError(f"{name} must be {what}, got {type(value).__name__}")


def check_node(name: str, node, n_nodes: int, what: str = "node") -> int:
    """A node index that exists on a shaft of `n_nodes` nodes."""
    bad = InputError(f"{name}: {what} must be an integer node index in 0..{n_nodes - 1}, got {node!r}")
    if isinstance(node, (bool, np.bool_, str, bytes)) or not is_concrete(node):
        raise bad
    try:
        f = float(node)
    except (TypeError, ValueError):
        raise bad from None
    if not np.isfinite(f) or f != int(f):
        raise bad
    if not 0 <= f < n_nodes:
        raise InputError(f"{name}: {what} at node {int(f)} does not exist: the shaft has nodes "
                         f"0..{n_nodes - 1}")
    return int(f)


def check_span(name_lo: str, lo, name_hi: str, hi) -> tuple:
    """Two finite concrete floats with `lo < hi`."""
    lo = float(as_numpy(name_lo, lo, shape=()))
    hi = float(as_numpy(name_hi, hi, shape=()))
    if not lo < hi:
        raise InputError(f"{name_lo} must be < {name_hi}, got {name_lo} = {lo!r}, {name_hi} = {hi!r}")
    return lo, hi


def as_components(components, cls, what: str, examples: str) -> tuple:
    """`components` (one, or an iterable of them) as a tuple of `cls` instances, or an
    `InputError` naming the first that is not (`what`: "rotorjax component", ...)."""
    if isinstance(components, cls):
        components = (components,)
    try:
        components = tuple(components)
    except TypeError:
        raise InputError(f"components must be a tuple of {what}s, got {type(components).__name__}") from None
    for i, c in enumerate(components):
        if not isinstance(c, cls):
            raise InputError(f"components[{i}] must be a {what} ({examples}), got {type(c).__name__}")
    return components
