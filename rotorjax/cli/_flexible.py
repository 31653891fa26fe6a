"""`campbell`, `response`: linear analyses of a finite-element rotor."""

import json
import os

import numpy as np

from ._common import InputError, NumericalError, build, check_range, preset_and_params, prepare_out, write_json


def _rotor(preset, params, n_modes):
    rotor = build(preset, params)[0]
    if n_modes is None:
        return rotor
    n = int(np.asarray(rotor.reduced_matrices()[0]).shape[0])
    if not 1 <= n_modes <= n:
        raise InputError(f"--reduce {n_modes}: n_modes (reduction) must be in 1..{n} (the rotor's dofs)")
    return rotor.reduce(n_modes)


def cmd_campbell(args) -> int:
    from rotorjax.flexible import campbell, critical_speeds_1x
    from rotorjax.plot import plot_campbell

    preset, params = preset_and_params(args, "campbell", "flexible")
    lo, hi = check_range("--range", *args.range)
    prepare_out(args.out)
    rotor = _rotor(preset, params, args.reduce)
    n = 2 * int(np.asarray(rotor.reduced_matrices()[0]).shape[0])
    if args.modes > n:
        raise InputError(f"--modes {args.modes}: the rotor has {n} modes" + (" after --reduce" if args.reduce else ""))
    speeds = np.linspace(lo, hi, args.n_speeds)
    camp = campbell(rotor, speeds, args.modes)
    crit = critical_speeds_1x(rotor, max(lo, 1e-6), hi, n_modes=args.modes)
    stem = os.path.join(args.out, f"campbell_{preset.name}")
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
    from rotorjax.flexible import unbalance_response
    from rotorjax.plot import plot_response

    preset, params = preset_and_params(args, "response", "flexible")
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
    peaks = [float(speeds[i]) for i in range(1, len(amp) - 1) if amp[i] > amp[i - 1] and amp[i] > amp[i + 1]]
    stem = os.path.join(args.out, f"response_{preset.name}")
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
