"""Undamped critical speed (UCS) map: the rotor's critical speeds against the
bearing stiffness, every bearing replaced by an isotropic spring `k` to ground
(no damping, no cross-coupling, no bearing mass; supports' pedestals dropped, as
ROSS's `Rotor.run_ucs` does), and where the real bearings' `kxx(W)`, `kyy(W)`
curves cross it.

ROSS's definition (`run_ucs`, ROSS 2.3.0): at each `k` the undamped natural
frequencies at speed 0 (`synchronous=False`), each pair of equal x- and
y-plane frequencies counted once (its `wn[::2]`), or with `synchronous=True` the
forward synchronous critical speeds (Rouch and Kao 1980: the disk and shaft
inertia `It - Ip`, a harmonic `e^{i W t}` at the spin speed with forward circular
whirl). Both are computed here on the forward-whirl subspace
(`y = -i x`, `sy = -i sx` at every node, invariant for an axisymmetric rotor on
isotropic springs) as the Hermitian pencil

    K_f u = W^2 (M_f - i G1_f) u      (synchronous; M_f u = ... without G1 at speed 0),

one `eigh` per `k`, vmapped over `k` in one compiled call. An intersection solves
`W = omega_j(k_b(W))` for a bearing's coefficient `k_b` (`kxx`, and `kyy` where it
differs) with the shared root finder (`rotorjax.analysis._roots.find_roots`) on
the exact map, not on an interpolation of the sampled one.
"""

import dataclasses

import equinox as eqx
import jax
import jax.numpy as jnp
import numpy as np

from ._roots import find_roots
from ..models._fe_rotor import DOFS_PER_NODE
from ..models._validate import InputError, as_count, check_span, is_concrete
from ..sweep import map_chunked
from ._frf import full_rotor


@dataclasses.dataclass(frozen=True)
class Intersection:
    """A critical speed on the real bearings: mode `mode` of the map meets
    bearing `bearing`'s `coefficient` ("kxx" or "kyy") at `speed` (rad/s) and
    stiffness `k` (N/m); `residual` `|omega_mode(k) - speed|`."""

    speed: float
    k: float
    mode: int
    bearing: int
    coefficient: str
    residual: float


class UCS(eqx.Module):
    """An undamped critical speed map.

    - `stiffness` (n_k,) N/m, log-spaced; `frequencies` (n_k, n_modes) rad/s (inf
      where a synchronous branch never meets 1x).
    - `bearing_speeds` (n_s,) rad/s and `bearing_k` (n_bearings, 2, n_s): each
      bearing's `kxx`, `kyy` at those speeds (the overlay).
    - `intersections`: the `Intersection`s, by speed.
    """

    stiffness: jax.Array
    frequencies: jax.Array
    bearing_speeds: jax.Array
    bearing_k: jax.Array
    synchronous: bool = eqx.field(static=True)
    intersections: tuple = eqx.field(static=True)


def bearing_stiffness(rotor, speed):
    """`(n_bearings, 2)`: every bearing's `kxx`, `kyy` at `speed` (rad/s)."""
    return rotor.bearing_coefficients(speed)[:, :2]


def _bare_matrices(rotor):
    """`(M, G1, K, B)` on the shaft's free dofs without any bearing (nor supports),
    and `B` the pattern of an isotropic unit spring at every bearing node."""
    # exact for bearings held in `bearing_params`; the rest (tables) is subtracted below
    zero = eqx.tree_at(lambda r: r.bearing_params, rotor, jnp.zeros_like(rotor.bearing_params))
    M, _, G1, K = zero.matrices(0.0)
    left = zero.bearing_coefficients(0.0)  # tables not held in bearing_params
    n = DOFS_PER_NODE * rotor.n_nodes
    M, G1, K = M[:n, :n], G1[:n, :n], K[:n, :n]
    B = jnp.zeros((n, n))
    for i, node in enumerate(rotor.bearing_nodes):
        b = DOFS_PER_NODE * node
        B = B.at[b, b].add(1.0).at[b + 1, b + 1].add(1.0)
        kxx, kyy, kxy, kyx = (left[i, j] for j in range(4))
        mxx, myy, mxy, myx = (left[i, j] for j in range(8, 12))
        K = K.at[b, b].add(-kxx).at[b + 1, b + 1].add(-kyy).at[b, b + 1].add(-kxy).at[b + 1, b].add(-kyx)
        M = M.at[b, b].add(-mxx).at[b + 1, b + 1].add(-myy).at[b, b + 1].add(-mxy).at[b + 1, b].add(-myx)
    free = np.asarray([d for d in np.asarray(rotor.free_dofs) if d < n], dtype=int)
    ix = np.ix_(free, free)
    return M[ix], G1[ix], K[ix], B[ix], free


def _forward_basis(free):
    """Columns spanning forward circular whirl on the free dofs: `(e_x - i e_y) / sqrt 2`
    and `(e_sx - i e_sy) / sqrt 2` per node."""
    pos = {int(d): i for i, d in enumerate(free)}
    cols = []
    for d in free:
        d = int(d)
        if d % 2 == 0:
            if (d + 1 in pos) != True:  # noqa: E712
                raise InputError(f"ucs: dof {d % DOFS_PER_NODE} of node {d // DOFS_PER_NODE} is fixed but not its "
                                 "partner: the UCS map needs an axisymmetric rotor (fix x and y, sx and sy together)")
            c = np.zeros(len(free), dtype=complex)
            c[pos[d]], c[pos[d + 1]] = 1 / np.sqrt(2), -1j / np.sqrt(2)
            cols.append(c)
        elif d - 1 not in pos:
            raise InputError(f"ucs: dof {d % DOFS_PER_NODE} of node {d // DOFS_PER_NODE} is fixed but not its "
                             "partner: the UCS map needs an axisymmetric rotor (fix x and y, sx and sy together)")
    return jnp.asarray(np.stack(cols, axis=1))


def _map_function(rotor, n_modes, synchronous):
    """`omega(k)`: the first `n_modes` critical speeds (rad/s) at isotropic bearing
    stiffness `k`, pure JAX (vmap it over `k`)."""
    M, G1, K, B, free = _bare_matrices(rotor)
    T = _forward_basis(free)
    Th = T.conj().T
    Mf = Th @ (M - 1j * G1 if synchronous else M + 0j) @ T
    Kf, Bf = Th @ K @ T, Th @ B @ T
    if is_concrete((M, K)):
        # the forward subspace must be invariant (an axisymmetric rotor: no x/y asymmetry)
        for name, a in (("mass", M), ("stiffness", K)):
            a = np.asarray(a)
            t = np.asarray(T)
            r = a @ t - t @ (t.conj().T @ a @ t)
            if np.linalg.norm(r) > 1e-9 * max(np.linalg.norm(a), 1e-300):
                raise InputError(f"ucs: the rotor's {name} differs between x and y (e.g. a point mass with mx != "
                                 "my): the UCS map needs an axisymmetric rotor")
    n_f = Kf.shape[0]
    if n_modes > n_f:
        raise InputError(f"n_modes must be at most {n_f} (the rotor's forward modes), got {n_modes}")

    def omega(k):
        A = Kf + k * Bf
        L = jnp.linalg.cholesky(0.5 * (A + A.conj().T))
        Linv = jax.scipy.linalg.solve_triangular(L, jnp.eye(n_f, dtype=A.dtype), lower=True)
        H = Linv @ Mf @ Linv.conj().T
        mu = jnp.linalg.eigvalsh(0.5 * (H + H.conj().T))
        w = jnp.sort(jnp.where(mu > 0, 1 / jnp.sqrt(jnp.where(mu > 0, mu, 1.0)), jnp.inf))
        return w[:n_modes]

    return omega


def ucs_frequencies(rotor, stiffness, n_modes=4, synchronous=False):
    """The map's values at the stiffnesses `stiffness` (N/m, any shape; vmapped):
    shape `stiffness.shape + (n_modes,)`."""
    rotor = full_rotor(rotor).full_rotor  # a ReducedRotor: its basis depends on the bearings
    n_modes = as_count("n_modes", n_modes, minimum=1)
    f = _map_function(rotor, n_modes, bool(synchronous))
    k = jnp.asarray(stiffness, dtype=jnp.float64)
    return jax.vmap(f)(k.reshape(-1)).reshape(k.shape + (n_modes,))


def ucs(rotor, stiffness_range=(1e5, 1e10), n_stiffness=60, n_modes=4, synchronous=False, speed_range=None,
        n_scan=200, xtol=1e-9) -> UCS:
    """Undamped critical speed map (see the module docstring).

    **Arguments:**
    - `rotor`: a `FlexibleRotor` (a `RotorScene`: its rotor; a `ReducedRotor`: its
      full rotor).
    - `stiffness_range`: `(lo, hi)` N/m, `0 < lo < hi`; `n_stiffness` log-spaced values.
      (ROSS's `stiffness_range` holds the exponents: ROSS `(6, 11)` is `(1e6, 1e11)` here.)
    - `n_modes`: critical speeds per stiffness (ROSS plots 4: `num_modes=16`).
    - `synchronous`: False (natural frequencies at speed 0) or True (forward
      synchronous critical speeds).
    - `speed_range`: `(lo, hi)` rad/s where the bearings' curves are drawn and their
      intersections searched (default: the span of the bearings' speed tables, as ROSS
      searches its first bearing's `frequency`; constant bearings: 0 to 1.1 times the
      map's highest finite value);
      `n_scan` samples, bisection to `max(xtol, xtol * speed)`.

    **Returns:** a `UCS`.
    """
    rotor = full_rotor(rotor).full_rotor
    lo, hi = check_span("stiffness_range[0]", stiffness_range[0], "stiffness_range[1]", stiffness_range[1])
    if not lo > 0:
        raise InputError(f"stiffness_range must be positive (a log scale), got ({lo!r}, {hi!r})")
    n_stiffness = as_count("n_stiffness", n_stiffness, minimum=2)
    n_modes = as_count("n_modes", n_modes, minimum=1)
    n_scan = as_count("n_scan", n_scan, minimum=2)
    synchronous = bool(synchronous)
    if not rotor.bearing_nodes:
        raise InputError("ucs: the rotor has no bearings to replace by springs")
    k = np.logspace(np.log10(lo), np.log10(hi), n_stiffness)
    f = _map_function(rotor, n_modes, synchronous)
    fmap = jax.jit(jax.vmap(f))
    freq = map_chunked(fmap, k)   # any number of stiffnesses, in bounded memory
    tables = [t for t in rotor.bearing_tables if t is not None]
    if speed_range is None and tables:  # inside the tables, as ROSS (no extrapolated coefficients)
        s_lo = min(float(np.asarray(t[0])[0]) for t in tables)
        s_hi = max(float(np.asarray(t[0])[-1]) for t in tables)
    elif speed_range is None:
        finite = freq[np.isfinite(freq)]
        s_lo, s_hi = 0.0, 1.1 * (float(finite.max()) if finite.size else 1.0)
    else:
        s_lo, s_hi = check_span("speed_range[0]", speed_range[0], "speed_range[1]", speed_range[1])
        if not s_lo >= 0:
            raise InputError(f"speed_range must be >= 0, got ({s_lo!r}, {s_hi!r})")
    speeds = np.linspace(s_lo, s_hi, n_scan)
    kb = jax.jit(jax.vmap(lambda s: bearing_stiffness(rotor, s)))
    curves = np.moveaxis(np.asarray(kb(jnp.asarray(speeds))), 0, -1)  # (n_b, 2, n_s)
    one = jax.jit(f)
    found = []
    seen = set()
    for b in range(curves.shape[0]):
        for c, coeff in enumerate(("kxx", "kyy")):
            if c == 1 and np.array_equal(curves[b, 1], curves[b, 0]):
                continue
            key = tuple(np.round(curves[b, c], 12))
            if key in seen:  # the same curve as an earlier bearing's: same intersections
                continue
            seen.add(key)
            kw = jax.jit(lambda s, b=b, c=c: bearing_stiffness(rotor, s)[b, c])
            kvals = curves[b, c]
            on_curve = np.asarray(fmap(jnp.asarray(np.where(kvals > 0, kvals, 1.0))))
            for j in range(n_modes):
                def g(s, j=j):
                    kk = float(kw(s))
                    return float(one(kk)[j]) - float(s) if kk > 0 else float("nan")

                vals = np.where(kvals > 0, on_curve[:, j] - speeds, np.nan)
                for r in find_roots(g, s_lo, s_hi, n_scan, values=vals, xtol=xtol, rtol=xtol):
                    kk = float(kw(r.x))
                    found.append(Intersection(r.x, kk, j, b, coeff, abs(float(one(kk)[j]) - r.x)))
    found.sort(key=lambda i: (i.speed, i.bearing, i.coefficient))
    return UCS(jnp.asarray(k), jnp.asarray(freq), jnp.asarray(speeds), jnp.asarray(curves), synchronous,
               tuple(found))
