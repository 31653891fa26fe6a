"""The one scan-and-bisect root finder, and the derivative of a root by the
implicit function theorem.

Critical speeds, Hopf points, Floquet crossings, the Campbell diagram's meetings
with the 1x line and the published closed forms (model 003's eq. 17, its
pseudo-balanced regime) all locate the zeros of a scalar function `g(x)` of one
parameter the same way:

1. sample `g` on `n_scan` equally spaced points of `[lo, hi]` (per point, or
   vectorised by the caller: `jax.vmap`, `rotorjax.sweep`);
2. bracket every change of sign between two finite samples (a bracket whose left
   sample is exactly zero is left to its left neighbour, so a zero on a sample is
   found once);
3. bisect each bracket to `xtol` (the end whose sign the midpoint shares moves;
   an exact zero counts as the other sign, so a plateau of zeros is approached
   from outside; a non-finite midpoint stops the bracket where it is);
4. where `g` has poles (a sign change through infinity, e.g. the modal sums at the
   bare shaft's frequencies), reject a refined bracket whose `|g|` at the midpoint
   is not small against the samples around it.

A root `x*` of `g(x, p) = 0` moves with a parameter `p` as
`dx*/dp = -(dg/dp) / (dg/dx)` (`root_gradient`, both derivatives by autodiff).
From a known root, `secant_root` follows it to other parameters (pure JAX, vmappable),
with that derivative.
"""

import dataclasses
from typing import Callable

import jax
import jax.numpy as jnp
import numpy as np

from ..models._validate import InputError, as_count, as_numpy, check_span


@dataclasses.dataclass(frozen=True)
class Root:
    """A refined sign change of `g`: `x` the midpoint of the final bracket
    `bracket = (a, b)`, `values = (g(a), g(b))` (`g(b)` None where `b` never moved
    and was not given), `slope` the secant `dg/dx` across the bracket (NaN for a
    bracket of zero width or an unknown end), `residual` `|g(x)|` where evaluated
    (the pole check), else NaN."""

    x: float
    bracket: tuple
    values: tuple
    slope: float
    residual: float = float("nan")


def grid(lo: float, hi: float, n_scan: int) -> np.ndarray:
    """The scan points: `n_scan` equally spaced points from `lo` to `hi`."""
    return np.linspace(lo, hi, n_scan)


def sign_changes(values) -> np.ndarray:
    """Indices `i` where `values[i]` and `values[i + 1]` are finite, of different
    sign, and `values[i] != 0`: the brackets `[x_i, x_{i+1}]` to refine."""
    v = np.asarray(values, dtype=float)
    ok = np.isfinite(v[:-1]) & np.isfinite(v[1:]) & (np.sign(v[:-1]) != np.sign(v[1:])) & (v[:-1] != 0)
    return np.flatnonzero(ok)


def bisect(g: Callable, a: float, b: float, ga: float, gb=None, *, xtol: float = 1e-10, rtol: float = 0.0,
           max_iter=None, secant=False, ftol=0.0) -> Root:
    """Bisect `g` on `[a, b]` (`ga = g(a)`, `gb = g(b)` or None) until the bracket
    is at most `max(xtol, rtol |b|)` wide, `max_iter` halvings are done, no
    floating-point midpoint is left, or a midpoint is non-finite. `g(x)` is called
    with a numpy float64 and must return something `float()` accepts. `secant`
    (with `gb`): each trial the bracket's secant point instead of its midpoint, the
    end kept twice in a row weighed by half (Illinois' false position: superlinear,
    ten to twenty calls where halving to 1e-14 takes forty-six; for a costly `g`);
    it stops at a trial point where `|g| <= ftol` too (the bracket closed on it)."""
    a, b, ga = np.float64(a), np.float64(b), float(ga)
    gb = None if gb is None else float(gb)
    wa, wb, kept = ga, gb, None          # the secant's weights (Illinois), and the end kept last
    it = 0
    while b - a > max(xtol, rtol * abs(b)) and (max_iter is None or it < max_iter):
        c = 0.5 * (a + b)
        if secant and gb is not None and wa != wb:
            c = np.float64(b - wb * (b - a) / (wb - wa))
            c = c if a < c < b else 0.5 * (a + b)
        if not a < c < b:
            break
        gc = float(g(c))
        if not np.isfinite(gc):
            break
        if abs(gc) <= ftol or (gc == 0.0 and secant):
            a = b = c
            ga = gb = gc
            break
        if np.sign(gc) == np.sign(ga):
            a, ga, wa = c, gc, gc
            wb = wb if kept != "b" or wb is None else 0.5 * wb
            kept = "b"
        else:
            b, gb, wb = c, gc, gc
            wa = wa if kept != "a" else 0.5 * wa
            kept = "a"
        it += 1
    slope = float((gb - ga) / (b - a)) if gb is not None and b > a else float("nan")
    return Root(x=float(0.5 * (a + b)), bracket=(float(a), float(b)), values=(ga, gb), slope=slope)


def find_roots(g: Callable, lo: float, hi: float, n_scan: int = 200, *, values=None, xtol: float = 1e-10,
               rtol: float = 0.0, max_iter=None, pole_tol=None, progress: bool = False,
               return_scan: bool = False):
    """Every sign change of `g` on `[lo, hi]`, bisected (see the module docstring).

    **Arguments:**

    - `g`: the function, called per point in the bisection (a numpy float64 in,
      something `float()` accepts out; jit it first if it is a JAX function).
    - `lo`, `hi`, `n_scan`: the scan, `grid(lo, hi, n_scan)`.
    - `values`: the samples of `g` on that grid: None (`g` called at every point),
      an array of `n_scan` values, or a function of the grid array returning them
      (vectorised: e.g. `lambda x: jax.vmap(g)(x)`, or through `rotorjax.sweep`).
      Non-finite samples are skipped.
    - `xtol`, `rtol`, `max_iter`: bisection to a bracket of `max(xtol, rtol |b|)`
      (see `bisect`).
    - `pole_tol`: None, or reject a refined sign change unless
      `|g(x)| < pole_tol (1 + |g(x_i)| + |g(x_{i+1})|)` (a sign change through a
      pole; kept roots carry `residual = |g(x)|`).
    - `progress`: a tqdm bar over the bisections.
    - `return_scan`: also return the scan `(x, values)`.

    **Returns:** the `Root`s in increasing `x` (with `return_scan`,
    `(roots, (x, values))`); `[]` when no sign change is found.
    """
    if not callable(g):
        raise InputError(f"g must be a function of one number, got {g!r}")
    lo, hi = check_span("lo", lo, "hi", hi)
    n_scan = as_count("n_scan", n_scan, minimum=2)
    xtol = float(as_numpy("xtol", xtol, sign="nonnegative", shape=()))
    rtol = float(as_numpy("rtol", rtol, sign="nonnegative", shape=()))
    if max_iter is not None:
        max_iter = as_count("max_iter", max_iter, minimum=0)
    if pole_tol is not None:
        pole_tol = float(as_numpy("pole_tol", pole_tol, sign="positive", shape=()))
    x = grid(lo, hi, n_scan)
    if values is None:
        v = np.array([float(g(xi)) for xi in x])
    else:
        v = values(x) if callable(values) else values
        v = np.asarray(v, dtype=float)
        if v.shape != (n_scan,):
            raise InputError(f"values must hold one sample of g per scan point, shape ({n_scan},), got shape "
                             f"{v.shape}")
    brackets = sign_changes(v)
    if progress and brackets.size:
        from tqdm.auto import tqdm

        brackets = tqdm(brackets, desc="bisection", unit="root", leave=False)
    roots = []
    for i in brackets:
        r = bisect(g, x[i], x[i + 1], v[i], v[i + 1], xtol=xtol, rtol=rtol, max_iter=max_iter)
        if pole_tol is not None:
            res = abs(float(g(np.float64(r.x))))
            if not res < pole_tol * (1 + abs(v[i]) + abs(v[i + 1])):
                continue
            r = dataclasses.replace(r, residual=res)
        roots.append(r)
    return (roots, (x, v)) if return_scan else roots


def root_gradient(g2: Callable, x, p):
    """`dx*/dp` of the root `x*` of `g2(x, p) = 0` through `(x, p)`, by the
    implicit function theorem: `-(dg2/dp) / (dg2/dx)`, both by autodiff. `p` may be
    a pytree of parameters (the result has its structure). Traceable (no `float()`);
    infinite where the root is not simple (`dg2/dx = 0`)."""
    if not callable(g2):
        raise InputError(f"g2 must be a function g2(x, p), got {g2!r}")
    x = jnp.asarray(x, dtype=jnp.float64)
    if x.shape != ():
        raise InputError(f"x (the root) must be a scalar, got shape {x.shape}")
    p = jax.tree_util.tree_map(lambda v: jnp.asarray(v, dtype=jnp.float64), p)
    gx, gp = jax.grad(g2, argnums=(0, 1))(x, p)
    return jax.tree_util.tree_map(lambda d: -d / gx, gp)


def frozen_tree(params):
    """`params` (a pytree) with every array's derivative stopped: the iterations of a
    root found by the implicit function theorem run on these."""
    return jax.tree_util.tree_map(lambda v: jax.lax.stop_gradient(v) if isinstance(v, jax.Array) else v, params)


def secant_root(g: Callable, params, guess, iters: int = 6, slope0=None, with_step=False):
    """The root near `guess` of `g(params, x)` (a scalar function, pure JAX), followed
    as `params` (a pytree) change, and the residual there: `(x*, g(params, x_n))`.

    At most `iters` evaluations of `g` on `params` without derivatives and one more,
    all at one place in the program: one `while_loop` whose body evaluates `g` once (a
    compiled program holds a copy of `g` for each place it is called, and compiling is
    most of the cost). The first evaluation is at `guess`; the second a forward
    difference from it (`1e-6` of it), or, given `slope0`, a Newton step with that slope;
    then secant steps (superlinear) from the last two, each keeping the last usable
    slope where the secant's is not (not finite, zero, of the other sign), until a step
    is within 1e-12 of `x` (no step more then: a secant through two points that close
    is the residual's rounding noise, and it threw a converged root far away) or
    `iters` evaluations. `x*` is the last step's end, the residual `g` where it
    started; the one more evaluation is a forward difference from there, the slope of
    the derivative. `g` is evaluated once more, on `params` as given, where the last
    step started: `x*`'s derivative is the implicit function theorem's `-(dg/dp) /
    (dg/dx)`, with no derivatives through the iterations, in either mode (two copies of
    `g` in a program, where there were three: model 000's stable range, 25 941
    operations with three, 10 039 with two and the regime's own copies cut, 2026-12-06).
    Vmappable over designs. A slope of the wrong sign or a root
    that has gone leaves the residual large: the caller checks it (`with_step`: also
    the last step's size, which measures it in `x`'s units)."""
    x0 = jnp.float64(guess)
    frozen = frozen_tree(params)
    s0 = jnp.float64(jnp.nan if slope0 is None else slope0)

    def body(c):
        k, xp, gp, x, slope, phase, root, res, step, origin = c
        gx = g(frozen, x)
        secant = (gx - gp) / jnp.where(x == xp, 1.0, x - xp)
        usable = (k > 0) & (x != xp) & jnp.isfinite(secant) & (secant != 0) & (
            ~jnp.isfinite(slope) | (jnp.sign(secant) == jnp.sign(slope)) | (phase == 1))
        slope = jnp.where(usable, secant, slope)
        newton = x - gx / jnp.where(jnp.isfinite(slope) & (slope != 0), slope, 1.0)
        probe = x + 1e-6 * jnp.maximum(jnp.abs(x), 1.0)           # a forward difference's second point
        nxt = jnp.where((k == 0) & ~jnp.isfinite(slope), probe, newton)
        iterating = phase == 0
        moved = jnp.abs(nxt - x)
        # converged (or out of steps): the answer is this step's end; one more evaluation, a forward
        # difference from the point the step started at, is the slope of the derivative
        last = iterating & ((moved <= 1e-12 * jnp.maximum(jnp.abs(nxt), 1.0)) | (k + 1 >= iters))
        return (k + 1, x, gx, jnp.where(last, probe, nxt), slope, jnp.where(iterating, last.astype(int), 2),
                jnp.where(iterating, nxt, root), jnp.where(iterating, gx, res), jnp.where(iterating, moved, step),
                jnp.where(iterating, x, origin))

    nan = jnp.float64(jnp.nan)
    c = jax.lax.while_loop(lambda c: c[5] < 2, body, (0, x0, nan, x0, s0, 0, x0, nan, nan, x0))
    start, root, residual, step, slope = c[9], c[6], c[7], c[8], c[4]
    # the derivative: g once more where the last step started, on `params` as given (its value is the loop's,
    # so the root is unchanged): -(dg/dp) / slope, in forward or reverse mode, whichever g allows (a Floquet
    # margin's ODE solve only reverse, a custom rule here would need forward)
    x = root - (g(params, start) - residual) / slope
    if with_step:
        return x, residual, step
    return x, residual


def bisect_batched(g: Callable, a, b, ga, index, *, xtol: float = 1e-10, rtol: float = 0.0, args=()) -> np.ndarray:
    """`bisect` of many brackets at once, in one compiled loop: bracket `j` is
    `[a[j], b[j]]` with `ga[j] = g(a[j], index[j], *args)`, and `g` is a traceable
    function of one point, an integer label (a mode number) and `args` (traced: a
    rotor). Each halving evaluates `g` at every midpoint in one vmapped call; the
    loop runs until the widest bracket is `max(xtol, rtol |b|)` wide (the same rule as
    `bisect`: the end whose sign the midpoint shares moves, an exact zero counts as
    the other sign, a non-finite midpoint stops its bracket). Returns the final
    brackets' midpoints."""
    import equinox as eqx

    a, b, ga = (np.asarray(v, dtype=np.float64) for v in (a, b, ga))
    index = np.asarray(index, dtype=np.int64)
    if a.size == 0:
        return np.zeros(0)
    tol = np.maximum(xtol, rtol * np.abs(b))
    halvings = int(np.clip(np.ceil(np.log2(np.max((b - a) / tol))), 0, 200))
    size = max(8, 1 << (a.size - 1).bit_length())   # padded: a few compiled programs for any count
    pad = np.minimum(np.arange(size), a.size - 1)
    out = _bisect_loop(eqx.Partial(g), jnp.asarray(a[pad]), jnp.asarray(b[pad]), jnp.asarray(ga[pad]),
                       jnp.asarray(index[pad]), jnp.asarray(halvings), args)
    return np.asarray(out)[: a.size]


def _bisect_loop_impl(g, a, b, ga, index, halvings, args):
    def body(_, carry):
        a, b, ga = carry
        c = 0.5 * (a + b)
        gc = jax.vmap(lambda x, i: g(x, i, *args))(c, index)
        ok = jnp.isfinite(gc) & (a < c) & (c < b)
        same = jnp.sign(gc) == jnp.sign(ga)
        return jnp.where(ok & same, c, a), jnp.where(ok & ~same, c, b), jnp.where(ok & same, gc, ga)

    a, b, _ = jax.lax.fori_loop(0, halvings, body, (a, b, ga))
    return 0.5 * (a + b)


def _jit_loop():
    import equinox as eqx

    return eqx.filter_jit(_bisect_loop_impl)


_bisect_loop = _jit_loop()
