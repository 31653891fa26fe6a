"""Static deflection of a finite-element rotor under its own weight: `K q = F`,
with the bearings at rest (speed 0) and any supports (pedestals), and the
bearing reactions, shear force and bending moment along the shaft.

The gravity load is the consistent one, `F = M g`, with `g` the rigid-body
field of the acceleration on every translational dof along `axis` (shaft nodes
and pedestals; the section rotations get none): the shaft's distributed weight
(consistent nodal forces and moments), the disks' and point masses' weights.
Bearing mass coefficients are not weights (a fluid film's added mass) and are
left out. The end forces of element `e`, `s_e = K_e q_e - F_e` (what the nodes
exert on the element, in dof directions), give the internal forces at its ends:
per bending plane, with `w` the displacement and `s = dw/dz` (or the section
rotation), `V_left = s_w1`, `V_right = -s_w2`, `M_left = -s_s1`,
`M_right = s_s2`: the textbook convention in which a simply supported beam under
its weight has `V(0) = +R`, `dM/dz = V` and a positive (sagging) moment
`M(L/2) = w L^2 / 8` (`M = E I w''`). ROSS's `run_static` reports `-V` and
`-M` (the opposite convention; same magnitudes), and its deformation with the
bearings made rigid (`k = 1e20`), not with their stiffness as here.
"""

import equinox as eqx
import jax
import jax.numpy as jnp
import numpy as np

from .._errors import NumericalError
from ..models._fe_rotor import DOFS_PER_NODE
from ..models._validate import as_param, check_choice, is_concrete
from ._frf import full_rotor

AXES = ("x", "y")


class StaticResult(eqx.Module):
    """The static state of a rotor under gravity (SI units).

    - `positions`: node positions along the shaft (m), `(n_nodes,)`.
    - `displacement`: `(x, y)` per node (m), `(n_nodes, 2)`; `rotation`: `(sx, sy)` (rad).
    - `bearing_reactions`: the force each bearing exerts on the shaft, `(x, y)` (N),
      `(n_bearings, 2)`; with the constraint reactions they balance `weight`.
    - `constraint_reactions`: forces (and moments) at fixed dofs, `(n_nodes, 4)`
      (zero where no dof is fixed).
    - `disk_forces`: gravity on each disk, `(x, y)` (N), `(n_disks, 2)`.
    - `weight`: total gravity force on shaft, disks and point masses, `(x, y)` (N).
    - `element_ends`: positions of each element's ends, `(n_el, 2)`.
    - `shear`, `moment`: shear force (N) and bending moment (N m) at each element's
      two ends, per bending plane, `(n_el, 2 ends, 2 planes (xz, yz))` (convention:
      module docstring).
    - `residual`: `|K q - F| / |F|` on the free dofs (a check of the solve).
    """

    positions: jax.Array
    displacement: jax.Array
    rotation: jax.Array
    bearing_reactions: jax.Array
    constraint_reactions: jax.Array
    disk_forces: jax.Array
    weight: jax.Array
    element_ends: jax.Array
    shear: jax.Array
    moment: jax.Array
    residual: jax.Array
    axis: str = eqx.field(static=True)


def _full_rotor(rotor):
    """The `FlexibleRotor` behind a rotor, a reduced rotor or a `RotorScene`."""
    return full_rotor(rotor).full_rotor


def _grounded_bearing_masses(rotor):
    """`(node, 2x2 mass coefficients)` of the bearings that join the shaft to the
    ground directly (not through a support), at speed 0."""
    coef = rotor.bearing_coefficients(0.0)
    out = []
    for i, node in enumerate(rotor.bearing_nodes):
        if i not in rotor.support_bearings:
            mxx, myy, mxy, myx = coef[i, 8], coef[i, 9], coef[i, 10], coef[i, 11]
            out.append((node, jnp.array([[mxx, mxy], [myx, myy]])))
    return out


def static(rotor, gravity=9.80665, axis="y") -> StaticResult:
    """Static deflection under gravity `gravity` (m/s^2) acting in `-axis`
    (`"x"` or `"y"`): `K q = M g`, bearings at rest, fixed dofs held (see the
    module docstring for the load, the reactions and the sign of shear and moment).

    **Arguments:**
    - `rotor`: a `FlexibleRotor` (a `ReducedRotor` or `RotorScene`: its full
      finite-element rotor; a scene's components are not included).
    - `gravity`: the acceleration (m/s^2), any finite number (negative: along `+axis`).
    - `axis`: the vertical axis, `"x"` or `"y"`.

    **Returns:** a `StaticResult`. Raises `NumericalError` (concrete inputs) where
    the stiffness matrix is singular: the rotor is not supported.
    """
    rotor = _full_rotor(rotor)
    check_choice("axis", axis, AXES)
    g = as_param("gravity", gravity, shape=())
    singular = NumericalError("static: the stiffness matrix is singular (the rotor is not supported)")
    f = rotor.free_dofs
    if is_concrete(rotor) and _singular(rotor, rotor.matrices(0.0)[3][np.ix_(f, f)], f):
        raise singular
    result = _static(rotor, g, axis)
    if is_concrete(result.displacement) and not (np.all(np.isfinite(np.asarray(result.displacement)))
                                                 and float(result.residual) < 1e-6):
        raise singular
    return result


@eqx.filter_jit
def _static(rotor, g, axis):
    """The static solution (compiled once per rotor layout and axis)."""
    a = AXES.index(axis)
    M, _, _, K = rotor.matrices(0.0)
    n_nodes, n = rotor.n_nodes, K.shape[0]
    nd = DOFS_PER_NODE
    trans = np.concatenate([np.arange(n_nodes) * nd + a, np.arange(nd * n_nodes + a, n, 2)])
    field = jnp.zeros(n).at[trans].set(-g)
    F = M @ field
    for node, mb in _grounded_bearing_masses(rotor):
        F = F.at[nd * node: nd * node + 2].add(-mb @ field[nd * node: nd * node + 2])
    f = rotor.free_dofs
    Kff, Ff = K[np.ix_(f, f)], F[f]
    qf = jnp.linalg.solve(Kff, Ff)
    residual = jnp.linalg.norm(Kff @ qf - Ff) / jnp.maximum(jnp.linalg.norm(Ff), 1e-300)
    q = rotor.expand(qf)
    # reactions at fixed dofs: what holds them, F_c = K q - F there (zero elsewhere)
    fixed = np.asarray(rotor.fixed_dofs, dtype=int)
    cons = jnp.zeros(n).at[fixed].set((K @ q - F)[fixed])[: nd * n_nodes].reshape(n_nodes, nd)

    Me, _, Ke = rotor.element_matrices()
    idx = np.arange(n_nodes - 1)[:, None] * nd + np.arange(2 * nd)[None, :]
    s = jnp.einsum("eij,ej->ei", Ke, q[idx]) - jnp.einsum("eij,ej->ei", Me, field[idx])
    # per plane p (0: x with sx, 1: y with sy): w1, s1, w2, s2 = p, p + 2, p + 4, p + 6
    shear = jnp.stack([jnp.stack([s[:, p], -s[:, p + 4]], axis=1) for p in (0, 1)], axis=2)
    moment = jnp.stack([jnp.stack([-s[:, p + 2], s[:, p + 6]], axis=1) for p in (0, 1)], axis=2)

    # a bearing's force on the shaft: what acts at its node besides the shaft's
    # elements, -(K - K_elements) q there (disks and point masses add no stiffness)
    Kel = rotor.shaft_matrices()[2]
    outside = -((K - Kel) @ q)[: nd * n_nodes].reshape(n_nodes, nd)[:, :2]
    reactions = _split_by_node(rotor, outside, q)
    pos = rotor.node_positions
    disk_forces = jnp.stack([rotor.disk_params[:, 0] * field[nd * np.asarray(rotor.disk_nodes, dtype=int) + p]
                             for p in (0, 1)], axis=1) if rotor.disk_nodes else jnp.zeros((0, 2))
    shaft_trans = np.arange(n_nodes) * nd
    weight = jnp.stack([jnp.sum(F[shaft_trans + p]) for p in (0, 1)])
    return StaticResult(positions=pos, displacement=q[: nd * n_nodes].reshape(n_nodes, nd)[:, :2],
                        rotation=q[: nd * n_nodes].reshape(n_nodes, nd)[:, 2:], bearing_reactions=reactions,
                        constraint_reactions=cons, disk_forces=disk_forces, weight=weight,
                        element_ends=jnp.stack([pos[:-1], pos[1:]], axis=1), shear=shear, moment=moment,
                        residual=residual, axis=axis)


def _rigid_modes(rotor, n):
    """The four rigid-body motions on all dofs: translations in x and y, rotations
    in the xz and yz planes (pedestals move with their bearing's node)."""
    nd, n_nodes = DOFS_PER_NODE, rotor.n_nodes
    z = np.asarray(rotor.node_positions)
    ped = [rotor.bearing_nodes[b] for b in rotor.support_bearings]
    R = np.zeros((n, 4))
    for p in (0, 1):
        R[p: nd * n_nodes: nd, p] = 1.0
        R[p: nd * n_nodes: nd, 2 + p] = z
        R[p + 2: nd * n_nodes: nd, 2 + p] = 1.0
        for j, node in enumerate(ped):
            R[nd * n_nodes + 2 * j + p, p] = 1.0
            R[nd * n_nodes + 2 * j + p, 2 + p] = z[node]
    return R


def _singular(rotor, K, f):
    """`K` (free dofs `f`) leaves a rigid-body motion (or a part of one) free."""
    K = np.asarray(K)
    if not np.all(np.isfinite(K)):
        return True
    R = _rigid_modes(rotor, rotor.n_dofs)
    fixed = np.setdiff1d(np.arange(rotor.n_dofs), f)
    if fixed.size:   # the combinations of rigid motions no fixed dof holds
        _, sv, vt = np.linalg.svd(R[fixed])
        rank = int(np.sum(sv > 1e-12 * max(sv.max(), 1.0)))
        R = R @ vt[rank:].T
    R = R[f]
    if R.shape[1] == 0:
        return False
    Q, _ = np.linalg.qr(R)
    smin = np.linalg.svd(K @ Q, compute_uv=False).min()
    return bool(smin <= 1e-12 * np.linalg.norm(K, 2))


def _split_by_node(rotor, outside, q):
    """Each bearing's force on the shaft: the node's non-element force when it is
    the node's only bearing, else split by the bearings' own stiffness."""
    nodes = list(rotor.bearing_nodes)
    if not nodes:
        return jnp.zeros((0, 2))
    rows = []
    for i, node in enumerate(nodes):
        if nodes.count(node) == 1:
            rows.append(outside[node])
        else:
            c = rotor.bearing_coefficients(0.0)[i]
            kb = jnp.array([[c[0], c[2]], [c[3], c[1]]])
            rows.append(-kb @ q[DOFS_PER_NODE * node: DOFS_PER_NODE * node + 2])
    return jnp.stack(rows)
