"""`bifurcation`: model 004's extrema diagram over a swept parameter (vmapped)."""

import json
import math
import os

import numpy as np

from ._common import InputError, build, grid_spec, preset_and_params, prepare_out, write_json
from ._simulate import window

#: Parameters `bifurcation` can sweep, and where each sits in the scene.
SWEEPABLE = ("eps", "N", "phase", "f_S", "chi", "kappa", "eta_S")


def _where(key):
    return {"eps": lambda s: s.eps, "N": lambda s: s.N, "phase": lambda s: s.phase,
            "f_S": lambda s: s.limiters.friction, "chi": lambda s: s.limiters.clearance,
            "kappa": lambda s: s.limiters.stiffness, "eta_S": lambda s: s.limiters.damping}[key]


def auto_chunk(n, rounds=8, most=16):
    """Lanes per vmapped call: at most `most`, and small enough that the progress
    bar advances `rounds` times."""
    return max(1, min(most, math.ceil(n / rounds)))


def cmd_bifurcation(args) -> int:
    import equinox as eqx
    import jax.numpy as jnp

    import rotorjax as rj
    from rotorjax.analysis import precession
    from rotorjax.plot import plot_bifurcation
    from rotorjax.sweep import sweep

    preset, params = preset_and_params(args, "bifurcation", "contact")
    key, lo, hi, n = grid_spec("--param", args.param, preset, params, allowed=SWEEPABLE)
    if params["events"]:
        raise InputError("--set events=1: bifurcation sweeps use the smoothed contact (events=0); the "
                         "event-located contact runs one point at a time (`simulate --set events=1`)")
    base, y0, t_end = build(preset, params)
    if key in ("f_S", "chi", "kappa", "eta_S") and base.limiters is None:
        raise InputError(f"--param {key}: needs limiters (--set n_limiters=0 removed them)")
    build(preset, dict(params, **{key: lo}))  # validates the range's ends
    build(preset, dict(params, **{key: hi}))
    prepare_out(args.out)
    n_save = int(40 * params["revolutions"])
    where = _where(key)
    solver = "dopri8" if args.solver == "auto" else args.solver

    def run(p):
        scene = eqx.tree_at(where, base, jnp.broadcast_to(p[key], jnp.shape(where(base))))
        t1 = 2 * jnp.pi / scene.N * params["revolutions"]
        r = rj.simulate(scene, y0, (0.0, t1), saveat=n_save, solver=solver, rtol=args.rtol, atol=args.atol,
                        max_steps=args.max_steps)
        o = r.outputs
        return {"ts": r.ts, "x": o["disk_x"], "y": o["disk_y"], "vx": o["disk_vx"], "vy": o["disk_vy"],
                "code": r.code}

    values = np.linspace(lo, hi, n)
    chunk = args.chunk or auto_chunk(n)
    res = sweep(run, {key: values}, chunk_size=chunk, progress=not args.json and n > chunk)
    v = res.values
    rows, extrema, lams = [], [], []
    for i, val in enumerate(values):
        code = int(np.asarray(v["code"])[i])
        speed = params["N"] if key != "N" else val
        t_end_i = 2 * np.pi / speed * params["revolutions"]
        if code != 0:
            rows.append({key: float(val), "code": code, "mean_Lambda": None})
            extrema.append(np.zeros(0))
            lams.append(np.nan)
            continue
        pr = precession(np.asarray(v["ts"])[i], np.asarray(v["x"])[i], np.asarray(v["y"])[i],
                        np.asarray(v["vx"])[i], np.asarray(v["vy"])[i], speed,
                        window=window(dict(params, N=speed), t_end_i))
        rows.append({key: float(val), "code": 0, "mean_Lambda": pr.mean, "direction": pr.direction,
                     "extrema_x": [float(pr.extrema_x.min()), float(pr.extrema_x.max())] if pr.extrema_x.size
                     else None})
        extrema.append(pr.extrema_x)
        lams.append(pr.mean)
    lams = np.asarray(lams)
    switches = [0.5 * (values[i] + values[i + 1]) for i in range(n - 1)
                if np.isfinite(lams[i]) and np.isfinite(lams[i + 1]) and np.sign(lams[i]) != np.sign(lams[i + 1])]
    stem = os.path.join(args.out, f"bifurcation_{preset.name}_{key}")
    plot_bifurcation(values, extrema, lams, stem + ".png", key,
                     title=f"{preset.name}: extrema of disk x vs {key} (N = {params['N']:g}, "
                           f"{params['revolutions']} revolutions)")
    failed = sum(r["code"] != 0 for r in rows)
    out = {"preset": preset.name, "param": key, "params": params, "points": rows,
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
