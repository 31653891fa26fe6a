"""Prescribed spin: the rotor's angle `theta(t)` is given, not solved for."""

import abc
from typing import Callable

import equinox as eqx
import jax
import jax.numpy as jnp

from ._validate import InputError, as_param


class AbstractSpeedProfile(eqx.Module):
    """A prescribed spin angle `theta(t)`; speed and acceleration by autodiff."""

    @abc.abstractmethod
    def angle(self, t) -> jax.Array:
        ...

    def speed(self, t) -> jax.Array:
        return jax.jvp(self.angle, (t,), (jnp.ones_like(t),))[1]

    def acceleration(self, t) -> jax.Array:
        return jax.jvp(self.speed, (t,), (jnp.ones_like(t),))[1]


def speed_alias(speed, alias, alias_name: str, owner: str):
    """The speed passed as `speed`, or under its paper symbol `alias_name` (a
    documented alias, by keyword); exactly one of the two."""
    if alias is not None:
        if speed is not None:
            raise InputError(f"{owner}: give the speed once, as speed or as {alias_name} (its alias), "
                             f"not both")
        return alias
    if speed is None:
        raise InputError(f"{owner}: the speed is required (speed, or {alias_name})")
    return speed


class ConstantSpeed(AbstractSpeedProfile):
    """`theta(t) = theta0 + speed * t` (rad/s, or the dimensionless `nu`, `n`).

    **Arguments:** `speed` (alias `omega`), `theta0`. `ConstantSpeed(2.0)`,
    `ConstantSpeed(speed=2.0)` and `ConstantSpeed(omega=2.0)` are the same profile.
    The constant is the field `constant` (a leaf for `eqx.tree_at`); `profile.speed(t)`
    is the speed at time `t`, as for every profile (`profile.omega`: deprecated)."""

    constant: jax.Array
    theta0: jax.Array

    def __init__(self, speed=None, theta0=0.0, *, omega=None):
        name = "omega (speed)" if omega is not None else "speed"
        self.constant = as_param(name, speed_alias(speed, omega, "omega", "ConstantSpeed"), shape=())
        self.theta0 = as_param("theta0", theta0, shape=())

    @property
    def omega(self):
        """Deprecated: the constant speed (`constant`)."""
        return self.constant

    def angle(self, t):
        return self.theta0 + self.constant * t

    def speed(self, t):
        return self.constant + 0.0 * t


class RunUp(AbstractSpeedProfile):
    """Constant angular acceleration: `theta = theta0 + speed0 t + alpha t^2 / 2`.

    **Arguments:** the initial speed `speed0` (alias `omega0`; the field
    `initial_speed`), `acceleration` (a negative one is a run-down; the field
    `acceleration_rate`), `theta0`."""

    initial_speed: jax.Array
    acceleration_rate: jax.Array
    theta0: jax.Array

    def __init__(self, speed0=None, acceleration=None, theta0=0.0, *, omega0=None):
        name = "omega0 (initial speed)" if omega0 is not None else "speed0 (initial speed)"
        self.initial_speed = as_param(name, speed_alias(speed0, omega0, "omega0", "RunUp"), shape=())
        if acceleration is None:
            raise InputError("RunUp: acceleration is required")
        self.acceleration_rate = as_param("acceleration", acceleration, shape=())
        self.theta0 = as_param("theta0", theta0, shape=())

    @property
    def speed0(self):
        """The initial speed (`initial_speed`)."""
        return self.initial_speed

    @property
    def omega0(self):
        """Deprecated: the initial speed (`initial_speed`)."""
        return self.initial_speed

    def angle(self, t):
        return self.theta0 + self.initial_speed * t + 0.5 * self.acceleration_rate * t**2

    def speed(self, t):
        return self.initial_speed + self.acceleration_rate * t

    def acceleration(self, t):
        return self.acceleration_rate + 0.0 * t


class CustomSpeed(AbstractSpeedProfile):
    """Any user function `theta(t)` written with `jax.numpy`; speed and
    acceleration are its derivatives by autodiff."""

    fn: Callable = eqx.field(static=True)

    def __init__(self, angle_fn: Callable):
        if not callable(angle_fn):
            raise InputError(f"angle_fn must be callable, got {angle_fn!r}")
        self.fn = angle_fn

    def angle(self, t):
        return jnp.asarray(self.fn(t), dtype=jnp.float64)
