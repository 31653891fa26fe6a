"""`bifurcation`: an extrema diagram over a swept parameter (one batch of runs: each
run advances by its own adaptive steps, `rotorjax.solve.simulate_batch`)."""

import json
import math

import numpy as np

from ._common import InputError, build, grid_spec, out_stem, prepare_out, preset_and_params, write_json


def auto_chunk(n, rounds=8, most=16):
    """Lanes per vmapped call: at most `most`, and small enough that the progress
    bar advances `rounds` times."""
    return max(1, min(most, math.ceil(n / rounds)))


def cmd_bifurcation(args) -> int:
    import equinox as eqx
    import jax.numpy as jnp

    from rotorjax.analysis._summary import precession_diagram, speeds_at
    from rotorjax.models import leaf_at
    from rotorjax.plot import plot_bifurcation
    from rotorjax.solve import IVP
    from rotorjax.sweep import sweep

    from ._common import save_figure

    preset, params = preset_and_params(args, "bifurcation")
    key, lo, hi, n = grid_spec("--param", args.param, preset, params, allowed=tuple(preset.sweepable))
    base = build(preset, params)
    events = bool(base.extras.get("events"))
    if events and args.batch not in ("auto", "buffered"):
        raise InputError("--set events=1: event-located contact runs in the buffered batch; drop --batch "
                         f"{args.batch}")
    path = preset.sweepable[key]   # a path into the scene (`rotorjax.models.leaf_at`), or a function of it
    where = (lambda s: leaf_at(s, path)) if isinstance(path, str) else path
    try:
        where(base.scene)
    except InputError as e:
        raise InputError(f"--param {key}: {e}") from None
    build(preset, dict(params, **{key: lo}))  # validates the range's ends
    build(preset, dict(params, **{key: hi}))
    prepare_out(args.out)
    revolutions = base.extras["revolutions"]
    n_save = int(base.extras.get("saves_per_revolution", 40) * revolutions)
    solver = "dopri8" if args.solver == "auto" else args.solver
    scene0, y0 = base.scene, base.y0

    def run(p):
        scene = eqx.tree_at(where, scene0, jnp.broadcast_to(p[key], jnp.shape(where(scene0))))
        t1 = 2 * jnp.pi / scene.speed.speed(0.0) * revolutions  # a span per point when N is swept
        return IVP(scene, y0, (0.0, t1), saveat=n_save, solver=solver, rtol=args.rtol, atol=args.atol,
                   max_steps=args.max_steps, events=events)

    values = np.linspace(lo, hi, n)
    chunk = args.chunk or auto_chunk(n)
    res = sweep(run, {key: values}, chunk_size=chunk, progress=not args.json and n > chunk, batch=args.batch,
                lanes=args.lanes)
    r = res.values
    lanes = {"ts": r.ts, "x": r.outputs["disk_x"], "y": r.outputs["disk_y"], "vx": r.outputs["disk_vx"],
             "vy": r.outputs["disk_vy"], "code": r.code}
    speed = float(speeds_at(scene0, [0.0])[0])
    speeds = values if key == preset.speed_key else np.full(n, speed)
    rows, extrema, lams, switches = precession_diagram(key, values, lanes, speeds, revolutions,
                                                       base.extras.get("analysis_revolutions", 300))
    stem = out_stem(args.out, preset, "bifurcation_", f"_{key}")
    save_figure(plot_bifurcation(values, extrema, lams, param=key,
                                 title=f"{preset.name}: extrema of disk x vs {key} ({preset.speed_key} = "
                                       f"{params[preset.speed_key]:g}, {revolutions} revolutions)"), stem + ".png")
    failed = sum(r["code"] != 0 for r in rows)
    steps = np.asarray(r.stats["num_steps"])
    out = {"preset": preset.name, "param": key, "params": params, "points": rows,
           "batch": {"method": r.solver.partition("+")[2] or args.batch, "solver": r.solver,
                     "steps_mean": float(steps.mean()), "steps_max": int(steps.max()),
                     **({"events": [int(e) for e in np.asarray(r.stats["num_events"])]} if events else {})},
           "Lambda_sign_switches": switches, "failed_points": failed,
           "files": {"plot": stem + ".png", "data": stem + ".json"}}
    write_json(stem + ".json", out, indent=2)
    if args.json:
        print(json.dumps(out, indent=2))
    else:
        for r in rows:
            lam = f"failed (code {r['code']})" if r["mean_Lambda"] is None else f"<Lambda> = {r['mean_Lambda']:+.4f}"
            print(f"  {key} = {r[key]:.6g}: {lam}")
        print("  <Lambda> changes sign near " + (", ".join(f"{s:.6g}" for s in switches) or "nowhere")
              + f"; wrote {stem}.png")
        if failed:
            print(f"  {failed} of {n} points failed (raise --max-steps, or loosen --rtol)")
    return 0 if not failed else 3
