"""Model 003 with a ball auto-balancer (Kovachev, eqs. 24-30): its stationary
regimes in the rotating frame and their stability. The model is
`rotorjax.models.ModalBalancerRotor` (its docstring states the equations).

In the rotating frame (`w = v e^{-i theta0}`, `alpha_j = theta_j - theta0`) the
stationary regimes are (eqs. 25-30): balanced C (`w = 0`, balls cancel the
imbalance), pseudo-balanced PS (`a^T w = 0` with a bent shaft, only for `d = 0`),
and unbalanced NS1/NS2/NS3 by the balancing coefficient
`sigma = sum_j m_j r_j (-1)^{delta_j} / m0`.
"""

import itertools

import equinox as eqx
import jax
import jax.numpy as jnp
import numpy as np

from .._autodiff import value_and_jacfwd
from ._roots import find_roots
from ._rotating import rotating_field
from ..models._frequency import frequency_response
from ..models._modal import ModalShaft
from ..models._modal_balancer import ModalBalancerRotor
from ..models._validate import InputError, as_count, check_span, check_type, is_concrete
from ._modal003 import closed_form_sums


class BalancerRegime(eqx.Module):
    """A stationary regime of model 003 with balls: `kind` in {"C", "PS", "NS1",
    "NS2", "NS3"}, the rotating-frame state, residual, eigenvalues, margin."""

    kind: str = eqx.field(static=True)
    sigma: float = eqx.field(static=True)
    z: jax.Array
    residual: jax.Array
    eigenvalues: jax.Array
    margin: jax.Array
    disk_amplitude: jax.Array


@eqx.filter_jit
def _field_and_jacobian(rotor, z):
    """The rotating-frame field at `z` and its Jacobian, compiled once per layout
    (the field is composed from the components' energies: op by op it is slow)."""
    def field(zz):
        return rotating_field(rotor, 0.0, zz)

    return value_and_jacfwd(field)(z)


def _regime(rotor, kind, sigma, w, alpha):
    n = rotor.shaft.n_modes
    z = jnp.concatenate([jnp.real(w), jnp.imag(w), alpha, jnp.zeros(2 * n + rotor.n_balls)])
    f, jac = _field_and_jacobian(rotor, z)
    res = jnp.max(jnp.abs(f))
    eig = jnp.linalg.eigvals(jac)
    a, _, _ = rotor.shaft.mode_vectors()
    return BalancerRegime(kind=kind, sigma=sigma, z=z, residual=res, eigenvalues=eig,
                          margin=jnp.max(jnp.real(eig)), disk_amplitude=jnp.abs(a @ w))


def balanced_regime(rotor):
    """Regime C: shaft straight, two (or more, fanned) balls cancelling the imbalance."""
    from ..models import balancing_angles

    check_type("rotor", rotor, ModalBalancerRotor, "a ModalBalancerRotor")
    mr = rotor.ball_mass * rotor.ball_radius
    if rotor.n_balls < 1:
        raise InputError("rotor: a rotor without balls has no balanced regime")
    c = rotor.shaft.m0 / (rotor.n_balls * mr[0])
    if not isinstance(c, jax.core.Tracer):
        if not np.allclose(np.asarray(mr), float(mr[0])):
            raise InputError("rotor: the balanced regime is built for identical balls")
        if c > 1:
            raise InputError(f"rotor: the balls cannot cancel the imbalance: m0 = {float(rotor.shaft.m0)} > "
                             f"sum m_j r_j = {rotor.n_balls * float(mr[0])}")
    alpha = balancing_angles(rotor.n_balls, c)
    return _regime(rotor, "C", float("nan"), jnp.zeros(rotor.shaft.n_modes, dtype=complex), alpha)


def unbalanced_regimes(rotor):
    """All NS regimes (eqs. 28-30): for every assignment `delta_j` of the balls to the
    disk-centre ray (0) or its opposite (1), `sigma = sum m_j r_j (-1)^delta_j / m0`, and
    the roots `rho > 0` of eq. (30)."""
    check_type("rotor", rotor, ModalBalancerRotor, "a ModalBalancerRotor")
    s = rotor.shaft
    if not is_concrete(s.m0) or not float(s.m0) > 0:
        raise InputError(f"rotor.shaft.m0 (imbalance mass) must be > 0 for the unbalanced regimes "
                         f"(sigma = sum m_j r_j (-1)^delta_j / m0), got {s.m0}")
    omega = float(rotor.speed.speed(0.0))
    M, C, K = s.synchronous_matrices()
    a, _, _ = s.mode_vectors()
    q = complex(a @ frequency_response(M, C, K, a, omega))
    m0 = float(s.m0)
    mr = np.asarray(rotor.ball_mass * rotor.ball_radius)
    identical = np.allclose(mr, mr[0]) if mr.size else True
    deltas = (itertools.combinations_with_replacement((0, 1), rotor.n_balls) if identical
              else itertools.product((0, 1), repeat=rotor.n_balls))
    out = []
    for delta in deltas:
        sigma = float(np.sum(mr * (-1.0) ** np.array(delta)) / m0)
        disc = q.real**2 + (1 - sigma**2) * q.imag**2
        if disc < 0:
            continue
        for sign in (1.0, -1.0):
            rho = omega**2 * m0 * (sigma * q.real + sign * np.sqrt(disc))
            if rho <= 1e-14:
                continue
            e_beta = omega**2 * m0 * q / (rho - omega**2 * m0 * sigma * q)
            beta = float(np.angle(e_beta))
            w = frequency_response(M, C, K, (omega**2 * m0 * (1 + sigma * np.exp(1j * beta))) * a, omega)
            alpha = jnp.asarray(beta - np.pi * np.array(delta, dtype=float))
            kind = "NS3" if abs(sigma) < 1e-12 else ("NS1" if sigma > 0 else "NS2")
            out.append(_regime(rotor, kind, sigma, w, alpha))
    return out


def pseudo_balanced_speeds(shaft, lo, hi, n_scan=4000):
    """Speeds of the pseudo-balanced regime PS (eq. 27): the disk centre stays on the
    axis while the shaft is bent, where `S11 + S12^2 J w^2 / (1 - S22 J w^2) = 0`
    (closed-form sums), by the shared scan and bisection (`rotorjax.analysis.find_roots`,
    the sign changes through the sums' poles rejected). PS exists only without damping."""
    check_type("shaft", shaft, ModalShaft, "a rotorjax.flexible.ModalShaft")
    lo, hi = check_span("lo", lo, "hi", hi)
    n_scan = as_count("n_scan", n_scan, minimum=2)
    if float(shaft.d) != 0:
        raise InputError("shaft: the pseudo-balanced regime PS exists only without damping (d = 0), "
                         f"got d = {float(shaft.d)}")
    z0, J = float(shaft.z0), float(shaft.J)

    def f(w):
        s11, s12, s22 = (np.real(complex(x)) for x in closed_form_sums(w, z0))
        return s11 + s12**2 * J * w**2 / (1 - s22 * J * w**2)

    return [r.x for r in find_roots(f, lo, hi, n_scan, xtol=0.0, max_iter=60, pole_tol=1e-6)]


def balancer003_regimes(rotor):
    """Every stationary regime of model 003 with balls at its constant speed (Kovachev):
    the balanced regime C where the balls can cancel the imbalance, and the unbalanced
    ones (closed forms, eqs. 25-30). Returns `(regimes, notes)`, a note where C does not
    exist."""
    check_type("rotor", rotor, ModalBalancerRotor, "a ModalBalancerRotor")
    if rotor.n_balls < 1:
        raise InputError("--set n_balls=0: flexible-abb regimes need balls, e.g. --set n_balls=2")
    found, notes = [], []
    try:
        found.append(balanced_regime(rotor))
    except ValueError as e:
        notes.append(f"(no balanced regime: {e})")
    return found + unbalanced_regimes(rotor), notes


class ModalCriticalSpeeds(eqx.Module):
    """Model 003's critical speeds (units omega_1): `critical_speeds`, by `method`;
    `excited` the natural frequencies the disk's unbalance excites (to draw)."""

    critical_speeds: tuple = eqx.field(static=True)
    method: str = eqx.field(static=True)
    excited: np.ndarray


def balancer003_critical_speeds(shaft, lo, hi, exact=False) -> ModalCriticalSpeeds:
    """The critical speeds of model 003's shaft in `[lo, hi]`: the natural frequencies
    its disk's unbalance excites (the modal model), or with `exact` the roots of the
    closed-form equation (17) (`exact_critical_speeds`)."""
    from ._modal003 import exact_critical_speeds, modal003_natural_frequencies

    check_type("shaft", shaft, ModalShaft, "a rotorjax.models.ModalShaft")
    f, excited = (np.asarray(v) for v in modal003_natural_frequencies(shaft))
    if exact:
        speeds = exact_critical_speeds(float(shaft.m), float(shaft.z0), float(shaft.J), lo, hi)
        method = "closed form, eq. (17)"
    else:
        speeds = [float(v) for v, e in zip(f, excited) if e and lo <= v <= hi]
        method = f"modal model, {shaft.n_modes} modes"
    return ModalCriticalSpeeds(tuple(float(s) for s in speeds), method, f[excited.astype(bool)])
