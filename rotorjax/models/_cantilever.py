"""Model 004: a cantilever flexible rotor with a disk at its free end, Voigt
internal friction and external damping (Azarov, Guskov, Panovko 2023), as a
finite-element shaft in the paper's dimensionless units (eq. 7).

Units: length `l` (the shaft), mass `M` (the disk), time
`T* = sqrt(M l^3 / (E I_R))`; so `E I_R = 1`, the shaft's mass per unit length is
`mu_R = m_R l / M`, the disk's transverse inertia `beta = B / (M l^2) = eps_D^2 / 16`
(`eps_D = D / l`) and its polar inertia `2 beta` (thin disk). The spin speed is
`N = Omega T*` (`speed` in the methods' signatures, with the paper's `N` accepted
as an alias).

Equations (fixed frame, free dofs of the clamped shaft `q`):

    M q'' + (C + Ci + N G1) q' + (K + N Ci J) q = F(t, q, q'),

with `K` the shaft's bending stiffness, `Ci = 2 eta_i K` Voigt internal damping
(the paper's `q_V = -2 eta_i (xi'''' ' + N S xi'''')`: damping of the strain rate
seen in the rotating frame, which adds the circulatory stiffness `N Ci J`, `J` the
quarter-turn `(x, y) -> (y, -x)` of every node's displacement and slope),
`C = 2 eta_e M_1 + 2 eta_Dxi (disk translation) + 2 eta_Dtheta (disk tilt)` (`M_1`
the consistent translational mass of a unit-density shaft), and `G1` the
gyroscopic matrix of shaft (Rayleigh beam) and disk. The loads `F` (unbalance
`eps N^2 (cos(N t + phi), sin(N t + phi))`, gravity `-gamma` along x, limiter
contact) act at the disk (node `n_elements`).

The rotor is a linear system (`linear_matrices(speed)`); its analyses are functions
in `rotorjax.analysis`: `state_matrix`, `modes`, `linear_margin`, `hopf_points`,
`least_stable_whirl(rotor, speed, rotor.disk_dofs[:2])` (whirl at the disk), and the
unbalance response of `cantilever_scene(rotor, N, eps=eps, phase=phase)` by
`scene_unbalance_response`. In synchronous forward whirl the shaft does not deform
in the rotating frame, so internal friction does no work and drops out of that
response (a check, tested).
"""

import warnings

import equinox as eqx
import jax
import jax.numpy as jnp
import numpy as np

from ._contract import AbstractLinearSystem, LinearMatrices
from ._fe_reduction import undamped_modes
from ._fe_rotor import DOFS_PER_NODE, FlexibleRotor
from ._rotation import quarter_turn_matrix
from ._frequency import frequency_response
from ._speed import speed_alias
from ._validate import InputError, as_count, as_param

#: The paper's base case (SI): shaft length, shaft and disk diameters, disk thickness;
#: steel (E, rho), eccentricity, limiter clearance and stiffness.
PAPER_SI = dict(l=0.7, d=0.02, D=0.2, a=0.01, E=2.1e11, rho=7800.0, e=0.001, h=0.0075, k_S=4.087e6)


def groups_from_si(l, d, D, a, E, rho, g=9.81):
    """The paper's dimensionless groups (eq. 7) and scales from SI geometry and
    material: `mu_R`, `beta`, `eps_D`, `d_ratio = d / l`, `gamma = M g l^2 / EI`, and
    `T_star` (s), `M` (kg), `EI` (N m^2), `l` (m)."""
    for name, v in (("l", l), ("d", d), ("D", D), ("a", a), ("E", E), ("rho", rho)):
        as_param(name, v, sign="positive", shape=())
    as_param("g (gravity)", g, sign="nonnegative", shape=())
    M = rho * np.pi * D**2 / 4 * a
    EI = E * np.pi * d**4 / 64
    m_R = rho * np.pi * d**2 / 4
    return {"mu_R": m_R * l / M, "beta": (D / l) ** 2 / 16, "eps_D": D / l, "d_ratio": d / l,
            "gamma": M * g * l**2 / EI, "T_star": float(np.sqrt(M * l**3 / EI)), "M": M, "EI": EI, "l": l}


def limiter_groups_from_si(k, h, d_S, l, M, EI):
    """Limiter stiffness `kappa = k l^3 / EI`, clearance `chi = h / l` and damping
    `eta = d_S sqrt(l^3 / (M EI))` (eq. 7; the paper prints `k l / EI`, a typo: its
    `k_S = 4.087e6 N/m` gives the stated `kappa = 850` only with `l^3`)."""
    for name, v, sign in (("k", k, "nonnegative"), ("h", h, "positive"), ("d_S", d_S, "nonnegative"),
                          ("l", l, "positive"), ("M", M, "positive"), ("EI", EI, "positive")):
        as_param(name, v, sign=sign, shape=())
    return {"kappa": k * l**3 / EI, "chi": h / l, "eta": d_S * np.sqrt(l**3 / (M * EI))}


class CantileverRotor(AbstractLinearSystem):
    """Model 004's rotor (see the module docstring), dimensionless.

    **Arguments:** `mu_R` (shaft mass / disk mass), `beta` (disk transverse inertia,
    `eps_D^2 / 16` for a thin disk of diameter `eps_D`), `d_ratio` (shaft diameter /
    length: the shaft's rotary inertia), `eta_i` (internal, Voigt), `eta_e` (external,
    per unit length), `eta_Dxi`, `eta_Dtheta` (disk translation and tilt damping),
    `n_elements` (static, >= 1; Rayleigh beam elements).
    """

    mu_R: jax.Array
    beta: jax.Array
    d_ratio: jax.Array
    eta_i: jax.Array
    eta_e: jax.Array
    eta_Dxi: jax.Array
    eta_Dtheta: jax.Array
    n_elements: int = eqx.field(static=True)

    def __init__(self, mu_R, beta, d_ratio, eta_i, eta_e, eta_Dxi=0.0, eta_Dtheta=0.0, n_elements=8):
        self.mu_R = as_param("mu_R (shaft/disk mass ratio)", mu_R, sign="positive", shape=())
        self.beta = as_param("beta (disk inertia)", beta, sign="nonnegative", shape=())
        self.d_ratio = as_param("d_ratio (shaft diameter / length)", d_ratio, sign="positive", shape=())
        self.eta_i = as_param("eta_i (internal damping)", eta_i, sign="nonnegative", shape=())
        self.eta_e = as_param("eta_e (external damping)", eta_e, sign="nonnegative", shape=())
        self.eta_Dxi = as_param("eta_Dxi (disk damping)", eta_Dxi, sign="nonnegative", shape=())
        self.eta_Dtheta = as_param("eta_Dtheta (disk angular damping)", eta_Dtheta, sign="nonnegative",
                                   shape=())
        self.n_elements = as_count("n_elements", n_elements, minimum=1)

    @classmethod
    def from_si(cls, l, d, D, a, E, rho, T_V=0.0, d_e=0.0, d_Dr=0.0, d_Dtheta=0.0, n_elements=8):
        """From SI geometry (m), material (Pa, kg/m^3) and damping: Voigt relaxation
        time `T_V` (s), external damping per unit length `d_e` (N s/m^2), disk
        translational `d_Dr` (N s/m) and angular `d_Dtheta` (N m s) damping, by eq. (7)."""
        g = groups_from_si(l, d, D, a, E, rho)
        for name, v in (("T_V", T_V), ("d_e", d_e), ("d_Dr", d_Dr), ("d_Dtheta", d_Dtheta)):
            as_param(name, v, sign="nonnegative", shape=())
        root = np.sqrt(g["M"] * l**3 * g["EI"])
        return cls(g["mu_R"], g["beta"], g["d_ratio"], eta_i=T_V / 2 * np.sqrt(g["EI"] / (g["M"] * l**3)),
                   eta_e=d_e * l**4 / (2 * root), eta_Dxi=d_Dr * l**3 / (2 * root),
                   eta_Dtheta=d_Dtheta * l / (2 * root), n_elements=n_elements)

    @property
    def n_nodes(self) -> int:
        return self.n_elements + 1

    @property
    def disk_node(self) -> int:
        """The disk's node (the free end; node 0 is clamped)."""
        return self.n_elements

    @property
    def disk_dofs(self) -> np.ndarray:
        """Indices of the disk's `(x, y, sx, sy)` among the free dofs."""
        return DOFS_PER_NODE * (self.n_elements - 1) + np.arange(DOFS_PER_NODE)

    def shaft(self, density=None, disk=True, theory="rayleigh") -> FlexibleRotor:
        """The FE shaft in these units (`E I = 1`, `rho A = mu_R`), clamped at node 0."""
        n = self.n_elements
        area, inertia = jnp.pi * self.d_ratio**2 / 4, jnp.pi * self.d_ratio**4 / 64
        rho = (self.mu_R if density is None else density) / area
        disks = ((n, 1.0, self.beta, 2 * self.beta),) if disk else ()
        return FlexibleRotor(jnp.full(n, 1.0 / n), self.d_ratio, E=1 / inertia, G=1.0, rho=rho, nu=0.3,
                             disks=disks, theory=theory,
                             fixed_dofs=tuple((0, k) for k in range(DOFS_PER_NODE)),
                             plausibility=False)   # nondimensional units: no SI ranges apply

    def scene_rotor(self, n_modes=None):
        """The shaft as a `RotorScene` rotor: `shaft()` (all free dofs), or reduced to
        its `n_modes` lowest undamped modes (`ReducedRotor`, the basis of
        `modal_basis(n_modes)`)."""
        shaft = self.shaft()
        if n_modes is None:
            return shaft
        n_modes = as_count("n_modes", n_modes, minimum=1, maximum=DOFS_PER_NODE * self.n_elements)
        return shaft.reduce(n_modes)

    def damping_components(self) -> tuple:
        """The damping of `matrices()` as `RotorScene` components: `InternalDamping`
        (`T_V = 2 eta_i`, so `C_i = 2 eta_i K`), `ExternalDamping(2 eta_e)` (`2 eta_e M_1`)
        and `DiskDamping` at the disk (`2 eta_Dxi`, `2 eta_Dtheta`)."""
        from ._external_damping import DiskDamping, ExternalDamping
        from ._internal_damping import InternalDamping

        return (InternalDamping(2 * self.eta_i), ExternalDamping(2 * self.eta_e),
                DiskDamping(self.disk_node, 2 * self.eta_Dxi, 2 * self.eta_Dtheta))

    def matrices(self):
        """`(M, C, G1, K, Ci, J)` on the free dofs (see the module docstring)."""
        M, _, G1, K = self.shaft().reduced_matrices()
        M1 = self.shaft(density=1.0, disk=False, theory="euler-bernoulli").reduced_matrices()[0]
        d = self.disk_dofs
        C = 2 * self.eta_e * M1
        C = C.at[d[:2], d[:2]].add(2 * self.eta_Dxi).at[d[2:], d[2:]].add(2 * self.eta_Dtheta)
        J = jnp.asarray(quarter_turn_matrix(self.n_elements))
        return M, C, G1, K, 2 * self.eta_i * K, J

    def linear_matrices(self, speed) -> LinearMatrices:
        """`M q'' + (C + Ci + speed G1) q' + (K + speed Ci J) q = f` at `speed` (the
        paper's `N`) on the free dofs."""
        M, C, G1, K, Ci, J = self.matrices()
        return LinearMatrices(M, C + Ci, speed * G1, K + speed * Ci @ J)

    def state_matrix(self, speed=None, *, N=None):
        """Deprecated: `rotorjax.analysis.state_matrix(rotor, speed)`."""
        speed = speed_alias(speed, N, "N", "CantileverRotor.state_matrix")
        _deprecated("state_matrix", "rotorjax.analysis.state_matrix(rotor, speed)")
        return self.linear_matrices(speed).state_matrix()

    def eigenvalues(self, speed=None, *, N=None):
        """Deprecated: `jnp.linalg.eigvals(rotorjax.analysis.state_matrix(rotor, speed))`
        (or `rotorjax.analysis.modes(rotor, speed)`: the upper half-plane, sorted)."""
        speed = speed_alias(speed, N, "N", "CantileverRotor.eigenvalues")
        _deprecated("eigenvalues", "jnp.linalg.eigvals(rotorjax.analysis.state_matrix(rotor, speed)) or "
                    "rotorjax.analysis.modes(rotor, speed)")
        return jnp.linalg.eigvals(self.linear_matrices(jnp.asarray(speed, dtype=jnp.float64)).state_matrix())

    def stability_margin(self, speed=None, *, N=None):
        """Deprecated: `rotorjax.analysis.linear_margin(rotor, speed)`."""
        speed = speed_alias(speed, N, "N", "CantileverRotor.stability_margin")
        _deprecated("stability_margin", "rotorjax.analysis.linear_margin(rotor, speed)")
        return jnp.max(jnp.real(jnp.linalg.eigvals(self.linear_matrices(speed).state_matrix())))

    def modal_basis(self, n_modes):
        """The `n_modes` lowest undamped non-rotating modes (mass-normalised), for a
        reduced-order simulation; held fixed under differentiation."""
        n_free = DOFS_PER_NODE * self.n_elements  # node 0 is clamped
        n_modes = as_count("n_modes", n_modes, minimum=1, maximum=n_free)
        M, _, _, K, _, _ = self.matrices()
        return jax.lax.stop_gradient(undamped_modes(M, K)[1][:, :n_modes])

    def unbalance_response(self, speed=None, eps=None, phase=0.0, *, N=None):
        """Deprecated: `rotorjax.analysis.scene_unbalance_response(cantilever_scene(rotor,
        speed, eps=eps, phase=phase), [speed])[0]` (complex amplitudes of all free dofs)."""
        N = speed_alias(speed, N, "N", "CantileverRotor.unbalance_response")
        if eps is None:
            raise InputError("CantileverRotor.unbalance_response: eps (the eccentricity) is required")
        _deprecated("unbalance_response", "rotorjax.analysis.scene_unbalance_response(rotorjax.models."
                    "cantilever_scene(rotor, speed, eps=eps, phase=phase), [speed])[0]")
        lin, d = self.linear_matrices(N), self.disk_dofs
        fx = eps * N**2 * jnp.exp(1j * phase)
        F = jnp.zeros(lin.M.shape[0], dtype=jnp.complex128).at[d[0]].set(fx).at[d[1]].set(-1j * fx)
        return frequency_response(lin.M, lin.C + lin.G, lin.K, F, N)

    def whirl_direction(self, speed=None, *, N=None):
        """Deprecated: `rotorjax.analysis.least_stable_whirl(rotor, speed, rotor.disk_dofs[:2])`."""
        speed = speed_alias(speed, N, "N", "CantileverRotor.whirl_direction")
        _deprecated("whirl_direction", "rotorjax.analysis.least_stable_whirl(rotor, speed, rotor.disk_dofs[:2])")
        lam, vec = jnp.linalg.eig(self.linear_matrices(jnp.asarray(speed, dtype=jnp.float64)).state_matrix())
        k = jnp.argmax(jnp.real(lam) + 1e-9 * jnp.sign(jnp.imag(lam)))  # the Im > 0 member
        x, y = vec[self.disk_dofs[0], k], vec[self.disk_dofs[1], k]
        fwd = jnp.abs(x + 1j * y) >= jnp.abs(x - 1j * y)
        return lam[k], jnp.where(jnp.imag(lam[k]) >= 0, fwd, ~fwd)


def _deprecated(method, instead):
    warnings.warn(f"CantileverRotor.{method} is deprecated (analyses live in rotorjax.analysis): use {instead}",
                  DeprecationWarning, stacklevel=3)
