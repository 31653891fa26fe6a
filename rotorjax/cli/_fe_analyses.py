"""Analyses of a finite-element rotor (the `ross-compare` preset, rotor files):
`static` (deflection, reactions, shear and moment under gravity), `modes` (damped
modes at a speed, with shape plots)."""

import json

import numpy as np

from ._output_units import units_for
from ._common import (InputError, NumericalError, build, is_rotor_file, operating_speed, out_stem, prepare_out,
                      preset_and_params, speed_warnings, write_json)

#: kinds of preset with a finite-element rotor


def _scene(preset, params):
    """The preset's finite-element rotor scene (its linear part counts: components'
    linearisations included)."""
    from ._common import fe_rotor

    scene = build(preset, params).scene
    fe_rotor(scene)   # the kind check: a RotorScene
    return scene


def cmd_static(args) -> int:
    from rotorjax.analysis import static
    from rotorjax.models import has_films
    from rotorjax.plot import plot_static
    from ._common import save_figure

    preset, params = preset_and_params(args, "static")
    units = units_for(args, preset)
    prepare_out(args.out)
    scene = _scene(preset, params)
    if has_films(scene):
        return _static_in_films(args, preset, params, scene)
    res = static(scene, gravity=args.gravity, axis=args.axis)
    p = ("x", "y").index(args.axis)
    disp, shear, moment = (np.asarray(a) for a in (res.displacement, res.shear, res.moment))
    reactions = np.asarray(res.bearing_reactions)
    if not (np.all(np.isfinite(disp)) and np.all(np.isfinite(reactions))):
        raise NumericalError("static: non-finite displacements")
    full = scene.full_rotor   # a reduced rotor's full one
    stem = out_stem(args.out, preset, "static_")
    save_figure(plot_static(res, title=f"{preset.name}: static deflection under gravity ({args.axis})",
                            unit=units.label("deflection"), factor=units.factor("deflection")), stem + ".png")
    k_max = int(np.argmax(np.abs(disp[:, p])))
    out = {"preset": preset.name, "unit": f"{units.label('deflection')}, N, N m", "gravity": args.gravity,
           "axis": args.axis,
           "positions": np.asarray(res.positions).tolist(), "displacement": disp.tolist(),
           "rotation": np.asarray(res.rotation).tolist(),
           "bearing_reactions": [{"bearing": i, "node": int(n), "x": float(r[0]), "y": float(r[1])}
                                 for i, (n, r) in enumerate(zip(full.bearing_nodes, reactions))],
           "disk_forces": [{"disk": i, "node": int(n), "x": float(f[0]), "y": float(f[1])}
                           for i, (n, f) in enumerate(zip(full.disk_nodes, np.asarray(res.disk_forces)))],
           "weight": np.asarray(res.weight).tolist(),
           "element_ends": np.asarray(res.element_ends).tolist(),
           "shear": shear[:, :, p].tolist(), "moment": moment[:, :, p].tolist(),
           "shear_both_planes": shear.tolist(), "moment_both_planes": moment.tolist(),
           "max_deflection": {"node": k_max, "value": float(disp[k_max, p])},
           "max_moment": float(np.max(np.abs(moment[:, :, p]))),
           "residual": float(res.residual), "files": {"plot": stem + ".png"}}
    units.convert(out, {"displacement": "deflection", "max_deflection.value": "deflection"})
    write_json(stem + ".json", out)
    if args.json:
        print(json.dumps(out))
    else:
        print(f"{preset.name}: static deflection under g = {args.gravity:g} m/s^2 along -{args.axis}")
        print(f"  weight: {abs(out['weight'][p]):.6g} N; largest deflection {out['max_deflection']['value']:.6g} "
              f"{units.label('deflection')} at node {k_max}; largest bending moment {out['max_moment']:.6g} N m")
        for row in out["bearing_reactions"]:
            print(f"  bearing {row['bearing']} (node {row['node']}): reaction {row[args.axis]:.6g} N")
        print(f"wrote {stem}.png and .json")
    return 0


def _static_in_films(args, preset, params, scene) -> int:
    """`static` of a rotor on fluid films: the equilibrium at the running speed under
    the file's own loads ([gravity]), per bearing."""
    from rotorjax.analysis import bearing_equilibrium

    for option, given in (("--gravity", args.gravity != 9.80665), ("--axis", args.axis != "y")):
        if given:
            raise InputError(f"{option}: a rotor on fluid-film bearings is loaded by its file's [gravity] table "
                             f"(and its own weight); set gravity.g / gravity.angle with --set instead")
    speed, speed_source = _speed(args, preset, params)
    res = bearing_equilibrium(scene, speed)
    stem = out_stem(args.out, preset, "static_")
    rows = [dict(f.as_dict(), attitude_deg=float(np.degrees(f.attitude))) for f in res.films]
    out = {"preset": preset.name, "speed": speed, "speed_source": speed_source, "unit": "m, N, rad",
           "load": "the file's [gravity] and the rotor's weight", "bearings": rows,
           "displacement": res.displacement.tolist(), "residual": res.residual, "iterations": res.iterations,
           "files": {"json": stem + ".json"}}
    write_json(stem + ".json", out)
    if args.json:
        print(json.dumps(out))
        return 0
    print(f"{preset.name}: static equilibrium in the fluid-film bearings at {speed:g} rad/s ({speed_source})")
    for r in rows:
        print(f"  {r['kind']} at node {r['node']}: eccentricity {r['eccentricity']:.4f}, attitude "
              f"{r['attitude_deg']:.2f} deg, minimum film {r['min_film'] * 1e6:.3f} um, load {r['load']:.6g} N")
    print(f"  Newton: {res.iterations} steps, relative residual {res.residual:.1e}")
    print(f"wrote {stem}.json")
    return 0


def cmd_modes(args) -> int:
    from rotorjax.analysis import check_supported, modes
    from rotorjax.plot import plot_mode_shapes, plot_mode_shapes_3d
    from ._common import save_figure

    preset, params = preset_and_params(args, "modes")
    units = units_for(args, preset)
    prepare_out(args.out)
    scene = _scene(preset, params)
    n = 2 * int(scene.n_shaft)
    if args.n_modes > n // 2:
        raise InputError(f"--n-modes {args.n_modes}: the rotor has {n // 2} modes (upper half-plane eigenvalues)")
    speed, speed_source = _speed(args, preset, params)
    check_supported(scene, speed, what=preset.name)
    speed_warnings(scene, speed)
    m = modes(scene, speed, args.n_modes)
    wd, wn, zeta, logdec = (np.asarray(a) for a in (m.frequencies, m.natural_frequencies, m.damping_ratio,
                                                     m.log_dec))
    if not (np.all(np.isfinite(wd)) and np.all(np.isfinite(wn))):
        raise NumericalError("modes: non-finite natural frequencies (fewer oscillating modes than --n-modes?)")
    whirl = [str(w) for w in m.whirl]
    full = scene.full_rotor
    stem = out_stem(args.out, preset, "modes_")
    title = f"{preset.name} at {units.value(speed, 'speed'):g} {units.label('speed')}"
    save_figure(plot_mode_shapes(m, full, title=title), stem + "_shapes.png")
    save_figure(plot_mode_shapes_3d(m, full, title=title), stem + "_3d.png")
    rows = [{"mode": k, "damped_frequency": float(wd[k]), "damped_frequency_hz": float(wd[k] / (2 * np.pi)),
             "natural_frequency": float(wn[k]), "damping_ratio": float(zeta[k]), "log_dec": float(logdec[k]),
             "whirl": whirl[k]} for k in range(len(wd))]
    out = {"preset": preset.name, "speed": speed, "speed_source": speed_source, "unit": units.label("frequency"),
           "modes": rows, "files": {"shapes": stem + "_shapes.png", "shapes_3d": stem + "_3d.png"}}
    units.convert(out, {"speed": "speed", "modes.*.damped_frequency": "frequency",
                        "modes.*.natural_frequency": "frequency"})
    write_json(stem + ".json", out)
    if args.json:
        print(json.dumps(out))
    else:
        f = units.label("frequency")
        print(f"{preset.name}: damped modes at {out['speed']:g} {units.label('speed')} ({speed_source})")
        print(f"{'mode':>4}  {f'wd ({f})':>12}  {'wd (Hz)':>10}  {f'wn ({f})':>12}  {'damping':>10}  "
              f"{'log dec':>10}  whirl")
        for r in rows:
            print(f"{r['mode']:>4}  {r['damped_frequency']:>12.4f}  {r['damped_frequency_hz']:>10.4f}  "
                  f"{r['natural_frequency']:>12.4f}  {r['damping_ratio']:>10.4g}  {r['log_dec']:>10.4g}  "
                  f"{r['whirl']}")
        print(f"wrote {stem}_shapes.png, {stem}_3d.png and .json")
    return 0


def _speed(args, preset, params, option="--speed"):
    """`(speed, source)`: `--speed`, else the rotor's operating speed (a rotor file's
    `[rotor] speed`, 0 for a preset without one)."""
    if args.speed is not None:
        return float(args.speed), option
    speed = operating_speed(preset, params)
    return speed, ("[rotor] speed of the file" if is_rotor_file(preset) else f"{preset.name}'s speed")


# ---- ucs, frf, level1 (the UCS map, frequency-response functions, API 684 level I) ----

def _fe_rotor(preset, params):
    """The preset's `FlexibleRotor` (or reduced rotor)."""
    from ._common import fe_rotor

    return fe_rotor(build(preset, params).scene)


def _node_option(option, text, node, n_nodes):
    if not 0 <= node < n_nodes:
        raise InputError(f"{option} {text}: the rotor has nodes 0..{n_nodes - 1}")
    return node


def point_spec(text):
    """`NODE,DIR` (`2,x`): a node index and a direction x or y (argparse type)."""
    import argparse

    parts = [p.strip() for p in text.split(",")]
    if len(parts) != 2:
        raise argparse.ArgumentTypeError(f"expected NODE,DIR (e.g. 2,x), got {text!r}")
    try:
        node = int(parts[0])
    except ValueError:
        raise argparse.ArgumentTypeError(f"expected NODE,DIR with an integer NODE (e.g. 2,x), got {text!r}") \
            from None
    if node < 0:
        raise argparse.ArgumentTypeError(f"NODE must be >= 0, got {text!r}")
    if parts[1] not in ("x", "y"):
        raise argparse.ArgumentTypeError(f"DIR must be x or y, got {text!r}")
    return node, parts[1]


def cmd_ucs(args) -> int:
    import math

    from rotorjax.analysis import ucs
    from rotorjax.plot import plot_ucs
    from rotorjax.sweep import check_grid_size

    from ._common import save_figure

    preset, params = preset_and_params(args, "ucs")
    units = units_for(args, preset)
    lo, hi = args.range
    text = f"--range {lo:g} {hi:g}"
    if not lo > 0:
        raise InputError(f"{text}: KLO must be > 0 (the stiffness axis is logarithmic, N/m)")
    if not lo < hi:
        raise InputError(f"{text}: need KLO < KHI")
    if not math.isfinite(math.log10(hi)):
        raise InputError(f"{text}: KHI is too large")
    check_grid_size("--n", args.n, 120.0 * (args.n_modes + 1))   # the map in the JSON and the plot
    prepare_out(args.out)
    rotor = _fe_rotor(preset, params)
    rotor = rotor.full_rotor   # a reduced rotor's full one (the basis depends on the bearings)
    n_forward = len([d for d in rotor.free_dofs if d < 4 * rotor.n_nodes]) // 2
    if args.n_modes > n_forward:
        raise InputError(f"--n-modes {args.n_modes}: the rotor has {n_forward} forward modes")
    if not rotor.bearing_nodes:
        raise InputError(f"ucs: {preset.name} has no bearings to replace by springs")
    res = ucs(rotor, (lo, hi), args.n, args.n_modes, synchronous=args.synchronous)
    k, f = np.asarray(res.stiffness), np.asarray(res.frequencies)
    if not np.any(np.isfinite(f)):
        raise NumericalError("ucs: no finite critical speed in the map")
    stem = out_stem(args.out, preset, "ucs_")
    inter = [{"speed": i.speed, "k": i.k, "mode": i.mode, "bearing": i.bearing, "coefficient": i.coefficient,
              "residual": i.residual} for i in res.intersections]
    save_figure(plot_ucs(k, units.value(f, "speed"), None, units.value(np.asarray(res.bearing_speeds), "speed"),
                         np.asarray(res.bearing_k), [(i["k"], units.value(i["speed"], "speed")) for i in inter],
                         title=f"{preset.name}: undamped critical speed map", synchronous=args.synchronous,
                         unit=units.label("speed")), stem + ".png")
    out = {"preset": preset.name, "unit": f"{units.label('speed')}, N/m", "synchronous": args.synchronous,
           "stiffness": k.tolist(), "critical_speeds": [[v if math.isfinite(v) else None for v in row]
                                                         for row in f.tolist()],
           "bearing_speeds": np.asarray(res.bearing_speeds).tolist(),
           "bearing_kxx": np.asarray(res.bearing_k)[:, 0].tolist(),
           "bearing_kyy": np.asarray(res.bearing_k)[:, 1].tolist(),
           "intersections": inter, "files": {"plot": stem + ".png"}}
    units.convert(out, {"critical_speeds": "speed", "bearing_speeds": "speed", "intersections.*.speed": "speed"})
    write_json(stem + ".json", out)
    if args.json:
        print(json.dumps(out))
    else:
        print(f"{preset.name}: undamped critical speed map, k = {lo:g} .. {hi:g} N/m, {args.n_modes} modes "
              + ("(forward synchronous)" if args.synchronous else "(at rest)"))
        for i in out["intersections"]:
            print(f"  mode {i['mode']} meets bearing {i['bearing']} {i['coefficient']} at {i['speed']:.4f} "
                  f"{units.label('speed')} (k = {i['k']:.6g} N/m)")
        if not inter:
            print("  no intersection with the bearings' stiffness in the searched speed range")
        print(f"wrote {stem}.png and .json")
    return 0


def cmd_frf(args) -> int:
    from rotorjax.analysis import check_supported, frf_curve
    from rotorjax.plot import plot_frf
    from rotorjax.sweep import check_grid_size

    from ._common import check_range, save_figure

    preset, params = preset_and_params(args, "frf")
    units = units_for(args, preset)
    lo, hi = check_range("--range", *args.range)
    prepare_out(args.out)
    scene = _scene(preset, params)
    for option, (node, d) in (("--input", args.input), ("--output", args.output)):
        _node_option(option, f"{node},{d}", node, scene.n_nodes)
    check_grid_size("--n", args.n, 200.0)   # the curve in the JSON (five numbers a point) and the plots
    check_supported(scene, hi if args.speed is None else args.speed, what=preset.name)
    speed_warnings(scene, lo if args.speed is None else args.speed, hi if args.speed is None else None)
    try:
        res = frf_curve(scene, args.input, args.output, np.linspace(lo, hi, args.n), args.kind, speed=args.speed)
    except InputError as e:  # a fixed dof
        name = str(e).split(":")[0]
        raise InputError(f"--{name} {','.join(map(str, getattr(args, name)))}: {str(e).split(': ', 1)[-1]}") \
            from None
    w, h = res.frequencies, np.asarray(res.values)
    if not np.all(np.isfinite(h)):
        raise NumericalError("frf: non-finite response (an undamped rotor exactly at a natural frequency?)")
    unit = {"displacement": "m/N", "velocity": "m/s/N", "acceleration": "m/s^2/N"}[args.kind]
    stem = out_stem(args.out, preset, "frf_")
    running = ("synchronous (speed = frequency)" if args.speed is None
               else f"at {units.value(args.speed, 'speed'):g} {units.label('speed')}")
    title = (f"{preset.name}: {args.kind} at {args.output[0]}{args.output[1]} / force at "
             f"{args.input[0]}{args.input[1]}, {running}")
    bode, polar = plot_frf(units.value(w, "frequency"), h, title=title, unit=unit,
                           frequency_unit=units.label("frequency"))
    save_figure(bode, stem + "_bode.png")
    save_figure(polar, stem + "_polar.png")
    mag = np.abs(h)
    out = {"preset": preset.name, "input": list(args.input), "output": list(args.output), "kind": args.kind,
           "unit": f"{units.label('frequency')}, {unit}", "speed": args.speed, "frequencies": w.tolist(),
           "magnitude": mag.tolist(),
           "phase": np.angle(h).tolist(), "real": h.real.tolist(), "imag": h.imag.tolist(),
           "peaks": [p.x for p in res.peaks], "peak_magnitudes": [p.y for p in res.peaks],
           "files": {"bode": stem + "_bode.png", "polar": stem + "_polar.png"}}
    units.convert(out, {"speed": "speed", "frequencies": "frequency", "peaks": "frequency"})
    write_json(stem + ".json", out)
    if args.json:
        print(json.dumps(out))
    else:
        print(f"{title}: peaks at " + (", ".join(f"{x:.3f} {units.label('frequency')} ({y:.4g} {unit})"
                                                 for x, y in zip(out["peaks"], out["peak_magnitudes"]))
                                       or "none inside the range"))
        print(f"wrote {stem}_bode.png, {stem}_polar.png and .json")
    return 0


def cmd_level1(args) -> int:
    import math

    from rotorjax.analysis import check_supported, level1, mid_span_node
    from rotorjax.plot import plot_level1
    from ._common import save_figure

    preset, params = preset_and_params(args, "level1")
    units = units_for(args, preset)
    prepare_out(args.out)
    scene = _scene(preset, params)
    rotor = scene.rotor
    speed, speed_source = _speed(args, preset, params)
    if not speed > 0:
        raise InputError(f"level1: give --speed (the maximum continuous speed, rad/s): {preset.name} has no "
                         "operating speed ([rotor] speed)")
    args.speed = speed   # what the rest of the command reports
    check_supported(scene, speed, what=preset.name)
    speed_warnings(scene, speed)
    if args.node is not None:
        _node_option("--node", str(args.node), args.node, rotor.n_nodes)
    node = mid_span_node(scene) if args.node is None else args.node
    if args.q_max is None and not rotor.full_rotor.bearing_nodes:
        raise InputError(f"level1: {preset.name} has no bearings; give --q-max")
    res = level1(scene, args.speed, node=node, q_max=args.q_max, n=args.n)
    q, ld = np.asarray(res.q), np.asarray(res.log_dec)
    if not np.all(np.isfinite(ld)):
        raise NumericalError("level1: non-finite log decrements (no forward mode found?)")
    q0 = float(res.q0) if res.crossed else None
    stem = out_stem(args.out, preset, "level1_")
    shown = f"{units.value(args.speed, 'speed'):g} {units.label('speed')}"
    save_figure(plot_level1(q, ld, q0=q0, title=f"{preset.name}: API 684 level I at {shown}, Q at node {node}"),
                stem + ".png")
    out = {"preset": preset.name, "speed": args.speed, "speed_source": speed_source, "node": node,
           "unit": f"N/m, {units.label('speed')}",
           "q0": q0, "check_at_q0": {"real_part": None if q0 is None else float(res.real_part_at_q0),
                                     "max_real_part": None if q0 is None else float(res.max_real_part_at_q0)},
           "log_dec_0": float(res.log_dec_0), "q": q.tolist(), "log_dec": ld.tolist(),
           "files": {"plot": stem + ".png"}}
    units.convert(out, {"speed": "speed"})
    write_json(stem + ".json", out)
    if args.json:
        print(json.dumps(out))
    else:
        print(f"{preset.name}: level I at {shown}, Q at node {node}: log dec at Q = 0 "
              f"{float(res.log_dec_0):.4g}" + ("" if q0 is None else f"; threshold Q0 = {q0:.6g} N/m "
                                                f"(max Re lambda there {float(res.max_real_part_at_q0):.2g} 1/s)"))
        print(f"wrote {stem}.png and .json")
    if q0 is None:
        why = (f"the log decrement at Q = 0 is {float(res.log_dec_0):.3g}, not positive (an undamped or "
               "unstable rotor)" if float(res.log_dec_0) < 1e-9 else
               f"the log decrement stays positive up to --q-max {float(q[-1]):g} N/m (raise --q-max)")
        raise NumericalError(f"level1: no threshold Q0 found: {why}; q0 is null in {stem}.json")
    if not math.isfinite(q0):
        raise NumericalError("level1: non-finite threshold")
    return 0
