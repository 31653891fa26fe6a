"""Branch points of a curve `G(x) = 0` (`G: R^{n+1} -> R^n`): where another curve
of solutions crosses it, `G'(x)` loses rank (a symmetric rotor's pitchfork, a
transcritical exchange of stability).

- `refine(G, a, b)`: the branch point between two points `a`, `b` of the curve
  (where the bordered determinant `det [G'; t^T]` changed sign), by Newton
  (`rotorjax._newton`, one compiled loop) on the extended system of Moore (1980)
  and Keller (1977)

      G(x) + mu phi = 0,   G'(x)^T phi = 0,   phi0 . phi = 1,

  in `(x, phi, mu)`: `phi` the left null vector of `G'`, `mu` an unfolding
  parameter that is 0 at the branch point. The system is regular at a simple
  branch point (a two-dimensional null space of `G'`, the crossing transversal),
  so Newton converges quadratically there, where a corrector along the curve is
  singular.
- The tangent of the other curve: with `t1` the curve's own tangent and `t2` the
  other unit vector of the null space, the algebraic bifurcation equation
  `phi . G''[v, v] = 0`, `v = cos(th) t1 + sin(th) t2`, has two roots (the two
  curves' tangents; Keller 1977, Seydel "Practical bifurcation and stability
  analysis" sec. 5.6): the one farther from `t1` is the other curve's.

`continue_branch` refines every branch point it meets this way, and
`switch_branch` continues the other curve from it."""

import jax
import jax.numpy as jnp
import numpy as np

from .._newton import newton
from ..solve._lift import compiled

#: Newton's relative step tolerance and iteration cap on the extended system
TOL, MAX_ITER = 1e-13, 40


def _extended(G, z, phi0):
    """The extended system at `z = (x, phi, mu)` (sizes `n + 1`, `n`, 1)."""
    n = phi0.size
    x, phi, mu = z[:n + 1], z[n + 1:2 * n + 1], z[2 * n + 1]
    Gx, pullback = jax.vjp(G, x)
    return jnp.concatenate([Gx + mu * phi, pullback(phi)[0], (phi0 @ phi - 1.0)[None]])


@compiled
def _solve(G, z0, phi0):
    """Newton on `_extended` from `z0`; returns `(z, max |G(x)|, max |G'(x)^T phi|
    / max |phi|, iterations)`."""
    n = phi0.size
    z, (_, iterations) = newton(lambda z: _extended(G, z, phi0), z0, TOL, MAX_ITER, floor=1e-15)
    x, phi = z[:n + 1], z[n + 1:2 * n + 1]
    Gx, pullback = jax.vjp(G, x)
    return (z, jnp.max(jnp.abs(Gx)), jnp.max(jnp.abs(pullback(phi)[0])) / jnp.max(jnp.abs(phi)),
            iterations)


@compiled
def _second(G, x, phi, t1, t2):
    """`phi . G''(x)[v, w]` for `(v, w)` = `(t1, t1)`, `(t1, t2)`, `(t2, t2)`."""
    def along(v, w):
        return phi @ jax.jvp(lambda y: jax.jvp(G, (y,), (v,))[1], (x,), (w,))[1]
    return jnp.stack([along(t1, t1), along(t1, t2), along(t2, t2)])


def _null_basis(J, t):
    """An orthonormal basis `(t1, t2)` of the null space of `J` (`n x (n + 1)`, rank
    `n - 1`: its two smallest right singular vectors), `t1` nearest `t`."""
    _, _, Vt = np.linalg.svd(J)
    N = Vt[-2:].T                      # (n + 1) x 2
    t1 = N @ (N.T @ t)
    t1 /= np.linalg.norm(t1)
    c = N.T @ t1                       # t1 in the basis N; t2 the unit vector across it
    t2 = N @ np.array([-c[1], c[0]])
    return t1, t2 / np.linalg.norm(t2)


def other_tangent(G, x, phi, J, t):
    """The unit tangent of the curve that crosses `G = 0`'s curve at its branch
    point `x` (`phi` the left null vector of `J = G'(x)`, `t` the curve's own
    tangent there), oriented towards increasing last coordinate (then increasing
    first, where that is 0); and a note where the bifurcation equation has no
    second real root (not a simple crossing: the direction orthogonal to `t` in the
    null space is returned)."""
    t1, t2 = _null_basis(np.asarray(J), np.asarray(t, dtype=float))
    a11, a12, a22 = np.asarray(_second(G, jnp.asarray(x), jnp.asarray(phi), jnp.asarray(t1), jnp.asarray(t2)))
    # a11 cos^2 + 2 a12 cos sin + a22 sin^2 = A + B cos 2th + C sin 2th
    A, B, C = 0.5 * (a11 + a22), 0.5 * (a11 - a22), a12
    R = np.hypot(B, C)
    note = None
    if R == 0.0 or abs(A) > R:
        th, note = 0.5 * np.pi, "the bifurcation equation has no real root besides the branch's own tangent"
    else:
        roots = 0.5 * (np.arctan2(C, B) + np.array([1.0, -1.0]) * np.arccos(-A / R))
        th = roots[np.argmax(np.abs(np.sin(roots)))]   # the one farther from t1
    v = np.cos(th) * t1 + np.sin(th) * t2
    v /= np.linalg.norm(v)
    lead = v[-1] if abs(v[-1]) > 1e-12 else v[np.argmax(np.abs(v) > 1e-12)]
    return (v if lead > 0 else -v), note


def refine(G, J, a, b):
    """The branch point between the curve's points `a` and `b` (rows `x`), `J` the
    curve's Jacobian `G'` at the one nearer it: Newton on the extended system from
    the midpoint, `phi0` the left singular vector of `J`'s smallest singular value.
    Returns `(x, phi, residual, iterations)`, `residual` the larger of `max |G(x)|`
    and `max |G'(x)^T phi| / max |phi|` (non-finite where Newton met non-finite
    values)."""
    U, _, _ = np.linalg.svd(np.asarray(J))
    phi0 = U[:, -1]
    n = phi0.size
    z0 = np.concatenate([0.5 * (np.asarray(a) + np.asarray(b)), phi0, [0.0]])
    z, r_g, r_phi, iterations = (np.asarray(v) for v in _solve(G, jnp.asarray(z0), jnp.asarray(phi0)))
    return z[:n + 1], z[n + 1:2 * n + 1], float(np.max([r_g, r_phi])), int(iterations)
