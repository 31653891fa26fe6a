"""Beam finite elements for a rotating shaft (Euler-Bernoulli and Timoshenko).

Each bending plane uses the same 4x4 element matrices on `(w1, s1, w2, s2)`, where
`w` is the displacement and `s` the cross-section rotation (the slope `dw/dz` for
Euler-Bernoulli), for `(x, sx)` in the xz plane and `(y, sy)` in the yz plane.
With shear parameter `phi = 12 E I / (kappa G A L^2)` (0 for Euler-Bernoulli):

- stiffness  `E I / ((1 + phi) L^3) [[12, 6L, -12, 6L], [6L, (4+phi)L^2, -6L, (2-phi)L^2], ...]`,
- translational and rotary (consistent) mass of Przemieniecki / Friswell et al.,
  "Dynamics of Rotating Machines" (2010), sec. 5.4,
- gyroscopic matrix `Omega [[0, Mp], [-Mp, 0]]` between the planes, `Mp` the rotary
  mass matrix with the polar `rho Ip = 2 rho I`.

With a disk's tilt equations `It sx'' + Ip Omega sy' = ...`, `It sy'' - Ip Omega sx' = ...`
forward whirl stiffens with speed (tested).
"""

import jax.numpy as jnp


def _sym4(a, b, c, d, e, f, g, h, i, j):
    """Symmetric 4x4 from its upper triangle (a b c d / e f g / h i / j)."""
    return jnp.array([[a, b, c, d], [b, e, f, g], [c, f, h, i], [d, g, i, j]])


def stiffness(E, I, L, phi):
    k = E * I / ((1 + phi) * L**3)
    return k * _sym4(12.0, 6 * L, -12.0, 6 * L, (4 + phi) * L**2, -6 * L, (2 - phi) * L**2,
                     12.0, -6 * L, (4 + phi) * L**2)


def translational_mass(rho, A, L, phi):
    m1 = 312 + 588 * phi + 280 * phi**2
    m2 = 44 + 77 * phi + 35 * phi**2
    m3 = 108 + 252 * phi + 140 * phi**2
    m4 = 26 + 63 * phi + 35 * phi**2
    m5 = 8 + 14 * phi + 7 * phi**2
    m6 = 6 + 14 * phi + 7 * phi**2
    k = rho * A * L / (840 * (1 + phi) ** 2)
    return k * _sym4(m1, m2 * L, m3, -m4 * L, m5 * L**2, m4 * L, -m6 * L**2, m1, -m2 * L, m5 * L**2)


def rotary_mass(rho, I, L, phi):
    a = (3 - 15 * phi) * L
    b = (4 + 5 * phi + 10 * phi**2) * L**2
    c = (-1 - 5 * phi + 5 * phi**2) * L**2
    k = rho * I / (30 * (1 + phi) ** 2 * L)
    return k * _sym4(36.0, a, -36.0, a, b, -a, c, 36.0, -a, b)


def element_matrices(E, G, rho, d_out, d_in, L, kappa, shear: bool, rotary: bool):
    """`(M, G1, K)` of one element on its 8 dofs `(x1, y1, sx1, sy1, x2, y2, sx2, sy2)`,
    with the gyroscopic matrix per unit speed `G1` (so `G = Omega G1`)."""
    A = jnp.pi / 4 * (d_out**2 - d_in**2)
    I = jnp.pi / 64 * (d_out**4 - d_in**4)
    phi = 12 * E * I / (kappa * G * A * L**2) if shear else 0.0 * L
    kp = stiffness(E, I, L, phi)
    mp = translational_mass(rho, A, L, phi)
    mr = rotary_mass(rho, I, L, phi) if rotary else jnp.zeros((4, 4))
    gp = rotary_mass(rho, 2 * I, L, phi)
    # plane matrices act on (w1, s1, w2, s2); scatter to node order (x, y, sx, sy)
    ix = jnp.array([0, 2, 4, 6])   # x1, sx1, x2, sx2
    iy = jnp.array([1, 3, 5, 7])   # y1, sy1, y2, sy2

    def place(blk_xx, blk_yy, blk_xy=None, blk_yx=None):
        out = jnp.zeros((8, 8))
        out = out.at[jnp.ix_(ix, ix)].set(blk_xx).at[jnp.ix_(iy, iy)].set(blk_yy)
        if blk_xy is not None:
            out = out.at[jnp.ix_(ix, iy)].set(blk_xy).at[jnp.ix_(iy, ix)].set(blk_yx)
        return out
    M = place(mp + mr, mp + mr)
    K = place(kp, kp)
    # The section's rotation field involves all four plane dofs, so the whole rotary
    # matrix (with the polar moment) couples the planes: +Mp from y into x, -Mp back.
    G1 = place(jnp.zeros((4, 4)), jnp.zeros((4, 4)), gp, -gp)
    return M, G1, K
