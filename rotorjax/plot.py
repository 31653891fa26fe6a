"""Figures built from result objects (matplotlib is imported on first use)."""

import numpy as np


def _plt():
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    return plt


def _save(fig, path, axes=(), legend=True):
    """The common finish of every figure: grid, legend, layout, PNG, close."""
    for ax in axes:
        ax.grid(alpha=0.3)
        if legend:
            ax.legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(path, dpi=120)
    _plt().close(fig)
    return path


def _amplitude_axis(ax, values):
    ax.set_ylabel("whirl amplitude")
    v = np.asarray(values)
    v = v[np.isfinite(v) & (v > 0)]
    if v.size and v.max() / max(v.min(), 1e-300) > 1e3:
        ax.set_yscale("log")


def plot_simulation(result, path, title="", speed=None, x_label="time"):
    """Whirl amplitude and weight angles against time (or against `speed`, for a
    run-up: pass the speed at the saved times). Writes a PNG to `path`."""
    plt = _plt()
    out = result.outputs
    x = np.asarray(result.ts) if speed is None else np.asarray(speed)
    has_weights = "weight_angles" in out
    fig, axes = plt.subplots(2 if has_weights else 1, 1, figsize=(8, 6 if has_weights else 3.5),
                             sharex=True, squeeze=False)
    ax = axes[0, 0]
    amp = np.asarray(out["whirl_amplitude"])
    ax.plot(x, amp, lw=0.8)
    _amplitude_axis(ax, amp)
    ax.set_title(title)
    ax.grid(alpha=0.3)
    if has_weights:
        ax2 = axes[1, 0]
        ang = np.asarray(out["weight_angles"])
        for j in range(ang.shape[1]):
            ax2.plot(x, ang[:, j], ".", ms=1.5, label=f"weight {j + 1}")
        ax2.set_ylabel("weight angle rel. rotor (rad)")
        ax2.set_ylim(-np.pi, np.pi)
        ax2.legend(loc="upper right", fontsize=8)
        ax2.grid(alpha=0.3)
    axes[-1, 0].set_xlabel(x_label)
    if not bool(np.all(np.asarray(result.success))):
        fig.text(0.5, 0.5, f"FAILED: {result.message}", color="red", ha="center")
    fig.tight_layout()
    fig.savefig(path, dpi=120)
    plt.close(fig)
    return path


def plot_curves(x, curves: dict, path, x_label, y_label, title="", log=False, shade=None):
    """Several named curves on one axis; `shade` is an optional boolean mask over `x`
    drawn as a background band (e.g. where a criterion predicts balancing)."""
    plt = _plt()
    fig, ax = plt.subplots(figsize=(8, 4))
    if shade is not None:
        shade = np.asarray(shade)
        ax.fill_between(x, 0, 1, where=shade, color="tab:green", alpha=0.12,
                        transform=ax.get_xaxis_transform(), label="criterion: balancing")
    for label, y in curves.items():
        ax.plot(x, y, lw=1.0, label=label)
    if log:
        ax.set_yscale("log")
    ax.set_xlabel(x_label)
    ax.set_ylabel(y_label)
    ax.set_title(title)
    return _save(fig, path, [ax])


def plot_stability_map(x, y, margin, path, x_label, y_label, title=""):
    """Stability margin over a grid (`margin[i, j]` at `x[i], y[j]`), with the zero
    contour (the stability boundary at the grid's resolution)."""
    plt = _plt()
    m = np.asarray(margin, dtype=float)
    fig, ax = plt.subplots(figsize=(8, 5))
    lim = np.nanmax(np.abs(m)) if np.isfinite(m).any() else 1.0
    im = ax.pcolormesh(x, y, m.T, cmap="RdBu_r", vmin=-lim, vmax=lim, shading="auto")
    if np.nanmin(m) < 0 < np.nanmax(m):
        ax.contour(x, y, m.T, levels=[0.0], colors="k", linewidths=1.0)
    fig.colorbar(im, ax=ax, label="stability margin (< 0 stable)")
    ax.set_xlabel(x_label)
    ax.set_ylabel(y_label)
    ax.set_title(title)
    fig.tight_layout()
    fig.savefig(path, dpi=120)
    plt.close(fig)
    return path


def plot_campbell(speeds, frequencies, forward, path, critical=(), title=""):
    """Campbell diagram: damped natural frequencies against speed, forward whirl
    solid red, backward dashed blue, with the 1x line and the critical speeds."""
    plt = _plt()
    fig, ax = plt.subplots(figsize=(8, 5))
    f, fw = np.asarray(frequencies), np.asarray(forward)
    for k in range(f.shape[1]):
        ax.plot(speeds, np.where(fw[:, k], f[:, k], np.nan), "-", color="tab:red", lw=1.2,
                label="forward" if k == 0 else None)
        ax.plot(speeds, np.where(~fw[:, k], f[:, k], np.nan), "--", color="tab:blue", lw=1.2,
                label="backward" if k == 0 else None)
    ax.plot(speeds, speeds, "k:", lw=1, label="1x")
    for c in critical:
        ax.plot([c], [c], "ko", ms=4)
    ax.set_xlabel("speed (rad/s)")
    ax.set_ylabel("damped natural frequency (rad/s)")
    ax.set_ylim(0, np.nanmax(f) * 1.05)
    ax.set_title(title)
    return _save(fig, path, [ax])


def plot_response(speeds, X, Y, path, title=""):
    """Unbalance response amplitude (log) and phase of x and y against speed."""
    plt = _plt()
    fig, (a1, a2) = plt.subplots(2, 1, figsize=(8, 6), sharex=True)
    for z, label in ((X, "x"), (Y, "y")):
        a1.semilogy(speeds, np.abs(z), label=label)
        a2.plot(speeds, np.degrees(np.angle(z)), label=label)
    a1.set_ylabel("amplitude (m)")
    a2.set_ylabel("phase (deg)")
    a2.set_xlabel("speed (rad/s)")
    a1.set_title(title)
    return _save(fig, path, [a1, a2])


def plot_precession(result, prec, path, title="", clearance=None):
    """Model 004 run: disk-centre orbit (window, with the once-per-revolution
    samples), the relative precession speed `Lambda(t)` and its spectrum."""
    plt = _plt()
    out = result.outputs
    ts, x, y = np.asarray(result.ts), np.asarray(out["disk_x"]), np.asarray(out["disk_y"])
    k = ts >= prec.ts[0]
    fig, axes = plt.subplots(2, 2, figsize=(11, 8))
    ax = axes[0, 0]
    ax.plot(x[k], y[k], lw=0.4, label="disk centre")
    ax.plot(prec.strobe_x, prec.strobe_y, ".", color="C3", ms=3, label="once per revolution")
    if clearance is not None:
        a = np.linspace(0, 2 * np.pi, 200)
        ax.plot(clearance * np.cos(a), clearance * np.sin(a), "k:", lw=0.8, label="clearance")
    ax.set_aspect("equal")
    ax.set_xlabel("x / l")
    ax.set_ylabel("y / l")
    ax = axes[0, 1]
    ax.plot(ts, x, lw=0.4, label="x")
    ax.set_xlabel("time")
    ax.set_ylabel("disk x / l")
    ax = axes[1, 0]
    ax.plot(prec.ts, np.clip(prec.Lambda, -5, 5), lw=0.4, label="Lambda(t)")
    ax.axhline(prec.mean, color="C3", label=f"<Lambda> = {prec.mean:.4f}")
    ax.set_xlabel("time")
    ax.set_ylabel("Lambda = psi' / N")
    ax = axes[1, 1]
    ax.plot(prec.frequencies, prec.spectrum, lw=0.6, label="|FFT Lambda|")
    ax.set_xlabel("frequency (cycles per time unit)")
    ax.set_yscale("log")
    fig.suptitle(title)
    return _save(fig, path, axes.ravel())


def plot_bifurcation(values, extrema, mean_lambda, path, param, title=""):
    """Extrema diagram of the disk's x against a swept parameter, with <Lambda>."""
    plt = _plt()
    fig, axes = plt.subplots(2, 1, figsize=(8, 7), sharex=True)
    for v, ext, lam in zip(values, extrema, mean_lambda):
        axes[0].plot(np.full(len(ext), v), ext, ".", ms=1.5, color="C3" if lam < 0 else "k")
    axes[0].set_ylabel("extrema of disk x / l")
    axes[1].plot(values, mean_lambda, "o-", ms=3, label="<Lambda>")
    axes[1].axhline(0, color="k", lw=0.6)
    axes[1].set_xlabel(param)
    axes[1].set_ylabel("<Lambda>")
    fig.suptitle(title)
    return _save(fig, path, axes[1:])
