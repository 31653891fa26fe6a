"""From raw vibration signals to 1x phasors, and the measurement file formats.

A run is sampled vibration channels plus a once-per-revolution reference (a
tachometer pulse channel). The rotor angle is `theta = 2 pi k` at the k-th pulse
(rising edge through half the pulse height), linear in between; each channel is
fitted over whole revolutions by least squares,
`x(t) ~ a cos theta + b sin theta + c`, and reported as the phasor `X = a - i b`
so that `x = Re(X e^{i theta})`: amplitude `|X|`, phase `arg X` measured from the
mark in the direction of rotation (see `rotorjax.models._balancing_machine`). The run's speed is the mean
of `2 pi / (pulse period)` over the fitted revolutions.

Files (CSV with a header row, or NumPy `.npz` with the same names):
- `time` (s, strictly increasing), `tacho` (pulse channel), one column per sensor
  (`x1`, `x2`, ...), and optionally `run` (an integer label per sample: several
  runs in one file) and `trial_plane`, `trial_unbalance` (kg m), `trial_angle` (deg) (per sample,
  constant within a run: the trial weight of that run; plane -1 for none).

`read_signals` checks a file against this description before anything is computed
from it: every malformed file raises an `InputError` that names the file (as the
user gave it), the column and the row where it applies (CSV: the 1-based data row
and the line of the file; `.npz`: the 0-based sample index), and what would be
valid. `balancing_runs` adds the checks a balancing needs (one run without a trial
weight, one trial run per plane, at least as many sensors as planes).
"""

import dataclasses
import os
import re
import zipfile

import numpy as np

from .._errors import InputError
from ._datasets import resolve_data


@dataclasses.dataclass(frozen=True)
class Phasors:
    """1x phasors of one run: `speed` (rad/s), `X` (complex, per sensor),
    `revolutions` fitted, `residual_rms` of the fit per sensor."""

    speed: float
    X: np.ndarray
    revolutions: int
    residual_rms: np.ndarray


def pulse_times(t, tacho):
    """Times of the rising edges of a once-per-revolution pulse channel (linear
    interpolation through half its height)."""
    t, tacho = np.asarray(t, dtype=float), np.asarray(tacho, dtype=float)
    if t.ndim != 1 or tacho.shape != t.shape:
        raise InputError(f"time has shape {t.shape} but the tacho channel {tacho.shape}: one value per sample")
    if t.size == 0:
        raise InputError("no samples")
    if not np.all(np.isfinite(tacho)):
        i = int(np.argmax(~np.isfinite(tacho)))
        raise InputError(f"the tacho channel has NaN or infinite values (first at sample index {i}, 0-based)")
    lo, hi = np.min(tacho), np.max(tacho)
    if not hi > lo:
        raise InputError(f"the tacho channel is constant ({lo:.6g} in every sample): no once-per-revolution "
                         "pulses")
    level = 0.5 * (lo + hi)
    up = np.where((tacho[:-1] < level) & (tacho[1:] >= level))[0]
    if up.size < 2:
        raise InputError(f"the tacho channel has {up.size} rising edge(s): at least 2 pulses (one "
                         "revolution) are needed")
    f = (level - tacho[up]) / (tacho[up + 1] - tacho[up])
    return t[up] + f * (t[up + 1] - t[up])


def rotor_angle(t, pulses, degree=1):
    """`theta(t)` from the pulse times: the least-squares polynomial of `degree` in
    `t` through `theta(pulse_k) = 2 pi k` (degree 1: constant speed; 3: a run-up),
    which averages the pulses' timing errors (one sample at most) instead of
    following them; NaN outside the first and last pulse. Returns `(theta, speed)`
    with `speed(t)` the polynomial's derivative."""
    k = np.arange(pulses.size) * 2 * np.pi
    deg = int(min(degree, pulses.size - 1))
    tc, ts = pulses.mean(), max(np.ptp(pulses), 1e-300)
    c = np.polyfit((pulses - tc) / ts, k, deg)
    inside = (t >= pulses[0]) & (t <= pulses[-1])
    u = (t - tc) / ts
    theta = np.where(inside, np.polyval(c, u), np.nan)
    speed = np.where(inside, np.polyval(np.polyder(c), u) / ts, np.nan)
    return theta, speed


def phasors(t, channels, tacho=None, pulses=None) -> Phasors:
    """1x phasors of one steady run (see the module docstring). `channels`:
    `(n_samples, n_sensors)`; give `tacho` (pulse channel) or `pulses` (times)."""
    t = np.asarray(t, dtype=float)
    x = np.asarray(channels, dtype=float)
    x = x[:, None] if x.ndim == 1 else x
    _check_samples(t, x)
    if pulses is None:
        if tacho is None:
            raise InputError("give the tacho channel or the pulse times")
        pulses = pulse_times(t, tacho)
    pulses = _check_pulses(pulses)
    theta, _ = rotor_angle(t, pulses, degree=1)
    k = np.isfinite(theta)
    if k.sum() < 8:
        raise InputError(f"{int(k.sum())} samples lie within whole revolutions: at least 8 are needed")
    basis = np.stack([np.cos(theta[k]), np.sin(theta[k]), np.ones(k.sum())], axis=1)
    coef, *_ = np.linalg.lstsq(basis, x[k], rcond=None)
    resid = x[k] - basis @ coef
    speed = float(2 * np.pi * (pulses.size - 1) / (pulses[-1] - pulses[0]))
    return Phasors(speed=speed, X=coef[0] - 1j * coef[1], revolutions=int(pulses.size - 1),
                   residual_rms=np.sqrt(np.mean(resid**2, axis=0)))


@dataclasses.dataclass(frozen=True, eq=False)
class OrderTrack:
    """1x phasors along a run-up and what is needed to treat a model's response the
    same way (`order_track(..., full=True)`; see `identify(..., tracking=...)`).

    - `speeds` (rad/s, `(n_blocks,)`), `X` (complex, `(n_blocks, n_sensors)`): as
      `order_track` returns them;
    - `sigma` (`(n_blocks, n_sensors)`): the standard deviation of the real (and of
      the imaginary) part of each phasor from white sensor noise of rms `noise_rms`,
      `noise_rms * sqrt(((G^-1)_cc + (G^-1)_ss) / 2)` with `G` the block's normal
      matrix: it grows with the speed, as a revolution holds fewer samples;
    - `noise_rms` (`(n_sensors,)`): the sensor noise, pooled from the residuals of
      the blocks' least-squares fits;
    - `time`, `theta`, `speed` (`(n_samples,)`): every sample's time, the fitted
      rotor angle and speed (NaN outside the first and the last pulse); `block`
      (int): each sample's block (an index into `speeds`; -1 for samples outside
      the pulses or in dropped blocks);
    - `normal_inv` (`(n_blocks, 3, 3)`): `G^-1` of each block (basis cos, sin, 1);
    - `block_time` (`(n_blocks,)`): the blocks' mean sample times;
    - `angle`: the rotor-angle polynomial `theta(t) = polyval(coef, (t - tc) / ts)`
      as `(coef, tc, ts)`; `angle_cov`: the covariance of `coef` (from the pulses'
      timing scatter, `pulse_jitter` s rms): the uncertainty of the phase reference;
    - `revolutions_per_block`.
    """

    speeds: np.ndarray
    X: np.ndarray
    sigma: np.ndarray
    noise_rms: np.ndarray
    time: np.ndarray
    theta: np.ndarray
    speed: np.ndarray
    block: np.ndarray
    normal_inv: np.ndarray
    block_time: np.ndarray
    angle: tuple
    angle_cov: np.ndarray
    pulse_jitter: float
    revolutions_per_block: int

    def angle_derivatives(self, t, order=0):
        """`d^order theta / dt^order` at times `t` (rad/s^order) from the angle polynomial."""
        c, tc, ts = self.angle
        for _ in range(order):
            c = np.polyder(c)
        return np.polyval(c, (np.asarray(t, dtype=float) - tc) / ts) / ts**order

    def angle_sensitivity(self, t):
        """`(d theta / d coef, d speed / d coef)` at times `t`: `(len(t), deg + 1)` each
        (the rotor angle and speed are linear in the polynomial's coefficients)."""
        c, tc, ts = self.angle
        u = (np.asarray(t, dtype=float) - tc) / ts
        deg = c.size - 1
        V = np.vander(u, deg + 1)
        dV = np.zeros_like(V)
        for j in range(deg):               # column j holds u^(deg - j)
            dV[:, j] = (deg - j) * u ** (deg - j - 1) / ts
        return V, dV


def _angle_fit(pulses, degree, weighted=True):
    """The rotor-angle polynomial through `theta(pulse_k) = 2 pi k`: `(coef, tc, ts)`,
    the covariance of `coef` and the pulses' timing scatter (s rms).

    A pulse detected `dt` late puts the angle `speed * dt` off, so along a run-up
    the fast pulses scatter most in angle: the fit is weighted by `1 / speed^2`
    (speed from the previous pass; three passes), which is least squares in the
    pulse times and cuts the angle error where the run is slow by a factor of
    about 2.5 for a cubic, less at the fast end (`weighted=False`: the
    unweighted fit, as before). The coefficients' covariance is
    `s_t^2 (V^T W V)^-1` (a sandwich for the unweighted fit), `s_t` the rms
    timing residual."""
    k = np.arange(pulses.size) * 2 * np.pi
    deg = int(min(degree, pulses.size - 1))
    tc, ts = pulses.mean(), max(np.ptp(pulses), 1e-300)
    u = (pulses - tc) / ts
    V = np.vander(u, deg + 1)
    w = np.ones_like(u)
    speed = None
    for _ in range(3 if weighted else 1):
        sw = np.sqrt(w)
        c = np.linalg.lstsq(V * sw[:, None], k * sw, rcond=None)[0]
        speed = np.abs(np.polyval(np.polyder(c), u) / ts)
        speed = np.maximum(speed, 1e-3 * max(float(speed.max()), 1e-300))
        if weighted:
            w = 1.0 / speed**2
    r = k - V @ c
    wt = 1.0 / speed**2                 # the timing residuals, whatever the fit's weights
    s_t2 = float(np.sum(wt * r**2)) / max(pulses.size - deg - 1, 1)
    # a fit with weights w of angle errors of variance s_t^2 / wt
    Vw = V * w[:, None]
    bread = np.linalg.pinv(Vw.T @ V)
    cov = bread @ ((Vw * (s_t2 / wt * w)[:, None]).T @ V) @ bread
    return (c, tc, ts), cov, float(np.sqrt(s_t2))


def order_track(t, channels, tacho=None, pulses=None, revolutions_per_block=1, degree=3, *, full=False,
                weighted=True):
    """1x phasors per block of revolutions along a run-up: `(speeds, X)` with
    `X` of shape `(n_blocks, n_sensors)`. The angle is one smooth fit over the
    whole run (a polynomial of `degree` in time through `theta(pulse_k) = 2 pi k`,
    weighted by `1 / speed^2`: least squares in the pulse times, see `_angle_fit`;
    `weighted=False`: unweighted, as before issue 13);
    each block is fitted by least squares as in `phasors`, its speed the mean of
    the fitted speed over the block.

    With `full=True`, returns an `OrderTrack` instead: the same phasors with their
    noise, the angle's uncertainty and the block operator, which let `identify`
    fit the run-up's transient response instead of the steady one.

    The angle comes from the tacho only: pulses sampled at `fs` are detected to
    within half a sample, so the phase reference itself carries an error (a few
    mrad at the ends of a 1 kHz run-up to 400 rad/s), common to all sensors and
    smooth along the run; `OrderTrack.angle_cov` states it."""
    t = np.asarray(t, dtype=float)
    x = np.asarray(channels, dtype=float)
    x = x[:, None] if x.ndim == 1 else x
    _check_samples(t, x)
    if pulses is None:
        if tacho is None:
            raise InputError("give the tacho channel or the pulse times")
        pulses = pulse_times(t, tacho)
    n = int(revolutions_per_block)
    if n < 1 or n != revolutions_per_block:
        raise InputError(f"revolutions_per_block must be an integer >= 1, got {revolutions_per_block}")
    pulses = _check_pulses(pulses)
    (c_ang, tc, ts), angle_cov, jitter = _angle_fit(pulses, degree, weighted)
    inside = (t >= pulses[0]) & (t <= pulses[-1])
    u = (t - tc) / ts
    theta = np.where(inside, np.polyval(c_ang, u), np.nan)
    speed = np.where(inside, np.polyval(np.polyder(c_ang), u) / ts, np.nan)
    ok = np.isfinite(theta)
    if not ok.any():
        raise InputError("no sample lies between the first and the last tacho pulse")
    th, sp, xs = theta[ok], speed[ok], x[ok]
    k = np.floor(th / (2 * np.pi * n)).astype(int)
    k -= k.min()
    # per block, the normal equations of x ~ a cos + b sin + c, summed with bincount
    c, s_ = np.cos(th), np.sin(th)
    basis = (c, s_, np.ones_like(c))
    nb = int(k.max()) + 1
    A = np.empty((nb, 3, 3))
    for i in range(3):
        for j in range(i, 3):
            A[:, i, j] = A[:, j, i] = np.bincount(k, basis[i] * basis[j], minlength=nb)
    rhs = np.stack([np.stack([np.bincount(k, basis[i] * xs[:, m], minlength=nb) for i in range(3)], axis=-1)
                    for m in range(xs.shape[1])], axis=-1)                      # (nb, 3, n_sensors)
    count = np.bincount(k, minlength=nb)
    keep = count >= 8
    coef = np.linalg.solve(A[keep], rhs[keep])
    speeds = np.bincount(k, sp, minlength=nb)[keep] / count[keep]
    X = coef[:, 0, :] - 1j * coef[:, 1, :]
    if not full:
        return speeds, X
    # the sensor noise, pooled over the blocks' fits (3 coefficients each)
    index = np.full(nb, -1)
    index[keep] = np.arange(int(keep.sum()))
    block = index[k]
    used = block >= 0
    fit = np.einsum("si,sim->sm", np.stack(basis, axis=1)[used], coef[block[used]])
    rss = np.sum((xs[used] - fit) ** 2, axis=0)
    noise_rms = np.sqrt(rss / max(int(used.sum()) - 3 * int(keep.sum()), 1))
    Ginv = np.linalg.inv(A[keep])
    sigma = noise_rms[None, :] * np.sqrt(0.5 * (Ginv[:, 0, 0] + Ginv[:, 1, 1]))[:, None]
    block_time = np.bincount(k, t[ok], minlength=nb)[keep] / count[keep]
    block_all = np.full(t.size, -1)
    block_all[ok] = block
    return OrderTrack(speeds=speeds, X=X, sigma=sigma, noise_rms=noise_rms, time=t, theta=theta, speed=speed,
                      block=block_all, normal_inv=Ginv, block_time=block_time, angle=(c_ang, tc, ts),
                      angle_cov=angle_cov, pulse_jitter=jitter, revolutions_per_block=n)


def _check_pulses(pulses):
    p = np.asarray(pulses, dtype=float)
    if p.ndim != 1 or p.size < 2:
        raise InputError(f"pulse times of shape {p.shape}: expected a 1-D array of at least 2 times")
    if not np.all(np.isfinite(p)) or not np.all(np.diff(p) > 0):
        raise InputError("pulse times must be finite and strictly increasing")
    return p


def _check_samples(t, x):
    if t.ndim != 1 or x.ndim != 2 or x.shape[0] != t.shape[0]:
        raise InputError(f"time has shape {t.shape} but the channels {x.shape}: expected (n_samples,) and "
                         "(n_samples, n_sensors)")
    if not np.all(np.isfinite(t)):
        i = int(np.argmax(~np.isfinite(t)))
        raise InputError(f"time has NaN or infinite values (first at sample index {i}, 0-based)")
    bad = ~np.isfinite(x)
    if bad.any():
        i, m = (int(v) for v in np.argwhere(bad)[0])
        raise InputError(f"channel {m} has NaN or infinite values (first at sample index {i}, 0-based)")
    if not np.all(np.diff(t) > 0):
        i = int(np.argmax(np.diff(t) <= 0))
        raise InputError(f"time is not strictly increasing (sample index {i + 1}, 0-based: {t[i + 1]:.10g} "
                         f"after {t[i]:.10g})")


# --- measurement files -------------------------------------------------------

_FORMATS = "a CSV file with a header row (.csv) or a NumPy archive (.npz)"
_EXAMPLE = "time,tacho,x1,x2"
_TRIAL = ("trial_plane", "trial_unbalance", "trial_angle")


class _Where:
    """Where sample `i` lies in the file, in the user's terms: the 1-based data row
    and the line of a CSV file, the 0-based sample index of a `.npz` array."""

    def __init__(self, lines=None):
        self.lines = lines

    def __call__(self, i):
        i = int(i)
        if self.lines is None:
            return f"sample index {i} (0-based)"
        return f"data row {i + 1} (line {self.lines[i]})"


def _num(v):
    return f"{float(v):.10g}"


def _read_csv(file, label):
    """`({column: float array}, _Where)` of a CSV file, or an InputError."""
    names, rows, where = _read_table(file, label)
    try:
        table = np.array(rows, dtype=float)
    except ValueError:
        _raise_bad_cell(rows, names, where, label)
        raise InputError(f"{label}: the data rows cannot be read as numbers") from None
    return {n: table[:, j].copy() for j, n in enumerate(names)}, _Where(where)


def _read_table(file, label, example=_EXAMPLE, row="sample"):
    """The text table of a CSV file, `(names, rows, where)`: the column names, the
    data rows as lists of strings (as many as names) and each row's 1-based line
    number; or an InputError (not text, no header, bad names, ragged rows). No cell
    is converted: `_read_csv` makes numbers of them. `example` (a header) and `row`
    (what a data row holds) word the messages."""
    try:
        with open(file, "rb") as f:
            raw = f.read()
    except OSError as e:
        raise InputError(f"{label}: cannot be read ({e.strerror or e})") from None
    if not raw.strip():
        size = "0 bytes" if not raw else f"{len(raw)} bytes, only whitespace"
        raise InputError(f"{label}: empty file ({size}): expected a header row such as {example} and one data "
                         f"row per {row}")
    if raw[:4] == b"PK\x03\x04":
        raise InputError(f"{label}: a zip archive (an Excel workbook or a .npz?), not a text CSV file: export the "
                         f"sheet as CSV, or name a NumPy archive .npz; expected {_FORMATS}")
    if raw[:2] in (b"\xff\xfe", b"\xfe\xff"):
        raise InputError(f"{label}: UTF-16 text: save the file as UTF-8 (or ASCII) CSV")
    nul = raw.find(b"\x00")
    if nul >= 0:
        raise InputError(f"{label}: binary data (a zero byte at offset {nul}), not a text CSV file: expected "
                         f"{_FORMATS}")
    try:
        text = raw.decode("utf-8-sig")
    except UnicodeDecodeError as e:
        line = raw.count(b"\n", 0, e.start) + 1
        col = e.start - (raw.rfind(b"\n", 0, e.start) + 1) + 1
        raise InputError(f"{label}: not UTF-8 text (byte 0x{raw[e.start]:02x} at line {line}, byte {col}): "
                         "save the file as UTF-8, with ASCII column names") from None
    lines = [ln.rstrip("\r") for ln in text.split("\n")]

    header_at, comment_at = None, None
    for i, ln in enumerate(lines):
        s = ln.strip()
        if s.startswith("#"):
            comment_at = i
        elif s:
            header_at = i
            break
    if header_at is None:
        raise InputError(f"{label}: no header row and no data (only blank or comment lines): expected a header "
                         f"row such as {example} and one data row per {row}")
    header, first_data = lines[header_at], header_at + 1
    if _is_number(header.split(",")[0]):
        # `np.savetxt(..., header=...)` writes the header as a comment: accept that one
        if comment_at is not None and "," in lines[comment_at]:
            header, first_data = lines[comment_at].strip().lstrip("#"), header_at
        else:
            raise InputError(f"{label}: line {header_at + 1} is data ({header.strip()[:40]!r}), not a header: "
                             f"the first line must name the columns, e.g. {example}")
    names = [n.strip().strip('"').strip("'").strip() for n in header.split(",")]
    hline = (comment_at if first_data == header_at else header_at) + 1
    if len(names) == 1:
        for sep, word in ((";", "semicolons"), ("\t", "tabs"), ("|", "bars")):
            if sep in names[0]:
                raise InputError(f"{label}: the header (line {hline}) is separated by {word}, not commas: "
                                 f"expected comma-separated columns such as {example}")
    for j, n in enumerate(names):
        if not n:
            raise InputError(f"{label}: column {j + 1} of the header (line {hline}) has no name: every column "
                             f"needs a name, e.g. {example} (a trailing comma?)")
    seen = {}
    for j, n in enumerate(names):
        if n in seen:
            raise InputError(f"{label}: duplicate column name {n!r} (columns {seen[n] + 1} and {j + 1} of the "
                             f"header, line {hline}): each column needs its own name")
        seen[n] = j

    rows, where = [], []
    for i in range(first_data, len(lines)):
        s = lines[i].strip()
        if s and not s.startswith("#"):
            rows.append(lines[i].split(","))
            where.append(i + 1)
    cols_desc = ", ".join(names)
    if not rows:
        raise InputError(f"{label}: a header ({cols_desc}) but no data rows: expected one row per {row}")
    counts = np.fromiter(map(len, rows), dtype=int, count=len(rows))
    if np.any(counts != len(names)):
        j = int(np.argmax(counts != len(names)))
        hint = ": the file looks truncated" if j == len(rows) - 1 and counts[j] < len(names) else ""
        raise InputError(f"{label}: data row {j + 1} (line {where[j]}) has {counts[j]} field(s) but the header "
                         f"names {len(names)} columns ({cols_desc}){hint}")
    return names, rows, where


def _is_number(s):
    try:
        float(s)
    except ValueError:
        return False
    return True


def _raise_bad_cell(rows, names, where, label):
    for i, row in enumerate(rows):
        for j, cell in enumerate(row):
            if not _is_number(cell):
                what = "an empty cell" if not cell.strip() else f"{cell.strip()[:40]!r} is not a number"
                raise InputError(f"{label}: column {names[j]!r}, data row {i + 1} (line {where[i]}): {what}; "
                                 "every cell must be a number (decimal point, no units)")


def _wanted(name):
    return name in ("time", "tacho", "run") + _TRIAL or name.startswith("x")


def _read_npz(file, label):
    """`({column: float array}, _Where)` of a `.npz` archive, or an InputError."""
    if os.path.getsize(file) == 0:
        raise InputError(f"{label}: empty file (0 bytes): expected a NumPy archive written by numpy.savez "
                         "with arrays time, tacho, x1, ...")
    if not zipfile.is_zipfile(file):
        raise InputError(f"{label}: not a valid .npz archive (not a zip file: truncated or corrupt?): expected "
                         "an archive written by numpy.savez with arrays time, tacho, x1, ...")
    try:
        z = np.load(file, allow_pickle=False)
    except Exception as e:                                                     # noqa: BLE001 - any reader failure
        raise InputError(f"{label}: cannot be read as a .npz archive ({type(e).__name__}: {e})") from None
    cols = {}
    with z:
        names = list(z.files)
        for k in names:
            try:
                a = np.asarray(z[k])
            except Exception as e:                                             # noqa: BLE001
                if not _wanted(k):
                    continue
                raise InputError(f"{label}: array {k!r} cannot be read ({type(e).__name__}: {e}): the archive "
                                 "is corrupt or holds Python objects") from None
            if a.dtype.kind not in "biuf" or a.ndim != 1:
                if not _wanted(k):
                    continue                                                   # metadata: not ours to judge
                if a.dtype.kind not in "biuf":
                    raise InputError(f"{label}: array {k!r} has dtype {a.dtype}: expected real numbers, one per "
                                     "sample")
                raise InputError(f"{label}: array {k!r} has shape {a.shape}: expected a 1-D array, one value "
                                 "per sample")
            cols[k] = a.astype(float)
    if not cols:
        found = f" (found {', '.join(names)})" if names else ""
        raise InputError(f"{label}: the .npz archive holds no arrays of numbers{found}: expected time, tacho, x1, ...")
    lengths = {k: v.size for k, v in cols.items() if _wanted(k)}
    if len(set(lengths.values())) > 1:
        desc = ", ".join(f"{k} {n}" for k, n in lengths.items())
        raise InputError(f"{label}: arrays of different lengths ({desc}): every array needs one value per sample")
    if lengths and next(iter(lengths.values())) == 0:
        raise InputError(f"{label}: the arrays are empty: no samples")
    n = next(iter(lengths.values()), None)
    return {k: v for k, v in cols.items() if n is None or v.size == n}, _Where(None)


def _sensor_key(name):
    m = re.fullmatch(r"x(\d+)", name)
    return (0, int(m.group(1)), name) if m else (1, 0, name)


def _run_index(cols):
    """`[(label, sample indices)]` per run, in label order."""
    if "run" not in cols:
        return [(None, np.arange(cols["time"].size))]
    labels = cols["run"]
    return [(int(r), np.flatnonzero(labels == r)) for r in np.unique(labels)]


def _check_columns(cols, label, where, sensors):
    found = ", ".join(cols) or "none"
    if sensors is None:
        sensors = sorted((k for k in cols if k.startswith("x")), key=_sensor_key)
    else:
        sensors = [sensors] if isinstance(sensors, str) else list(sensors)
        dup = sorted({s for s in sensors if sensors.count(s) > 1})
        if dup:
            raise InputError(f"sensors: {', '.join(dup)} given more than once")
    missing = [c for c in ["time", "tacho"] + sensors if c not in cols]
    if missing:
        lower = {k.lower() for k in cols}
        case = "; column names are case-sensitive" if any(c.lower() in lower for c in missing) else ""
        raise InputError(f"{label}: missing column(s) {', '.join(missing)}; found {found} (needed: time, tacho "
                         f"and one column per sensor, x1, x2, ...){case}")
    if not sensors:
        raise InputError(f"{label}: no sensor columns (named x1, x2, ...); found {found}")
    trial = [c for c in _TRIAL if c in cols]
    if trial and len(trial) < len(_TRIAL):
        raise InputError(f"{label}: incomplete trial-weight columns: found {', '.join(trial)} but not "
                         f"{', '.join(c for c in _TRIAL if c not in cols)}: give all of {', '.join(_TRIAL)} or "
                         "none")
    used = ["time", "tacho"] + sensors + [c for c in ("run",) + _TRIAL if c in cols]
    for c in used:
        bad = ~np.isfinite(cols[c])
        if bad.any():
            i = int(np.argmax(bad))
            raise InputError(f"{label}: column {c!r} has NaN or infinite values (first at {where(i)}: "
                             f"{cols[c][i]}): every value must be a finite number")
    if "run" in cols:
        r = cols["run"]
        bad = r != np.round(r)
        if bad.any():
            i = int(np.argmax(bad))
            raise InputError(f"{label}: column 'run', {where(i)}: {_num(r[i])} is not an integer run label")
    runs = _run_index(cols)
    t = cols["time"]
    for r, idx in runs:
        dt = np.diff(t[idx])
        if np.any(dt <= 0):
            j = int(np.argmax(dt <= 0))
            in_run = "" if r is None else f" in run {r}"
            restart = r is None and t[idx[j + 1]] <= t[idx[0]]
            hint = " (several runs in one file need a 'run' column labelling each sample)" if restart else ""
            raise InputError(f"{label}: time is not strictly increasing{in_run} at {where(idx[j + 1])}: "
                             f"{_num(t[idx[j + 1]])} after {_num(t[idx[j]])}{hint}")
    if trial:
        plane = cols["trial_plane"]
        bad = (plane != np.round(plane)) | (plane < -1)
        if bad.any():
            i = int(np.argmax(bad))
            raise InputError(f"{label}: column 'trial_plane', {where(i)}: {_num(plane[i])} is not a plane "
                             "number: expected 0, 1, 2, ... (the plane of the run's trial weight) or -1 (none)")
        for r, idx in runs:
            for c in _TRIAL:
                v = cols[c][idx]
                if np.any(v != v[0]):
                    j = int(np.argmax(v != v[0]))
                    run = "the file" if r is None else f"run {r}"
                    hint = " (several runs in one file need a 'run' column)" if r is None else ""
                    raise InputError(f"{label}: column {c!r} changes within {run} at {where(idx[j])}: "
                                     f"{_num(v[j])} after {_num(v[0])}: a run's trial weight is one value "
                                     f"for all its samples{hint}")
            u = cols["trial_unbalance"][idx[0]]
            if plane[idx[0]] >= 0 and not u > 0:
                run = "" if r is None else f", run {r}"
                raise InputError(f"{label}: column 'trial_unbalance', {where(idx[0])}{run}: {_num(u)} with a "
                                 f"trial weight in plane {int(plane[idx[0]])}: a trial unbalance must be > 0 "
                                 "(kg m; its direction is trial_angle)")
    for r, idx in runs:
        try:
            pulse_times(t[idx], cols["tacho"][idx])
        except InputError as e:
            run = "" if r is None else f"run {r}: "
            raise InputError(f"{label}: {run}{e}") from None
    return sensors


def read_signals(path, sensors=None) -> dict:
    """Read a measurement file (CSV or .npz; columns in the module docstring).

    **Arguments:**
    - `path`: the file (`str` or `os.PathLike`), or the name of a shipped dataset
      (`"runup"`, `"balancing-runs"`: see `resolve_data`).
    - `sensors`: the sensor columns to use (default: every column named `x*`, in
      the order x1, x2, ..., x10).

    **Returns:** `{column: float array}` for every column of the file, plus
    `"sensors"` (the list of sensor columns) and `"path"` (the file as given).

    **Raises:** `InputError` (a `ValueError`) for a file that is missing, not CSV or
    `.npz`, unreadable or malformed: the message names the file as given, the column
    and the row where they apply, and what would be valid."""
    label = os.fsdecode(os.fspath(path)) if isinstance(path, (str, bytes, os.PathLike)) else str(path)
    file = resolve_data(path)
    ext = os.path.splitext(file)[1].lower()
    if ext == ".npz":
        cols, where = _read_npz(file, label)
    elif ext == ".csv":
        cols, where = _read_csv(file, label)
    else:
        raise InputError(f"{label}: unsupported file type {ext or '(no extension)'!r}: expected {_FORMATS}")
    cols["sensors"] = _check_columns(cols, label, where, sensors)
    cols["path"] = label
    return cols


def runs_from_signals(cols) -> list:
    """Split a file's columns by `run` and extract each run's phasors and trial
    weight: `[{"run", "speed", "X", "trial": (plane, complex unbalance) or None,
    "revolutions", "residual_rms", "samples"}]`, in run-label order.

    **Raises:** `InputError` naming the file (when `cols` came from `read_signals`)
    and the run, for a run whose phasors cannot be extracted or whose trial weight
    is incomplete or not a positive finite unbalance."""
    pre = f"{cols['path']}: " if cols.get("path") else ""
    t_all = cols["time"]
    labels = np.asarray(cols.get("run", np.zeros_like(t_all)), dtype=float)
    if labels.shape != t_all.shape or not np.all(np.isfinite(labels)) or np.any(labels != np.round(labels)):
        raise InputError(f"{pre}the run labels must be one integer per sample")
    out = []
    for r in np.unique(labels):
        sel = labels == r
        t = t_all[sel]
        if not np.all(np.diff(t) > 0):
            raise InputError(f"{pre}run {int(r)}: time is not strictly increasing")
        try:
            p = phasors(t, np.stack([cols[s][sel] for s in cols["sensors"]], axis=1), tacho=cols["tacho"][sel])
        except ValueError as e:
            raise InputError(f"{pre}run {int(r)}: {e}") from None
        trial = None
        if "trial_plane" in cols and cols["trial_plane"][sel][0] >= 0:
            missing = [c for c in ("trial_unbalance", "trial_angle") if c not in cols]
            if missing:
                raise InputError(f"{pre}run {int(r)} has a trial plane but no column(s) {', '.join(missing)}")
            plane, u, a = (float(cols[c][sel][0]) for c in _TRIAL)
            if plane != int(plane) or not (np.isfinite(u) and u > 0) or not np.isfinite(a):
                raise InputError(f"{pre}run {int(r)}: trial weight plane {plane:g}, unbalance {u:g} kg m, angle "
                                 f"{a:g} deg: expected an integer plane, an unbalance > 0 and a finite angle")
            trial = (int(plane), u * np.exp(1j * np.radians(a)))
        out.append({"run": int(r), "speed": p.speed, "X": p.X, "trial": trial,
                    "revolutions": p.revolutions, "residual_rms": p.residual_rms, "samples": int(sel.sum())})
    return out


# --- the runs of a balancing -------------------------------------------------

@dataclasses.dataclass(frozen=True, eq=False)
class BalancingData:
    """The runs of an influence-coefficient balancing, checked (see `balancing_runs`).

    - `path`: the file as given;
    - `base`: the run without a trial weight (a `runs_from_signals` entry);
    - `trials_by_plane`: `{plane: run}`, one trial run per plane in `planes`;
    - `planes`: the correction planes used, in order (tuple of int);
    - `sensors`: the sensor columns (tuple of str);
    - `n_samples_base`: the number of samples of the base run.
    """

    path: str
    base: dict
    trials_by_plane: dict
    planes: tuple
    sensors: tuple
    n_samples_base: int

    @property
    def speed(self) -> float:
        """The base run's speed (rad/s)."""
        return self.base["speed"]

    @property
    def X0(self) -> np.ndarray:
        """1x phasors of the base run, `(n_sensors,)`."""
        return self.base["X"]

    @property
    def X_trials(self) -> np.ndarray:
        """1x phasors of the trial runs, `(n_planes, n_sensors)`, in `planes` order."""
        return np.stack([self.trials_by_plane[p]["X"] for p in self.planes])

    @property
    def trial_unbalances(self) -> np.ndarray:
        """The complex trial unbalances (kg m), `(n_planes,)`, in `planes` order."""
        return np.array([self.trials_by_plane[p]["trial"][1] for p in self.planes])


#: trial runs must turn within this fraction of the base run's speed
SPEED_TOLERANCE = 0.05


def _planes_wanted(planes, label, available):
    if isinstance(planes, str):
        try:
            wanted = [int(p) for p in planes.split(",")]
        except ValueError:
            raise InputError(f"planes must be comma-separated plane numbers, got {planes!r}") from None
    else:
        try:
            wanted = [int(p) for p in planes]
            ok = all(int(p) == p for p in planes)
        except (TypeError, ValueError):
            ok = False
        if not ok:
            raise InputError(f"planes must be plane numbers (integers), got {planes!r}")
    if not wanted:
        raise InputError("planes: give at least one plane")
    dup = sorted({p for p in wanted if wanted.count(p) > 1})
    if dup:
        raise InputError(f"planes: plane(s) {dup} given more than once")
    missing = [p for p in wanted if p not in available]
    if missing:
        raise InputError(f"{label}: no trial run for plane(s) {missing} (trial planes in the file: {available})")
    return wanted


def balancing_runs(path, planes=None) -> BalancingData:
    """Read a balancing's runs from a measurement file and check that they make a
    balancing: exactly one run without a trial weight, at least one trial run, one
    trial run per plane, at least as many sensors as planes (fewer would leave the
    least-squares correction underdetermined), trial runs at the base run's speed
    (within `SPEED_TOLERANCE`), and trial weights that changed the vibration.

    **Arguments:**
    - `path`: the file, or a dataset name (see `read_signals`).
    - `planes`: the correction planes to use (a sequence of int, or a string such as
      `"0,1"`); default: every plane with a trial run.

    **Returns:** a `BalancingData`.

    **Raises:** `InputError` naming the file (as given) and what is wrong."""
    cols = read_signals(path)
    label = cols["path"]
    runs = runs_from_signals(cols)
    base = [r for r in runs if r["trial"] is None]
    trials = [r for r in runs if r["trial"] is not None]
    if len(base) != 1:
        which = f" (runs {', '.join(str(r['run']) for r in base)})" if base else ""
        raise InputError(f"{label}: need exactly one run without a trial weight (trial_plane -1), found "
                         f"{len(base)}{which}")
    if not trials:
        raise InputError(f"{label}: no runs with a trial weight (columns run, trial_plane, trial_unbalance, "
                         "trial_angle): the influence coefficients cannot be estimated")
    by_plane = {}
    for r in trials:
        p = r["trial"][0]
        if p in by_plane:
            raise InputError(f"{label}: runs {by_plane[p]['run']} and {r['run']} both have a trial weight in plane "
                             f"{p}: need one trial run per plane")
        by_plane[p] = r
    available = sorted(by_plane)
    chosen = available if planes is None else _planes_wanted(planes, label, available)
    sensors = tuple(cols["sensors"])
    if len(sensors) < len(chosen):
        s = "" if len(sensors) == 1 else "s"
        raise InputError(f"{label} has {len(sensors)} sensor column{s} ({', '.join(sensors)}) but {len(chosen)} "
                         "trial planes: need at least as many sensors as planes")
    b = base[0]
    for p in chosen:
        r = by_plane[p]
        if abs(r["speed"] / b["speed"] - 1) > SPEED_TOLERANCE:
            raise InputError(f"{label}: run {r['run']} (trial weight in plane {p}) turns at {r['speed']:.4g} rad/s "
                             f"but run {b['run']} (no trial weight) at {b['speed']:.4g} rad/s: influence "
                             f"coefficients need runs at one speed (within {SPEED_TOLERANCE:.0%})")
        if np.max(np.abs(r["X"] - b["X"])) <= 1e-12 * np.max(np.abs(b["X"])):
            raise InputError(f"{label}: run {r['run']} (trial weight in plane {p}) has the same 1x vibration as run "
                             f"{b['run']} without a trial weight: the trial weight changed nothing (a copied run?)")
    return BalancingData(path=label, base=b, trials_by_plane={p: by_plane[p] for p in chosen},
                         planes=tuple(chosen), sensors=sensors, n_samples_base=b["samples"])
