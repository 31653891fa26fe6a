"""A plain cylindrical fluid-film journal bearing: static equilibrium and the eight
linearised stiffness and damping coefficients against speed.

**Frame.** `x` is horizontal, `y` vertical (up), `z` along the shaft; the journal
rotates counter-clockwise about `+z` at `speed` (rad/s). The static load `W` acts on
the journal along `-y` (gravity: the bearing carries `W`, its film pushes the journal
along `+y`). At equilibrium the journal centre sits at `e (sin phi, -cos phi)` from
the bearing centre: below the centre and, for counter-clockwise rotation, displaced
towards `+x` by the attitude angle `phi` (measured from the load line in the direction
of rotation).

**Coefficients.** About the equilibrium the film force on the journal is
`f = f0 - k q - c dq/dt`, `q = (x, y)`, with `k = [[kxx, kxy], [kyx, kyy]]` (N/m) and
`c = [[cxx, cxy], [cyx, cyy]]` (N s/m), `k_ij = -dF_i/dx_j` — the matrices a rotor
model adds at the bearing's node (`Bearing(node, kxx=..., ...)`).

**Film.** A full (360 deg) plain bore of length `L`, diameter `D = 2 R`, radial
clearance `c`, isoviscous incompressible lubricant of viscosity `mu`, ambient
pressure at both ends, no supply groove, film thickness `h = c - x cos(theta) -
y sin(theta)` (`theta` from `+x`, counter-clockwise); Reynolds' equation

    (1/R^2) d/dtheta(h^3 dp/dtheta) + d/dz(h^3 dp/dz) = 6 mu speed dh/dtheta + 12 mu dh/dt.

- `method="short"` (Ocvirk's short-bearing theory, `L/D -> 0`): the
  `theta`-gradient term is dropped, the pressure is integrated in closed form and
  kept where positive (Gümbel / half-Sommerfeld cavitation). With the Sommerfeld
  number `S = mu N L D / W (R/c)^2` (`N = speed / 2 pi`, rev/s) and the modified
  (Ocvirk) number `S_s = pi S (L/D)^2 = mu speed D L^3 / (8 c^2 W)` the eccentricity
  ratio `eps = e/c` solves

      S_s eps sqrt(pi^2 (1 - eps^2) + 16 eps^2) / (1 - eps^2)^2 = 1,

  the attitude angle is `tan(phi) = pi sqrt(1 - eps^2) / (4 eps)`, and the
  coefficients are `k = (W/c) a(eps)`, `c = (W/(c speed)) b(eps)` with the closed forms
  of Friswell, Penny, Garvey & Lees, *Dynamics of Rotating Machines* (Cambridge UP,
  2010), sec. 5.5 (short bearing; `a_uu ... b_vv` with `u = x`, `v = y`; p. 177 as cited
  by ROSS's `CylindricalBearing`, which uses the same expressions). Pure JAX:
  traceable, differentiable (the eccentricity root carries its implicit-function
  gradient) and vmappable over speeds.
- `method="finite"`: Reynolds' equation in full on a `(theta, z)` grid (conservative
  second-order finite differences, `n_theta` points round the bore, `n_z` intervals
  over the half length, the mid-plane symmetry used), with Swift-Stieber (Reynolds)
  cavitation: `p >= 0` as a linear complementarity problem solved exactly by a
  primal-dual active-set method (`inlet="max-film"` also holds `p = 0` along the
  widest gap, Raimondi & Boyd's convention for the full bearing). The equilibrium
  eccentricity is a bracketed root (Brent) of the load balance — by the bearing's
  rotational symmetry the load magnitude depends on `eps` alone and the attitude
  follows from the force's direction. Of the coefficients, the radial columns are
  five-point central differences of the film force in the journal's radial position
  and velocity; the tangential columns follow exactly from the same symmetry (see
  `_finite_dimensionless`). NumPy/SciPy, not traceable. Converges to the
  short-bearing result as `L/D -> 0` (relative difference ~ `(L/D)^2`) and to second
  order in the mesh away from the cavitation boundary.

The dimensionless coefficients `k c / W` and `c c speed / W` depend on `eps` (and
`L/D` for the finite solution) only.
"""

import equinox as eqx
import jax
import jax.numpy as jnp
import numpy as np

from ._validate import InputError, as_count, as_param, check_choice, is_concrete, show

__all__ = ["JOURNAL_METHODS", "INLETS", "JournalCoefficients", "PlainJournal", "plain_journal",
           "short_bearing_eccentricity", "short_bearing_coefficients", "finite_bearing_state"]

JOURNAL_METHODS = ("short", "finite")
INLETS = ("free", "max-film")
_PI = np.pi


class JournalCoefficients(eqx.Module):
    """A plain journal's static equilibrium and linearised coefficients at each speed
    (see the module docstring for the frame and sign convention).

    **Fields:** (`n` = number of speeds)
    - `speeds`: (n,) rad/s.
    - `eccentricity`: (n,) eccentricity ratio `e / c`.
    - `attitude`: (n,) attitude angle (rad), from the load line (`-y`) towards `+x`.
    - `sommerfeld`: (n,) Sommerfeld number `mu N L D / W (R/c)^2`, `N` in rev/s.
    - `position`: (n, 2) journal-centre displacement from the bearing centre (m),
      `e (sin phi, -cos phi)`.
    - `k`: (n, 2, 2) stiffness `[[kxx, kxy], [kyx, kyy]]` (N/m).
    - `c`: (n, 2, 2) damping `[[cxx, cxy], [cyx, cyy]]` (N s/m).
    - `method`: "short" or "finite" (static).
    """

    speeds: jax.Array
    eccentricity: jax.Array
    attitude: jax.Array
    sommerfeld: jax.Array
    position: jax.Array
    k: jax.Array
    c: jax.Array
    method: str = eqx.field(static=True, default="short")


# --------------------------------------------------------------------------- short bearing
def _load_function(eps):
    """`eps sqrt(pi^2 (1 - eps^2) + 16 eps^2) / (1 - eps^2)^2`: the short bearing's load
    in units of `mu speed R L^3 / (4 c^2)`, increasing from 0 (eps = 0) to inf (eps -> 1)."""
    s = 1.0 - eps ** 2
    return eps * jnp.sqrt(_PI ** 2 * s + 16.0 * eps ** 2) / s ** 2


def short_bearing_eccentricity(modified_sommerfeld, n_bisect: int = 64):
    """Eccentricity ratio of a short (Ocvirk) bearing at the modified Sommerfeld number
    `S_s = mu speed D L^3 / (8 c^2 W)` (scalar; vmap for more): the root in (0, 1) of
    `S_s g(eps) = 1` (module docstring).

    `n_bisect` bisection steps on the bracket [0, 1] (the left side is monotonic, so
    the bracket always holds the single root) then one Newton step on
    `log S_s + log g(eps)` from the (gradient-stopped) bisection point: the step
    polishes the last bits and gives the implicit-function derivative
    `d eps / d S_s = -(1/S_s) / (d log g / d eps)` exactly."""
    ss = jnp.asarray(modified_sommerfeld, dtype=jnp.float64)
    target = jax.lax.stop_gradient(ss)

    def step(_, bracket):
        lo, hi = bracket
        mid = 0.5 * (lo + hi)
        above = target * _load_function(mid) > 1.0
        return jnp.where(above, lo, mid), jnp.where(above, mid, hi)

    lo, hi = jax.lax.fori_loop(0, n_bisect, step, (jnp.zeros_like(target), jnp.ones_like(target)))
    e0 = jax.lax.stop_gradient(0.5 * (lo + hi))
    residual = jnp.log(ss) + jnp.log(_load_function(e0))
    slope = jax.grad(lambda e: jnp.log(_load_function(e)))(e0)
    return e0 - residual / slope


def short_bearing_coefficients(eps):
    """The short bearing's attitude angle and dimensionless coefficients at eccentricity
    ratio `eps` (scalar in (0, 1)): `(phi, a, b)`, `a` = `k c / W`, `b` = `c c speed / W`,
    each (2, 2) `[[xx, xy], [yx, yy]]` in this module's frame. Friswell et al. (2010)
    sec. 5.5 (checked against a numerical integration of the pressure in the tests)."""
    e2 = eps ** 2
    s = 1.0 - e2
    rs = jnp.sqrt(s)
    pi2 = _PI ** 2
    h0 = 1.0 / (pi2 * s + 16.0 * e2) ** 1.5
    auu = h0 * 4.0 * (pi2 * (2.0 - e2) + 16.0 * e2)
    auv = h0 * _PI * (pi2 * s ** 2 - 16.0 * e2 ** 2) / (eps * rs)
    avu = -h0 * _PI * (pi2 * s * (1.0 + 2.0 * e2) + 32.0 * e2 * (1.0 + e2)) / (eps * rs)
    avv = h0 * 4.0 * (pi2 * (1.0 + 2.0 * e2) + 32.0 * e2 * (1.0 + e2) / s)
    buu = h0 * 2.0 * _PI * rs * (pi2 * (1.0 + 2.0 * e2) - 16.0 * e2) / eps
    buv = -h0 * 8.0 * (pi2 * (1.0 + 2.0 * e2) - 16.0 * e2)
    bvv = h0 * 2.0 * _PI * (pi2 * s ** 2 + 48.0 * e2) / (eps * rs)
    phi = jnp.arctan2(_PI * rs, 4.0 * eps)
    a = jnp.array([[auu, auv], [avu, avv]])
    b = jnp.array([[buu, buv], [buv, bvv]])
    return phi, a, b


def _short_point(speed, load, viscosity, length, diameter, clearance):
    """One speed, pure JAX (vmapped by `plain_journal`)."""
    ss = viscosity * speed * diameter * length ** 3 / (8.0 * clearance ** 2 * load)
    eps = short_bearing_eccentricity(ss)
    phi, a, b = short_bearing_coefficients(eps)
    sommerfeld = ss / _PI * (diameter / length) ** 2
    e = eps * clearance
    position = jnp.stack([e * jnp.sin(phi), -e * jnp.cos(phi)])
    return eps, phi, sommerfeld, position, load / clearance * a, load / (clearance * speed) * b


# one compilation per number of speeds, shared by every call (and inlined under an outer jit)
_short_table = jax.jit(jax.vmap(_short_point, in_axes=(0, None, None, None, None, None)))


# -------------------------------------------------------------------------- finite bearing
class _Grid:
    """The (theta, zeta) mesh on half the bearing (`zeta = z / R` in [0, L/D]; the
    mid-plane zeta = 0 is a symmetry plane, zeta = L/D the ambient edge)."""

    def __init__(self, ratio: float, n_theta: int, n_z: int):
        self.ratio, self.n_theta, self.n_z = ratio, n_theta, n_z
        self.dtheta = 2 * _PI / n_theta
        self.dzeta = ratio / n_z
        self.theta = self.dtheta * np.arange(n_theta)
        self.half = self.theta + 0.5 * self.dtheta  # theta_{j+1/2}
        # quadrature weights: periodic rectangle rule in theta, trapezoid in zeta
        # (the edge row, p = 0, is not an unknown)
        wz = np.full(n_z, self.dzeta)
        wz[0] = 0.5 * self.dzeta
        self.weights = (self.dtheta * wz)[None, :] * np.ones((n_theta, 1))
        j = np.arange(n_theta)
        k = np.arange(n_z)
        self.index = j[:, None] * n_z + k[None, :]


def _reynolds_matrix(grid: _Grid, x: float, y: float):
    """The negated discrete Reynolds operator `M` (an M-matrix) and the film
    thickness at nodes and half-nodes, for journal position `(x, y)` in units of `c`."""
    import scipy.sparse as sp

    nt, nz = grid.n_theta, grid.n_z
    h_half = 1.0 - x * np.cos(grid.half) - y * np.sin(grid.half)
    h_node = 1.0 - x * np.cos(grid.theta) - y * np.sin(grid.theta)
    a_plus = h_half ** 3 / grid.dtheta ** 2                 # between j and j+1
    a_minus = np.roll(h_half, 1) ** 3 / grid.dtheta ** 2    # between j-1 and j
    b = h_node ** 3 / grid.dzeta ** 2
    idx = grid.index
    rows, cols, vals = [], [], []

    def add(r, c, v):
        rows.append(r.ravel())
        cols.append(c.ravel())
        vals.append(np.broadcast_to(v, r.shape).ravel())

    ap = np.repeat(a_plus[:, None], nz, axis=1)
    am = np.repeat(a_minus[:, None], nz, axis=1)
    bz = np.repeat(b[:, None], nz, axis=1)
    # z-direction: 2 b at the mid-plane (mirror ghost), b (k-1) + b (k+1) inside,
    # the edge neighbour k = n_z has p = 0
    # the mid-plane row is a half control volume (every entry halved), which keeps M
    # symmetric: the complementarity problem is then a convex quadratic program
    half = np.ones(nz)
    half[0] = 0.5
    add(idx, idx, (ap + am + 2.0 * bz) * half)
    add(idx, np.roll(idx, -1, axis=0), -ap * half)
    add(idx, np.roll(idx, 1, axis=0), -am * half)
    if nz > 1:
        add(idx[:, :-1], idx[:, 1:], -bz[:, :-1])
        add(idx[:, 1:], idx[:, :-1], -bz[:, 1:])
    n = nt * nz
    m = sp.csr_matrix((np.concatenate(vals), (np.concatenate(rows), np.concatenate(cols))), shape=(n, n))
    return m, h_half, h_node


def _rhs(grid: _Grid, h_half, vx: float, vy: float):
    """The right side `dH/dtheta - 2 (vx cos + vy sin)` (conservative difference of H;
    velocities in units of `c speed`), per node, the n_z columns equal."""
    dh = (h_half - np.roll(h_half, 1)) / grid.dtheta
    f = dh - 2.0 * (vx * np.cos(grid.theta) + vy * np.sin(grid.theta))
    out = np.repeat(f[:, None], grid.n_z, axis=1)
    out[:, 0] *= 0.5  # the mid-plane half control volume
    return out.ravel()


def _solve_lcp(m, f, cavitated=None, pinned=None, max_iter: int = 100):
    """`P >= 0`, `w = M P + f >= 0`, `P w = 0` (Swift-Stieber cavitation as the
    obstacle problem of the Reynolds equation `-M P = f`), by the primal-dual
    active-set method (finite and exact for an M-matrix). `cavitated` is a starting
    guess of the set where P = 0; `pinned` nodes are held at P = 0. Returns `(P, cavitated, iterations)`."""
    import scipy.sparse.linalg as spla

    n = f.shape[0]
    if cavitated is None:
        cavitated = f > 0.0  # Gümbel's guess: cavitated where the film diverges
    tol = 1e-12 * (np.max(np.abs(f)) + 1e-300)
    if pinned is not None:
        cavitated = cavitated | pinned
    for it in range(1, max_iter + 1):
        free = ~cavitated
        p = np.zeros(n)
        if free.any():
            p[free] = spla.spsolve(m[free][:, free].tocsc(), -f[free])
        w = m @ p + f  # the multiplier: 0 on the free set, >= 0 where cavitated
        new = np.where(cavitated, w > -tol, p < -tol * 1e-3)
        if pinned is not None:
            new |= pinned
        if np.array_equal(new, cavitated):
            return p, cavitated, it
        if it > 20:  # guard against a cycle: from here on the cavitated set only grows
            new |= cavitated & (w > -tol * 1e3)
        cavitated = new
    raise RuntimeError("the cavitation active set did not settle")  # pragma: no cover


def finite_bearing_state(x, y, vx=0.0, vy=0.0, *, ratio, n_theta=240, n_z=16, inlet="free", cavitated=None):
    """Solve the finite bearing's Reynolds equation (Swift-Stieber cavitation) for the
    journal at `(x, y)` (units of the clearance, `x^2 + y^2 < 1`) moving at
    `(vx, vy)` (units of `clearance * speed`), `ratio` = L/D; `inlet` as in
    `PlainJournal`.

    **Returns:** `(force, pressure, cavitated)`: the dimensionless film force on the
    journal (2,) in units of `12 mu speed R^4 / c^2`, the dimensionless pressure
    `p / (6 mu speed (R/c)^2)` on the half mesh (n_theta, n_z) (theta from +x, zeta =
    z/R from the mid-plane; the edge row is 0), and the active set (for warm starts)."""
    grid = _grid(float(ratio), int(n_theta), int(n_z))
    if cavitated is None and n_theta >= 64 and n_theta % 2 == 0:
        # nested iteration: the active-set method moves the cavitation boundary about a
        # node per iteration, so start from the solution on a mesh half as fine
        _, coarse, _ = finite_bearing_state(x, y, vx, vy, ratio=ratio, n_theta=n_theta // 2, n_z=n_z,
                                            inlet=inlet)
        fine = np.empty((n_theta, n_z))
        fine[0::2] = coarse
        fine[1::2] = 0.5 * (coarse + np.roll(coarse, -1, axis=0))
        cavitated = (fine <= 0.0).ravel()
    m, h_half, _ = _reynolds_matrix(grid, float(x), float(y))
    f = _rhs(grid, h_half, float(vx), float(vy))
    pinned = None
    if inlet == "max-film":  # p = 0 along the (nearest mesh line to the) widest gap
        j = int(np.rint((np.arctan2(-y, -x) % (2 * _PI)) / grid.dtheta)) % grid.n_theta
        pinned = np.zeros((grid.n_theta, grid.n_z), dtype=bool)
        pinned[j] = True
        pinned = pinned.ravel()
    p, cav, _ = _solve_lcp(m, f, cavitated, pinned)
    pm = p.reshape(grid.n_theta, grid.n_z)
    ix = np.sum(grid.weights * pm * np.cos(grid.theta)[:, None])
    iy = np.sum(grid.weights * pm * np.sin(grid.theta)[:, None])
    return -np.array([ix, iy]), pm, cav


_GRIDS: dict = {}


def _grid(ratio, n_theta, n_z):
    key = (ratio, n_theta, n_z)
    if key not in _GRIDS:
        if len(_GRIDS) > 32:
            _GRIDS.clear()
        _GRIDS[key] = _Grid(ratio, n_theta, n_z)
    return _GRIDS[key]


def _finite_dimensionless(eps, ratio, n_theta, n_z, inlet="free", step=None):
    """Attitude angle, dimensionless load `|f|`, and dimensionless `k c / W`,
    `c c speed / W` (global frame) at eccentricity ratio `eps`.

    Solved with the mesh aligned with the line of centres (e along +x). Rotational
    symmetry gives the tangential columns exactly: turning the journal by `a` turns
    the force by `a` (`dF/dt = J F / eps`), and a whirl velocity `v_t` only scales the
    Reynolds right side by `1 - 2 v_t / eps` (the complementarity problem is positively
    homogeneous), so `dF/dv_t = -2 F / eps`. The radial columns are five-point
    differences in `eps` and in the radial velocity, with a step wide enough to
    average the grid-scale kinks of the discrete cavitation boundary."""
    opts = dict(ratio=ratio, n_theta=n_theta, n_z=n_z, inlet=inlet)
    f0, _, cav = finite_bearing_state(eps, 0.0, **opts)
    load = np.hypot(*f0)
    if step is None:
        step = min(0.01, 0.2 * eps, 0.2 * (1.0 - eps))
    coef = np.array([1.0, -8.0, 8.0, -1.0]) / (12.0 * step)
    offsets = np.array([-2.0, -1.0, 1.0, 2.0]) * step
    df_de = sum(w * finite_bearing_state(eps + d, 0.0, cavitated=cav, **opts)[0] for w, d in zip(coef, offsets))
    df_dv = sum(w * finite_bearing_state(eps, 0.0, d, 0.0, cavitated=cav, **opts)[0]
                for w, d in zip(coef, offsets))
    turn = np.array([[0.0, -1.0], [1.0, 0.0]])
    k_local = -np.column_stack([df_de, turn @ f0 / eps]) / load
    c_local = -np.column_stack([df_dv, -2.0 * f0 / eps]) / load
    beta = np.arctan2(f0[1], f0[0])  # the force's direction with e along +x
    phi = _PI - beta                 # the attitude that turns it onto +y
    psi = phi - 0.5 * _PI            # the line of centres' direction at equilibrium
    rot = np.array([[np.cos(psi), -np.sin(psi)], [np.sin(psi), np.cos(psi)]])
    return phi, load, rot @ k_local @ rot.T, rot @ c_local @ rot.T


def _finite_load(eps, ratio, n_theta, n_z, inlet="free", warm=None):
    """|f| at `eps`; `warm` (a one-item list) carries the last active set between calls."""
    cav = None if warm is None else warm[0]
    f, _, cav = finite_bearing_state(eps, 0.0, ratio=ratio, n_theta=n_theta, n_z=n_z, inlet=inlet,
                                     cavitated=cav)
    if warm is not None:
        warm[0] = cav
    return float(np.hypot(*f))


_EPS_RANGE = (1e-6, 0.995)


def _finite(speeds, load, viscosity, length, diameter, clearance, n_theta, n_z, inlet):
    from scipy.optimize import brentq

    ratio = length / diameter
    radius = diameter / 2
    scale = 12.0 * viscosity * radius ** 4 / clearance ** 2  # force per (rad/s) per unit |f|
    lo, hi = _EPS_RANGE
    f_lo = _finite_load(lo, ratio, n_theta, n_z, inlet)
    f_hi = _finite_load(hi, ratio, n_theta, n_z, inlet)
    out = {k: [] for k in ("eps", "phi", "k", "c")}
    for w in speeds:
        target = load / (scale * w)  # the dimensionless load the film must carry
        if not f_lo < target < f_hi:
            # outside what the mesh resolves: marked, not raised for the whole table
            out["eps"].append(np.nan)
            out["phi"].append(np.nan)
            out["k"].append(np.full((2, 2), np.nan))
            out["c"].append(np.full((2, 2), np.nan))
            continue
        warm = [None]
        eps = brentq(lambda e: np.log(_finite_load(e, ratio, n_theta, n_z, inlet, warm) / target), lo, hi,
                     xtol=1e-12, rtol=1e-11)
        phi, _, kbar, cbar = _finite_dimensionless(eps, ratio, n_theta, n_z, inlet)
        out["eps"].append(eps)
        out["phi"].append(phi)
        out["k"].append(load / clearance * kbar)
        out["c"].append(load / (clearance * w) * cbar)
    eps = np.array(out["eps"])
    phi = np.array(out["phi"])
    sommerfeld = viscosity * (speeds / (2 * _PI)) * length * diameter / load * (radius / clearance) ** 2
    e = eps * clearance
    position = np.stack([e * np.sin(phi), -e * np.cos(phi)], axis=-1)
    return JournalCoefficients(jnp.asarray(speeds), jnp.asarray(eps), jnp.asarray(phi),
                               jnp.asarray(sommerfeld), jnp.asarray(position),
                               jnp.asarray(np.array(out["k"])), jnp.asarray(np.array(out["c"])), "finite")


# ---------------------------------------------------------------------------- public API
def _check_geometry(diameter, clearance):
    if is_concrete((diameter, clearance)) and not float(clearance) < float(diameter) / 2:
        raise InputError(f"clearance must be < diameter / 2 (the journal's radius), got clearance = "
                         f"{show(clearance)}, diameter = {show(diameter)}")


def _speeds(speeds):
    if isinstance(speeds, (str, bytes)) or speeds is None:
        raise InputError(f"speeds (rad/s) must be a positive number or a 1-D array of them, got {speeds!r}")
    arr = as_param("speeds (rad/s)", speeds, sign="positive")
    if arr.ndim == 0:
        arr = arr[None]
    if arr.ndim != 1 or arr.shape[0] < 1:
        raise InputError(f"speeds (rad/s) must be a positive number or a 1-D array of >= 1 speeds, "
                         f"got shape {arr.shape}" + (f": {show(speeds)}" if is_concrete(speeds) else ""))
    return arr


class PlainJournal(eqx.Module):
    """A plain cylindrical (360 deg) fluid-film journal bearing carrying a static load
    along `-y` (module docstring: frame, equations, sources).

    **Arguments:**
    - `load`: static load `W` on the bearing (N, > 0), acting on the journal along
      `-y` (gravity).
    - `viscosity`: lubricant dynamic viscosity `mu` (Pa s, > 0).
    - `length`: bearing length `L` (m, > 0).
    - `diameter`: journal diameter `D` (m, > 0).
    - `clearance`: radial clearance `c` (m, > 0, < D/2).
    - `method`: "short" (Ocvirk closed form, JAX) or "finite" (Reynolds' equation on a
      mesh with Swift-Stieber cavitation, NumPy).
    - `n_theta`, `n_z`: the finite mesh, points round the bore (even) and intervals
      over the half length (used by `method="finite"`).
    - `inlet`: where the finite film may start. "free" (default): Swift-Stieber
      complementarity everywhere (`p >= 0`, the film forms and ruptures where the
      problem says). "max-film": besides, `p = 0` along the line of maximum film
      thickness, the full-bearing convention of Raimondi & Boyd (1958).
    """

    load: jax.Array
    viscosity: jax.Array
    length: jax.Array
    diameter: jax.Array
    clearance: jax.Array
    method: str = eqx.field(static=True)
    n_theta: int = eqx.field(static=True)
    n_z: int = eqx.field(static=True)
    inlet: str = eqx.field(static=True)

    def __init__(self, load, viscosity, length, diameter, clearance, method="short", n_theta=240, n_z=16,
                 inlet="free"):
        self.load = as_param("load (N)", load, sign="positive", shape=())
        self.viscosity = as_param("viscosity (Pa s)", viscosity, sign="positive", shape=())
        self.length = as_param("length (m)", length, sign="positive", shape=())
        self.diameter = as_param("diameter (m)", diameter, sign="positive", shape=())
        self.clearance = as_param("clearance (m)", clearance, sign="positive", shape=())
        _check_geometry(self.diameter, self.clearance)
        check_choice("method", method, JOURNAL_METHODS)
        self.method = method
        self.n_theta = as_count("n_theta", n_theta, minimum=8)
        if self.n_theta % 2:
            raise InputError(f"n_theta must be even (the mesh holds the line of centres both ways), got {n_theta}")
        self.n_z = as_count("n_z", n_z, minimum=2)
        check_choice("inlet", inlet, INLETS)
        self.inlet = inlet

    def coefficients(self, speeds) -> JournalCoefficients:
        """Equilibrium and coefficients at `speeds` (rad/s, > 0; a scalar or 1-D)."""
        speeds = _speeds(speeds)
        if self.method == "short":
            eps, phi, somm, pos, k, c = _short_table(speeds, self.load, self.viscosity, self.length,
                                                     self.diameter, self.clearance)
            return JournalCoefficients(speeds, eps, phi, somm, pos, k, c, "short")
        if not is_concrete((speeds, self.load, self.viscosity, self.length, self.diameter, self.clearance)):
            raise InputError('method="finite" computes with NumPy: its inputs must be concrete values, '
                             'not traced ones (use method="short" inside jit/vmap/grad)')
        return _finite(np.asarray(speeds), *(float(v) for v in (self.load, self.viscosity, self.length,
                                                                 self.diameter, self.clearance)),
                       self.n_theta, self.n_z, self.inlet)

    def bearing(self, node, speeds):
        """A speed-dependent linear `Bearing` at shaft node `node` whose eight
        coefficients are tabulated at `speeds` (rad/s, > 0, strictly increasing, >= 2
        values) and interpolated at the running speed by the rotor model."""
        from ._fe_rotor import Bearing  # noqa: PLC0415 (a sibling module, imported when used)

        arr = _speeds(speeds)
        if arr.shape[0] < 2:
            raise InputError(f"speeds (rad/s) must hold >= 2 speeds for a speed-dependent bearing, got "
                             f"{show(speeds)}")
        if is_concrete(arr) and not np.all(np.diff(np.asarray(arr)) > 0):
            raise InputError(f"speeds (rad/s) must be strictly increasing, got {show(speeds)}")
        r = self.coefficients(arr)
        k, c = r.k, r.c
        return Bearing(node, kxx=k[:, 0, 0], kyy=k[:, 1, 1], kxy=k[:, 0, 1], kyx=k[:, 1, 0],
                       cxx=c[:, 0, 0], cyy=c[:, 1, 1], cxy=c[:, 0, 1], cyx=c[:, 1, 0], speeds=r.speeds)


def plain_journal(speeds, load, viscosity, length, diameter, clearance, method="short",
                  n_theta=240, n_z=16, inlet="free") -> JournalCoefficients:
    """A plain journal bearing's static equilibrium and eight linearised coefficients
    at `speeds` (rad/s): `PlainJournal(load, viscosity, length, diameter, clearance,
    method, n_theta, n_z, inlet).coefficients(speeds)` (see `PlainJournal` for the arguments).

    **Returns:** `JournalCoefficients` (speeds, eccentricity, attitude, sommerfeld,
    position, k, c). With `method="finite"`, a speed whose equilibrium lies outside
    `0 < eps < 0.995` has NaN entries instead of failing the whole table."""
    return PlainJournal(load, viscosity, length, diameter, clearance, method, n_theta, n_z,
                        inlet).coefficients(speeds)
