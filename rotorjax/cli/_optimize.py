"""`optimize ROTOR.toml --vary KEY=LO:HI ... --objective NAME [--constraint NAME>=V ...]`:
a rotor file's parameters chosen within bounds against its margins (`rotorjax.design`),
with the optimised rotor written as a rotor file; or a preset's `--set` keys against
its reference motion's stable speed range (an auto-balancer's auto-balancing range),
the optimum written as its `--set` values."""

import json
import os

import numpy as np

from ._common import (InputError, NumericalError, design_target, is_rotor_file, out_stem, prepare_out, save_figure,
                      write_json)


def _vary(texts):
    if not texts:
        raise InputError("--vary: give at least one parameter and its bounds, e.g. --vary bearing0.kxx=1e5:1e7")
    out = {}
    for text in texts:
        key, sep, bounds = text.partition("=")
        lo, colon, hi = bounds.partition(":")
        if not sep or not colon or not key.strip():
            raise InputError(f"--vary {text!r}: give KEY=LO:HI, e.g. bearing0.kxx=1e5:1e7")
        try:
            a, b = float(lo), float(hi)
        except ValueError:
            raise InputError(f"--vary {text!r}: {lo!r} and {hi!r} must be numbers") from None
        key = key.strip()
        if key in out:
            raise InputError(f"--vary {text}: {key} is given twice")
        out[key] = (a, b)
    return out


def _scatter(texts):
    from rotorjax.uncertainty import parse_distribution

    out = {}
    for text in texts or []:
        key, dist = parse_distribution(text, "--scatter")
        if key in out:
            raise InputError(f"--scatter {text}: {key} is given twice")
        out[key] = dist
    return out or None


def cmd_optimize(args) -> int:
    from rotorjax.design import optimize_rotor, parse_constraint, preset_problem, rotor_problem
    from rotorjax.io import read_rotor_file, save_rotor
    from rotorjax.plot import plot_design

    preset, params, overrides = design_target(args, "optimize")
    vary = _vary(args.vary)
    constraints = [parse_constraint(c) for c in (args.constraint or [])]
    scatter = _scatter(args.scatter)
    if args.starts < 1:
        raise InputError(f"--starts {args.starts}: at least 1")
    prepare_out(args.out)
    sense = {"max": 1, "min": -1, None: None}[args.sense]
    robust = dict(scatter=scatter, robust_k=args.robust, robust_samples=args.robust_samples, seed=args.seed)
    stem = out_stem(args.out, preset, "optimize_")
    if is_rotor_file(preset):
        file = read_rotor_file(preset.name, overrides)
        problem = rotor_problem(file, vary, args.objective or "min-log-dec", constraints, speed_range=args.range,
                                n_modes=args.modes,
                                operating=args.operating, probes=args.probe, sense=sense,
                                max_frequency=args.max_frequency, **robust)
    else:
        problem = preset_problem(preset, params, vary, args.objective or "stable-range", constraints,
                                 speed_range=args.range, sense=sense, n_scan=args.n_scan, **robust)
    design = optimize_rotor(problem, n_starts=args.starts, seed=args.seed, progress=not args.json)
    o = design.optimum
    files = {"plot": stem + ".png", "json": stem + ".json"}
    if is_rotor_file(preset):
        files["rotor"] = stem + ".toml"
        save_rotor(read_rotor_file(preset.name, {**overrides, **design.overrides()}).scene, files["rotor"],
                   name=f"{file.name}-optimized")
        span = problem.settings["range"] or problem.settings.get("critical_range")
        look = dict(campbell=design.campbell(np.linspace(span[0], span[1], 60)) if span else None)
    else:
        look = dict(margins=design.margins(np.linspace(*problem.settings["range"], 80)),
                    speed_label=f"{preset.speed_key} ({preset.units.get(preset.speed_key, '')})")
    save_figure(plot_design(design=design, title=f"{os.path.basename(preset.name)}: {problem.objective}", **look),
                files["plot"])
    out = {"preset": preset.name, **design.as_dict(), "files": files}
    if not is_rotor_file(preset):
        out["set"] = {**overrides, **design.after}
    write_json(stem + ".json", out)
    if args.json:
        print(json.dumps(out, indent=2))
    else:
        _summary(args, preset, out, o, stem)
    where = files.get("rotor", files["json"])
    if not o.converged:
        raise NumericalError(f"optimize: {o.reason}; the best point found is written to {where}")
    rescan = out.get("rescan")
    if rescan and not rescan["agree"]:
        raise NumericalError(f"optimize: at the optimum a fresh scan finds a stable range of {rescan['scanned']:.6g}, "
                             f"the thresholds followed from the start {rescan['followed']:.6g} (an unstable band "
                             f"opened or closed unseen); narrow the bounds; the point is written to {where}")
    return 0


def _summary(args, preset, out, o, stem):
    obj = out["objective"]
    unit = f" {obj['unit']}" if obj["unit"] else ""
    robust = out["robust"]
    what = (f"{obj['name']} (mean {'-' if obj['sense'] == 'max' else '+'} {robust['k']:g} sd over "
            f"{robust['samples']} samples of the scatter)" if robust else obj["name"])
    print(f"{preset.name}: {obj['sense']}imise {what}: {obj['before']:.6g} -> {obj['after']:.6g}{unit} "
          f"({o.reason}; {o.evaluations} evaluations, start {o.best + 1} of {args.starts})")
    for k, v in out["parameters"].items():
        print(f"  {k}: {v['before']:.6g} -> {v['after']:.6g}  (bounds {v['lo']:g}..{v['hi']:g})")
    for r in out["constraints"]:
        unit = f" {r['unit']}" if r["unit"] else ""
        stat = f" (mean {r['mean']:.6g}, sd {r['sd']:.3g})" if "mean" in r else ""
        print(f"  constraint {r['name']} {r['op']} {r['limit']:g}: {r['value']:.6g}{unit}{stat} "
              f"({'met' if r['met'] else 'NOT met'}, multiplier {r['multiplier']:.3g})")
    if "rescan" in out:
        r = out["rescan"]
        verdict = "agrees" if r["agree"] else "DISAGREES"
        print(f"  checked by a fresh scan: stable range {r['scanned']:.6g} ({verdict}), "
              f"thresholds {', '.join(f'{t:.6g}' for t in r['thresholds']) or 'none'}")
    if "set" in out:
        print("  as --set values: " + " ".join(f"--set {k}={v:.6g}" for k, v in out["set"].items()))
    wrote = ", ".join(v for k, v in out["files"].items() if k != "json")
    print(f"  wrote {wrote} and {stem}.json")
