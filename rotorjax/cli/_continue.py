"""`continue`: a branch in one parameter, or a stability boundary in two."""

import json
import os

import numpy as np

from ._common import (InputError, NumericalError, get_preset, out_stem, param_span, prepare_out, preset_params,
                      stability_study, write_json)

#: the accuracy of a boundary's dense curve between its points (along --param, at fixed --param2)
DENSE_TOL = 1e-6


def _check_key(preset, option, key):
    if key not in preset.defaults:
        raise InputError(f"{option} {key}: unknown parameter for {preset.name}; known: "
                         f"{', '.join(sorted(preset.defaults))}")
    if key in preset.topology_keys + preset.integer_keys:
        raise InputError(f"{option} {key}: {key!r} changes the scene's structure: it cannot be continued")


def _direction(text):
    return {"both": None, "up": 1.0, "+1": 1.0, "1": 1.0, "down": -1.0, "-1": -1.0}[text]


def _box(preset, args, key, key2, start):
    """The parameter box of a boundary: `--box` (checked), else the preset's default
    (`Preset.boundary_box`)."""
    if args.box is None:
        return preset.boundary_box(key, key2, start)
    lo1, hi1, lo2, hi2 = args.box
    for option_part, lo, hi, k in (("LO1 HI1", lo1, hi1, key), ("LO2 HI2", lo2, hi2, key2)):
        if not (np.isfinite(lo) and np.isfinite(hi) and lo < hi):
            raise InputError(f"--box {' '.join(f'{v:g}' for v in args.box)}: {option_part} ({k}) need "
                             "finite LO < HI")
        for v in (lo, hi):
            try:
                preset.check(k, v)
            except InputError as e:
                raise InputError(f"--box: {e}") from None
    return [lo1, hi1, lo2, hi2], "--box"


def _param_range(preset, key, to, start):
    """`--to LO HI` checked (finite, LO < HI, inside the key's valid values), or
    by default the start halved and doubled."""
    if to is None:
        return preset.continuation_range(start), "default (start halved and doubled)"
    return param_span("--to", preset, key, *to), "--to"


def cmd_continue(args) -> int:
    from rotorjax.analysis import continue_branch, floquet_crossings, trace_boundaries, trace_boundary
    from rotorjax.plot import plot_boundaries, plot_curves
    from ._common import save_figure

    preset = get_preset(args.preset)
    params = preset_params(preset, args.set)
    key, key2 = args.param, args.param2
    _check_key(preset, "--param", key)
    if key2 is not None:
        _check_key(preset, "--param2", key2)
        if key2 == key:
            raise InputError(f"--param {key} --param2 {key2}: the two parameters must differ")
    n_start = 2 if key2 else 1
    if args.start is not None and len(args.start) != n_start:
        raise InputError(f"--from needs {n_start} value(s): {key}" + (f" {key2}" if key2 else "")
                         + f"; got {len(args.start)}")
    start = list(args.start) if args.start else [params[key]] + ([params[key2]] if key2 else [])
    for k, v in zip((key, key2), start):
        try:
            preset.check(k, v)
        except InputError as e:
            raise InputError(f"--from: {e}") from None
    if args.ds_max < args.ds:
        raise InputError(f"--ds {args.ds:g} --ds-max {args.ds_max:g}: need DS <= DS_MAX")
    if key2 and args.to is not None:
        raise InputError("--to is for one-parameter continuation; a boundary takes --box")
    if not key2 and args.box is not None:
        raise InputError("--box is for a boundary (--param2); one-parameter continuation takes --to")
    if key2 and args.switch:
        raise InputError(f"--switch: branch points are switched at on a one-parameter branch; a boundary "
                         f"(--param2 {key2}) has none to switch at: leave out --switch or --param2")
    direction = _direction(args.direction)
    prepare_out(args.out)
    stem = out_stem(args.out, preset, "continue_", f"_{key}" + (f"_{key2}" if key2 else ""))
    out = {"preset": preset.name, "param": key, "param2": key2, "start": start,
           "start_source": "--from" if args.start else "the preset's values"}
    study = stability_study(preset, params)
    if key2:
        if study is None:
            raise InputError(f"{preset.name!r} has no reference regime whose boundary could be traced")
        gradient = args.gradient if args.gradient != "auto" else study.gradient
        box, box_source = _box(preset, args, key, key2, start)
        if args.start is not None and not (box[0] <= start[0] <= box[1] and box[2] <= start[1] <= box[3]):
            raise InputError(f"--from {start[0]:g} {start[1]:g}: outside the box {key} in [{box[0]:g}, {box[1]:g}]"
                             f", {key2} in [{box[2]:g}, {box[3]:g}] ({box_source}); give --box")
        if args.start is None and direction is not None:
            raise InputError(f"--direction {args.direction}: one way from a start given with --from; without it "
                             "every boundary in the box is traced both ways")

        def sigma(a, b):
            return study.margin(dict(params, **{key: a, key2: b}))

        bounds = (np.array([box[0], box[2]]), np.array([box[1], box[3]]))
        if args.start is None:
            found = trace_boundaries(sigma, ((box[0], box[1]), (box[2], box[3])), dense_tol=DENSE_TOL,
                                     ds=args.ds, ds_max=args.ds_max, max_points=args.max_points,
                                     gradient=gradient, names=(key, key2), progress=not args.json)
            if not found.branches:
                failed = [c.error for c in found.crossings if c.error is not None]
                raise InputError(f"no stability boundary meets the edge of the box {key} in [{box[0]:g}, "
                                 f"{box[1]:g}], {key2} in [{box[2]:g}, {box[3]:g}] nor crosses {key2} = "
                                 + ", ".join(f"{v:g}" for v in found.lines)
                                 + (f": {failed[0]}" if failed else "")
                                 + f"; give --from {key.upper()} {key2.upper()} near one, or another --box")
            branches = found.branches
            crossings = found.crossings
            start = branches[0].x[branches[0].start].tolist()
            out["start_source"] = (f"crossings located round the box's edge and along {key} at {key2} = "
                                   + ", ".join(f"{v:.6g}" for v in found.lines))
            out["lines"] = found.lines.tolist()
        else:
            branches = [trace_boundary(sigma, start, bounds=bounds, ds=args.ds, ds_max=args.ds_max,
                                       max_points=args.max_points, gradient=gradient,
                                       direction=None if direction is None else (0.0, direction),
                                       names=(key, key2), progress=not args.json, dense_tol=DENSE_TOL)]
            crossings = ()
            start = branches[0].x[branches[0].start].tolist()
        first = branches[0]
        out.update({"kind": "stability boundary (margin = 0)", "regime": study.regime, "start": start,
                    "box": box, "box_source": box_source, "dense_tol": DENSE_TOL,
                    "n_branches": len(branches),
                    "branches": [c.as_dict(names=(key, key2), dense=8) for c in branches],
                    "crossings": [c.as_dict(names=(key, key2)) for c in crossings],
                    # the first branch, as before there were several
                    key: first.x[:, 0].tolist(), key2: first.x[:, 1].tolist(),
                    "residuals": first.residuals.tolist(), "steps": first.steps.tolist(),
                    "stopped": first.stopped, "stops": list(first.stops), "gradient": gradient})
        np.savetxt(stem + ".csv", np.concatenate([np.column_stack([c.x, c.residuals, np.full(len(c.x), i)])
                                                  for i, c in enumerate(branches)]),
                   delimiter=",", header=f"{key},{key2},residual,branch", comments="", fmt="%.17g")
        save_figure(plot_boundaries(branches, crossings, key=key, key2=key2, box=box,
                                    title=f"{preset.name}: stability boundary of {study.regime}"), stem + ".png")
    elif study is not None and study.floquet_family is not None:
        if args.switch:
            raise InputError(f"--switch: {preset.name} is continued by the Floquet multipliers of its main motion "
                             f"along {key}, a scan with no branch points to switch at; leave out --switch")
        (lo, hi), out["range_source"] = _param_range(preset, key, args.to, start[0])
        found = floquet_crossings(study.floquet_family(params, key), lo, hi,
                                  n_scan=args.max_points if args.max_points < 400 else 60, progress=not args.json)
        out.update({"kind": "Floquet multipliers of the main motion", "range": [lo, hi],
                    "crossings": [c.as_dict() for c in found]})
        with open(stem + ".csv", "w") as f:
            f.write(f"{key},kind,residual\n")
            for c in found:
                f.write(f"{c.p},{c.kind},{c.residual}\n")
    else:
        if study is None or study.branch_problem is None:
            raise InputError(f"{preset.name!r} has no stationary branch to continue in one parameter; trace a "
                             "boundary with --param2, or use `critical-speeds` / `hopf`")
        F, u0 = study.branch_problem(params, key)
        (lo, hi), out["range_source"] = _param_range(preset, key, args.to, start[0])
        if not lo <= start[0] <= hi:
            raise InputError(f"--to {lo:g} {hi:g}: the start {key} = {start[0]:g} lies outside")
        out["range"] = [lo, hi]
        br = continue_branch(F, u0, start[0], p_bounds=(lo, hi), ds=args.ds, ds_max=args.ds_max,
                             max_points=args.max_points, direction=direction, name=key,
                             progress=not args.json)
        out.update({"kind": "branch of the balanced regime (rotating frame)", **_branch_dict(br)})
        switched = _switched(F, br, (lo, hi), args, key) if args.switch else []
        if args.switch:
            out["switched"] = [dict(_branch_dict(b), at=e.p) for e, b in switched]
        rows = [np.column_stack([b.p, b.margin, b.curve.residuals, np.full(b.p.size, i)])
                for i, b in enumerate([br] + [b for _, b in switched])]
        np.savetxt(stem + ".csv", np.concatenate(rows), delimiter=",",
                   header=f"{key},margin,residual" + (",branch" if args.switch else ""), comments="",
                   fmt="%.17g")
        save_figure(plot_curves(br.p, {"largest real part": br.margin, **{
            f"switched at {key} = {e.p:.6g}": (b.p, b.margin) for e, b in switched}}, x_label=key,
            y_label="margin", title=f"{preset.name}: branch in {key}"), stem + ".png")
    out["files"] = {"data": stem + ".csv", "summary": stem + ".json"}
    if os.path.exists(stem + ".png"):
        out["files"]["plot"] = stem + ".png"
    write_json(stem + ".json", out, indent=2)
    if args.json:
        print(json.dumps(out, indent=2))
        return 0
    print(f"{preset.name}: {out['kind']}; wrote {stem}.csv, .json")
    if "range" in out:
        print(f"  {key} in [{out['range'][0]:g}, {out['range'][1]:g}] ({out['range_source']})")
    if "box" in out:
        b = out["box"]
        print(f"  box {key} in [{b[0]:g}, {b[1]:g}], {key2} in [{b[2]:g}, {b[3]:g}] ({out['box_source']})")
        if "lines" in out:
            print(f"  started from {out['start_source']}")
        else:
            print(f"  started from ({key}, {key2}) = ({out['start'][0]:.8g}, {out['start'][1]:.8g}) "
                  f"({out['start_source']}, corrected along {key})")
        print(f"  {out['n_branches']} branch(es); steps kept the dense curve between points within "
              f"{out['dense_tol']:g} of the boundary along {key} (estimated):")
        for i, br in enumerate(out["branches"]):
            print(f"  branch {i + 1}: {key} in [{min(br[key]):.6g}, {max(br[key]):.6g}], {key2} in "
                  f"[{min(br[key2]):.6g}, {max(br[key2]):.6g}]; {br['n_points']} points, interpolation error "
                  f"<= {br['interpolation_error_max']:.1e}, residual <= {max(br['residuals']):.1e}; "
                  f"{br['stopped']}")
        for c in out.get("crossings", []):
            if "error" in c:
                print(f"  crossing at ({c[key]:.6g}, {c[key2]:.6g}) not traced: {c['error']}")
        return 0
    for c in out.get("crossings", []) + out.get("events", []):
        how = f"; {c['note']}" if "note" in c else ""
        print(f"  {c.get('kind')} at {key} = {c['p']:.8g} (residual {c['residual']:.1e}{how})")
    if "stopped" in out:
        print(f"  stopped: {out['stopped']}")
    if args.switch and not out["switched"]:
        print("  --switch: no refined branch point on the branch")
    for b in out.get("switched", []):
        print(f"  switched at the branch point {key} = {b['at']:.8g}: {key} in [{min(b['p']):.6g}, "
              f"{max(b['p']):.6g}], {b['n_points']} points, {sum(not s for s in b['stable'])} unstable; "
              + "; ".join(f"{e['kind']} at {key} = {e['p']:.8g}" for e in b["events"])
              + f"; stopped: {b['stopped']}")
    return 0


def _branch_dict(br):
    """A branch's JSON: `Branch.as_dict` and the whirl amplitude at each point."""
    return {**br.as_dict(), "whirl_amplitude": np.linalg.norm(br.u[:, :2], axis=1).tolist()}


def _switched(F, br, bounds, args, key):
    """`--switch`: `[(event, branch)]`, the branch crossing `br` at each of its refined
    branch points, traced over the same range. A branch point located to the step
    only is reported and not switched at; a crossing branch that does not start is
    a numerical failure (exit 3)."""
    import warnings

    from rotorjax.analysis import switch_branch
    from .._errors import PlausibilityWarning

    out = []
    for e in br.events:
        if e.kind != "branch_point":
            continue
        if e.tangent is None:
            warnings.warn(f"--switch: the branch point at {key} = {e.p:.8g} was not switched at: {e.note}",
                          PlausibilityWarning)
            continue
        try:
            other = switch_branch(F, e, p_bounds=bounds, ds=args.ds, ds_max=args.ds_max,
                                  max_points=args.max_points, name=key, progress=not args.json)
        except ValueError as err:
            raise NumericalError(f"--switch: the branch crossing at {key} = {e.p:.8g} did not start: {err}; "
                                 "give a smaller --ds") from None
        out.append((e, other))
    return out
