"""`optimize ROTOR.toml --vary KEY=LO:HI ... --objective NAME [--constraint NAME>=V ...]`:
a rotor file's parameters chosen within bounds against its margins (`rotorjax.design`),
with the optimised rotor written as a rotor file."""

import json
import os

import numpy as np

from ._common import InputError, NumericalError, out_stem, prepare_out, rotor_file_target, write_json


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
    from rotorjax.design import optimize_rotor, parse_constraint, rotor_problem
    from rotorjax.io import read_rotor_file, save_rotor
    from rotorjax.plot import plot_design
    from ._common import save_figure

    preset, overrides = rotor_file_target(args, "optimize")
    vary = _vary(args.vary)
    constraints = [parse_constraint(c) for c in (args.constraint or [])]
    scatter = _scatter(args.scatter)
    if args.starts < 1:
        raise InputError(f"--starts {args.starts}: at least 1")
    prepare_out(args.out)
    file = read_rotor_file(preset.name, overrides)
    sense = {"max": 1, "min": -1, None: None}[args.sense]
    problem = rotor_problem(file, vary, args.objective, constraints, speed_range=args.range, n_modes=args.modes,
                            operating=args.operating, probes=args.probe, sense=sense,
                            max_frequency=args.max_frequency, scatter=scatter, robust_k=args.robust,
                            robust_samples=args.robust_samples, seed=args.seed)
    design = optimize_rotor(problem, n_starts=args.starts, seed=args.seed, progress=not args.json)
    o = design.optimum
    stem = out_stem(args.out, preset, "optimize_")
    rotor_path = stem + ".toml"
    save_rotor(read_rotor_file(preset.name, {**overrides, **design.after}).scene, rotor_path,
               name=f"{file.name}-optimized")
    span = problem.settings["range"] or problem.settings.get("critical_range")
    campbell = design.campbell(np.linspace(span[0], span[1], 60)) if span else None
    save_figure(plot_design(design=design, campbell=campbell,
                            title=f"{os.path.basename(preset.name)}: {problem.objective}"), stem + ".png")
    out = {"preset": preset.name, **design.as_dict(),
           "files": {"rotor": rotor_path, "plot": stem + ".png", "json": stem + ".json"}}
    write_json(stem + ".json", out)
    obj = out["objective"]
    if args.json:
        print(json.dumps(out, indent=2))
    else:
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
        print(f"  wrote {rotor_path}, {stem}.png and .json")
    if not o.converged:
        raise NumericalError(f"optimize: {o.reason}; the best point found is written to {rotor_path}")
    return 0
