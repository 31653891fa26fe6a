"""Identification of the balancing machine from measured 1x responses: fit support
stiffness and damping (and optionally the rotor's unbalances, mass, inertia) by
Levenberg-Marquardt (Gauss-Newton with damping) or optax, through the complex
frequency response, with autodiff Jacobians.

Parameters are fitted as logarithms (positivity by reparametrisation). The
residuals are the real and imaginary parts of `(model - measured) / sigma` over
all speeds and sensors. Two models:

- `steady` (default): the steady 1x response `X = K(w) D` at each speed;
- `runup` (`tracking=`, an `OrderTrack` from `order_track(..., full=True)`): the
  phasors a run-up actually produces. The machine's response to the unbalance
  forcing along the measured speed profile (the tacho's angle fit) is computed in
  the time domain, exactly for a linear machine (modal coordinates, exponential
  integrator: `q_{n+1} = e^{lambda h} q_n + int e^{lambda (h - s)} f(s) ds` with
  the forcing's envelope expanded to second order in the step), and order-tracked
  with the same block operator as the data. The transient through the resonances
  (a steady fit is biased by ~0.5 % in stiffness and damping at 19 rad/s^2) and the
  smoothing of a one-revolution block are then in the model, not in the residuals.

Uncertainty (`covariance=`): at the optimum, with `J` the Jacobian of the scaled
residuals `r`,

- `classical`: `s^2 (J^T J)^-1`, `s^2` the residual variance: right for
  independent residuals of one variance (a steady sweep);
- `sandwich`: `(J^T J)^-1 (sum_b g_b g_b^T) (J^T J)^-1` with `g_b = J_b^T r_b` the
  score of speed point `b` (its Re/Im residuals of all sensors together):
  unequal variances;
- `hac` (Newey-West): the sandwich with the lagged products of neighbouring
  speed points, Bartlett weights over `L = floor(4 (n / 100)^(2/9))` lags: serial
  correlation along a sweep;

each times `n / (n - p)`.

The phase reference (with `tracking`, `reference="joint"`): the angle comes from
a tacho sampled with the signals, so each pulse is timed to within half a sample
and the fitted angle is off by a smooth `dtheta(t)` (a few mrad at the ends of a
1 kHz run-up to 400 rad/s: 0.5 % of a phasor), the same for all sensors. Fitted
with a steady or run-up model as if exact, it biases the damping by up to 1 % in
an unknown direction. So the angle polynomial's error is fitted too, with the
tacho fit's covariance (`OrderTrack.angle_cov`) as its prior (whitened prior rows
in the residuals, counted in the bread and the meat): the data see most of it
(the model's phase pattern over the run is rigid), and the intervals include
what they cannot see.

`covariance="auto"` is `hac` with `tracking` and `classical` without (as before,
for steady sweeps). Parameters map to 95 % intervals by the delta method,
`p exp(+-1.96 sd_log)`. Parameters the data cannot see (relative standard
deviation above 0.3, i.e. an interval wider than a factor 3, or a Jacobian near
rank deficiency) are flagged, and so are residuals with structure (lag-1
autocorrelation or a runs test on their signs, per sensor and Re/Im): a model
that misses a systematic effect.
"""

import dataclasses
import functools

import equinox as eqx
import jax
import jax.numpy as jnp
import numpy as np

from ..analysis._balancing002 import balancing_response
from ..models._balancing_machine import BalancingMachine
from ..models._parameters import with_values
from ._lm import levenberg_marquardt

FITTABLE = ("k1", "k2", "c1", "c2", "m", "I")


@dataclasses.dataclass(frozen=True)
class Identification:
    """Estimates with 95 % intervals, the unbalances (if fitted), fit quality,
    identifiability warnings and the optimiser's history."""

    names: tuple
    estimates: dict
    intervals: dict
    std: dict
    unbalances: np.ndarray | None
    rms_residual: float
    iterations: int
    converged: bool
    warnings: list
    history: list
    #: covariance of theta (log-parameters, then Re and Im of fitted unbalances)
    covariance: np.ndarray | None = None
    covariance_method: str = "classical"
    #: "steady" or "runup" (the transient-aware model, `tracking=`)
    model: str = "steady"
    #: per channel ("x1 Re", ...): lag-1 autocorrelation, runs-test z, effective number of points
    residual_structure: dict | None = None
    #: run-up model with the joint phase reference: the fitted error of the tacho's angle at each point (rad)
    phase_correction: np.ndarray | None = None

    def as_dict(self):
        out = {"estimates": self.estimates, "intervals_95": self.intervals, "std": self.std,
               "rms_residual": self.rms_residual, "iterations": self.iterations,
               "converged": self.converged, "warnings": self.warnings, "model": self.model,
               "covariance_method": self.covariance_method}
        if self.residual_structure is not None:
            out["residual_structure"] = self.residual_structure
        if self.unbalances is not None:
            out["unbalances"] = [{"magnitude": float(abs(u)), "angle_deg": float(np.degrees(np.angle(u)))}
                                 for u in self.unbalances]
        return out


def _machine_with(base: BalancingMachine, names, logp):
    """`base` with the parameters `names` at `exp(logp)`, set through their paths (the
    one parameter mechanism: `rotorjax.models._parameters.with_values`)."""
    return with_values(base, [BalancingMachine.parameter_path(k) for k in names], jnp.exp(logp))


class Residual(eqx.Module):
    """`r(theta)`: theta = (log params, then Re/Im of the unbalances when they are
    fitted); stacked Re/Im residuals over speeds and sensors, scaled by `sigma`.
    A module (data as leaves), so one compilation serves every data set of a shape."""

    base: BalancingMachine
    names: tuple = eqx.field(static=True)
    speeds: jax.Array
    planes: jax.Array
    X: jax.Array
    sigma: jax.Array
    unbalances: jax.Array | None

    def __call__(self, theta):
        n, n_planes = len(self.names), self.planes.shape[0]
        machine = _machine_with(self.base, self.names, theta[:n])
        if self.unbalances is None:
            D = theta[n:n + n_planes] + 1j * theta[n + n_planes:]
        else:
            D = self.unbalances
        model = jax.vmap(lambda w: balancing_response(machine, w, self.planes, D))(self.speeds)
        d = (model - self.X) / self.sigma
        return jnp.concatenate([jnp.real(d).ravel(), jnp.imag(d).ravel()])


def residual_fn(base, names, speeds, planes, X, sigma=1.0, unbalances=None) -> Residual:
    return Residual(base, tuple(names), jnp.asarray(speeds, dtype=jnp.float64),
                    jnp.asarray(planes, dtype=jnp.float64), jnp.asarray(X, dtype=jnp.complex128),
                    jnp.asarray(sigma, dtype=jnp.float64),
                    None if unbalances is None else jnp.asarray(unbalances, dtype=jnp.complex128))


@eqx.filter_jit
def _stacked_influence(machine, speeds, planes):
    K = jax.vmap(lambda w: machine.influence_matrix(w, planes))(speeds)
    return K.reshape(-1, planes.shape[0])


def optax_fit(r, theta0, steps=2000, learning_rate=1e-2):
    """Minimise `|r|^2` with optax's Adam (for comparison with LM; slower)."""
    import optax

    opt = optax.adam(learning_rate)
    loss = eqx.filter_jit(jax.value_and_grad(lambda th: jnp.sum(r(th) ** 2)))
    theta = jnp.asarray(theta0, dtype=jnp.float64)
    state = opt.init(theta)

    @jax.jit
    def step(theta, state):
        v, g = loss(theta)
        upd, state = opt.update(g, state)
        return optax.apply_updates(theta, upd), state, v

    history = []
    for _ in range(steps):
        theta, state, v = step(theta, state)
        history.append(float(v))
    return theta, {"iterations": steps, "history": history, "cost": float(loss(theta)[0])}


def identify(base, speeds, X, planes, fit=("k1", "k2", "c1", "c2"), sigma=None, unbalances=None,
             guess=None, max_iter=200, *, tracking=None, reference="joint", covariance="auto",
             hac_lags=None) -> Identification:
    """Fit `fit` (names in `FITTABLE`) of `base` to measured phasors `X[speed, sensor]`.

    **Arguments:**

    - `base`: a `BalancingMachine` holding the known values and the starting guesses.
    - `speeds` (rad/s), `X` (complex, `(n_speeds, 2)`): the measured 1x phasors.
    - `planes`: the correction planes (m from support 1).
    - `fit`: the parameters to fit.
    - `sigma`: the phasors' noise (scalar, or one per phasor `(n_speeds, 2)` or per
      speed); default 1, or `tracking.sigma` with `tracking` (weighted least squares).
    - `unbalances`: the known unbalances (kg m, complex), or None to fit them too.
    - `guess`: starting values `{name: value}` (default: `base`'s).
    - `tracking`: the `OrderTrack` the phasors came from (`order_track(...,
      full=True)`): fit the run-up model (the order-tracked transient response)
      instead of the steady one; `speeds` must be (a selection of) its speeds.
    - `reference`: with `tracking`, `"joint"` also fits the error of the phase
      reference (the tacho's angle fit), with the fit's own covariance as its
      prior; `"none"` takes the tacho's angle as exact.
    - `covariance`: `"auto"`, `"classical"`, `"sandwich"` or `"hac"` (see the module).
    - `hac_lags`: the Newey-West lags (default `floor(4 (n / 100)^(2/9))`).

    **Returns:** an `Identification`.
    """
    bad = [k for k in fit if k not in FITTABLE]
    if bad or not fit:
        raise ValueError(f"--fit must name some of {', '.join(FITTABLE)}; got {', '.join(fit) or 'nothing'}")
    if reference not in ("joint", "none"):
        raise ValueError(f"reference must be 'joint' or 'none', got {reference!r}")
    if covariance not in COVARIANCES:
        raise ValueError(f"covariance must be one of {', '.join(COVARIANCES)}, got {covariance!r}")
    speeds = np.asarray(speeds, dtype=float)
    X = np.asarray(X, dtype=complex)
    if X.shape != (speeds.size, 2):
        raise ValueError(f"X must have shape (n_speeds, 2) = ({speeds.size}, 2), got {X.shape}")
    names = tuple(fit)
    sel = None if tracking is None else _match_blocks(tracking, speeds)
    if sigma is None:
        sig = tracking.sigma[sel] if tracking is not None else np.ones(X.shape)
    else:
        sig = np.asarray(sigma, dtype=float)
        sig = np.broadcast_to(sig[:, None] if sig.shape == (speeds.size,) else sig, X.shape).copy()
        if not np.all(np.isfinite(sig) & (sig > 0)):
            raise ValueError("sigma must be finite and > 0")
    scalar_sigma = sigma is not None and np.ndim(sigma) == 0
    start = guess or {}
    logp0 = [np.log(float(start.get(k, getattr(base, k)))) for k in names]
    if unbalances is None:
        # linear in the unbalances: start from least squares at the guessed machine
        K = np.asarray(_stacked_influence(_machine_with(base, names, jnp.asarray(logp0)),
                                          jnp.asarray(speeds), jnp.asarray(planes, dtype=jnp.float64)))
        D0 = np.linalg.lstsq(K, X.ravel(), rcond=None)[0]
        theta0 = np.concatenate([logp0, D0.real, D0.imag])
    else:
        theta0 = np.asarray(logp0)
    r = residual_fn(base, names, speeds, planes, X, float(sigma) if scalar_sigma else sig, unbalances)
    theta, J, info = levenberg_marquardt(r, theta0, max_iter=max_iter)
    model = "steady"
    if tracking is not None:
        # the run-up model, started from the steady fit (a few per cent off at most)
        r = _RunupResidual.build(base, names, planes, X, sig, unbalances, tracking, sel, reference == "joint")
        theta = np.concatenate([np.asarray(theta), np.zeros(r.n_reference)])
        theta, J, info2 = levenberg_marquardt(r, theta, max_iter=max_iter)
        info = {"iterations": info["iterations"] + info2["iterations"], "converged": info2["converged"],
                "history": info["history"] + info2["history"], "cost": info2["cost"]}
        model = "runup"
    res = np.asarray(r(theta))
    J = np.asarray(J)
    J_prior, phase = None, None
    if tracking is not None:
        J_prior = J[r.prior_rows] if r.n_reference else None
        phase = r.phase_error(theta)
        res, J = res[r.rows], J[r.rows]
    theta = np.asarray(theta)
    warnings = []
    # identifiability of the whole problem: the prior rows settle what the data cannot (a constant
    # phase error and the unbalances' common angle are one direction for the data alone)
    sv = np.linalg.svd(J if J_prior is None else np.concatenate([J, J_prior]), compute_uv=False)
    if sv[-1] < 1e-10 * sv[0]:
        warnings.append(f"the Jacobian is rank deficient (condition {sv[0] / max(sv[-1], 1e-300):.1e}): "
                        "some parameters are not identifiable from these data")
    method = ("hac" if tracking is not None else "classical") if covariance == "auto" else covariance
    cov = theta_covariance(J, res, method, n_points=speeds.size, lags=hac_lags, J_prior=J_prior)
    n_main = theta.size - (0 if J_prior is None else J_prior.shape[0])
    cov, theta = cov[:n_main, :n_main], theta[:n_main]
    sd_log = np.sqrt(np.maximum(np.diag(cov), 0.0))
    est, ints, std = {}, {}, {}
    for i, k in enumerate(names):
        p = float(np.exp(theta[i]))
        est[k] = p
        std[k] = p * float(sd_log[i])
        ints[k] = [p * float(np.exp(-1.96 * sd_log[i])), p * float(np.exp(1.96 * sd_log[i]))]
        if sd_log[i] > 0.3:
            warnings.append(f"{k} is poorly determined by the data (relative sd {sd_log[i]:.2f}: the 95 % "
                            f"interval spans a factor {np.exp(3.92 * sd_log[i]):.1f})")
    structure = residual_structure(res.reshape(2, speeds.size, 2))
    warnings += _structure_warnings(structure, method, model)
    if method == "classical" and speeds.size > 2 * theta.size:
        # unequal residual variances make s^2 (J^T J)^-1 too narrow where the noisy points weigh most
        robust = theta_covariance(J, res, "sandwich", n_points=speeds.size)[:n_main, :n_main]
        ratio = np.sqrt(np.maximum(np.diag(robust), 0.0) / np.maximum(np.diag(cov), 1e-300))[:len(names)]
        if np.max(ratio) > SANDWICH_RATIO_LIMIT:
            k = names[int(np.argmax(ratio))]
            warnings.append(f"the residuals' variance is not uniform: the sandwich standard deviation of {k} is "
                            f"{np.max(ratio):.1f} times the classical one, so the classical intervals are too "
                            "narrow: give sigma per point or use covariance='sandwich'")
    n = len(names)
    D = None if unbalances is not None else np.asarray(theta[n:n + len(planes)] + 1j * theta[n + len(planes):])
    sig_stack = np.concatenate([sig.ravel(), sig.ravel()])
    return Identification(names=names, estimates=est, intervals=ints, std=std, unbalances=D,
                          rms_residual=float(np.sqrt(np.mean((res * sig_stack) ** 2))), iterations=info["iterations"],
                          converged=info["converged"], warnings=warnings, history=info["history"],
                          covariance=cov, covariance_method=method, model=model, residual_structure=structure,
                          phase_correction=phase)


COVARIANCES = ("auto", "classical", "sandwich", "hac")


def newey_west_lags(n):
    """The Newey-West (1994) rule of thumb, `floor(4 (n / 100)^(2/9))`."""
    return int(np.floor(4 * (n / 100.0) ** (2.0 / 9.0)))


def theta_covariance(J, res, method="classical", n_points=None, lags=None, J_prior=None):
    """The covariance of the fitted `theta` from the Jacobian `J` and the residuals
    `res` of a least-squares fit (`(n_res, p)` and `(n_res,)`, stacked as `identify`
    stacks them: all real parts, then all imaginary parts, each `(n_points,
    n_sensors)` row-major). `method`: `"classical"` (`s^2 (J^T J)^+`), `"sandwich"`
    (per speed point) or `"hac"` (Newey-West over neighbouring speed points, `lags`
    default `newey_west_lags`); see the module docstring.

    `J_prior`: the Jacobian of prior rows (whitened: unit variance, independent of
    the data), which enter the bread `(J^T J + J_p^T J_p)^+` and, as their own
    variance `J_p^T J_p`, the meat; their parameters are not counted in the degrees
    of freedom (each comes with its prior row)."""
    J, res = np.asarray(J, dtype=float), np.asarray(res, dtype=float)
    n_res, p = J.shape
    Jp = np.zeros((0, p)) if J_prior is None else np.asarray(J_prior, dtype=float)
    dof = max(n_res - (p - Jp.shape[0]), 1)
    bread = np.linalg.pinv(J.T @ J + Jp.T @ Jp)
    if method == "classical":
        return float(res @ res) / dof * bread
    if method not in ("sandwich", "hac"):
        raise ValueError(f"covariance method must be classical, sandwich or hac, got {method!r}")
    n = int(n_points if n_points is not None else n_res // 4)
    # the score of each speed point: its Re and Im residuals of all sensors together
    g = (J * res[:, None]).reshape(2, n, -1, p).sum(axis=(0, 2))         # (n, p)
    meat = g.T @ g
    if method == "hac":
        L = newey_west_lags(n) if lags is None else int(lags)
        for lag in range(1, min(L, n - 1) + 1):
            G = g[lag:].T @ g[:-lag]
            meat += (1 - lag / (L + 1)) * (G + G.T)
    return bread @ (n_res / dof * meat + Jp.T @ Jp) @ bread


def residual_structure(res):
    """Per channel (sensor and Re/Im) of residuals `res[part, point, sensor]` in
    speed order: the lag-1 autocorrelation `rho1`, the runs test on the signs
    (`runs_z`: (runs - expected) / sd; strongly negative: long runs of one sign),
    and the effective number of independent points `n_eff = n (1 - rho1) / (1 + rho1)`
    (an AR(1) reading)."""
    res = np.asarray(res, dtype=float)
    out = {}
    for part, pname in enumerate(("Re", "Im")):
        for m in range(res.shape[2]):
            e = res[part, :, m] - res[part, :, m].mean()
            n = e.size
            rho1 = float(e[1:] @ e[:-1] / max(e @ e, 1e-300)) if n > 2 else 0.0
            sgn = np.sign(e[e != 0])
            n_pos, n_neg = int(np.sum(sgn > 0)), int(np.sum(sgn < 0))
            nn = n_pos + n_neg
            if n_pos and n_neg and nn > 2:
                runs = 1 + int(np.sum(sgn[1:] != sgn[:-1]))
                mu = 2.0 * n_pos * n_neg / nn + 1
                var = 2.0 * n_pos * n_neg * (2.0 * n_pos * n_neg - nn) / (nn**2 * (nn - 1))
                z = float((runs - mu) / np.sqrt(max(var, 1e-300)))
            else:
                z = 0.0
            r1 = min(max(rho1, -0.999), 0.999)
            out[f"x{m + 1} {pname}"] = {"n": n, "rho1": rho1, "runs_z": z,
                                        "n_eff": float(n * (1 - r1) / (1 + r1))}
    return out


#: residuals show structure when a channel's lag-1 autocorrelation exceeds
#: `max(RHO1_LIMIT, 3 / sqrt(n))` or its runs test has |z| > RUNS_Z_LIMIT (p < 0.001)
RHO1_LIMIT = 0.2
RUNS_Z_LIMIT = 3.29
#: with the classical covariance, warn when a sandwich standard deviation exceeds the classical one this much
SANDWICH_RATIO_LIMIT = 1.5


def _structure_warnings(structure, method, model):
    bad = {k: v for k, v in structure.items()
           if v["rho1"] > max(RHO1_LIMIT, 3 / np.sqrt(max(v["n"], 1))) or abs(v["runs_z"]) > RUNS_Z_LIMIT}
    if not bad:
        return []
    desc = "; ".join(f"{k}: lag-1 autocorrelation {v['rho1']:.2f}, runs test z {v['runs_z']:.1f}, "
                     f"about {v['n_eff']:.0f} of {v['n']} points independent" for k, v in bad.items())
    if method == "classical":
        advice = ("the classical intervals assume independent residuals and are too narrow: use "
                  "covariance='hac'" + ("" if model == "runup" else ", and for a run-up the run-up model "
                                        "(tracking=order_track(..., full=True))"))
    else:
        advice = (f"the {method} intervals allow for correlated residuals, but structure means the model misses "
                  "a systematic effect that also biases the estimates: coverage cannot be trusted")
    return [f"the residuals show structure ({desc}): {advice}"]


def _match_blocks(tracking, speeds):
    """The indices of `speeds` among `tracking.speeds` (exact: a selection of them)."""
    where = {float(w): i for i, w in enumerate(tracking.speeds)}
    idx = [where.get(float(w), -1) for w in speeds]
    if min(idx, default=-1) < 0 or len(set(idx)) != len(idx):
        raise ValueError("speeds must be a selection of tracking.speeds (the phasors the order tracking "
                         "returned), each at most once")
    return np.asarray(idx, dtype=int)


# --- the run-up model -----------------------------------------------------------

def _phi(z):
    """`phi_1, phi_2, phi_3` of the exponential integrators, `phi_k(z) = sum_j z^j / (j + k)!`,
    for complex `z` (Taylor near 0; double `where` so derivatives stay finite)."""
    small = jnp.abs(z) < 1e-2
    zs = jnp.where(small, 1.0, z)
    p1 = jnp.expm1(zs) / zs
    p2 = (p1 - 1.0) / zs
    p3 = (p2 - 0.5) / zs
    t1 = 1 + z / 2 + z**2 / 6 + z**3 / 24 + z**4 / 120
    t2 = 0.5 + z / 6 + z**2 / 24 + z**3 / 120 + z**4 / 720
    t3 = 1 / 6 + z / 24 + z**2 / 120 + z**3 / 720 + z**4 / 5040
    return jnp.where(small, t1, p1), jnp.where(small, t2, p2), jnp.where(small, t3, p3)


class RunupData(eqx.Module):
    """What the run-up model needs of an `OrderTrack`, padded to bucketed sizes so
    that data sets of one sampling share one compilation: the step `h`; at the
    start of each step the fitted angle and speed and the Taylor coefficients
    `g0, g1, g2` of the forcing envelope `(w^2 - i w') e^{i (theta - theta_n - w_n tau)}`;
    the start (`theta0`, `w0`); each sample's block basis (cos, sin, 1) and segment;
    the blocks' inverse normal matrices."""

    h: jax.Array
    theta_n: jax.Array
    w_n: jax.Array
    g0: jax.Array
    g1: jax.Array
    g2: jax.Array
    theta0: jax.Array
    w0: jax.Array
    basis: jax.Array
    segment: jax.Array
    normal_inv: jax.Array
    n_blocks: int = eqx.field(static=True)
    fft_size: int = eqx.field(static=True)

    @classmethod
    def from_tracking(cls, tracking):
        t = np.asarray(tracking.time, dtype=float)
        dt = np.diff(t)
        h = float(np.median(dt))
        if t.size < 3 or np.max(np.abs(dt - h)) > 1e-4 * h:
            raise ValueError("the run-up model needs uniformly sampled signals (constant time step)")
        d = [tracking.angle_derivatives(t[:-1], k) for k in range(5)]
        th, w, w1, w2, w3 = d
        s0 = w**2 - 1j * w1                                  # the forcing envelope per unit unbalance
        s1 = 2 * w * w1 - 1j * w2
        s2 = 2 * w1**2 + 2 * w * w2 - 1j * w3
        g2 = 0.5 * s2 + 0.5j * w1 * s0                       # with the chirp phase e^{i w' tau^2 / 2}
        nb = tracking.speeds.size
        nb_pad = _bucket(nb + 1)
        seg = np.where(tracking.block >= 0, tracking.block, nb_pad - 1)
        theta_all = tracking.angle_derivatives(t, 0)
        basis = np.stack([np.cos(theta_all), np.sin(theta_all), np.ones_like(t)], axis=1)
        Ginv = np.zeros((nb_pad, 3, 3))
        Ginv[:nb] = tracking.normal_inv
        return cls(jnp.asarray(h), jnp.asarray(th), jnp.asarray(w), jnp.asarray(s0), jnp.asarray(s1),
                   jnp.asarray(g2), jnp.asarray(float(theta_all[0])), jnp.asarray(float(
                       tracking.angle_derivatives(t[:1], 1)[0])), jnp.asarray(basis), jnp.asarray(seg),
                   jnp.asarray(Ginv), nb_pad, _fft_size(2 * t.size))


def _fft_size(n):
    """The smallest `2^a 3^b 5^c >= n` (a fast FFT length)."""
    best = 1 << int(np.ceil(np.log2(max(n, 1))))
    p5 = 1
    while p5 < best:
        p35 = p5
        while p35 < best:
            m = p35
            while m < n:
                m *= 2
            best = min(best, m)
            p35 *= 3
        p5 *= 5
    return best


def _bucket(n, q=64):
    return int(-(-n // q) * q)


def _mode_signals(lam, h, theta_n, w_n, g0, g1, g2, fft_size):
    """Per mode `j` (eigenvalue `lam_j`) and sample `n`: `u_j(n)`, the modal response
    to the unit forcing envelope `g e^{i theta}` from rest, and `e^{lam_j h n}`, the
    free decay of a unit initial state; both `(n_samples, 4)`.

    Over a step, `q_{n+1} = e^{lam h} q_n + e^{i (theta_n + w_n h)} h (g0 phi_1 +
    g1 h phi_2 + 2 g2 h^2 phi_3)((lam - i w_n) h)`, exact for the envelope's Taylor
    polynomial. The recurrence is a causal convolution with the decaying kernel
    `e^{lam h j}`, done by FFT (a sequential scan over 20 000 samples is far slower
    on a CPU, and slower still to differentiate)."""
    z = (lam[None, :] - 1j * w_n[:, None]) * h
    p1, p2, p3 = _phi(z)
    c = jnp.exp(1j * (theta_n + w_n * h))[:, None] * (g0[:, None] * h * p1 + g1[:, None] * h**2 * p2
                                                      + 2 * g2[:, None] * h**3 * p3)
    n_steps = c.shape[0]
    powers = jnp.exp(lam[None, :] * h * jnp.arange(n_steps + 1, dtype=jnp.float64)[:, None])   # (n + 1, 4)
    conv = jnp.fft.ifft(jnp.fft.fft(powers[:-1], fft_size, axis=0) * jnp.fft.fft(c, fft_size, axis=0),
                        axis=0)[:n_steps]
    return jnp.concatenate([jnp.zeros((1, lam.size), dtype=c.dtype), conv]), powers


def _blocks(y, basis, segment, normal_inv, n_blocks):
    """The order tracking of real signals `y` `(n_samples, k)`: the phasor `a - i b`
    of each block's least-squares fit `y ~ a cos + b sin + c`, `(n_blocks, k)`."""
    S = jax.ops.segment_sum(basis[:, :, None] * y[:, None, :], segment, num_segments=n_blocks)
    coef = jnp.einsum("bij,bjm->bim", normal_inv, S)
    return coef[:, 0, :] - 1j * coef[:, 1, :]


@functools.partial(jax.custom_jvp, nondiff_argnums=(10, 11))
def _mode_blocks(lam, h, theta_n, w_n, g0, g1, g2, basis, segment, normal_inv, n_blocks, fft_size):
    """The order-tracked real and imaginary parts of `_mode_signals`: `(Re u, Im u,
    Re e, Im e)` as block phasors, `(n_blocks, 4)` each. Each mode's signals depend
    on its own eigenvalue only, and holomorphically, so the JVP needs one complex
    derivative per mode whatever the number of parameters (the custom rule: 2
    evaluations instead of 1 + 2 x 4 for a Jacobian in 4 parameters and 2 unbalances)."""
    u, e = _mode_signals(lam, h, theta_n, w_n, g0, g1, g2, fft_size)
    parts = jnp.concatenate([u.real, u.imag, e.real, e.imag], axis=1)
    return tuple(jnp.split(_blocks(parts, basis, segment, normal_inv, n_blocks), 4, axis=1))


@_mode_blocks.defjvp
def _mode_blocks_jvp(n_blocks, fft_size, primals, tangents):
    lam, h, theta_n, w_n, g0, g1, g2, basis, segment, normal_inv = primals
    dlam = tangents[0]
    (u, e), (du, de) = jax.jvp(lambda l: _mode_signals(l, h, theta_n, w_n, g0, g1, g2, fft_size), (lam,),
                               (jnp.ones_like(lam),))
    parts = jnp.concatenate([u.real, u.imag, e.real, e.imag, du.real, du.imag, de.real, de.imag], axis=1)
    ur, ui, er, ei, dur, dui, der, dei = jnp.split(_blocks(parts, basis, segment, normal_inv, n_blocks), 8, axis=1)
    a, b = jnp.real(dlam)[None, :], jnp.imag(dlam)[None, :]
    # d Re(u) = Re(u' dlam) = a Re u' - b Im u';  d Im(u) = a Im u' + b Re u'
    return (ur, ui, er, ei), (a * dur - b * dui, a * dui + b * dur, a * der - b * dei, a * dei + b * der)


def runup_phasors(machine, planes, unbalances, data: RunupData):
    """The 1x phasors that order tracking extracts from the machine's run-up: the
    time response to the unbalances along the fitted speed profile (from the steady
    response at the first sample), projected block by block as the data were;
    `(n_blocks_padded, 2)` complex (padding rows are 0).

    In modal coordinates (`M = V diag(lam) V^-1`, the first-order form of eq. 9) the
    state is `q_j(n) = beta_j u_j(n) + q0_j e^{lam_j h n}`, `beta = V^-1 (0, A^-1 L D)`
    the modal forcing of the unbalances, and the support displacements are
    `x = Re(V_top q)`; order tracking is real-linear, so the phasors are
    `sum_j Re(w_j) P[Re u_j] - Im(w_j) P[Im u_j]` (and the same for the free part)."""
    A, B, C = machine.matrices()
    Ai = jnp.linalg.inv(A)
    M = jnp.block([[jnp.zeros((2, 2)), jnp.eye(2)], [-Ai @ C, -Ai @ B]])
    lam, V = jax.lax.linalg.eig(M, compute_left_eigenvectors=False, enable_eigvec_derivs=True)
    Vi = jnp.linalg.inv(V)
    planes = jnp.asarray(planes, dtype=jnp.float64)
    lever = jnp.stack([machine.l - planes, planes]) / machine.l                 # (2, n_planes)
    D = jnp.asarray(unbalances, dtype=jnp.complex128)
    beta = Vi[:, 2:] @ (Ai.astype(jnp.complex128) @ (lever.astype(jnp.complex128) @ D))   # (4,)
    X0 = balancing_response(machine, data.w0, planes, D)
    q0 = Vi @ (jnp.concatenate([X0, 1j * data.w0 * X0]) * jnp.exp(1j * data.theta0))
    ur, ui, er, ei = _mode_blocks(lam, data.h, data.theta_n, data.w_n, data.g0, data.g1, data.g2, data.basis,
                                  data.segment, data.normal_inv, data.n_blocks, data.fft_size)
    wu, we = V[:2] * beta[None, :], V[:2] * q0[None, :]                        # (sensor, mode)
    return ur @ wu.real.T - ui @ wu.imag.T + er @ we.real.T - ei @ we.imag.T


class _RunupResidual(eqx.Module):
    """`r(theta)` of the run-up model: as `Residual`, the model phasors from
    `runup_phasors`, padded to bucketed sizes (`rows`: the residuals that are data).

    With `reference`, theta ends with `eta`, the phase reference's error in whitened
    form: the tacho's angle fit is off by `dtheta(t) = V(t) L eta` (`L L^T` the
    covariance of its coefficients, `V` their sensitivities), which turns each
    measured phasor by `e^{-i dtheta}`; so the model is turned likewise and `eta`
    gets the prior rows `eta` (its prior `N(0, I)`: the tacho fit's own scatter)."""

    base: BalancingMachine
    names: tuple = eqx.field(static=True)
    planes: jax.Array
    X: jax.Array
    sigma: jax.Array
    mask: jax.Array
    select: jax.Array
    unbalances: jax.Array | None
    data: RunupData
    phase_basis: jax.Array | None
    n_points: int = eqx.field(static=True)
    n_padded: int = eqx.field(static=True)

    @property
    def n_reference(self):
        return 0 if self.phase_basis is None else self.phase_basis.shape[1]

    @property
    def rows(self):
        """The residuals that are data (the rest is padding and the prior's rows)."""
        n, n_pad = self.n_points, self.n_padded
        return np.concatenate([np.arange(2 * n), 2 * n_pad + np.arange(2 * n)])

    @property
    def prior_rows(self):
        return 4 * self.n_padded + np.arange(self.n_reference)

    @classmethod
    def build(cls, base, names, planes, X, sigma, unbalances, tracking, sel, reference=True):
        n = sel.size
        n_pad = _bucket(n)
        Xp = np.zeros((n_pad, 2), dtype=complex)
        Xp[:n] = X
        sp = np.ones((n_pad, 2))
        sp[:n] = sigma
        mask = np.zeros((n_pad, 2))
        mask[:n] = 1.0
        selp = np.zeros(n_pad, dtype=int)
        selp[:n] = sel
        basis = None
        if reference:
            Vth, _ = tracking.angle_sensitivity(tracking.block_time[sel])
            w, U = np.linalg.eigh(np.asarray(tracking.angle_cov))
            L = U * np.sqrt(np.maximum(w, 0.0))[None, :]          # L L^T = angle_cov
            basis = np.zeros((n_pad, L.shape[1]))
            basis[:n] = Vth @ L
            basis = jnp.asarray(basis)
        return cls(base, tuple(names), jnp.asarray(planes, dtype=jnp.float64), jnp.asarray(Xp), jnp.asarray(sp),
                   jnp.asarray(mask), jnp.asarray(selp),
                   None if unbalances is None else jnp.asarray(unbalances, dtype=jnp.complex128),
                   RunupData.from_tracking(tracking), basis, n, n_pad)

    def phase_error(self, theta):
        """The fitted error of the phase reference at each block (rad), `(n_points,)`."""
        if self.phase_basis is None:
            return np.zeros(self.n_points)
        eta = np.asarray(theta)[np.asarray(theta).size - self.n_reference:]
        return np.asarray(self.phase_basis)[:self.n_points] @ eta

    def __call__(self, theta):
        n, n_planes = len(self.names), self.planes.shape[0]
        machine = _machine_with(self.base, self.names, theta[:n])
        D = theta[n:n + n_planes] + 1j * theta[n + n_planes:n + 2 * n_planes] if self.unbalances is None \
            else self.unbalances
        model = runup_phasors(machine, self.planes, D, self.data)[self.select]
        if self.phase_basis is not None:
            eta = theta[theta.size - self.n_reference:]
            model = model * jnp.exp(-1j * (self.phase_basis @ eta))[:, None]
        d = self.mask * (model - self.X) / self.sigma
        out = [jnp.real(d).ravel(), jnp.imag(d).ravel()]
        if self.phase_basis is not None:
            out.append(theta[theta.size - self.n_reference:])
        return jnp.concatenate(out)


def _fitted_theta(result, unbalances):
    """`theta` of a fit (log-parameters, then Re and Im of fitted unbalances) and
    the unbalances to use when they were known."""
    fitted = result.unbalances is not None
    if fitted and unbalances is not None:
        raise ValueError("the unbalances were fitted (result.unbalances): pass unbalances only when they "
                         "were known in the fit")
    if not fitted and unbalances is None:
        raise ValueError("the unbalances were known in the fit: pass them as unbalances")
    logp = np.log([result.estimates[k] for k in result.names])
    if fitted:
        D = np.asarray(result.unbalances, dtype=complex)
        return jnp.asarray(np.concatenate([logp, D.real, D.imag])), None
    return jnp.asarray(logp), jnp.asarray(unbalances, dtype=jnp.complex128)


def _response_of_theta(machine, names, planes, known):
    """`X(theta, speeds)`: the model's complex support amplitudes, shape (n, 2)."""
    n, n_planes = len(names), planes.shape[0]

    def response(theta, speeds):
        m = _machine_with(machine, names, theta[:n])
        D = theta[n:n + n_planes] + 1j * theta[n + n_planes:] if known is None else known
        return jax.vmap(lambda w: balancing_response(m, w, planes, D))(speeds)

    return response


@eqx.filter_jit
def _response_jacobian(machine, names, planes, known, theta, speeds):
    """The model response at `theta` and its Jacobian d X / d theta, (n, 2) and (n, 2, p)."""
    response = _response_of_theta(machine, names, planes, known)
    return response(theta, speeds), jax.jacfwd(lambda th: response(th, speeds))(theta)


def fit_covariance(result, machine, fit_speeds, planes, unbalances=None):
    """The covariance of `theta` (the fit's log-parameters, then Re and Im of the
    fitted unbalances) as `identify` forms it: `s^2 (J^T J)^+` with `J` the
    Jacobian of the model's Re/Im responses at `fit_speeds` and `s^2` the residual
    variance rebuilt from `result.rms_residual` (the scale `sigma` cancels)."""
    theta, known = _fitted_theta(result, unbalances)
    planes = jnp.asarray(planes, dtype=jnp.float64)
    ws = jnp.atleast_1d(jnp.asarray(fit_speeds, dtype=jnp.float64))
    Jc = np.asarray(_response_jacobian(machine, tuple(result.names), planes, known, theta, ws)[1])
    J = np.concatenate([Jc.real.reshape(-1, theta.size), Jc.imag.reshape(-1, theta.size)])
    n_res = J.shape[0]
    s2 = n_res * result.rms_residual**2 / max(n_res - theta.size, 1)
    return s2 * np.linalg.pinv(J.T @ J)


def response_band(result: Identification, machine: BalancingMachine, speeds, planes, unbalances=None,
                  level=0.95, *, fit_speeds=None, covariance=None):
    """The fitted model's 1x response and a confidence band on its amplitude.

    The band comes from the delta method: with `theta` the fitted parameters (the
    logarithms of `result.names`, then Re and Im of the unbalances when they were
    fitted) and `Sigma` their covariance, `sd|X| = sqrt(g^T Sigma g)` with
    `g = d|X|/d theta` (from `jax.jacfwd` of `X`), and the band is `|X| +- z sd|X|`
    (`z` the normal quantile of `level`; the lower edge is clipped at 0). It is the
    band of the fitted response, from the parameters' uncertainty only; a new
    measurement scatters around it by the sensor noise besides.

    By default the band uses the covariance `identify` stored (`result.covariance`,
    its `covariance_method`); for a result without one, or when `fit_speeds` is
    given, the classical covariance is rebuilt: `s^2 (J^T J)^+` at the optimum, `J`
    the Jacobian of the residuals at the speeds of the fit and `s^2` their variance
    (from `result.rms_residual`; for a scalar `sigma`).

    **Arguments:**

    - `result`: what `identify` returned.
    - `machine`: the `BalancingMachine` passed to `identify` as `base` (the known
      values; the fitted ones are replaced by `result.estimates`).
    - `speeds`: the speeds (rad/s) at which to evaluate the band.
    - `planes`: the correction planes of the fit (m from support 1).
    - `unbalances`: the known unbalances (kg m, complex) when they were not fitted;
      leave out when `result.unbalances` holds fitted ones.
    - `level`: the band's coverage (0.95: a 95 % band).
    - `fit_speeds`: the speeds of the measurements used in the fit (default
      `speeds`); needed only to rebuild the covariance.
    - `covariance`: the covariance of `theta` (default `result.covariance`).

    **Returns:** `(X_fit, amp_lo, amp_hi)`: the complex support amplitudes of the
    fitted model, shape `(len(speeds), 2)`, and the lower and upper edges of the
    band on `|X_fit|` (same shape, m).
    """
    from jax.scipy.special import ndtri

    if not 0 < level < 1:
        raise ValueError(f"level must lie in (0, 1), got {level}")
    theta, known = _fitted_theta(result, unbalances)
    planes = jnp.asarray(planes, dtype=jnp.float64)
    speeds = jnp.atleast_1d(jnp.asarray(speeds, dtype=jnp.float64))
    if covariance is None and fit_speeds is None and result.covariance is not None:
        covariance = result.covariance
    if covariance is None:
        covariance = fit_covariance(result, machine, speeds if fit_speeds is None else fit_speeds, planes,
                                    unbalances)
    covariance = np.asarray(covariance, dtype=float)
    if covariance.shape != (theta.size, theta.size):
        raise ValueError(f"covariance must have shape ({theta.size}, {theta.size}) (log-parameters, then Re "
                         f"and Im of fitted unbalances), got {covariance.shape}")
    X, dX = (np.asarray(v) for v in _response_jacobian(machine, tuple(result.names), planes, known, theta,
                                                           speeds))
    amp = np.abs(X)
    # d|X| = Re(conj(X) dX) / |X|: the chain rule through |.| (0 where X = 0)
    g = np.real(np.conj(X)[..., None] * dX) / np.where(amp > 0, amp, 1.0)[..., None]   # (n, 2, p)
    sd = np.sqrt(np.maximum(np.einsum("scp,pq,scq->sc", g, covariance, g), 0.0))
    z = float(ndtri(0.5 + level / 2))
    return X, np.maximum(amp - z * sd, 0.0), amp + z * sd


@dataclasses.dataclass(frozen=True, eq=False)
class RunupIdentification:
    """`identify_runup`'s outcome: the fit (`result`, an `Identification`), the data
    it used (`path`, `sensors`, `speeds` and phasors `X` of the revolutions kept),
    and the fitted model's response with its 95 % band (`fitted`, `band_lo`,
    `band_hi`, at `speeds`)."""

    result: Identification
    path: str
    sensors: tuple
    speeds: np.ndarray
    X: np.ndarray
    fitted: np.ndarray
    band_lo: np.ndarray
    band_hi: np.ndarray

    @property
    def n_points(self) -> int:
        return int(len(self.speeds))


def identify_runup(scene, path, fit=("k1", "k2", "c1", "c2"), *, block=1, min_speed=0.0, fit_unbalance=False,
                   stage=None) -> RunupIdentification:
    """Identify a balancing machine from a measured run-up file: read the signals,
    order-track the 1x phasors (`block` revolutions per estimate), keep the
    revolutions at or above `min_speed` (rad/s), fit `fit` with the run-up model
    starting from the `BalancingScene` `scene` (its machine, planes and, unless
    `fit_unbalance`, its unbalances), and compute the fitted response's 95 % band.
    `stage(text)`, if given, is called as each stage starts (progress)."""
    from ..models._balancing_machine import BalancingScene
    from ..models._validate import InputError
    from ._signals import order_track, read_signals

    if not isinstance(scene, BalancingScene):
        raise InputError(f"identify_runup needs a BalancingScene (a machine with planes and unbalances), got "
                         f"{type(scene).__name__}")
    stage = stage or (lambda text: None)
    stage("reading the signals")
    cols = read_signals(path)
    if len(cols["sensors"]) < 2:
        raise InputError(f"{path}: the balancing machine needs two sensor columns (x1, x2), found "
                         f"{', '.join(cols['sensors'])}")
    x = np.stack([cols[s] for s in cols["sensors"][:2]], axis=1)
    stage("order tracking (1x phasors per revolution)")
    track = order_track(cols["time"], x, tacho=cols["tacho"], revolutions_per_block=block, full=True)
    speeds, X = track.speeds, track.X
    keep = speeds >= min_speed
    if keep.sum() < max(4, len(fit)):
        raise InputError(f"{path}: {int(keep.sum())} revolutions above --min-speed {min_speed:g} rad/s; "
                         f"need at least {max(4, len(fit))}")
    base, planes = scene.machine, scene.planes
    unb = None if fit_unbalance else scene.unbalances
    stage("Levenberg-Marquardt fit (autodiff Jacobians)")
    res = identify(base, speeds[keep], X[keep], planes, fit=fit, unbalances=unb, tracking=track)
    stage("the model's 95% band, plot")
    Xf, lo, hi = response_band(res, base, speeds[keep], planes, unbalances=unb)
    return RunupIdentification(result=res, path=path, sensors=tuple(cols["sensors"][:2]), speeds=speeds[keep],
                               X=X[keep], fitted=Xf, band_lo=lo, band_hi=hi)
