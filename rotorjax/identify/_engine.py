"""The one identification engine, for every scene (`identify`): what stays the same
whichever model the data measure.

A scene's model reduces its data to a residual `r(theta)` (scaled, real parts then
imaginary parts) over the fitted parameters in theta units (`Parameter`: positive
quantities as logarithms, signed ones scaled by their start), and a start. The
engine then

1. searches: the one Levenberg-Marquardt (`_lm`), from the start alone or from
   `n_starts` starts at once (the start and a Latin hypercube over `spread`-fold
   factors either way), vmapped; or optax's Adam from the start (`method="optax"`,
   the gradient-descent comparison);
2. takes the covariance of the parameters and the fitted unbalances at the optimum
   (`_covariance.theta_covariance`: classical, sandwich or HAC);
3. reports one `Identification`: estimates with 95 % intervals by the delta method
   (`p exp(+-1.96 sd_log)` for log-parameters, `v +- 1.96 sd` for the others),
   standard deviations and correlations, the fitted unbalances with intervals on
   their magnitude and angle, other minima of the global stage the data do not
   tell apart, and one set of warnings: parameters the data cannot see or barely
   determine (relative sd above 0.3), a rank-deficient Jacobian (the parameters in
   its null direction named), classical intervals a sandwich finds too narrow, no
   convergence.
"""

import dataclasses

import equinox as eqx
import jax
import jax.numpy as jnp
import numpy as np

from .._errors import NumericalError
from ..models._parameters import ParameterPath, with_values
from ._covariance import theta_covariance, variance_warnings
from ._lm import levenberg_marquardt, lm_batch

#: a parameter whose relative standard deviation exceeds this is poorly determined
POORLY_DETERMINED = 0.3
#: the 95 % normal quantile of the intervals
Z95 = 1.96


@dataclasses.dataclass(frozen=True)
class Parameter:
    """One fitted parameter: the leaves it sets (`path`), how it is fitted (`log`, or
    linearly with `scale`) and its start."""

    name: str
    path: ParameterPath
    log: bool
    # values, not structure: a compiled fit serves every start (`apply` takes the scales as an array)
    scale: float = dataclasses.field(compare=False)
    start: float = dataclasses.field(compare=False)

    @property
    def unbalance(self) -> bool:
        """Whether it sets an unbalance (not the rotor's matrices)."""
        return self.path.targets[0].leaf[0] == "components"

    def to_theta(self, value):
        return np.log(value) if self.log else value / self.scale

    def from_theta(self, theta, scale=None):
        return jnp.exp(theta) if self.log else theta * (self.scale if scale is None else scale)


def apply(params, scene, theta, scales=None):
    """`scene` (any pytree the parameters' paths address) with the parameters set from
    `theta` (pure JAX: differentiable and vmappable); `scales` the signed parameters'
    scales as an array (values, not structure), default their own."""
    values = [p.from_theta(theta[k], None if scales is None else scales[k]) for k, p in enumerate(params)]
    return with_values(scene, [p.path for p in params], values)


@dataclasses.dataclass(frozen=True, eq=False)
class Identification:
    """What `identify` returns, for every scene: estimates with 95 % intervals,
    standard deviations and correlations; the fitted unbalances (complex, kg m, at
    `unbalance_sites`: rotor nodes or the machine's correction planes) with intervals
    on their magnitude and angle; the fit (cost, RMS of `|model - measured|` over the
    phasors, iterations, convergence, starts, other minima); warnings; and the data
    against the fitted model."""

    names: tuple
    estimates: dict
    intervals: dict
    std: dict
    correlation: np.ndarray
    #: of (the parameters in theta units, then Re and Im of the fitted unbalances)
    covariance: np.ndarray
    covariance_method: str
    theta: np.ndarray
    #: the fitted unbalances (complex, kg m), or None when none was fitted
    unbalances: np.ndarray | None
    #: where they sit: `("node", n)` on a rotor file, `("plane", a)` (m) on the machine
    unbalance_sites: tuple
    #: per fitted unbalance: `(magnitude_ci95, phase_ci95)` (kg m, rad)
    unbalance_intervals: tuple
    rms_residual: float
    cost: float
    iterations: int
    converged: bool
    warnings: list
    #: the response model: "steady" (1x phasors), "runup" (order-tracked transient), "receptance"
    model: str
    n_starts: int = 1
    #: other minima the data do not tell apart: [{"cost", "estimates"}]
    minima: list = dataclasses.field(default_factory=list)
    #: the cost after each accepted step of a single-start fit
    history: list = dataclasses.field(default_factory=list)
    #: the fitted rotor's forward 1x critical speeds: [{"speed", "ci95", "std", "mode"}]
    critical_speeds: list = dataclasses.field(default_factory=list)
    #: per channel ("x1 Re", ...): lag-1 autocorrelation, runs-test z, effective number of points
    residual_structure: dict | None = None
    #: run-up model with the joint phase reference: the fitted error of the tacho's angle at each point (rad)
    phase_correction: np.ndarray | None = None
    #: the measurements (`PhasorData`, or the machine's `SweepData`)
    data: object = dataclasses.field(default=None, repr=False)
    #: the fitted model's phasors at the data's rows, and their noise
    fitted: np.ndarray | None = dataclasses.field(default=None, repr=False)
    sigma: np.ndarray | None = dataclasses.field(default=None, repr=False)
    #: lower and upper edges of the 95 % band on `|fitted|` (where the scene gives one)
    band: tuple | None = dataclasses.field(default=None, repr=False)
    #: the residual the fit minimised (for `estimates_jacobian`)
    residual: object = dataclasses.field(default=None, repr=False)

    @property
    def unbalance_table(self) -> list:
        """The fitted unbalances as records: the site, magnitude (kg m), phase (rad),
        `angle_deg`, and their 95 % intervals."""
        out = []
        for (kind, where), u, (mag_ci, ph_ci) in zip(self.unbalance_sites, self.unbalances if self.unbalances
                                                     is not None else (), self.unbalance_intervals):
            out.append({kind: where, "magnitude": float(abs(u)), "phase": float(np.angle(u)),
                        "angle_deg": float(np.degrees(np.angle(u))), "magnitude_ci95": list(mag_ci),
                        "phase_ci95": list(ph_ci)})
        return out

    def as_dict(self):
        out = {"estimates": self.estimates, "intervals_95": self.intervals, "ci95": self.intervals,
               "std": self.std, "rms_residual": self.rms_residual, "residual_rms": self.rms_residual,
               "iterations": self.iterations, "converged": self.converged, "warnings": list(self.warnings),
               "model": self.model, "covariance_method": self.covariance_method,
               "correlation": {"names": list(self.names), "matrix": np.round(self.correlation, 6).tolist()},
               "unbalances": self.unbalance_table, "critical_speeds": self.critical_speeds,
               "n_starts": self.n_starts, "minima": self.minima, "cost": self.cost}
        if self.data is not None:
            out["n_rows"] = int(self.data.n)
        if self.residual_structure is not None:
            out["residual_structure"] = self.residual_structure
        return out


def starts(center, params, n_starts, spread, seed=0):
    """`n_starts` starting points: `center` first, then a Latin hypercube over
    `[-log(spread), log(spread)]` per log-parameter (`[-spread, spread]` scaled
    units for signed ones, `[-pi, pi]` for phases) around it; entries of `center`
    after the parameters' stay."""
    rng = np.random.default_rng(seed)
    p = len(params)
    n = max(int(n_starts) - 1, 0)
    u = (np.stack([rng.permutation(n) for _ in range(p)], axis=1).reshape(n, p) + rng.random((n, p))) / max(n, 1)
    u = np.concatenate([u, np.full((n, center.size - p), 0.5)], axis=1)
    half = np.array([np.log(spread) if q.log else (np.pi / q.scale if q.name.endswith(".phase") else spread)
                     for q in params]).reshape(p)
    # entries after the parameters (a scene's own: unbalances it fits as parameters) start where they are
    half = np.concatenate([half, np.zeros(center.size - p)])
    return np.concatenate([center[None, :], center[None, :] + (2 * u - 1) * half[None, :]])


@dataclasses.dataclass(frozen=True)
class Search:
    """How the engine searches: `n_starts` (1: a local fit from the start), their
    `spread` and `seed`, `max_iter`, `method` ("lm" or "optax"), and the iterates'
    `bound` and `max_step` around the start (theta units)."""

    n_starts: int = 1
    spread: float = 10.0
    seed: int = 0
    max_iter: int = 200
    method: str = "lm"
    bound: float = np.inf
    max_step: float = np.inf


def search(r, center, params, how: Search):
    """Minimise `|r(theta)|^2` from `center` (theta units; its first `len(params)`
    entries are `params`, the rest, if any, start where they are). Returns
    `(theta, info, lanes)`: `info` the iterations, convergence, cost and (one start)
    its history and the Jacobian `J` at `theta`; `lanes` `(thetas, costs)` of every start (None for one start)."""
    center = np.asarray(center, dtype=float)
    if center.size == 0:
        return center, {"iterations": 0, "converged": True, "history": [], "cost": float("nan")}, None
    if how.method == "optax":
        theta, info = optax_fit(r, center, steps=how.max_iter * 20)
        return np.asarray(theta), {**info, "converged": True}, None
    if how.n_starts <= 1:
        theta, J, info = levenberg_marquardt(r, center, max_iter=how.max_iter, bound=how.bound,
                                             max_step=how.max_step)
        return np.asarray(theta), {**info, "J": J}, None
    th0 = starts(center, params, how.n_starts, how.spread, how.seed)
    ths, costs, done, it = lm_batch(r, jnp.asarray(th0), jnp.asarray(center), max_iter=how.max_iter,
                                    bound=how.bound, max_step=how.max_step)
    ths, costs = np.asarray(ths), np.asarray(costs)
    ok = np.isfinite(costs)
    if not ok.any():
        raise NumericalError(f"identify: no start gives a finite fit of {', '.join(q.name for q in params)}")
    best = int(np.argmin(np.where(ok, costs, np.inf)))
    return ths[best], {"iterations": it, "converged": bool(np.asarray(done)[best]), "history": [],
                       "cost": float(costs[best]), "n_used": int(ok.sum())}, (ths, costs)


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


def _estimates(params, theta, sd):
    """Estimates, 95 % intervals, standard deviations and the poorly-determined warnings."""
    est, ints, std, warnings = {}, {}, {}, []
    for i, q in enumerate(params):
        v = float(q.from_theta(theta[i]))
        est[q.name] = v
        if q.log:
            s, rel = v * float(sd[i]), float(sd[i])
            ints[q.name] = [v * float(np.exp(-Z95 * sd[i])), v * float(np.exp(Z95 * sd[i]))]
        else:
            s = float(sd[i]) * q.scale
            rel = s / max(abs(v), 1e-300)
            ints[q.name] = [v - Z95 * s, v + Z95 * s]
        std[q.name] = s
        if rel > POORLY_DETERMINED:
            warnings.append(f"{q.name} is poorly determined by the data (relative sd {rel:.2f}): its 95 % "
                            "interval is wide; the measurements barely depend on it")
    return est, ints, std, warnings


def _unbalance_intervals(u, cov, p):
    """95 % intervals on the magnitude and angle of each fitted unbalance (delta method;
    their Re parts at `p + j`, Im parts at `p + k + j` of `cov`)."""
    k, out = len(u), []
    for j in range(k):
        c = cov[np.ix_([p + j, p + k + j], [p + j, p + k + j])]
        mag = abs(u[j])
        gm = np.array([u[j].real, u[j].imag]) / max(mag, 1e-300)
        gp = np.array([-u[j].imag, u[j].real]) / max(mag**2, 1e-300)
        sm, sp = float(np.sqrt(max(gm @ c @ gm, 0))), float(np.sqrt(max(gp @ c @ gp, 0)))
        ph = float(np.angle(u[j]))
        out.append(((float(mag - Z95 * sm), float(mag + Z95 * sm)), (ph - Z95 * sp, ph + Z95 * sp)))
    return tuple(out)


def identifiability(J, names):
    """Warnings on the Jacobian (columns in theta units): parameters it barely sees,
    and its rank (the names in its null direction)."""
    out = []
    norms = np.linalg.norm(J, axis=0)
    top = max(float(norms.max()), 1e-300) if norms.size else 1.0
    blind = [n for n, v in zip(names, norms) if v < 1e-8 * top]
    for n in blind:
        out.append(f"the data cannot see {n}: the measurements do not change with it (e.g. a bearing at a node "
                   "of the excited modes, or a direction not measured)")
    if J.shape[1] > 1:
        U, s, Vt = np.linalg.svd(J / np.maximum(norms, 1e-300), full_matrices=False)
        if s[-1] < 1e-8 * s[0]:
            v = Vt[-1]
            involved = [names[i] for i in np.argsort(-np.abs(v)) if abs(v[i]) > 0.2]
            out.append(f"the Jacobian is rank deficient (condition {s[0] / max(s[-1], 1e-300):.1e}): "
                       f"{', '.join(involved)} cannot be told apart by these data")
    return out


def other_minima(params, ths, costs, theta, cost, sd, margin):
    """Distinct converged minima of the global stage within `margin` of the best cost."""
    out = []
    order = np.argsort(np.where(np.isfinite(costs), costs, np.inf))
    seen = [theta]
    for i in order:
        if not np.isfinite(costs[i]) or costs[i] > cost + margin:
            break
        d = np.abs(ths[i] - theta)
        if np.all(d <= np.maximum(3 * sd, 0.02)):
            continue
        if any(np.all(np.abs(ths[i] - s) <= np.maximum(3 * sd, 0.02)) for s in seen[1:]):
            continue
        seen.append(ths[i])
        out.append({"cost": float(costs[i]),
                    "estimates": {q.name: float(q.from_theta(ths[i][k])) for k, q in enumerate(params)}})
        if len(out) == 3:
            break
    return out


@dataclasses.dataclass(frozen=True)
class Optimum:
    """What a scene's model gives the engine at the optimum: the parameters (theta
    units) and fitted unbalances, the residuals and their Jacobian over (parameters,
    Re u, Im u) (`res`, `J`: the data's rows; `J_prior`: whitened prior rows of
    nuisance parameters, or None), the column names, and the number of points the
    covariance groups the residuals by."""

    theta: np.ndarray
    u: np.ndarray
    res: np.ndarray
    J: np.ndarray
    names: tuple
    n_points: int
    J_prior: np.ndarray | None = None
    lags: int | None = None


def report(params, opt: Optimum, info, lanes, *, covariance, sites, model, warnings=(), **fields):
    """The `Identification` at the optimum `opt` of a search (`info`, `lanes` from
    `search`): covariance, estimates and intervals, unbalances, warnings. `fields`:
    the scene's own (`data`, `fitted`, `critical_speeds`, ...)."""
    p, k = len(params), len(opt.u)
    res, J = np.asarray(opt.res), np.asarray(opt.J)
    if not np.all(np.isfinite(res)) or not np.all(np.isfinite(J)):
        raise NumericalError("identify: the fitted model gives non-finite phasors or gradients")
    cov = theta_covariance(J, res, covariance, n_points=opt.n_points, lags=opt.lags, J_prior=opt.J_prior)
    n_main = p + 2 * k
    cov = cov[:n_main, :n_main]
    sd = np.sqrt(np.maximum(np.diag(cov), 0.0))
    est, ints, std, warn = _estimates(params, opt.theta, sd)
    warnings = list(warnings) + warn
    Jall = J if opt.J_prior is None else np.concatenate([J, opt.J_prior])
    warnings += identifiability(Jall, list(opt.names))
    if covariance == "classical":
        warnings += variance_warnings(J, res, cov, [q.name for q in params], opt.n_points)
    cost = float(res @ res)
    minima = []
    if lanes is not None and p:
        from scipy.stats import chi2  # noqa: PLC0415 (scipy.stats: a quarter of the CLI's import time)

        dof = max(res.size - n_main, 1)
        minima = other_minima(params, lanes[0][:, :p], lanes[1], opt.theta[:p], cost, sd[:p],
                              chi2.ppf(0.95, p) * cost / dof)
        if minima:
            alt = minima[0]["estimates"]
            warnings.append(f"{len(minima)} other minim{'um' if len(minima) == 1 else 'a'} fit the data comparably "
                            f"(within the 95 % chi-square margin of the best): e.g. "
                            + ", ".join(f"{n} = {alt[n]:.4g} (best {est[n]:.4g})" for n in list(alt)[:4])
                            + "; the data do not tell them apart")
    if not info["converged"]:
        warnings.append("the fit did not converge: the estimates are the last iterate")
    corr = cov[:p, :p] / np.maximum(np.outer(sd[:p], sd[:p]), 1e-300)
    u = np.asarray(opt.u, dtype=complex)
    return Identification(
        names=tuple(q.name for q in params), estimates=est, intervals=ints, std=std, correlation=corr,
        covariance=cov, covariance_method=covariance, theta=np.asarray(opt.theta[:p]),
        unbalances=u if k else None, unbalance_sites=tuple(sites) if k else (),
        unbalance_intervals=_unbalance_intervals(u, cov, p), cost=cost,
        iterations=int(info["iterations"]), converged=bool(info["converged"]), warnings=warnings, model=model,
        n_starts=int(info.get("n_used", 1)), minima=minima, history=list(info.get("history", [])), **fields)
