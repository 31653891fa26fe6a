"""`steady`, `critical-speeds`, `stability-map`, `hopf`: stationary regimes and
where their stability changes."""

import json
import sys

import numpy as np

from ._output_units import Units, units_for
from ._common import (InputError, NumericalError, Stages, build, check_range, grid_spec, is_rotor_file, out_stem,
                      prepare_out, preset_and_params, stability_study, wrong_kind)


def cmd_steady(args) -> int:
    from rotorjax.plot import plot_regime_amplitudes, plot_steady_regimes
    from ._common import save_figure

    preset, params = preset_and_params(args, "steady", speed_option=args.speed)
    prepare_out(args.out)
    stages = Stages("steady", 3, enabled=not args.json)
    rows, notes = _regimes(preset, params, args.n_angles, stages)
    stages("plot")
    stages.close()
    for note in notes:
        print(f"  {note}", file=sys.stderr)
    key, speed = preset.speed_key, params[preset.speed_key]
    stem = out_stem(args.out, preset, "steady_")
    planar = all("weight_angles" in r for r in rows)
    if planar:
        save_figure(plot_steady_regimes(regimes=rows, title=f"{preset.name}: stationary regimes at {key} = {speed:g}"),
                    stem + ".png")
        out = {"preset": preset.name, "speed": speed, "params": params, "n_regimes": len(rows), "regimes": rows}
    else:
        save_figure(plot_regime_amplitudes(regimes=rows,
                                           title=f"{preset.name}: stationary regimes at {key} = {speed:g}"),
                    stem + ".png")
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


def _regimes(preset, params, n_angles, stage):
    """Every stationary regime of the preset's scene under its `steady_overrides` (e.g.
    a zero run-up rate), as JSON rows, and notes: model 003's closed forms for its
    modal balancer rotor, else `rotorjax.analysis.steady_states` (multi-started Newton)."""
    from rotorjax.analysis import balancer003_regimes, steady_states
    from rotorjax.models import ModalBalancerRotor, provides

    stage("building the scene")
    scene = build(preset, dict(params, **preset.steady_overrides)).scene
    if isinstance(scene, ModalBalancerRotor):
        stage("balanced and unbalanced regimes")
        found, notes = balancer003_regimes(scene)
        return [{"kind": r.kind, "sigma": None if r.kind == "C" else r.sigma,
                 "disk_amplitude": float(r.disk_amplitude), "max_eigenvalue_real_part": float(r.margin),
                 "verdict": "stable" if float(r.margin) < -1e-9 else "unstable",
                 "residual": float(r.residual)} for r in found], notes
    if not (provides(scene, "to_rotating") and len(scene.weight_coordinates()[0])):
        raise wrong_kind(preset, "steady")   # stationary regimes of balancing weights, multi-started
    stage(f"Newton from {n_angles} starts per weight angle, stability by autodiff (one compiled call)")
    return [r.as_dict() for r in steady_states(scene, n_angles=n_angles)], []


def cmd_critical_speeds(args) -> int:
    from rotorjax.models import ModalBalancerRotor, provides

    preset, params = preset_and_params(args, "critical-speeds")

    # model 003's modal shaft: its own closed forms; a scene with a reference motion: the speeds where its
    # stability changes; any other finite-element rotor: its Campbell diagram's 1x crossings
    setup = build(preset, params)
    modal = isinstance(setup.scene, ModalBalancerRotor)
    study = None if modal else stability_study(preset, params, setup)
    shaft = study is None and not modal and provides(setup.scene, "shaft")
    if args.exact and not modal:
        raise InputError(f"--exact: the closed form (17) is model 003's (flexible-abb), not {preset.name}'s")
    if not (shaft or modal) and study is None:
        raise wrong_kind(preset, "critical-speeds")
    if units_for(args, preset).system != "si" and not shaft:
        raise InputError(f"--units {args.units}: {preset.name}'s critical speeds are in its own speed unit "
                         f"({preset.speed_key}); use --units si")
    lo, hi = check_range("--range", *args.range, positive_lo=study is not None)
    prepare_out(args.out)
    if shaft:
        return _crossings(preset, params, lo, hi, args, _campbell_crossings(preset, params, lo, hi, args))
    if modal:
        return _crossings(preset, params, lo, hi, args, _modal_crossings(preset, params, lo, hi, args))
    return _margin_roots(preset, params, study, lo, hi, args)


def _modal_crossings(preset, params, lo, hi, args) -> dict:
    """Model 003's critical speeds (`rotorjax.analysis.balancer003_critical_speeds`) as
    `_crossings` presents them: the excited natural frequencies are the diagram."""
    from rotorjax.analysis import balancer003_critical_speeds

    if args.modes is not None:
        try:
            params = dict(params, modes=preset.check("modes", args.modes))
        except InputError as e:
            raise InputError(f"--modes {args.modes}: {str(e).split(': ', 1)[1]}") from None
    res = balancer003_critical_speeds(build(preset, params).scene.shaft, lo, hi, exact=args.exact)
    excited = np.asarray(res.excited)
    shown = excited[excited <= 1.2 * hi] if np.any(excited <= 1.2 * hi) else excited[:1]
    return {"params": params, "method": res.method,
            "unit": "omega_1 (first pinned-pinned frequency of the bare shaft)",
            "critical_speeds": list(res.critical_speeds),
            "campbell": (np.linspace(lo, hi, 2), np.tile(shown, (2, 1)), np.ones((2, shown.size), bool)),
            "present": {"unit": "omega_1 (dimensionless)",
                        "title": f"natural frequencies excited by the disk's unbalance, critical speeds "
                                 f"({res.method})"}}


def _campbell_crossings(preset, params, lo, hi, args) -> dict:
    """A finite-element rotor's 1x crossings (`rotorjax.analysis.campbell_critical_speeds`) as
    `_crossings` presents them."""
    from rotorjax.analysis import campbell_critical_speeds

    scene = build(preset, params).scene
    res = campbell_critical_speeds(scene, lo, hi, n_scan=args.n_scan, n_modes=args.modes or 8, what=preset.name)
    out = res.as_dict()
    out["campbell"] = (res.speeds, res.frequencies, res.forward)
    out["present"] = {"unit": "rad/s", "title": "critical speeds (1x crossings)"}
    return out


def _margin_roots(preset, params, study, lo, hi, args) -> int:
    """Critical speeds as the sign changes of the preset's stability margin."""
    from rotorjax.analysis import stability_thresholds
    from rotorjax.plot import plot_margin
    from ._common import save_figure

    key = preset.speed_key
    study.margin(dict(params, **{key: 0.5 * (lo + hi)}))  # validates the parameters
    found, (scan_x, scan_m) = stability_thresholds(lambda v: study.margin(dict(params, **{key: v})), lo, hi,
                                              n_scan=args.n_scan, return_scan=True, progress=not args.json)
    out = {"preset": preset.name, "regime": study.regime, "range": [lo, hi], "params": params,
           "critical_speeds": [c.as_dict() for c in found]}
    published = study.published[0] if study.published else None
    if published is not None:
        out["criterion_roots"] = published.within(lo, hi)
    stem = out_stem(args.out, preset, "critical_speeds_")
    save_figure(plot_margin(speeds=scan_x, margin=scan_m, roots=[c.speed for c in found],
                            title=f"{preset.name}: stability of {study.regime}", speed_label=f"{key} (dimensionless)",
                            margin_label="margin: largest Re(lambda) or Floquet exponent (dimensionless)",
                            extra_roots=out.get("criterion_roots"),
                            extra_label=published.label if published is not None else ""),
                stem + ".png")
    out["files"] = {"plot": stem + ".png"}
    if not np.any(np.isfinite(scan_m)):
        raise NumericalError(f"critical-speeds: the margin could not be computed at any of the {args.n_scan} scan "
                             f"points in [{lo:g}, {hi:g}]")
    if not np.all(np.isfinite(scan_m)):
        out["failed_scan_points"] = int(np.sum(~np.isfinite(scan_m)))
    if args.json:
        print(json.dumps(out, indent=2))
        return 0
    print(f"{preset.name}: critical speeds of {study.regime} in [{lo:g}, {hi:g}]:")
    if not found:
        print("  none (the margin keeps its sign over the range)")
    for c in found:
        print(f"  {key} = {c.speed:.6f}   stable {c.stable_side}")
    if "criterion_roots" in out:
        print(f"  {published.label}: "
              + (", ".join(f"{r:.4f}" for r in out["criterion_roots"]) or "none in the range"))
    if "failed_scan_points" in out:
        print(f"  warning: the margin could not be computed at {out['failed_scan_points']} of {args.n_scan} "
              "scan points (brackets there were skipped)")
    print(f"  wrote {stem}.png")
    return 0


def _crossings(preset, params, lo, hi, args, found) -> int:
    """Critical speeds as crossings of a Campbell diagram (1x crossings, natural frequencies)."""
    from rotorjax.plot import plot_campbell
    from ._common import save_figure

    (speeds, freqs, forward), look = found.pop("campbell"), found.pop("present")
    out = {"preset": preset.name, "range": [lo, hi], "params": found.pop("params", params), **found}
    crit = [c["speed"] if isinstance(c, dict) else c for c in out["critical_speeds"]]
    stem = out_stem(args.out, preset, "critical_speeds_")
    what = out.get("method", "1x crossings")
    units = Units(args.units)   # not si only for a shaft model's speeds in rad/s (`cmd_critical_speeds`)
    plotted = look["unit"] if units.system == "si" else units.label("speed")
    save_figure(plot_campbell(units.value(speeds, "speed"), units.value(freqs, "frequency"), forward,
                              critical=units.value(crit, "speed"), unit=plotted,
                              frequency_unit=None if units.system == "si" else units.label("frequency"),
                              title=f"{preset.name}: {look['title']}"), stem + ".png")
    out["files"] = {"plot": stem + ".png"}
    if look["unit"] == "rad/s":   # a shaft model's (model 003's are in its omega_1)
        out["unit"] = units.label("speed")
        lo, hi = units.value(lo, "speed"), units.value(hi, "speed")
        units.convert(out, {"range": "speed", "critical_speeds.*.speed": "speed",
                            "synchronous_determinant_roots": "speed"})
    if args.json:
        print(json.dumps(out, indent=2))
        return 0
    print(f"{preset.name}: critical speeds ({what}) in [{lo:g}, {hi:g}] {out['unit']}:")
    if not crit:
        print("  none in the range")
    for c in out["critical_speeds"]:
        if isinstance(c, dict) and units.system == "si":
            print(f"  {c['speed']:.4f} rad/s  ({c['speed'] * 30 / np.pi:.1f} rpm)  mode {c['mode']}, "
                  f"{c['whirl']} whirl")
        elif isinstance(c, dict):
            print(f"  {c['speed']:.1f} {out['unit']}  mode {c['mode']}, {c['whirl']} whirl")
        else:
            print(f"  {c:.6f}")
    if out.get("synchronous_determinant_roots"):
        print("  roots of the synchronous determinant (undamped): "
              + ", ".join(f"{r:.4f}" for r in out["synchronous_determinant_roots"]))
    print(f"  wrote {stem}.png")
    return 0


def cmd_stability_map(args) -> int:
    from rotorjax.plot import plot_stability_map

    from ._common import save_figure

    preset, params = preset_and_params(args, "stability-map")
    study = stability_study(preset, params)
    if study is None:
        raise InputError(f"{preset.name!r} has no reference regime to map")
    xk, xlo, xhi, nx = grid_spec("--x", args.x, preset, params)
    yk, ylo, yhi, ny = grid_spec("--y", args.y, preset, params)
    if xk == yk:
        raise InputError(f"--x {xk} and --y {yk}: the two axes need different parameters")
    prepare_out(args.out)
    grid = {xk: np.linspace(xlo, xhi, nx), yk: np.linspace(ylo, yhi, ny)}
    study.margin(dict(params, **{xk: grid[xk][0], yk: grid[yk][0]}))  # validates
    gx, gy = np.meshgrid(grid[xk], grid[yk], indexing="ij")
    margin = study.margins({xk: gx.reshape(-1), yk: gy.reshape(-1)}, args.chunk, not args.json).reshape(nx, ny)
    ok = np.isfinite(margin)
    if not ok.any():
        raise NumericalError(f"stability-map: the margin could not be computed at any of the {nx}x{ny} points")
    stem = out_stem(args.out, preset, "stability_map_")
    save_figure(plot_stability_map(grid[xk], grid[yk], margin, x_label=xk, y_label=yk,
                                   title=f"{preset.name}: stability of {study.regime}"), stem + ".png")
    np.savez(stem + ".npz", **{xk: grid[xk], yk: grid[yk]}, margin=margin)
    out = {"preset": preset.name, "regime": study.regime, "x": xk, "y": yk,
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
    from rotorjax.analysis import StraightRunning
    from rotorjax.plot import plot_margin
    from rotorjax.presets import hopf_report
    from ._common import save_figure

    preset, params = preset_and_params(args, "hopf")
    setup = build(preset, params)
    if not isinstance(setup.reference, StraightRunning):
        raise wrong_kind(preset, "hopf")
    if is_rotor_file(preset) and not args.range:
        raise InputError(f"--range LO HI is required for a rotor file: the speed range to search, rad/s (e.g. "
                         f"--range {0.5 * float(params['speed'] or 100):g} {2 * float(params['speed'] or 100):g})")
    lo, hi = check_range("--range", *(args.range or HOPF_RANGE), positive_lo=True)
    prepare_out(args.out)
    found, look = hopf_report(preset, params, lo, hi, n_scan=args.n_scan, progress=not args.json)
    scan_x, scan_m = found.pop("scan")
    out = {"preset": preset.name, "params": params, "range": [lo, hi],
           "range_source": "--range" if args.range else "default", **found}
    stem = out_stem(args.out, preset, "hopf_")
    save_figure(plot_margin(speeds=scan_x, margin=scan_m, roots=[h["speed"] for h in out["hopf_points"]],
                            title=f"{preset.name}: {look['title']}", speed_label=look["speed_label"],
                            margin_label=look["margin_label"], root_label="Hopf point",
                            extra_roots=look["extra_roots"], extra_label=look["extra_label"]), stem + ".png")
    out["files"] = {"plot": stem + ".png"}
    if args.json:
        print(json.dumps(out, indent=2))
        return 0
    key = preset.speed_key
    src = "" if args.range else " (the default range; set it with --range LO HI)"
    if not out["hopf_points"]:
        print(f"{preset.name}: {setup.reference.label} keeps its stability over {key} in [{lo:g}, {hi:g}]{src}")
    else:
        print(f"{preset.name}: searched {key} in [{lo:g}, {hi:g}]{src}")
    d_key, d_label = look["sensitivity"]
    for d in out["hopf_points"]:
        sens = f"; {d_label} = {d[d_key]:.4f}" if d_key else ""
        print(f"  Hopf point at {key} = {d['speed']:.6f} (whirl frequency {d['frequency']:.6f}, ratio "
              f"{d['whirl_frequency_ratio']:.4f}, {d['whirl']} whirl){sens}")
    if "paper_fit" in out:
        fit = out["paper_fit"]
        print(f"  the paper's fit {fit['formula']} gives {fit[key + '_crit']:.4f}")
    print(f"  wrote {stem}.png")
    return 0
