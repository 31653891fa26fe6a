"""`balance ROTOR.toml`: multi-plane, multi-speed balancing of a rotor file's
flexible rotor from a phasor file (a baseline run and one trial run per plane, or
the model's influence coefficients)."""

import json
import math
import os

import numpy as np

from ._common import InputError, build, int_list, is_rotor_file, prepare_out, preset_and_params, write_json

#: the phasor file used when --data is not given
DEFAULT_DATA = "flexible-trials"


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
    """An `InputError` of `balance_rotor` about `planes:`/`speeds:` restated with the option."""
    text = str(e)
    for key, option, value in (("planes: ", "--planes", args.planes), ("speeds: ", "--speeds", args.speeds)):
        if text.startswith(key):
            return InputError(f"{option} {value}: {text[len(key):]}")
    return e


def cmd_fe_balance(args) -> int:
    from rotorjax.identify._fe_balance import _check_unbalance_data, balance_rotor
    from rotorjax.identify._phasor_file import read_phasors
    from rotorjax.plot import plot_fe_balance
    from ._common import save_figure

    preset, params = preset_and_params(args, "balance")
    if not is_rotor_file(preset):   # the balancing machine is balanced from its runs, without a preset
        raise InputError(f"`balance {preset.name}`: the balancing machine is balanced without naming it: "
                         "`rotorjax balance --runs FILE ...`; a preset named here must be a rotor file")
    planes = None if args.planes is None else int_list("--planes", args.planes)
    speeds = None if args.speeds is None else _speed_list(args.speeds)
    if args.out:
        prepare_out(args.out)
    data = read_phasors(args.data if args.data is not None else DEFAULT_DATA)
    if planes is None:   # default: every node that carries a trial weight in the data
        _check_unbalance_data(data)
        planes = sorted({int(n) for n in data.trial_node if n >= 0})
        if not planes:
            raise InputError(f"--planes: {data.path} has no trial runs to take the correction planes from; name "
                             "them (FE nodes), e.g. --planes 2,4")
        args.planes = ",".join(map(str, planes))
    rotor = build(preset, params).scene.full_rotor   # a reduced rotor's full one
    try:
        res = balance_rotor(data, planes, speeds=speeds, method=args.method, influence=args.influence, rotor=rotor,
                            rotor_mass=args.rotor_mass, service_speed=args.service_speed,
                            grade=2.5 if args.grade is None else args.grade)
    except InputError as e:
        raise _as_option(e, args) from None
    out = {"preset": preset.name, **res.as_dict()}
    if args.out:
        stem = os.path.join(args.out, "balance_rotor")
        save_figure(plot_fe_balance(result=res, title=f"{preset.name}: {len(planes)}-plane balancing from "
                                                      f"{os.path.basename(res.path)}"), stem + ".png")
        out["files"] = {"plot": stem + ".png", "json": stem + ".json"}
        write_json(stem + ".json", out, indent=2)
    if args.json:
        print(json.dumps(out, indent=2))
        return 0
    speeds_used = ", ".join(f"{s:.4g}" for s in out["speeds"])
    print(f"{preset.name}: {res.method} balancing in {len(planes)} plane(s) at {speeds_used} rad/s from "
          f"{res.path} (influence coefficients: {res.influence})")
    for c in out["corrections"]:
        print(f"  node {c['node']}: add {c['magnitude']:.4g} kg m at {c['phase_deg']:.1f} deg")
    r = out["residual"]
    print(f"  vibration max {r['before_max']:.3g} m -> {r['after_max']:.3g} m predicted, rms {r['before_rms']:.3g} m "
          f"-> {r['after_rms']:.3g} m")
    worst = int(np.argmax(np.abs(res.predicted)))
    n, d = res.sensors[worst]
    print(f"  largest predicted residual at {res.speeds[worst]:.4g} rad/s, node {n} {d}")
    for line in res.explanation:
        print(f"  {line}")
    for w in res.warnings:
        print(f"  warning: {w}")
    if args.out:
        print(f"  wrote {out['files']['plot']} and {out['files']['json']}")
    return 0
