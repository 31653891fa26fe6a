"""Linear analyses of a `FlexibleRotor` (or a `RotorScene`'s linear part): damped modes, Campbell diagram, critical
speeds, unbalance response, logarithmic decrements. All pure, differentiable with
respect to the rotor's parameters, and vmappable over speeds or designs."""

import equinox as eqx
import jax
import jax.numpy as jnp
import numpy as np

from ..models._validate import (InputError, as_count, as_numpy, as_param, check_choice, check_node,
                               check_span, is_concrete)
from ..analysis._roots import bisect_batched, sign_changes
from ..models._fe_rotor import DOFS_PER_NODE
from ..models._contract import LinearMatrices
from ..models._rotor_scene import RotorScene
from ..models._frequency import frequency_response


def _check_rotor(rotor, scenes=True):
    """The number of coordinates of a `FlexibleRotor`, `ReducedRotor` or (where
    `scenes`) a `RotorScene` (its linear part: components' linearisations included)."""
    if scenes and isinstance(rotor, RotorScene):
        return rotor.n_shaft
    if not all(hasattr(rotor, a) for a in ("free_dofs", "reduced_matrices", "expand", "n_nodes")):
        what = "FlexibleRotor, ReducedRotor or RotorScene" if scenes else "FlexibleRotor or ReducedRotor"
        raise InputError(f"rotor must be a {what}, got {type(rotor).__name__}")
    return len(rotor.free_dofs) if not hasattr(rotor, "basis") else rotor.n_modes


def _check_n_modes(name, n_modes, rotor, allow_none=True, bounded=False):
    """`n_modes` >= 1; `bounded`: also at most the rotor's number of coordinates
    (where the modes are indexed; elsewhere a larger count keeps them all)."""
    n = _check_rotor(rotor)
    if n_modes is None and allow_none:
        return None
    return as_count(name, n_modes, minimum=1, maximum=n if bounded else None)


def _check_speed(name, speed):
    if is_concrete(speed):
        as_param(name, speed, shape=())


class Modes(eqx.Module):
    """Damped modes at one speed, sorted by natural frequency (rad/s).

    - `frequencies`: damped natural frequencies `|Im lambda|` (the modes with
      `Im lambda > 0`); `eigenvalues` the matching `lambda`.
    - `log_dec`: logarithmic decrement `-2 pi Re lambda / |Im lambda|`.
    - `natural_frequencies`: `|lambda|` (rad/s, ROSS's `wn`); `damping_ratio`:
      `-Re lambda / |lambda|`.
    - `forward`: the dominant whirl direction (True: the forward-whirling part of
      the shape, `|x + i y|^2` summed over the nodes, outweighs the backward one).
    - `whirl_value`: ROSS's classification (`whirl_direction`, `whirl_values`):
      each node's orbit whirls forward when `y` lags `x` (`Im(conj(x) y) < 0` for
      `Im lambda > 0`), backward when it leads; the mode is forward (0.0) when every
      node's orbit is forward, backward (1.0) when every one is backward, else mixed
      (0.5). Unlike ROSS, nodes that barely move (`|x|^2 + |y|^2` below `1e-12` of
      the largest) or whose orbit is a straight line (`|Im(conj(x) y)|` below `1e-9`
      of `|x|^2 + |y|^2`) are not counted (ROSS counts a straight line as backward,
      and the sign of a phase difference of round-off size decides there); a mode
      with no counted node (planar) is mixed. `whirl` gives the labels.
    - `shapes`: complex mode shapes on all dofs (fixed dofs zero), columns.
    """

    eigenvalues: jax.Array
    frequencies: jax.Array
    log_dec: jax.Array
    forward: jax.Array
    shapes: jax.Array
    natural_frequencies: jax.Array
    damping_ratio: jax.Array
    whirl_value: jax.Array

    @property
    def whirl(self) -> np.ndarray:
        """`"forward"`, `"backward"` or `"mixed"` per mode (numpy strings, the
        shape of `whirl_value`)."""
        return whirl_labels(self.whirl_value)


def whirl_labels(whirl_value) -> np.ndarray:
    """ROSS's whirl values (0, 0.5, 1) as labels."""
    v = np.asarray(whirl_value)
    return np.where(v == 0.0, "forward", np.where(v == 1.0, "backward", "mixed"))


def _whirl_value(x, y):
    """ROSS's node-by-node whirl classification (see `Modes`) of shapes `x`, `y`
    (nodes x modes)."""
    a = jnp.abs(x) ** 2 + jnp.abs(y) ** 2
    s = jnp.imag(jnp.conj(x) * y)
    counted = (a > 1e-12 * jnp.max(a, axis=0, keepdims=True)) & (jnp.abs(s) > 1e-9 * a)
    any_fwd = jnp.any(counted & (s < 0), axis=0)
    any_bwd = jnp.any(counted & (s > 0), axis=0)
    return jnp.where(any_fwd & ~any_bwd, 0.0, jnp.where(any_bwd & ~any_fwd, 1.0, 0.5))


def state_matrix(rotor, speed):
    """First-order matrix of `M q'' + (C + speed G1) q' + K q = 0` at `speed` (rad/s)
    (a `RotorScene`: its `linear_matrices(speed)`)."""
    if isinstance(rotor, RotorScene):
        return rotor.linear_matrices(speed).state_matrix()
    M, C, G1, K = rotor.reduced_matrices(speed)
    return LinearMatrices(M, C, speed * G1, K).state_matrix()


def modes(rotor, speed, n_modes=None) -> Modes:
    """Damped eigen-analysis at spin speed `speed` (rad/s)."""
    n_modes = _check_n_modes("n_modes", n_modes, rotor)
    _check_speed("speed", speed)
    return _modes(rotor, jnp.asarray(speed, dtype=jnp.float64), n_modes)


@eqx.filter_jit
def _modes(rotor, speed, n_modes):
    """`modes`, compiled once per rotor layout and number of modes."""
    a = state_matrix(rotor, speed)
    lam, vec = jnp.linalg.eig(a)
    n = a.shape[0] // 2
    # keep the upper half-plane (one of each conjugate pair), sorted by frequency
    key = jnp.where(jnp.imag(lam) > 0, jnp.imag(lam), jnp.inf)
    order = jnp.argsort(key)[:n]
    lam, vec = lam[order], vec[:n, order]
    if n_modes is not None:
        lam, vec = lam[:n_modes], vec[:, :n_modes]
    full = rotor.expand(vec)
    shaft = full[: DOFS_PER_NODE * rotor.n_nodes]   # shaft nodes (not supports' pedestals)
    x = shaft[0::DOFS_PER_NODE]
    y = shaft[1::DOFS_PER_NODE]
    fwd = jnp.abs(x + 1j * y)   # forward-whirl amplitude per node (for Im lambda > 0)
    bwd = jnp.abs(x - 1j * y)
    forward = jnp.sum(fwd**2, axis=0) >= jnp.sum(bwd**2, axis=0)
    freq = jnp.abs(jnp.imag(lam))
    wn = jnp.abs(lam)
    return Modes(eigenvalues=lam, frequencies=freq, log_dec=-2 * jnp.pi * jnp.real(lam) / freq,
                 forward=forward, shapes=full, natural_frequencies=wn, damping_ratio=-jnp.real(lam) / wn,
                 whirl_value=_whirl_value(x, y))


def damped_frequencies(rotor, speed, n_modes=None):
    """Damped natural frequencies (rad/s) at `speed`, sorted, from the eigenvalues
    only: differentiable with respect to the rotor's parameters and the speed."""
    n_modes = _check_n_modes("n_modes", n_modes, rotor)
    _check_speed("speed", speed)
    lam = jnp.linalg.eigvals(state_matrix(rotor, jnp.asarray(speed, dtype=jnp.float64)))
    f = jnp.sort(jnp.where(jnp.imag(lam) > 0, jnp.imag(lam), jnp.inf))[: lam.shape[0] // 2]
    return f if n_modes is None else f[:n_modes]


def campbell(rotor, speeds, n_modes=8):
    """Damped natural frequencies and whirl directions over `speeds` (vmapped)."""
    n_modes = _check_n_modes("n_modes", n_modes, rotor)
    if is_concrete(speeds):
        as_numpy("speeds", speeds, ndim=1)
    return jax.vmap(lambda s: modes(rotor, s, n_modes))(jnp.asarray(speeds, dtype=jnp.float64))


_campbell_compiled = eqx.filter_jit(campbell)
_modes_compiled = eqx.filter_jit(modes)


def critical_speeds_1x(rotor, lo, hi, n_scan=200, n_modes=12, xtol=1e-9, whirl="all", return_scan=False,
                       scan=None):
    """Intersections of the Campbell diagram's branches with the 1x line
    `frequency = speed`, located by a scan plus bisection on `omega_k(Omega) - Omega`
    (the shared root finder's steps, `rotorjax.analysis._roots`, to `xtol * max(1, speed)`).
    `whirl="forward"` keeps the forward-whirl branches only (those an unbalance
    excites); "all" also the backward ones (as ROSS reports them).
    Returns `[(speed, mode index)]` in rad/s, sorted (with `return_scan`, also the
    scan `(speeds, Modes)`: the Campbell diagram on the scan's speeds). `scan`: such a
    diagram computed already (the scan is then its speeds, no second eigen-analysis)."""
    check_choice("whirl", whirl, ("all", "forward"))
    lo, hi = check_span("lo", lo, "hi", hi)
    n_scan = as_count("n_scan", n_scan, minimum=2)
    n_modes = _check_n_modes("n_modes", n_modes, rotor, allow_none=False, bounded=True)
    as_param("xtol", xtol, sign="positive", shape=())
    if scan is None:
        speeds = np.linspace(lo, hi, n_scan)
        # the rotor is an argument (not a constant): one compilation per rotor layout
        camp = _campbell_compiled(rotor, jnp.asarray(speeds), n_modes)
    else:  # a Campbell diagram the caller has computed already (its speeds in [lo, hi], >= n_modes modes)
        speeds, camp = np.asarray(scan[0], dtype=float), scan[1]
        if speeds.ndim != 1 or np.asarray(camp.frequencies).shape[:2] != (speeds.size, n_modes):
            raise InputError(f"scan must be (speeds, Modes) with {n_modes} modes at each speed")
    freq = np.asarray(camp.frequencies)
    fwd = np.asarray(camp.forward)

    brackets = []
    for k in range(n_modes):
        g = freq[:, k] - speeds
        for i in sign_changes(g):
            if whirl == "forward" and not (fwd[i, k] and fwd[i + 1, k]):
                continue
            brackets.append((speeds[i], speeds[i + 1], g[i], k))
    found = []
    if brackets:
        a, b, ga, ks = (np.array(v) for v in zip(*brackets))
        # every bracket halved at once, in one compiled loop (eigenvalues only)
        x = bisect_batched(_crossing_residual, a, b, ga, ks, xtol=xtol, rtol=xtol, args=(rotor, n_modes))
        found = sorted((float(s), int(k)) for s, k in zip(x, ks))
    return (found, (speeds, camp)) if return_scan else found


def _crossing_residual(speed, k, rotor, n_modes):
    """`omega_k(speed) - speed`: the k-th damped natural frequency's distance from 1x."""
    return damped_frequencies(rotor, speed, n_modes)[k] - speed


def critical_speed(rotor, k, guess, iters=6):
    """The speed where the `k`-th damped natural frequency (sorted, all whirl
    directions) equals the speed: the fixed point `Omega = omega_k(Omega)`, which
    converges fast because gyroscopic effects make `|d omega_k / d Omega|` small (the
    residual `omega_k(Omega) - Omega` is returned to check it). Pure JAX, vmappable
    over designs; differentiate with the implicit function theorem on
    `omega_k(Omega) - Omega = 0`."""
    n = _check_rotor(rotor)
    k = as_count("k (mode index)", k, minimum=0, maximum=n - 1)
    iters = as_count("iters", iters, minimum=1)
    _check_speed("guess", guess)
    w = jnp.float64(guess)
    for _ in range(iters):  # unrolled: a few iterations, no while loop around LAPACK calls
        w = damped_frequencies(rotor, w, k + 1)[k]
    return w, damped_frequencies(rotor, w, k + 1)[k] - w


def unbalance_response(rotor, node, unbalance, phase, speeds, probe_nodes=None):
    """Steady response to a rotating unbalance `unbalance` (kg m) at `node` and
    `phase` (rad), at spin speeds `speeds` (rad/s, vmapped): complex amplitudes of
    `x` and `y` at `probe_nodes` (default: all nodes), `x = Re(X e^{i Omega t})`.

    The force is `F = unbalance Omega^2 (cos(Omega t + phase), sin(Omega t + phase))`,
    so `F_x = U Omega^2 e^{i phase}` and `F_y = -i F_x`; the response solves
    `(K - Omega^2 M + i Omega (C + Omega G1)) Q = F`. (For a `RotorScene` with its
    `Unbalance` components: `rotorjax.analysis.scene_unbalance_response`.)
    """
    _check_rotor(rotor, scenes=False)
    node = check_node("node", node, rotor.n_nodes, "unbalance")
    if probe_nodes is None:
        probe = np.arange(rotor.n_nodes)
    else:
        probe_nodes = np.atleast_1d(as_numpy("probe_nodes", probe_nodes))
        if probe_nodes.ndim != 1 or probe_nodes.size < 1:
            raise InputError(f"probe_nodes must be a node or a 1-D list of >= 1 nodes, got shape "
                             f"{probe_nodes.shape}")
        probe = np.array([check_node(f"probe_nodes[{i}]", p, rotor.n_nodes, "probe")
                          for i, p in enumerate(probe_nodes)], dtype=int)
    for name, v in (("unbalance", unbalance), ("phase", phase)):
        if is_concrete(v):
            as_param(name, v, shape=())
    if is_concrete(speeds):
        as_numpy("speeds", speeds, ndim=1)
    mats = rotor.reduced_matrices()
    f = rotor.free_dofs
    b = DOFS_PER_NODE * node
    if b not in f or b + 1 not in f:
        raise InputError(f"node: the unbalance node {node} has fixed translation dofs")
    pos = {dof: i for i, dof in enumerate(f)}
    ix, iy = pos[b], pos[b + 1]

    unit = rotor.project(jnp.zeros(len(f), dtype=jnp.complex128).at[ix].set(1.0).at[iy].set(-1j))

    def one(w):
        F = unbalance * w**2 * jnp.exp(1j * phase) * unit
        # bearing coefficients at each speed (tabulated bearings)
        M, C, G1, K = rotor.reduced_matrices(w) if getattr(rotor, "speed_dependent", False) else mats
        Q = frequency_response(M, C + w * G1, K, F, w)
        full = rotor.expand(Q)
        return full[DOFS_PER_NODE * probe], full[DOFS_PER_NODE * probe + 1]

    return jax.vmap(one)(jnp.asarray(speeds, dtype=jnp.float64))


def _asymmetry(a):
    a = np.asarray(a)
    return np.linalg.norm(a - a.T) / max(np.linalg.norm(a), 1e-300)


def synchronous_critical_speeds(rotor, n_speeds=None):
    """Undamped critical speeds as the roots of the synchronous determinant
    `det(K - Omega^2 M + i Omega^2 G1) = 0` (a harmonic solution `e^{i Omega t}` at
    the spin speed: every Campbell branch, forward and backward, meeting 1x).

    `i G1` is Hermitian (G1 real skew), so this is the Hermitian pencil
    `(M - i G1) u = mu K u` with `mu = 1 / Omega^2`: one `eigh`, no scan, exact,
    differentiable and vmappable. Modes with `mu <= 0` (gyroscopic stiffening
    outruns the inertia: the branch never meets 1x) have no critical speed.
    Returns the speeds (rad/s) ascending, `inf` where there is none; `n_speeds`
    keeps the first ones. Requires an undamped rotor with symmetric stiffness
    (damping moves the roots off the real axis: use `critical_speeds_1x`).
    """
    n = _check_rotor(rotor, scenes=False)
    if n_speeds is not None:
        n_speeds = as_count("n_speeds", n_speeds, minimum=1, maximum=n)
    if getattr(rotor, "speed_dependent", False):
        raise InputError("synchronous_critical_speeds needs bearings that do not depend on speed; "
                         "use critical_speeds_1x with tabulated bearings")
    M, C, G1, K = rotor.reduced_matrices()
    if not isinstance(C, jax.core.Tracer) and np.any(np.asarray(C) != 0):
        raise InputError("synchronous_critical_speeds needs an undamped rotor (C = 0); "
                         "use critical_speeds_1x with damping")
    if not isinstance(K, jax.core.Tracer) and _asymmetry(K) > 1e-9:
        raise InputError("synchronous_critical_speeds needs a symmetric stiffness (no kxy != kyx)")
    L = jnp.linalg.cholesky(0.5 * (K + K.T))
    Linv = jax.scipy.linalg.solve_triangular(L, jnp.eye(K.shape[0]), lower=True)
    H = Linv @ (M - 1j * G1) @ Linv.T
    mu = jnp.linalg.eigvalsh(0.5 * (H + H.conj().T))
    speeds = jnp.sort(jnp.where(mu > 0, 1 / jnp.sqrt(jnp.where(mu > 0, mu, 1.0)), jnp.inf))
    return speeds if n_speeds is None else speeds[:n_speeds]
