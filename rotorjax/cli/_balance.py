"""`balance` and `identify`: one command path each for every scene (model 002's
balancing machine, any rotor file); `identify` on a rotor file is presented by
`_fe_identify`."""

import json
import math
import os

import numpy as np

from ._common import InputError, Stages, build, get_preset, int_list, name_list, out_stem, prepare_out
from ._common import is_rotor_file, preset_and_params, write_json

_ROTOR_ONLY_IDENTIFY = {"--weights": ("weights", "relative"), "--covariance": ("covariance", "classical"),
                        "--starts": ("starts", 32), "--spread": ("spread", 10.0), "--method": ("method", "lm")}
#: the phasor file a shipped rotor file is balanced from when --data is not given
DEFAULT_BALANCE_DATA = "flexible-trials"


def _not_here(args, options, where):
    for option, (dest, default) in options.items():
        if getattr(args, dest, default) != default:
            raise InputError(f"{option} applies to {where}")


def _speed_list(text):
    """`--speeds 100,200`: comma-separated positive numbers (rad/s)."""
    try:
        values = [float(v) for v in text.split(",") if v.strip()]
    except ValueError:
        raise InputError(f"--speeds {text}: expected comma-separated numbers (rad/s)") from None
    if not values:
        raise InputError(f"--speeds {text!r}: empty list")
    if not all(math.isfinite(v) and v > 0 for v in values):
        raise InputError(f"--speeds {text}: speeds must be finite and > 0 (rad/s)")
    return values


def _as_option(e, args):
    """An `InputError` of `balance` about `planes:`/`speeds:`/`holes` restated with the option."""
    text = str(e)
    for key, option, value in (("planes: ", "--planes", args.planes), ("speeds: ", "--speeds", args.speeds)):
        if text.startswith(key):
            return InputError(f"{option}{'' if value is None else ' ' + value}: {text[len(key):]}")
    return e


def _balance_input(args):
    """`(label, data, scene, planes, rotor_mass, radius, stem)` of `balance`: the balancing
    machine's runs (no ROTOR; its preset's scene is the model) or a rotor file's
    phasor runs (its rotor is the model)."""
    from rotorjax import identify as idf
    from rotorjax.identify import read_phasors

    planes = None if args.planes is None else int_list("--planes", args.planes)
    if args.preset is None:
        for option, value in (("--set", args.set), ("--data", args.data)):
            if value is not None:
                raise InputError(f"{option} applies to a rotor file: `rotorjax balance ROTOR.toml --data FILE ...` "
                                 "(the balancing machine's runs are --runs FILE)")
        data = idf.balancing_runs(idf.resolve_data(args.runs) if args.runs else idf.BALANCING_RUNS, planes)
        machine = get_preset("balancing-machine")
        scene = build(machine, dict(machine.defaults)).scene
        mass = 10.0 if args.rotor_mass is None else args.rotor_mass
        radius = 0.01 if args.radius is None else args.radius
        return "the balancing machine", data, scene, None, mass, radius, "balance"
    if args.runs is not None:
        raise InputError("--runs applies to the balancing machine (no ROTOR); with a rotor file give --data "
                         "PHASOR_FILE")
    preset, params = preset_and_params(args, "balance")
    if not is_rotor_file(preset):   # the balancing machine is balanced from its runs, without a preset
        raise InputError(f"`balance {preset.name}`: the balancing machine is balanced without naming it: "
                         "`rotorjax balance --runs FILE ...`; a preset named here must be a rotor file")
    if args.holes is not None and args.radius is None:
        raise InputError(f"--holes {args.holes}: a split onto holes needs the correction radius (--radius M)")
    data = read_phasors(args.data if args.data is not None else DEFAULT_BALANCE_DATA)
    rotor = build(preset, params).scene.full_rotor   # a reduced rotor's full one
    return preset.name, data, rotor, planes, args.rotor_mass, args.radius, "balance_rotor"


def cmd_balance(args) -> int:
    from rotorjax import identify as idf
    from rotorjax.plot import plot_balance, plot_fe_balance
    from ._common import save_figure

    if args.holes is not None and args.holes < 2:
        raise InputError(f"--holes {args.holes}: a split needs >= 2 equally spaced holes (omit --holes for none)")
    if args.model:
        if args.influence not in (None, "model"):
            raise InputError(f"--model and --influence {args.influence} contradict each other")
        args.influence = "model"
    speeds = None if args.speeds is None else _speed_list(args.speeds)
    prepare_out(args.out)
    label, data, scene, planes, mass, radius, name = _balance_input(args)
    try:
        res = idf.balance(data, planes, speeds=speeds, method=args.method, influence=args.influence or "trials",
                          scene=scene, rotor_mass=mass, service_speed=args.service_speed,
                          grade=2.5 if args.grade is None else args.grade, radius=radius, holes=args.holes)
    except InputError as e:
        raise _as_option(e, args) from None
    out = {"preset": None if args.preset is None else label, **res.as_dict()}
    stem = os.path.join(args.out, name)
    title = (f"{label}: {res.method} balancing in {len(res.planes)} plane(s) from {os.path.basename(res.path)}"
             + (f", radius {radius:g} m" if radius is not None else ""))
    if len(res.balancing_speeds) == 1:     # one speed: the phasors and corrections on polar axes
        corr, unit = (res.masses_g, "g") if radius is not None else (res.W, "kg m")
        fig = plot_balance(before=res.X0, after=res.predicted, corrections=corr, planes=list(res.planes),
                           mass_unit=unit, title=title)
    else:
        fig = plot_fe_balance(result=res, title=title)
    save_figure(fig, stem + ".png", bbox_inches="tight")
    out["files"] = {"plot": stem + ".png", "json": stem + ".json"}
    write_json(stem + ".json", out, indent=2)
    if args.json:
        print(json.dumps(out, indent=2))
        return 0
    rpm = res.service_speed * 30 / np.pi
    print(f"{label}: {res.method} balancing in {len(res.planes)} plane(s) at "
          f"{', '.join(f'{s:.4g}' for s in out['speeds'])} rad/s from {res.path}, {len(set(res.sensors))} sensors "
          f"(influence coefficients: {res.influence}; service speed {res.service_speed:.4g} rad/s, {rpm:.0f} rpm)")
    for c in out["corrections"]:
        where = f"{res.plane_key} {c[res.plane_key]}"
        if radius is not None:
            print(f"  {where}: add {c['mass_g']:.3f} g at {c['angle_deg']:.1f} deg (radius {c['radius_m']} m; "
                  f"{c['magnitude']:.4g} kg m)")
            for h in c.get("holes", []):
                print(f"    or {h['mass_g']:.3f} g in the hole at {h['angle_deg']:.1f} deg")
        else:
            print(f"  {where}: add {c['magnitude']:.4g} kg m at {c['phase_deg']:.1f} deg")
    r = out["residual"]
    print(f"  vibration max {r['before_max']:.3g} m -> {r['after_max']:.3g} m predicted, rms {r['before_rms']:.3g} m "
          f"-> {r['after_rms']:.3g} m")
    worst = int(np.argmax(np.abs(res.predicted)))
    n, d = res.sensors[worst]
    sensor = f"sensor {res.sensor_names[n]}" if res.sensor_names else f"node {n} {d}"
    print(f"  largest predicted residual at {res.speeds[worst]:.4g} rad/s, {sensor}")
    for line in res.explanation:
        print(f"  {line}")
    for w in res.warnings:
        print(f"  warning: {w}")
    print(f"  wrote {out['files']['plot']} and {out['files']['json']}")
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
    res = idf.identify(scene, path, fit, fit_unbalance=args.fit_unbalance, block=args.block,
                       min_speed=args.min_speed, stage=stages, band=True)
    stages("the model's 95% band, plot")
    data = res.data
    out = {"preset": preset.name, "data": path, "fit": list(fit), "n_points": data.n,
           "speed_range_rad_s": [float(data.speeds.min()), float(data.speeds.max())],
           "start": {k: params[k] for k in fit}, **res.as_dict()}
    stem = out_stem(args.out, preset, "identify_")
    fitted, lo, hi = res.band
    save_figure(plot_identification(speeds=data.speeds, data=data.X, fit=fitted, lo=lo, hi=hi,
                                    title=f"{preset.name}: fit of {', '.join(fit)} to {os.path.basename(path)}",
                                    channels=list(data.sensors)), stem + ".png")
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
