"""Numerical continuation: branches of stationary regimes in one parameter, with
folds, Hopf points and branch points detected and refined; and curves in two
parameters (stability boundaries, fold curves).

One engine, `trace_curve`, follows an implicit curve `G(x) = 0`, `G: R^{k+1} -> R^k`,
by pseudo-arclength: tangent from the null space of `G'(x)` (autodiff, or central
differences), Euler predictor, Newton corrector on `[G(x); t . (x - x_pred)] = 0`,
step adapted to the corrector's effort, to the turning of the tangent and, when a
`dense_tol` is given, to the accuracy of the curve between the points. On top of it:

- `continue_branch(F, u0, p0)`: `x = (u, p)`, `G = F(u, p)` (a stationary regime
  of a first-order field, e.g. the rotating-frame field); along the branch the
  eigenvalues of `F_u` give stability; a sign change of the bordered determinant
  `det [F_u F_p; t^T]` is a branch point (also where the tangent turns back in `p`
  there: a pitchfork met along its bifurcating branch), else one of the tangent's
  `p` component a fold (refined on `{F = 0, det F_u = 0}`), and a change in the number of
  unstable eigenvalues through a complex pair a Hopf point (refined by bisection
  along the branch on the pair's real part).
- `trace_boundary(sigma, p0)`: `x = (p1, p2)`, `G = sigma(p1, p2)`: a stability
  boundary, `sigma` the margin of a regime (largest real part, or Floquet
  exponent) as a function of two parameters; `boundary_sensitivity` gives its
  normal shift per unit of a third parameter by the implicit function theorem.
- `trace_boundaries(sigma, box)`: every boundary branch in a box, started from the
  crossings `critical_speeds` locates along `p1` on a few lines of constant `p2`.
- `fold_curve(F, u0, p0)`: `x = (u, p1, p2)`, `G = (F, det F_u)`.

Curves are traced both ways from the start unless a direction is given; each
end stops for a stated reason: on the edge of the parameter box (the last step
is cut to land on it), a closed loop, `max_points`, a corrector that fails at
the smallest step, or a non-finite function value. Steps are cut where the
tangent turns, so folds are drawn as curves, not kinks.

Dense output: between two points the curve is the cubic Hermite interpolant of
the points and their unit tangents (`Curve.dense`). Its error is estimated on
every interval from its midpoint `H`: the Newton correction `-J^+ G(H)` of `H`
onto the curve (`J` the mean of the end points' Jacobians), i.e. the distance of
the interpolant from the curve where it is largest (the error of a cubic Hermite
interpolant goes as `s^2 (1 - s)^2`). With `dense_tol`, a step whose estimate
exceeds `0.8 dense_tol` is cut (the error goes as the fourth power of the step)
and the next step is sized for it, so the curve, not just its points, is
accurate to `dense_tol`.

Every result carries its checks: the residual of the defining system at every
point, the step history, the interpolation error estimates, and why each end
stopped.
"""

import dataclasses
import re
import warnings
from typing import Callable

import equinox as eqx
import jax
import jax.numpy as jnp
import numpy as np

from .._autodiff import value_and_jacfwd
from .._newton import newton
from ..solve._lift import Lifted, call, chunks, compiled, jacobian, lift
from ..solve._results import RESULTS, code_of
from . import _arclength, _branch_points
from ._roots import bisect, root_gradient


def _hermite(x0, t0, x1, t1, s):
    """Cubic Hermite interpolant from `x0` (unit tangent `t0`) to `x1` (`t1`) at
    the fractions `s` (1-D), the tangents scaled by the chord length."""
    h = float(np.linalg.norm(x1 - x0))
    s = np.asarray(s, dtype=float)[:, None]
    s2, s3 = s * s, s * s * s
    return ((2 * s3 - 3 * s2 + 1) * x0 + (s3 - 2 * s2 + s) * h * t0 + (3 * s2 - 2 * s3) * x1
            + (s3 - s2) * h * t1)


def _stop_kind(reason):
    """`"box edge (mu_w = 1.0)"` -> `"box edge"`; `"corrector failed (...) at ..."` -> `"corrector failed"`."""
    for kind in ("box edge", "closed loop", "max_points reached", "corrector failed", "start"):
        if reason.startswith(kind):
            return kind
    return reason.split(" at ")[0]


def physical_stops(stops, name, physical, lo=None, hi=None, as_name=None):
    """`stops` (a curve's, traced in scaled units) with each `<name> = <value>`
    rewritten as `physical(value)` (named `as_name`, where given), exactly `lo` or
    `hi` where it lands within 1e-9 of one (a box edge)."""
    def back(m):
        v = physical(float(m.group(1)))
        for b in (lo, hi):
            if b is not None and abs(v - b) <= 1e-9 * max(1.0, abs(b)):
                v = b
        return f"{as_name or name} = {v}"

    pattern = re.compile(rf"{re.escape(name)} = ([-+.\deE]+|nan|inf)")
    return tuple(pattern.sub(back, s) for s in stops)


#: the outcome of an end by how its reason begins; an end for any other reason (a caller's `watch`) is a failure
STOP_RESULTS = {"box edge": RESULTS.successful, "closed loop": RESULTS.successful, "start": RESULTS.successful,
                "max_points reached": RESULTS.max_points_reached, "corrector failed": RESULTS.solver_failure,
                "non-finite": RESULTS.nonfinite, "no periodic motion": RESULTS.root_not_converged}


def stop_result(reason):
    """The `RESULTS` item of a curve's end stopped for `reason` (see `Curve`)."""
    return next((r for kind, r in STOP_RESULTS.items() if reason.startswith(kind)), RESULTS.solver_failure)


@dataclasses.dataclass(frozen=True)
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
    - `tangents`: the unit tangent at each point, pointing from `x[0]` towards
      `x[-1]`; with the points they define the dense curve (`dense`).
    - `errors`: `errors[i]` estimates the largest distance between the dense
      curve and the true curve on the interval from `x[i-1]` to `x[i]` (0 at the
      first point; see the module docstring), measured along `error_axis` when
      that is set (a boundary: along `p1` at fixed `p2`, as a critical speed
      would be), else orthogonally to the curve.
    - `dense_tol`: the accuracy the steps were controlled to (None: not
      controlled; the estimates are there all the same).

    A reason is one of `"box edge (<name> = <bound>)"` (the last point lies on
    that bound), `"closed loop"` (`x[-1]` repeats `x[0]`), `"max_points
    reached"`, `"corrector failed (step below ds_min) at <point>"` and
    `"non-finite <G> at <point>"`.

    Frozen: a new curve is made with `dataclasses.replace`."""

    x: np.ndarray
    residuals: np.ndarray
    steps: np.ndarray
    iterations: np.ndarray
    stopped: str
    stops: tuple = ()
    start: int = 0
    tangents: np.ndarray = None
    errors: np.ndarray = None
    dense_tol: float = None
    error_axis: int = None

    def __post_init__(self):
        object.__setattr__(self, "stops", tuple(self.stops))

    @property
    def results(self) -> tuple:
        """The outcome at each end (`stops`) as a `rotorjax.solve.RESULTS` item:
        `successful` on the box's edge, round a closed loop and at a one-way start;
        `max_points_reached`, `solver_failure` (the corrector failed at the smallest
        step), `nonfinite` or `root_not_converged` where it ended inside its box."""
        return tuple(stop_result(s) for s in self.stops)

    @property
    def complete(self) -> bool:
        """Whether both ends are where the curve ends (`results` all `successful`),
        not cut short inside the box."""
        return all(r == RESULTS.successful for r in self.results)

    @property
    def stop(self) -> str:
        """The stop reasons in one word each: `"box edge"` when both ends are on the
        box's edge (likewise `"closed loop"`, ...), else `"low end: <kind>; high end:
        <kind>"` (one way: the far end's kind)."""
        a, b = (_stop_kind(s) for s in self.stops) if len(self.stops) == 2 else ("", self.stopped)
        if a == "start":
            return b
        return a if a == b else f"low end: {a}; high end: {b}"

    def dense(self, n: int = 8) -> np.ndarray:
        """The curve sampled `n` times per interval (the cubic Hermite interpolant
        of the points and tangents): `(n (len(x) - 1) + 1, dim)` rows, the points
        included (every `n`-th row)."""
        if self.tangents is None or len(self.x) < 2:
            return np.asarray(self.x)
        s = np.linspace(0.0, 1.0, int(n) + 1)[1:]
        parts = [self.x[:1]] + [_hermite(self.x[i], self.tangents[i], self.x[i + 1], self.tangents[i + 1], s)
                                for i in range(len(self.x) - 1)]
        return np.concatenate(parts)

    def meets(self, axis: int, value: float) -> np.ndarray:
        """The points (rows) where the dense curve meets the hyperplane `x[axis] =
        value`, e.g. a boundary's critical speeds `p1` at `p2 = value`:
        `curve.meets(1, value)[:, 0]`."""
        return np.array([pt for pt, _ in _meets(self, axis, value)]).reshape(-1, self.x.shape[1])

    def as_dict(self, names=None, dense: int = 8) -> dict:
        """JSON-ready: one list per coordinate (named by `names`, default `x0`,
        `x1`, ...), the checks, the stop reasons, the unit tangents (rows) and the
        dense curve (`n` samples per interval)."""
        names = [f"x{i}" for i in range(self.x.shape[1])] if names is None else list(names)
        d = self.dense(dense)
        out = {k: self.x[:, i].tolist() for i, k in enumerate(names) if k is not None}
        out.update({"residuals": self.residuals.tolist(), "steps": self.steps.tolist(),
                    "stop": self.stop, "stopped": self.stopped, "stops": list(self.stops),
                    "stop_codes": [code_of(r) for r in self.results],
                    "start": int(self.start), "n_points": int(self.x.shape[0])})
        if self.errors is not None:
            out.update({"interpolation_errors": self.errors.tolist(),
                        "interpolation_error_max": float(np.max(self.errors)),
                        "dense_tol": self.dense_tol,
                        "error_measured": ("orthogonally to the curve" if self.error_axis is None else
                                           f"along {names[self.error_axis]} at fixed other coordinates")})
        if self.tangents is not None:
            out["tangents"] = self.tangents.tolist()
        out["dense"] = {k: d[:, i].tolist() for i, k in enumerate(names) if k is not None}
        return out


def _tangent(jac):
    """Unit null vector of a `k x (k+1)` Jacobian."""
    q, _ = np.linalg.qr(jac.T, mode="complete")
    return q[:, -1]


@compiled
def _jacobians(G, x):
    """`G`'s Jacobian at each row of `x`."""
    return (jax.vmap(jax.jacfwd(G))(x),)


class _Front:
    """One direction of tracing: its points so far with their tangents (pointing
    the way it goes), Jacobians and interpolation error estimates, the next step,
    and its stop reason (None while it goes on)."""

    def __init__(self, x0, r0, t0, J0, ds):
        self.xs, self.res, self.steps, self.iters = [x0.copy()], [r0], [0.0], [0]
        self.ts, self.errs = [t0], [0.0]
        self.t, self.J, self.ds, self.stop = t0, J0, ds, None
        self.nonfinite = 0     # successive steps that met non-finite values of G

    def append(self, y, r, step, it, t, J, err):
        self.xs.append(y)
        self.res.append(r)
        self.steps.append(step)
        self.iters.append(it)
        self.ts.append(t)
        self.errs.append(err)
        self.t, self.J = t, J


# the step control's limits, the compiled core's (`_arclength`)
_MAX_TURN_HALVINGS, _MAX_NONFINITE = _arclength.MAX_TURN_HALVINGS, _arclength.MAX_NONFINITE
_MAX_DENSE_CUTS, _AXIS_FLOOR = _arclength.MAX_DENSE_CUTS, _arclength.AXIS_FLOOR
_DENSE_SAFETY = 0.8        # the midpoint estimate is kept below this fraction of dense_tol


def _evaluators(G, gradient, fd_step, x0):
    """`(g, jac)`: `G` and its Jacobian as NumPy functions of a NumPy point,
    compiled once per structure of `G` (`lift`: a second curve of the same problem,
    other values, reuses the compilation); the Jacobian by autodiff, or by central
    differences with relative step `fd_step` from `g`."""
    Gl = G if isinstance(G, Lifted) else lift(G, jnp.asarray(x0, dtype=jnp.float64))

    def g(x):
        return np.atleast_1d(np.asarray(call(Gl, jnp.asarray(x)), dtype=float))

    return g, _jacobian(Gl, g, gradient, fd_step)


def _jacobian(G, g, gradient, fd_step):
    """The Jacobian of `G` (a `Lifted` function, or a plain one: compiled per call)
    as a NumPy function `jac(x, gx=None)`: by autodiff, or
    by central differences from `g`; given `gx = g(x)`, by forward differences
    (half the evaluations; enough for the chord method's Jacobian, not for
    tangents)."""
    if gradient == "autodiff":
        if isinstance(G, Lifted):
            def Jj(x):
                return jacobian(G, x)
        else:
            Jj = jax.jit(jax.jacfwd(G))

        def jac(x, gx=None):
            return np.asarray(Jj(jnp.asarray(x)), dtype=float).reshape(-1, x.size)
    elif gradient == "fd":
        def jac(x, gx=None):
            cols = []
            for i in range(x.size):
                h = fd_step * max(1.0, abs(x[i]))
                e = np.zeros_like(x)
                e[i] = h
                cols.append((g(x + e) - g(x - e)) / (2 * h) if gx is None else (g(x + e) - gx) / h)
            return np.stack(cols, axis=-1).reshape(-1, x.size)
    else:
        raise ValueError(f"gradient must be 'autodiff' or 'fd', got {gradient!r}")
    return jac


def _trace(G, x0, *, ds, ds_min, ds_max, max_points, tol, direction, bounds, max_newton, start_tol, gradient,
           fd_step, gtol, max_turn, names, what, progress=False, dense_tol=None, error_axis=None,
           evaluators=None, watch=None) -> Curve:
    # a JAX `G` differentiated by autodiff runs on the compiled core (`_arclength`); the loop of `advance`
    # below is for a `G` evaluated by the caller's NumPy code (Jacobians by differences)
    Gl = None
    if evaluators is None and G is not None and gradient == "autodiff":
        Gl = G if isinstance(G, Lifted) else lift(G, jnp.asarray(x0, dtype=jnp.float64))
        G = Gl
    core = Gl is not None
    g, jac = _evaluators(G, gradient, fd_step, x0) if evaluators is None else evaluators
    # watch: `(w, reasons)`, `w(x)` a JAX function of a new point, 0 to go on, `i` to stop for `reasons[i - 1]`
    wl = None if watch is None else watch[0] if isinstance(watch[0], Lifted) else lift(watch[0], jnp.asarray(x0))
    # a Jacobian by differences costs 2 (k + 1) evaluations of G: the corrector keeps the one at its
    # predictor (the chord method) rather than forming one per iteration
    chord = gradient == "fd"

    x0 = np.asarray(x0, dtype=float)
    m = x0.size
    names = [f"x[{i}]" for i in range(m)] if names is None else list(names)
    if len(names) != m:
        raise ValueError(f"names has {len(names)} entries for a point of {m} coordinates")
    if dense_tol is not None and not (np.isfinite(dense_tol) and dense_tol > 0):
        raise ValueError(f"dense_tol must be a positive number or None, got {dense_tol!r}")
    if error_axis is not None and m != 2:
        raise ValueError(f"error_axis is for curves in two coordinates; this one has {m}")
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
        """Newton on `[G(y); row . y - c] = 0` from `y` (the chord method, the Jacobian at `y`, for
        `gradient="fd"`): `(y, iterations, max |G|, None)` when accepted, `(None, iterations, None, bad)`
        when not, `bad` the point where `G` (or its Jacobian) was not finite, if that is why."""
        J, last = None, np.inf
        for it in range(1, max_newton + 1):
            gy = g(y)
            if not np.all(np.isfinite(gy)):
                return None, it, None, y
            if J is None or not chord:
                J = jac(y, gy) if chord else jac(y)
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
            # converged; or at the rounding floor of an ill-conditioned system (a step within 1e3 tol
            # that no longer contracts: more iterations only stir the noise)
            stalled = step <= 1e3 * tol and step > 0.5 * last
            floor = stalled or (it == max_newton and step <= 1e3 * tol)
            last = step
            if step <= tol or floor:
                r = float(np.max(np.abs(g(y))))
                if not np.isfinite(r):
                    return None, it, None, y
                # a stalled iteration only showed the floor: not counted as the corrector's work
                done = it - 1 if stalled and step > tol else it
                return (y, done, r, None) if r <= gtol else (None, it, None, None)
        return None, max_newton, None, None

    def oriented_tangent(y, t):
        """`(tangent at y oriented along t, its angle to t, the Jacobian at y)`."""
        J = jac(y)
        tn = _tangent(J)
        tn = tn if tn @ t >= 0 else -tn
        return tn, float(np.arccos(np.clip(tn @ t, -1.0, 1.0))), J

    def interval_error(x, tx, Jx, y, ty, Jy):
        """The interpolation error estimate on `x -> y`: the Newton correction of the Hermite midpoint
        (with the mean Jacobian), its length, or its length along `error_axis` (2-D: divided by that
        component of the unit normal, floored)."""
        if not (np.all(np.isfinite(Jx)) and np.all(np.isfinite(Jy))):
            return np.inf
        H = _hermite(x, tx, y, ty, [0.5])[0]
        gH = g(H)
        if not np.all(np.isfinite(gH)):
            return np.inf
        J = 0.5 * (Jx + Jy)
        d = float(np.linalg.norm(np.linalg.lstsq(J, -gH, rcond=None)[0]))
        if error_axis is None:
            return d
        nu = np.abs(J[0, error_axis]) / max(float(np.linalg.norm(J[0])), 1e-300)
        return d / max(nu, _AXIS_FLOOR)

    # the largest error of a piece lies near, not exactly at, its midpoint: keep the estimate a little lower
    target = None if dense_tol is None else _DENSE_SAFETY * dense_tol

    def too_coarse(err, cuts):
        return target is not None and err > target and cuts < _MAX_DENSE_CUTS

    def shrink(err):
        """The step factor that brings an interpolation error `err` to about the target (error ~ step^4)."""
        return float(np.clip(0.9 * (target / err) ** 0.25, 0.2, 0.9)) if np.isfinite(err) else 0.2

    def land(f, x, y0, k, b, reach, may_refuse, cuts):
        """Correct `y0` onto the curve with coordinate `k` fixed at the bound `b`: the end point on the
        box edge, if the curve reaches it within about `reach` (and, when `may_refuse`, without
        turning by more than `max_turn`), and the interpolation error to it is within `dense_tol`.
        Returns ("landed" | "turns" | "coarse" | "missed", interpolation error)."""
        z, it, r, _ = correct(y0, np.eye(m)[k], b)
        if z is None:
            return "missed", None
        z[k] = b
        if outside(z) or (z - x) @ f.t <= 0 or np.linalg.norm(z - x) > 2 * reach:
            return "missed", None
        tz, angle, Jz = oriented_tangent(z, f.t)
        if angle > max_turn and may_refuse:
            return "turns", None
        err = interval_error(x, f.t, f.J, z, tz, Jz)
        if too_coarse(err, cuts):
            return "coarse", err
        f.append(z, r, float(np.linalg.norm(z - x)), it, tz, Jz, err)
        f.stop = edge(k, b)
        return "landed", err

    def closes(x, y, t, other):
        """Whether the chord `x -> y` (tangent `t` at `y`) runs into the other front's last point,
        that front coming the other way round: the curve is a closed loop."""
        p, d = other.xs[-1], y - x
        dd = d @ d
        if dd == 0:
            return False
        s = (p - x) @ d / dd
        return 0 < s <= 1.1 and np.linalg.norm(x + s * d - p) <= 0.1 * np.sqrt(dd) and t @ other.t < -0.5

    def heads_out(f):
        """Whether the front stands on the box's edge heading out (then stopped there)."""
        s_edge, k, b = to_box(f.xs[-1], f.t)
        if s_edge <= 1e-12 * max(1.0, np.max(np.abs(f.xs[-1]))):
            f.stop = edge(k, b)
        return f.stop is not None

    knobs = jnp.asarray([ds_min, ds_max, tol, gtol, max_turn, max_newton, np.inf if target is None else target,
                         -1 if error_axis is None else error_axis], dtype=jnp.float64)
    box = (jnp.asarray(lo), jnp.asarray(hi))

    def march_front(f, other, budget, pause):
        """`advance` by the compiled core: up to `pause` points (at most `_arclength.CHUNK`)."""
        out = _arclength.march(Gl, wl, jnp.asarray(f.xs[-1]), jnp.asarray(f.t), jnp.asarray(f.J), jnp.float64(f.ds),
                               jnp.asarray(f.nonfinite), jnp.asarray(other.xs[-1]), jnp.asarray(other.t),
                               jnp.asarray(other.J), jnp.float64(other.res[-1]), jnp.asarray(budget),
                               jnp.asarray(pause), *box, knobs)
        out = jax.tree_util.tree_map(np.asarray, out)
        for i in range(int(out.n)):
            f.append(out.x[i], float(out.residuals[i]), float(out.steps[i]), int(out.iterations[i]), out.t[i],
                     None, float(out.errors[i]))
        f.J, f.ds, f.nonfinite = out.J, float(out.ds), int(out.nonfinite)
        code, k = int(out.stop), int(out.stop_k)
        if code == _arclength.CLOSED and other.stop is None:
            other.stop = "closed loop"
        f.stop = {_arclength.EDGE: lambda: edge(k, out.stop_b),
                  _arclength.FAILED: lambda: f"corrector failed (step below ds_min) at {at(f.xs[-1])}",
                  _arclength.NONFINITE: lambda: f"non-finite {what} at {at(out.bad)}",
                  _arclength.CLOSED: lambda: "closed loop",
                  _arclength.FULL: lambda: "max_points reached" + ("" if boxed else " (no parameter box given)"),
                  _arclength.WATCH: lambda: watch[1][k - 1],
                  _arclength.PAUSE: lambda: None}[code]()

    def advance(f, other):
        x, ds, t = f.xs[-1], f.ds, f.t
        bad, turns, cuts = None, 0, 0
        while True:
            if ds < ds_min:
                f.stop = (f"non-finite {what} at {at(bad)}" if bad is not None else
                          f"corrector failed (step below ds_min) at {at(x)}")
                return
            may_refuse = turns < _MAX_TURN_HALVINGS and ds / 2 >= ds_min
            s_edge, k, b = to_box(x, t)
            if s_edge <= ds:
                # the predictor would leave the box: try the edge it meets
                how, err = land(f, x, x + s_edge * t, k, b, s_edge, may_refuse, cuts)
                if how == "landed":
                    return
                if how in ("turns", "coarse"):
                    turns += how == "turns"
                    cuts += how == "coarse"
                    ds = s_edge * (0.5 if how == "turns" else shrink(err))
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
                frac = (b - x[k]) / (y[k] - x[k])
                how, err = land(f, x, x + frac * (y - x), k, b, max(ds, float(np.linalg.norm(y - x))), may_refuse,
                                cuts)
                if how == "landed":
                    return
                turns += how == "turns"
                cuts += how == "coarse"
                # too coarse to the edge: a step short of it, sized for the error
                ds *= frac * shrink(err) if how == "coarse" else 0.5
                continue
            tn, angle, Jn = oriented_tangent(y, t)
            if angle > max_turn and may_refuse:
                turns += 1
                ds /= 2
                continue
            if closes(x, y, tn, other):
                p, tp = other.xs[-1].copy(), -other.t
                err = interval_error(x, t, f.J, p, tp, other.J)
                if too_coarse(err, cuts) and ds * shrink(err) >= ds_min:
                    cuts += 1
                    ds *= shrink(err)
                    continue
                f.append(p, float(np.max(np.abs(g(p)))), float(np.linalg.norm(p - x)), it, tp, other.J, err)
                f.stop = "closed loop"
                if other.stop is None:
                    other.stop = "closed loop"
                return
            err = interval_error(x, t, f.J, y, tn, Jn)
            if too_coarse(err, cuts) and ds * shrink(err) >= ds_min:
                cuts += 1
                ds *= shrink(err)
                continue
            f.append(y, r, ds, it, tn, Jn, err)
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
            easy = it - 2 if chord else it      # the chord method converges linearly: two more are easy
            grow = 1.5 if easy <= 3 else 1.0 if easy <= 5 else 0.5
            if angle > 0:
                grow = min(grow, 0.8 * max_turn / angle)
            if target is not None and err > 0:
                grow = min(grow, 0.9 * (target / err) ** 0.25)
            f.ds = min(max(ds * max(grow, 0.25), ds_min), ds_max)
            return

    J0 = jac(x0)
    t0 = _tangent(J0)
    both = direction is None
    if not both:
        t0 = t0 if t0 @ np.asarray(direction, dtype=float) >= 0 else -t0
    elif t0[-1] < 0:
        t0 = -t0
    hi_f = _Front(x0, r0, t0, J0, ds)
    lo_f = _Front(x0, r0, -t0, J0, ds)
    if not both:
        lo_f.stop = "start"           # stands still: the start, for the closed-loop test
    fronts = [f for f in (hi_f, lo_f) if f.stop is None]
    from tqdm.auto import tqdm

    bar = tqdm(total=max_points, desc="continuation", unit="point", disable=not progress, leave=False)
    while any(f.stop is None for f in fronts):
        bar.update(len(hi_f.xs) + len(lo_f.xs) - 1 - bar.n)
        # the compiled core: the points left shared between the fronts still going, round by round
        share = -(-(max_points - (len(hi_f.xs) + len(lo_f.xs) - 1)) // sum(f.stop is None for f in fronts))
        for f in fronts:
            other = lo_f if f is hi_f else hi_f
            if f.stop is not None:
                continue
            if core:
                march_front(f, other, max_points - (len(hi_f.xs) + len(lo_f.xs) - 1), max(share, 1))
                continue
            if heads_out(f):
                continue
            if len(hi_f.xs) + len(lo_f.xs) - 1 >= max_points:
                f.stop = "max_points reached" + ("" if boxed else " (no parameter box given)")
                continue
            before = len(f.xs)
            advance(f, other)
            if wl is not None and len(f.xs) > before and f.stop != "closed loop":
                # the caller's verdict on the new point (e.g. a model that no longer resolves it): stops the front
                code = int(call(wl, jnp.asarray(f.xs[-1])))
                f.stop = watch[1][code - 1] if code > 0 else f.stop
    bar.close()
    rev = slice(None, 0, -1)
    x = np.asarray(lo_f.xs[rev] + hi_f.xs)
    res = np.asarray(lo_f.res[rev] + hi_f.res)
    steps = np.asarray([0.0] + lo_f.steps[1:][::-1] + hi_f.steps[1:])
    iters = np.asarray([0] + lo_f.iters[1:][::-1] + hi_f.iters[1:])
    tangents = np.asarray([-tt for tt in lo_f.ts[rev]] + hi_f.ts)
    errors = np.asarray([0.0] + lo_f.errs[1:][::-1] + hi_f.errs[1:])
    stops = (lo_f.stop, hi_f.stop)
    if not both:
        stopped = hi_f.stop
    elif stops == ("closed loop", "closed loop"):
        stopped = "closed loop"
    else:
        stopped = f"low end: {stops[0]}; high end: {stops[1]}"
    return Curve(x=x, residuals=res, steps=steps, iterations=iters, stopped=stopped, stops=stops,
                 start=len(lo_f.xs) - 1, tangents=tangents, errors=errors, dense_tol=dense_tol,
                 error_axis=error_axis)


def trace_curve(G: Callable, x0, ds=0.01, ds_min=1e-9, ds_max=0.2, max_points=200, tol=1e-11,
                direction=None, bounds=None, max_newton=8, start_tol=1e-7, gradient="autodiff",
                fd_step=1e-6, gtol=1e-8, max_turn=0.2, names=None, dense_tol=None) -> Curve:
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
    - `dense_tol`: the accuracy of the dense curve (`Curve.dense`, cubic Hermite
      between the points) to control the steps to: a step whose midpoint error
      estimate exceeds `0.8 dense_tol` is cut, the next one sized for it (None:
      steps not controlled by it; `Curve.errors` holds the estimates either way).
    - With `gradient="fd"` the corrector forms the Jacobian once, at its
      predictor, by forward differences, and keeps it (the chord method): `dim`
      evaluations of `G` besides one per iteration, instead of `2 dim + 1` per
      iteration. Tangents are always from central differences.
    - An end stops with "non-finite G at <point>" when the steps from it fail on
      non-finite values of `G` down to `ds_min`, or three successive steps are cut
      short by them (the curve runs into a region where `G` is undefined).

    **Returns:** a `Curve`; its `stops` say why each end is where it is.

    A start with `max |G(x0)| > start_tol` raises a ValueError stating the residual.
    """
    return _trace(G, x0, ds=ds, ds_min=ds_min, ds_max=ds_max, max_points=max_points, tol=tol,
                  direction=direction, bounds=bounds, max_newton=max_newton, start_tol=start_tol,
                  gradient=gradient, fd_step=fd_step, gtol=gtol, max_turn=max_turn, names=names, what="G",
                  dense_tol=dense_tol)


def _deprecated_key(cls, key):
    warnings.warn(f"{cls.__name__}[{key!r}]: the rows are {cls.__name__} objects now; read the attribute "
                  f"(.{key}) or as_dict()[{key!r}] (item access goes in the next release)", DeprecationWarning,
                  stacklevel=3)


@dataclasses.dataclass(frozen=True)
class BranchEvent:
    """A fold, Hopf point or branch point found along a `Branch` (one of its
    `events`).

    - `kind`: `"fold"` (refined by Newton on `F = 0` and `F_u` singular, a
      bordered test function), `"hopf"`
      (refined by bisection along the branch on the crossing pair's real part) or
      `"branch_point"` (a sign change of the bordered determinant, refined by
      Newton on Moore and Keller's extended system, `_branch_points`); on a
      branch of periodic motions (`periodic_branch`) a crossing pair is a
      `"period-doubling"` or a `"neimark-sacker"` point.
    - `p`, `u`: the parameter and the state there.
    - `residual`: max |.| of the defining system there (where the refinement
      failed and the event is located to the step, with a `note`: the larger
      `max |F|` of the two points around it).
    - `between`: `(i, i + 1)`, the branch's points it lies between.
    - `frequency`: a Hopf point's `|Im lambda|` of the crossing pair (a
      Neimark-Sacker or period-doubling point's exponent frequency; None for the
      other kinds).
    - `note`: a remark on how it was located (an event located to the step, not
      refined: why), else None.
    - `tangent`: at a refined branch point, the unit tangent `(u, p)` of the
      branch that crosses this one there (towards increasing `p`), the start of
      `switch_branch`; None for the other kinds, and on periodic branches (their
      events' `u` are the physical coefficients, not the continuation's unknowns).
    - `crossing`: at a Hopf point, how many stability exponents cross there (the
      change in the number of unstable ones): 2 for a complex pair; on a branch of
      periodic motions 1 for a real multiplier through -1 (a period doubling), 2
      for a pair (Neimark-Sacker). None for the other kinds.
    - `switched`: at a refined branch point of a periodic branch traced with
      `periodic_branch(switch=True)`, the crossing branch, `(PeriodicBranch,
      coefficients)` as `periodic_branch` returns them; else None.

    `as_dict()` gives the JSON row; `event["p"]` style access still reads the same
    keys, deprecated (for code written against the former dict rows)."""

    kind: str
    p: float
    u: np.ndarray
    residual: float
    between: tuple
    frequency: float = None
    note: str = None
    crossing: int = None
    tangent: np.ndarray = None
    switched: tuple = None

    def __post_init__(self):
        object.__setattr__(self, "between", tuple(int(i) for i in self.between))

    def as_dict(self) -> dict:
        """JSON-ready: `{"kind", "p", "u": [...], "frequency" (Hopf), "residual",
        "between": [i, i + 1], "note", "crossing", "tangent" (when set)}`."""
        out = {"kind": self.kind, "p": self.p, "u": np.asarray(self.u).tolist()}
        if self.frequency is not None:
            out["frequency"] = self.frequency
        out.update({"residual": self.residual, "between": list(self.between)})
        if self.note is not None:
            out["note"] = self.note
        if self.crossing is not None:
            out["crossing"] = self.crossing
        if self.tangent is not None:
            out["tangent"] = np.asarray(self.tangent).tolist()
        return out

    def __getitem__(self, key):
        _deprecated_key(type(self), key)
        return self.as_dict()[key] if key != "u" else self.u

    def __contains__(self, key):
        return key in self.as_dict()


@dataclasses.dataclass(frozen=True)
class Branch:
    """A branch of stationary regimes `u(p)`: `u`, `p`, the largest real part of
    the eigenvalues (`margin`) and stability at each point, the detected `events`
    (a tuple of `BranchEvent`: kind "fold", "hopf" or "branch_point", with the
    refined `p`, `u`, the residual of its defining system, and for Hopf the
    frequency), and the curve's checks. Frozen (`dataclasses.replace` for a new
    one)."""

    u: np.ndarray
    p: np.ndarray
    margin: np.ndarray
    stable: np.ndarray
    events: tuple
    curve: Curve

    def __post_init__(self):
        object.__setattr__(self, "events", tuple(self.events))

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
                "events": [e.as_dict() for e in self.events],
                "residual_max": float(self.curve.residuals.max()), "stopped": self.curve.stopped,
                "stops": list(self.curve.stops), "stop_codes": [code_of(r) for r in self.curve.results],
                "start": int(self.curve.start), "n_points": int(self.p.size)}


def _borders(J0):
    """`(b, c)`: the left and right singular vectors of the smallest singular value
    of `J0` (`F_u` near a fold), the borders of `bordered_fold`."""
    U, _, Vt = np.linalg.svd(np.asarray(J0))
    return jnp.asarray(U[:, -1]), jnp.asarray(Vt[-1])


def bordered_fold(J, b, c):
    """The bordered test function of a fold, zero exactly where `J = F_u` is
    singular: the last component of the solution of `[[J, b], [c^T, 0]] [v; g] =
    [0; 1]` (`b`, `c` from `_borders` near the fold). Unlike `det F_u` it is of the
    size of `F_u`'s smallest singular value, whatever the dimension (a determinant
    of a few hundred unknowns overflows)."""
    n = J.shape[0]
    A = jnp.block([[J, b[:, None]], [c[None, :], jnp.zeros((1, 1))]])
    return jnp.linalg.solve(A, jnp.zeros(n + 1).at[n].set(1.0))[n]


def _fold_function(J0):
    """`g(F_u)`: `bordered_fold` with the borders of `J0`."""
    b, c = _borders(J0)
    return lambda J: bordered_fold(J, b, c)


def continue_branch(F: Callable, u0, p0, p_bounds=(-np.inf, np.inf), ds=0.01, ds_max=0.2, max_points=300,
                    tol=1e-11, direction=None, start_tol=1e-8, ds_min=1e-9, max_turn=0.2, name="p",
                    progress=False, dense_tol=None, gtol=1e-8, exponents=None, watch=None) -> Branch:
    """One-parameter continuation of `F(u, p) = 0` from a solution `(u0, p0)`
    within `p_bounds` (a missing bound: NaN or infinite).

    `direction`: None (default) traces both ways from the start, the points
    ordered from the end reached towards decreasing `p` to the end reached
    towards increasing `p`; `1` or `-1` traces one way, towards increasing or
    decreasing `p`; a vector `(du, dp)` one way, the first tangent along it (to
    go on from a branch's end past a fold). An end inside `p_bounds`' edge lands on it exactly. `name`
    names `p` in the stop reasons (`Branch.stops`, e.g. "box edge (nu = 4.0)").
    At most `max_points` points in all. `dense_tol`: as in `trace_curve` (the dense
    branch is `Branch.curve.dense()`, rows `(u, p)`). `gtol`: the largest `max |F|`
    a corrected point may keep (as in `trace_curve`). `exponents(F_u, u, p)`: the
    stability exponents at a point from its Jacobian (default: all its eigenvalues;
    harmonic balance passes Hill's physical ones); the margin is their largest real
    part. `F` is traced once and its programs (the corrector's, the fold's and the
    Hopf refinement's) compiled once per structure (`solve._lift`): another branch of
    the same equations with other arrays reuses them. `watch = (w, reasons)`, given:
    `w(x)`, a JAX function of every new point `x = (u, p)` returning an integer,
    stops the branch there for `reasons[w(x) - 1]` where it is positive."""
    u0 = np.asarray(u0, dtype=float)
    n = u0.size

    def G(x):
        return F(x[:n], x[n])

    lo = np.full(n + 1, np.nan)
    hi = np.full(n + 1, np.nan)
    lo[n], hi[n] = p_bounds
    d = None
    if direction is not None and np.ndim(direction) == 1:
        d = np.asarray(direction, dtype=float)
    elif direction is not None:
        d = np.zeros(n + 1)
        d[n] = direction
    x0 = np.concatenate([u0, [p0]])
    Gl = lift(G, jnp.asarray(x0))   # every program below compiled once per structure of F
    curve = _trace(Gl, x0, ds=ds, ds_min=ds_min, ds_max=ds_max, max_points=max_points,
                   tol=tol, direction=d, bounds=(lo, hi), max_newton=8, start_tol=start_tol, gradient="autodiff",
                   fd_step=1e-6, gtol=gtol, max_turn=max_turn, names=[None] * n + [name], what="F",
                   progress=progress, dense_tol=dense_tol, watch=watch)

    def Fu(u, p):
        return jacobian(Gl, jnp.concatenate([jnp.asarray(u), jnp.atleast_1d(p)]))[:, :n]

    xs = curve.x
    if exponents is None:
        def exponents(J, u, p):
            return np.linalg.eigvals(J)
    tangents = curve.tangents     # oriented along the curve
    eig, bordered, jacs = _point_checks(Gl, xs, tangents, exponents)
    margin = np.array([e.real.max() for e in eig])
    checks = _Checks(Gl, Fu, n, gtol, exponents)
    events = []
    for i in range(len(xs) - 1):
        events += checks.between(xs, tangents, eig, bordered, jacs, curve.residuals, i, (i, i + 1),
                                 SUBDIVISION_DEPTH)
    return Branch(u=xs[:, :n], p=xs[:, n], margin=margin, stable=margin < 0, events=tuple(events), curve=curve)


def _point_checks(Gl, xs, tangents, exponents):
    """At every point `x` of a branch of `G = 0` (`Gl` lifted; `tangents` along it):
    the stability exponents (`exponents(F_u, u, p)`), the sign of the bordered
    determinant `det [G_x; t]` (slogdet's: a determinant of a few hundred unknowns
    overflows), and the Jacobians `[F_u F_p]` of the points on either side of a
    fold (by index; only those are kept: all of a large system's would not fit in
    memory)."""
    n = xs.shape[1] - 1
    turns = np.flatnonzero(np.sign(tangents[:-1, n]) != np.sign(tangents[1:, n]))
    keep = set(turns) | set(turns + 1)
    eig, bordered, jacs = [], [], {}
    for first, (J,) in chunks(_jacobians, Gl, (xs,), row_bytes=8 * n * (n + 1)):
        for j, Jx in enumerate(J):
            i = first + j
            eig.append(np.asarray(exponents(Jx[:, :n], xs[i, :n], xs[i, n])))
            bordered.append(np.linalg.slogdet(np.concatenate([Jx, tangents[i][None]], axis=0))[0])
            if i in keep:
                jacs[i] = Jx
    return eig, np.array(bordered), jacs


#: an interval of a branch in which an event is found or the exponents' signs change is cut into this many
#: parts, their ends corrected onto the branch, and each part checked again; a part is cut again, down to this
#: depth, where its events do not account for the exponents that crossed in it (more crossed than its fold,
#: branch point and Hopf point explain) or its fold or branch point did not refine from its midpoint (two
#: events in one step: a complex pair leaving, then a real exponent returning)
SUBDIVISIONS, SUBDIVISION_DEPTH = 4, 2


class _Checks:
    """The events between two successive points of a branch of `G(x) = F(x[:n], x[n])
    = 0` (`Gl` lifted, `Fu(u, p)` its Jacobian in `u`): folds, branch points and Hopf
    points, each refined; an interval with an event or a change of stability is cut
    into parts (`SUBDIVISIONS`), and a part whose events are not all refined, or do
    not account for the exponents that crossed, again (`SUBDIVISION_DEPTH`); the
    events found in the parts keep the interval's `between`."""

    def __init__(self, Gl, Fu, n, gtol, exponents):
        self.Gl, self.Fu, self.n, self.gtol, self.exponents = Gl, Fu, n, gtol, exponents

    def between(self, xs, tangents, eig, bordered, jacs, residuals, i, between, depth):
        n, Gl = self.n, self.Gl
        a, b = xs[i], xs[i + 1]
        step_residual = max(residuals[i], residuals[i + 1])
        unstable = [int(np.sum(eig[j].real > 0)) for j in (i, i + 1)]
        events = []
        fold = np.sign(tangents[i][n]) != np.sign(tangents[i + 1][n])
        # the bordered determinant keeps its sign through a fold (the curve is regular there) and changes it at a
        # branch point, also where the curve turns back in p there (a symmetric rotor's pitchfork met along its
        # bifurcating branch: a fold of the tangent, not of the curve)
        crossed = np.sign(bordered[i]) != np.sign(bordered[i + 1])
        # cut once wherever something happens (a complex pair that leaves and returns as a real exponent, or meets
        # another, leaves the counts at the ends as one crossing would), before refining anything
        if depth == SUBDIVISION_DEPTH and (crossed or fold or unstable[0] != unstable[1]):
            finer = self._subdivided(a, b, tangents[i], tangents[i + 1], between, depth)
            if finer is not None:
                return finer
        if crossed:
            events.append(_branch_point_event(Gl, a, b, n, between, self.gtol, step_residual))
        elif fold:
            borders = _borders(jacs[i][:, :n] if abs(tangents[i][n]) < abs(tangents[i + 1][n]) else jacs[i + 1][:, :n])
            z, r = _refined_fold(Gl, jnp.asarray(0.5 * (a + b)), *borders)
            events.append(_refined_event(np.asarray(z), float(r), a, b, n, between, self.gtol, step_residual))
        explained = int(crossed or fold)
        if unstable[0] != unstable[1] and not fold:   # at a fold a real eigenvalue crosses
            # the eigenvalue that crossed: the least unstable one on the more unstable
            # side (not the one nearest the axis, which may be a lightly damped
            # high mode that never crosses)
            e = eig[i + 1] if unstable[1] > unstable[0] else eig[i]
            crossing = e[e.real > 0][np.argmin(e[e.real > 0].real)]
            if abs(crossing.imag) > 1e-8 * max(1.0, abs(crossing)):
                hopf = _refine_hopf(Gl, self.Fu, a, b, n, between=between, exponents=self.exponents)
                # a pair whose real part did not change sign across the step (two real
                # eigenvalues on one side meeting as a pair): no crossing to report
                if hopf.residual <= HOPF_TOL * max(1.0, hopf.frequency):
                    events.append(dataclasses.replace(hopf, crossing=abs(unstable[1] - unstable[0])))
                    explained += 2
        unrefined = any(e.note is not None and e.note.startswith("located to the step") for e in events)
        # a part cut again while its events are not all refined or do not account for the exponents that crossed
        if 0 < depth < SUBDIVISION_DEPTH and (unrefined or abs(unstable[1] - unstable[0]) > explained):
            finer = self._subdivided(a, b, tangents[i], tangents[i + 1], between, depth)
            if finer is not None:
                return finer
        return events

    def _subdivided(self, a, b, ta, tb, between, depth):
        """The events of `a -> b`'s `SUBDIVISIONS` parts (None where a point between
        does not correct onto the branch)."""
        n, Gl = self.n, self.Gl
        chord = (b - a) / np.linalg.norm(b - a)
        guesses = _hermite(a, ta * np.sign(ta @ chord), b, tb * np.sign(tb @ chord),
                           np.linspace(0.0, 1.0, SUBDIVISIONS + 1)[1:-1])
        xs = [a]
        for guess in guesses:
            y = np.asarray(_on_branch(Gl, jnp.asarray(guess), jnp.asarray(chord)))
            r = np.max(np.abs(np.asarray(call(Gl, jnp.asarray(y))))) if np.all(np.isfinite(y)) else np.inf
            if not r <= self.gtol:
                return None
            xs.append(y)
        xs = np.array(xs + [b])
        J = np.concatenate([np.asarray(J) for _, (J,) in chunks(_jacobians, Gl, (xs,), row_bytes=8 * n * (n + 1))])
        tangents = np.array([t * np.sign(t @ chord) for t in (_tangent(Jx) for Jx in J)])
        eig, bordered, jacs = _point_checks(Gl, xs, tangents, self.exponents)
        residuals = [float(np.max(np.abs(np.asarray(call(Gl, jnp.asarray(x)))))) for x in xs]
        events = []
        for j in range(len(xs) - 1):
            events += self.between(xs, tangents, eig, bordered, jacs, residuals, j, between, depth - 1)
        return events


#: `switch_branch`: how many times the first step off a branch point is halved before it gives up
SWITCH_HALVINGS = 6


def switch_branch(F: Callable, event: BranchEvent, p_bounds=(-np.inf, np.inf), h=None, ds=0.01,
                  start_tol=1e-8, **options) -> Branch:
    """The branch of `F(u, p) = 0` that crosses another at its branch point `event`
    (a refined `"branch_point"` of `continue_branch` on the same `F`, holding the
    crossing branch's `tangent`): its first point `h` (default `ds`; halved up to
    `SWITCH_HALVINGS` times until it converges) from the
    branch point along that tangent, corrected by Newton on the hyperplane normal
    to it, then `continue_branch` from there (`p_bounds`, `ds`, `start_tol` and
    `options` as there; traced both ways by default, so through the branch point to
    the crossing branch's other side). A ValueError where `event` is not a refined
    branch point, or the first point does not converge (give a smaller `h`)."""
    if event.kind != "branch_point" or event.tangent is None:
        raise ValueError(f"switch_branch needs a refined branch point (its tangent); got a {event.kind!r} event"
                         + (f" ({event.note})" if event.note else ""))
    u = np.asarray(event.u, dtype=float)
    n = u.size

    def G(x):
        return F(x[:n], x[n])

    x0 = np.concatenate([u, [event.p]])
    Gl = lift(G, jnp.asarray(x0))
    h = ds if h is None else h
    t = np.asarray(event.tangent, dtype=float)
    for k in range(SWITCH_HALVINGS + 1):
        y = np.asarray(_on_branch(Gl, jnp.asarray(x0 + h / 2 ** k * t), jnp.asarray(t)))
        r = float(np.max(np.abs(np.asarray(call(Gl, jnp.asarray(y))))))
        if np.all(np.isfinite(y)) and r <= start_tol:
            break
    else:
        raise ValueError(f"switch_branch: the first point on the crossing branch, {h:g} to {h / 2 ** k:g} from the "
                         f"branch point, did not converge (residual {r:.1e} > {start_tol:g}); give a smaller h")
    return continue_branch(F, y[:n], y[n], p_bounds=p_bounds, ds=ds, start_tol=start_tol, **options)


def _refined_event(z, r, a, b, n, between, gtol, step_residual, kind="fold",
                system="the fold's defining system") -> BranchEvent:
    """A fold (or another `kind` of event) between the branch's points `a` and `b`
    (rows `(u, p)`): refined to `z` (Newton on its defining `system`, residual `r`)
    where that converged (`z` finite, `r <= gtol`, no farther from the step's
    midpoint than the step is long, in every coordinate's largest change); else
    located to the step, at the midpoint, with `step_residual` (the larger `max |F|`
    of the two points) and a note saying why, never a non-finite point."""
    a, b = np.asarray(a), np.asarray(b)
    mid = 0.5 * (a + b)
    if (np.all(np.isfinite(z)) and np.isfinite(r) and r <= gtol
            and np.max(np.abs(z - mid)) <= np.max(np.abs(b - a))):
        return BranchEvent(kind=kind, p=float(z[n]), u=z[:n], residual=r, between=between)
    why = f"residual {r:.1e} > {gtol:g}" if np.isfinite(r) and r > gtol else (
        "a non-finite iterate" if not (np.all(np.isfinite(z)) and np.isfinite(r)) else "it left the step")
    return BranchEvent(kind=kind, p=float(mid[n]), u=mid[:n], residual=float(step_residual), between=between,
                       note=f"located to the step; not refined (Newton on {system}: {why})")


def _branch_point_event(G, a, b, n, between, gtol, step_residual) -> BranchEvent:
    """The branch point between the branch's points `a` and `b` (`G` lifted), refined
    on Moore and Keller's extended system (`_branch_points.refine`), with the
    crossing branch's unit tangent; else located to the step as `_refined_event` says."""
    mid = 0.5 * (np.asarray(a) + np.asarray(b))
    x, phi, r, _ = _branch_points.refine(G, jacobian(G, jnp.asarray(mid)), a, b)
    event = _refined_event(x, r, a, b, n, between, gtol, step_residual, kind="branch_point",
                        system="the branch point's extended system")
    if event.note is not None:
        return event
    chord = (np.asarray(b) - np.asarray(a)) / np.linalg.norm(np.asarray(b) - np.asarray(a))
    tangent, note = _branch_points.other_tangent(G, x, phi, jacobian(G, jnp.asarray(x)), chord)
    return dataclasses.replace(event, tangent=tangent, note=note)


def _fold_system(G, z, b, c):
    """`[G(z); bordered_fold(G_u(z), b, c)]` (on the curve of `G(u, p) = 0`, `z =
    (u, p)`, where `G_u` is singular) and its Jacobian in `z`: `G`'s, and the
    bordered test function's gradient `-w^T (G_u)_z v` (`v`, `w` from the bordered
    system and its transpose; Govaerts 2000, sec. 3.3), the second derivatives by
    `n + 1` directional derivatives of `w^T G_u v` rather than the `(n + 1)^2` of
    differentiating the Jacobian itself (a balance of a few hundred unknowns:
    seconds, not minutes). `G` and its Jacobian come from one forward-mode pass."""
    n = z.size - 1
    Gz, Jz = value_and_jacfwd(G)(z)
    A = jnp.block([[Jz[:, :n], b[:, None]], [c[None, :], jnp.zeros((1, 1))]])
    e = jnp.zeros(n + 1).at[n].set(1.0)
    vg = jnp.linalg.solve(A, e)            # [v; g]: g the test function (`bordered_fold`)
    v = vg.at[n].set(0.0)
    w = jnp.linalg.solve(A.T, e)[:n]

    def bilinear(y):
        return w @ jax.jvp(G, (y,), (v,))[1]

    return jnp.concatenate([Gz, vg[n:]]), jnp.concatenate([Jz, -jax.jacfwd(bilinear)(z)[None]])


@compiled
def _refined_fold(G, z0, b, c):
    """The fold near `z0` (rows `(u, p)`) by the one Newton (`rotorjax._newton`) on
    `_fold_system`, in one compiled loop per structure of `G`: `(z, max |residual|)`
    (the residual from the loop's last evaluation: one copy of the system in the
    program)."""
    z, (_, _, r, _) = newton(None, z0, 1e-12, 30, floor=1e-10, unit=1.0, final=True,
                             value_and_jacobian=lambda y: _fold_system(G, y, b, c))
    return z, jnp.max(jnp.abs(r))


#: a refined Hopf point's largest residual (the pair's real part, F), relative to its frequency
HOPF_TOL = 1e-8


def _refine_hopf(G, Fu, a, b, n, between, exponents) -> BranchEvent:
    """Bisection (Illinois' false position) between two branch points on the real
    part of the eigenvalue pair nearest the imaginary axis (of `exponents(F_u, u,
    p)`, as in `continue_branch`), each trial point corrected onto the branch (one compiled
    corrector per structure of `G(x) = F(x[:n], x[n])`, a `Lifted` function)."""
    tt = jnp.asarray((b - a) / np.linalg.norm(b - a))

    def corrected(s):
        return np.asarray(_on_branch(G, jnp.asarray(a + s * (b - a)), tt))

    def pair_real(y):
        e = np.asarray(exponents(np.asarray(Fu(y[:n], y[n])), y[:n], y[n]))
        k = np.argsort(np.abs(e.real))
        cand = [e[j] for j in k if abs(e[j].imag) > 1e-10]
        return cand[0].real, abs(cand[0].imag)

    (ra, wa), (rb, wb) = pair_real(a), pair_real(b)
    # to a real part well inside the refined point's tolerance (HOPF_TOL of the frequency)
    s = bisect(lambda c: pair_real(corrected(c))[0], 0.0, 1.0, ra, rb, xtol=1e-12, max_iter=60, secant=True,
               ftol=1e-3 * HOPF_TOL * min(wa, wb)).x
    y = corrected(s)
    re, omega = pair_real(y)
    return BranchEvent(kind="hopf", p=float(y[n]), u=y[:n], frequency=float(omega),
                       residual=float(max(np.max(np.abs(np.asarray(call(G, jnp.asarray(y))))), abs(re))),
                       between=between)


@compiled
def _on_branch(G, xp, tt):
    """Newton on `[G(y); tt . (y - xp)] = 0` from `xp` (at most eight steps, to
    round-off, in one compiled loop)."""
    def H(y):
        return jnp.concatenate([G(y), jnp.dot(tt, y - xp)[None]])
    return newton(H, xp, 1e-14, 8, floor=1e-12, unit=1.0)[0]


def _correct_start(s, a, bounds, names, max_iter=30, axis=0):
    """Newton on `s(a) = 0` (central-difference slope) from `a`, `a` the start's
    coordinate `axis`, kept inside the box's range of that coordinate: each step
    at most a quarter of the box's width, and a step that would leave the box
    fails at once with a message naming the start (instead of wandering to where
    the margin is expensive or meaningless)."""
    lo, hi = -np.inf, np.inf
    if bounds is not None:
        lo, hi = (float(np.asarray(b, dtype=float).reshape(-1)[axis]) for b in bounds)
        lo, hi = (-np.inf if np.isnan(lo) else lo), (np.inf if np.isnan(hi) else hi)
    width = hi - lo if np.isfinite(hi - lo) else np.inf
    a0, name = a, names[axis]
    for _ in range(max_iter):
        h = 1e-6 * max(1.0, abs(a))
        va = float(s(a))
        slope = (float(s(a + h)) - float(s(a - h))) / (2 * h)
        if not np.isfinite(va) or not np.isfinite(slope) or slope == 0:
            break
        step = float(np.clip(-va / slope, -0.25 * width, 0.25 * width))
        if not lo <= a + step <= hi:
            raise ValueError(f"no stability boundary near the start {name} = {a0:.6g}: Newton along "
                             f"{name} leaves the box [{lo:.6g}, {hi:.6g}] (margin {va:.3g} at {a:.6g}); "
                             "start nearer the boundary")
        a += step
        if abs(step) < 1e-14 * max(1.0, abs(a)):
            break
    return a


def _on_path(sigma, path, s):
    """`sigma` at the point `s` of the polygon `path` (rows `(s_k, p1_k, p2_k)`)."""
    return sigma(jnp.interp(s, path[:, 0], path[:, 1]), jnp.interp(s, path[:, 0], path[:, 2]))


def _margin_functions(sigma, gradient, n_vertices=2, fd_step=1e-6):
    """For `sigma(p1, p2)`: `along(path)`, the margin along a polygon in the
    parameter plane as a JAX function of the polygon's parameter `s` (`path`:
    rows `(s_k, p1_k, p2_k)`, `s_k` increasing), and `(g, jac)` for `_trace`.

    `along(path)` is an `eqx.Partial` whose `path` is an array leaf, so that under
    `eqx.filter_jit` (the bisection of `critical_speeds`) one compilation serves
    every path of `n_vertices` vertices (and every call with the same `sigma`);
    `g` evaluates a point through that same compiled function, on a path standing
    still at the point (`s = 0`), rather than compiling `sigma` once more."""
    def along(path):
        return eqx.Partial(_on_path, sigma, jnp.asarray(path, dtype=jnp.float64))

    steps = np.arange(float(n_vertices))

    def g(x):
        still = np.column_stack([steps, np.full(n_vertices, x[0]), np.full(n_vertices, x[1])])
        return np.atleast_1d(np.asarray(eqx.filter_jit(along(still))(jnp.float64(0.0)), dtype=float))

    def G(x):
        return jnp.atleast_1d(sigma(x[0], x[1]))

    return along, (g, _jacobian(G, g, gradient, fd_step))


def _boundary(evaluators, p0, *, correct, bounds, names, axis=0, **kw) -> Curve:
    """`trace_boundary` with its evaluators made: `p0` corrected along coordinate
    `axis` (p1 unless the start lies on a side of the box), then traced."""
    g = evaluators[0]
    x0 = np.asarray(p0, dtype=float)
    if correct:
        def s(a):
            y = x0.copy()
            y[axis] = a
            return g(y)[0]

        x0[axis] = _correct_start(s, x0[axis], bounds, names, axis=axis)
    return _trace(None, x0, bounds=bounds, names=names, max_newton=8, gtol=1e-8, fd_step=1e-6, what="margin",
                  error_axis=0, evaluators=evaluators, **kw)


def trace_boundary(sigma: Callable, p0, bounds=None, ds=0.01, ds_max=0.2, max_points=200, tol=1e-11,
                   direction=None, gradient="autodiff", start_tol=1e-7, correct=True, ds_min=1e-9,
                   max_turn=0.2, names=("p1", "p2"), progress=False, dense_tol=None) -> Curve:
    """The curve `sigma(p1, p2) = 0` in two parameters through (or, with `correct`,
    near) `p0`: a stability boundary when `sigma` is a regime's margin. `p0` is
    first corrected along `p1` (Newton, 1-D) when `correct` is set.

    `direction`: None (default) traces both ways and joins the halves (ordered
    from the end reached towards decreasing `p2` at the start to the one towards
    increasing `p2`); a vector `(d1, d2)` traces one way. `bounds`: `(lo, hi)`
    (NaN: no bound); an end at the box lands on its edge exactly. `names` name
    `(p1, p2)` in the stop reasons (`Curve.stops`, e.g. "box edge (mu_w = 1.0)").

    The interpolation errors (`Curve.errors`) are measured along `p1` at fixed
    `p2`, the error a critical speed read off the dense curve would have (where
    the boundary runs within 3 degrees of the `p1` axis, at most 20 times the
    distance to the curve); `dense_tol` bounds them (None: not controlled). See
    `trace_curve` for the rest."""
    _, evaluators = _margin_functions(sigma, gradient)
    return _boundary(evaluators, p0, correct=correct, bounds=bounds, names=names, ds=ds, ds_min=ds_min,
                     ds_max=ds_max, max_points=max_points, tol=tol, direction=direction, start_tol=start_tol,
                     gradient=gradient, max_turn=max_turn, progress=progress, dense_tol=dense_tol)


@dataclasses.dataclass(frozen=True)
class BoundaryCrossing:
    """A crossing of a stability boundary that `trace_boundaries`' scan located
    (one of `Boundaries.crossings`).

    - `p1`, `p2`: where it lies (on its branch, when it has one).
    - `along`: the name of the parameter scanned there (`p1`'s on a line or the
      box's bottom or top, `p2`'s on its sides).
    - `stable_side`: `"above"` or `"below"`, the side of it, in that parameter,
      where the margin is negative.
    - `branch`: the index of the branch through it (traced from it, or found on
      one traced before; `p1, p2` are then that branch's point), or None when no
      branch could be started there, with the reason in `error`.

    `as_dict(names)` gives the JSON row; `crossing["p1"]` style access still reads
    the same keys, deprecated (for code written against the former dict rows)."""

    p1: float
    p2: float
    along: str
    stable_side: str
    branch: int = None
    error: str = None

    def as_dict(self, names=("p1", "p2")) -> dict:
        """JSON-ready: `{names[0]: p1, names[1]: p2, "along", "stable_side",
        "branch", "error" (when set)}` (`names` default `("p1", "p2")`; the CLI
        names them by the parameters)."""
        k1, k2 = names
        return {k1: self.p1, k2: self.p2, "along": self.along, "stable_side": self.stable_side,
                "branch": self.branch, **({"error": self.error} if self.error is not None else {})}

    def __getitem__(self, key):
        _deprecated_key(type(self), key)
        return self.as_dict()[key]

    def __contains__(self, key):
        return key in self.as_dict()


@dataclasses.dataclass(frozen=True)
class Boundaries:
    """Every branch of a stability boundary that `trace_boundaries` found in a box.

    - `branches`: one `Curve` per branch, in the order the scan met them.
    - `lines`: the values of `p2` inside the box along which `p1` was scanned
      (besides the box's edge).
    - `crossings`: each crossing the scan located, a `BoundaryCrossing` (where,
      the parameter scanned there, the stable side, and the index of the branch
      through it, or None with an `error`), in the scan path's order.
    - `box`: `((lo1, hi1), (lo2, hi2))`.

    It is also the sequence of its branches (`len`, iteration, indexing). Frozen;
    `branches` and `crossings` are tuples."""

    branches: tuple
    crossings: tuple
    lines: np.ndarray
    box: tuple

    def __post_init__(self):
        object.__setattr__(self, "branches", tuple(self.branches))
        object.__setattr__(self, "crossings", tuple(self.crossings))

    def __len__(self):
        return len(self.branches)

    def __iter__(self):
        return iter(self.branches)

    def __getitem__(self, i):
        return self.branches[i]


def _meets(curve: Curve, axis: int, value: float, n: int = 32):
    """`(point, error estimate of its interval)` wherever the dense curve meets
    `x[axis] = value`: on each Hermite piece that changes side, that coordinate
    is bisected in the piece's parameter."""
    out = []
    if curve.tangents is None:
        return out
    s = np.linspace(0.0, 1.0, n + 1)
    x, t = curve.x, curve.tangents
    for i in range(len(x) - 1):
        def piece(u):
            return _hermite(x[i], t[i], x[i + 1], t[i + 1], u)

        side = piece(s)[:, axis] - value
        # a change of side within a sample step, or a sample on the hyperplane (once: as a step's left end,
        # or as the curve's last point)
        hits = (side[:-1] * side[1:] < 0) | (side[:-1] == 0)
        if i == len(x) - 2 and side[-1] == 0:
            hits = np.append(hits, True)
        for k in np.flatnonzero(hits):
            a, b, fa = (s[k], s[k + 1], side[k]) if k < n else (1.0, 1.0, 0.0)
            u = bisect(lambda c: piece([c])[0, axis] - value, a, b, fa, xtol=1e-13).x
            pt = piece([u])[0]
            pt[axis] = value
            err = float(curve.errors[i + 1]) if curve.errors is not None else 0.0
            if not any(np.array_equal(pt, q) for q, _ in out):      # a closed loop's first and last point
                out.append((pt, err))
    return out


def _scan_path(lo1, hi1, lo2, hi2, lines):
    """The scan path: round the box's edge (bottom, right side, top, left side),
    then up the left side to the first line and along each line in turn
    (alternately towards increasing and decreasing `p1`), joined along the
    sides. Rows `(s, p1, p2)`, `s` the length in box units (the box's width and
    height each count 1)."""
    verts = [(lo1, lo2), (hi1, lo2), (hi1, hi2), (lo1, hi2), (lo1, lo2)]
    side, other = lo1, hi1
    for b in lines:
        verts += [(side, b), (other, b)]
        side, other = other, side
    verts = np.asarray(verts, dtype=float)
    legs = np.abs(np.diff(verts, axis=0)) / np.array([hi1 - lo1, hi2 - lo2])
    s = np.concatenate([[0.0], np.cumsum(legs.sum(axis=1))])
    return np.column_stack([s, verts])


def trace_boundaries(sigma: Callable, box, n_lines: int = 3, n_scan: int = 40, xtol: float = 1e-4,
                     dense_tol=1e-6, ds=0.02, ds_max=0.2, max_points=200, tol=1e-11, gradient="autodiff",
                     names=("p1", "p2"), ds_min=1e-9, max_turn=0.2, chunk_size=16,
                     progress=False) -> Boundaries:
    """Every branch of the stability boundary `sigma(p1, p2) = 0` in a box, each
    traced both ways to where it ends (the box's edges, through turning points,
    or round a closed loop), with its dense curve accurate to `dense_tol`.

    **Arguments:**

    - `sigma`: the margin, a JAX-traceable scalar function of `(p1, p2)`.
    - `box`: `((lo1, hi1), (lo2, hi2))`, finite.
    - `n_lines`, `n_scan`, `xtol`, `chunk_size`: the starts. One `critical_speeds`
      scan (`n_scan` points per width or height of the box, `chunk_size` per
      vmapped call) and bisection (to `xtol` of the box's size: the starts are
      then corrected by Newton, the other crossings moved onto their branches)
      runs along one continuous path: round the box's
      edge, then along `n_lines` lines of constant `p2` (the middles of equal
      bands across the box), joined along the sides. Every branch that ends on
      the box's edge is met on the edge; the lines meet closed loops inside.
      Crossings are taken in the path's order; one that lies on a branch traced
      already (that branch's dense curve meets its line or side within the
      crossing's final bisection bracket, widened by ten times the branch's
      error estimate there or 1e-6 of the box) is assigned to it; any other is
      corrected along its line or side by `trace_boundary`'s bounded Newton and
      traced. Not found: a closed loop that crosses no line, and branches that
      cross the path twice within one scan step.
    - `dense_tol`: the accuracy of each branch's dense curve along `p1` at fixed
      `p2` (see `trace_boundary`); None: steps not controlled by it.
    - the rest: as in `trace_boundary` (`max_points` per branch).

    **Returns:** `Boundaries`: its branches, the lines, and every crossing with
    the branch through it.
    """
    from ._critical import critical_speeds

    (lo1, hi1), (lo2, hi2) = ((float(a), float(b)) for a, b in box)
    for lo, hi, k in ((lo1, hi1, names[0]), (lo2, hi2, names[1])):
        if not (np.isfinite(lo) and np.isfinite(hi) and lo < hi):
            raise ValueError(f"box: the range of {k} must be finite and increasing, got ({lo}, {hi})")
    if int(n_lines) < 1 or int(n_scan) < 2:
        raise ValueError(f"need n_lines >= 1 and n_scan >= 2, got {n_lines} and {n_scan}")
    n_lines = int(n_lines)
    bounds = (np.array([lo1, lo2]), np.array([hi1, hi2]))
    lines = lo2 + (np.arange(n_lines) + 0.5) / n_lines * (hi2 - lo2)
    path = _scan_path(lo1, hi1, lo2, hi2, lines)
    along, evaluators = _margin_functions(sigma, gradient, n_vertices=len(path))
    length = path[-1, 0]
    found = critical_speeds(along(path), 0.0, length, n_scan=int(np.ceil(n_scan * length)) + 1, xtol=xtol,
                            chunk_size=chunk_size, progress=progress)
    crossings = []
    for c in found:
        k = min(int(np.searchsorted(path[:, 0], c.speed, side="right")) - 1, len(path) - 2)
        leg = path[k + 1, 1:] - path[k, 1:]
        axis = 0 if leg[0] != 0 else 1
        p = path[k, 1:] + (c.speed - path[k, 0]) / (path[k + 1, 0] - path[k, 0]) * leg
        p[1 - axis] = path[k, 1 + (1 - axis)]           # exactly on its line, or on the box's side
        side = c.stable_side if leg[axis] > 0 else {"above": "below", "below": "above"}[c.stable_side]
        span = sorted(path[k, 1 + axis] + (np.asarray(c.bracket) - path[k, 0]) / (path[k + 1, 0] - path[k, 0])
                      * leg[axis])
        crossings.append({"p1": float(p[0]), "p2": float(p[1]), "along": names[axis], "stable_side": side,
                          "branch": None, "_axis": axis, "_span": span})
    floor = 1e-6 * np.array([hi1 - lo1, hi2 - lo2])
    branches = []

    for c in crossings:
        if c["branch"] is not None or "error" in c:
            continue
        axis = c["_axis"]
        try:
            curve = _boundary(evaluators, (c["p1"], c["p2"]), correct=True, bounds=bounds, names=names,
                              axis=axis, ds=ds, ds_min=ds_min, ds_max=ds_max, max_points=max_points, tol=tol,
                              direction=None, start_tol=1e-7, gradient=gradient, max_turn=max_turn,
                              progress=progress, dense_tol=dense_tol)
        except ValueError as e:
            c["error"] = str(e)
            continue
        branches.append(curve)
        c["branch"] = len(branches) - 1        # its own start, where the corrected start lies
        c["p1"], c["p2"] = (float(v) for v in curve.x[curve.start])
        for o in crossings:
            if o["branch"] is None and "error" not in o:
                ax, (a, b) = o["_axis"], o["_span"]
                for pt, err in _meets(curve, 1 - ax, (o["p1"], o["p2"])[1 - ax]):
                    if a - max(floor[ax], 10 * err) <= pt[ax] <= b + max(floor[ax], 10 * err):
                        # the branch's point there, to its accuracy rather than the bisection's
                        o["branch"], o["p1"], o["p2"] = c["branch"], float(pt[0]), float(pt[1])
                        break
    rows = tuple(BoundaryCrossing(p1=c["p1"], p2=c["p2"], along=c["along"], stable_side=c["stable_side"],
                                  branch=c["branch"], error=c.get("error")) for c in crossings)
    return Boundaries(branches=tuple(branches), crossings=rows, lines=lines,
                      box=((lo1, hi1), (lo2, hi2)))


def boundary_sensitivity(sigma3: Callable, point, q, axis=0) -> float:
    """How far the boundary `sigma(p1, p2; q) = 0` moves along parameter `axis`
    (0: p1 at fixed p2) per unit of a third parameter `q`, by the implicit
    function theorem: `-(d sigma/d q) / (d sigma / d p_axis)` (autodiff)."""
    p1, p2 = (jnp.float64(v) for v in point)

    def along(x, qq):
        return sigma3(x, p2, qq) if axis == 0 else sigma3(p1, x, qq)

    return float(root_gradient(along, point[axis], q))


def fold_curve(F: Callable, u0, p0, ds=0.01, ds_max=0.2, max_points=200, tol=1e-11, bounds=None,
               direction=None, names=("p1", "p2")) -> Curve:
    """Two-parameter continuation of folds of `F(u, p1, p2) = 0`: the curve
    `{F = 0, F_u singular}` in `(u, p1, p2)` from a fold `(u0, p0 = (p1, p2))`
    (singular: the bordered test function of the fold, bordered by `F_u`'s
    singular vectors at the start); both ways from it unless `direction` (a
    vector in `(u, p1, p2)`) is given."""
    u0 = np.asarray(u0, dtype=float)
    n = u0.size
    g = _fold_function(jax.jacfwd(F)(jnp.asarray(u0), *(jnp.float64(v) for v in p0)))

    def G(x):
        f, Fu = value_and_jacfwd(F)(x[:n], x[n], x[n + 1])
        return jnp.concatenate([f, g(Fu)[None]])

    return trace_curve(G, np.concatenate([u0, np.asarray(p0, dtype=float)]), ds=ds, ds_max=ds_max,
                       max_points=max_points, tol=tol, bounds=bounds, direction=direction,
                       names=[None] * n + list(names))


def fold_gradient(F: Callable, u, p, q):
    """How a fold `(u*, p*)` of `F(u, p, q) = 0` moves with a third parameter `q`:
    `dp*/dq`, by the implicit function theorem on the fold's defining system
    `[F; g(F_u)] = 0` (`g` the bordered test function, bordered at the fold itself):
    `d(u*, p*)/dq = -G_(u,p)^{-1} G_q`, all by autodiff (`q` a scalar)."""
    u = jnp.asarray(u, dtype=jnp.float64)
    n = u.size
    p, q = jnp.float64(p), jnp.float64(q)
    g = _fold_function(jax.jacfwd(F)(u, p, q))

    def G(z, qq):
        f, Fu = value_and_jacfwd(F)(z[:n], z[n], qq)
        return jnp.concatenate([f, g(Fu)[None]])

    z = jnp.concatenate([u, p[None]])
    Gz, Gq = jax.jacfwd(G, argnums=(0, 1))(z, q)
    return float(-jnp.linalg.solve(Gz, Gq)[n])


@dataclasses.dataclass(frozen=True)
class FloquetCrossing:
    """Where a periodic regime's Floquet multiplier crosses the unit circle (one
    row of `floquet_crossings`).

    - `p`: the parameter at the crossing (bisected to `xtol`).
    - `kind`: the crossing multiplier: `"+1"` (fold or pitchfork of the periodic
      regime), `"-1"` (period doubling) or `"complex pair"` (Neimark-Sacker).
    - `multiplier`: `(real, imag)` of the multiplier nearest the unit circle.
    - `residual`: `| |mu| - 1 |` of that multiplier.
    - `closure`, `liouville_error`, `code`: the checks and the `RESULTS` code of
      the Floquet result at the crossing.
    - `stable_side`: `"above"` or `"below"`, the side in `p` where the largest
      multiplier lies inside the unit circle.

    `as_dict()` gives the JSON row; `row["p"]` style access reads the same keys
    (for code written against the former dict rows)."""

    p: float
    kind: str
    multiplier: tuple
    residual: float
    closure: float
    liouville_error: float
    stable_side: str
    code: int = 0

    def __post_init__(self):
        object.__setattr__(self, "multiplier", tuple(float(v) for v in self.multiplier))

    def as_dict(self) -> dict:
        """JSON-ready: `{"p", "kind", "multiplier": [re, im], "residual", "closure",
        "liouville_error", "stable_side", "code"}`."""
        return {"p": self.p, "kind": self.kind, "multiplier": list(self.multiplier), "residual": self.residual,
                "closure": self.closure, "liouville_error": self.liouville_error,
                "stable_side": self.stable_side, "code": self.code}

    def __getitem__(self, key):
        return self.as_dict()[key]


def floquet_crossings(floquet_fn: Callable, lo: float, hi: float, n_scan: int = 60, xtol: float = 1e-10,
                      progress: bool = False) -> tuple:
    """Follow a periodic regime's Floquet multipliers along a parameter and find
    where one leaves (or enters) the unit circle: `floquet_fn(p)` returns a
    `FloquetResult` (e.g. `anisotropic_abb.main_motion_floquet` at speed `p`).
    Each crossing is located by `critical_speeds` (vmapped scan, bisection) on
    `max |mu| - 1` and classified by the
    crossing multiplier: at +1 (fold or pitchfork of the periodic regime), at -1
    (period doubling), or a complex pair (Neimark-Sacker: quasi-periodic motion).
    Returns a tuple of `FloquetCrossing` (in increasing `p`); the checks are
    those of the Floquet result at the crossing."""
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
        out.append(FloquetCrossing(p=c.speed, kind=kind, multiplier=(mu[k].real, mu[k].imag),
                                   residual=float(abs(abs(mu[k]) - 1)), closure=float(r.closure),
                                   liouville_error=float(r.liouville_error), stable_side=c.stable_side,
                                   code=int(np.asarray(r.code))))
    return tuple(out)


def boundary_points(sigma: Callable, p1_guess, p2_values, iters: int = 12):
    """Batched pointwise boundary solves: for each `p2`, Newton along `p1` on
    `sigma(p1, p2) = 0` from `p1_guess` (scalar or per point), vmapped over the
    batch (a fixed number of iterations in one compiled loop, so the whole batch is
    one call and `sigma` is traced twice, not `iters` times). Returns `(p1, residual)`
    arrays; a point whose residual stays large has not converged."""
    p2 = jnp.asarray(p2_values, dtype=jnp.float64)
    p1 = jnp.broadcast_to(jnp.asarray(p1_guess, dtype=jnp.float64), p2.shape)
    ds = jax.grad(sigma, argnums=0)

    def solve(a, b):
        a = jax.lax.fori_loop(0, iters, lambda _, a: a - sigma(a, b) / ds(a, b), a)
        return a, jnp.abs(sigma(a, b))

    return jax.jit(jax.vmap(solve))(p1, p2)
