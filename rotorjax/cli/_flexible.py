"""`campbell`, `response`: linear analyses of a finite-element rotor (the
`ross-compare` preset, rotor files)."""

import json

import numpy as np

from ._common import (InputError, NumericalError, build, check_range, out_stem, prepare_out, preset_and_params,
                      speed_warnings, write_json)

#: kinds of preset with a finite-element rotor


def _rotor(preset, params, n_modes, scene=False):
    """The preset's FE rotor, reduced to its `n_modes` lowest undamped modes (`--reduce`);
    with `scene`, its `RotorScene` (on the reduced rotor), whose linear part counts
    the components' linearisations (a rotor file's cubic bearings, internal damping)."""
    from rotorjax.models import RotorScene
    from ._common import fe_rotor

    sc = build(preset, params).scene
    rotor = fe_rotor(sc)
    if n_modes is not None:
        n = rotor.n_coordinates
        if not 1 <= n_modes <= n:
            raise InputError(f"--reduce {n_modes}: n_modes (reduction) must be in 1..{n} (the rotor's dofs)")
        rotor = rotor.reduce(n_modes)
    if not scene:
        return rotor
    return sc if n_modes is None else RotorScene(rotor, sc.speed, sc.components)


def _campbell_at(speeds, rotor, n_modes):
    """`campbell` with the speeds first (a batched function for `map_chunked`)."""
    from rotorjax.analysis import campbell

    return campbell(rotor, speeds, n_modes)


def cmd_campbell(args) -> int:
    import jax

    from rotorjax.analysis import check_supported, critical_speeds_1x, track_modes, track_order
    from rotorjax.plot import plot_campbell_tracked
    from rotorjax.sweep import check_grid_size, map_chunked

    from ._common import save_figure
    from ._output_units import units_for

    preset, params = preset_and_params(args, "campbell")
    units = units_for(args, preset)
    lo, hi = check_range("--range", *args.range)
    prepare_out(args.out)
    rotor = _rotor(preset, params, args.reduce, scene=True)
    check_grid_size("--n-speeds", args.n_speeds, 800.0 * (args.modes + 4))  # tracked and plain, in the JSON
    check_supported(rotor, hi, what=preset.name)
    speed_warnings(rotor, lo, hi)
    dofs = rotor.n_coordinates
    n = 2 * dofs
    if args.modes > n:
        raise InputError(f"--modes {args.modes}: the rotor has {n} modes" + (" after --reduce" if args.reduce else ""))
    speeds = np.linspace(lo, hi, args.n_speeds)
    # a few modes above those shown, so that branches entering from above are tracked
    # too; the modes shown are the lowest of those (one compiled program, in chunks)
    wide = map_chunked(_campbell_at, speeds, rotor, min(args.modes + 4, dofs))
    k = min(args.modes, dofs)
    camp = jax.tree_util.tree_map(lambda a: a[..., :k], wide)
    tracked = track_modes(wide)
    _, mac_step = track_order(wide)
    t_freq = np.asarray(tracked.frequencies)[:, :k]
    t_whirl = np.asarray(tracked.whirl)[:, :k]
    t_logdec = np.asarray(tracked.log_dec)[:, :k]
    # the crossings of the diagram's own branches (its speeds are the scan), bisected
    crit = critical_speeds_1x(rotor, lo, hi, n_modes=k, scan=(speeds, camp))
    stem = out_stem(args.out, preset, "campbell_")
    save_figure(plot_campbell_tracked(units.value(speeds, "speed"), units.value(t_freq, "frequency"), t_whirl,
                                      t_logdec, critical=units.value([s for s, _ in crit], "speed"),
                                      title=f"{preset.name}: Campbell diagram (tracked modes)"
                                      + (f" (reduced to {args.reduce} modes)" if args.reduce else ""),
                                      unit=units.label("speed"), frequency_unit=units.label("frequency")),
                stem + ".png")
    out = {"preset": preset.name, "unit": units.label("speed"), "speeds": speeds.tolist(),
           "frequencies": np.asarray(camp.frequencies).tolist(),
           "forward": np.asarray(camp.forward).tolist(),
           "log_dec": np.asarray(camp.log_dec).tolist(),
           "tracked": {"frequencies": t_freq.tolist(), "whirl": t_whirl.tolist(), "log_dec": t_logdec.tolist(),
                       "min_mac": mac_step[:, :k].min(axis=0).tolist()},
           "critical_speeds": [s for s, _ in crit], "files": {"plot": stem + ".png"}}
    if not np.all(np.isfinite(out["frequencies"])):
        raise NumericalError("campbell: non-finite natural frequencies")
    units.convert(out, {"speeds": "speed", "critical_speeds": "speed", "frequencies": "frequency",
                        "tracked.frequencies": "frequency"})
    write_json(stem + ".json", out)
    if args.json:
        print(json.dumps(out))
    else:
        print(f"wrote {stem}.png and .json; critical speeds ({units.label('speed')}): "
              + (", ".join(f"{s:.3f}" for s in out["critical_speeds"])
                 or f"none in [{units.value(lo, 'speed'):g}, {units.value(hi, 'speed'):g}]"))
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


def rotor_unbalances(scene):
    """The `(node, magnitude, phase)` of the scene's `Unbalance` components (a rotor
    file's `[[unbalance]]` tables, a preset's load case), in order."""
    from rotorjax.models import Unbalance

    return [(int(c.node), float(c.magnitude), float(c.phase)) for c in scene.components
            if isinstance(c, Unbalance)]


def default_node(scene):
    """Where a bare `--unbalance MAG` goes without `--node`: the rotor's first
    unbalance's node, else its heaviest disk's node, else the middle of its bearing span."""
    from rotorjax.analysis import full_rotor, mid_span_node

    given = rotor_unbalances(scene)
    if given:
        return given[0][0], "the rotor's unbalance"
    full = full_rotor(scene).full_rotor
    if len(full.disk_nodes):
        masses = np.asarray(full.disk_params)[:, 0]
        return int(full.disk_nodes[int(np.argmax(masses))]), "the heaviest disk"
    return mid_span_node(scene), "mid-span"


def _unbalances(args, scene, n_nodes, name):
    """`(triples, source)`: the unbalances the response uses and where they came from:
    `--unbalance NODE,MAG,PHASE` triples; a bare `--unbalance MAG` at `--node` (default:
    `default_node`) and `--phase`; `--node`/`--phase` alone move the rotor's single
    unbalance; otherwise the rotor's own (a rotor file's `[[unbalance]]`)."""
    given = args.unbalance or []
    triples = [u for u in given if isinstance(u, tuple)]
    own = rotor_unbalances(scene)
    if triples and len(triples) != len(given):
        raise InputError("--unbalance: give one magnitude (at --node, --phase) or NODE,MAG,PHASE triples, not both")
    if triples:
        if args.node is not None or args.phase is not None:
            raise InputError("--node and --phase apply to a bare --unbalance MAG, not to NODE,MAG,PHASE triples")
        for node, mag, phase in triples:
            if not node < n_nodes:
                raise InputError(f"--unbalance {node},{mag:g},{phase:g}: the rotor has nodes 0..{n_nodes - 1}")
        return triples, "--unbalance"
    if len(given) > 1:
        raise InputError("--unbalance: a bare magnitude may be given once; use NODE,MAG,PHASE for several")
    if args.node is not None and not 0 <= args.node < n_nodes:
        raise InputError(f"--node {args.node}: the rotor has nodes 0..{n_nodes - 1}")
    phase = 0.0 if args.phase is None else args.phase
    if given:
        node, where = (args.node, "--node") if args.node is not None else default_node(scene)
        return [(node, given[0], phase)], f"--unbalance at {where}"
    if not own:
        raise InputError(f"{name} has no unbalance (a rotor file's [[unbalance]] table); give --unbalance "
                         "NODE,MAG,PHASE (kg m, rad), or --unbalance MAG with --node")
    if args.node is None and args.phase is None:
        return own, "the rotor file" if name.endswith(".toml") else f"the {name} preset"
    if len(own) > 1:
        raise InputError(f"--node/--phase: {name} has {len(own)} unbalances; give them with --unbalance "
                         "NODE,MAG,PHASE")
    node = own[0][0] if args.node is None else args.node
    phase = own[0][2] if args.phase is None else args.phase
    return [(node, own[0][1], phase)], "the rotor's unbalance, moved by --node/--phase"


#: the kinds of `response`'s JSON numbers (`--units`): the response at the probe an
#: amplitude (peak-to-peak where the system's convention is), the deflected shape's
#: semi-axes and displacements deflections
RESPONSE_UNITS = {"range": "speed", "peaks": "speed", "speed_at_max": "speed", "peak_amplitudes": "amplitude",
                  "max_amplitude": "amplitude", "deflected_shape.speed": "speed", "curve.speeds": "speed",
                  **{f"curve.{k}": "amplitude" for k in ("amplitude", "x_abs", "y_abs")},
                  **{f"deflected_shape.{k}": "deflection" for k in ("major", "minor", "x_abs", "y_abs")}}


def cmd_response(args) -> int:
    from rotorjax.analysis import check_supported, deflected_shape, response_curve
    from rotorjax.plot import plot_deflected_shape, plot_response
    from rotorjax.sweep import check_grid_size

    from ._common import save_figure
    from ._output_units import units_for

    preset, params = preset_and_params(args, "response")
    units = units_for(args, preset)
    lo, hi = check_range("--range", *args.range, positive_lo=True)
    prepare_out(args.out)
    scene = _rotor(preset, params, args.reduce, scene=True)
    n_nodes = scene.n_nodes
    check_grid_size("--n", args.n, 64.0 * n_nodes + 400.0)   # the response at every node, the plot
    if args.probe is not None and not 0 <= args.probe < n_nodes:
        raise InputError(f"--probe {args.probe}: the rotor has nodes 0..{n_nodes - 1}")
    triples, source = _unbalances(args, scene, n_nodes, preset.name)
    check_supported(scene, hi, what=preset.name)
    speed_warnings(scene, lo, hi)
    curve = response_curve(scene, triples, np.linspace(lo, hi, args.n), args.probe)
    if not np.all(np.isfinite(curve.amplitude)):
        raise NumericalError("response: non-finite amplitudes (an undamped rotor exactly at a critical speed?)")
    what = ", ".join(f"{m:g} kg m at node {n} ({p:g} rad)" for n, m, p in triples)
    probe_source = "--probe" if not curve.probe_chosen else "largest response"
    stem = out_stem(args.out, preset, "response_")
    save_figure(plot_response(units.value(curve.speeds, "speed"), units.value(curve.x, "amplitude"),
                              units.value(curve.y, "amplitude"), title=f"{preset.name}: unbalance response at "
                              f"node {curve.probe} ({what})", speed_unit=units.label("speed"),
                              amplitude_unit=units.label("amplitude")), stem + ".png")
    single = len(given := (args.unbalance or [])) == 1 and not isinstance(given[0], tuple)
    out = {"preset": preset.name, "node": triples[0][0], "probe": curve.probe, "probe_source": probe_source,
           "unbalance": triples[0][1] if single else None,
           "unbalances": [{"node": n, "magnitude": m, "phase": p} for n, m, p in triples],
           "unbalance_source": source, "range": [lo, hi], "n": args.n,
           "unit": f"{units.label('speed')}, {units.label('amplitude')}", "peaks": [p.x for p in curve.peaks],
           "peak_amplitudes": [p.y for p in curve.peaks],
           "max_amplitude": curve.max_amplitude, "speed_at_max": curve.speed_at_max,
           "curve": {"speeds": np.asarray(curve.speeds).tolist(), "amplitude": np.asarray(curve.amplitude).tolist(),
                     "x_abs": np.abs(curve.x).tolist(), "y_abs": np.abs(curve.y).tolist()},
           "files": {"plot": stem + ".png", "json": stem + ".json"}}
    if args.shape_at is not None:
        shape = deflected_shape(scene, triples, args.shape_at)
        major = np.asarray(shape.major)
        if not np.all(np.isfinite(major)):
            raise NumericalError(f"response: non-finite deflected shape at --shape-at {args.shape_at:g}")
        save_figure(plot_deflected_shape(np.asarray(shape.positions), units.value(np.asarray(shape.x), "deflection"),
                                         units.value(np.asarray(shape.y), "deflection"),
                                         units.value(major, "deflection"),
                                         title=f"{preset.name}: deflected shape at "
                                         f"{units.value(args.shape_at, 'speed'):g} {units.label('speed')} ({what})",
                                         unit=units.label("deflection")), stem + "_shape.png")
        out["deflected_shape"] = {"speed": args.shape_at, "positions": np.asarray(shape.positions).tolist(),
                                  "major": major.tolist(), "minor": np.asarray(shape.minor).tolist(),
                                  "angle": np.asarray(shape.angle).tolist(),
                                  "x_abs": np.abs(np.asarray(shape.x)).tolist(),
                                  "y_abs": np.abs(np.asarray(shape.y)).tolist()}
        out["files"]["shape"] = stem + "_shape.png"
    units.convert(out, RESPONSE_UNITS)
    write_json(stem + ".json", out)
    if args.json:
        print(json.dumps(out, indent=2))
    else:
        s, a = units.label("speed"), units.label("amplitude")
        print(f"{preset.name}: unbalance {what} (from {source}); response at node {curve.probe} ({probe_source})")
        print("  peaks at " + (", ".join(f"{x:.3f} {s} ({y:.4g} {a})"
                                         for x, y in zip(out["peaks"], out["peak_amplitudes"]))
                               or "none inside the range")
              + f"; largest {out['max_amplitude']:.4g} {a} at {out['speed_at_max']:.3f} {s}")
        print(f"wrote {stem}.png and .json")
    return 0
