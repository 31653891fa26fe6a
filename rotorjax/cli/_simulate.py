"""`rotorjax simulate`: a preset's scene (or a rotor file's) in time."""

import dataclasses
import json
import re

import numpy as np

from ._common import (InputError, build, out_stem, prepare_out, preset_and_params, save_figure, write_json,
                      wrong_kind)

#: kinds of preset that are simulated (rotor files included)


def summarize(result, scene, params, preset_name, t_end, revolutions=5) -> dict:
    """The JSON summary of one simulation: the preset, its parameters and the end
    time, then `rotorjax.analysis.simulation_summary` (the `final_*` values only
    after a success, `null` otherwise; after a failure `last_valid_time` and
    `last_valid_whirl_amplitude` describe the last valid saved state)."""
    from rotorjax.analysis._summary import simulation_summary

    return {"preset": preset_name, "params": params, "t_end": float(t_end),
            **simulation_summary(result, scene, revolutions)}


def _failure_line(summary):
    at = summary.get("last_valid_time")
    where = "no valid saved state" if at is None else f"last valid saved state at t = {at:.6g}"
    line = f"  the run failed before t_end = {summary['t_end']:.6g} ({where}): no final state to report"
    films = summary.get("last_valid_film_eccentricity")
    if films:
        name, eps = max(films.items(), key=lambda kv: kv[1])
        kind, node = re.fullmatch(r"(journal|sfd)(\d+)", name).groups()   # the films' output names
        kind = "journal bearing" if kind == "journal" else "squeeze-film damper"
        line += (f"\n  the {kind} at node {node} ({name}) had eccentricity {eps:.4f} at t = {at:.6g}"
                 + (": its journal was running into the wall (the film cannot carry the load: lower the load or "
                    "unbalance, or raise the speed, viscosity or length)" if eps > 0.9 else ""))
    return line


def cmd_simulate(args) -> int:
    from rotorjax.analysis import plan_run
    from rotorjax.analysis._summary import has_disk_motion, revolutions_of, run, saves_for

    preset, params = preset_and_params(args, "simulate", speed_option=args.speed)
    setup = build(preset, params)
    if setup.y0 is None:
        raise wrong_kind(preset, "simulate")
    t_end = setup.t_end if args.t_end is None else args.t_end
    if t_end is None:
        raise InputError(f"{preset.name}: no default run length at {preset.speed_key} = "
                         f"{params[preset.speed_key]:g}; give --speed W (> 0) or --t-end")
    try:
        plan = plan_run(setup.scene, setup.y0, t_end, args.rtol, args.max_steps, modes=args.modes)
    except InputError as e:
        raise InputError(f"--modes: {e}") from None
    prepare_out(args.out)
    scene, events = plan.scene, setup.extras.get("events", False)
    setup = dataclasses.replace(setup, scene=scene, y0=plan.y0)
    n_save = args.n_save or saves_for(scene, t_end, setup.extras.get("saves_per_revolution"))
    solver = ("kvaerno5" if plan.implicit else "dopri8") if args.solver == "auto" and not events else args.solver
    result = run(scene, setup.y0, t_end, events=events, saveat=n_save, solver=solver, rtol=args.rtol,
                 atol=args.atol, max_steps=args.max_steps, progress=not args.json)
    stem = out_stem(args.out, preset)
    if has_disk_motion(result):
        summary, files = _precession(preset, params, setup, t_end, result, stem, revolutions_of(scene, t_end))
    else:
        summary, files = _orbit(preset, params, setup, t_end, result, stem)
    np.savez(stem + ".npz", ts=np.asarray(result.ts), ys=np.asarray(result.ys),
             **{k: np.asarray(v) for k, v in result.outputs.items()})
    summary["files"] = files
    summary["integration"] = dict(plan.as_dict(), solver_option=args.solver)
    write_json(stem + ".json", summary, indent=2)
    if args.json:
        print(json.dumps(summary, indent=2))
        return 0 if summary["success"] else 3
    print(f"{preset.name}: {summary['message']} ({summary['solver']}, {summary['stats']['num_steps']} steps)")
    if plan.modes is not None:
        print(f"  {plan.reason}; modes above {plan.cutoff_frequency:.4g} rad/{preset.time_unit} left out "
              "(--modes all keeps them)")
    if plan.implicit and args.solver == "auto" and not events:
        print(f"  Kvaerno5 (implicit): a decaying eigenvalue ({plan.estimate.fastest_decay:.3g} per "
              f"{preset.time_unit}) would hold Dopri8 to about {plan.estimate.explicit_steps:.3g} steps "
              "(--solver dopri8 overrides)")
    if not summary["success"]:
        print(_failure_line(dict(summary, t_end=t_end)))
        return 3
    if "mean_Lambda" in summary:
        print(f"  <Lambda> = {summary['mean_Lambda']:.4f} ({summary['direction']} whirl), max disk x "
              f"{summary['max_disk_x']:.5f}, contact {100 * summary['contact_fraction']:.1f}% of the time"
              + (f", energy residual {summary['energy_residual']:.1e}" if "energy_residual" in summary else ""))
    elif "final_whirl_amplitude" in summary:
        print(f"  final whirl amplitude {summary['final_whirl_amplitude']:.6g}, max over last "
              f"{summary['revolutions_in_window']} revolutions "
              f"{summary['max_whirl_amplitude_last_revolutions']:.6g}")
    if "weight_angles_final" in summary:
        print("  weight angles rel. rotor (rad): " + ", ".join(f"{a:.4f}" for a in summary["weight_angles_final"]))
    print(f"  wrote {stem}.npz, .json" + (", .png" if "plot" in files else ""))
    return 0


def _orbit(preset, params, setup, t_end, result, stem):
    """Summary and plot of a run judged by its outputs over the last revolutions."""
    from rotorjax.analysis._summary import speed_varies, speeds_at
    from rotorjax.plot import plot_simulation

    summary = summarize(result, setup.scene, params, preset.name, t_end)
    run_up = speed_varies(setup.scene, result.ts)
    save_figure(plot_simulation(result, title=f"{preset.name}: {preset.source}",
                                speed=speeds_at(setup.scene, result.ts) if run_up else None,
                                x_label="speed" if run_up else "time", time_unit=preset.time_unit,
                                unit=preset.length_unit), stem + ".png")
    return summary, {"plot": stem + ".png", "data": stem + ".npz", "summary": stem + ".json"}


def _precession(preset, params, setup, t_end, result, stem, revolutions):
    """Summary and plot of a run judged by the precession of its disk centre."""
    from rotorjax.analysis._summary import analysis_window, precession_summary, speeds_at, valid_states
    from rotorjax.plot import plot_precession

    summary = {"preset": preset.name, "params": params, "t_end": t_end, "revolutions": revolutions,
               "success": bool(result.success), "code": int(result.code), "message": result.message,
               "solver": result.solver, "stats": {k: int(v) for k, v in result.stats.items()}}
    files = {"data": stem + ".npz", "summary": stem + ".json"}
    if not result.success:
        valid = valid_states(result)
        summary["last_valid_time"] = float(np.asarray(result.ts)[valid][-1]) if valid.any() else None
        return summary, files
    speed = abs(float(speeds_at(setup.scene, [t_end])[0]))
    window = analysis_window(t_end, speed, setup.extras.get("analysis_revolutions", 300))
    details, prec = precession_summary(result, setup.scene, window)
    summary.update(details)
    files["plot"] = save_figure(plot_precession(result, prec, clearance=setup.extras.get("clearance"),
                                                title=f"{preset.name}: {preset.speed_key} = "
                                                      f"{params[preset.speed_key]:g}"), stem + ".png")
    return summary, files
