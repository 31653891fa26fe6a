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


class ConstantSpeed(AbstractSpeedProfile):
    """`theta(t) = theta0 + speed * t` (rad/s, or the dimensionless `nu`, `n`)."""

    omega: jax.Array
    theta0: jax.Array

    def __init__(self, omega, theta0=0.0):
        self.omega = as_param("omega (speed)", omega, shape=())
        self.theta0 = as_param("theta0", theta0, shape=())

    def angle(self, t):
        return self.theta0 + self.omega * t

    def speed(self, t):
        return self.omega + 0.0 * t


class RunUp(AbstractSpeedProfile):
    """Constant angular acceleration: `theta = theta0 + omega0 t + alpha t^2 / 2`.

    A negative `acceleration` is a run-down."""

    omega0: jax.Array
    acceleration_rate: jax.Array
    theta0: jax.Array

    def __init__(self, omega0, acceleration, theta0=0.0):
        self.omega0 = as_param("omega0 (initial speed)", omega0, shape=())
        self.acceleration_rate = as_param("acceleration", acceleration, shape=())
        self.theta0 = as_param("theta0", theta0, shape=())

    def angle(self, t):
        return self.theta0 + self.omega0 * t + 0.5 * self.acceleration_rate * t**2

    def speed(self, t):
        return self.omega0 + self.acceleration_rate * t

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
