"""`balance` and `identify`: model 002's balancing machine from measured vibration."""

import json
import os

from ._common import InputError, Stages, build, int_list, name_list, out_stem, prepare_out, preset_and_params


def cmd_balance(args) -> int:
    from rotorjax import identify as idf
    from rotorjax.plot import plot_balance

    path = idf.resolve_data(args.runs) if args.runs else idf.BALANCING_RUNS
    planes = int_list("--planes", args.planes) if args.planes else None
    if args.holes is not None and args.holes < 2:
        raise InputError(f"--holes {args.holes}: a split needs >= 2 equally spaced holes (omit --holes for none)")
    prepare_out(args.out)
    res = idf.balance(idf.balancing_runs(path, planes), radius=args.radius, holes=args.holes,
                      rotor_mass=args.rotor_mass)
    out = res.as_dict()
    stem = os.path.join(args.out, "balance")
    plot_balance(stem + ".png", res.X0, res.predicted, res.masses_g, planes=list(res.planes),
                 title=f"balancing at {res.speed:.1f} rad/s, {len(res.planes)} plane(s), radius {args.radius:g} m")
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

    preset, params = preset_and_params(args, "identify", "machine")
    fit = name_list("--fit", args.fit, idf.FITTABLE)
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
    plot_identification(stem + ".png", found.speeds, found.X, found.fitted, found.band_lo, found.band_hi,
                        title=f"{preset.name}: fit of {', '.join(fit)} to {os.path.basename(path)}",
                        channels=list(found.sensors))
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
