"""Validation: the oil-whirl onset of a rigid symmetric rotor on two identical short
(Ocvirk, pi-film) journal bearings against the classical rigid-rotor threshold.

The reference is derived here, independently of `rotorjax` (numpy/scipy only):

- **Film force.** Short-bearing Reynolds equation, `d/dz(h^3 dp/dz) = 6 mu (omega
  dh/dtheta + 2 dh/dt)`, `p = 0` at `z = +-L/2`, so `p = 3 mu (z^2 - L^2/4) (omega
  h_theta + 2 h_t) / h^3`; the film `h = c - x cos(theta) - y sin(theta)` (`theta` from
  `+x` counter-clockwise, the journal spinning counter-clockwise at `omega`), the
  positive pressure kept (pi film, half-Sommerfeld). Integrated over `z` and onto the
  journal (`F = -R int int p (cos, sin) dtheta dz`), in units `X = x / c`, `X' = dX /
  d(omega t)`: `F = (mu R L^3 omega / (2 c^2)) f`, with

      f(X, Y, X', Y') = int_arc G / H^3 (cos(theta), sin(theta)) dtheta,
      H = 1 - X cos - Y sin,  G = X sin - Y cos - 2 (X' cos + Y' sin),

  `arc` the half circle where `G < 0` (`G` is a single sinusoid in `theta`). The
  integrand vanishes at both ends of the arc, so the derivatives of `f` are the
  integrals of the integrand's derivatives (typed in below, no finite differences);
  all by `scipy.integrate.quad` at ~1e-12.
- **Coefficients.** The equilibrium at eccentricity `eps0` is where `f` points along
  `+y` (the load `W` along `-y`); `K_ij = -(df_i/dX_j) / |f|`, `C_ij = -(df_i/dX'_j) /
  |f|`, i.e. `k c / W` and `c c omega / W` in the frame of `rotorjax.models` (x
  horizontal, y up). The load and attitude are checked against Ocvirk's closed forms
  (typed in here: `W = mu U L^3 / (4 c^2) eps sqrt(pi^2 (1 - eps^2) + 16 eps^2) / (1 -
  eps^2)^2`, `tan(phi) = pi sqrt(1 - eps^2) / (4 eps)`; Ocvirk, NACA TN 2808, 1952;
  e.g. Hamrock, Schmid & Jacobson, *Fundamentals of Fluid Film Lubrication*, ch. 11).
- **Threshold** (Lund, J. Appl. Mech. 32, 1965; e.g. Childs, *Turbomachinery
  Rotordynamics*, 1993, ch. 3): at the onset `lambda = i nu` solves `det(k - m nu^2 +
  i nu c) = 0` for the mass `m` per bearing; the imaginary part gives `m nu^2 = k_eq`,
  the real part `nu^2 = ((kxx - k_eq)(kyy - k_eq) - kxy kyx) / (cxx cyy - cxy cyx)`,
  so in the dimensionless coefficients `nu / omega = gamma`, `m omega^2 c / W = K_eq /
  gamma^2` (`K_eq`, `gamma^2` as in `_lund`). With `W = m g` the threshold speed is
  `omega_th = sqrt(K_eq / gamma^2 g / c)`, independent of the mass.

**The rotor.** A two-element finite-element shaft with a central disk (small diametral
inertia: the conical mode is far from unstable), the journals at both end nodes,
gravity, no linear bearings. Its cylindrical mode is exactly the two-degree-of-freedom
journal of the reference (`m` = half the rotor's mass) but for the shaft's bending
flexibility, which softens the film's support: with steel (`E = 211 GPa`) the onset
comes out ~1e-3 low (measured -1.0e-3, -0.9e-3, -0.4e-3 at eps0 = 0.1, 0.5, 0.7), an
error that scales as `1/E`; the shaft here is 100 x stiffer (`E = 2.11e13 Pa`,
`plausibility=False`), which leaves ~1e-5 (measured, see `ONSET_RTOL`).

One rotor layout for the whole file: the cases differ in viscosity (and one in
clearance) only. Each `hopf_points` call still compiles its own programs (~6 s of CPU;
the scene is a closure constant), and each `hopf_speed_gradient` call ~16 s (eager
reverse mode through the equilibrium and the eigenvalues), so the cases are few: the
file takes ~65 s of CPU.
"""

import equinox as eqx
import jax.numpy as jnp
import numpy as np
import pytest
from scipy.integrate import quad
from scipy.optimize import brentq

from rotorjax.analysis import hopf_points, hopf_speed_gradient
from rotorjax.models import FlexibleRotor, Gravity, JournalBearing, RotorScene

# ----------------------------------------------------------------------------- the reference
_QUAD = dict(epsabs=1e-13, epsrel=1e-12, limit=200)


def _film(X, Y, Xd=0.0, Yd=0.0):
    """`f` (2,), `df/d(X, Y)` (2, 2) and `df/d(X', Y')` (2, 2) of the dimensionless
    pi-film force (module docstring)."""
    # G = A sin(t) + B cos(t) = rho sin(t + d): negative on (pi - d, 2 pi - d)
    A, B = X - 2.0 * Yd, -(Y + 2.0 * Xd)
    d = np.arctan2(B, A)
    lo, hi = np.pi - d, 2.0 * np.pi - d

    def H(t):
        return 1.0 - X * np.cos(t) - Y * np.sin(t)

    def G(t):
        return X * np.sin(t) - Y * np.cos(t) - 2.0 * (Xd * np.cos(t) + Yd * np.sin(t))

    p = lambda t: G(t) / H(t) ** 3                                              # noqa: E731
    dp = (lambda t: np.sin(t) / H(t) ** 3 + 3.0 * G(t) * np.cos(t) / H(t) ** 4,   # d/dX
          lambda t: -np.cos(t) / H(t) ** 3 + 3.0 * G(t) * np.sin(t) / H(t) ** 4,  # d/dY
          lambda t: -2.0 * np.cos(t) / H(t) ** 3,                                  # d/dX'
          lambda t: -2.0 * np.sin(t) / H(t) ** 3)                                  # d/dY'
    trig = (np.cos, np.sin)

    def q(fn):
        return quad(fn, lo, hi, **_QUAD)[0]

    f = np.array([q(lambda t, u=u: p(t) * u(t)) for u in trig])
    J = np.array([[q(lambda t, u=u, v=v: v(t) * u(t)) for v in dp] for u in trig])
    return f, J[:, :2], J[:, 2:]


def _load(eps):
    """`|f|` at eccentricity `eps` (the load in units of `mu R L^3 omega / (2 c^2)`)."""
    return float(np.hypot(*_film(eps, 0.0)[0]))


def _coefficients(eps):
    """`(|f|, (X, Y), K, C)` at the equilibrium of eccentricity `eps` under a load along `-y`."""
    f0 = _film(eps, 0.0)[0]
    psi = 0.5 * np.pi - np.arctan2(f0[1], f0[0])   # turn the journal so the film force points along +y
    X, Y = eps * np.cos(psi), eps * np.sin(psi)
    f, J, Jd = _film(X, Y)
    mag = float(np.hypot(*f))
    return mag, (X, Y), -J / mag, -Jd / mag


def _lund(K, C):
    """`(K_eq, gamma^2)`: the rigid rotor's threshold `m omega^2 c / W = K_eq / gamma^2`
    and whirl ratio `gamma` (module docstring)."""
    keq = (K[0, 0] * C[1, 1] + K[1, 1] * C[0, 0] - K[0, 1] * C[1, 0] - K[1, 0] * C[0, 1]) / (C[0, 0] + C[1, 1])
    g2 = ((K[0, 0] - keq) * (K[1, 1] - keq) - K[0, 1] * K[1, 0]) / (C[0, 0] * C[1, 1] - C[0, 1] * C[1, 0])
    return keq, g2


def _gamma2(eps):
    return _lund(*_coefficients(eps)[2:])[1]


# ------------------------------------------------------------------------------- the rotor
G_ACC = 9.81
LENGTH, DIAMETER, CLEARANCE = 0.05, 0.2, 2e-4     # each bearing: L/D = 0.25
E_STIFF = 100 * 211e9                             # module docstring: residual flexibility ~1e-5
ROTOR = FlexibleRotor([0.25, 0.25], 0.2, E=E_STIFF, G=100 * 81.2e9, theory="euler-bernoulli",
                      disks=((1, 100.0, 0.1, 0.2),), plausibility=False)
#: half the rotor's mass: the x-x block of the mass matrix summed (the rigid translation)
MASS = 0.5 * float(jnp.sum(ROTOR.matrices(0.0)[0][0::4, 0::4]))
W = MASS * G_ACC                                  # load per bearing (N)

#: three cases (each `hopf_points` call costs ~6 s of CPU); eps0 = 0.3 measured as well
#: (onset -1.05e-5, whirl ratio 3.3e-7) and left out for time
EPS_CASES = (0.05, 0.5, 0.7)
#: measured onset / omega_th - 1 = -1.04e-5, -0.89e-5, -0.44e-5 (eps0 = 0.05, 0.5, 0.7: the
#: shaft's flexibility, always low), the whirl ratio / gamma - 1 = 3e-8, -7.2e-7, -4.2e-6
ONSET_RTOL, RATIO_RTOL = 3e-5, 1e-5


def _scene(viscosity, clearance=CLEARANCE):
    return RotorScene(ROTOR, 0.0, (Gravity(G_ACC), JournalBearing(0, viscosity, LENGTH, DIAMETER, clearance),
                                   JournalBearing(2, viscosity, LENGTH, DIAMETER, clearance)))


def _design(eps0):
    """The reference threshold speed, whirl ratio and the viscosity that puts the
    equilibrium at `eps0` at that speed."""
    mag, _, K, C = _coefficients(eps0)
    keq, g2 = _lund(K, C)
    omega = float(np.sqrt(keq / g2 * G_ACC / CLEARANCE))
    # W = mu R L^3 omega / (2 c^2) |f|
    viscosity = 2.0 * CLEARANCE ** 2 * W / (0.5 * DIAMETER * LENGTH ** 3 * omega * mag)
    return omega, float(np.sqrt(g2)), viscosity


@pytest.fixture(scope="module")
def onsets():
    out = {}
    for eps0 in EPS_CASES:
        omega, gamma, viscosity = _design(eps0)
        points = hopf_points(_scene(viscosity), 0.7 * omega, 1.3 * omega, n_scan=6)
        out[eps0] = (omega, gamma, viscosity, points)
    return out


# --------------------------------------------------------------------------------- the tests
@pytest.mark.parametrize("eps", [0.05, 0.3, 0.7])
def test_reference_film_matches_ocvirk(eps):
    """The quadrature reference against Ocvirk's closed-form load and attitude angle,
    and the short bearing's symmetric damping (`C_xy = C_yx`)."""
    mag, (X, Y), _, C = _coefficients(eps)
    s = 1.0 - eps ** 2
    # W / (mu R L^3 omega / (2 c^2)) = (1/2) eps sqrt(pi^2 s + 16 eps^2) / s^2  (U = omega R)
    assert mag == pytest.approx(0.5 * eps * np.sqrt(np.pi ** 2 * s + 16 * eps ** 2) / s ** 2, rel=1e-11)
    # the journal sits below the centre, displaced towards +x (the direction of rotation) by phi
    assert X > 0 and Y < 0
    assert np.arctan2(X, -Y) == pytest.approx(np.arctan(np.pi * np.sqrt(s) / (4 * eps)), rel=1e-11)
    assert C[0, 1] == pytest.approx(C[1, 0], rel=1e-10)


@pytest.mark.parametrize("eps0", EPS_CASES)
def test_onset_speed_and_whirl_ratio(onsets, eps0):
    """One Hopf point in `[0.7, 1.3] omega_th`, at Lund's threshold speed, whirling at
    `gamma` times the speed."""
    omega, gamma, _, points = onsets[eps0]
    assert len(points) == 1, points
    (p,) = points
    assert p.speed == pytest.approx(omega, rel=ONSET_RTOL)
    assert p.frequency / p.speed == pytest.approx(gamma, rel=RATIO_RTOL)


def test_light_load_half_frequency_whirl(onsets):
    """At light load the whirl is at (just over) half the running speed: measured
    0.500754 at eps0 = 0.05 (the reference gamma = 0.500754; 1/2 as eps0 -> 0)."""
    _, gamma, _, (p,) = onsets[0.05]
    assert p.frequency / p.speed == pytest.approx(0.5, rel=5e-3)
    assert gamma == pytest.approx(0.5, rel=5e-3)


#: the published eccentricity above which the short-bearing rigid rotor is stable at every
#: speed (this file's reference gives 0.75603: gamma^2 -> 0 with K_eq = 1.52 > 0)
EPS_STABLE_PUBLISHED = 0.756


def test_stable_above_critical_eccentricity():
    """`gamma^2` (and with it the threshold `K_eq / gamma^2`) changes sign at eps ~ 0.756:
    above it the linearised short bearing is stable whatever the rotor's mass, hence at
    every speed. The value is the one commonly quoted for the short (Ocvirk, pi film)
    bearing with a rigid rotor; (the stable region above eps ~ 0.75 goes back to
    Holmes, J. Mech. Eng. Sci. 2, 1960, and appears in rotordynamics texts such as
    Childs 1993 — quoted from memory, the page not checked here). Then a rotor whose
    journals run above it over a tenfold speed range: no Hopf point, and every scanned
    margin negative."""
    eps_c = brentq(_gamma2, 0.7, 0.8, xtol=1e-12)
    assert eps_c == pytest.approx(EPS_STABLE_PUBLISHED, abs=1e-3)
    k_eq, g2 = _lund(*_coefficients(eps_c - 1e-3)[2:])
    assert k_eq > 0 and g2 > 0 and k_eq / g2 > 100   # the threshold grows without bound below eps_c
    assert _gamma2(eps_c + 1e-3) < 0
    # heavy load: eps = 0.8 at the top speed, larger below (the Sommerfeld number ~ viscosity x speed)
    hi = 1500.0
    viscosity = 2.0 * CLEARANCE ** 2 * W / (0.5 * DIAMETER * LENGTH ** 3 * hi * _load(0.8))
    points, (speeds, margins) = hopf_points(_scene(viscosity), 0.1 * hi, hi, n_scan=8, return_scan=True)
    assert points == []
    assert np.all(np.isfinite(margins)) and np.all(margins < 0), margins


# ------------------------------------------------------------------------------- gradients
@eqx.filter_jit
def _margin(scene, speed):
    """The largest real part of the linearisation's eigenvalues (compiled once for
    every scene of this file's layout)."""
    return jnp.max(jnp.real(jnp.linalg.eigvals(scene.linear_matrices(speed).state_matrix())))


#: measured IFT / FD - 1: 1.3e-6 (viscosity), 1.4e-7 (clearance)
GRADIENT_RTOL = 1e-5


def _onset(scene, guess):
    """The margin's root near `guess` (brentq on the compiled margin)."""
    f = lambda s: float(_margin(scene, jnp.float64(s)))   # noqa: E731
    return brentq(f, 0.97 * guess, 1.03 * guess, xtol=1e-12, rtol=1e-15)


@pytest.mark.parametrize("param", ["viscosity", "clearance"])
def test_onset_gradient_implicit_vs_finite_differences(onsets, param):
    """`d(onset speed)/d(viscosity)` and `d/d(clearance)` by the implicit function
    theorem (`hopf_speed_gradient`) against finite differences of the onset speed: the
    five-point stencil, relative step 5e-3 (its truncation error ~1e-7 here). The
    onsets carry ~1e-9 relative noise (the margin's, ~2e-8 1/s, from the eigenvalues
    of the stiff shaft's state matrix), so a small step does worse: the central
    difference with step 1e-4 misses by ~2e-4, with 1e-3 by ~1e-5 (measured).
    Measured agreement: see `GRADIENT_RTOL`."""
    omega, _, viscosity, (p,) = onsets[0.5]
    value = {"viscosity": viscosity, "clearance": CLEARANCE}[param]

    def scene_at(v):
        return _scene(v, CLEARANCE) if param == "viscosity" else _scene(viscosity, v)

    ift = hopf_speed_gradient(lambda s, v: scene_at(v).linear_matrices(s).state_matrix(), p.speed, value)
    h = 5e-3 * value
    on = {k: _onset(scene_at(value + k * h), p.speed) for k in (-2, -1, 1, 2)}
    fd = (on[-2] - 8.0 * on[-1] + 8.0 * on[1] - on[2]) / (12.0 * h)
    assert ift == pytest.approx(fd, rel=GRADIENT_RTOL)
