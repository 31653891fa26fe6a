"""Passive auto-balancer: N correction weights running in a race on the rotor."""

import jax
import jax.numpy as jnp
import equinox as eqx
import numpy as np

from ._base import AbstractComponent, Kinematics
from ._validate import (InputError, as_count, as_numpy, as_param, check, check_choice, check_type,
                        is_concrete, show)

#: Inertia factor `K` by weight type (a ball rolling in its race carries 7/5 of its
#: translational inertia along the race, a roller 3/2, a pendulum bob 1).
INERTIA_FACTORS = {"pendulum": 1.0, "ball": 7.0 / 5.0, "roller": 3.0 / 2.0}


class Race(eqx.Module):
    """The weights' track in the rotor frame: an ellipse with semi-axes
    `r1` (along the rotor-frame x axis) and `r2`, centred at `center`.

    A weight's position is parametrised by ONE angle `psi`,
    `p(psi) = center + (r1 cos psi, r2 sin psi)`, so there is no constraint to drift.
    `psi` is the ellipse's parametric angle; on a circle it is the polar angle.
    """

    r1: jax.Array
    r2: jax.Array
    center: jax.Array

    def __init__(self, r1, r2, center=(0.0, 0.0)):
        self.r1 = as_param("r1 (race semi-axis)", r1, sign="positive", shape=())
        self.r2 = as_param("r2 (race semi-axis)", r2, sign="positive", shape=())
        self.center = as_param("race center", center, shape=(2,))

    @classmethod
    def circular(cls, radius) -> "Race":
        radius = as_param("radius (race radius)", radius, sign="positive", shape=())
        return cls(radius, radius)

    @classmethod
    def eccentric(cls, radius, offset, offset_angle=0.0) -> "Race":
        """A circle whose centre is `offset` from the rotor centre at `offset_angle`."""
        radius = as_param("radius (race radius)", radius, sign="positive", shape=())
        offset = as_param("offset (race centre offset)", offset, sign="nonnegative", shape=())
        angle = as_param("offset_angle", offset_angle, shape=())
        return cls(radius, radius, offset * jnp.stack([jnp.cos(angle), jnp.sin(angle)]))

    @classmethod
    def elliptic(cls, r1, r2) -> "Race":
        return cls(r1, r2)

    def position(self, psi):
        return self.center + jnp.stack([self.r1 * jnp.cos(psi), self.r2 * jnp.sin(psi)])

    def tangent(self, psi):
        """`dp/dpsi`."""
        return jnp.stack([-self.r1 * jnp.sin(psi), self.r2 * jnp.cos(psi)])


class AutoBalancer(AbstractComponent):
    """Passive auto-balancer with `N` correction weights of mass `mass` (shape
    `(N,)`) in a `race`, with viscous drag `drag` on their motion relative to the rotor.

    Weight j has one coordinate `psi_j` (the race parameter, relative to the rotor).
    With `p_j = race.position(psi_j)` and relative velocity `v_j = race.tangent(psi_j) psid_j`,

        T = sum_j m_j/2 |d/dt (C + R(theta) p_j)|^2 + (K - 1) m_j/2 |v_j|^2,
        D = sum_j drag/2 |v_j|^2,

    where the second kinetic term is the weight's own rotation (rolling in the race,
    valid for a weight much smaller than the race): `K = 1` pendulum, `7/5` ball,
    `3/2` roller. On a circular race at constant speed this gives model 001's
    `K m R^2 phi'' + b_w R^2 (phi' - w) + m R (-x'' sin phi + y'' cos phi) = 0`.
    """

    mass: jax.Array
    inertia_factor: jax.Array
    drag: jax.Array
    race: Race

    def __init__(self, mass, race: Race, drag=0.0, kind="ball", inertia_factor=None):
        mass = as_param("weight mass", mass, sign="positive")
        if mass.ndim != 1 or mass.shape[0] < 1:
            raise InputError(
                f"weight mass must be a 1-D array with one entry per weight (>= 1 weight), "
                f"got shape {mass.shape}"
            )
        self.mass = mass
        if inertia_factor is None:
            check_choice("weight kind", kind, sorted(INERTIA_FACTORS))
            inertia_factor = INERTIA_FACTORS[kind]
        self.inertia_factor = as_param("inertia_factor", inertia_factor, shape=())
        check("inertia_factor", inertia_factor, lambda a: a >= 1.0,
              ">= 1 (1 pendulum, 7/5 ball, 3/2 roller)")
        self.drag = as_param("weight drag", drag, sign="nonnegative", shape=())
        check_type("race", race, Race, "a rotorjax.models.Race")
        self.race = race

    @property
    def n_weights(self) -> int:
        return self.mass.shape[0]

    @property
    def n_coords(self) -> int:
        return self.n_weights

    def kinetic(self, kin: Kinematics, q, qd):
        def one(m, psi, psid):
            p = self.race.position(psi)
            v_rel = self.race.tangent(psi) * psid
            v = kin.velocity_of(p, v_rel)
            return 0.5 * m * (v @ v) + 0.5 * (self.inertia_factor - 1.0) * m * (v_rel @ v_rel)

        return jnp.sum(jax.vmap(one)(self.mass, q, qd))

    def dissipation(self, kin, q, qd):
        v_rel = jax.vmap(self.race.tangent)(q) * qd[:, None]
        return 0.5 * self.drag * jnp.sum(v_rel**2)

    def mass_moment(self, kin, q):
        return self.mass @ jax.vmap(self.race.position)(q)

    def outputs(self, kin, q, qd):
        p = jax.vmap(self.race.position)(q)
        return {"weight_angles": jnp.arctan2(p[:, 1], p[:, 0])}

    def describe(self):
        return f"auto-balancer ({self.n_weights} weights)"


def weights_at(angles, race: Race) -> np.ndarray:
    """Race parameters `psi` of weights at the given polar angles about the rotor
    centre (rotor frame); used to set initial states. The rotor centre must lie
    inside the race (then each polar angle meets the race once)."""
    check_type("race", race, Race, "a rotorjax.models.Race")
    angles = np.atleast_1d(as_numpy("angles", angles))
    if angles.ndim != 1:
        raise InputError(f"angles must be a scalar or a 1-D array, got shape {angles.shape}")
    r1, r2 = float(race.r1), float(race.r2)
    cx, cy = (float(v) for v in np.asarray(race.center))
    if (cx / r1) ** 2 + (cy / r2) ** 2 >= 1:
        raise InputError("race: the rotor centre must lie inside the race to place weights by angle, "
                         f"got center {show((cx, cy))} for semi-axes ({r1}, {r2})")
    grid = np.linspace(-np.pi, np.pi, 4097)

    def polar(psi):
        return np.arctan2(cy + r2 * np.sin(psi), cx + r1 * np.cos(psi))

    out = []
    for a in angles:
        diff = lambda psi: np.angle(np.exp(1j * (polar(psi) - a)))  # noqa: E731
        psi = grid[np.argmin(np.abs(diff(grid)))]
        for _ in range(50):  # secant refinement; polar(psi) is monotone in psi
            h = 1e-7
            slope = (diff(psi + h) - diff(psi - h)) / (2 * h)
            step = diff(psi) / slope
            psi -= step
            if abs(step) < 1e-15:
                break
        out.append(psi)
    return np.asarray(out)


def balancing_angles(N: int, c):
    """Angles of `N` identical weights placed symmetrically about the direction
    opposite an imbalance of relative size `c` (imbalance / sum of the weights'
    mass moments), so that they cancel it: `mean(e^{i psi}) + c = 0`, `c <= 1`.
    Traceable in `c` for `N <= 2`."""
    N = as_count("N (number of weights)", N, minimum=1)
    if not is_concrete(c):
        if N != 2:
            raise InputError(f"sweeping c is supported for N = 2 weights, got N = {N}")
    else:
        c = float(as_numpy("c (relative imbalance)", c, shape=()))
        if not 0 <= c <= 1 or (N == 1 and c != 1):
            valid = "c = 1" if N == 1 else "0 <= c <= 1"
            raise InputError(f"{N} weight(s) cannot cancel an imbalance c = {c}: need {valid}")
    if N == 1:
        return jnp.array([np.pi])
    if N == 2:
        half = jnp.arccos(-c)  # cos(half) = -c: the pair's resultant is -c
        return jnp.stack([half, 2 * np.pi - half])
    # N >= 3: a symmetric fan about pi with the spread solved by bisection.
    offsets = np.arange(N) - (N - 1) / 2
    lo, hi = 0.0, 2 * np.pi / N
    for _ in range(200):
        mid = 0.5 * (lo + hi)
        resultant = np.mean(np.cos(np.pi + offsets * mid))  # in [-1, ...]
        lo, hi = (mid, hi) if resultant < -c else (lo, mid)
    return np.pi + offsets * 0.5 * (lo + hi)
