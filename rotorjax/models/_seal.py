"""A linear seal: an annular (labyrinth, damper, hole-pattern) seal's rotordynamic
coefficients at a shaft node, as ROSS's `SealElement`.

A seal acts on the rotor as a bearing does, `-(K q + C q' + M q'')` on the node's
`(x, y)`, with stiffness, damping and mass coefficients, direct and cross-coupled,
tabulated against the running speed (a seal's cross-coupled stiffness, from the
swirl of its leakage, grows with speed: the destabilising term of a compressor's
seals). It is a `Bearing` of kind "seal": the rotor holds its coefficients with the
bearings' (every analysis of the rotor sees it), and a rotor file reads and writes it
as a `[[seal]]` entry (`TABLE`).
"""

import numpy as np

from ._fe_rotor import BEARING_COEFFICIENTS, Bearing, check_speed_table, complete_coefficients
from ._table import ComponentTable, Key, node_key, one_or_each


class Seal(Bearing):
    """A linear seal at `node`: `Seal(node, speeds=[...], kxx=[...], kxy=[...], cxx=...)`,
    the arguments of a `Bearing` (coefficients by keyword, each one value or one per
    speed; `kyy`, `cyy`, `myy` default to `kxx`, `cxx`, `mxx`; N/m, N s/m, kg; speeds
    rad/s). ROSS: `SealElement(n, kxx=..., cxx=..., frequency=speeds)`."""

    kind = "seal"
    nonnegative = ("cxx", "cyy")   # a labyrinth seal's direct stiffness is negative


def _complete(entries, where):
    """Coefficients left out take their defaults (0, or the one they follow); lists need
    `speeds` and one value per speed."""
    for i, s in enumerate(entries):
        complete_coefficients(s)
        check_speed_table(s, where, i)


def _part(s):
    speeds = None if "speeds" not in s else np.array(s["speeds"], dtype=np.float64)
    return Seal(s["node"], speeds=speeds, **{k: (np.array(s[k], dtype=np.float64) if isinstance(s[k], list)
                                                 else s[k]) for k in BEARING_COEFFICIENTS})


def _entry(seal):
    out = {"node": seal.node}
    if seal.speeds is not None:
        out["speeds"] = [float(w) for w in np.asarray(seal.speeds)]
    for k in BEARING_COEFFICIENTS:
        value = one_or_each(getattr(seal, k))
        if k in ("kxx", "kyy", "cxx", "cyy") or np.any(np.asarray(value) != 0):
            out[k] = value
    return out


def _coefficient(k):
    direct = k[1] == k[2]
    what = {"k": ("stiffness", "N/m"), "c": ("damping", "N s/m"), "m": ("mass coefficient", "kg")}[k[0]]
    meaning = f"{'' if direct else 'cross '}{what[0]} {k[1:]} (one value, or one per speed)"
    # a seal's direct stiffness may be negative (a labyrinth's); its direct damping and mass may not
    return Key("number_or_numbers", what[1], meaning, "nonnegative" if direct and k[0] in "cm" else "any",
               required=k == "kxx")


#: its rotor-file table, `[[seal]]`
TABLE = ComponentTable(True, {
    "node": node_key("seal"),
    "speeds": Key("numbers", "rad/s", "speeds of the coefficient table", "nonnegative"),
    **{k: _coefficient(k) for k in BEARING_COEFFICIENTS},
}, "a linear seal (stiffness, damping and mass coefficients, direct and cross-coupled, tabulated against speed)",
    name="seal", builds=Seal, from_table=_part, to_table=_entry, complete=_complete, part="bearing")
