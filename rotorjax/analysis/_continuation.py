"""Numerical continuation: branches of stationary regimes in one parameter, with
folds, Hopf points and branch points detected and refined; and curves in two
parameters (stability boundaries, fold curves).

One engine, `trace_curve`, follows an implicit curve `G(x) = 0`, `G: R^{k+1} -> R^k`,
by pseudo-arclength: tangent from the null space of `G'(x)` (autodiff), Euler
predictor, Newton corrector on `[G(x); t . (x - x_pred)] = 0`, step adapted to the
corrector's effort. On top of it:

- `continue_branch(F, u0, p0)`: `x = (u, p)`, `G = F(u, p)` (a stationary regime
  of a first-order field, e.g. the rotating-frame field); along the branch the
  eigenvalues of `F_u` give stability; a sign change of the tangent's `p`
  component is a fold (refined on `{F = 0, det F_u = 0}`), of the bordered
  determinant `det [F_u F_p; t^T]` a branch point, and a change in the number of
  unstable eigenvalues through a complex pair a Hopf point (refined by bisection
  along the branch on the pair's real part).
- `trace_boundary(sigma, p0)`: `x = (p1, p2)`, `G = sigma(p1, p2)`: a stability
  boundary, `sigma` the margin of a regime (largest real part, or Floquet
  exponent) as a function of two parameters; `boundary_sensitivity` gives its
  normal shift per unit of a third parameter by the implicit function theorem.
- `fold_curve(F, u0, p0)`: `x = (u, p1, p2)`, `G = (F, det F_u)`.

Curves are traced both ways from the start unless a direction is given; each
end stops for a stated reason: on the edge of the parameter box (the last step
is cut to land on it), a closed loop, `max_points`, a corrector that fails at
the smallest step, or a non-finite function value. Steps are cut where the
tangent turns, so folds are drawn as curves, not kinks.

Every result carries its checks: the residual of the defining system at every
point, the step history, and why each end stopped.
"""

import dataclasses
from typing import Callable

import jax
import jax.numpy as jnp
import numpy as np


@dataclasses.dataclass
class Curve:
    """Points `x` (rows) of an implicit curve, with `residuals` (max |G|), the
    arclength steps taken (`steps[i]`: from `x[i-1]` to `x[i]`, 0 at the first
    point), the corrector's iterations, and why it ends:

    - `stops`: the reasons at its two ends, `(at x[0], at x[-1])`. Traced both
      ways from the start, `x[0]` is the end reached towards decreasing last
      coordinate at the start (the "low end"), `x[-1]` the "high end"; traced one
      way, `x[0]` is the start and `stops[0] == "start"`.
    - `stopped`: one line for both: `"low end: <reason>; high end: <reason>"`
      (just `"closed loop"` for a closed loop), or the far end's reason when
      traced one way.
    - `start`: the index of the starting point in `x`.

    A reason is one of `"box edge (<name> = <bound>)"` (the last point lies on
    that bound), `"closed loop"` (`x[-1]` repeats `x[0]`), `"max_points
    reached"`, `"corrector failed (step below ds_min) at <point>"` and
    `"non-finite <G> at <point>"`."""

    x: np.ndarray
    residuals: np.ndarray
    steps: np.ndarray
    iterations: np.ndarray
    stopped: str
    stops: tuple = ()
    start: int = 0


def _tangent(jac):
    """Unit null vector of a `k x (k+1)` Jacobian."""
    q, _ = np.linalg.qr(jac.T, mode="complete")
    return q[:, -1]


class _Front:
    """One direction of tracing: its points so far, the tangent at the last one
    (pointing the way it goes), the next step, and its stop reason (None while
    it goes on)."""

    def __init__(self, x0, r0, t0, ds):
        self.xs, self.res, self.steps, self.iters = [x0.copy()], [r0], [0.0], [0]
        self.t, self.ds, self.stop = t0, ds, None
        self.nonfinite = 0     # successive steps that met non-finite values of G


_MAX_TURN_HALVINGS = 6     # at a singular point the tangent may jump: accept the step after this many
_MAX_NONFINITE = 3         # successive steps cut short by non-finite G: the curve runs into where G is undefined


def _trace(G, x0, *, ds, ds_min, ds_max, max_points, tol, direction, bounds, max_newton, start_tol, gradient,
           fd_step, gtol, max_turn, names, what, progress=False) -> Curve:
    Gj = jax.jit(G)
    if gradient == "autodiff":
        Jj = jax.jit(jax.jacfwd(G))

        def jac(x):
            return np.asarray(Jj(jnp.asarray(x)))
    elif gradient == "fd":
        def jac(x):
            cols = []
            for i in range(x.size):
                h = fd_step * max(1.0, abs(x[i]))
                e = np.zeros_like(x)
                e[i] = h
                cols.append((np.asarray(Gj(jnp.asarray(x + e))) - np.asarray(Gj(jnp.asarray(x - e)))) / (2 * h))
            return np.stack(cols, axis=-1).reshape(-1, x.size)
    else:
        raise ValueError(f"gradient must be 'autodiff' or 'fd', got {gradient!r}")

    def g(x):
        return np.atleast_1d(np.asarray(Gj(jnp.asarray(x)), dtype=float))

    x0 = np.asarray(x0, dtype=float)
    m = x0.size
    names = [f"x[{i}]" for i in range(m)] if names is None else list(names)
    if len(names) != m:
        raise ValueError(f"names has {len(names)} entries for a point of {m} coordinates")
    shown = [i for i in range(m) if names[i] is not None] or list(range(m))

    def at(x):
        s = ", ".join(f"{names[i] or f'x[{i}]'} = {x[i]:.8g}" for i in shown)
        return s if len(shown) == 1 else f"({s})"

    r0 = float(np.max(np.abs(g(x0))))
    if not np.isfinite(r0) or r0 > start_tol:
        raise ValueError(f"the starting point is not on the curve: residual {r0:.3e} > {start_tol:.1e} "
                         "(correct it first, e.g. with Newton at fixed parameters)")
    # NaN (or an infinite value) in `bounds` means no bound on that coordinate
    lo, hi = np.full(m, -np.inf), np.full(m, np.inf)
    if bounds is not None:
        b_lo, b_hi = (np.broadcast_to(np.asarray(b, dtype=float), (m,)) for b in bounds)
        lo = np.where(np.isnan(b_lo), -np.inf, b_lo)
        hi = np.where(np.isnan(b_hi), np.inf, b_hi)
        for i in range(m):
            if lo[i] > hi[i]:
                raise ValueError(f"empty box: lower bound {lo[i]} > upper bound {hi[i]} for {names[i] or i}")
        if np.any(x0 < lo) or np.any(x0 > hi):
            raise ValueError(f"the starting point {x0} lies outside the bounds")
    boxed = bool(np.any(np.isfinite(lo) | np.isfinite(hi)))
    eps = 1e-12 * np.maximum(1.0, np.maximum(np.abs(np.where(np.isfinite(lo), lo, 0.0)),
                                             np.abs(np.where(np.isfinite(hi), hi, 0.0))))

    def outside(y):
        return bool(np.any(y < lo - eps) or np.any(y > hi + eps))

    def edge(k, b):
        return f"box edge ({names[k] or f'x[{k}]'} = {float(b)!r})"

    def to_box(x, t):
        """The step along `t` from `x` to the first bound it meets: (step, coordinate, bound)."""
        best = (np.inf, None, None)
        for i in range(m):
            if t[i] > 0 and np.isfinite(hi[i]):
                s = max(0.0, (hi[i] - x[i]) / t[i])
                best = min(best, (s, i, hi[i]), key=lambda z: z[0])
            elif t[i] < 0 and np.isfinite(lo[i]):
                s = max(0.0, (lo[i] - x[i]) / t[i])
                best = min(best, (s, i, lo[i]), key=lambda z: z[0])
        return best

    def correct(y, row, c):
        """Newton on `[G(y); row . y - c] = 0` from `y`: `(y, iterations, max |G|, None)` when accepted,
        `(None, iterations, None, bad)` when not, `bad` the point where `G` (or its Jacobian) was not
        finite, if that is why."""
        for it in range(1, max_newton + 1):
            gy = g(y)
            if not np.all(np.isfinite(gy)):
                return None, it, None, y
            J = jac(y)
            if not np.all(np.isfinite(J)):
                return None, it, None, y
            try:
                dy = np.linalg.solve(np.vstack([J, row[None, :]]), -np.concatenate([gy, [row @ y - c]]))
            except np.linalg.LinAlgError:
                return None, it, None, None
            y = y + dy
            if not np.all(np.isfinite(y)):
                return None, it, None, None
            step = np.max(np.abs(dy)) / max(1.0, np.max(np.abs(y)))
            if step <= tol or (it == max_newton and step <= 1e3 * tol):
                r = float(np.max(np.abs(g(y))))
                if not np.isfinite(r):
                    return None, it, None, y
                return (y, it, r, None) if r <= gtol else (None, it, None, None)
        return None, max_newton, None, None

    def oriented_tangent(y, t):
        tn = _tangent(jac(y))
        tn = tn if tn @ t >= 0 else -tn
        return tn, float(np.arccos(np.clip(tn @ t, -1.0, 1.0)))

    def land(f, x, y0, k, b, reach, may_refuse):
        """Correct `y0` onto the curve with coordinate `k` fixed at the bound `b`: the end point on the
        box edge, if the curve reaches it within about `reach` (and, when `may_refuse`, without
        turning by more than `max_turn`). Returns "landed", "turns" or "missed"."""
        z, it, r, _ = correct(y0, np.eye(m)[k], b)
        if z is None:
            return "missed"
        z[k] = b
        if outside(z) or (z - x) @ f.t <= 0 or np.linalg.norm(z - x) > 2 * reach:
            return "missed"
        tz, angle = oriented_tangent(z, f.t)
        if angle > max_turn and may_refuse:
            return "turns"
        f.xs.append(z)
        f.res.append(r)
        f.steps.append(float(np.linalg.norm(z - x)))
        f.iters.append(it)
        f.t, f.stop = tz, edge(k, b)
        return "landed"

    def closes(x, y, t, other):
        """Whether the chord `x -> y` (tangent `t` at `y`) runs into the other front's last point,
        that front coming the other way round: the curve is a closed loop."""
        p, d = other.xs[-1], y - x
        dd = d @ d
        if dd == 0:
            return False
        s = (p - x) @ d / dd
        return 0 < s <= 1.1 and np.linalg.norm(x + s * d - p) <= 0.1 * np.sqrt(dd) and t @ other.t < -0.5

    def advance(f, other):
        x, ds, t = f.xs[-1], f.ds, f.t
        s_edge, k, b = to_box(x, t)
        if s_edge <= 1e-12 * max(1.0, np.max(np.abs(x))):
            f.stop = edge(k, b)           # on the edge, heading out
            return
        bad, turns = None, 0
        while True:
            if ds < ds_min:
                f.stop = (f"non-finite {what} at {at(bad)}" if bad is not None else
                          f"corrector failed (step below ds_min) at {at(x)}")
                return
            may_refuse = turns < _MAX_TURN_HALVINGS and ds / 2 >= ds_min
            s_edge, k, b = to_box(x, t)
            if s_edge <= ds:
                # the predictor would leave the box: try the edge it meets
                how = land(f, x, x + s_edge * t, k, b, s_edge, may_refuse)
                if how == "landed":
                    return
                if how == "turns":
                    turns += 1
                    ds = s_edge / 2
                    continue
            xp = x + ds * t
            y, it, r, why = correct(xp, t, t @ xp)
            bad = why if why is not None else bad
            if y is None:
                ds /= 2
                continue
            if outside(y):
                # the curve crosses the box between x and y: land where the chord first crosses it
                crossed = {i: (hi[i] if y[i] > hi[i] else lo[i]) for i in range(m)
                           if y[i] > hi[i] + eps[i] or y[i] < lo[i] - eps[i]}
                k = min(crossed, key=lambda i: (crossed[i] - x[i]) / (y[i] - x[i]))
                b = crossed[k]
                how = land(f, x, x + (b - x[k]) / (y[k] - x[k]) * (y - x), k, b,
                           max(ds, float(np.linalg.norm(y - x))), may_refuse)
                if how == "landed":
                    return
                turns += how == "turns"
                ds /= 2
                continue
            tn, angle = oriented_tangent(y, t)
            if angle > max_turn and may_refuse:
                turns += 1
                ds /= 2
                continue
            if closes(x, y, tn, other):
                p = other.xs[-1].copy()
                f.xs.append(p)
                f.res.append(float(np.max(np.abs(g(p)))))
                f.steps.append(float(np.linalg.norm(p - x)))
                f.iters.append(it)
                f.t, f.stop = tn, "closed loop"
                if other.stop is None:
                    other.stop = "closed loop"
                return
            f.xs.append(y)
            f.res.append(r)
            f.steps.append(ds)
            f.iters.append(it)
            f.t = tn
            if bad is not None:
                # a longer step met non-finite values: do not grow towards them, and stop rather
                # than creep up to where G is undefined in ever shorter steps
                f.nonfinite += 1
                f.ds = ds
                if f.nonfinite >= _MAX_NONFINITE:
                    f.stop = f"non-finite {what} at {at(bad)}"
                return
            f.nonfinite = 0
            # grow with an easy corrector and a straight curve; shrink where it works hard or turns
            grow = 1.5 if it <= 3 else 1.0 if it <= 5 else 0.5
            if angle > 0:
                grow = min(grow, 0.8 * max_turn / angle)
            f.ds = min(max(ds * max(grow, 0.25), ds_min), ds_max)
            return

    t0 = _tangent(jac(x0))
    both = direction is None
    if not both:
        t0 = t0 if t0 @ np.asarray(direction, dtype=float) >= 0 else -t0
    elif t0[-1] < 0:
        t0 = -t0
    hi_f = _Front(x0, r0, t0, ds)
    lo_f = _Front(x0, r0, -t0, ds)
    if not both:
        lo_f.stop = "start"           # stands still: the start, for the closed-loop test
    fronts = [f for f in (hi_f, lo_f) if f.stop is None]
    from tqdm.auto import tqdm

    bar = tqdm(total=max_points, desc="continuation", unit="point", disable=not progress, leave=False)
    while any(f.stop is None for f in fronts):
        bar.update(len(hi_f.xs) + len(lo_f.xs) - 1 - bar.n)
        for f in fronts:
            if f.stop is not None:
                continue
            if len(hi_f.xs) + len(lo_f.xs) - 1 >= max_points:
                f.stop = "max_points reached" + ("" if boxed else " (no parameter box given)")
                continue
            advance(f, lo_f if f is hi_f else hi_f)
    bar.close()
    rev = slice(None, 0, -1)
    x = np.asarray(lo_f.xs[rev] + hi_f.xs)
    res = np.asarray(lo_f.res[rev] + hi_f.res)
    steps = np.asarray([0.0] + lo_f.steps[1:][::-1] + hi_f.steps[1:])
    iters = np.asarray([0] + lo_f.iters[1:][::-1] + hi_f.iters[1:])
    stops = (lo_f.stop, hi_f.stop)
    if not both:
        stopped = hi_f.stop
    elif stops == ("closed loop", "closed loop"):
        stopped = "closed loop"
    else:
        stopped = f"low end: {stops[0]}; high end: {stops[1]}"
    return Curve(x=x, residuals=res, steps=steps, iterations=iters, stopped=stopped, stops=stops,
                 start=len(lo_f.xs) - 1)


def trace_curve(G: Callable, x0, ds=0.01, ds_min=1e-9, ds_max=0.2, max_points=200, tol=1e-11,
                direction=None, bounds=None, max_newton=8, start_tol=1e-7, gradient="autodiff",
                fd_step=1e-6, gtol=1e-8, max_turn=0.2, names=None) -> Curve:
    """Follow `G(x) = 0` from `x0` (see the module docstring).

    **Arguments:**

    - `direction`: None (default) traces both ways from `x0` and joins the halves
      into one curve, ordered from the end reached towards decreasing last
      coordinate to the end reached towards increasing (`x0` once, at
      `Curve.start`). A vector traces one way only, the first tangent along it.
    - `bounds`: `(lo, hi)` arrays for `x` (NaN or an infinite value: no bound).
      Where a step would leave them, it is cut so that the curve's last point
      lies on the bound it meets first (Newton with that coordinate fixed), and
      that end stops with `"box edge (<name> = <bound>)"`.
    - `max_points`: at most this many points in all (both halves together).
    - `gradient`: "autodiff" or "fd" (central differences with relative `fd_step`,
      for `G` whose derivatives autodiff cannot give reliably, e.g. Floquet margins).
    - A corrected point is accepted when Newton's last step is below `tol`
      (relative; or below `1e3 tol` at the iteration cap: the noise floor of `G`)
      and `max |G| <= gtol`. The step grows at most 1.5x per point, less when the
      corrector needs more than 3 iterations or the tangent turns; a step whose
      tangent turns by more than `max_turn` (radians) is halved and retried.
    - `names`: one per coordinate, for the stop reasons (None: not shown).
    - An end stops with "non-finite G at <point>" when the steps from it fail on
      non-finite values of `G` down to `ds_min`, or three successive steps are cut
      short by them (the curve runs into a region where `G` is undefined).

    **Returns:** a `Curve`; its `stops` say why each end is where it is.

    A start with `max |G(x0)| > start_tol` raises a ValueError stating the residual.
    """
    return _trace(G, x0, ds=ds, ds_min=ds_min, ds_max=ds_max, max_points=max_points, tol=tol,
                  direction=direction, bounds=bounds, max_newton=max_newton, start_tol=start_tol,
                  gradient=gradient, fd_step=fd_step, gtol=gtol, max_turn=max_turn, names=names, what="G")


@dataclasses.dataclass
class Branch:
    """A branch of stationary regimes `u(p)`: `u`, `p`, the largest real part of
    the eigenvalues (`margin`) and stability at each point, the detected `events`
    (kind "fold", "hopf" or "branch_point", with the refined `p`, `u`, the
    residual of its defining system, and for Hopf the frequency), and the curve's
    checks."""

    u: np.ndarray
    p: np.ndarray
    margin: np.ndarray
    stable: np.ndarray
    events: list
    curve: Curve

    @property
    def stopped(self) -> str:
        """Why the branch ends where it does (both ends when traced both ways; see `Curve`)."""
        return self.curve.stopped

    @property
    def stops(self) -> tuple:
        """The stop reasons at the branch's two ends, `(at p[0], at p[-1])` (see `Curve`)."""
        return self.curve.stops

    def as_dict(self):
        return {"p": self.p.tolist(), "margin": self.margin.tolist(), "stable": self.stable.tolist(),
                "events": [{k: (v.tolist() if isinstance(v, np.ndarray) else v) for k, v in e.items()}
                           for e in self.events],
                "residual_max": float(self.curve.residuals.max()), "stopped": self.curve.stopped,
                "stops": list(self.curve.stops), "start": int(self.curve.start), "n_points": int(self.p.size)}


def _newton(fun, x0, tol=1e-12, max_iter=30):
    x = jnp.asarray(x0, dtype=jnp.float64)
    J = jax.jit(jax.jacfwd(fun))
    f = jax.jit(fun)
    for _ in range(max_iter):
        dx = jnp.linalg.solve(J(x), -f(x))
        x = x + dx
        if float(jnp.max(jnp.abs(dx))) <= tol * max(1.0, float(jnp.max(jnp.abs(x)))):
            break
    return np.asarray(x), float(jnp.max(jnp.abs(f(x))))


def continue_branch(F: Callable, u0, p0, p_bounds=(-np.inf, np.inf), ds=0.01, ds_max=0.2, max_points=300,
                    tol=1e-11, direction=None, start_tol=1e-8, ds_min=1e-9, max_turn=0.2, name="p",
                    progress=False) -> Branch:
    """One-parameter continuation of `F(u, p) = 0` from a solution `(u0, p0)`
    within `p_bounds` (a missing bound: NaN or infinite).

    `direction`: None (default) traces both ways from the start, the points
    ordered from the end reached towards decreasing `p` to the end reached
    towards increasing `p`; `1` or `-1` traces one way, towards increasing or
    decreasing `p`. An end inside `p_bounds`' edge lands on it exactly. `name`
    names `p` in the stop reasons (`Branch.stops`, e.g. "box edge (nu = 4.0)").
    At most `max_points` points in all."""
    u0 = np.asarray(u0, dtype=float)
    n = u0.size

    def G(x):
        return F(x[:n], x[n])

    lo = np.full(n + 1, np.nan)
    hi = np.full(n + 1, np.nan)
    lo[n], hi[n] = p_bounds
    d = None
    if direction is not None:
        d = np.zeros(n + 1)
        d[n] = direction
    curve = _trace(G, np.concatenate([u0, [p0]]), ds=ds, ds_min=ds_min, ds_max=ds_max, max_points=max_points,
                   tol=tol, direction=d, bounds=(lo, hi), max_newton=8, start_tol=start_tol, gradient="autodiff",
                   fd_step=1e-6, gtol=1e-8, max_turn=max_turn, names=[None] * n + [name], what="F",
                   progress=progress)
    Jx = jax.jit(jax.jacfwd(G))   # [F_u F_p], one Jacobian per point

    def Fu(u, p):
        return Jx(jnp.concatenate([jnp.asarray(u), jnp.atleast_1d(p)]))[:, :n]

    xs = curve.x
    jacs = [np.asarray(Jx(jnp.asarray(x))) for x in xs]
    eig = [np.linalg.eigvals(J[:, :n]) for J in jacs]
    margin = np.array([e.real.max() for e in eig])
    n_unstable = np.array([int(np.sum(e.real > 0)) for e in eig])
    tangents = np.array([_tangent(J) for J in jacs])
    for i in range(1, len(tangents)):
        if tangents[i] @ tangents[i - 1] < 0:
            tangents[i] = -tangents[i]
    bordered = np.array([np.linalg.det(np.vstack([J, t[None, :]])) for J, t in zip(jacs, tangents)])
    events = []
    for i in range(len(xs) - 1):
        a, b = xs[i], xs[i + 1]
        if np.sign(tangents[i][n]) != np.sign(tangents[i + 1][n]):
            def ext(z):
                return jnp.concatenate([F(z[:n], z[n]), jnp.linalg.det(jax.jacfwd(F)(z[:n], z[n]))[None]])
            z, r = _newton(ext, 0.5 * (a + b))
            events.append({"kind": "fold", "p": float(z[n]), "u": z[:n], "residual": r, "between": [i, i + 1]})
        elif np.sign(bordered[i]) != np.sign(bordered[i + 1]):
            events.append({"kind": "branch_point", "p": float(0.5 * (a[n] + b[n])), "u": 0.5 * (a[:n] + b[:n]),
                           "residual": float(max(curve.residuals[i], curve.residuals[i + 1])),
                           "between": [i, i + 1], "note": "located to the step; not refined"})
        if n_unstable[i] != n_unstable[i + 1]:
            e0, e1 = eig[i], eig[i + 1]
            crossing = e1[np.argmin(np.abs(e1.real))] if n_unstable[i + 1] > n_unstable[i] else e0[np.argmin(np.abs(e0.real))]
            if abs(crossing.imag) > 1e-8 * max(1.0, abs(crossing)):
                events.append(_refine_hopf(F, Fu, a, b, n) | {"between": [i, i + 1]})
    return Branch(u=xs[:, :n], p=xs[:, n], margin=margin, stable=margin < 0, events=events, curve=curve)


def _refine_hopf(F, Fu, a, b, n):
    """Bisection between two branch points on the real part of the eigenvalue pair
    nearest the imaginary axis, each trial point corrected onto the branch (one
    compiled corrector: Newton on `[F; t . (y - x_pred)] = 0`, unrolled)."""
    tt = jnp.asarray((b - a) / np.linalg.norm(b - a))

    @jax.jit
    def correct(xp):
        def G(y):
            return jnp.concatenate([F(y[:n], y[n]), jnp.dot(tt, y - xp)[None]])
        y = xp
        for _ in range(8):
            y = y - jnp.linalg.solve(jax.jacfwd(G)(y), G(y))
        return y

    def corrected(s):
        return np.asarray(correct(jnp.asarray(a + s * (b - a))))

    def pair_real(y):
        e = np.linalg.eigvals(np.asarray(Fu(y[:n], y[n])))
        k = np.argsort(np.abs(e.real))
        cand = [e[j] for j in k if abs(e[j].imag) > 1e-10]
        return cand[0].real, abs(cand[0].imag)

    lo, hi = 0.0, 1.0
    flo = pair_real(a)[0]
    for _ in range(60):
        mid = 0.5 * (lo + hi)
        fm = pair_real(corrected(mid))[0]
        if np.sign(fm) == np.sign(flo):
            lo, flo = mid, fm
        else:
            hi = mid
        if hi - lo < 1e-14:
            break
    y = corrected(0.5 * (lo + hi))
    re, omega = pair_real(y)
    return {"kind": "hopf", "p": float(y[n]), "u": y[:n], "frequency": omega,
            "residual": float(max(np.max(np.abs(np.asarray(F(y[:n], y[n])))), abs(re)))}


def _correct_start(s, a, bounds, names, max_iter=30):
    """Newton on `s(a) = 0` (central-difference slope) from `a`, kept inside the
    box's first coordinate: each step at most a quarter of the box's width, and a
    step that would leave the box fails at once with a message naming the start
    (instead of wandering to where the margin is expensive or meaningless)."""
    lo, hi = -np.inf, np.inf
    if bounds is not None:
        lo, hi = (float(np.asarray(b, dtype=float).reshape(-1)[0]) for b in bounds)
        lo, hi = (-np.inf if np.isnan(lo) else lo), (np.inf if np.isnan(hi) else hi)
    width = hi - lo if np.isfinite(hi - lo) else np.inf
    a0 = a
    for _ in range(max_iter):
        h = 1e-6 * max(1.0, abs(a))
        va = float(s(a))
        slope = (float(s(a + h)) - float(s(a - h))) / (2 * h)
        if not np.isfinite(va) or not np.isfinite(slope) or slope == 0:
            break
        step = float(np.clip(-va / slope, -0.25 * width, 0.25 * width))
        if not lo <= a + step <= hi:
            raise ValueError(f"no stability boundary near the start {names[0]} = {a0:.6g}: Newton along "
                             f"{names[0]} leaves the box [{lo:.6g}, {hi:.6g}] (margin {va:.3g} at {a:.6g}); "
                             "start nearer the boundary")
        a += step
        if abs(step) < 1e-14 * max(1.0, abs(a)):
            break
    return a


def trace_boundary(sigma: Callable, p0, bounds=None, ds=0.01, ds_max=0.2, max_points=200, tol=1e-11,
                   direction=None, gradient="autodiff", start_tol=1e-7, correct=True, ds_min=1e-9,
                   max_turn=0.2, names=("p1", "p2"), progress=False) -> Curve:
    """The curve `sigma(p1, p2) = 0` in two parameters through (or, with `correct`,
    near) `p0`: a stability boundary when `sigma` is a regime's margin. `p0` is
    first corrected along `p1` (Newton, 1-D) when `correct` is set.

    `direction`: None (default) traces both ways and joins the halves (ordered
    from the end reached towards decreasing `p2` at the start to the one towards
    increasing `p2`); a vector `(d1, d2)` traces one way. `bounds`: `(lo, hi)`
    (NaN: no bound); an end at the box lands on its edge exactly. `names` name
    `(p1, p2)` in the stop reasons (`Curve.stops`, e.g. "box edge (mu_w = 1.0)").
    See `trace_curve` for the rest."""
    def G(x):
        return jnp.atleast_1d(sigma(x[0], x[1]))

    x0 = np.asarray(p0, dtype=float)
    if correct:
        x0 = np.array([_correct_start(jax.jit(lambda a: sigma(a, x0[1])), x0[0], bounds, names), x0[1]])
    return _trace(G, x0, ds=ds, ds_min=ds_min, ds_max=ds_max, max_points=max_points, tol=tol,
                  direction=direction, bounds=bounds, max_newton=8, start_tol=start_tol, gradient=gradient,
                  fd_step=1e-6, gtol=1e-8, max_turn=max_turn, names=names, what="margin", progress=progress)


def boundary_sensitivity(sigma3: Callable, point, q, axis=0) -> float:
    """How far the boundary `sigma(p1, p2; q) = 0` moves along parameter `axis`
    (0: p1 at fixed p2) per unit of a third parameter `q`, by the implicit
    function theorem: `-(d sigma/d q) / (d sigma / d p_axis)` (autodiff)."""
    g = jax.grad(sigma3, argnums=(0, 1, 2))(jnp.float64(point[0]), jnp.float64(point[1]), jnp.float64(q))
    return float(-g[2] / g[axis])


def fold_curve(F: Callable, u0, p0, ds=0.01, ds_max=0.2, max_points=200, tol=1e-11, bounds=None,
               direction=None, names=("p1", "p2")) -> Curve:
    """Two-parameter continuation of folds of `F(u, p1, p2) = 0`: the curve
    `{F = 0, det F_u = 0}` in `(u, p1, p2)` from a fold `(u0, p0 = (p1, p2))`;
    both ways from it unless `direction` (a vector in `(u, p1, p2)`) is given."""
    u0 = np.asarray(u0, dtype=float)
    n = u0.size

    def G(x):
        u, p1, p2 = x[:n], x[n], x[n + 1]
        return jnp.concatenate([F(u, p1, p2), jnp.linalg.det(jax.jacfwd(F)(u, p1, p2))[None]])

    return trace_curve(G, np.concatenate([u0, np.asarray(p0, dtype=float)]), ds=ds, ds_max=ds_max,
                       max_points=max_points, tol=tol, bounds=bounds, direction=direction,
                       names=[None] * n + list(names))


def floquet_crossings(floquet_fn: Callable, lo: float, hi: float, n_scan: int = 60, xtol: float = 1e-10,
                      progress: bool = False):
    """Follow a periodic regime's Floquet multipliers along a parameter and find
    where one leaves (or enters) the unit circle: `floquet_fn(p)` returns a
    `FloquetResult` (e.g. `anisotropic_abb.main_motion_floquet` at speed `p`).
    Each crossing is located by `critical_speeds` (vmapped scan, bisection) on
    `max |mu| - 1` and classified by the
    crossing multiplier: at +1 (fold or pitchfork of the periodic regime), at -1
    (period doubling), or a complex pair (Neimark-Sacker: quasi-periodic motion).
    Returns `[{"p", "kind", "multiplier", "residual", "closure", "liouville_error",
    "stable_side"}]`; the checks are those of the Floquet result at the crossing."""
    from ._critical import critical_speeds

    f = jax.jit(floquet_fn)
    out = []
    for c in critical_speeds(lambda p: jnp.max(jnp.abs(floquet_fn(p).multipliers)) - 1, lo, hi,
                             n_scan=n_scan, xtol=xtol, progress=progress):
        r = f(c.speed)
        mu = np.asarray(r.multipliers)
        k = int(np.argmin(np.abs(np.abs(mu) - 1)))
        ang = abs(np.angle(mu[k]))
        kind = "+1" if ang < 1e-3 else "-1" if abs(ang - np.pi) < 1e-3 else "complex pair"
        out.append({"p": c.speed, "kind": kind, "multiplier": [float(mu[k].real), float(mu[k].imag)],
                    "residual": float(abs(abs(mu[k]) - 1)), "closure": float(r.closure),
                    "liouville_error": float(r.liouville_error), "stable_side": c.stable_side})
    return out


def boundary_points(sigma: Callable, p1_guess, p2_values, iters: int = 12):
    """Batched pointwise boundary solves: for each `p2`, Newton along `p1` on
    `sigma(p1, p2) = 0` from `p1_guess` (scalar or per point), vmapped over the
    batch (a fixed number of iterations, so the whole batch is one call). Returns
    `(p1, residual)` arrays; a point whose residual stays large has not converged."""
    p2 = jnp.asarray(p2_values, dtype=jnp.float64)
    p1 = jnp.broadcast_to(jnp.asarray(p1_guess, dtype=jnp.float64), p2.shape)
    ds = jax.grad(sigma, argnums=0)

    def solve(a, b):
        for _ in range(iters):
            a = a - sigma(a, b) / ds(a, b)
        return a, jnp.abs(sigma(a, b))

    return jax.jit(jax.vmap(solve))(p1, p2)
