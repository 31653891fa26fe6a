"""Bad rotor files and overrides: each raises `InputError` naming the file and the
entry (table, index, key) as the user wrote it."""

import copy
import json
import math

import pytest

from rotorjax._errors import InputError
from rotorjax.io import load_rotor
from rotorjax.presets._rotor_file import preset_from_file


def _shaft(i):
    return {"L": 0.1, "od": 0.05, "id": 0.0, "material": "steel"}


BASE = {
    "rotor": {"name": "t", "theory": "timoshenko"},
    "material": [{"name": "steel", "E": 211e9, "G": 81.2e9, "rho": 7810.0}],
    "shaft": [_shaft(i) for i in range(6)],  # nodes 0..6
    "disk": [{"node": 3, "m": 10.0, "Id": 0.05, "Ip": 0.08}],
    "bearing": [{"node": 0, "kxx": 1e6}, {"node": 6, "kxx": 1e6, "cxx": 10.0}],
    "unbalance": [{"node": 3, "magnitude": 1e-4}],
}
LIMITERS = {"node": 3, "angles": [0.0, 2.0, 4.0], "clearance": 1e-3, "stiffness": 1e7, "radius": 0.1}
FILM = {"node": 0, "type": "journal", "viscosity": 0.03, "length": 0.02, "diameter": 0.05, "clearance": 5e-5}
BALANCER = {"node": 3, "n_weights": 2, "mass": 0.05, "radius": 0.1}


def _value(v):
    if isinstance(v, bool):
        return "true" if v else "false"
    if isinstance(v, str):
        return json.dumps(v)
    if isinstance(v, float):
        return "inf" if v == math.inf else "-inf" if v == -math.inf else "nan" if v != v else repr(v)
    if isinstance(v, list):
        return "[" + ", ".join(_value(x) for x in v) + "]"
    return str(v)


def toml(doc) -> str:
    """A small TOML writer for the test documents (scalars, lists, tables)."""
    out = []
    for name, value in doc.items():
        if isinstance(value, dict):
            out.append(f"[{name}]")
            out += [f"{k} = {_value(v)}" for k, v in value.items()]
        elif isinstance(value, list) and value and all(isinstance(e, dict) for e in value):
            for e in value:
                out.append(f"[[{name}]]")
                out += [f"{k} = {_value(v)}" for k, v in e.items()]
        else:
            out.insert(0, f"{name} = {_value(value)}")
        out.append("")
    return "\n".join(out)


def edit(fn):
    """A case's file: BASE changed by `fn(doc)`."""
    def make():
        doc = copy.deepcopy(BASE)
        fn(doc)
        return toml(doc)
    return make


def setitem(path, value):
    """`doc[table][index][key] = value` (index None for single tables)."""
    table, index, key = path

    def fn(doc):
        entry = doc[table] if index is None else doc[table][index]
        entry[key] = value
    return edit(fn)


def delitem(table, index, key):
    def fn(doc):
        del (doc[table] if index is None else doc[table][index])[key]
    return edit(fn)


def add(table, entry, single=False):
    def fn(doc):
        if single:
            doc[table] = entry
        else:
            doc.setdefault(table, []).append(copy.deepcopy(entry))
    return edit(fn)


def raw(text):
    return lambda: text


def dup_material(doc):
    doc["material"].append(dict(doc["material"][0]))


def limiters_with(**changes):
    entry = dict(LIMITERS, **changes)
    return add("limiters", {k: v for k, v in entry.items() if v is not None})


def balancer_with(**changes):
    entry = dict(BALANCER, **changes)
    return add("auto_balancer", {k: v for k, v in entry.items() if v is not None})


# (id, file maker, overrides, substrings the message must hold)
CASES = [
    ("od-not-above-id", setitem(("shaft", 4, "id"), 0.06), None,
     ["rotor.toml: shaft[4].od must be > id (got od = 0.05, id = 0.06)"]),
    ("node-off-the-shaft", setitem(("bearing", 1, "node"), 9), None,
     ["bearing[1].node = 9: the shaft has nodes 0..6"]),
    ("negative-node", setitem(("unbalance", 0, "node"), -1), None,
     ["unbalance[0].node = -1: the shaft has nodes 0..6"]),
    ("float-node", setitem(("disk", 0, "node"), 2.0), None, ["disk[0].node must be an integer"]),
    ("unknown-table", add("bearings", {"node": 1, "kxx": 1.0}), None,
     ["unknown table [bearings]", "did you mean 'bearing'", "known tables: rotor, material"]),
    ("unknown-key", setitem(("bearing", 0, "kzz"), 1.0), None,
     ["bearing[0].kzz: unknown key", "the keys of [[bearing]] are node, kxx, kyy"]),
    ("unknown-key-single", setitem(("rotor", None, "speeds"), 1.0), None,
     ["rotor.speeds: unknown key", "did you mean 'speed'"]),
    ("missing-required", delitem("disk", 0, "Id"), None, ["disk[0].Id is missing"]),
    ("missing-theory", delitem("rotor", None, "theory"), None, ["rotor.theory is missing"]),
    # a string is a value with a unit ("0.05 m", or "0.05": SI); one that is no quantity, or of another dimension, is
    # refused
    ("string-for-number", setitem(("shaft", 1, "od"), "fifty mm"), None,
     ["shaft[1].od must be a number, or a number and a unit (\"1.5e7 N/m\", \"3600 rpm\", \"2 in\"), got 'fifty mm'"]),
    ("wrong-unit", setitem(("shaft", 1, "od"), "0.05 kg"), None,
     ["shaft[1].od = '0.05 kg': a mass (kg), and this value is a length, in m"]),
    ("list-for-number", setitem(("disk", 0, "m"), [1.0, 2.0]), None,
     ["disk[0].m must be a number, got a list ([1.0, 2.0])"]),
    ("bool-for-number", setitem(("bearing", 0, "kxx"), True), None,
     ["bearing[0].kxx must be a number, got a boolean (true)"]),
    ("inf", setitem(("bearing", 1, "cxx"), math.inf), None, ["bearing[1].cxx must be finite, got inf"]),
    ("nan", setitem(("disk", 0, "m"), math.nan), None, ["disk[0].m must be finite, got nan"]),
    ("negative", setitem(("bearing", 0, "kxx"), -1.0), None, ["bearing[0].kxx must be >= 0 (got -1.0)"]),
    ("zero-modulus", setitem(("material", 0, "E"), 0.0), None, ["material[0].E must be > 0 (got 0.0)"]),
    ("nu-out-of-range", setitem(("material", 0, "nu"), 0.7), None, ["material[0].nu must be in (-1, 0.5]"]),
    ("unknown-material", setitem(("shaft", 2, "material"), "stel"), None,
     ['shaft[2].material = "stel": no [[material]] of that name', "did you mean 'steel'"]),
    ("material-not-a-string", setitem(("shaft", 0, "material"), 3), None,
     ["shaft[0].material must be a string, got the number 3"]),
    ("duplicate-material", edit(dup_material), None,
     ['material[1].name = "steel": duplicate material name (also material[0])']),
    ("no-material", edit(lambda d: (d.pop("material"), d["shaft"][1].update(material="bronze"))), None,
     ['shaft[1].material = "bronze": no [[material]] of that name and no built-in material', "defined: none",
      'built in: "steel"']),
    ("material-no-G-nor-nu", edit(lambda d: d["material"][0].pop("G")), None,
     ["material[0]: give G (shear modulus, Pa) or nu (Poisson's ratio)"]),
    # tapered elements, bearings with speed tables and mass coefficients, plain journals,
    # point masses and supports (issue 15)
    ("taper-three-values", setitem(("shaft", 0, "od"), [0.05, 0.04, 0.03]), None,
     ["shaft[0].od must be a number or [left, right] (a tapered element), got 3 values"]),
    ("taper-id-above-od", edit(lambda d: d["shaft"][2].update(od=[0.05, 0.02], id=[0.0, 0.03])), None,
     ["shaft[2].od must be > id at the right end (got od = 0.02, id = 0.03)"]),
    ("taper-not-numbers", setitem(("shaft", 1, "id"), [0.0, "a"]), None, ["shaft[1].id[1] must be a number"]),
    ("bearing-list-no-speeds", setitem(("bearing", 0, "kxx"), [1e6, 2e6]), None,
     ["bearing[0].kxx is a list: give the speeds it is tabulated at"]),
    ("bearing-list-length", edit(lambda d: d["bearing"][1].update(speeds=[0.0, 100.0, 200.0], kxx=[1e6, 2e6])),
     None, ["bearing[1].kxx has 2 values but speeds has 3"]),
    ("bearing-speeds-order", edit(lambda d: d["bearing"][0].update(speeds=[0.0, 200.0, 100.0], kxx=[1e6] * 3)),
     None, ["bearing[0].speeds must be strictly increasing (speeds[2] = 100.0 after 200.0)"]),
    ("bearing-one-speed", edit(lambda d: d["bearing"][0].update(speeds=[100.0])), None,
     ["bearing[0].speeds must hold at least 2 speeds (got 1)"]),
    ("bearing-negative-speed", edit(lambda d: d["bearing"][0].update(speeds=[-1.0, 100.0])), None,
     ["bearing[0].speeds[0] must be >= 0 (got -1.0)"]),
    ("bearing-negative-mass", setitem(("bearing", 0, "mxx"), -1.0), None, ["bearing[0].mxx must be >= 0"]),
    ("bearing-no-kxx", delitem("bearing", 0, "kxx"), None, ["bearing[0].kxx is missing (required: stiffness xx"]),
    ("bearing-bad-type", setitem(("bearing", 0, "type"), "ball"), None,
     ['bearing[0].type must be one of "linear", "plain-journal", "journal", "sfd" (got "ball")']),
    ("journal-with-kxx", setitem(("bearing", 0, "type"), "plain-journal"), None,
     ["bearing[0].kxx: a plain-journal bearing computes its coefficients"]),
    ("journal-missing-viscosity", edit(lambda d: d["bearing"].__setitem__(0, {
        "node": 0, "type": "plain-journal", "load": 100.0, "length": 0.02, "diameter": 0.05,
        "clearance": 5e-5, "speeds": [100.0, 200.0]})), None,
     ["bearing[0].viscosity is missing (required for type = \"plain-journal\": lubricant dynamic viscosity"]),
    ("journal-clearance", edit(lambda d: d["bearing"].__setitem__(0, {
        "node": 0, "type": "plain-journal", "load": 100.0, "viscosity": 0.03, "length": 0.02, "diameter": 0.05,
        "clearance": 0.03, "speeds": [100.0, 200.0]})), None,
     ["bearing[0].clearance must be < diameter / 2 (got clearance = 0.03, diameter = 0.05)"]),
    ("journal-method", edit(lambda d: d["bearing"].__setitem__(0, {
        "node": 0, "type": "plain-journal", "load": 100.0, "viscosity": 0.03, "length": 0.02, "diameter": 0.05,
        "clearance": 5e-5, "speeds": [100.0, 200.0], "method": "long"})), None,
     ['bearing[0].method must be one of "short", "finite" (got "long")']),
    # fluid films as nonlinear forces ([[bearing]] type = "journal" / "sfd")
    ("film-load", edit(lambda d: d["bearing"].__setitem__(0, dict(FILM, load=100.0))), None,
     ['bearing[0].load: a type = "journal" bearing (journal bearing) takes', "do not give load"]),
    ("film-kxx", edit(lambda d: d["bearing"].__setitem__(0, dict(FILM, kxx=1e6))), None,
     ["bearing[0].kxx: a type = \"journal\" bearing", "not a coefficient table"]),
    ("film-speeds", edit(lambda d: d["bearing"].__setitem__(0, dict(FILM, speeds=[1.0, 2.0]))), None,
     ["bearing[0].speeds: a type = \"journal\" bearing"]),
    ("film-missing-clearance", edit(lambda d: d["bearing"].__setitem__(
        0, {k: v for k, v in FILM.items() if k != "clearance"})), None,
     ['bearing[0].clearance is missing (required for type = "journal": radial clearance, m)']),
    ("film-clearance-zero", edit(lambda d: d["bearing"].__setitem__(0, dict(FILM, clearance=0.0))), None,
     ["bearing[0].clearance", "> 0"]),
    ("film-clearance-radius", edit(lambda d: d["bearing"].__setitem__(0, dict(FILM, clearance=0.03))), None,
     ["bearing[0].clearance must be < diameter / 2"]),
    ("film-viscosity", edit(lambda d: d["bearing"].__setitem__(0, dict(FILM, viscosity=-0.01))), None,
     ["bearing[0].viscosity", "> 0"]),
    ("film-length", edit(lambda d: d["bearing"].__setitem__(0, dict(FILM, length=0.0))), None,
     ["bearing[0].length", "> 0"]),
    ("film-short-long", edit(lambda d: d["bearing"].__setitem__(0, dict(FILM, length=0.06))), None,
     ["bearing[0].length: the short-bearing model needs L/D <= 1, got L/D = 1.2"]),
    ("film-finite-range", edit(lambda d: d["bearing"].__setitem__(0, dict(FILM, model="finite", length=0.01))),
     None, ["bearing[0].length: the finite-bearing model covers 0.25 <= L/D <= 1, got L/D = 0.2"]),
    ("film-model", edit(lambda d: d["bearing"].__setitem__(0, dict(FILM, model="medium"))), None,
     ["bearing[0].model must be one of"]),
    ("sfd-film", edit(lambda d: d["bearing"].__setitem__(0, dict(FILM, type="sfd", film="3pi"))), None,
     ["bearing[0].film must be one of"]),
    ("sfd-model", edit(lambda d: d["bearing"].__setitem__(0, dict(FILM, type="sfd", model="short"))), None,
     ['bearing[0].model: a type = "sfd" bearing (squeeze-film damper) takes']),
    ("sfd-spring-list", edit(lambda d: d["bearing"].__setitem__(0, dict(FILM, type="sfd", kxx=[1.0, 2.0]))),
     None, ["bearing[0].kxx: a squeeze-film damper's centring spring is one number"]),
    ("support-under-film", edit(lambda d: (d["bearing"].__setitem__(0, dict(FILM)),
                                           d.__setitem__("support", [{"bearing": 0, "m": 5.0, "kxx": 1e7}]))),
     None, ['support[0].bearing = 0: that bearing is a type = "journal" fluid film']),
    ("film-viscosity-set", edit(lambda d: d["bearing"].__setitem__(0, dict(FILM))), {"bearing0.viscosity": "0"},
     ["bearing0.viscosity"]),
    ("journal-key-on-linear", setitem(("bearing", 1, "viscosity"), 0.03), None,
     ['bearing[1].viscosity belongs to type = "plain-journal" bearings']),
    ("point-mass-both", add("point_mass", {"node": 2, "m": 1.0, "mx": 1.0}), None,
     ["point_mass[0]: give either m or mx and my, not both"]),
    # [[seal]] (issue 33): its table declared by its component, checked by the same reader
    ("seal-no-kxx", add("seal", {"node": 2, "cxx": 10.0}), None, ["seal[0].kxx is missing (required: stiffness xx"]),
    ("seal-list-no-speeds", add("seal", {"node": 2, "kxx": [1e5, 2e5]}), None,
     ["seal[0].kxx is a list: give the speeds it is tabulated at"]),
    ("seal-list-length", add("seal", {"node": 2, "speeds": [0.0, 100.0, 200.0], "kxx": 1e5, "kxy": [1.0, 2.0]}),
     None, ["seal[0].kxy has 2 values but speeds has 3"]),
    ("seal-speeds-order", add("seal", {"node": 2, "speeds": [0.0, 200.0, 100.0], "kxx": 1e5}), None,
     ["seal[0].speeds must be strictly increasing (speeds[2] = 100.0 after 200.0)"]),
    ("seal-negative-damping", add("seal", {"node": 2, "kxx": -1e5, "cxx": -1.0}), None,
     ["seal[0].cxx must be >= 0 (got -1.0)"]),
    ("seal-node", add("seal", {"node": 7, "kxx": 1e5}), None, ["seal[0].node = 7: the shaft has nodes 0..6"]),
    ("seal-unknown-key", add("seal", {"node": 2, "kxx": 1e5, "leakage": 0.1}), None,
     ["seal[0].leakage: unknown key; the keys of [[seal]] are node, speeds, kxx"]),
    ("seal-single", add("seal", {"node": 2, "kxx": 1e5}, single=True), None,
     ["seal must be an array of tables: write [[seal]]"]),
    ("seal-override-missing", edit(lambda d: None), {"seal0.kxx": 1.0},
     ["override seal0.kxx: the file has no [[seal]] table"]),
    ("point-mass-half", add("point_mass", {"node": 2, "mx": 1.0}), None,
     ["point_mass[0].my is missing (mx and my go together)"]),
    ("point-mass-node", add("point_mass", {"node": 9, "m": 1.0}), None,
     ["point_mass[0].node = 9: the shaft has nodes 0..6"]),
    ("support-index", add("support", {"bearing": 2, "m": 5.0, "kxx": 1e7}), None,
     ["support[0].bearing = 2: the file has 2 [[bearing]] entries (indices 0..1)"]),
    ("support-negative", add("support", {"bearing": -1, "m": 5.0, "kxx": 1e7}), None,
     ["support[0].bearing must be >= 0"]),
    ("support-no-kxx", add("support", {"bearing": 0, "m": 5.0}), None, ["support[0].kxx is missing"]),
    ("support-twice", edit(lambda d: d.update(support=[{"bearing": 1, "m": 5.0, "kxx": 1e7},
                                                       {"bearing": 1, "m": 2.0, "kxx": 1e7}])), None,
     ["support[1].bearing = 1: that bearing already sits on support[0]"]),
    ("empty-shaft", edit(lambda d: d.pop("shaft")), None, ["no [[shaft]] entries"]),
    ("missing-rotor", edit(lambda d: d.pop("rotor")), None, ["missing table [rotor]"]),
    ("bad-theory", setitem(("rotor", None, "theory"), "timo"), None,
     ['rotor.theory must be one of "euler-bernoulli", "rayleigh", "timoshenko" (got "timo")']),
    ("shaft-as-single-table", raw('[rotor]\ntheory = "timoshenko"\n[shaft]\nL = 0.1\n'), None,
     ["shaft must be an array of tables: write [[shaft]]"]),
    ("rotor-as-array", raw('[[rotor]]\ntheory = "timoshenko"\n'), None,
     ["rotor must be a single table: write [rotor], not [[rotor]]"]),
    ("top-level-key", edit(lambda d: d.update(speed=3)), None, ["speed = 3: a key outside any table"]),
    ("syntax-error", raw('[rotor]\ntheory = "timoshenko"\nname = = 3\n'), None,
     ["rotor.toml: not valid TOML", "line 3", "column"]),
    ("n-modes-too-many", setitem(("rotor", None, "n_modes"), 100), None,
     ["rotor.n_modes = 100: the shaft has 28 free dofs"]),
    ("n-modes-zero", setitem(("rotor", None, "n_modes"), 0), None, ["rotor.n_modes must be >= 1 (got 0)"]),
    ("date-for-number", raw(toml(BASE).replace("m = 10.0", "m = 1979-05-27")), None,
     ["disk[0].m must be a number, got a date"]),
    ("limiters-angles-and-n", limiters_with(n=3), None,
     ["limiters[0]: give either angles = [...] or n (with first_angle), not both"]),
    ("limiters-neither", limiters_with(angles=None), None, ["limiters[0]: give either angles", "got neither"]),
    ("limiters-clearance-count", limiters_with(clearance=[1e-3, 1e-3]), None,
     ["limiters[0].clearance must be a number or one value per limiter (3), got 2 values"]),
    ("limiters-angle-string", limiters_with(angles=[0.0, "north", 4.0]), None,
     ['limiters[0].angles[1] must be a number, or a number and a unit']),
    ("limiters-empty-angles", limiters_with(angles=[]), None, ["limiters[0].angles must be a non-empty list"]),
    ("limiters-negative-stiffness", limiters_with(stiffness=[1e7, -1.0, 1e7]), None,
     ["limiters[0].stiffness[1] must be >= 0 (got -1.0)"]),
    ("balancer-neither", balancer_with(n_weights=None, mass=None), None,
     ["auto_balancer[0]: give either masses = [...] or n_weights and mass; got neither"]),
    ("balancer-mass-missing", balancer_with(mass=None), None, ["auto_balancer[0].mass is missing"]),
    ("balancer-kind", balancer_with(kind="marble"), None,
     ['auto_balancer[0].kind must be one of "ball", "roller", "pendulum" (got "marble")']),
    ("balancer-radius-and-r1", balancer_with(r1=0.1), None, ["auto_balancer[0]: give either radius or r1 and r2"]),
    ("balancer-center-size", balancer_with(center=[0.0]), None, ["auto_balancer[0].center must be [x, y]"]),
    ("balancer-weights-zero", balancer_with(n_weights=0), None, ["auto_balancer[0].n_weights must be >= 1"]),
    ("fixed-unknown-dof", add("fixed", {"node": 0, "dofs": ["z"]}), None,
     ['fixed[0].dofs[0] must be one of "x", "y", "sx", "sy" (got "z")']),
    ("fixed-dof-twice", add("fixed", {"node": 0, "dofs": ["x", "x"]}), None, ["fixed[0].dofs names a dof twice"]),
    ("fixed-everything", edit(lambda d: d.update(fixed=[{"node": i} for i in range(7)])), None,
     ["[[fixed]] entries hold every dof of the shaft at zero"]),
    ("clearance-zero", add("clearance_bearing", {"node": 6, "clearance": 0.0, "k": 1e7}), None,
     ["clearance_bearing[0].clearance must be > 0 (got 0.0)"]),
    ("cubic-missing-k3", add("cubic_bearing", {"node": 0, "k": 1e6}), None, ["cubic_bearing[0].k3 is missing"]),
    ("internal-damping-negative", add("internal_damping", {"relaxation_time": -1e-5}, single=True), None,
     ["internal_damping.relaxation_time must be >= 0 (got -1e-05)"]),
    ("gravity-string", add("gravity", {"g": "9.81 N"}, single=True), None,
     ["gravity.g = '9.81 N': a force (N), and this value is an acceleration, in m/s^2"]),
    # external and disk damping, probes
    ("external-damping-negative", add("external_damping", {"coefficient": -0.5}, single=True), None,
     ["external_damping.coefficient must be >= 0 (got -0.5)"]),
    ("external-damping-missing", add("external_damping", {}, single=True), None,
     ["external_damping.coefficient is missing (required: viscous damping of the shaft's lateral motion per "
      "unit length, N s/m^2)"]),
    ("external-damping-array", edit(lambda d: d.update(external_damping=[{"coefficient": 1.0}])), None,
     ["external_damping must be a single table: write [external_damping], not [[external_damping]]"]),
    ("external-damping-unknown-key", add("external_damping", {"coeff": 1.0}, single=True), None,
     ["external_damping.coeff: unknown key (did you mean 'coefficient'?)"]),
    ("disk-damping-negative", add("disk_damping", {"node": 3, "translational": -2.0}), None,
     ["disk_damping[0].translational must be >= 0 (got -2.0)"]),
    ("disk-damping-negative-angular", add("disk_damping", {"node": 3, "translational": 2.0, "angular": -0.1}),
     None, ["disk_damping[0].angular must be >= 0 (got -0.1)"]),
    ("disk-damping-node-off-the-shaft", add("disk_damping", {"node": 7, "translational": 2.0}), None,
     ["disk_damping[0].node = 7: the shaft has nodes 0..6"]),
    ("disk-damping-missing", add("disk_damping", {"node": 3}), None, ["disk_damping[0].translational is missing"]),
    ("disk-damping-unknown-key", add("disk_damping", {"node": 3, "translational": 2.0, "rotational": 0.1}), None,
     ["disk_damping[0].rotational: unknown key", "the keys of [[disk_damping]] are node, translational, angular"]),
    ("disk-damping-override", add("disk_damping", {"node": 3, "translational": 2.0}),
     {"disk_damping0.translational": -1.0},
     ["disk_damping[0].translational must be >= 0 (got -1.0)", "disk_damping0.translational=-1.0"]),
    ("probe-node-off-the-shaft", add("probe", {"node": 9}), None, ["probe[0].node = 9: the shaft has nodes 0..6"]),
    ("probe-missing-node", add("probe", {"name": "left"}), None, ["probe[0].node is missing"]),
    ("probe-name-not-a-word", add("probe", {"node": 3, "name": "left disk"}), None,
     ['probe[0].name = "left disk": must be a word (letters, digits and _']),
    ("probe-name-number", add("probe", {"node": 3, "name": 3}), None, ["probe[0].name must be a string"]),
    ("probe-name-node", add("probe", {"node": 3, "name": "node"}), None,
     ['probe[0].name = "node": its outputs node_x, node_y would replace the scene\'s own']),
    ("probe-same-name", edit(lambda d: d.update(probe=[{"node": 2}, {"node": 4}])), None,
     ['probe[1].name = "disk": probe[0] has that name already']),
    ("probe-unknown-key", add("probe", {"node": 3, "label": "x"}), None,
     ["probe[0].label: unknown key", "the keys of [[probe]] are node, name"]),
    # impossible values (issue 28): no rigid body has Ip > 2 Id; no section has id >= od
    ("disk-ip-above-2id", setitem(("disk", 0, "Ip"), 0.2), None,
     ["disk[0].Ip = 0.2 > 2 Id = 0.1 kg m^2: impossible for a rigid body", "perpendicular-axis theorem",
      "are Id and Ip swapped"]),
    ("disk-id-ip-swapped", edit(lambda d: d["disk"][0].update(Id=0.08, Ip=0.5)), None,
     ["disk[0].Ip = 0.5 > 2 Id = 0.16 kg m^2"]),
    ("disk-negative-mass", setitem(("disk", 0, "m"), -1.0), None, ["disk[0].m must be > 0 (got -1.0)"]),
    ("disk-negative-ip", setitem(("disk", 0, "Ip"), -0.1), None, ["disk[0].Ip must be >= 0 (got -0.1)"]),
    ("id-equal-od", setitem(("shaft", 3, "id"), 0.05), None,
     ["shaft[3].od must be > id (got od = 0.05, id = 0.05)"]),
    ("taper-id-equal-od", edit(lambda d: d["shaft"][1].update(od=[0.06, 0.04], id=[0.02, 0.04])), None,
     ["shaft[1].od must be > id at the right end (got od = 0.04, id = 0.04)"]),
    ("negative-point-mass", add("point_mass", {"node": 2, "m": -2.0}), None,
     ["point_mass[0].m must be >= 0 (got -2.0)"]),
    ("negative-density", setitem(("material", 0, "rho"), -7810.0), None, ["material[0].rho must be > 0"]),
    # a typo's suggestion is the key meant: a doubled letter names the direct coefficient (issue 28, item 9)
    ("suggest-kx", setitem(("bearing", 0, "kx"), 1e6), None, ["bearing[0].kx: unknown key (did you mean 'kxx'?)"]),
    ("suggest-ky", setitem(("bearing", 1, "ky"), 1e6), None, ["bearing[1].ky: unknown key (did you mean 'kyy'?)"]),
    ("suggest-cx", setitem(("bearing", 0, "cx"), 10.0), None, ["bearing[0].cx: unknown key (did you mean 'cxx'?)"]),
    ("suggest-cy", setitem(("bearing", 0, "cy"), 10.0), None, ["bearing[0].cy: unknown key (did you mean 'cyy'?)"]),
    ("suggest-mx", setitem(("bearing", 0, "mx"), 1.0), None, ["bearing[0].mx: unknown key (did you mean 'mxx'?)"]),
    ("suggest-case", setitem(("disk", 0, "ip"), 0.08), None, ["disk[0].ip: unknown key (did you mean 'Ip'?)"]),
    ("suggest-prefix", setitem(("bearing", 0, "spee"), 1.0), None,
     ["bearing[0].spee: unknown key (did you mean 'speeds'?)"]),
    ("override-suggest-kx", edit(lambda d: None), {"bearing0.kx": 1.0},
     ["override bearing0.kx: unknown key 'kx'", "did you mean 'kxx'"]),
    # overrides (the CLI's --set)
    ("override-disk-ip", edit(lambda d: None), {"disk0.Ip": 0.5},
     ["disk[0].Ip = 0.5 > 2 Id = 0.1 kg m^2", "(set by the override disk0.Ip=0.5)"]),
    ("override-disk-id", edit(lambda d: None), {"disk0.Id": 0.01},
     ["disk[0].Ip = 0.08 > 2 Id = 0.02 kg m^2", "(set by the override disk0.Id=0.01)"]),
    ("override-negative", edit(lambda d: None), {"bearing0.kxx": -5.0},
     ["bearing[0].kxx must be >= 0 (got -5.0)", "bearing0.kxx=-5.0"]),
    ("override-od-id", edit(lambda d: None), {"shaft4.id": 0.06},
     ["shaft[4].od must be > id (got od = 0.05, id = 0.06)", "shaft4.id=0.06"]),
    ("override-node", edit(lambda d: None), {"disk0.node": "9"},
     ["disk[0].node = 9: the shaft has nodes 0..6", "disk0.node=9"]),
    ("override-index", edit(lambda d: None), {"bearing7.kxx": 1.0},
     ["override bearing7.kxx: the file has 2 [[bearing]] entries (bearing0..bearing1)"]),
    ("override-key", edit(lambda d: None), {"bearing0.kxxx": 1.0},
     ["override bearing0.kxxx: unknown key 'kxxx'", "did you mean 'kxx'"]),
    ("override-table", edit(lambda d: None), {"bearings0.kxx": 1.0},
     ["override bearings0.kxx: unknown table 'bearings'"]),
    ("override-not-a-number", edit(lambda d: None), {"bearing0.kxx": "abc"},
     ["override bearing0.kxx must be a number, or a number and a unit"]),
    ("override-absent-table", edit(lambda d: None), {"gravity.g": 1.0},
     ["override gravity.g: the file has no [gravity] table"]),
    ("override-no-index", edit(lambda d: None), {"bearing.kxx": 1.0},
     ["override bearing.kxx", "bearing<index>.kxx"]),
    ("override-speed-string", edit(lambda d: None), {"speed": "fast"}, ["override speed must be a number, or a number and a unit"]),
]


@pytest.mark.parametrize("make,overrides,expected", [c[1:] for c in CASES], ids=[c[0] for c in CASES])
def test_bad_rotor_file(tmp_path, make, overrides, expected):
    path = tmp_path / "rotor.toml"
    path.write_text(make(), encoding="utf-8")
    with pytest.raises(InputError) as info:
        load_rotor(path, overrides)
    message = str(info.value)
    assert message.startswith(f"{path}: ")
    for text in expected:
        assert text in message, message


def test_cases_are_many_and_distinct():
    assert len(CASES) >= 30 and len({c[0] for c in CASES}) == len(CASES)


def test_the_base_file_is_valid(tmp_path):
    path = tmp_path / "rotor.toml"
    path.write_text(toml(BASE))
    assert load_rotor(path).n_nodes == 7
    for extra in (add("limiters", LIMITERS), add("auto_balancer", BALANCER),
                  add("external_damping", {"coefficient": 0.0}, single=True),
                  add("disk_damping", {"node": 3, "translational": 0.0}), add("probe", {"node": 6})):
        path.write_text(extra())
        load_rotor(path)


@pytest.mark.parametrize("setup,expected", [
    ("missing", "no such rotor file"),
    ("directory", "not a file"),
    ("latin1", "not UTF-8 text (byte 0xe9"),
])
def test_unreadable_files(tmp_path, setup, expected):
    path = tmp_path / "rotor.toml"
    if setup == "directory":
        path.mkdir()
    elif setup == "latin1":
        path.write_bytes(toml(BASE).replace('name = "t"', 'name = "café"').encode("latin-1"))
    with pytest.raises(InputError) as info:
        load_rotor(path)
    assert str(info.value) == f"{path}: {expected}" or str(info.value).startswith(f"{path}: {expected}")


def test_preset_set_keys_are_checked(tmp_path):
    path = tmp_path / "rotor.toml"
    path.write_text(toml(BASE))
    preset = preset_from_file(str(path))
    with pytest.raises(InputError, match="unknown parameter 'bearing9.kxx'"):
        preset.params({"bearing9.kxx": "1"})
    with pytest.raises(InputError, match=r"bearing0.kxx=-1: must be >= 0"):
        preset.params({"bearing0.kxx": "-1"})
    with pytest.raises(InputError, match=r"disk0.node=7: must be an integer in \[0,6\]"):
        preset.params({"disk0.node": "7"})
    with pytest.raises(InputError, match=r"rotor.toml: shaft\[1\].od must be > id .*shaft1.id=0.2"):
        preset.build(dict(preset.params(), **{"shaft1.id": 0.2}))
    bad = tmp_path / "bad.toml"
    bad.write_text(toml(BASE).replace("kxx = 1000000.0", "kxx = -1.0", 1))
    with pytest.raises(InputError, match=r"bad.toml: bearing\[0\].kxx must be >= 0"):
        preset_from_file(str(bad))
