"""`steady`, `critical-speeds`, `stability-map`, `hopf`: stationary regimes and
where their stability changes."""

import json
import os

import numpy as np

from ._common import (InputError, NumericalError, Stages, build, check_range, get_preset, grid_spec, preset_and_params, preset_params,
                      prepare_out, wrong_kind, write_json)


def _regime_dict(r):
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
    from rotorjax.analysis import steady_states
    from rotorjax.plot import plot_steady_regimes

    preset = get_preset(args.preset)
    if preset.kind not in ("planar", "modal"):
        raise wrong_kind(preset, "steady")
    params = preset_params(preset, args.set, {preset.speed_key: ("--speed", args.speed)})
    prepare_out(args.out)
    if preset.kind == "modal":
        return _modal_steady(preset, params, args)
    params["n_dot" if preset.speed_key == "n" else "nu_dot"] = 0.0
    stages = Stages("steady", 3, enabled=not args.json)
    stages("building the scene")
    scene, _, _ = build(preset, params)
    stages(f"Newton from {args.n_angles} starts per weight angle, stability by autodiff (one compiled call)")
    regimes = steady_states(scene, n_angles=args.n_angles)
    rows = [_regime_dict(r) for r in regimes]
    stem = os.path.join(args.out, f"steady_{preset.name}")
    stages("plot")
    stages.close()
    plot_steady_regimes(stem + ".png", rows, title=f"{preset.name}: stationary regimes at "
                        f"{preset.speed_key} = {params[preset.speed_key]:g}")
    out = {"preset": preset.name, "speed": params[preset.speed_key], "params": params,
           "n_regimes": len(rows), "regimes": rows, "files": {"plot": stem + ".png"}}
    if args.json:
        print(json.dumps(out, indent=2))
        return 0
    print(f"{preset.name} at {preset.speed_key} = {params[preset.speed_key]:g}: {len(rows)} stationary regimes")
    for r in rows:
        print(f"  amplitude {r['whirl_amplitude']:.6f}  weights at "
              + ", ".join(f"{a:+.4f}" for a in r["weight_angles"])
              + f" rad  max Re(lambda) {r['max_eigenvalue_real_part']:+.3e}  {r['verdict']}  ({r['kind']})")
    print(f"  wrote {stem}.png")
    return 0


def _modal_steady(preset, params, args) -> int:
    import sys

    from rotorjax.flexible import balanced_regime, unbalanced_regimes
    from rotorjax.plot import plot_regime_amplitudes
    from rotorjax.presets import flexible_abb

    if params["n_balls"] < 1:
        raise InputError("--set n_balls=0: flexible-abb regimes need balls, e.g. --set n_balls=2")
    stages = Stages("steady", 3, enabled=not args.json)
    stages("building the rotor")
    rotor = flexible_abb.build_balancer_rotor(params)
    stages("balanced and unbalanced regimes")
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
    stages("plot")
    stages.close()
    stem = os.path.join(args.out, f"steady_{preset.name}")
    plot_regime_amplitudes(stem + ".png", rows, title=f"{preset.name}: stationary regimes at omega = "
                           f"{params['omega']:g}, {params['n_balls']} balls")
    out = {"preset": preset.name, "speed": params["omega"], "params": params, "regimes": rows,
           "files": {"plot": stem + ".png"}}
    if args.json:
        print(json.dumps(out, indent=2))
        return 0
    print(f"{preset.name} at omega = {params['omega']:g}: {len(rows)} stationary regimes")
    for r in rows:
        print(f"  {r['kind']:4s} disk amplitude {r['disk_amplitude']:.6f}  max Re(lambda) "
              f"{r['max_eigenvalue_real_part']:+.3e}  {r['verdict']}")
    print(f"  wrote {stem}.png")
    return 0


def cmd_critical_speeds(args) -> int:
    from rotorjax.analysis import critical_speeds
    from rotorjax.plot import plot_margin

    preset, params = preset_and_params(args, "critical-speeds", ("planar", "modal", "flexible", "contact"))
    if args.exact and preset.kind != "modal":
        raise InputError(f"--exact: the closed form (17) is model 003's (flexible-abb), not {preset.name}'s")
    lo, hi = check_range("--range", *args.range, positive_lo=preset.kind in ("planar", "contact"))
    prepare_out(args.out)
    if preset.kind == "flexible":
        return _flexible_critical_speeds(preset, params, lo, hi, args)
    if preset.kind == "modal":
        return _modal_critical_speeds(preset, params, lo, hi, args)
    key = preset.speed_key
    preset.margin(dict(params, **{key: 0.5 * (lo + hi)}))  # validates the parameters
    found, (scan_x, scan_m) = critical_speeds(lambda v: preset.margin(dict(params, **{key: v})), lo, hi,
                                              n_scan=args.n_scan, return_scan=True, progress=not args.json)
    out = {"preset": preset.name, "regime": preset.regime, "range": [lo, hi], "params": params,
           "critical_speeds": [c.as_dict() for c in found]}
    extra = None
    if preset.name == "anisotropic-abb":
        from rotorjax.presets import anisotropic_abb

        out["criterion_roots"] = anisotropic_abb.criterion_roots(params["n_eta"], params["mu_xi"],
                                                                 params["mu_eta"], lo, hi)
        extra = out["criterion_roots"]
    stem = os.path.join(args.out, f"critical_speeds_{preset.name}")
    plot_margin(stem + ".png", scan_x, scan_m, [c.speed for c in found],
                title=f"{preset.name}: stability of {preset.regime}", speed_label=f"{key} (dimensionless)",
                margin_label="margin: largest Re(lambda) or Floquet exponent (dimensionless)",
                extra_roots=extra, extra_label="paper's criterion p(n) = 0 (eq. 18)")
    out["files"] = {"plot": stem + ".png"}
    if not np.any(np.isfinite(scan_m)):
        raise NumericalError(f"critical-speeds: the margin could not be computed at any of the {args.n_scan} scan "
                             f"points in [{lo:g}, {hi:g}]")
    if not np.all(np.isfinite(scan_m)):
        out["failed_scan_points"] = int(np.sum(~np.isfinite(scan_m)))
    if args.json:
        print(json.dumps(out, indent=2))
        return 0
    print(f"{preset.name}: critical speeds of {preset.regime} in [{lo:g}, {hi:g}]:")
    if not found:
        print("  none (the margin keeps its sign over the range)")
    for c in found:
        print(f"  {key} = {c.speed:.6f}   stable {c.stable_side}")
    if "criterion_roots" in out:
        print("  empirical criterion p(n) = 0 (paper eq. 18): "
              + (", ".join(f"{r:.4f}" for r in out["criterion_roots"]) or "none in the range"))
    if "failed_scan_points" in out:
        print(f"  warning: the margin could not be computed at {out['failed_scan_points']} of {args.n_scan} "
              "scan points (brackets there were skipped)")
    print(f"  wrote {stem}.png")
    return 0


def _n_dofs(rotor):
    return int(np.asarray(rotor.reduced_matrices()[0]).shape[0])


def _flexible_critical_speeds(preset, params, lo, hi, args) -> int:
    from rotorjax.flexible import campbell, critical_speeds_1x, modes
    from rotorjax.plot import plot_campbell

    rotor, _, _ = build(preset, params)
    n_modes = args.modes or 8
    if n_modes > 2 * _n_dofs(rotor):
        raise InputError(f"--modes {n_modes}: the rotor has {2 * _n_dofs(rotor)} modes")
    found = critical_speeds_1x(rotor, lo, hi, n_scan=args.n_scan, n_modes=n_modes)
    fwd = [bool(modes(rotor, s, n_modes).forward[k]) for s, k in found]
    out = {"preset": preset.name, "range": [lo, hi], "params": params, "unit": "rad/s",
           "critical_speeds": [{"speed": s, "mode": k, "whirl": "forward" if f else "backward"}
                               for (s, k), f in zip(found, fwd)]}
    M, C, _, K = (np.asarray(a) for a in rotor.reduced_matrices())
    if not np.any(C) and np.allclose(K, K.T, rtol=1e-12, atol=1e-12 * np.abs(K).max()):
        from rotorjax.flexible import synchronous_critical_speeds

        roots = np.asarray(synchronous_critical_speeds(rotor))
        out["synchronous_determinant_roots"] = [float(r) for r in roots if lo <= r <= hi]
    speeds = np.linspace(lo, hi, 100)
    camp = campbell(rotor, speeds, n_modes)
    stem = os.path.join(args.out, f"critical_speeds_{preset.name}")
    plot_campbell(speeds, np.asarray(camp.frequencies), np.asarray(camp.forward), stem + ".png",
                  critical=[s for s, _ in found], title=f"{preset.name}: critical speeds (1x crossings)")
    out["files"] = {"plot": stem + ".png"}
    if args.json:
        print(json.dumps(out, indent=2))
        return 0
    print(f"{preset.name}: critical speeds (1x crossings) in [{lo:g}, {hi:g}] rad/s:")
    if not found:
        print("  none in the range")
    for c in out["critical_speeds"]:
        print(f"  {c['speed']:.4f} rad/s  ({c['speed'] * 30 / np.pi:.1f} rpm)  mode {c['mode']}, {c['whirl']} whirl")
    if out.get("synchronous_determinant_roots"):
        print("  roots of the synchronous determinant (undamped): "
              + ", ".join(f"{r:.4f}" for r in out["synchronous_determinant_roots"]))
    print(f"  wrote {stem}.png")
    return 0


def _modal_critical_speeds(preset, params, lo, hi, args) -> int:
    from rotorjax.flexible import exact_critical_speeds
    from rotorjax.plot import plot_campbell

    if args.modes is not None:
        params["modes"] = preset_params(preset, [f"modes={args.modes}"])["modes"]
    shaft = build(preset, params)[0]
    f, excited = (np.asarray(v) for v in shaft.natural_frequencies())
    if args.exact:
        speeds = exact_critical_speeds(float(shaft.m), float(shaft.z0), float(shaft.J), lo, hi)
        method = "closed form, eq. (17)"
    else:
        speeds = [float(v) for v, e in zip(f, excited) if e and lo <= v <= hi]
        method = f"modal model, {shaft.n_modes} modes"
    grid = np.linspace(lo, hi, 2)
    excited_f = f[excited.astype(bool)]
    shown = excited_f[excited_f <= 1.2 * hi] if np.any(excited_f <= 1.2 * hi) else excited_f[:1]
    stem = os.path.join(args.out, f"critical_speeds_{preset.name}")
    plot_campbell(grid, np.tile(shown, (2, 1)), np.ones((2, shown.size), bool), stem + ".png",
                  critical=list(speeds), title=f"{preset.name}: natural frequencies excited by the disk's unbalance, critical speeds ({method})",
                  unit="omega_1 (dimensionless)")
    out = {"preset": preset.name, "range": [lo, hi], "params": params, "method": method,
           "unit": "omega_1 (first pinned-pinned frequency of the bare shaft)",
           "critical_speeds": speeds, "files": {"plot": stem + ".png"}}
    if args.json:
        print(json.dumps(out, indent=2))
        return 0
    print(f"{preset.name}: critical speeds ({method}) in units of omega_1: "
          + (", ".join(f"{v:.6f}" for v in speeds) or "none in the range"))
    print(f"  wrote {stem}.png")
    return 0


def cmd_stability_map(args) -> int:
    from rotorjax.plot import plot_stability_map
    from rotorjax.sweep import sweep

    preset, params = preset_and_params(args, "stability-map", ("planar", "modal", "contact"))
    if preset.margin is None:
        raise InputError(f"{preset.name!r} has no reference regime to map")
    xk, xlo, xhi, nx = grid_spec("--x", args.x, preset, params)
    yk, ylo, yhi, ny = grid_spec("--y", args.y, preset, params)
    if xk == yk:
        raise InputError(f"--x {xk} and --y {yk}: the two axes need different parameters")
    prepare_out(args.out)
    grid = {xk: np.linspace(xlo, xhi, nx), yk: np.linspace(ylo, yhi, ny)}
    preset.margin(dict(params, **{xk: grid[xk][0], yk: grid[yk][0]}))  # validates
    res = sweep(lambda pt: preset.margin(dict(params, **pt)), grid, chunk_size=args.chunk,
                progress=not args.json)
    margin = np.asarray(res.values)
    ok = np.isfinite(margin)
    if not ok.any():
        raise NumericalError(f"stability-map: the margin could not be computed at any of the {nx}x{ny} points")
    stem = os.path.join(args.out, f"stability_map_{preset.name}")
    plot_stability_map(grid[xk], grid[yk], margin, stem + ".png", xk, yk,
                       title=f"{preset.name}: stability of {preset.regime}")
    np.savez(stem + ".npz", **{xk: grid[xk], yk: grid[yk]}, margin=margin)
    out = {"preset": preset.name, "regime": preset.regime, "x": xk, "y": yk,
           "shape": [nx, ny], "stable_fraction": float(np.mean(margin[ok] < 0)),
           "failed_points": int(np.sum(~np.isfinite(margin))),
           "files": {"plot": stem + ".png", "data": stem + ".npz"}}
    if args.json:
        print(json.dumps(out, indent=2))
    else:
        print(f"stable at {100 * out['stable_fraction']:.1f}% of the {int(ok.sum())} computed points of the "
              f"{nx}x{ny} grid; wrote {stem}.png")
        if out["failed_points"]:
            print(f"  warning: the margin could not be computed at {out['failed_points']} points (blank on the map)")
    return 0


#: `hopf`'s speed range when `--range` is not given (units 1/T*).
HOPF_RANGE = (1.0, 40.0)


def cmd_hopf(args) -> int:
    from rotorjax.analysis import hopf_points, hopf_speed_gradient
    from rotorjax.plot import plot_margin
    from rotorjax.presets import cantilever_limiters as cl

    preset, params = preset_and_params(args, "hopf", "contact")
    lo, hi = check_range("--range", *(args.range or HOPF_RANGE), positive_lo=True)
    prepare_out(args.out)
    rotor = cl.build_rotor(params)
    points, (scan_x, scan_m) = hopf_points(rotor.state_matrix, lo, hi, n_scan=args.n_scan, return_scan=True,
                                             progress=not args.json)
    out = {"preset": preset.name, "params": params, "range": [lo, hi],
           "range_source": "--range" if args.range else "default",
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
    stem = os.path.join(args.out, f"hopf_{preset.name}")
    plot_margin(stem + ".png", scan_x, scan_m, [h.speed for h in points],
                title=f"{preset.name}: straight-line rotation, eta_i = {params['eta_i']:g}, "
                      f"eta_e = {params['eta_e']:g}",
                speed_label="spin speed N (units 1/T*)", margin_label="largest Re(lambda) (units 1/T*)",
                root_label="Hopf point",
                extra_roots=[out["paper_fit"]["N_crit"]] if "paper_fit" in out else None,
                extra_label="paper's fit 2.47 eta_e/eta_i + 1.64")
    out["files"] = {"plot": stem + ".png"}
    if args.json:
        print(json.dumps(out, indent=2))
        return 0
    src = "" if args.range else " (the default range; set it with --range LO HI)"
    if not points:
        print(f"{preset.name}: straight-line rotation keeps its stability over N in [{lo:g}, {hi:g}]{src}")
    else:
        print(f"{preset.name}: searched N in [{lo:g}, {hi:g}]{src}")
    for d in out["hopf_points"]:
        print(f"  Hopf point at N = {d['N_crit']:.6f} (whirl frequency {d['whirl_frequency']:.6f}, {d['whirl']} "
              f"whirl); dN/d eta_e = {d['dN_crit_d_eta_e']:.4f}")
    if "paper_fit" in out:
        print(f"  the paper's fit gives N_crit = {out['paper_fit']['N_crit']:.4f}")
    print(f"  wrote {stem}.png")
    return 0
