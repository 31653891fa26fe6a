"""`campbell`, `response`: linear analyses of a finite-element rotor (the
`ross-compare` preset, rotor files)."""

import json

import numpy as np

from ._common import (InputError, NumericalError, build, check_range, out_stem, prepare_out, preset_and_params,
                      write_json)

#: kinds of preset with a finite-element rotor
KINDS = ("flexible", "rotor")


def _rotor(preset, params, n_modes):
    """The preset's FE rotor, reduced to its `n_modes` lowest undamped modes (`--reduce`)."""
    from rotorjax.presets._hooks import fe_rotor, rotor_dofs

    rotor = fe_rotor(build(preset, params).scene)
    if n_modes is None:
        return rotor
    n = rotor_dofs(rotor)
    if not 1 <= n_modes <= n:
        raise InputError(f"--reduce {n_modes}: n_modes (reduction) must be in 1..{n} (the rotor's dofs)")
    return rotor.reduce(n_modes)


def cmd_campbell(args) -> int:
    from rotorjax.flexible import campbell, critical_speeds_1x
    from rotorjax.plot import plot_campbell
    from rotorjax.presets._hooks import rotor_dofs

    preset, params = preset_and_params(args, "campbell", KINDS)
    lo, hi = check_range("--range", *args.range)
    prepare_out(args.out)
    rotor = _rotor(preset, params, args.reduce)
    n = 2 * rotor_dofs(rotor)
    if args.modes > n:
        raise InputError(f"--modes {args.modes}: the rotor has {n} modes" + (" after --reduce" if args.reduce else ""))
    speeds = np.linspace(lo, hi, args.n_speeds)
    camp = campbell(rotor, speeds, args.modes)
    crit = critical_speeds_1x(rotor, max(lo, 1e-6), hi, n_modes=args.modes)
    stem = out_stem(args.out, preset, "campbell_")
    plot_campbell(speeds, np.asarray(camp.frequencies), np.asarray(camp.forward), stem + ".png",
                  critical=[s for s, _ in crit], title=f"{preset.name}: Campbell diagram"
                  + (f" (reduced to {args.reduce} modes)" if args.reduce else ""))
    out = {"preset": preset.name, "unit": "rad/s", "speeds": speeds.tolist(),
           "frequencies": np.asarray(camp.frequencies).tolist(),
           "forward": np.asarray(camp.forward).tolist(),
           "log_dec": np.asarray(camp.log_dec).tolist(),
           "critical_speeds": [s for s, _ in crit], "files": {"plot": stem + ".png"}}
    if not np.all(np.isfinite(out["frequencies"])):
        raise NumericalError("campbell: non-finite natural frequencies")
    write_json(stem + ".json", out)
    if args.json:
        print(json.dumps(out))
    else:
        print(f"wrote {stem}.png and .json; critical speeds (rad/s): "
              + (", ".join(f"{s:.3f}" for s, _ in crit) or f"none in [{lo:g}, {hi:g}]"))
    return 0


def cmd_response(args) -> int:
    from rotorjax.analysis._summary import local_maxima
    from rotorjax.flexible import unbalance_response
    from rotorjax.plot import plot_response

    preset, params = preset_and_params(args, "response", KINDS)
    lo, hi = check_range("--range", *args.range, positive_lo=True)
    prepare_out(args.out)
    rotor = _rotor(preset, params, args.reduce)
    for name, node in (("--node", args.node), ("--probe", args.probe)):
        if not 0 <= node < rotor.n_nodes:
            raise InputError(f"{name} {node}: the rotor has nodes 0..{rotor.n_nodes - 1}")
    speeds = np.linspace(lo, hi, args.n)
    X, Y = unbalance_response(rotor, args.node, args.unbalance, args.phase, speeds, probe_nodes=[args.probe])
    X, Y = np.asarray(X[:, 0]), np.asarray(Y[:, 0])
    amp = np.sqrt(np.abs(X) ** 2 + np.abs(Y) ** 2)
    if not np.all(np.isfinite(amp)):
        raise NumericalError("response: non-finite amplitudes (an undamped rotor exactly at a critical speed?)")
    peaks = local_maxima(speeds, amp)
    stem = out_stem(args.out, preset, "response_")
    plot_response(speeds, X, Y, stem + ".png", title=f"{preset.name}: unbalance response at node {args.probe} "
                  f"({args.unbalance:g} kg m at node {args.node})")
    out = {"preset": preset.name, "node": args.node, "probe": args.probe, "unbalance": args.unbalance,
           "unit": "rad/s, m", "peaks": peaks, "max_amplitude": float(amp.max()),
           "speed_at_max": float(speeds[np.argmax(amp)]), "files": {"plot": stem + ".png"}}
    if args.json:
        print(json.dumps(out, indent=2))
    else:
        print("peaks at " + (", ".join(f"{p:.2f}" for p in peaks) or "none inside the range")
              + f" rad/s; wrote {stem}.png")
    return 0
