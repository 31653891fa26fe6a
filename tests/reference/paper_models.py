"""Independent numpy reference implementations of two published rotor models.

Pure numpy, float64. No jax, no rotorjax import: this module is the yardstick
the JAX implementation is tested against.

Model 000 -- Bykov & Kovachev (2019): Jeffcott rotor with an n-ball
auto-balancer whose race is an ellipse (seed 000, eqs. (6), (7), (10), (11)).
==========================================================================

Dimensionless, prescribed spin
    theta(t) = nu0 t + nu_dot t^2 / 2,  thd = nu0 + nu_dot t,  thdd = nu_dot.
(x, y): rotor centre C in the FIXED frame; (xi_j, eta_j): ball j in the
ROTOR frame (axes along the ellipse axes).  The constraint
xi^2/rho1^2 + eta^2/rho2^2 = 1 is eliminated by the parametrisation

    xi_j = rho1 cos psi_j,          eta_j = rho2 sin psi_j,
    xi_j'  = -rho1 sin psi_j psid_j,  eta_j'  = rho2 cos psi_j psid_j,
    xi_j'' = -rho1 (cos psi_j psid_j^2 + sin psi_j psidd_j),
    eta_j''=  rho2 (-sin psi_j psid_j^2 + cos psi_j psidd_j).

With  A_j = xi_j'' - thd^2 xi_j - 2 thd eta_j' - thdd eta_j,
      B_j = eta_j'' - thd^2 eta_j + 2 thd xi_j' + thdd xi_j
(the rotor-frame components of the ball's acceleration relative to C):

  (1+n chi)(x'' + delta_n x' + x) = eps (thd^2 cos(th+alpha) + thdd sin(th+alpha))
                                    - chi sum_j (A_j cos th - B_j sin th)
  (1+n chi)(y'' + delta_n y' + y) = eps (thd^2 sin(th+alpha) - thdd cos(th+alpha))
                                    - chi sum_j (A_j sin th + B_j cos th)
  rho1^2 eta_j (A_j + delta_b xi_j'  + x'' cos th + y'' sin th)
      = rho2^2 xi_j (B_j + delta_b eta_j' + y'' cos th - x'' sin th)

Sign fixes with respect to the printed paper (checked against a Lagrangian
derivation: disk mass 1, ball mass chi, stiffness 1+n chi, damping
delta_n (1+n chi) on x, y, Rayleigh 0.5 chi delta_b (xi_j'^2 + eta_j'^2)):
  * eq. (6), eta-equation of the balls: printed "+ m_b thd^2 eta_j" must be
    "- m_b thd^2 eta_j" (centrifugal term; the xi-equation is correct);
  * eq. (7), y-equation: printed "+ thd^2 eta_j" inside B_j must be "- thd^2 eta_j";
  * eq. (7), ball equation: the printed x, y (no dots) must be x'', y''.

State layout (length 2n+4):
    y = [x, y, psi_1..psi_n, xd, yd, psid_1..psid_n]
The n+2 equations are linear in (x'', y'', psidd_1..psidd_n); the system is
assembled explicitly and solved with numpy.linalg.solve.

Parameter dict p: chi, eps, alpha, rho1, rho2, delta_n, delta_b, nu0, nu_dot.

Stationary regimes (eq. (11), rotating frame, nu = nu0 constant,
(1+2chi) generalised to (1+n chi)); residual vector, length 2n+2:
  r0   = (1+n chi)((1-nu^2) a_xi - nu delta_n a_eta) - nu^2 (eps cos alpha + chi sum xi_j0)
  r1   = (1+n chi)(nu delta_n a_xi + (1-nu^2) a_eta) - nu^2 (eps sin alpha + chi sum eta_j0)
  r2_j = rho1^2 eta_j0 a_xi - rho2^2 xi_j0 a_eta - (rho2^2 - rho1^2) xi_j0 eta_j0
  r3_j = rho2^2 xi_j0^2 + rho1^2 eta_j0^2 - rho1^2 rho2^2
Fixed-frame centre: x + i y = (a_xi + i a_eta) exp(i nu t).

Model 001 -- Filimonikhina et al. (2017): planar rotor on anisotropic
visco-elastic supports with an N-weight passive auto-balancer (seed 001,
README reconstruction of eqs. (4), (9)).
==========================================================================

  xi''  + 2 mu_xi xi'   + xi            - sigma sum_j (phi_j'' sin phi_j + phi_j'^2 cos phi_j) - c n^2 cos(n t) = 0
  eta'' + 2 mu_eta eta' + n_eta^2 eta   + sigma sum_j (phi_j'' cos phi_j - phi_j'^2 sin phi_j) - c n^2 sin(n t) = 0
  phi_j'' + mu_w (phi_j' - n) + eps (-xi'' sin phi_j + eta'' cos phi_j) = 0

phi_j is the absolute weight angle; the state uses the angle RELATIVE to the
rotor, psi_j = phi_j - n t, psid_j = phid_j - n, psidd_j = phidd_j.

State layout (length 2N+4):
    y = [xi, eta, psi_1..psi_N, xid, etad, psid_1..psid_N]
Parameter dict p: n_eta, mu_xi, mu_eta, sigma, c, eps, mu_w, n.

Main motion for N = 2, c = 0.5, sigma = 0.5: psi = (2pi/3, 4pi/3), all rates 0,
xi = eta = 0 is an exact solution for every n.

Empirical auto-balancing criterion (eq. (18)): balancing where p(n) < 0,
  p(n) = (1-n^2)(n_eta^2-n^2)(1+n_eta^2-2n^2)
         + 4 n^2 [(1-n^2) mu_eta^2 + (n_eta^2-n^2) mu_xi^2].
"""

import numpy as np

__all__ = [
    "rhs_000_paper",
    "stationary_residual_000",
    "rhs_001_paper",
    "criterion_p_001",
]


# ---------------------------------------------------------------------------
# Model 000
# ---------------------------------------------------------------------------
def rhs_000_paper(t, y, p):
    """dy/dt for model 000 (paper eq. (7), sign-fixed, ball angle psi_j).

    y = [x, y, psi_1..psi_n, xd, yd, psid_1..psid_n], n = (len(y) - 4) // 2.
    """
    y = np.asarray(y, dtype=np.float64)
    n = (y.size - 4) // 2
    chi = float(p["chi"])
    eps = float(p["eps"])
    alpha = float(p["alpha"])
    rho1 = float(p["rho1"])
    rho2 = float(p["rho2"])
    dn = float(p["delta_n"])
    db = float(p["delta_b"])
    nu0 = float(p["nu0"])
    nu_dot = float(p["nu_dot"])

    th = nu0 * t + 0.5 * nu_dot * t * t
    thd = nu0 + nu_dot * t
    thdd = nu_dot
    cth, sth = np.cos(th), np.sin(th)

    x, yy = y[0], y[1]
    psi = y[2:2 + n]
    xd, yd = y[2 + n], y[3 + n]
    psid = y[4 + n:4 + 2 * n]

    cp, sp = np.cos(psi), np.sin(psi)
    xi = rho1 * cp
    eta = rho2 * sp
    xi_d = -rho1 * sp * psid
    eta_d = rho2 * cp * psid
    # xi'' = dxi * psidd + xi0dd, eta'' = deta * psidd + eta0dd
    dxi = -rho1 * sp
    deta = rho2 * cp
    xi0dd = -rho1 * cp * psid ** 2
    eta0dd = -rho2 * sp * psid ** 2

    # known parts of A_j, B_j (psidd = 0)
    A0 = xi0dd - thd ** 2 * xi - 2.0 * thd * eta_d - thdd * eta
    B0 = eta0dd - thd ** 2 * eta + 2.0 * thd * xi_d + thdd * xi

    m = 1.0 + n * chi
    M = np.zeros((n + 2, n + 2))
    b = np.zeros(n + 2)

    # x equation
    M[0, 0] = m
    M[0, 2:] = chi * (dxi * cth - deta * sth)
    b[0] = (eps * (thd ** 2 * np.cos(th + alpha) + thdd * np.sin(th + alpha))
            - m * (dn * xd + x)
            - chi * np.sum(A0 * cth - B0 * sth))
    # y equation
    M[1, 1] = m
    M[1, 2:] = chi * (dxi * sth + deta * cth)
    b[1] = (eps * (thd ** 2 * np.sin(th + alpha) - thdd * np.cos(th + alpha))
            - m * (dn * yd + yy)
            - chi * np.sum(A0 * sth + B0 * cth))
    # ball equations: rho1^2 eta (...) - rho2^2 xi (...) = 0
    r1s, r2s = rho1 ** 2, rho2 ** 2
    for j in range(n):
        row = 2 + j
        M[row, 0] = r1s * eta[j] * cth + r2s * xi[j] * sth
        M[row, 1] = r1s * eta[j] * sth - r2s * xi[j] * cth
        M[row, row] = r1s * eta[j] * dxi[j] - r2s * xi[j] * deta[j]
        b[row] = -(r1s * eta[j] * (A0[j] + db * xi_d[j])
                   - r2s * xi[j] * (B0[j] + db * eta_d[j]))

    acc = np.linalg.solve(M, b)
    return np.concatenate(([xd, yd], psid, acc))


def stationary_residual_000(a_xi, a_eta, xi0, eta0, p):
    """Residual of the stationary equations (11) of model 000, length 2n+2.

    Order: [r0, r1, r2_1..r2_n, r3_1..r3_n] (see module docstring);
    nu = p['nu0'], (1+2chi) written as (1+n chi).
    """
    xi0 = np.atleast_1d(np.asarray(xi0, dtype=np.float64))
    eta0 = np.atleast_1d(np.asarray(eta0, dtype=np.float64))
    n = xi0.size
    chi = float(p["chi"])
    eps = float(p["eps"])
    alpha = float(p["alpha"])
    rho1 = float(p["rho1"])
    rho2 = float(p["rho2"])
    dn = float(p["delta_n"])
    nu = float(p["nu0"])
    m = 1.0 + n * chi
    r0 = m * ((1.0 - nu ** 2) * a_xi - nu * dn * a_eta) \
        - nu ** 2 * (eps * np.cos(alpha) + chi * np.sum(xi0))
    r1 = m * (nu * dn * a_xi + (1.0 - nu ** 2) * a_eta) \
        - nu ** 2 * (eps * np.sin(alpha) + chi * np.sum(eta0))
    r2 = rho1 ** 2 * eta0 * a_xi - rho2 ** 2 * xi0 * a_eta \
        - (rho2 ** 2 - rho1 ** 2) * xi0 * eta0
    r3 = rho2 ** 2 * xi0 ** 2 + rho1 ** 2 * eta0 ** 2 - rho1 ** 2 * rho2 ** 2
    return np.concatenate(([r0, r1], r2, r3))


# ---------------------------------------------------------------------------
# Model 001
# ---------------------------------------------------------------------------
def rhs_001_paper(t, y, p):
    """dy/dt for model 001 (README dimensionless equations), N weights.

    y = [xi, eta, psi_1..psi_N, xid, etad, psid_1..psid_N], psi_j = phi_j - n t.
    """
    y = np.asarray(y, dtype=np.float64)
    N = (y.size - 4) // 2
    n_eta = float(p["n_eta"])
    mu_xi = float(p["mu_xi"])
    mu_eta = float(p["mu_eta"])
    sigma = float(p["sigma"])
    c = float(p["c"])
    eps = float(p["eps"])
    mu_w = float(p["mu_w"])
    n = float(p["n"])

    xi, eta = y[0], y[1]
    psi = y[2:2 + N]
    xid, etad = y[2 + N], y[3 + N]
    psid = y[4 + N:4 + 2 * N]

    phi = psi + n * t
    phid = psid + n
    sph, cph = np.sin(phi), np.cos(phi)

    M = np.eye(N + 2)
    b = np.zeros(N + 2)
    # xi'' - sigma sum sin(phi) phi'' = ...
    M[0, 2:] = -sigma * sph
    b[0] = (-2.0 * mu_xi * xid - xi + sigma * np.sum(phid ** 2 * cph)
            + c * n ** 2 * np.cos(n * t))
    # eta'' + sigma sum cos(phi) phi'' = ...
    M[1, 2:] = sigma * cph
    b[1] = (-2.0 * mu_eta * etad - n_eta ** 2 * eta + sigma * np.sum(phid ** 2 * sph)
            + c * n ** 2 * np.sin(n * t))
    # phi_j'' - eps sin(phi_j) xi'' + eps cos(phi_j) eta'' = -mu_w (phi_j' - n)
    M[2:, 0] = -eps * sph
    M[2:, 1] = eps * cph
    b[2:] = -mu_w * (phid - n)

    acc = np.linalg.solve(M, b)
    return np.concatenate(([xid, etad], psid, acc))


def criterion_p_001(n, n_eta, mu_xi, mu_eta):
    """Eq. (18): p(n); auto-balancing where p(n) < 0. Works elementwise on n."""
    n = np.asarray(n, dtype=np.float64)
    n2 = n * n
    ne2 = n_eta * n_eta
    return ((1.0 - n2) * (ne2 - n2) * (1.0 + ne2 - 2.0 * n2)
            + 4.0 * n2 * ((1.0 - n2) * mu_eta ** 2 + (ne2 - n2) * mu_xi ** 2))
