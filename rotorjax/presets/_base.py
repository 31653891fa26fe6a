"""What a preset is: a published scene with named parameters, defaults, units and
valid ranges."""

import dataclasses
import functools
import re
from typing import Callable

import numpy as np

from .._errors import InputError

_INTERVAL = re.compile(r"^([\[(])\s*([-+.\deE]+|-inf)\s*,\s*([-+.\deE]+|inf)\s*([\])])$")
_BOUND = re.compile(r"^(>=|>|<=|<)\s*([-+.\deE]+)$")


def describe_domain(domain: str) -> str:
    """A domain in words, e.g. `"int>=1"` -> `"an integer >= 1"`."""
    if domain == "any":
        return "any finite number"
    if domain.startswith("{"):
        return "one of " + ", ".join(v.strip() for v in domain.strip("{}").split(","))
    if domain.startswith("int"):
        rest = domain[3:].strip()
        if rest == ">=0":
            return "a non-negative integer"
        if _INTERVAL.match(rest):
            return f"an integer in {rest}"
        return "an integer" + (f" {_spaced(rest)}" if rest else "")
    if _INTERVAL.match(domain):
        return f"in {domain}"
    return _spaced(domain)


def _spaced(bound: str) -> str:
    m = _BOUND.match(bound)
    return f"{m.group(1)} {m.group(2)}" if m else bound


def _within(value: float, domain: str) -> bool:
    if domain == "any":
        return True
    if domain.startswith("{"):
        return value in [float(v) for v in domain.strip("{}").split(",")]
    if domain.startswith("int"):
        return value == int(value) and _within(value, domain[3:].strip() or "any")
    m = _INTERVAL.match(domain)
    if m:
        lo, hi = float(m.group(2)), float(m.group(3))
        return (value >= lo if m.group(1) == "[" else value > lo) and (
            value <= hi if m.group(4) == "]" else value < hi)
    m = _BOUND.match(domain)
    if not m:
        raise ValueError(f"unknown domain {domain!r}")
    op, b = m.group(1), float(m.group(2))
    return {">": value > b, ">=": value >= b, "<": value < b, "<=": value <= b}[op]


def check_value(key: str, raw, domain: str, meaning: str = "", unit: str = ""):
    """`raw` (a string or number) as a number in `domain`, or an `InputError`
    `"key=raw: must be ... (meaning, unit)"` naming the key as the user gave it."""
    what = ", ".join(s for s in (meaning, unit) if s)
    where = f" ({what})" if what else ""
    try:
        value = float(raw)
    except (TypeError, ValueError):
        raise InputError(f"{key}={raw}: must be a number{where}") from None
    if not np.isfinite(value):
        raise InputError(f"{key}={raw}: must be finite{where}")
    if not _within(value, domain):
        raise InputError(f"{key}={raw}: must be {describe_domain(domain)}{where}")
    if domain.startswith("int") or domain.startswith("{"):
        value = int(value)
    return value


@dataclasses.dataclass(frozen=True)
class Setup:
    """What `Preset.build(params)` returns, the same for every preset.

    - `scene`: the model, a `rotorjax.models.AbstractScene` (what every analysis takes);
    - `y0`: the initial state of a run (None for presets that are not simulated in time);
    - `t_end`: the default run length in the preset's time unit (None likewise);
    - `extras`: preset-specific data, e.g. `events` (runs locate the contacts exactly),
      `saves_per_revolution` and `revolutions` (run lengths measured in revolutions),
      `clearance` (drawn on plots).

    For the scripts written when `build` returned a tuple, `scene, y0, t_end = setup`
    still works (deprecated: use the fields).
    """

    scene: object
    y0: object = None
    t_end: object = None
    extras: dict = dataclasses.field(default_factory=dict)


def _halved_and_doubled(v):
    return (0.5 * v, 2.0 * v) if v > 0 else (v - 1.0, v + 1.0) if v != 0 else (-1.0, 1.0)


@dataclasses.dataclass(frozen=True)
class Preset:
    """A published scene.

    - `name`: the CLI name (`elliptic-abb`, ...).
    - `source`: the publication.
    - `defaults`: the published parameter set; these names are the `--set` keys.
    - `build(params) -> Setup`: the scene (in the paper's dimensionless units), its
      initial state and default end time where it is simulated, and extras.
    - `describe_params`, `units`, `domains`: per key, its meaning, its unit
      (`"dimensionless"`, `"rad"`, `"N/m"`, ...) and its valid values (`"any"`,
      `">0"`, `">=0"`, `"int>=1"`, `"{0,1}"`, `"(0,1]"`); `params` checks every
      value against its domain before anything is built.
    - `time_unit`, `length_unit`: what one dimensionless unit is.
    - `speed_key`: the parameter that is the (dimensionless) speed.
    - `margin(params) -> scalar`: stability margin of the preset's reference regime
      (`regime` says which), traceable in the parameters (for maps and critical
      speeds); < 0 is stable.
    - `topology_keys`: parameters that change the scene's structure (not sweepable).
    - `box`: `{key: (lo, hi)}`, the default parameter range of those keys for
      tracing stability boundaries (`rotorjax continue --param2` without `--box`).
    - `kind`: which commands apply (`"planar"`, `"flexible"`, `"modal"`, `"contact"`,
      `"machine"`, `"rotor"` for rotor files).

    What the preset's model offers beyond `margin` (None where it does not):

    - `margin_gradient`: how boundary tangents of `margin` are computed, `"autodiff"`
      or `"fd"` (central differences, for Floquet margins).
    - `branch_problem(params, key) -> (F, u0)`: the stationary reference regime as a
      root `F(u, value) = 0` in the rotating frame, for one-parameter continuation in
      `key`.
    - `floquet_family(params, key) -> (value -> FloquetResult)`: the periodic
      reference motion's Floquet analysis as a function of `key`.
    - `criterion_roots(params, lo, hi) -> list`: the roots of a published empirical
      stability criterion in the speed range (`criterion_label` names it).
    - `regimes(params, n_angles, stage) -> (rows, notes)`: every stationary regime at
      the preset's speed, as JSON rows, and notes for the user.
    - `critical_speeds(params, lo, hi, n_scan, n_modes, exact, progress) -> dict`:
      critical speeds where they are not sign changes of `margin` (1x crossings,
      natural frequencies), with `"campbell"` `(speeds, frequencies, forward)` and
      `"present"` (unit, title) to plot; finite-element kinds (`"flexible"`,
      `"rotor"`) get the 1x crossings of their Campbell diagram by default.
    - `hopf(params, lo, hi, n_scan, progress) -> dict`: Hopf points of the reference
      motion, with `"scan"` `(speeds, margins)` and `"present"` (plot labels, the
      sensitivity reported).
    - `sweepable`: `{key: where}` for vmapped sweeps, `where(scene)` the leaf the key
      sets (raises `InputError` where the scene lacks the part).
    """

    name: str
    source: str
    defaults: dict
    build: Callable
    describe_params: dict
    time_unit: str
    length_unit: str
    integer_keys: tuple = ()
    speed_key: str = "n"
    margin: Callable = None
    regime: str = ""
    topology_keys: tuple = ()
    kind: str = "planar"
    units: dict = dataclasses.field(default_factory=dict)
    domains: dict = dataclasses.field(default_factory=dict)
    box: dict = dataclasses.field(default_factory=dict)
    margin_gradient: str = "autodiff"
    branch_problem: Callable = None
    floquet_family: Callable = None
    criterion_roots: Callable = None
    criterion_label: str = ""
    regimes: Callable = None
    critical_speeds: Callable = None
    hopf: Callable = None
    sweepable: dict = dataclasses.field(default_factory=dict)

    def __post_init__(self):
        if self.kind in ("flexible", "rotor") and self.critical_speeds is None:
            # a finite-element rotor: critical speeds are 1x crossings of its Campbell diagram
            from ._hooks import fe_critical_speeds

            object.__setattr__(self, "critical_speeds", functools.partial(fe_critical_speeds, self.build,
                                                                      name=self.name))
        missing = [k for k in self.defaults if k not in self.domains or k not in self.units]
        if missing:
            raise ValueError(f"preset {self.name!r}: no unit/domain for {missing}")
        for k, rng in self.box.items():
            lo, hi = rng
            if k not in self.defaults or not (np.isfinite(lo) and np.isfinite(hi) and lo < hi) or not (
                    _within(lo, self.domains[k]) and _within(hi, self.domains[k])):
                raise ValueError(f"preset {self.name!r}: box[{k!r}] = {rng!r} is not a finite increasing range "
                                 "of a known key's valid values")

    def boundary_box(self, key: str, key2: str, start) -> tuple:
        """The default parameter box `[lo1, hi1, lo2, hi2]` for tracing a stability
        boundary in `(key, key2)` from `start`, and where it came from: per key, the
        preset's `box`, or else the start halved and doubled within the key's valid
        values."""
        box, sources = [], []
        for k, v in ((key, start[0]), (key2, start[1])):
            if k in self.box:
                lo, hi = self.box[k]
                sources.append(f"{k}: the preset's default box")
            else:
                lo, hi = _halved_and_doubled(v)
                if self.domains[k] in (">0", ">=0") and lo < 0:
                    lo = 0.0
                sources.append(f"{k}: the start halved and doubled")
            box += [float(lo), float(hi)]
        from_box = [src.endswith("box") for src in sources]
        if all(from_box):
            return box, "the preset's default box"
        if not any(from_box):
            return box, "default (start halved and doubled)"
        return box, "; ".join(sources)

    @staticmethod
    def continuation_range(start) -> tuple:
        """The default range of a one-parameter continuation from `start`: the start
        halved and doubled."""
        return tuple(sorted((0.5 * start, 2.0 * start))) if start != 0 else (-1.0, 1.0)

    def check(self, key: str, raw):
        """One value for `key`, checked against its domain (see `check_value`)."""
        if key not in self.defaults:
            raise InputError(f"unknown parameter {key!r} for preset {self.name!r}; "
                             f"known: {', '.join(sorted(self.defaults))}")
        return check_value(key, raw, self.domains[key], self.describe_params.get(key, ""),
                           self.units[key])

    def params(self, overrides=None) -> dict:
        """Defaults with `overrides` applied; unknown keys, non-numbers and values
        outside a key's domain raise `InputError` naming the key."""
        params = dict(self.defaults)
        for key, value in (overrides or {}).items():
            params[key] = self.check(key, value)
        return params

    def info(self) -> list:
        """One dict per parameter: key, default, unit, valid values, meaning."""
        return [{"key": k, "default": v, "unit": self.units[k],
                 "valid": describe_domain(self.domains[k]), "meaning": self.describe_params.get(k, "")}
                for k, v in self.defaults.items()]

