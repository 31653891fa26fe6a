"""Model 002: a rigid rotor on a two-support balancing machine (Polushkin et al.
2016), with vector (complex) influence coefficients.

Coordinates: the support displacements `x1, x2` (horizontal plane). With rotor
mass `m`, transverse inertia `I` about the centre, span `l` (centre of mass
mid-span), support stiffness `k1, k2` and damping `c1, c2` (eq. 9):

    A = [[m/4 + I/l^2, m/4 - I/l^2], [m/4 - I/l^2, m/4 + I/l^2]],
    B = diag(c1, c2),  C = diag(k1, k2).

An unbalance `D = |D| e^{i phi}` (kg m) in a correction plane at distance `a` from
support 1 gives the force `Re(D w^2 e^{i w t}) (l - a, a) / l` (eq. 8), so the
support vibration `x = Re(X e^{i w t})` has the complex amplitudes
`X = K(w, a) D` with the vector influence coefficients (eqs. 15, 17)

    K(w, a) = (w^2 / l) (C - w^2 A + i w B)^-1 (l - a, a),

the one frequency-response solve (`rotorjax.models._frequency`) with `M = A`,
damping `B`, stiffness `C`.

Two classes: `BalancingMachine` is the rotor on its supports (what identification
fits: seven parameters, vmapped); `BalancingScene` is that machine with its
correction planes, unbalances and a speed profile, an `AbstractScene` (eq. 8 under
the rotating unbalance force as a vector field `f(t, y, args)` that
`rotorjax.simulate` integrates, linear matrices, unbalance load).

Phase convention (used everywhere in `rotorjax.identify`): angles are measured
from the once-per-revolution mark in the direction of rotation; a vibration
`x(t) = Re(X e^{i theta(t)})` with `theta` the rotor angle (0 at the mark).
"""

import warnings

import equinox as eqx
import jax
import jax.numpy as jnp
import numpy as np

from ._contract import AbstractLinearScene, LinearMatrices
from ._frequency import dynamic_stiffness, frequency_response
from ._parameters import ParameterPath, Target
from ._speed import AbstractSpeedProfile, ConstantSpeed
from ._validate import InputError, as_numpy, as_param, check_type, is_concrete


class BalancingMachine(eqx.Module):
    """The rotor on its two supports (SI: kg, kg m^2, m, N/m, N s/m)."""

    m: jax.Array
    I: jax.Array
    l: jax.Array
    k1: jax.Array
    k2: jax.Array
    c1: jax.Array
    c2: jax.Array

    def __init__(self, m, I, l, k1, k2, c1, c2):
        self.m = as_param("m (rotor mass)", m, sign="positive", shape=())
        self.I = as_param("I (transverse inertia)", I, sign="positive", shape=())
        self.l = as_param("l (support span)", l, sign="positive", shape=())
        self.k1 = as_param("k1 (support 1 stiffness)", k1, sign="positive", shape=())
        self.k2 = as_param("k2 (support 2 stiffness)", k2, sign="positive", shape=())
        self.c1 = as_param("c1 (support 1 damping)", c1, sign="nonnegative", shape=())
        self.c2 = as_param("c2 (support 2 damping)", c2, sign="nonnegative", shape=())

    #: its parameters: the fields, each a leaf (`parameter_path`)
    PARAMETERS = ("m", "I", "l", "k1", "k2", "c1", "c2")

    @staticmethod
    def parameter_path(name) -> ParameterPath:
        """The `ParameterPath` of the parameter `name` (`k1`, `c2`, `m`, ...): its field,
        set through `rotorjax.models._parameters.with_values` as a rotor file's are
        (`eqx.tree_at`; every entry of the support matrices is affine in it but `m`, `I`,
        `l`, which enter the mass matrix through `I / l^2`)."""
        if name not in BalancingMachine.PARAMETERS:
            raise InputError(f"{name!r} is not a parameter of the balancing machine; its parameters: "
                             f"{', '.join(BalancingMachine.PARAMETERS)}")
        return ParameterPath(name, (Target((name,)),), name in ("k1", "k2", "c1", "c2"))

    def matrices(self):
        """`(A, B, C)` of eq. (9)."""
        p, q = self.m / 4 + self.I / self.l**2, self.m / 4 - self.I / self.l**2
        A = jnp.array([[p, q], [q, p]])
        return A, jnp.diag(jnp.stack([self.c1, self.c2])), jnp.diag(jnp.stack([self.k1, self.k2]))

    def dynamic_stiffness(self, speed):
        """`C - speed^2 A + i speed B` at the running speed `speed` (rad/s)."""
        A, B, C = self.matrices()
        return dynamic_stiffness(A, B, C, speed)

    def lever(self, planes):
        """`(l - a_j, a_j) / l`: how a plane's force splits between the supports, `(2, n_planes)`."""
        planes = jnp.asarray(planes, dtype=jnp.float64)
        return jnp.stack([self.l - planes, planes]) / self.l

    def influence(self, speed, a):
        """Vector influence coefficients `(K_1, K_2)` of a plane at distance `a` from
        support 1, at speed `speed` (rad/s; the paper's `w`): eqs. (15), (17). Vmap over
        `speed` and `a`."""
        A, B, C = self.matrices()
        load = jnp.stack([self.l - a, a]).astype(jnp.complex128)
        return speed**2 / self.l * frequency_response(A, B, C, load, speed)

    def influence_matrix(self, speed, planes):
        """`K[i, j]`: support `i`, plane `j` at `planes[j]` (distances from support 1)."""
        _check_planes(planes)
        return jax.vmap(lambda a: self.influence(speed, a), out_axes=1)(jnp.asarray(planes, dtype=jnp.float64))

    def response(self, speed, planes, unbalances):
        """Deprecated: `rotorjax.analysis.balancing_response(machine, speed, planes,
        unbalances)` (the complex support amplitudes `X = K(speed) D`)."""
        warnings.warn("BalancingMachine.response is deprecated (analyses live in rotorjax.analysis): use "
                      "rotorjax.analysis.balancing_response(machine, speed, planes, unbalances)",
                      DeprecationWarning, stacklevel=2)
        n = _check_planes(planes)
        if is_concrete(unbalances):
            as_numpy("unbalances", unbalances, shape=(n,), dtype=np.complex128)
        return self.influence_matrix(speed, planes) @ jnp.asarray(unbalances, dtype=jnp.complex128)

    def unbalance_force(self, theta, theta_d, theta_dd, planes, unbalances):
        """The support forces of eq. (8) at the rotor angle `theta` with speed `theta_d`
        and acceleration `theta_dd`: `sum_j Re(D_j (theta_d^2 - i theta_dd) e^{i theta})
        (l - a_j, a_j) / l` (N, shape `(2,)`; the tangential part is that of a run-up)."""
        amp = jnp.real(jnp.asarray(unbalances) * (theta_d**2 - 1j * theta_dd) * jnp.exp(1j * theta))
        return self.lever(planes) @ amp


class BalancingScene(AbstractLinearScene):
    """A `BalancingMachine` with unbalances `D_j` (kg m, complex, angles from the
    mark) in correction planes at `a_j` (m from support 1), spun by a speed
    profile: model 002 as a scene.

    State `y = (x1, x2, x1', x2')` (m, m/s); outputs `x1`, `x2`. Linear matrices
    `M = A`, `C = B`, `G = 0`, `K = C` of eq. (9) at every speed; the unbalance load
    at speed `w` is `F = (w^2 / l) sum_j D_j (l - a_j, a_j)`, so
    `frequency_response(M, C, K, F, w)` is
    `rotorjax.analysis.balancing_response(machine, w, planes, unbalances)`.

    **Arguments:** `machine`, `planes` (1-D, distinct, within `[0, l]`),
    `unbalances` (complex, one per plane), `speed` (an `AbstractSpeedProfile` or a
    constant speed in rad/s; default 0).
    """

    machine: BalancingMachine
    planes: jax.Array
    unbalance_re: jax.Array   # real leaves (diffrax integrates real pytrees): D = re + i im
    unbalance_im: jax.Array
    speed: AbstractSpeedProfile

    def __init__(self, machine, planes, unbalances, speed=0.0):
        check_type("machine", machine, BalancingMachine, "a BalancingMachine")
        n = _check_planes(planes)
        if is_concrete(planes):
            a = np.asarray(planes, dtype=np.float64)
            if is_concrete(machine.l):
                l = float(machine.l)
                if np.any(a < 0) or np.any(a > l) or np.unique(a).size != a.size:
                    raise InputError(f"planes {a.tolist()} must be distinct positions within the span [0, l={l}] "
                                     "(distances from support 1)")
        if is_concrete(unbalances):
            as_numpy("unbalances", unbalances, shape=(n,), dtype=np.complex128)
        self.machine = machine
        self.planes = jnp.asarray(planes, dtype=jnp.float64)
        unbalances = jnp.asarray(unbalances, dtype=jnp.complex128)
        self.unbalance_re, self.unbalance_im = jnp.real(unbalances), jnp.imag(unbalances)
        self.speed = speed if isinstance(speed, AbstractSpeedProfile) else ConstantSpeed(speed)

    @property
    def unbalances(self) -> jax.Array:
        """The unbalances `D_j` (kg m, complex)."""
        return self.unbalance_re + 1j * self.unbalance_im

    @property
    def state_size(self) -> int:
        return 4

    @property
    def n_dof(self) -> int:
        return 2

    def describe(self) -> str:
        return f"balancing machine, {self.planes.shape[0]} correction plane(s)"

    def vector_field(self, t, y, args=None):
        """`y' = f(t, y, args)` (the diffrax convention; `args` unused): eq. (8),
        `A x'' + B x' + C x = F(theta, theta', theta'')`, the unbalance force
        (`BalancingMachine.unbalance_force`) at the angle, speed and acceleration
        of the scene's speed profile at `t`."""
        s = self.speed
        A, B, C = self.machine.matrices()
        x, v = y[:2], y[2:]
        f = self.machine.unbalance_force(s.angle(t), s.speed(t), s.acceleration(t), self.planes, self.unbalances)
        return jnp.concatenate([v, jnp.linalg.solve(A, f - B @ v - C @ x)])

    def outputs(self, t, y) -> dict:
        return {"x1": y[0], "x2": y[1]}

    def linear_matrices(self, speed) -> LinearMatrices:
        A, B, C = self.machine.matrices()
        return LinearMatrices(M=A, C=B, G=jnp.zeros_like(A), K=C)

    def unbalance_load(self, speed) -> jax.Array:
        return speed**2 * (self.machine.lever(self.planes) @ self.unbalances)

    def steady_state(self, speed):
        """The state on the steady response at constant speed `speed` and angle 0 (an
        initial state for runs that start on it)."""
        lm = self.linear_matrices(speed)
        X = frequency_response(lm.M, lm.C + lm.G, lm.K, self.unbalance_load(speed), speed)
        return jnp.concatenate([jnp.real(X), jnp.real(1j * speed * X)])


def _check_planes(planes):
    """Plane distances from support 1: a 1-D array of >= 1 finite values; returns their count."""
    if is_concrete(planes):
        as_numpy("planes", planes, ndim=1)
    n = np.shape(planes)
    if len(n) != 1 or n[0] < 1:
        raise InputError(f"planes must be a 1-D array of >= 1 plane distances, got shape {n}")
    return n[0]


def scalar_influence_matrix(l, planes_a):
    """The static "scalar" coefficients of eq. (3), for two planes at `A` from
    support 1 and `C` from support 2: `(l - A - C)^-1 [[l - A, A], [C, l - C]]`
    (the distribution of a plane's unbalance between the supports, without
    the machine's dynamics)."""
    l = float(as_numpy("l (support span)", l, sign="positive", shape=()))
    A, C = (float(v) for v in as_numpy("planes_a (plane distances A, C)", planes_a, shape=(2,)))
    if abs(l - A - C) <= 1e-12 * l:
        raise InputError(f"planes_a (plane distances A, C): the two planes coincide (A + C = l), so the "
                         f"coefficients are singular; got A = {A}, C = {C}, l = {l}")
    return jnp.array([[l - A, A], [C, l - C]]) / (l - A - C)
