"""Identification of a finite-element rotor (any rotor file) from measured 1x
phasors or impact-test receptances: bearing, support, disk, point-mass, material,
shaft-geometry and unbalance parameters by their rotor-file names.

The fit: weighted least squares on the complex residuals `(model - measured) /
sigma` (real and imaginary parts), over log-parameters (positive quantities) and
scaled signed ones (`_fe_params`), by Levenberg-Marquardt with autodiff
Jacobians through the FE model (`_fe_model`). Unbalances fitted at named nodes
enter linearly: for given rotor parameters they are the weighted linear
least-squares solution (variable projection), so the search runs over the rotor
parameters only and needs no start for them.

A local fit from a start a factor of a few off falls into spurious minima (a
bearing stiffness collapsing to near zero while the unbalance absorbs the
amplitude), so the search is global: `n_starts` starts, the given one and a
Latin hypercube over `spread`-fold factors either way (log-parameters), all run
by one vmapped LM (`_lm.lm_batch`, the one LM, which model 002's fits run as one
lane), each lane to convergence; the best is the estimate. Other minima whose cost
is within the 95 % chi-square margin of the best and whose parameters differ by more than three
standard deviations are reported: the data do not tell them apart.

Uncertainty: the delta method at the optimum (`theta_covariance`, classical or
sandwich) over the rotor parameters and the unbalances together; 95 % intervals
`p exp(+-1.96 sd_log)` for log-parameters, `v +- 1.96 sd` for the others. The
fitted rotor's forward 1x critical speeds in the data's range come with
intervals by the same delta method, their gradient by the implicit function
theorem on `omega_k(W; p) - W = 0`. Identifiability: the Jacobian's rank (the
parameters in its null direction named), parameters the data barely move, and
relative standard deviations above 0.3 are warnings.
"""

import dataclasses

import equinox as eqx
import jax
import jax.numpy as jnp
import numpy as np

from .._autodiff import value_and_jacfwd
from .._errors import InputError
from ._fe_model import phasor_model, receptances
from ..models._parameters import SceneParts
from ._engine import Identification, Optimum, Search, apply, report, search
from ._fe_params import RotorModel, rotor_model
from ._lm import AbstractJacobianResidual
from ._phasor_file import PhasorData, read_phasors

WEIGHTS = ("relative", "uniform")
#: relative weights: sigma_i = max(|X_i|, RELATIVE_FLOOR * max |X|)
RELATIVE_FLOOR = 1e-3
#: bound of the search around the start, in theta units (log-parameters: a factor e^7 ~ 1100)
BOUND = 7.0
#: the largest step per coordinate (theta units)
MAX_STEP = 2.0


class FEResidual(AbstractJacobianResidual):
    """`r(theta)`: the scaled residuals (real parts, then imaginary parts) of the
    rows at rotor parameters `theta`, the fitted unbalances projected out."""

    parts: SceneParts                     # the rotor file's full rotor and components, at the start
    params: tuple = eqx.field(static=True)
    unb_nodes: tuple = eqx.field(static=True)
    unb_places: tuple = eqx.field(static=True)   # the file's unbalances' places among the components
    fit_nodes: tuple = eqx.field(static=True)
    model: eqx.Module
    X: jax.Array
    sigma: jax.Array
    scales: jax.Array                     # the parameters' scales (signed ones), as `apply` takes them
    coupling: eqx.Module | None = None    # `Receptances` around the start, or None: direct solves

    @property
    def rotor(self):
        """The rotor at the start."""
        return self.parts.rotor

    def _rotor(self, theta):
        """`(rotor, (nodes, magnitudes, phases))`: the rotor and the file's unbalances at `theta`."""
        parts = apply(self.params, self.parts, theta, self.scales)
        unb = [parts.components[j] for j in self.unb_places]
        mags, phases = (jnp.stack([getattr(u, k) for u in unb]) if unb else jnp.zeros(0)
                        for k in ("magnitude", "phase"))
        return parts.rotor, (self.unb_nodes, mags, phases)

    def values(self, theta):
        """The parameters' values at `theta` (`(p,)`)."""
        return jnp.stack([q.from_theta(theta[k], self.scales[k]) for k, q in enumerate(self.params)]) \
            if self.params else jnp.zeros(0)

    def _matrices(self, theta, W):
        return self._rotor(theta)[0].reduced_matrices(W)

    def _parts(self, theta, R=None):
        """`(a, B)`: the rows' phasors with the fitted unbalances zero, and their
        response to each fitted unbalance (None when none is fitted); `R` the rows'
        unit responses (computed when not given)."""
        if self.coupling is not None:
            # the parameters' values set into the coupling directly: no FE assembly
            _, (_, mags, phases) = self._rotor(theta)
            if R is None:
                R = self.coupling.rows(self.model, self.values(theta))
        else:
            rotor, (_, mags, phases) = self._rotor(theta)
            R = self.model.rows(rotor) if R is None else R
        if self.model.kind == "frf":
            return R, None
        base = jnp.zeros(len(self.model.loads), dtype=jnp.complex128)
        for j, node in enumerate(self.unb_nodes):
            base = base.at[self.model.unit_index(node)].add(mags[j] * jnp.exp(1j * phases[j]))
        a = jnp.sum(R * (base[None, :] + self.model.trial), axis=1)
        if not self.fit_nodes:
            return a, None
        return a, R[:, np.array([self.model.unit_index(n) for n in self.fit_nodes])]

    @staticmethod
    def _project(a, B, X, sigma):
        Bw, rw = B / sigma[:, None], (X - a) / sigma
        return jnp.linalg.solve(Bw.conj().T @ Bw, Bw.conj().T @ rw)

    def unbalances(self, theta):
        """The fitted unbalances at `theta` (complex, kg m), the weighted linear least-squares solution."""
        a, B = self._parts(theta)
        return self._project(a, B, self.X, self.sigma)

    def predict(self, theta, u=None, R=None):
        a, B = self._parts(theta, R)
        if B is None:
            return a
        return a + B @ (self._project(a, B, self.X, self.sigma) if u is None else u)

    def res_jac(self, theta):
        """`(r, dr/dtheta)`: forward-mode autodiff through the receptance coupling, or
        with direct solves one LU per solve point (`PhasorModel.solves_jvp`)."""
        if self.coupling is not None:
            return value_and_jacfwd(self)(theta)
        H, dH = self.model.solves_jvp(self._matrices, theta)
        R, dR = self.model.gather(H), self.model.gather(dH)

        def g(R, th):
            return self._scaled(self.predict(th, R=R))

        p = theta.shape[0]
        res = g(R, theta)
        J = jax.vmap(lambda dRk, ek: jax.jvp(g, (R, theta), (dRk, ek))[1], in_axes=(-1, 0), out_axes=1)(
            dR, jnp.eye(p, dtype=theta.dtype))
        return res, J

    def _scaled(self, m):
        d = (m - self.X) / self.sigma
        return jnp.concatenate([jnp.real(d), jnp.imag(d)])

    def __call__(self, theta):
        return self._scaled(self.predict(theta))

    def full(self, theta_u):
        """The residuals with the fitted unbalances as parameters too: `theta_u =
        (theta, Re u, Im u)` (for the covariance)."""
        p, k = len(self.params), len(self.fit_nodes)
        u = theta_u[p:p + k] + 1j * theta_u[p + k:]
        return self._scaled(self.predict(theta_u[:p], u if k else None))


def _sigma(data, weights):
    if data.sigma is not None:
        return np.asarray(data.sigma, dtype=float)
    if weights == "uniform":
        return np.ones(data.n)
    mag = np.abs(data.X)
    return np.maximum(mag, RELATIVE_FLOOR * max(float(mag.max()), 1e-300))


def problem(rotor, data, fit, fit_unbalance=(), overrides=None, weights="relative", coupling=True):
    """`(model, params, residual, center)`: the `RotorModel`, the fitted
    `Parameter`s, the `FEResidual` and the start in theta units."""
    model = rotor if isinstance(rotor, RotorModel) else rotor_model(rotor, overrides)
    data = data if isinstance(data, PhasorData) else read_phasors(data)
    if weights not in WEIGHTS:
        raise InputError(f"--weights {weights}: expected one of {', '.join(WEIGHTS)}")
    fit = tuple(fit)
    fit_unbalance = tuple(int(n) for n in fit_unbalance)
    if not fit and not fit_unbalance:
        raise InputError("--fit: name at least one parameter to fit (e.g. bearing0.kxx), or --fit-unbalance NODES")
    params = model.parameters(fit)
    if len(set(fit_unbalance)) != len(fit_unbalance):
        raise InputError(f"--fit-unbalance {','.join(map(str, fit_unbalance))}: a node is named twice")
    for n in fit_unbalance:
        if not 0 <= n < model.rotor.n_nodes:
            raise InputError(f"--fit-unbalance {n}: not a node of the rotor (0..{model.rotor.n_nodes - 1})")
    if data.kind == "frf":
        if fit_unbalance:
            raise InputError(f"--fit-unbalance: {data.path} holds receptances (impact tests), which no unbalance "
                             "drives")
        if any(p.unbalance for p in params):
            raise InputError(f"--fit: {data.path} holds receptances (impact tests): unbalance parameters cannot "
                             "be fitted from them")
    elif not (model.unbalances or fit_unbalance or np.any(data.trial_node >= 0)):
        raise InputError(f"{model.label} has no [[unbalance]] and nothing is fitted at a node: the model of "
                         f"{data.path} has no excitation; give --fit-unbalance NODES (the unbalance is then fitted)")
    unb_nodes = tuple(int(u.node_index) for u in model.unbalances)
    pm = phasor_model(model.rotor, data, unb_nodes + fit_unbalance)
    sig = _sigma(data, weights)
    r = FEResidual(model.parts, params, unb_nodes, model.unbalance_places,
                   fit_unbalance, pm, jnp.asarray(data.X, dtype=jnp.complex128), jnp.asarray(sig),
                   jnp.array([q.scale for q in params], dtype=jnp.float64).reshape(len(params)))
    center = np.array([p.to_theta(p.start) for p in params], dtype=float)
    # receptance coupling holds where the matrices are affine in every fitted value (not a material, a diameter)
    if coupling and all(q.path.affine or q.unbalance for q in params):
        v0 = np.array([q.from_theta(c) for q, c in zip(params, center)], dtype=float).reshape(len(params))
        dv0 = np.array([v if q.log else q.scale for q, v in zip(params, v0)], dtype=float).reshape(len(params))
        r = eqx.tree_at(lambda m: m.coupling, r, receptances(pm, model.rotor, r._matrices, center, v0, dv0),
                        is_leaf=lambda x: x is None)
    if pm.kind == "unbalance" and len(fit_unbalance) > 0 and 2 * data.n < 2 * len(fit_unbalance) + len(params):
        raise InputError(f"{data.path}: {data.n} phasors cannot determine {len(params)} parameters and "
                         f"{len(fit_unbalance)} complex unbalances")
    return model, params, r, center


def _rotor_of(r, theta):
    return r._rotor(theta)[0]


@eqx.filter_jit
def _critical_gradient(r, W, theta, k):
    """`(g_W, g_theta)` of `g = omega_k(W; theta) - W` (the implicit function theorem's inputs)."""
    from ..analysis._linear import damped_frequencies

    def g(W, th):
        return damped_frequencies(_rotor_of(r, th), W, k + 1)[k] - W

    return jax.grad(g, argnums=(0, 1))(W, theta)


def _critical_speeds(r, theta, cov, lo, hi):
    """The fitted rotor's forward 1x critical speeds in `[lo, hi]` with 95 % intervals
    (delta method; `dW/dtheta = -g_theta / g_W` on `omega_k(W; theta) = W`)."""
    from ..analysis._linear import critical_speeds_1x

    rotor = eqx.filter_jit(_rotor_of)(r, jnp.asarray(theta))
    out = []
    n_modes = min(12, len(rotor.free_dofs))
    for W, k in critical_speeds_1x(rotor, lo, hi, n_modes=n_modes, whirl="forward"):
        gW, gth = _critical_gradient(r, jnp.float64(W), jnp.asarray(theta), int(k))
        dW = -np.asarray(gth) / float(gW)
        c = cov[:len(theta), :len(theta)]
        sd = float(np.sqrt(max(dW @ c @ dW, 0.0)))
        out.append({"speed": float(W), "ci95": [float(W - 1.96 * sd), float(W + 1.96 * sd)], "std": sd,
                    "mode": int(k)})
    return out


def identify_rotor(rotor, data, fit, *, fit_unbalance=(), overrides=None, weights="relative",
                   covariance="classical", n_starts=32, spread=10.0, method="lm", max_iter=200, seed=0,
                   critical_speeds=True) -> Identification:
    """Fit the rotor-file parameters `fit` (names as `--set` keys: `bearing0.kxx`, ...)
    and the unbalances at the nodes `fit_unbalance` to measured phasors (see
    `identify`).

    - `rotor`: a rotor file (its values, with `overrides`, are the start) or a `RotorModel`.
    - `data`: a `PhasorData` or a phasor file (unbalance phasors, trial runs, or receptances).
    - `weights`: `"relative"` (sigma = |X|, floored at 1e-3 of the largest: every
      phasor counts by its relative error, as noise proportional to the signal
      makes it) or `"uniform"`; a file's `sigma` column overrides both.
    - `covariance`: `"classical"` or `"sandwich"` (unequal variances).
    - `n_starts`, `spread`, `seed`: the global stage (1 start: a local fit).
    - `method`: `"lm"` or `"optax"` (Adam from the given start, `20 max_iter` steps, no global
      stage: the gradient-descent option, for comparison; slower).
    - `critical_speeds`: report the fitted rotor's forward critical speeds in the data's speed range.

    **Raises:** `InputError` naming the option, file and row; `NumericalError` when
    no start gives a finite fit.
    """
    if covariance not in ("classical", "sandwich"):
        raise InputError(f"--covariance {covariance}: expected classical or sandwich")
    if method not in ("lm", "optax"):
        raise InputError(f"--method {method}: expected lm or optax")
    if int(n_starts) < 1:
        raise InputError(f"--starts {n_starts}: at least 1")
    if not spread > 1:
        raise InputError(f"--spread {spread}: must be > 1 (a factor either way)")
    model, params, r, center = problem(rotor, data, fit, fit_unbalance, overrides, weights)
    data = data if isinstance(data, PhasorData) else read_phasors(data)
    warnings = []
    if model.nonlinear:
        warnings.append(f"the 1x model is the linear rotor: the file's {', '.join(sorted(set(model.nonlinear)))} "
                        "component(s) are left out")
    how = Search(n_starts=int(n_starts), spread=spread, seed=seed, max_iter=max_iter, method=method, bound=BOUND,
                 max_step=MAX_STEP)
    theta, info, lanes = search(r, center, params, how)
    u, res, J, fitted = (np.asarray(a) for a in _at_optimum(r, jnp.asarray(theta)))
    nodes = r.fit_nodes
    names = tuple(q.name for q in params) + tuple(f"unbalance@{n}.{part}" for part in ("re", "im") for n in nodes)
    out = report(params, Optimum(theta, u, res, J, names, data.n), info, lanes, covariance=covariance,
                 sites=tuple(("node", n) for n in nodes), model="receptance" if data.kind == "frf" else "steady",
                 warnings=warnings, rms_residual=float(np.sqrt(np.mean(np.abs(fitted - data.X) ** 2))),
                 data=data, fitted=fitted, sigma=np.asarray(r.sigma), residual=r)
    if critical_speeds and data.kind != "frf" and params:
        crit = _critical_speeds(r, theta, out.covariance, float(np.min(data.speed)), float(np.max(data.speed)))
        out = dataclasses.replace(out, critical_speeds=crit)
    return out


@eqx.filter_jit
def _at_optimum(r, theta):
    """The fitted unbalances, the residuals and Jacobian over (theta, Re u, Im u), and
    the model's phasors, at `theta` (one compiled call)."""
    if r.fit_nodes:
        u = r.unbalances(theta)
    else:
        u = jnp.zeros(0, dtype=jnp.complex128)
    full = jnp.concatenate([theta, jnp.real(u), jnp.imag(u)])
    return u, r.full(full), jax.jacfwd(r.full)(full), r.predict(theta)


def estimates_jacobian(result: Identification):
    """`d estimate / d (Re X, Im X)`, shape `(n_params, 2 n_rows)`: how the estimates
    move with the measured phasors, by the implicit function theorem on the
    optimality condition `grad_theta |r(theta, X)|^2 = 0` (exact for the fit the
    optimiser returned; checked against re-fits of perturbed data in the tests)."""
    r = result.residual
    theta = jnp.asarray(result.theta)
    Xr = jnp.concatenate([jnp.real(r.X), jnp.imag(r.X)])
    n = r.X.shape[0]

    def grad_cost(th, x):
        rr = eqx.tree_at(lambda m: m.X, r, x[:n] + 1j * x[n:])
        return jax.grad(lambda t: 0.5 * jnp.sum(rr(t) ** 2))(th)

    H = jax.jacfwd(grad_cost, argnums=0)(theta, Xr)
    B = jax.jacfwd(grad_cost, argnums=1)(theta, Xr)
    dtheta = -np.linalg.solve(np.asarray(H), np.asarray(B))
    scale = np.array([float(q.from_theta(result.theta[i])) if q.log else q.scale
                      for i, q in enumerate(r.params)])
    return scale[:, None] * dtheta
