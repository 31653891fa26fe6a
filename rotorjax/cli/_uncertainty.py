"""`uncertainty ROTOR.toml --dist KEY=normal(MEAN,SD) ... [--output NAME ...]`: a rotor
file's critical speeds, log decrements and design quantities (response, onset,
separation margin, ...) as distributions (vmapped Monte Carlo and first-order
moments), with the probability that a mode is unstable and that a critical speed is
short of API 684's separation margin; or a preset's stability thresholds and stable
speed range (an auto-balancer's auto-balancing range)."""

import json
import os

import numpy as np

from ._common import InputError, NumericalError, design_target, is_rotor_file, out_stem, prepare_out, write_json


def _inputs(texts):
    from rotorjax.uncertainty import parse_distribution

    if not texts:
        raise InputError("--dist: give at least one parameter's distribution, e.g. --dist "
                         "'bearing0.kxx=lognormal(1e6,1e5)'")
    out = {}
    for text in texts:
        key, dist = parse_distribution(text)
        if key in out:
            raise InputError(f"--dist {text}: {key} is given twice")
        out[key] = dist
    return out


def cmd_uncertainty(args) -> int:
    from rotorjax.plot import plot_uncertainty
    from rotorjax.uncertainty import CHUNK_SIZE, preset_quantities, propagate, rotor_quantities
    from ._common import save_figure

    preset, params, overrides = design_target(args, "uncertainty")
    inputs = _inputs(args.dist)
    if args.samples < 2:
        raise InputError(f"--samples {args.samples}: at least 2")
    if args.modes < 0:
        raise InputError(f"--modes {args.modes}: at least 0")
    prepare_out(args.out)
    lo, hi = args.range if args.range is not None else (None, None)
    if is_rotor_file(preset):
        q = rotor_quantities(preset.name, inputs, lo=lo, hi=hi, speed=args.speed, n_modes=args.modes,
                             overrides=overrides, quantities=tuple(args.output or ()), operating=args.operating,
                             probes=args.probe)
    else:
        for option, given in (("--output", args.output), ("--speed", args.speed), ("--operating", args.operating),
                              ("--probe", args.probe)):
            if given:
                raise InputError(f"{option}: a rotor file's; {preset.name} (a preset) gives its stability "
                                 "thresholds and stable-range over --range")
        q = preset_quantities(preset, params, inputs, args.range, n_scan=args.n_scan)
    # the design quantities in vmapped chunks of 16: 64 samples of response, separation margin and mass in one
    # program hung XLA's CPU runtime in 3 runs of 4 (every thread idle); 16 at a time ran every time
    res = propagate(q.fn, inputs, samples=args.samples, seed=args.seed, names=q.outputs, fallback=q.fallback,
                    chunk_size=16 if args.output or not is_rotor_file(preset) else CHUNK_SIZE, progress=not args.json,
                    reverse=not is_rotor_file(preset))
    unstable, short = {}, {}
    for name in q.outputs:
        if name.startswith("log_dec_") or name == "min-log-dec" or name == "separation-margin":
            p, (a, b) = res.probability(name, below=0.0)
            (short if name == "separation-margin" else unstable)[name] = {"p": p, "ci95": [a, b]}
    out = {"preset": preset.name, "speed": q.speed, "parameters": {k: float(v) for k, v in zip(q.names, q.nominal)},
           "nominal_critical_speeds": [w for w, _ in q.critical], **res.as_dict(),
           "probability_unstable": unstable}
    if short:
        out["probability_separation_short"] = short
    if q.settings:
        out["settings"] = q.settings
    stem = out_stem(args.out, preset, "uncertainty_")
    title = f"{os.path.basename(preset.name)}: {res.n} samples of {len(inputs)} parameter(s)"
    save_figure(plot_uncertainty(result=res, title=title), stem + ".png")
    out["files"] = {"plot": stem + ".png", "json": stem + ".json"}
    if res.n < args.samples:
        out["warnings"] = [f"{args.samples - res.n} of {args.samples} samples gave non-finite outputs (a critical "
                           "speed's fixed point did not converge there) and are left out of the statistics"]
    write_json(stem + ".json", out)
    if args.json:
        print(json.dumps(out, indent=2))
    else:
        print(f"{preset.name}: {res.n} samples of {', '.join(f'{k} ~ {d.text()}' for k, d in inputs.items())}")
        for j, name in enumerate(q.outputs):
            lo5, hi95 = float(res.quantiles[0.05][j]), float(res.quantiles[0.95][j])
            # which parameter's scatter moves it most: none where every sample gives the same value (an
            # undamped rotor's log decrements, 0 in each)
            most = (f"most from {q.names[int(np.argmax(res.shares[j]))]}" if res.std[j] > 0
                    else "the same in every sample")
            print(f"  {name}: mean {res.mean[j]:.6g} (+- {res.sem[j]:.2g}), sd {res.std[j]:.4g}, 5-95 % "
                  f"[{lo5:.6g}, {hi95:.6g}]; first order {res.fosm_mean[j]:.6g} +- {res.fosm_std[j]:.4g}; {most}")
        for name, u in {**unstable, **short}.items():
            print(f"  P({name} < 0) = {u['p']:.4g}, 95 % [{u['ci95'][0]:.3g}, {u['ci95'][1]:.3g}]")
        for w in out.get("warnings", []):
            print(f"  warning: {w}")
        print(f"  wrote {stem}.png and .json")
    if res.n < 2:
        raise NumericalError("uncertainty: fewer than 2 samples gave finite outputs")
    return 0
