"""Identification of the balancing machine from measured 1x responses: fit support
stiffness and damping (and optionally the rotor's unbalances, mass, inertia) by
Levenberg-Marquardt (Gauss-Newton with damping) or optax, through the complex
frequency response, with autodiff Jacobians.

Parameters are fitted as logarithms (positivity by reparametrisation). The
residuals are the real and imaginary parts of `(model - measured) / sigma` over
all speeds and sensors. At the optimum, the covariance of the log-parameters is
`s^2 (J^T J)^-1` (`s^2` the residual variance), mapped to the parameters by the
delta method; 95 % intervals are `p exp(+-1.96 sd_log)`. Parameters the data
cannot see (relative standard deviation above 0.3, i.e. an interval wider than a
factor 3, or a Jacobian near rank deficiency) are flagged.
"""

import dataclasses

import equinox as eqx
import jax
import jax.numpy as jnp
import numpy as np

from ._machine import BalancingMachine

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

    def as_dict(self):
        out = {"estimates": self.estimates, "intervals_95": self.intervals, "std": self.std,
               "rms_residual": self.rms_residual, "iterations": self.iterations,
               "converged": self.converged, "warnings": self.warnings}
        if self.unbalances is not None:
            out["unbalances"] = [{"magnitude": float(abs(u)), "angle_deg": float(np.degrees(np.angle(u)))}
                                 for u in self.unbalances]
        return out


def _machine_with(base: BalancingMachine, names, logp):
    vals = {k: getattr(base, k) for k in ("m", "I", "l", "k1", "k2", "c1", "c2")}
    for i, k in enumerate(names):
        vals[k] = jnp.exp(logp[i])
    return BalancingMachine(**vals)


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
        model = jax.vmap(lambda w: machine.response(w, self.planes, D))(self.speeds)
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


@eqx.filter_jit
def _res_jac(r, theta):
    return r(theta), jax.jacfwd(r)(theta)


def levenberg_marquardt(r, theta0, max_iter=100, tol=1e-12, lam0=1e-3):
    """Minimise `|r(theta)|^2` with autodiff Jacobians; returns `(theta, J, info)`."""
    def res_jac(th):
        return _res_jac(r, th)

    theta = jnp.asarray(theta0, dtype=jnp.float64)
    res, J = res_jac(theta)
    cost = float(res @ res)
    lam = lam0
    history = [cost]
    converged = False
    it = 0
    for it in range(1, max_iter + 1):
        JtJ, g = J.T @ J, J.T @ res
        step = -jnp.linalg.solve(JtJ + lam * jnp.diag(jnp.diag(JtJ) + 1e-300), g)
        new = theta + step
        res_new, J_new = res_jac(new)
        cost_new = float(res_new @ res_new)
        if np.isfinite(cost_new) and cost_new < cost:
            small = float(jnp.max(jnp.abs(step))) < 1e-10 or (cost - cost_new) <= tol * cost
            theta, res, J, cost = new, res_new, J_new, cost_new
            lam = max(lam / 10, 1e-12)
            history.append(cost)
            if small:
                converged = True
                break
        else:
            lam *= 10
            if lam > 1e12:
                converged = float(jnp.max(jnp.abs(g))) < 1e-8 * max(cost, 1e-300) ** 0.5
                break
    return theta, J, {"iterations": it, "converged": converged, "history": history, "cost": cost}


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
             guess=None, max_iter=200) -> Identification:
    """Fit `fit` (names in `FITTABLE`) of `base` (a `BalancingMachine` holding the
    known values and the starting guesses) to measured phasors `X[speed, sensor]`,
    with the unbalances in `planes` known (`unbalances`) or fitted (None)."""
    bad = [k for k in fit if k not in FITTABLE]
    if bad or not fit:
        raise ValueError(f"--fit must name some of {', '.join(FITTABLE)}; got {', '.join(fit) or 'nothing'}")
    speeds = np.asarray(speeds, dtype=float)
    X = np.asarray(X, dtype=complex)
    if X.shape != (speeds.size, 2):
        raise ValueError(f"X must have shape (n_speeds, 2) = ({speeds.size}, 2), got {X.shape}")
    names = tuple(fit)
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
    s = 1.0 if sigma is None else float(sigma)
    r = residual_fn(base, names, speeds, planes, X, s, unbalances)
    theta, J, info = levenberg_marquardt(r, theta0, max_iter=max_iter)
    res = np.asarray(r(theta))
    J = np.asarray(J)
    dof = max(res.size - theta.size, 1)
    s2 = float(res @ res) / dof
    warnings = []
    sv = np.linalg.svd(J, compute_uv=False)
    if sv[-1] < 1e-10 * sv[0]:
        warnings.append(f"the Jacobian is rank deficient (condition {sv[0] / max(sv[-1], 1e-300):.1e}): "
                        "some parameters are not identifiable from these data")
    cov = s2 * np.linalg.pinv(J.T @ J)
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
    n = len(names)
    D = None if unbalances is not None else np.asarray(theta[n:n + len(planes)] + 1j * theta[n + len(planes):])
    return Identification(names=names, estimates=est, intervals=ints, std=std, unbalances=D,
                          rms_residual=float(np.sqrt(np.mean(res**2)) * s), iterations=info["iterations"],
                          converged=info["converged"], warnings=warnings, history=info["history"])


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
        return jax.vmap(lambda w: m.response(w, planes, D))(speeds)

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

    `Identification` keeps the intervals, not the covariance, so by default the
    covariance is rebuilt exactly as `identify` formed it: `s^2 (J^T J)^+` at the
    optimum, `J` the Jacobian of the residuals at the speeds of the fit and `s^2`
    their variance (from `result.rms_residual`; independent of `sigma`).

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
    - `covariance`: the covariance of `theta` (rebuilt when None).

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
