"""The `rotorjax` command: a thin layer over the public functions."""

import argparse
import json
import os
import sys

import numpy as np


class UsageError(ValueError):
    pass


def _parse_sets(items):
    out = {}
    for item in items or ():
        if "=" not in item:
            raise UsageError(f"--set expects key=value, got {item!r}")
        key, value = item.split("=", 1)
        out[key.strip()] = value.strip()
    return out


def _speed_at(scene, ts):
    import jax

    return np.asarray(jax.vmap(scene.speed.speed)(np.asarray(ts)))


def summarize(result, scene, params, preset_name, t_end, revolutions=5) -> dict:
    """The JSON summary of one simulation. After a failure, the values describe the
    last valid saved state (`last_valid_time`), and `success` is false."""
    ts = np.asarray(result.ts)
    valid = np.isfinite(ts) & np.all(np.isfinite(np.asarray(result.ys)), axis=-1)
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
    speed_end = abs(float(_speed_at(scene, ts[-1:])[0]))
    window = revolutions * 2 * np.pi / speed_end if speed_end > 0 else ts[-1] - ts[0]
    last = ts >= ts[-1] - window
    summary.update({
        "last_valid_time": float(ts[-1]),
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


def _contact_run(preset, params, scene, y0, t_end, args, n_save):
    """One run of a contact preset, smoothed or event-located (`events`)."""
    import rotorjax as rj
    from rotorjax.solve import simulate_events

    if params["events"]:
        solver = "dopri8" if args.solver == "auto" else args.solver
        return simulate_events(scene, y0, (0.0, t_end), saveat=n_save, solver=solver, rtol=args.rtol,
                               atol=args.atol, max_steps=args.max_steps)
    return rj.simulate(scene, y0, (0.0, t_end), saveat=n_save, solver=args.solver, rtol=args.rtol,
                       atol=args.atol, max_steps=args.max_steps)


def _window(params, t_end):
    """The analysis window: the last 300 revolutions (the paper's), at most the
    second half of the run."""
    revs = t_end * params["N"] / (2 * np.pi)
    return (max(0.5, 1 - 300 / revs), 1.0)


def _contact_simulate(preset, params, args) -> int:
    from rotorjax.analysis import precession
    from rotorjax.contact._scene import energy_residual
    from rotorjax.plot import plot_precession

    scene, y0, t_end = preset.build(params)
    if args.t_end is not None:
        if not args.t_end > 0:
            raise UsageError(f"--t-end must be > 0, got {args.t_end}")
        t_end = args.t_end
    revs = t_end * params["N"] / (2 * np.pi)
    n_save = args.n_save or max(4000, int(40 * revs))
    result = _contact_run(preset, params, scene, y0, t_end, args, n_save)
    o = {k: np.asarray(v) for k, v in result.outputs.items()}
    summary = {"preset": preset.name, "params": params, "t_end": t_end, "revolutions": revs,
               "success": bool(result.success), "code": int(result.code), "message": result.message,
               "solver": result.solver, "stats": {k: int(v) for k, v in result.stats.items()}}
    if result.success:
        prec = precession(result.ts, o["disk_x"], o["disk_y"], o["disk_vx"], o["disk_vy"], params["N"],
                          window=_window(params, t_end))
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
    os.makedirs(args.out, exist_ok=True)
    stem = os.path.join(args.out, preset.name)
    np.savez(stem + ".npz", ts=np.asarray(result.ts), ys=np.asarray(result.ys), **o)
    files = {"data": stem + ".npz", "summary": stem + ".json"}
    if result.success:
        files["plot"] = plot_precession(result, prec, stem + ".png", clearance=params["chi"],
                                        title=f"{preset.name}: N = {params['N']}, eps = {params['eps']}")
    summary["files"] = files
    with open(stem + ".json", "w") as f:
        json.dump(summary, f, indent=2)
    if args.json:
        print(json.dumps(summary, indent=2))
    else:
        print(f"{preset.name}: {summary['message']} ({summary['solver']}, {summary['stats']['num_steps']} steps)")
        if result.success:
            print(f"  <Lambda> = {summary['mean_Lambda']:.4f} ({summary['direction']} whirl), max disk x "
                  f"{summary['max_disk_x']:.5f}, contact {100 * summary['contact_fraction']:.1f}% of the time, "
                  f"energy residual {summary['energy_residual']:.1e}")
        print(f"  wrote {stem}.npz, .json" + (", .png" if result.success else ""))
    return 0 if result.success else 3


def cmd_hopf(args) -> int:
    from rotorjax.analysis import hopf_points, hopf_speed_gradient

    preset, params = _preset_and_params(args, "hopf", "contact")
    lo, hi = args.range
    if not 0 <= lo < hi:
        raise UsageError(f"--range must satisfy 0 <= LO < HI, got {lo} {hi}")
    from rotorjax.presets import cantilever_limiters as cl

    rotor = cl.build_rotor(params)
    points = hopf_points(rotor.state_matrix, lo, hi, n_scan=args.n_scan)
    out = {"preset": preset.name, "params": params, "range": [lo, hi],
           "unit": "speed N and whirl frequency in 1/T*", "hopf_points": []}
    for h in points:
        lam, fwd = rotor.whirl_direction(h.speed)

        def a_of(s, eta_e):
            return cl.build_rotor(dict(params, eta_e=eta_e)).state_matrix(s)

        d = h.as_dict()
        d.update({"N_crit": h.speed, "whirl_frequency": h.frequency,
                  "whirl": "forward" if bool(fwd) else "backward",
                  "dN_crit_d_eta_e": hopf_speed_gradient(a_of, h.speed, params["eta_e"])})
        out["hopf_points"].append(d)
    if points:
        out["N_crit"], out["whirl_frequency"] = points[0].speed, points[0].frequency
        ratio = params["eta_e"] / params["eta_i"] if params["eta_i"] > 0 else None
        out["eta_e_over_eta_i"] = ratio
        if ratio is not None:
            out["paper_fit"] = {"N_crit": 2.47 * ratio + 1.64, "formula": "N_crit = 2.47 eta_e/eta_i + 1.64"}
    if args.json:
        print(json.dumps(out, indent=2))
    else:
        if not points:
            print(f"{preset.name}: straight-line rotation keeps its stability over N in [{lo}, {hi}]")
        for d in out["hopf_points"]:
            print(f"{preset.name}: Hopf point at N = {d['N_crit']:.6f} (whirl frequency "
                  f"{d['whirl_frequency']:.6f}, {d['whirl']} whirl); dN/d eta_e = {d['dN_crit_d_eta_e']:.4f}")
        if "paper_fit" in out:
            print(f"  the paper's fit gives N_crit = {out['paper_fit']['N_crit']:.4f}")
    return 0


def cmd_bifurcation(args) -> int:
    import equinox as eqx
    import jax.numpy as jnp

    import rotorjax as rj
    from rotorjax.analysis import precession
    from rotorjax.plot import plot_bifurcation
    from rotorjax.sweep import sweep

    preset, params = _preset_and_params(args, "bifurcation", "contact")
    key, lo, hi, n = args.param[0], float(args.param[1]), float(args.param[2]), int(args.param[3])
    if key not in ("eps", "N", "phase", "f_S", "chi", "kappa", "eta_S"):
        raise UsageError(f"--param must be one of eps, N, phase, f_S, chi, kappa, eta_S; got {key!r}")
    if n < 2 or not hi > lo:
        raise UsageError(f"--param needs LO < HI and NP >= 2, got {lo} {hi} {n}")
    if params["events"]:
        raise UsageError("bifurcation sweeps use the smoothed contact (events=0); the event-located "
                         "contact runs one point at a time (`simulate --set events=1`)")
    base, y0, t_end = preset.build(params)
    if key in ("f_S", "chi", "kappa", "eta_S") and base.limiters is None:
        raise UsageError(f"--param {key} needs limiters (n_limiters > 0)")
    preset.build(dict(params, **{key: lo}))  # validates the range's ends
    preset.build(dict(params, **{key: hi}))
    n_save = int(40 * params["revolutions"])
    where = {"eps": lambda s: s.eps, "N": lambda s: s.N, "phase": lambda s: s.phase,
             "f_S": lambda s: s.limiters.friction, "chi": lambda s: s.limiters.clearance,
             "kappa": lambda s: s.limiters.stiffness, "eta_S": lambda s: s.limiters.damping}[key]

    def run(p):
        v = p[key]
        old = where(base)
        scene = eqx.tree_at(where, base, jnp.broadcast_to(v, jnp.shape(old)))
        t1 = 2 * jnp.pi / scene.N * params["revolutions"]
        r = rj.simulate(scene, y0, (0.0, t1), saveat=n_save, solver="dopri8" if args.solver == "auto"
                        else args.solver, rtol=args.rtol, atol=args.atol, max_steps=args.max_steps)
        o = r.outputs
        return {"ts": r.ts, "x": o["disk_x"], "y": o["disk_y"], "vx": o["disk_vx"], "vy": o["disk_vy"],
                "code": r.code}

    values = np.linspace(lo, hi, n)
    res = sweep(run, {key: values}, chunk_size=args.chunk, progress=not args.json)
    v = res.values
    rows, extrema, lams = [], [], []
    for i, val in enumerate(values):
        code = int(np.asarray(v["code"])[i])
        speed = params["N"] if key != "N" else val
        t_end_i = 2 * np.pi / speed * params["revolutions"]
        if code != 0:
            rows.append({key: float(val), "code": code, "mean_Lambda": None})
            extrema.append(np.zeros(0))
            lams.append(np.nan)
            continue
        pr = precession(np.asarray(v["ts"])[i], np.asarray(v["x"])[i], np.asarray(v["y"])[i],
                        np.asarray(v["vx"])[i], np.asarray(v["vy"])[i], speed,
                        window=_window(dict(params, N=speed), t_end_i))
        rows.append({key: float(val), "code": 0, "mean_Lambda": pr.mean, "direction": pr.direction,
                     "extrema_x": [float(pr.extrema_x.min()), float(pr.extrema_x.max())] if pr.extrema_x.size
                     else None})
        extrema.append(pr.extrema_x)
        lams.append(pr.mean)
    lams = np.asarray(lams)
    switches = [0.5 * (values[i] + values[i + 1]) for i in range(n - 1)
                if np.isfinite(lams[i]) and np.isfinite(lams[i + 1]) and np.sign(lams[i]) != np.sign(lams[i + 1])]
    os.makedirs(args.out, exist_ok=True)
    stem = os.path.join(args.out, f"bifurcation_{preset.name}_{key}")
    plot_bifurcation(values, extrema, lams, stem + ".png", key,
                     title=f"{preset.name}: extrema of disk x vs {key}")
    out = {"preset": preset.name, "param": key, "params": params, "points": rows,
           "Lambda_sign_switches": switches, "files": {"plot": stem + ".png", "data": stem + ".json"}}
    with open(stem + ".json", "w") as f:
        json.dump(out, f, indent=2)
    if args.json:
        print(json.dumps(out, indent=2))
    else:
        for r in rows:
            lam = "failed" if r["mean_Lambda"] is None else f"<Lambda> = {r['mean_Lambda']:+.4f}"
            print(f"  {key} = {r[key]:.6g}: {lam}")
        print("  <Lambda> changes sign near " + (", ".join(f"{s:.6g}" for s in switches) or "nowhere")
              + f"; wrote {stem}.png")
    return 0 if all(r["code"] == 0 for r in rows) else 3


def cmd_balance(args) -> int:
    from rotorjax import identify as idf

    path = args.runs or idf.BALANCING_RUNS
    cols = idf.read_signals(path)
    runs = idf.runs_from_signals(cols)
    base = [r for r in runs if r["trial"] is None]
    trials = [r for r in runs if r["trial"] is not None]
    if len(base) != 1:
        raise UsageError(f"{path}: need exactly one run without a trial weight, found {len(base)}")
    planes = sorted({r["trial"][0] for r in trials})
    if not planes:
        raise UsageError(f"{path}: no runs with a trial weight (columns run, trial_plane, trial_unbalance, "
                         "trial_angle): the influence coefficients cannot be estimated")
    if args.planes:
        try:
            wanted = [int(p) for p in args.planes.split(",")]
        except ValueError:
            raise UsageError(f"--planes must be comma-separated plane numbers, got {args.planes!r}") from None
        missing = [p for p in wanted if p not in planes]
        if missing:
            raise UsageError(f"--planes {args.planes}: no trial run for plane(s) {missing} in {path} "
                             f"(trial planes: {planes})")
        planes = wanted
    by_plane = {r["trial"][0]: r for r in trials}
    X0 = base[0]["X"]
    K = idf.influence_from_trials(X0, np.stack([by_plane[p]["X"] for p in planes]),
                                  np.array([by_plane[p]["trial"][1] for p in planes]))
    if K.shape[0] == K.shape[1]:
        W = -idf.unbalance_from_vibration(K, X0)
    else:
        W = idf.least_squares_correction(K, X0)
    predicted = X0 + K @ W
    speed = base[0]["speed"]
    # residual unbalance from the phasors' noise: sigma_X = rms residual * sqrt(2 / samples)
    labels = cols.get("run", np.zeros_like(cols["time"]))
    n_samples = int(np.sum(labels == base[0]["run"]))
    sigma_X = np.asarray(base[0]["residual_rms"]) * np.sqrt(2.0 / max(n_samples, 1))
    sigma_U = np.sqrt(np.abs(np.linalg.pinv(K)) ** 2 @ sigma_X**2)
    residual_gmm = float(np.sum(sigma_U)) * 1e6
    initial_gmm = float(np.sum(np.abs(W))) * 1e6
    out = {"runs_file": path, "speed_rad_s": speed, "speed_rpm": speed * 30 / np.pi,
           "phase_convention": "angles from the once-per-revolution mark, in the direction of rotation",
           "influence_matrix": [[{"magnitude": float(abs(k)), "angle_deg": float(np.degrees(np.angle(k)))}
                                 for k in row] for row in K],
           "corrections": [], "vibration_before": [float(abs(x)) for x in X0],
           "predicted_vibration_after": [float(abs(x)) for x in predicted],
           "residual_unbalance_g_mm": residual_gmm}
    for p, w in zip(planes, W):
        c = {"plane": p, "unbalance_kg_m": float(abs(w)), "angle_deg": float(np.degrees(np.angle(w)) % 360),
             "mass_g": float(abs(w) / args.radius * 1e3), "radius_m": args.radius}
        if args.holes:
            holes = np.arange(args.holes) * 2 * np.pi / args.holes
            (ma, aa), (mb, ab) = idf.split_onto_holes(w / args.radius * 1e3, holes)
            c["holes"] = [{"angle_deg": float(np.degrees(aa)), "mass_g": ma},
                          {"angle_deg": float(np.degrees(ab)), "mass_g": mb}]
        out["corrections"].append(c)
    if args.rotor_mass:
        out["rotor_mass_kg"] = args.rotor_mass
        out["iso_grade_before"] = idf.grade_reached(initial_gmm, args.rotor_mass, speed)
        out["iso_grade_reached"] = idf.grade_reached(residual_gmm, args.rotor_mass, speed)
        out["permissible_unbalance_g_mm"] = {str(G): idf.permissible_unbalance(G, args.rotor_mass, speed)
                                             for G in (1.0, 2.5, 6.3, 16.0)}
    if args.json:
        print(json.dumps(out, indent=2))
    else:
        print(f"balancing at {speed:.2f} rad/s ({out['speed_rpm']:.0f} rpm), {len(planes)} planes:")
        for c in out["corrections"]:
            print(f"  plane {c['plane']}: add {c['mass_g']:.3f} g at {c['angle_deg']:.1f} deg "
                  f"(radius {c['radius_m']} m)")
        print("  vibration before " + ", ".join(f"{v:.3g}" for v in out["vibration_before"])
              + "; predicted after " + ", ".join(f"{v:.3g}" for v in out["predicted_vibration_after"]))
        if "iso_grade_reached" in out:
            print(f"  ISO 21940-11 grade reached: G{out['iso_grade_reached']} (before: G{out['iso_grade_before']})")
    return 0


def cmd_identify(args) -> int:
    from rotorjax import identify as idf

    preset, params = _preset_and_params(args, "identify", "machine")
    fit = tuple(k.strip() for k in args.fit.split(",") if k.strip())
    path = args.data or idf.RUNUP
    cols = idf.read_signals(path)
    x = np.stack([cols[s] for s in cols["sensors"][:2]], axis=1)
    if x.shape[1] != 2:
        raise UsageError(f"{path}: the balancing machine needs two sensor columns (x1, x2)")
    speeds, X = idf.order_track(cols["time"], x, tacho=cols["tacho"], revolutions_per_block=args.block)
    keep = speeds >= args.min_speed
    if keep.sum() < 4:
        raise UsageError(f"{path}: fewer than 4 revolutions above --min-speed {args.min_speed}")
    base, planes, U = preset.build(params)
    res = idf.identify(base, speeds[keep], X[keep], planes, fit=fit,
                       unbalances=None if args.fit_unbalance else U)
    out = {"preset": preset.name, "data": path, "fit": list(fit), "n_points": int(keep.sum()),
           "speed_range_rad_s": [float(speeds[keep].min()), float(speeds[keep].max())],
           "start": {k: params[k] for k in fit}, **res.as_dict()}
    if args.json:
        print(json.dumps(out, indent=2))
    else:
        print(f"{preset.name}: identified from {out['n_points']} revolutions of {path}")
        for k in fit:
            lo, hi = res.intervals[k]
            print(f"  {k} = {res.estimates[k]:.6g}   95% [{lo:.6g}, {hi:.6g}]")
        for w in res.warnings:
            print(f"  warning: {w}")
    return 0 if res.converged else 3


def _branch_problem(preset, params, key):
    """`(F(u, v), u0)` of the preset's stationary reference regime, for
    one-parameter continuation in `key` (elliptic-abb: the balanced regime of a
    circular race, in the rotating frame); None for presets without one."""
    if preset.name != "elliptic-abb":
        return None
    from rotorjax.analysis import rotating_field
    from rotorjax.presets import jeffcott_abb as ja

    regime = ja.balanced_regime(params)
    if not bool(regime.converged):
        raise UsageError(f"no balanced regime at the starting parameters (residual {float(regime.residual):.2e})")

    def F(u, v):
        q = dict(params, **{key: v})
        scene = ja.scene_from_groups(q["chi"], q["eps"], q["alpha"], q["rho1"], q["rho2"], q["delta_n"],
                                     q["delta_b"], nu=q["nu"], n_balls=params["n_balls"], K=q["K"])
        return rotating_field(scene, 0.0, u)

    return F, np.asarray(regime.z)


def cmd_continue(args) -> int:
    from rotorjax import presets
    from rotorjax.analysis import continue_branch, floquet_crossings, trace_boundary

    preset = presets.get(args.preset)
    params = preset.params(_parse_sets(args.set))
    key, key2 = args.param, args.param2
    for k in (key, key2):
        if k is not None and k not in preset.defaults:
            raise UsageError(f"unknown parameter {k!r} for {preset.name}; known: {', '.join(sorted(preset.defaults))}")
        if k is not None and k in preset.topology_keys + preset.integer_keys:
            raise UsageError(f"{k!r} changes the scene's structure: it cannot be continued")
    start = args.start if args.start else [params[key]] + ([params[key2]] if key2 else [])
    if len(start) != (2 if key2 else 1):
        raise UsageError(f"--from needs {2 if key2 else 1} value(s): {key}" + (f" {key2}" if key2 else ""))
    os.makedirs(args.out, exist_ok=True)
    stem = os.path.join(args.out, f"continue_{preset.name}_{key}" + (f"_{key2}" if key2 else ""))
    out = {"preset": preset.name, "param": key, "param2": key2, "start": start}
    if key2:
        if preset.margin is None:
            raise UsageError(f"{preset.name!r} has no reference regime whose boundary could be traced")
        gradient = args.gradient if args.gradient != "auto" else ("fd" if preset.name == "anisotropic-abb" else
                                                                    "autodiff")

        def sigma(a, b):
            return preset.margin(dict(params, **{key: a, key2: b}))

        box = args.box or [np.nan] * 4
        curve = trace_boundary(sigma, start, bounds=(np.array([box[0], box[2]]), np.array([box[1], box[3]])),
                               ds=args.ds, ds_max=args.ds_max, max_points=args.max_points, gradient=gradient,
                               direction=(0.0, 1.0) if args.direction > 0 else (0.0, -1.0))
        out.update({"kind": "stability boundary (margin = 0)", "regime": preset.regime,
                    key: curve.x[:, 0].tolist(), key2: curve.x[:, 1].tolist(),
                    "residuals": curve.residuals.tolist(), "steps": curve.steps.tolist(),
                    "stopped": curve.stopped, "gradient": gradient})
        np.savetxt(stem + ".csv", np.column_stack([curve.x, curve.residuals]), delimiter=",",
                   header=f"{key},{key2},residual", comments="")
        from rotorjax.plot import plot_curves

        plot_curves(curve.x[:, 0], {"boundary": curve.x[:, 1]}, stem + ".png", key, key2,
                    title=f"{preset.name}: stability boundary of {preset.regime}")
    elif preset.name == "anisotropic-abb":
        from rotorjax.presets import anisotropic_abb as ab

        lo, hi = args.to if args.to else (start[0] * 0.5, start[0] * 2)

        def fl(v):
            q = dict(params, **{key: v})
            return ab.main_motion_floquet({k: q[k] for k in ab.GROUPS}, q["n"], q["K"])

        found = floquet_crossings(fl, lo, hi, n_scan=args.max_points if args.max_points < 400 else 60)
        out.update({"kind": "Floquet multipliers of the main motion", "range": [lo, hi], "crossings": found})
        with open(stem + ".csv", "w") as f:
            f.write(f"{key},kind,residual\n")
            for c in found:
                f.write(f"{c['p']},{c['kind']},{c['residual']}\n")
    else:
        prob = _branch_problem(preset, params, key)
        if prob is None:
            raise UsageError(f"{preset.name!r} has no stationary branch to continue in one parameter; trace a "
                             "boundary with --param2, or use `critical-speeds` / `hopf`")
        F, u0 = prob
        lo, hi = args.to if args.to else (-np.inf, np.inf)
        br = continue_branch(F, u0, start[0], p_bounds=(lo, hi), ds=args.ds, ds_max=args.ds_max,
                             max_points=args.max_points, direction=args.direction)
        out.update({"kind": "branch of the balanced regime (rotating frame)", **br.as_dict(),
                    "whirl_amplitude": np.linalg.norm(br.u[:, :2], axis=1).tolist()})
        np.savetxt(stem + ".csv", np.column_stack([br.p, br.margin, br.curve.residuals]), delimiter=",",
                   header=f"{key},margin,residual", comments="")
        from rotorjax.plot import plot_curves

        plot_curves(br.p, {"largest real part": br.margin}, stem + ".png", key, "margin",
                    title=f"{preset.name}: branch in {key}")
    out["files"] = {"data": stem + ".csv", "summary": stem + ".json"}
    if os.path.exists(stem + ".png"):
        out["files"]["plot"] = stem + ".png"
    with open(stem + ".json", "w") as f:
        json.dump(out, f, indent=2)
    if args.json:
        print(json.dumps(out, indent=2))
    else:
        print(f"{preset.name}: {out['kind']}; wrote {stem}.csv, .json")
        for c in out.get("crossings", []) + out.get("events", []):
            print(f"  {c.get('kind')} at {key} = {c['p']:.8g} (residual {c['residual']:.1e})")
        if "stopped" in out:
            print(f"  stopped: {out['stopped']}")
    return 0


_KIND_COMMANDS = {
    "planar": "a planar rotor: use `simulate`, `steady`, `critical-speeds`, `stability-map`",
    "flexible": "a finite-element rotor: use `campbell`, `response`, `critical-speeds`",
    "modal": "model 003's modal shaft: use `steady`, `critical-speeds`, `stability-map`",
    "contact": "model 004's rotor with limiters: use `simulate`, `hopf`, `bifurcation`, `critical-speeds`, "
               "`stability-map`",
    "machine": "a balancing machine: use `balance`, `identify`",
}


def _wrong_kind(preset, command):
    return UsageError(f"`{command}` does not apply to {preset.name!r}, {_KIND_COMMANDS[preset.kind]}")


def _planar(preset, command):
    if preset.kind != "planar":
        raise _wrong_kind(preset, command)
    return preset


def _preset_and_params(args, command, kind):
    """The preset named on the command line, checked to be of `kind`, and its
    parameters with the `--set` overrides applied."""
    from rotorjax import presets

    preset = presets.get(args.preset)
    if preset.kind != kind:
        raise _wrong_kind(preset, command)
    return preset, preset.params(_parse_sets(args.set))


def cmd_simulate(args) -> int:
    import rotorjax as rj
    from rotorjax import presets
    from rotorjax.plot import plot_simulation

    preset = presets.get(args.preset)
    params = preset.params(_parse_sets(args.set))
    if preset.kind == "contact":
        return _contact_simulate(preset, params, args)
    _planar(preset, "simulate")
    scene, y0, t_end = preset.build(params)
    if args.t_end is not None:
        if not args.t_end > 0:
            raise UsageError(f"--t-end must be > 0, got {args.t_end}")
        t_end = args.t_end
    result = rj.simulate(scene, y0, (0.0, t_end), saveat=args.n_save or 4000, solver=args.solver,
                         rtol=args.rtol, atol=args.atol, max_steps=args.max_steps)
    summary = summarize(result, scene, params, preset.name, t_end)
    os.makedirs(args.out, exist_ok=True)
    stem = os.path.join(args.out, preset.name)
    run_up = bool(params.get("nu_dot", 0) or params.get("n_dot", 0))
    speed = _speed_at(scene, result.ts) if run_up else None
    plot_simulation(result, stem + ".png", title=f"{preset.name}: {preset.source}", speed=speed,
                    x_label=("speed" if run_up else "time") + f" (time unit {preset.time_unit})")
    np.savez(stem + ".npz", ts=np.asarray(result.ts), ys=np.asarray(result.ys),
             **{k: np.asarray(v) for k, v in result.outputs.items()})
    summary["files"] = {"plot": stem + ".png", "data": stem + ".npz", "summary": stem + ".json"}
    with open(stem + ".json", "w") as f:
        json.dump(summary, f, indent=2)
    if args.json:
        print(json.dumps(summary, indent=2))
    else:
        print(f"{preset.name}: {summary['message']} ({summary['solver']}, "
              f"{summary['stats']['num_steps']} steps)")
        if summary["last_valid_time"] is None:
            print("  no valid saved state")
            return 3
        print(f"  final whirl amplitude {summary['final_whirl_amplitude']:.6g}, max over last "
              f"{summary['revolutions_in_window']} revolutions "
              f"{summary['max_whirl_amplitude_last_revolutions']:.6g}")
        if "weight_angles_final" in summary:
            print("  weight angles rel. rotor (rad): "
                  + ", ".join(f"{a:.4f}" for a in summary["weight_angles_final"]))
        print(f"  wrote {stem}.png, .npz, .json")
    return 0 if summary["success"] else 3


def _regime_dict(r, scene):
    return {
        "whirl_amplitude": float(r.whirl_amplitude),
        "weight_angles": [float(a) for a in np.asarray(r.weight_angles)],
        "max_eigenvalue_real_part": float(r.margin),
        "verdict": r.verdict,
        "kind": r.kind,
        "residual": float(r.residual),
        "state_rotating_frame": [float(v) for v in np.asarray(r.z)],
    }


def cmd_steady(args) -> int:
    from rotorjax import presets
    from rotorjax.analysis import steady_states

    preset = presets.get(args.preset)
    overrides = _parse_sets(args.set)
    overrides[preset.speed_key] = args.speed
    if preset.kind == "modal":
        return _modal_steady(preset, preset.params(overrides), args)
    _planar(preset, "steady")
    params = preset.params(overrides)
    if preset.speed_key == "n":
        params["n_dot"] = 0.0
    else:
        params["nu_dot"] = 0.0
    scene, _, _ = preset.build(params)
    regimes = steady_states(scene, n_angles=args.n_angles)
    out = {"preset": preset.name, "speed": args.speed, "params": params,
           "n_regimes": len(regimes), "regimes": [_regime_dict(r, scene) for r in regimes]}
    if args.json:
        print(json.dumps(out, indent=2))
    else:
        print(f"{preset.name} at {preset.speed_key} = {args.speed}: {len(regimes)} stationary regimes")
        for r in out["regimes"]:
            print(f"  amplitude {r['whirl_amplitude']:.6f}  weights at "
                  + ", ".join(f"{a:+.4f}" for a in r["weight_angles"])
                  + f" rad  max Re(lambda) {r['max_eigenvalue_real_part']:+.3e}  {r['verdict']}"
                  f"  ({r['kind']})")
    return 0


def _modal_steady(preset, params, args) -> int:
    from rotorjax.flexible import balanced_regime, unbalanced_regimes
    from rotorjax.presets import flexible_abb

    if params["n_balls"] < 1:
        raise UsageError("flexible-abb regimes need balls: --set n_balls=2")
    rotor = flexible_abb.build_balancer_rotor(params)
    regimes = []
    try:
        regimes.append(balanced_regime(rotor))
    except ValueError as e:
        print(f"  (no balanced regime: {e})", file=sys.stderr)
    regimes += unbalanced_regimes(rotor)
    rows = [{"kind": r.kind, "sigma": None if r.kind == "C" else r.sigma,
             "disk_amplitude": float(r.disk_amplitude), "max_eigenvalue_real_part": float(r.margin),
             "verdict": "stable" if float(r.margin) < -1e-9 else "unstable",
             "residual": float(r.residual)} for r in regimes]
    out = {"preset": preset.name, "speed": args.speed, "params": params, "regimes": rows}
    if args.json:
        print(json.dumps(out, indent=2))
    else:
        print(f"{preset.name} at omega = {args.speed}: {len(rows)} stationary regimes")
        for r in rows:
            print(f"  {r['kind']:4s} disk amplitude {r['disk_amplitude']:.6f}  max Re(lambda) "
                  f"{r['max_eigenvalue_real_part']:+.3e}  {r['verdict']}")
    return 0


def cmd_critical_speeds(args) -> int:
    from rotorjax import presets
    from rotorjax.analysis import critical_speeds

    preset = presets.get(args.preset)
    params = preset.params(_parse_sets(args.set))
    lo, hi = args.range
    if preset.kind == "flexible":
        return _flexible_critical_speeds(preset, params, lo, hi, args)
    if preset.kind == "modal":
        return _modal_critical_speeds(preset, params, lo, hi, args)
    key = preset.speed_key
    preset.margin(dict(params, **{key: 0.5 * (lo + hi)}))  # validates the parameters
    found = critical_speeds(lambda v: preset.margin(dict(params, **{key: v})), lo, hi,
                            n_scan=args.n_scan)
    out = {"preset": preset.name, "regime": preset.regime, "range": [lo, hi], "params": params,
           "critical_speeds": [c.as_dict() for c in found]}
    if preset.name == "anisotropic-abb":
        from rotorjax.presets import anisotropic_abb

        out["criterion_roots"] = anisotropic_abb.criterion_roots(params["n_eta"], params["mu_xi"],
                                                 params["mu_eta"], lo, hi)
    if args.json:
        print(json.dumps(out, indent=2))
    else:
        print(f"{preset.name}: critical speeds of {preset.regime} in [{lo}, {hi}]:")
        if not found:
            print("  none (the margin keeps its sign over the range)")
        for c in found:
            print(f"  {key} = {c.speed:.6f}   stable {c.stable_side}")
        if "criterion_roots" in out:
            print("  empirical criterion p(n) = 0 (paper eq. 18): "
                  + ", ".join(f"{r:.4f}" for r in out["criterion_roots"]))
    return 0


def cmd_stability_map(args) -> int:
    from rotorjax import presets
    from rotorjax.plot import plot_stability_map
    from rotorjax.sweep import sweep

    preset = presets.get(args.preset)
    if preset.margin is None:
        raise UsageError(f"{preset.name!r} has no reference regime to map")
    params = preset.params(_parse_sets(args.set))
    (xk, xlo, xhi, nx), (yk, ylo, yhi, ny) = args.x, args.y
    for k in (xk, yk):
        if k not in params:
            raise UsageError(f"unknown parameter {k!r} for preset {preset.name!r}")
        if k in preset.topology_keys:
            raise UsageError(f"{k!r} changes the scene's structure and cannot be mapped")
    nx, ny = int(nx), int(ny)
    if nx < 2 or ny < 2:
        raise UsageError("NX and NY must be >= 2")
    grid = {xk: np.linspace(float(xlo), float(xhi), nx), yk: np.linspace(float(ylo), float(yhi), ny)}
    preset.margin(dict(params, **{xk: grid[xk][0], yk: grid[yk][0]}))  # validates
    res = sweep(lambda pt: preset.margin(dict(params, **pt)), grid, chunk_size=args.chunk,
                progress=not args.json)
    margin = np.asarray(res.values)
    os.makedirs(args.out, exist_ok=True)
    stem = os.path.join(args.out, f"stability_map_{preset.name}")
    plot_stability_map(grid[xk], grid[yk], margin, stem + ".png", xk, yk,
                       title=f"{preset.name}: stability of {preset.regime}")
    np.savez(stem + ".npz", **{xk: grid[xk], yk: grid[yk]}, margin=margin)
    out = {"preset": preset.name, "regime": preset.regime, "x": xk, "y": yk,
           "shape": [nx, ny], "stable_fraction": float(np.mean(margin < 0)),
           "failed_points": int(np.sum(~np.isfinite(margin))),
           "files": {"plot": stem + ".png", "data": stem + ".npz"}}
    if args.json:
        print(json.dumps(out, indent=2))
    else:
        print(f"stable at {100 * out['stable_fraction']:.1f}% of {nx}x{ny} points; wrote {stem}.png")
    return 0


def _flexible_critical_speeds(preset, params, lo, hi, args) -> int:
    from rotorjax.flexible import critical_speeds_1x

    rotor, _, _ = preset.build(params)
    n_modes = args.modes or 8
    found = critical_speeds_1x(rotor, lo, hi, n_scan=args.n_scan, n_modes=n_modes)
    fwd = _forward_flags(rotor, found, n_modes)
    out = {"preset": preset.name, "range": [lo, hi], "params": params, "unit": "rad/s",
           "critical_speeds": [{"speed": s, "mode": k, "whirl": "forward" if f else "backward"}
                               for (s, k), f in zip(found, fwd)]}
    M, C, _, K = (np.asarray(a) for a in rotor.reduced_matrices())
    if not np.any(C) and np.allclose(K, K.T, rtol=1e-12, atol=1e-12 * np.abs(K).max()):
        from rotorjax.flexible import synchronous_critical_speeds

        roots = np.asarray(synchronous_critical_speeds(rotor))
        out["synchronous_determinant_roots"] = [float(r) for r in roots if lo <= r <= hi]
    if args.json:
        print(json.dumps(out, indent=2))
    else:
        print(f"{preset.name}: critical speeds (1x crossings) in [{lo}, {hi}] rad/s:")
        for c in out["critical_speeds"]:
            print(f"  {c['speed']:.4f} rad/s  ({c['speed'] * 30 / np.pi:.1f} rpm)  mode {c['mode']}, "
                  f"{c['whirl']} whirl")
        if "synchronous_determinant_roots" in out:
            print("  roots of the synchronous determinant (undamped): "
                  + ", ".join(f"{r:.4f}" for r in out["synchronous_determinant_roots"]))
    return 0


def _modal_critical_speeds(preset, params, lo, hi, args) -> int:
    from rotorjax.flexible import exact_critical_speeds

    if args.modes is not None:
        params["modes"] = preset.params({"modes": args.modes})["modes"]
    shaft = preset.build(params)[0]
    if args.exact:
        speeds = exact_critical_speeds(float(shaft.m), float(shaft.z0), float(shaft.J), lo, hi)
        method = "closed form, eq. (17)"
    else:
        f, excited = (np.asarray(v) for v in shaft.natural_frequencies())
        speeds = [float(v) for v, e in zip(f, excited) if e and lo <= v <= hi]
        method = f"modal model, {shaft.n_modes} modes"
    out = {"preset": preset.name, "range": [lo, hi], "params": params, "method": method,
           "unit": "omega_1 (first pinned-pinned frequency of the bare shaft)",
           "critical_speeds": speeds}
    if args.json:
        print(json.dumps(out, indent=2))
    else:
        print(f"{preset.name}: critical speeds ({method}) in units of omega_1: "
              + ", ".join(f"{v:.6f}" for v in speeds))
    return 0


def _forward_flags(rotor, found, n_modes):
    from rotorjax.flexible import modes

    return [bool(modes(rotor, s, n_modes).forward[k]) for s, k in found]


def _maybe_reduced(rotor, n_modes):
    return rotor if n_modes is None else rotor.reduce(n_modes)


def cmd_campbell(args) -> int:
    from rotorjax.flexible import campbell, critical_speeds_1x
    from rotorjax.plot import plot_campbell

    preset, params = _preset_and_params(args, "campbell", "flexible")
    rotor = _maybe_reduced(preset.build(params)[0], args.reduce)
    lo, hi = args.range
    if not (0 <= lo < hi):
        raise UsageError(f"--range must satisfy 0 <= LO < HI, got {lo} {hi}")
    speeds = np.linspace(lo, hi, args.n_speeds)
    camp = campbell(rotor, speeds, args.modes)
    crit = critical_speeds_1x(rotor, max(lo, 1e-6), hi, n_modes=args.modes)
    os.makedirs(args.out, exist_ok=True)
    stem = os.path.join(args.out, f"campbell_{preset.name}")
    plot_campbell(speeds, np.asarray(camp.frequencies), np.asarray(camp.forward), stem + ".png",
                  critical=[s for s, _ in crit], title=f"{preset.name}: Campbell diagram")
    out = {"preset": preset.name, "unit": "rad/s", "speeds": speeds.tolist(),
           "frequencies": np.asarray(camp.frequencies).tolist(),
           "forward": np.asarray(camp.forward).tolist(),
           "log_dec": np.asarray(camp.log_dec).tolist(),
           "critical_speeds": [s for s, _ in crit], "files": {"plot": stem + ".png"}}
    with open(stem + ".json", "w") as f:
        json.dump(out, f)
    if args.json:
        print(json.dumps(out))
    else:
        print(f"wrote {stem}.png and .json; critical speeds (rad/s): "
              + ", ".join(f"{s:.3f}" for s, _ in crit))
    return 0


def cmd_response(args) -> int:
    from rotorjax.flexible import unbalance_response
    from rotorjax.plot import plot_response

    preset, params = _preset_and_params(args, "response", "flexible")
    rotor = _maybe_reduced(preset.build(params)[0], args.reduce)
    lo, hi = args.range
    if not (0 < lo < hi):
        raise UsageError(f"--range must satisfy 0 < LO < HI, got {lo} {hi}")
    for name, node in (("--node", args.node), ("--probe", args.probe)):
        if not 0 <= node < rotor.n_nodes:
            raise UsageError(f"{name} {node}: the rotor has nodes 0..{rotor.n_nodes - 1}")
    speeds = np.linspace(lo, hi, args.n)
    X, Y = unbalance_response(rotor, args.node, args.unbalance, args.phase, speeds,
                              probe_nodes=[args.probe])
    X, Y = np.asarray(X[:, 0]), np.asarray(Y[:, 0])
    amp = np.sqrt(np.abs(X) ** 2 + np.abs(Y) ** 2)
    peaks = [float(speeds[i]) for i in range(1, len(amp) - 1) if amp[i] > amp[i - 1] and amp[i] > amp[i + 1]]
    os.makedirs(args.out, exist_ok=True)
    stem = os.path.join(args.out, f"response_{preset.name}")
    plot_response(speeds, X, Y, stem + ".png", title=f"{preset.name}: unbalance response at node {args.probe}")
    out = {"preset": preset.name, "node": args.node, "probe": args.probe, "unbalance": args.unbalance,
           "unit": "rad/s, m", "peaks": peaks, "max_amplitude": float(amp.max()),
           "speed_at_max": float(speeds[np.argmax(amp)]), "files": {"plot": stem + ".png"}}
    if args.json:
        print(json.dumps(out, indent=2))
    else:
        print("peaks at " + ", ".join(f"{p:.2f}" for p in peaks) + f" rad/s; wrote {stem}.png")
    return 0


def cmd_presets(args) -> int:
    from rotorjax import presets

    for p in presets.PRESETS.values():
        print(f"{p.name}: {p.source}")
        for k, v in p.defaults.items():
            print(f"  {k} = {v}    {p.describe_params.get(k, '')}")
    return 0


def cmd_demo(args) -> int:
    from rotorjax.demo import run_demo

    run_demo(args.out)
    return 0


def _command(sub, name, help, fn, flags=()):
    """A subcommand on a preset, with the shared `--set`, `--json` and `--out`."""
    p = sub.add_parser(name, help=help)
    p.add_argument("preset")
    p.add_argument("--set", action="append", metavar="KEY=VALUE",
                   help="override a preset parameter (repeatable)")
    p.add_argument("--json", action="store_true", help="print a JSON summary to stdout")
    p.add_argument("--out", default="rotorjax-out")
    for args, kwargs in flags:
        p.add_argument(*args, **kwargs)
    p.set_defaults(fn=fn)
    return p


def _range(required=True):
    return (("--range",), dict(type=float, nargs=2, metavar=("LO", "HI"), required=required))


def _reduce():
    return (("--reduce",), dict(type=int, default=None, metavar="N",
                                help="reduce to the N lowest undamped modes first (ReducedRotor)"))


def build_parser():
    parser = argparse.ArgumentParser(prog="rotorjax", description=__doc__)
    sub = parser.add_subparsers(dest="command", required=True)
    _command(sub, "simulate", "simulate a preset scene", cmd_simulate, [
        (("--t-end",), dict(type=float, default=None)),
        (("--solver",), dict(default="auto")),
        (("--rtol",), dict(type=float, default=1e-8)),
        (("--atol",), dict(type=float, default=1e-10)),
        (("--max-steps",), dict(type=int, default=500_000)),
        (("--n-save",), dict(type=int, default=None,
                             help="saved states (default 4000; cantilever-limiters: 40 per revolution)")),
    ])
    _command(sub, "steady", "all stationary regimes at a speed (rotating frame)", cmd_steady, [
        (("--speed",), dict(type=float, required=True)),
        (("--n-angles",), dict(type=int, default=16, help="starts per weight angle")),
    ])
    _command(sub, "critical-speeds", "speeds where stability changes (planar) or 1x crossings "
             "(flexible)", cmd_critical_speeds, [
        _range(),
        (("--n-scan",), dict(type=int, default=200)),
        (("--modes",), dict(type=int, default=None,
                            help="modes tracked (ross-compare) or shaft modes (flexible-abb)")),
        (("--exact",), dict(action="store_true", help="flexible-abb: the closed-form equation (17)")),
    ])
    _command(sub, "stability-map", "stability margin over a 2-D parameter grid", cmd_stability_map, [
        (("--x",), dict(nargs=4, metavar=("KEY", "LO", "HI", "NX"), required=True)),
        (("--y",), dict(nargs=4, metavar=("KEY", "LO", "HI", "NY"), required=True)),
        (("--chunk",), dict(type=int, default=32)),
    ])
    _command(sub, "campbell", "Campbell diagram of a flexible rotor", cmd_campbell, [
        _range(),
        (("--n-speeds",), dict(type=int, default=100)),
        (("--modes",), dict(type=int, default=8)),
        _reduce(),
    ])
    _command(sub, "response", "unbalance response of a flexible rotor", cmd_response, [
        _range(),
        (("--n",), dict(type=int, default=2000, help="number of speeds")),
        (("--node",), dict(type=int, default=2, help="node of the unbalance")),
        (("--probe",), dict(type=int, default=2, help="node where the response is read")),
        (("--unbalance",), dict(type=float, default=1e-3, help="kg m")),
        (("--phase",), dict(type=float, default=0.0, help="rad")),
        _reduce(),
    ])
    _command(sub, "hopf", "Hopf point of straight-line rotation (internal friction)", cmd_hopf, [
        _range(required=False),
        (("--n-scan",), dict(type=int, default=80)),
    ])
    _command(sub, "bifurcation", "extrema diagram over a swept parameter (vmapped)", cmd_bifurcation, [
        (("--param",), dict(nargs=4, metavar=("KEY", "LO", "HI", "NP"), required=True)),
        (("--solver",), dict(default="auto")),
        (("--rtol",), dict(type=float, default=1e-8)),
        (("--atol",), dict(type=float, default=1e-10)),
        (("--max-steps",), dict(type=int, default=1_000_000)),
        (("--chunk",), dict(type=int, default=16)),
    ])
    _command(sub, "continue", "continuation: a branch in one parameter, or a stability boundary in two",
             cmd_continue, [
                 (("--param",), dict(required=True)),
                 (("--param2",), dict(default=None)),
                 (("--from",), dict(dest="start", type=float, nargs="+", default=None,
                                    help="starting value(s) (default: the preset's)")),
                 (("--to",), dict(type=float, nargs=2, default=None, metavar=("LO", "HI"),
                                  help="range of --param (one-parameter continuation)")),
                 (("--box",), dict(type=float, nargs=4, default=None, metavar=("LO1", "HI1", "LO2", "HI2"),
                                   help="parameter box for a boundary")),
                 (("--ds",), dict(type=float, default=0.02)),
                 (("--ds-max",), dict(type=float, default=0.2)),
                 (("--max-points",), dict(type=int, default=200)),
                 (("--direction",), dict(type=float, default=1.0)),
                 (("--gradient",), dict(default="auto", choices=("auto", "autodiff", "fd"))),
             ])
    bal = sub.add_parser("balance", help="correction weights from runs with trial weights")
    bal.add_argument("--runs", default=None, help="CSV/.npz of runs (default: the shipped dataset)")
    bal.add_argument("--planes", default=None, help="comma-separated plane numbers (default: all trial planes)")
    bal.add_argument("--radius", type=float, default=0.01, help="correction radius, m")
    bal.add_argument("--holes", type=int, default=0, help="split onto N equally spaced holes")
    bal.add_argument("--rotor-mass", type=float, default=10.0, help="kg, for the ISO grade")
    bal.add_argument("--json", action="store_true")
    bal.set_defaults(fn=cmd_balance)
    _command(sub, "identify", "identify support stiffness/damping from measured vibration", cmd_identify, [
        (("--data",), dict(default=None, help="run-up CSV/.npz (default: the shipped dataset)")),
        (("--fit",), dict(default="k1,k2,c1,c2")),
        (("--fit-unbalance",), dict(action="store_true", help="also fit the unbalances")),
        (("--block",), dict(type=int, default=1, help="revolutions per 1x estimate")),
        (("--min-speed",), dict(type=float, default=0.0, help="rad/s")),
    ])
    demo = sub.add_parser("demo", help="a short representative study with plots")
    demo.add_argument("--out", default="rotorjax-out")
    demo.set_defaults(fn=cmd_demo)
    pre = sub.add_parser("presets", help="list presets and their parameters")
    pre.set_defaults(fn=cmd_presets)
    return parser


def main(argv=None) -> int:
    parser = build_parser()
    args = parser.parse_args(argv)
    try:
        return args.fn(args)
    except (ValueError, UsageError) as e:
        print(f"rotorjax: error: {e}", file=sys.stderr)
        return 2


if __name__ == "__main__":
    sys.exit(main())
