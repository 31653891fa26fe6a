"""A rotor file's linear quantities as functions of its parameters, for propagation:
the forward 1x critical speeds and the logarithmic decrements of the first modes.

Parameters are addressed by the rotor file's names (`bearing0.kxx`, `disk1.m`,
`material0.E`, `shaft2.od`, ...: the `--set` keys), each resolved once to the
leaves of the scene it sets (`rotorjax.models._parameters`), as identification
addresses them. The outputs, for the file's full linear rotor:

- `critical_speed_i`: the forward 1x critical speeds the nominal rotor has in
  `[lo, hi]` (`critical_speeds_1x`), each followed to the sample's rotor by the fixed
  point `Omega = omega_k(Omega)` from the nominal value (`critical_speed`, pure JAX):
  a sample whose fixed point has not converged (residual above 1e-8 of the speed)
  gives NaN and is counted, not averaged;
- `log_dec_i`: the logarithmic decrements of the first `n_modes` damped modes (by
  frequency) at `speed`.
"""

import dataclasses

import jax.numpy as jnp
import numpy as np

from .._errors import InputError, NumericalError
from ..analysis import critical_speed, critical_speeds_1x, damped_eigenvalues
from ..io import read_rotor_file
from ..models import SpinMatrices
from ..models._parameters import parts_of, value_of, with_values
from ._distributions import reaches_zero

#: a fixed point whose residual exceeds this (relative to the speed) has not converged
CRITICAL_TOLERANCE = 1e-8


@dataclasses.dataclass(frozen=True, eq=False)
class RotorQuantities:
    """`fn(values) -> outputs` of a rotor file (see the module), the outputs' names, the
    parameters' names and nominal values, and the nominal critical speeds."""

    fn: object
    outputs: tuple
    names: tuple
    nominal: np.ndarray
    critical: tuple
    speed: float
    label: str


def rotor_quantities(rotor, inputs, *, lo=None, hi=None, speed=None, n_modes=3, overrides=None,
                     option="--dist") -> RotorQuantities:
    """The quantities of the rotor file `rotor` (a path or a `RotorFile`) as a function
    of the parameters `inputs` (their names, or `{name: distribution}`: a positive
    quantity's distribution must stay positive, so a normal one within 5 standard
    deviations, a uniform one above 0; a lognormal one always does).

    - `lo`, `hi` (rad/s): the range of the critical speeds (default 0 to 1.5 x `speed`);
      `speed` (rad/s): where the log decrements are taken (default the file's `[rotor]
      speed`); `n_modes`: how many log decrements (0: none).
    - `overrides`: `--set` values for the file; `option`: the option the names came
      with, for the messages.
    """
    file = read_rotor_file(rotor, overrides) if isinstance(rotor, str) else rotor
    parts = parts_of(file.scene)
    names = tuple(inputs)
    paths = []
    for name in names:
        path = file.path(name)
        if path is None:
            raise InputError(f"{option} {name}: not a parameter of {file.label}; `rotorjax presets "
                             f"{file.label}` lists its keys")
        if path.refusal:
            raise InputError(f"{option} {name}: {path.refusal}")
        paths.append(path)
        dist = inputs[name] if isinstance(inputs, dict) else None
        if dist is not None and not file.signed(name) and reaches_zero(dist):
            raise InputError(f"{option} {name}={dist.text()}: {name} is a positive quantity and this distribution "
                             "reaches 0 or below; give lognormal(MEAN, SD), or a narrower one")
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
    rotor0 = parts.rotor
    n_dof = len(rotor0.free_dofs)
    if n_modes > n_dof:
        raise InputError(f"--modes {n_modes}: {file.label} has {n_dof} free dofs")
    crit = tuple((float(W), int(k)) for W, k in critical_speeds_1x(rotor0, lo, hi, n_modes=min(12, n_dof),
                                                                  whirl="forward"))
    if not crit and not n_modes:
        raise InputError(f"--range {lo:g} {hi:g}: {file.label} has no forward critical speed there, and no log "
                         "decrements were asked for (--modes)")

    def fn(values):
        r = with_values(parts, paths, values).rotor
        if not r.speed_dependent:   # assembled once for every speed the critical speeds' iterations visit
            r = SpinMatrices(*r.reduced_matrices(0.0))
        out = []
        for W, k in crit:
            w, res = critical_speed(r, k, W)
            out.append(jnp.where(jnp.abs(res) <= CRITICAL_TOLERANCE * jnp.abs(w), w, jnp.nan))
        if n_modes:
            lam = damped_eigenvalues(r, speed, n_modes)
            out.extend(-2 * jnp.pi * jnp.real(lam) / jnp.imag(lam))
        return jnp.stack(out)

    nominal = np.array([float(value_of(parts, p)) for p in paths])
    outputs = tuple(f"critical_speed_{i}" for i in range(len(crit))) + tuple(f"log_dec_{i}" for i in range(n_modes))
    f0 = np.asarray(fn(jnp.asarray(nominal)))
    if not np.all(np.isfinite(f0)):
        raise NumericalError(f"{file.label}: the nominal rotor's quantities are not finite "
                             f"({', '.join(n for n, v in zip(outputs, f0) if not np.isfinite(v))})")
    return RotorQuantities(fn, outputs, names, nominal, crit, speed, file.label)

