"""`periodic`: the branch of periodic forced motions in one parameter (harmonic
balance continued through folds), its stability and bifurcations."""

import dataclasses
import json
import os

import numpy as np

from ._common import (InputError, NumericalError, build, get_preset, out_stem, param_span, prepare_out, preset_params,
                      write_json)
from ._continue import _check_key

#: `--method` as the library names it
METHODS = {"hb": "harmonic-balance", "shooting": "shooting"}

#: what each bifurcation means for the motion, as the summary says it
MEANING = {
    "fold": "two periodic motions meet and end (a jump)",
    "period-doubling": "a multiplier leaves through -1: a motion of twice the period is born",
    "neimark-sacker": "a pair of multipliers leaves the unit circle: the motion turns quasi-periodic, with a "
                      "second frequency",
    "branch-point": "another branch of periodic motions crosses this one",
    "hopf": "a pair of exponents crosses the imaginary axis",
}

#: what to change, per way a branch can stop inside the range (`Curve.results`: an end that is not `successful`,
#: on the range's edge or round a closed loop, leaves part of the range untraced: exit 3), by the outcome's name
REMEDY = {"max_points_reached": "raise --max-points (or --ds-max, for longer steps)",
          "solver_failure": "lower --ds-max, or raise --harmonics (--max-harmonics with auto)",
          "nonfinite": "lower --ds-max, or narrow --range",
          "root_not_converged": "raise --max-harmonics, or narrow --range"}


def _scene_at(preset, params, key, setup, option="--param"):
    """`p -> scene` with `key` at `p`, traceable in `p`: the speed leaf replaced
    where `key` is the speed; a rotor file's entry where the scene depends on it
    affinely (`presets.affine_scene`); else the preset rebuilt (refused where that
    does not trace)."""
    import equinox as eqx
    import jax

    from rotorjax.models import ConstantSpeed
    from rotorjax.presets import affine_scene

    scene = setup.scene
    if not isinstance(scene.speed, ConstantSpeed):
        raise InputError(f"`periodic` needs a constant speed: {preset.name}'s scene runs at a "
                         f"{type(scene.speed).__name__}")
    if key == preset.speed_key and float(scene.speed.constant) == float(params[key]):
        return lambda p: eqx.tree_at(lambda s: s.speed.constant, scene, p)
    if preset.kind == "rotor":
        try:
            return affine_scene(lambda p: preset.build(dict(params, **{key: p})).scene, params[key], key)
        except ValueError as e:
            raise InputError(f"{option} {key}: {e}") from None

    def at(p):
        return preset.build(dict(params, **{key: p})).scene

    try:
        jax.eval_shape(lambda p: at(p).vector_field(0.0, setup.y0, None), float(params[key]))
    except Exception:  # noqa: BLE001 - any failure to trace means the build is not a function of a traced value
        raise InputError(f"{option} {key}: {preset.name}'s scene cannot be built as a function of {key} "
                         f"(it does not trace); continue in {preset.speed_key}") from None
    return at


def _periodic_scene(scene_at, scene, y0):
    """`scene_at` and the guess without a work state (it grows along a periodic
    motion), where the scene keeps one."""
    from rotorjax.models import provides

    if not provides(scene, "without_work"):
        return scene_at, y0
    n = scene.without_work().state_size
    return (lambda p: scene_at(p).without_work()), y0[:n]


def _amplitude_of(scene, y0, node):
    """The phrase for what the amplitude is, after checking that the scene has it."""
    out = scene.outputs(0.0, y0)
    if node is None:
        if "whirl_amplitude" in out:
            return "largest whirl_amplitude over the period"
        if "node_x" in out:
            raise InputError("the scene has no output whirl_amplitude: give --node N (a shaft node, 0.."
                             f"{np.shape(out['node_x'])[0] - 1})")
        raise InputError("the scene has neither nodes nor an output whirl_amplitude: `periodic` has no amplitude "
                         "to report")
    if "node_x" not in out or "node_y" not in out:
        raise InputError(f"--node {node}: the scene has no nodes (no outputs node_x, node_y); leave --node out")
    n_nodes = int(np.shape(out["node_x"])[0])
    if not node < n_nodes:
        raise InputError(f"--node {node}: the scene's nodes are 0..{n_nodes - 1}")
    return f"largest radius of node {node}'s orbit over the period"


def _start(preset, params, key, lo, hi, given):
    """The branch's start and where it comes from: `--from` (inside the range), else
    the preset's (the rotor file's) value of `key` where it lies in the range, else the
    range's end nearest to that value."""
    if given is not None:
        try:
            start = preset.check(key, given)
        except InputError as e:
            raise InputError(f"--from: {e}") from None
        if not lo <= start <= hi:
            raise InputError(f"--range {lo:g} {hi:g}: the start --from {key} = {start:g} lies outside")
        return start, "--from"
    own = float(params[key])
    if lo <= own <= hi:
        return own, "the preset's value"
    start = lo if abs(own - lo) <= abs(own - hi) else hi
    return start, f"the end of --range nearest to the preset's value {own:g}"


def _failure(failed, stem):
    """The exit-3 message: the first reason, the others after it (a branch that ran
    out of points may also have missed its harmonics target), and the files written."""
    also = f"; also: {'; '.join(failed[1:])}" if len(failed) > 1 else ""
    return f"{failed[0]}{also} (files written: {os.path.basename(stem)}.*)"


def _incomplete(curve, p, key, lo, hi, max_points):
    """The reasons (with what to change) why a branch (its `Curve`) ended inside the
    range, one per end whose outcome is not `successful` (the range's edge, a closed
    loop)."""
    from rotorjax.solve import RESULTS

    out = []
    for end, stop, result in zip((p[0], p[-1]), curve.stops, curve.results):
        if result == RESULTS.successful:
            continue
        remedy = next((r for k, r in REMEDY.items() if result == getattr(RESULTS, k)), "lower --ds-max")
        at = f" (--max-points {max_points}) at {key} = {float(end):.8g}" if result == RESULTS.max_points_reached \
            else ""
        out.append(f"the branch stopped inside --range {lo:g} {hi:g}: {stop}{at}; {remedy}")
    return out


def _branch_row(br, amp, truncation, key):
    """A `PeriodicBranch`'s JSON row (`amp`, `truncation`: `branch_amplitude`'s)."""
    return {key: br.p.tolist(), "amplitude": amp.tolist(), "stable": br.stable.tolist(),
            "margin": br.margin.tolist(), "time_residual": truncation.tolist(),
            "harmonics": [int(h) for h in br.harmonics], "truncation": br.truncation.tolist(),
            "n_points": int(br.p.size), "stop": br.curve.stop, "stops": list(br.stops)}


def _not_switched(events, switched, key, lo, hi, max_points):
    """`--switch`'s exit-3 reasons: a branch point whose crossing branch did not
    start, a switched branch that ended inside the range; a branch point located
    to the step only is warned of, not switched at."""
    import warnings

    from .._errors import PlausibilityWarning

    out = []
    for e in events:
        if e.kind != "branch_point" or e.switched is not None:
            continue
        if e.note is not None and e.note.startswith("not switched at"):
            out.append(f"--switch: the branch crossing at {key} = {e.p:.8g} did not start ({e.note}); give a "
                       "smaller --ds")
        else:
            warnings.warn(f"--switch: the branch point at {key} = {e.p:.8g} was not switched at: {e.note}",
                          PlausibilityWarning)
    for e, b, *_ in switched:
        out += [f"--switch: the branch switched onto at {key} = {e.p:.8g}: {why}"
                for why in _incomplete(b.curve, b.p, key, lo, hi, max_points)]
    return out


def _harmonics_used(harmonics):
    """`"1 harmonic"`, `"8 harmonics"` or `"1 to 4 harmonics"`: the counts along a branch."""
    lo, hi = int(np.min(harmonics)), int(np.max(harmonics))
    return f"{lo} harmonic{'s' if lo > 1 else ''}" if lo == hi else f"{lo} to {hi} harmonics"


def cmd_periodic(args) -> int:
    from rotorjax.analysis import branch_amplitude, periodic_branch
    from rotorjax.plot import plot_boundaries, plot_periodic_branch
    from rotorjax.solve import RESULTS
    from ._common import save_figure

    preset = get_preset(args.preset)
    params = preset_params(preset, args.set)
    key = args.param
    _check_key(preset, "--param", key)
    lo, hi = param_span("--range", preset, key, *args.range)
    if key == preset.speed_key and not lo > 0:
        raise InputError(f"--range {lo:g} {hi:g}: the speed must stay > 0 (the forcing's period is 2 pi / speed)")
    range2 = _second_parameter(args, preset, params, key)
    if args.switch and (args.from_hopf or args.method == "shooting"):
        raise InputError(f"--switch: branch points are switched at on a harmonic-balance branch of forced motions, "
                         f"not with {'--from-hopf' if args.from_hopf else '--method shooting'}; leave out --switch")
    if args.from_hopf:
        return _from_hopf(args, preset, params, key, lo, hi)
    if args.hopf_amplitude is not None:
        raise InputError(f"--hopf-amplitude {args.hopf_amplitude:g}: it sizes the first cycle of --from-hopf; "
                         "give --from-hopf too, or leave it out")
    start, start_source = _start(preset, params, key, lo, hi, args.start)
    if args.ds_max is not None and args.ds is not None and args.ds_max < args.ds:
        raise InputError(f"--ds {args.ds:g} --ds-max {args.ds_max:g}: need DS <= DS_MAX")
    # default steps in proportion to the range (the library's: range / 100, range / 10)
    ds_max = max((hi - lo) / 10, args.ds or 0.0) if args.ds_max is None else args.ds_max
    ds = min((hi - lo) / 100, ds_max) if args.ds is None else args.ds
    setup = build(preset, dict(params, **{key: start}))
    if setup.y0 is None:
        raise InputError(f"`periodic` starts from the scene's rest state; {preset.name} has none")
    if setup.extras.get("events"):
        raise InputError(f"--method {args.method}: the exact (event-located) contact of --set events=1 is not "
                         "offered by `periodic` (harmonic balance and fixed-step shooting use the smoothed "
                         "contact: --set events=0)")
    scene_at, guess = _periodic_scene(_scene_at(preset, dict(params, **{key: start}), key, setup), setup.scene,
                                      setup.y0)
    amplitude_of = _amplitude_of(setup.scene, setup.y0, args.node)
    scene_at2 = None if range2 is None else _scene_at2(preset, dict(params, **{key: start}), args.param2, setup)
    prepare_out(args.out)
    stem = out_stem(args.out, preset, "periodic_", f"_{key}")

    br, coefficients = periodic_branch(scene_at, start, guess, (lo, hi), args.harmonics,
                                       subharmonic=args.subharmonic, name=key, ds=ds, ds_max=ds_max,
                                       max_points=args.max_points, progress=not args.json,
                                       method=METHODS[args.method], steps=args.steps,
                                       truncation_tol=args.truncation_tol, max_harmonics=args.max_harmonics,
                                       switch=args.switch)
    auto = args.harmonics == "auto"
    used = _harmonics_used(br.harmonics)
    amp, truncation = branch_amplitude(scene_at, br.p, coefficients, node=args.node,
                                       subharmonic=args.subharmonic, truncation=True)

    def bifurcations_of(branch, coefs):
        return _bifurcations(branch.events, key, lambda events: branch_amplitude(
            scene_at, *_event_motions(events, coefs), node=args.node, subharmonic=args.subharmonic))

    bifurcations = bifurcations_of(br, coefficients)
    switched = [(e, b, c, *branch_amplitude(scene_at, b.p, c, node=args.node, subharmonic=args.subharmonic,
                                            truncation=True))
                for e in sorted(br.events, key=lambda e: e.p) if e.switched is not None for b, c in [e.switched]]
    second = None
    if range2 is not None:
        second = _jump_boundary(scene_at2, br, coefficients, key, args.param2, float(params[args.param2]),
                                (lo, hi), range2, args)
    out = {"preset": preset.name, "param": key, "node": args.node, "amplitude_unit": preset.length_unit,
           "amplitude_of": amplitude_of, "method": METHODS[args.method], "harmonics": args.harmonics,
           **({"truncation_tol": args.truncation_tol, "max_harmonics": args.max_harmonics} if auto else {}),
           "subharmonic": args.subharmonic, "range": [lo, hi], "start": start,
           "start_source": start_source,
           "branches": [_branch_row(br, amp, truncation, key)],
           "bifurcations": bifurcations}
    if args.switch:
        out["switched"] = [dict(_branch_row(b, a, t, key), at=e.p, bifurcations=bifurcations_of(b, c))
                           for e, b, c, a, t in switched]
    columns, header = [br.p, amp, br.stable.astype(int), br.margin], f"{key},amplitude,stable,margin"
    if second is not None:
        sensitivity, curves = second
        out.update({"param2": args.param2, "range2": list(range2), "param2_value": float(params[args.param2]),
                    "fold_curves": [_fold_curve_row(c, e, key, args.param2) for e, c in curves]})
        out["branches"][0]["d_amplitude_d_param2"] = sensitivity.tolist()
        columns.append(sensitivity)
        header += f",d_amplitude_d_{args.param2}"
        np.savetxt(stem + "_folds.csv", np.concatenate(
            [np.column_stack([c.x[:, -2:], np.full(len(c.x), i)]) for i, (_, c) in enumerate(curves)]
            or [np.zeros((0, 3))]), delimiter=",", header=f"{key},{args.param2},fold_curve", comments="",
            fmt="%.17g")
    rows = np.column_stack(columns)
    if args.switch:      # the switched branches' rows below the branch's, numbered in the last column
        header += ",branch"
        rows = np.concatenate([np.column_stack([rows, np.zeros(len(rows))])] + [
            np.column_stack([b.p, a, b.stable.astype(int), b.margin] + [np.full(b.p.size, np.nan)] * (
                len(columns) - 4) + [np.full(b.p.size, i + 1.0)]) for i, (_, b, _, a, _) in enumerate(switched)])
    np.savetxt(stem + ".csv", rows, delimiter=",", header=header, comments="", fmt="%.17g")
    unit = f" ({preset.length_unit})" if preset.length_unit else ""
    key_unit = preset.units.get(key, "")
    labels = dict(x_label=key + (f" ({key_unit})" if key_unit not in ("", "dimensionless") else ""),
                  y_label=f"amplitude{unit}", title=f"{os.path.basename(preset.name)}: periodic motions in {key} "
                                                    f"({used}); amplitude: {amplitude_of}")
    figure = plot_periodic_branch(br.p, amp, br.stable, [dict(b, p=b[key]) for b in bifurcations], **labels)
    for (_, b, _, a, _), row in zip(switched, out.get("switched", [])):
        plot_periodic_branch(b.p, a, b.stable, [dict(v, p=v[key]) for v in row["bifurcations"]], ax=figure.axes[0],
                             **labels)
    save_figure(figure, stem + ".png")
    out["files"] = {"data": stem + ".csv", "summary": stem + ".json", "plot": stem + ".png"}
    if second is not None:
        # the curves drawn through their points in (key, key2) (their tangents are in the unknowns too)
        drawn = [dataclasses.replace(c, x=c.x[:, -2:], tangents=None) for _, c in second[1]]
        save_figure(plot_boundaries(drawn, [], key=key, key2=args.param2,
                                    box=(lo, hi, *range2),
                                    title=f"{os.path.basename(preset.name)}: folds of the periodic motions (the "
                                          "jump boundary)"), stem + "_folds.png")
        out["files"].update({"fold_curves": stem + "_folds.csv", "fold_plot": stem + "_folds.png"})
    write_json(stem + ".json", out, indent=2)
    failed = _incomplete(br.curve, br.p, key, lo, hi, args.max_points)
    if second is not None:
        failed += [f"the fold curve from {key} = {e.p:.8g} stopped inside --range and --range2: {stop}; lower "
                   "--ds-max" for e, c in second[1] for stop, r in zip(c.stops, c.results)
                   if not r == RESULTS.successful]
    if args.switch:
        failed += _not_switched(br.events, switched, key, lo, hi, args.max_points)
    if auto:     # the target, held at every point unless --max-harmonics ran out
        worst = int(np.argmax(br.truncation))
        if not br.truncation[worst] <= args.truncation_tol:
            failed.append(f"harmonics insufficient: the truncation error estimate is {br.truncation[worst]:.2e} > "
                          f"--truncation-tol {args.truncation_tol:g} at {key} = {br.p[worst]:.8g} with "
                          f"--max-harmonics {args.max_harmonics}; raise --max-harmonics (or --truncation-tol)")
    else:
        failed += _residual_too_large(truncation, br.p, key, args.max_time_residual, "orbit")
    if args.json:
        print(json.dumps(out, indent=2))
    else:
        print(f"{preset.name}: periodic motions in {key} by {METHODS[args.method]}, {used}"
              + (f" (auto: truncation error estimate <= {args.truncation_tol:g})" if auto else "")
              + (f", period {args.subharmonic} x the forcing's" if args.subharmonic > 1 else "")
              + f"; wrote {stem}.csv, .json, .png")
        print(f"  {key} in [{lo:g}, {hi:g}] from {start:g} ({out['start_source']}); {br.p.size} points, "
              f"{int(np.sum(~br.stable))} unstable; amplitude: {amplitude_of}, {preset.length_unit}")
        _print_bifurcations(bifurcations, key)
        print(f"  stops: {'; '.join(br.stops)}")
        if args.switch and not switched:
            print("  --switch: no branch point switched at")
        for row in out.get("switched", []):
            print(f"  switched at the branch point {key} = {row['at']:.8g}: {key} in [{min(row[key]):.6g}, "
                  f"{max(row[key]):.6g}], {row['n_points']} points, {sum(not v for v in row['stable'])} unstable; "
                  f"stops: {'; '.join(row['stops'])}")
            _print_bifurcations(row["bifurcations"], key)
        if second is not None:
            _print_second(out, key, args.param2)
    if failed:
        raise NumericalError(_failure(failed, stem))
    return 0


def _second_parameter(args, preset, params, key):
    """`--param2` and `--range2` checked: the range of --param2 (its value halved and
    doubled by default), or None without --param2."""
    key2 = args.param2
    if key2 is None:
        if args.range2 is not None:
            raise InputError(f"--range2 {' '.join(f'{v:g}' for v in args.range2)}: it is the range of --param2; "
                             "give --param2 too, or leave it out")
        return None
    _check_key(preset, "--param2", key2)
    if key2 == key:
        raise InputError(f"--param2 {key2}: the two parameters must differ")
    if key != preset.speed_key:
        raise InputError(f"--param2 {key2}: the folds are continued in ({preset.speed_key}, {key2}); give --param "
                         f"{preset.speed_key}")
    for given, option in ((args.from_hopf, "--from-hopf"), (args.method != "hb", "--method shooting")):
        if given:
            raise InputError(f"--param2 {key2}: {option} does not apply (the fold curves and the amplitude's "
                             "derivative are of the forced branch, by harmonic balance); leave it out")
    if args.range2 is None:
        return preset.continuation_range(float(params[key2]))
    lo2, hi2 = param_span("--range2", preset, key2, *args.range2)
    if not lo2 <= float(params[key2]) <= hi2:
        raise InputError(f"--range2 {lo2:g} {hi2:g}: {key2} = {float(params[key2]):g} (the branch's) lies outside")
    return lo2, hi2


def _scene_at2(preset, params, key2, setup):
    """`(speed, q) -> scene` with `key2` at `q` (traceable in both; see `_scene_at`),
    without a work state where the scene keeps one."""
    import equinox as eqx

    from rotorjax.models import provides

    at_q = _scene_at(preset, params, key2, setup, option="--param2")
    drop = provides(setup.scene, "without_work")

    def at(speed, q):
        scene = eqx.tree_at(lambda s: s.speed.constant, at_q(q), speed)
        return scene.without_work() if drop else scene

    return at


def _jump_boundary(scene_at2, br, coefficients, key, key2, q0, span, span2, args):
    """`(sensitivity, [(fold event, Curve), ...])`: the amplitude's derivative in
    `key2` at every point of the branch, and each refined fold continued in `(key,
    key2)` within the two ranges (the jump boundary)."""
    from rotorjax.analysis import branch_amplitude_gradient, periodic_fold_curve

    sensitivity = branch_amplitude_gradient(scene_at2, br.p, q0, coefficients, node=args.node,
                                            subharmonic=args.subharmonic)
    curves = []
    for e in sorted((e for e in br.events if e.kind == "fold" and e.note is None), key=lambda e: e.p):
        if any(np.any(np.abs(c.meets(c.x.shape[1] - 1, q0)[:, -2] - e.p) <= 1e-3 * (span[1] - span[0]))
               for _, c in curves):
            continue     # on a curve already traced (the two folds of a branch meet at a cusp inside the box)
        Y = np.reshape(e.u, coefficients.shape[1:])
        rows = np.flatnonzero(np.any(Y != 0, axis=1))
        Y = Y[:2 * max(1, (int(rows.max()) + 1) // 2 if rows.size else 1) + 1]   # the fold's own harmonics
        try:
            curve = periodic_fold_curve(scene_at2, (e.p, q0), Y, subharmonic=args.subharmonic,
                                        bounds=((span[0], span2[0]), (span[1], span2[1])), ds=0.01, ds_max=0.05,
                                        max_points=args.max_points, names=(key, key2))
        except ValueError as err:
            raise NumericalError(f"--param2 {key2}: the fold at {key} = {e.p:.8g} could not be continued: {err}") \
                from None
        curves.append((e, curve))
    return sensitivity, curves


def _fold_curve_row(curve, fold, key, key2):
    """The JSON row of one fold curve: its points in `(key, key2)`, the fold it
    starts from, residuals and stops."""
    from rotorjax.solve import code_of

    return {"from": {key: float(fold.p)}, key: curve.x[:, -2].tolist(), key2: curve.x[:, -1].tolist(),
            "residual_max": float(np.max(curve.residuals)), "n_points": int(len(curve.x)), "stop": curve.stop,
            "stops": list(curve.stops), "stop_codes": [code_of(r) for r in curve.results]}


def _print_second(out, key, key2):
    d = out["branches"][0]["d_amplitude_d_param2"]
    print(f"  d(amplitude)/d({key2}) along the branch: {min(d):.4g} to {max(d):.4g} (at {key2} = "
          f"{out['param2_value']:g}; unbounded towards a fold)")
    lo2, hi2 = out["range2"]
    if not out["fold_curves"]:
        print(f"  no refined fold to continue in ({key}, {key2})")
    for i, c in enumerate(out["fold_curves"], start=1):
        print(f"  fold curve {i} (from {key} = {c['from'][key]:.8g}), the jump boundary in {key2} in [{lo2:g}, "
              f"{hi2:g}]: {key} in [{min(c[key]):.6g}, {max(c[key]):.6g}], {c['n_points']} points, residual <= "
              f"{c['residual_max']:.1e}; {c['stop']}")


def _event_motions(events, coefficients):
    """The events' parameter values and coefficients `(events, 2H + 1, n)`."""
    return (np.array([e.p for e in events]),
            np.stack([np.reshape(e.u, coefficients.shape[1:]) for e in events]))


def _bifurcations(events, key, amplitude):
    """The JSON rows of a branch's events in order of the parameter: kind, value, the
    motion's amplitude there (`amplitude(events)`), residual, meaning, and a
    secondary frequency or a note where the event has one."""
    events = sorted(events, key=lambda e: e.p)
    if not events:
        return []
    amp = amplitude(events)
    rows = []
    for e, a in zip(events, amp):
        kind = e.kind.replace("_", "-")
        row = {"kind": kind, key: float(e.p), "amplitude": float(a), "residual": float(e.residual),
               "meaning": MEANING[kind]}
        if e.frequency is not None and e.kind != "fold":
            row["frequency"] = float(e.frequency)
        if e.note is not None:
            row["note"] = e.note
        rows.append(row)
    return rows


def _print_bifurcations(bifurcations, key):
    for b in bifurcations:
        second = f" {b['frequency']:.6g} rad per time unit" if b["kind"] == "neimark-sacker" else ""
        how = f"; {b['note']}" if "note" in b else ""
        print(f"  {b['kind']} at {key} = {b[key]:.8g}, amplitude {b['amplitude']:.4g} "
              f"(residual {b['residual']:.1e}{how}): {b['meaning']}{second}")


def _residual_too_large(residual, p, key, limit, what):
    """`[why]` where a point's time-domain residual (the truncation error of the
    harmonics) exceeds `--max-time-residual`, else `[]`."""
    worst = int(np.argmax(residual))
    if not residual[worst] > limit:
        return []
    return [f"harmonics insufficient: the time-domain residual of the reconstructed {what} is {residual[worst]:.2e} "
            f"> --max-time-residual {limit:g} at {key} = {p[worst]:.8g}; raise --harmonics"]


#: `--harmonics auto` for limit cycles (adaptive harmonics follow forced branches)
HOPF_HARMONICS = 8


def _from_hopf(args, preset, params, key, lo, hi):
    """`periodic --from-hopf`: the limit cycles born at the lowest Hopf point of the
    reference motion in the range, continued away from it by harmonic balance."""
    from rotorjax.analysis import (StraightRunning, branch_amplitude, hopf_cycle_branch, is_autonomous,
                                   reference_hopf_points)
    from rotorjax.plot import plot_periodic_branch
    from ._common import save_figure

    for given, option in ((args.start is not None, "--from"), (args.method != "hb", "--method"),
                          (args.subharmonic != 1, "--subharmonic")):
        if given:
            raise InputError(f"--from-hopf: {option} does not apply (the limit cycles start at the Hopf point, "
                             "by harmonic balance, at their own period); leave it out")
    if key != preset.speed_key:
        raise InputError(f"--from-hopf: --param {key}: Hopf points are found in the speed; give --param "
                         f"{preset.speed_key}")
    setup = build(preset, dict(params, **{key: lo}))
    if not isinstance(setup.reference, StraightRunning):
        raise InputError(f"--from-hopf: {preset.name} has no reference motion with linear equations to find Hopf "
                         "points of (a rotor file on fluid films, or model 004, has)")
    if setup.y0 is None:
        raise InputError(f"--from-hopf: {preset.name} has no rest state to start from")
    scene_at, guess = _periodic_scene(_scene_at(preset, dict(params, **{key: lo}), key, setup), setup.scene,
                                      setup.y0)
    if not is_autonomous(scene_at(lo), guess):
        keys = preset.forcing_keys(params, {key: lo})
        hint = (" (--set " + " ".join(f"{k}=0" for k in keys) + ")") if keys else ""
        raise InputError(f"--from-hopf: {preset.name}'s equations depend on time (a forcing, such as an "
                         f"unbalance): limit cycles need an autonomous scene; set the forcing to zero{hint}")
    amplitude_of = _amplitude_of(setup.scene, setup.y0, args.node)
    report = reference_hopf_points(setup.reference, lo, hi, progress=not args.json)
    if not report.points:
        raise InputError(f"--from-hopf: --range {lo:g} {hi:g}: {setup.reference.label} has no Hopf point in "
                         f"it (`rotorjax hopf {preset.name} --range LO HI` searches a wider range)")
    hopf = report.points[0]
    at_hopf = build(preset, dict(params, **{key: hopf.speed}))
    _, y_eq = _periodic_scene(scene_at, at_hopf.scene, at_hopf.y0)   # a guess: the cycle's mean is solved for
    harmonics = HOPF_HARMONICS if args.harmonics == "auto" else args.harmonics
    prepare_out(args.out)
    stem = out_stem(args.out, preset, "periodic_", f"_{key}_hopf")
    br, coefficients, periods, p_first = hopf_cycle_branch(
        scene_at, hopf, y_eq, (lo, hi), harmonics, amplitude=args.hopf_amplitude, name=key,
        **({"ds": args.ds} if args.ds is not None else {}), **({"ds_max": args.ds_max} if args.ds_max else {}),
        max_points=args.max_points, progress=not args.json)
    amp, residual = branch_amplitude(scene_at, br.p, coefficients, node=args.node, periods=periods,
                                     truncation=True)
    # an event's period: its step's mean (the events carry the coefficients, not the frequency)
    bifurcations = _bifurcations(br.events, key, lambda events: branch_amplitude(
        scene_at, *_event_motions(events, coefficients), node=args.node,
        periods=[0.5 * (periods[e.between[0]] + periods[e.between[1]]) for e in events]))
    criticality = "subcritical" if p_first < hopf.speed else "supercritical"
    out = {"preset": preset.name, "param": key, "node": args.node, "amplitude_unit": preset.length_unit,
           "amplitude_of": amplitude_of, "method": "harmonic-balance", "harmonics": harmonics,
           "range": [lo, hi], "start": p_first, "start_source": "--from-hopf",
           "hopf": {key: hopf.speed, "frequency": hopf.frequency, "criticality": criticality,
                    "first_cycle": {key: p_first, "period": float(periods[br.curve.start])}},
           "branches": [{key: br.p.tolist(), "amplitude": amp.tolist(), "period": np.asarray(periods).tolist(),
                         "stable": br.stable.tolist(), "margin": br.margin.tolist(),
                         "time_residual": residual.tolist(), "harmonics": [harmonics] * int(br.p.size),
                         # each cycle's state at phase 0: the series' mean plus its cosines (start a run on it)
                         "state_at_phase_0": (coefficients[:, 0] + coefficients[:, 1::2].sum(axis=1)).tolist(),
                         "n_points": int(br.p.size), "stop": br.curve.stop, "stops": list(br.stops)}],
           "bifurcations": bifurcations}
    np.savetxt(stem + ".csv", np.column_stack([br.p, amp, periods, br.stable.astype(int), br.margin]),
               delimiter=",", header=f"{key},amplitude,period,stable,margin", comments="", fmt="%.17g")
    unit = f" ({preset.length_unit})" if preset.length_unit else ""
    save_figure(plot_periodic_branch(br.p, amp, br.stable, [dict(b, p=b[key]) for b in bifurcations],
                                     x_label=key, y_label=f"amplitude{unit}",
                                     title=f"{os.path.basename(preset.name)}: limit cycles from the Hopf point "
                                           f"at {key} = {hopf.speed:.6g}; amplitude: {amplitude_of}"),
                stem + ".png")
    out["files"] = {"data": stem + ".csv", "summary": stem + ".json", "plot": stem + ".png"}
    write_json(stem + ".json", out, indent=2)
    failed = _incomplete(br.curve, br.p, key, lo, hi, args.max_points)
    failed += _residual_too_large(residual, br.p, key, args.max_time_residual, "cycle")
    if args.json:
        print(json.dumps(out, indent=2))
    else:
        print(f"{preset.name}: limit cycles born at the Hopf point {key} = {hopf.speed:.8g} (whirl frequency "
              f"{hopf.frequency:.6g}, {criticality}), by harmonic balance with {harmonics} harmonics; wrote "
              f"{stem}.csv, .json, .png")
        print(f"  {key} in [{lo:g}, {hi:g}]; {br.p.size} cycles, {int(np.sum(~br.stable))} unstable, amplitude "
              f"{float(np.min(amp)):.4g} to {float(np.max(amp)):.4g} {preset.length_unit} ({amplitude_of})")
        _print_bifurcations(bifurcations, key)
        print(f"  stops: {'; '.join(br.stops)}")
    if failed:
        raise NumericalError(_failure(failed, stem))
    return 0
