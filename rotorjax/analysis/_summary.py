"""Summaries of a simulation, for any scene, from its outputs.

A run is judged over its last revolutions: `revolution_window` turns a number of
revolutions at the run's final speed into a time window, `analysis_window` into the
fraction of the run that a precession analysis reads (the last `revolutions`, at
most the second half). `simulation_summary` reports a run from the scene's named
outputs (`whirl_amplitude` where the scene has one: final and largest over the
window; every other output's final value); `precession_summary` adds, for scenes
whose outputs include the disk centre's motion (`disk_x`, `disk_y`, `disk_vx`,
`disk_vy`), the precession index, the extrema, the contact forces and the energy
balance; `precession_diagram` does the same per lane of a vmapped sweep.
`run` integrates smoothly or, with `events`, locating every contact change.
"""

import numpy as np

#: outputs a precession analysis needs (the disk centre's position and velocity)
DISK_OUTPUTS = ("disk_x", "disk_y", "disk_vx", "disk_vy")


def run(scene, y0, t_end, *, events=False, saveat=4000, solver="auto", rtol=1e-8, atol=1e-10,
        max_steps=500_000, progress=False):
    """Integrate `scene` from `y0` over `(0, t_end)`: with `events`, event-located
    (`rotorjax.solve.simulate_events`, exact contact law; `"auto"` is Dopri8),
    else smoothly (`rotorjax.solve.simulate`)."""
    from ..solve import simulate, simulate_events

    if events:
        return simulate_events(scene, y0, (0.0, t_end), saveat=saveat, solver="dopri8" if solver == "auto" else solver,
                               rtol=rtol, atol=atol, max_steps=max_steps)
    return simulate(scene, y0, (0.0, t_end), saveat=saveat, solver=solver, rtol=rtol, atol=atol,
                    max_steps=max_steps, progress=progress)


def speeds_at(scene, ts) -> np.ndarray:
    """The scene's prescribed speed at the times `ts`."""
    import jax

    return np.asarray(jax.vmap(scene.speed.speed)(np.asarray(ts, dtype=np.float64)))


def speed_varies(scene, ts) -> bool:
    """Whether the prescribed speed changes over `ts` (a run-up or run-down)."""
    s = speeds_at(scene, ts)
    return bool(np.ptp(s[np.isfinite(s)]) > 0) if np.any(np.isfinite(s)) else False


def revolutions_of(scene, t_end) -> float:
    """Revolutions in `(0, t_end)` at the scene's speed at `t_end` (constant speed: exact)."""
    return float(t_end * abs(speeds_at(scene, [t_end])[0]) / (2 * np.pi))


def saves_for(scene, t_end, per_revolution=None, least=4000) -> int:
    """Saved states of a run: `least`, or `per_revolution` per revolution if more."""
    if per_revolution is None:
        return least
    return max(least, int(per_revolution * revolutions_of(scene, t_end)))


def revolution_window(ts, speed_end, revolutions) -> np.ndarray:
    """Mask of the times `ts` within the last `revolutions` turns at `speed_end`
    (the whole run when the speed is 0)."""
    ts = np.asarray(ts)
    window = revolutions * 2 * np.pi / speed_end if speed_end > 0 else ts[-1] - ts[0]
    return ts >= ts[-1] - window


def analysis_window(t_end, speed, revolutions=300) -> tuple:
    """The fraction of a run of length `t_end` at `speed` that a precession analysis
    reads: the last `revolutions` (the paper's 300), at most the second half."""
    revs = t_end * speed / (2 * np.pi)
    return (max(0.5, 1 - revolutions / revs), 1.0)


def valid_states(result) -> np.ndarray:
    """Mask of the saved states that are finite (a failed run leaves inf/nan)."""
    ts = np.asarray(result.ts)
    return np.isfinite(ts) & np.all(np.isfinite(np.asarray(result.ys)), axis=-1)


def _value(v):
    v = np.asarray(v)
    return float(v) if v.ndim == 0 else v.tolist()


def simulation_summary(result, scene, revolutions=5, amplitude="whirl_amplitude") -> dict:
    """A run's outcome from the scene's outputs, JSON-ready: success, code, message,
    solver, statistics; the last valid time (and amplitude); after a success, the
    final speed and, for the `amplitude` output, its final value and largest value
    over the last `revolutions`, and every other output's final value (`NAME_final`).
    After a failure the `final_*` entries are None."""
    outputs = {k: np.asarray(v) for k, v in result.outputs.items()}
    others = [k for k in outputs if k != amplitude]
    has_amp = amplitude in outputs
    valid = valid_states(result)
    summary = {
        "success": bool(result.success),
        "code": int(result.code),
        "message": result.message,
        "solver": result.solver,
        "stats": {k: int(v) for k, v in result.stats.items()},
        "revolutions_in_window": revolutions,
    }
    if not valid.any():
        summary["last_valid_time"] = None
        return summary
    ts = np.asarray(result.ts)[valid]
    summary["last_valid_time"] = float(ts[-1])
    if has_amp:
        amp = outputs[amplitude][valid]
        summary[f"last_valid_{amplitude}"] = _value(amp[-1])
    if not result.success:
        films = {k[:-len("_eccentricity")]: _value(outputs[k][valid][-1]) for k in others
                 if k.endswith("_eccentricity")}
        if films:   # fluid films: how close each journal was to its wall
            summary["last_valid_film_eccentricity"] = films
        keys = ([f"final_{amplitude}", f"max_{amplitude}_last_revolutions"] if has_amp else []) + ["final_speed"]
        for key in keys + [f"{k}_final" for k in others]:
            summary[key] = None
        return summary
    speed_end = abs(float(speeds_at(scene, ts[-1:])[0]))
    last = revolution_window(ts, speed_end, revolutions)
    if has_amp:
        summary[f"final_{amplitude}"] = _value(amp[-1])
        summary[f"max_{amplitude}_last_revolutions"] = float(np.max(amp[last]))
    summary["final_speed"] = speed_end
    for k in others:
        summary[f"{k}_final"] = _value(outputs[k][valid][-1])
    return summary


def has_disk_motion(result) -> bool:
    """Whether the run's outputs include the disk centre's motion (`DISK_OUTPUTS`)."""
    return all(k in result.outputs for k in DISK_OUTPUTS)


def precession_summary(result, scene, window):
    """The precession of the disk centre over the fraction `window` of a successful
    run (`rotorjax.analysis.precession` at the scene's final speed), with the disk's
    and contacts' extremes over the window and the energy balance where the scene
    has one. Returns `(summary dict, Precession)`."""
    from ..models import energy_residual, provides
    from ._precession import precession

    o = {k: np.asarray(v) for k, v in result.outputs.items()}
    ts = np.asarray(result.ts)
    speed = abs(float(speeds_at(scene, ts[-1:])[0]))
    prec = precession(ts, o["disk_x"], o["disk_y"], o["disk_vx"], o["disk_vy"], speed, window=window)
    k = ts >= prec.ts[0]
    normal = o.get("normal_forces", np.zeros((ts.size, 0)))
    normal_w = normal[k] if normal.size else np.zeros((int(k.sum()), 0))
    radius = o["radius"] if "radius" in o else np.hypot(o["disk_x"], o["disk_y"])
    summary = prec.as_dict()
    summary.update({
        "window": [float(prec.ts[0]), float(prec.ts[-1])],
        "max_disk_x": float(o["disk_x"][k].max()), "min_disk_x": float(o["disk_x"][k].min()),
        "max_radius": float(radius[k].max()),
        "max_normal_force": float(normal.max()) if normal.size else 0.0,  # whole run
        "contact_fraction": float(np.mean(np.any(normal_w > 1e-9, axis=1))) if normal_w.size else 0.0,
    })
    if provides(scene, "energy") and "work" in o:
        summary["energy_residual"] = energy_residual(scene, result.ys)
    return summary, prec


def precession_diagram(key, values, lanes, speeds, revolutions, analysis_revolutions=300):
    """Per value of a swept parameter, the precession of a vmapped run: `lanes` holds
    `ts`, `x`, `y`, `vx`, `vy`, `code` (one row per value), `speeds` the spin speed
    of each run, `revolutions` its length. Returns `(rows, extrema, means,
    switches)`: JSON rows, the extrema of `x` and `<Lambda>` per value, and where
    `<Lambda>` changes sign (midpoints)."""
    from ._precession import precession

    values = np.asarray(values)
    rows, extrema, lams = [], [], []
    for i, val in enumerate(values):
        code = int(np.asarray(lanes["code"])[i])
        if code != 0:
            rows.append({key: float(val), "code": code, "mean_Lambda": None})
            extrema.append(np.zeros(0))
            lams.append(np.nan)
            continue
        speed = float(speeds[i])
        t_end = 2 * np.pi / speed * revolutions
        pr = precession(*(np.asarray(lanes[c])[i] for c in ("ts", "x", "y", "vx", "vy")), speed,
                        window=analysis_window(t_end, speed, analysis_revolutions))
        rows.append({key: float(val), "code": 0, "mean_Lambda": pr.mean, "direction": pr.direction,
                     "extrema_x": [float(pr.extrema_x.min()), float(pr.extrema_x.max())] if pr.extrema_x.size
                     else None})
        extrema.append(pr.extrema_x)
        lams.append(pr.mean)
    lams = np.asarray(lams)
    n = values.size
    switches = [0.5 * (values[i] + values[i + 1]) for i in range(n - 1)
                if np.isfinite(lams[i]) and np.isfinite(lams[i + 1]) and np.sign(lams[i]) != np.sign(lams[i + 1])]
    return rows, extrema, lams, switches


def local_maxima(x, y) -> list:
    """The `x` where `y` has a strict interior local maximum (peaks of a sampled curve)."""
    x, y = np.asarray(x), np.asarray(y)
    return [float(x[i]) for i in range(1, len(y) - 1) if y[i] > y[i - 1] and y[i] > y[i + 1]]
