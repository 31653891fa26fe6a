"""API 684 level I stability screening: a destabilising cross-coupled stiffness
`Q` (N/m) at the rotor's mid-span,

    K[x, y] += Q,   K[y, x] -= Q      (f_x = -Q y, f_y = +Q x),

a tangential force that follows forward whirl (`x = cos, y = sin` gets
`f = Q (-sin, cos)`: positive work per cycle) and so lowers the logarithmic
decrement of the first forward mode; the threshold `Q0` is where that decrement
crosses zero (API 684, 2nd ed., section 2.9.3.3; ROSS's `Rotor.run_level1`
applies the same `BearingElement(n, kxx=0, cxx=0, kxy=Q, kyx=-Q)`).

The decrement at a given `Q` (`level1_log_dec`) is pure JAX: differentiable and
vmappable over `Q` and over designs. `level1` samples it on `[0, q_max]`, locates
`Q0` with the shared root finder (`rotorjax.analysis._roots.find_roots`), and
checks it independently: the largest real part of all eigenvalues at `Q0` is ~0.
"""

import equinox as eqx
import jax
import jax.numpy as jnp
import numpy as np

from ._roots import find_roots
from ..models._contract import LinearMatrices
from ..models._fe_rotor import DOFS_PER_NODE
from ..models._validate import InputError, as_count, as_param, check_node, is_concrete
from ._frf import linear_system
from ._ucs import bearing_stiffness


#: log decrements below this (in magnitude) count as zero (round-off of an undamped rotor's)
NOISE = 1e-9


class Level1(eqx.Module):
    """A level I screening at one `speed` (rad/s) with `Q` at `node`.

    - `q` (n,) N/m and `log_dec` (n,): the first forward mode's logarithmic
      decrement against `Q`; `log_dec_0` at `Q = 0`.
    - `q0`: the threshold (N/m), NaN where `log_dec` has no sign change on
      `[0, q_max]` (`crossed` False).
    - `real_part_at_q0`: Re lambda of the tracked mode at `q0`, and
      `max_real_part_at_q0` the largest over all modes (both ~0 at a true threshold;
      the second > 0 flags another mode that went unstable first).
    """

    node: int = eqx.field(static=True)
    speed: float = eqx.field(static=True)
    q: jax.Array
    log_dec: jax.Array
    log_dec_0: jax.Array
    q0: jax.Array
    crossed: bool = eqx.field(static=True)
    real_part_at_q0: jax.Array
    max_real_part_at_q0: jax.Array


def mid_span_node(rotor) -> int:
    """The node nearest the middle of the bearing span (outermost bearings), or of
    the shaft with fewer than two bearings."""
    _, rotor = linear_system(rotor)
    rotor = rotor.full_rotor
    x = np.asarray(rotor.node_positions)
    nodes = sorted(set(rotor.bearing_nodes))
    mid = 0.5 * (x[nodes[0]] + x[nodes[-1]]) if len(nodes) >= 2 else 0.5 * (x[0] + x[-1])
    return int(np.argmin(np.abs(x - mid)))


def _cross_coupling(rotor, node):
    """The unit cross-coupling pattern (`K[x, y] = 1`, `K[y, x] = -1`) in the rotor's coordinates."""
    free = np.asarray(rotor.free_dofs)
    pos = {int(d): i for i, d in enumerate(free)}
    b = DOFS_PER_NODE * node
    if b not in pos or b + 1 not in pos:
        raise InputError(f"node: the cross-coupling node {node} has fixed translation dofs")
    P = jnp.zeros((len(free), len(free))).at[pos[b], pos[b + 1]].set(1.0).at[pos[b + 1], pos[b]].set(-1.0)
    # in the rotor's coordinates (modal ones: Phi^T P Phi); `project` maps each side
    return rotor.project(rotor.project(P).T).T


def _first_forward(matrices, rotor, P, q, speed):
    """`(lambda, all lambdas)`: the lowest-frequency forward mode's eigenvalue. One
    eigen-decomposition, of `A` without its derivatives: the whirl is read from
    its eigenvectors, and the chosen eigenvalue gets its derivative from first-order
    perturbation, `lambda = lambda_0 + u^H (A - A_0) v` (`u^H` the row of `V^-1`, so
    `u^H v = 1`; the added term is zero in value), exact for a simple eigenvalue."""
    M, C, K = matrices(speed)
    A = LinearMatrices(M, C, jnp.zeros_like(C), K + q * P).state_matrix()
    A0 = jax.lax.stop_gradient(A)
    lam0, vec = jnp.linalg.eig(A0)
    n = M.shape[0]
    key = jnp.where(jnp.imag(lam0) > 0, jnp.imag(lam0), jnp.inf)
    order = jnp.argsort(key)[:n]
    v = rotor.expand(vec[:n, order])
    x, y = v[0::DOFS_PER_NODE], v[1::DOFS_PER_NODE]
    forward = (jnp.sum(jnp.abs(x + 1j * y) ** 2, axis=0) >= jnp.sum(jnp.abs(x - 1j * y) ** 2, axis=0)) \
        & jnp.isfinite(key[order])
    kk = order[jnp.argmax(forward)]
    u = jnp.linalg.solve(vec.T, jnp.zeros(A.shape[0], dtype=vec.dtype).at[kk].set(1.0))
    first = lam0[kk] + u @ ((A - A0) @ vec[:, kk])
    return jnp.where(jnp.any(forward), first, jnp.nan + 0j), lam0


def _prepare(system, node):
    matrices, rotor = linear_system(system)
    if node is None:
        node = mid_span_node(rotor)
    node = check_node("node", node, rotor.n_nodes, "cross-coupling node")
    return matrices, rotor, node, _cross_coupling(rotor, node)


def level1_log_dec(rotor, q, speed, node=None):
    """Logarithmic decrement `-2 pi Re lambda / Im lambda` of the first forward mode at
    cross-coupled stiffness `q` (N/m, scalar) at `node` (default: mid-span) and
    running speed `speed` (rad/s). Pure JAX in `q`, `speed` and the rotor's
    parameters (vmap over `q` or designs)."""
    matrices, rotor, node, P = _prepare(rotor, node)
    for name, v in (("q", q), ("speed", speed)):
        if is_concrete(v):
            as_param(name, v, shape=())
    lam, _ = _first_forward(matrices, rotor, P, jnp.asarray(q, dtype=jnp.float64),
                            jnp.asarray(speed, dtype=jnp.float64))
    return -2 * jnp.pi * jnp.real(lam) / jnp.imag(lam)


def level1(rotor, speed, node=None, q_max=None, n=41, xtol=1e-9) -> Level1:
    """API 684 level I screening (see the module docstring).

    **Arguments:**
    - `rotor`: a `FlexibleRotor`, `ReducedRotor` or `RotorScene` (its rotor).
    - `speed`: the running speed (rad/s; API 684: the maximum continuous speed),
      required; the bearings are evaluated at it.
    - `node`: where `Q` acts (default: `mid_span_node`).
    - `q_max`: the largest `Q` (N/m; default: the largest bearing direct stiffness
      at `speed`); `n` values from 0 to `q_max` (>= 2).
    - `xtol`: the bisection's relative tolerance on `Q0`.

    **Returns:** a `Level1`; `q0` NaN (and `crossed` False) where the decrement
    does not change sign on `[0, q_max]`: it stays positive, or it is not positive
    at `Q = 0` (an unstable rotor, or an undamped one: `|log dec| < NOISE` counts
    as zero, and a crossing needs a positive start).
    """
    matrices, rotor, node, P = _prepare(rotor, node)
    speed = float(as_param("speed", speed, shape=()))
    n = as_count("n", n, minimum=2)
    if q_max is None:
        kb = np.asarray(bearing_stiffness(rotor.full_rotor, speed)) if \
            rotor.full_rotor.bearing_nodes else np.zeros((0, 2))
        q_max = float(kb.max()) if kb.size and kb.max() > 0 else None
        if q_max is None:
            raise InputError("q_max: give it (the rotor has no bearing stiffness to scale it by)")
    q_max = float(as_param("q_max", q_max, sign="positive", shape=()))
    W = jnp.float64(speed)

    def ld(q):
        lam, _ = _first_forward(matrices, rotor, P, q, W)
        return -2 * jnp.pi * jnp.real(lam) / jnp.imag(lam)

    curve = jax.jit(jax.vmap(ld))
    one = jax.jit(ld)
    qs = np.linspace(0.0, q_max, n)
    values = np.asarray(curve(jnp.asarray(qs)))
    # decrements within round-off of zero (an undamped rotor) are zero: no spurious crossings in the noise
    snap = lambda v: 0.0 if abs(v) < NOISE else v  # noqa: E731
    roots = find_roots(lambda q: snap(float(one(q))), 0.0, q_max, n, values=np.array([snap(v) for v in values]),
                       xtol=xtol * q_max, rtol=xtol)
    if roots:
        q0 = roots[0].x
        first, lam = jax.jit(lambda q: _first_forward(matrices, rotor, P, q, W))(jnp.float64(q0))
        re, max_re = float(jnp.real(first)), float(jnp.max(jnp.real(lam)))
    else:
        q0, re, max_re = float("nan"), float("nan"), float("nan")
    return Level1(node, speed, jnp.asarray(qs), jnp.asarray(values), jnp.asarray(values[0]), jnp.asarray(q0),
                  bool(roots), jnp.asarray(re), jnp.asarray(max_re))
