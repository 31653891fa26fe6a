"""`campbell`, `response`: linear analyses of a finite-element rotor (the
`ross-compare` preset, rotor files)."""

import json

import numpy as np

from ._common import (InputError, NumericalError, build, check_range, out_stem, prepare_out, preset_and_params,
                      write_json)

#: kinds of preset with a finite-element rotor
KINDS = ("flexible", "rotor")


def _rotor(preset, params, n_modes, scene=False):
    """The preset's FE rotor, reduced to its `n_modes` lowest undamped modes (`--reduce`);
    with `scene`, its `RotorScene` (on the reduced rotor), whose linear part counts
    the components' linearisations (a rotor file's cubic bearings, internal damping)."""
    from rotorjax.models import RotorScene
    from rotorjax.presets._hooks import fe_rotor, rotor_dofs

    sc = build(preset, params).scene
    rotor = fe_rotor(sc)
    if n_modes is not None:
        n = rotor_dofs(rotor)
        if not 1 <= n_modes <= n:
            raise InputError(f"--reduce {n_modes}: n_modes (reduction) must be in 1..{n} (the rotor's dofs)")
        rotor = rotor.reduce(n_modes)
    if not scene:
        return rotor
    return sc if n_modes is None else RotorScene(rotor, sc.speed, sc.components)


def cmd_campbell(args) -> int:
    from rotorjax.flexible import campbell, critical_speeds_1x, track_modes, track_order
    from rotorjax.plot import plot_campbell_tracked
    from rotorjax.presets._hooks import rotor_dofs

    preset, params = preset_and_params(args, "campbell", KINDS)
    lo, hi = check_range("--range", *args.range)
    prepare_out(args.out)
    rotor = _rotor(preset, params, args.reduce, scene=True)
    dofs = rotor_dofs(rotor)
    n = 2 * dofs
    if args.modes > n:
        raise InputError(f"--modes {args.modes}: the rotor has {n} modes" + (" after --reduce" if args.reduce else ""))
    speeds = np.linspace(lo, hi, args.n_speeds)
    # a few modes above those shown, so that branches entering from above are tracked too
    wide = campbell(rotor, speeds, min(args.modes + 4, dofs))
    k = min(args.modes, dofs)
    camp = campbell(rotor, speeds, args.modes)
    tracked = track_modes(wide)
    _, mac_step = track_order(wide)
    t_freq = np.asarray(tracked.frequencies)[:, :k]
    t_whirl = np.asarray(tracked.whirl)[:, :k]
    t_logdec = np.asarray(tracked.log_dec)[:, :k]
    crit = critical_speeds_1x(rotor, max(lo, 1e-6), hi, n_modes=args.modes)
    stem = out_stem(args.out, preset, "campbell_")
    plot_campbell_tracked(speeds, t_freq, t_whirl, t_logdec, stem + ".png", critical=[s for s, _ in crit],
                          title=f"{preset.name}: Campbell diagram (tracked modes)"
                          + (f" (reduced to {args.reduce} modes)" if args.reduce else ""))
    out = {"preset": preset.name, "unit": "rad/s", "speeds": speeds.tolist(),
           "frequencies": np.asarray(camp.frequencies).tolist(),
           "forward": np.asarray(camp.forward).tolist(),
           "log_dec": np.asarray(camp.log_dec).tolist(),
           "tracked": {"frequencies": t_freq.tolist(), "whirl": t_whirl.tolist(), "log_dec": t_logdec.tolist(),
                       "min_mac": mac_step[:, :k].min(axis=0).tolist()},
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


def unbalance_spec(text):
    """`--unbalance`: a magnitude `U` (kg m, > 0; at `--node` with `--phase`) or
    `NODE,MAG,PHASE` (an argparse type)."""
    import argparse

    from ._common import positive

    if "," not in text:
        return positive(text)
    parts = [p.strip() for p in text.split(",")]
    bad = argparse.ArgumentTypeError(f"expected NODE,MAG,PHASE (e.g. 2,1e-3,0: node, kg m, rad) or a magnitude, "
                                     f"got {text!r}")
    if len(parts) != 3:
        raise bad
    try:
        node, mag, phase = int(parts[0]), float(parts[1]), float(parts[2])
    except ValueError:
        raise bad from None
    if node < 0:
        raise argparse.ArgumentTypeError(f"NODE must be >= 0, got {text!r}")
    if not (np.isfinite(mag) and mag > 0):
        raise argparse.ArgumentTypeError(f"MAG must be a finite number > 0 (kg m), got {text!r}")
    if not np.isfinite(phase):
        raise argparse.ArgumentTypeError(f"PHASE must be finite (rad), got {text!r}")
    return node, mag, phase


def _unbalances(args, n_nodes):
    """`(triples, single)`: the NODE,MAG,PHASE unbalances of `--unbalance`, or None
    and the single magnitude at `--node`."""
    given = args.unbalance or [1e-3]
    triples = [u for u in given if isinstance(u, tuple)]
    if triples and len(triples) != len(given):
        raise InputError("--unbalance: give one magnitude (at --node, --phase) or NODE,MAG,PHASE triples, not both")
    if not triples:
        if len(given) > 1:
            raise InputError("--unbalance: a bare magnitude may be given once; use NODE,MAG,PHASE for several")
        return None, given[0]
    for node, mag, phase in triples:
        if not node < n_nodes:
            raise InputError(f"--unbalance {node},{mag:g},{phase:g}: the rotor has nodes 0..{n_nodes - 1}")
    return triples, None


def cmd_response(args) -> int:
    from rotorjax.analysis._summary import local_maxima
    from rotorjax.flexible import deflected_shape, unbalance_response, unbalance_response_many
    from rotorjax.plot import plot_deflected_shape, plot_response

    preset, params = preset_and_params(args, "response", KINDS)
    lo, hi = check_range("--range", *args.range, positive_lo=True)
    prepare_out(args.out)
    rotor = _rotor(preset, params, args.reduce)
    for name, node in (("--node", args.node), ("--probe", args.probe)):
        if not 0 <= node < rotor.n_nodes:
            raise InputError(f"{name} {node}: the rotor has nodes 0..{rotor.n_nodes - 1}")
    triples, single = _unbalances(args, rotor.n_nodes)
    speeds = np.linspace(lo, hi, args.n)
    if triples is None:
        X, Y = unbalance_response(rotor, args.node, single, args.phase, speeds, probe_nodes=[args.probe])
        triples_used = [(args.node, single, args.phase)]
        what = f"{single:g} kg m at node {args.node}"
    else:
        X, Y = unbalance_response_many(rotor, triples, speeds, probe_nodes=[args.probe])
        triples_used = triples
        what = ", ".join(f"{m:g} kg m at node {n} ({p:g} rad)" for n, m, p in triples)
    X, Y = np.asarray(X[:, 0]), np.asarray(Y[:, 0])
    amp = np.sqrt(np.abs(X) ** 2 + np.abs(Y) ** 2)
    if not np.all(np.isfinite(amp)):
        raise NumericalError("response: non-finite amplitudes (an undamped rotor exactly at a critical speed?)")
    peaks = local_maxima(speeds, amp)
    stem = out_stem(args.out, preset, "response_")
    plot_response(speeds, X, Y, stem + ".png", title=f"{preset.name}: unbalance response at node {args.probe} "
                  f"({what})")
    out = {"preset": preset.name, "node": args.node, "probe": args.probe,
           "unbalance": single if triples is None else None,
           "unbalances": [{"node": n, "magnitude": m, "phase": p} for n, m, p in triples_used],
           "unit": "rad/s, m", "peaks": peaks, "max_amplitude": float(amp.max()),
           "speed_at_max": float(speeds[np.argmax(amp)]), "files": {"plot": stem + ".png"}}
    if args.shape_at is not None:
        shape = deflected_shape(rotor, triples_used, args.shape_at)
        major = np.asarray(shape.major)
        if not np.all(np.isfinite(major)):
            raise NumericalError(f"response: non-finite deflected shape at --shape-at {args.shape_at:g}")
        plot_deflected_shape(np.asarray(shape.positions), np.asarray(shape.x), np.asarray(shape.y), major,
                             stem + "_shape.png", title=f"{preset.name}: deflected shape at {args.shape_at:g} "
                             f"rad/s ({what})")
        out["deflected_shape"] = {"speed": args.shape_at, "positions": np.asarray(shape.positions).tolist(),
                                  "major": major.tolist(), "minor": np.asarray(shape.minor).tolist(),
                                  "angle": np.asarray(shape.angle).tolist(),
                                  "x_abs": np.abs(np.asarray(shape.x)).tolist(),
                                  "y_abs": np.abs(np.asarray(shape.y)).tolist()}
        out["files"]["shape"] = stem + "_shape.png"
    if args.json:
        print(json.dumps(out, indent=2))
    else:
        print("peaks at " + (", ".join(f"{p:.2f}" for p in peaks) or "none inside the range")
              + f" rad/s; wrote {stem}.png")
    return 0
