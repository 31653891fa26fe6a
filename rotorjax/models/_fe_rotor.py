"""A finite-element rotor: shaft elements, rigid disks and linear bearings at nodes."""

import equinox as eqx
import jax
import jax.numpy as jnp
import numpy as np

from ._validate import (InputError, as_param, as_vector, check, check_choice, check_node,
                               is_concrete, per_item, show)
from ._fe_elements import element_matrices

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


class FlexibleRotor(eqx.Module):
    """Shaft of `n` beam elements between `n + 1` nodes, rigid disks and linear
    bearings at nodes, assembled into `M q'' + (C + Omega G1) q' + K q = F`.

    Node dofs `(x, y, sx, sy)`: displacements and section rotations (slopes for
    Euler-Bernoulli). Element and disk/bearing parameters are array leaves
    (differentiable, vmappable); node indices, `theory` and `fixed_dofs` are static.

    **Arguments:**
    - `lengths`, `d_out`, `d_in`: per element (m); `E`, `G`, `rho` (Pa, Pa, kg/m^3)
      and `nu` (Poisson's ratio, default `E / (2 G) - 1`, for Cowper's shear
      coefficient): each a scalar (one material) or one value per element.
    - `disks`: `(node, mass, It, Ip)` tuples; `bearings`: `(node, kxx, kyy, cxx, cyy)` or
      `(node, kxx, kyy, cxx, cyy, kxy, kyx, cxy, cyx)` tuples.
    - `theory`: "timoshenko" (shear and rotary inertia), "rayleigh" (rotary inertia,
      no shear) or "euler-bernoulli" (neither; the gyroscopic matrix is kept).
    - `fixed_dofs`: `(node, dof)` pairs held at zero (dof 0..3 = x, y, sx, sy).
    """

    lengths: jax.Array
    d_out: jax.Array
    d_in: jax.Array
    E: jax.Array
    G: jax.Array
    rho: jax.Array
    nu: jax.Array  # Poisson's ratio behind kappa (given, or E / (2 G) - 1)
    kappa: jax.Array
    disk_nodes: tuple = eqx.field(static=True)
    disk_params: jax.Array  # (n_disks, 3): mass, It, Ip
    bearing_nodes: tuple = eqx.field(static=True)
    bearing_params: jax.Array  # (n_bearings, 8): kxx, kyy, kxy, kyx, cxx, cyy, cxy, cyx
    theory: str = eqx.field(static=True)
    fixed_dofs: tuple = eqx.field(static=True)

    def __init__(self, lengths, d_out, d_in=0.0, E=211e9, G=81.2e9, rho=7810.0, disks=(),
                 bearings=(), theory="timoshenko", fixed_dofs=(), nu=None):
        lengths = as_vector("element lengths", lengths, sign="positive", what="elements")
        n_el = lengths.shape[0]
        d_out = per_item("d_out (outer diameter)", d_out, n_el, sign="positive", what="element")
        d_in = per_item("d_in (inner diameter)", d_in, n_el, sign="nonnegative", what="element")
        if is_concrete((d_in, d_out)) and np.any(np.asarray(d_in) >= np.asarray(d_out)):
            k = int(np.argmax(np.asarray(d_in) >= np.asarray(d_out)))
            raise InputError(f"d_in (inner diameter) must be smaller than d_out (outer diameter), got "
                             f"d_in = {float(d_in[k])!r} >= d_out = {float(d_out[k])!r} (element {k})")
        self.lengths, self.d_out, self.d_in = lengths, d_out, d_in
        self.E = _material("E (Young's modulus)", E, n_el, "positive")
        self.G = _material("G (shear modulus)", G, n_el, "positive")
        self.rho = _material("rho (density)", rho, n_el, "positive")
        if nu is None:
            nu = self.E / (2 * self.G) - 1
        else:
            nu = _material("nu (Poisson's ratio)", nu, n_el, "any")
            check("nu (Poisson's ratio)", nu, lambda a: (a > -1) & (a <= 0.5), "in (-1, 0.5]")
        self.nu = nu
        self.kappa = cowper_shear_coefficient(nu, self.d_out, self.d_in)
        check_choice("theory", theory, ("timoshenko", "rayleigh", "euler-bernoulli"))
        self.theory = theory
        n_nodes = n_el + 1

        disks = _entries("disks", disks)
        bearings = _entries("bearings", bearings)
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
        bearing_nodes, brow = [], []
        for i, b in enumerate(bearings):
            if len(b) == 5:
                node, kxx, kyy, cxx, cyy = b
                kxy = kyx = cxy = cyx = 0.0
            elif len(b) == 9:
                node, kxx, kyy, cxx, cyy, kxy, kyx, cxy, cyx = b
            else:
                raise InputError(f"bearings[{i}] must be (node, kxx, kyy, cxx, cyy[, kxy, kyx, cxy, cyx]), "
                                 f"got {len(b)} values: {show(b)}")
            bearing_nodes.append(check_node(f"bearings[{i}]", node, n_nodes, "bearing"))
            p = f"bearings[{i}]"
            brow.append([as_param(f"{p} kxx", kxx, sign="nonnegative", shape=()),
                         as_param(f"{p} kyy", kyy, sign="nonnegative", shape=()),
                         as_param(f"{p} kxy", kxy, shape=()), as_param(f"{p} kyx", kyx, shape=()),
                         as_param(f"{p} cxx", cxx, sign="nonnegative", shape=()),
                         as_param(f"{p} cyy", cyy, sign="nonnegative", shape=()),
                         as_param(f"{p} cxy", cxy, shape=()), as_param(f"{p} cyx", cyx, shape=())])
        self.bearing_nodes = tuple(bearing_nodes)
        self.bearing_params = jnp.array(brow, dtype=jnp.float64).reshape(len(bearings), 8)
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
    def n_nodes(self) -> int:
        return self.lengths.shape[0] + 1

    @property
    def n_dofs(self) -> int:
        return DOFS_PER_NODE * self.n_nodes

    @property
    def free_dofs(self) -> np.ndarray:
        return np.setdiff1d(np.arange(self.n_dofs), np.asarray(self.fixed_dofs, dtype=int))

    @property
    def node_positions(self) -> jax.Array:
        return jnp.concatenate([jnp.zeros(1), jnp.cumsum(self.lengths)])

    def matrices(self):
        """Global `(M, C, G1, K)` on all dofs (`G = Omega G1`)."""
        n = self.n_dofs
        shear = self.theory == "timoshenko"
        rotary = self.theory in ("timoshenko", "rayleigh")
        # a material given once is closed over (unbatched); per-element values are mapped
        axes = tuple(0 if a.ndim else None for a in (self.E, self.G, self.rho))
        Me, Ge, Ke = jax.vmap(
            lambda E, G, rho, L, do, di, kap: element_matrices(E, G, rho, do, di, L, kap, shear, rotary),
            in_axes=axes + (0, 0, 0, 0),
        )(self.E, self.G, self.rho, self.lengths, self.d_out, self.d_in, self.kappa)
        idx = np.arange(self.n_nodes - 1)[:, None] * DOFS_PER_NODE + np.arange(8)[None, :]
        rows = np.repeat(idx[:, :, None], 8, axis=2)
        cols = np.repeat(idx[:, None, :], 8, axis=1)
        M = jnp.zeros((n, n)).at[rows, cols].add(Me)
        G1 = jnp.zeros((n, n)).at[rows, cols].add(Ge)
        K = jnp.zeros((n, n)).at[rows, cols].add(Ke)
        C = jnp.zeros((n, n))
        for i, node in enumerate(self.disk_nodes):
            b = DOFS_PER_NODE * node
            m, it, ip = self.disk_params[i]
            M = M.at[b, b].add(m).at[b + 1, b + 1].add(m).at[b + 2, b + 2].add(it).at[b + 3, b + 3].add(it)
            G1 = G1.at[b + 2, b + 3].add(ip).at[b + 3, b + 2].add(-ip)
        for i, node in enumerate(self.bearing_nodes):
            b = DOFS_PER_NODE * node
            kxx, kyy, kxy, kyx, cxx, cyy, cxy, cyx = self.bearing_params[i]
            K = K.at[b, b].add(kxx).at[b + 1, b + 1].add(kyy).at[b, b + 1].add(kxy).at[b + 1, b].add(kyx)
            C = C.at[b, b].add(cxx).at[b + 1, b + 1].add(cyy).at[b, b + 1].add(cxy).at[b + 1, b].add(cyx)
        return M, C, G1, K

    def reduced_matrices(self):
        """`(M, C, G1, K)` on the free dofs only."""
        f = self.free_dofs
        return tuple(a[np.ix_(f, f)] for a in self.matrices())

    def expand(self, q):
        """Free-dof vector (or columns) to all dofs, fixed dofs zero."""
        q = jnp.asarray(q)
        return jnp.zeros((self.n_dofs,) + q.shape[1:], dtype=q.dtype).at[self.free_dofs].set(q)

    def project(self, f):
        """A load on the free dofs, in this rotor's coordinates (the identity here;
        see `ReducedRotor`)."""
        return f

    def reduce(self, n_modes):
        """This rotor reduced to its `n_modes` lowest undamped modes (`ReducedRotor`;
        `1 <= n_modes <=` the number of free dofs)."""
        from ._fe_reduction import ReducedRotor

        return ReducedRotor(self, n_modes)
