import jax
import numpy as np


def tree_allclose(a, b, rtol=1e-10, atol=1e-12) -> bool:
    la, lb = jax.tree_util.tree_leaves(a), jax.tree_util.tree_leaves(b)
    if len(la) != len(lb):
        return False
    return all(np.allclose(np.asarray(x), np.asarray(y), rtol=rtol, atol=atol) for x, y in zip(la, lb))


def central_difference(f, x, h):
    """Central finite difference of scalar `f` at scalar `x` (error O(h^2)), as a
    Python float (numpy, for array-valued `f`): never a JAX array, which
    `pytest.approx` (9.2) cannot take as its expected value."""
    d = np.asarray((f(x + h) - f(x - h)) / (2 * h), dtype=float)
    return float(d) if d.ndim == 0 else d


def set_csv_field(line_no, field, value):
    """An edit of a CSV text's lines: field `field` (0-based) of line `line_no`
    (1-based) set to `value` (for the bad-file tables)."""
    def edit(lines):
        parts = lines[line_no - 1].split(",")
        parts[field] = value
        lines[line_no - 1] = ",".join(parts)
        return lines
    return edit
