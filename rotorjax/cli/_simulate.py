"""`rotorjax simulate`: a preset scene in time (planar rotors, and model 004's
cantilever with limiters)."""

import json
import os

import numpy as np

from ._common import build, get_preset, preset_params, prepare_out, wrong_kind, write_json


def _speed_at(scene, ts):
    import jax

    return np.asarray(jax.vmap(scene.speed.speed)(np.asarray(ts)))


def _valid(result):
    ts = np.asarray(result.ts)
    return np.isfinite(ts) & np.all(np.isfinite(np.asarray(result.ys)), axis=-1)


def summarize(result, scene, params, preset_name, t_end, revolutions=5) -> dict:
    """The JSON summary of one simulation. The `final_*` values are those of the
    end time and are given only after a success (`null` otherwise); after a failure,
    `last_valid_time` and `last_valid_whirl_amplitude` describe the last valid saved
    state."""
    ts = np.asarray(result.ts)
    valid = _valid(result)
    summary = {
        "preset": preset_name,
        "params": params,
        "t_end": float(t_end),
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
    ts = ts[valid]
    amp = np.asarray(result.outputs["whirl_amplitude"])[valid]
    summary["last_valid_time"] = float(ts[-1])
    summary["last_valid_whirl_amplitude"] = float(amp[-1])
    if not result.success:
        for key in ("final_whirl_amplitude", "max_whirl_amplitude_last_revolutions", "final_speed",
                    "residual_imbalance_final", "weight_angles_final"):
            summary[key] = None
        return summary
    speed_end = abs(float(_speed_at(scene, ts[-1:])[0]))
    window = revolutions * 2 * np.pi / speed_end if speed_end > 0 else ts[-1] - ts[0]
    last = ts >= ts[-1] - window
    summary.update({
        "final_whirl_amplitude": float(amp[-1]),
        "max_whirl_amplitude_last_revolutions": float(np.max(amp[last])),
        "final_speed": speed_end,
        "residual_imbalance_final": float(np.asarray(result.outputs["residual_imbalance"])[valid][-1]),
    })
    if "weight_angles" in result.outputs:
        summary["weight_angles_final"] = [
            float(a) for a in np.asarray(result.outputs["weight_angles"])[valid][-1]
        ]
    return summary


def _failure_line(summary):
    at = summary.get("last_valid_time")
    where = "no valid saved state" if at is None else f"last valid saved state at t = {at:.6g}"
    return f"  the run failed before t_end = {summary['t_end']:.6g} ({where}): no final state to report"


def cmd_simulate(args) -> int:
    preset = get_preset(args.preset)
    if preset.kind == "contact":
        return _contact_simulate(preset, preset_params(preset, args.set), args)
    if preset.kind != "planar":
        raise wrong_kind(preset, "simulate")
    import rotorjax as rj
    from rotorjax.plot import plot_simulation

    params = preset_params(preset, args.set)
    prepare_out(args.out)
    scene, y0, t_end = build(preset, params)
    if args.t_end is not None:
        t_end = args.t_end
    result = rj.simulate(scene, y0, (0.0, t_end), saveat=args.n_save or 4000, solver=args.solver,
                         rtol=args.rtol, atol=args.atol, max_steps=args.max_steps, progress=not args.json)
    summary = summarize(result, scene, params, preset.name, t_end)
    stem = os.path.join(args.out, preset.name)
    run_up = bool(params.get("nu_dot", 0) or params.get("n_dot", 0))
    speed = _speed_at(scene, result.ts) if run_up else None
    plot_simulation(result, stem + ".png", title=f"{preset.name}: {preset.source}", speed=speed,
                    x_label=("speed" if run_up else "time") + f" (time unit {preset.time_unit})")
    np.savez(stem + ".npz", ts=np.asarray(result.ts), ys=np.asarray(result.ys),
             **{k: np.asarray(v) for k, v in result.outputs.items()})
    summary["files"] = {"plot": stem + ".png", "data": stem + ".npz", "summary": stem + ".json"}
    write_json(stem + ".json", summary, indent=2)
    if args.json:
        print(json.dumps(summary, indent=2))
        return 0 if summary["success"] else 3
    print(f"{preset.name}: {summary['message']} ({summary['solver']}, {summary['stats']['num_steps']} steps)")
    if not summary["success"]:
        print(_failure_line(summary))
        return 3
    print(f"  final whirl amplitude {summary['final_whirl_amplitude']:.6g}, max over last "
          f"{summary['revolutions_in_window']} revolutions {summary['max_whirl_amplitude_last_revolutions']:.6g}")
    if "weight_angles_final" in summary:
        print("  weight angles rel. rotor (rad): " + ", ".join(f"{a:.4f}" for a in summary["weight_angles_final"]))
    print(f"  wrote {stem}.png, .npz, .json")
    return 0


def contact_run(params, scene, y0, t_end, args, n_save):
    """One run of a contact preset, smoothed or event-located (`events`)."""
    import rotorjax as rj
    from rotorjax.solve import simulate_events

    if params["events"]:
        solver = "dopri8" if args.solver == "auto" else args.solver
        return simulate_events(scene, y0, (0.0, t_end), saveat=n_save, solver=solver, rtol=args.rtol,
                               atol=args.atol, max_steps=args.max_steps)
    return rj.simulate(scene, y0, (0.0, t_end), saveat=n_save, solver=args.solver, rtol=args.rtol,
                       atol=args.atol, max_steps=args.max_steps, progress=not args.json)


def window(params, t_end):
    """The analysis window: the last 300 revolutions (the paper's), at most the
    second half of the run."""
    revs = t_end * params["N"] / (2 * np.pi)
    return (max(0.5, 1 - 300 / revs), 1.0)


def _contact_simulate(preset, params, args) -> int:
    from rotorjax.analysis import precession
    from rotorjax.contact._scene import energy_residual
    from rotorjax.plot import plot_precession

    prepare_out(args.out)
    scene, y0, t_end = build(preset, params)
    if args.t_end is not None:
        t_end = args.t_end
    revs = t_end * params["N"] / (2 * np.pi)
    n_save = args.n_save or max(4000, int(40 * revs))
    result = contact_run(params, scene, y0, t_end, args, n_save)
    o = {k: np.asarray(v) for k, v in result.outputs.items()}
    summary = {"preset": preset.name, "params": params, "t_end": t_end, "revolutions": revs,
               "success": bool(result.success), "code": int(result.code), "message": result.message,
               "solver": result.solver, "stats": {k: int(v) for k, v in result.stats.items()}}
    if result.success:
        prec = precession(result.ts, o["disk_x"], o["disk_y"], o["disk_vx"], o["disk_vy"], params["N"],
                          window=window(params, t_end))
        k = np.asarray(result.ts) >= prec.ts[0]
        normal = o["normal_forces"][k] if o["normal_forces"].size else np.zeros((int(k.sum()), 0))
        summary.update(prec.as_dict())
        summary.update({
            "window": [float(prec.ts[0]), float(prec.ts[-1])],
            "max_disk_x": float(o["disk_x"][k].max()), "min_disk_x": float(o["disk_x"][k].min()),
            "max_radius": float(o["radius"][k].max()),
            "max_normal_force": float(o["normal_forces"].max()) if normal.size else 0.0,  # whole run
            "contact_fraction": float(np.mean(np.any(normal > 1e-9, axis=1))) if normal.size else 0.0,
            "energy_residual": energy_residual(scene, result.ys),
        })
    else:
        valid = _valid(result)
        summary["last_valid_time"] = float(np.asarray(result.ts)[valid][-1]) if valid.any() else None
    stem = os.path.join(args.out, preset.name)
    np.savez(stem + ".npz", ts=np.asarray(result.ts), ys=np.asarray(result.ys), **o)
    files = {"data": stem + ".npz", "summary": stem + ".json"}
    if result.success:
        files["plot"] = plot_precession(result, prec, stem + ".png", clearance=params["chi"],
                                        title=f"{preset.name}: N = {params['N']}, eps = {params['eps']}")
    summary["files"] = files
    write_json(stem + ".json", summary, indent=2)
    if args.json:
        print(json.dumps(summary, indent=2))
        return 0 if result.success else 3
    print(f"{preset.name}: {summary['message']} ({summary['solver']}, {summary['stats']['num_steps']} steps)")
    if not result.success:
        summary["t_end"] = t_end
        print(_failure_line(summary))
        return 3
    print(f"  <Lambda> = {summary['mean_Lambda']:.4f} ({summary['direction']} whirl), max disk x "
          f"{summary['max_disk_x']:.5f}, contact {100 * summary['contact_fraction']:.1f}% of the time, "
          f"energy residual {summary['energy_residual']:.1e}")
    print(f"  wrote {stem}.npz, .json, .png")
    return 0


