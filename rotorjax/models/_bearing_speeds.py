"""A speed-tabulated bearing used outside its table: the plausibility check of the
speeds an analysis uses (apart from `_plausibility`, which the rotor imports, because
it reads rotors and scenes)."""

import numpy as np

from ._contract import AbstractShaftModel
from ._plausibility import number, warn
from ._validate import is_concrete


def _flexible_rotor(scene_or_rotor):
    """The `FlexibleRotor` inside a scene or a reduced rotor, or `None`."""
    return scene_or_rotor.full_rotor if isinstance(scene_or_rotor, AbstractShaftModel) else None


def check_speeds(scene_or_rotor, speeds) -> list:
    """Warn (`PlausibilityWarning`) for every speed-tabulated bearing whose table the
    `speeds` leave: outside its table a bearing's coefficients are extrapolated
    linearly from the table's end slopes (`_interpolate.spline`).

    **Arguments:**
    - `scene_or_rotor`: a `RotorScene`, a `FlexibleRotor` or a `ReducedRotor`; any
      other scene has no bearing tables (nothing to check).
    - `speeds`: the speeds (rad/s) an analysis uses: a number or an array (only its
      minimum and maximum matter). Traced speeds or tables are not checked.

    **Returns:** the warnings' texts, one per bearing, e.g. `"bearing 1 (node 7):
    speeds up to 3000 rad/s are outside its table (10..1500 rad/s): its coefficients
    are extrapolated"`; `[]` when every speed is inside every table.
    """
    rotor = _flexible_rotor(scene_or_rotor)
    if rotor is None or not is_concrete(speeds):
        return []
    s = np.ravel(np.asarray(speeds, dtype=np.float64))
    s = s[np.isfinite(s)]
    if s.size == 0:
        return []
    lo, hi = float(s.min()), float(s.max())
    out = []
    for i, table in enumerate(rotor.bearing_tables):
        if table is None or not is_concrete(table[0]):
            continue
        t = np.asarray(table[0], dtype=np.float64)
        t_lo, t_hi = float(t[0]), float(t[-1])
        slack = 1e-9 * max(abs(t_lo), abs(t_hi), 1.0)
        below, above = lo < t_lo - slack, hi > t_hi + slack
        if not (below or above):
            continue
        if below and above:
            used = f"speeds {number(lo)}..{number(hi)} rad/s leave"
        elif above:
            used = f"speeds up to {number(hi)} rad/s are outside"
        else:
            used = f"speeds down to {number(lo)} rad/s are outside"
        text = (f"bearing {i} (node {rotor.bearing_nodes[i]}): {used} its table ({number(t_lo)}..{number(t_hi)} "
                f"rad/s): its coefficients are extrapolated")
        warn(text)
        out.append(text)
    return out
