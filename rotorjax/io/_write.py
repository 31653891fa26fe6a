"""Writing a scene as a rotor file (`save_rotor`): floats exactly, every registered
part through its table's `to_table`, checked as the reader checks a file."""

import os
import pathlib

import numpy as np

from .._errors import InputError
from ..models._fe_reduction import ReducedRotor
from ..models._fe_rotor import BEARING_COEFFICIENTS, DOFS_PER_NODE
from ..models._materials import poisson_ratio
from ..models._registry import TABLES
from ..models._table import floats, one_or_each
from ..models._rotor_scene import RotorScene
from ..models._speed import ConstantSpeed
from ..models._validate import is_concrete
from ._check import complete_table
from ._read import Ctx
from ._schema import DOF_NAMES


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
    for i, c in enumerate(scene.components):
        if not any(isinstance(c, table.builds) for table in TABLES if table.part != "bearing"):
            raise InputError(f"save_rotor: components[{i}] ({type(c).__name__}) has no rotor-file table; rotor files "
                             f"hold {', '.join(_class_names())}")
    lines = ["# A rotorjax rotor file (SI units), written by rotorjax.io.save_rotor.", "",
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
        lines += ["", "[[shaft]]", f"L = {_f(lengths[i])}", f"od = {_toml_value(one_or_each(d_out[i]))}",
                  f"id = {_toml_value(one_or_each(d_in[i]))}", f"material = {_s(names[per_el[i]])}"]
    for node, (m, it, ip) in zip(rotor.disk_nodes, np.asarray(rotor.disk_params)):
        lines += ["", "[[disk]]", f"node = {node}", f"m = {_f(m)}", f"Id = {_f(it)}", f"Ip = {_f(ip)}"]
    kinds = rotor.bearing_kinds
    known = ["bearing"] + [table.builds.kind for table in TABLES if table.part == "bearing"]
    if any(k not in known for k in kinds):
        raise InputError(f"save_rotor: bearings[{next(i for i, k in enumerate(kinds) if k not in known)}] is of kind "
                         f"{next(k for k in kinds if k not in known)!r}, which has no rotor-file table; rotor files "
                         f"hold {', '.join(known)}")
    first = next((i for i, k in enumerate(kinds) if k != "bearing"), len(kinds))
    if "bearing" in kinds[first:]:
        raise InputError(f"save_rotor: bearings[{kinds.index('bearing', first)}] (a Bearing) follows bearings[{first}] "
                         f"(a {kinds[first]}); a rotor file lists its [[bearing]] entries first: build the rotor "
                         f"with the Bearings first")
    if any(kinds[b] != "bearing" for b in rotor.support_bearings):
        raise InputError("save_rotor: a support carries a " + next(kinds[b] for b in rotor.support_bearings
                                                                  if kinds[b] != "bearing")
                         + "; a rotor file's [[support]] carries a [[bearing]]")
    for i, node in enumerate(rotor.bearing_nodes):
        table = rotor.bearing_tables[i]
        if kinds[i] != "bearing":
            continue
        lines += ["", "[[bearing]]", f"node = {node}"]
        if table is None:
            values = np.concatenate([np.asarray(rotor.bearing_params[i]), np.asarray(rotor.bearing_mass[i])])
        else:
            lines.append(f"speeds = {_toml_value(floats(table[0]))}")
            values = np.asarray(table[1])
        coef = dict(zip(BEARING_COEFFICIENTS, values))
        for k in BEARING_COEFFICIENTS:
            if k in ("kxx", "kyy", "cxx", "cyy") or np.any(np.asarray(coef[k]) != 0):
                lines.append(f"{k} = {_toml_value(one_or_each(coef[k]))}")
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

    for table in TABLES:
        if table.part == "bearing":
            found = [rotor.bearing(i, table.builds) for i, k in enumerate(rotor.bearing_kinds)
                     if k == table.builds.kind]
        else:
            found = [c for c in scene.components if isinstance(c, table.builds)]
        if not table.array and len(found) > 1:
            raise InputError(f"save_rotor: a rotor file holds one {table.head}; the scene has {len(found)} "
                             f"{type(found[0]).__name__} components")
        lines += _written(table, found)
    return "\n".join(lines) + "\n"


def _written(table, parts):
    """The lines of a registered table's entries for `parts`, checked as the reader
    checks them (the table's `complete` on what is written)."""
    entries = []
    for c in parts:
        try:
            entries.append(table.to_table(c))
        except InputError as e:
            raise InputError(f"save_rotor: {e}") from None
    where = Ctx("save_rotor")
    complete_table(where, table, [dict(e) for e in entries])
    lines = []
    for e in entries:
        lines += ["", table.head] + [f"{k} = {_toml_value(v)}" for k, v in e.items()]
    return lines


def _class_names():
    return [k.__name__ for table in TABLES if table.part != "bearing"
            for k in (table.builds if isinstance(table.builds, tuple) else (table.builds,))]


def _toml_value(v) -> str:
    """A value of a table entry as TOML (floats exactly)."""
    if isinstance(v, str):
        return _s(v)
    if isinstance(v, (bool, np.bool_)):
        raise AssertionError(v)
    if isinstance(v, (int, np.integer)):
        return str(int(v))
    if isinstance(v, list):
        return "[" + ", ".join(_s(x) if isinstance(x, str) else _f(x) for x in v) + "]"
    return _f(v)


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
