"""The finite-length plain journal bearing's film force as a smooth, differentiable
interpolant of the project's own Reynolds solver (`_journal_bearing.finite_bearing_state`,
240 x 16 mesh, Swift-Stieber cavitation), for time integration.

**Normalisation.** Local frame: the journal centre at eccentricity ratio `eps` along `+x`,
film `h = c (1 - eps cos(beta))`, `beta` from the line of centres. The Reynolds right side
is `6 mu [a sin(beta) + b cos(beta)]` with `a = e speed - 2 v_t`, `b = -2 v_r` (`v_r`,
`v_t` the journal centre's radial and tangential velocity, `e = eps c`); with
`rho = hypot(a, b)`, `delta = atan2(b, a)` the cavitated problem's positive homogeneity
gives the film force on the journal

    F_local = (12 mu R^4 rho / c^3) Fhat(eps, delta; L/D),   Fhat = (Fhat_r, Fhat_t),

radial (`+x`) and tangential (`+y`) components. `Fhat(eps, delta; L/D)` is
`finite_bearing_state(eps, 0, vx=-sin(delta)/2, vy=(eps - cos(delta))/2, ratio=L/D)[0]`.

**Method.** `Fhat = C * Fhat_short` as complex numbers (`r + i t`): `Fhat_short` is the
short-bearing (Ocvirk, Gümbel cavitation) force `(L/D)^3/3 * integral over sin(beta +
delta) < 0 of sin(beta + delta) (cos beta, sin beta) / (1 - eps cos beta)^3 dbeta`, in
closed form through Sommerfeld's substitution (the integrand becomes a trigonometric
polynomial of degree 2); the correction `C` (-> 1 as `L/D -> 0`) is tabulated by the
solver and interpolated as a tensor product: Chebyshev (24 Gauss-Lobatto nodes) in
`sqrt(1 - eps)` over `0 <= eps <= 0.98`, trigonometric (64 equispaced points) in
`delta`, Chebyshev (7 Gauss-Lobatto nodes) in `L/D` over `[0.25, 1]` (10 752 solves).
`C` is smooth in all three, so the interpolant's error is mostly the solver's own
grid-scale noise (the cavitation boundary moving node by node). Above the table (`eps > 0.98`) `C` is
continued as the power of `t = sqrt(1 - eps)` that matches its value and slope at
`eps = 0.98` (the finite/short ratio tends to a power of `sqrt(1 - eps)`): finite, C1
at the junction, the load under pure rotation growing up to `eps -> 1`.

**Accuracy** (measured against the solver on the same mesh, the tests in
`tests/models/test_finite_film.py`): at 300 random points (any `delta`,
`0.25 <= L/D <= 1`) the error is < 4e-5 of `|Fhat|` for `eps < 0.5`, < 5.3e-4 for
`eps < 0.9`, < 3.5e-3 for `eps <= 0.98`; beyond the table 1 % at `eps = 0.985`, 5 % at
0.99, 17 % at 0.995 (where the 240-point mesh itself resolves the film's minimum with
a few cells). Static load and attitude (`delta = 0`) against
`PlainJournal(method="finite")`: within 2e-4 (eps 0.1-0.97); the eight coefficients by
autodiff: within 0.1 % of the coefficient matrix norm for `eps <= 0.9`, 1.2 % at 0.95.
Cost (CPU): ~18 us per evaluation inside a compiled program (~100 us with its
`jacfwd` in `eps` and `delta`), ~65 us per separate call of `jax.jit(finite_film_force)`
(mostly dispatch), ~3 us per point vmapped over 1000.

The table is `data/finite_film.npz`, written by `tools/make_finite_film_table.py`.
"""

import functools
import importlib.resources

import jax.numpy as jnp
import numpy as np

from ._validate import InputError, is_concrete, show

__all__ = ["finite_film_force", "short_film_force", "RATIO_RANGE"]

RATIO_RANGE = (0.25, 1.0)  # the table's L/D range (the npz holds the same)


@functools.cache
def _table():
    """The npz's interpolation coefficients, loaded on first use (as NumPy; embedded
    as constants where traced)."""
    path = importlib.resources.files("rotorjax.models").joinpath("data/finite_film.npz")
    with path.open("rb") as fh, np.load(fh) as z:
        return {k: np.asarray(z[k]) for k in ("coef", "t_range", "ratio_range")}


def chebyshev_basis(u, n: int):
    """`(T_0(u), ..., T_{n-1}(u))` by the three-term recurrence (smooth at u = +-1)."""
    t = [jnp.ones_like(u), u]
    for _ in range(n - 2):
        t.append(2.0 * u * t[-1] - t[-2])
    return jnp.stack(t[:n])


def fourier_basis(delta, n: int):
    """The real trigonometric basis of the `n`-point (even) periodic interpolant:
    `1, cos(d), sin(d), ..., cos((n/2 - 1) d), sin((n/2 - 1) d), cos(n/2 d)`."""
    m = jnp.arange(1, n // 2, dtype=jnp.float64)
    md = m * delta
    pairs = jnp.stack([jnp.cos(md), jnp.sin(md)], axis=-1).reshape(-1)
    return jnp.concatenate([jnp.ones((1,)), pairs, jnp.cos(0.5 * n * delta)[None]])


def short_film_force(eps, delta, ratio):
    """The short-bearing (Ocvirk) dimensionless force in `Fhat`'s normalisation (module
    docstring): `(L/D)^3 / 3` times the half-arc integral, in closed form. Scalars
    `0 <= eps < 1`; returns (2,) (radial, tangential)."""
    eps = jnp.asarray(eps, dtype=jnp.float64)
    delta = jnp.asarray(delta, dtype=jnp.float64)
    s2 = 1.0 - eps * eps
    s = jnp.sqrt(s2)
    k = eps / (1.0 + s)  # tan(gamma/2) = sqrt((1+e)/(1-e)) tan(beta/2), lifted continuously
    cd, sd = jnp.cos(delta), jnp.sin(delta)

    def lift(b):
        return b + 2.0 * jnp.arctan2(k * jnp.sin(b), 1.0 - k * jnp.cos(b))

    def primitive(g):
        # in gamma the integrand is [s cd sin g + sd (cos g + e)] (cos g + e, s sin g) s / s2^3
        sg, cg, s2g = jnp.sin(g), jnp.cos(g), jnp.sin(2.0 * g)
        a_ss, a_cc, a_sc = 0.5 * g - 0.25 * s2g, 0.5 * g + 0.25 * s2g, 0.5 * sg * sg
        fr = s * cd * a_sc + sd * a_cc + 2.0 * eps * sd * sg - eps * s * cd * cg + eps * eps * sd * g
        ft = s2 * cd * a_ss + s * sd * a_sc - eps * s * sd * cg
        return jnp.stack([fr, ft])

    integral = (primitive(lift(2.0 * jnp.pi - delta)) - primitive(lift(jnp.pi - delta))) / (s2 * s2 * s)
    return ratio ** 3 / 3.0 * integral


def film_correction(eps, delta, ratio):
    """The tabulated correction `C = Fhat / Fhat_short` (complex, as (2,) real, imag);
    beyond the table, continued as a power of `sqrt(1 - eps)`."""
    tab = _table()
    coef = jnp.asarray(tab["coef"])  # (2, n_eps, n_ratio, n_delta)
    t_lo, t_hi = (float(v) for v in tab["t_range"])
    r_lo, r_hi = (float(v) for v in tab["ratio_range"])
    _, n_e, n_r, n_d = coef.shape
    # beyond the table (t < t_lo) the correction is continued as a power of t, C(t_lo)
    # (t / t_lo)^q with the complex exponent q = t C'(t) / C(t) at t_lo (C1 at the junction;
    # the finite/short ratio tends to a power of sqrt(1 - eps) as eps -> 1)
    t = jnp.sqrt(jnp.maximum(1.0 - eps, 1e-30))
    inside = t >= t_lo
    t_in = jnp.where(inside, t, t_lo)
    u = 2.0 * (t_in - t_lo) / (t_hi - t_lo) - 1.0
    v = 2.0 * (ratio - r_lo) / (r_hi - r_lo) - 1.0
    c = coef @ fourier_basis(delta, n_d)       # (2, n_e, n_r)
    c = c @ chebyshev_basis(v, n_r)             # (2, n_e)
    value = c @ chebyshev_basis(u, n_e)         # (2,)
    i = np.arange(n_e)
    c0 = c @ jnp.asarray((-1.0) ** i)           # C and dC/du at u = -1 (t = t_lo)
    dc = c @ jnp.asarray((-1.0) ** (i + 1) * i * i) * (2.0 * t_lo / (t_hi - t_lo))
    den = c0[0] ** 2 + c0[1] ** 2
    qr = (dc[0] * c0[0] + dc[1] * c0[1]) / den
    qi = (dc[1] * c0[0] - dc[0] * c0[1]) / den
    log_t = jnp.log(jnp.where(inside, t_lo, t) / t_lo)
    mag, arg = jnp.exp(qr * log_t), qi * log_t
    cos_a, sin_a = mag * jnp.cos(arg), mag * jnp.sin(arg)
    outside = jnp.stack([c0[0] * cos_a - c0[1] * sin_a, c0[0] * sin_a + c0[1] * cos_a])
    return jnp.where(inside, value, outside)


def finite_film_force(eps, delta, ratio):
    """The finite plain journal's dimensionless film force `Fhat(eps, delta; L/D)` (module
    docstring: `F_local = 12 mu R^4 rho / c^3 * Fhat`).

    **Arguments:** (scalars; `vmap` for more)
    - `eps`: eccentricity ratio, `0 <= eps < 1` (tabulated to 0.98, continued beyond:
      module docstring).
    - `delta`: the right side's phase `atan2(b, a)` (rad, any real).
    - `ratio`: `L/D`, in `[0.25, 1]` (checked when concrete; a traced value outside is
      extrapolated).

    **Returns:** (2,) `(Fhat_r, Fhat_t)`: radial (along the line of centres, away from
    the bearing centre) and tangential components.
    """
    if is_concrete(ratio):
        r = np.asarray(ratio, dtype=np.float64)
        if not np.all((r >= RATIO_RANGE[0] - 1e-12) & (r <= RATIO_RANGE[1] + 1e-12)):
            raise InputError(f"L/D (ratio) must be in [{RATIO_RANGE[0]}, {RATIO_RANGE[1]}] (the finite "
                             f"film table's range), got {show(ratio)}")
    if is_concrete(eps):
        e = np.asarray(eps, dtype=np.float64)
        if not np.all((e >= 0.0) & (e < 1.0)):
            raise InputError(f"eps (eccentricity ratio) must be in [0, 1), got {show(eps)}")
    eps = jnp.asarray(eps, dtype=jnp.float64)
    delta = jnp.asarray(delta, dtype=jnp.float64)
    ratio = jnp.asarray(ratio, dtype=jnp.float64)
    cr, ci = film_correction(eps, delta, ratio)
    sr, st = short_film_force(eps, delta, ratio)
    return jnp.stack([cr * sr - ci * st, cr * st + ci * sr])
