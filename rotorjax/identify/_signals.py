"""From raw vibration signals to 1x phasors, and the measurement file formats.

A run is sampled vibration channels plus a once-per-revolution reference (a
tachometer pulse channel). The rotor angle is `theta = 2 pi k` at the k-th pulse
(rising edge through half the pulse height), linear in between; each channel is
fitted over whole revolutions by least squares,
`x(t) ~ a cos theta + b sin theta + c`, and reported as the phasor `X = a - i b`
so that `x = Re(X e^{i theta})`: amplitude `|X|`, phase `arg X` measured from the
mark in the direction of rotation (see `_machine`). The run's speed is the mean
of `2 pi / (pulse period)` over the fitted revolutions.

Files (CSV with a header row, or NumPy `.npz` with the same names):
- `time` (s, strictly increasing), `tacho` (pulse channel), one column per sensor
  (`x1`, `x2`, ...), and optionally `run` (an integer label per sample: several
  runs in one file) and `trial_plane`, `trial_unbalance` (kg m), `trial_angle` (deg) (per sample,
  constant within a run: the trial weight of that run; plane -1 for none).
"""

import dataclasses
import os

import numpy as np


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
    lo, hi = np.min(tacho), np.max(tacho)
    if not hi > lo:
        raise ValueError("the tacho channel is constant: no once-per-revolution pulses")
    level = 0.5 * (lo + hi)
    up = np.where((tacho[:-1] < level) & (tacho[1:] >= level))[0]
    if up.size < 2:
        raise ValueError(f"the tacho channel has {up.size} rising edge(s): at least 2 pulses (one "
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
            raise ValueError("give the tacho channel or the pulse times")
        pulses = pulse_times(t, tacho)
    pulses = np.asarray(pulses, dtype=float)
    theta, _ = rotor_angle(t, pulses, degree=1)
    k = np.isfinite(theta)
    if k.sum() < 8:
        raise ValueError("fewer than 8 samples lie within whole revolutions")
    basis = np.stack([np.cos(theta[k]), np.sin(theta[k]), np.ones(k.sum())], axis=1)
    coef, *_ = np.linalg.lstsq(basis, x[k], rcond=None)
    resid = x[k] - basis @ coef
    speed = float(2 * np.pi * (pulses.size - 1) / (pulses[-1] - pulses[0]))
    return Phasors(speed=speed, X=coef[0] - 1j * coef[1], revolutions=int(pulses.size - 1),
                   residual_rms=np.sqrt(np.mean(resid**2, axis=0)))


def order_track(t, channels, tacho=None, pulses=None, revolutions_per_block=1, degree=3):
    """1x phasors per block of revolutions along a run-up: `(speeds, X)` with
    `X` of shape `(n_blocks, n_sensors)`. The angle is one smooth fit over the
    whole run (`rotor_angle` with `degree`); each block is fitted by least squares
    as in `phasors`, its speed the mean of the fitted speed over the block."""
    t = np.asarray(t, dtype=float)
    x = np.asarray(channels, dtype=float)
    x = x[:, None] if x.ndim == 1 else x
    _check_samples(t, x)
    if pulses is None:
        pulses = pulse_times(t, tacho)
    theta, speed = rotor_angle(t, np.asarray(pulses, dtype=float), degree)
    n = int(revolutions_per_block)
    if n < 1:
        raise ValueError(f"revolutions_per_block must be >= 1, got {revolutions_per_block}")
    ok = np.isfinite(theta)
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
    return speeds, coef[:, 0, :] - 1j * coef[:, 1, :]


def _check_samples(t, x):
    if t.ndim != 1 or x.shape[0] != t.shape[0]:
        raise ValueError(f"time has {t.shape} samples but the channels have {x.shape[0]}")
    if not np.all(np.isfinite(t)) or not np.all(np.isfinite(x)):
        raise ValueError("the signals contain NaN or infinite values")
    if not np.all(np.diff(t) > 0):
        i = int(np.argmax(np.diff(t) <= 0))
        raise ValueError(f"time is not strictly increasing (sample {i + 1}: {t[i + 1]} after {t[i]})")


def read_signals(path, sensors=None) -> dict:
    """Read a measurement file (CSV or .npz; columns in the module docstring).
    Returns `{column: array}` with `sensors` (default: every column named `x*`)
    checked; malformed files raise a ValueError naming the problem."""
    if not os.path.exists(path):
        raise ValueError(f"{path}: no such file")
    if path.endswith(".npz"):
        with np.load(path) as z:
            cols = {k: np.asarray(z[k], dtype=float) for k in z.files}
    else:
        try:
            data = np.genfromtxt(path, delimiter=",", names=True, dtype=float, encoding="utf-8")
        except ValueError as e:
            raise ValueError(f"{path}: not a CSV table with a header row ({e})") from None
        if data.dtype.names is None or data.size == 0:
            raise ValueError(f"{path}: not a CSV table with a header row and data")
        cols = {k: np.atleast_1d(np.asarray(data[k], dtype=float)) for k in data.dtype.names}
    sensors = sorted(k for k in cols if k.startswith("x")) if sensors is None else list(sensors)
    missing = [c for c in ["time", "tacho"] + sensors if c not in cols]
    if missing:
        raise ValueError(f"{path}: missing column(s) {', '.join(missing)}; found {', '.join(sorted(cols))}")
    if not sensors:
        raise ValueError(f"{path}: no sensor columns (named x1, x2, ...)")
    for c in ["time", "tacho"] + sensors:
        if not np.all(np.isfinite(cols[c])):
            raise ValueError(f"{path}: column {c!r} has NaN or missing values "
                             f"(first at row {int(np.argmax(~np.isfinite(cols[c])))})")
    cols["sensors"] = sensors
    return cols


def runs_from_signals(cols) -> list:
    """Split a file's columns by `run` and extract each run's phasors and trial
    weight: `[{"run", "speed", "X", "trial": (plane, complex unbalance) or None}]`."""
    labels = cols.get("run", np.zeros_like(cols["time"]))
    out = []
    for r in np.unique(labels):
        sel = labels == r
        t = cols["time"][sel]
        if not np.all(np.diff(t) > 0):
            raise ValueError(f"run {int(r)}: time is not strictly increasing")
        try:
            p = phasors(t, np.stack([cols[s][sel] for s in cols["sensors"]], axis=1), tacho=cols["tacho"][sel])
        except ValueError as e:
            raise ValueError(f"run {int(r)}: {e}") from None
        trial = None
        if "trial_plane" in cols and cols["trial_plane"][sel][0] >= 0:
            missing = [c for c in ("trial_unbalance", "trial_angle") if c not in cols]
            if missing:
                raise ValueError(f"run {int(r)} has a trial plane but no column(s) {', '.join(missing)}")
            trial = (int(cols["trial_plane"][sel][0]),
                     float(cols["trial_unbalance"][sel][0]) * np.exp(1j * np.radians(cols["trial_angle"][sel][0])))
        out.append({"run": int(r), "speed": p.speed, "X": p.X, "trial": trial,
                    "revolutions": p.revolutions, "residual_rms": p.residual_rms})
    return out
