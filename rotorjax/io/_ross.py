"""A rotor saved by ROSS (`ross.Rotor.save`, its TOML and JSON forms, versions 1.x to
3.x) as a rotorjax rotor file: `ross_rotor_text` reads it, `import_ross` writes it.

ROSS writes one section per element, `"ClassName_tag"`, each in SI base units, and a
`[parameters]` table (`min_w`, `max_w`, `rated_w`). What maps, and how:

- `ShaftElement` -> `[[shaft]]` (`L`; `od`, `id` from `odl`/`odr`, `idl`/`idr`, a
  pair where they differ: tapered) with its `material` (`name`, `rho`, `E`, `G_s`) ->
  `[[material]]` (one per distinct set of constants). The theory is the rotor's: shear
  and rotary inertia -> `timoshenko`, rotary inertia alone -> `rayleigh`, neither ->
  `euler-bernoulli`, the same on every element; Cowper's shear coefficient (ROSS's
  default `shear_method_calc`).
- `DiskElement` -> `[[disk]]` (`m`, `Id`, `Ip`); `PointMass` at a shaft node ->
  `[[point_mass]]` (`mx`, `my`).
- `BearingElement` and the bearing and seal classes ROSS saves with their coefficient
  lists (`SealElement`, `BallBearingElement`, `RollerBearingElement`,
  `CylindricalBearing`, ...) -> `[[bearing]]` with the lateral coefficients (`k`, `c`,
  `m` of `xx`, `xy`, `yx`, `yy`): one value each, or a table over the speeds (ROSS
  2.x's `frequency`, evaluated at the rotor's speed; 3.x's `speed`); a class's own
  model parameters are not read (its coefficients are what ROSS computed from them).
- `[parameters] rated_w` -> `[rotor] speed`.

Refused, by the section's name and why (`InputError`), rather than dropped: what a
lateral rotor file cannot hold: axial or torsional terms (`kzz`, `czz`, `mzz`, a point
mass's `mz` different from zero), shaft axial force or torque, an element's
proportional damping (`alpha`, `beta`) and the whole rotor's damping (3.x's
`[parameters]` `alpha`, `beta`, `default_damping_ratio`, `modal_damping_ratio`, where
not zero), gyroscopic effects switched off, Hutchinson's shear coefficient, concentric
shaft layers on one node, a theory that differs between elements, bearings linked to
another node (`n_link`), coefficients tabulated over the excitation frequency (ROSS
3.x's `frequency`, a magnetic bearing's or a squeeze-film damper's) or over speed and
frequency at once, and any other element class (couplings, gears, thrust pads, ...).

Every value ROSS wrote is SI already (it converts pint quantities when it saves).
`notes` says what the translation chose where the two tools differ: ROSS interpolates
a bearing table with a smoothing spline (2.x) or PCHIP (3.x), rotorjax with a
not-a-knot cubic through the points, so coefficients agree at the table's speeds."""

import json
import pathlib
import tomllib

import numpy as np

from .._errors import InputError
from ._write import _f, _s, _toml_value

LATERAL = tuple(f"{k}{d}" for k in "kcm" for d in ("xx", "xy", "yx", "yy"))
AXIAL = ("kzz", "czz", "mzz")
#: the keys of a bearing or seal section read (ROSS's own `ross_2to3.TABLE_KEYS`); the rest are model parameters
TABLE_KEYS = set(LATERAL + AXIAL) | {"n", "speed", "frequency", "tag", "n_link", "scale_factor", "color",
                                     "interpolation", "seal_leakage"}
BEARING_CLASSES = ("BearingElement", "SealElement", "BallBearingElement", "RollerBearingElement",
                   "CylindricalBearing", "LabyrinthSeal", "MagneticBearingElement", "BearingElement6DoF")
SHAFT_CLASSES = ("ShaftElement", "ShaftElement6DoF")
DISK_CLASSES = ("DiskElement", "DiskElement6DoF")
MASS_CLASSES = ("PointMass", "PointMass6DoF")


def read_ross(path):
    """`(label, data)`: the file's name and its sections (TOML, or JSON for `.json`, as
    ROSS picks)."""
    label = str(path)
    p = pathlib.Path(label)
    if not p.is_file():
        raise InputError(f"{label}: no such file (a rotor saved by ROSS's Rotor.save, .toml or .json)")
    try:
        text = p.read_text(encoding="utf-8")
    except (OSError, UnicodeDecodeError) as e:
        raise InputError(f"{label}: cannot be read as UTF-8 text ({e})") from None
    try:
        data = json.loads(text) if p.suffix.lower() == ".json" else tomllib.loads(text)
    except (json.JSONDecodeError, tomllib.TOMLDecodeError) as e:
        kind = "JSON" if p.suffix.lower() == ".json" else "TOML"
        raise InputError(f"{label}: not valid {kind}: {e}") from None
    if not isinstance(data, dict) or not any(isinstance(v, dict) and "_" in k for k, v in data.items()):
        raise InputError(f"{label}: not a rotor saved by ROSS (no element sections such as "
                         "\"ShaftElement_Shaft Element 0\")")
    return label, data


def _number(where, key, value, label):
    if isinstance(value, str):          # files of ROSS before 1.1 wrote some numbers as strings
        try:
            value = float(value)
        except ValueError:
            pass
    if isinstance(value, bool) or not isinstance(value, (int, float)) or not np.isfinite(value):
        raise InputError(f"{label}: [{where}] {key} = {value!r}: expected a finite number")
    return float(value)


def _numbers(where, key, value, label):
    if isinstance(value, list):
        if any(isinstance(v, list) for v in value):
            raise InputError(f"{label}: [{where}] {key}: a table over speed and frequency at once (ROSS 3.x); a "
                             "rotor file's bearing coefficients depend on the speed alone")
        return [_number(where, key, v, label) for v in value]
    return [_number(where, key, value, label)]


def _refuse(label, where, why):
    raise InputError(f"{label}: [{where}]: {why}; rotorjax cannot represent it (remove it, or change it in ROSS "
                     "and save again)")


#: ROSS 3.x's damping of the whole rotor (`Rotor(modal_damping_ratio=, default_damping_ratio=, alpha=, beta=)`)
ROTOR_DAMPING = {"alpha": "proportional damping of the whole rotor (alpha M)",
                 "beta": "proportional damping of the whole rotor (beta K)",
                 "default_damping_ratio": "modal damping of the whole rotor",
                 "modal_damping_ratio": "modal damping of the rotor's first modes"}


def _rotor_damping(label, params):
    for key, what in ROTOR_DAMPING.items():
        v = params.get(key)
        values = v if isinstance(v, list) else [] if v is None else [v]
        if any(_number("parameters", key, x, label) != 0 for x in values):
            _refuse(label, "parameters", f"{key} = {v}: {what}")


def _shaft(label, where, s, materials):
    get = s.get
    for key in ("axial_force", "torque", "alpha", "beta"):
        if _number(where, key, get(key, 0) or 0, label) != 0:
            what = {"axial_force": "a shaft axial force", "torque": "a shaft torque",
                    "alpha": "proportional damping (alpha M)", "beta": "proportional damping (beta K)"}[key]
            _refuse(label, where, f"{key} = {get(key)}: {what}")
    if get("gyroscopic", True) is False:
        _refuse(label, where, "gyroscopic = false: rotorjax's shaft elements always carry their gyroscopic terms")
    if get("shear_method_calc", "cowper") not in ("cowper", None):
        _refuse(label, where, f"shear_method_calc = {get('shear_method_calc')!r}: rotorjax uses Cowper's shear "
                              "coefficient")
    shear, rotary = get("shear_effects", True), get("rotary_inertia", True)
    if shear and not rotary:
        _refuse(label, where, "shear_effects without rotary_inertia: rotorjax's theories are euler-bernoulli, "
                              "rayleigh and timoshenko")
    theory = "timoshenko" if shear else ("rayleigh" if rotary else "euler-bernoulli")
    mat = get("material")
    if not isinstance(mat, dict):
        raise InputError(f"{label}: [{where}] material: missing (ROSS writes it as a table of name, rho, E, G_s)")
    consts = tuple(_number(f"{where}.material", k, mat.get(k), label) for k in ("rho", "E", "G_s"))
    name = str(mat.get("name") or "material")
    key = materials.setdefault(consts, _unique(name, [m for m in materials.values()]))
    num = lambda k: _number(where, k, get(k), label)   # noqa: E731
    odl, idl = num("odl"), num("idl")
    odr = odl if get("odr") is None else num("odr")
    idr = idl if get("idr") is None else num("idr")
    return theory, {"L": num("L"), "od": odl if odl == odr else [odl, odr], "id": idl if idl == idr else [idl, idr],
                    "material": key}


def _unique(name, taken):
    out, i = name, 1
    while out in taken:
        i += 1
        out = f"{name}-{i}"
    return out


def _bearing(label, where, b, version):
    for key in AXIAL:
        if key in b and any(v != 0 for v in _numbers(where, key, b[key], label)):
            _refuse(label, where, f"{key} = {b[key]}: an axial coefficient (rotorjax's rotors move laterally)")
    axis = None
    if "speed" in b and b["speed"] is not None:
        axis = "speed"
        if b.get("frequency") is not None:
            _refuse(label, where, "a table over speed and excitation frequency at once")
    elif b.get("frequency") is not None:
        if version >= 3:
            _refuse(label, where, "coefficients over the excitation frequency (ROSS 3.x's frequency; a rotor "
                                  "file's bearing tables are over the rotor's speed)")
        axis = "frequency"          # ROSS 1.x-2.x evaluate this table at the rotor's speed
    entry = {"node": int(_number(where, "n", b.get("n"), label))}
    speeds = None if axis is None else _numbers(where, axis, b[axis], label)
    for key in LATERAL:
        if key not in b or b[key] is None:
            continue
        values = _numbers(where, key, b[key], label)
        if speeds is not None and len(values) not in (1, len(speeds)):
            raise InputError(f"{label}: [{where}] {key}: {len(values)} values for {len(speeds)} speeds")
        if speeds is None and len(values) > 1:
            raise InputError(f"{label}: [{where}] {key}: {len(values)} values and no speeds (frequency) for them")
        zero = all(v == 0 for v in values)
        if zero and (key[1:] in ("xy", "yx") or key[0] == "m" and all(  # kyy, cyy, myy default to kxx, cxx, mxx
                v == 0 for v in _numbers(where, key[0] + "xx", b.get(key[0] + "xx", 0), label))):
            continue
        entry[key] = values[0] if len(values) == 1 or all(v == values[0] for v in values) else values
    if speeds is not None and any(isinstance(v, list) for v in entry.values()):
        if len(speeds) == 1:
            speeds = None
        else:
            entry["speeds"] = speeds
    elif speeds is not None:
        speeds = None
    return entry, speeds is not None and (b.get("interpolation") or ("smoothing" if version < 3 else "pchip"))


def _supports(label, bearings, masses, last):
    """`(bearings, supports, masses)`: the bearings at shaft nodes, the pedestals and the
    point masses at shaft nodes. ROSS carries a pedestal as a bearing linked (`n_link`)
    to a node of its own beyond the shaft's, a point mass there and a bearing from it
    to the ground; that is a rotor file's `[[support]]` (mass, and stiffness and
    damping to the ground without cross terms or tables). Any other use of a node
    beyond the shaft's is refused."""
    own, linked, pedestal = [], {}, {}
    for key, entry, n_link in bearings:
        if n_link is not None:
            if not 0 <= entry["node"] <= last or int(n_link) <= last:
                _refuse(label, key, f"n_link = {n_link}: a bearing between nodes {entry['node']} and {n_link} (a "
                                    "rotor file carries a bearing between a shaft node and a pedestal of its own)")
            linked.setdefault(int(n_link), []).append((key, entry))
        elif 0 <= entry["node"] <= last:
            own.append((key, entry))
        else:
            pedestal.setdefault(entry["node"], []).append((key, entry))
    at = {}
    for row in masses:
        at.setdefault(row["node"], []).append(row)
    supports = []
    for node in sorted(set(linked) | set(pedestal) | {n for n in at if not 0 <= n <= last}):
        up, down, mass = linked.get(node, []), pedestal.get(node, []), at.get(node, [])
        if len(up) != 1 or len(down) != 1 or len(mass) != 1:
            raise InputError(f"{label}: node {node} (beyond the shaft's nodes 0..{last}) carries {len(up)} linked "
                             f"bearing(s), {len(down)} bearing(s) to the ground and {len(mass)} point mass(es); a "
                             "rotor file's [[support]] is one of each (a pedestal); rotorjax cannot represent this")
        (key, base), m = down[0], mass[0]
        bad = [k for k in base if k not in ("node", "kxx", "kyy", "cxx", "cyy")]
        if bad or any(isinstance(v, list) for v in base.values()) or m["mx"] != m["my"] or not m["mx"] > 0:
            raise InputError(f"{label}: [{key}] and its point mass at node {node}: a pedestal with "
                             f"{', '.join(bad) or 'a table or unequal masses'}; a rotor file's [[support]] has one "
                             "mass and constant kxx, kyy, cxx, cyy to the ground; rotorjax cannot represent this")
        own.append(up[0])
        supports.append({"bearing": len(own) - 1, "m": m["mx"],
                         **{k: base.get(k, base.get(k[0] + "xx", 0.0)) for k in ("kxx", "kyy", "cxx", "cyy")}})
    return own, supports, [m for m in masses if 0 <= m["node"] <= last]


def _version(label, data):
    v = data.get("ross_version")
    if v is None:
        # before 2.1 no version was written: 2.0 added the axial coefficients and a point mass's mz
        six = any(isinstance(s, dict) and ("kzz" in s or "mz" in s) for s in data.values())
        return 2 if six else 1
    try:
        return int(str(v).split(".")[0])
    except ValueError:
        raise InputError(f"{label}: ross_version = {v!r}: not a version number") from None


def ross_rotor_text(path, name=None):
    """`(text, summary)`: the rotor file (TOML) of the ROSS rotor saved at `path` (see the
    module) and what it holds: `version` (ROSS's major version, from `ross_version` or
    the keys), `elements` `{table: count}`, `theory`, `speed` (rad/s or None), `notes`."""
    label, data = read_ross(path)
    version = _version(label, data)
    shafts, disks, bearings, masses, materials, theories, notes = [], [], [], [], {}, set(), []
    interpolations = set()
    for key, section in data.items():
        if key in ("parameters", "ross_version") or key.startswith("_") or not isinstance(section, dict):
            continue
        cls = key.split("_")[0]
        if cls in SHAFT_CLASSES:
            theory, entry = _shaft(label, key, section, materials)
            theories.add(theory)
            shafts.append((int(_number(key, "n", section.get("n"), label)), key, entry))
        elif cls in DISK_CLASSES:
            disks.append({"node": int(_number(key, "n", section.get("n"), label)),
                          **{k: _number(key, k, section.get(k), label) for k in ("m", "Id", "Ip")}})
        elif cls in MASS_CLASSES:
            m = section.get("m")
            mx, my = section.get("mx", m), section.get("my", m)
            if section.get("mz") not in (None, 0, 0.0) and section.get("mz") != m:
                _refuse(label, key, f"mz = {section.get('mz')}: an axial mass different from the lateral ones")
            masses.append({"node": int(_number(key, "n", section.get("n"), label)),
                           "mx": _number(key, "mx", mx, label), "my": _number(key, "my", my, label)})
        elif cls in BEARING_CLASSES or "Seal" in cls or "Bearing" in cls:
            unread = sorted(set(section) - TABLE_KEYS)
            entry, interp = _bearing(label, key, {k: v for k, v in section.items() if k in TABLE_KEYS}, version)
            if interp:
                interpolations.add(interp)
            if cls != "BearingElement" and unread:
                notes.append(f"[{key}]: read as its coefficients; its model parameters ({', '.join(unread[:4])}"
                             f"{', ...' if len(unread) > 4 else ''}) are not")
            bearings.append((key, entry, section.get("n_link")))
        else:
            _refuse(label, key, f"a {cls}: rotorjax's rotor files hold shaft elements, disks, point masses, "
                                "bearings and seals")
    if not shafts:
        raise InputError(f"{label}: no ShaftElement sections (a rotor needs its shaft)")
    shafts.sort(key=lambda s: s[0])
    nodes = [s[0] for s in shafts]
    for i in range(1, len(nodes)):
        if nodes[i] == nodes[i - 1]:
            _refuse(label, shafts[i][1], f"n = {nodes[i]} is also [{shafts[i - 1][1]}]'s: concentric shaft layers "
                                         "on one node pair")
    if nodes != list(range(nodes[0], nodes[0] + len(nodes))) or nodes[0] != 0:
        raise InputError(f"{label}: the shaft elements' n are {nodes}: expected 0, 1, 2, ... (one per element)")
    if len(theories) > 1:
        raise InputError(f"{label}: the shaft elements mix theories ({', '.join(sorted(theories))}: their "
                         "shear_effects and rotary_inertia differ); a rotor file has one theory")
    last = len(nodes)
    for row in disks:
        if not 0 <= row["node"] <= last:
            raise InputError(f"{label}: a DiskElement at n = {row['node']}: beyond the shaft's nodes (0..{last})")
    bearings, supports, masses = _supports(label, bearings, masses, last)
    if "smoothing" in interpolations:
        notes.append("ROSS 2.x evaluates a bearing table with a smoothing spline (scipy UnivariateSpline), rotorjax "
                     "with a not-a-knot cubic through the points: they agree at the table's speeds")
    elif interpolations:
        notes.append(f"ROSS interpolates the bearing tables by {' and '.join(sorted(interpolations))}, rotorjax with "
                     "a not-a-knot cubic through the points: they agree at the table's speeds")
    params = data.get("parameters") or {}
    params = params if isinstance(params, dict) else {}
    _rotor_damping(label, params)
    rated = params.get("rated_w")
    speed = None if rated is None else _number("parameters", "rated_w", rated, label)
    stem, theory = pathlib.Path(label).stem, theories.pop()
    lines = [f"# Imported from {pathlib.Path(label).name} (a rotor saved by ROSS {data.get('ross_version', version)})"
             " by `rotorjax import-ross`. SI units.", "", "[rotor]",
             f"name = {_s(name or stem)}", f"theory = {_s(theory)}"]
    if speed is not None:
        lines.append(f"speed = {_f(speed)}      # rad/s (ROSS's rated_w)")
    for (rho, E, G), mname in materials.items():
        lines += ["", "[[material]]", f"name = {_s(mname)}", f"E = {_f(E)}", f"G = {_f(G)}", f"rho = {_f(rho)}"]
    for n, key, entry in shafts:
        lines += ["", f"[[shaft]]            # {key.split('_', 1)[1]}: nodes {n}, {n + 1}"]
        lines += [f"{k} = {_toml_value(v)}" for k, v in entry.items()]
    for table, rows in (("disk", disks), ("point_mass", masses), ("bearing", [e for _, e in bearings]),
                        ("support", supports)):
        for row in rows:
            lines += ["", f"[[{table}]]"] + [f"{k} = {_toml_value(v)}" for k, v in row.items()]
    summary = {"version": version, "theory": theory,
               "elements": {"shaft": len(shafts), "material": len(materials), "disk": len(disks),
                            "point_mass": len(masses), "bearing": len(bearings), "support": len(supports)},
               "speed": speed, "notes": notes}
    return "\n".join(lines) + "\n", summary


def import_ross(path, out=None, name=None):
    """Write the rotor file of the ROSS rotor at `path` to `out` (default: beside it,
    `<stem>_rotorjax.toml`), read it back (`read_rotor_file`: the file checks as any
    rotor file does) and return the summary of `ross_rotor_text` with `out`."""
    from ._paths import read_rotor_file

    text, summary = ross_rotor_text(path, name)
    out = str(out) if out is not None else str(pathlib.Path(path).with_name(pathlib.Path(path).stem + "_rotorjax.toml"))
    try:
        pathlib.Path(out).write_text(text, encoding="utf-8")
    except OSError as e:
        raise InputError(f"--out {out}: cannot be written ({e.strerror})") from None
    read_rotor_file(out)
    return {**summary, "out": out}
