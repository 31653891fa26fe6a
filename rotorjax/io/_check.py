"""Checking a rotor file, before anything is built: every key against its table's
declaration, the checks across keys and entries, and plausibility warnings."""

import json
import math
import pathlib

from .._errors import InputError
from .._units import to_si
from ..models._fe_rotor import (BEARING_COEFFICIENTS, DOFS_PER_NODE, SUPPORT_FOLLOWS, check_speed_table,
                                complete_coefficients, follow)
from ..models._fluid_film import SFD_FOLLOWS
from ..models._materials import MATERIALS, shear_modulus
from ..models._plausibility import IP_TOLERANCE, RANGES, gyration, judge, number
from ..models._registry import TABLES
from ..models._table import NO_DEFAULT
from ._read import describe_value, location, suggest, toml_repr
from ._schema import DOF_NAMES, FILM_KEYS, FILM_TYPES, JOURNAL_KEYS, SCHEMA


#: the domains a key may state beyond its sign: the test, and the words of the message
_DOMAINS = {"(-1,0.5]": (lambda v: -1 < v <= 0.5, "in (-1, 0.5]"), ">=1": (lambda v: v >= 1, ">= 1")}
_SIGN_TEST = {"positive": (lambda v: v > 0, "> 0"), "nonnegative": (lambda v: v >= 0, ">= 0")}


def _number(ctx, where, value, sign="any", loc=None, unit=None):
    """A number (or, with `unit`, a string with a unit, converted to `unit`: `"1.5e7
    N/m"`), finite and of the sign asked."""
    loc = where if loc is None else loc
    if isinstance(value, str) and unit is not None:
        try:
            value = to_si(value, unit, where)
        except InputError as e:
            ctx.fail(str(e), loc)
    if isinstance(value, bool) or not isinstance(value, (int, float)):
        ctx.fail(f"{where} must be a number, got {describe_value(value)}", loc)
    try:
        v = float(value)
    except OverflowError:
        ctx.fail(f"{where} must be finite, got {value}", loc)
    if not math.isfinite(v):
        ctx.fail(f"{where} must be finite, got {toml_repr(v)}", loc)
    if sign in _SIGN_TEST and not _SIGN_TEST[sign][0](v):
        ctx.fail(f"{where} must be {_SIGN_TEST[sign][1]} (got {toml_repr(value)})", loc)
    return v


def _value(ctx, table, index, key, spec, value, n_nodes):
    """One key's value checked against its spec (node ranges included)."""
    where = location(table, index, key)
    kind = spec.kind
    if kind == "number":
        v = _number(ctx, where, value, spec.sign, unit=spec.unit)
        if spec.domain in _DOMAINS and not _DOMAINS[spec.domain][0](v):
            ctx.fail(f"{where} must be {_DOMAINS[spec.domain][1]} (got {toml_repr(value)})", where)
        return v
    if kind in ("count", "node", "index"):
        if isinstance(value, bool) or not isinstance(value, int):
            ctx.fail(f"{where} must be an integer, got {describe_value(value)}", where)
        if kind == "index" and value < 0:
            ctx.fail(f"{where} must be >= 0 (an index from 0; got {value})", where)
        if kind == "node" and not 0 <= value < n_nodes:
            ctx.fail(f"{where} = {value}: the shaft has nodes 0..{n_nodes - 1}", where)
        if kind == "count" and value < 1:
            ctx.fail(f"{where} must be >= 1 (got {value})", where)
        return value
    if kind == "string":
        if not isinstance(value, str):
            ctx.fail(f"{where} must be a string, got {describe_value(value)}", where)
        if spec.choices and value not in spec.choices:
            ctx.fail(f"{where} must be one of {', '.join(json.dumps(c) for c in spec.choices)} "
                     f"(got {toml_repr(value)})", where)
        return value
    if kind in ("numbers", "number_or_numbers"):
        if kind == "number_or_numbers" and not isinstance(value, list):
            return _number(ctx, where, value, spec.sign, unit=spec.unit)
        if not isinstance(value, list):
            ctx.fail(f"{where} must be a list of numbers, got {describe_value(value)}", where)
        if not value:
            ctx.fail(f"{where} must be a non-empty list of numbers, got []", where)
        return [_number(ctx, f"{where}[{j}]", v, spec.sign, loc=where, unit=spec.unit) for j, v in enumerate(value)]
    if kind == "strings":
        if not isinstance(value, list) or not value:
            ctx.fail(f"{where} must be a non-empty list of strings, got {describe_value(value)}", where)
        for j, v in enumerate(value):
            if not isinstance(v, str) or v not in spec.choices:
                ctx.fail(f"{where}[{j}] must be one of {', '.join(json.dumps(c) for c in spec.choices)} "
                         f"(got {toml_repr(v)})", where)
        if len(set(value)) != len(value):
            ctx.fail(f"{where} names a dof twice (got {toml_repr(value)})", where)
        return list(value)
    raise AssertionError(kind)


def entries_of(ctx, doc, table):
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
            ctx.fail(f"{table} must be an array of tables ([[{table}]]), got {describe_value(raw)}", table)
        return list(enumerate(raw))
    if isinstance(raw, list):
        ctx.fail(f"{table} must be a single table: write [{table}], not [[{table}]]", table)
    if not isinstance(raw, dict):
        ctx.fail(f"{table} must be a table ([{table}]), got {describe_value(raw)}", table)
    return [(None, raw)]


def _check_keys(ctx, table, index, entry, n_nodes):
    """Known keys present, required ones there; values checked. Returns a dict."""
    spec = SCHEMA[table]
    head = f"[[{table}]]" if spec.array else f"[{table}]"
    for key in entry:
        if key not in spec.keys:
            ctx.fail(f"{location(table, index, key)}: unknown key{suggest(key, list(spec.keys))}; "
                     f"the keys of {head} are {', '.join(spec.keys)}", location(table, index, key))
    for key, k in spec.keys.items():
        if k.required and key not in entry:
            what = ", ".join(s for s in (k.meaning, k.unit) if s and s not in ("node", "count"))
            ctx.fail(f"{location(table, index, key)} is missing (required: {what or key})")
    return {key: _value(ctx, table, index, key, spec.keys[key], v, n_nodes) for key, v in entry.items()}


def _bearing(ctx, i, b):
    """A [[bearing]] entry checked and completed: a linear bearing (constant or with a
    `speeds` table) or a plain journal (its own keys only)."""
    kind = b.setdefault("type", "linear")
    given = [k for k in BEARING_COEFFICIENTS if k in b]
    if kind in FILM_TYPES:
        return _film_bearing(ctx, i, b, given)
    if kind == "plain-journal":
        if given:
            ctx.fail(f"{location('bearing', i, given[0])}: a plain-journal bearing computes its coefficients "
                     f"(from load, viscosity, length, diameter, clearance); do not give {given[0]}",
                     location("bearing", i, given[0]))
        for key in JOURNAL_KEYS[:-1] + ("speeds",):
            if key not in b:
                ctx.fail(f"{location('bearing', i, key)} is missing (required for type = \"plain-journal\": "
                         f"{SCHEMA['bearing'].keys[key].meaning}, {SCHEMA['bearing'].keys[key].unit})")
        b.setdefault("method", "short")
        if not b["clearance"] < b["diameter"] / 2:
            ctx.fail(f"{location('bearing', i, 'clearance')} must be < diameter / 2 (got clearance = "
                     f"{toml_repr(b['clearance'])}, diameter = {toml_repr(b['diameter'])})",
                     location("bearing", i, "clearance"))
    else:
        extra = [k for k in JOURNAL_KEYS if k in b]
        if extra:
            ctx.fail(f"{location('bearing', i, extra[0])} belongs to type = \"plain-journal\" bearings; this "
                     f"bearing is linear (give type = \"plain-journal\", or kxx, ...)",
                     location("bearing", i, extra[0]))
        if "kxx" not in b:
            ctx.fail(f"{location('bearing', i, 'kxx')} is missing (required: stiffness xx, N/m)")
        complete_coefficients(b)
    check_speed_table(b, _Where(ctx, "bearing"), i)
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
            ctx.fail(f"{location('bearing', i, key)}: a type = \"{kind}\" bearing ({what}) takes "
                     f"{', '.join(own)}; {reason}", location("bearing", i, key))
    for key in FILM_KEYS:
        if key not in b:
            spec = SCHEMA["bearing"].keys[key]
            ctx.fail(f"{location('bearing', i, key)} is missing (required for type = \"{kind}\": {spec.meaning}, "
                     f"{spec.unit})")
    for key in ("kxx", "kyy"):
        if isinstance(b.get(key), list):
            ctx.fail(f"{location('bearing', i, key)}: a squeeze-film damper's centring spring is one number (N/m)",
                     location("bearing", i, key))
    if not b["clearance"] < b["diameter"] / 2:
        ctx.fail(f"{location('bearing', i, 'clearance')} must be < diameter / 2 (the journal's radius; got clearance "
                 f"= {toml_repr(b['clearance'])}, diameter = {toml_repr(b['diameter'])})",
                 location("bearing", i, "clearance"))
    if kind == "journal":
        b.setdefault("model", "short")
        ratio = b["length"] / b["diameter"]
        if b["model"] == "short" and ratio > 1.0:
            ctx.fail(f"{location('bearing', i, 'length')}: the short-bearing model needs L/D <= 1, got L/D = "
                     f"{ratio:.4g}; use model = \"finite\"", location("bearing", i, "length"))
        if b["model"] == "short" and ratio > 0.5:
            ctx.warn(f"{location('bearing', i, 'length')}: L/D = {ratio:.4g} > 0.5: the short-bearing model "
                     f"overestimates the load capacity (use model = \"finite\")", location("bearing", i, "length"))
        if b["model"] == "finite" and not 0.25 <= ratio <= 1.0:
            ctx.fail(f"{location('bearing', i, 'length')}: the finite-bearing model covers 0.25 <= L/D <= 1, got "
                     f"L/D = {ratio:.4g}", location("bearing", i, "length"))
    else:
        b.setdefault("film", "pi")
        b.setdefault("kxx", 0.0)
        b.update(follow(b, SFD_FOLLOWS))
    return b


def validate(ctx, doc):
    """The file's content, checked, as plain Python values per table."""
    for name, value in doc.items():
        if name not in SCHEMA:
            if isinstance(value, (dict, list)):
                ctx.fail(f"unknown table [{name}]{suggest(name, list(SCHEMA))}; known tables: "
                         f"{', '.join(SCHEMA)}", name)
            ctx.fail(f"{name} = {toml_repr(value)}: a key outside any table; rotor files hold tables only "
                     f"(known: {', '.join(SCHEMA)})", name)
    if "rotor" not in doc:
        ctx.fail("missing table [rotor] (with theory = \"timoshenko\", \"rayleigh\" or \"euler-bernoulli\")")
    entries_of(ctx, doc, "rotor")
    shafts = entries_of(ctx, doc, "shaft")
    if not shafts:
        ctx.fail("no [[shaft]] entries: a rotor needs at least one shaft element", "shaft")
    n_nodes = len(shafts) + 1
    out = {}
    for table in SCHEMA:
        out[table] = [_check_keys(ctx, table, i, e, n_nodes) for i, e in entries_of(ctx, doc, table)]

    _plausible_values(ctx, out)
    materials = {}
    for i, m in enumerate(out["material"]):
        if m["name"] in materials:
            ctx.fail(f"material[{i}].name = {toml_repr(m['name'])}: duplicate material name "
                     f"(also material[{materials[m['name']]}])", location("material", i, "name"))
        materials[m["name"]] = i
        if "G" not in m and "nu" not in m:
            ctx.fail(f"material[{i}]: give G (shear modulus, Pa) or nu (Poisson's ratio)", location("material", i))
        m.setdefault("G", shear_modulus(m["E"], m.get("nu", 0.0)))
    for i, s in enumerate(out["shaft"]):
        for key in ("od", "id"):
            v = s.get(key, 0.0)
            if isinstance(v, list) and len(v) != 2:
                ctx.fail(f"{location('shaft', i, key)} must be a number or [left, right] (a tapered element), "
                         f"got {len(v)} values", location("shaft", i, key))
            s[key] = [v, v] if not isinstance(v, list) else v
        for end, j in (("left", 0), ("right", 1)):
            if not s["od"][j] > s["id"][j]:
                od, idd = location("shaft", i, "od"), location("shaft", i, "id")
                at = "" if s["od"][0] == s["od"][1] and s["id"][0] == s["id"][1] else f" at the {end} end"
                ctx.fail(f"{od} must be > id{at} (got od = {toml_repr(s['od'][j])}, "
                         f"id = {toml_repr(s['id'][j])})", od if od in ctx.overridden else idd)
        if s["material"] not in materials and s["material"] not in MATERIALS:
            defined = list(materials) + [n for n in MATERIALS if n not in materials]
            ctx.fail(f"shaft[{i}].material = {toml_repr(s['material'])}: no [[material]] of that name and no "
                     f"built-in material{suggest(s['material'], defined)}; defined: "
                     f"{', '.join(json.dumps(n) for n in materials) or 'none'}; built in: "
                     f"{', '.join(json.dumps(n) for n in MATERIALS)}", location("shaft", i, "material"))

    _plausible_slenderness(ctx, out["shaft"])
    _disks(ctx, out["disk"])
    for i, b in enumerate(out["bearing"]):
        _bearing(ctx, i, b)
    for i, pm in enumerate(out["point_mass"]):
        where = location("point_mass", i)
        if ("m" in pm) == ("mx" in pm or "my" in pm):
            ctx.fail(f"{where}: give either m or mx and my{', not both' if 'm' in pm else '; got neither'}",
                     where)
        if "m" in pm:
            pm["mx"] = pm["my"] = pm.pop("m")
        for key in ("mx", "my"):
            if key not in pm:
                ctx.fail(f"{location('point_mass', i, key)} is missing (mx and my go together)")
    carried = {}
    for i, sup in enumerate(out["support"]):
        n_b = len(out["bearing"])
        if not sup["bearing"] < n_b:
            ctx.fail(f"support[{i}].bearing = {sup['bearing']}: the file has {n_b} [[bearing]] "
                     f"entr{'y' if n_b == 1 else 'ies'} (indices 0..{n_b - 1})" if n_b else
                     f"support[{i}].bearing = {sup['bearing']}: the file has no [[bearing]] entries",
                     location("support", i, "bearing"))
        if out["bearing"][sup["bearing"]]["type"] in FILM_TYPES:
            ctx.fail(f"support[{i}].bearing = {sup['bearing']}: that bearing is a type = "
                     f"\"{out['bearing'][sup['bearing']]['type']}\" fluid film; pedestals carry linear bearings only",
                     location("support", i, "bearing"))
        if sup["bearing"] in carried:
            ctx.fail(f"support[{i}].bearing = {sup['bearing']}: that bearing already sits on "
                     f"support[{carried[sup['bearing']]}]", location("support", i, "bearing"))
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
    for table in TABLES:
        if table.part != "film":
            complete_table(ctx, table, out[table.name])
    ctx.issue_warnings()
    return out


class _Where:
    """How a table's `complete` names its entries: `fail`, `warn` (the file's), `loc`."""

    def __init__(self, ctx, name):
        self.fail, self.warn, self._name = ctx.fail, ctx.warn, name

    def loc(self, index, key=None):
        return location(self._name, index if SCHEMA[self._name].array else None, key)


def complete_table(ctx, table, entries):
    """A registered table's entries completed: the keys' defaults, then the table's
    own checks and derived values."""
    for e in entries:
        for key, k in table.keys.items():
            if k.default is not NO_DEFAULT and key not in e:
                e[key] = list(k.default) if isinstance(k.default, list) else k.default
    if table.complete is not None:
        table.complete(entries, _Where(ctx, table.name))


def _plausible_values(ctx, out):
    """A plausibility warning for each implausible value of a key that names its quantity
    (`Key.plausible`), once per key and value: `shaft[0].od = 60 m (and 5 more [[shaft]]
    entries): ...; did you mean mm?`."""
    judged = [(table, key, k.plausible) for table, spec in SCHEMA.items() for key, k in spec.keys.items()
              if k.plausible]
    for table, key, quantity in judged:
        seen = {}
        for i, entry in enumerate(out[table]):
            value = entry.get(key)
            for v in (value if isinstance(value, list) else [value]):
                if v is not None and v != 0:
                    seen.setdefault(v, []).append(i)
        for v, where in seen.items():
            why = judge(quantity, v)
            if why:
                loc = location(table, where[0], key)
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
                     location("shaft", i, "L"))
            return


def _disks(ctx, disks):
    """`Ip <= 2 Id` (an `InputError` beyond `IP_TOLERANCE`: no rigid body has more); radii
    of gyration (a warning)."""
    for i, d in enumerate(disks):
        if d["Ip"] > 2 * d["Id"] * (1 + IP_TOLERANCE):
            ip, idd = location("disk", i, "Ip"), location("disk", i, "Id")
            ctx.fail(f"{ip} = {toml_repr(d['Ip'])} > 2 Id = {number(2 * d['Id'])} kg m^2: impossible for a rigid "
                     f"body (the perpendicular-axis theorem: Ip <= 2 Id); are Id and Ip swapped, or in different "
                     f"units?",
                     ip if ip in ctx.overridden else idd)
        for key in ("Id", "Ip"):
            why = gyration(d[key], d["m"])
            if why:
                loc = location("disk", i, key)
                ctx.warn(f"{loc} = {number(d[key])} kg m^2 with m = {number(d['m'])} kg: {why}", loc)
