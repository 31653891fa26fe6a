"""The parameters of a rotor file that identification can fit, by their rotor-file
names, and the map from a parameter vector to the rotor they make.

Names (the `--set` keys of the file): `bearingI.COEF` (the I-th `[[bearing]]`, COEF
in kxx, kyy, kxy, kyx, cxx, cyy, cxy, cyx, mxx, myy, mxy, myx), `supportI.KEY`
(m, kxx, kyy, cxx, cyy), `diskI.KEY` (m, Id, Ip), `point_massI.KEY` (m, mx, my),
`unbalanceJ.magnitude` / `unbalanceJ.phase`.

A coefficient the file leaves at its default follows the one it defaults to
(`kyy` follows `kxx`, `cyy` follows `cxx`, `myy` follows `mxx`; a point mass's `m`
is both `mx` and `my`), as `--set` treats it. Positive quantities are fitted as
logarithms (positivity by reparametrisation, and a factor error is one step);
signed ones (cross-coupled coefficients, phases) linearly, scaled by their start
(or 1 when it is 0). Bearings tabulated against speed and plain journals compute
their coefficients and cannot be fitted coefficient by coefficient.
"""

import dataclasses
import os

import equinox as eqx
import jax.numpy as jnp
import numpy as np

from .._errors import InputError
from ..models._fe_rotor import BEARING_COEFFICIENTS
from ..models._rotor_file import file_parameters, load_rotor
from ..models._unbalance import Unbalance

_BEARING_FOLLOW = {"kxx": "kyy", "cxx": "cyy", "mxx": "myy"}
_SUPPORT_KEYS = ("m", "kxx", "kyy", "cxx", "cyy")
_SUPPORT_FOLLOW = {"kxx": "kyy", "cxx": "cyy"}
_DISK_KEYS = ("m", "Id", "Ip")
_POINT_MASS = {"m": (0, 1), "mx": (0,), "my": (1,)}
_SIGNED = ("kxy", "kyx", "cxy", "cyx", "mxy", "myx", "phase")


@dataclasses.dataclass(frozen=True)
class Parameter:
    """One fitted parameter: where it lives (`leaf` of the `FlexibleRotor`, or
    `"unbalance"`), the entries it sets, how it is fitted (`log` or `linear` with
    `scale`) and its start."""

    name: str
    leaf: str
    entries: tuple      # ((row, column), ...) in `leaf`; for "unbalance": ((index, 0|1),) magnitude|phase
    log: bool
    # values, not structure: a compiled fit serves every start (`apply` takes the scales as an array)
    scale: float = dataclasses.field(compare=False)
    start: float = dataclasses.field(compare=False)

    def to_theta(self, value):
        return np.log(value) if self.log else value / self.scale

    def from_theta(self, theta, scale=None):
        return jnp.exp(theta) if self.log else theta * (self.scale if scale is None else scale)


def _fittable(rotor, entries, n_unbalances):
    names = [f"bearing{i}.{k}" for i in range(len(rotor.bearing_nodes)) for k in BEARING_COEFFICIENTS]
    names += [f"support{i}.{k}" for i in range(rotor.n_supports) for k in _SUPPORT_KEYS]
    names += [f"disk{i}.{k}" for i in range(len(rotor.disk_nodes)) for k in _DISK_KEYS]
    names += [f"point_mass{i}.{k}" for i in range(len(rotor.point_mass_nodes)) for k in _POINT_MASS]
    names += [f"unbalance{j}.{k}" for j in range(n_unbalances) for k in ("magnitude", "phase")]
    return names


def _split(name):
    table, _, key = name.partition(".")
    digits = len(table) - len(table.rstrip("0123456789"))
    if not key or not digits:
        return None, None, None
    return table[:-digits], int(table[-digits:]), key


def parameter(name, rotor, entries, unbalances, option="--fit"):
    """The `Parameter` called `name` on `rotor` (the file's `entries`, from
    `file_parameters`, tell which values the file gives); `unbalances` are the
    file's `Unbalance` components."""
    table, i, key = _split(name)
    known = _fittable(rotor, entries, len(unbalances))
    if name not in known:
        hint = f"; fittable here: {', '.join(known[:12])}{', ...' if len(known) > 12 else ''}" if known else ""
        if table == "bearing" and i is not None and i < len(rotor.bearing_nodes):
            hint = f"; a bearing's coefficients are {', '.join(BEARING_COEFFICIENTS)}"
        raise InputError(f"{option} {name}: not a parameter of this rotor file{hint}")
    start = None
    if table == "bearing":
        if rotor.bearing_tables[i] is not None:
            raise InputError(f"{option} {name}: bearing{i} is tabulated against speed (or a plain journal, which "
                             "computes its coefficients); only constant bearings' coefficients can be fitted")
        col = BEARING_COEFFICIENTS.index(key)
        leaf, c = ("bearing_params", col) if col < 8 else ("bearing_mass", col - 8)
        cells = [(i, c)]
        follower = _BEARING_FOLLOW.get(key)
        if follower and f"bearing{i}.{follower}" not in entries:
            j = BEARING_COEFFICIENTS.index(follower)
            cells.append((i, j if j < 8 else j - 8))
        start = float(getattr(rotor, leaf)[i, c])
    elif table == "support":
        col = _SUPPORT_KEYS.index(key)
        cells = [(i, col)]
        follower = _SUPPORT_FOLLOW.get(key)
        if follower and f"support{i}.{follower}" not in entries:
            cells.append((i, _SUPPORT_KEYS.index(follower)))
        leaf, start = "support_params", float(rotor.support_params[i, col])
    elif table == "disk":
        leaf, cells = "disk_params", [(i, _DISK_KEYS.index(key))]
        start = float(rotor.disk_params[i, _DISK_KEYS.index(key)])
    elif table == "point_mass":
        leaf, cells = "point_mass_params", [(i, c) for c in _POINT_MASS[key]]
        start = float(rotor.point_mass_params[i, _POINT_MASS[key][0]])
    else:   # unbalance
        leaf, cells = "unbalance", [(i, 0 if key == "magnitude" else 1)]
        u = unbalances[i]
        start = float(u.magnitude if key == "magnitude" else u.phase)
    signed = key in _SIGNED
    if not signed and not start > 0:
        raise InputError(f"{option} {name}: its start value is {start:g}; a positive quantity is fitted as a "
                         f"logarithm and needs a start > 0 (give one with --set {name}=VALUE)")
    return Parameter(name, leaf, tuple(cells), not signed, abs(start) if signed and start != 0 else 1.0, start)


@dataclasses.dataclass(frozen=True, eq=False)
class RotorModel:
    """A rotor file's linear rotor (`FlexibleRotor`, the full one when the file
    reduces it) and its unbalances `(node, magnitude, phase)`, at the file's values
    (with `overrides`), and the fittable parameters' names."""

    label: str
    rotor: eqx.Module
    unbalances: tuple          # Unbalance components of the file
    entries: dict              # name -> FileParameter (what the file gives)
    nonlinear: tuple           # names of the file's other components (not modelled by the 1x fit)

    def parameters(self, names, option="--fit"):
        out = []
        for n in names:
            if n in [p.name for p in out]:
                raise InputError(f"{option}: {n} is named twice")
            out.append(parameter(n, self.rotor, self.entries, self.unbalances, option))
        return tuple(out)

    @property
    def fittable(self):
        return _fittable(self.rotor, self.entries, len(self.unbalances))


def rotor_model(path, overrides=None, *, scene=None, entries=None) -> RotorModel:
    """The `RotorModel` of the rotor file at `path` with `--set` `overrides`; a
    caller that has built the file's `scene` and read its `entries` (the `--set`
    keys, e.g. a preset's `defaults`) passes them, and the file is not read again."""
    if entries is None:
        label, _, entries = file_parameters(path)
    else:
        label = os.fspath(path)
    if scene is None:
        scene = load_rotor(path, overrides)
    rotor = scene.full_rotor   # a reduced rotor: its full one
    unb = tuple(c for c in scene.components if isinstance(c, Unbalance))
    other = tuple(type(c).__name__ for c in scene.components if not isinstance(c, Unbalance))
    return RotorModel(label, rotor, unb, entries, other)


def apply(params, rotor, unbalances, theta, scales):
    """`(rotor, unbalances)` with the parameters set from `theta` (pure JAX:
    differentiable and vmappable); `unbalances` as `(nodes, magnitudes, phases)`,
    `scales` the signed parameters' scales (an array: values, not structure);
    `rotor` None: the unbalances only."""
    nodes, mags, phases = unbalances
    for k, p in enumerate(params):
        v = p.from_theta(theta[k], scales[k])
        if p.leaf == "unbalance":
            (j, which), = p.entries
            if which == 0:
                mags = mags.at[j].set(v)
            else:
                phases = phases.at[j].set(v)
            continue
        if rotor is None:
            continue
        a = getattr(rotor, p.leaf)
        for (r, c) in p.entries:
            a = a.at[r, c].set(v)
        rotor = eqx.tree_at(lambda m, leaf=p.leaf: getattr(m, leaf), rotor, a)
    return rotor, (nodes, mags, phases)
