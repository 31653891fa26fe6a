"""Precession of a whirling disk centre (model 004's precession index).

With the disk centre `(x, y)` at angle `psi = atan2(y, x)`, the precession speed is
`psi' = (x y' - y x') / (x^2 + y^2)` and the relative precession speed
`Lambda(t) = psi' / N`: `+1` synchronous forward whirl, `-1` synchronous backward
whirl. (The paper's footnote writes `psi'` with the opposite sign; we keep the
usual counter-clockwise angle, so that forward whirl, in the spin's direction, is
positive.) Its mean `<Lambda>` is computed from the unwrapped angle,
`(psi(t_end) - psi(t_start)) / (N (t_end - t_start))`, which, unlike the mean of
samples of `Lambda(t)`, is not spoiled by passages near the origin.
"""

import dataclasses

import numpy as np


@dataclasses.dataclass(frozen=True)
class Precession:
    """Precession of one run over its analysis window (see the module docstring).

    - `ts`, `Lambda`: the window's times and the relative precession speed;
    - `mean`: `<Lambda>`; `direction`: "forward", "backward" or "none";
    - `frequencies`, `spectrum`: one-sided amplitude spectrum of `Lambda(t)`, in
      cycles per time unit (the paper's `nu`);
    - `strobe_ts`, `strobe_x`, `strobe_y`: once-per-revolution samples;
    - `extrema_x`: the local extrema of `x` in the window (bifurcation diagrams).
    """

    ts: np.ndarray
    Lambda: np.ndarray
    mean: float
    direction: str
    frequencies: np.ndarray
    spectrum: np.ndarray
    strobe_ts: np.ndarray
    strobe_x: np.ndarray
    strobe_y: np.ndarray
    extrema_x: np.ndarray

    def as_dict(self, n_peaks=5):
        top = np.argsort(self.spectrum[1:])[::-1][:n_peaks] + 1
        return {"mean_Lambda": self.mean, "direction": self.direction,
                "spectrum_peaks": [{"frequency": float(self.frequencies[i]),
                                    "amplitude": float(self.spectrum[i])} for i in sorted(top)],
                "n_extrema": int(self.extrema_x.size),
                "extrema_x_range": ([float(self.extrema_x.min()), float(self.extrema_x.max())]
                                    if self.extrema_x.size else None)}


def precession(ts, x, y, vx, vy, N, window=(0.5, 1.0), tol=0.05) -> Precession:
    """Analyse the saved disk-centre motion `x, y` (velocities `vx, vy`) at equally
    spaced times `ts` over the fraction `window` of the run; `<Lambda>` within `tol`
    of 0 counts as no net precession."""
    ts, x, y, vx, vy = (np.asarray(a, dtype=float) for a in (ts, x, y, vx, vy))
    if not (ts.ndim == 1 and ts.size >= 8 and all(a.shape == ts.shape for a in (x, y, vx, vy))):
        raise ValueError("ts, x, y, vx, vy must be 1-D arrays of the same length (>= 8)")
    if not np.all(np.isfinite(np.stack([x, y, vx, vy]))):
        raise ValueError("the motion contains non-finite values (a failed run?)")
    if not N > 0:
        raise ValueError(f"N (spin speed) must be > 0, got {N}")
    lo, hi = window
    if not 0 <= lo < hi <= 1:
        raise ValueError(f"window must satisfy 0 <= start < end <= 1, got {window}")
    t0, t1 = ts[0] + lo * (ts[-1] - ts[0]), ts[0] + hi * (ts[-1] - ts[0])
    k = (ts >= t0) & (ts <= t1)
    t, xw, yw, vxw, vyw = ts[k], x[k], y[k], vx[k], vy[k]
    r2 = xw**2 + yw**2
    lam = np.where(r2 > 0, (xw * vyw - yw * vxw) / np.where(r2 > 0, r2, 1.0), 0.0) / N
    psi = np.unwrap(np.arctan2(yw, xw))
    mean = float((psi[-1] - psi[0]) / (N * (t[-1] - t[0])))
    direction = "forward" if mean > tol else "backward" if mean < -tol else "none"
    dt = t[1] - t[0]
    spec = np.abs(np.fft.rfft(lam - lam.mean())) * 2 / lam.size
    freqs = np.fft.rfftfreq(lam.size, dt)
    strobe = np.arange(np.ceil(t[0] * N / (2 * np.pi)), np.floor(t[-1] * N / (2 * np.pi)) + 1) * 2 * np.pi / N
    ext = np.where(((xw[1:-1] > xw[:-2]) & (xw[1:-1] >= xw[2:])) | ((xw[1:-1] < xw[:-2]) & (xw[1:-1] <= xw[2:])))[0] + 1
    return Precession(ts=t, Lambda=lam, mean=mean, direction=direction, frequencies=freqs, spectrum=spec,
                      strobe_ts=strobe, strobe_x=np.interp(strobe, t, xw), strobe_y=np.interp(strobe, t, yw),
                      extrema_x=xw[ext])
