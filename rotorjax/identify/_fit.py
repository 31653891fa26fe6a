"""Model 002's balancing machine identified from its measured 1x responses: the
supports' stiffness and damping (and optionally the rotor's unbalances, mass,
inertia), through the complex frequency response, by the one engine (`_engine`:
Levenberg-Marquardt with autodiff Jacobians, the covariance, intervals and
warnings of every scene).

Parameters are fitted as logarithms (positivity by reparametrisation). The
residuals are the real and imaginary parts of `(model - measured) / sigma` over
all speeds and sensors. Two models:

- `steady` (default): the steady 1x response `X = K(w) D` at each speed;
- `runup` (the data came from order tracking: an `OrderTrack` from
  `order_track(..., full=True)`, or a run-up signal file): the phasors a run-up
  actually produces (`_runup_model`), started from the steady fit, with the phase
  reference's error fitted jointly (`reference="joint"`).

`covariance="auto"` is `hac` with the run-up model and `classical` without
(`_covariance`); residual structure is reported per sensor and Re/Im.
"""

import dataclasses

import equinox as eqx
import jax
import jax.numpy as jnp
import numpy as np

from .._autodiff import value_and_jacfwd
from .._errors import InputError
from ..analysis._balancing002 import balancing_response
from ..models._balancing_machine import BalancingMachine, BalancingScene
from ._covariance import COVARIANCES, residual_structure, structure_warnings
from ._engine import Identification, Optimum, Parameter, Search, report, search
from ._runup_model import _match_blocks, _RunupResidual, machine_with
from ._signals import OrderTrack

FITTABLE = ("k1", "k2", "c1", "c2", "m", "I")


@dataclasses.dataclass(frozen=True, eq=False)
class SweepData:
    """The machine's measured 1x phasors: `speeds` (rad/s), `X` (complex, `(n, 2)`),
    the sensors' names, the file they came from, and the `OrderTrack` they came from
    (the run-up model's input; None for steady phasors)."""

    speeds: np.ndarray
    X: np.ndarray
    sensors: tuple = ("x1", "x2")
    path: str | None = None
    tracking: OrderTrack | None = None

    @property
    def n(self) -> int:
        return int(len(self.speeds))


def sweep_data(data, option="data") -> SweepData:
    """`data` as `SweepData`: itself, an `OrderTrack`, or `(speeds, X)`."""
    if isinstance(data, SweepData):
        return data
    if isinstance(data, OrderTrack):
        return SweepData(np.asarray(data.speeds, dtype=float), np.asarray(data.X, dtype=complex), tracking=data)
    if isinstance(data, tuple) and len(data) == 2:
        speeds, X = np.asarray(data[0], dtype=float), np.asarray(data[1], dtype=complex)
        if speeds.ndim != 1 or X.shape != (speeds.size, 2):
            raise InputError(f"{option}: (speeds, X) with speeds 1-D and X of shape (n_speeds, 2) = ({speeds.size}, "
                             f"2); got speeds {speeds.shape}, X {X.shape}")
        return SweepData(speeds, X)
    raise InputError(f"{option}: the balancing machine is identified from (speeds, X), an OrderTrack or a run-up "
                     f"signal file; got {type(data).__name__}")


def runup_data(path, block=1, min_speed=0.0, n_params=4, stage=None) -> SweepData:
    """The 1x phasors of a run-up signal file: read, order-tracked (`block`
    revolutions per estimate), the revolutions at or above `min_speed` (rad/s) kept."""
    from ._signals import order_track, read_signals

    stage = stage or (lambda text: None)
    stage("reading the signals")
    cols = read_signals(path)
    if len(cols["sensors"]) < 2:
        raise InputError(f"{path}: the balancing machine needs two sensor columns (x1, x2), found "
                         f"{', '.join(cols['sensors'])}")
    x = np.stack([cols[s] for s in cols["sensors"][:2]], axis=1)
    stage("order tracking (1x phasors per revolution)")
    track = order_track(cols["time"], x, tacho=cols["tacho"], revolutions_per_block=block, full=True)
    keep = track.speeds >= min_speed
    if keep.sum() < max(4, n_params):
        raise InputError(f"{path}: {int(keep.sum())} revolutions above --min-speed {min_speed:g} rad/s; "
                         f"need at least {max(4, n_params)}")
    return SweepData(track.speeds[keep], track.X[keep], tuple(cols["sensors"][:2]), str(path), track)


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
        machine = machine_with(self.base, self.names, theta[:n])
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


@eqx.filter_jit
def _residuals(r, theta):
    return r(theta)


def identify_machine(scene: BalancingScene, data, fit=("k1", "k2", "c1", "c2"), *, fit_unbalance=False,
                     sigma=None, max_iter=200, reference="joint", covariance="auto", hac_lags=None,
                     n_starts=1, spread=10.0, seed=0, band=False) -> Identification:
    """Fit `fit` (names in `FITTABLE`) of the `BalancingScene` `scene` (its machine's
    values are the start) to measured phasors `data` (see `identify`).

    - `fit_unbalance`: fit the unbalances in the scene's planes too (started at the
      linear least-squares values at the start); else they are the scene's.
    - `sigma`: the phasors' noise (scalar, or one per phasor `(n_speeds, 2)` or per
      speed); default 1, or the order tracking's (weighted least squares).
    - `reference`: with the run-up model, `"joint"` also fits the error of the phase
      reference (the tacho's angle fit), with the fit's own covariance as its prior;
      `"none"` takes the tacho's angle as exact.
    - `covariance`: `"auto"`, `"classical"`, `"sandwich"` or `"hac"`; `hac_lags` the
      Newey-West lags.
    - `n_starts`, `spread`, `seed`: the global stage of the steady fit (1: a local fit).
    - `band`: also the fitted steady response at the data's speeds and its 95 % band
      (`response_band`).
    """
    bad = [k for k in fit if k not in FITTABLE]
    if bad or not fit:
        raise InputError(f"params must name some of {', '.join(FITTABLE)}; got {', '.join(fit) or 'nothing'}")
    if reference not in ("joint", "none"):
        raise InputError(f"reference must be 'joint' or 'none', got {reference!r}")
    if covariance not in COVARIANCES:
        raise InputError(f"covariance must be one of {', '.join(COVARIANCES)}, got {covariance!r}")
    if not int(n_starts) >= 1:
        raise InputError(f"n_starts must be at least 1, got {n_starts}")
    data = sweep_data(data)
    speeds, X, tracking = data.speeds, data.X, data.tracking
    base, planes = scene.machine, np.asarray(scene.planes, dtype=float)
    unbalances = None if fit_unbalance else np.asarray(scene.unbalances, dtype=complex)
    names = tuple(fit)
    sel = None if tracking is None else _match_blocks(tracking, speeds)
    if sigma is None:
        sig = tracking.sigma[sel] if tracking is not None else np.ones(X.shape)
    else:
        sig = np.asarray(sigma, dtype=float)
        sig = np.broadcast_to(sig[:, None] if sig.shape == (speeds.size,) else sig, X.shape).copy()
        if not np.all(np.isfinite(sig) & (sig > 0)):
            raise InputError("sigma must be finite and > 0")
    scalar_sigma = sigma is not None and np.ndim(sigma) == 0
    params = tuple(Parameter(k, BalancingMachine.parameter_path(k), True, 1.0, float(getattr(base, k)))
                   for k in names)
    logp0 = [np.log(q.start) for q in params]
    if unbalances is None:
        # linear in the unbalances: start from least squares at the guessed machine
        K = np.asarray(_stacked_influence(machine_with(base, names, jnp.asarray(logp0)),
                                          jnp.asarray(speeds), jnp.asarray(planes, dtype=jnp.float64)))
        D0 = np.linalg.lstsq(K, X.ravel(), rcond=None)[0]
        theta0 = np.concatenate([logp0, D0.real, D0.imag])
    else:
        theta0 = np.asarray(logp0)
    r = residual_fn(base, names, speeds, planes, X, float(sigma) if scalar_sigma else sig, unbalances)
    theta, info, lanes = search(r, theta0, params, Search(int(n_starts), spread, seed, max_iter))
    if lanes is not None:
        # the best start again as one lane: its Jacobian and convergence test
        used = info["n_used"]
        theta, info, _ = search(r, theta, params, Search(max_iter=max_iter))
        info["n_used"] = used
    model = "steady"
    if tracking is not None:
        # the run-up model, started from the steady fit (a few per cent off at most)
        r = _RunupResidual.build(base, names, planes, X, sig, unbalances, tracking, sel, reference == "joint")
        theta, info2, lanes = search(r, np.concatenate([theta, np.zeros(r.n_reference)]), params,
                                     Search(max_iter=max_iter))
        info = {**info2, "iterations": info["iterations"] + info2["iterations"],
                "history": info["history"] + info2["history"], "n_used": info.get("n_used", 1)}
        model = "runup"
    res, J = np.asarray(_residuals(r, jnp.asarray(theta))), np.asarray(info["J"])
    J_prior, phase = None, None
    if tracking is not None:
        J_prior = J[r.prior_rows] if r.n_reference else None
        phase = r.phase_error(theta)
        res, J = res[r.rows], J[r.rows]
    n, k = len(names), 0 if unbalances is not None else len(planes)
    D = np.asarray(theta[n:n + k] + 1j * theta[n + k:n + 2 * k])
    method = ("hac" if tracking is not None else "classical") if covariance == "auto" else covariance
    structure = residual_structure(res.reshape(2, speeds.size, 2))
    cols = (names + tuple(f"unbalance@{a:g} m {part}" for part in ("re", "im") for a in planes[:k])
            + tuple(f"phase reference {i}" for i in range(J.shape[1] - n - 2 * k)))
    d = res.reshape(2, speeds.size, 2) * sig[None]
    fitted = X + d[0] + 1j * d[1]
    out = report(params, Optimum(theta[:n], D, res, J, cols, speeds.size, J_prior, hac_lags), info, lanes,
                 covariance=method, sites=tuple(("plane", float(a)) for a in planes), model=model,
                 warnings=structure_warnings(structure, method, model),
                 rms_residual=float(np.sqrt(np.mean(np.abs(d[0] + 1j * d[1]) ** 2))), residual_structure=structure,
                 phase_correction=phase, data=data, fitted=fitted, sigma=sig, residual=r)
    if band:
        out = dataclasses.replace(out, band=response_band(out, base, speeds, planes, unbalances))
    return out


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
        m = machine_with(machine, names, theta[:n])
        D = theta[n:n + n_planes] + 1j * theta[n + n_planes:] if known is None else known
        return jax.vmap(lambda w: balancing_response(m, w, planes, D))(speeds)

    return response


@eqx.filter_jit
def _response_jacobian(machine, names, planes, known, theta, speeds):
    """The model response at `theta` and its Jacobian d X / d theta, (n, 2) and (n, 2, p)."""
    response = _response_of_theta(machine, names, planes, known)
    return value_and_jacfwd(lambda th: response(th, speeds))(theta)


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
    # `rms_residual` is over complex phasors: the squared residuals sum to (n_res / 2) rms^2
    s2 = n_res / 2 * result.rms_residual**2 / max(n_res - theta.size, 1)
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
