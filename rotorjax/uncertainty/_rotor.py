"""A rotor file's linear quantities as functions of its parameters, for propagation:
the forward 1x critical speeds and the logarithmic decrements of the first modes.

Parameters are addressed by the rotor file's names (`bearing0.kxx`, `disk1.m`,
`material0.E`, `shaft2.od`, ...: the `--set` keys), each resolved once to the
leaves of the scene it sets (`rotorjax.models._parameters`), as identification
addresses them. The outputs, for the file's linear(ised) rotor (the full shaft and its
bearings; with fluid films, seals or supports, the scene that linearises them):

- `critical_speed_i`: the forward 1x critical speeds the nominal rotor has in
  `[lo, hi]` (`critical_speeds_1x`), each followed to the sample's rotor by the fixed
  point `Omega = omega_k(Omega)` from the nominal value (`critical_speed`, pure JAX).
  For the shaft and its bearings, `fn` takes Newton steps on the nominal eigenpair
  (`critical_pair`: linear solves, then one eigenvalue problem, the residual); a
  scene with components linearised at each speed keeps the secant steps. A sample
  Newton leaves with a residual above 1e-8 of the speed (at a close pair: the
  followed mode has changed rank among the sorted frequencies, or converged slowly;
  1.6 % of samples on ROSS's example rotor) gives NaN there, and `fallback` (which `propagate` calls on
  those samples) computes the same fixed point by secant steps on the sorted
  frequency. A sample neither converges on gives NaN and is counted, not averaged;
- `log_dec_i`: the logarithmic decrements of the first `n_modes` damped modes (by
  frequency) at `speed`;
- any of the quantities a design optimises (`rotorjax.analysis.scene_quantities`,
  asked for by name): `min-log-dec` (the floor over the range), `separation-margin`
  (API 684's slack, percent), `response` (the largest unbalance-response amplitude at
  the probes over the range, m), `onset` (the stability threshold, rad/s), `mass`.
"""

import dataclasses

import jax.numpy as jnp
import numpy as np

from .._errors import InputError, NumericalError
from ..analysis import (critical_pair, critical_speed, critical_speeds_1x, damped_eigenvalues, log_decrement,
                        scene_quantities)
from ..io import read_rotor_file
from ..models import SpinMatrices, Unbalance
from ..models._parameters import parts_of, scene_from, value_of, with_values
from ._distributions import reaches_zero, support

#: a fixed point whose residual exceeds this (relative to the speed) has not converged
CRITICAL_TOLERANCE = 1e-8
#: Newton steps on the nominal eigenpair per critical speed (from 10 % scatter of 8 bearing coefficients, the
#: fixed point to 1e-12 in 4)
NEWTON_STEPS = 4


@dataclasses.dataclass(frozen=True, eq=False)
class RotorQuantities:
    """`fn(values) -> outputs` of a rotor file (see the module) and its `fallback` (the
    same outputs, the critical speeds by the secant path: for the samples `fn` leaves
    NaN; None where `fn` takes no Newton steps), the outputs' names, the parameters'
    names and nominal values, the nominal critical speeds, and the settings of the
    design quantities asked for (`SceneQuantities.settings`)."""

    fn: object
    fallback: object
    outputs: tuple
    names: tuple
    nominal: np.ndarray
    critical: tuple
    speed: float
    label: str
    settings: dict = dataclasses.field(default_factory=dict)


def file_scatter(file, name, dist, option):
    """The `ParameterPath` of the rotor file's parameter `name`, checked to scatter as
    `dist` does (`InputError` naming `option` otherwise): a positive quantity's draws
    above 0, a position's between the nodes either side of its own (`support`)."""
    path = file.parameter_path(name, option)
    between, (a, b) = file.interval(name), support(dist)
    if between is not None and not between[0] < a <= b < between[1]:
        raise InputError(f"{option} {name}={dist.text()}: reaches {a:g} .. {b:g} m (within 5 standard deviations, or "
                         f"the ends of a uniform one), and {name} must stay between the nodes either side of its own, "
                         f"at {between[0]:g} and {between[1]:g} m")
    if not file.signed(name) and reaches_zero(dist):
        raise InputError(f"{option} {name}={dist.text()}: {name} is a positive quantity and this distribution "
                         "reaches 0 or below; give lognormal(MEAN, SD), or a narrower one")
    return path


def rotor_quantities(rotor, inputs, *, lo=None, hi=None, speed=None, n_modes=3, overrides=None, quantities=(),
                     operating=None, probes=None, option="--dist") -> RotorQuantities:
    """The quantities of the rotor file `rotor` (a path or a `RotorFile`) as a function
    of the parameters `inputs` (their names, or `{name: distribution}`: a positive
    quantity's distribution must stay positive, so a normal one within 5 standard
    deviations, a uniform one above 0; a lognormal one always does).

    - `lo`, `hi` (rad/s): the range of the critical speeds (default 0 to 1.5 x `speed`);
      `speed` (rad/s): where the log decrements are taken (default the file's `[rotor]
      speed`); `n_modes`: how many log decrements (0: none).
    - `quantities`: names of `scene_quantities` to add, over the speed range `[lo,
      hi]`, with `operating` `(lo, hi)` rad/s for `separation-margin` and `probes`
      (nodes) for `response`;
    - `overrides`: `--set` values for the file; `option`: the option the names came
      with, for the messages.
    """
    file = read_rotor_file(rotor, overrides) if isinstance(rotor, str) else rotor
    parts = parts_of(file.scene)
    names = tuple(inputs)
    paths = [file_scatter(file, name, inputs[name], option) if isinstance(inputs, dict)
             else file.parameter_path(name, option) for name in names]
    file.check_together(names, option)
    speed = float(file.entries["speed"].value) if speed is None else float(speed)
    if hi is None and not speed > 0:
        raise InputError(f"--range: {file.label} has no operating speed ([rotor] speed) to take the critical "
                         "speeds' range from; give --range LO HI (rad/s), or --speed")
    lo = 0.0 if lo is None else float(lo)
    hi = 1.5 * speed if hi is None else float(hi)
    if not 0 <= lo < hi:
        raise InputError(f"--range {lo:g} {hi:g}: the critical speeds' range needs 0 <= LO < HI (rad/s)")
    n_modes = int(n_modes)
    if n_modes and not speed >= 0:
        raise InputError(f"--speed {speed:g}: the log decrements need a speed >= 0")
    # the file's linear(ised) rotor: the shaft and its bearings alone, assembled once for every speed the
    # critical speeds' iterations visit; or, with components that add to the linear equations (fluid
    # films, seals, supports), the scene they linearise
    bare = all(isinstance(c, Unbalance) for c in parts.components)

    def linear(p):
        if not bare:
            return scene_from(p, file.scene)
        return p.rotor if p.rotor.speed_dependent else SpinMatrices(*p.rotor.reduced_matrices(0.0))

    rotor0 = parts.rotor if bare else file.scene
    n_dof = file.scene.n_coordinates if not bare else len(rotor0.free_dofs)
    if n_modes > n_dof:
        raise InputError(f"--modes {n_modes}: {file.label} has {n_dof} free dofs")
    crit = tuple((float(W), int(k)) for W, k in critical_speeds_1x(rotor0, lo, hi, n_modes=min(12, n_dof),
                                                                  whirl="forward"))
    if not crit and not n_modes and not quantities:
        raise InputError(f"--range {lo:g} {hi:g}: {file.label} has no forward critical speed there, and no log "
                         "decrements were asked for (--modes)")
    plan = scene_quantities(file.scene, quantities, label=file.label, speed_range=(lo, hi),
                            n_modes=max(n_modes, 1), operating=operating, probes=probes) if quantities else None

    # Newton on the nominal eigenpair for the shaft and its bearings; a scene that linearises components about
    # their equilibrium at each speed keeps the secant path
    pairs = [critical_pair(linear(parts), k, W) if bare else None for W, k in crit]

    def quantities(values, newton):
        p = with_values(parts, paths, values)
        r = linear(p)
        out = []
        for (W, k), pair in zip(crit, pairs):
            w, res = (critical_speed(r, k, W, iters=NEWTON_STEPS, pair=pair) if newton and pair is not None
                      else critical_speed(r, k, W))
            out.append(jnp.where(jnp.abs(res) <= CRITICAL_TOLERANCE * jnp.abs(w), w, jnp.nan))
        if n_modes:
            out.extend(log_decrement(damped_eigenvalues(r, speed, n_modes)))
        if plan is not None:
            out.extend(plan.evaluate(p).values())
        return jnp.stack(out)

    def fn(values):
        return quantities(values, True)

    def secant(values):
        return quantities(values, False)

    nominal = np.array([float(value_of(parts, p)) for p in paths])
    outputs = (tuple(f"critical_speed_{i}" for i in range(len(crit))) + tuple(f"log_dec_{i}" for i in range(n_modes))
               + (plan.names if plan is not None else ()))
    f0 = np.asarray(secant(jnp.asarray(nominal)))
    if not np.all(np.isfinite(f0)):
        raise NumericalError(f"{file.label}: the nominal rotor's quantities are not finite "
                             f"({', '.join(n for n, v in zip(outputs, f0) if not np.isfinite(v))})")
    # no Newton path (no critical speed, or a linearised scene): `fn` is the secant path, nothing to evaluate again
    fallback = secant if any(pair is not None for pair in pairs) else None
    return RotorQuantities(fn, fallback, outputs, names, nominal, crit, speed, file.label,
                           plan.settings if plan is not None else {})

