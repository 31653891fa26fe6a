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

Tapered elements (a linear taper of both diameters) are Genta's conical element
(G. Genta, A. Gugliotta, "A conical element for finite element rotor dynamics",
J. Sound Vib. 120 (1988) 175-182) exactly as ROSS 2.3.0 writes it (`ShaftElement`):
area and second moment polynomial along the element with the coefficients
`a1, b1` and `a2, b2, gama, delta`, `phi` and Cowper's `kappa` from the mid-length
section (mean diameters). ROSS's 6 dofs per node `(x, y, z, alpha, beta, theta)` map
to ours as `x = x`, `y = y`, `sx = beta`, `sy = -alpha` (alpha the rotation about x:
a positive alpha tilts the section towards -y), so both planes share one 4x4
matrix; ROSS's axial and torsional dofs are uncoupled from bending and left out.

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


def conical_coefficients(d_out, d_in):
    """Genta's geometric coefficients of a conical element (ROSS `ShaftElement`):
    along `xi = z / L` the area is `A_l (1 + a1 xi + b1 xi^2)` and the second
    moment `I_l (1 + a2 xi + b2 xi^2 + gama xi^3 + delta xi^4)`. `d_out`, `d_in`
    are `(left, right)` pairs. Returns `A_l, I_l, A, I, (a1, a2, b1, b2, gama, delta)`
    with `A`, `I` at mid-length."""
    odl, odr = d_out[0], d_out[1]
    idl, idr = d_in[0], d_in[1]
    A_l = jnp.pi * (odl**2 - idl**2) / 4
    I_l = jnp.pi * (odl**4 - idl**4) / 64
    roj, rij, rok, rik = odl / 2, idl / 2, odr / 2, idr / 2
    dro, dri = rok - roj, rik - rij
    a1 = 2 * jnp.pi * (roj * dro - rij * dri) / A_l
    a2 = jnp.pi * (roj**3 * dro - rij**3 * dri) / I_l
    b1 = jnp.pi * (dro**2 - dri**2) / A_l
    b2 = 3 * jnp.pi * (roj**2 * dro**2 - rij**2 * dri**2) / (2 * I_l)
    gama = jnp.pi * (roj * dro**3 - rij * dri**3) / I_l
    delta = jnp.pi * (dro**4 - dri**4) / (4 * I_l)
    A = A_l * (1 + a1 * 0.5 + b1 * 0.5**2)
    I = I_l * (1 + a2 * 0.5 + b2 * 0.5**2 + gama * 0.5**3 + delta * 0.5**4)
    return A_l, I_l, A, I, (a1, a2, b1, b2, gama, delta)


def _plane(d11, d12, d13, d14, d22, d23, d24, d33, d34, d44):
    return _sym4(d11, d12, d13, d14, d22, d23, d24, d33, d34, d44)


def conical_translational_mass(rho, A_l, L, phi, a1, b1):
    p = phi
    m1 = (468 + 882 * p + 420 * p**2) + a1 * (108 + 210 * p + 105 * p**2) + b1 * (38 + 78 * p + 42 * p**2)
    m2 = ((66 + 115.5 * p + 52.5 * p**2) + a1 * (21 + 40.5 * p + 21 * p**2)
          + b1 * (8.5 + 18 * p + 10.5 * p**2)) * L
    m3 = (162 + 378 * p + 210 * p**2) + a1 * (81 + 189 * p + 105 * p**2) + b1 * (46 + 111 * p + 63 * p**2)
    m4 = ((39 + 94.5 * p + 52.5 * p**2) + a1 * (18 + 40.5 * p + 21 * p**2)
          + b1 * (9.5 + 21 * p + 10.5 * p**2)) * L
    m5 = ((12 + 21 * p + 10.5 * p**2) + a1 * (4.5 + 9 * p + 5.25 * p**2) + b1 * (2 + 4.5 * p + 3 * p**2)) * L**2
    m6 = ((39 + 94.5 * p + 52.5 * p**2) + a1 * (21 + 54 * p + 31.5 * p**2)
          + b1 * (12.5 + 34.5 * p + 21 * p**2)) * L
    m7 = ((9 + 21 * p + 10.5 * p**2) + a1 * (4.5 + 10.5 * p + 5.25 * p**2) + b1 * (2.5 + 6 * p + 3 * p**2)) * L**2
    m8 = (468 + 882 * p + 420 * p**2) + a1 * (360 + 672 * p + 315 * p**2) + b1 * (290 + 540 * p + 252 * p**2)
    m9 = ((66 + 115.5 * p + 52.5 * p**2) + a1 * (45 + 75 * p + 31.5 * p**2)
          + b1 * (32.5 + 52.5 * p + 21 * p**2)) * L
    m10 = ((12 + 21 * p + 10.5 * p**2) + a1 * (7.5 + 12 * p + 5.25 * p**2) + b1 * (5 + 7.5 * p + 3 * p**2)) * L**2
    k = rho * A_l * L / (1260 * (1 + p) ** 2)
    return k * _plane(m1, m2, m3, -m4, m5, m6, -m7, m8, -m9, m10)


def conical_rotary_mass(rho, I_l, L, phi, a2, b2, gama, delta):
    """Rotary inertia of the section (with `2 I_l`: the gyroscopic block)."""
    p = phi
    m11 = 252 + 126 * a2 + 72 * b2 + 45 * gama + 30 * delta
    m12 = (21 - 105 * p + a2 * (21 - 42 * p) + b2 * (15 - 21 * p) + gama * (10.5 - 12 * p)
           + delta * (7.5 - 7.5 * p)) * L
    m13 = (21 - 105 * p - 63 * a2 * p - b2 * (6 + 42 * p) - gama * (7.5 + 30 * p)
           - delta * (7.5 + 22.5 * p)) * L
    m14 = (28 + 35 * p + 70 * p**2 + a2 * (7 - 7 * p + 17.5 * p**2) + b2 * (4 - 7 * p + 7 * p**2)
           + gama * (2.75 - 5 * p + 3.5 * p**2) + delta * (2 - 3.5 * p + 2 * p**2)) * L**2
    m15 = (7 + 35 * p - 35 * p**2 + a2 * (3.5 + 17.5 * p - 17.5 * p**2) + b2 * (3 + 10.5 * p - 10.5 * p**2)
           + gama * (2.75 + 7 * p - 7 * p**2) + delta * (2.5 + 5 * p - 5 * p**2)) * L**2
    m16 = (28 + 35 * p + 70 * p**2 + a2 * (21 + 42 * p + 52.5 * p**2) + b2 * (18 + 42 * p + 42 * p**2)
           + gama * (16.25 + 40 * p + 35 * p**2) + delta * (15 + 37.5 * p + 30 * p**2)) * L**2
    k = rho * I_l / (210 * L * (1 + p) ** 2)
    return k * _plane(m11, m12, -m11, m13, m14, -m12, -m15, m11, -m13, m16)


def conical_stiffness(E, I_l, I, A_l, A, L, phi, a1, a2, b1, b2, gama, delta):
    p = phi
    k1 = 1260 + 630 * a2 + 504 * b2 + 441 * gama + 396 * delta
    s = p * (105 * a2 + 105 * b2 + 94.5 * gama + 84 * delta)
    k2 = (630 + 210 * a2 + 147 * b2 + 126 * gama + 114 * delta - s) * L
    k3 = (630 + 420 * a2 + 357 * b2 + 315 * gama + 282 * delta + s) * L
    k4 = (420 + 210 * p + 105 * p**2 + a2 * (105 + 52.5 * p**2) + b2 * (56 - 35 * p + 35 * p**2)
          + gama * (42 - 42 * p + 26.25 * p**2) + delta * (36 - 42 * p + 21 * p**2)) * L**2
    k5 = (210 - 210 * p - 105 * p**2 + a2 * (105 - 105 * p - 52.5 * p**2) + b2 * (91 - 70 * p - 35 * p**2)
          + gama * (84 - 52.5 * p - 26.25 * p**2) + delta * (78 - 42 * p - 21 * p**2)) * L**2
    k6 = (420 + 210 * p + 105 * p**2 + a2 * (315 + 210 * p + 52.5 * p**2) + b2 * (266 + 175 * p + 35 * p**2)
          + gama * (231 + 147 * p + 26.25 * p**2) + delta * (204 + 126 * p + 21 * p**2)) * L**2
    k7 = 12 + 6 * a1 + 4 * b1
    k8 = (6 + 3 * a1 + 2 * b1) * L
    k9 = (3 + 1.5 * a1 + b1) * L**2
    K1 = _plane(k1, k2, -k1, k3, k4, -k2, k5, k1, -k3, k6) * I_l / 105
    K2 = _plane(k7, k8, -k7, k8, k9, -k8, k9, k7, -k8, k9) * I * p * A_l / A
    return E / (L**3 * (1 + p) ** 2) * (K1 + K2)


def element_matrices(E, G, rho, d_out, d_in, L, kappa, shear: bool, rotary: bool):
    """`(M, G1, K)` of one element on its 8 dofs `(x1, y1, sx1, sy1, x2, y2, sx2, sy2)`,
    with the gyroscopic matrix per unit speed `G1` (so `G = Omega G1`).

    `d_out`, `d_in`: scalars (a cylinder) or `(left, right)` pairs (a linear taper):
    Genta's conical element as ROSS 2.3.0 writes it (`ShaftElement.M`, `.K`, `.G`),
    with `phi = 12 E I / (kappa G A L^2)` from the mid-length section and ROSS's
    dofs mapped as `(x, y, sx, sy) = (x, y, beta, -alpha)` (see the module
    docstring). Equal to the cylindrical element above when left == right."""
    d_out = jnp.broadcast_to(jnp.asarray(d_out, dtype=jnp.float64), (2,))
    d_in = jnp.broadcast_to(jnp.asarray(d_in, dtype=jnp.float64), (2,))
    A_l, I_l, A, I, (a1, a2, b1, b2, gama, delta) = conical_coefficients(d_out, d_in)
    phi = 12 * E * I / (kappa * G * A * L**2) if shear else 0.0 * L
    kp = conical_stiffness(E, I_l, I, A_l, A, L, phi, a1, a2, b1, b2, gama, delta)
    mp = conical_translational_mass(rho, A_l, L, phi, a1, b1)
    mr = conical_rotary_mass(rho, I_l, L, phi, a2, b2, gama, delta) if rotary else jnp.zeros((4, 4))
    gp = conical_rotary_mass(rho, 2 * I_l, L, phi, a2, b2, gama, delta)
    # plane matrices act on (w1, s1, w2, s2); node order (x, y, sx, sy) interleaves the planes: entry
    # (2 m + p, 2 n + q) is block (p, q)'s (m, n), p, q = 0 for x, 1 for y: a transpose, not four scatters
    # (the element matrices of a rotor layout compiled in 0.73 s instead of 0.98, 2026-12-02)

    def place(blk_xx, blk_yy, blk_xy=None, blk_yx=None):
        zero = jnp.zeros_like(blk_xx)
        blocks = jnp.stack([jnp.stack([blk_xx, zero if blk_xy is None else blk_xy]),
                            jnp.stack([zero if blk_yx is None else blk_yx, blk_yy])])
        return blocks.transpose(2, 0, 3, 1).reshape(8, 8)
    M = place(mp + mr, mp + mr)
    K = place(kp, kp)
    # The section's rotation field involves all four plane dofs, so the whole rotary
    # matrix (with the polar moment) couples the planes: +Mp from y into x, -Mp back.
    G1 = place(jnp.zeros((4, 4)), jnp.zeros((4, 4)), gp, -gp)
    return M, G1, K
