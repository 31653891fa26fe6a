"""The model of a phasor file on a finite-element rotor: every measured 1x phasor
(or impact-test receptance) as the one frequency-response solve predicts it.

Unbalance phasors: at each distinct speed `W` one solve with a right-hand side per
loaded node (the file's unbalances, the fitted unbalance nodes, the trial weights'
nodes), a unit unbalance `F_x = W^2`, `F_y = -i W^2` each; a row's phasor is the
row's sensor dof of `sum_k H_k u_k`, with `u` the unbalances of the row's run (the
rotor's own plus the run's trial weight). Receptances: at each distinct
(running speed, frequency) pair one solve per input dof. Pure JAX in the
parameters: differentiable and vmappable.
"""

import equinox as eqx
import jax
import jax.numpy as jnp
import numpy as np

from .._errors import InputError
from ..models._fe_rotor import DOFS_PER_NODE
from ..models._frequency import frequency_response, frequency_response_jvp


def _free_position(rotor, node, direction, what):
    """Position of a node's x or y among the free dofs, or an InputError naming `what`."""
    if not 0 <= node < rotor.n_nodes:
        raise InputError(f"{what}: node {node} is not a node of the rotor (0..{rotor.n_nodes - 1})")
    pos = {int(d): i for i, d in enumerate(np.asarray(rotor.free_dofs))}
    dof = DOFS_PER_NODE * int(node) + int(direction)
    if dof not in pos:
        raise InputError(f"{what}: node {node} {'xy'[int(direction)]} is a fixed dof of the rotor")
    return pos[dof]


class PhasorModel(eqx.Module):
    """The index arrays that map a phasor file onto the rotor's solves."""

    kind: str = eqx.field(static=True)
    speeds: jax.Array            # distinct running speeds (unbalance) or (speed, frequency) pairs (frf)
    point: jax.Array             # (n,) the row's solve
    out: jax.Array               # (n,) the row's free-dof position
    loads: tuple = eqx.field(static=True)         # load nodes (unbalance) or input free-dof positions (frf)
    load_pos: jax.Array          # (n_loads, 2) free-dof positions of x, y (unbalance)
    col: jax.Array               # frf: (n,) the row's input column
    trial: jax.Array             # (n, n_loads) complex: each row's trial weight on the loads
    speed_dependent: bool = eqx.field(static=True)   # the rotor's bearings depend on speed

    def points(self):
        """`(W, w, scale)` per solve point: running speed, excitation frequency and the
        load's scale (an unbalance's `W^2`; 1 for a unit force)."""
        if self.kind == "frf":
            return self.speeds[:, 0], self.speeds[:, 1], jnp.ones(self.speeds.shape[0])
        return self.speeds, self.speeds, self.speeds**2

    def unit_loads(self, n):
        """`(n, n_loads)`: a unit force at each input dof (frf), or a unit unbalance's
        `F_x = 1`, `F_y = -i` at each load node."""
        F = jnp.zeros((n, len(self.loads)), dtype=jnp.complex128)
        cols = np.arange(len(self.loads))
        if self.kind == "frf":
            return F.at[np.asarray(self.loads), cols].set(1.0)
        return F.at[self.load_pos[:, 0], cols].set(1.0).at[self.load_pos[:, 1], cols].set(-1j)

    def solves(self, rotor):
        """`H[point, free dof, load]`: the responses to unit loads at every solve point
        (the matrices assembled once when no bearing depends on speed)."""
        fixed = None if rotor.speed_dependent else rotor.reduced_matrices()
        F = self.unit_loads(len(rotor.free_dofs))

        def one(W, w, s):
            M, C, G1, K = rotor.reduced_matrices(W) if fixed is None else fixed
            return frequency_response(M, C + W * G1, K, s * F, w)

        return jax.vmap(one)(*self.points())

    def solves_jvp(self, matrices, theta):
        """`(H, dH)`: `solves` of the rotor `matrices(theta, W)` makes (its
        `reduced_matrices`) and their derivatives along each component of `theta`,
        `(P, n, L)` and `(P, n, L, p)`, one LU per point (`frequency_response_jvp`)."""
        def mats(W):
            M, C, G1, K = matrices(theta, W)
            dM, dC, dG1, dK = jax.jacfwd(lambda th: matrices(th, W))(theta)
            return (M, C, G1, K), (dM, dC, dG1, dK)

        fixed = None if self.speed_dependent else mats(0.0)

        def one(W, w, s):
            (M, C, G1, K), (dM, dC, dG1, dK) = mats(W) if fixed is None else fixed
            F = self.unit_loads(M.shape[0])
            return frequency_response_jvp(M, C + W * G1, K, dM, dC + W * dG1, dK, s * F, w)

        return jax.vmap(one)(*self.points())

    def gather(self, H):
        """The rows' entries of solves `H` (`(P, n, L, ...)`): `(n_rows, L, ...)`, or for
        frf data `(n_rows, ...)` (each row's own input)."""
        if self.kind == "frf":
            return H[self.point, self.out, self.col]
        return H[self.point, self.out]

    def rows(self, rotor):
        """`(n, n_loads)`: each row's response to a unit load at each load (frf: `(n,)`)."""
        return self.gather(self.solves(rotor))

    def unit_index(self, node):
        return self.loads.index(int(node))


def phasor_model(rotor, data, unbalance_nodes=()) -> "PhasorModel":
    """The `PhasorModel` of `data` (a `PhasorData`) on `rotor`, with loads at
    `unbalance_nodes` (the rotor's and the fitted unbalances' nodes) and at the
    trial weights' nodes. Rows on nodes the rotor lacks, or on fixed dofs, are bad
    input naming the row."""
    label = data.path
    out = np.empty(data.n, dtype=int)
    for i in range(data.n):
        out[i] = _free_position(rotor, int(data.node[i]), int(data.direction[i]), f"{label}: {data.row(i)}")
    if data.kind == "frf":
        pairs, point = np.unique(np.stack([data.speed, data.frequency], axis=1), axis=0, return_inverse=True)
        inputs = np.empty(data.n, dtype=int)
        for i in range(data.n):
            inputs[i] = _free_position(rotor, int(data.input_node[i]), int(data.input_direction[i]),
                                       f"{label}: {data.row(i)} (input)")
        loads, col = np.unique(inputs, return_inverse=True)
        return PhasorModel("frf", jnp.asarray(pairs), jnp.asarray(point.ravel()), jnp.asarray(out),
                           tuple(int(v) for v in loads), jnp.zeros((0, 2), dtype=int), jnp.asarray(col.ravel()),
                           jnp.zeros((data.n, 0), dtype=jnp.complex128), rotor.speed_dependent)
    speeds, point = np.unique(data.speed, return_inverse=True)
    nodes = list(dict.fromkeys(int(n) for n in unbalance_nodes))
    for n in np.unique(data.trial_node[data.trial_node >= 0]):
        if int(n) not in nodes:
            nodes.append(int(n))
    load_pos = np.array([[_free_position(rotor, n, d, f"{label}: unbalance or trial weight") for d in (0, 1)]
                         for n in nodes], dtype=int).reshape(len(nodes), 2)
    trial = np.zeros((data.n, len(nodes)), dtype=complex)
    has = data.trial_node >= 0
    for i in np.flatnonzero(has):
        trial[i, nodes.index(int(data.trial_node[i]))] = data.trial_magnitude[i] * np.exp(1j * data.trial_phase[i])
    return PhasorModel("unbalance", jnp.asarray(speeds), jnp.asarray(point.ravel()), jnp.asarray(out),
                       tuple(nodes), jnp.asarray(load_pos), jnp.zeros(0, dtype=int), jnp.asarray(trial),
                       rotor.speed_dependent)


#: the receptance coupling pays when the modified dofs are at most this fraction of the free dofs
COUPLING_FRACTION = 0.5


class Receptances(eqx.Module):
    """The rows' responses when the fitted parameters change the rotor's matrices
    only on a few dofs `D` (bearings, supports, disks, point masses act at their
    nodes): with `G = Z0^-1` at the start (one LU per solve point, once), the
    Woodbury identity gives the modified rotor's receptances exactly,

        H_SL = G_SL - G_SD (I + dZ G_DD)^-1 dZ G_DL,   dZ = Z(theta) - Z0 on D,

    `S` the sensor dofs, `L` the loads: per parameter set a `d x d` solve per
    point instead of a full one (structural modification, receptance coupling).

    The matrices are affine in each parameter's value (a bearing coefficient, a
    pedestal's, a disk's mass or inertia enters once), so `dZ` is assembled from
    the values directly, `dX = sum_k (v_k - v_k0) B_k` on `D` with `B_k` the
    derivative of `X` with respect to value `k`: no FE assembly per parameter set."""

    dofs: jax.Array              # (d,) free-dof positions of D
    G_SL: jax.Array              # (P, n_S, L)
    G_SD: jax.Array              # (P, n_S, d)
    G_DD: jax.Array              # (P, d, d)
    G_DL: jax.Array              # (P, d, L)
    basis: tuple                 # (B_M, B_C, B_G1, B_K), each (p, d, d): d(matrix on D) / d(value k)
    values0: jax.Array           # (p,) the values at the start
    sensor: jax.Array            # (n_rows,) each row's sensor among S

    def rows(self, model, values):
        """The rows' unit responses (as `PhasorModel.rows`) of the rotor with the
        parameter values `values` (`(p,)`, in the order of the fit)."""
        D = self.dofs
        dv = values - self.values0
        dM, dC, dG1, dK = (jnp.tensordot(dv, B, axes=1) for B in self.basis)
        W, w, _ = model.points()

        def one(W, w, G_SL, G_SD, G_DD, G_DL):
            dZ = dK - w**2 * dM + 1j * w * (dC + W * dG1)
            T = jnp.linalg.solve(jnp.eye(D.shape[0]) + dZ @ G_DD, dZ @ G_DL)
            return G_SL - G_SD @ T

        H = jax.vmap(one)(W, w, self.G_SL, self.G_SD, self.G_DD, self.G_DL)
        if model.kind == "frf":
            return H[model.point, self.sensor, model.col]
        return H[model.point, self.sensor]


@eqx.filter_jit
def _start(matrices, theta0):
    """The matrices at `theta0` (speed 0) and their derivatives (compiled: assembling
    the FE matrices eagerly is slow)."""
    return matrices(theta0, 0.0), jax.jacfwd(lambda th: matrices(th, 0.0))(theta0)


@eqx.filter_jit
def _blocks(model, matrices, theta0, S, D, start):
    """`G = Z0^-1` on the blocks `(S, L)`, `(S, D)`, `(D, D)`, `(D, L)` at every solve
    point: one solve per point with the loads and unit columns on `D`."""
    n = start[0].shape[0]
    F = model.unit_loads(n)
    E = jnp.zeros((n, D.shape[0]), dtype=jnp.complex128).at[D, jnp.arange(D.shape[0])].set(1.0)
    L = F.shape[1]

    def one(W, w, s):
        M, C, G1, K = start if not model.speed_dependent else matrices(theta0, W)
        X = frequency_response(M, C + W * G1, K, jnp.concatenate([s * F, E], axis=1), w)
        return X[S, :L], X[S, L:], X[D][:, L:], X[D][:, :L]

    return jax.vmap(one)(*model.points())


def receptances(model: PhasorModel, rotor, matrices, theta0, values0, dvalues0):
    """The `Receptances` of `model` around `theta0` for parameters that change
    `matrices(theta, W)` (the rotor's `reduced_matrices`), or None when they change
    more than `COUPLING_FRACTION` of the dofs (then the direct solves are cheaper).
    `values0` are the parameters' values at `theta0` and `dvalues0` their
    derivatives with respect to theta there."""
    n = len(rotor.free_dofs)
    (M0, C0, G10, K0), d = _start(matrices, jnp.asarray(theta0, dtype=jnp.float64))
    touched = np.zeros(n, dtype=bool)
    for a in d:
        nz = np.asarray(jnp.any(a != 0, axis=-1))
        touched |= nz.any(axis=1) | nz.any(axis=0)
    D = np.flatnonzero(touched)
    if D.size > COUPLING_FRACTION * n:
        return None
    S, sensor = np.unique(np.asarray(model.out), return_inverse=True)
    G_SL, G_SD, G_DD, G_DL = _blocks(model, matrices, jnp.asarray(theta0, dtype=jnp.float64), jnp.asarray(S),
                                     jnp.asarray(D), (M0, C0, G10, K0))
    dv = jnp.asarray(dvalues0, dtype=jnp.float64)
    basis = tuple(jnp.moveaxis(a[D][:, D], -1, 0) / dv[:, None, None] for a in d)
    return Receptances(jnp.asarray(D), G_SL, G_SD, G_DD, G_DL, basis, jnp.asarray(values0, dtype=jnp.float64),
                       jnp.asarray(sensor.ravel()))
