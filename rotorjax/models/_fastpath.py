"""Hand-derived equations for the planar balancer rotor: the benchmarked fast path.

For a scene made of a `RigidRotor`, `Supports` and one `AutoBalancer` (any race
shape, any weight inertia factor, any speed profile), Newton-Euler gives, with `R`
the rotation by `theta`, `J` the rotation by pi/2, `p_j`, `t_j = dp/dpsi`,
`k_j = d2p/dpsi2` the weight's position, tangent and curvature vector on the race
(rotor frame) and `e` the rotor's eccentricity vector:

    weights:  K m_j |t_j|^2 psidd_j + m_j t_j . R^T C'' = b_j,
              b_j = -K m_j (t_j . k_j) psid_j^2 - m_j thdd t_j . J p_j
                    + m_j thd^2 t_j . p_j - drag |t_j|^2 psid_j
    rotor:    M_tot C'' + sum_j m_j R t_j psidd_j = f,
              f = -K_s C - C_s C' - M R (thdd J e - thd^2 e)
                  - sum_j m_j R (k_j psid_j^2 + 2 thd J t_j psid_j + thdd J p_j - thd^2 p_j)

Eliminating `psidd_j` leaves a 2x2 system for `C''` (a Schur complement). It is
written in scalars, weight by weight (the number of weights is static): under
`vmap` every line is one elementwise operation over the lanes, which XLA fuses,
where small matrix products would become batched dots (1.6x slower per lane on the
CPU, measured at 1 024 lanes). These are
the Lagrangian equations of `Scene` written out; `tests/models/test_fastpath.py`
checks them equal to the autodiff path at random states and parameters, and
`benchmarks/sweep_throughput.py` measures what they save.
"""

import jax.numpy as jnp

from .._sincos import sincos
from ._rotation import turn


def planar_balancer_field(rotor, supports, balancer, speed, t, y):
    """`dy/dt` for state `y = (x, y, psi_1..psi_N, xd, yd, psid_1..psid_N)`."""
    n_w = balancer.n_weights
    th, thd, thdd = speed.angle(t), speed.speed(t), speed.acceleration(t)
    race, K = balancer.race, balancer.inertia_factor
    r1, r2, cx0, cy0 = race.r1, race.r2, race.center[0], race.center[1]
    ex = rotor.eccentricity * jnp.cos(rotor.phase)
    ey = rotor.eccentricity * jnp.sin(rotor.phase)
    # rotor frame force on the rotor: -M (thdd J e - thd^2 e) - sum_j m_j (...)
    fx = -rotor.mass * (-thdd * ey - thd**2 * ex)
    fy = -rotor.mass * (thdd * ex - thd**2 * ey)
    a00 = a11 = rotor.mass + jnp.sum(balancer.mass)
    a01 = 0.0
    rhs_x = rhs_y = 0.0
    per = []
    # the weights' angles and the spin angle in one `sincos` (one copy of it in the program, not n_w + 2)
    sines, cosines = sincos(jnp.stack([*(y[2 + j] for j in range(n_w)), jnp.asarray(th, dtype=y.dtype)]))
    spin = (sines[n_w], cosines[n_w])
    for j in range(n_w):
        m = balancer.mass[j]
        psid = y[4 + n_w + j]
        s, c = sines[j], cosines[j]
        px, py = cx0 + r1 * c, cy0 + r2 * s           # position
        tx, ty = -r1 * s, r2 * c                       # tangent
        kx, ky = -r1 * c, -r2 * s                      # curvature
        tt = tx * tx + ty * ty
        b = (-K * m * (tx * kx + ty * ky) * psid**2 - m * thdd * (tx * -py + ty * px)
             + m * thd**2 * (tx * px + ty * py) - balancer.drag * tt * psid)
        # (k psid^2 + 2 thd J t psid + thdd J p - thd^2 p) m, rotor frame
        fx = fx - m * (kx * psid**2 - 2 * thd * ty * psid - thdd * py - thd**2 * px)
        fy = fy - m * (ky * psid**2 + 2 * thd * tx * psid + thdd * px - thd**2 * py)
        rtx, rty = turn(spin, (tx, ty))                 # R t
        w = m / (K * tt)
        a00, a01, a11 = a00 - w * rtx * rtx, a01 - w * rtx * rty, a11 - w * rty * rty
        g = b / (K * tt)
        rhs_x, rhs_y = rhs_x - rtx * g, rhs_y - rty * g
        per.append((b, m, rtx, rty, tt))
    # fixed frame: R f - K_s C - C_s C'
    rfx, rfy = turn(spin, (fx, fy))
    rhs_x = rhs_x + rfx - supports.kx * y[0] - supports.cx * y[2 + n_w]
    rhs_y = rhs_y + rfy - supports.ky * y[1] - supports.cy * y[3 + n_w]
    det = a00 * a11 - a01 * a01
    xdd = (a11 * rhs_x - a01 * rhs_y) / det
    ydd = (a00 * rhs_y - a01 * rhs_x) / det
    psidd = [(b - m * (rtx * xdd + rty * ydd)) / (K * m * tt) for b, m, rtx, rty, tt in per]
    return jnp.stack([y[2 + n_w], y[3 + n_w], *[y[4 + n_w + j] for j in range(n_w)], xdd, ydd, *psidd])
