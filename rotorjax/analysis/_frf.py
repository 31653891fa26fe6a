"""Frequency-response functions and the steady response to several unbalances
of a finite-element rotor: all through the one frequency-response solve
(`rotorjax.models._frequency.frequency_response`),

    (K(W) - w^2 M(W) + i w (C(W) + W G1)) Q = F,

with the bearing coefficients evaluated at the running speed `W`. A receptance
`H_oi(w)` is the displacement `Q_o` for a unit force `F_i`; `speed=None` makes
the rotor run at the excitation frequency (`W = w`: ROSS's `run_freq_response`,
whose `transfer_matrix(speed=s)` is the synchronous case), a number holds `W`
fixed while `w` sweeps. Velocity and acceleration are `i w H` and `-w^2 H`.
"""

import dataclasses

import equinox as eqx
import jax
import jax.numpy as jnp
import numpy as np

from ..models._fe_rotor import DOFS_PER_NODE
from ..models._frequency import frequency_response
from ..models._contract import require
from ..models._validate import InputError, as_numpy, as_param, check_choice, check_node, is_concrete, show

#: the translation directions and their dof within a node
DIRECTIONS = {"x": 0, "y": 1}
KINDS = ("displacement", "velocity", "acceleration")


def full_rotor(rotor, what="rotor"):
    """`rotor` itself, checked to be a shaft model (`FlexibleRotor`, `ReducedRotor` or
    `RotorScene`: `MissingCapability` otherwise)."""
    if not isinstance(rotor, eqx.Module):   # not a model at all (a number, a path)
        raise InputError(f"{what} must be a FlexibleRotor, ReducedRotor or RotorScene, got {type(rotor).__name__}")
    require(rotor, "shaft", what)
    return rotor


def linear_system(system):
    """`(matrices, system)`: `matrices(W)` the `(M, C + G, K)` of the shaft model's
    `linear_matrices(W)` at running speed `W` (bearings at `W`; a `RotorScene`'s
    components' linearisations included); the system's own coordinates (`expand`,
    `project`, `free_dofs`, nodes) are the ones they are written in."""
    full_rotor(system, "a linear analysis of a finite-element rotor")

    def matrices(W):
        lm = system.linear_matrices(W)
        return lm.M, lm.C + lm.G, lm.K

    return matrices, system


#: undamped eigenvalues `w^2` below this fraction of the largest are rigid-body modes
RIGID_BODY_RTOL = 1e-12


def rigid_body_modes(system, speed=0.0) -> int:
    """The number of rigid-body modes of `system` (a `RotorScene`, `FlexibleRotor` or
    `ReducedRotor`) with its bearings at `speed`: the undamped eigenvalues `w^2` of
    the symmetric parts of `(K, M)` with `|w^2| < RIGID_BODY_RTOL max |w^2|` (zero up
    to rounding: a rotor that its bearings do not hold in place)."""
    import scipy.linalg

    matrices, _ = linear_system(system)
    M, _, K = (np.asarray(a, dtype=float) for a in matrices(jnp.float64(speed)))
    M, K = 0.5 * (M + M.T), 0.5 * (K + K.T)
    try:
        lam = scipy.linalg.eigh(K, M, eigvals_only=True)
    except np.linalg.LinAlgError:  # a singular mass matrix: no rigid-body test possible here
        return 0
    scale = float(np.max(np.abs(lam))) if lam.size else 0.0
    return int(np.sum(np.abs(lam) <= RIGID_BODY_RTOL * scale)) if scale > 0 else int(lam.size)


def check_supported(system, speed=0.0, what="the rotor"):
    """Refuse (`InputError`) a rotor with rigid-body modes (`rigid_body_modes`): its
    linear analyses would report those zero frequencies as whirl modes and critical
    speeds. The message says why and what to add."""
    n = rigid_body_modes(system, speed)
    if n:
        raise InputError(f"{what} is not supported: it has {n} rigid-body mode{'s' if n > 1 else ''} (zero natural "
                         f"frequencies{f' with the bearings at {float(speed):g} rad/s' if speed else ''}), so its "
                         "modes, critical speeds and responses are meaningless; add bearings ([[bearing]] tables "
                         "with a stiffness) or fix dofs ([[fixed]])")
    return system


def dof_index(rotor, name, node, direction):
    """The position of `(node, direction)`'s translation among the free dofs."""
    node = check_node(name, node, rotor.n_nodes, "node")
    if not isinstance(direction, str) or direction not in DIRECTIONS:
        raise InputError(f"{name}: the direction must be 'x' or 'y', got {direction!r}")
    dof = DOFS_PER_NODE * node + DIRECTIONS[direction]
    free = np.asarray(rotor.free_dofs)
    where = np.flatnonzero(free == dof)
    if where.size == 0:
        raise InputError(f"{name}: dof {direction} of node {node} is fixed")
    return int(where[0])


def _point(name, value):
    try:
        node, direction = value
    except (TypeError, ValueError):
        raise InputError(f"{name} must be a (node, 'x' | 'y') pair, got {show(value)}") from None
    return node, direction


class FRF(eqx.Module):
    """A frequency-response function `H(w)` (complex, per unit force: m/N, m/s/N
    or m/s^2/N), with `frequencies` (rad/s), `kind`, the `input` and `output`
    `(node, direction)` and the running `speed` (None: the rotor runs at `w`)."""

    frequencies: jax.Array
    values: jax.Array
    kind: str = eqx.field(static=True)
    input: tuple = eqx.field(static=True)
    output: tuple = eqx.field(static=True)
    speed: object = eqx.field(static=True)

    @property
    def magnitude(self):
        return jnp.abs(self.values)

    @property
    def phase(self):
        return jnp.angle(self.values)


def frf(rotor, input, output, frequencies, kind="displacement", speed=None) -> FRF:
    """Frequency-response function from a force at `input = (node, "x" | "y")` to
    the motion at `output = (node, "x" | "y")`, at the excitation `frequencies`
    (rad/s, vmapped).

    **Arguments:**
    - `rotor`: a `FlexibleRotor`, `ReducedRotor` or `RotorScene` (its rotor).
    - `kind`: "displacement" (receptance `H`), "velocity" (`i w H`) or
      "acceleration" (`-w^2 H`).
    - `speed`: None (the rotor runs at the excitation frequency, as in ROSS's
      `run_freq_response`), or a fixed running speed (rad/s); the bearings are
      evaluated at the running speed either way.

    **Returns:** an `FRF`.
    """
    matrices, rotor = linear_system(rotor)
    check_choice("kind", kind, KINDS)
    ni, di = _point("input", input)
    no, do = _point("output", output)
    i = dof_index(rotor, "input", ni, di)
    o = dof_index(rotor, "output", no, do)
    if is_concrete(frequencies):
        as_numpy("frequencies", frequencies, ndim=1)
    if speed is not None and is_concrete(speed):
        as_param("speed", speed, shape=())
    n = len(rotor.free_dofs)
    f = rotor.project(jnp.zeros(n, dtype=jnp.complex128).at[i].set(1.0))

    def one(w):
        M, C, K = matrices(w if speed is None else jnp.asarray(speed, dtype=jnp.float64))
        H = rotor.expand(frequency_response(M, C, K, f, w))[rotor.free_dofs[o]]
        return {"displacement": H, "velocity": 1j * w * H, "acceleration": -w**2 * H}[kind]

    w = jnp.asarray(frequencies, dtype=jnp.float64)
    return FRF(w, jax.vmap(one)(w), kind, (int(ni), di), (int(no), do),
               None if speed is None else (float(speed) if is_concrete(speed) else speed))


def _unbalances(rotor, unbalances):
    """`(nodes, magnitudes, phases)`: static node indices, array magnitudes and phases."""
    try:
        rows = [tuple(u) for u in unbalances]
    except TypeError:
        raise InputError(f"unbalances must be a list of (node, magnitude kg m, phase rad), got "
                         f"{show(unbalances)}") from None
    if not rows:
        raise InputError("unbalances must hold at least one (node, magnitude kg m, phase rad)")
    nodes, mags, phases = [], [], []
    for k, u in enumerate(rows):
        if len(u) != 3:
            raise InputError(f"unbalances[{k}] must be (node, magnitude kg m, phase rad), got {show(u)}")
        node = check_node(f"unbalances[{k}]", u[0], rotor.n_nodes, "unbalance node")
        b = DOFS_PER_NODE * node
        free = set(np.asarray(rotor.free_dofs).tolist())
        if b not in free or b + 1 not in free:
            raise InputError(f"unbalances[{k}]: the unbalance node {node} has fixed translation dofs")
        nodes.append(node)
        mags.append(as_param(f"unbalances[{k}] magnitude", u[1], sign="nonnegative", shape=()))
        phases.append(as_param(f"unbalances[{k}] phase", u[2], shape=()))
    return tuple(nodes), jnp.stack(mags), jnp.stack(phases)


def _probe(rotor, probe_nodes):
    if probe_nodes is None:
        return np.arange(rotor.n_nodes)
    p = np.atleast_1d(as_numpy("probe_nodes", probe_nodes))
    if p.ndim != 1 or p.size < 1:
        raise InputError(f"probe_nodes must be a node or a 1-D list of >= 1 nodes, got shape {p.shape}")
    return np.array([check_node(f"probe_nodes[{i}]", v, rotor.n_nodes, "probe") for i, v in enumerate(p)],
                    dtype=int)


def _rotating_load(rotor, nodes, mags, phases):
    """The unit-speed load of rotating unbalances in the rotor's coordinates: per
    unbalance `F_x = U e^{i phase}`, `F_y = -i F_x` at its node (a force rotating with
    the shaft; times `W^2` at speed `W`), summed."""
    pos = {int(d): i for i, d in enumerate(np.asarray(rotor.free_dofs))}
    unit = jnp.zeros(len(pos), dtype=jnp.complex128)
    for k, node in enumerate(nodes):
        b = DOFS_PER_NODE * node
        u = mags[k] * jnp.exp(1j * phases[k])
        unit = unit.at[pos[b]].add(u).at[pos[b + 1]].add(-1j * u)
    return rotor.project(unit)


def _unbalance_solver(matrices, rotor, unbalances):
    """`Q(W)`: the response on all dofs at speed `W` to every unbalance at once."""
    unit = _rotating_load(rotor, *_unbalances(rotor, unbalances))

    def solve(w):
        M, C, K = matrices(w)
        return rotor.expand(frequency_response(M, C, K, w**2 * unit, w))

    return solve


def _at_probes(solve, probe, speeds):
    """`(X, Y)` at the probe nodes for every speed (vmapped)."""
    def one(w):
        q = solve(w)
        return q[DOFS_PER_NODE * probe], q[DOFS_PER_NODE * probe + 1]

    return jax.vmap(one)(jnp.asarray(speeds, dtype=jnp.float64))


def unbalance_response_many(rotor, unbalances, speeds, probe_nodes=None):
    """Steady response to several rotating unbalances at once,
    `unbalances = [(node, magnitude kg m, phase rad), ...]`, at spin speeds
    `speeds` (rad/s, vmapped): complex `X, Y` of shape `(n_speeds, n_probes)` at
    `probe_nodes` (default: all nodes), `x = Re(X e^{i W t})`. The loads add in
    one right-hand side (superposition is exact for the linear rotor); each is
    `F_x = U W^2 e^{i phase}`, `F_y = -i F_x` as in `unbalance_response`, and the
    bearings are evaluated at `W`."""
    matrices, rotor = linear_system(rotor)
    probe = _probe(rotor, probe_nodes)
    if is_concrete(speeds):
        as_numpy("speeds", speeds, ndim=1)
    return _at_probes(_unbalance_solver(matrices, rotor, unbalances), probe, speeds)


def unbalance_response(rotor, node, unbalance, phase, speeds, probe_nodes=None):
    """Steady response to a rotating unbalance `unbalance` (kg m, any sign) at `node`
    and `phase` (rad), at spin speeds `speeds` (rad/s, vmapped): complex amplitudes of
    `x` and `y` at `probe_nodes` (default: all nodes), `x = Re(X e^{i Omega t})`: the
    one-unbalance case of `unbalance_response_many` (the same solve).

    The force is `F = unbalance Omega^2 (cos(Omega t + phase), sin(Omega t + phase))`,
    so `F_x = U Omega^2 e^{i phase}` and `F_y = -i F_x`; the response solves
    `(K - Omega^2 M + i Omega (C + Omega G1)) Q = F` (a `RotorScene`: its linear
    part, components' linearisations included; for its own `Unbalance` components:
    `rotorjax.analysis.scene_unbalance_response`).
    """
    matrices, rotor = linear_system(rotor)
    node = check_node("node", node, rotor.n_nodes, "unbalance")
    probe = _probe(rotor, probe_nodes)
    for name, v in (("unbalance", unbalance), ("phase", phase)):
        if is_concrete(v):
            as_param(name, v, shape=())
    if is_concrete(speeds):
        as_numpy("speeds", speeds, ndim=1)
    b = DOFS_PER_NODE * node
    if b not in rotor.free_dofs or b + 1 not in rotor.free_dofs:
        raise InputError(f"node: the unbalance node {node} has fixed translation dofs")
    unit = _rotating_load(rotor, (node,), jnp.reshape(jnp.asarray(unbalance, dtype=jnp.float64), (1,)),
                          jnp.reshape(jnp.asarray(phase, dtype=jnp.float64), (1,)))

    def solve(w):
        M, C, K = matrices(w)
        return rotor.expand(frequency_response(M, C, K, w**2 * unit, w))

    return _at_probes(solve, probe, speeds)


class DeflectedShape(eqx.Module):
    """The rotor's steady orbit at every node at one `speed`: `x`, `y` complex
    amplitudes, `forward` and `backward` circular components
    (`(X + iY) / 2`, `(conj X + i conj Y) / 2`, ROSS's), `major`, `minor`
    semi-axes of the elliptic orbit (`|forward| +- |backward|`), `angle` of the major
    axis (its direction from x, in [0, pi) rad) and the node `positions` (m)."""

    speed: jax.Array
    positions: jax.Array
    x: jax.Array
    y: jax.Array
    forward: jax.Array
    backward: jax.Array
    major: jax.Array
    minor: jax.Array
    angle: jax.Array


def deflected_shape(rotor, unbalances, speed) -> DeflectedShape:
    """The deflected shape (orbit at every node) at spin speed `speed` under the
    `unbalances` of `unbalance_response_many`."""
    matrices, rotor = linear_system(rotor)
    if is_concrete(speed):
        as_param("speed", speed, shape=())
    w = jnp.asarray(speed, dtype=jnp.float64)
    q = _unbalance_solver(matrices, rotor, unbalances)(w)
    X, Y = q[0::DOFS_PER_NODE][:rotor.n_nodes], q[1::DOFS_PER_NODE][:rotor.n_nodes]
    fwd = X / 2 + 1j * Y / 2
    bwd = jnp.conj(X) / 2 + 1j * jnp.conj(Y) / 2
    # x + i y = fwd e^{i w t} + bwd e^{-i w t}: the phasors align (the major axis)
    # along the mean of their arguments, a direction defined modulo pi
    angle = jnp.mod((jnp.angle(fwd) + jnp.angle(bwd)) / 2, jnp.pi)
    major = jnp.abs(fwd) + jnp.abs(bwd)
    minor = jnp.abs(jnp.abs(fwd) - jnp.abs(bwd))
    return DeflectedShape(w, rotor.full_rotor.node_positions, X, Y, fwd, bwd, major, minor, angle)


# ---- curves over a speed or frequency range: chunked, peaks located, refined ----

def _unbalance_amplitudes(speeds, system, unbalances):
    """`(X, Y)` at every node, `(n_speeds, n_nodes)` (a batched function for
    `map_chunked`: the probe is chosen on the host, so one program serves all)."""
    return unbalance_response_many(system, unbalances, speeds)


def _traced_unbalances(unbalances):
    """Nodes static, magnitudes and phases as arrays (one compilation for any values)."""
    return tuple((int(n), jnp.asarray(m, dtype=jnp.float64), jnp.asarray(p, dtype=jnp.float64))
                 for n, m, p in unbalances)


@dataclasses.dataclass(frozen=True)
class ResponseCurve:
    """An unbalance response over a speed range, its peaks located exactly.

    - `speeds` (rad/s): the grid, with points added around each peak (sorted);
    - `x`, `y`: complex amplitudes at `probe` on `speeds`; `amplitude` `sqrt(|x|^2 +
      |y|^2)` (m);
    - `probe`: the node read; `probe_chosen`: True when it was chosen as the node of
      largest response on the grid;
    - `peaks`: the `Peak`s (`rotorjax.analysis.refine_maxima`) of the amplitude;
    - `max_amplitude`, `speed_at_max`: the largest amplitude over the range (a
      located peak, or an end of the range).
    """

    speeds: np.ndarray
    x: np.ndarray
    y: np.ndarray
    amplitude: np.ndarray
    probe: int
    probe_chosen: bool
    peaks: list
    max_amplitude: float
    speed_at_max: float


def response_curve(system, unbalances, speeds, probe=None, *, rtol=1e-10) -> ResponseCurve:
    """The unbalance response of `system` (a `RotorScene`, `FlexibleRotor` or
    `ReducedRotor`) to `unbalances = [(node, kg m, rad), ...]` over `speeds`
    (rad/s, any length: evaluated in fixed-size chunks), read at node `probe`
    (default: the node of largest amplitude on the grid), with every interior peak of
    the amplitude located to `rtol` and points added around it."""
    from ._peaks import refine_maxima, refined_grid
    from ..sweep import bucket_size, map_chunked

    _, rotor = linear_system(system)
    _unbalances(rotor, unbalances)   # checked here, with their messages
    speeds = as_numpy("speeds", speeds, ndim=1)
    size = bucket_size(len(speeds))
    traced = _traced_unbalances(unbalances)

    def at(w):
        return map_chunked(_unbalance_amplitudes, w, system, traced, size=size)

    X, Y = at(speeds)
    amp_all = np.sqrt(np.abs(X) ** 2 + np.abs(Y) ** 2)
    chosen = probe is None
    if chosen:
        probe = int(np.argmax(np.nanmax(np.where(np.isfinite(amp_all), amp_all, -np.inf), axis=0)))
    probe = check_node("probe", probe, rotor.n_nodes, "probe")

    def amplitude(w):
        x, y = at(w)
        return np.sqrt(np.abs(x[:, probe]) ** 2 + np.abs(y[:, probe]) ** 2)

    peaks = refine_maxima(amplitude, speeds, amp_all[:, probe], rtol=rtol, budget=size)
    grid = refined_grid(speeds, peaks)
    if grid.size != speeds.size:
        X, Y = at(grid)
    x, y = X[:, probe], Y[:, probe]
    amp = np.sqrt(np.abs(x) ** 2 + np.abs(y) ** 2)
    k = int(np.nanargmax(amp)) if np.any(np.isfinite(amp)) else 0
    top = max([(p.y, p.x) for p in peaks] + [(float(amp[k]), float(grid[k]))])
    return ResponseCurve(grid, x, y, amp, probe, chosen, peaks, float(top[0]), float(top[1]))


def _frf_values(w, system, input, output, kind, speed):
    return frf(system, input, output, w, kind, speed).values


@dataclasses.dataclass(frozen=True)
class FRFCurve:
    """An FRF over a frequency range (`frf`'s arguments), evaluated in chunks, its
    magnitude's peaks located exactly (`peaks`) and points added around them
    (`frequencies` sorted, `values` on them)."""

    frequencies: np.ndarray
    values: np.ndarray
    peaks: list


def frf_curve(system, input, output, frequencies, kind="displacement", speed=None, *, rtol=1e-10) -> FRFCurve:
    """`frf` over `frequencies` of any length (chunked), with the peaks of `|H|`
    located to `rtol` and the curve refined around them (smooth Bode and polar plots
    through the resonances)."""
    from ._peaks import refine_maxima, refined_grid
    from ..sweep import bucket_size, map_chunked

    w = as_numpy("frequencies", frequencies, ndim=1)
    frf(system, input, output, w[:1], kind, speed)   # the checks, with their messages
    size = bucket_size(len(w))
    s = None if speed is None else jnp.asarray(speed, dtype=jnp.float64)

    def at(f):
        return map_chunked(_frf_values, f, system, tuple(input), tuple(output), kind, s, size=size)

    h = at(w)
    peaks = refine_maxima(lambda f: np.abs(at(f)), w, np.abs(h), rtol=rtol, budget=size)
    grid = refined_grid(w, peaks)
    return FRFCurve(grid, at(grid) if grid.size != w.size else h, peaks)
