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

Eliminating `psidd_j` leaves a 2x2 system for `C''` (a Schur complement). These are
the Lagrangian equations of `Scene` written out; `tests/models/test_fastpath.py`
checks them equal to the autodiff path at random states and parameters, and
`benchmarks/sweep_throughput.py` measures what they save.
"""

import jax.numpy as jnp


from ._rotation import rotate as _rot


def planar_balancer_field(rotor, supports, balancer, speed, t, y):
    """`dy/dt` for state `y = (x, y, psi_1..psi_N, xd, yd, psid_1..psid_N)`."""
    n_w = balancer.n_weights
    psi, psid = y[2:2 + n_w], y[4 + n_w:]
    c, cd = y[0:2], y[2 + n_w:4 + n_w]
    th, thd, thdd = speed.angle(t), speed.speed(t), speed.acceleration(t)
    race, m, K = balancer.race, balancer.mass, balancer.inertia_factor

    cps, sps = jnp.cos(psi), jnp.sin(psi)
    p = race.center[:, None] + jnp.stack([race.r1 * cps, race.r2 * sps])       # (2, N)
    tg = jnp.stack([-race.r1 * sps, race.r2 * cps])                              # (2, N)
    kv = jnp.stack([-race.r1 * cps, -race.r2 * sps])                             # (2, N)
    jp = jnp.stack([-p[1], p[0]])
    jt = jnp.stack([-tg[1], tg[0]])
    tt = jnp.sum(tg * tg, axis=0)

    b = (-K * m * jnp.sum(tg * kv, axis=0) * psid**2 - m * thdd * jnp.sum(tg * jp, axis=0)
         + m * thd**2 * jnp.sum(tg * p, axis=0) - balancer.drag * tt * psid)
    e = rotor.eccentricity * jnp.stack([jnp.cos(rotor.phase), jnp.sin(rotor.phase)])
    je = jnp.stack([-e[1], e[0]])
    pr = psid[None, :]
    inner = (kv * pr**2 + 2 * thd * jt * pr + thdd * jp - thd**2 * p) @ m     # rotor frame
    f_rot = -rotor.mass * (thdd * je - thd**2 * e) - inner
    f = _rot(th, f_rot) - jnp.stack([supports.kx * c[0], supports.ky * c[1]]) \
        - jnp.stack([supports.cx * cd[0], supports.cy * cd[1]])

    # Eliminate psidd_j = (b_j - m_j t_j . R^T C'') / (K m_j |t_j|^2).
    rt = _rot(th, tg)                                                            # (2, N)
    w = m / (K * tt)
    mtot = rotor.mass + jnp.sum(m)
    a = mtot * jnp.eye(2) - (rt * w[None, :]) @ rt.T
    rhs = f - rt @ (b / (K * tt))
    det = a[0, 0] * a[1, 1] - a[0, 1] * a[1, 0]
    cdd = jnp.stack([a[1, 1] * rhs[0] - a[0, 1] * rhs[1], a[0, 0] * rhs[1] - a[1, 0] * rhs[0]]) / det
    psidd = (b - m * jnp.sum(rt * cdd[:, None], axis=0)) / (K * m * tt)
    return jnp.concatenate([cd, psid, cdd, psidd])
