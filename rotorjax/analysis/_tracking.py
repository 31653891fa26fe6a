"""Mode tracking along a Campbell diagram: the modal assurance criterion between
complex mode shapes, and branches that follow each mode's shape from speed to speed
instead of the sorted order (which swaps branches where they cross)."""

import jax.numpy as jnp
import numpy as np

from ..models._validate import InputError
from ._linear import Modes


def mac(a, b):
    """Modal assurance criterion between the columns of complex shapes `a` (n, ka)
    and `b` (n, kb): `|a_i^H b_j|^2 / ((a_i^H a_i)(b_j^H b_j))`, in [0, 1], 1 for
    shapes equal up to a complex factor. Returns `(ka, kb)`."""
    a, b = jnp.asarray(a), jnp.asarray(b)
    if a.ndim == 1:
        a = a[:, None]
    if b.ndim == 1:
        b = b[:, None]
    if a.shape[0] != b.shape[0]:
        raise InputError(f"mac: the shapes have {a.shape[0]} and {b.shape[0]} dofs")
    num = jnp.abs(jnp.conj(a).T @ b) ** 2
    den = jnp.real(jnp.sum(jnp.conj(a) * a, axis=0))[:, None] * jnp.real(jnp.sum(jnp.conj(b) * b, axis=0))[None, :]
    return num / jnp.where(den > 0, den, 1.0)


def _assign(c):
    """The column for each row maximising the summed MAC (Hungarian method;
    greedy on the largest entries where SciPy is absent)."""
    try:
        from scipy.optimize import linear_sum_assignment
    except ImportError:  # pragma: no cover - SciPy is a test dependency
        k = c.shape[0]
        out, used_r, used_c = np.full(k, -1), set(), set()
        for flat in np.argsort(-c, axis=None):
            i, j = divmod(int(flat), c.shape[1])
            if i not in used_r and j not in used_c:
                out[i] = j
                used_r.add(i)
                used_c.add(j)
        return out
    rows, cols = linear_sum_assignment(-c)
    out = np.empty(c.shape[0], dtype=int)
    out[rows] = cols
    return out


def track_order(campbell_result):
    """The permutation that tracks each branch: `order[i, k]` is the sorted index,
    at speed `i`, of branch `k` (branch `k` starts as the `k`-th mode at the first
    speed); and `mac_step[i, k]`, the MAC between branch `k`'s shapes at speeds
    `i - 1` and `i` (1 at the first speed). Concrete inputs (not under `jit`)."""
    shapes = np.asarray(campbell_result.shapes)
    if shapes.ndim != 3:
        raise InputError("track_modes needs a Campbell result (modes over several speeds: shapes of ndim 3), "
                         f"got shapes of ndim {shapes.ndim}")
    n_speeds, _, k = shapes.shape
    order = np.zeros((n_speeds, k), dtype=int)
    order[0] = np.arange(k)
    step = np.ones((n_speeds, k))
    for i in range(1, n_speeds):
        prev = shapes[i - 1][:, order[i - 1]]
        c = np.asarray(mac(prev, shapes[i]))
        order[i] = _assign(c)
        step[i] = c[np.arange(k), order[i]]
    return order, step


def track_modes(campbell_result) -> Modes:
    """`campbell_result` (a `Modes` over speeds, as `campbell` returns) with each
    speed's modes re-ordered to follow the previous speed's by the modal assurance
    criterion of their complex shapes (an optimal one-to-one assignment): column
    `k` is one branch, continuous through crossings of the sorted frequencies (where
    a forward branch meets a backward one, for example). Branch `k` starts as the
    `k`-th mode at the first speed. Where a mode enters or leaves the computed set
    (above the highest one kept), the top branches may change identity: compute a
    few more modes than needed. Concrete inputs (not under `jit`)."""
    order, _ = track_order(campbell_result)
    rows = np.arange(order.shape[0])[:, None]

    def per_mode(a):
        a = np.asarray(a)
        if a.ndim == 3:   # shapes: (speeds, dofs, modes)
            return jnp.asarray(np.take_along_axis(a, order[:, None, :], axis=2))
        return jnp.asarray(a[rows, order])

    return Modes(**{f: per_mode(getattr(campbell_result, f)) for f in Modes.__dataclass_fields__})
