"""Building the scene of a checked rotor file (`load_rotor`)."""

import numpy as np

from .._errors import InputError
from ..models._fe_rotor import BEARING_COEFFICIENTS, Bearing, FlexibleRotor, Support
from ..models._journal_bearing import PlainJournal
from ..models._materials import MATERIALS, poisson_ratio
from ..models._registry import TABLES
from ..models._rotor_scene import RotorScene
from ..models._speed import ConstantSpeed
from ._check import validate
from ._read import Ctx, apply_overrides, read_toml
from ._schema import DOF_NAMES, FILM_TYPES


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


def _registered(spec, table):
    """`(index, entry)` of a registered table's entries (a film's: its `[[bearing]]` index)."""
    if table.part == "film":
        return [(i, b) for i, b in enumerate(spec["bearing"]) if b["type"] in FILM_TYPES]
    return list(enumerate(spec[table.name]))


def build_scene(ctx, spec, track_work, placed=None):
    """The scene of a checked file; `placed` (a dict), when given, receives each
    registered entry's place, `(table, index) -> ("components", j)` among the scene's
    components or `("bearing", row)` among the rotor's bearings."""
    r = spec["rotor"][0]
    E, G, rho, nu = _material_constants(spec)
    shafts = spec["shaft"]
    d_out, d_in = _diameters(shafts)
    placed = {} if placed is None else placed
    bearings = [_bearing_entry(b) for b in spec["bearing"] if b["type"] not in FILM_TYPES]
    try:
        for table in TABLES:
            for i, entry in _registered(spec, table) if table.part == "bearing" else ():
                placed[(table.name, i)] = ("bearing", len(bearings))
                bearings.append(table.from_table(entry))
        rotor = FlexibleRotor(
            np.array([s["L"] for s in shafts]), d_out, d_in, E=E, G=G, rho=rho, nu=nu, plausibility=False,
            disks=tuple((d["node"], d["m"], d["Id"], d["Ip"]) for d in spec["disk"]),
            bearings=tuple(bearings), **_extras(spec), theory=r["theory"],
            fixed_dofs=tuple((f["node"], DOF_NAMES.index(d)) for f in spec["fixed"] for d in f["dofs"]))
        if "n_modes" in r:
            rotor = rotor.reduce(r["n_modes"])
        parts = []
        for table in TABLES:
            for i, entry in _registered(spec, table) if table.part != "bearing" else ():
                placed[(table.name, i)] = ("components", len(parts))
                parts.append(table.from_table(entry))
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
    label, doc = read_toml(path)
    ctx = Ctx(label)
    doc = apply_overrides(ctx, doc, overrides)
    return build_scene(ctx, validate(ctx, doc), bool(track_work))
