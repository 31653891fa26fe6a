"""Parameters as distributions: normal, lognormal and uniform, correlated through a
Gaussian copula.

A sample is drawn as `z = L e` (`e` independent standard normals, `L L^T = R` the
correlation matrix of the underlying normals), then each parameter from its own
`z_i`: normal `mean + sd z`, lognormal `exp(mu + s z)`, uniform `lo + (hi - lo)
Phi(z)`. For normal parameters `R` is their correlation; for the others it is the
correlation of the normals behind them (the copula's), which is what a correlation
of log-stiffnesses means for lognormal bearings.

Lognormal parameters are given by the mean and standard deviation of the quantity
itself (`lognormal(MEAN, SD)`: `s^2 = log(1 + (SD / MEAN)^2)`, `mu = log MEAN -
s^2 / 2`), as a data sheet states a scatter.
"""

import dataclasses
import re

import jax.numpy as jnp
import numpy as np
from jax.scipy.special import ndtr

from .._errors import InputError


@dataclasses.dataclass(frozen=True)
class Normal:
    """`N(mean, sd^2)`."""

    mean: float
    sd: float

    def from_normal(self, z):
        return self.mean + self.sd * z

    @property
    def std(self) -> float:
        return self.sd

    def text(self) -> str:
        return f"normal({self.mean:g}, {self.sd:g})"


@dataclasses.dataclass(frozen=True)
class LogNormal:
    """A positive quantity whose logarithm is normal, by the quantity's own `mean` and
    standard deviation `sd`."""

    mean: float
    sd: float

    @property
    def s(self) -> float:
        """The standard deviation of the logarithm."""
        return float(np.sqrt(np.log1p((self.sd / self.mean) ** 2)))

    @property
    def mu(self) -> float:
        """The mean of the logarithm."""
        return float(np.log(self.mean) - self.s**2 / 2)

    def from_normal(self, z):
        return jnp.exp(self.mu + self.s * z)

    @property
    def std(self) -> float:
        return self.sd

    def text(self) -> str:
        return f"lognormal({self.mean:g}, {self.sd:g})"


@dataclasses.dataclass(frozen=True)
class Uniform:
    """Uniform on `[lo, hi]`."""

    lo: float
    hi: float

    def from_normal(self, z):
        return self.lo + (self.hi - self.lo) * ndtr(z)

    @property
    def mean(self) -> float:
        return (self.lo + self.hi) / 2

    @property
    def std(self) -> float:
        return (self.hi - self.lo) / np.sqrt(12.0)

    def text(self) -> str:
        return f"uniform({self.lo:g}, {self.hi:g})"


KINDS = {"normal": Normal, "lognormal": LogNormal, "uniform": Uniform}
_SPEC = re.compile(r"^\s*([^=\s]+)\s*=\s*([a-z]+)\s*\(\s*([^,()]+)\s*,\s*([^,()]+)\s*\)\s*$")


def distribution(kind, a, b, name="the parameter"):
    """A checked distribution: `normal(mean, sd)`, `lognormal(mean, sd)` or
    `uniform(lo, hi)`; `name` says whose in the messages."""
    if kind not in KINDS:
        raise InputError(f"{name}: unknown distribution {kind!r}; known: {', '.join(f'{k}(A, B)' for k in KINDS)}")
    a, b = float(a), float(b)
    if not (np.isfinite(a) and np.isfinite(b)):
        raise InputError(f"{name}: {kind}({a:g}, {b:g}) needs finite numbers")
    if kind == "uniform":
        if not a < b:
            raise InputError(f"{name}: uniform({a:g}, {b:g}) needs LO < HI")
        return Uniform(a, b)
    if not b > 0:
        raise InputError(f"{name}: {kind}({a:g}, {b:g}): the standard deviation must be > 0")
    if kind == "lognormal" and not a > 0:
        raise InputError(f"{name}: lognormal({a:g}, {b:g}): a lognormal quantity's mean must be > 0")
    return KINDS[kind](a, b)


def support(dist) -> tuple:
    """The values `dist` draws, `(lo, hi)`: a uniform one's ends, a normal or lognormal
    one's within 5 standard deviations of the normal behind it (a draw beyond happens
    once in 3.5 million)."""
    if isinstance(dist, Uniform):
        return dist.lo, dist.hi
    if isinstance(dist, LogNormal):
        return float(np.exp(dist.mu - 5 * dist.s)), float(np.exp(dist.mu + 5 * dist.s))
    return dist.mean - 5 * dist.sd, dist.mean + 5 * dist.sd


def reaches_zero(dist) -> bool:
    """Whether `dist` puts weight at or below 0 (`support`): not for a positive quantity."""
    return support(dist)[0] <= 0


def parse_distribution(text, option="--dist"):
    """`KEY=kind(A,B)` (`bearing0.kxx=normal(1e6,5e4)`) as `(key, distribution)`."""
    m = _SPEC.match(text)
    if not m:
        raise InputError(f"{option} {text!r}: expected KEY=normal(MEAN,SD), KEY=lognormal(MEAN,SD) or "
                         "KEY=uniform(LO,HI)")
    key, kind, a, b = m.groups()
    try:
        a, b = float(a), float(b)
    except ValueError:
        raise InputError(f"{option} {text!r}: {a!r} and {b!r} must be numbers") from None
    return key, distribution(kind, a, b, f"{option} {text}")


def correlation_factor(names, correlation):
    """The lower Cholesky factor of the copula's correlation matrix over `names`
    (`correlation`: None, an `(n, n)` array, or `{(name_a, name_b): rho}`)."""
    n = len(names)
    if correlation is None:
        return np.eye(n)
    if isinstance(correlation, dict):
        R = np.eye(n)
        for pair, rho in correlation.items():
            a, b = pair
            for x in (a, b):
                if x not in names:
                    raise InputError(f"correlation: {x!r} is not one of the distributed parameters "
                                     f"({', '.join(names)})")
            i, j = names.index(a), names.index(b)
            if i == j:
                raise InputError(f"correlation: ({a}, {b}) pairs a parameter with itself")
            R[i, j] = R[j, i] = float(rho)
    else:
        R = np.asarray(correlation, dtype=float)
        if R.shape != (n, n):
            raise InputError(f"correlation must be {n} x {n} (one row per parameter), got shape {R.shape}")
    if not np.allclose(R, R.T) or not np.allclose(np.diag(R), 1.0) or np.any(np.abs(R) > 1):
        raise InputError("correlation must be symmetric with a unit diagonal and entries in [-1, 1]")
    try:
        return np.linalg.cholesky(R)
    except np.linalg.LinAlgError:
        raise InputError("correlation is not positive definite") from None
