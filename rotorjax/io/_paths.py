"""A rotor file's entries as parameters: each numeric key resolved, where the file's
meaning is known, to the leaves of the scene it sets (`rotorjax.models._parameters`)."""

import dataclasses

import numpy as np

from .._errors import InputError
from .._units import to_si
from ..models._fe_rotor import BEARING_COEFFICIENTS, BEARING_FOLLOWS, SUPPORT_FOLLOWS, SUPPORT_KEYS
from ..models._parameters import ParameterPath, Target
from ..models._registry import TABLES
from ..models._rotor_scene import RotorScene
from ._build import build_scene
from ._check import entries_of, validate
from ._read import Ctx, OVERRIDE_KEY, apply_overrides, location, read_toml
from ._schema import FILM_KEYS, FILM_TYPES, SCHEMA, SINGLE_KEY_ALIASES

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
    placed: dict = dataclasses.field(repr=False)   # (table, index) -> ("components", j) or ("bearing", row)

    def path(self, name):
        """The `ParameterPath` called `name` (`bearing0.kxy`, `material0.E`, `speed`),
        or None when the file has no such entry or key."""
        if name in self.entries:
            return self.entries[name].path
        if not isinstance(name, str):
            return None
        m = OVERRIDE_KEY.match(name)
        if not m or m.group(1) not in SCHEMA or name in SINGLE_KEY_ALIASES:
            return None
        table, index, key = m.group(1), m.group(2), m.group(3)
        spec = SCHEMA[table]
        i = None if index is None else int(index)
        if key == "position":
            node = self.node_of(name)
            return None if node is None else _position_path(name, table, i, node, self.spec["shaft"])
        if key not in spec.keys or spec.array != (i is not None) or spec.keys[key].kind not in (
                "number", "number_or_numbers"):
            return None
        entries = dict(self.raw.get(table, []))
        if i not in entries:
            return None
        return _parameter_path(name, table, i, key, entries[i], self.spec, self.placed, self.scene.full_rotor)

    def node_of(self, name):
        """The node that the entry `name` (`table<i>.key`) sits at, or None (no such entry,
        or one not at a node)."""
        m = OVERRIDE_KEY.match(name) if isinstance(name, str) else None
        if not m or m.group(1) not in SCHEMA or m.group(2) is None or "node" not in SCHEMA[m.group(1)].keys:
            return None
        entry = dict(self.raw.get(m.group(1), [])).get(int(m.group(2)))
        return None if entry is None or "node" not in entry else int(entry["node"])

    def interval(self, name):
        """The open interval `(lo, hi)` a position parameter (`bearing1.position`) may
        take, in m: between the nodes either side of its own, where they stand in the
        file; None for any other parameter."""
        path = self.path(name)
        if path is None or path.refusal or path.targets[0].rule != "node_position":
            return None
        z = np.concatenate([[0.0], np.cumsum([e["L"] for e in self.spec["shaft"]])])
        a, b = path.targets[0].index[0]
        return float(z[a]), float(z[b + 1])

    def check_together(self, names, option):
        """`InputError` naming `option` and two of `names` that set the same element
        length (a position and its node's element's `L`, or two positions at one node or
        at neighbouring nodes): applied one after the other, the second would move what
        the first placed."""
        seen = {}
        for name in names:
            path = self.path(name)
            for t in () if path is None else path.targets:
                if t.leaf != ("rotor", "lengths"):
                    continue
                for j in np.ravel(t.index[0]).tolist():
                    if j in seen and seen[j] != name:
                        raise InputError(f"{option} {seen[j]} and {name}: both set the length of shaft{j} (a "
                                         "position moves its node, and so the lengths of the elements either side); "
                                         "give one of them")
                    seen[j] = name

    def parameter_path(self, name, option):
        """`path(name)`, or `InputError` naming `option` and `name` where the file has no
        such parameter or refuses it (a parameter that cannot be moved smoothly)."""
        path = self.path(name)
        if path is None:
            raise InputError(f"{option} {name}: not a parameter of {self.label}; `rotorjax presets {self.label}` "
                             "lists its keys")
        if path.refusal:
            raise InputError(f"{option} {name}: {path.refusal}")
        return path

    def signed(self, name) -> bool:
        """Whether the key `name` may be negative (a cross-coupled coefficient, a phase)."""
        if name == "speed":
            return True
        table, key = OVERRIDE_KEY.match(name).group(1), name.rpartition(".")[2]
        if key == "position":
            return False
        return SCHEMA[table].keys[key].sign == "any"


def read_rotor_file(path, overrides=None) -> RotorFile:
    """The `RotorFile` of `path` with `overrides` (as `load_rotor`'s) applied."""
    label, doc = read_toml(path)
    ctx = Ctx(label)
    doc = apply_overrides(ctx, doc, overrides)
    spec = validate(ctx, doc)
    placed = {}
    scene = build_scene(ctx, spec, False, placed)
    n_el = len(spec["shaft"])
    n_free = len(scene.rotor.free_dofs)
    r = spec["rotor"][0]
    out = {"speed": FileParameter(float(r["speed"]), "rad/s", "operating speed ([rotor] speed)", "any", False,
                                  _speed_path("speed"))}
    for table, t in SCHEMA.items():
        for index, entry in _entries_in_si(ctx, doc, table):
            for key, value in entry.items():
                k = t.keys[key]
                scalar = k.kind in ("number", "count", "node", "index") or (k.kind == "number_or_numbers"
                                                                   and not isinstance(value, list))
                if not scalar or (table, key) == ("rotor", "speed"):
                    continue
                name = f"{table}{index}.{key}" if t.array else f"{table}.{key}"
                at = f" at node {entry['node']}" if "node" in entry and key != "node" else ""
                meaning = f"{location(table, index)}{at}: {k.meaning}"
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
    raw = {table: _entries_in_si(ctx, doc, table) for table in SCHEMA}
    return RotorFile(label, r["name"], out, scene, spec, raw, placed)


def _entries_in_si(ctx, doc, table):
    """`entries_of` with every value given with a unit (`"1.5e7 N/m"`) in SI (the file
    is valid: `validate` has converted each the same way)."""
    keys = SCHEMA[table].keys

    def si(index, key, v):
        k = keys.get(key)
        if k is None or k.kind not in ("number", "numbers", "number_or_numbers"):
            return v
        where = location(table, index, key)
        return [to_si(x, k.unit, where) for x in v] if isinstance(v, list) else to_si(v, k.unit, where)

    return [(i, {key: si(i, key, v) for key, v in e.items()}) for i, e in entries_of(ctx, doc, table)]


def _position_path(name, table, i, node, shaft):
    """`table<i>.position`: the axial position (m from node 0) of the node the entry
    sits at, moved between its neighbours (`Target` rule `node_position`: the lengths of
    the elements either side); refused at the shaft's ends (it would change the shaft's
    length) and where the shaft is not uniform across the node (it would move a step in
    diameter, a taper's end or a change of material with it)."""
    n_el = len(shaft)
    if node in (0, n_el):
        return _refused(name, f"{table}{i} sits at node {node}, the shaft's end: moving it would change the shaft's "
                              f"length (vary shaft{0 if node == 0 else n_el - 1}.L for that)")
    left, right = shaft[node - 1], shaft[node]
    uniform = all(np.ndim(e[k]) == 0 or e[k][0] == e[k][-1] for e in (left, right) for k in ("od", "id"))
    if not (uniform and np.all(np.ravel(left["od"])[-1] == np.ravel(right["od"])[0])
            and np.all(np.ravel(left["id"])[-1] == np.ravel(right["id"])[0]) and left["material"] == right["material"]):
        return _refused(name, f"{table}{i} sits at node {node}, where shaft{node - 1} and shaft{node} differ (a step, "
                              "a taper or another material): moving the node would move that too; split the shaft "
                              "so that the node lies inside a uniform section")
    return ParameterPath(name, (Target(("rotor", "lengths"), ((node - 1, node),), "node_position"),))


def _speed_path(name):
    """`[rotor] speed`: the constant speed of the scene's speed profile."""
    return ParameterPath(name, (Target(("speed", "constant")),))


def _refused(name, why):
    return ParameterPath(name, refusal=why)


#: the registered tables by name
_REGISTERED = {table.name: table for table in TABLES if table.part != "film"}
_FILMS = next(table for table in TABLES if table.part == "film")


def _parameter_path(name, table, i, key, entry, spec, placed, rotor):
    """The `ParameterPath` of the scalar file entry `name` (`table[i].key`; `entry`
    the keys the file gives): the leaves of the scene it sets, with the values that
    follow it where the file leaves them out, or why it is not a leaf; None for a key
    of another type of the entry's table (a film's key on a linear bearing)."""
    kind = SCHEMA[table].keys[key].kind
    if isinstance(entry.get(key), list):
        if table == "bearing" or SCHEMA[table].keys.get("speeds"):
            return _refused(name, f"{table}{i} is tabulated against speed (one value per speed); only its "
                                  f"single-valued coefficients are parameters")
        return _refused(name, f"{location(table, i, key)} is a list, not one value")
    if kind in ("count", "node", "index"):
        return _refused(name, "an integer that shapes the scene (a --set rebuilds it); it is not a value "
                              "that can be fitted")
    if table == "rotor":   # `[rotor] speed`, also called `speed`
        return _speed_path(name)
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
        b = spec["bearing"][i]
        if b["type"] == "plain-journal":
            return _refused(name, f"bearing{i} is a plain journal, which computes its coefficients (tabulated "
                                  f"against speed) when the rotor is built: they are not leaves of the scene")
        if key not in BEARING_COEFFICIENTS:
            return None   # a key of another bearing type
        row = [k for k, e in enumerate(spec["bearing"]) if e["type"] not in FILM_TYPES].index(i)
        return _coefficient_path(name, row, key, entry, rotor)
    reg = _FILMS if table == "bearing" else _REGISTERED[table]
    if table == "bearing" and key not in FILM_KEYS + (("kxx", "kyy") if spec["bearing"][i]["type"] == "sfd" else ()):
        return None   # a key of another bearing type
    if key in reg.refused:
        return _refused(name, reg.refused[key])
    i = 0 if i is None else i   # a single table: its one entry
    where, at = placed[(table, i)]
    if where == "bearing":
        return _coefficient_path(name, at, key, entry, rotor)
    targets = [Target(("components", at) + reg.leaves.get(k, (k,))) for k in reg.spread.get(key, (key,))]
    targets += [Target(("components", at) + reg.leaves.get(f, (f,)), None, rule)
                for f, rule in reg.followers.get(key, ()) if f not in entry]
    return ParameterPath(name, tuple(targets))


def _coefficient_path(name, row, key, entry, rotor):
    """A coefficient of the rotor's bearing `row` (a linear bearing's, a seal's): its
    entry of the rotor's constant coefficients, or every speed of its table; its
    followers with it (`BEARING_FOLLOWS`)."""
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
