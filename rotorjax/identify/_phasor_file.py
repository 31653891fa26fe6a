"""Measured 1x phasors of an FE rotor: the phasor file (CSV), and its making from raw signals.

One row per phasor. Columns (a header row; `#` comment lines allowed):

- required: `speed` (rad/s, the running speed), `node` (integer >= 0, the FE node
  of the sensor), `direction` (`x` or `y`, either case), `real`, `imag` (m): the
  response `x(t) = Re(X e^{i speed t})`, the convention of `unbalance_response`
  (an unbalance `U` at phase `phi` pushes with `U speed^2 (cos(speed t + phi),
  sin(speed t + phi))`);
- optional: `run` (integer, default 0); `trial_node`, `trial_magnitude` (kg m,
  > 0), `trial_phase` (rad): the trial weight added for the row's run, the three
  cells empty in rows of runs without one (the three columns come together; every
  row of a run has the same trial weight, or none); `sigma` (m, > 0): the
  phasor's noise (standard deviation of its real and of its imaginary part);
- FRF files (impact tests): `frequency` (rad/s, > 0, the excitation frequency),
  `input_node`, `input_direction` (x/y): `real`, `imag` are then `H` (m/N), the
  response at (`node`, `direction`) per unit force at (`input_node`,
  `input_direction`); `speed` is the running speed (0: at rest); no trial columns.

`read_phasors` checks every cell before anything is computed from the file: an
`InputError` names the file as given, the column and the data row with its line
(`FILE: column 'node', data row 4 (line 6): ...`). Duplicated measurements (same
run, speed, node, direction [, frequency, input_node, input_direction]) and
unknown columns (a typo) are errors. `make_phasors` builds the same thing in
Python with the same checks; `write_phasors` writes it back exactly (shortest
round-tripping decimals).

`phasors_from_signals` makes one from a raw measurement file (`read_signals`:
time, tacho, x1, x2, ..., run, trial_plane, trial_unbalance, trial_angle) and a
channel map (`x1=2:x,x2=2:y`: sensor column = FE node : direction): one phasor
per sensor of a steady run (`phasors`), one per block of revolutions of a run-up
(`order_track`).
"""

import dataclasses
import os
import re

import numpy as np

from .._errors import InputError
from ._datasets import resolve_data
from ._signals import (_read_table, _run_index, order_track, phasors, pulse_times, read_signals,
                       rotor_angle)

REQUIRED = ("speed", "node", "direction", "real", "imag")
TRIAL = ("trial_node", "trial_magnitude", "trial_phase")
FRF = ("frequency", "input_node", "input_direction")
OPTIONAL = ("run", "sigma") + TRIAL + FRF
KNOWN = REQUIRED + OPTIONAL
_EXAMPLE = "speed,node,direction,real,imag"
_DIRECTIONS = ("x", "y")

#: a run is steady (one phasor per sensor) when its speed varies by less than this fraction
STEADY_TOLERANCE = 0.01


@dataclasses.dataclass(frozen=True, eq=False)
class PhasorData:
    """Measured 1x phasors, one entry per row of a phasor file (see the module docstring).

    - `path`: the file as given (or the label of a Python-built set);
    - `speed` (rad/s), `node` (int), `direction` (int, 0 = x, 1 = y), `X` (complex,
      m, or m/N for FRFs), `run` (int): `(n,)` each;
    - `trial_node` (int, -1 = no trial weight), `trial_magnitude` (kg m, NaN where
      none), `trial_phase` (rad, NaN where none);
    - `sigma` (m) or None; `frequency` (rad/s), `input_node`, `input_direction`:
      FRF files only, else None;
    - `lines`: the CSV line of each row (None: built in Python).
    """

    path: str
    speed: np.ndarray
    node: np.ndarray
    direction: np.ndarray
    X: np.ndarray
    run: np.ndarray
    trial_node: np.ndarray
    trial_magnitude: np.ndarray
    trial_phase: np.ndarray
    sigma: np.ndarray | None
    frequency: np.ndarray | None
    input_node: np.ndarray | None
    input_direction: np.ndarray | None
    lines: tuple | None = None

    @property
    def kind(self) -> str:
        """`"frf"` (an impact test: `frequency`, `input_node`, `input_direction`) or `"unbalance"`."""
        return "frf" if self.frequency is not None else "unbalance"

    @property
    def n(self) -> int:
        """The number of phasors (rows)."""
        return int(self.speed.size)

    def row(self, i) -> str:
        """Where entry `i` (0-based) came from, in the user's terms: `data row K (line L)`."""
        return _row_text(self.lines, int(i))

    def runs(self) -> list:
        """The run labels, sorted."""
        return [int(r) for r in np.unique(self.run)]

    def trial(self, run):
        """The trial weight of `run`: `(node, magnitude kg m, phase rad)`, or None."""
        rows = np.flatnonzero(self.run == run)
        if rows.size == 0:
            raise InputError(f"{self.path}: no run {run!r} (runs: {', '.join(map(str, self.runs()))})")
        i = rows[0]
        if self.trial_node[i] < 0:
            return None
        return int(self.trial_node[i]), float(self.trial_magnitude[i]), float(self.trial_phase[i])

    def select(self, mask) -> "PhasorData":
        """The entries where `mask` (booleans, or indices) holds, with their lines."""
        idx = np.arange(self.n)[np.asarray(mask)]
        changes = {f.name: getattr(self, f.name)[idx] for f in dataclasses.fields(self)
                   if isinstance(getattr(self, f.name), np.ndarray)}
        lines = None if self.lines is None else tuple(self.lines[i] for i in idx)
        return dataclasses.replace(self, lines=lines, **changes)


def _row_text(lines, i):
    return f"entry {i} (0-based)" if lines is None else f"data row {i + 1} (line {lines[i]})"


def _num(v):
    return f"{float(v):.10g}"


# --- reading -------------------------------------------------------------------

def _check_names(names, label):
    unknown = [n for n in names if n not in KNOWN]
    if unknown:
        lower = [n for n in unknown if n.lower() in KNOWN]
        hint = "; column names are lower case" if lower else ""
        raise InputError(f"{label}: unknown column(s) {', '.join(map(repr, unknown))}: a phasor file has the "
                         f"columns {', '.join(REQUIRED)} (required), {', '.join(OPTIONAL)} (optional){hint}")
    missing = [n for n in REQUIRED if n not in names]
    if missing:
        raise InputError(f"{label}: missing column(s) {', '.join(missing)}; found {', '.join(names)} (a phasor "
                         f"file needs {', '.join(REQUIRED)})")
    for group, what in ((TRIAL, "trial-weight"), (FRF, "FRF (impact test)")):
        found = [n for n in group if n in names]
        if found and len(found) < len(group):
            raise InputError(f"{label}: incomplete {what} columns: found {', '.join(found)} but not "
                             f"{', '.join(n for n in group if n not in names)}: give all of {', '.join(group)} "
                             "or none")
    if FRF[0] in names and TRIAL[0] in names:
        raise InputError(f"{label}: an FRF file (columns {', '.join(FRF)}) with trial-weight columns "
                         f"({', '.join(TRIAL)}): trial weights belong in a file of unbalance responses")


def _number_cell(cell):
    """`(value, None)` or `(None, what is wrong)` for one cell."""
    s = cell.strip()
    if not s:
        return None, "an empty cell"
    try:
        v = float(s)
    except ValueError:
        return None, f"{s[:40]!r} is not a number (decimal point, no units)"
    if not np.isfinite(v):
        return None, f"{s!r} is not a finite number"
    return v, None


def _direction_cell(cell):
    s = cell.strip()
    if not s:
        return None, "an empty cell; expected x or y"
    if s.lower() in _DIRECTIONS:
        return _DIRECTIONS.index(s.lower()), None
    return None, f"{s[:40]!r} is not a direction: expected x or y"


def _parse_cells(names, rows, lines, label):
    """`{column: array}` of the table (directions as 0/1, empty trial cells NaN), or an
    InputError at the first bad cell (row by row)."""
    col = {n: j for j, n in enumerate(names)}
    values = {n: np.empty(len(rows)) for n in names}
    has_trial = TRIAL[0] in col
    for i, row in enumerate(rows):
        if has_trial:
            empty = [not row[col[n]].strip() for n in TRIAL]
            if any(empty) and not all(empty):
                n = TRIAL[empty.index(True)]
                given = ", ".join(m for m, e in zip(TRIAL, empty) if not e)
                raise InputError(f"{label}: column {n!r}, {_row_text(lines, i)}: an empty cell while {given} "
                                 f"{'is' if ', ' not in given else 'are'} given: a trial weight needs all of "
                                 f"{', '.join(TRIAL)} (node, kg m, rad); leave all three empty for none")
        for j, n in enumerate(names):
            cell = row[j]
            if n in TRIAL and not cell.strip():
                values[n][i] = np.nan
                continue
            v, bad = (_direction_cell if n in ("direction", "input_direction") else _number_cell)(cell)
            if bad is not None:
                needed = "" if n in TRIAL or "direction" in n else f"; every row needs a {n}"
                raise InputError(f"{label}: column {n!r}, {_row_text(lines, i)}: {bad}{needed}")
            values[n][i] = v
    return values


def read_phasors(path) -> PhasorData:
    """Read a phasor file (CSV; columns in the module docstring) and check it.

    **Arguments:**
    - `path`: the file (`str` or `os.PathLike`), or a shipped dataset's name (see
      `resolve_data`).

    **Returns:** a `PhasorData`.

    **Raises:** `InputError` (a `ValueError`) for a file that is missing, not CSV
    text or malformed: the message names the file as given, the column and the
    data row (with its line) where they apply, and what would be valid."""
    label = os.fsdecode(os.fspath(path)) if isinstance(path, (str, bytes, os.PathLike)) else str(path)
    file = resolve_data(path)
    ext = os.path.splitext(file)[1].lower()
    if ext != ".csv":
        raise InputError(f"{label}: unsupported file type {ext or '(no extension)'!r}: a phasor file is a CSV "
                         f"file (.csv) with a header row such as {_EXAMPLE}")
    names, rows, lines = _read_table(file, label, example=_EXAMPLE, row="phasor")
    _check_names(names, label)
    v = _parse_cells(names, rows, lines, label)
    n = len(rows)
    fields = dict(speed=v["speed"], node=v["node"], direction=v["direction"].astype(int),
                  X=v["real"] + 1j * v["imag"], run=v.get("run", np.zeros(n)),
                  trial_node=v.get("trial_node", np.full(n, np.nan)),
                  trial_magnitude=v.get("trial_magnitude", np.full(n, np.nan)),
                  trial_phase=v.get("trial_phase", np.full(n, np.nan)), sigma=v.get("sigma"),
                  frequency=v.get("frequency"), input_node=v.get("input_node"),
                  input_direction=None if "input_direction" not in v else v["input_direction"].astype(int))
    return _finish(fields, label, tuple(lines))


# --- the checks every phasor set passes ------------------------------------------

def _finish(f, label, lines):
    """Check the fields (floats; directions 0/1; trial NaN where none) and make the `PhasorData`."""
    def at(name, i):
        if lines is not None:
            return f"{label}: column {name!r}, {_row_text(lines, i)}"
        arg = {"real": "X", "imag": "X"}.get(name, name)
        return f"{label}: {arg}[{i}]"

    def first(bad):
        return int(np.argmax(bad))

    frf = f["frequency"] is not None
    columns = [("speed", f["speed"]), ("node", f["node"]), ("real", f["X"].real), ("imag", f["X"].imag),
               ("run", f["run"])]
    columns += [(n, f[n]) for n in ("sigma", "frequency", "input_node") if f[n] is not None]
    for name, a in columns:
        bad = ~np.isfinite(a)
        if bad.any():
            i = first(bad)
            raise InputError(f"{at(name, i)}: {a[i]} is not a finite number")
    for name, a, positive in (("speed", f["speed"], not frf), ("sigma", f["sigma"], True),
                              ("frequency", f["frequency"], True)):
        if a is None:
            continue
        bad = ~(a > 0) if positive else ~(a >= 0)
        if bad.any():
            i = first(bad)
            why = {"speed": ("an unbalance response needs the rotor turning: speed > 0 (rad/s)" if positive else
                             "the running speed must be >= 0 (rad/s; 0 at rest)"),
                   "sigma": "a noise standard deviation must be > 0 (m)",
                   "frequency": "an excitation frequency must be > 0 (rad/s)"}[name]
            raise InputError(f"{at(name, i)}: {_num(a[i])}: {why}")
    for name, a, what in (("node", f["node"], "an FE node number: an integer >= 0"),
                          ("input_node", f["input_node"], "an FE node number: an integer >= 0"),
                          ("run", f["run"], "a run label: an integer")):
        if a is None:
            continue
        bad = a != np.round(a)
        if name != "run":
            bad |= a < 0
        if bad.any():
            i = first(bad)
            raise InputError(f"{at(name, i)}: {_num(a[i])} is not {what}")
    tn, tm, tp = f["trial_node"], f["trial_magnitude"], f["trial_phase"]
    has = np.isfinite(tn)
    bad = has & ((tn != np.round(tn)) | (tn < 0))
    if bad.any():
        i = first(bad)
        raise InputError(f"{at('trial_node', i)}: {_num(tn[i])} is not an FE node number: an integer >= 0")
    bad = has & ~(tm > 0)
    if bad.any():
        i = first(bad)
        raise InputError(f"{at('trial_magnitude', i)}: {_num(tm[i])}: a trial weight's unbalance must be > 0 "
                         "(kg m; its direction is trial_phase)")
    bad = has & ~np.isfinite(tp)
    if bad.any():
        i = first(bad)
        raise InputError(f"{at('trial_phase', i)}: {tp[i]} is not a finite angle (rad)")
    if frf and has.any():
        i = first(has)
        raise InputError(f"{at('trial_node', i)}: a trial weight in an FRF (impact test): trial weights belong "
                         "to unbalance responses")
    _check_trials_per_run(f, at, lines)
    _check_duplicates(f, label, lines, frf)
    tni = np.where(has, tn, -1).astype(int)
    return PhasorData(
        path=label, speed=f["speed"].astype(float), node=f["node"].astype(int),
        direction=np.asarray(f["direction"]).astype(int), X=f["X"].astype(complex), run=f["run"].astype(int),
        trial_node=tni, trial_magnitude=np.where(has, tm, np.nan), trial_phase=np.where(has, tp, np.nan),
        sigma=None if f["sigma"] is None else f["sigma"].astype(float),
        frequency=None if not frf else f["frequency"].astype(float),
        input_node=None if not frf else f["input_node"].astype(int),
        input_direction=None if not frf else np.asarray(f["input_direction"]).astype(int), lines=lines)


def _trial_text(node, mag, phase):
    return "none" if not np.isfinite(node) else f"node {int(node)}, {_num(mag)} kg m, {_num(phase)} rad"


def _check_trials_per_run(f, at, lines):
    run, trial = f["run"], (f["trial_node"], f["trial_magnitude"], f["trial_phase"])
    first_of = {}
    for i in range(run.size):
        r = run[i]
        if r not in first_of:
            first_of[r] = i
            continue
        j = first_of[r]
        differ = [n for n, a in zip(TRIAL, trial) if not (a[i] == a[j] or (np.isnan(a[i]) and np.isnan(a[j])))]
        if differ:
            raise InputError(f"{at(differ[0], i)}: run {int(r)}'s trial weight is {_trial_text(*(a[i] for a in trial))}"
                             f" here but {_trial_text(*(a[j] for a in trial))} in {_row_text(lines, j)}: every row "
                             "of a run has the same trial weight, or none (different weights are different runs)")


def _check_duplicates(f, label, lines, frf):
    keys = [f["run"], f["speed"], f["node"], f["direction"]]
    if frf:
        keys += [f["frequency"], f["input_node"], f["input_direction"]]
    seen = {}
    for i, key in enumerate(zip(*(np.asarray(k).tolist() for k in keys))):
        if key in seen:
            j = seen[key]
            desc = (f"run {int(key[0])}, speed {_num(key[1])} rad/s, node {int(key[2])}, direction "
                    f"{_DIRECTIONS[int(key[3])]}")
            if frf:
                desc += f", frequency {_num(key[4])} rad/s, input node {int(key[5])} {_DIRECTIONS[int(key[6])]}"
            raise InputError(f"{label}: {_row_text(lines, i)} repeats {_row_text(lines, j)} ({desc}): one phasor "
                             "per measurement (a row pasted twice? a missing run label?)")
        seen[key] = i


# --- building and writing --------------------------------------------------------

def _directions_arg(name, value, label):
    a = np.asarray(value)
    out = np.empty(a.shape, dtype=int)
    for i, v in enumerate(a.reshape(-1)):
        v = v.item() if isinstance(v, np.generic) else v
        if isinstance(v, str) and v.strip().lower() in _DIRECTIONS:
            out.reshape(-1)[i] = _DIRECTIONS.index(v.strip().lower())
        elif not isinstance(v, (str, bool)) and v in (0, 1):
            out.reshape(-1)[i] = int(v)
        else:
            raise InputError(f"{label}: {name}[{i}]: {v!r} is not a direction: expected 'x' or 'y' (or 0, 1)")
    return out


def make_phasors(speed, node, direction, X, run=None, trial=None, sigma=None, frequency=None, input_node=None,
                 input_direction=None, *, path="make_phasors") -> PhasorData:
    """A `PhasorData` from Python values, with the checks of `read_phasors`.

    **Arguments** (one value per phasor; scalars are repeated):
    - `speed` (rad/s), `node` (int), `direction` (`"x"`/`"y"` or 0/1), `X` (complex);
    - `run` (int labels, default 0);
    - `trial`: `{run: (node, magnitude kg m, phase rad)}` for the runs with a trial weight;
    - `sigma` (m, > 0) or None;
    - `frequency` (rad/s), `input_node`, `input_direction`: an FRF set (all three or none);
    - `path`: the label the messages (and `PhasorData.path`) use.

    **Raises:** `InputError` naming the argument and the entry (0-based)."""
    frf_args = {"frequency": frequency, "input_node": input_node, "input_direction": input_direction}
    given = [k for k, v in frf_args.items() if v is not None]
    if given and len(given) < 3:
        raise InputError(f"{path}: {', '.join(given)} given without "
                         f"{', '.join(k for k in frf_args if k not in given)}: an FRF set needs all three")
    if given and trial:
        raise InputError(f"{path}: an FRF set (frequency, input_node, input_direction) with trial weights: trial "
                         "weights belong to unbalance responses")
    raw = {"speed": speed, "node": node, "direction": direction, "X": X,
           "run": 0 if run is None else run, **({} if sigma is None else {"sigma": sigma}),
           **({k: v for k, v in frf_args.items()} if given else {})}
    arrays = {k: np.asarray(v) for k, v in raw.items()}
    try:
        shape = np.broadcast_shapes(*(a.shape for a in arrays.values()))
    except ValueError:
        shapes = ", ".join(f"{k} {a.shape}" for k, a in arrays.items())
        raise InputError(f"{path}: arguments of different lengths ({shapes}): one value per phasor") from None
    if len(shape) > 1:
        raise InputError(f"{path}: arguments of shape {shape}: expected one value per phasor (1-D)")
    n = int(np.prod(shape))
    arrays = {k: np.broadcast_to(a, shape).reshape(n) for k, a in arrays.items()}
    for k, a in arrays.items():
        kinds = "biufc" if k == "X" else ("biuf" if "direction" not in k else "biuU")
        if a.dtype.kind not in kinds:
            raise InputError(f"{path}: {k} has dtype {a.dtype}: expected "
                             f"{'x/y' if 'direction' in k else 'numbers'}")
    f = {k: arrays[k].astype(float) for k in ("speed", "node", "run")}
    f["direction"] = _directions_arg("direction", arrays["direction"], path)
    f["X"] = arrays["X"].astype(complex)
    f["sigma"] = arrays["sigma"].astype(float) if "sigma" in arrays else None
    for k in frf_args:
        f[k] = None
    if given:
        f["frequency"], f["input_node"] = arrays["frequency"].astype(float), arrays["input_node"].astype(float)
        f["input_direction"] = _directions_arg("input_direction", arrays["input_direction"], path)
    for k in TRIAL:
        f[k] = np.full(n, np.nan)
    labels = set(np.asarray(f["run"]).tolist())
    for r, w in (trial or {}).items():
        if r not in labels:
            raise InputError(f"{path}: trial weight for run {r!r}, but no phasor has that run (runs: "
                             f"{', '.join(_num(v) for v in sorted(labels))})")
        if w is None:
            continue
        try:
            tn, tm, tp = (float(v) for v in w)
        except (TypeError, ValueError):
            raise InputError(f"{path}: trial[{r!r}] = {w!r}: expected (node, magnitude kg m, phase rad)") from None
        if not (tn == round(tn) and tn >= 0 and np.isfinite(tm) and tm > 0 and np.isfinite(tp)):
            raise InputError(f"{path}: trial[{r!r}] = {w!r}: expected an FE node (integer >= 0), a magnitude > 0 "
                             "(kg m) and a finite phase (rad)")
        rows = f["run"] == r
        f["trial_node"][rows], f["trial_magnitude"][rows], f["trial_phase"][rows] = tn, tm, tp
    return _finish(f, path, None)


def _float_text(v):
    return repr(float(v))


def write_phasors(path, data) -> str:
    """Write `data` (a `PhasorData`) as a phasor file; `read_phasors` gives it back exactly.

    **Returns:** the path written (`str`). **Raises:** `InputError` naming the path
    when it cannot be written."""
    if not isinstance(data, PhasorData):
        raise InputError(f"write_phasors: expected a PhasorData, got {type(data).__name__}")
    label = os.fsdecode(os.fspath(path))
    trial = bool(np.any(data.trial_node >= 0))
    names = ["run", "speed", "node", "direction", "real", "imag"]
    names += ["sigma"] * (data.sigma is not None) + list(TRIAL) * trial + list(FRF) * (data.kind == "frf")
    out = ["# rotorjax phasor file: x(t) = Re((real + i imag) e^(i speed t)); SI units (rad/s, m"
           + (", m/N" if data.kind == "frf" else "") + ", kg m, rad)", ",".join(names)]
    for i in range(data.n):
        cells = [str(int(data.run[i])), _float_text(data.speed[i]), str(int(data.node[i])),
                 _DIRECTIONS[int(data.direction[i])], _float_text(data.X[i].real), _float_text(data.X[i].imag)]
        if data.sigma is not None:
            cells.append(_float_text(data.sigma[i]))
        if trial:
            cells += (["", "", ""] if data.trial_node[i] < 0 else
                      [str(int(data.trial_node[i])), _float_text(data.trial_magnitude[i]),
                       _float_text(data.trial_phase[i])])
        if data.kind == "frf":
            cells += [_float_text(data.frequency[i]), str(int(data.input_node[i])),
                      _DIRECTIONS[int(data.input_direction[i])]]
        out.append(",".join(cells))
    try:
        with open(label, "w", encoding="utf-8", newline="\n") as fh:
            fh.write("\n".join(out) + "\n")
    except OSError as e:
        raise InputError(f"{label}: cannot be written ({e.strerror or e})") from None
    return label


# --- raw signals to phasors --------------------------------------------------------

_MAP_EXAMPLE = "x1=2:x,x2=2:y"
_CHANNELS_LINE = re.compile(r"^\s*#\s*channels\s*:(.*)$", re.IGNORECASE)


def _node_value(v):
    """An FE node number (int >= 0) from text or a number, or None."""
    if isinstance(v, bool):
        return None
    if isinstance(v, str):
        try:
            v = float(v.strip())
        except ValueError:
            return None
    try:
        v = float(v)
    except (TypeError, ValueError):
        return None
    return int(v) if np.isfinite(v) and v == round(v) and v >= 0 else None


def _parse_map_text(text, source):
    """`{channel: (node, direction 0/1)}` of `x1=2:x,x2=2:y`; errors start with `source`."""
    items = [s.strip() for s in text.split(",")]
    if not any(items):
        raise InputError(f"{source}: empty channel map: expected CHANNEL=NODE:DIR items such as {_MAP_EXAMPLE}")
    pairs = []
    for item in items:
        if not item:
            raise InputError(f"{source}: an empty item (two commas in a row, or a trailing comma?): expected "
                             f"CHANNEL=NODE:DIR items such as {_MAP_EXAMPLE}")
        name, eq, rest = item.partition("=")
        node_text, colon, dir_text = rest.partition(":")
        if not eq or not name.strip() or not colon:
            raise InputError(f"{source}: {item!r} is not CHANNEL=NODE:DIR (e.g. {_MAP_EXAMPLE}: sensor column x1 "
                             "at FE node 2, direction x)")
        pairs.append((name.strip(), node_text.strip(), dir_text.strip(), item))
    return _check_map(pairs, source)


def _check_map(pairs, source):
    out, where = {}, {}
    for name, node, direction, item in pairs:
        what = f"{item!r}" if isinstance(item, str) else f"{name!r}: {item!r}"
        n = _node_value(node)
        if n is None:
            raise InputError(f"{source}: {what}: node {node!r} is not an FE node number (an integer >= 0)")
        d = direction.strip().lower() if isinstance(direction, str) else None
        if d not in _DIRECTIONS:
            raise InputError(f"{source}: {what}: direction {direction!r} is not x or y")
        if name in out:
            raise InputError(f"{source}: channel {name} is mapped more than once")
        key = (n, _DIRECTIONS.index(d))
        if key in where:
            raise InputError(f"{source}: channels {where[key]} and {name} both map to node {n}, direction {d}: "
                             "one sensor per node and direction")
        out[name], where[key] = key, name
    return out


def _map_from_argument(mapping):
    if isinstance(mapping, str):
        source = f"--map {mapping}" if mapping.strip() else "--map ''"
        return _parse_map_text(mapping, source), source
    if not isinstance(mapping, dict):
        raise InputError(f"mapping: expected {{channel: (node, 'x' or 'y')}} or text such as {_MAP_EXAMPLE!r}, "
                         f"got {type(mapping).__name__}")
    if not mapping:
        raise InputError(f"mapping: empty channel map: expected {{channel: (node, 'x' or 'y')}}")
    pairs = []
    for name, v in mapping.items():
        if not isinstance(v, (tuple, list)) or len(v) != 2:
            raise InputError(f"mapping: {name!r}: {v!r}: expected (node, 'x' or 'y')")
        pairs.append((str(name), v[0], v[1], v))
    return _check_map(pairs, "mapping"), "mapping"


def _map_from_file(file, label):
    """The channel map of `# channels: ...` comment lines of a CSV file (None: none)."""
    if os.path.splitext(file)[1].lower() != ".csv":
        return None
    with open(file, encoding="utf-8-sig") as fh:
        found = [(k + 1, ln.rstrip("\r\n")) for k, ln in enumerate(fh) if _CHANNELS_LINE.match(ln)]
    if not found:
        return None
    if len(found) > 1:
        raise InputError(f"{label}: lines {found[0][0]} and {found[1][0]} both give '# channels:': give the "
                         "channel map once")
    k, text = found[0]
    source = f"{label}: line {k} ({text.strip()!r})"
    return _parse_map_text(_CHANNELS_LINE.match(text).group(1), source), source


def _is_steady(pulses):
    """Whether the speed over the pulses varies by less than `STEADY_TOLERANCE` (a
    quadratic angle fit: the pulses' timing scatter averages out)."""
    if pulses.size < 4:
        return True
    _, speed = rotor_angle(pulses, pulses, degree=2)
    return float(np.ptp(speed)) < STEADY_TOLERANCE * float(np.mean(np.abs(speed)))


def phasors_from_signals(path, mapping=None, revolutions_per_block=None) -> PhasorData:
    """The 1x phasors of a raw measurement file (see `read_signals`) as a `PhasorData`.

    **Arguments:**
    - `path`: the raw file (CSV or `.npz`), or a shipped dataset name.
    - `mapping`: the sensors' FE nodes and directions, `{"x1": (2, "x"), ...}` or the
      text `"x1=2:x,x2=2:y"`; default: the CSV file's comment line
      `# channels: x1=2:x, x2=2:y`. Every sensor column must be mapped.
    - `revolutions_per_block`: revolutions per phasor of a run whose speed varies
      (default 1); a steady run (speed within `STEADY_TOLERANCE`) gives one phasor
      per sensor.

    Trial weights map as `trial_plane` -> `trial_node` (the plane number is the FE
    node), `trial_unbalance` -> `trial_magnitude`, `trial_angle` (deg) -> `trial_phase` (rad).

    **Raises:** `InputError` naming the file, the option (`--map` for text) or the
    comment line, and the channel or run."""
    if revolutions_per_block is None:
        revolutions_per_block = 1
    elif isinstance(revolutions_per_block, bool) or _node_value(revolutions_per_block) in (None, 0):
        raise InputError(f"revolutions_per_block must be an integer >= 1, got {revolutions_per_block!r}")
    cols = read_signals(path)
    label = cols["path"]
    if mapping is not None:
        channels, source = _map_from_argument(mapping)
    else:
        found = _map_from_file(resolve_data(path), label)
        if found is None:
            raise InputError(f"{label}: no channel map: give the sensors' FE nodes and directions (--map "
                             f"{_MAP_EXAMPLE}, or mapping=...), or a comment line '# channels: {_MAP_EXAMPLE}' "
                             "in the CSV file")
        channels, source = found
    sensors = cols["sensors"]
    for name in channels:
        if name not in sensors:
            raise InputError(f"{source}: channel {name!r} is not a sensor column of {label} (its sensor columns: "
                             f"{', '.join(sensors)})")
    unmapped = [s for s in sensors if s not in channels]
    if unmapped:
        raise InputError(f"{label}: sensor column(s) {', '.join(unmapped)} without a channel map entry (mapped: "
                         f"{', '.join(channels)}): map every sensor, e.g. {unmapped[0]}=NODE:x, or remove the "
                         "column")
    node = np.array([channels[s][0] for s in sensors], dtype=float)
    direction = np.array([channels[s][1] for s in sensors])
    rows = {k: [] for k in ("speed", "node", "direction", "X", "run")}
    trial = {}
    has_trial = "trial_plane" in cols
    for r, idx in _run_index(cols):
        t = cols["time"][idx]
        x = np.stack([cols[s][idx] for s in sensors], axis=1)
        run = 0 if r is None else r
        try:
            pulses = pulse_times(t, cols["tacho"][idx])
            if _is_steady(pulses):
                p = phasors(t, x, pulses=pulses)
                speeds, X = np.array([p.speed]), p.X[None, :]
            else:
                speeds, X = order_track(t, x, pulses=pulses, revolutions_per_block=revolutions_per_block)
        except InputError as e:
            raise InputError(f"{label}: {'' if r is None else f'run {r}: '}{e}") from None
        if speeds.size == 0:
            raise InputError(f"{label}: {'' if r is None else f'run {r}: '}no block of "
                             f"{revolutions_per_block} revolution(s) holds 8 samples")
        nb, ns = X.shape
        rows["speed"].append(np.repeat(speeds, ns))
        rows["node"].append(np.tile(node, nb))
        rows["direction"].append(np.tile(direction, nb))
        rows["X"].append(X.reshape(-1))
        rows["run"].append(np.full(nb * ns, run))
        if has_trial and cols["trial_plane"][idx[0]] >= 0:
            trial[run] = (int(cols["trial_plane"][idx[0]]), float(cols["trial_unbalance"][idx[0]]),
                          float(np.radians(cols["trial_angle"][idx[0]])))
    return make_phasors(*(np.concatenate(rows[k]) for k in ("speed", "node", "direction", "X", "run")),
                        trial=trial or None, path=label)
