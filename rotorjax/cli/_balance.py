"""`balance` and `identify`: model 002's balancing machine from measured vibration."""

import json
import os

import numpy as np

from ._common import InputError, NumericalError, Stages, name_list, preset_and_params, prepare_out, int_list


def cmd_balance(args) -> int:
    from rotorjax import identify as idf
    from rotorjax.plot import plot_balance

    path = idf.resolve_data(args.runs) if args.runs else idf.BALANCING_RUNS
    planes = int_list("--planes", args.planes) if args.planes else None
    if args.holes is not None and args.holes < 2:
        raise InputError(f"--holes {args.holes}: a split needs >= 2 equally spaced holes (omit --holes for none)")
    prepare_out(args.out)
    data = idf.balancing_runs(path, planes)
    planes = list(data.planes)
    X0 = data.X0
    K = idf.influence_from_trials(X0, data.X_trials, data.trial_unbalances)
    W = -idf.unbalance_from_vibration(K, X0) if K.shape[0] == K.shape[1] else idf.least_squares_correction(K, X0)
    if not np.all(np.isfinite(W)):
        raise NumericalError("balance: the corrections are not finite (a singular influence matrix: do two trial "
                             "planes act alike?)")
    predicted = X0 + K @ W
    warnings = []
    cond = float(np.linalg.cond(K))
    if cond > 1e6:
        warnings.append(f"the influence matrix is ill-conditioned (condition number {cond:.2g}): the planes act "
                        "almost alike on the sensors, so the corrections are uncertain")
    speed = data.speed
    # residual unbalance from the phasors' noise: sigma_X = rms residual * sqrt(2 / samples)
    sigma_X = np.asarray(data.base["residual_rms"]) * np.sqrt(2.0 / max(data.n_samples_base, 1))
    sigma_U = np.sqrt(np.abs(np.linalg.pinv(K)) ** 2 @ sigma_X**2)
    residual_gmm = float(np.sum(sigma_U)) * 1e6
    initial_gmm = float(np.sum(np.abs(W))) * 1e6
    out = {"runs_file": data.path, "speed_rad_s": speed, "speed_rpm": speed * 30 / np.pi,
           "sensors": list(data.sensors),
           "phase_convention": "angles from the once-per-revolution mark, in the direction of rotation",
           "influence_matrix": [[{"magnitude": float(abs(k)), "angle_deg": float(np.degrees(np.angle(k)))}
                                 for k in row] for row in K],
           "corrections": [], "vibration_before": [float(abs(x)) for x in X0],
           "predicted_vibration_after": [float(abs(x)) for x in predicted],
           "residual_unbalance_g_mm": residual_gmm, "influence_condition_number": cond, "warnings": warnings}
    for p, w in zip(planes, W):
        c = {"plane": p, "unbalance_kg_m": float(abs(w)), "angle_deg": float(np.degrees(np.angle(w)) % 360),
             "mass_g": float(abs(w) / args.radius * 1e3), "radius_m": args.radius}
        if args.holes:
            holes = np.arange(args.holes) * 2 * np.pi / args.holes
            (ma, aa), (mb, ab) = idf.split_onto_holes(w / args.radius * 1e3, holes)
            c["holes"] = [{"angle_deg": float(np.degrees(aa)), "mass_g": ma},
                          {"angle_deg": float(np.degrees(ab)), "mass_g": mb}]
        out["corrections"].append(c)
    out["rotor_mass_kg"] = args.rotor_mass
    out["iso_grade_before"] = idf.grade_reached(initial_gmm, args.rotor_mass, speed)
    out["iso_grade_reached"] = idf.grade_reached(residual_gmm, args.rotor_mass, speed)
    out["permissible_unbalance_g_mm"] = {str(G): idf.permissible_unbalance(G, args.rotor_mass, speed)
                                         for G in (1.0, 2.5, 6.3, 16.0)}
    stem = os.path.join(args.out, "balance")
    plot_balance(stem + ".png", X0, predicted, np.asarray(W) / args.radius * 1e3, planes=planes,
                 title=f"balancing at {speed:.1f} rad/s, {len(planes)} plane(s), radius {args.radius:g} m")
    out["files"] = {"plot": stem + ".png"}
    if args.json:
        print(json.dumps(out, indent=2))
        return 0
    print(f"balancing at {speed:.2f} rad/s ({out['speed_rpm']:.0f} rpm), {len(planes)} planes, "
          f"{len(data.sensors)} sensors:")
    for c in out["corrections"]:
        print(f"  plane {c['plane']}: add {c['mass_g']:.3f} g at {c['angle_deg']:.1f} deg (radius {c['radius_m']} m)")
        for h in c.get("holes", []):
            print(f"    or {h['mass_g']:.3f} g in the hole at {h['angle_deg']:.1f} deg")
    print("  vibration before " + ", ".join(f"{v:.3g}" for v in out["vibration_before"])
          + " m; predicted after " + ", ".join(f"{v:.3g}" for v in out["predicted_vibration_after"]) + " m")
    print(f"  ISO 21940-11 grade reached: G{out['iso_grade_reached']} (before: G{out['iso_grade_before']}), "
          f"rotor mass {args.rotor_mass:g} kg")
    for w in warnings:
        print(f"  warning: {w}")
    print(f"  wrote {stem}.png")
    return 0


#: Parameters `identify --fit` can estimate.
FITTABLE = ("k1", "k2", "c1", "c2", "m", "I")


def cmd_identify(args) -> int:
    from rotorjax import identify as idf
    from rotorjax.plot import plot_identification

    preset, params = preset_and_params(args, "identify", "machine")
    fit = name_list("--fit", args.fit, FITTABLE)
    path = idf.resolve_data(args.data) if args.data else idf.RUNUP
    prepare_out(args.out)
    stages = Stages("identify", 4, enabled=not args.json)
    stages("reading the signals")
    cols = idf.read_signals(path)
    if len(cols["sensors"]) < 2:
        raise InputError(f"{path}: the balancing machine needs two sensor columns (x1, x2), found "
                         f"{', '.join(cols['sensors'])}")
    x = np.stack([cols[s] for s in cols["sensors"][:2]], axis=1)
    stages("order tracking (1x phasors per revolution)")
    track = idf.order_track(cols["time"], x, tacho=cols["tacho"], revolutions_per_block=args.block, full=True)
    speeds, X = track.speeds, track.X
    keep = speeds >= args.min_speed
    if keep.sum() < max(4, len(fit)):
        raise InputError(f"{path}: {int(keep.sum())} revolutions above --min-speed {args.min_speed:g} rad/s; "
                         f"need at least {max(4, len(fit))}")
    base, planes, U = preset.build(params)
    unb = None if args.fit_unbalance else U
    stages("Levenberg-Marquardt fit (autodiff Jacobians)")
    res = idf.identify(base, speeds[keep], X[keep], planes, fit=fit, unbalances=unb, tracking=track)
    out = {"preset": preset.name, "data": path, "fit": list(fit), "n_points": int(keep.sum()),
           "speed_range_rad_s": [float(speeds[keep].min()), float(speeds[keep].max())],
           "start": {k: params[k] for k in fit}, **res.as_dict()}
    stem = os.path.join(args.out, "identify_" + preset.name)
    stages("the model's 95% band, plot")
    Xf, lo, hi = idf.response_band(res, base, speeds[keep], planes, unbalances=unb)
    plot_identification(stem + ".png", speeds[keep], X[keep], Xf, lo, hi,
                        title=f"{preset.name}: fit of {', '.join(fit)} to {os.path.basename(path)}",
                        channels=list(cols["sensors"][:2]))
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
