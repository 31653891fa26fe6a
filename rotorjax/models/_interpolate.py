"""Interpolation of speed tables (bearing coefficients against running speed).

`spline(x, y, s)` is the not-a-knot cubic spline through the points `(x_i, y_i)`
(scipy's `CubicSpline(x, y, bc_type="not-a-knot")`): C2 inside the table, the
quadratic through the points when there are 3 of them, the line when there are 2.
Outside the table it continues linearly with the end slopes (bearing tables are
not meant to be extrapolated far; a cubic's end piece would diverge fast).
`rotorjax.models.check_speeds(scene, speeds)` warns (`PlausibilityWarning`) when
the speeds an analysis uses leave a bearing's table; inside `jit` nothing can warn.

Pure JAX: differentiable in the values, the table speeds and the evaluation
speed, and vmappable. The number of points is static.

ROSS (`BearingElement`) interpolates a table with `scipy.interpolate.UnivariateSpline`
(cubic, smoothing `s = len(x)`), or `interp1d` of degree 1 or 2 for 2 or 3 points.
With 2, 3 or 4 points (and for data on a cubic) that is the same curve inside the
table; with more points ROSS's smoothing spline does not pass through the points
(residuals of order 1 in the coefficient's units), this one does.
"""

import jax.numpy as jnp


def _moments(x, y):
    """Second derivatives `M_i` at the points (`y` is `(..., n)`), from the
    continuity of the first derivative inside and the not-a-knot conditions."""
    n = x.shape[0]
    if n == 2:
        return jnp.zeros_like(y)
    h = jnp.diff(x)
    d = jnp.diff(y, axis=-1) / h.reshape((1,) * (y.ndim - 1) + h.shape)
    rhs = jnp.zeros(y.shape[:-1] + (n,), dtype=y.dtype)
    rhs = rhs.at[..., 1:-1].set(6 * (d[..., 1:] - d[..., :-1]))
    A = jnp.zeros((n, n), dtype=x.dtype)
    i = jnp.arange(1, n - 1)
    A = A.at[i, i - 1].set(h[:-1]).at[i, i].set(2 * (h[:-1] + h[1:])).at[i, i + 1].set(h[1:])
    if n == 3:
        # the parabola through the points: constant second derivative
        A = A.at[0, 0].set(1.0).at[0, 1].set(-1.0).at[2, 1].set(1.0).at[2, 2].set(-1.0)
    else:
        # not-a-knot: the third derivative is continuous at x_1 and x_{n-2}
        A = A.at[0, 0].set(h[1]).at[0, 1].set(-(h[0] + h[1])).at[0, 2].set(h[0])
        A = A.at[-1, -3].set(h[-1]).at[-1, -2].set(-(h[-2] + h[-1])).at[-1, -1].set(h[-2])
    return jnp.linalg.solve(A, rhs.reshape(-1, n).T).T.reshape(rhs.shape)


def spline(x, y, s):
    """The table `(x, y)` evaluated at `s` (see the module docstring).

    **Arguments:**
    - `x`: `(n,)` strictly increasing abscissae (`n >= 2`, static).
    - `y`: `(n,)` or `(m, n)` ordinates (`m` curves on the same abscissae).
    - `s`: a scalar.

    **Returns:** `()` or `(m,)`.
    """
    x = jnp.asarray(x, dtype=jnp.float64)
    y = jnp.asarray(y, dtype=jnp.float64)
    s = jnp.asarray(s, dtype=jnp.float64)
    n = x.shape[0]
    Mo = _moments(x, y)
    k = jnp.clip(jnp.searchsorted(x, s, side="right") - 1, 0, n - 2)
    x0, h = x[k], x[k + 1] - x[k]
    y0, y1 = y[..., k], y[..., k + 1]
    m0, m1 = Mo[..., k], Mo[..., k + 1]
    b = (y1 - y0) / h - h * (2 * m0 + m1) / 6
    inside_t = s - x0   # (no clip: its derivative at the table's ends is halved)
    inside = y0 + b * inside_t + m0 / 2 * inside_t**2 + (m1 - m0) / (6 * h) * inside_t**3
    h0, hn = x[1] - x[0], x[-1] - x[-2]
    slope0 = (y[..., 1] - y[..., 0]) / h0 - h0 * (2 * Mo[..., 0] + Mo[..., 1]) / 6
    slope_n = (y[..., -1] - y[..., -2]) / hn + hn * (Mo[..., -2] + 2 * Mo[..., -1]) / 6
    below = y[..., 0] + slope0 * (s - x[0])
    above = y[..., -1] + slope_n * (s - x[-1])
    return jnp.where(s < x[0], below, jnp.where(s > x[-1], above, inside))
