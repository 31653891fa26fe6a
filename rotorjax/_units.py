"""Units at the edge: a value a user writes with a unit (`"1.5e7 N/m"`, `"3600rpm"`,
`"2 in"`, `"25 g*mm"`) converted to the SI unit rotorjax computes in, by pint. Inside,
everything stays SI floats (differentiable); only the text a user gives passes here.

- `to_si(text, unit, where)`: the value in `unit` (an SI unit as the rotor-file schema
  and the CLI write them: `"N/m"`, `"N s/m"`, `"kg m^2"`, `"rad/s"`, `"m"`, ...). A bare
  number is SI already. A unit of another dimension, an unknown unit, or text that is no
  quantity is an `InputError` naming `where` (the option, or the file, table, index and
  key) and both dimensions.
- Two readings differ from pint's own, on purpose: `Hz` counts cycles per second
  (1 Hz = 2 pi rad/s; pint reads 1 Hz as 1 rad/s, its radian being dimensionless), and
  `mil`/`mils` are thousandths of an inch (pint's `mil` is a plane angle).

pint is imported on first use (a bare number never needs it)."""

import math
import re

from ._errors import InputError

_REGISTRY = None


def _pint_unit(unit):
    """A unit as the rotor-file schema and the CLI write it (`"N s/m"`, `"kg m^2"`), as
    pint reads it."""
    return unit.replace("^", "**").replace(" ", "*")

#: units with no dimension to check
DIMENSIONLESS = ("", "dimensionless", "count", "index", "node", "-")


#: what a quantity in each SI unit is, for the messages
NAMES = {"m": "a length", "kg": "a mass", "N/m": "a stiffness", "N s/m": "a damping", "rad/s": "a speed",
         "Pa": "a pressure or modulus", "kg/m^3": "a density", "kg m^2": "an inertia", "kg m": "an unbalance",
         "Pa s": "a viscosity", "N": "a force", "s": "a time", "N m": "a moment", "m/s^2": "an acceleration"}


def _what(q, ureg):
    """`q`'s kind in words (`NAMES`), or its dimensionality."""
    for unit, name in NAMES.items():
        if q.dimensionality == ureg.parse_units(_pint_unit(unit)).dimensionality:
            return f"{name} ({unit})"
    return f"of dimension {q.dimensionality}"


def _registry():
    global _REGISTRY
    if _REGISTRY is None:
        import pint

        ureg = pint.UnitRegistry()
        ureg.define("rotational_hertz = revolution / second = rHz")
        _REGISTRY = ureg
    return _REGISTRY


def _pint_text(text):
    text = re.sub(r"(?<![A-Za-z_])([kMG]?)Hz\b", r"\1rHz", text)
    text = re.sub(r"(?<![A-Za-z_])mils?\b", "thou", text)
    return text.replace("µ", "u").replace("μ", "u")


def number(text):
    """`text` as a bare number (no unit), or None."""
    try:
        v = float(str(text).strip())
    except ValueError:
        return None
    return v


def to_si(text, unit, where, joiner=" = "):
    """The value of `text` (a number, or a string `"VALUE UNIT"`) in the SI unit `unit`;
    `InputError` naming `where` otherwise (see the module; `joiner` between `where` and
    the text in the message: `" = "` for a file's key, `" "` for an option)."""
    if isinstance(text, (int, float)) and not isinstance(text, bool):
        return float(text)
    bare = number(text)
    if bare is not None:
        return bare
    import pint

    ureg = _registry()
    target = _pint_unit(unit)
    if not re.match(r"\s*[-+]?(\d|\.\d)", str(text)):
        raise InputError(f"{where} must be a number, or a number and a unit (\"1.5e7 N/m\", \"3600 rpm\", "
                         f"\"2 in\"), got {text!r}")
    try:
        q = ureg.parse_expression(_pint_text(str(text).strip()))
    except (pint.errors.UndefinedUnitError, pint.errors.DefinitionSyntaxError, SyntaxError, TypeError,
            ValueError, AttributeError, KeyError) as e:
        names = e.unit_names if isinstance(e, pint.errors.UndefinedUnitError) else (str(e),)
        name = ", ".join(names) if isinstance(names, (tuple, list)) else str(names)
        raise InputError(f"{where}{joiner}{text!r}: not a quantity (unknown unit {name!r}); write a number in "
                         f"{unit or 'SI'}, or a number and a unit, e.g. \"1.5e7 N/m\", \"3600 rpm\", \"2 in\"") \
            from None
    if not isinstance(q, ureg.Quantity):
        return float(q)
    if unit in DIMENSIONLESS:
        if not q.dimensionless:
            raise InputError(f"{where}{joiner}{text!r}: {_what(q, ureg)}; this value has no unit")
        return float(q.to("dimensionless").magnitude)
    try:
        v = float(q.to(target).magnitude)
    except pint.errors.DimensionalityError:
        want = NAMES.get(unit, f"of dimension {ureg.parse_units(target).dimensionality}")
        raise InputError(f"{where}{joiner}{text!r}: {_what(q, ureg)}, and this value is {want}, in {unit}") from None
    if not math.isfinite(v):
        raise InputError(f"{where}{joiner}{text!r}: not finite")
    return v
