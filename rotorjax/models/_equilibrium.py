"""A rotor's static equilibrium in its nonlinear bearings at a running speed, and
the linear equations about it.

A journal bearing carries the rotor by where the journal sits in it: at a speed
`speed` the shaft coordinates `q*` solve

    R(q) = F_static + sum_k f_k(q, q' = 0, speed) - (K + speed K_s) q = 0,

`f_k` the forces of the components that act at rest (fluid films, cubic and
clearance bearings: `in_equilibrium`), by Newton on the whole finite-element rotor
(`rotorjax._newton`, differentiable by the implicit function theorem). A step is
shortened so that no film's journal moves more than half its way to the wall. The
linearisation there, by autodiff of the same forces, `K_f = -df/dq`, `C_f =
-df/dq'`, added to the shaft's, is the rotor's linear equations at that speed
(`RotorScene.linear_matrices`): every linear analysis (modes, Campbell, Hopf
points, unbalance response) of a rotor on fluid films goes through it.
"""

import equinox as eqx
import jax
import jax.numpy as jnp
import numpy as np

from .._errors import NumericalError
from .._autodiff import value_and_jacfwd
from .._newton import newton
from ._contract import LinearMatrices
from ._rotor_component import ShaftState
from ._validate import InputError, is_concrete

#: relative residual `|R| / (|F_static| + |K q|)` below which the equilibrium counts as found
RESIDUAL_TOL = 1e-8


class Equilibrium(eqx.Module):
    """The static equilibrium at `speed` (rad/s): the shaft coordinates `q`, the
    relative residual, Newton's iterations and whether it `converged` (residual
    below `RESIDUAL_TOL`, every film's journal inside its clearance)."""

    q: jax.Array
    speed: jax.Array
    residual: jax.Array
    iterations: jax.Array
    converged: jax.Array


def films(scene):
    """The scene's fluid films (journal bearings, squeeze-film dampers)."""
    from ._fluid_film import _Film  # noqa: PLC0415

    return tuple(c for c in scene.components if isinstance(c, _Film))


def has_films(scene) -> bool:
    return bool(films(scene))


def _state(scene, q, qd, speed):
    z = jnp.zeros(())
    return ShaftState(t=z, theta=z, theta_dot=jnp.asarray(speed, dtype=jnp.float64) + z, theta_ddot=z,
                      q=q, qd=qd, E=scene.E)


def equilibrium_force(scene, q, qd, speed):
    """The generalised force of the components that act at rest, at shaft
    coordinates `q`, velocities `qd` and `speed`."""
    s = _state(scene, q, qd, speed)
    out = jnp.zeros(scene.n_shaft)
    for c in scene.components:
        if c.in_equilibrium:
            f = c.force(s, None, None)
            out = out + scene._node_rows(f.node).T @ f.f
    return out


def _check(scene, speed):
    """Refuse what has no static equilibrium to find (concrete scenes)."""
    if any(c.n_coords for c in scene.components):
        raise InputError("static equilibrium: components with coordinates of their own (an auto-balancer's "
                         "weights) are not part of it; build the rotor without them")
    loose = [c for c in films(scene) if not c.centred]
    if loose:   # a damper without a centring spring carries no static load: is the rest enough?
        zero = jnp.zeros(scene.n_shaft)
        J = jax.jacfwd(lambda q: equilibrium_force(scene, q, zero, speed))(zero) - scene._linear_about_rest(speed).K
        if not np.linalg.cond(np.asarray(J)) < 1e13:
            raise InputError(f"static equilibrium: the {loose[0].label} has no centring spring (kxx, kyy) and "
                             f"nothing else holds the rotor there: its film carries no static load, so the static "
                             f"problem is singular; give kxx and kyy")


def _limit(scene):
    """A Newton step shortened so that no journal moves more than half its way to the wall."""
    fl = films(scene)
    if not fl:
        return None

    def limit(x, dx):
        alpha = jnp.ones(())
        for c in fl:
            rows = scene._node_rows(c.node)
            u, du = rows @ x, rows @ dx
            r, dr = jnp.sqrt(u @ u), jnp.sqrt(du @ du)
            room = 0.5 * (c.clearance - r)
            alpha = jnp.minimum(alpha, jnp.where(dr > room, room / jnp.maximum(dr, 1e-300), 1.0))
        return jnp.maximum(alpha, 0.0) * dx

    return limit


#: Newton's defaults for the static equilibrium: step tolerance and iterations
TOL, MAX_ITER = 1e-12, 200


def static_equilibrium(scene, speed, guess=None, tol=TOL, max_iter=MAX_ITER) -> Equilibrium:
    """The static equilibrium of a `RotorScene` at `speed` (rad/s) from `guess` (its
    shaft coordinates; default the straight shaft). Traceable and differentiable in
    the scene's parameters and the speed (one compiled program per rotor layout);
    check `converged`."""
    speed = jnp.asarray(speed, dtype=jnp.float64)
    if is_concrete((scene.M, speed)):
        _check(scene, speed)
    q0 = jnp.zeros(scene.n_shaft) if guess is None else jnp.asarray(guess, dtype=jnp.float64)
    return _solve(scene, speed, q0, tol, max_iter)


def _newton_solve(scene, speed, q0, tol, max_iter):
    """`(q, iterations, lin)`: Newton on the residual (module docstring) from `q0`; `lin` the
    linear equations about the straight shaft at rest (their `K` is the residual's)."""
    lin = scene._linear_about_rest(speed)
    K = lin.K
    zero = jnp.zeros(scene.n_shaft)

    def residual(q):
        return scene.F0 + equilibrium_force(scene, q, zero, speed) - K @ q

    q, (_, it) = newton(residual, q0, tol, max_iter, limit=_limit(scene))
    return q, it, lin


def _verdict(scene, speed, q, r, it, K) -> Equilibrium:
    """The equilibrium `q` with its residual `r` judged (relative size, journals inside)."""
    scale = jnp.linalg.norm(scene.F0) + jnp.linalg.norm(K @ q) + jnp.finfo(jnp.float64).tiny
    rel = jnp.linalg.norm(r) / scale
    inside = jnp.ones((), dtype=bool)
    s = _state(scene, q, jnp.zeros(scene.n_shaft), speed)
    for c in films(scene):
        inside = inside & (c.eccentricity(s) < 1.0)
    ok = jnp.isfinite(rel) & (rel < RESIDUAL_TOL) & inside
    return Equilibrium(q=q, speed=speed, residual=rel, iterations=it, converged=ok)


@eqx.filter_jit
def _solve(scene, speed, q0, tol, max_iter) -> Equilibrium:
    q, it, lin = _newton_solve(scene, speed, q0, tol, max_iter)
    r = scene.F0 + equilibrium_force(scene, q, jnp.zeros(scene.n_shaft), speed) - lin.K @ q
    return _verdict(scene, speed, q, r, it, lin.K)


def equilibrium_matrices(scene, speed) -> LinearMatrices:
    """The linear equations about the static equilibrium at `speed`: NaN where it is
    not found when traced (a scan over speeds), an error when concrete (a journal at
    a speed <= 0: `InputError`; no equilibrium: `NumericalError`)."""
    speed = jnp.asarray(speed, dtype=jnp.float64)
    if is_concrete(speed) and not float(speed) > 0 and any(c.spins for c in films(scene)):
        raise InputError(f"the rotor's linear equations at {float(speed):g} rad/s: a journal bearing carries its "
                         f"load only while the shaft spins (its equilibrium and coefficients need a speed > 0)")
    if is_concrete((scene.M, speed)):
        _check(scene, speed)
    eq, lm = _linearised(scene, speed, jnp.zeros(scene.n_shaft), TOL, MAX_ITER)
    if is_concrete(eq.converged) and not bool(eq.converged):
        raise NumericalError(f"the rotor's linear equations at {float(speed):g} rad/s: its static equilibrium in "
                             f"the fluid films was not found (relative residual {float(eq.residual):.2e} after "
                             f"{int(eq.iterations)} Newton steps; a journal may be pressed against its wall)")
    return lm


@eqx.filter_jit
def _linearised(scene, speed, q0, tol, max_iter):
    """The equilibrium (`static_equilibrium`'s) and the linear equations about it: the
    residual there and `K_f`, `C_f` from one Jacobian of the forces in `(q, q')`, so
    that the program holds two copies of the forces (Newton's and this), not four."""
    q, it, lin = _newton_solve(scene, speed, q0, tol, max_iter)
    n = scene.n_shaft
    f, j = value_and_jacfwd(lambda qv: equilibrium_force(scene, qv[:n], qv[n:], speed))(
        jnp.concatenate([q, jnp.zeros(n)]))
    eq = _verdict(scene, speed, q, scene.F0 + f - lin.K @ q, it, lin.K)
    bad = jnp.where(eq.converged, 0.0, jnp.nan)
    return eq, LinearMatrices(M=lin.M, C=lin.C - j[:, n:] + bad, G=lin.G, K=lin.K - j[:, :n] + bad)
