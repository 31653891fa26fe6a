"""The `rotorjax` command: a thin layer over the public functions."""

import argparse
import json
import os
import sys
import time

import numpy as np


class UsageError(ValueError):
    pass


def _parse_sets(items):
    out = {}
    for item in items or ():
        if "=" not in item:
            raise UsageError(f"--set expects key=value, got {item!r}")
        key, value = item.split("=", 1)
        out[key.strip()] = value.strip()
    return out


def _speed_at(scene, ts):
    import jax

    return np.asarray(jax.vmap(scene.speed.speed)(np.asarray(ts)))


def summarize(result, scene, params, preset_name, t_end, revolutions=5) -> dict:
    """The JSON summary of one simulation. After a failure, the values describe the
    last valid saved state (`last_valid_time`), and `success` is false."""
    ts = np.asarray(result.ts)
    valid = np.isfinite(ts) & np.all(np.isfinite(np.asarray(result.ys)), axis=-1)
    summary = {
        "preset": preset_name,
        "params": params,
        "t_end": float(t_end),
        "success": bool(result.success),
        "code": int(result.code),
        "message": result.message,
        "solver": result.solver,
        "stats": {k: int(v) for k, v in result.stats.items()},
        "revolutions_in_window": revolutions,
    }
    if not valid.any():
        summary["last_valid_time"] = None
        return summary
    ts = ts[valid]
    amp = np.asarray(result.outputs["whirl_amplitude"])[valid]
    speed_end = abs(float(_speed_at(scene, ts[-1:])[0]))
    window = revolutions * 2 * np.pi / speed_end if speed_end > 0 else ts[-1] - ts[0]
    last = ts >= ts[-1] - window
    summary.update({
        "last_valid_time": float(ts[-1]),
        "final_whirl_amplitude": float(amp[-1]),
        "max_whirl_amplitude_last_revolutions": float(np.max(amp[last])),
        "final_speed": speed_end,
        "residual_imbalance_final": float(np.asarray(result.outputs["residual_imbalance"])[valid][-1]),
    })
    if "weight_angles" in result.outputs:
        summary["weight_angles_final"] = [
            float(a) for a in np.asarray(result.outputs["weight_angles"])[valid][-1]
        ]
    return summary


def cmd_simulate(args) -> int:
    import rotorjax as rj
    from rotorjax import presets
    from rotorjax.plot import plot_simulation

    preset = presets.get(args.preset)
    params = preset.params(_parse_sets(args.set))
    scene, y0, t_end = preset.build(params)
    if args.t_end is not None:
        if not args.t_end > 0:
            raise UsageError(f"--t-end must be > 0, got {args.t_end}")
        t_end = args.t_end
    result = rj.simulate(scene, y0, (0.0, t_end), saveat=args.n_save, solver=args.solver,
                         rtol=args.rtol, atol=args.atol, max_steps=args.max_steps)
    summary = summarize(result, scene, params, preset.name, t_end)
    os.makedirs(args.out, exist_ok=True)
    stem = os.path.join(args.out, preset.name)
    run_up = bool(params.get("nu_dot", 0) or params.get("n_dot", 0))
    speed = _speed_at(scene, result.ts) if run_up else None
    plot_simulation(result, stem + ".png", title=f"{preset.name}: {preset.source}", speed=speed,
                    x_label=("speed" if run_up else "time") + f" (time unit {preset.time_unit})")
    np.savez(stem + ".npz", ts=np.asarray(result.ts), ys=np.asarray(result.ys),
             **{k: np.asarray(v) for k, v in result.outputs.items()})
    summary["files"] = {"plot": stem + ".png", "data": stem + ".npz", "summary": stem + ".json"}
    with open(stem + ".json", "w") as f:
        json.dump(summary, f, indent=2)
    if args.json:
        print(json.dumps(summary, indent=2))
    else:
        print(f"{preset.name}: {summary['message']} ({summary['solver']}, "
              f"{summary['stats']['num_steps']} steps)")
        if summary["last_valid_time"] is None:
            print("  no valid saved state")
            return 3
        print(f"  final whirl amplitude {summary['final_whirl_amplitude']:.6g}, max over last "
              f"{summary['revolutions_in_window']} revolutions "
              f"{summary['max_whirl_amplitude_last_revolutions']:.6g}")
        if "weight_angles_final" in summary:
            print("  weight angles rel. rotor (rad): "
                  + ", ".join(f"{a:.4f}" for a in summary["weight_angles_final"]))
        print(f"  wrote {stem}.png, .npz, .json")
    return 0 if summary["success"] else 3


def cmd_presets(args) -> int:
    from rotorjax import presets

    for p in presets.PRESETS.values():
        print(f"{p.name}: {p.source}")
        for k, v in p.defaults.items():
            print(f"  {k} = {v}    {p.describe_params.get(k, '')}")
    return 0


def cmd_demo(args) -> int:
    from rotorjax.demo import run_demo

    run_demo(args.out)
    return 0


def build_parser():
    parser = argparse.ArgumentParser(prog="rotorjax", description=__doc__)
    sub = parser.add_subparsers(dest="command", required=True)

    sim = sub.add_parser("simulate", help="simulate a preset scene")
    sim.add_argument("preset")
    sim.add_argument("--set", action="append", metavar="KEY=VALUE",
                     help="override a dimensionless parameter (repeatable)")
    sim.add_argument("--t-end", type=float, default=None)
    sim.add_argument("--out", default="rotorjax-out")
    sim.add_argument("--json", action="store_true", help="print a JSON summary to stdout")
    sim.add_argument("--solver", default="auto")
    sim.add_argument("--rtol", type=float, default=1e-8)
    sim.add_argument("--atol", type=float, default=1e-10)
    sim.add_argument("--max-steps", type=int, default=500_000)
    sim.add_argument("--n-save", type=int, default=4000)
    sim.set_defaults(fn=cmd_simulate)

    demo = sub.add_parser("demo", help="a short representative study with plots")
    demo.add_argument("--out", default="rotorjax-out")
    demo.set_defaults(fn=cmd_demo)

    pre = sub.add_parser("presets", help="list presets and their parameters")
    pre.set_defaults(fn=cmd_presets)
    return parser


def main(argv=None) -> int:
    parser = build_parser()
    args = parser.parse_args(argv)
    try:
        return args.fn(args)
    except (ValueError, UsageError) as e:
        print(f"rotorjax: error: {e}", file=sys.stderr)
        return 2


if __name__ == "__main__":
    sys.exit(main())
