"""`balance` and `identify`: model 002's balancing machine from measured vibration;
on a rotor file they hand over to `_fe_balance` and `_fe_identify`."""

import json
import os

from ._common import InputError, Stages, build, get_preset, int_list, name_list, out_stem, prepare_out
from ._common import is_rotor_file, preset_and_params

#: options of the rotor-file forms, with their defaults (given with the balancing machine: bad input)
_ROTOR_ONLY_BALANCE = {"--set": ("set", None), "--data": ("data", None), "--speeds": ("speeds", None),
                       "--method": ("method", "ls"), "--influence": ("influence", None), "--model": ("model", False),
                       "--service-speed": ("service_speed", None), "--grade": ("grade", 2.5)}
_ROTOR_ONLY_IDENTIFY = {"--weights": ("weights", "relative"), "--covariance": ("covariance", "classical"),
                        "--starts": ("starts", 32), "--spread": ("spread", 10.0), "--method": ("method", "lm")}


def _not_here(args, options, where):
    for option, (dest, default) in options.items():
        if getattr(args, dest, default) != default:
            raise InputError(f"{option} applies to {where}")


def cmd_balance(args) -> int:
    from rotorjax import identify as idf
    from rotorjax.plot import plot_balance
    from ._common import save_figure

    if args.preset is not None:
        from ._fe_balance import cmd_fe_balance

        for option, dest in (("--runs", "runs"), ("--holes", "holes")):
            if getattr(args, dest) is not None:
                raise InputError(f"{option} applies to the balancing machine (no ROTOR); with a rotor file give "
                                 "--data PHASOR_FILE")
        if args.radius != 0.01:
            raise InputError("--radius applies to the balancing machine (no ROTOR): a rotor file's corrections are "
                             "unbalances, kg m")
        if args.model:
            if args.influence not in (None, "model"):
                raise InputError(f"--model and --influence {args.influence} contradict each other")
            args.influence = "model"
        args.influence = args.influence or "trials"
        return cmd_fe_balance(args)
    _not_here(args, _ROTOR_ONLY_BALANCE, "a rotor file: `rotorjax balance ROTOR.toml --data FILE ...`")
    args.rotor_mass = 10.0 if args.rotor_mass is None else args.rotor_mass

    path = idf.resolve_data(args.runs) if args.runs else idf.BALANCING_RUNS
    planes = int_list("--planes", args.planes) if args.planes else None
    if args.holes is not None and args.holes < 2:
        raise InputError(f"--holes {args.holes}: a split needs >= 2 equally spaced holes (omit --holes for none)")
    prepare_out(args.out)
    res = idf.balance(idf.balancing_runs(path, planes), radius=args.radius, holes=args.holes,
                      rotor_mass=args.rotor_mass)
    out = res.as_dict()
    stem = os.path.join(args.out, "balance")
    save_figure(plot_balance(before=res.X0, after=res.predicted, corrections=res.masses_g, planes=list(res.planes),
                             title=f"balancing at {res.speed:.1f} rad/s, {len(res.planes)} plane(s), "
                                   f"radius {args.radius:g} m"), stem + ".png", bbox_inches="tight")
    out["files"] = {"plot": stem + ".png"}
    if args.json:
        print(json.dumps(out, indent=2))
        return 0
    print(f"balancing at {res.speed:.2f} rad/s ({out['speed_rpm']:.0f} rpm), {len(res.planes)} planes, "
          f"{len(res.sensors)} sensors:")
    for c in out["corrections"]:
        print(f"  plane {c['plane']}: add {c['mass_g']:.3f} g at {c['angle_deg']:.1f} deg (radius {c['radius_m']} m)")
        for h in c.get("holes", []):
            print(f"    or {h['mass_g']:.3f} g in the hole at {h['angle_deg']:.1f} deg")
    print("  vibration before " + ", ".join(f"{v:.3g}" for v in out["vibration_before"])
          + " m; predicted after " + ", ".join(f"{v:.3g}" for v in out["predicted_vibration_after"]) + " m")
    print(f"  ISO 21940-11 grade reached: G{out['iso_grade_reached']} (before: G{out['iso_grade_before']}), "
          f"rotor mass {args.rotor_mass:g} kg")
    for w in res.warnings:
        print(f"  warning: {w}")
    print(f"  wrote {stem}.png")
    return 0


def cmd_identify(args) -> int:
    from rotorjax import identify as idf
    from rotorjax.plot import plot_identification
    from ._common import save_figure

    if is_rotor_file(get_preset(args.preset)):
        from ._fe_identify import cmd_fe_identify

        for option, dest in (("--block", "block"), ("--min-speed", "min_speed")):
            if getattr(args, dest) is not None:
                raise InputError(f"{option} applies to the balancing machine's run-up signals, not to a rotor "
                                 "file's phasor file")
        return cmd_fe_identify(args)
    _not_here(args, _ROTOR_ONLY_IDENTIFY, "a rotor file: `rotorjax identify ROTOR.toml --data FILE ...`")
    if args.fit_unbalance not in (None, True):
        raise InputError(f"--fit-unbalance {args.fit_unbalance}: the balancing machine fits its own unbalances; "
                         "give --fit-unbalance without nodes")
    args.fit_unbalance = args.fit_unbalance is True
    args.block = 1 if args.block is None else args.block
    args.min_speed = 0.0 if args.min_speed is None else args.min_speed
    preset, params = preset_and_params(args, "identify")
    fit = name_list("--fit", args.fit or "k1,k2,c1,c2", idf.FITTABLE)
    path = idf.resolve_data(args.data) if args.data else idf.RUNUP
    scene = build(preset, params).scene
    prepare_out(args.out)
    stages = Stages("identify", 4, enabled=not args.json)
    found = idf.identify_runup(scene, path, fit, block=args.block, min_speed=args.min_speed,
                               fit_unbalance=args.fit_unbalance, stage=stages)
    res = found.result
    out = {"preset": preset.name, "data": path, "fit": list(fit), "n_points": found.n_points,
           "speed_range_rad_s": [float(found.speeds.min()), float(found.speeds.max())],
           "start": {k: params[k] for k in fit}, **res.as_dict()}
    stem = out_stem(args.out, preset, "identify_")
    save_figure(plot_identification(speeds=found.speeds, data=found.X, fit=found.fitted, lo=found.band_lo,
                                    hi=found.band_hi,
                                    title=f"{preset.name}: fit of {', '.join(fit)} to {os.path.basename(path)}",
                                    channels=list(found.sensors)), stem + ".png")
    out["files"] = {"plot": stem + ".png"}
    stages.close()
    if args.json:
        print(json.dumps(out, indent=2))
    else:
        print(f"{preset.name}: identified from {out['n_points']} revolutions of {path}")
        for k in fit:
            lo_k, hi_k = res.intervals[k]
            print(f"  {k} = {res.estimates[k]:.6g}   95% [{lo_k:.6g}, {hi_k:.6g}]")
        for w in res.warnings:
            print(f"  warning: {w}")
        if not res.converged:
            print("  the fit did not converge: the estimates above are the last iterate")
        print(f"  wrote {stem}.png")
    return 0 if res.converged else 3
