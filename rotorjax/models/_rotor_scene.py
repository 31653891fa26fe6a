"""The finite-element rotor as a scene: a shaft with disks and bearings, spun by a
speed profile, plus only the components a study needs.

Coordinates: the rotor's (`FlexibleRotor`: its free dofs; `ReducedRotor`: the
amplitudes of its lowest undamped modes), then each component's own (an
auto-balancer's weights). State `y = (q, q', [W])`, `W` the work of every force
but the symmetric stiffness (with `track_work`), so that `energy(y(t)) -
energy(y(0)) = W(t)` checks an integration.

Equations: the linear part, with each component's linear contribution added,

    M q'' + (C + speed G1) q' + (K + speed K_s) q = P^T (F_static + sum_k f_k(t, x, x')),

where `f_k` are the components' remaining (nonlinear, time-dependent) forces on
the shaft's physical dofs `x = P q` (`P` expands free or modal coordinates to all
dofs: with a reduced rotor the linear part is modal, the nonlinear forces act at
physical dofs). With components that own coordinates the equations come from
Lagrange's equations of the summed energies with these forces added.
"""

import equinox as eqx
import jax
import jax.numpy as jnp
import numpy as np

from ._contract import (AbstractContactScene, AbstractEnergyScene, AbstractLinearScene, AbstractLocalScene,
                        AbstractReducibleScene, AbstractRotatingScene, AbstractShaftModel, LinearMatrices, LocalForces,
                        MissingCapability)
from ._fe_reduction import ReducedRotor, undamped_modes
from ._fe_rotor import DOFS_PER_NODE, FlexibleRotor
from ._base import Kinematics
from ._equilibrium import equilibrium_matrices, films, has_films
from ._lagrange import lagrange_terms
from ._rotation import to_fixed_pair, to_rotating_pair
from ._rotor_component import AbstractRotorComponent, NodeLoad, ShaftState
from ._speed import AbstractSpeedProfile, ConstantSpeed
from ._validate import InputError, as_components, show


def _coords(rotor, a_full):
    """A full-dof matrix in the rotor's coordinates (free dofs, or modal)."""
    f = rotor.free_dofs
    a = a_full[np.ix_(f, f)]
    if isinstance(rotor, ReducedRotor):
        a = rotor.basis.T @ a @ rotor.basis
    return a


def _load(rotor, f_full):
    """A full-dof load in the rotor's coordinates."""
    f = rotor.free_dofs
    if f.size and f[-1] - f[0] == f.size - 1:   # contiguous: a slice, cheaper than a gather per step
        return rotor.project(f_full[int(f[0]):int(f[-1]) + 1])
    return rotor.project(f_full[f])


@eqx.filter_jit
def _assemble(rotor, table_speed, components):
    """The scene's linear part `(M, Minv, C, G1, K, Ks, F0)`: the rotor's matrices at
    `table_speed` with each component's linearisation and static load added. One
    compiled program per rotor layout (and kept by the persistent compilation
    cache), instead of hundreds of small operations dispatched one by one."""
    full = rotor.full_rotor
    M, C, G1, K = rotor.reduced_matrices(table_speed)
    n_full = full.n_dofs
    Cf, Kf, Ksf = (jnp.zeros((n_full, n_full)) for _ in range(3))
    F0 = jnp.zeros(n_full)
    for c in components:
        part = c.linear_part(full)
        if part is not None:
            Cf, Kf, Ksf = Cf + part[0], Kf + part[1], Ksf + part[2]
        load = c.static_load(full)
        if load is not None:
            F0 = F0 + load
    return (M, jnp.linalg.inv(M), C + _coords(rotor, Cf), G1, K + _coords(rotor, Kf), _coords(rotor, Ksf),
            _load(rotor, F0), rotor.expand(jnp.eye(M.shape[0])))


class RotorScene(AbstractLinearScene, AbstractShaftModel, AbstractRotatingScene, AbstractContactScene,
                 AbstractEnergyScene, AbstractReducibleScene, AbstractLocalScene):
    """A finite-element rotor scene (see the module docstring).

    **Arguments:**
    - `rotor`: a `FlexibleRotor`, or a `ReducedRotor` (`rotor.reduce(n_modes)`)
      for a modal linear part.
    - `speed`: a speed profile (rad/s), or a number for a constant speed.
    - `components`: rotor components (`Unbalance`, `Gravity`, `InternalDamping`,
      `CubicBearing`, `ClearanceBearing`, `BalancerAt`, `LimitersAt`).
    - `track_work`: add the work state `W` (energy balance checks).
    """

    rotor: eqx.Module
    speed: AbstractSpeedProfile
    components: tuple
    track_work: bool = eqx.field(static=True)
    M: jax.Array
    Minv: jax.Array
    C: jax.Array
    G1: jax.Array
    K: jax.Array
    Ks: jax.Array          # per unit speed (circulatory)
    F0: jax.Array          # static load, in the coordinates
    E: jax.Array           # shaft coordinates -> all dofs (the basis, padded with the fixed dofs)
    Ksym: jax.Array        # the symmetric part of K (the potential energy)
    L: jax.Array           # [[K, C], [Ks, G1] (, [Ksym, 0])] on (q, q'): the linear part in one product

    def __init__(self, rotor, speed=0.0, components=(), track_work=False):
        if not isinstance(rotor, (FlexibleRotor, ReducedRotor)):
            raise InputError(f"rotor must be a FlexibleRotor or ReducedRotor, got {type(rotor).__name__}")
        if not isinstance(speed, AbstractSpeedProfile):
            speed = ConstantSpeed(speed)
        components = as_components(components, AbstractRotorComponent, "rotor component",
                                   "Unbalance, BalancerAt, LimitersAt, ...")
        full = rotor.full_rotor
        for i, c in enumerate(components):
            if c.node is not None and not c.node < full.n_nodes:
                raise InputError(f"components[{i}] ({c.describe()}): the shaft has nodes 0..{full.n_nodes - 1}")
        if track_work and any(c.n_coords for c in components):
            raise InputError("track_work: the energy balance is kept for shafts without components that own "
                             "coordinates (an auto-balancer's weights)")
        self.rotor, self.speed, self.components, self.track_work = rotor, speed, components, bool(track_work)
        # tabulated bearings: the time-domain equations use the coefficients at the
        # profile's initial speed; `linear_matrices(speed)` re-evaluates them
        self.M, self.Minv, self.C, self.G1, self.K, self.Ks, self.F0, self.E = _assemble(
            rotor, jnp.asarray(self._table_speed(), dtype=jnp.float64), components)
        self.Ksym = 0.5 * (self.K + self.K.T)
        zero = jnp.zeros_like(self.K)
        rows = [[self.K, self.C], [self.Ks, self.G1]] + ([[self.Ksym, zero]] if self.track_work else [])
        self.L = jnp.block(rows)

    # --- coordinates -------------------------------------------------------------------
    def _coords(self, a_full):
        return _coords(self.rotor, a_full)

    def _load(self, f_full):
        return _load(self.rotor, f_full)

    @property
    def n_shaft(self) -> int:
        """Number of shaft coordinates (free dofs, or modes)."""
        return self.M.shape[0]

    @property
    def n_dof(self) -> int:
        return self.n_shaft + sum(c.n_coords for c in self.components)

    @property
    def state_size(self) -> int:
        return 2 * self.n_dof + (1 if self.track_work else 0)

    @property
    def full_rotor(self):
        """The `FlexibleRotor` of the shaft (a reduced one's full rotor)."""
        return self.rotor.full_rotor

    @property
    def n_coordinates(self) -> int:
        return self.n_shaft

    def reduced_matrices(self, speed=0.0):
        """The bare shaft's `(M, C, G1, K)` in the shaft coordinates (no component's
        linearisation: that is `linear_matrices`)."""
        return self.rotor.reduced_matrices(speed)

    def project(self, f):
        """A load on the free dofs to the shaft coordinates."""
        return self.rotor.project(f)

    @property
    def n_contacts(self) -> int:
        return sum(c.n_contacts for c in self.components)

    def _own_slices(self):
        start, out = self.n_shaft, []
        for c in self.components:
            out.append(slice(start, start + c.n_coords))
            start += c.n_coords
        return out

    def _contact_slices(self):
        start, out = 0, []
        for c in self.components:
            out.append(slice(start, start + c.n_contacts))
            start += c.n_contacts
        return out

    def shaft_state(self, t, q, qd) -> ShaftState:
        """The shaft's physical state at `t` from the coordinates `q, q'` (all of them)."""
        t = jnp.asarray(t, dtype=jnp.float64)
        ns = self.n_shaft
        return ShaftState(t=t, theta=self.speed.angle(t), theta_dot=self.speed.speed(t),
                          theta_ddot=self.speed.acceleration(t), q=q[:ns], qd=qd[:ns], E=self.E)

    def split(self, y):
        n = self.n_dof
        return y[:n], y[n:2 * n]

    # --- equations ----------------------------------------------------------------------
    def _forces(self, t, q, qd, active):
        """Generalised force on the shaft coordinates (linear part and components), and
        the shaft state."""
        f, s, _ = self._forces_and_ksym(t, q, qd, active)
        return f, s

    def _forces_and_ksym(self, t, q, qd, active):
        """`_forces`, with `Ksym q` from the same product when the work is tracked."""
        ns = self.n_shaft
        s = self.shaft_state(t, q, qd)
        at_nodes, f_full = {}, None
        for c, sl, cs in zip(self.components, self._own_slices(), self._contact_slices()):
            f = c.force(s, q[sl], qd[sl], None if active is None else active[cs])
            if isinstance(f, NodeLoad):   # summed per node, then through the node's two rows
                at_nodes[f.node] = f.f if f.node not in at_nodes else at_nodes[f.node] + f.f
            elif f is not None:
                f_full = f if f_full is None else f_full + f
        gen = self.F0
        for node, f2 in at_nodes.items():
            gen = gen + self._node_rows(node).T @ f2
        if f_full is not None:
            gen = gen + self._load(f_full)
        # one product `L (q, q')`, then the speed: under vmap each lane may have its own
        # speed, and summing matrices per lane costs more than the products
        a = self.L @ jnp.concatenate([q[:ns], qd[:ns]])
        return gen - (a[:ns] + s.theta_dot * a[ns:2 * ns]), s, a[2 * ns:]

    def vector_field(self, t, y, args=None):
        """`dy/dt`; `args` is the contact set (booleans, one per contact) for
        event-located integration, `None` for smooth contact laws."""
        q, qd = self.split(y)
        f, _, ksym_q = self._forces_and_ksym(t, q, qd, args)
        if any(c.n_coords for c in self.components):
            qdd = self._with_own_coordinates(t, q, qd, f)
        else:
            qdd = self.Minv @ f
        out = [qd, qdd]
        if self.track_work:
            ns = self.n_shaft
            power = qd[:ns] @ (f + ksym_q)
            out.append(power[None])
        return jnp.concatenate(out)

    def _Ksym(self):
        return self.Ksym

    def _node_rows(self, node):
        """`P_k`: the node's `(x, y)` as a linear map of the shaft coordinates."""
        b = DOFS_PER_NODE * node
        return self.E[b:b + 2]

    def _with_own_coordinates(self, t, q, qd, f):
        """Accelerations with components that own coordinates: each one's Lagrange
        equations in its local coordinates `r = (x_k, y_k, own)` (a few, so the
        autodiff is small), assembled with `r = A q`, `A` the node's rows and the
        identity on its own coordinates: `M = M_shaft + sum A^T M_r A`,
        `rhs = f + sum A^T f_r`."""
        ns, n = self.n_shaft, self.n_dof
        t = jnp.asarray(t, dtype=jnp.float64)
        mass = jnp.zeros((n, n)).at[:ns, :ns].set(self.M)
        rhs = jnp.concatenate([f, jnp.zeros(n - ns)])
        for c, sl in zip(self.components, self._own_slices()):
            if not c.n_coords:
                continue
            A = jnp.zeros((2 + c.n_coords, n)).at[:2, :ns].set(self._node_rows(c.node))
            A = A.at[2:, sl].set(jnp.eye(c.n_coords))
            m_r, f_r = lagrange_terms(lambda r, rd, tt: self._local_lagrangian(c, r, rd, tt),
                                      lambda r, rd, tt: c.dissipation(self._local_kinematics(r, rd, tt), r[2:],
                                                                      rd[2:]),
                                      A @ q, A @ qd, t)
            mass, rhs = mass + A.T @ m_r @ A, rhs + A.T @ f_r
        return jnp.linalg.solve(mass, rhs)

    def _local_kinematics(self, r, rd, t) -> Kinematics:
        return Kinematics(t=t, theta=self.speed.angle(t), theta_dot=self.speed.speed(t), x=r[0], y=r[1],
                          xd=rd[0], yd=rd[1])

    def _local_lagrangian(self, c, r, rd, t):
        kin = self._local_kinematics(r, rd, t)
        return c.kinetic(kin, r[2:], rd[2:]) - c.potential(kin, r[2:])

    # --- capabilities -------------------------------------------------------------------
    def linear_matrices(self, speed) -> LinearMatrices:
        """The linear equations at `speed`, in the shaft coordinates (tabulated
        bearings at `speed`): about the straight, resting shaft (weights of an
        auto-balancer frozen), or, on fluid films (journal bearings, squeeze-film
        dampers), about the static equilibrium at `speed` with the films'
        linearisation (`rotorjax.models.static_equilibrium`; NaN where it is not found)."""
        if has_films(self):
            return equilibrium_matrices(self, speed)
        return self._linear_about_rest(speed)

    def local_forces(self) -> LocalForces | None:
        """The equations at the constant speed `w` split (`LocalForces`): the linear
        part `A` of `(q, q')` with `K + w K_s`, `C + w G1`, `a0` the static load's
        acceleration, and the components' forces at their nodes (`force(t, x, v)`:
        `x`, `v` the displacements and velocities `(x, y)` of the nodes whose forces
        read the motion, in node order; the forces at those nodes, then at the others
        with a force, an unbalance's). None with components that own coordinates or
        load all dofs, a work state, or a speed that varies."""
        if self.track_work or not isinstance(self.speed, ConstantSpeed) or any(c.n_coords for c in self.components):
            return None
        probe = self.shaft_state(0.0, jnp.zeros(self.n_shaft), jnp.zeros(self.n_shaft))
        loads = [(c, c.force(probe, jnp.zeros(0), jnp.zeros(0))) for c in self.components]
        if any(f is not None and not isinstance(f, NodeLoad) for _, f in loads):
            return None
        loaded = [c for c, f in loads if f is not None]
        reads = sorted({c.node for c in loaded if c.reads_motion})
        nodes = reads + sorted({c.node for c in loaded} - set(reads))
        ns, w = self.n_shaft, self.speed.constant
        K, C = self.L[:ns, :ns] + w * self.L[ns:2 * ns, :ns], self.L[:ns, ns:2 * ns] + w * self.L[ns:2 * ns, ns:2 * ns]
        A = jnp.block([[jnp.zeros((ns, ns)), jnp.eye(ns)], [-self.Minv @ K, -self.Minv @ C]])
        R = jnp.concatenate([self._node_rows(k) for k in nodes]) if nodes else jnp.zeros((0, ns))
        E = jnp.concatenate([jnp.zeros((ns, R.shape[0])), self.Minv @ R.T])
        # the read nodes' rows of an all-dof map from (x, v): each component reads its node as on the shaft
        picks = np.zeros((DOFS_PER_NODE * self.full_rotor.n_nodes, 2 * len(reads)))
        for i, k in enumerate(reads):
            picks[DOFS_PER_NODE * k:DOFS_PER_NODE * k + 2, 2 * i:2 * i + 2] = np.eye(2)
        picks = jnp.asarray(picks)

        def force(t, x, v):
            t = jnp.asarray(t, dtype=jnp.float64)
            s = ShaftState(t=t, theta=self.speed.angle(t), theta_dot=self.speed.speed(t),
                           theta_ddot=self.speed.acceleration(t), q=x, qd=v, E=picks)
            total = {k: jnp.zeros(2) for k in nodes}
            for c in loaded:
                f = c.force(s, jnp.zeros(0), jnp.zeros(0))
                total[f.node] = total[f.node] + f.f
            return jnp.concatenate([total[k] for k in nodes]) if nodes else jnp.zeros(0)

        return LocalForces(A=A, a0=jnp.concatenate([jnp.zeros(ns), self.Minv @ self.F0]),
                           S=R[:2 * len(reads)], E=E, force=force)

    def _linear_about_rest(self, speed) -> LinearMatrices:
        """About the straight, resting shaft: the linear parts only."""
        M, C, K = self.M, self.C, self.K
        if self.rotor.speed_dependent:
            now, then = self.rotor.reduced_matrices(speed), self.rotor.reduced_matrices(self._table_speed())
            M, C, K = M + now[0] - then[0], C + now[1] - then[1], K + now[3] - then[3]
        return LinearMatrices(M=M, C=C, G=speed * self.G1, K=K + speed * self.Ks)

    def _table_speed(self):
        """The speed at which the time-domain equations take tabulated bearings' coefficients."""
        if not self.rotor.speed_dependent:
            return 0.0
        return self.speed.speed(jnp.zeros(()))

    def unbalance_load(self, speed):
        full = self.rotor.full_rotor
        total = jnp.zeros(full.n_dofs, dtype=jnp.complex128)
        found = False
        for c in self.components:
            load = c.unbalance_load(full, speed)
            if load is not None:
                total, found = total + load, True
        if not found:
            raise MissingCapability(f"RotorScene ({self.describe()}) has no Unbalance component")
        return self.rotor.project(total[self.rotor.free_dofs])

    def expand(self, q_shaft):
        """Shaft coordinates (vector or columns) to all dofs."""
        return self.rotor.expand(q_shaft)

    def without_work(self):
        if not self.track_work:
            return self
        return RotorScene(self.rotor, self.speed, self.components, track_work=False)

    def energy(self, y):
        """`q'^T M q' / 2 + q^T K_sym q / 2` (shaft coordinates; every other force's
        work is in the work state)."""
        ns = self.n_shaft
        q, qd = self.split(y)
        return 0.5 * qd[:ns] @ (self.M @ qd[:ns]) + 0.5 * q[:ns] @ (self._Ksym() @ q[:ns])

    def check_state(self, y) -> None:
        """Refuse a state with a fluid film's journal at or beyond its wall."""
        q, qd = self.split(jnp.asarray(y))
        s = self.shaft_state(0.0, q, qd)
        for c in films(self):
            eps = float(c.eccentricity(s))
            if not eps < 1.0:
                raise InputError(f"y0: the {c.label} starts at eccentricity {eps:.4g} (its journal at "
                                 f"{show(s.position(c.node))} m, clearance {show(c.clearance)} m): a journal must "
                                 f"start inside its clearance (eccentricity < 1)")

    def contact_indicator(self, t, y):
        q, qd = self.split(y)
        s = self.shaft_state(t, q, qd)
        parts = [c.contact_indicator(s, q[sl], qd[sl]) for c, sl in zip(self.components, self._own_slices())
                 if c.n_contacts]
        return jnp.concatenate(parts) if parts else jnp.zeros(0)

    def _check_rotating(self):
        if isinstance(self.rotor, ReducedRotor):
            raise MissingCapability("RotorScene: the rotating frame needs the full FE rotor (a modal basis of "
                                    "an isotropic rotor is not closed under rotation): build it without reduce()")
        fixed = set(self.rotor.fixed_dofs)
        for d in fixed:
            pair = d + 1 if d % 2 == 0 else d - 1
            if pair not in fixed:
                raise MissingCapability(f"RotorScene: the rotating frame needs x and y (and sx and sy) fixed "
                                        f"together; dof {d} is fixed, dof {pair} is not")

    def _pairs(self, t, y, inverse):
        self._check_rotating()
        n, ns = self.n_dof, self.n_shaft
        th, thd = self.speed.angle(t), self.speed.speed(t)
        f = self.rotor.free_dofs
        x = self.rotor.expand(y[:ns]).reshape(-1, 2).T      # rows: (x, sx...), (y, sy...)
        v = self.rotor.expand(y[n:n + ns]).reshape(-1, 2).T
        move = to_fixed_pair if inverse else to_rotating_pair
        u, ud = move(th, thd, x, v)
        qs = u.T.reshape(-1)[f]
        qsd = ud.T.reshape(-1)[f]
        return jnp.concatenate([qs, y[ns:n], qsd, y[n + ns:]])

    def to_rotating(self, t, y):
        """Every node's displacement and slope pairs turned into the frame spinning
        with the rotor (own coordinates are relative to the rotor already)."""
        return self._pairs(t, y, inverse=False)

    def to_fixed(self, t, z):
        return self._pairs(t, z, inverse=True)

    def weight_coordinates(self):
        from ._node_parts import BalancerAt
        from ._validate import is_concrete

        for c, sl in zip(self.components, self._own_slices()):
            if isinstance(c, BalancerAt):
                m = c.balancer.mass
                same = is_concrete(m) and bool(np.all(np.asarray(m) == np.asarray(m)[0]))
                return np.arange(sl.start, sl.stop), same
        return np.zeros(0, dtype=int), True

    # --- modal reduction ---------------------------------------------------------------
    @property
    def reducible(self) -> bool:
        return isinstance(self.rotor, FlexibleRotor)

    def reduction_basis(self):
        """`(w, Phi)`: the bare shaft's undamped modes at rest (bearings included),
        ascending, mass-normalised: the basis `FlexibleRotor.reduce` keeps the first
        columns of."""
        M, _, _, K = self.full_rotor.reduced_matrices()
        w2, phi = undamped_modes(M, K)
        return np.sqrt(np.maximum(np.asarray(w2), 0.0)), np.asarray(phi)

    def _whole(self, what):
        if not self.reducible:
            raise InputError(f"{what}: the shaft is already reduced ({self.rotor.n_modes} modes)")

    def reduce(self, n_modes) -> "RotorScene":
        """This scene with its shaft reduced to the `n_modes` lowest undamped modes
        (`FlexibleRotor.reduce`): speed, components and work state kept."""
        self._whole("reduce")
        return RotorScene(self.rotor.reduce(n_modes), self.speed, self.components, self.track_work)

    def reduction_maps(self, n_modes):
        """`(E, P)` for the state of `reduce(n_modes)`: `y = E y_r` expands a reduced
        state, `y_r = P y` projects a state on the mass-normalised modes (`Phi^T M`
        on the shaft's displacements and velocities; the components' coordinates and
        the work kept), `P E = I`. The reduced linearisation is about `P J E` (exact
        for the shaft's own terms)."""
        self._whole("reduction_maps")
        M = np.asarray(self.rotor.reduced_matrices()[0])
        phi = self.reduction_basis()[1][:, :n_modes]
        n_c = self.n_dof - self.n_shaft
        blocks = lambda shaft: [shaft, np.eye(n_c), shaft, np.eye(n_c)] + [np.eye(1)] * self.track_work  # noqa: E731
        return jax.scipy.linalg.block_diag(*blocks(phi)), jax.scipy.linalg.block_diag(*blocks(phi.T @ M))

    def rest_state(self, angles=None):
        """The straight shaft at rest, weights spread evenly (or at `angles`)."""
        parts = [jnp.zeros(self.n_shaft)]
        for c in self.components:
            if c.n_coords:
                parts.append(c.rest_coords() if angles is None else jnp.asarray(angles, dtype=jnp.float64))
        q = jnp.concatenate(parts)
        extra = [jnp.zeros(1)] if self.track_work else []
        return jnp.concatenate([q, jnp.zeros_like(q)] + extra)

    def state_from_response(self, Q, speed, t=0.0):
        """The fixed-frame state at `t` of the synchronous motion `q = Re(Q e^{i speed t})`
        of the shaft coordinates (own coordinates at rest)."""
        e = jnp.exp(1j * speed * t)
        q, qd = jnp.real(Q * e), jnp.real(1j * speed * Q * e)
        y = self.rest_state()
        ns, n = self.n_shaft, self.n_dof
        return y.at[:ns].set(q).at[n:n + ns].set(qd)

    # --- outputs ------------------------------------------------------------------------
    def outputs(self, t, y):
        """`node_x`, `node_y` (m, every node), `whirl_amplitude` (the largest node
        orbit radius), each component's own outputs, and `energy`, `work` with
        `track_work`."""
        q, qd = self.split(y)
        s = self.shaft_state(t, q, qd)
        # the nodes' (x, y) rows of E only (not the slopes, nor supports' pedestals)
        n = self.n_nodes
        nx = self.E[0:DOFS_PER_NODE * n:DOFS_PER_NODE] @ s.q
        ny = self.E[1:DOFS_PER_NODE * n:DOFS_PER_NODE] @ s.q
        out = {"node_x": nx, "node_y": ny, "whirl_amplitude": jnp.sqrt(jnp.max(nx**2 + ny**2))}
        for c, sl in zip(self.components, self._own_slices()):
            out.update(c.outputs(s, q[sl], qd[sl]))
        if self.track_work:
            out["energy"] = self.energy(y)
            out["work"] = y[-1]
        return out

    def describe(self) -> str:
        full = self.rotor.full_rotor
        base = f"FE rotor ({full.lengths.shape[0]} elements, {self.n_shaft} coordinates)"
        return ", ".join([base] + [c.describe() for c in self.components])
