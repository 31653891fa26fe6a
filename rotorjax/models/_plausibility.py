"""Plausibility of physical inputs: values that are valid but unlikely, most often a
unit slip (`E = 205` meant in GPa, `od = 60` meant in mm).

An implausible value is a `rotorjax._errors.PlausibilityWarning` (issued with
`warnings.warn` outside `jit`, where the value is concrete; a traced value is never
inspected); the CLI prints each on stderr as `rotorjax: warning: ...` and adds it to
its JSON `warnings`. Impossible values are `InputError`s, raised by the checks of
the constructors and of the rotor-file loader, not here.

The plausible ranges (`RANGES`), chosen so that any metal, ceramic or engineering
polymer shaft and any machine from a dental drill to a turbine-generator passes,
while the usual slips fall outside:

| quantity                                   | plausible         | slips named (the first that fits) |
|--------------------------------------------|-------------------|-----------------------------------|
| Young's modulus `E`, shear modulus `G`     | 1e9..1e12 Pa      | GPa, MPa, psi                     |
| density `rho`                              | 500..25000 kg/m^3 | g/cm^3, lb/in^3, t/mm^3           |
| lengths, diameters, radii (`L`, `od`; a    | 0.5 mm..5 m       | mm, cm, in                        |
| journal's length and diameter; race, rim)  |                   |                                   |
| bores `id` (a taper may close to a point)  | up to 5 m         | mm, cm, in                        |
| element slenderness `L / od` (mean od of a | 0.05..50          | (a slip in `L` or `od`)           |
| taper; when `L` and `od` are plausible)    |                   |                                   |
| a disk's radii of gyration `sqrt(Ip / m)`, | 0.5 mm..5 m       | kg mm^2, kg cm^2                  |
| `sqrt(Id / m)` (nonzero inertias)          |                   |                                   |

A disk with `Ip > 2 Id` (beyond `IP_TOLERANCE`, 5 %) is impossible for a rigid body
(the perpendicular-axis theorem): an `InputError` in a rotor file, a warning from
`FlexibleRotor` (whose published validation cases, ROSS's among them, include such
disks).

A speed-tabulated bearing is extrapolated linearly outside its table
(`_interpolate.spline`); `check_speeds(scene, speeds)` warns when the speeds an
analysis uses leave a table.
"""

import dataclasses
import math
import os
import sys
import warnings

import numpy as np

from .._errors import PlausibilityWarning
from ._validate import is_concrete

__all__ = ["IP_TOLERANCE", "RANGES", "PlausibleRange", "PlausibilityWarning", "check_speeds", "disk_warnings",
           "gyration", "judge", "number", "shaft_warnings", "warn"]


@dataclasses.dataclass(frozen=True)
class PlausibleRange:
    """`lo..hi` (SI `unit`) of a `what`, with the units a slip most likely used:
    `slips` are `(unit, factor to SI)`, tried in order."""

    what: str
    unit: str
    lo: float
    hi: float
    text: str  # the range as a message states it
    slips: tuple = ()


_STRESS = (("GPa", 1e9), ("MPa", 1e6), ("psi", 6894.757293168361))
_LENGTH = (("mm", 1e-3), ("cm", 1e-2), ("in", 0.0254))

RANGES = {
    "E": PlausibleRange("Young's modulus", "Pa", 1e9, 1e12, "1e9..1e12 Pa", _STRESS),
    "G": PlausibleRange("shear modulus", "Pa", 1e9, 1e12, "1e9..1e12 Pa", _STRESS),
    "rho": PlausibleRange("density", "kg/m^3", 500.0, 25000.0, "500..25000 kg/m^3",
                          (("g/cm^3", 1e3), ("lb/in^3", 27679.904710203125), ("t/mm^3", 1e12))),
    "length": PlausibleRange("length", "m", 5e-4, 5.0, "0.5 mm..5 m", _LENGTH),
    "diameter": PlausibleRange("diameter", "m", 5e-4, 5.0, "0.5 mm..5 m", _LENGTH),
    # a bore may taper to nothing (a refined taper has tiny ones): only too large is a slip
    "bore": PlausibleRange("bore (inner diameter)", "m", 0.0, 5.0, "0..5 m", _LENGTH),
    "radius": PlausibleRange("radius", "m", 5e-4, 5.0, "0.5 mm..5 m", _LENGTH),
    "slenderness": PlausibleRange("element slenderness L / od", "", 0.05, 50.0, "0.05..50"),
    "gyration": PlausibleRange("radius of gyration", "m", 5e-4, 5.0, "0.5 mm..5 m",
                               (("kg mm^2", 1e-6), ("kg cm^2", 1e-4))),
}


#: how far a disk's `Ip` may exceed `2 Id` before it is impossible (rounded published
#: values of a thin disk, whose `Ip = 2 Id` exactly, may land a little above)
IP_TOLERANCE = 0.05


def number(x) -> str:
    """`x` for a message: 6 significant digits, exponents without `+` or zeros."""
    s = f"{float(x):.6g}"
    if "e" in s:
        mant, exp = s.split("e")
        s = f"{mant}e{int(exp)}"
    return s


def _inside(r, v):
    return r.lo <= v <= r.hi


def judge(quantity: str, value) -> str | None:
    """Why `value` (SI, a concrete number) is implausible as `quantity` (a key of
    `RANGES`), naming the likely slip, or `None` when it is plausible. Zero and
    negative values are left to the sign checks (`None`).

    **Returns:** e.g. `"outside the plausible 1e9..1e12 Pa for Young's modulus; did
    you mean GPa (205 GPa = 2.05e11 Pa)?"`.
    """
    r = RANGES[quantity]
    v = float(value)
    if not math.isfinite(v) or v <= 0 or _inside(r, v):
        return None
    head = f"outside the plausible {r.text} for a {r.what}"
    for unit, factor in r.slips:
        if _inside(r, v * factor):
            return f"{head}; did you mean {unit} ({number(v)} {unit} = {number(v * factor)} {r.unit})?"
    return f"{head}; check its units"


def gyration(inertia, mass) -> str | None:
    """Why a disk's inertia (kg m^2) is implausible for its mass (kg): its radius of
    gyration `sqrt(inertia / mass)` outside 0.5 mm..5 m, naming the likely unit of
    the inertia; `None` when plausible (or the inertia is 0)."""
    r = RANGES["gyration"]
    i, m = float(inertia), float(mass)
    if not (math.isfinite(i) and math.isfinite(m)) or i <= 0 or m <= 0:
        return None
    k = math.sqrt(i / m)
    if _inside(r, k):
        return None
    head = f"its radius of gyration sqrt(I / m) = {number(k)} m is outside the plausible {r.text}"
    for unit, factor in r.slips:
        if _inside(r, math.sqrt(i * factor / m)):
            return f"{head}; did you mean {unit} ({number(i)} {unit} = {number(i * factor)} kg m^2)?"
    return f"{head}; check the units of the inertia and the mass"


_MODELS = os.path.dirname(os.path.abspath(__file__))


def warn(text: str) -> None:
    """Issue `text` as a `PlausibilityWarning`, attributed to the first caller outside
    `rotorjax.models` and equinox (the line that built the rotor or loaded the file)."""
    frame, level = sys._getframe(0), 1
    while frame is not None and (frame.f_code.co_filename.startswith(_MODELS)
                                 or f"{os.sep}equinox{os.sep}" in frame.f_code.co_filename):
        frame, level = frame.f_back, level + 1
    warnings.warn(text, PlausibilityWarning, stacklevel=level)


def _values(value):
    """`value` as a flat float array, or `None` when it is traced."""
    if not is_concrete(value):
        return None
    return np.ravel(np.asarray(value, dtype=np.float64))


def _name(short, gloss, k, count, n):
    """`d_out (outer diameter)` for a value every element has, else `d_out[3] (outer
    diameter)` for element 3 (with `(and 2 more elements)` when others have it too)."""
    if count == n:
        return f"{short} ({gloss})"
    more = f" (and {count - 1} more element{'s' if count > 2 else ''})" if count > 1 else ""
    return f"{short}[{k}] ({gloss}){more}"


def _first_of_each(values):
    """`(first index, value, count)` for each distinct value, in order."""
    seen = {}
    for k, v in enumerate(values):
        if v in seen:
            seen[v][2] += 1
        else:
            seen[v] = [k, v, 1]
    return [tuple(s) for s in seen.values()]


def shaft_warnings(lengths, d_out, d_in, E, G, rho) -> list:
    """The plausibility texts of a `FlexibleRotor`'s shaft (`RANGES`), naming its
    arguments (`E (Young's modulus) = 205 Pa: ...`); traced values are skipped.
    `d_out`, `d_in`: `(n,)` or `(n, 2)` (tapered)."""
    out = []
    L = _values(lengths)
    do = None if not is_concrete(d_out) else np.asarray(d_out, dtype=np.float64)
    di = None if not is_concrete(d_in) else np.asarray(d_in, dtype=np.float64)
    for short, gloss, quantity, value in (("E", "Young's modulus", "E", E), ("G", "shear modulus", "G", G),
                                          ("rho", "density", "rho", rho)):
        v = _values(value)
        if v is None:
            continue
        for k, x, count in _first_of_each(v.tolist()):
            why = judge(quantity, x)
            if why:
                out.append(f"{_name(short, gloss, k, count, v.size)} = {number(x)} {RANGES[quantity].unit}: {why}")
    ok = {}
    for short, gloss, quantity, arr in (("lengths", "element length", "length", L),
                                        ("d_out", "outer diameter", "diameter", do),
                                        ("d_in", "inner diameter", "bore", di)):
        if arr is None:
            continue
        per = arr.reshape(arr.shape[0], -1) if arr.ndim else arr.reshape(1, 1)
        n = per.shape[0]
        bad = np.zeros(n, dtype=bool)
        for k, x, count in _first_of_each([float(x) for x in per.ravel()]):
            why = None if (short == "d_in" and x == 0) else judge(quantity, x)
            if why:
                has = np.any(per == x, axis=1)
                out.append(f"{_name(short, gloss, k // per.shape[1], int(has.sum()), n)} = {number(x)} m: {why}")
                bad |= has
        ok[short] = ~bad
    if L is not None and do is not None:
        mean_od = do.reshape(do.shape[0], -1).mean(axis=1) if do.ndim else np.full(L.shape, float(do))
        mean_od = np.broadcast_to(mean_od, L.shape)
        good = np.broadcast_to(ok["lengths"], L.shape) & np.broadcast_to(ok["d_out"], L.shape)
        for k in range(L.shape[0]):
            why = judge("slenderness", L[k] / mean_od[k]) if good[k] else None
            if why:
                out.append(f"element {k}: L / od = {number(L[k] / mean_od[k])} (L = {number(L[k])} m, "
                           f"od = {number(mean_od[k])} m) is outside the plausible {RANGES['slenderness'].text}: "
                           f"a unit slip in the length or the diameter?")
                break  # one is enough: the others follow from the same slip
    return out


def disk_warnings(name, mass, it, ip) -> list:
    """The plausibility texts of one disk (`name`: how the caller names it, e.g.
    `disks[0]`): `Ip > 2 It` (no rigid body has it; an error in a rotor file) and
    radii of gyration outside 0.5 mm..5 m."""
    if not is_concrete((mass, it, ip)):
        return []
    m, it, ip = float(mass), float(it), float(ip)
    out = []
    if ip > 2 * it * (1 + IP_TOLERANCE):
        out.append(f"{name}: Ip = {number(ip)} > 2 It = {number(2 * it)} kg m^2: no rigid body has a polar "
                   f"inertia above twice its diametral one (the perpendicular-axis theorem); are It and Ip "
                   f"swapped, or in different units?")
    for key, value in (("It", it), ("Ip", ip)):
        why = gyration(value, m)
        if why:
            out.append(f"{name}: {key} = {number(value)} kg m^2 with mass = {number(m)} kg: {why}")
    return out
