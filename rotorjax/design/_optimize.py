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

Every start runs in lock-step: one compiled program evaluates `L` and its gradient
at every start's point at once (`jax.vmap`), and the loops around it run on the host
(a compiled loop around the eigenvalue solves deadlocked XLA's CPU runtime); a start
stops changing when it has converged. The result has every start's end point, the best
start's history (per outer iteration: objective, largest violation, `mu`, projected
gradient, inner iterations), each constraint's value and multiplier.
"""

import dataclasses
import functools

import jax
import jax.numpy as jnp
import numpy as np
from tqdm.auto import tqdm

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


def _evaluator(fn, m, a, b, log):
    """`L`, `(f, c)` and `dL/du` at every start's point at once: one compiled program
    per `fn` (cached), the loops around it on the host."""
    return _batched(fn, m, tuple(a), tuple(b), tuple(bool(v) for v in log))


@functools.lru_cache(maxsize=32)
def _batched(fn, m, a, b, log):
    a, b, log = np.array(a), np.array(b), np.array(log)

    def lagrangian(u, lam, mu):
        f, c = fn(_to_x(u, a, b, log))
        c = jnp.reshape(c, (m,))
        return f + jnp.sum(jnp.maximum(0.0, lam + mu * c) ** 2 - lam**2) / (2 * mu), (f, c)

    vg = jax.jit(jax.vmap(jax.value_and_grad(lagrangian, has_aux=True)))

    def evaluate(U, lam, mu):
        (val, (f, c)), g = vg(jnp.asarray(U), jnp.asarray(lam), jnp.asarray(mu))
        return np.asarray(val), np.asarray(f), np.asarray(c).reshape(len(U), m), np.asarray(g)

    return evaluate


def _projected_gradient(U, G):
    return np.max(np.abs(np.clip(U - G, 0.0, 1.0) - U), axis=-1)


def _inner(evaluate, U, lam, mu, tol, max_inner, trace, pos, active, ftol=1e-12):
    """Projected BFGS on `L(., lam, mu)` in the unit box from each row of `U` (the rows
    not `active` are carried along unchanged): `(U, f, c, G, evaluations, iterations,
    stop, trace, pos)`."""
    S, n = U.shape
    val, f, c, G = evaluate(U, lam, mu)
    gmax = np.maximum(np.max(np.abs(G), axis=1), 1e-300)
    H = np.eye(n)[None] * np.minimum(1.0, 0.1 / gmax)[:, None, None]
    n_eval, it = np.ones(S, int), np.zeros(S, int)
    stop = np.zeros(S, int)
    running = active.copy()
    for _ in range(max_inner):
        running &= (stop == 0) & (_projected_gradient(U, G) > tol * np.maximum(1.0, np.abs(val)))
        if not running.any():
            break
        free = ~(((U <= 0.0) & (G > 0)) | ((U >= 1.0) & (G < 0)))
        ff = free[:, :, None] & free[:, None, :]
        D = -np.einsum("sij,sj->si", np.where(ff, H, 0.0), np.where(free, G, 0.0))
        descent = np.einsum("si,si->s", D, G) < 0
        scale = np.minimum(1.0, 0.1 / np.maximum(np.max(np.abs(G), axis=1), 1e-300))
        D = np.where(descent[:, None], D, -np.where(free, G, 0.0) * scale[:, None])
        H = np.where(descent[:, None, None], H, np.eye(n)[None] * scale[:, None, None])
        # projected backtracking (Armijo), every running start's trial point at once
        step, ok, k = np.ones(S), np.zeros(S, bool), np.zeros(S, int)
        Un, vn, fn_, cn, Gn = U.copy(), val.copy(), f.copy(), c.copy(), G.copy()
        for _ in range(24):
            trying = running & ~ok
            if not trying.any():
                break
            T = np.where(trying[:, None], np.clip(U + step[:, None] * D, 0.0, 1.0), U)
            tv, tf, tc, tG = evaluate(T, lam, mu)
            good = trying & np.isfinite(tv) & np.all(np.isfinite(tG), axis=1) & (
                tv <= val + 1e-4 * np.einsum("si,si->s", G, T - U))
            Un[good], vn[good], fn_[good], cn[good], Gn[good] = T[good], tv[good], tf[good], tc[good], tG[good]
            ok |= good
            k += trying
            step = np.where(trying & ~good, step * 0.5, step)
        Sd, Y = Un - U, Gn - G
        sy = np.einsum("si,si->s", Sd, Y)
        rho = 1.0 / np.where(sy > 0, sy, 1.0)
        V = np.eye(n)[None] - rho[:, None, None] * Sd[:, :, None] * Y[:, None, :]
        curved = sy > 1e-12 * np.linalg.norm(Sd, axis=1) * np.linalg.norm(Y, axis=1)
        H_new = np.where(curved[:, None, None], V @ H @ np.swapaxes(V, 1, 2)
                         + rho[:, None, None] * Sd[:, :, None] * Sd[:, None, :], H)
        upd = running & ok
        # stalled: no acceptable step, or a step that no longer lowers L (relative to its size)
        flat = upd & (val - vn <= ftol * np.maximum(1.0, np.abs(val)))
        for s_ in np.flatnonzero(upd & (pos < trace.shape[1])):
            trace[s_, pos[s_]] = [fn_[s_], np.max(np.maximum(cn[s_], 0.0), initial=0.0)]
        pos = pos + upd
        U = np.where(upd[:, None], Un, U)
        val, f = np.where(upd, vn, val), np.where(upd, fn_, f)
        c, G = np.where(upd[:, None], cn, c), np.where(upd[:, None], Gn, G)
        H = np.where(upd[:, None, None], H_new, H)
        n_eval += np.where(running, k, 0)
        it += running
        stop = np.where(running, np.where(ok, np.where(flat, FLAT, 0), NO_STEP), stop)
    return U, f, c, G, n_eval, it, stop, trace, pos


def _solve(fn, U0, a, b, log, *, m, tol, max_outer, max_inner, mu0, progress=False):
    """Every start's augmented-Lagrangian run (see the module), lock-step: each outer
    iteration's subproblems for all the starts not yet done, their evaluations batched
    (one compiled `L` and gradient for all starts); the loops run on the host, so no
    compiled loop holds the eigenvalue solves (XLA's CPU runtime deadlocked on a
    vmapped loop of them: `rotorjax._config`)."""
    evaluate = _evaluator(fn, m, a, b, log)
    S = U0.shape[0]
    U = np.array(U0, dtype=float)
    lam = np.zeros((S, m))
    mu = np.full(S, float(mu0))
    viol_prev = np.full(S, np.inf)
    hist = np.full((S, max_outer, 6), np.nan)
    trace = np.full((S, TRACE, 2), np.nan)
    pos = np.zeros(S, int)
    k = np.zeros(S, int)
    n_eval = np.zeros(S, int)
    running = np.ones(S, bool)
    bar = tqdm(total=max_outer, desc="optimize", unit="outer", leave=False, disable=not progress)
    for _ in range(max_outer):
        if not running.any():
            break
        U, f, c, G, ne, inner, stop, trace, pos = _inner(evaluate, U, lam, mu, tol, max_inner, trace, pos, running)
        viol = np.max(np.maximum(c, 0.0), axis=1, initial=0.0)
        lam_new = np.maximum(0.0, lam + mu[:, None] * c)
        pg = _projected_gradient(U, G)
        compl = np.max(np.abs(np.minimum(-c, lam_new)), axis=1, initial=0.0)
        scale = np.maximum(1.0, np.abs(f))
        done = (viol <= tol) & (compl <= tol) & ((pg <= tol * scale) | (stop == FLAT))
        stuck = (stop == NO_STEP) & (inner <= 1)      # not a step from where the last subproblem ended
        mu_new = np.where(viol > 0.25 * viol_prev, np.minimum(10 * mu, 1e10), mu)
        for s_ in np.flatnonzero(running):
            hist[s_, k[s_]] = [f[s_], viol[s_], mu[s_], pg[s_], inner[s_], stop[s_]]
        lam = np.where(running[:, None], lam_new, lam)
        mu = np.where(running, mu_new, mu)
        viol_prev = np.where(running, viol, viol_prev)
        n_eval += np.where(running, ne, 0)
        k += running
        running &= ~(done | stuck)
        bar.update()
        best = np.min(np.where((viol <= tol) & np.isfinite(f), f, np.inf))
        bar.set_postfix(running=int(running.sum()), best=float(best), violation=float(np.min(viol)), refresh=False)
    bar.close()
    last = hist[np.arange(S), np.maximum(k - 1, 0)]
    done = (last[:, 1] <= tol) & ((last[:, 3] <= tol * np.maximum(1.0, np.abs(last[:, 0]))) | (last[:, 5] == FLAT))
    ends = np.asarray(jax.vmap(lambda v: _to_x(v, a, b, log))(jnp.asarray(U)))
    _, f_end, c_end, _ = evaluate(U, lam, mu)
    return U, lam, k, hist, n_eval, done, trace, ends, f_end, c_end


def minimize(fn, lo, hi, starts, *, log=None, tol=1e-6, max_outer=30, max_inner=200, mu0=10.0,
             progress=False) -> Optimum:
    """Minimise `fn(x) -> (f, c)` (`f` a scalar, `c` an `(m,)` array, `c <= 0` met; pure
    JAX) over `lo <= x <= hi` from each row of `starts` `(n_starts, n)` (see the
    module). `log`: per parameter, whether it is scaled in its logarithm (needs
    `lo > 0`). `f` and `c` should be of order one (scale them). `progress`: a bar over
    the outer iterations, on stderr (tqdm), with the starts still running and the best
    feasible objective. Returns an `Optimum`; `InputError` for bad bounds or starts."""
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
    u, lam, k, hist, n_eval, done, trace, ends, f_end, c_end = _solve(
        fn, _to_u(starts, a, b, log), a, b, log, m=m, tol=float(tol), max_outer=int(max_outer),
        max_inner=int(max_inner), mu0=float(mu0), progress=progress)
    c_end = c_end.reshape(len(ends), m)
    # a bound held is the bound itself (its logarithm's round trip is not: 399.9999999999999 for 400)
    ends = np.where(u >= 1.0, hi, np.where(u <= 0.0, lo, np.clip(ends, lo, hi)))
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
