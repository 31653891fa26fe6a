"""What a preset is: a published scene with named parameters, defaults, units and
valid ranges."""

import dataclasses
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
    - `reference`: the motion whose stability the maps, critical speeds, Hopf points
      and boundaries are about (`rotorjax.analysis.StationaryRegime`, `PeriodicOrbit`,
      `StraightRunning`, or `NoReference` with the reason), or None; every stability
      analysis takes it (`rotorjax.analysis.stability_margin(setup.reference)`).
    - `published`: the paper's own estimates to compare with (`PublishedSpeeds`).

    For the scripts written when `build` returned a tuple, `scene, y0, t_end = setup`
    still works (deprecated: use the fields).
    """

    scene: object
    y0: object = None
    t_end: object = None
    extras: dict = dataclasses.field(default_factory=dict)
    reference: object = None
    published: tuple = ()

    def __iter__(self):
        # `scene, y0, t_end = setup` (deprecated: the tuple `build` returned before `Setup`)
        return iter((self.scene, self.y0, self.t_end))


@dataclasses.dataclass(frozen=True)
class PublishedSpeeds:
    """Speeds a paper's own formula gives (an empirical criterion's roots, an
    estimated threshold), drawn and reported beside the computed ones: `label` names
    it on plots, `formula` writes it out, `details` the groups it was evaluated at."""

    label: str
    speeds: tuple
    formula: str = ""
    details: dict = dataclasses.field(default_factory=dict)

    def within(self, lo, hi) -> list:
        return [float(s) for s in self.speeds if lo <= s <= hi]


def hopf_report(preset, params, lo, hi, n_scan=80, progress=True):
    """`(out, look)`: the Hopf points of the preset's reference motion at `params` in
    `[lo, hi]` (`rotorjax.analysis.reference_hopf_points`, with the derivative of each
    Hopf speed with respect to `preset.hopf_sensitivity`) as JSON, the paper's
    estimate beside them (`Setup.published`) and the scan (`out["scan"]`); `look`
    holds the plot's labels."""
    from ..analysis import reference_hopf_points

    setup = preset.build(params)
    key, sens = preset.speed_key, preset.hopf_sensitivity
    sensitivity = (params[sens], lambda v: preset.build(dict(params, **{sens: v})).reference) if sens else None
    res = reference_hopf_points(setup.reference, lo, hi, n_scan=n_scan, sensitivity=sensitivity, progress=progress)
    unit = "rad/s" if preset.kind == "rotor" else f"1/({preset.time_unit})"
    out = {"unit": f"speed {key} and whirl frequency in {unit}", **res.as_dict(key, sens)}
    published = setup.published[0] if setup.published else None
    if published is not None:
        out.update(published.details)
        out["paper_fit"] = {f"{key}_crit": published.speeds[0], "formula": published.formula}
    out["scan"] = (res.speeds, res.margins)
    look = {"title": setup.reference.label,
            "speed_label": f"spin speed {key} ({preset.units[key]})",
            "margin_label": "largest Re(lambda)",
            "extra_roots": list(published.speeds) if published is not None else None,
            "extra_label": published.label if published is not None else "",
            "sensitivity": (f"d{key}_crit_d_{sens}", f"d{key}/d {sens}") if sens else ("", "")}
    return out, look


def _halved_and_doubled(v):
    return (0.5 * v, 2.0 * v) if v > 0 else (v - 1.0, v + 1.0) if v != 0 else (-1.0, 1.0)


@dataclasses.dataclass(frozen=True)
class Preset:
    """A published scene, as data: nothing in it is callable but `build`.

    - `name`: the CLI name (`elliptic-abb`, ...).
    - `source`: the publication.
    - `defaults`: the published parameter set; these names are the `--set` keys.
    - `build(params) -> Setup`: the scene (in the paper's dimensionless units), its
      initial state and default end time where it is simulated, its reference motion
      (`Setup.reference`: what stability maps, critical speeds and boundaries are
      about), the paper's own estimates (`Setup.published`), and extras. Traceable in
      the parameters a map or a boundary sweeps.
    - `describe_params`, `units`, `domains`: per key, its meaning, its unit
      (`"dimensionless"`, `"rad"`, `"N/m"`, ...) and its valid values (`"any"`,
      `">0"`, `">=0"`, `"int>=1"`, `"{0,1}"`, `"(0,1]"`); `params` checks every
      value against its domain before anything is built.
    - `time_unit`, `length_unit`: what one dimensionless unit is.
    - `speed_key`: the parameter that is the (dimensionless) speed.
    - `topology_keys`: parameters that change the scene's structure (not sweepable).
    - `box`: `{key: (lo, hi)}`, the default parameter range of those keys for
      tracing stability boundaries (`rotorjax continue --param2` without `--box`).
    - `kind`: a word for what the preset is (`"planar"`, `"flexible"`, `"modal"`,
      `"contact"`, `"machine"`, `"rotor"` for rotor files), listed by `rotorjax
      presets`; which commands apply is found from the built scene's capabilities and
      reference motion, not from it.
    - `steady_overrides`: parameter values under which the stationary regimes are
      sought (`rotorjax steady`: e.g. a zero run-up rate).
    - `sweepable`: `{key: path}` for vmapped sweeps (`rotorjax bifurcation`): the
      scene's leaf each key sets, as a path (`rotorjax.models.leaf_at`, e.g.
      `"components[LimitersAt].limiters.clearance"`).
    - `hopf_sensitivity`: the parameter whose derivative of each Hopf speed
      `rotorjax hopf` reports (implicit function theorem), e.g. `"eta_e"`.

    Every analysis is a library function of the built scene or reference
    (`rotorjax.analysis.stability_margin(preset.build(p).reference)`, ...). The
    attributes `margin`, `regime`, `margin_gradient`, `branch_problem`,
    `floquet_family`, `criterion_roots`, `criterion_label`, `regimes`,
    `critical_speeds` and `hopf` of earlier releases are kept, computed from them
    (deprecated).
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
    topology_keys: tuple = ()
    kind: str = "planar"
    units: dict = dataclasses.field(default_factory=dict)
    domains: dict = dataclasses.field(default_factory=dict)
    box: dict = dataclasses.field(default_factory=dict)
    sweepable: dict = dataclasses.field(default_factory=dict)
    steady_overrides: dict = dataclasses.field(default_factory=dict)
    hopf_sensitivity: str = ""

    # --- deprecated attributes, computed from `build` and the library -------------------
    def _reference(self):
        """The reference motion at the preset's defaults."""
        return self.build(self.params()).reference

    @property
    def margin(self):
        """Deprecated: `lambda p: rotorjax.analysis.stability_margin(build(p).reference)`."""
        if self._reference() is None:
            return None
        from ..analysis import stability_margin

        return lambda p: stability_margin(self.build(p).reference)

    @property
    def regime(self) -> str:
        """Deprecated: the reference motion's label (`Setup.reference.label`)."""
        ref = self._reference()
        return "" if ref is None else ref.label

    @property
    def margin_gradient(self) -> str:
        """Deprecated: `rotorjax.analysis.margin_gradient(build(p).reference)`."""
        from ..analysis import AbstractReference, NoReference, margin_gradient

        ref = self._reference()
        ok = isinstance(ref, AbstractReference) and not isinstance(ref, NoReference)
        return margin_gradient(ref) if ok else "autodiff"

    @property
    def branch_problem(self):
        """Deprecated: `rotorjax.analysis.branch_problem` of the stationary reference regime."""
        from ..analysis import PeriodicOrbit, branch_problem

        ref = self._reference()
        if ref is None or isinstance(ref, PeriodicOrbit):
            return None
        return lambda p, key: branch_problem(lambda v: self.build(dict(p, **{key: v})).reference, p[key])

    @property
    def floquet_family(self):
        """Deprecated: `rotorjax.analysis.floquet_family` of the periodic reference motion."""
        from ..analysis import PeriodicOrbit, floquet_family

        if not isinstance(self._reference(), PeriodicOrbit):
            return None
        return lambda p, key: floquet_family(lambda v: self.build(dict(p, **{key: v})).reference)

    @property
    def criterion_roots(self):
        """Deprecated: `build(p).published[0].within(lo, hi)`."""
        if not self.build(self.params()).published:
            return None
        return lambda p, lo, hi: self.build(p).published[0].within(lo, hi)

    @property
    def criterion_label(self) -> str:
        """Deprecated: `build(p).published[0].label`."""
        published = self.build(self.params()).published
        return published[0].label if published else ""

    @property
    def regimes(self):
        """Deprecated: `rotorjax.analysis.steady_states` of the scene under
        `steady_overrides`, as JSON rows (`Regime.as_dict`)."""
        from ..models import provides

        scene = self.build(self.params()).scene
        if not (provides(scene, "to_rotating") and len(scene.weight_coordinates()[0])):
            return None

        def regimes(params, n_angles=16, stage=None):
            from ..analysis import steady_states

            scene = self.build(dict(params, **self.steady_overrides)).scene
            return [r.as_dict() for r in steady_states(scene, n_angles=n_angles)], []

        return regimes

    @property
    def critical_speeds(self):
        """Deprecated: `rotorjax.analysis.campbell_critical_speeds` of a finite-element
        rotor (as the dict the CLI presents)."""
        from ..models import provides

        setup = self.build(self.params())
        if setup.reference is not None or not provides(setup.scene, "shaft"):
            return None   # a reference motion's critical speeds are its stability thresholds

        def critical_speeds(params, lo, hi, n_scan=200, n_modes=None, exact=False, progress=True):
            from ..analysis import campbell_critical_speeds

            res = campbell_critical_speeds(self.build(params).scene, lo, hi, n_scan=n_scan, n_modes=n_modes or 8,
                                           what=self.name)
            return dict(res.as_dict(), campbell=(res.speeds, res.frequencies, res.forward),
                        present={"unit": "rad/s", "title": "critical speeds (1x crossings)"})

        return critical_speeds

    @property
    def hopf(self):
        """Deprecated: `hopf_report` (the Hopf points of a `StraightRunning` reference)."""
        from ..analysis import StraightRunning

        if not isinstance(self._reference(), StraightRunning):
            return None

        def hopf(params, lo, hi, n_scan=80, progress=True):
            out, look = hopf_report(self, params, lo, hi, n_scan=n_scan, progress=progress)
            return dict(out, present=look)

        return hopf

    def __post_init__(self):
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

    def forcing_keys(self, params: dict, held: dict) -> list:
        """The parameters that make the scene forced (its equations depend on time):
        a rotor file's unbalance magnitudes that are not zero, else each non-zero
        parameter whose zero leaves the scene autonomous (`analysis.is_autonomous`,
        at its rest state; e.g. model 004's `eps`). `held`: values kept while each is
        tried (the speed); a combination that does not build is skipped."""
        from ..analysis import is_autonomous

        keys = [k for k, v in params.items() if k.startswith("unbalance") and k.endswith(".magnitude") and v]
        if keys:
            return keys
        for k, v in params.items():
            if k in held or isinstance(v, bool) or not isinstance(v, float) or v == 0:
                continue
            try:
                setup = self.build(dict(params, **held, **{k: 0.0}))
            except (InputError, ZeroDivisionError):
                continue
            if setup.y0 is not None and is_autonomous(setup.scene, setup.y0):
                keys.append(k)
        return keys

    def info(self) -> list:
        """One dict per parameter: key, default, unit, valid values, meaning."""
        return [{"key": k, "default": v, "unit": self.units[k],
                 "valid": describe_domain(self.domains[k]), "meaning": self.describe_params.get(k, "")}
                for k, v in self.defaults.items()]

