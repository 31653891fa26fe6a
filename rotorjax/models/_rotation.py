"""The one rotation helper: planar vectors turned by the spin angle.

Every place that goes between the fixed frame and the frame spinning with the
rotor (a component's kinematics, the rotating-frame state of a scene, the
hand-derived fast path) uses these. Vectors are pairs along the first axis,
`v = (v_x, v_y)` of shape `(2, ...)`.
"""

import jax.numpy as jnp

from .._sincos import sincos


def rotate(theta, v):
    """`R(theta) v`: `v` turned by `theta` (counter-clockwise)."""
    return turn(sincos(theta), v)


def turn(sc, v):
    """`R v` for the rotation whose `(sin, cos)` is `sc`: one `sincos` serves every
    vector turned by the same angle (each call of it is some thirty operations in a
    program, which XLA compiles one by one before it folds the copies)."""
    s, c = sc
    return jnp.stack([c * v[0] - s * v[1], s * v[0] + c * v[1]])


def quarter_turn(v):
    """`J v = R(pi/2) v = (-v_y, v_x)` (multiplication of `v_x + i v_y` by `i`)."""
    return jnp.stack([-v[1], v[0]])


def to_rotating_pair(theta, theta_dot, p, p_dot):
    """A fixed-frame position and velocity `(p, p')` seen in the frame spinning at
    angle `theta` and rate `theta_dot`: `u = R^T p`, `u' = R^T p' - theta_dot J u`."""
    s, c = sincos(theta)
    u = turn((-s, c), p)
    return u, turn((-s, c), p_dot) - theta_dot * quarter_turn(u)


def to_fixed_pair(theta, theta_dot, u, u_dot):
    """Inverse of `to_rotating_pair`: `p = R u`, `p' = R (u' + theta_dot J u)`."""
    sc = sincos(theta)
    return turn(sc, u), turn(sc, u_dot + theta_dot * quarter_turn(u))


def quarter_turn_matrix(n_nodes: int):
    """`J` on all dofs of a shaft of `n_nodes` nodes: per node `(x, y, sx, sy) ->
    (y, -x, sy, -sx)` (the complex displacement `x + i y` times `-i`; the
    circulatory term of internal damping is `speed C_i J q`)."""
    import numpy as np

    blk = np.array([[0, 1, 0, 0], [-1, 0, 0, 0], [0, 0, 0, 1], [0, 0, -1, 0]], dtype=float)
    return np.kron(np.eye(n_nodes), blk)
