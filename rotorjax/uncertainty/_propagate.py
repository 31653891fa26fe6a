"""Uncertainty propagation for any function of a scene's parameters written in JAX:
vmapped Monte Carlo (through `rotorjax.sweep`, the one batched evaluation), the
first-order second-moment method from autodiff gradients, the probability of a
margin's violation with its confidence interval, and each parameter's share of an
output's variance.

- Monte Carlo: `n` samples from the distributions (`_distributions`: a Gaussian
  copula), the outputs evaluated in vmapped chunks; mean, standard deviation
  (with the mean's standard error `sd / sqrt(n)`) and quantiles of each output.
  Samples whose outputs are not finite (a solver that did not converge there) are
  evaluated again with `fallback` where one is given (a slower path to the same
  outputs: `RotorQuantities.fallback`), in vmapped chunks of 16; those still not
  finite are counted and left out of the statistics, and named in the result.
- First order (FOSM): `mean ~ f(mu)`, `var ~ g^T Sigma g` with `g = df/dp` at the
  parameters' means (`jax.jacfwd`, or `jax.jacrev`) and `Sigma_ij = rho_ij sd_i sd_j` (`rho` the
  copula's correlation, exact for normal parameters); the share of parameter `i`
  is `g_i^2 sd_i^2 / sum_j g_j^2 sd_j^2` (uncorrelated reading).
- Violation probability: the fraction `k / n` of samples where an output crosses a
  limit, with its 95 % Wilson interval.
"""

import dataclasses

import equinox as eqx
import jax
import jax.numpy as jnp
import numpy as np

from .._errors import InputError, NumericalError
from ..sweep import sweep
from ._distributions import correlation_factor

#: the quantiles reported
QUANTILES = (0.05, 0.5, 0.95)
#: samples per vmapped call: a rotor's batched matrices stay in the cache (1024 at once took 10 % longer a sample
#: on ROSS's example rotor)
CHUNK_SIZE = 128


@dataclasses.dataclass(frozen=True, eq=False)
class Propagation:
    """Outputs as distributions (see the module).

    - `inputs`: `{name: distribution}`; `outputs`: the output names;
    - `samples` `(n, n_outputs)` and `input_samples` `(n, n_inputs)` (the drawn
      values), `finite` `(n,)`: the samples whose outputs are all finite;
    - Monte Carlo: `mean`, `std`, `sem` (standard error of the mean), `quantiles`
      `{q: (n_outputs,)}`;
    - first order: `fosm_mean`, `fosm_std`, `gradient` `(n_outputs, n_inputs)`,
      `shares` `(n_outputs, n_inputs)`;
    - `retried`: how many samples `fallback` evaluated again.
    """

    inputs: dict
    outputs: tuple
    samples: np.ndarray
    input_samples: np.ndarray
    finite: np.ndarray
    mean: np.ndarray
    std: np.ndarray
    sem: np.ndarray
    quantiles: dict
    fosm_mean: np.ndarray
    fosm_std: np.ndarray
    gradient: np.ndarray
    shares: np.ndarray
    retried: int = 0

    @property
    def n(self) -> int:
        return int(self.finite.sum())

    def probability(self, output, below=None, above=None):
        """`(p, (lo, hi))`: the fraction of the samples where `output` is below `below`
        (or above `above`), with its 95 % Wilson interval."""
        if (below is None) == (above is None):
            raise InputError("probability: give one of below= or above=")
        if output not in self.outputs:
            raise InputError(f"probability: {output!r} is not an output; outputs: {', '.join(self.outputs)}")
        x = self.samples[self.finite, self.outputs.index(output)]
        k = int(np.sum(x < below) if below is not None else np.sum(x > above))
        return wilson(k, x.size)

    def as_dict(self) -> dict:
        out = {}
        for j, name in enumerate(self.outputs):
            out[name] = {"mean": float(self.mean[j]), "std": float(self.std[j]), "sem": float(self.sem[j]),
                         "quantiles": {str(q): float(v[j]) for q, v in self.quantiles.items()},
                         "first_order": {"mean": float(self.fosm_mean[j]), "std": float(self.fosm_std[j])},
                         "shares": {k: float(self.shares[j, i]) for i, k in enumerate(self.inputs)}}
        return {"inputs": {k: d.text() for k, d in self.inputs.items()}, "samples": int(self.samples.shape[0]),
                "finite_samples": self.n, "retried_samples": self.retried, "outputs": out}


def wilson(k, n, z=1.959963984540054):
    """`(k / n, (lo, hi))` with the Wilson score interval (95 % by default)."""
    if n < 1:
        return float("nan"), (float("nan"), float("nan"))
    p = k / n
    d = 1 + z**2 / n
    c = (p + z**2 / (2 * n)) / d
    h = z * np.sqrt(p * (1 - p) / n + z**2 / (4 * n**2)) / d
    return float(p), (0.0 if k == 0 else float(max(c - h, 0.0)), 1.0 if k == n else float(min(c + h, 1.0)))


def draw(inputs, n, correlation=None, seed=0):
    """`(n, n_inputs)` samples of the distributions `inputs` (`{name: dist}`), through
    the copula with `correlation` (see `_distributions.correlation_factor`)."""
    names = list(inputs)
    L = correlation_factor(names, correlation)
    z = np.random.default_rng(seed).standard_normal((n, len(names))) @ L.T
    return np.stack([np.asarray(inputs[k].from_normal(jnp.asarray(z[:, i]))) for i, k in enumerate(names)], axis=1)


def propagate(fn, inputs, samples=10_000, correlation=None, seed=0, chunk_size=CHUNK_SIZE, names=None,
              progress=False, reverse=False, fallback=None) -> Propagation:
    """Outputs of `fn` as distributions (see the module).

    **Arguments:**
    - `fn`: `fn(values) -> outputs`, `values` a `(n_inputs,)` array in the order of
      `inputs`, `outputs` a `(n_outputs,)` array; pure JAX (vmapped and
      differentiated).
    - `inputs`: `{name: Normal | LogNormal | Uniform}`.
    - `samples` (>= 2), `correlation` (None, a matrix, or `{(a, b): rho}`), `seed`,
      `chunk_size` (samples per vmapped call, `CHUNK_SIZE` by default).
    - `names`: the outputs' names (default `y0, y1, ...`).
    - `progress`: a progress bar over the chunks, on stderr (tqdm).
    - `reverse`: the first-order gradient in reverse mode (`jax.jacrev`), for an `fn`
      that integrates in time (diffrax's adjoint is reverse-mode only); else forward
      (`jax.jacfwd`).
    - `fallback`: `fallback(values) -> outputs`, as `fn`, for the samples (and the
      first-order point) where `fn`'s outputs are not all finite.

    **Returns:** a `Propagation`. **Raises:** `InputError` for bad input;
    `NumericalError` when no sample gives finite outputs.
    """
    if not inputs:
        raise InputError("inputs: give at least one parameter's distribution")
    if not isinstance(samples, (int, np.integer)) or samples < 2:
        raise InputError(f"samples must be an integer >= 2, got {samples!r}")
    keys = list(inputs)
    X = draw(inputs, int(samples), correlation, seed)
    Y = _evaluate(fn, X, chunk_size, progress)
    again = np.flatnonzero(~np.all(np.isfinite(Y), axis=1)) if fallback is not None else np.zeros(0, int)
    if again.size:  # padded to whole chunks of 16 (repeating the last): one compilation for any count
        rows = again[np.minimum(np.arange(-(-again.size // 16) * 16), again.size - 1)]
        Y[again] = _evaluate(fallback, X[rows], 16, False)[:again.size]
    names = tuple(names) if names is not None else tuple(f"y{j}" for j in range(Y.shape[1]))
    if len(names) != Y.shape[1]:
        raise InputError(f"names: {len(names)} names for {Y.shape[1]} outputs")
    finite = np.all(np.isfinite(Y), axis=1)
    if finite.sum() < 2:
        raise NumericalError(f"propagate: {int(finite.sum())} of {X.shape[0]} samples give finite outputs")
    Yf = Y[finite]
    mean, std = Yf.mean(axis=0), Yf.std(axis=0, ddof=1)
    mu = np.array([inputs[k].mean for k in keys], dtype=float)
    sd = np.array([inputs[k].std for k in keys], dtype=float)
    L = correlation_factor(keys, correlation)
    cov = (L @ L.T) * np.outer(sd, sd)
    g, f0 = _first_order(fn, mu, reverse)
    if fallback is not None and not np.all(np.isfinite(f0)):
        g, f0 = _first_order(fallback, mu, reverse)
    g = g.reshape(f0.size, len(keys))
    var = np.einsum("oi,ij,oj->o", g, cov, g)
    contrib = (g * sd[None, :]) ** 2
    shares = contrib / np.maximum(contrib.sum(axis=1, keepdims=True), 1e-300)
    return Propagation(inputs=dict(inputs), outputs=names, samples=Y, input_samples=X, finite=finite, mean=mean,
                       std=std, sem=std / np.sqrt(Yf.shape[0]),
                       quantiles={q: np.quantile(Yf, q, axis=0) for q in QUANTILES}, fosm_mean=f0,
                       fosm_std=np.sqrt(np.maximum(var, 0.0)), gradient=g, shares=shares, retried=int(again.size))


def _first_order(fn, mu, reverse):
    """`(df/dp, f)` at `mu`, in one pass (the value as the Jacobian's auxiliary output),
    compiled as one program (run op by op, the Jacobian of a separation margin's eigenvalue
    solves compiled some 500 small programs)."""
    jacobian = jax.jacrev if reverse else jax.jacfwd

    def f(v):
        y = jnp.atleast_1d(fn(v))
        return y, y

    g, f0 = jax.jit(jacobian(f, has_aux=True))(jnp.asarray(mu))
    return np.asarray(g), np.asarray(f0)


def _evaluate(fn, X, chunk_size, progress):
    """`fn` on each row of `X`, in vmapped chunks (`rotorjax.sweep`): `(n, n_outputs)`.
    A `Partial` of `fn`, not a fresh lambda: the same `fn` again (another draw, more
    samples, the fallback's next chunk count) finds its vmapped program compiled."""
    res = sweep(eqx.Partial(_row, fn), {f"p{i}": X[:, i] for i in range(X.shape[1])}, mode="zip",
                chunk_size=chunk_size, progress=bool(progress))
    return np.array(res.values).reshape(X.shape[0], -1)


def _row(fn, point):
    return jnp.atleast_1d(fn(jnp.stack([point[f"p{i}"] for i in range(len(point))])))

