"""Cost at matched error: a peer's cost at rotorjax's error, read off the peer's own
tolerance (or step) ladder by log-log interpolation."""

import numpy as np


def interpolate_cost(errors, costs, target):
    """The cost at `target` error along a ladder of `(errors, costs)` by log-log
    interpolation. A rung without a finite positive error (a coarse fixed-step run that
    blew up) is left out. Returns `(cost, how)`: "interpolated", or "extrapolated: ..."
    when the ladder does not bracket `target` (the nearest rung's cost)."""
    errors, costs = np.asarray(errors, dtype=float), np.asarray(costs, dtype=float)
    ok = np.isfinite(errors) & (errors > 0)
    if not ok.any():
        return float("nan"), "no rung of the peer has a finite error"
    e, c = np.log(errors[ok]), np.log(costs[ok])
    order = np.argsort(e)
    e, c = e[order], c[order]
    t = np.log(target)
    if t < e[0]:
        return float(np.exp(c[0])), "extrapolated: peer never reached this error (its finest rung's cost)"
    if t > e[-1]:
        return float(np.exp(c[-1])), "extrapolated: clamped at the peer's loosest rung"
    return float(np.exp(np.interp(t, e, c))), "interpolated"
