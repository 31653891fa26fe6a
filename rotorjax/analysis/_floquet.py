"""Floquet analysis of time-periodic scenes from the variational equations.

For `y' = f(t, y)` with `f` periodic of period `T` and a periodic solution `y*(t)`,
the monodromy matrix `M = Phi(T)` solves `Phi' = df/dy(t, y*(t)) Phi`, `Phi(0) = I`,
integrated alongside the state (so the step-size controller sees both). The
multipliers are the eigenvalues of `M`; the exponents `log|mu| / T`. Forward-mode
differentiation straight through an adaptive controller gives wrong monodromy
matrices on model 001 (shared/PERFORMANCE.md): this is why the variational
equations are integrated instead.

Self-checks returned with every result: `det M` against Liouville's formula
`exp(int_0^T tr df/dy dt)` (integrated alongside too), and the orbit's closure
`|y(T) - y(0)|`.

`floquet_many` (`floquet_batch` of a batch of `PeriodicOrbit`s) runs many periodic
motions at once: the variational equations are a scene (`Variational`: the state,
the monodromy matrix and the trace integral as one state vector), so the batch is
`simulate_batch`'s, its lanes stepped together as arrays of lanes and refilled from
the queue (no point waits for the slowest one).
"""

import diffrax
import equinox as eqx
import jax
import jax.numpy as jnp

from ..models._contract import AbstractScene
from ..solve._results import AbstractOutcome, result_code


class FloquetResult(AbstractOutcome):
    """Monodromy matrix, multipliers, exponents, verdict and self-checks.

    - `margin`: the largest Floquet exponent `max log|mu| / T` (< 0: stable).
    - `liouville_error`: `|log|det M| - int tr J| ` (should be ~ the tolerance).
    - `closure`: max-norm of `y(T) - y(0)` (0 for a true periodic solution).
    - `code`: the outcome's index in `rotorjax.solve.RESULTS`, the same codes as
      `SimulationResult.code`: `successful` (0), `max_steps_reached` (1),
      `nonfinite` (2: the monodromy matrix or the orbit is not finite),
      `solver_failure` (3); `result` is it as a `RESULTS` item.
    """

    monodromy: jax.Array
    multipliers: jax.Array
    exponents: jax.Array
    margin: jax.Array
    period: jax.Array
    liouville_error: jax.Array
    closure: jax.Array
    code: jax.Array

    @property
    def stable(self):
        return self.margin < 0

    @property
    def max_modulus(self):
        return jnp.max(jnp.abs(self.multipliers))

    @property
    def checked_margin(self):
        """`margin` where the integration succeeded (`code == 0`), NaN elsewhere."""
        return jnp.where(self.code == 0, self.margin, jnp.nan)


def _augmented(t, state, scene):
    """`(f, J Phi, tr J)`: the Jacobian `J = df/dy` is formed once (n tangents of one
    linearisation) and serves both the variational equations and the trace; 4x
    faster on the model-001 stability map than pushing Phi's columns and the
    identity's through separately (`benchmarks/stability_map.py`)."""
    y, phi, _ = state
    dy, tangent = jax.linearize(lambda yy: scene.vector_field(t, yy), y)
    jac = jax.vmap(tangent, in_axes=1, out_axes=1)(jnp.eye(y.shape[0], dtype=y.dtype))
    return dy, jac @ phi, jnp.trace(jac)


class Variational(AbstractScene):
    """A scene's variational equations as a scene: the state `(y, Phi, int tr J)`
    flattened (`Phi` row by row), `Phi' = J Phi`, so that any integrator of scenes
    (`simulate_batch`'s kernels) integrates the monodromy matrix. The step-size
    controller's norm over the flat state is the one `monodromy` uses over the
    tuple (diffrax's RMS norm is over all elements)."""

    scene: AbstractScene

    @property
    def speed(self):
        return self.scene.speed

    @property
    def n(self) -> int:
        return self.scene.state_size

    @property
    def state_size(self) -> int:
        return self.n * (self.n + 1) + 1

    @staticmethod
    def initial_state(y0):
        """`(y0, I, 0)`, flattened."""
        y0 = jnp.asarray(y0, dtype=jnp.float64)
        n = y0.shape[0]
        return jnp.concatenate([y0, jnp.eye(n, dtype=y0.dtype).reshape(-1), jnp.zeros((1,), y0.dtype)])

    @staticmethod
    def split(s):
        """The flat state -> `(y, Phi, int tr J)`."""
        n = int(round((s.shape[0] - 1) ** 0.5 - 0.5))  # s has n (n + 1) + 1 elements
        return s[:n], s[n:n + n * n].reshape(n, n), s[-1]

    def vector_field(self, t, s, args=None):
        y, phi, _ = self.split(s)
        dy, dphi, tr = _augmented(t, (y, phi, None), self.scene)
        return jnp.concatenate([dy, dphi.reshape(-1), tr[None]])

    def outputs(self, t, s) -> dict:
        return self.scene.outputs(t, self.split(s)[0])

    def describe(self) -> str:
        return f"the variational equations of {self.scene.describe()}"


def monodromy(scene, y0, period, t0=0.0, rtol=1e-10, atol=1e-12, max_steps=100_000):
    """Integrate the state and its variational equations over one period."""
    y0 = jnp.asarray(y0, dtype=jnp.float64)
    n = y0.shape[0]
    state0 = (y0, jnp.eye(n), jnp.zeros(()))
    sol = diffrax.diffeqsolve(
        diffrax.ODETerm(_augmented), diffrax.Dopri8(), t0=t0, t1=t0 + period, dt0=None,
        y0=state0, args=scene, stepsize_controller=diffrax.PIDController(rtol=rtol, atol=atol),
        max_steps=max_steps, throw=False,
    )
    y1, m, trace_integral = (x[-1] for x in sol.ys)
    return y1, m, trace_integral, sol.result


def floquet(scene, y0, period, t0=0.0, rtol=1e-10, atol=1e-12, max_steps=100_000) -> FloquetResult:
    """Floquet multipliers of the periodic solution through `y0` (at `t0`) of a
    scene whose equations have period `period`. Pure; vmap over scenes."""
    period = jnp.asarray(period, dtype=jnp.float64)
    y1, m, trace_integral, result = monodromy(scene, y0, period, t0, rtol, atol, max_steps)
    return _result(jnp.asarray(y0, dtype=jnp.float64), y1, m, trace_integral, period, result_code(result, (m, y1)))


def _result(y0, y1, m, trace_integral, period, code) -> FloquetResult:
    """The multipliers, exponents and self-checks from the monodromy matrix, with the
    integration's `RESULTS` code."""
    mult = jnp.linalg.eigvals(m)
    exps = jnp.log(jnp.abs(mult)) / period
    _, logdet = jnp.linalg.slogdet(m)
    return FloquetResult(
        monodromy=m, multipliers=mult, exponents=exps, margin=jnp.max(exps), period=period,
        liouville_error=jnp.abs(logdet - trace_integral), closure=jnp.max(jnp.abs(y1 - y0)),
        code=code.astype(jnp.int32),
    )


#: XLA options for `floquet_many`'s program on the CPU: XLA's newer CPU fusion
#: emitters compile the forward-mode derivative of a right-hand side over lanes into a
#: loop fusion that evaluates the whole derivative for every output element (its
#: output concatenation fused with its operands): one Jacobian-vector product of model
#: 001's field over 128 lanes cost 2 400 ns a lane against 55 ns for the field, and
#: 170 ns with the older emitters (one core). The field alone is faster with the newer
#: ones (model 001's sweep: 1.7 against 3.3 us a lane-step), so only the Floquet
#: programs (this one, and `stability_margins`' sweep of periodic references) turn them
#: off.
CPU_COMPILER_OPTIONS = {"xla_cpu_use_fusion_emitters": False}


#: `floquet_many`'s default lanes: the variational state (73 numbers for model 001's 8)
#: times Dopri8's 14 stages stays in one core's cache (model 001's map, one core: 64
#: lanes 3 900 points/s, 32 3 500, 128 2 300)
LANES = 64


def floquet_many(scenes, y0s, periods, rtol, atol, lanes=None, steps_per_round=8, method="auto", shard=False,
                 max_steps=100_000) -> FloquetResult:
    """`floquet` of many periodic motions at once (what `floquet_batch` runs): `scenes`
    with a batch axis `N` in front of their array leaves, `y0s` `(N, state_size)`,
    `periods` `(N,)`. The variational equations of every motion are integrated by
    `simulate_batch` (Dopri8 at `rtol`/`atol`; `lanes` (default `min(N, LANES)`),
    `steps_per_round`, `method` and `shard` as there: by default the vectorised
    kernel, lanes refilled from the queue; on the CPU with `CPU_COMPILER_OPTIONS`)."""
    from ..solve import simulate_batch

    var = Variational(scenes)
    lanes = min(y0s.shape[0], LANES) if lanes is None else lanes
    s0 = jax.vmap(Variational.initial_state)(y0s)
    options = CPU_COMPILER_OPTIONS if jax.default_backend() == "cpu" else None
    res = simulate_batch(var, s0, (0.0, periods), solver=diffrax.Dopri8(), rtol=rtol, atol=atol,
                         max_steps=max_steps, lanes=lanes, steps_per_round=steps_per_round, method=method,
                         shard=shard, compiler_options=options)
    y1, m, trace_integral = jax.vmap(Variational.split)(res.ys[:, -1])
    return jax.vmap(_result)(y0s, y1, m, trace_integral, periods, res.code)


def _field(t, y, scene):
    return scene.vector_field(t, y)


def flow_samples(scene, y0, period, t0=0.0, steps=256, n_samples=None):
    """The states at `n_samples` equally spaced instants over one period from `y0`
    (the last the state after the whole period), integrated in `steps` fixed steps
    of Dopri8: the discrete map is what forward-mode differentiation sees, so its
    derivatives are exact for it (an adaptive controller's are not: see
    shared/PERFORMANCE.md). `n_samples` must divide `steps` (default: just the end
    state, shape `(1, n)`)."""
    period = jnp.asarray(period, dtype=jnp.float64)
    m = n_samples or 1
    ts = t0 + period * jnp.arange(1, m + 1) / m
    sol = diffrax.diffeqsolve(
        diffrax.ODETerm(_field), diffrax.Dopri8(), t0=t0, t1=t0 + period, dt0=period / steps, y0=y0, args=scene,
        stepsize_controller=diffrax.ConstantStepSize(), saveat=diffrax.SaveAt(ts=ts), max_steps=steps + 2,
        adjoint=diffrax.ForwardMode(), throw=False,
    )
    return sol.ys


def shoot(scene, y_guess, period, t0=0.0, max_iter=20, tol=1e-11, rtol=1e-11, atol=1e-13, autonomous=False):
    """Shooting: Newton on `y(t0 + T) - y(t0) = 0` with the monodromy as the
    Jacobian. With `autonomous`, the period is an unknown too, closed by the phase
    condition `f(y_guess) . (y - y_guess) = 0` (the orbit's start on the plane
    through the guess across the flow), the Jacobian bordered by `f(y(T))` and
    `f(y_guess)`. Returns `(y0, period, closure, iterations, converged)`, `closure`
    the max-norm of `y(t0 + T) - y(t0)` at the last iterate."""
    y = jnp.asarray(y_guess, dtype=jnp.float64)
    T = jnp.asarray(period, dtype=jnp.float64)
    n = y.shape[0]
    normal = scene.vector_field(t0, y)
    closure = jnp.inf
    for it in range(max_iter):
        y1, m, _, _ = monodromy(scene, y, T, t0, rtol, atol)
        g = y1 - y
        closure = float(jnp.max(jnp.abs(g)))
        if closure < tol:
            return y, T, closure, it, True
        if not autonomous:
            y = y - jnp.linalg.solve(m - jnp.eye(n), g)
            continue
        J = jnp.block([[m - jnp.eye(n), scene.vector_field(t0 + T, y1)[:, None]],
                       [normal[None, :], jnp.zeros((1, 1))]])
        dx = jnp.linalg.solve(J, jnp.concatenate([g, jnp.dot(normal, y - y_guess)[None]]))
        y, T = y - dx[:n], T - dx[n]
    return y, T, closure, max_iter, False


def periodic_orbit_by_shooting(scene, y_guess, period, t0=0.0, max_iter=20, tol=1e-11, rtol=1e-11, atol=1e-13):
    """The legacy form of `periodic_orbit` (no `method`): shooting at the fixed
    period, returning `(y0, closure, converged)`; for an equilibrium-like motion
    (such as model 001's main motion) one iteration confirms it."""
    y, _, closure, _, ok = shoot(scene, y_guess, period, t0, max_iter, tol, rtol, atol)
    return y, closure, ok
