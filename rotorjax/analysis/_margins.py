"""A linear rotor's margins over a speed range, as smooth functions of its parameters
(for design and for reports):

- `log_dec_floor`: a smooth lower bound on the least logarithmic decrement of the
  first `n_modes` modes over `[lo, hi]`. On a grid of speeds, each mode's log
  decrement and its speed derivative (a forward difference, 1e-4 of the spacing)
  give a cubic Hermite interpolant per interval; the interpolant's least value on
  each interval (its ends and the roots of its derivative) catches a dip between
  grid speeds, so the floor does not depend on a dip falling on the grid; the
  Kreisselmeier-Steinhauser soft minimum of those values lies below all of them
  by at most `softness`. The floor is below the least value on the grid, and below
  the true least value up to the interpolation's error, `O(h^4)` in the spacing
  (the tests measure it against a dense grid). Where sorted modes exchange order
  between two speeds the interpolant spans two modes; its least value there is
  still at most the two ends' values.
- API 684's amplification factors and separation margins of 1x critical speeds:
  `amplification_factor` from the mode's damping (`AF = 1 / (2 zeta)`, the
  half-power bandwidth's value for a lightly damped mode, `N_c / (N_2 - N_1)`), and
  `required_separation_margin`: no margin when `AF < 2.5`; otherwise, in percent of
  the operating speed it is nearest, `min(16, 17 (1 - 1 / (AF - 1.5)))` for a
  critical speed below the minimum operating speed and `min(26, 10 + 17 (1 - 1 /
  (AF - 1.5)))` above the maximum continuous speed (API 684 2nd ed., the
  separation-margin criteria it takes from API 617 7th ed. 2.6.2.10);
  `separation_slack`: the margin a critical speed has (negative inside the
  operating range) less the margin it needs.
- `onset_speed`: a stability threshold (the largest real part of the eigenvalues
  crossing zero) followed from a known one to other parameters (`secant_root`).
- `soft_min`: the Kreisselmeier-Steinhauser soft minimum these use.
"""

import jax
import jax.numpy as jnp
import numpy as np

from ..models._contract import require
from ..models._validate import InputError
from ._linear import damped_eigenvalues, system_eigenvalues
from ._roots import secant_root

#: API 684 / API 617: below this amplification factor a critical speed needs no margin
AF_CRITICAL = 2.5

#: the largest log decrement counted (a mode this damped is as good as overdamped)
CAP = 10.0

#: what a mode above `log_dec_floor`'s cut adds to its log decrement (out of the soft minimum)
EXCLUDED = 10.0

#: the forward difference of the log decrements' speed slopes, as a fraction of the grid's spacing
SLOPE_STEP = 1e-4


def soft_min(x, softness):
    """The Kreisselmeier-Steinhauser soft minimum of the values `x`: at most `min(x)`
    and at least `min(x) - softness` (`rho = log(len(x)) / softness`)."""
    x = jnp.ravel(x)
    if x.size == 1:
        return x[0]
    rho = np.log(x.size) / softness
    return -jax.nn.logsumexp(-rho * x) / rho


def _log_decs(rotor, speed, n_modes, cut=None):
    """The log decrements of the first `n_modes` modes at `speed`, at most `CAP` (an
    overdamped pair, `Im lambda = 0`, counts as `CAP`: the slopes stay finite where a
    pair turns overdamped between two speeds); with `cut`, each raised by
    `EXCLUDED x sigmoid((f - cut) / (0.02 cut))` (out of the count above the cut)."""
    lam = damped_eigenvalues(rotor, speed, n_modes)
    ok = jnp.imag(lam) > 0
    d = jnp.minimum(jnp.where(ok, -2 * jnp.pi * jnp.real(lam) / jnp.where(ok, jnp.imag(lam), 1.0), CAP), CAP)
    if cut is None:
        return d
    return d + EXCLUDED * jax.nn.sigmoid((jnp.imag(lam) - cut) / (0.02 * cut))


def _hermite_minima(y0, y1, m0, m1, h):
    """The least value on `[0, 1]` of the cubic Hermite interpolant with end values
    `y0, y1` and slopes `m0, m1` (per unit speed; `h` the interval): the least of the
    values at the ends and at the derivative's roots in the interval (elementwise)."""
    c1 = h * m0
    c2 = 3 * (y1 - y0) - 2 * h * m0 - h * m1
    c3 = 2 * (y0 - y1) + h * m0 + h * m1
    a, b, c = 3 * c3, 2 * c2, c1          # p'(t) = a t^2 + b t + c
    disc = b * b - 4 * a * c
    real = disc > 0
    sq = jnp.sqrt(jnp.where(real, disc, 1.0))
    q = -0.5 * (b + jnp.where(b >= 0, sq, -sq))
    safe_q = jnp.where(q == 0, 1.0, q)
    safe_a = jnp.where(a == 0, 1.0, a)
    r1 = jnp.where(real & (a != 0), q / safe_a, 0.0)
    r2 = jnp.where(real & (q != 0), c / safe_q, 0.0)
    # a linear derivative (a = 0): its root -c / b
    r1 = jnp.where((a == 0) & (b != 0), -c / jnp.where(b == 0, 1.0, b), r1)

    def p(t):
        t = jnp.clip(t, 0.0, 1.0)
        return y0 + t * (c1 + t * (c2 + t * c3))

    # the least of the four (a hard minimum: continuous as a root leaves the interval, and a nearly straight
    # interval's noisy cubic coefficient cannot change how many candidates the soft minimum counts)
    return jnp.min(jnp.stack([y0, y1, p(r1), p(r2)], axis=-1), axis=-1)


def _grid(lo, hi, n_grid):
    if not (np.isfinite(lo) and np.isfinite(hi) and 0 <= lo < hi):
        raise InputError(f"the log decrements' speed range needs 0 <= LO < HI, got ({lo:g}, {hi:g})")
    if int(n_grid) < 2:
        raise InputError(f"n_grid must be >= 2, got {n_grid}")
    return np.linspace(float(lo), float(hi), int(n_grid))


def log_dec_floor(rotor, lo, hi, n_modes, n_grid=33, softness=2e-3, cut=None):
    """A smooth lower bound on the least log decrement of the first `n_modes` modes
    (by frequency, every whirl direction) over speeds `[lo, hi]` (rad/s) of a linear
    rotor (see the module): `n_grid` speeds, the Hermite interpolants' least values,
    their soft minimum within `softness`. Traceable in the rotor's parameters.

    `cut` (`(n_grid,)` damped frequencies, rad/s, from `mode_cut`): count the modes
    below it at each speed instead (of the first `n_modes`, each mode fading out over
    2 % of the cut above it): a design cannot then drop a mode from the count by
    moving its frequency past a neighbour's."""
    speeds = _grid(lo, hi, n_grid)
    if not softness > 0:
        raise InputError(f"softness must be > 0, got {softness}")
    h = float(speeds[1] - speeds[0])
    eps = SLOPE_STEP * h
    # the slopes by a forward difference (eigenvalues only: the floor's own gradient then needs no
    # derivatives of eigenvectors, which JAX does not give for non-symmetric matrices)
    both = jnp.asarray(np.concatenate([speeds, speeds + eps]))
    cuts = None if cut is None else jnp.asarray(np.concatenate([cut, cut]))
    d2 = jax.vmap(lambda s, c: _log_decs(rotor, s, n_modes, c))(both, cuts)
    d, dd = d2[: speeds.size], (d2[speeds.size:] - d2[: speeds.size]) / eps       # (n_grid, n_modes)
    return soft_min(_hermite_minima(d[:-1], d[1:], dd[:-1], dd[1:], h), softness)


def mode_cut(rotor, lo, hi, n_modes, n_grid=33, gap=1.1, extra=4):
    """`(n, n_eigenvalues, cut)` for `log_dec_floor`'s `cut`, from this rotor's Campbell
    diagram on the floor's speeds: the first `n` >= `n_modes` modes whose next mode is
    at least `gap` times higher in frequency at every speed (a near pair, such as the
    two whirls of a mode on anisotropic bearings, is counted whole), the cut halfway
    between them (geometric mean; one frequency for every speed where the two modes'
    frequency bands do not overlap), and `n + extra` eigenvalues to follow (modes
    that may come down below it)."""
    speeds = _grid(lo, hi, n_grid)
    require(rotor, "linear_system", "mode_cut")
    n_all = rotor.n_coordinates
    k = min(n_all, n_modes + 2 * extra)
    f = np.imag(np.asarray(jax.jit(jax.vmap(lambda s: damped_eigenvalues(rotor, s, k)))(jnp.asarray(speeds))))
    n = n_modes
    while n < k and not np.all(f[:, n] >= gap * f[:, n - 1]):
        n += 1
    if n >= k:
        return k, k, None
    below, above = f[:, n - 1].max(), f[:, n].min()
    cut = np.full(speeds.size, np.sqrt(below * above)) if above > below else np.sqrt(f[:, n - 1] * f[:, n])
    return n, min(n_all, n + extra), cut


def amplification_factor(eigenvalue):
    """API 684's amplification factor of a mode from its eigenvalue: `1 / (2 zeta)`,
    `zeta = -Re lambda / |lambda|` (the half-power bandwidth's `N_c / (N_2 - N_1)` of
    a lightly damped mode): infinite for an undamped mode (`Re lambda = 0`, a
    conservative system's, `conservative`) and for an unstable one, which nothing
    damps (it had been negative there, and so asked for no margin)."""
    re = jnp.real(eigenvalue)
    damped = re < 0
    return jnp.where(damped, jnp.abs(eigenvalue) / (-2 * jnp.where(damped, re, -1.0)), jnp.inf)


def required_separation_margin(af, below):
    """API 684's required separation margin (percent of the operating speed) of a
    critical speed with amplification factor `af`, `below` the operating range (else
    above it): 0 when `af < 2.5` (see the module)."""
    base = 17 * (1 - 1 / jnp.maximum(af - 1.5, 1.0))
    need = jnp.where(below, jnp.minimum(16.0, base), jnp.minimum(26.0, 10 + base))
    return jnp.where(af < AF_CRITICAL, 0.0, need)


def separation_slack(critical, af, op_lo, op_hi):
    """The separation margin a 1x critical speed has from the operating range
    `[op_lo, op_hi]` (percent of the nearer end; negative inside the range), less the
    margin API 684 requires of it: `>= 0` meets the requirement. Elementwise."""
    below = critical <= 0.5 * (op_lo + op_hi)
    have = jnp.where(below, 100 * (op_lo - critical) / op_lo, 100 * (critical - op_hi) / op_hi)
    return have - required_separation_margin(af, below)


def api684_margins(rotor, lo, hi, op_lo, op_hi):
    """API 684's table of a linear rotor's forward 1x critical speeds in `[lo, hi]`
    (rad/s) against the operating range `[op_lo, op_hi]`: per critical speed its
    `speed`, `mode` (sorted by frequency), amplification factor `af`
    (`amplification_factor` of the mode's eigenvalue at its critical speed), the
    separation margin it has (`margin`, percent of the nearer end of the range,
    negative inside it), the margin required (`required`), and whether it `meets` it.
    A report's numbers (NumPy floats), not a design's smooth quantity."""
    from ._linear import critical_speeds_1x

    if not 0 < op_lo <= op_hi:
        raise InputError(f"the operating range must satisfy 0 < LO <= HI (rad/s), got {op_lo:g} {op_hi:g}")
    rows = []
    for W, k in critical_speeds_1x(rotor, lo, hi, whirl="forward"):
        af = float(amplification_factor(damped_eigenvalues(rotor, W, k + 1)[k]))
        below = W <= 0.5 * (op_lo + op_hi)
        have = 100 * (op_lo - W) / op_lo if below else 100 * (W - op_hi) / op_hi
        need = float(required_separation_margin(af, below))
        rows.append({"speed": float(W), "mode": int(k), "af": af, "below": bool(below), "margin": float(have),
                     "required": need, "meets": bool(have >= need)})
    return rows


def onset_speed(rotor, guess, frequency, iters=8):
    """The speed near `guess` where the mode of damped frequency nearest `frequency`
    (rad/s) turns unstable (its eigenvalue's real part crosses zero), and that real
    part there (to check it): `secant_root` from a threshold found by
    `stability_thresholds` (the largest real part, `linear_margin`, is kinked where
    another mode leads it: the secant follows the one mode). Traceable; its
    derivative is the implicit function theorem's."""
    return secant_root(lambda r, s: mode_real_part(r, s, frequency), rotor, guess, iters)


def mode_real_part(rotor, speed, frequency):
    """The real part of the eigenvalue of `rotor`'s linear equations at `speed` whose
    damped frequency is nearest `frequency` (rad/s): one mode's stability margin,
    smooth where the largest real part (`linear_margin`) is kinked by another mode
    overtaking it."""
    lam = system_eigenvalues(rotor, speed)
    return jnp.real(lam[jnp.argmin(jnp.abs(jnp.imag(lam) - frequency))])
