"""Linear analyses of a `FlexibleRotor` (or a `RotorScene`'s linear part): damped modes, Campbell diagram, critical
speeds, unbalance response, logarithmic decrements. All pure, differentiable with
respect to the rotor's parameters, and vmappable over speeds or designs."""

import equinox as eqx
import jax
import jax.numpy as jnp
import numpy as np

from ..models._validate import (InputError, as_count, as_numpy, as_param, check_choice, check_node,
                               check_span, is_concrete)
from ._roots import bisect_batched, frozen_tree, secant_root, sign_changes
from ..models._fe_rotor import DOFS_PER_NODE
from ..models._contract import AbstractShaftModel, require
from ..models._frequency import frequency_response


def _check_rotor(rotor, needed_by="a finite-element analysis", capability="shaft"):
    """The number of coordinates of a shaft model (`FlexibleRotor`, `ReducedRotor`,
    or a `RotorScene`: its linear part, components' linearisations included), or with
    `capability="linear_system"` of any linear system (a linear scene); anything
    else is refused with `MissingCapability`."""
    require(rotor, capability, needed_by)
    return rotor.n_coordinates


def _check_n_modes(name, n_modes, rotor, allow_none=True, bounded=False, needed_by="a finite-element analysis",
                   capability="shaft"):
    """`n_modes` >= 1; `bounded`: also at most the rotor's number of coordinates
    (where the modes are indexed; elsewhere a larger count keeps them all)."""
    n = _check_rotor(rotor, needed_by, capability)
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
    """ROSS's whirl values (0, 0.5, 1) as labels (NaN, a system without nodes: "undefined")."""
    v = np.asarray(whirl_value)
    return np.where(np.isnan(v), "undefined",
                    np.where(v == 0.0, "forward", np.where(v == 1.0, "backward", "mixed")))


def _whirl_value(x, y):
    """ROSS's node-by-node whirl classification (see `Modes`) of shapes `x`, `y`
    (nodes x modes)."""
    a = jnp.abs(x) ** 2 + jnp.abs(y) ** 2
    s = jnp.imag(jnp.conj(x) * y)
    counted = (a > 1e-12 * jnp.max(a, axis=0, keepdims=True)) & (jnp.abs(s) > 1e-9 * a)
    any_fwd = jnp.any(counted & (s < 0), axis=0)
    any_bwd = jnp.any(counted & (s > 0), axis=0)
    return jnp.where(any_fwd & ~any_bwd, 0.0, jnp.where(any_bwd & ~any_fwd, 1.0, 0.5))


@jax.custom_jvp
def eigenvalues(a):
    """The eigenvalues of the real square matrix `a` (`jnp.linalg.eigvals`), with
    their derivative from the left and right eigenvectors, `d lambda_i = u_i^H dA v_i /
    (u_i^H v_i)` (first order, simple eigenvalues). JAX's own rule inverts the
    complex eigenvector matrix, slow on CPU: the value and gradient of `log_dec_floor`
    on ROSS's example rotor took 1.1 s with it, 45 ms with this rule (2 cores). The
    rule is linear in `dA`, so reverse mode transposes it."""
    return jnp.linalg.eigvals(a)


@eigenvalues.defjvp
def _eigenvalues_jvp(primals, tangents):
    (a,), (da,) = primals, tangents
    lam, u, v = jax.lax.linalg.eig(a, compute_left_eigenvectors=True, compute_right_eigenvectors=True)
    u = jnp.conj(u)
    return lam, jnp.einsum("ji,jk,ki->i", u, da.astype(lam.dtype), v) / jnp.einsum("ji,ji->i", u, v)


def state_matrix(rotor, speed):
    """First-order matrix of the linear system's `M q'' + (C + G) q' + K q = 0` at
    `speed` (rad/s): its `linear_matrices(speed)` (a `RotorScene`'s components'
    linearisations included)."""
    return rotor.linear_matrices(speed).state_matrix()


def modes(rotor, speed, n_modes=None) -> Modes:
    """Damped eigen-analysis at spin speed `speed` (rad/s) of any linear system: a
    finite-element rotor (shapes on all its dofs, whirl from its nodes' orbits) or
    any other linear scene (shapes on its coordinates; whirl undefined: `whirl_value`
    NaN, `forward` False)."""
    n_modes = _check_n_modes("n_modes", n_modes, rotor, needed_by="modes", capability="linear_system")
    _check_speed("speed", speed)
    return _modes(rotor, jnp.asarray(speed, dtype=jnp.float64), n_modes)


@eqx.filter_jit
def _modes(rotor, speed, n_modes):
    """`modes`, compiled once per rotor layout and number of modes."""
    m = rotor.linear_matrices(speed)
    a = m.state_matrix()
    lam, vec = jnp.linalg.eig(a)
    lam = on_axis(lam, conservative(m))
    n = a.shape[0] // 2
    # keep the upper half-plane (one of each conjugate pair), sorted by frequency
    key = jnp.where(jnp.imag(lam) > 0, jnp.imag(lam), jnp.inf)
    order = jnp.argsort(key)[:n]
    lam, vec = lam[order], vec[:n, order]
    if n_modes is not None:
        lam, vec = lam[:n_modes], vec[:, :n_modes]
    freq = jnp.abs(jnp.imag(lam))
    wn = jnp.abs(lam)
    if not isinstance(rotor, AbstractShaftModel):   # no nodes: no orbits to classify
        nan = jnp.full(lam.shape, jnp.nan)
        return Modes(eigenvalues=lam, frequencies=freq, log_dec=log_decrement(lam),
                     forward=jnp.zeros(lam.shape, bool), shapes=vec, natural_frequencies=wn,
                     damping_ratio=0.0 - jnp.real(lam) / wn, whirl_value=nan)
    full = rotor.expand(vec)
    shaft = full[: DOFS_PER_NODE * rotor.n_nodes]   # shaft nodes (not supports' pedestals)
    x = shaft[0::DOFS_PER_NODE]
    y = shaft[1::DOFS_PER_NODE]
    fwd = jnp.abs(x + 1j * y)   # forward-whirl amplitude per node (for Im lambda > 0)
    bwd = jnp.abs(x - 1j * y)
    forward = jnp.sum(fwd**2, axis=0) >= jnp.sum(bwd**2, axis=0)
    return Modes(eigenvalues=lam, frequencies=freq, log_dec=log_decrement(lam),
                 forward=forward, shapes=full, natural_frequencies=wn, damping_ratio=0.0 - jnp.real(lam) / wn,
                 whirl_value=_whirl_value(x, y))


def conservative(m):
    """Whether the linear equations `m` (`LinearMatrices`) conserve energy about a
    stable equilibrium: no damping (`C = 0`), `G` skew, `M` and `K` symmetric (exactly,
    as assembled: a cross-coupled bearing's `kxy != kyx` is circulatory, not
    conservative) and `K` positive definite (its Cholesky factor finite). Every
    eigenvalue then lies on the imaginary axis (gyroscopic forces do no work, so the
    energy `q'^T M q' + q^T K q` is constant: Kelvin-Tait-Chetaev), and the real parts
    an eigenvalue solver returns are rounding of either sign (about 1e-13 of the
    frequency on ROSS's example rotor), which a log decrement, an amplification factor
    or a probability of instability would read as physics. Traceable."""
    exact = jnp.all(m.C == 0) & jnp.all(m.G == -m.G.T) & jnp.all(m.M == m.M.T) & jnp.all(m.K == m.K.T)
    return exact & jnp.all(jnp.isfinite(jnp.linalg.cholesky(m.K)))


def on_axis(lam, flag):
    """The eigenvalues `lam` with their real parts exactly 0 where `flag` (a conservative
    system's, `conservative`), their derivatives kept (a damping coefficient at 0 still
    has its first-order effect)."""
    return jnp.where(flag, lam - jax.lax.stop_gradient(jnp.real(lam)), lam)


def system_eigenvalues(system, speed):
    """Every eigenvalue of the linear system's first-order matrix at `speed` (`eigenvalues`:
    differentiable), with real parts exactly 0 where the system is `conservative`."""
    m = system.linear_matrices(speed)
    return on_axis(eigenvalues(m.state_matrix()), conservative(m))


def log_decrement(lam):
    """The logarithmic decrement `-2 pi Re lambda / |Im lambda|` of the eigenvalues
    `lam` (0, not -0, on the imaginary axis)."""
    return 2 * jnp.pi * (0.0 - jnp.real(lam)) / jnp.abs(jnp.imag(lam))


def damped_eigenvalues(rotor, speed, n_modes=None):
    """The eigenvalues of the damped modes at `speed` (one of each conjugate pair, the
    upper half-plane), sorted by frequency, from the eigenvalues only: differentiable
    with respect to the rotor's parameters and the speed (unlike `modes`, whose
    eigenvectors JAX does not differentiate). Log decrements are
    `-2 pi Re lambda / Im lambda`; a conservative system's real parts are exactly 0
    (`conservative`)."""
    n_modes = _check_n_modes("n_modes", n_modes, rotor, needed_by="damped_eigenvalues", capability="linear_system")
    _check_speed("speed", speed)
    lam = system_eigenvalues(rotor, jnp.asarray(speed, dtype=jnp.float64))
    order = jnp.argsort(jnp.where(jnp.imag(lam) > 0, jnp.imag(lam), jnp.inf))[: lam.shape[0] // 2]
    return lam[order] if n_modes is None else lam[order[:n_modes]]


def damped_frequencies(rotor, speed, n_modes=None):
    """Damped natural frequencies (rad/s) at `speed`, sorted, from the eigenvalues
    only: differentiable with respect to the rotor's parameters and the speed."""
    n_modes = _check_n_modes("n_modes", n_modes, rotor, needed_by="damped_frequencies", capability="linear_system")
    _check_speed("speed", speed)
    lam = eigenvalues(state_matrix(rotor, jnp.asarray(speed, dtype=jnp.float64)))
    f = jnp.sort(jnp.where(jnp.imag(lam) > 0, jnp.imag(lam), jnp.inf))[: lam.shape[0] // 2]
    return f if n_modes is None else f[:n_modes]


def least_stable_whirl(system, speed, dofs):
    """The eigenvalue of largest real part of any linear system at `speed` (of a
    conjugate pair, the member with `Im >= 0`) and whether its mode whirls forward
    (in the spin's direction) at the coordinates `dofs = (x, y)` (the positions in
    `q` of one point's two translations, e.g. a disk's): `(eigenvalue, forward)`.
    Traceable in the speed and the system's parameters (not in `dofs`)."""
    n = _check_rotor(system, "least_stable_whirl", "linear_system")
    d = np.asarray(dofs) if is_concrete(dofs) else None
    if (d is None or d.shape != (2,) or not np.issubdtype(d.dtype, np.integer)
            or np.any(d < 0) or np.any(d >= n)):
        raise InputError(f"dofs must be two coordinate indices (x, y) in 0..{n - 1}, got {dofs!r}")
    _check_speed("speed", speed)
    lam, vec = jnp.linalg.eig(state_matrix(system, jnp.asarray(speed, dtype=jnp.float64)))
    k = jnp.argmax(jnp.real(lam) + 1e-9 * jnp.sign(jnp.imag(lam)))  # of a pair, the Im > 0 member
    x, y = vec[int(d[0]), k], vec[int(d[1]), k]
    fwd = jnp.abs(x + 1j * y) >= jnp.abs(x - 1j * y)   # for Im lambda > 0; reversed below it
    return lam[k], jnp.where(jnp.imag(lam[k]) >= 0, fwd, ~fwd)


def campbell(rotor, speeds, n_modes=8):
    """Damped natural frequencies and whirl directions over `speeds` (vmapped)."""
    n_modes = _check_n_modes("n_modes", n_modes, rotor, needed_by="campbell", capability="linear_system")
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
    n_modes = _check_n_modes("n_modes", n_modes, rotor, allow_none=False, bounded=True,
                             needed_by="critical_speeds_1x")
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


def critical_speed(rotor, k, guess, iters=6, pair=None):
    """The speed where the `k`-th damped natural frequency (sorted, all whirl
    directions) equals the speed, near `guess`: the root of `g(Omega) = omega_k(Omega)
    - Omega`, and the residual `g` there (to check it). Pure JAX, vmappable over
    designs; its derivative with respect to the rotor's parameters is the implicit
    function theorem's.

    - Without `pair`: by `secant_root` (`iters` evaluations of `g`, eigenvalues only;
      the first step a fixed-point step, `g' = d omega / d Omega - 1 ~ -1`).
    - With `pair = (lam, u)` (`critical_pair`: a nearby rotor's eigenvalue and mode
      shape at `guess`, e.g. the nominal design's): `iters` Newton steps on the
      quadratic eigenproblem and the speed together (`_eigenpair_newton`: linear
      solves, no eigenvalue problem), then one evaluation of `g` at the speed found,
      which is the residual: the speed is this rotor's `k`-th frequency's fixed point
      only where it is small. Near a close pair the followed mode can change rank
      among the sorted frequencies (the nominal's `k`-th becoming the sample's
      `k-1`-th), or converge slowly: the residual is then large, and the caller asks
      the secant path.
    """
    n = _check_rotor(rotor, "critical_speed", "linear_system")
    k = as_count("k (mode index)", k, minimum=0, maximum=n - 1)
    iters = as_count("iters", iters, minimum=2 if pair is None else 1)
    _check_speed("guess", guess)
    g = lambda r, w: damped_frequencies(r, w, k + 1)[k] - w  # noqa: E731
    if pair is None:
        return secant_root(g, rotor, guess, iters, slope0=-1.0)
    w, slope = _eigenpair_newton(frozen_tree(rotor), guess, pair, iters)
    g1 = g(rotor, w)
    return w - g1 / slope, g1


def critical_pair(rotor, k, speed):
    """`(lam, u)`: the `k`-th damped mode (sorted by frequency, upper half-plane) of
    the linear system `rotor` at `speed`, its shape `u` in the system's coordinates
    (`q`) of unit norm; the start of `critical_speed(..., pair=)` for designs near
    this one (concrete: numpy)."""
    lam, vec = np.linalg.eig(np.asarray(state_matrix(rotor, jnp.float64(speed))))
    up = np.flatnonzero(lam.imag > 0)
    i = up[np.argsort(lam.imag[up])][as_count("k (mode index)", k, minimum=0, maximum=up.size - 1)]
    u = vec[: vec.shape[0] // 2, i]
    return complex(lam[i]), u / np.linalg.norm(u)


def _eigenpair_newton(rotor, speed, pair, iters):
    """`iters` Newton steps on the quadratic eigenproblem `T(lam, Omega) u = (lam^2 M +
    lam (C + G) + K) u = 0`, `c^H u = 1` (`c` the start shape), `Im lam = Omega`, from
    `pair` at `speed`: each step one complex bordered solve of the coordinates' size
    plus one (not the first-order matrix's twice that) with two right-hand sides, its
    second column the speed's direction (`dT/dOmega u`, from one JVP of the linear
    matrices), from which the step in `Omega` that keeps `Im lam = Omega` follows.
    Returns `(Omega, dg/dOmega)`, the slope of `g = Im lam(Omega) - Omega` at the last
    iterate (for the implicit function theorem), both without derivatives."""
    lam, u = jnp.asarray(pair[0], dtype=jnp.complex128), jnp.asarray(pair[1], dtype=jnp.complex128)
    c, n, w = jnp.conj(u), u.shape[0], jnp.float64(speed)
    slope = jnp.float64(-1.0)
    for _ in range(iters):
        m, dm = jax.jvp(rotor.linear_matrices, (w,), (jnp.float64(1.0),))
        t = lam**2 * m.M + lam * (m.C + m.G) + m.K
        t_lam, t_w = 2 * lam * m.M + m.C + m.G, lam**2 * dm.M + lam * (dm.C + dm.G) + dm.K
        border = jnp.zeros((n + 1, n + 1), jnp.complex128)
        border = border.at[:n, :n].set(t).at[:n, n].set(t_lam @ u).at[n, :n].set(c)
        rhs = jnp.stack([jnp.append(-(t @ u), 1.0 - c @ u), jnp.append(-(t_w @ u), 0.0)], axis=1)
        s = jnp.linalg.solve(border, rhs)
        slope = jnp.imag(s[n, 1]) - 1.0
        dw = (w - jnp.imag(lam + s[n, 0])) / slope
        u, lam, w = u + s[:n, 0] + dw * s[:n, 1], lam + s[n, 0] + dw * s[n, 1], w + dw
    return jax.lax.stop_gradient(w), jax.lax.stop_gradient(slope)


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
    n = _check_rotor(rotor, "synchronous_critical_speeds")
    if n_speeds is not None:
        n_speeds = as_count("n_speeds", n_speeds, minimum=1, maximum=n)
    if rotor.speed_dependent:
        raise InputError("synchronous_critical_speeds needs bearings that do not depend on speed; "
                         "use critical_speeds_1x with tabulated bearings")
    lm = rotor.linear_matrices(0.0)   # a RotorScene: its components' linearisations included
    M, C, K = lm.M, lm.C, lm.K
    G1 = rotor.linear_matrices(1.0).G
    if not isinstance(K, jax.core.Tracer) and not np.allclose(np.asarray(rotor.linear_matrices(1.0).K),
                                                              np.asarray(K), rtol=1e-12, atol=0.0):
        raise InputError("synchronous_critical_speeds needs a stiffness independent of speed (no internal "
                         "damping's circulatory terms); use critical_speeds_1x")
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


class CampbellCriticalSpeed(eqx.Module):
    """One 1x crossing of a Campbell diagram: `speed` (rad/s), the branch `mode`
    (sorted by frequency) and its whirl, `"forward"` or `"backward"`."""

    speed: float = eqx.field(static=True)
    mode: int = eqx.field(static=True)
    whirl: str = eqx.field(static=True)

    def as_dict(self) -> dict:
        return {"speed": self.speed, "mode": self.mode, "whirl": self.whirl}


class CampbellCriticalSpeeds(eqx.Module):
    """What `campbell_critical_speeds` returns: the crossings (`critical_speeds`),
    the roots of the synchronous determinant in the range where they apply (an
    undamped rotor with symmetric, speed-independent stiffness; else None), and the
    scan's Campbell diagram (`speeds`, `frequencies`, `forward`) to draw."""

    critical_speeds: tuple
    synchronous_determinant_roots: tuple | None
    speeds: np.ndarray
    frequencies: np.ndarray
    forward: np.ndarray

    def as_dict(self) -> dict:
        """The crossings (and the determinant's roots where they apply) as JSON."""
        out = {"unit": "rad/s", "critical_speeds": [c.as_dict() for c in self.critical_speeds]}
        if self.synchronous_determinant_roots is not None:
            out["synchronous_determinant_roots"] = list(self.synchronous_determinant_roots)
        return out


def campbell_critical_speeds(rotor, lo, hi, n_scan=200, n_modes=8, what="the rotor") -> CampbellCriticalSpeeds:
    """The critical speeds of a shaft model in `[lo, hi]` (rad/s) as its Campbell
    diagram shows them: the 1x crossings of its first `n_modes` damped natural
    frequencies (`critical_speeds_1x`), each with its whirl direction, and for an
    undamped rotor with symmetric stiffness the roots of the synchronous determinant
    (`synchronous_critical_speeds`) too. A rotor with rigid-body modes is refused
    (`check_supported`, `what` names it). (The speeds where a reference motion's
    stability changes are `rotorjax.analysis.critical_speeds` of its margin.)"""
    from ..models import check_speeds
    from ._frf import check_supported

    n = 2 * _check_rotor(rotor, "campbell_critical_speeds")
    check_supported(rotor, hi, what=what)
    check_speeds(rotor, [lo, hi])
    if n_modes > n:
        raise InputError(f"--modes {n_modes}: the rotor has {n} modes")
    found, (speeds, camp) = critical_speeds_1x(rotor, lo, hi, n_scan=n_scan, n_modes=n_modes, return_scan=True)
    fwd = [bool(modes(rotor, s, n_modes).forward[k]) for s, k in found]
    crossings = tuple(CampbellCriticalSpeed(s, k, "forward" if f else "backward") for (s, k), f in zip(found, fwd))
    lm0, lm1 = rotor.linear_matrices(0.0), rotor.linear_matrices(1.0)   # a scene's components count
    C, K = np.asarray(lm0.C), np.asarray(lm0.K)
    roots = None
    if (not rotor.speed_dependent and not np.any(C) and np.array_equal(K, np.asarray(lm1.K))
            and np.allclose(K, K.T, rtol=1e-12, atol=1e-12 * np.abs(K).max())):
        roots = tuple(float(r) for r in np.asarray(synchronous_critical_speeds(rotor)) if lo <= r <= hi)
    return CampbellCriticalSpeeds(crossings, roots, np.asarray(speeds), np.asarray(camp.frequencies),
                                  np.asarray(camp.forward))
