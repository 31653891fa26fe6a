"""`steady`, `critical-speeds`, `stability-map`, `hopf`: stationary regimes and
where their stability changes."""

import json
import sys

import numpy as np

from ._common import (InputError, NumericalError, Stages, check_range, grid_spec, out_stem, prepare_out,
                      preset_and_params, wrong_kind)


def cmd_steady(args) -> int:
    from rotorjax.plot import plot_regime_amplitudes, plot_steady_regimes

    preset, params = preset_and_params(args, "steady", ("planar", "modal"), speed_option=args.speed)
    if preset.regimes is None:
        raise wrong_kind(preset, "steady")
    prepare_out(args.out)
    stages = Stages("steady", 3, enabled=not args.json)
    rows, notes = preset.regimes(params, n_angles=args.n_angles, stage=stages)
    stages("plot")
    stages.close()
    for note in notes:
        print(f"  {note}", file=sys.stderr)
    key, speed = preset.speed_key, params[preset.speed_key]
    stem = out_stem(args.out, preset, "steady_")
    planar = all("weight_angles" in r for r in rows)
    if planar:
        plot_steady_regimes(stem + ".png", rows, title=f"{preset.name}: stationary regimes at {key} = {speed:g}")
        out = {"preset": preset.name, "speed": speed, "params": params, "n_regimes": len(rows), "regimes": rows}
    else:
        plot_regime_amplitudes(stem + ".png", rows, title=f"{preset.name}: stationary regimes at {key} = {speed:g}")
        out = {"preset": preset.name, "speed": speed, "params": params, "regimes": rows}
    out["files"] = {"plot": stem + ".png"}
    if args.json:
        print(json.dumps(out, indent=2))
        return 0
    print(f"{preset.name} at {key} = {speed:g}: {len(rows)} stationary regimes")
    for r in rows:
        if planar:
            print(f"  amplitude {r['whirl_amplitude']:.6f}  weights at "
                  + ", ".join(f"{a:+.4f}" for a in r["weight_angles"])
                  + f" rad  max Re(lambda) {r['max_eigenvalue_real_part']:+.3e}  {r['verdict']}  ({r['kind']})")
        else:
            print(f"  {r['kind']:4s} disk amplitude {r['disk_amplitude']:.6f}  max Re(lambda) "
                  f"{r['max_eigenvalue_real_part']:+.3e}  {r['verdict']}")
    print(f"  wrote {stem}.png")
    return 0


def cmd_critical_speeds(args) -> int:
    preset, params = preset_and_params(args, "critical-speeds", ("planar", "modal", "flexible", "contact", "rotor"))
    if args.exact and preset.kind != "modal":
        raise InputError(f"--exact: the closed form (17) is model 003's (flexible-abb), not {preset.name}'s")
    if preset.critical_speeds is None and preset.margin is None:
        raise wrong_kind(preset, "critical-speeds")
    lo, hi = check_range("--range", *args.range, positive_lo=preset.critical_speeds is None)
    prepare_out(args.out)
    if preset.critical_speeds is not None:
        return _crossings(preset, params, lo, hi, args)
    return _margin_roots(preset, params, lo, hi, args)


def _margin_roots(preset, params, lo, hi, args) -> int:
    """Critical speeds as the sign changes of the preset's stability margin."""
    from rotorjax.analysis import critical_speeds
    from rotorjax.plot import plot_margin

    key = preset.speed_key
    preset.margin(dict(params, **{key: 0.5 * (lo + hi)}))  # validates the parameters
    found, (scan_x, scan_m) = critical_speeds(lambda v: preset.margin(dict(params, **{key: v})), lo, hi,
                                              n_scan=args.n_scan, return_scan=True, progress=not args.json)
    out = {"preset": preset.name, "regime": preset.regime, "range": [lo, hi], "params": params,
           "critical_speeds": [c.as_dict() for c in found]}
    if preset.criterion_roots is not None:
        out["criterion_roots"] = preset.criterion_roots(params, lo, hi)
    stem = out_stem(args.out, preset, "critical_speeds_")
    plot_margin(stem + ".png", scan_x, scan_m, [c.speed for c in found],
                title=f"{preset.name}: stability of {preset.regime}", speed_label=f"{key} (dimensionless)",
                margin_label="margin: largest Re(lambda) or Floquet exponent (dimensionless)",
                extra_roots=out.get("criterion_roots"), extra_label=preset.criterion_label)
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
        print(f"  {preset.criterion_label}: "
              + (", ".join(f"{r:.4f}" for r in out["criterion_roots"]) or "none in the range"))
    if "failed_scan_points" in out:
        print(f"  warning: the margin could not be computed at {out['failed_scan_points']} of {args.n_scan} "
              "scan points (brackets there were skipped)")
    print(f"  wrote {stem}.png")
    return 0


def _crossings(preset, params, lo, hi, args) -> int:
    """Critical speeds the preset's model computes itself (1x crossings, natural frequencies)."""
    from rotorjax.plot import plot_campbell

    found = preset.critical_speeds(params, lo, hi, n_scan=args.n_scan, n_modes=args.modes, exact=args.exact,
                                   progress=not args.json)
    (speeds, freqs, forward), look = found.pop("campbell"), found.pop("present")
    out = {"preset": preset.name, "range": [lo, hi], "params": found.pop("params", params), **found}
    crit = [c["speed"] if isinstance(c, dict) else c for c in out["critical_speeds"]]
    stem = out_stem(args.out, preset, "critical_speeds_")
    what = out.get("method", "1x crossings")
    plot_campbell(speeds, freqs, forward, stem + ".png", critical=crit, unit=look["unit"],
                  title=f"{preset.name}: {look['title']}")
    out["files"] = {"plot": stem + ".png"}
    if args.json:
        print(json.dumps(out, indent=2))
        return 0
    print(f"{preset.name}: critical speeds ({what}) in [{lo:g}, {hi:g}] {out['unit']}:")
    if not crit:
        print("  none in the range")
    for c in out["critical_speeds"]:
        if isinstance(c, dict):
            print(f"  {c['speed']:.4f} rad/s  ({c['speed'] * 30 / np.pi:.1f} rpm)  mode {c['mode']}, "
                  f"{c['whirl']} whirl")
        else:
            print(f"  {c:.6f}")
    if out.get("synchronous_determinant_roots"):
        print("  roots of the synchronous determinant (undamped): "
              + ", ".join(f"{r:.4f}" for r in out["synchronous_determinant_roots"]))
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
    stem = out_stem(args.out, preset, "stability_map_")
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
    from rotorjax.plot import plot_margin

    preset, params = preset_and_params(args, "hopf", "contact")
    if preset.hopf is None:
        raise wrong_kind(preset, "hopf")
    lo, hi = check_range("--range", *(args.range or HOPF_RANGE), positive_lo=True)
    prepare_out(args.out)
    found = preset.hopf(params, lo, hi, n_scan=args.n_scan, progress=not args.json)
    (scan_x, scan_m), look = found.pop("scan"), found.pop("present")
    out = {"preset": preset.name, "params": params, "range": [lo, hi],
           "range_source": "--range" if args.range else "default", **found}
    stem = out_stem(args.out, preset, "hopf_")
    plot_margin(stem + ".png", scan_x, scan_m, [h["speed"] for h in out["hopf_points"]],
                title=f"{preset.name}: {look['title']}", speed_label=look["speed_label"],
                margin_label=look["margin_label"], root_label="Hopf point", extra_roots=look["extra_roots"],
                extra_label=look["extra_label"])
    out["files"] = {"plot": stem + ".png"}
    if args.json:
        print(json.dumps(out, indent=2))
        return 0
    key = preset.speed_key
    src = "" if args.range else " (the default range; set it with --range LO HI)"
    if not out["hopf_points"]:
        print(f"{preset.name}: {preset.regime} keeps its stability over {key} in [{lo:g}, {hi:g}]{src}")
    else:
        print(f"{preset.name}: searched {key} in [{lo:g}, {hi:g}]{src}")
    d_key, d_label = look["sensitivity"]
    for d in out["hopf_points"]:
        print(f"  Hopf point at {key} = {d['speed']:.6f} (whirl frequency {d['frequency']:.6f}, {d['whirl']} "
              f"whirl); {d_label} = {d[d_key]:.4f}")
    if "paper_fit" in out:
        fit = out["paper_fit"]
        print(f"  the paper's fit {fit['formula']} gives {fit[key + '_crit']:.4f}")
    print(f"  wrote {stem}.png")
    return 0
