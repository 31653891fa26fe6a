"""Levenberg-Marquardt: the one least-squares solver of identification (model 002's
machine and run-up fits, rotor files' fits), vmapped over starts.

`lm_batch(r, theta0, center)` runs every row of `theta0` at once; each iteration is
one compiled, vmapped step over all lanes, in a Python loop (XLA's CPU runtime can
stall on a `while_loop` around LAPACK calls, and the loop stops as soon as every lane
is done). A lane is done when a step lowers the cost by less than `tol` relatively
(or moves theta by less than 1e-10), or when no damping makes a step lower it, i.e.
at rounding. Steps may be limited (`max_step` units per coordinate) and the iterates
kept within `center +- bound`. `levenberg_marquardt(r, theta0)` is one lane of it,
with the Jacobian at the optimum, the cost history and whether it converged.

Residuals: any callable `r(theta)`, with forward-mode autodiff Jacobians, or an
`AbstractJacobianResidual` with its own (faster) `res_jac`.
"""

import abc

import equinox as eqx
import jax
import jax.numpy as jnp
import numpy as np

from .._autodiff import value_and_jacfwd


class AbstractJacobianResidual(eqx.Module):
    """A residual `r(theta)` that has its own (faster) `res_jac(theta) -> (r, dr/dtheta)`."""

    @abc.abstractmethod
    def __call__(self, theta):
        """The residuals at `theta`."""

    @abc.abstractmethod
    def res_jac(self, theta):
        """`(r(theta), dr/dtheta)`."""


def res_jac(r, theta):
    """The residuals and their Jacobian: `r.res_jac` where the residual has its own
    (faster) one, else forward-mode autodiff."""
    if isinstance(r, AbstractJacobianResidual):
        return r.res_jac(theta)
    return value_and_jacfwd(r)(theta)


#: `res_jac` compiled (one evaluation, as the benchmarks time it)
_res_jac = eqx.filter_jit(res_jac)



@eqx.filter_jit
def _lm_init(r, theta0, lam0):
    res, J = jax.vmap(lambda th: res_jac(r, th))(theta0)
    n = theta0.shape[0]
    return (theta0, res, J, jnp.sum(res**2, axis=1), jnp.full(n, lam0), jnp.zeros(n, dtype=bool),
            jnp.zeros(n, dtype=bool))


@eqx.filter_jit
def _lm_step(r, state, center, tol, bound, max_step):
    """One Levenberg-Marquardt iteration of every lane (lanes that are done keep their state)."""

    def one(th, res, J, cost, lam, done, small_done):
        JtJ, g = J.T @ J, J.T @ res
        d = jnp.diag(JtJ)
        step = -jnp.linalg.solve(JtJ + lam * jnp.diag(d + 1e-12 * jnp.max(d)), g)
        new = jnp.clip(th + jnp.clip(step, -max_step, max_step), center - bound, center + bound)
        res_n, J_n = res_jac(r, new)
        cost_n = res_n @ res_n
        ok = jnp.isfinite(cost_n) & (cost_n < cost) & ~done
        small = ok & (((cost - cost_n) <= tol * cost) | (jnp.max(jnp.abs(new - th)) < 1e-10))
        th, res, J, cost = (jnp.where(ok, a, b) for a, b in ((new, th), (res_n, res), (J_n, J), (cost_n, cost)))
        lam = jnp.where(done, lam, jnp.where(ok, jnp.maximum(lam / 10, 1e-12), lam * 10))
        return th, res, J, cost, lam, done | small | (lam > 1e12), small_done | small

    return jax.vmap(one)(*state)


def _run(r, theta0, center, max_iter, tol, bound, max_step, lam0, history=None):
    state = _lm_init(r, jnp.asarray(theta0, dtype=jnp.float64), lam0)
    center = jnp.asarray(center, dtype=jnp.float64)
    if history is not None:
        history.append(float(state[3][0]))
    it = 0
    for it in range(1, max_iter + 1):
        state = _lm_step(r, state, center, tol, bound, max_step)
        if history is not None:
            history.append(float(state[3][0]))
        if bool(jnp.all(state[5])):
            break
    return state, it


def lm_batch(r, theta0, center, max_iter=200, tol=1e-12, bound=7.0, max_step=2.0):
    """Levenberg-Marquardt from each row of `theta0` at once (see the module
    docstring): steps limited to `max_step` units, iterates to `center +- bound`.
    Returns `(theta, cost, done, iterations)`."""
    state, it = _run(r, theta0, center, max_iter, tol, bound, max_step, 1e-3)
    return state[0], state[3], state[5], it


def levenberg_marquardt(r, theta0, max_iter=100, tol=1e-12, lam0=1e-3, bound=np.inf,
                        max_step=np.inf):
    """Minimise `|r(theta)|^2` from `theta0` (one lane of `lm_batch`; steps and
    iterates unlimited unless `max_step` and `bound` around `theta0` say); returns
    `(theta, J, info)`: the Jacobian at `theta`, and `info` with the iterations, the cost and its history (after each accepted
    step), and whether it converged: a step lowered the cost by less than `tol`, or,
    where no damping lowers it any more (rounding), the Gauss-Newton step would not
    lower it measurably either (a test independent of the parameters' scales)."""
    theta0 = jnp.asarray(theta0, dtype=jnp.float64)
    costs = []
    state, it = _run(r, theta0[None, :], theta0, max_iter, tol, bound, max_step, lam0, costs)
    theta, res, J, cost = (a[0] for a in state[:4])
    cost = float(cost)
    converged = bool(state[6][0])
    if not converged and bool(state[5][0]):
        Jn, gn = np.asarray(J), np.asarray(J.T @ res)
        predicted = float(gn @ (np.linalg.pinv(Jn.T @ Jn) @ gn))
        converged = (float(np.max(np.abs(gn))) < 1e-8 * max(cost, 1e-300) ** 0.5
                     or predicted <= 1e-8 * max(cost, 1e-300))
    history = costs[:1]
    for c in costs[1:]:
        if c < history[-1]:
            history.append(c)
    return theta, J, {"iterations": it, "converged": converged, "history": history, "cost": cost}
