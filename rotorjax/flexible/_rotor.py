"""A finite-element rotor: shaft elements, rigid disks and linear bearings at nodes."""

import equinox as eqx
import jax
import jax.numpy as jnp
import numpy as np

from ..models._validate import as_param
from ._elements import element_matrices

DOFS_PER_NODE = 4  # x, y, sx, sy


def cowper_shear_coefficient(nu, d_out, d_in):
    """Cowper's shear coefficient of a (hollow) circular section."""
    m = d_in / d_out
    a = (1 + m**2) ** 2
    return 6 * (1 + nu) * a / ((7 + 6 * nu) * a + (20 + 12 * nu) * m**2)


class FlexibleRotor(eqx.Module):
    """Shaft of `n` beam elements between `n + 1` nodes, rigid disks and linear
    bearings at nodes, assembled into `M q'' + (C + Omega G1) q' + K q = F`.

    Node dofs `(x, y, sx, sy)`: displacements and section rotations (slopes for
    Euler-Bernoulli). Element and disk/bearing parameters are array leaves
    (differentiable, vmappable); node indices, `theory` and `fixed_dofs` are static.

    **Arguments:**
    - `lengths`, `d_out`, `d_in`: per element (m); `E`, `G`, `rho` (Pa, Pa, kg/m^3).
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
    kappa: jax.Array
    disk_nodes: tuple = eqx.field(static=True)
    disk_params: jax.Array  # (n_disks, 3): mass, It, Ip
    bearing_nodes: tuple = eqx.field(static=True)
    bearing_params: jax.Array  # (n_bearings, 8): kxx, kyy, kxy, kyx, cxx, cyy, cxy, cyx
    theory: str = eqx.field(static=True)
    fixed_dofs: tuple = eqx.field(static=True)

    def __init__(self, lengths, d_out, d_in=0.0, E=211e9, G=81.2e9, rho=7810.0, disks=(),
                 bearings=(), theory="timoshenko", fixed_dofs=(), nu=None):
        lengths = as_param("element lengths", lengths, sign="positive")
        if lengths.ndim != 1 or lengths.shape[0] < 1:
            raise ValueError(f"element lengths must be a 1-D array of >= 1 elements, got shape {lengths.shape}")
        n_el = lengths.shape[0]
        d_out = jnp.broadcast_to(as_param("d_out (outer diameter)", d_out, sign="positive"), (n_el,))
        d_in = jnp.broadcast_to(as_param("d_in (inner diameter)", d_in, sign="nonnegative"), (n_el,))
        if not isinstance(d_out, jax.core.Tracer) and np.any(np.asarray(d_in) >= np.asarray(d_out)):
            raise ValueError("d_in (inner diameter) must be smaller than d_out")
        self.lengths, self.d_out, self.d_in = lengths, d_out, d_in
        self.E = as_param("E (Young's modulus)", E, sign="positive")
        self.G = as_param("G (shear modulus)", G, sign="positive")
        self.rho = as_param("rho (density)", rho, sign="positive")
        nu = self.E / (2 * self.G) - 1 if nu is None else nu
        self.kappa = cowper_shear_coefficient(nu, self.d_out, self.d_in)
        if theory not in ("timoshenko", "rayleigh", "euler-bernoulli"):
            raise ValueError(f"theory must be 'timoshenko', 'rayleigh' or 'euler-bernoulli', got {theory!r}")
        self.theory = theory
        n_nodes = n_el + 1

        def node_index(kind, node):
            if int(node) != node or not 0 <= node < n_nodes:
                raise ValueError(f"{kind} at node {node}: the shaft has nodes 0..{n_nodes - 1}")
            return int(node)

        self.disk_nodes = tuple(node_index("disk", d[0]) for d in disks)
        rows = [[as_param("disk mass", d[1], sign="positive"), as_param("disk It", d[2], sign="nonnegative"),
                 as_param("disk Ip", d[3], sign="nonnegative")] for d in disks]
        self.disk_params = jnp.array(rows, dtype=jnp.float64).reshape(len(disks), 3)
        self.bearing_nodes = tuple(node_index("bearing", b[0]) for b in bearings)
        brow = []
        for b in bearings:
            if len(b) == 5:
                node, kxx, kyy, cxx, cyy = b
                kxy = kyx = cxy = cyx = 0.0
            elif len(b) == 9:
                node, kxx, kyy, cxx, cyy, kxy, kyx, cxy, cyx = b
            else:
                raise ValueError("a bearing is (node, kxx, kyy, cxx, cyy[, kxy, kyx, cxy, cyx])")
            brow.append([as_param("bearing kxx", kxx, sign="nonnegative"),
                         as_param("bearing kyy", kyy, sign="nonnegative"), as_param("bearing kxy", kxy),
                         as_param("bearing kyx", kyx), as_param("bearing cxx", cxx, sign="nonnegative"),
                         as_param("bearing cyy", cyy, sign="nonnegative"), as_param("bearing cxy", cxy),
                         as_param("bearing cyx", cyx)])
        self.bearing_params = jnp.array(brow, dtype=jnp.float64).reshape(len(bearings), 8)
        fixed = []
        for node, dof in fixed_dofs:
            node_index("fixed dof", node)
            if dof not in (0, 1, 2, 3):
                raise ValueError(f"fixed dof must be 0..3 (x, y, sx, sy), got {dof}")
            fixed.append(DOFS_PER_NODE * int(node) + int(dof))
        self.fixed_dofs = tuple(sorted(set(fixed)))

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
        Me, Ge, Ke = jax.vmap(
            lambda L, do, di, kap: element_matrices(self.E, self.G, self.rho, do, di, L, kap, shear, rotary)
        )(self.lengths, self.d_out, self.d_in, self.kappa)
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
        """This rotor reduced to its `n_modes` lowest undamped modes (`ReducedRotor`)."""
        from ._reduction import ReducedRotor

        return ReducedRotor(self, n_modes)
