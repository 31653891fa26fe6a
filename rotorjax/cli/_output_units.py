"""`--units`: the unit system a command presents its numbers in (printed tables, its
JSON, its plot axes). The analyses compute in SI; only what a command shows is
converted, here, once.

- `si`: speeds and frequencies in rad/s, amplitudes and deflections in m (amplitudes
  zero-to-peak, the size of the response's phasor).
- `rpm-um`: speeds in rev/min (rpm), frequencies in cycles/min (cpm), vibration
  amplitudes in micrometres peak-to-peak (the convention of vibration measurement,
  API 684's), static deflections in micrometres.
- `rpm-mil`: as `rpm-um` with mils (thousandths of an inch) for micrometres.

A command names the kind of each number it outputs (`convert`'s `fields`: a dotted
path into its JSON, `*` for every item of a list) and its JSON says the units it is
in (`"units"`)."""

import math
from typing import NamedTuple

from .._errors import InputError

_RPM = 30.0 / math.pi      # rev/min per rad/s
_MIL = 1e3 / 0.0254        # mils per metre

#: per system, each kind of number: (its label, the factor from SI)
SYSTEMS = {
    "si": {"speed": ("rad/s", 1.0), "frequency": ("rad/s", 1.0), "amplitude": ("m", 1.0),
           "deflection": ("m", 1.0)},
    "rpm-um": {"speed": ("rpm", _RPM), "frequency": ("cpm", _RPM), "amplitude": ("um pk-pk", 2e6),
               "deflection": ("um", 1e6)},
    "rpm-mil": {"speed": ("rpm", _RPM), "frequency": ("cpm", _RPM), "amplitude": ("mil pk-pk", 2 * _MIL),
                "deflection": ("mil", _MIL)},
}

UNITS_OPTION = (("--units",), dict(choices=tuple(SYSTEMS), default="si",
                                   help="units of the printed numbers, the JSON and the plot axes: si (rad/s, m), "
                                        "rpm-um (rpm, cpm, micrometres; amplitudes peak-to-peak) or rpm-mil (rpm, "
                                        "cpm, mils; amplitudes peak-to-peak)"))


def _scaled(value, factor):
    if value is None or isinstance(value, (str, bool)):
        return value
    if isinstance(value, (list, tuple)):
        return [_scaled(v, factor) for v in value]
    return float(value) * factor


def _apply(node, keys, factor):
    if not keys or node is None:
        return _scaled(node, factor)
    key, rest = keys[0], keys[1:]
    if key == "*":
        return [_apply(item, rest, factor) for item in node]
    if isinstance(node, dict) and key in node:
        node[key] = _apply(node[key], rest, factor)
    return node


class Units(NamedTuple):
    """A `--units` system: `label(kind)`, `value(x, kind)`, `convert(out, fields)`."""

    system: str = "si"

    def label(self, kind):
        return SYSTEMS[self.system][kind][0]

    def factor(self, kind):
        return SYSTEMS[self.system][kind][1]

    def value(self, x, kind):
        """`x` (SI; a number, a list, an array) in this system's unit of `kind`."""
        import numpy as np

        if isinstance(x, (list, tuple)):
            return _scaled(x, self.factor(kind))
        if np.ndim(x) == 0:
            return float(x) * self.factor(kind)
        return np.asarray(x) * self.factor(kind)

    def stated(self, kinds):
        """What the JSON says of its units: the system and each kind's unit."""
        return {"system": self.system, **{k: self.label(k) for k in kinds}}

    def convert(self, out, fields):
        """`out` (a command's JSON, SI) with each of `fields` (`{"a.*.b": kind}`)
        converted in place, and `out["units"]` stating the units; returns `out`."""
        for path, kind in fields.items():
            _apply(out, path.split("."), self.factor(kind))
        out["units"] = self.stated(dict.fromkeys(fields.values()))
        return out


def units_for(args, preset):
    """The `Units` of `args.units` for `preset`: a system other than si needs speeds
    with a unit (a preset in dimensionless speeds is refused, naming `--units`)."""
    system = args.units
    if system != "si" and preset.units.get(preset.speed_key) == "dimensionless":
        raise InputError(f"--units {system}: {preset.name}'s {preset.speed_key} is dimensionless (so are its "
                         "other speeds and amplitudes); use --units si")
    return Units(system)
