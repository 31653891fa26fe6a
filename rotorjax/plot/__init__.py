"""Figures built from result objects (matplotlib is imported on first use).

Every function draws on the axes `ax=` (or the figure `fig=`, where it draws several
panels) it is given, or on a new pyplot figure, and returns the `Figure`: in a
notebook it shows like any matplotlib figure, and the caller saves it where it
likes. Nothing here chooses a matplotlib backend or writes a file:
the CLI picks the non-interactive one (Agg) and saves its PNGs
(`rotorjax.cli._common.save_figure`). The `path` arguments of the earlier
file-writing versions are still accepted, and ignored with a `FutureWarning`.
"""

import re
import textwrap
import warnings

import numpy as np


def _plt():
    import matplotlib.pyplot as plt

    return plt


def _unwritten(path, name, stacklevel=4):
    """The file-writing versions' `path`: still accepted, not written (a warning says so)."""
    if path is not None:
        warnings.warn(f"{name}: rotorjax.plot draws and returns the Figure but no longer writes it; "
                      f"{str(path)!r} is not written: save the returned Figure", FutureWarning,
                      stacklevel=stacklevel)


def _on_axes(ax, figsize, path=None, name="plot"):
    """`(figure, axes, layout)`: the given `ax` and its figure (whose layout is the
    caller's), or a new pyplot figure of `figsize` with one axes (laid out here)."""
    _unwritten(path, name)
    if ax is None:
        fig, ax = _plt().subplots(figsize=figsize)
        return fig, ax, True
    return ax.figure, ax, False


def _on_figure(fig, figsize, path=None, name="plot"):
    """`(figure, layout)`: the given (empty) `fig`, laid out here unless it has a
    layout engine of its own, or a new pyplot figure of `figsize`."""
    _unwritten(path, name)
    if fig is None:
        return _plt().figure(figsize=figsize), True
    return fig, fig.get_layout_engine() is None


def _wrap_to_width(text, original, width, renderer):
    """Wrap `original` (its own line breaks kept) at word boundaries into the `Text`
    until it is at most `width` display units wide."""
    lines = original.split("\n")
    n = max(len(line) for line in lines)
    while n > 12:
        wide = text.get_window_extent(renderer).width
        if wide <= width:
            return
        n = min(n - 1, int(n * width / wide))
        text.set_text("\n".join(textwrap.fill(line, max(n, 12), break_on_hyphens=False) or line
                                for line in lines))


def _titles(fig):
    """The figure's title and every axes' titles that have text, each with the width
    of its slot: the figure's for `suptitle`, an axes' share of the subplots' width
    (a colorbar's gridspec nests in it) for an axes title."""
    width = fig.bbox.width
    slots = [(fig._suptitle, 0.96 * width)] if fig._suptitle is not None else []
    pars = fig.subplotpars
    for ax in fig.axes:
        spec = ax.get_subplotspec()
        if spec is None:    # a colorbar or an inset: no title of its own
            continue
        share = min(1.0, spec.get_position(fig).width / (pars.right - pars.left))
        slots += [(t, 0.92 * width * share) for t in (ax.title, ax._left_title, ax._right_title)]
    return [(t, room) for t, room in slots if t.get_text()]


def _fit_titles_and_layout(fig):
    """Wrap the titles to their slots, lay the figure out (`tight_layout`), and wrap
    again any title that still crosses the figure's edge (an axes title is centred
    on its axes, which the tick labels push off the figure's centre): the CLI's
    titles name the preset, the input, the output and the running condition, longer
    than a narrow figure (a 6-inch polar plot) is wide."""
    renderer = fig._get_renderer()   # any canvas (an Agg one, or a notebook's)
    slots = [(t, t.get_text(), room) for t, room in _titles(fig)]
    for text, original, room in slots:
        _wrap_to_width(text, original, room, renderer)
    fig.tight_layout()
    edge, moved = 0.01 * fig.bbox.width, False
    for text, original, _ in slots:
        box = text.get_window_extent(renderer)
        over = max(fig.bbox.x0 + edge - box.x0, box.x1 - (fig.bbox.x1 - edge))
        if over > 0:
            _wrap_to_width(text, original, box.width - 2 * over, renderer)
            moved = True
    if moved:
        fig.tight_layout()


def _finish(fig, axes=(), legend=True, layout=True):
    """The common finish of every figure: grid, legend, and (with `layout`) the
    titles wrapped to fit and the layout. Returns `fig`."""
    for ax in axes:
        ax.grid(alpha=0.3)
        if legend:
            ax.legend(fontsize=8)
    if layout:
        _fit_titles_and_layout(fig)
    return fig


def _amplitude_axis(ax, values, label="whirl amplitude"):
    ax.set_ylabel(label)
    v = np.asarray(values)
    v = v[np.isfinite(v) & (v > 0)]
    if v.size and v.max() / max(v.min(), 1e-300) > 1e3:
        ax.set_yscale("log")


def _time_axis_label(x_label, time_unit=None):
    """The x label of a run: `x_label` ("time" or "speed") with the unit made of
    `time_unit` ("time (s)", "speed (rad/s)"; "time (1/Omega)" for a dimensionless
    time). A label in the form "time (time unit s)" is read as the quantity and
    its time unit, so the word is not said twice."""
    old = re.fullmatch(r"\s*(\S+)\s*\(time unit (.+)\)\s*", x_label)
    if old:
        x_label, time_unit = old.group(1), time_unit or old.group(2)
    if time_unit is None:
        return x_label
    if x_label == "speed":
        return "speed (rad/s)" if time_unit == "s" else f"speed (rad per {time_unit})"
    return f"{x_label} ({time_unit})"


def plot_simulation(result, path=None, title="", speed=None, x_label="time", time_unit=None, node=None, unit=None,
                    amplitude_label=None, *, fig=None):
    """Whirl amplitude and weight angles against time (or against `speed`, for a
    run-up: pass the speed at the saved times), on `fig` (one or two panels) or a
    new figure.

    **Arguments:**

    - `x_label`: "time" or "speed" (an older "time (time unit s)" is understood).
    - `time_unit`: the preset's time unit ("s", "1/Omega"): the x label becomes
      "time (s)", "speed (rad/s)".
    - `node`: plot the orbit radius `hypot(node_x, node_y)` of this node (a rotor
      scene's outputs) instead of the `whirl_amplitude` output (the largest over
      the nodes for a rotor scene).
    - `unit`: the amplitude's unit (the preset's length unit); a rotor scene's
      amplitudes are in m without it.
    - `amplitude_label`: the amplitude axis's name, before the unit.
    - `fig`: an empty figure to draw on (default: a new one).

    **Returns:** the `Figure`.
    """
    out = result.outputs
    x = np.asarray(result.ts) if speed is None else np.asarray(speed)
    has_weights = "weight_angles" in out
    nodes = "node_x" in out     # a rotor scene: every node's x, y in m
    if node is not None:
        if not nodes:
            raise ValueError(f"node={node}: the result has no node_x, node_y outputs (only a rotor scene's has)")
        amp = np.hypot(np.asarray(out["node_x"])[:, node], np.asarray(out["node_y"])[:, node])
        name = f"whirl amplitude at node {node}"
    else:
        amp = np.asarray(out["whirl_amplitude"])
        name = "whirl amplitude, largest over the nodes" if nodes else "whirl amplitude"
    unit = "m" if unit is None and nodes else unit
    label = (amplitude_label or name) + (f" ({unit})" if unit else "")
    fig, layout = _on_figure(fig, (8, 6 if has_weights else 3.5), path, "plot_simulation")
    axes = fig.subplots(2 if has_weights else 1, 1, sharex=True, squeeze=False)
    ax = axes[0, 0]
    ax.plot(x, amp, lw=0.8)
    _amplitude_axis(ax, amp, label)
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
    axes[-1, 0].set_xlabel(_time_axis_label(x_label, time_unit))
    if not bool(np.all(np.asarray(result.success))):
        fig.text(0.5, 0.5, f"FAILED: {result.message}", color="red", ha="center")
    return _finish(fig, layout=layout)


def plot_curves(x, curves: dict, path=None, x_label="", y_label="", title="", log=False, shade=None, *, ax=None):
    """Several named curves on one axis (`ax`, or a new figure's), each `y` over
    `x` or a pair `(x_i, y_i)` of its own; `shade` is an optional boolean mask over
    `x` drawn as a background band (e.g. where a criterion predicts balancing).
    Returns the `Figure`."""
    fig, ax, layout = _on_axes(ax, (8, 4), path, "plot_curves")
    if shade is not None:
        shade = np.asarray(shade)
        ax.fill_between(x, 0, 1, where=shade, color="tab:green", alpha=0.12,
                        transform=ax.get_xaxis_transform(), label="criterion: balancing")
    for label, y in curves.items():
        ax.plot(*(y if isinstance(y, tuple) else (x, y)), lw=1.0, label=label)
    if log:
        ax.set_yscale("log")
    ax.set_xlabel(x_label)
    ax.set_ylabel(y_label)
    ax.set_title(title)
    return _finish(fig, [ax], layout=layout)


def plot_stability_map(x, y, margin, path=None, x_label="", y_label="", title="", *, ax=None):
    """Stability margin over a grid (`margin[i, j]` at `x[i], y[j]`), with the zero
    contour (the stability boundary at the grid's resolution), on `ax` (its colorbar
    beside it) or a new figure. Returns the `Figure`."""
    m = np.asarray(margin, dtype=float)
    fig, ax, layout = _on_axes(ax, (8, 5), path, "plot_stability_map")
    lim = np.nanmax(np.abs(m)) if np.isfinite(m).any() else 1.0
    im = ax.pcolormesh(x, y, m.T, cmap="RdBu_r", vmin=-lim, vmax=lim, shading="auto")
    if np.nanmin(m) < 0 < np.nanmax(m):
        ax.contour(x, y, m.T, levels=[0.0], colors="k", linewidths=1.0)
    fig.colorbar(im, ax=ax, label="stability margin (< 0 stable)")
    ax.set_xlabel(x_label)
    ax.set_ylabel(y_label)
    ax.set_title(title)
    return _finish(fig, layout=layout)


def plot_campbell(speeds, frequencies, forward, path=None, critical=(), title="", unit="rad/s", *, ax=None,
                  frequency_unit=None):
    """Campbell diagram: damped natural frequencies against speed, forward whirl
    solid red, backward dashed blue, with the 1x line and the critical speeds
    (`unit`: of the speeds, and of the frequencies unless `frequency_unit` names
    theirs: rpm and cpm, say), on `ax` or a new figure. Returns the `Figure`."""
    fig, ax, layout = _on_axes(ax, (8, 5), path, "plot_campbell")
    f, fw = np.asarray(frequencies), np.asarray(forward)
    for k in range(f.shape[1]):
        ax.plot(speeds, np.where(fw[:, k], f[:, k], np.nan), "-", color="tab:red", lw=1.2,
                label="forward" if k == 0 else None)
        ax.plot(speeds, np.where(~fw[:, k], f[:, k], np.nan), "--", color="tab:blue", lw=1.2,
                label="backward" if k == 0 else None)
    ax.plot(speeds, speeds, "k:", lw=1, label="1x")
    for i, c in enumerate(critical):
        ax.plot([c], [c], "ko", ms=4, label="critical speed (1x crossing)" if i == 0 else None)
    ax.set_xlabel(f"speed ({unit})")
    ax.set_ylabel(f"damped natural frequency ({frequency_unit or unit})")
    ax.set_ylim(0, max(np.nanmax(f), np.max(speeds)) * 1.05)
    ax.set_title(title)
    return _finish(fig, [ax], layout=layout)


def plot_response(speeds, X, Y, path=None, title="", *, fig=None, speed_unit="rad/s", amplitude_unit="m"):
    """Unbalance response amplitude (log) and phase of x and y against speed, two
    panels on `fig` (empty) or a new figure (the axes labelled in `speed_unit` and
    `amplitude_unit`: the numbers are given in them). Returns the `Figure`."""
    fig, layout = _on_figure(fig, (8, 6), path, "plot_response")
    a1, a2 = fig.subplots(2, 1, sharex=True)
    for z, label in ((X, "x"), (Y, "y")):
        a1.semilogy(speeds, np.abs(z), label=label)
        a2.plot(speeds, np.degrees(np.angle(z)), label=label)
    a1.set_ylabel(f"amplitude ({amplitude_unit})")
    a2.set_ylabel("phase (deg)")
    a2.set_xlabel(f"speed ({speed_unit})")
    a1.set_title(title)
    return _finish(fig, [a1, a2], layout=layout)


def plot_precession(result, prec, path=None, title="", clearance=None, *, fig=None):
    """Model 004 run: disk-centre orbit (window, with the once-per-revolution
    samples), the relative precession speed `Lambda(t)` and its spectrum: four
    panels on `fig` (empty) or a new figure. Returns the `Figure`."""
    fig, layout = _on_figure(fig, (11, 8), path, "plot_precession")
    out = result.outputs
    ts, x, y = np.asarray(result.ts), np.asarray(out["disk_x"]), np.asarray(out["disk_y"])
    k = ts >= prec.ts[0]
    axes = fig.subplots(2, 2)
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
    return _finish(fig, axes.ravel(), layout=layout)


def plot_bifurcation(values, extrema, mean_lambda, path=None, param="", title="", *, fig=None):
    """Extrema diagram of the disk's x against a swept parameter, with <Lambda>: two
    panels on `fig` (empty) or a new figure. Returns the `Figure`."""
    fig, layout = _on_figure(fig, (8, 7), path, "plot_bifurcation")
    axes = fig.subplots(2, 1, sharex=True)
    for v, ext, lam in zip(values, extrema, mean_lambda):
        axes[0].plot(np.full(len(ext), v), ext, ".", ms=1.5, color="C3" if lam < 0 else "k")
    axes[0].set_ylabel("extrema of disk x / l")
    axes[1].plot(values, mean_lambda, "o-", ms=3, label="<Lambda>")
    axes[1].axhline(0, color="k", lw=0.6)
    axes[1].set_xlabel(param)
    axes[1].set_ylabel("<Lambda>")
    fig.suptitle(title)
    return _finish(fig, axes[1:], layout=layout)


# --- one picture per CLI analysis ------------------------------------------------------

#: How a regime's verdict is drawn: filled for stable, hollow red for unstable.
_VERDICT_STYLE = {
    "stable": dict(marker="o", color="tab:blue", mfc="tab:blue", label="stable"),
    "unstable": dict(marker="o", color="tab:red", mfc="none", label="unstable"),
    "marginal": dict(marker="D", color="tab:orange", mfc="none", label="marginal"),
}


def _verdict_style(verdict):
    return _VERDICT_STYLE.get(verdict, dict(marker="s", color="tab:gray", mfc="none", label=str(verdict)))


def plot_steady_regimes(path=None, regimes=None, title="", x_label="weight angle relative to the rotor (rad)",
                        y_label="whirl amplitude (dimensionless)", *, ax=None):
    """Stationary regimes of a rotor with an automatic balancer on the plane (weight
    angle, whirl amplitude): a regime is one marker per weight at
    `(weight_angles[j], whirl_amplitude)`, the markers of one regime joined by a
    thin line and numbered as in `regimes`; filled markers for stable regimes,
    hollow red for unstable ones. A regime without weights is drawn as a
    horizontal line at its amplitude.

    **Arguments:**

    - `regimes`: dicts with `weight_angles` (rad, possibly empty), `whirl_amplitude`
      (float), `verdict` ("stable", "unstable", "marginal") and `kind`, e.g. the
      `regimes` of `rotorjax steady --json`. For regimes without weight angles
      (the modal model 003) use `plot_regime_amplitudes`.
    - `title`: the run's parameters.
    - `ax`: the axes to draw on (default: a new figure's); `path`: ignored (the
      file-writing version's), give `regimes` and `title` by keyword.

    **Returns:** the `Figure`.
    """
    if regimes is None:
        raise TypeError("plot_steady_regimes: missing the argument 'regimes'")
    missing = [i + 1 for i, r in enumerate(regimes) if "weight_angles" not in r]
    if missing:
        raise ValueError(f"regimes {missing} have no 'weight_angles'; plot regimes given by kind and "
                         "amplitude with plot_regime_amplitudes")
    fig, ax, layout = _on_axes(ax, (8, 5), path, "plot_steady_regimes")
    seen = set()
    for i, r in enumerate(regimes):
        st = dict(_verdict_style(r["verdict"]))
        label = st.pop("label")
        amp = float(r["whirl_amplitude"])
        ang = np.asarray(r["weight_angles"], dtype=float).ravel()
        if ang.size == 0:
            ax.axhline(amp, color=st["color"], lw=1.0, ls="-" if r["verdict"] == "stable" else "--",
                       label=f"{label} (no weights)" if (label, 0) not in seen else None)
            seen.add((label, 0))
            continue
        ax.plot(ang, np.full(ang.size, amp), "-", color=st["color"], lw=0.6, alpha=0.6)
        ax.plot(ang, np.full(ang.size, amp), ls="none", ms=8, mew=1.5,
                label=label if (label, 1) not in seen else None, **st)
        seen.add((label, 1))
        ax.annotate(str(i + 1), (ang[0], amp), textcoords="offset points", xytext=(6, 6), fontsize=8)
    ax.set_xlim(-np.pi - 0.2, np.pi + 0.2)
    ax.set_xticks(np.arange(-1, 1.01, 0.5) * np.pi, ["-pi", "-pi/2", "0", "pi/2", "pi"])
    top = max([float(r["whirl_amplitude"]) for r in regimes] + [0.0])
    ax.set_ylim(-0.05 * top if top > 0 else -1, 1.12 * top if top > 0 else 1)
    ax.set_xlabel(x_label)
    ax.set_ylabel(y_label)
    ax.set_title(title + "\n(numbers: regime index; one marker per weight, a line joins one regime)",
                 fontsize=10)
    if not regimes:
        ax.text(0.5, 0.5, "no stationary regime found", transform=ax.transAxes, ha="center")
    return _finish(fig, [ax], legend=bool(regimes), layout=layout)


def plot_regime_amplitudes(path=None, regimes=None, title="", y_label="disk amplitude (dimensionless)",
                           amplitude_key="disk_amplitude", *, ax=None):
    """Stationary regimes given by kind and amplitude (model 003: "C", "PS", "NS1",
    ...): the amplitude of each regime over a categorical axis of kinds (in order
    of first appearance; several regimes of one kind side by side), filled for
    stable, hollow red for unstable.

    **Arguments:**

    - `regimes`: dicts with `kind`, `verdict` and the amplitude under
      `amplitude_key` (e.g. the `regimes` of `rotorjax steady flexible-abb --json`);
      an optional `sigma` is written next to the marker.
    - `title`: the run's parameters.
    - `ax`: the axes to draw on (default: a new figure's); `path`: ignored (the
      file-writing version's), give `regimes` and `title` by keyword.

    **Returns:** the `Figure`.
    """
    if regimes is None:
        raise TypeError("plot_regime_amplitudes: missing the argument 'regimes'")
    fig, ax, layout = _on_axes(ax, (8, 4.5), path, "plot_regime_amplitudes")
    kinds = list(dict.fromkeys(str(r["kind"]) for r in regimes))
    count = {k: sum(str(r["kind"]) == k for r in regimes) for k in kinds}
    placed = {k: 0 for k in kinds}
    seen = set()
    for r in regimes:
        k = str(r["kind"])
        j = placed[k]
        placed[k] += 1
        x = kinds.index(k) + (j - (count[k] - 1) / 2) * min(0.6 / count[k], 0.2)
        st = dict(_verdict_style(r["verdict"]))
        label = st.pop("label")
        amp = float(r[amplitude_key])
        ax.plot([x], [amp], ls="none", ms=9, mew=1.5, label=label if label not in seen else None, **st)
        seen.add(label)
        if r.get("sigma") is not None:
            ax.annotate(f"sigma={r['sigma']:g}", (x, amp), textcoords="offset points", xytext=(6, 4),
                        fontsize=7)
    amps = [float(r[amplitude_key]) for r in regimes if np.isfinite(float(r[amplitude_key]))]
    top = max(amps + [0.0])
    if top > 0:
        ax.set_ylim(min(amps + [0.0]) - 0.05 * top, 1.12 * top)     # room for the sigma labels
    ax.set_xticks(range(len(kinds)), kinds)
    ax.set_xlim(-0.6, max(len(kinds), 1) - 0.4)
    ax.set_xlabel("regime kind")
    ax.set_ylabel(y_label)
    ax.set_title(title, fontsize=10)
    if not regimes:
        ax.text(0.5, 0.5, "no stationary regime found", transform=ax.transAxes, ha="center")
    return _finish(fig, [ax], legend=bool(regimes), layout=layout)


def plot_margin(path=None, speeds=None, margin=None, roots=None, title="", speed_label="speed",
                margin_label="stability margin", root_label="critical speed", extra_roots=None, extra_label=None, *,
                ax=None):
    """Stability margin against speed (largest real part of the eigenvalues, or
    largest Floquet exponent): the curve, the zero line, the stable region
    (margin < 0) shaded, the located `roots` as dots on the zero line with dotted
    verticals, and optionally a second set `extra_roots` (e.g. an empirical
    criterion's roots) as crosses.

    **Arguments:**

    - `speeds`, `margin`: 1-D arrays of one length (non-finite margins are gaps).
    - `roots`, `extra_roots`: speeds (floats) where the margin is zero.
    - `speed_label`, `margin_label`: axis labels with units (or "dimensionless").
    - `title`: the run's parameters.
    - `ax`: the axes to draw on (default: a new figure's); `path`: ignored (the
      file-writing version's), give the other arguments by keyword.

    **Returns:** the `Figure`.
    """
    if speeds is None or margin is None:
        raise TypeError("plot_margin: missing the argument 'speeds' or 'margin'")
    speeds = np.asarray(speeds, dtype=float)
    m = np.asarray(margin, dtype=float)
    fig, ax, layout = _on_axes(ax, (8, 4.5), path, "plot_margin")
    stable = np.isfinite(m) & (m < 0)
    ax.fill_between(speeds, 0, 1, where=stable, color="tab:green", alpha=0.12, step="mid",
                    transform=ax.get_xaxis_transform(), label="stable (margin < 0)")
    ax.plot(speeds, m, color="k", lw=1.2, label="margin")
    ax.axhline(0.0, color="0.4", lw=0.8)
    roots = [] if roots is None else [float(r) for r in np.ravel(roots)]
    for r in roots:
        ax.axvline(r, color="tab:red", ls=":", lw=0.9)
    if roots:
        ax.plot(roots, np.zeros(len(roots)), "o", color="tab:red", ms=6, ls="none",
                label=f"{root_label}: " + ", ".join(f"{r:.4g}" for r in roots))
    extra = [] if extra_roots is None else [float(r) for r in np.ravel(extra_roots)]
    if extra:
        ax.plot(extra, np.zeros(len(extra)), "x", color="tab:purple", ms=9, mew=2, ls="none",
                label=f"{extra_label or 'other roots'}: " + ", ".join(f"{r:.4g}" for r in extra))
    if not np.any(np.isfinite(m)):
        ax.text(0.5, 0.5, "no finite margin", transform=ax.transAxes, ha="center", color="red")
    ax.set_xlabel(speed_label)
    ax.set_ylabel(margin_label)
    ax.set_title(title, fontsize=10)
    return _finish(fig, [ax], layout=layout)


def _arrow(ax, angle, radius, color, ls="-", lw=1.6):
    ax.annotate("", xy=(angle, radius), xytext=(0.0, 0.0),
                arrowprops=dict(arrowstyle="-|>", color=color, lw=lw, ls=ls, shrinkA=0, shrinkB=0))


def plot_balance(path=None, before=None, after=None, corrections=None, title="", unit="m", planes=None,
                 mass_unit="g", *, fig=None):
    """Two-plane (or more) balancing on polar axes. Left: the 1x vibration phasors
    per sensor, measured before (solid) and predicted after the correction
    (dashed). Right: the correction per plane, a mass at an angle. Angles are
    measured from the once-per-revolution mark in the direction of rotation
    (counter-clockwise on the plot).

    **Arguments:**

    - `before`, `after`: complex phasors, one per sensor (in `unit`).
    - `corrections`: complex correction masses, one per plane: `|c|` in
      `mass_unit` at the angle `arg c` (e.g. `W / radius * 1e3` for `W` in kg m
      and grams).
    - `planes`: the plane numbers (default 1, 2, ...).
    - `title`: the run's parameters.
    - `fig`: an empty figure to draw the two polar panels on (default: a new one);
      `path`: ignored (the file-writing version's), give the others by keyword.

    **Returns:** the `Figure` (its legends hang below the axes: save it with
    `bbox_inches="tight"`).
    """
    if before is None or after is None or corrections is None:
        raise TypeError("plot_balance: missing the argument 'before', 'after' or 'corrections'")
    before = np.atleast_1d(np.asarray(before, dtype=complex))
    after = np.atleast_1d(np.asarray(after, dtype=complex))
    corr = np.atleast_1d(np.asarray(corrections, dtype=complex))
    planes = list(range(1, corr.size + 1)) if planes is None else list(planes)
    fig, layout = _on_figure(fig, (11, 5.5), path, "plot_balance")
    a1 = fig.add_subplot(1, 2, 1, projection="polar")
    a2 = fig.add_subplot(1, 2, 2, projection="polar")
    from matplotlib.lines import Line2D

    rmax = max(float(np.max(np.abs(np.concatenate([before, after])))), 1e-300)
    # radii in a power of ten of `unit` named in the title, not as an offset text that
    # polar axes put on top of the angle labels
    e = int(np.floor(np.log10(rmax)))
    scale, scaled_unit = (1.0, unit) if -2 <= e <= 2 else (10.0**-e, f"1e{e} {unit}")
    rmax *= scale
    before, after = before * scale, after * scale
    for i, (b, a) in enumerate(zip(before, after)):
        _arrow(a1, np.angle(b), abs(b), "tab:blue")
        _arrow(a1, np.angle(a), abs(a), "tab:green", ls="--")
        a1.annotate(f"S{i + 1}", (np.angle(b), abs(b)), textcoords="offset points", xytext=(4, 4),
                    fontsize=8, color="tab:blue")
        a1.annotate(f"S{i + 1}", (np.angle(a), abs(a)), textcoords="offset points", xytext=(4, -10),
                    fontsize=8, color="tab:green")
    a1.set_rmax(1.1 * rmax)
    a1.legend([Line2D([], [], color="tab:blue"), Line2D([], [], color="tab:green", ls="--")],
              ["measured before: " + ", ".join(f"{abs(b) / scale:.3g}" for b in before) + f" {unit}",
               "predicted after: " + ", ".join(f"{abs(a) / scale:.3g}" for a in after) + f" {unit}"],
              fontsize=8, loc="upper center", bbox_to_anchor=(0.5, -0.1))
    a1.set_title(f"1x vibration per sensor S1, S2, ... (radius: amplitude, {scaled_unit})", fontsize=9, pad=18)
    a1.set_xlabel("phase from the once-per-revolution mark (deg)", fontsize=8)
    cmax = max(float(np.max(np.abs(corr))) if corr.size else 0.0, 1e-300)
    handles, labels = [], []
    for k, (p, c) in enumerate(zip(planes, corr)):
        color = f"C{(k + 3) % 10}"
        _arrow(a2, np.angle(c), abs(c), color, lw=2.0)
        a2.plot([np.angle(c)], [abs(c)], "o", color=color, ms=7)
        handles.append(Line2D([], [], color=color, marker="o"))
        labels.append(f"plane {p}: {abs(c):.1f} {mass_unit} at {np.degrees(np.angle(c)) % 360:.0f} deg")
    a2.set_rmax(1.15 * cmax)
    a2.legend(handles, labels, fontsize=8, loc="upper center", bbox_to_anchor=(0.5, -0.1))
    a2.set_title(f"correction masses (radius: mass, {mass_unit})", fontsize=9, pad=18)
    a2.set_xlabel("angle from the once-per-revolution mark (deg)", fontsize=8)
    for ax in (a1, a2):
        ax.grid(alpha=0.3)
    fig.suptitle(title + "\nangles from the once-per-revolution mark, positive in the direction of "
                 "rotation (counter-clockwise here)", fontsize=10)
    return _finish(fig, layout=layout)


def _break_wraps(x, deg):
    """A gap (NaN) where a phase in degrees wraps past +-180, instead of a vertical line."""
    cut = np.flatnonzero(np.abs(np.diff(deg)) > 180) + 1
    return np.insert(np.asarray(x, dtype=float), cut, np.nan), np.insert(deg, cut, np.nan)


def plot_identification(path=None, speeds=None, data=None, fit=None, lo=None, hi=None, title="", channels=None,
                        unit="m", speed_label="speed (rad/s)", level=0.95, *, fig=None):
    """Identification on a Bode plot: measured 1x phasors (dots) against the fitted
    model (lines), amplitude (log scale) above and phase below, with the model's
    confidence band on the amplitude (from `rotorjax.identify.response_band`) shaded.

    **Arguments:**

    - `speeds`: shape `(n,)` (rad/s).
    - `data`, `fit`: complex, shape `(n, c)`: measured and model phasors (in `unit`).
    - `lo`, `hi`: the band's edges on `|fit|`, shape `(n, c)`.
    - `channels`: `c` names (e.g. `["x1", "x2"]`).
    - `title`: the run's parameters.
    - `fig`: an empty figure to draw the two panels on (default: a new one);
      `path`: ignored (the file-writing version's), give the others by keyword.

    **Returns:** the `Figure`.
    """
    if any(v is None for v in (speeds, data, fit, lo, hi, channels)):
        raise TypeError("plot_identification: give speeds, data, fit, lo, hi and channels")
    w = np.asarray(speeds, dtype=float)
    data, fit = (np.asarray(v, dtype=complex).reshape(w.size, -1) for v in (data, fit))
    lo, hi = (np.asarray(v, dtype=float).reshape(w.size, -1) for v in (lo, hi))
    order = np.argsort(w)
    fig, layout = _on_figure(fig, (9, 7), path, "plot_identification")
    a1, a2 = fig.subplots(2, 1, sharex=True)
    for j, name in enumerate(channels):
        c = f"C{j}"
        a1.fill_between(w[order], np.maximum(lo[order, j], 1e-300), hi[order, j], color=c, alpha=0.25,
                        lw=0, label=f"{name} model {100 * level:.0f} % band")
        a1.plot(w, np.abs(data[:, j]), ".", color=c, ms=3, alpha=0.6, label=f"{name} measured")
        a1.plot(w[order], np.abs(fit[order, j]), "-", color=c, lw=1.3, label=f"{name} model")
        a2.plot(w, np.degrees(np.angle(data[:, j])), ".", color=c, ms=3, alpha=0.6, label=f"{name} measured")
        a2.plot(*_break_wraps(w[order], np.degrees(np.angle(fit[order, j]))), "-", color=c, lw=1.3,
                label=f"{name} model")
    a1.set_yscale("log")
    a1.set_ylabel(f"1x amplitude ({unit})")
    a2.set_ylabel("phase (deg, from the once-per-rev mark)")
    a2.set_ylim(-180, 180)
    a2.set_yticks(np.arange(-180, 181, 90))
    a2.set_xlabel(speed_label)
    a1.set_title(title, fontsize=10)
    return _finish(fig, [a1, a2], layout=layout)


def plot_fe_identification(path=None, result=None, title="", unit="m", *, fig=None):
    """A rotor file's `Identification` on a Bode plot per channel (run, node, direction):
    measured phasors (dots) against the fitted model (lines), amplitude and phase,
    and below the scaled residuals `(model - measured) / sigma` (real and
    imaginary parts) against speed (frequency for receptances): three panels on
    `fig` (empty) or a new figure. `path` is ignored (the file-writing version's).
    Returns the `Figure`."""
    if result is None:
        raise TypeError("plot_fe_identification: missing the argument 'result'")
    d = result.data
    x = np.asarray(d.frequency if d.kind == "frf" else d.speed, dtype=float)
    if d.kind == "frf":
        keys = list(zip(d.input_node.tolist(), d.input_direction.tolist(), d.node.tolist(), d.direction.tolist(),
                        d.speed.tolist()))
        name = {k: f"{k[2]}{'xy'[k[3]]}/{k[0]}{'xy'[k[1]]} at {k[4]:g} rad/s" for k in keys}
    else:
        keys = list(zip(d.run.tolist(), d.node.tolist(), d.direction.tolist()))
        name = {k: (f"run {k[0]} " if len(set(d.run.tolist())) > 1 else "") + f"node {k[1]} {'xy'[k[2]]}"
                for k in keys}
    fig, layout = _on_figure(fig, (9, 9), path, "plot_fe_identification")
    a1, a2, a3 = fig.subplots(3, 1, sharex=True)
    scaled = (result.fitted - d.X) / result.sigma
    for j, k in enumerate(dict.fromkeys(keys)):
        sel = np.array([kk == k for kk in keys])
        o = np.argsort(x[sel])
        xs, ds, fs, rs = x[sel][o], d.X[sel][o], result.fitted[sel][o], scaled[sel][o]
        c = f"C{j % 10}"
        a1.plot(xs, np.abs(ds), ".", color=c, ms=4, alpha=0.7, label=f"{name[k]} measured")
        a1.plot(xs, np.abs(fs), "-", color=c, lw=1.2)
        a2.plot(xs, np.degrees(np.angle(ds)), ".", color=c, ms=4, alpha=0.7)
        a2.plot(*_break_wraps(xs, np.degrees(np.angle(fs))), "-", color=c, lw=1.2)
        a3.plot(xs, rs.real, ".", color=c, ms=3)
        a3.plot(xs, rs.imag, "x", color=c, ms=3)
    a1.set_yscale("log")
    a1.set_ylabel(f"1x amplitude ({unit})" if d.kind != "frf" else "receptance (m/N)")
    a2.set_ylabel("phase (deg)")
    a2.set_ylim(-180, 180)
    a2.set_yticks(np.arange(-180, 181, 90))
    a3.set_ylabel("scaled residual (. Re, x Im)")
    a3.axhline(0, color="k", lw=0.6)
    a3.set_xlabel("frequency (rad/s)" if d.kind == "frf" else "speed (rad/s)")
    for cs in result.critical_speeds:
        for a in (a1, a2, a3):
            a.axvspan(cs["ci95"][0], cs["ci95"][1], color="0.8", alpha=0.5, lw=0)
    a1.set_title(title, fontsize=10)
    for a in (a2, a3):
        a.grid(alpha=0.3)
    return _finish(fig, [a1], legend=True, layout=layout)


def plot_boundaries(branches, crossings, path=None, key="", key2="", box=None, title="", *, ax=None):
    """Stability boundaries in two parameters: every branch's dense (cubic Hermite)
    curve with its points marked, and the crossings the scan located
    (`BoundaryCrossing`s, or JSON rows with the coordinates under `key`, `key2`)
    (`box`: `(lo1, hi1, lo2, hi2)`, the axes' limits; default: fitted to the
    curves), on `ax` or a new figure. Returns the `Figure`."""
    fig, ax, layout = _on_axes(ax, (8, 5), path, "plot_boundaries")
    for i, c in enumerate(branches):
        d = c.dense(8)
        line, = ax.plot(d[:, 0], d[:, 1], lw=1.2, label=f"branch {i + 1} ({c.stop})")
        ax.plot(c.x[:, 0], c.x[:, 1], "o", ms=2.5, color=line.get_color())
    if crossings:
        pts = [(c[key], c[key2]) if isinstance(c, dict) else (c.p1, c.p2) for c in crossings]
        ax.plot([a for a, _ in pts], [b for _, b in pts], "kx", ms=6, label="crossings located by the scan")
    if box is not None:
        ax.set_xlim(box[0], box[1])
        ax.set_ylim(box[2], box[3])
    ax.set_xlabel(key)
    ax.set_ylabel(key2)
    ax.set_title(title)
    return _finish(fig, [ax], layout=layout)



#: how `plot_periodic_branch` marks each kind of bifurcation
_BIFURCATION_MARKERS = {"fold": "o", "branch-point": "s", "period-doubling": "D", "neimark-sacker": "^", "hopf": "v"}


def plot_periodic_branch(p, amplitude, stable, bifurcations=(), path=None, x_label="", y_label="amplitude",
                         title="", *, ax=None):
    """A branch of periodic motions: `amplitude` against the parameter `p`, stable
    parts solid and unstable parts dashed (`stable`, one flag per point), and the
    `bifurcations` marked and labelled by kind (dicts with `kind`, `p` and
    `amplitude`, or `BranchEvent`-like objects with `kind`, `p`, `amplitude`), on
    `ax` or a new figure. Returns the `Figure`."""
    fig, ax, layout = _on_axes(ax, (8, 4.5), path, "plot_periodic_branch")
    p, amplitude = np.asarray(p, dtype=float), np.asarray(amplitude, dtype=float)
    stable = np.asarray(stable, dtype=bool)
    labelled = set()
    start = 0
    for i in range(1, len(p) + 1):   # runs of equal stability, each joined to the next run's first point
        if i == len(p) or stable[i] != stable[start]:
            label = "stable" if stable[start] else "unstable"
            ax.plot(p[start:i + 1], amplitude[start:i + 1], "-" if stable[start] else "--", color="tab:blue",
                    lw=1.3, label=None if label in labelled else label)
            labelled.add(label)
            start = i
    for b in bifurcations:
        kind, bp, ba = (b["kind"], b["p"], b["amplitude"]) if isinstance(b, dict) else (b.kind, b.p, b.amplitude)
        ax.plot([bp], [ba], _BIFURCATION_MARKERS.get(kind, "x"), color="tab:red", ms=6,
                label=None if kind in labelled else kind)
        labelled.add(kind)
        ax.annotate(f"{kind} ({bp:.6g})", (bp, ba), textcoords="offset points", xytext=(5, 5), fontsize=7)
    ax.set_xlabel(x_label)
    ax.set_ylabel(y_label)
    ax.set_title(title)
    return _finish(fig, [ax], layout=layout)

# ---- finite-element rotor: static deflection, mode shapes, tracked Campbell diagram ----

def plot_static(result, path=None, title="", *, fig=None, unit="µm", factor=1e6):
    """A `StaticResult`: deflection (in `unit`, `factor` of them to the metre), shear
    force and bending moment along the shaft in the plane of gravity (shear and moment
    at both ends of every element), three panels on `fig` (empty) or a new figure.
    Returns the `Figure`."""
    p = ("x", "y").index(result.axis)
    z = np.asarray(result.positions)
    ends = np.asarray(result.element_ends)
    fig, layout = _on_figure(fig, (8, 8), path, "plot_static")
    a1, a2, a3 = fig.subplots(3, 1, sharex=True)
    a1.plot(z, factor * np.asarray(result.displacement)[:, p], "o-", ms=3, label=f"{result.axis} ({unit})")
    a1.set_ylabel(f"deflection ({unit})")
    a2.plot(ends.ravel(), np.asarray(result.shear)[:, :, p].ravel(), "-", color="tab:green", label="shear force")
    a2.set_ylabel("shear force (N)")
    a3.plot(ends.ravel(), np.asarray(result.moment)[:, :, p].ravel(), "-", color="tab:purple",
            label="bending moment")
    a3.set_ylabel("bending moment (N m)")
    a3.set_xlabel("axial position (m)")
    a1.set_title(title)
    return _finish(fig, [a1, a2, a3], layout=layout)


def mode_shape_lines(shape, rotor, n_per_element=8):
    """A complex mode shape (all dofs) along the shaft: axial positions and the
    complex `x`, `y` between the nodes by the beam's cubic (Hermite) shape functions
    on `(w, dw/dz)`, normalised so that the largest of `|x|`, `|y|` is 1 and real."""
    v = np.asarray(shape)
    n_nodes = rotor.n_nodes
    nd = 4
    L = np.asarray(rotor.lengths)
    z0 = np.concatenate([[0.0], np.cumsum(L)])
    t = np.linspace(0.0, 1.0, n_per_element)
    N = np.stack([1 - 3 * t**2 + 2 * t**3, t - 2 * t**2 + t**3, 3 * t**2 - 2 * t**3, -t**2 + t**3], axis=1)
    zs, xs, ys = [], [], []
    for e in range(n_nodes - 1):
        Ne = N * np.array([1.0, L[e], 1.0, L[e]])
        for plane, out in ((0, xs), (1, ys)):
            dofs = [nd * e + plane, nd * e + plane + 2, nd * (e + 1) + plane, nd * (e + 1) + plane + 2]
            out.append(Ne @ v[dofs])
        zs.append(z0[e] + L[e] * t)
    z, x, y = np.concatenate(zs), np.concatenate(xs), np.concatenate(ys)
    big = np.concatenate([x, y])
    scale = big[np.argmax(np.abs(big))]
    return z, x / scale, y / scale


def _major_axis(x, y):
    """Semi-major axis of the orbits `(Re(x e^{it}), Re(y e^{it}))`."""
    return np.sqrt(0.5 * (np.abs(x) ** 2 + np.abs(y) ** 2 + np.abs(x**2 + y**2)))


def _minor_axis(x, y):
    """Semi-minor axis of the orbits `(Re(x e^{it}), Re(y e^{it}))`, positive where
    the orbit whirls forward (`y` lags `x`: `Im(conj(x) y) < 0`), negative backward."""
    b = np.sqrt(np.maximum(0.5 * (np.abs(x) ** 2 + np.abs(y) ** 2 - np.abs(x**2 + y**2)), 0.0))
    return np.where(np.imag(np.conj(x) * y) > 0, -b, b)


def signed_major_axis(x, y):
    """The orbits' semi-major axis along the shaft with a sign: negative where a
    station moves against the station of the largest orbit (`Re(conj(x_r) x +
    conj(y_r) y) < 0`: the two orbits half a period apart), so that the nodal points
    of a bending mode show as sign changes, as in a planar mode shape."""
    a = _major_axis(x, y)
    r = int(np.argmax(a))
    return np.where(np.real(np.conj(x[r]) * x + np.conj(y[r]) * y) < 0, -a, a)


def _mode_label(modes, k):
    return (f"mode {k}: {float(modes.frequencies[k]):.1f} rad/s, {str(modes.whirl[k])}, "
            f"log dec {float(modes.log_dec[k]):.3g}")


def plot_mode_shapes(modes, rotor, path=None, title="", *, fig=None):
    """2-D mode shapes of a `Modes` (one speed), one panel per mode: the orbits'
    semi-major axis along the shaft (signed: negative where a station moves against
    the largest orbit, so nodal points show), as ROSS's 2-D mode shape draws it,
    and the semi-minor axis (positive forward whirl, negative backward): equal to
    the major one for a circular orbit, zero for a planar one. Normalised so that
    the largest of `|x|`, `|y|` is 1. On `fig` (empty) or a new figure; returns the
    `Figure`."""
    k_all = len(np.asarray(modes.frequencies))
    cols = min(k_all, 2)
    rows = -(-k_all // cols)
    fig, layout = _on_figure(fig, (6 * cols, 2.8 * rows), path, "plot_mode_shapes")
    axes = fig.subplots(rows, cols, squeeze=False)
    shapes = np.asarray(modes.shapes)
    for k in range(k_all):
        ax = axes.flat[k]
        z, x, y = mode_shape_lines(shapes[:, k], rotor)
        ax.plot(z, signed_major_axis(x, y), "-", color="k", lw=1.8, label="major semi-axis")
        ax.plot(z, _minor_axis(x, y), "-.", color="tab:purple", lw=1.1,
                label="minor semi-axis (+ forward, - backward)")
        ax.axhline(0.0, color="0.6", lw=0.6)
        ax.plot(np.asarray(rotor.node_positions), np.zeros(rotor.n_nodes), "k.", ms=3)
        ax.set_title(_mode_label(modes, k), fontsize=9)
        ax.set_xlabel("axial position (m)")
        ax.set_ylabel("orbit semi-axes")
    for ax in list(axes.flat)[k_all:]:
        ax.set_visible(False)
    fig.suptitle(title)
    return _finish(fig, list(axes.flat)[:k_all], layout=layout)


def plot_mode_shapes_3d(modes, rotor, path=None, title="", n_orbit=60, *, fig=None):
    """3-D mode shapes of a `Modes`: the orbits `(x(t), y(t))` along the shaft (at
    the nodes, and the deflected line at one instant), one panel per mode, on `fig`
    (empty) or a new figure. Returns the `Figure`."""
    k_all = len(np.asarray(modes.frequencies))
    cols = min(k_all, 2)
    rows = -(-k_all // cols)
    fig, layout = _on_figure(fig, (6 * cols, 4.5 * rows), path, "plot_mode_shapes_3d")
    shapes = np.asarray(modes.shapes)
    ph = np.exp(1j * np.linspace(0, 2 * np.pi, n_orbit))
    axes = []
    for k in range(k_all):
        ax = fig.add_subplot(rows, cols, k + 1, projection="3d")
        z, x, y = mode_shape_lines(shapes[:, k], rotor, n_per_element=6)
        ax.plot(z, x.real, y.real, "-", color="tab:red", lw=1.5)
        zn = np.asarray(rotor.node_positions)
        idx = np.searchsorted(z, zn).clip(0, len(z) - 1)
        for i in idx:
            ax.plot(np.full(n_orbit, z[i]), (x[i] * ph).real, (y[i] * ph).real, "-", color="tab:blue", lw=0.8)
        ax.plot(z, 0 * z, 0 * z, "k-.", lw=0.6)
        ax.set_xlabel("axial position (m)")
        ax.set_ylabel("x")
        ax.set_zlabel("y")
        ax.set_title(_mode_label(modes, k), fontsize=9)
        axes.append(ax)
    fig.suptitle(title)
    return _finish(fig, axes, legend=False, layout=layout)


def plot_campbell_tracked(speeds, frequencies, whirl, log_dec, path=None, critical=(), title="", unit="rad/s", *,
                          ax=None, frequency_unit=None):
    """Campbell diagram of tracked branches (`frequencies` speeds x branches):
    forward whirl solid red, backward dashed blue, mixed dotted grey, drawn over
    dots coloured by the logarithmic decrement (a colorbar; at most about 40 dots
    per branch, so the line styles show between them); the 1x line and its
    crossings (`unit`: of the speeds, and of the frequencies unless `frequency_unit`
    names theirs). The legend names the line styles with proxy lines (no marker) and
    only the whirl directions present. On `ax` (its colorbar beside it) or a new
    figure; returns the `Figure`."""
    from matplotlib.lines import Line2D

    fig, ax, layout = _on_axes(ax, (9, 5.5), path, "plot_campbell_tracked")
    speeds = np.asarray(speeds, dtype=float)
    f, w, d = np.asarray(frequencies), np.asarray(whirl), np.asarray(log_dec, dtype=float)
    d = np.where(np.abs(d) < 1e-9, 0.0, d)   # an undamped rotor's round-off
    styles = {"forward": ("-", "tab:red"), "backward": ("--", "tab:blue"), "mixed": (":", "0.4")}
    handles, labels = [], []
    for label, (ls, colour) in styles.items():
        if not np.any(w == label):
            continue
        for k in range(f.shape[1]):
            ax.plot(speeds, np.where(w[:, k] == label, f[:, k], np.nan), ls=ls, color=colour, lw=1.5, zorder=3)
        handles.append(Line2D([], [], ls=ls, color=colour, lw=1.5, marker="None"))
        labels.append(f"{label} whirl")
    finite = d[np.isfinite(d)]
    lo, hi = (float(finite.min()), float(finite.max())) if finite.size else (0.0, 1.0)
    every = slice(None, None, max(1, -(-len(speeds) // 40)))
    sc = ax.scatter(np.repeat(speeds[every, None], f.shape[1], 1), f[every], c=d[every], s=14, cmap="viridis",
                    vmin=lo, vmax=hi if hi > lo else lo + 1e-12, zorder=2, edgecolors="none")
    fig.colorbar(sc, ax=ax, label="logarithmic decrement (dots)")
    ax.plot(speeds, speeds, "k:", lw=1, zorder=1)
    handles.append(Line2D([], [], ls=":", color="k", lw=1))
    labels.append("1x")
    for c in critical:
        ax.plot([c], [c], "rx", ms=7, mew=2, zorder=4)
    if len(critical):
        handles.append(Line2D([], [], ls="none", marker="x", color="r", ms=7, mew=2))
        labels.append("1x crossing")
    ax.set_xlabel(f"speed ({unit})")
    ax.set_ylabel(f"damped natural frequency ({frequency_unit or unit})")
    ax.set_ylim(0, max(np.nanmax(f), np.max(speeds)) * 1.05)
    ax.set_title(title)
    ax.grid(alpha=0.3)
    ax.legend(handles, labels, fontsize=8, handlelength=3)
    return _finish(fig, layout=layout)


#: A bearing's colour on the UCS map (its kxx dashed, kyy dotted), apart from the modes' C0, C1, ...
_BEARING_COLOURS = ("k", "tab:brown", "tab:pink", "tab:olive", "tab:cyan", "0.55")


def _bearing_label(members):
    """"bearing 0 kxx"; curves that coincide share one line: "bearing 0 kxx = kyy",
    "bearings 0, 1 kxx = kyy" (or each one named where they do not form such a block)."""
    bearings = list(dict.fromkeys(b for b, _ in members))
    names = list(dict.fromkeys(n for _, n in members))
    if len(members) == len(bearings) * len(names):
        return (f"bearing{'s' if len(bearings) > 1 else ''} " + ", ".join(map(str, bearings)) + " "
                + " = ".join(names))
    return " = ".join(f"bearing {b} {n}" for b, n in members)


def plot_ucs(stiffness, frequencies, path=None, bearing_speeds=None, bearing_k=None, intersections=(), title="",
             synchronous=False, *, ax=None, unit="rad/s"):
    """Undamped critical speed map (log-log): critical speed against bearing
    stiffness, one curve per mode, with each bearing's `kxx` (dashed) and `kyy`
    (dotted) against speed in the bearing's own colour (`bearing_k` (n_b, 2, n_s)
    at `bearing_speeds`; curves that coincide drawn once, their legend entry naming
    them all) and their intersections (`(k, speed)` pairs). On `ax` or a new
    figure; returns the `Figure`."""
    fig, ax, layout = _on_axes(ax, (8, 5), path, "plot_ucs")
    k, f = np.asarray(stiffness), np.asarray(frequencies)
    for j in range(f.shape[1]):
        ax.loglog(k, np.where(np.isfinite(f[:, j]), f[:, j], np.nan), "-", lw=1.4, label=f"mode {j + 1}")
    if bearing_k is not None:
        s, kb = np.asarray(bearing_speeds), np.asarray(bearing_k)
        curves = []     # [values, [(bearing, coefficient), ...], line style, colour]: equal curves drawn once
        for b in range(kb.shape[0]):
            for c, (name, ls) in enumerate((("kxx", "--"), ("kyy", ":"))):
                same = next((cv for cv in curves if np.array_equal(cv[0], kb[b, c])), None)
                if same is not None:
                    same[1].append((b, name))
                else:
                    curves.append([kb[b, c], [(b, name)], ls, _BEARING_COLOURS[b % len(_BEARING_COLOURS)]])
        for values, members, ls, colour in curves:
            ok = (values > 0) & (s > 0)
            ax.loglog(values[ok], s[ok], ls=ls, color=colour, lw=1.3, label=_bearing_label(members))
    for i, (ki, si) in enumerate(intersections):
        ax.plot([ki], [si], "o", color="tab:red", ms=5, label="critical speed on the bearings" if i == 0 else None)
    ax.set_xlim(k[0], k[-1])
    finite = f[np.isfinite(f)]
    if finite.size:
        ax.set_ylim(finite.min() / 2, finite.max() * 2)
    ax.set_xlabel("bearing stiffness (N/m)")
    ax.set_ylabel(f"critical speed ({unit})" + (" (forward synchronous)" if synchronous else " (at rest)"))
    ax.set_title(title)
    return _finish(fig, [ax], layout=layout)


def _frf_points(frequencies, values):
    w, h = np.asarray(frequencies, dtype=float).ravel(), np.asarray(values).ravel()
    order = np.argsort(w, kind="stable")
    return w[order], h[order]


def plot_bode(frequencies, values, title="", unit="m/N", *, fig=None, frequency_unit="rad/s"):
    """A frequency-response function's Bode plot: magnitude (log) above, phase
    (degrees, with a gap where it wraps past +-180) below, on `fig` (empty) or a new
    figure. The frequencies may be uneven and in any order (joined in order of
    frequency). Returns the `Figure`."""
    w, h = _frf_points(frequencies, values)
    fig, layout = _on_figure(fig, (8, 6))
    a1, a2 = fig.subplots(2, 1, sharex=True)
    a1.semilogy(w, np.abs(h), lw=1.2)
    a2.plot(*_break_wraps(w, np.degrees(np.angle(h))), lw=1.2)
    a2.set_ylim(-180, 180)
    a2.set_yticks(np.arange(-180, 181, 90))
    a1.set_ylabel(f"magnitude ({unit})")
    a2.set_ylabel("phase (deg)")
    a2.set_xlabel(f"frequency ({frequency_unit})")
    a1.set_title(title)
    return _finish(fig, [a1, a2], legend=False, layout=layout)


def plot_nyquist(frequencies, values, title="", unit="m/N", *, ax=None):
    """A frequency-response function's polar (Nyquist) plot: Im against Re, the
    frequency increasing along the curve (its ends marked), on `ax` or a new
    figure. Returns the `Figure`."""
    w, h = _frf_points(frequencies, values)
    fig, ax, layout = _on_axes(ax, (6, 6))
    ax.plot(h.real, h.imag, lw=1.2)
    ax.plot([h.real[0]], [h.imag[0]], "o", color="tab:green", ms=4, label=f"{w[0]:g} rad/s")
    ax.plot([h.real[-1]], [h.imag[-1]], "s", color="tab:red", ms=4, label=f"{w[-1]:g} rad/s")
    ax.set_xlabel(f"real ({unit})")
    ax.set_ylabel(f"imaginary ({unit})")
    ax.set_aspect("equal", adjustable="datalim")
    ax.set_title(title + " (polar)" if title else "polar")
    return _finish(fig, [ax], layout=layout)


def plot_frf(frequencies, values, path_bode=None, path_polar=None, title="", unit="m/N", *, fig=None, ax=None,
             frequency_unit="rad/s"):
    """A frequency-response function: Bode (`plot_bode`, on `fig`) and polar
    (`plot_nyquist`, on `ax`), each on a new figure by default. The frequencies may
    be spaced unevenly (refined near the resonances, so that the polar curve is
    smooth) and in any order: the points are joined in order of frequency. Long
    titles are wrapped to the figure's width. `path_bode`, `path_polar`: ignored
    (the file-writing version's).

    **Returns:** the two `Figure`s, `(bode, polar)`.
    """
    _unwritten(path_bode, "plot_frf", 3)
    _unwritten(path_polar, "plot_frf", 3)
    return (plot_bode(frequencies, values, title, unit, fig=fig, frequency_unit=frequency_unit),
            plot_nyquist(frequencies, values, title, unit, ax=ax))


def plot_deflected_shape(positions, x, y, major, path=None, title="", *, ax=None, unit="m"):
    """Deflected shape at one speed: the orbit's major semi-axis along the shaft and
    the `x`, `y` displacements at the instant `t = 0` (real parts; all in `unit`), on
    `ax` or a new figure. Returns the `Figure`."""
    fig, ax, layout = _on_axes(ax, (8, 4), path, "plot_deflected_shape")
    z = np.asarray(positions)
    ax.plot(z, np.asarray(major), "k-o", ms=3, lw=1.4, label="major semi-axis")
    ax.plot(z, np.real(np.asarray(x)), "--", lw=1.0, label="x (t = 0)")
    ax.plot(z, np.real(np.asarray(y)), ":", lw=1.0, label="y (t = 0)")
    ax.set_xlabel("axial position (m)")
    ax.set_ylabel(f"displacement ({unit})")
    ax.set_title(title)
    return _finish(fig, [ax], layout=layout)


def plot_level1(q, log_dec, path=None, q0=None, title="", *, ax=None):
    """API 684 level I: the first forward mode's log decrement against the
    cross-coupled stiffness, with the threshold `q0` where it crosses zero marked
    and annotated ("Q0 = ... N/m"). `q` runs from 0 to about the bearings'
    stiffness, and `Q0` is often a small part of it: where `Q0` is below 5 % of the
    largest `Q` the axis is symmetric-logarithmic (linear from 0 to the power of ten
    below `Q0`, logarithmic above), so that `Q0` stands clear of 0. The curve joins
    the computed points and passes through `(Q0, 0)`. On `ax` or a new figure;
    returns the `Figure`."""
    fig, ax, layout = _on_axes(ax, (8, 4), path, "plot_level1")
    q, ld = np.asarray(q, dtype=float), np.asarray(log_dec, dtype=float)
    order = np.argsort(q)
    q, ld = q[order], ld[order]
    crossed = q0 is not None and np.isfinite(q0)
    line_q, line_ld = q, ld
    if crossed:
        k = int(np.searchsorted(q, q0))
        line_q, line_ld = np.insert(q, k, q0), np.insert(ld, k, 0.0)   # the root is a point of the curve
    ax.plot(line_q, line_ld, "-", color="tab:blue", lw=1.2)
    ax.plot(q, ld, "o", color="tab:blue", ms=3, label="log decrement, first forward mode")
    ax.axhline(0.0, color="k", lw=0.8)
    x_label = "cross-coupled stiffness Q (N/m)"
    if crossed:
        text = f"Q0 = {q0:.4g} N/m"
        ax.axvline(q0, color="tab:red", ls="--", lw=1.0)
        ax.plot([q0], [0.0], "D", color="tab:red", ms=6, zorder=3, label=text)
        ax.annotate(text, (q0, 0.0), textcoords="offset points", xytext=(10, 14), color="tab:red", fontsize=9,
                    arrowprops=dict(arrowstyle="-", color="tab:red", lw=0.8))
        if 0 < q0 < 0.05 * q.max():
            linthresh = 10.0 ** np.floor(np.log10(q0))
            ax.set_xscale("symlog", linthresh=linthresh)
            x_label = f"cross-coupled stiffness Q (N/m; linear below {linthresh:.0e}, logarithmic above)"
    ax.set_xlim(min(q.min(), 0.0), q.max())
    ax.set_xlabel(x_label)
    ax.set_ylabel("log decrement")
    ax.set_title(title)
    return _finish(fig, [ax], layout=layout)


def plot_fe_balance(path=None, result=None, title="", *, ax=None):
    """A balancing over several speeds (`rotorjax.identify.Balancing`): the
    1x vibration magnitude per sensor against speed, measured before (solid) and
    predicted after the corrections (dashed), with the corrections in the title. On
    `ax` or a new figure; `path` is ignored (the file-writing version's). Returns
    the `Figure`."""
    if result is None:
        raise TypeError("plot_fe_balance: missing the argument 'result'")
    fig, ax, layout = _on_axes(ax, (8, 4.5), path, "plot_fe_balance")
    speeds = np.asarray(result.speeds)
    before, after = np.abs(np.asarray(result.X0)), np.abs(np.asarray(result.predicted))
    for k, sensor in enumerate(dict.fromkeys(result.sensors)):
        rows = [i for i, s in enumerate(result.sensors) if s == sensor]
        order = np.argsort(speeds[rows])
        r = np.asarray(rows)[order]
        color = f"C{k % 10}"
        ax.plot(speeds[r], before[r], "-o", color=color, ms=4, lw=1.2, label=f"node {sensor[0]} {sensor[1]}: before")
        ax.plot(speeds[r], after[r], "--s", color=color, ms=4, lw=1.2, label=f"node {sensor[0]} {sensor[1]}: after")
    values = np.concatenate([before, after])
    values = values[values > 0]
    if values.size and values.max() / values.min() > 1e2:
        ax.set_yscale("log")
    ax.set_xlabel("speed (rad/s)")
    ax.set_ylabel("1x vibration magnitude (m)")
    corr = ", ".join(f"node {n}: {m:.3g} kg m at {np.degrees(p) % 360:.0f} deg" for n, m, p in result.corrections)
    ax.set_title(f"{title}\ncorrections ({result.method}): {corr}", fontsize=9)
    return _finish(fig, [ax], layout=layout)


def work_precision_curve(ax, points, label, style):
    """One method's curve on a work-precision diagram (log cost across, log error up),
    each marker labelled with its tolerance. `points`: `(error, cost, tolerance label)`;
    a zero or non-finite error cannot be drawn on a log axis and is left out.
    Returns `ax`'s `Figure`."""
    pts = sorted((e, c, t) for e, c, t in points if np.isfinite(e) and e > 0 and np.isfinite(c) and c > 0)
    if not pts:
        return ax.figure
    ax.loglog([p[1] for p in pts], [p[0] for p in pts], style, label=label, markersize=4)
    for e, c, t in pts:
        ax.annotate(t, (c, e), fontsize=5, xytext=(2, 2), textcoords="offset points")
    return ax.figure


def plot_bench(report, path=None, *, fig=None):
    """`rotorjax bench`'s figure: one panel per comparison; a work-precision diagram
    where the methods have ladders, else the time per analysis as bars with the
    agreement in the title. The machine and date in the caption. On `fig` (empty) or
    a new figure; returns the `Figure`."""
    from matplotlib.ticker import NullFormatter

    comps = report["comparisons"]
    fig, layout = _on_figure(fig, (5.2 * len(comps), 4.6), path, "plot_bench")
    axes = fig.subplots(1, len(comps))
    for ax, c in zip(np.atleast_1d(axes), comps):
        ladders = any(len(pts) > 1 for pts in c["curves"].values())
        if ladders:
            for name, pts in c["curves"].items():
                style = "o-" if name == c["rotorjax"] else ("x--" if "numba" in name else "d:")
                work_precision_curve(ax, [(p["error"], p["cost"], p["tol"]) for p in pts], name, style)
            ax.set_xlabel(c["cost_unit"].replace("s per", "seconds per"))
            ax.set_ylabel(c["error_label"])
            ax.grid(True, which="both", alpha=0.3)
        else:
            names = list(c["curves"])
            costs = [c["curves"][n][0]["cost"] for n in names]
            ax.bar(range(len(names)), costs, color=["C0"] + ["C1"] * (len(names) - 1))
            ax.set_xticks(range(len(names)), [n.replace(" run_", "\nrun_") for n in names], fontsize=7)
            ax.set_yscale("log")
            ax.set_ylabel(c["cost_unit"].replace("s per", "seconds per"))
            if "agreement_max_rel" in c["checks"]:
                ax.text(0.5, 0.95, f"agreement {c['checks']['agreement_max_rel']:.1e} (relative)",
                        transform=ax.transAxes, ha="center", va="top", fontsize=7)
            ax.grid(True, axis="y", which="both", alpha=0.3)
        skipped = "; ".join(s["peer"] + " skipped" for s in c["skipped"])
        ax.set_title(textwrap.fill(f"{c['name']}: {c['what']}", 70) + (f"\n({skipped})" if skipped else ""),
                     fontsize=7)
        ax.xaxis.set_minor_formatter(NullFormatter())
        if ladders:
            ax.legend(fontsize=6)
    m = report["machine"]
    fig.suptitle(f"rotorjax bench: {m['device']}, {m['cpu_count']} CPU cores, {m['platform'][:48]}, jax "
                 f"{m['jax']}, {m['date']}", fontsize=8)
    return _finish(fig, layout=layout)


def plot_uncertainty(path=None, result=None, title="", *, fig=None):
    """Outputs as distributions (`rotorjax.uncertainty.Propagation`): per output, the
    Monte Carlo histogram (as a density) with the first-order normal density
    `N(f(mu), g^T Sigma g)` over it and the 5 / 95 % sample quantiles marked. On `fig`
    (empty) or a new figure; `path` is ignored. Returns the `Figure`."""
    if result is None:
        raise TypeError("plot_uncertainty: missing the argument 'result'")
    n = len(result.outputs)
    cols = min(n, 3)
    rows = -(-n // cols)
    fig, layout = _on_figure(fig, (4.2 * cols, 3.2 * rows), path, "plot_uncertainty")
    axes = []
    Y = np.asarray(result.samples)[np.asarray(result.finite)]
    for j, name in enumerate(result.outputs):
        ax = fig.add_subplot(rows, cols, j + 1)
        y = Y[:, j]
        if np.all(y == y[0]):   # the same in every sample (an undamped rotor's log decrements): no density
            v = float(y[0])
            ax.axvline(v, color="C0", lw=2, label=f"every sample: {v:.6g}")
            ax.set_xlim(v - (0.5 * abs(v) or 1.0), v + (0.5 * abs(v) or 1.0))
            ax.set_yticks([])
            ax.set_xlabel(name)
            axes.append(ax)
            continue
        ax.hist(y, bins=min(60, max(10, y.size // 50)), density=True, alpha=0.5, color="C0", label="Monte Carlo")
        m, s = float(result.fosm_mean[j]), float(result.fosm_std[j])
        if s > 0:
            x = np.linspace(min(y.min(), m - 4 * s), max(y.max(), m + 4 * s), 300)
            ax.plot(x, np.exp(-0.5 * ((x - m) / s) ** 2) / (s * np.sqrt(2 * np.pi)), "C3-", lw=1.2,
                    label="first order")
        for q in (0.05, 0.95):
            ax.axvline(float(result.quantiles[q][j]), color="k", ls=":", lw=0.8)
        ax.set_xlabel(name)
        ax.set_ylabel("density")
        axes.append(ax)
    if title:
        fig.suptitle(title, fontsize=10)
    return _finish(fig, axes, layout=layout)


def plot_design(path=None, design=None, campbell=None, title="", *, margins=None, speed_label="speed", fig=None):
    """A design's optimisation (`rotorjax.design.RotorDesign`): the objective and the
    largest constraint violation after each accepted step of the best start; and,
    with `campbell` `(speeds, before, after)` (each `Modes` over `speeds`), the
    Campbell diagram before (grey) and after (colour), the 1x line dashed; or, with
    `margins` `(speeds, before, after)` (a preset's reference-motion stability
    margins), the margin over `speed_label` before and after, the stable side below
    0. On `fig` (empty) or a new figure; `path` is ignored. Returns the `Figure`."""
    if design is None:
        raise TypeError("plot_design: missing the argument 'design'")
    cols = 2 if campbell is not None or margins is not None else 1
    fig, layout = _on_figure(fig, (5.0 * cols, 3.8), path, "plot_design")
    ax = fig.add_subplot(1, cols, 1)
    h = np.asarray(design.optimum.steps)
    sense = design.problem.sense
    k = np.arange(1, h.shape[0] + 1)
    scale = design.problem.scales[design.problem.objective]
    ax.plot(k, -sense * h[:, 0] * scale, "C0.-", label=design.problem.objective)
    ax.set_xlabel("step (accepted, the best start)")
    ax.set_ylabel(design.problem.objective)
    axes = [ax]
    if design.problem.constraints:
        ax2 = ax.twinx()
        ax2.semilogy(k, np.maximum(h[:, 1], 1e-16), "C3--", lw=0.8, label="largest violation")
        ax2.set_ylabel("largest violation (scaled)")
    if campbell is not None:
        speeds, before, after = campbell
        ax = fig.add_subplot(1, cols, 2)
        ax.plot(speeds, np.asarray(before.frequencies), color="0.6", lw=1)
        ax.plot(speeds, np.asarray(after.frequencies), color="C0", lw=1.2)
        ax.plot(speeds, speeds, "k--", lw=0.8, label="1x")
        ax.set_ylim(0, 1.5 * float(np.max(speeds)))
        ax.set_xlabel("speed (rad/s)")
        ax.set_ylabel("damped natural frequency (rad/s)")
        ax.set_title("Campbell: before (grey), after", fontsize=9)
        axes.append(ax)
    if margins is not None:
        speeds, before, after = margins
        ax = fig.add_subplot(1, cols, 2)
        ax.plot(speeds, before, color="0.6", lw=1, label="before")
        ax.plot(speeds, after, color="C0", lw=1.2, label="after")
        ax.axhline(0.0, color="k", lw=0.6)
        ax.set_xlabel(speed_label)
        ax.set_ylabel("stability margin (< 0: stable)")
        ax.set_title("reference motion's margin: before (grey), after", fontsize=9)
        axes.append(ax)
    if title:
        fig.suptitle(title, fontsize=10)
    return _finish(fig, axes, layout=layout)


from ._rotor import layout as rotor_layout  # noqa: E402  (the drawing uses the helpers above)
from ._rotor import rotor as rotor  # noqa: E402
from ._interactive import Trace, figure_html, lines_figure, plotly_js  # noqa: E402,F401  (a page's figures)
from ._interactive import available as interactive_available  # noqa: E402,F401
