"""Model 004 with limiters: one run and an eccentricity sweep, rotorjax vs scipy.

(a) The base case (`cantilever-limiters` defaults: N = 15, eps = 0.00142, kappa = 850,
6 modes) over 300 revolutions: rotorjax smoothed contact (Dopri8, and Kvaerno5 as
the implicit option), rotorjax event-located contact (Dopri8 + diffrax events),
scipy Radau and LSODA on the same smoothed equations in numpy
(`tests/reference/model_004.py`), over a tolerance ladder that starts at
rtol = atol = 1e-7 (the paper's ode23t setting). Accuracy: the motion with contact is
chaotic (errors grow about 1.4x per revolution), so a run's error is the
disk-position error after 5 revolutions (the run starts with a kick that brings
the disk to the limiters in the first revolution: several contacts) against rotorjax Dopri8 at rtol
1e-12 (whose own uncertainty, against rtol 1e-13, is reported); `<Lambda>` and the
maximum disk x over the last 150 revolutions are reported too. The ratio at
matched accuracy interpolates each scipy method's time at rotorjax's error
(log-log in its ladder).
(b) A 64-point eccentricity sweep (eps in [0, 0.002], 300 revolutions, smoothed
contact, rotorjax at rtol 1e-7) in vmapped calls vs a scipy LSODA loop at the
tolerance that matches rotorjax's error, timed on a subset and extrapolated.

(c) The full FE model (all 32 dofs) against the 6-mode reduction, 50 revolutions:
the stiffness ratio, the solver "auto" picks, Dopri8 and Kvaerno5 on each.

Run: python benchmarks/limiters.py; writes benchmarks/results/limiters.json.
"""

import argparse
import json
import os
import sys
import time

import numpy as np
from scipy.integrate import solve_ivp

sys.path.insert(0, os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
from _common import machine, timed, write_results  # noqa: E402


def _with_ratio(d):
    d["ratio"] = d.get("seconds", d.get("seconds_at_least")) / d["rotorjax_seconds"]
    return d


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--revolutions", type=int, default=300)
    ap.add_argument("--n-sweep", type=int, default=64)
    ap.add_argument("--scipy-sweep", type=int, default=3)
    args = ap.parse_args()

    import equinox as eqx
    import jax
    import jax.numpy as jnp

    import rotorjax as rj
    from rotorjax.analysis import precession
    from rotorjax.presets import cantilever_limiters as cl
    from rotorjax.solve import simulate_events
    from tests.reference.model_004 import NumpyModel004

    # a kick that brings the disk to the limiters in the first revolution, so that
    # the accuracy measure (after 5 revolutions) covers contact
    p = dict(cl.PRESET.defaults, perturbation=0.02)
    scene = cl.build_scene(p)
    y0 = cl.initial_state(scene, p)
    N = p["N"]
    T = 2 * np.pi / N * args.revolutions
    n_save = 40 * args.revolutions
    ts = np.linspace(0, T, n_save)
    t20 = 2 * np.pi / N * 5
    ref20 = rj.simulate(scene, y0, (0.0, t20), saveat=None, solver="dopri8", rtol=1e-12, atol=1e-15,
                        max_steps=10**7)
    ref13 = rj.simulate(scene, y0, (0.0, t20), saveat=None, solver="dopri8", rtol=1e-13, atol=1e-16,
                        max_steps=10**7)
    disk = np.asarray(scene.disk[:2])
    pos_ref = disk @ np.asarray(ref20.ys[-1])[: scene.n_coords]
    ref_uncertainty = float(np.linalg.norm(disk @ np.asarray(ref13.ys[-1])[: scene.n_coords] - pos_ref)
                            / np.linalg.norm(pos_ref))

    def stats(ts_, ys):
        q = ys[:, : scene.n_coords]
        qd = ys[:, scene.n_coords: 2 * scene.n_coords]
        x, y = q @ disk.T[:, 0], q @ disk.T[:, 1]
        vx, vy = qd @ disk.T[:, 0], qd @ disk.T[:, 1]
        pr = precession(ts_, x, y, vx, vy, N, window=(0.5, 1.0))
        return {"mean_Lambda": pr.mean, "max_disk_x": float(x[ts_ >= ts_[-1] / 2].max())}

    def err20(y_end):
        return float(np.linalg.norm(disk @ np.asarray(y_end)[: scene.n_coords] - pos_ref) / np.linalg.norm(pos_ref))

    runs = {}
    for tol in (1e-7, 1e-9):
        for name, make in (
            ("rotorjax_smooth_dopri8", lambda tt, tol=tol: rj.simulate(
                scene, y0, (0.0, tt), saveat=n_save if tt == T else None, solver="dopri8", rtol=tol,
                atol=tol, max_steps=10**7)),
            ("rotorjax_smooth_kvaerno5", lambda tt, tol=tol: rj.simulate(
                scene, y0, (0.0, tt), saveat=n_save if tt == T else None, solver="kvaerno5", rtol=tol,
                atol=tol, max_steps=10**7)),
            ("rotorjax_events_dopri8", lambda tt, tol=tol: simulate_events(
                scene, y0, (0.0, tt), saveat=n_save if tt == T else 2, rtol=tol, atol=tol)),
        ):
            t_run, res = timed(lambda: make(T), repeats=1 if "kvaerno" in name else 3)
            short = make(t20)
            runs[f"{name}_rtol{tol:g}"] = {
                "seconds": t_run, "success": bool(res.success), "steps": int(res.stats["num_steps"]),
                "rejected": int(res.stats["num_rejected_steps"]),
                **({"events": int(res.stats["num_events"])} if "num_events" in res.stats else {}),
                "error_after_5_revolutions": err20(short.ys[-1]),
                **stats(np.asarray(res.ts), np.asarray(res.ys))}
            print(name, tol, runs[f"{name}_rtol{tol:g}"], flush=True)
    model = NumpyModel004(scene)
    ladders = {"Radau": (1e-7, 1e-9), "LSODA": (1e-7, 1e-9, 1e-11, 1e-12)}
    for method, tols in ladders.items():
        for tol in tols:
            t0 = time.perf_counter()
            sol = solve_ivp(model, (0.0, T), np.asarray(y0), method=method, rtol=tol, atol=tol, t_eval=ts)
            t_run = time.perf_counter() - t0
            short = solve_ivp(model, (0.0, t20), np.asarray(y0), method=method, rtol=tol, atol=tol)
            runs[f"scipy_{method}_rtol{tol:g}"] = {
                "seconds": t_run, "success": bool(sol.success), "rhs_evaluations": int(sol.nfev),
                "error_after_5_revolutions": err20(short.y[:, -1]), **stats(sol.t, sol.y.T)}
            print(method, tol, runs[f"scipy_{method}_rtol{tol:g}"], flush=True)

    def matched(method, ours):
        """scipy's time interpolated (log-log) at rotorjax's error; None if outside its ladder."""
        pts = sorted((runs[f"scipy_{method}_rtol{t:g}"]["error_after_5_revolutions"],
                      runs[f"scipy_{method}_rtol{t:g}"]["seconds"]) for t in ladders[method])
        e, c = np.log([p[0] for p in pts]), np.log([p[1] for p in pts])
        target = np.log(runs[ours]["error_after_5_revolutions"])
        if target < e.min():
            return {"seconds_at_least": float(np.exp(c[0])), "note": "scipy's ladder does not reach this error"}
        if target > e.max():
            return {"seconds": float(np.exp(c[-1])), "note": "scipy's loosest run is already this accurate"}
        return {"seconds": float(np.exp(np.interp(target, e, c)))}

    # (c) what the modal reduction buys: the full FE model (32 dofs) is stiff (Voigt
    # damping of the high shaft modes), so "auto" picks the implicit Kvaerno5
    from rotorjax.solve import choose_solver, stiffness_ratio

    full_p = dict(p, n_modes=0)
    full = cl.build_scene(full_p)
    yf = cl.initial_state(full, full_p)
    t50 = 2 * np.pi / N * 50
    full_runs = {"stiffness_ratio_full": stiffness_ratio(full, yf), "auto_full": type(choose_solver(full, yf)).__name__,
                 "stiffness_ratio_reduced": stiffness_ratio(scene, y0),
                 "auto_reduced": type(choose_solver(scene, y0)).__name__, "revolutions": 50}
    for label, sc, yy in (("reduced_6_modes", scene, y0), ("full_fe", full, yf)):
        for solver in ("dopri8", "kvaerno5"):
            t_run, res = timed(lambda: rj.simulate(sc, yy, (0.0, t50), saveat=2000, solver=solver, rtol=1e-7,
                                                    atol=1e-7, max_steps=10**7), repeats=1)
            full_runs[f"{label}_{solver}"] = {"seconds": t_run, "steps": int(res.stats["num_steps"]),
                                              "success": bool(res.success)}
    print(full_runs, flush=True)

    # (b) eccentricity sweep
    eps = np.linspace(0.0, 0.002, args.n_sweep)

    def one(e):
        s = eqx.tree_at(lambda s: s.eps, scene, e)
        r = rj.simulate(s, y0, (0.0, T), saveat=n_save, solver="dopri8", rtol=1e-7, atol=1e-7, max_steps=10**7)
        o = r.outputs
        return o["disk_x"], o["disk_y"], o["disk_vx"], o["disk_vy"], r.code

    # vmapped calls of 16 lanes: adaptive lanes run in lock-step, so a few smaller
    # calls beat one of 64 (measured: 6.6 s vs 8.7 s)
    sweep_fn = jax.jit(jax.vmap(one))

    def sweep_all():
        parts = [sweep_fn(jnp.asarray(eps[i:i + 16])) for i in range(0, len(eps), 16)]
        return [jnp.concatenate(a) for a in zip(*parts)]
    t_sweep, (x, y, vx, vy, code) = timed(sweep_all, repeats=1)
    lams = [precession(ts, *(np.asarray(a)[i] for a in (x, y, vx, vy)), N, window=(0.5, 1.0)).mean
            for i in range(len(eps))]
    # scipy LSODA's tolerance at rotorjax's (rtol 1e-7) error, from its ladder
    target = runs["rotorjax_smooth_dopri8_rtol1e-07"]["error_after_5_revolutions"]
    sweep_tol = max([t for t in ladders["LSODA"] if runs[f"scipy_LSODA_rtol{t:g}"]["error_after_5_revolutions"]
                     <= target] or [min(ladders["LSODA"])])
    t0 = time.perf_counter()
    for e in eps[: args.scipy_sweep]:
        m = NumpyModel004(eqx.tree_at(lambda s: s.eps, scene, jnp.float64(e)))
        solve_ivp(m, (0.0, T), np.asarray(y0), method="LSODA", rtol=sweep_tol, atol=sweep_tol, t_eval=ts)
    t_scipy_each = (time.perf_counter() - t0) / args.scipy_sweep
    switch = [float(0.5 * (eps[i] + eps[i + 1])) for i in range(len(eps) - 1) if np.sign(lams[i]) != np.sign(lams[i + 1])]

    base = runs["rotorjax_smooth_dopri8_rtol1e-07"]["seconds"]
    out = {
        "benchmark": "model 004 limiters",
        "machine": machine(),
        "versions": {"jax": jax.__version__},
        "setup": {"revolutions": args.revolutions, "N": N, "eps": p["eps"], "kappa": p["kappa"],
                  "perturbation": p["perturbation"],
                  "n_modes": p["n_modes"], "smoothing": p["smoothing"], "saved_states": n_save},
        "single_run": runs,
        "reference_uncertainty_after_5_revolutions": ref_uncertainty,
        "ratios_single_run_same_tolerance_1e-7": {
            "scipy_Radau_over_rotorjax_smooth": runs["scipy_Radau_rtol1e-07"]["seconds"] / base,
            "scipy_LSODA_over_rotorjax_smooth": runs["scipy_LSODA_rtol1e-07"]["seconds"] / base,
            "scipy_LSODA_over_rotorjax_events": runs["scipy_LSODA_rtol1e-07"]["seconds"]
            / runs["rotorjax_events_dopri8_rtol1e-07"]["seconds"],
        },
        "matched_accuracy": {
            ours: {m: _with_ratio({**matched(m, ours), "rotorjax_seconds": runs[ours]["seconds"],
                                   "error": runs[ours]["error_after_5_revolutions"]}) for m in ladders}
            for ours in ("rotorjax_smooth_dopri8_rtol1e-07", "rotorjax_smooth_dopri8_rtol1e-09",
                         "rotorjax_events_dopri8_rtol1e-07")},
        "reduction_and_stiffness": full_runs,
        "sweep": {"n": args.n_sweep, "rotorjax_s": t_sweep, "rotorjax_s_per_point": t_sweep / args.n_sweep,
                  "failed": int(np.sum(np.asarray(code) != 0)), "scipy_LSODA_s_per_point": t_scipy_each,
                  "scipy_subset": args.scipy_sweep, "scipy_rtol": sweep_tol,
                  "ratio": t_scipy_each * args.n_sweep / t_sweep,
                  "eps": eps.tolist(), "mean_Lambda": lams, "Lambda_sign_switch_eps": switch},
    }
    print(json.dumps({k: v for k, v in out.items() if k not in ("machine",)}, indent=1)[:4000])
    write_results("limiters", out)


if __name__ == "__main__":
    main()
