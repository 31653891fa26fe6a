"""Rotor files: a finite-element rotor scene as a TOML file (SI units).

`load_rotor(path)` reads a file into a `RotorScene`; `save_rotor(scene, path)`
writes one back (exactly: `load_rotor(save_rotor(scene))` has the same arrays).

Tables (array tables `[[...]]` hold one entry per item; indices in messages and
in override keys count from 0 in file order). A key with a default (after `=`)
may be left out; the others are required, except where two ways are offered
(`angles` or `n`, `masses` or `n_weights` + `mass`, `radius` or `r1` + `r2`):

| table                   | keys (defaults after `=`)                                                   |
|-------------------------|-----------------------------------------------------------------------------|
| `[rotor]`               | `name` (= file stem), `theory` ("euler-bernoulli", "rayleigh",             |
|                         | "timoshenko"), `n_modes` (optional: modal reduction), `speed` (rad/s, = 0) |
| `[[material]]`          | `name`, `E` (Pa), `G` (Pa; or `nu`), `rho` (kg/m^3), `nu` (= E / (2 G) - 1) |
| `[[shaft]]`             | `L` (m), `od` (m), `id` (m, = 0), `material` (a `[[material]]`'s name or a |
|                         | built-in one: steel, stainless, aluminium, titanium); `od`, `id` may be    |
|                         | `[left, right]` (a tapered element); element i joins nodes i and i + 1     |
| `[[disk]]`              | `node`, `m` (kg), `Id` (kg m^2, diametral), `Ip` (kg m^2, polar)            |
| `[[bearing]]`           | `node`, `kxx`, `kyy` (= kxx), `kxy`, `kyx` (= 0) (N/m), `cxx` (= 0),        |
|                         | `cyy` (= cxx), `cxy`, `cyx` (= 0) (N s/m), `mxx` (= 0), `myy` (= mxx),      |
|                         | `mxy`, `myx` (= 0) (kg); with `speeds = [...]` (rad/s) each coefficient     |
|                         | may be a list of the same length (evaluated at the running speed by a     |
|                         | not-a-knot cubic spline). `type = "plain-journal"` instead: `load` (N,     |
|                         | along -y), `viscosity` (Pa s), `length`, `diameter`, `clearance` (m),      |
|                         | `method` ("short", "finite"; = "short"), `speeds` (the table's speeds).   |
|                         | `type = "journal"`: a fluid-film journal bearing as a nonlinear force       |
|                         | (loaded by `[gravity]` and the rotor's own weight, no `load`): `model`     |
|                         | ("short", "finite", "long"; = "short"), `viscosity`, `length`,             |
|                         | `diameter`, `clearance`. `type = "sfd"`: a squeeze-film damper:            |
|                         | `viscosity`, `length`, `diameter`, `clearance`, `film` ("pi", "2pi";      |
|                         | = "pi"), a centring spring `kxx` (N/m, = 0), `kyy` (= kxx)                 |
| `[[point_mass]]`        | `node`, `m` (kg) or `mx` + `my`                                             |
| `[[support]]`           | `bearing` (index from 0), `m` (kg), `kxx`, `kyy` (= kxx) (N/m), `cxx`       |
|                         | (= 0), `cyy` (= cxx) (N s/m): a pedestal between the bearing and ground    |
| `[[fixed]]`             | `node`, `dofs` (= ["x", "y", "sx", "sy"])                                  |
| `[[unbalance]]`         | `node`, `magnitude` (kg m), `phase` (rad, = 0)                              |
| `[internal_damping]`    | `relaxation_time` (s, Voigt)                                                |
| `[external_damping]`    | `coefficient` (N s/m^2: viscous damping of the shaft's lateral motion per   |
|                         | unit length, by its surroundings)                                           |
| `[[disk_damping]]`      | `node`, `translational` (N s/m, on the node's x, y velocity), `angular`     |
|                         | (N m s, on its tilt rates; = 0)                                             |
| `[gravity]`             | `g` (m/s^2, = 9.81), `angle` (rad, = -pi/2: along -y)                       |
| `[[cubic_bearing]]`     | `node`, `k3` (N/m^3), `k` (N/m, = 0), `c` (N s/m, = 0)                      |
| `[[clearance_bearing]]` | `node`, `clearance` (m), `k` (N/m), `c` (N s/m, = 0),                       |
|                         | `smoothing` (m, = clearance / 1000)                                         |
| `[[limiters]]`          | `node`, `angles` (rad, list) or `n` + `first_angle` (= 0), `clearance` (m), |
|                         | `stiffness` (N/m), `damping` (N s/m, = 0), `friction` (= 0) (each a number  |
|                         | or one per limiter), `radius` (m, rim), `smoothing` (m, = 1e-6)             |
| `[[auto_balancer]]`     | `node`, `masses` (kg, list) or `n_weights` + `mass`, `radius` or `r1` +     |
|                         | `r2` (m), `center` (m, = [0, 0]), `drag` (N s/m, = 0), `kind` ("ball",      |
|                         | "roller", "pendulum"; = "ball") or `inertia_factor`                         |
| `[[probe]]`             | `node`, `name` (= "disk"; letters, digits, _): a sensor, outputs only:      |
|                         | `<name>_x`, `<name>_y`, `<name>_vx`, `<name>_vy` (m, m/s), `<name>_tilt_x`, |
|                         | `<name>_tilt_y` (rad), `<name>_radius` (m); names differ between probes     |

The scene's components come in this order, each table's entries in file order:
unbalances, internal damping, external damping, disk damping, gravity, fluid films
(`[[bearing]]` entries of type "journal" and "sfd", in file order), cubic
bearings, clearance bearings, limiters, auto-balancers (whose weights'
coordinates follow the shaft's in the state), probes. A shaft whose elements all have the same material constants gets
scalar `E`, `G`, `rho`, `nu` (the exact arrays of a one-material `FlexibleRotor`);
otherwise they are per element.

Every check happens here, before anything is constructed, so an error names the
file, the table, the index and the key as the user wrote them
(`rotor.toml: shaft[4].od must be > id (got od = 0.05, id = 0.06)`), as an
`InputError`; so is a disk with `Ip > 2 Id` (beyond 5 %, for rounding: no rigid
body has it). Values that are valid but implausible in SI units, most likely a
unit slip, are `PlausibilityWarning`s issued once the file is valid, named the
same way and naming the slip (`rotor.toml: shaft[0].od = 60 m: outside the
plausible 0.5 mm..5 m for a diameter; did you mean mm (60 mm = 0.06 m)?`): `E`,
`G` outside 1e9..1e12 Pa, `rho` outside 500..25000 kg/m^3, lengths, diameters and
radii outside 0.5 mm..5 m (bores: above 5 m), an element's `L / od` outside
0.05..50, a disk's radius of gyration outside 0.5 mm..5 m
(`rotorjax.models._plausibility`).

Overrides (`load_rotor(path, {"bearing0.kxx": 2e7})`, the CLI's `--set`) name an
entry as `<table><index>.<key>` for array tables, `<table>.<key>` for single
tables, and `speed` for `[rotor] speed`.

The same names are parameter paths (`read_rotor_file(path).path(name)`): each
numeric key of an entry resolves, here, where the file's meaning is known, to the
leaves of the scene it sets (`rotorjax.models._parameters`), with the values that
follow it where the file leaves them out (`kyy` after `kxx`, a material's `G` or
`nu`, a clearance bearing's smoothing), so that setting it through the leaves builds
the scene the override builds.
"""

import dataclasses
import difflib
import importlib.resources
import json
import math
import os
import pathlib
import re
import tomllib

import jax
import numpy as np

from .._errors import InputError
from ._balancer import INERTIA_FACTORS, AutoBalancer, Race
from ._external_damping import DiskDamping, ExternalDamping
from ._fe_reduction import ReducedRotor
from ._fe_rotor import (BEARING_COEFFICIENTS, BEARING_FOLLOWS, DOFS_PER_NODE, SUPPORT_FOLLOWS, SUPPORT_KEYS, Bearing,
                        FlexibleRotor, Support, follow)
from ._fluid_film import JOURNAL_MODELS, SFD_FILMS, SFD_FOLLOWS, JournalBearing, SqueezeFilmDamper
from ._journal_bearing import PlainJournal
from ._gravity import Gravity
from ._internal_damping import InternalDamping
from ._limiters import Limiters
from ._materials import MATERIALS, poisson_ratio, shear_modulus
from ._node_parts import BalancerAt, LimitersAt
from ._node_probe import NodeProbe
from ._parameters import ParameterPath, Target
from ._nonlinear_bearings import ClearanceBearing, CubicBearing
from ._plausibility import IP_TOLERANCE, RANGES, gyration, judge, number, warn
from ._rotor_scene import RotorScene
from ._speed import ConstantSpeed
from ._unbalance import Unbalance
from ._validate import is_concrete

DOF_NAMES = ("x", "y", "sx", "sy")
THEORIES = ("euler-bernoulli", "rayleigh", "timoshenko")
KINDS = ("ball", "roller", "pendulum")
BEARING_TYPES = ("linear", "plain-journal", "journal", "sfd")
#: the [[bearing]] types that are nonlinear force components, not linear coefficients
FILM_TYPES = ("journal", "sfd")
FILM_KEYS = ("viscosity", "length", "diameter", "clearance")
JOURNAL_METHODS = ("short", "finite")
JOURNAL_KEYS = ("load", "viscosity", "length", "diameter", "clearance", "method")


# --- the schema -----------------------------------------------------------------------
@dataclasses.dataclass(frozen=True)
class _Key:
    """One key of a table. `kind`: "number", "count" (an integer), "node", "string",
    "numbers" (a list), "number_or_numbers" or "strings"; `sign` for numbers (and
    every entry of a list): "positive", "nonnegative" or "any"."""

    kind: str
    unit: str = ""
    meaning: str = ""
    sign: str = "any"
    required: bool = False
    choices: tuple = ()
    domain: str = ""  # a preset domain when the sign does not say it (nu, inertia_factor)


@dataclasses.dataclass(frozen=True)
class _Table:
    array: bool
    keys: dict
    meaning: str


def _node(what):
    return _Key("node", "node", f"node of the {what}", required=True)


_N, _S = "number", "string"
SCHEMA = {
    "rotor": _Table(False, {
        "name": _Key(_S, meaning="the rotor's name"),
        "theory": _Key(_S, meaning="shaft element theory", required=True, choices=THEORIES),
        "n_modes": _Key("count", "count", "modes kept by modal reduction of the linear part"),
        "speed": _Key(_N, "rad/s", "operating speed"),
    }, "the rotor"),
    "material": _Table(True, {
        "name": _Key(_S, meaning="material name", required=True),
        "E": _Key(_N, "Pa", "Young's modulus", "positive", True),
        "G": _Key(_N, "Pa", "shear modulus (or nu)", "positive"),
        "rho": _Key(_N, "kg/m^3", "density", "positive", True),
        "nu": _Key(_N, "dimensionless", "Poisson's ratio (Cowper's shear coefficient)", domain="(-1,0.5]"),
    }, "a shaft material"),
    "shaft": _Table(True, {
        "L": _Key(_N, "m", "element length", "positive", True),
        "od": _Key("number_or_numbers", "m", "outer diameter ([left, right]: tapered)", "positive", True),
        "id": _Key("number_or_numbers", "m", "inner diameter ([left, right]: tapered)", "nonnegative"),
        "material": _Key(_S, meaning="material (a [[material]] name or a built-in one)", required=True),
    }, "a shaft element"),
    "disk": _Table(True, {
        "node": _node("disk"),
        "m": _Key(_N, "kg", "mass", "positive", True),
        "Id": _Key(_N, "kg m^2", "diametral (transverse) inertia", "nonnegative", True),
        "Ip": _Key(_N, "kg m^2", "polar inertia", "nonnegative", True),
    }, "a rigid disk"),
    "bearing": _Table(True, {
        "node": _node("bearing"),
        "kxx": _Key("number_or_numbers", "N/m", "stiffness xx", "nonnegative"),
        "kyy": _Key("number_or_numbers", "N/m", "stiffness yy", "nonnegative"),
        "kxy": _Key("number_or_numbers", "N/m", "cross stiffness xy"),
        "kyx": _Key("number_or_numbers", "N/m", "cross stiffness yx"),
        "cxx": _Key("number_or_numbers", "N s/m", "damping xx", "nonnegative"),
        "cyy": _Key("number_or_numbers", "N s/m", "damping yy", "nonnegative"),
        "cxy": _Key("number_or_numbers", "N s/m", "cross damping xy"),
        "cyx": _Key("number_or_numbers", "N s/m", "cross damping yx"),
        "mxx": _Key("number_or_numbers", "kg", "mass coefficient xx", "nonnegative"),
        "myy": _Key("number_or_numbers", "kg", "mass coefficient yy", "nonnegative"),
        "mxy": _Key("number_or_numbers", "kg", "cross mass coefficient xy"),
        "myx": _Key("number_or_numbers", "kg", "cross mass coefficient yx"),
        "type": _Key(_S, meaning="bearing type", choices=BEARING_TYPES),
        "speeds": _Key("numbers", "rad/s", "speeds of the coefficient table", "nonnegative"),
        "load": _Key(_N, "N", "static load on a plain journal (along -y)", "positive"),
        "viscosity": _Key(_N, "Pa s", "lubricant dynamic viscosity", "positive"),
        "length": _Key(_N, "m", "journal bearing length", "positive"),
        "diameter": _Key(_N, "m", "journal diameter", "positive"),
        "clearance": _Key(_N, "m", "radial clearance", "positive"),
        "method": _Key(_S, meaning="journal-bearing solution", choices=JOURNAL_METHODS),
        "model": _Key(_S, meaning="journal-bearing film model", choices=JOURNAL_MODELS),
        "film": _Key(_S, meaning="squeeze-film extent", choices=SFD_FILMS),
    }, "a bearing: linear (constant, speed-dependent, or a plain journal's coefficients), or a fluid film "
       "(journal bearing, squeeze-film damper) as a nonlinear force"),
    "point_mass": _Table(True, {
        "node": _node("point mass"),
        "m": _Key(_N, "kg", "mass (x and y)", "nonnegative"),
        "mx": _Key(_N, "kg", "mass in x", "nonnegative"),
        "my": _Key(_N, "kg", "mass in y", "nonnegative"),
    }, "a point mass at a node"),
    "support": _Table(True, {
        "bearing": _Key("index", "index", "the [[bearing]] (index from 0) the pedestal carries", required=True),
        "m": _Key(_N, "kg", "pedestal mass", "positive", True),
        "kxx": _Key(_N, "N/m", "pedestal-to-ground stiffness xx", "nonnegative", True),
        "kyy": _Key(_N, "N/m", "pedestal-to-ground stiffness yy", "nonnegative"),
        "cxx": _Key(_N, "N s/m", "pedestal-to-ground damping xx", "nonnegative"),
        "cyy": _Key(_N, "N s/m", "pedestal-to-ground damping yy", "nonnegative"),
    }, "a bearing pedestal (mass, stiffness and damping to ground)"),
    "fixed": _Table(True, {
        "node": _node("fixed dofs"),
        "dofs": _Key("strings", meaning="dofs held at zero", choices=DOF_NAMES),
    }, "dofs held at zero"),
    "unbalance": _Table(True, {
        "node": _node("unbalance"),
        "magnitude": _Key(_N, "kg m", "unbalance (mass times eccentricity)", "nonnegative", True),
        "phase": _Key(_N, "rad", "angle from the reference mark"),
    }, "an unbalance"),
    "internal_damping": _Table(False, {
        "relaxation_time": _Key(_N, "s", "Voigt relaxation time T_V", "nonnegative", True),
    }, "Voigt internal damping of the shaft"),
    "external_damping": _Table(False, {
        "coefficient": _Key(_N, "N s/m^2", "viscous damping of the shaft's lateral motion per unit length",
                            "nonnegative", True),
    }, "viscous damping of the shaft by its surroundings"),
    "disk_damping": _Table(True, {
        "node": _node("disk damping"),
        "translational": _Key(_N, "N s/m", "viscous damping of the node's x, y motion", "nonnegative", True),
        "angular": _Key(_N, "N m s", "viscous damping of the node's tilts sx, sy", "nonnegative"),
    }, "viscous damping at a node (a disk's: air, squeeze film)"),
    "gravity": _Table(False, {
        "g": _Key(_N, "m/s^2", "gravitational acceleration", "nonnegative"),
        "angle": _Key(_N, "rad", "direction of gravity in the x-y plane"),
    }, "gravity"),
    "cubic_bearing": _Table(True, {
        "node": _node("cubic bearing"),
        "k3": _Key(_N, "N/m^3", "cubic (hardening) stiffness", "nonnegative", True),
        "k": _Key(_N, "N/m", "linear stiffness", "nonnegative"),
        "c": _Key(_N, "N s/m", "damping", "nonnegative"),
    }, "an isotropic bearing with cubic stiffness"),
    "clearance_bearing": _Table(True, {
        "node": _node("clearance bearing"),
        "clearance": _Key(_N, "m", "radial clearance", "positive", True),
        "k": _Key(_N, "N/m", "contact stiffness", "positive", True),
        "c": _Key(_N, "N s/m", "contact damping", "nonnegative"),
        "smoothing": _Key(_N, "m", "contact smoothing length", "positive"),
    }, "a bearing with a radial clearance"),
    "limiters": _Table(True, {
        "node": _node("limiters"),
        "angles": _Key("numbers", "rad", "angles of the limiters"),
        "n": _Key("count", "count", "number of evenly spaced limiters"),
        "first_angle": _Key(_N, "rad", "angle of the first of n evenly spaced limiters"),
        "clearance": _Key("number_or_numbers", "m", "clearance to the rim", "positive", True),
        "stiffness": _Key("number_or_numbers", "N/m", "contact stiffness", "nonnegative", True),
        "damping": _Key("number_or_numbers", "N s/m", "contact damping", "nonnegative"),
        "friction": _Key("number_or_numbers", "dimensionless", "Coulomb friction coefficient", "nonnegative"),
        "radius": _Key(_N, "m", "rim radius (friction slip speed)", "nonnegative", True),
        "smoothing": _Key(_N, "m", "contact smoothing length", "positive"),
    }, "visco-elastic limiters with friction around a node"),
    "auto_balancer": _Table(True, {
        "node": _node("auto-balancer"),
        "masses": _Key("numbers", "kg", "mass of each weight", "positive"),
        "n_weights": _Key("count", "count", "number of identical weights"),
        "mass": _Key(_N, "kg", "mass of each of n_weights weights", "positive"),
        "radius": _Key(_N, "m", "race radius", "positive"),
        "r1": _Key(_N, "m", "race semi-axis along the rotor-frame x axis", "positive"),
        "r2": _Key(_N, "m", "race semi-axis along the rotor-frame y axis", "positive"),
        "center": _Key("numbers", "m", "race centre in the rotor frame (x, y)"),
        "drag": _Key(_N, "N s/m", "viscous drag on the weights' relative motion", "nonnegative"),
        "kind": _Key(_S, meaning="weight kind", choices=KINDS),
        "inertia_factor": _Key(_N, "dimensionless", "inertia factor (instead of kind)", domain=">=1"),
    }, "a ball, roller or pendulum auto-balancer"),
    "probe": _Table(True, {
        "node": _node("probe"),
        "name": _Key(_S, meaning="the probe's name, the prefix of its outputs (<name>_x, <name>_y, ...)"),
    }, "a sensor at a node (outputs only)"),
}
#: a probe's name: the prefix of output keys (`disk_x`), so a word
PROBE_NAME = re.compile(r"[A-Za-z_][A-Za-z0-9_]*")
#: the scene's own outputs a probe's would replace (`node_x`, `node_y`)
RESERVED_PROBE_NAMES = ("node",)
SINGLE_KEY_ALIASES = {"speed": ("rotor", None, "speed")}


# --- reading ------------------------------------------------------------------------
class _Ctx:
    """The file being read: its label (the path as given) and the entries set by
    overrides (named in messages as well)."""

    def __init__(self, label):
        self.label = label
        self.overridden = {}
        self.warnings = []

    def _note(self, loc):
        return f" (set by the override {self.overridden[loc]})" if loc in self.overridden else ""

    def fail(self, msg, loc=None):
        raise InputError(f"{self.label}: {msg}{self._note(loc)}")

    def warn(self, msg, loc=None):
        """Note a plausibility warning; issued once the whole file is valid."""
        text = f"{self.label}: {msg}{self._note(loc)}"
        if text not in self.warnings:
            self.warnings.append(text)

    def issue_warnings(self):
        for text in self.warnings:
            warn(text)


def _loc(table, index, key=None):
    s = table if index is None else f"{table}[{index}]"
    return s if key is None else f"{s}.{key}"


def _toml_repr(value):
    """A value as TOML would write it (for messages)."""
    if isinstance(value, bool):
        return "true" if value else "false"
    if isinstance(value, str):
        return json.dumps(value, ensure_ascii=False)
    if isinstance(value, float):
        return repr(value)
    if isinstance(value, list):
        return "[" + ", ".join(_toml_repr(v) for v in value) + "]"
    if isinstance(value, dict):
        return "{" + ", ".join(f"{k} = {_toml_repr(v)}" for k, v in value.items()) + "}"
    return str(value)


def _what(value):
    """`value`'s TOML type in words, with the value."""
    if isinstance(value, bool):
        return f"a boolean ({_toml_repr(value)})"
    if isinstance(value, str):
        return f"a string ({_toml_repr(value)})"
    if isinstance(value, list):
        return f"a list ({_toml_repr(value)})"
    if isinstance(value, dict):
        return "a table"
    if isinstance(value, (int, float)):
        return f"the number {_toml_repr(value)}"
    return f"a {type(value).__name__} ({value})"


def _closest(name, known):
    """The key `name` most likely meant, or `None`: a doubled last letter (`kx` ->
    `kxx`, `cy` -> `cyy`: the direct coefficient before a cross one), the first key
    that starts with it (`spee` -> `speed`), a different case (`ip` -> `Ip`), else
    the nearest by `difflib` (`kzz` -> `kxx`)."""
    known = list(known)
    if not isinstance(name, str) or not name:
        return None
    if name + name[-1] in known:
        return name + name[-1]
    prefixed = [k for k in known if k.startswith(name)]
    if prefixed:
        return prefixed[0]
    folded = [k for k in known if k.lower() == name.lower()]
    if folded:
        return folded[0]
    close = difflib.get_close_matches(name, known, n=1)
    return close[0] if close else None


def _suggest(name, known):
    close = _closest(name, known)
    return f" (did you mean {close!r}?)" if close else ""


def _read(path):
    """The file's label and its parsed TOML."""
    if not isinstance(path, (str, os.PathLike)):
        raise InputError(f"rotor file: expected a path, got {type(path).__name__}")
    label = os.fspath(path)
    p = pathlib.Path(label)
    if not p.exists() and os.sep not in label and label.endswith(".toml"):
        try:  # a bare name of a shipped rotor file (`flexible_rig.toml`), as the CLI finds it
            p = shipped_rotor(label)
        except InputError:
            pass
    if not p.exists():
        raise InputError(f"{label}: no such rotor file")
    if not p.is_file():
        raise InputError(f"{label}: not a file (a rotor file is a TOML file)")
    try:
        raw = p.read_bytes()
    except OSError as e:
        raise InputError(f"{label}: cannot be read ({e.strerror})") from None
    try:
        text = raw.decode("utf-8")
    except UnicodeDecodeError as e:
        raise InputError(f"{label}: not UTF-8 text (byte 0x{raw[e.start]:02x} at offset {e.start}); "
                         f"a rotor file is UTF-8 TOML") from None
    if text.startswith("\ufeff"):
        text = text[1:]
    try:
        doc = tomllib.loads(text)
    except tomllib.TOMLDecodeError as e:
        raise InputError(f"{label}: not valid TOML: {e}") from None
    return label, doc


# --- overrides ------------------------------------------------------------------------
_OVERRIDE = re.compile(r"^([a-z_]+?)(\d+)?\.([A-Za-z_][A-Za-z0-9_]*)$")


def _parse_override_key(ctx, okey):
    """`(table, index, key)` of an override key (`bearing0.kxx`, `gravity.g`, `speed`)."""
    if not isinstance(okey, str):
        ctx.fail(f"override key {okey!r} must be a string such as 'bearing0.kxx'")
    if okey in SINGLE_KEY_ALIASES:
        return SINGLE_KEY_ALIASES[okey]
    m = _OVERRIDE.match(okey)
    if not m:
        ctx.fail(f"override {okey}: expected <table><index>.<key> (e.g. bearing0.kxx) or <table>.<key> "
                 f"(e.g. gravity.g)")
    table, index, key = m.group(1), m.group(2), m.group(3)
    if table not in SCHEMA:
        ctx.fail(f"override {okey}: unknown table {table!r}{_suggest(table, list(SCHEMA))}; "
                 f"known: {', '.join(SCHEMA)}")
    spec = SCHEMA[table]
    if spec.array and index is None:
        ctx.fail(f"override {okey}: [[{table}]] has one entry per item: name it as {table}<index>.{key} "
                 f"(e.g. {table}0.{key})")
    if not spec.array and index is not None:
        ctx.fail(f"override {okey}: [{table}] is a single table: name it as {table}.{key}")
    if key not in spec.keys:
        ctx.fail(f"override {okey}: unknown key {key!r} of [{'[' if spec.array else ''}{table}"
                 f"{']' if spec.array else ''}]{_suggest(key, list(spec.keys))}; known: {', '.join(spec.keys)}")
    return table, None if index is None else int(index), key


def _override_value(ctx, okey, spec, value):
    """An override's value as the file would hold it (strings parsed for numeric keys)."""
    if isinstance(value, (np.ndarray, np.generic, jax.Array)):
        if not is_concrete(value):
            ctx.fail(f"override {okey}: a traced value cannot be written into a rotor file; "
                     f"overrides are concrete")
        value = value.tolist()
    if isinstance(value, tuple):
        value = list(value)
    if isinstance(value, str) and spec.kind in ("number", "count", "node", "index", "number_or_numbers"):
        text = value.strip()
        try:
            value = int(text) if spec.kind in ("count", "node", "index") else float(text)
        except ValueError:
            try:
                value = float(text)
            except ValueError:
                ctx.fail(f"override {okey}={value}: must be a number")
    if spec.kind in ("count", "node", "index") and isinstance(value, float) and value.is_integer():
        value = int(value)
    return value


def _apply_overrides(ctx, doc, overrides):
    if not overrides:
        return doc
    if not isinstance(overrides, dict):
        ctx.fail(f"overrides must be a dict such as {{'bearing0.kxx': 2e7}}, got {type(overrides).__name__}")
    doc = {k: ([dict(e) if isinstance(e, dict) else e for e in v] if isinstance(v, list)
               else dict(v) if isinstance(v, dict) else v) for k, v in doc.items()}
    for okey, value in overrides.items():
        table, index, key = _parse_override_key(ctx, okey)
        spec = SCHEMA[table]
        if table not in doc:
            if table == "rotor":
                ctx.fail(f"override {okey}: the file has no [rotor] table")
            ctx.fail(f"override {okey}: the file has no {'[[' if spec.array else '['}{table}"
                     f"{']]' if spec.array else ']'} table (overrides change entries, they do not add them)")
        entries = doc[table]
        if spec.array:
            if not isinstance(entries, list) or not all(isinstance(e, dict) for e in entries):
                continue  # reported by the validation
            if not index < len(entries):
                have = f"{table}0..{table}{len(entries) - 1}" if len(entries) > 1 else f"{table}0"
                ctx.fail(f"override {okey}: the file has {len(entries)} [[{table}]] "
                         f"entr{'y' if len(entries) == 1 else 'ies'} ({have})")
            entry = entries[index]
        else:
            if not isinstance(entries, dict):
                continue
            entry = entries
        entry[key] = _override_value(ctx, okey, spec.keys[key], value)
        ctx.overridden[_loc(table, index, key)] = f"{okey}={_toml_repr(entry[key])}"
    return doc


# --- validation -----------------------------------------------------------------------
_SIGN_TEST = {"positive": (lambda v: v > 0, "> 0"), "nonnegative": (lambda v: v >= 0, ">= 0")}


def _number(ctx, where, value, sign="any", loc=None):
    loc = where if loc is None else loc
    if isinstance(value, bool) or not isinstance(value, (int, float)):
        ctx.fail(f"{where} must be a number, got {_what(value)}", loc)
    try:
        v = float(value)
    except OverflowError:
        ctx.fail(f"{where} must be finite, got {value}", loc)
    if not math.isfinite(v):
        ctx.fail(f"{where} must be finite, got {_toml_repr(v)}", loc)
    if sign in _SIGN_TEST and not _SIGN_TEST[sign][0](v):
        ctx.fail(f"{where} must be {_SIGN_TEST[sign][1]} (got {_toml_repr(value)})", loc)
    return v


def _value(ctx, table, index, key, spec, value, n_nodes):
    """One key's value checked against its spec (node ranges included)."""
    where = _loc(table, index, key)
    kind = spec.kind
    if kind == "number":
        v = _number(ctx, where, value, spec.sign)
        if key == "nu" and not -1 < v <= 0.5:
            ctx.fail(f"{where} must be in (-1, 0.5] (got {_toml_repr(value)})", where)
        if key == "inertia_factor" and not v >= 1:
            ctx.fail(f"{where} must be >= 1 (1 pendulum, 7/5 ball, 3/2 roller; got {_toml_repr(value)})", where)
        return v
    if kind in ("count", "node", "index"):
        if isinstance(value, bool) or not isinstance(value, int):
            ctx.fail(f"{where} must be an integer, got {_what(value)}", where)
        if kind == "index" and value < 0:
            ctx.fail(f"{where} must be >= 0 (an index from 0; got {value})", where)
        if kind == "node" and not 0 <= value < n_nodes:
            ctx.fail(f"{where} = {value}: the shaft has nodes 0..{n_nodes - 1}", where)
        if kind == "count" and value < 1:
            ctx.fail(f"{where} must be >= 1 (got {value})", where)
        return value
    if kind == "string":
        if not isinstance(value, str):
            ctx.fail(f"{where} must be a string, got {_what(value)}", where)
        if spec.choices and value not in spec.choices:
            ctx.fail(f"{where} must be one of {', '.join(json.dumps(c) for c in spec.choices)} "
                     f"(got {_toml_repr(value)})", where)
        return value
    if kind in ("numbers", "number_or_numbers"):
        if kind == "number_or_numbers" and not isinstance(value, list):
            return _number(ctx, where, value, spec.sign)
        if not isinstance(value, list):
            ctx.fail(f"{where} must be a list of numbers, got {_what(value)}", where)
        if not value:
            ctx.fail(f"{where} must be a non-empty list of numbers, got []", where)
        return [_number(ctx, f"{where}[{j}]", v, spec.sign, loc=where) for j, v in enumerate(value)]
    if kind == "strings":
        if not isinstance(value, list) or not value:
            ctx.fail(f"{where} must be a non-empty list of strings, got {_what(value)}", where)
        for j, v in enumerate(value):
            if not isinstance(v, str) or v not in spec.choices:
                ctx.fail(f"{where}[{j}] must be one of {', '.join(json.dumps(c) for c in spec.choices)} "
                         f"(got {_toml_repr(v)})", where)
        if len(set(value)) != len(value):
            ctx.fail(f"{where} names a dof twice (got {_toml_repr(value)})", where)
        return list(value)
    raise AssertionError(kind)


def _entries(ctx, doc, table):
    """The raw entries of `table` as a list of `(index, dict)` (index None for single tables)."""
    spec = SCHEMA[table]
    if table not in doc:
        return []
    raw = doc[table]
    if spec.array:
        if isinstance(raw, dict):
            ctx.fail(f"{table} must be an array of tables: write [[{table}]] (one per entry), not [{table}]",
                     table)
        if not isinstance(raw, list) or not all(isinstance(e, dict) for e in raw):
            ctx.fail(f"{table} must be an array of tables ([[{table}]]), got {_what(raw)}", table)
        return list(enumerate(raw))
    if isinstance(raw, list):
        ctx.fail(f"{table} must be a single table: write [{table}], not [[{table}]]", table)
    if not isinstance(raw, dict):
        ctx.fail(f"{table} must be a table ([{table}]), got {_what(raw)}", table)
    return [(None, raw)]


def _check_keys(ctx, table, index, entry, n_nodes):
    """Known keys present, required ones there; values checked. Returns a dict."""
    spec = SCHEMA[table]
    head = f"[[{table}]]" if spec.array else f"[{table}]"
    for key in entry:
        if key not in spec.keys:
            ctx.fail(f"{_loc(table, index, key)}: unknown key{_suggest(key, list(spec.keys))}; "
                     f"the keys of {head} are {', '.join(spec.keys)}", _loc(table, index, key))
    for key, k in spec.keys.items():
        if k.required and key not in entry:
            what = ", ".join(s for s in (k.meaning, k.unit) if s and s not in ("node", "count"))
            ctx.fail(f"{_loc(table, index, key)} is missing (required: {what or key})")
    return {key: _value(ctx, table, index, key, spec.keys[key], v, n_nodes) for key, v in entry.items()}


def _bearing(ctx, i, b):
    """A [[bearing]] entry checked and completed: a linear bearing (constant or with a
    `speeds` table) or a plain journal (its own keys only)."""
    where = _loc("bearing", i)
    kind = b.setdefault("type", "linear")
    given = [k for k in BEARING_COEFFICIENTS if k in b]
    if kind in FILM_TYPES:
        return _film_bearing(ctx, i, b, given)
    if kind == "plain-journal":
        if given:
            ctx.fail(f"{_loc('bearing', i, given[0])}: a plain-journal bearing computes its coefficients "
                     f"(from load, viscosity, length, diameter, clearance); do not give {given[0]}",
                     _loc("bearing", i, given[0]))
        for key in JOURNAL_KEYS[:-1] + ("speeds",):
            if key not in b:
                ctx.fail(f"{_loc('bearing', i, key)} is missing (required for type = \"plain-journal\": "
                         f"{SCHEMA['bearing'].keys[key].meaning}, {SCHEMA['bearing'].keys[key].unit})")
        b.setdefault("method", "short")
        if not b["clearance"] < b["diameter"] / 2:
            ctx.fail(f"{_loc('bearing', i, 'clearance')} must be < diameter / 2 (got clearance = "
                     f"{_toml_repr(b['clearance'])}, diameter = {_toml_repr(b['diameter'])})",
                     _loc("bearing", i, "clearance"))
    else:
        extra = [k for k in JOURNAL_KEYS if k in b]
        if extra:
            ctx.fail(f"{_loc('bearing', i, extra[0])} belongs to type = \"plain-journal\" bearings; this "
                     f"bearing is linear (give type = \"plain-journal\", or kxx, ...)", _loc("bearing", i, extra[0]))
        if "kxx" not in b:
            ctx.fail(f"{_loc('bearing', i, 'kxx')} is missing (required: stiffness xx, N/m)")
        for k in BEARING_COEFFICIENTS:
            if k not in BEARING_FOLLOWS:
                b.setdefault(k, 0.0)
        b.update(follow(b, BEARING_FOLLOWS))
    speeds = b.get("speeds")
    if speeds is not None:
        if len(speeds) < 2:
            ctx.fail(f"{_loc('bearing', i, 'speeds')} must hold at least 2 speeds (got {len(speeds)})",
                     _loc("bearing", i, "speeds"))
        if any(b2 <= a for a, b2 in zip(speeds, speeds[1:])):
            j = next(j for j in range(1, len(speeds)) if speeds[j] <= speeds[j - 1])
            ctx.fail(f"{_loc('bearing', i, 'speeds')} must be strictly increasing (speeds[{j}] = "
                     f"{_toml_repr(speeds[j])} after {_toml_repr(speeds[j - 1])})", _loc("bearing", i, "speeds"))
    for k in BEARING_COEFFICIENTS:
        v = b.get(k)
        if isinstance(v, list):
            if speeds is None:
                ctx.fail(f"{_loc('bearing', i, k)} is a list: give the speeds it is tabulated at "
                         f"(speeds = [...], rad/s)", _loc("bearing", i, k))
            if len(v) != len(speeds):
                ctx.fail(f"{_loc('bearing', i, k)} has {len(v)} values but speeds has {len(speeds)}",
                         _loc("bearing", i, k))
    return b


def _film_bearing(ctx, i, b, given):
    """A [[bearing]] of type "journal" or "sfd", checked and completed."""
    kind = b["type"]
    what = "journal bearing" if kind == "journal" else "squeeze-film damper"
    own = FILM_KEYS + (("model",) if kind == "journal" else ("film", "kxx", "kyy"))
    for key in list(b):
        if key not in own + ("node", "type"):
            reason = ("its load is the rotor's weight ([gravity]) and any static force; do not give load"
                      if key == "load" else
                      "it is a nonlinear force, not a coefficient table" if key in ("speeds", "method") or
                      key in BEARING_COEFFICIENTS else "not a key of this bearing type")
            ctx.fail(f"{_loc('bearing', i, key)}: a type = \"{kind}\" bearing ({what}) takes "
                     f"{', '.join(own)}; {reason}", _loc("bearing", i, key))
    for key in FILM_KEYS:
        if key not in b:
            spec = SCHEMA["bearing"].keys[key]
            ctx.fail(f"{_loc('bearing', i, key)} is missing (required for type = \"{kind}\": {spec.meaning}, "
                     f"{spec.unit})")
    for key in ("kxx", "kyy"):
        if isinstance(b.get(key), list):
            ctx.fail(f"{_loc('bearing', i, key)}: a squeeze-film damper's centring spring is one number (N/m)",
                     _loc("bearing", i, key))
    if not b["clearance"] < b["diameter"] / 2:
        ctx.fail(f"{_loc('bearing', i, 'clearance')} must be < diameter / 2 (the journal's radius; got clearance "
                 f"= {_toml_repr(b['clearance'])}, diameter = {_toml_repr(b['diameter'])})",
                 _loc("bearing", i, "clearance"))
    if kind == "journal":
        b.setdefault("model", "short")
        ratio = b["length"] / b["diameter"]
        if b["model"] == "short" and ratio > 1.0:
            ctx.fail(f"{_loc('bearing', i, 'length')}: the short-bearing model needs L/D <= 1, got L/D = "
                     f"{ratio:.4g}; use model = \"finite\"", _loc("bearing", i, "length"))
        if b["model"] == "short" and ratio > 0.5:
            ctx.warn(f"{_loc('bearing', i, 'length')}: L/D = {ratio:.4g} > 0.5: the short-bearing model "
                     f"overestimates the load capacity (use model = \"finite\")", _loc("bearing", i, "length"))
        if b["model"] == "finite" and not 0.25 <= ratio <= 1.0:
            ctx.fail(f"{_loc('bearing', i, 'length')}: the finite-bearing model covers 0.25 <= L/D <= 1, got "
                     f"L/D = {ratio:.4g}", _loc("bearing", i, "length"))
    else:
        b.setdefault("film", "pi")
        b.setdefault("kxx", 0.0)
        b.update(follow(b, SFD_FOLLOWS))
    return b


def _validate(ctx, doc):
    """The file's content, checked, as plain Python values per table."""
    for name, value in doc.items():
        if name not in SCHEMA:
            if isinstance(value, (dict, list)):
                ctx.fail(f"unknown table [{name}]{_suggest(name, list(SCHEMA))}; known tables: "
                         f"{', '.join(SCHEMA)}", name)
            ctx.fail(f"{name} = {_toml_repr(value)}: a key outside any table; rotor files hold tables only "
                     f"(known: {', '.join(SCHEMA)})", name)
    if "rotor" not in doc:
        ctx.fail("missing table [rotor] (with theory = \"timoshenko\", \"rayleigh\" or \"euler-bernoulli\")")
    _entries(ctx, doc, "rotor")
    shafts = _entries(ctx, doc, "shaft")
    if not shafts:
        ctx.fail("no [[shaft]] entries: a rotor needs at least one shaft element", "shaft")
    n_nodes = len(shafts) + 1
    out = {}
    for table in SCHEMA:
        out[table] = [_check_keys(ctx, table, i, e, n_nodes) for i, e in _entries(ctx, doc, table)]

    _plausible_values(ctx, out)
    materials = {}
    for i, m in enumerate(out["material"]):
        if m["name"] in materials:
            ctx.fail(f"material[{i}].name = {_toml_repr(m['name'])}: duplicate material name "
                     f"(also material[{materials[m['name']]}])", _loc("material", i, "name"))
        materials[m["name"]] = i
        if "G" not in m and "nu" not in m:
            ctx.fail(f"material[{i}]: give G (shear modulus, Pa) or nu (Poisson's ratio)", _loc("material", i))
        m.setdefault("G", shear_modulus(m["E"], m.get("nu", 0.0)))
    for i, s in enumerate(out["shaft"]):
        for key in ("od", "id"):
            v = s.get(key, 0.0)
            if isinstance(v, list) and len(v) != 2:
                ctx.fail(f"{_loc('shaft', i, key)} must be a number or [left, right] (a tapered element), "
                         f"got {len(v)} values", _loc("shaft", i, key))
            s[key] = [v, v] if not isinstance(v, list) else v
        for end, j in (("left", 0), ("right", 1)):
            if not s["od"][j] > s["id"][j]:
                od, idd = _loc("shaft", i, "od"), _loc("shaft", i, "id")
                at = "" if s["od"][0] == s["od"][1] and s["id"][0] == s["id"][1] else f" at the {end} end"
                ctx.fail(f"{od} must be > id{at} (got od = {_toml_repr(s['od'][j])}, "
                         f"id = {_toml_repr(s['id'][j])})", od if od in ctx.overridden else idd)
        if s["material"] not in materials and s["material"] not in MATERIALS:
            defined = list(materials) + [n for n in MATERIALS if n not in materials]
            ctx.fail(f"shaft[{i}].material = {_toml_repr(s['material'])}: no [[material]] of that name and no "
                     f"built-in material{_suggest(s['material'], defined)}; defined: "
                     f"{', '.join(json.dumps(n) for n in materials) or 'none'}; built in: "
                     f"{', '.join(json.dumps(n) for n in MATERIALS)}", _loc("shaft", i, "material"))

    _plausible_slenderness(ctx, out["shaft"])
    _disks(ctx, out["disk"])
    for i, b in enumerate(out["bearing"]):
        _bearing(ctx, i, b)
    for i, pm in enumerate(out["point_mass"]):
        where = _loc("point_mass", i)
        if ("m" in pm) == ("mx" in pm or "my" in pm):
            ctx.fail(f"{where}: give either m or mx and my{', not both' if 'm' in pm else '; got neither'}",
                     where)
        if "m" in pm:
            pm["mx"] = pm["my"] = pm.pop("m")
        for key in ("mx", "my"):
            if key not in pm:
                ctx.fail(f"{_loc('point_mass', i, key)} is missing (mx and my go together)")
    carried = {}
    for i, sup in enumerate(out["support"]):
        n_b = len(out["bearing"])
        if not sup["bearing"] < n_b:
            ctx.fail(f"support[{i}].bearing = {sup['bearing']}: the file has {n_b} [[bearing]] "
                     f"entr{'y' if n_b == 1 else 'ies'} (indices 0..{n_b - 1})" if n_b else
                     f"support[{i}].bearing = {sup['bearing']}: the file has no [[bearing]] entries",
                     _loc("support", i, "bearing"))
        if out["bearing"][sup["bearing"]]["type"] in FILM_TYPES:
            ctx.fail(f"support[{i}].bearing = {sup['bearing']}: that bearing is a type = "
                     f"\"{out['bearing'][sup['bearing']]['type']}\" fluid film; pedestals carry linear bearings only",
                     _loc("support", i, "bearing"))
        if sup["bearing"] in carried:
            ctx.fail(f"support[{i}].bearing = {sup['bearing']}: that bearing already sits on "
                     f"support[{carried[sup['bearing']]}]", _loc("support", i, "bearing"))
        carried[sup["bearing"]] = i
        sup.setdefault("cxx", 0.0)
        sup.update(follow(sup, SUPPORT_FOLLOWS))
    fixed = set()
    for i, f in enumerate(out["fixed"]):
        f.setdefault("dofs", list(DOF_NAMES))
        fixed.update(DOFS_PER_NODE * f["node"] + DOF_NAMES.index(d) for d in f["dofs"])
    n_free = DOFS_PER_NODE * n_nodes - len(fixed)
    if n_free == 0:
        ctx.fail("fixed: the [[fixed]] entries hold every dof of the shaft at zero: nothing is left to move",
                 "fixed")
    r = out["rotor"][0]
    r.setdefault("name", pathlib.Path(ctx.label).stem)
    r.setdefault("speed", 0.0)
    if "n_modes" in r and not r["n_modes"] <= n_free:
        ctx.fail(f"rotor.n_modes = {r['n_modes']}: the shaft has {n_free} free dofs (n_modes must be "
                 f"1..{n_free})", "rotor.n_modes")
    for u in out["unbalance"]:
        u.setdefault("phase", 0.0)
    for g in out["gravity"]:
        g.setdefault("g", 9.81)
        g.setdefault("angle", -np.pi / 2)
    for d in out["disk_damping"]:
        d.setdefault("angular", 0.0)
    _probes(ctx, out["probe"])
    for c in out["cubic_bearing"]:
        c.setdefault("k", 0.0)
        c.setdefault("c", 0.0)
    for c in out["clearance_bearing"]:
        c.setdefault("c", 0.0)
        c.setdefault("smoothing", None)

    for i, lim in enumerate(out["limiters"]):
        where = _loc("limiters", i)
        if ("angles" in lim) == ("n" in lim):
            ctx.fail(f"{where}: give either angles = [...] or n (with first_angle)"
                     f"{', not both' if 'angles' in lim else '; got neither'}", where)
        if "angles" in lim and "first_angle" in lim:
            ctx.fail(f"{where}.first_angle goes with n (evenly spaced limiters), not with angles",
                     _loc("limiters", i, "first_angle"))
        if "n" in lim:
            first, count = lim.pop("first_angle", 0.0), lim.pop("n")
            lim["angles"] = [float(a) for a in first + 2 * np.pi * np.arange(count) / count]
        n = len(lim["angles"])
        lim.setdefault("damping", 0.0)
        lim.setdefault("friction", 0.0)
        lim.setdefault("smoothing", 1e-6)
        for key in ("clearance", "stiffness", "damping", "friction"):
            if isinstance(lim[key], list) and len(lim[key]) != n:
                ctx.fail(f"{_loc('limiters', i, key)} must be a number or one value per limiter ({n}), "
                         f"got {len(lim[key])} values", _loc("limiters", i, key))

    for i, ab in enumerate(out["auto_balancer"]):
        where = _loc("auto_balancer", i)
        has_list, has_count = "masses" in ab, ("n_weights" in ab or "mass" in ab)
        if has_list == has_count:
            ctx.fail(f"{where}: give either masses = [...] or n_weights and mass"
                     f"{', not both' if has_list else '; got neither'}", where)
        if has_count:
            for key in ("n_weights", "mass"):
                if key not in ab:
                    ctx.fail(f"{_loc('auto_balancer', i, key)} is missing (n_weights and mass go together)")
            ab["masses"] = [ab.pop("mass")] * ab.pop("n_weights")
        if ("radius" in ab) == ("r1" in ab or "r2" in ab):
            ctx.fail(f"{where}: give either radius or r1 and r2 (an elliptic race)"
                     f"{', not both' if 'radius' in ab else '; got neither'}", where)
        if "radius" in ab:
            ab["r1"] = ab["r2"] = ab.pop("radius")
        for key in ("r1", "r2"):
            if key not in ab:
                ctx.fail(f"{_loc('auto_balancer', i, key)} is missing (r1 and r2 go together)")
        ab.setdefault("center", [0.0, 0.0])
        if len(ab["center"]) != 2:
            ctx.fail(f"{_loc('auto_balancer', i, 'center')} must be [x, y] (2 numbers), got "
                     f"{len(ab['center'])}", _loc("auto_balancer", i, "center"))
        if "kind" in ab and "inertia_factor" in ab:
            ctx.fail(f"{where}: give kind or inertia_factor, not both", where)
        ab.setdefault("drag", 0.0)
    ctx.issue_warnings()
    return out


#: the keys whose values `_plausibility.judge` checks, and as what (`RANGES`)
PLAUSIBLE = {
    ("material", "E"): "E", ("material", "G"): "G", ("material", "rho"): "rho",
    ("shaft", "L"): "length", ("shaft", "od"): "diameter", ("shaft", "id"): "bore",
    ("bearing", "length"): "length", ("bearing", "diameter"): "diameter",
    ("limiters", "radius"): "radius",
    ("auto_balancer", "radius"): "radius", ("auto_balancer", "r1"): "radius", ("auto_balancer", "r2"): "radius",
}


def _plausible_values(ctx, out):
    """A plausibility warning for each implausible value (`PLAUSIBLE`), once per key and
    value: `shaft[0].od = 60 m (and 5 more [[shaft]] entries): ...; did you mean mm?`."""
    for (table, key), quantity in PLAUSIBLE.items():
        seen = {}
        for i, entry in enumerate(out[table]):
            value = entry.get(key)
            for v in (value if isinstance(value, list) else [value]):
                if v is not None and v != 0:
                    seen.setdefault(v, []).append(i)
        for v, where in seen.items():
            why = judge(quantity, v)
            if why:
                loc = _loc(table, where[0], key)
                more = len(set(where) - {where[0]})
                also = f" (and {more} more [[{table}]] entr{'y' if more == 1 else 'ies'})" if more else ""
                ctx.warn(f"{loc} = {number(v)} {RANGES[quantity].unit}{also}: {why}", loc)


def _plausible_slenderness(ctx, shafts):
    """One warning for the first element whose `L / od` (mean od of a taper) is outside
    the plausible range while `L` and `od` each are plausible."""
    for i, s in enumerate(shafts):
        od = (s["od"][0] + s["od"][1]) / 2
        if judge("length", s["L"]) or any(judge("diameter", d) for d in s["od"]):
            continue
        why = judge("slenderness", s["L"] / od)
        if why:
            ctx.warn(f"shaft[{i}]: L / od = {number(s['L'] / od)} (L = {number(s['L'])} m, od = {number(od)} m) "
                     f"is outside the plausible {RANGES['slenderness'].text}: a unit slip in L or od?",
                     _loc("shaft", i, "L"))
            return


def _disks(ctx, disks):
    """`Ip <= 2 Id` (an `InputError` beyond `IP_TOLERANCE`: no rigid body has more); radii
    of gyration (a warning)."""
    for i, d in enumerate(disks):
        if d["Ip"] > 2 * d["Id"] * (1 + IP_TOLERANCE):
            ip, idd = _loc("disk", i, "Ip"), _loc("disk", i, "Id")
            ctx.fail(f"{ip} = {_toml_repr(d['Ip'])} > 2 Id = {number(2 * d['Id'])} kg m^2: impossible for a rigid "
                     f"body (the perpendicular-axis theorem: Ip <= 2 Id); are Id and Ip swapped, or in different "
                     f"units?",
                     ip if ip in ctx.overridden else idd)
        for key in ("Id", "Ip"):
            why = gyration(d[key], d["m"])
            if why:
                loc = _loc("disk", i, key)
                ctx.warn(f"{loc} = {number(d[key])} kg m^2 with m = {number(d['m'])} kg: {why}", loc)


def _probes(ctx, probes):
    """Each probe named (default "disk"), by a word, not `node` (the scene's own
    `node_x`, `node_y`), and no two alike (their outputs would overwrite each
    other's)."""
    seen = {}
    for i, p in enumerate(probes):
        p.setdefault("name", "disk")
        name, where = p["name"], _loc("probe", i, "name")
        if not PROBE_NAME.fullmatch(name):
            ctx.fail(f"{where} = {_toml_repr(name)}: must be a word (letters, digits and _, not starting with a "
                     f"digit): it prefixes the probe's outputs ({name}_x, ...)", where)
        if name in RESERVED_PROBE_NAMES:
            ctx.fail(f"{where} = {_toml_repr(name)}: its outputs {name}_x, {name}_y would replace the scene's own "
                     f"(every node's x, y); choose another name", where)
        if name in seen:
            ctx.fail(f"{where} = {_toml_repr(name)}: probe[{seen[name]}] has that name already (their outputs "
                     f"would overwrite each other's); give each probe its own name", where)
        seen[name] = i


# --- building -------------------------------------------------------------------------
def _material_constants(spec):
    """`E, G, rho, nu` for `FlexibleRotor`: scalars when every element has the same
    constants, per-element arrays otherwise (`nu` None where no material gives it).
    A shaft's material is the file's `[[material]]` of that name, else the built-in one."""
    mats = {m["name"]: m for m in spec["material"]}
    for name in {s["material"] for s in spec["shaft"]} - set(mats):
        lib = MATERIALS[name]
        mats[name] = {"name": name, "E": lib.E, "G": lib.G, "rho": lib.rho, "nu": lib.nu}
    used = [mats[s["material"]] for s in spec["shaft"]]

    eff = [(m["E"], m["G"], m["rho"], m.get("nu", poisson_ratio(m["E"], m["G"]))) for m in used]
    given = any("nu" in m for m in used)
    if all(e == eff[0] for e in eff):
        E, G, rho, nu = eff[0]
        return E, G, rho, (nu if given else None)
    E, G, rho, nu = (np.array(col, dtype=np.float64) for col in zip(*eff))
    return E, G, rho, (nu if given else None)


def _diameters(shafts):
    """Outer and inner diameters: per element, or `[left, right]` per element when
    any element is tapered."""
    od = np.array([s["od"] for s in shafts], dtype=np.float64)
    idd = np.array([s["id"] for s in shafts], dtype=np.float64)
    if np.all(od[:, 0] == od[:, 1]) and np.all(idd[:, 0] == idd[:, 1]):
        return od[:, 0], idd[:, 0]
    return od, idd


def _bearing_entry(b):
    """A `FlexibleRotor` bearing: the plain tuple for a constant bearing without mass
    coefficients (the arrays of earlier files, unchanged), else a `Bearing`."""
    if b["type"] == "plain-journal":
        journal = PlainJournal(b["load"], b["viscosity"], b["length"], b["diameter"], b["clearance"],
                               method=b["method"])
        return journal.bearing(b["node"], np.array(b["speeds"], dtype=np.float64))
    if "speeds" not in b and all(b[k] == 0 for k in ("mxx", "myy", "mxy", "myx")):
        return (b["node"], b["kxx"], b["kyy"], b["cxx"], b["cyy"], b["kxy"], b["kyx"], b["cxy"], b["cyx"])
    coef = {k: (np.array(b[k], dtype=np.float64) if isinstance(b[k], list) else b[k])
            for k in BEARING_COEFFICIENTS}
    speeds = None if "speeds" not in b else np.array(b["speeds"], dtype=np.float64)
    return Bearing(b["node"], speeds=speeds, **coef)


def _film_component(b):
    geometry = (b["viscosity"], b["length"], b["diameter"], b["clearance"])
    if b["type"] == "journal":
        return JournalBearing(b["node"], *geometry, model=b["model"])
    return SqueezeFilmDamper(b["node"], *geometry, film=b["film"], kxx=b["kxx"], kyy=b["kyy"])


def _limiters(lim):
    return LimitersAt(lim["node"], Limiters(np.array(lim["angles"]), np.asarray(lim["clearance"]),
                                            np.asarray(lim["stiffness"]), np.asarray(lim["damping"]),
                                            np.asarray(lim["friction"]), lim["smoothing"]), lim["radius"])


def _auto_balancer(ab):
    race = Race(ab["r1"], ab["r2"], tuple(ab["center"]))
    if "inertia_factor" in ab:
        bal = AutoBalancer(np.array(ab["masses"]), race, ab["drag"], inertia_factor=ab["inertia_factor"])
    else:
        bal = AutoBalancer(np.array(ab["masses"]), race, ab["drag"], kind=ab.get("kind", "ball"))
    return BalancerAt(ab["node"], bal)


#: the scene's components, in its order: each table's entries in file order (`[[bearing]]`: the fluid films)
_COMPONENTS = (
    ("unbalance", lambda u: Unbalance(u["node"], u["magnitude"], u["phase"])),
    ("internal_damping", lambda d: InternalDamping(d["relaxation_time"])),
    ("external_damping", lambda d: ExternalDamping(d["coefficient"])),
    ("disk_damping", lambda d: DiskDamping(d["node"], d["translational"], d["angular"])),
    ("gravity", lambda g: Gravity(g["g"], g["angle"])),
    ("bearing", _film_component),
    ("cubic_bearing", lambda c: CubicBearing(c["node"], c["k3"], c["k"], c["c"])),
    ("clearance_bearing", lambda c: ClearanceBearing(c["node"], c["clearance"], c["k"], c["c"], c["smoothing"])),
    ("limiters", _limiters),
    ("auto_balancer", _auto_balancer),
    ("probe", lambda p: NodeProbe(p["node"], p["name"])),
)


def _extras(spec):
    """Point masses and supports (keyword arguments only where the file has them)."""
    out = {}
    if spec["point_mass"]:
        out["point_masses"] = tuple((p["node"], p["mx"], p["my"]) for p in spec["point_mass"])
    if spec["support"]:
        # a support names its bearing among the file's [[bearing]] entries; the FE rotor's exclude the films
        linear = [i for i, b in enumerate(spec["bearing"]) if b["type"] not in FILM_TYPES]
        out["supports"] = tuple(Support(linear.index(s["bearing"]), s["m"], s["kxx"], s["kyy"], s["cxx"], s["cyy"])
                                for s in spec["support"])
    return out


def _build(ctx, spec, track_work, placed=None):
    """The scene of a checked file; `placed` (a dict), when given, receives each
    component entry's place among the scene's components, `(table, index) -> j`."""
    r = spec["rotor"][0]
    E, G, rho, nu = _material_constants(spec)
    shafts = spec["shaft"]
    d_out, d_in = _diameters(shafts)
    try:
        rotor = FlexibleRotor(
            np.array([s["L"] for s in shafts]), d_out, d_in, E=E, G=G, rho=rho, nu=nu, plausibility=False,
            disks=tuple((d["node"], d["m"], d["Id"], d["Ip"]) for d in spec["disk"]),
            bearings=tuple(_bearing_entry(b) for b in spec["bearing"] if b["type"] not in FILM_TYPES),
            **_extras(spec),
            theory=r["theory"],
            fixed_dofs=tuple((f["node"], DOF_NAMES.index(d)) for f in spec["fixed"] for d in f["dofs"]))
        if "n_modes" in r:
            rotor = rotor.reduce(r["n_modes"])
        parts = []
        placed = {} if placed is None else placed
        for table, make in _COMPONENTS:
            for i, entry in enumerate(spec[table]):
                if table != "bearing" or entry["type"] in FILM_TYPES:
                    placed[(table, i)] = len(parts)
                    parts.append(make(entry))
        return RotorScene(rotor, ConstantSpeed(r["speed"]), tuple(parts), track_work=track_work)
    except InputError as e:  # a check the loader does not repeat (e.g. nu from E and G)
        raise InputError(f"{ctx.label}: {e}") from None


def load_rotor(path, overrides=None, *, track_work=False) -> RotorScene:
    """The `RotorScene` of a rotor file (see the module docstring for the tables).

    **Arguments:**
    - `path`: the TOML file.
    - `overrides`: `{key: value}` replacing entries of the file before it is
      checked: `"bearing0.kxx"` (array tables: table, index from 0, key),
      `"gravity.g"` (single tables), `"speed"` (`[rotor] speed`). Strings are
      parsed as numbers for numeric keys (as `--set` gives them).
    - `track_work`: give the scene a work state (energy-balance checks).

    **Returns:** the scene, at the constant speed `[rotor] speed` (0 by default).

    **Raises:** `InputError` naming the file, table, index and key.
    """
    label, doc = _read(path)
    ctx = _Ctx(label)
    doc = _apply_overrides(ctx, doc, overrides)
    return _build(ctx, _validate(ctx, doc), bool(track_work))


@dataclasses.dataclass(frozen=True)
class FileParameter:
    """A scalar entry of a rotor file, as a `--set` key sees it."""

    value: object
    unit: str
    meaning: str
    domain: str
    integer: bool
    path: ParameterPath = dataclasses.field(default=None, compare=False)  # the leaves it sets in the scene


def file_parameters(path):
    """The file's label, its `[rotor] name` and its scalar numeric entries as
    `{key: FileParameter}` (keys `table<index>.key`, `table.key`, and `speed`),
    after checking the whole file (it is built once)."""
    return file_parameters_and_scene(path)[:3]


def file_parameters_and_scene(path):
    """`file_parameters(path)` and the `RotorScene` the file builds (the check's
    build, for a caller that needs the scene as the file gives it: no second build)."""
    f = read_rotor_file(path)
    return f.label, f.name, f.entries, f.scene


@dataclasses.dataclass(frozen=True, eq=False)
class RotorFile:
    """A rotor file read, checked and built once: its label and `[rotor] name`, its
    scalar entries (`{key: FileParameter}`), its scene, and `path(name)`, the
    `ParameterPath` of any numeric key of its entries (given or left at its default)."""

    label: str
    name: str
    entries: dict
    scene: RotorScene
    spec: dict = dataclasses.field(repr=False)
    raw: dict = dataclasses.field(repr=False)      # table -> [(index, the entry as the file gives it)]
    placed: dict = dataclasses.field(repr=False)   # (table, index) -> the component's place in the scene

    def path(self, name):
        """The `ParameterPath` called `name` (`bearing0.kxy`, `material0.E`, `speed`),
        or None when the file has no such entry or key."""
        if name in self.entries:
            return self.entries[name].path
        if not isinstance(name, str):
            return None
        m = _OVERRIDE.match(name)
        if not m or m.group(1) not in SCHEMA or name in SINGLE_KEY_ALIASES:
            return None
        table, index, key = m.group(1), m.group(2), m.group(3)
        spec = SCHEMA[table]
        i = None if index is None else int(index)
        if key not in spec.keys or spec.array != (i is not None) or spec.keys[key].kind not in (
                "number", "number_or_numbers"):
            return None
        entries = dict(self.raw.get(table, []))
        if i not in entries:
            return None
        return _parameter_path(name, table, i, key, entries[i], self.spec, self.placed, self.scene.full_rotor)

    def signed(self, name) -> bool:
        """Whether the key `name` may be negative (a cross-coupled coefficient, a phase)."""
        if name == "speed":
            return True
        table, key = _OVERRIDE.match(name).group(1), name.rpartition(".")[2]
        return SCHEMA[table].keys[key].sign == "any"


def read_rotor_file(path, overrides=None) -> RotorFile:
    """The `RotorFile` of `path` with `overrides` (as `load_rotor`'s) applied."""
    label, doc = _read(path)
    ctx = _Ctx(label)
    doc = _apply_overrides(ctx, doc, overrides)
    spec = _validate(ctx, doc)
    placed = {}
    scene = _build(ctx, spec, False, placed)
    n_el = len(spec["shaft"])
    n_free = len(scene.rotor.free_dofs)
    r = spec["rotor"][0]
    out = {"speed": FileParameter(float(r["speed"]), "rad/s", "operating speed ([rotor] speed)", "any", False,
                                  ParameterPath("speed", (Target(("speed", "constant")),)))}
    for table, t in SCHEMA.items():
        for index, entry in _entries(ctx, doc, table):
            for key, value in entry.items():
                k = t.keys[key]
                scalar = k.kind in ("number", "count", "node", "index") or (k.kind == "number_or_numbers"
                                                                   and not isinstance(value, list))
                if not scalar or (table, key) == ("rotor", "speed"):
                    continue
                name = f"{table}{index}.{key}" if t.array else f"{table}.{key}"
                at = f" at node {entry['node']}" if "node" in entry and key != "node" else ""
                meaning = f"{_loc(table, index)}{at}: {k.meaning}"
                if k.kind == "node":
                    domain = f"int[0,{n_el}]"
                elif k.kind == "index":
                    domain = f"int[0,{max(len(spec['bearing']) - 1, 0)}]"
                elif k.kind == "count":
                    domain = f"int[1,{n_free}]" if key == "n_modes" else "int>=1"
                else:
                    domain = k.domain or {"positive": ">0", "nonnegative": ">=0", "any": "any"}[k.sign]
                integer = k.kind in ("node", "count", "index")
                where = _parameter_path(name, table, index, key, entry, spec, placed, scene.full_rotor)
                out[name] = FileParameter(int(value) if integer else float(value), k.unit or "dimensionless",
                                          meaning, domain, integer, where)
    raw = {table: _entries(ctx, doc, table) for table in SCHEMA}
    return RotorFile(label, r["name"], out, scene, spec, raw, placed)


def _refused(name, why):
    return ParameterPath(name, refusal=why)


#: keys of component tables that are not the component's field of the same name
_COMPONENT_LEAVES = {
    ("limiters", "clearance"): ("limiters", "clearance"), ("limiters", "stiffness"): ("limiters", "stiffness"),
    ("limiters", "damping"): ("limiters", "damping"), ("limiters", "friction"): ("limiters", "friction"),
    ("limiters", "smoothing"): ("limiters", "smoothing"), ("limiters", "radius"): ("radius",),
    ("auto_balancer", "mass"): ("balancer", "mass"), ("auto_balancer", "drag"): ("balancer", "drag"),
    ("auto_balancer", "inertia_factor"): ("balancer", "inertia_factor"),
    ("auto_balancer", "r1"): ("balancer", "race", "r1"), ("auto_balancer", "r2"): ("balancer", "race", "r2"),
}
#: a key that sets several leaves
_COMPONENT_SPREAD = {("auto_balancer", "radius"): ("r1", "r2")}


def _parameter_path(name, table, i, key, entry, spec, placed, rotor):
    """The `ParameterPath` of the scalar file entry `name` (`table[i].key`; `entry`
    the keys the file gives): the leaves of the scene it sets, with the values that
    follow it where the file leaves them out, or why it is not a leaf; None for a key
    of another type of the entry's table (a film's key on a linear bearing)."""
    kind = SCHEMA[table].keys[key].kind
    if isinstance(entry.get(key), list):
        if table == "bearing":
            return _refused(name, f"bearing{i} is tabulated against speed (one value per speed); only its "
                                  f"single-valued coefficients are parameters")
        return _refused(name, f"{_loc(table, i, key)} is a list, not one value")
    if kind in ("count", "node", "index"):
        return _refused(name, "an integer that shapes the scene (a --set rebuilds it); it is not a value "
                              "that can be fitted")
    if table == "material":
        return _material_path(name, i, key, entry, spec, rotor)
    if table == "shaft":
        leaf = {"L": "lengths", "od": "d_out", "id": "d_in"}[key]
        return ParameterPath(name, (Target(("rotor", leaf), (i,)),))
    if table == "disk":
        return ParameterPath(name, (Target(("rotor", "disk_params"), (i, ("m", "Id", "Ip").index(key))),), True)
    if table == "point_mass":
        cols = {"m": (0, 1), "mx": (0,), "my": (1,)}[key]
        return ParameterPath(name, tuple(Target(("rotor", "point_mass_params"), (i, c)) for c in cols), True)
    if table == "support":
        keys = [key] + [f for f, lead in SUPPORT_FOLLOWS.items() if lead == key and f not in entry]
        return ParameterPath(name, tuple(Target(("rotor", "support_params"), (i, SUPPORT_KEYS.index(k)))
                                         for k in keys), True)
    if table == "bearing" and spec["bearing"][i]["type"] not in FILM_TYPES:
        return _bearing_path(name, i, key, entry, spec, rotor)
    i = 0 if i is None else i   # a single table: its one entry
    j = placed[(table, i)]
    if (table, key) == ("limiters", "first_angle"):
        return _refused(name, "it places the limiters when the file is read (their angles are the leaves); "
                              "not a value that can be fitted")
    if table == "bearing" and key not in FILM_KEYS + (("kxx", "kyy") if spec["bearing"][i]["type"] == "sfd" else ()):
        return None   # a key of another bearing type
    keys = list(_COMPONENT_SPREAD.get((table, key), (key,)))
    if table == "bearing":   # a squeeze-film damper's centring spring
        keys += [f for f, lead in SFD_FOLLOWS.items() if lead == key and f not in entry]
    targets = [Target(("components", j) + _COMPONENT_LEAVES.get((table, k), (k,))) for k in keys]
    if (table, key) == ("clearance_bearing", "clearance") and "smoothing" not in entry:
        targets.append(Target(("components", j, "smoothing"), None, "smoothing"))
    return ParameterPath(name, tuple(targets))


def _bearing_path(name, i, key, entry, spec, rotor):
    """A linear bearing's coefficient: its entry of the rotor's constant coefficients, or
    every speed of its table; its followers with it (`BEARING_FOLLOWS`)."""
    b = spec["bearing"][i]
    if b["type"] == "plain-journal":
        return _refused(name, f"bearing{i} is a plain journal, which computes its coefficients (tabulated against "
                              f"speed) when the rotor is built: they are not leaves of the scene")
    if key not in BEARING_COEFFICIENTS:
        return None   # a key of another bearing type
    row = [k for k, e in enumerate(spec["bearing"]) if e["type"] not in FILM_TYPES].index(i)
    keys = [key] + [f for f, lead in BEARING_FOLLOWS.items() if lead == key and f not in entry]
    targets = []
    for k in keys:
        col = BEARING_COEFFICIENTS.index(k)
        if rotor.bearing_tables[row] is not None:
            targets.append(Target(("rotor", "bearing_tables", row, 1), (col,)))
        elif col < 8:
            targets.append(Target(("rotor", "bearing_params"), (row, col)))
        else:
            targets.append(Target(("rotor", "bearing_mass"), (row, col - 8)))
    return ParameterPath(name, tuple(targets), True)


def _material_path(name, i, key, entry, spec, rotor):
    """A material constant: the entries of the shaft's elements made of it; `G` follows
    `E` and `nu` when the material leaves `G` out, `nu` follows `E` and `G` when it
    leaves `nu` out (as the loader and `FlexibleRotor` complete them)."""
    mat = spec["material"][i]["name"]
    used = tuple(j for j, s in enumerate(spec["shaft"]) if s["material"] == mat)
    if not used:
        return _refused(name, f"no [[shaft]] element is made of material {mat!r}")
    if np.ndim(rotor.E) == 0:
        if len(used) < len(spec["shaft"]):
            return _refused(name, f"material {mat!r} has the same constants as another material of the shaft, "
                                  f"and the rotor holds them once: give it different constants to fit it")
        index = None
    else:
        index = (used,)
    targets = [Target(("rotor", key), index)]
    if key in ("E", "nu") and "G" not in entry:
        targets.append(Target(("rotor", "G"), index, "shear_modulus"))
    if key in ("E", "G") and "nu" not in entry:
        targets.append(Target(("rotor", "nu"), index, "poisson"))
    return ParameterPath(name, tuple(targets))


# --- writing --------------------------------------------------------------------------
def _f(x) -> str:
    """A float, exactly (shortest repr: TOML reads back the same double)."""
    return repr(float(x))


def _s(text: str) -> str:
    """A TOML basic string."""
    out = []
    for ch in text:
        if ch in '"\\':
            out.append("\\" + ch)
        elif ord(ch) < 0x20 or ord(ch) == 0x7F:
            out.append({"\n": "\\n", "\t": "\\t", "\r": "\\r"}.get(ch, f"\\u{ord(ch):04x}"))
        else:
            out.append(ch)
    return '"' + "".join(out) + '"'


def _floats(a) -> str:
    return "[" + ", ".join(_f(x) for x in np.ravel(np.asarray(a))) + "]"


def _one_or_each(a) -> str:
    a = np.ravel(np.asarray(a))
    return _f(a[0]) if np.all(a == a[0]) else _floats(a)


def rotor_file_text(scene, name="rotor") -> str:
    """The TOML text of `scene` (what `save_rotor` writes)."""
    if not isinstance(scene, RotorScene):
        raise InputError(f"save_rotor: scene must be a RotorScene, got {type(scene).__name__}")
    if not isinstance(name, str):
        raise InputError(f"save_rotor: name must be a string, got {type(name).__name__}")
    if not is_concrete(scene):
        raise InputError("save_rotor: the scene holds traced values (inside jit/vmap); save a concrete scene")
    rotor, n_modes = scene.rotor, None
    if isinstance(rotor, ReducedRotor):
        rotor, n_modes = rotor.rotor, rotor.n_modes
    sp = scene.speed
    if not isinstance(sp, ConstantSpeed) or float(sp.theta0) != 0.0:
        raise InputError(f"save_rotor: a rotor file holds a constant speed ([rotor] speed) from angle 0; "
                         f"this scene's speed is {type(sp).__name__}"
                         + ("" if not isinstance(sp, ConstantSpeed) else f" with theta0 = {_f(sp.theta0)}"))
    lines = ["# A rotorjax rotor file (SI units), written by rotorjax.models.save_rotor.", "",
             "[rotor]", f"name = {_s(name)}", f"theory = {_s(rotor.theory)}", f"speed = {_f(sp.constant)}"]
    if n_modes is not None:
        lines.append(f"n_modes = {n_modes}")

    n_el = rotor.lengths.shape[0]
    cols = [np.broadcast_to(np.asarray(a, dtype=np.float64), (n_el,)) for a in (rotor.E, rotor.G, rotor.rho,
                                                                                 rotor.nu)]
    per_el = [tuple(float(c[i]) for c in cols) for i in range(n_el)]
    names = {}
    for m in per_el:
        if m not in names:
            names[m] = f"material{len(names)}"
            E, G, rho, nu = m
            lines += ["", "[[material]]", f"name = {_s(names[m])}", f"E = {_f(E)}", f"G = {_f(G)}",
                      f"rho = {_f(rho)}"]
            if nu != poisson_ratio(E, G):
                lines.append(f"nu = {_f(nu)}")
    lengths, d_out, d_in = (np.asarray(a) for a in (rotor.lengths, rotor.d_out, rotor.d_in))
    for i in range(n_el):
        lines += ["", "[[shaft]]", f"L = {_f(lengths[i])}", f"od = {_one_or_each(d_out[i])}",
                  f"id = {_one_or_each(d_in[i])}", f"material = {_s(names[per_el[i]])}"]
    for node, (m, it, ip) in zip(rotor.disk_nodes, np.asarray(rotor.disk_params)):
        lines += ["", "[[disk]]", f"node = {node}", f"m = {_f(m)}", f"Id = {_f(it)}", f"Ip = {_f(ip)}"]
    for i, node in enumerate(rotor.bearing_nodes):
        table = rotor.bearing_tables[i]
        lines += ["", "[[bearing]]", f"node = {node}"]
        if table is None:
            values = np.concatenate([np.asarray(rotor.bearing_params[i]), np.asarray(rotor.bearing_mass[i])])
        else:
            lines.append(f"speeds = {_floats(table[0])}")
            values = np.asarray(table[1])
        coef = dict(zip(BEARING_COEFFICIENTS, values))
        for k in BEARING_COEFFICIENTS:
            if k in ("kxx", "kyy", "cxx", "cyy") or np.any(np.asarray(coef[k]) != 0):
                lines.append(f"{k} = {_one_or_each(coef[k])}")
    for node, (mx, my) in zip(rotor.point_mass_nodes, np.asarray(rotor.point_mass_params)):
        lines += ["", "[[point_mass]]", f"node = {node}"]
        lines += [f"m = {_f(mx)}"] if mx == my else [f"mx = {_f(mx)}", f"my = {_f(my)}"]
    for b, (m, kxx, kyy, cxx, cyy) in zip(rotor.support_bearings, np.asarray(rotor.support_params)):
        lines += ["", "[[support]]", f"bearing = {b}", f"m = {_f(m)}", f"kxx = {_f(kxx)}", f"kyy = {_f(kyy)}",
                  f"cxx = {_f(cxx)}", f"cyy = {_f(cyy)}"]
    by_node = {}
    for d in rotor.fixed_dofs:
        by_node.setdefault(d // DOFS_PER_NODE, []).append(DOF_NAMES[d % DOFS_PER_NODE])
    for node, dofs in by_node.items():
        lines += ["", "[[fixed]]", f"node = {node}", "dofs = [" + ", ".join(_s(d) for d in dofs) + "]"]

    order = (Unbalance, InternalDamping, ExternalDamping, DiskDamping, Gravity, JournalBearing, SqueezeFilmDamper,
             CubicBearing, ClearanceBearing, LimitersAt, BalancerAt, NodeProbe)
    groups = {cls: [] for cls in order}
    for i, c in enumerate(scene.components):
        cls = next((k for k in order if type(c) is k), None)
        if cls is None:
            raise InputError(f"save_rotor: components[{i}] ({type(c).__name__}) has no rotor-file table; "
                             f"rotor files hold {', '.join(k.__name__ for k in order)}")
        groups[cls].append(c)
    for cls, table in ((InternalDamping, "internal_damping"), (ExternalDamping, "external_damping"),
                       (Gravity, "gravity")):
        if len(groups[cls]) > 1:
            raise InputError(f"save_rotor: a rotor file holds one [{table}]; the scene has {len(groups[cls])} "
                             f"{cls.__name__} components")
    for u in groups[Unbalance]:
        lines += ["", "[[unbalance]]", f"node = {u.node}", f"magnitude = {_f(u.magnitude)}",
                  f"phase = {_f(u.phase)}"]
    for d in groups[InternalDamping]:
        lines += ["", "[internal_damping]", f"relaxation_time = {_f(d.relaxation_time)}"]
    for d in groups[ExternalDamping]:
        lines += ["", "[external_damping]", f"coefficient = {_f(d.coefficient)}"]
    for d in groups[DiskDamping]:
        lines += ["", "[[disk_damping]]", f"node = {d.node}", f"translational = {_f(d.translational)}",
                  f"angular = {_f(d.angular)}"]
    for g in groups[Gravity]:
        lines += ["", "[gravity]", f"g = {_f(g.g)}", f"angle = {_f(g.angle)}"]
    for c in [c for c in scene.components if type(c) in (JournalBearing, SqueezeFilmDamper)]:  # the scene's order
        lines += ["", "[[bearing]]", f"node = {c.node}"]
        if isinstance(c, JournalBearing):
            lines += ['type = "journal"', f"model = {_s(c.model)}"]
        else:
            lines += ['type = "sfd"', f"film = {_s(c.film)}", f"kxx = {_f(c.kxx)}", f"kyy = {_f(c.kyy)}"]
        lines += [f"viscosity = {_f(c.viscosity)}", f"length = {_f(c.length)}", f"diameter = {_f(c.diameter)}",
                  f"clearance = {_f(c.clearance)}"]
    for c in groups[CubicBearing]:
        lines += ["", "[[cubic_bearing]]", f"node = {c.node}", f"k3 = {_f(c.k3)}", f"k = {_f(c.k)}",
                  f"c = {_f(c.c)}"]
    for c in groups[ClearanceBearing]:
        lines += ["", "[[clearance_bearing]]", f"node = {c.node}", f"clearance = {_f(c.clearance)}",
                  f"k = {_f(c.k)}", f"c = {_f(c.c)}", f"smoothing = {_f(c.smoothing)}"]
    for c in groups[LimitersAt]:
        lim = c.limiters
        if lim.slip_regularisation != 1e-6:
            raise InputError(f"save_rotor: {c.describe()} has slip_regularisation = {lim.slip_regularisation!r}; "
                             f"rotor files hold the default 1e-6")
        lines += ["", "[[limiters]]", f"node = {c.node}", f"angles = {_floats(lim.angles)}",
                  f"clearance = {_one_or_each(lim.clearance)}", f"stiffness = {_one_or_each(lim.stiffness)}",
                  f"damping = {_one_or_each(lim.damping)}", f"friction = {_one_or_each(lim.friction)}",
                  f"radius = {_f(c.radius)}", f"smoothing = {_f(lim.smoothing)}"]
    for c in groups[BalancerAt]:
        b = c.balancer
        masses = np.asarray(b.mass)
        lines += ["", "[[auto_balancer]]", f"node = {c.node}"]
        if np.all(masses == masses[0]):
            lines += [f"n_weights = {masses.shape[0]}", f"mass = {_f(masses[0])}"]
        else:
            lines.append(f"masses = {_floats(masses)}")
        r1, r2 = float(b.race.r1), float(b.race.r2)
        lines += [f"radius = {_f(r1)}"] if r1 == r2 else [f"r1 = {_f(r1)}", f"r2 = {_f(r2)}"]
        if np.any(np.asarray(b.race.center) != 0):
            lines.append(f"center = {_floats(b.race.center)}")
        lines.append(f"drag = {_f(b.drag)}")
        factor = float(b.inertia_factor)
        kind = next((k for k in KINDS if INERTIA_FACTORS[k] == factor), None)
        lines.append(f"kind = {_s(kind)}" if kind else f"inertia_factor = {_f(factor)}")
    probe_names = [p.name for p in groups[NodeProbe]]
    for p in groups[NodeProbe]:
        if probe_names.count(p.name) > 1:
            raise InputError(f"save_rotor: {probe_names.count(p.name)} probes are named {p.name!r}; a rotor file "
                             f"names each probe once")
        if not PROBE_NAME.fullmatch(p.name) or p.name in RESERVED_PROBE_NAMES:
            raise InputError(f"save_rotor: {p.describe()}: a rotor file names a probe by a word (letters, digits "
                             f"and _), not {', '.join(RESERVED_PROBE_NAMES)}")
        lines += ["", "[[probe]]", f"node = {p.node}", f"name = {_s(p.name)}"]
    return "\n".join(lines) + "\n"


def save_rotor(scene, path, name=None):
    """Write `scene` (a `RotorScene` of the parts a rotor file holds, at a constant
    speed) to `path` as a rotor file. Floats are written exactly, so
    `load_rotor(path)` rebuilds the same arrays (components in the file's order;
    materials named `material0`, ... per distinct set of constants; `track_work`
    is a run option, not part of the file). `name`: the `[rotor] name` (default:
    the file's stem). Returns `path`."""
    label = os.fspath(path) if isinstance(path, (str, os.PathLike)) else None
    if label is None:
        raise InputError(f"save_rotor: expected a path, got {type(path).__name__}")
    text = rotor_file_text(scene, pathlib.Path(label).stem if name is None else name)
    try:
        pathlib.Path(label).write_text(text, encoding="utf-8")
    except OSError as e:
        raise InputError(f"{label}: cannot be written ({e.strerror})") from None
    return path


def shipped_rotor(name: str) -> pathlib.Path:
    """The path of a rotor file shipped with rotorjax (`"ross_compare"`, ...; the
    `.toml` suffix is optional)."""
    files = importlib.resources.files("rotorjax.rotors")
    known = sorted(p.name[:-5] for p in files.iterdir() if p.name.endswith(".toml"))
    stem = name[:-5] if isinstance(name, str) and name.endswith(".toml") else name
    if stem not in known:
        raise InputError(f"unknown shipped rotor {name!r}; known: {', '.join(known)}")
    return pathlib.Path(str(files / f"{stem}.toml"))
