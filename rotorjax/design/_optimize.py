"""The one mechanism for constrained design: minimise `f(x)` subject to `c_j(x) <= 0`
and bounds `lo <= x <= hi`, from many starts at once (vmapped), on JAX gradients.

- **Scaling.** Each parameter is mapped to `u` in `[0, 1]`, linearly, or in its
  logarithm where `log` says (a stiffness or damping spanning decades).
- **Augmented Lagrangian** (Powell-Hestenes-Rockafellar) for the inequality
  constraints: `L = f + sum_j (max(0, lambda_j + mu c_j)^2 - lambda_j^2) / (2 mu)`;
  after each subproblem `lambda <- max(0, lambda + mu c)`, and `mu` grows tenfold
  when the largest violation has not fallen to a quarter.
- **Subproblems** in the box: projected quasi-Newton. BFGS's inverse Hessian acts on
  the free variables (those not held at a bound by the gradient), a projected
  backtracking (Armijo) search on the step, BFGS updates where `s^T y > 0`.
- **Convergence** (the KKT conditions to `tol`): largest violation, complementarity
  `min(-c_j, lambda_j)`, and a solved subproblem: its projected gradient in `u`
  below `tol` (relative to `max(1, |f|)`), or no step lowering `L` by more than 1e-12
  of it.

Every start runs the same compiled loops (`jax.vmap` over the starts: each lane stops
changing when it has converged). The result has every start's end point, the best
start's history (per outer iteration: objective, largest violation, `mu`, projected
gradient, inner iterations), each constraint's value and multiplier.
"""

import dataclasses
import functools

import jax
import jax.numpy as jnp
import numpy as np

from .._errors import InputError

#: why a subproblem stopped short of its tolerance: its steps no longer lower `L`; no step is acceptable
FLAT, NO_STEP = 1, 2
#: how many accepted steps `Optimum.steps` keeps
TRACE = 400


@dataclasses.dataclass(frozen=True, eq=False)
class Optimum:
    """The end of `minimize`.

    - `x`, `objective`, `constraints` (`c_j`, `<= 0` met), `multipliers`: the best
      start's (the least objective among the feasible ends, else the least violation);
    - `converged` (the KKT conditions to `tol`), `feasible` (violation `<= tol`),
      `reason` (a sentence); `iterations` (outer), `evaluations` (of `f`, `c` and
      their gradients), `history` `(iterations, 6)`: objective, largest violation,
      `mu`, projected gradient, inner iterations, and why the subproblem stopped
      (0: its tolerance or its iterations, `FLAT`, `NO_STEP`) per outer iteration;
      `steps` `(n, 2)`: the objective and largest violation after each accepted step
      (the first `TRACE`);
    - all starts: `starts`, `ends` `(n_starts, n)`, `end_objectives`,
      `end_violations`, `end_converged`; `best` (the index).
    """

    x: np.ndarray
    objective: float
    constraints: np.ndarray
    multipliers: np.ndarray
    converged: bool
    feasible: bool
    reason: str
    iterations: int
    evaluations: int
    history: np.ndarray
    steps: np.ndarray
    starts: np.ndarray
    ends: np.ndarray
    end_objectives: np.ndarray
    end_violations: np.ndarray
    end_converged: np.ndarray
    best: int


def _ends(lo, hi, log):
    """The scaled box's ends: `lo`, `hi`, or their logarithms where `log`."""
    return (np.where(log, np.log(np.where(log, lo, 1.0)), lo), np.where(log, np.log(np.where(log, hi, 1.0)), hi))


def _to_x(u, a, b, log):
    z = a + (b - a) * u
    return jnp.where(log, jnp.exp(z), z)


def _to_u(x, a, b, log):
    return (np.where(log, np.log(np.where(log, x, 1.0)), x) - a) / (b - a)


def _projected_gradient(u, g):
    return jnp.max(jnp.abs(jnp.clip(u - g, 0.0, 1.0) - u))


def _inner(vg, u, lam, mu, tol, max_inner, trace, pos, ftol=1e-12):
    """Projected BFGS on `L(., lam, mu)` in the unit box from `u`: `(u, (L, (f, c)), g, evaluations)`."""
    n = u.shape[0]
    (val, aux), g = vg(u, lam, mu)
    H = jnp.eye(n) * jnp.minimum(1.0, 0.1 / jnp.maximum(jnp.max(jnp.abs(g)), 1e-300))

    def cond(s):
        it, u, val, aux, g, H, n_eval, stop, trace, pos = s
        return (it < max_inner) & (stop == 0) & (_projected_gradient(u, g) > tol * jnp.maximum(1.0, jnp.abs(val)))

    def body(s):
        it, u, val, aux, g, H, n_eval, _, trace, pos = s
        free = ~(((u <= 0.0) & (g > 0)) | ((u >= 1.0) & (g < 0)))
        ff = free[:, None] & free[None, :]
        d = -(jnp.where(ff, H, 0.0) @ jnp.where(free, g, 0.0))
        descent = jnp.dot(d, g) < 0
        d = jnp.where(descent, d, -jnp.where(free, g, 0.0) * jnp.minimum(1.0, 0.1 / jnp.max(jnp.abs(g))))
        H = jnp.where(descent, H, jnp.eye(n) * jnp.minimum(1.0, 0.1 / jnp.max(jnp.abs(g))))

        def ls_cond(t):
            step, k, un, vn, auxn, gn, ok = t
            return ~ok & (k < 24)

        def ls_body(t):
            step, k, _, _, _, _, _ = t
            un = jnp.clip(u + step * d, 0.0, 1.0)
            (vn, auxn), gn = vg(un, lam, mu)
            ok = jnp.isfinite(vn) & jnp.all(jnp.isfinite(gn)) & (vn <= val + 1e-4 * jnp.dot(g, un - u))
            return step * 0.5, k + 1, un, vn, auxn, gn, ok

        _, k, un, vn, auxn, gn, ok = jax.lax.while_loop(ls_cond, ls_body, (1.0, 0, u, val, aux, g, False))
        s_, y = un - u, gn - g
        sy = jnp.dot(s_, y)
        rho = 1.0 / jnp.where(sy > 0, sy, 1.0)
        V = jnp.eye(n) - rho * jnp.outer(s_, y)
        curved = sy > 1e-12 * jnp.linalg.norm(s_) * jnp.linalg.norm(y)
        H_new = jnp.where(curved, V @ H @ V.T + rho * jnp.outer(s_, s_), H)
        keep = lambda new, old: jnp.where(ok, new, old)  # noqa: E731
        # stalled: no acceptable step, or a step that no longer lowers L (relative to its size)
        flat = ok & (val - vn <= ftol * jnp.maximum(1.0, jnp.abs(val)))
        trace = jnp.where(ok & (pos < trace.shape[0]), trace.at[jnp.minimum(pos, trace.shape[0] - 1)].set(
            jnp.stack([auxn[0], jnp.max(jnp.maximum(auxn[1], 0.0), initial=0.0)])), trace)
        return (it + 1, keep(un, u), keep(vn, val), jax.tree_util.tree_map(keep, auxn, aux), keep(gn, g),
                keep(H_new, H), n_eval + k, jnp.where(ok, jnp.where(flat, FLAT, 0), NO_STEP), trace, pos + ok)

    it, u, val, aux, g, H, n_eval, stop, trace, pos = jax.lax.while_loop(
        cond, body, (0, u, val, aux, g, H, 1, 0, trace, pos))
    return u, aux, g, n_eval, it, stop, trace, pos


def _run(vg, u0, m, tol, max_outer, max_inner, mu0):
    """One start: the augmented Lagrangian's outer loop (see the module)."""
    lam = jnp.zeros(m)
    hist = jnp.full((max_outer, 6), jnp.nan)
    trace = jnp.full((TRACE, 2), jnp.nan)

    def cond(s):
        k, u, lam, mu, viol, hist, n_eval, done, trace, pos = s
        return (k < max_outer) & ~done

    def body(s):
        k, u, lam, mu, viol_prev, hist, n_eval, _, trace, pos = s
        u, (f, c), g, ne, inner, stop, trace, pos = _inner(vg, u, lam, mu, tol, max_inner, trace, pos)
        viol = jnp.max(jnp.maximum(c, 0.0), initial=0.0)
        lam_new = jnp.maximum(0.0, lam + mu * c)
        # the Lagrangian's gradient with the new multipliers: the same as L's at the subproblem's end
        pg = _projected_gradient(u, g)
        compl = jnp.max(jnp.abs(jnp.minimum(-c, lam_new)), initial=0.0)
        # converged: feasible, the multipliers consistent, and the subproblem solved (its projected gradient
        # small, or no further decrease possible at working precision)
        scale = jnp.maximum(1.0, jnp.abs(f))
        done = (viol <= tol) & (compl <= tol) & ((pg <= tol * scale) | (stop == FLAT))
        stuck = (stop == NO_STEP) & (inner <= 1)      # not a step from where the last subproblem ended
        mu_new = jnp.where(viol > 0.25 * viol_prev, jnp.minimum(10 * mu, 1e10), mu)
        hist = hist.at[k].set(jnp.stack([f, viol, mu, pg, inner, stop]))
        return k + 1, u, lam_new, mu_new, viol, hist, n_eval + ne, done | stuck, trace, pos

    k, u, lam, mu, viol, hist, n_eval, end, trace, pos = jax.lax.while_loop(
        cond, body, (0, u0, lam, jnp.float64(mu0), jnp.float64(jnp.inf), hist, 0, False, trace, 0))
    last = hist[jnp.maximum(k - 1, 0)]
    done = end & (last[1] <= tol) & ((last[3] <= tol * jnp.maximum(1.0, jnp.abs(last[0]))) | (last[5] == FLAT))
    return u, lam, k, hist, n_eval, done, trace


@functools.partial(jax.jit, static_argnames=("fn", "m", "tol", "max_outer", "max_inner", "mu0"))
def _solve(fn, u0s, a, b, log, *, m, tol, max_outer, max_inner, mu0):
    """Every start's run, and `fn` at the ends: one compiled program per `fn` and
    settings (a second `minimize` of the same function reuses it)."""
    def lagrangian(u, lam, mu):
        f, c = fn(_to_x(u, a, b, log))
        c = jnp.reshape(c, (m,))
        return f + jnp.sum(jnp.maximum(0.0, lam + mu * c) ** 2 - lam**2) / (2 * mu), (f, c)

    vg = jax.value_and_grad(lagrangian, has_aux=True)
    u, lam, k, hist, n_eval, done, trace = jax.vmap(
        lambda u0: _run(vg, u0, m, tol, max_outer, max_inner, mu0))(u0s)
    ends = jax.vmap(lambda v: _to_x(v, a, b, log))(u)
    f_end, c_end = jax.vmap(fn)(ends)
    return u, lam, k, hist, n_eval, done, trace, ends, f_end, c_end


def minimize(fn, lo, hi, starts, *, log=None, tol=1e-6, max_outer=30, max_inner=200, mu0=10.0) -> Optimum:
    """Minimise `fn(x) -> (f, c)` (`f` a scalar, `c` an `(m,)` array, `c <= 0` met; pure
    JAX) over `lo <= x <= hi` from each row of `starts` `(n_starts, n)` (see the
    module). `log`: per parameter, whether it is scaled in its logarithm (needs
    `lo > 0`). `f` and `c` should be of order one (scale them). Returns an `Optimum`;
    `InputError` for bad bounds or starts."""
    lo, hi = np.asarray(lo, dtype=float), np.asarray(hi, dtype=float)
    starts = np.atleast_2d(np.asarray(starts, dtype=float))
    n = lo.size
    log = np.zeros(n, bool) if log is None else np.asarray(log, bool)
    if hi.shape != (n,) or starts.shape[1] != n or log.shape != (n,):
        raise InputError(f"minimize: lo, hi, log and the starts' rows must have one entry per parameter ({n})")
    if not (np.all(np.isfinite(lo)) and np.all(np.isfinite(hi)) and np.all(lo < hi)):
        raise InputError("minimize: every bound needs finite lo < hi")
    if np.any(log & (lo <= 0)):
        raise InputError("minimize: a parameter scaled in its logarithm needs lo > 0")
    if np.any(starts < lo) or np.any(starts > hi):
        raise InputError("minimize: every start must lie within the bounds")
    a, b = _ends(lo, hi, log)
    m = int(np.prod(jax.eval_shape(fn, jnp.asarray(starts[0]))[1].shape))
    u, lam, k, hist, n_eval, done, trace, ends, f_end, c_end = (np.asarray(v) for v in _solve(
        fn, jnp.asarray(_to_u(starts, a, b, log)), jnp.asarray(a), jnp.asarray(b), jnp.asarray(log), m=m,
        tol=float(tol), max_outer=int(max_outer), max_inner=int(max_inner), mu0=float(mu0)))
    c_end = c_end.reshape(len(ends), m)
    viol = np.max(np.maximum(c_end, 0.0), axis=1, initial=0.0)
    finite = np.isfinite(f_end) & np.all(np.isfinite(c_end), axis=1)
    feasible = finite & (viol <= tol)
    if feasible.any():
        best = int(np.flatnonzero(feasible)[np.argmin(f_end[feasible])])
    else:
        best = int(np.argmin(np.where(finite, viol, np.inf)))
    kb = int(k[best])
    if done[best]:
        reason = f"converged: feasible and stationary to {tol:g} after {kb} outer iterations"
    elif not finite[best]:
        reason = "no start ended at a point where the objective and constraints are finite"
    else:
        last = hist[best, kb - 1]
        why = " (no step lowered the objective: it may not be smooth there)" if last[5] == NO_STEP else ""
        reason = (f"not converged after {kb} outer iterations: largest violation {last[1]:.3g}, projected gradient "
                  f"{last[3]:.3g} (tolerance {tol:g}){why}")
    return Optimum(x=ends[best], objective=float(f_end[best]), constraints=c_end[best], multipliers=lam[best],
                   converged=bool(done[best]), feasible=bool(feasible[best]), reason=reason, iterations=kb,
                   evaluations=int(n_eval[best]), history=hist[best, :kb],
                   steps=trace[best][np.isfinite(trace[best, :, 0])], starts=starts, ends=ends,
                   end_objectives=f_end, end_violations=viol, end_converged=done.astype(bool), best=best)


def latin_starts(lo, hi, n_starts, first=None, log=None, seed=0):
    """`(n_starts, n)` starting points in the bounds: `first` (clipped into them) and a
    Latin hypercube in the scaled box (logarithmic where `log`)."""
    lo, hi = np.asarray(lo, dtype=float), np.asarray(hi, dtype=float)
    n = lo.size
    log = np.zeros(n, bool) if log is None else np.asarray(log, bool)
    a, b = _ends(lo, hi, log)
    rng = np.random.default_rng(seed)
    k = n_starts - (first is not None)
    u = (np.stack([rng.permutation(k) for _ in range(n)], axis=1) + rng.random((k, n))) / max(k, 1)
    rows = [np.asarray(jax.vmap(lambda v: _to_x(v, a, b, log))(jnp.asarray(u)))] if k > 0 else []
    if first is not None:
        rows.insert(0, np.clip(np.asarray(first, dtype=float), lo, hi)[None, :])
    return np.concatenate(rows, axis=0)
