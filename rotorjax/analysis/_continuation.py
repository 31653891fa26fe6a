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

Every result carries its checks: the residual of the defining system at every
point, the step history, and why it stopped.
"""

import dataclasses
from typing import Callable

import jax
import jax.numpy as jnp
import numpy as np


@dataclasses.dataclass
class Curve:
    """Points `x` (rows) of an implicit curve, with `residuals` (max |G|), the
    arclength steps taken, the corrector's iterations, and `stopped` (why)."""

    x: np.ndarray
    residuals: np.ndarray
    steps: np.ndarray
    iterations: np.ndarray
    stopped: str


def _tangent(jac):
    """Unit null vector of a `k x (k+1)` Jacobian."""
    q, _ = np.linalg.qr(jac.T, mode="complete")
    return q[:, -1]


def trace_curve(G: Callable, x0, ds=0.01, ds_min=1e-9, ds_max=0.2, max_points=200, tol=1e-11,
                direction=None, bounds=None, max_newton=8, start_tol=1e-7, gradient="autodiff",
                fd_step=1e-6, gtol=1e-8) -> Curve:
    """Follow `G(x) = 0` from `x0` (see the module docstring).

    - `direction`: a vector the first tangent should point along (default: the
      tangent's own sign, with its last component positive).
    - `bounds`: `(lo, hi)` arrays for `x` (NaN for no bound): leaving them stops
      the curve cleanly (`stopped` says so), the last point inside kept.
    - `gradient`: "autodiff" or "fd" (central differences with relative `fd_step`,
      for `G` whose derivatives autodiff cannot give reliably, e.g. Floquet margins).
    - A corrected point is accepted when Newton's last step is below `tol`
      (relative; or below `1e3 tol` at the iteration cap: the noise floor of `G`)
      and `max |G| <= gtol`.
    A start with `max |G(x0)| > start_tol` raises a ValueError stating the residual.
    """
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

    x = np.asarray(x0, dtype=float)
    r0 = float(np.max(np.abs(g(x))))
    if not np.isfinite(r0) or r0 > start_tol:
        raise ValueError(f"the starting point is not on the curve: residual {r0:.3e} > {start_tol:.1e} "
                         "(correct it first, e.g. with Newton at fixed parameters)")
    lo = hi = None
    if bounds is not None:
        lo, hi = (np.where(np.isnan(np.asarray(b, dtype=float)), -np.inf if k == 0 else np.inf,
                           np.asarray(b, dtype=float)) for k, b in enumerate(bounds))
        if np.any(x < lo) or np.any(x > hi):
            raise ValueError(f"the starting point {x} lies outside the bounds")
    t = _tangent(jac(x))
    if direction is not None:
        t = t if t @ np.asarray(direction, dtype=float) >= 0 else -t
    elif t[-1] < 0:
        t = -t
    xs, res, steps, iters = [x.copy()], [r0], [0.0], [0]
    stopped = "max_points"
    while len(xs) < max_points:
        ok = False
        while ds >= ds_min:
            xp = x + ds * t
            y = xp.copy()
            for it in range(1, max_newton + 1):
                gy = g(y)
                A = np.vstack([jac(y), t[None, :]])
                rhs = np.concatenate([gy, [t @ (y - xp)]])
                try:
                    dy = np.linalg.solve(A, -rhs)
                except np.linalg.LinAlgError:
                    break
                y = y + dy
                if not np.all(np.isfinite(y)):
                    break
                step = np.max(np.abs(dy)) / max(1.0, np.max(np.abs(y)))
                if step <= tol or (it == max_newton and step <= 1e3 * tol):
                    ok = float(np.max(np.abs(g(y)))) <= gtol
                    break
            if ok:
                break
            ds /= 2
        if not ok:
            stopped = "step size below ds_min: the corrector does not converge (a singular point?)"
            break
        if lo is not None and (np.any(y < lo) or np.any(y > hi)):
            stopped = "left the parameter box"
            break
        t_new = _tangent(jac(y))
        t = t_new if t_new @ t >= 0 else -t_new
        xs.append(y.copy())
        res.append(float(np.max(np.abs(g(y)))))
        steps.append(ds)
        iters.append(it)
        x = y
        if len(xs) > 3 and np.linalg.norm(x - xs[0]) < 0.5 * ds and steps[-1] > 0:
            stopped = "closed loop"
            break
        ds = min(ds * (1.5 if it <= 3 else 1.0 if it <= 5 else 0.5), ds_max)
    return Curve(x=np.asarray(xs), residuals=np.asarray(res), steps=np.asarray(steps),
                 iterations=np.asarray(iters), stopped=stopped)


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

    def as_dict(self):
        return {"p": self.p.tolist(), "margin": self.margin.tolist(), "stable": self.stable.tolist(),
                "events": [{k: (v.tolist() if isinstance(v, np.ndarray) else v) for k, v in e.items()}
                           for e in self.events],
                "residual_max": float(self.curve.residuals.max()), "stopped": self.curve.stopped,
                "n_points": int(self.p.size)}


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
                    tol=1e-11, direction=1.0, start_tol=1e-8) -> Branch:
    """One-parameter continuation of `F(u, p) = 0` from a solution `(u0, p0)`,
    towards increasing `p` (`direction=1`) or decreasing (-1), within `p_bounds`."""
    u0 = np.asarray(u0, dtype=float)
    n = u0.size

    def G(x):
        return F(x[:n], x[n])

    lo = np.full(n + 1, np.nan)
    hi = np.full(n + 1, np.nan)
    lo[n], hi[n] = p_bounds
    d = np.zeros(n + 1)
    d[n] = direction
    curve = trace_curve(G, np.concatenate([u0, [p0]]), ds=ds, ds_max=ds_max, max_points=max_points, tol=tol,
                        direction=d, bounds=(lo, hi), start_tol=start_tol)
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


def trace_boundary(sigma: Callable, p0, bounds=None, ds=0.01, ds_max=0.2, max_points=200, tol=1e-11,
                   direction=None, gradient="autodiff", start_tol=1e-7, correct=True) -> Curve:
    """The curve `sigma(p1, p2) = 0` in two parameters through (or, with `correct`,
    near) `p0`: a stability boundary when `sigma` is a regime's margin. `p0` is
    first corrected along `p1` (Newton, 1-D) when `correct` is set."""
    def G(x):
        return jnp.atleast_1d(sigma(x[0], x[1]))

    x0 = np.asarray(p0, dtype=float)
    if correct:
        s = jax.jit(lambda a: sigma(a, x0[1]))
        a = x0[0]
        for _ in range(30):
            h = 1e-6 * max(1.0, abs(a))
            va = float(s(a))
            slope = (float(s(a + h)) - float(s(a - h))) / (2 * h)
            if not np.isfinite(va) or slope == 0:
                break
            step = -va / slope
            a += step
            if abs(step) < 1e-14 * max(1.0, abs(a)):
                break
        x0 = np.array([a, x0[1]])
    return trace_curve(G, x0, ds=ds, ds_max=ds_max, max_points=max_points, tol=tol, direction=direction,
                       bounds=bounds, gradient=gradient, start_tol=start_tol)


def boundary_sensitivity(sigma3: Callable, point, q, axis=0) -> float:
    """How far the boundary `sigma(p1, p2; q) = 0` moves along parameter `axis`
    (0: p1 at fixed p2) per unit of a third parameter `q`, by the implicit
    function theorem: `-(d sigma/d q) / (d sigma / d p_axis)` (autodiff)."""
    g = jax.grad(sigma3, argnums=(0, 1, 2))(jnp.float64(point[0]), jnp.float64(point[1]), jnp.float64(q))
    return float(-g[2] / g[axis])


def fold_curve(F: Callable, u0, p0, ds=0.01, ds_max=0.2, max_points=200, tol=1e-11, bounds=None,
               direction=None) -> Curve:
    """Two-parameter continuation of folds of `F(u, p1, p2) = 0`: the curve
    `{F = 0, det F_u = 0}` in `(u, p1, p2)` from a fold `(u0, p0 = (p1, p2))`."""
    u0 = np.asarray(u0, dtype=float)
    n = u0.size

    def G(x):
        u, p1, p2 = x[:n], x[n], x[n + 1]
        return jnp.concatenate([F(u, p1, p2), jnp.linalg.det(jax.jacfwd(F)(u, p1, p2))[None]])

    return trace_curve(G, np.concatenate([u0, np.asarray(p0, dtype=float)]), ds=ds, ds_max=ds_max,
                       max_points=max_points, tol=tol, bounds=bounds, direction=direction)


def floquet_crossings(floquet_fn: Callable, lo: float, hi: float, n_scan: int = 60, xtol: float = 1e-10):
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
                             n_scan=n_scan, xtol=xtol):
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
