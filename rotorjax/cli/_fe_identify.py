"""`identify` on a rotor file: its bearing (support, disk, unbalance) parameters
fitted to a phasor file."""

import json
import os

from ._common import InputError, NumericalError, prepare_out, preset_and_params, write_json

#: the dataset a shipped rotor file is identified from when --data is not given
DEFAULT_DATA = {"flexible_rig.toml": "flexible-runup"}


def names(option, text):
    """A comma-separated list of names (no empty ones)."""
    out = [s.strip() for s in text.split(",")]
    if not text.strip() or any(not s for s in out):
        raise InputError(f"{option} {text!r}: expected comma-separated names, e.g. bearing0.kxx,bearing0.kyy")
    return out


def nodes(option, text):
    out = []
    for s in text.split(","):
        s = s.strip()
        try:
            v = int(s)
        except ValueError:
            raise InputError(f"{option} {text!r}: expected comma-separated node numbers, e.g. 2,4") from None
        if v < 0:
            raise InputError(f"{option} {text!r}: node {v} is negative")
        out.append(v)
    return out


def default_fit(model):
    """Every stiffness and damping coefficient the file gives for its constant bearings."""
    return [n for n in model.fittable
            if n.startswith("bearing") and n.split(".")[1] in ("kxx", "kyy", "cxx", "cyy") and n in model.entries]


def cmd_fe_identify(args) -> int:
    from rotorjax.identify import identify
    from rotorjax.identify._fe_params import rotor_model
    from rotorjax.plot import plot_fe_identification
    from ._common import save_figure

    preset, params = preset_and_params(args, "identify")
    path = preset.name
    model = rotor_model(path, {k: v for k, v in params.items() if v != preset.defaults.get(k)})
    data = args.data or DEFAULT_DATA.get(os.path.basename(path))
    if data is None:
        raise InputError(f"identify {preset.name}: give the measurements with --data FILE (a phasor file: speed, "
                         "node, direction, real, imag)")
    fit = names("--fit", args.fit) if args.fit else default_fit(model)
    if args.fit_unbalance in (None, False):
        fit_unbalance = []
    elif args.fit_unbalance is True:
        raise InputError("--fit-unbalance: name the nodes of the unbalances to fit on a rotor file, e.g. "
                         "--fit-unbalance 2,4")
    else:
        fit_unbalance = nodes("--fit-unbalance", args.fit_unbalance)
    prepare_out(args.out)
    res = identify(model, data, fit, fit_unbalance=fit_unbalance, weights=args.weights,
                   covariance=args.covariance, n_starts=args.starts, spread=args.spread, method=args.method)
    out = {"rotor": preset.name, "data": res.data.path, "fit": list(res.names),
           "fit_unbalance": fit_unbalance, "start": {k: model.parameters([k])[0].start for k in res.names},
           **res.as_dict()}
    stem = os.path.join(args.out, "identify_" + os.path.splitext(os.path.basename(path))[0])
    save_figure(plot_fe_identification(result=res, title=f"{preset.name}: fit of {len(res.names)} parameter(s) "
                                                         f"to {os.path.basename(res.data.path)}"), stem + ".png")
    out["files"] = {"plot": stem + ".png", "json": stem + ".json"}
    write_json(stem + ".json", out)
    if not all(map(_finite, res.estimates.values())):
        raise NumericalError("identify: non-finite estimates")
    if args.json:
        print(json.dumps(out, indent=2))
    else:
        print(f"{preset.name}: {len(res.names)} parameter(s) fitted to {res.data.n} phasors of {res.data.path} "
              f"({res.n_starts} starts)")
        for k in res.names:
            lo, hi = res.intervals[k]
            print(f"  {k} = {res.estimates[k]:.6g}   95% [{lo:.6g}, {hi:.6g}]")
        for u in res.unbalance_table:
            print(f"  unbalance at node {u['node']}: {u['magnitude']:.4g} kg m at {u['phase']:.4f} rad   "
                  f"95% [{u['magnitude_ci95'][0]:.4g}, {u['magnitude_ci95'][1]:.4g}] kg m")
        for c in res.critical_speeds:
            print(f"  critical speed {c['speed']:.4f} rad/s   95% [{c['ci95'][0]:.4f}, {c['ci95'][1]:.4f}]")
        print(f"  residual rms {res.rms_residual:.3g}")
        for w in res.warnings:
            print(f"  warning: {w}")
        print(f"  wrote {stem}.png and .json")
    return 0 if res.converged else 3


def _finite(v):
    return v == v and abs(v) != float("inf")
