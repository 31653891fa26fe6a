"""A finite-element rotor: shaft elements (cylindrical or tapered), rigid disks, point
masses, linear bearings (constant or tabulated against speed) and pedestal supports."""

import equinox as eqx
import jax
import jax.numpy as jnp
import numpy as np

from ._validate import (InputError, as_param, as_vector, check, check_choice, check_node,
                               is_concrete, show)
from ._contract import AbstractShaftModel, LinearMatrices
from ._fe_elements import element_matrices
from ._interpolate import spline
from ._materials import poisson_ratio
from ._plausibility import disk_warnings, shaft_warnings, warn

DOFS_PER_NODE = 4  # x, y, sx, sy


def cowper_shear_coefficient(nu, d_out, d_in):
    """Cowper's shear coefficient of a (hollow) circular section."""
    check("d_out (outer diameter)", d_out, lambda a: a > 0, "> 0")
    m = d_in / d_out
    a = (1 + m**2) ** 2
    return 6 * (1 + nu) * a / ((7 + 6 * nu) * a + (20 + 12 * nu) * m**2)


def _entries(name, value):
    """A tuple of tuples (disks, bearings, fixed dofs); a single entry is not accepted."""
    try:
        entries = tuple(tuple(e) for e in value)
    except TypeError:
        raise InputError(f"{name} must be a tuple of tuples, got {show(value)}") from None
    return entries


def _material(name, value, n_el, sign):
    """A material constant: a scalar (the whole shaft) or one value per element."""
    v = as_param(name, value, sign=sign)
    if v.ndim != 0 and v.shape != (n_el,):
        raise InputError(f"{name} must be a scalar or one value per element ({n_el}), got shape {v.shape}"
                         + (f": {show(value)}" if is_concrete(value) else ""))
    return v


BEARING_COEFFICIENTS = ("kxx", "kyy", "kxy", "kyx", "cxx", "cyy", "cxy", "cyx", "mxx", "myy", "mxy", "myx")
#: a bearing's coefficient left out takes the one it follows (`Bearing`, rotor files, fitted parameters)
BEARING_FOLLOWS = {"kyy": "kxx", "cyy": "cxx", "myy": "mxx"}
#: a pedestal's likewise (`Support`)
SUPPORT_KEYS = ("m", "kxx", "kyy", "cxx", "cyy")
SUPPORT_FOLLOWS = {"kyy": "kxx", "cyy": "cxx"}


def follow(values: dict, follows: dict) -> dict:
    """`values` with each key of `follows` that is None (or absent) set to the value
    of the key it follows: the one place a follower's default is taken."""
    out = dict(values)
    for k, leader in follows.items():
        if out.get(k) is None:
            out[k] = out[leader]
    return out


def complete_coefficients(entry):
    """A rotor-file entry of bearing coefficients with those it leaves out: 0, or the
    one each follows (`BEARING_FOLLOWS`), in place."""
    for k in BEARING_COEFFICIENTS:
        if k not in BEARING_FOLLOWS:
            entry.setdefault(k, 0.0)
    entry.update(follow(entry, BEARING_FOLLOWS))


def check_speed_table(entry, where, i):
    """A rotor-file entry of bearing coefficients (a `[[bearing]]`, a `[[seal]]`):
    `speeds` holds >= 2 strictly increasing speeds, and a coefficient given as a list
    has one value per speed (`where.fail`, `where.loc` name the entry)."""
    speeds = entry.get("speeds")
    if speeds is not None:
        loc = where.loc(i, "speeds")
        if len(speeds) < 2:
            where.fail(f"{loc} must hold at least 2 speeds (got {len(speeds)})", loc)
        if any(b <= a for a, b in zip(speeds, speeds[1:])):
            j = next(j for j in range(1, len(speeds)) if speeds[j] <= speeds[j - 1])
            where.fail(f"{loc} must be strictly increasing (speeds[{j}] = {speeds[j]!r} after "
                       f"{speeds[j - 1]!r})", loc)
    for k in BEARING_COEFFICIENTS:
        v, loc = entry.get(k), where.loc(i, k)
        if isinstance(v, list):
            if speeds is None:
                where.fail(f"{loc} is a list: give the speeds it is tabulated at (speeds = [...], rad/s)", loc)
            if len(v) != len(speeds):
                where.fail(f"{loc} has {len(v)} values but speeds has {len(speeds)}", loc)


class Bearing(eqx.Module):
    """A linear bearing at a shaft node: force `-(K q + C q' + M q'')` on the node's
    `(x, y)` (or, with a `Support`, on its motion relative to the pedestal), with

        K = [[kxx, kxy], [kyx, kyy]],  C = [[cxx, cxy], [cyx, cyy]],  M = [[mxx, mxy], [myx, myy]]

    (N/m, N s/m, kg). `kyy`, `cyy`, `myy` default to `kxx`, `cxx`, `mxx`. With
    `speeds` (rad/s, strictly increasing, >= 2 values) each coefficient is one value
    or one per speed, evaluated at the running speed by
    `rotorjax.models._interpolate.spline` (not-a-knot cubic through the points,
    linear outside the table; `check_speeds` warns when an analysis leaves it). The
    values are checked when a `FlexibleRotor` is built (errors name `bearings[i]`).

    The coefficients are keyword-only, `Bearing(node, kxx=1e7, cxx=500.0)`: a
    positional list would read one way here (`kxx, kyy, kxy, kyx`) and another in
    the `(node, kxx, kyy, cxx, cyy)` tuples `FlexibleRotor` accepts.

    `kind` names the element (a subclass with the same law, such as a `Seal`, has its
    own): the rotor keeps it, so a rotor file writes the element back to its table."""

    kind = "bearing"
    nonnegative = ("kxx", "kyy", "cxx", "cyy")   # the coefficients that may not be negative
    node: int = eqx.field(static=True)
    kxx: object
    kyy: object
    kxy: object
    kyx: object
    cxx: object
    cyy: object
    cxy: object
    cyx: object
    mxx: object
    myy: object
    mxy: object
    myx: object
    speeds: object

    def __init__(self, node, *, kxx, kyy=None, kxy=0.0, kyx=0.0, cxx=0.0, cyy=None, cxy=0.0, cyx=0.0, mxx=0.0,
                 myy=None, mxy=0.0, myx=0.0, speeds=None):
        self.node = node
        given = dict(kxx=kxx, kyy=kyy, kxy=kxy, kyx=kyx, cxx=cxx, cyy=cyy, cxy=cxy, cyx=cyx, mxx=mxx, myy=myy,
                     mxy=mxy, myx=myx)
        for k, v in follow(given, BEARING_FOLLOWS).items():
            setattr(self, k, v)
        self.speeds = speeds


class Support(eqx.Module):
    """A pedestal of mass `m` (kg) under bearing `bearing` (its index in
    `bearings`): two dofs `(x, y)` appended after the shaft's, joined to the shaft
    node by the bearing and to ground by `kxx`, `kyy` (N/m) and `cxx`, `cyy`
    (N s/m); `kyy`, `cyy` default to `kxx`, `cxx`. Positional order:
    `Support(bearing, m, kxx, kyy, cxx, cyy)` (no cross terms: the order of the
    `(bearing, m, kxx, kyy, cxx, cyy)` tuples)."""

    bearing: int = eqx.field(static=True)
    m: object
    kxx: object
    kyy: object
    cxx: object
    cyy: object

    def __init__(self, bearing, m, kxx, kyy=None, cxx=0.0, cyy=None):
        self.bearing = bearing
        self.m = m
        for k, v in follow(dict(kxx=kxx, kyy=kyy, cxx=cxx, cyy=cyy), SUPPORT_FOLLOWS).items():
            setattr(self, k, v)


def _diameter(name, value, n_el, sign):
    """A diameter: scalar, per element `(n_el,)` or `(left, right)` per element `(n_el, 2)`."""
    v = as_param(name, value, sign=sign)
    if v.ndim == 0:
        return jnp.full(n_el, v)
    if v.shape in ((n_el,), (n_el, 2)):
        return v
    raise InputError(f"{name} must be a scalar or one value per element ({n_el}), got shape {v.shape}"
                     + (f": {show(value)}" if is_concrete(value) else "")
                     + f" (a taper: (left, right) per element, shape ({n_el}, 2))")


def _bearing_entry(i, b, n_nodes):
    """`(node, values, speeds)`: `values` (12,) for a constant bearing, (12, n) with
    `speeds` (n,) for a table (order `BEARING_COEFFICIENTS`)."""
    p = f"bearings[{i}]"
    nonnegative = Bearing.nonnegative
    if isinstance(b, Bearing):
        raw = {k: getattr(b, k) for k in BEARING_COEFFICIENTS}
        node, speeds, nonnegative = b.node, b.speeds, b.nonnegative
    else:
        forms = ("a Bearing or a tuple (node, kxx, kyy, cxx, cyy) or (node, kxx, kyy, cxx, cyy, kxy, kyx, "
                 "cxy, cyx)")
        tuples = "(node, kxx, kyy, cxx, cyy) or (node, kxx, kyy, cxx, cyy, kxy, kyx, cxy, cyx), or a Bearing"
        named = "name the coefficients with Bearing(node, kxx=..., kyy=..., kxy=..., cxx=..., ...)"
        if isinstance(b, dict):
            raise InputError(f"{p} must be {forms}, got a dict: {named}, e.g. Bearing(**{p})")
        try:
            b = tuple(b)
        except TypeError:
            raise InputError(f"{p} must be {forms}, got {show(b)}") from None
        if len(b) == 5:
            node, kxx, kyy, cxx, cyy = b
            kxy = kyx = cxy = cyx = 0.0
        elif len(b) == 9:
            node, kxx, kyy, cxx, cyy, kxy, kyx, cxy, cyx = b
        else:
            raise InputError(f"{p} must be {tuples}; a tuple of {len(b)} values is ambiguous ({named}): "
                             f"{show(b)}")
        raw = dict(kxx=kxx, kyy=kyy, kxy=kxy, kyx=kyx, cxx=cxx, cyy=cyy, cxy=cxy, cyx=cyx,
                   mxx=0.0, myy=0.0, mxy=0.0, myx=0.0)
        speeds = None
    node = check_node(p, node, n_nodes, "bearing")
    if speeds is not None:
        speeds = as_param(f"{p} speeds", speeds, sign="nonnegative")
        if speeds.ndim != 1 or speeds.shape[0] < 2:
            raise InputError(f"{p} speeds must be a 1-D list of >= 2 speeds (rad/s), got shape {speeds.shape}")
        if is_concrete(speeds) and not np.all(np.diff(np.asarray(speeds)) > 0):
            raise InputError(f"{p} speeds must be strictly increasing, got {show(speeds)}")
    rows = []
    for k in BEARING_COEFFICIENTS:
        v = as_param(f"{p} {k}", raw[k], sign="nonnegative" if k in nonnegative else "any")
        if speeds is None:
            if v.ndim != 0:
                raise InputError(f"{p} {k} must be one value (give speeds for a table), got shape {v.shape}: "
                                 f"{show(raw[k])}")
        elif v.ndim == 0:
            v = jnp.full(speeds.shape, v)
        elif v.ndim != 1 or v.shape[0] != speeds.shape[0]:
            raise InputError(f"{p} {k} has {v.size} values but speeds has {speeds.shape[0]}")
        rows.append(v)
    return node, jnp.stack(rows), speeds


def _support_entry(i, s, n_bearings):
    p = f"supports[{i}]"
    if isinstance(s, Support):
        vals = (s.bearing, s.m, s.kxx, s.kyy, s.cxx, s.cyy)
    else:
        try:
            s = tuple(s)
        except TypeError:
            raise InputError(f"{p} must be a Support or a tuple (bearing_index, m, kxx, kyy, cxx, cyy), "
                             f"got {show(s)}") from None
        if len(s) != 6:
            raise InputError(f"{p} must be (bearing_index, m, kxx, kyy, cxx, cyy), got {len(s)} values: {show(s)}")
        vals = s
    bearing = vals[0]
    if isinstance(bearing, (bool, np.bool_)) or not isinstance(bearing, (int, np.integer)):
        raise InputError(f"{p} bearing index must be an integer, got {bearing!r}")
    if not 0 <= int(bearing) < n_bearings:
        raise InputError(f"{p} bearing index {int(bearing)} out of range ({n_bearings} bearings)")
    row = [as_param(f"{p} m (pedestal mass)", vals[1], sign="positive", shape=())]
    row += [as_param(f"{p} {k}", v, sign="nonnegative", shape=()) for k, v in zip(("kxx", "kyy", "cxx", "cyy"),
                                                                              vals[2:])]
    return int(bearing), row


class FlexibleRotor(AbstractShaftModel):
    """Shaft of `n` beam elements between `n + 1` nodes, rigid disks, point masses,
    linear bearings at nodes and pedestal supports, assembled into
    `M q'' + (C + Omega G1) q' + K q = F` (bearing coefficients at the speed `Omega`).

    Dofs: per shaft node `(x, y, sx, sy)` (displacements and section rotations,
    slopes for Euler-Bernoulli), then per support its pedestal's `(x, y)`:
    `n_dofs = 4 n_nodes + 2 n_supports`. Parameters are array leaves
    (differentiable, vmappable); node indices, `theory`, `fixed_dofs`, which
    bearings have speed tables and which have supports are static.

    **Arguments:**
    - `lengths` (m): per element. `d_out`, `d_in` (m): a scalar, one value per element,
      or `(left, right)` per element, shape `(n, 2)`: a linear taper (Genta's conical
      element, as ROSS; see `_fe_elements`).
    - `E`, `G`, `rho` (Pa, Pa, kg/m^3) and `nu` (Poisson's ratio, default
      `E / (2 G) - 1`, for Cowper's shear coefficient of the mean section): each a
      scalar (one material) or one value per element (`MATERIALS`, `material(name)`).
    - `disks`: `(node, mass, It, Ip)` tuples.
    - `bearings`: `Bearing`s (coefficients by keyword), or tuples of 5 or 9 values in
      this order: `(node, kxx, kyy, cxx, cyy)` or `(node, kxx, kyy, cxx, cyy, kxy,
      kyx, cxy, cyx)` (direct stiffness and damping first; any other length is an
      `InputError`).
    - `theory`: "timoshenko" (shear and rotary inertia), "rayleigh" (rotary inertia,
      no shear) or "euler-bernoulli" (neither; the gyroscopic matrix is kept). ROSS:
      `shear_effects`, `rotary_inertia` True/True, False/True, False/False.
    - `fixed_dofs`: `(node, dof)` pairs held at zero (dof 0..3 = x, y, sx, sy).
    - `point_masses`: `(node, m)` or `(node, mx, my)` (kg) added to the node's x, y mass.
    - `supports`: `Support`s, or `(bearing_index, m, kxx, kyy, cxx, cyy)` tuples.
    - `plausibility`: warn (`PlausibilityWarning`) about concrete values that are
      valid but implausible in SI units, most likely a unit slip (see
      `rotorjax.models._plausibility`): `E`, `G` outside 1e9..1e12 Pa, `rho` outside
      500..25000 kg/m^3, lengths and diameters outside 0.5 mm..5 m, an element's
      `L / od` outside 0.05..50, a disk with `Ip > 2 It` (1.05 x, rounding) or a
      radius of gyration outside 0.5 mm..5 m. `False` for a nondimensional model
      (or values checked already, as the rotor-file loader does). Traced values are
      never inspected.
    """

    lengths: jax.Array
    d_out: jax.Array       # (n_el,) or, tapered, (n_el, 2) = (left, right)
    d_in: jax.Array
    E: jax.Array
    G: jax.Array
    rho: jax.Array
    nu: jax.Array  # Poisson's ratio behind kappa (given, or E / (2 G) - 1)
    tapered: bool = eqx.field(static=True)
    disk_nodes: tuple = eqx.field(static=True)
    disk_params: jax.Array  # (n_disks, 3): mass, It, Ip
    bearing_nodes: tuple = eqx.field(static=True)
    bearing_params: jax.Array  # (n_bearings, 8): kxx, kyy, kxy, kyx, cxx, cyy, cxy, cyx (NaN for tables)
    bearing_mass: jax.Array    # (n_bearings, 4): mxx, myy, mxy, myx (NaN for tables)
    bearing_tables: tuple      # per bearing None, or (speeds (n,), values (12, n))
    bearing_kinds: tuple = eqx.field(static=True)   # per bearing its `kind` ("bearing", "seal")
    point_mass_nodes: tuple = eqx.field(static=True)
    point_mass_params: jax.Array  # (n_point_masses, 2): mx, my
    support_bearings: tuple = eqx.field(static=True)
    support_params: jax.Array  # (n_supports, 5): m, kxx, kyy, cxx, cyy
    theory: str = eqx.field(static=True)
    fixed_dofs: tuple = eqx.field(static=True)

    def __init__(self, lengths, d_out, d_in=0.0, E=211e9, G=81.2e9, rho=7810.0, disks=(),
                 bearings=(), theory="timoshenko", fixed_dofs=(), nu=None, point_masses=(), supports=(), *,
                 plausibility=True):
        lengths = as_vector("element lengths", lengths, sign="positive", what="elements")
        n_el = lengths.shape[0]
        d_out = _diameter("d_out (outer diameter)", d_out, n_el, "positive")
        d_in = _diameter("d_in (inner diameter)", d_in, n_el, "nonnegative")
        self.tapered = d_out.ndim == 2 or d_in.ndim == 2
        if self.tapered:
            d_out, d_in = (jnp.broadcast_to(d.reshape(n_el, -1), (n_el, 2)) for d in (d_out, d_in))
        if is_concrete((d_in, d_out)) and np.any(np.asarray(d_in) >= np.asarray(d_out)):
            bad = np.asarray(d_in) >= np.asarray(d_out)
            k = int(np.argmax(bad.reshape(n_el, -1).any(axis=1)))
            raise InputError(f"d_in (inner diameter) must be smaller than d_out (outer diameter), got "
                             f"d_in = {show(d_in[k])} >= d_out = {show(d_out[k])} (element {k})")
        self.lengths, self.d_out, self.d_in = lengths, d_out, d_in
        self.E = _material("E (Young's modulus)", E, n_el, "positive")
        self.G = _material("G (shear modulus)", G, n_el, "positive")
        self.rho = _material("rho (density)", rho, n_el, "positive")
        if nu is None:
            nu = poisson_ratio(self.E, self.G)
        else:
            nu = _material("nu (Poisson's ratio)", nu, n_el, "any")
            check("nu (Poisson's ratio)", nu, lambda a: (a > -1) & (a <= 0.5), "in (-1, 0.5]")
        self.nu = nu
        check_choice("theory", theory, ("timoshenko", "rayleigh", "euler-bernoulli"))
        self.theory = theory
        n_nodes = n_el + 1

        disks = _entries("disks", disks)
        fixed_dofs = _entries("fixed_dofs", fixed_dofs)
        disk_nodes, rows = [], []
        for i, d in enumerate(disks):
            if len(d) != 4:
                raise InputError(f"disks[{i}] must be (node, mass, It, Ip), got {show(d)}")
            disk_nodes.append(check_node(f"disks[{i}]", d[0], n_nodes, "disk"))
            rows.append([as_param(f"disks[{i}] mass", d[1], sign="positive", shape=()),
                         as_param(f"disks[{i}] It", d[2], sign="nonnegative", shape=()),
                         as_param(f"disks[{i}] Ip", d[3], sign="nonnegative", shape=())])
        self.disk_nodes = tuple(disk_nodes)
        self.disk_params = jnp.array(rows, dtype=jnp.float64).reshape(len(disks), 3)
        if plausibility:
            texts = shaft_warnings(lengths, d_out, d_in, self.E, self.G, self.rho)
            for i, row in enumerate(rows):
                texts += disk_warnings(f"disks[{i}]", *row)
            for text in texts:
                warn(text)

        if isinstance(bearings, Bearing):
            bearings = (bearings,)
        try:
            bearings = tuple(bearings)
        except TypeError:
            raise InputError(f"bearings must be a tuple of Bearings or tuples, got {show(bearings)}") from None
        bearing_nodes, brow, mrow, tables = [], [], [], []
        nan = jnp.full(12, jnp.nan)
        for i, b in enumerate(bearings):
            node, values, speeds = _bearing_entry(i, b, n_nodes)
            bearing_nodes.append(node)
            const = values if speeds is None else nan
            brow.append(const[:8])
            mrow.append(const[8:])
            tables.append(None if speeds is None else (speeds, values))
        self.bearing_nodes = tuple(bearing_nodes)
        self.bearing_params = jnp.stack(brow) if brow else jnp.zeros((0, 8))
        self.bearing_mass = jnp.stack(mrow) if mrow else jnp.zeros((0, 4))
        self.bearing_tables = tuple(tables)
        self.bearing_kinds = tuple(b.kind if isinstance(b, Bearing) else Bearing.kind for b in bearings)

        pm_nodes, pm_rows = [], []
        for i, pm in enumerate(_entries("point_masses", point_masses)):
            if len(pm) not in (2, 3):
                raise InputError(f"point_masses[{i}] must be (node, m) or (node, mx, my), got {show(pm)}")
            pm_nodes.append(check_node(f"point_masses[{i}]", pm[0], n_nodes, "point mass"))
            ms = pm[1:] if len(pm) == 3 else (pm[1], pm[1])
            pm_rows.append([as_param(f"point_masses[{i}] {k}", m, sign="nonnegative", shape=())
                            for k, m in zip(("mx", "my") if len(pm) == 3 else ("m", "m"), ms)])
        self.point_mass_nodes = tuple(pm_nodes)
        self.point_mass_params = jnp.array(pm_rows, dtype=jnp.float64).reshape(len(pm_nodes), 2)

        if isinstance(supports, Support):
            supports = (supports,)
        try:
            supports = tuple(supports)
        except TypeError:
            raise InputError(f"supports must be a tuple of Supports or tuples, got {show(supports)}") from None
        s_bearings, s_rows = [], []
        for i, s in enumerate(supports):
            bearing, row = _support_entry(i, s, len(bearings))
            if bearing in s_bearings:
                raise InputError(f"supports[{i}]: bearing {bearing} already stands on "
                                 f"supports[{s_bearings.index(bearing)}]")
            s_bearings.append(bearing)
            s_rows.append(row)
        self.support_bearings = tuple(s_bearings)
        self.support_params = jnp.array(s_rows, dtype=jnp.float64).reshape(len(s_rows), 5)

        fixed = []
        for i, pair in enumerate(fixed_dofs):
            if len(pair) != 2:
                raise InputError(f"fixed_dofs[{i}] must be a (node, dof) pair, got {show(pair)}")
            node, dof = pair
            node = check_node(f"fixed_dofs[{i}]", node, n_nodes, "fixed dof")
            if isinstance(dof, bool) or dof not in (0, 1, 2, 3):
                raise InputError(f"fixed_dofs[{i}]: fixed dof must be 0..3 (x, y, sx, sy), got {dof!r}")
            fixed.append(DOFS_PER_NODE * node + int(dof))
        self.fixed_dofs = tuple(sorted(set(fixed)))
        if len(self.fixed_dofs) == self.n_dofs:
            raise InputError("fixed_dofs hold every dof of the shaft at zero: nothing is left to move")

    @property
    def kappa(self) -> jax.Array:
        """Cowper's shear coefficient per element, from `nu` and the mean inner and
        outer diameters (as ROSS): derived from the leaves, so it follows a fitted
        diameter or Poisson's ratio."""
        mean_out = self.d_out.mean(axis=1) if self.tapered else self.d_out
        mean_in = self.d_in.mean(axis=1) if self.tapered else self.d_in
        return cowper_shear_coefficient(self.nu, mean_out, mean_in)

    @property
    def n_nodes(self) -> int:
        return self.lengths.shape[0] + 1

    @property
    def n_supports(self) -> int:
        return len(self.support_bearings)

    @property
    def n_dofs(self) -> int:
        return DOFS_PER_NODE * self.n_nodes + 2 * self.n_supports

    @property
    def speed_dependent(self) -> bool:
        """Whether any bearing's coefficients are tabulated against speed."""
        return any(t is not None for t in self.bearing_tables)

    @property
    def free_dofs(self) -> np.ndarray:
        return np.setdiff1d(np.arange(self.n_dofs), np.asarray(self.fixed_dofs, dtype=int))

    @property
    def node_positions(self) -> jax.Array:
        return jnp.concatenate([jnp.zeros(1), jnp.cumsum(self.lengths)])

    def support_dofs(self, j) -> tuple:
        """The `(x, y)` dof indices of support `j`'s pedestal."""
        p = DOFS_PER_NODE * self.n_nodes + 2 * j
        return p, p + 1

    def translation(self, ux, uy):
        """The all-dof vector of a rigid translation `(ux, uy)` of the shaft and the
        pedestals (rotations zero)."""
        e = jnp.zeros(self.n_dofs)
        e = e.at[0:DOFS_PER_NODE * self.n_nodes:DOFS_PER_NODE].set(ux)
        e = e.at[1:DOFS_PER_NODE * self.n_nodes:DOFS_PER_NODE].set(uy)
        for j in range(self.n_supports):
            px, py = self.support_dofs(j)
            e = e.at[px].set(ux).at[py].set(uy)
        return e

    def mass(self):
        """Total mass (kg): the shaft elements' (the consistent mass matrix's rigid
        translation, `sum rho A L`) plus the disks' and point masses' (pedestals are
        not the rotor's). Traceable in the rotor's parameters."""
        M, _, _ = self.shaft_matrices()
        e = jnp.zeros(M.shape[0]).at[0:DOFS_PER_NODE * self.n_nodes:DOFS_PER_NODE].set(1.0)
        out = e @ M @ e
        if self.disk_nodes:
            out = out + jnp.sum(self.disk_params[:, 0])
        if self.point_mass_nodes:
            out = out + jnp.sum(self.point_mass_params[:, 0])
        return out

    def bearing_coefficients(self, speed=0.0):
        """`(n_bearings, 12)`: each bearing's kxx, kyy, kxy, kyx, cxx, cyy, cxy, cyx,
        mxx, myy, mxy, myx at `speed` (rad/s; tables through `spline`)."""
        if is_concrete(speed):
            as_param("speed", speed, shape=())
        speed = jnp.asarray(speed, dtype=jnp.float64)
        rows = []
        for i, table in enumerate(self.bearing_tables):
            if table is None:
                rows.append(jnp.concatenate([self.bearing_params[i], self.bearing_mass[i]]))
            else:
                rows.append(spline(table[0], table[1], speed))
        return jnp.stack(rows) if rows else jnp.zeros((0, 12))

    def bearing(self, i, cls=Bearing):
        """Bearing `i` as a `cls` (`Bearing`, or the subclass of its kind): its node,
        its coefficients (arrays over `speeds` for a table) and `speeds`."""
        table = self.bearing_tables[i]
        if table is None:
            speeds, values = None, jnp.concatenate([self.bearing_params[i], self.bearing_mass[i]])
        else:
            speeds, values = table
        return cls(self.bearing_nodes[i], speeds=speeds, **dict(zip(BEARING_COEFFICIENTS, values)))

    @property
    def supports(self) -> tuple:
        """The supports as `Support`s (values from `support_params`)."""
        return tuple(Support(b, *self.support_params[j]) for j, b in enumerate(self.support_bearings))

    def element_matrices(self):
        """Per-element `(M_e, G1_e, K_e)`, each `(n_el, 8, 8)` on
        `(x1, y1, sx1, sy1, x2, y2, sx2, sy2)`."""
        shear = self.theory == "timoshenko"
        rotary = self.theory in ("timoshenko", "rayleigh")
        # a material given once is closed over (unbatched); per-element values are mapped
        axes = tuple(0 if a.ndim else None for a in (self.E, self.G, self.rho))
        Me, Ge, Ke = jax.vmap(
            lambda E, G, rho, L, do, di, kap: element_matrices(E, G, rho, do, di, L, kap, shear, rotary),
            in_axes=axes + (0, 0, 0, 0),
        )(self.E, self.G, self.rho, self.lengths, self.d_out, self.d_in, self.kappa)
        return Me, Ge, Ke

    def shaft_matrices(self):
        """`(M, G1, K)` of the shaft elements alone, on all dofs."""
        n = self.n_dofs
        idx = np.arange(self.n_nodes - 1)[:, None] * DOFS_PER_NODE + np.arange(8)[None, :]
        rows = np.repeat(idx[:, :, None], 8, axis=2)
        cols = np.repeat(idx[:, None, :], 8, axis=1)
        # the three matrices in one scatter (one loop for XLA to compile, not three)
        M, G1, K = jnp.zeros((3, n, n)).at[:, rows, cols].add(jnp.stack(self.element_matrices()))
        return M, G1, K

    def matrices(self, speed=0.0):
        """Global `(M, C, G1, K)` on all dofs (`G = Omega G1`), bearing coefficients
        (mass coefficients included) at `speed` (rad/s)."""
        M, G1, K = self.shaft_matrices()
        # every lumped term (disks, point masses, bearings, pedestals) as (row, column, value) entries, added
        # to each matrix in one scatter, in the order in which they are listed (one loop for XLA to compile,
        # not one per entry)
        entries = {"M": [], "C": [], "G1": [], "K": []}

        def add(name, rows, cols, values):
            entries[name].append((np.asarray(rows).ravel(), np.asarray(cols).ravel(), jnp.ravel(values)))

        for i, node in enumerate(self.disk_nodes):
            b = DOFS_PER_NODE * node
            m, it, ip = self.disk_params[i]
            add("M", [b, b + 1, b + 2, b + 3], [b, b + 1, b + 2, b + 3], jnp.stack([m, m, it, it]))
            add("G1", [b + 2, b + 3], [b + 3, b + 2], jnp.stack([ip, -ip]))
        for i, node in enumerate(self.point_mass_nodes):
            b = DOFS_PER_NODE * node
            add("M", [b, b + 1], [b, b + 1], self.point_mass_params[i, :2])
        coef = self.bearing_coefficients(speed)
        for i, node in enumerate(self.bearing_nodes):
            b = DOFS_PER_NODE * node
            kxx, kyy, kxy, kyx, cxx, cyy, cxy, cyx, mxx, myy, mxy, myx = coef[i]
            blocks = [jnp.array([[kxx, kxy], [kyx, kyy]]), jnp.array([[cxx, cxy], [cyx, cyy]]),
                      jnp.array([[mxx, mxy], [myx, myy]])]
            if i in self.support_bearings:
                # the bearing acts on the shaft's motion relative to its pedestal
                d = np.array([b, b + 1, *self.support_dofs(self.support_bearings.index(i))])
                blocks = [jnp.block([[a, -a], [-a, a]]) for a in blocks]
            else:
                d = np.array([b, b + 1])
            rows, cols = np.meshgrid(d, d, indexing="ij")
            for name, a in zip(("K", "C", "M"), blocks):
                add(name, rows, cols, a)
        for j in range(self.n_supports):
            px, py = self.support_dofs(j)
            m, kxx, kyy, cxx, cyy = self.support_params[j]
            add("M", [px, py], [px, py], jnp.stack([m, m]))
            add("K", [px, py], [px, py], jnp.stack([kxx, kyy]))
            add("C", [px, py], [px, py], jnp.stack([cxx, cyy]))
        out = {"M": M, "C": jnp.zeros_like(K), "G1": G1, "K": K}
        for name, parts in entries.items():
            if parts:
                rows, cols, values = zip(*parts)
                out[name] = out[name].at[np.concatenate(rows), np.concatenate(cols)].add(jnp.concatenate(values))
        return out["M"], out["C"], out["G1"], out["K"]

    def reduced_matrices(self, speed=0.0):
        """`(M, C, G1, K)` on the free dofs only, bearing coefficients at `speed`."""
        return _reduced_matrices(self, jnp.asarray(speed, dtype=jnp.float64))

    @property
    def full_rotor(self) -> "FlexibleRotor":
        return self

    @property
    def n_coordinates(self) -> int:
        return len(self.free_dofs)

    def linear_matrices(self, speed) -> LinearMatrices:
        """`(M, C, speed G1, K)` on the free dofs, bearings at `speed`."""
        M, C, G1, K = self.reduced_matrices(speed)
        return LinearMatrices(M=M, C=C, G=speed * G1, K=K)

    def expand(self, q):
        """Free-dof vector (or columns) to all dofs, fixed dofs zero."""
        q = jnp.asarray(q)
        f = self.free_dofs
        if f.size and f[-1] - f[0] == f.size - 1:   # contiguous (a clamped end): a pad, cheaper than a scatter
            return jnp.pad(q, [(int(f[0]), self.n_dofs - 1 - int(f[-1]))] + [(0, 0)] * (q.ndim - 1))
        return jnp.zeros((self.n_dofs,) + q.shape[1:], dtype=q.dtype).at[f].set(q)

    def project(self, f):
        """A load on the free dofs, in this rotor's coordinates (the identity here;
        see `ReducedRotor`)."""
        return f

    def reduce(self, n_modes):
        """This rotor reduced to its `n_modes` lowest undamped modes (`ReducedRotor`;
        `1 <= n_modes <=` the number of free dofs)."""
        from ._fe_reduction import ReducedRotor

        return ReducedRotor(self, n_modes)


@eqx.filter_jit
def _reduced_matrices(rotor, speed):
    """`FlexibleRotor.reduced_matrices`, as one compiled program per rotor layout: the
    assembly (element matrices, scatter, bearings) is traced once per process and
    layout, however many analyses call it, and compiled once (the persistent
    compilation cache keeps it across runs), instead of hundreds of operations
    dispatched one by one."""
    f = rotor.free_dofs
    return tuple(a[np.ix_(f, f)] for a in rotor.matrices(speed))
