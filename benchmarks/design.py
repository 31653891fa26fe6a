"""Design optimisation: the 8 bearing coefficients of ross_compare.toml for the
largest least log decrement over 0..1000 rad/s, `rotorjax.design` against scipy's
SLSQP on the same objective.

The case: `ross_compare.toml` (ROSS's example rotor) with its bearings given damping
(`cxx = cyy = 500 N s/m`); varied: kxx, kyy, cxx, cyy of both bearings, k in
[5e5, 5e6] N/m, c in [100, 2000] N s/m (both searched in their logarithms); the
objective: `min-log-dec` over 0..1000 rad/s (`n_modes=3`: the 4 modes below 430
rad/s counted), maximised, from the file's values. Why these bounds: in the region
where the counted modes stay in their band and none turns overdamped, the floor rises
with damping and with softer bearings, so the optimum is the soft, damped corner
(every parameter at a bound; the path to it is not trivial: the x and y modes take
turns as the least damped). Wider bounds reach the region where modes leave the band
or turn overdamped and the objective has kinks and jumps (`EXPLORED` lists what was
tried).

- rotorjax: `optimize_rotor(problem, n_starts=1)`, timed after a first call (the
  median of repeats). `minimize` traces and compiles its loops anew on every call,
  so each call pays that compilation; the same compiled loop is also built once
  (`rotorjax.design._optimize._run`, the body `minimize` compiles) and its run
  timed alone: what a call would cost if the compilation were reused.
- the peer: `scipy.optimize.minimize(method="SLSQP")` in the same scaled variables
  (`u` in [0, 1], logarithmic where `problem.log`), on the same objective
  `problem.fn(x(u))[0]` compiled once with `jax.jit` (the strongest objective a user
  could hand it), bounds [0, 1], the same start: gradients by scipy's finite
  differences (`jac=None`, its default step), the same with a larger step (the
  default step meets the floor's small jumps, see `fd_step_sweep`), and with
  the exact gradient (`jax.grad`, compiled once) to separate the optimiser from the
  gradient.

Times, objectives (unscaled, `problem.quantities(x)`), evaluations and the ratios
(SLSQP time / rotorjax time) are written to `results/design.json`.
"""

import argparse
import json
import os
import sys
import time

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from _common import CpuWatch, machine, timed_first, write_results  # noqa: E402

SETS = {"bearing0.cxx": 500.0, "bearing0.cyy": 500.0, "bearing1.cxx": 500.0, "bearing1.cyy": 500.0}
K_BOUNDS, C_BOUNDS = (5e5, 5e6), (100.0, 2000.0)
SPEED_RANGE, N_MODES = (0.0, 1000.0), 3
#: the larger finite-difference step (absolute, in the unit box) of the second SLSQP row
FD_STEP = 1e-4
#: the finite-difference steps tried (scipy's default first)
FD_STEPS = (1.4901161193847656e-08, 1e-6, 1e-5, 1e-4, 1e-3)
#: a method reached the optimum when its objective is within this (relative) of the best one's
REACHED = 1e-4

#: the bounds tried before these (all 8 coefficients, k and c ranges as given; SLSQP from the file's values)
EXPLORED = [
    {"k": [3e5, 3e6], "c": [100, 3000], "outcome": "optimum at the soft, damped corner (min-log-dec 1.499), but next "
     "to the region where a pair turns overdamped (least damped frequency 0.5 rad/s there): rotorjax not converged "
     "(projected gradient 1.8e-6 against tol 1e-6, its last subproblems ending with no acceptable step, 723 "
     "evaluations, ~50 s); SLSQP-FD stopped at 0.080. A nearby design (k = 3e5 / 2.4e5, c = 2913) gives a "
     "spurious floor of -148."},
    {"k": [3e5, 3e6], "c": [100, 3e4], "outcome": "a maximum at c ~ 5500 / 6400 with min-log-dec 2.699, reached by "
     "pushing the second mode pair (log dec 1.48 / 1.78) above the 430 rad/s cut, out of the count: not a design "
     "improvement; a pair overdamped below 1000 rad/s; the scaled objective jumps by 5.5e4 within 1e-3 of it; "
     "rotorjax not converged (projected gradient 0.73, no acceptable step, 1226 evaluations, ~77 s)."},
    {"k": [5e5, 5e6], "c": [100, 3e4], "outcome": "maximum at c ~ 9200 / 6900 (1.613): past the overdamped onset "
     "(c ~ 3000-5000 at k <= 1e6), same kinks as above."},
    {"k": [1e5, 1e7], "c": [100, 1e5], "outcome": "maximum 10.4 at near-rigid-body designs with overdamped modes: "
     "ill posed."},
    {"k": [5e5, 5e6], "c": [100, 3000], "outcome": "corner optimum (0.821), but the 4th and 5th modes' frequency "
     "bands overlap there (330 / 312 rad/s)."},
    {"k": [5e5, 5e6], "c": [100, 1000], "outcome": "clean: corner optimum 0.277 (counted modes <= 267 rad/s, the "
     "next >= 498 rad/s); SLSQP-FD with its default step stops at 0.077."},
    {"k": [5e5, 5e6], "c": [100, 2000], "outcome": "chosen: clean (counted modes <= ~290 rad/s, the least damped "
     "frequency >= 73 rad/s), corner optimum 0.552, a longer path than c <= 1000."},
    {"k": [5e5, 5e6], "c": [100, 3000], "constraint": "separation-margin >= 0, operating 400..600 rad/s",
     "outcome": "tried to make k interior (the separation margin of the 862 rad/s critical against softer "
     "bearings): SLSQP with exact gradients ended with the constraint inactive (margin 0.81) and bearing1.kyy at "
     "its upper bound (0.686), SLSQP-FD at 0.129: no meaningful comparison, dropped."},
]


def _unit_box(p):
    """`x(u)` (jax) and `u(x)` (numpy) of the problem's scaled variables (as `minimize` scales them)."""
    import jax.numpy as jnp

    log = np.asarray(p.log, bool)
    a = np.where(log, np.log(np.where(log, p.lo, 1.0)), p.lo)
    b = np.where(log, np.log(np.where(log, p.hi, 1.0)), p.hi)

    def to_x(u):
        z = a + (b - a) * u
        return jnp.where(log, jnp.exp(z), z)

    def to_u(x):
        return (np.where(log, np.log(np.where(log, x, 1.0)), x) - a) / (b - a)

    return to_x, to_u


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--smoke", action="store_true", help="tiny sizes, nothing written")
    args = ap.parse_args()
    import jax

    jax.config.update("jax_enable_x64", True)
    import jax.numpy as jnp
    import scipy
    import scipy.optimize as so

    from rotorjax.design import optimize_rotor, rotor_problem
    from rotorjax.io import read_rotor_file, shipped_rotor

    smoke = args.smoke
    repeats = 0 if smoke else 3
    tol, max_outer = 1e-6, (2 if smoke else 30)
    slsqp_opts = {"maxiter": 3} if smoke else {}
    watch = CpuWatch()
    file = read_rotor_file(str(shipped_rotor("ross_compare")), SETS)
    if smoke:   # two parameters, a coarse floor
        vary = {f"bearing{b}.cxx": C_BOUNDS for b in (0, 1)}
        extra = {"n_grid": 5}
    else:
        vary = {f"bearing{b}.{c}": (K_BOUNDS if c[0] == "k" else C_BOUNDS) for b in (0, 1)
                for c in ("kxx", "kyy", "cxx", "cyy")}
        extra = {}
    t0 = time.perf_counter()
    p = rotor_problem(file, vary, "min-log-dec", speed_range=SPEED_RANGE, n_modes=N_MODES, **extra)
    setup = time.perf_counter() - t0
    x0 = np.clip(p.nominal, p.lo, p.hi)
    q = jax.jit(p.quantities)
    scale = p.scales["min-log-dec"]

    def objective(x):
        return float(q(jnp.asarray(x))["min-log-dec"])

    # rotorjax: the whole call, as a user makes it
    t_rj, first_rj, d = timed_first(lambda: optimize_rotor(p, n_starts=1, tol=tol, max_outer=max_outer), repeats)
    o = d.optimum
    rj = {"seconds": t_rj, "first_call_s": first_rj, "objective": d.quantities_after["min-log-dec"],
          "objective_before": d.quantities_before["min-log-dec"], "converged": o.converged, "reason": o.reason,
          "outer_iterations": o.iterations, "inner_iterations": int(np.nansum(o.history[:, 4])),
          "evaluations": o.evaluations, "x": dict(zip(p.names, map(float, o.x)))}
    # the peer: SLSQP in the same unit box on the same jitted objective
    to_x, to_u = _unit_box(p)
    u0 = to_u(x0)
    f_jit = jax.jit(lambda u: p.fn(to_x(u))[0])
    g_jit = jax.jit(jax.grad(lambda u: p.fn(to_x(u))[0]))
    t0 = time.perf_counter()
    jax.block_until_ready((f_jit(jnp.asarray(u0)), g_jit(jnp.asarray(u0))))
    peer_compile = time.perf_counter() - t0
    # the cost of one evaluation (compiled): the objective, its gradient
    n_eval = 1 if smoke else 7
    t_f, _, _ = timed_first(lambda: f_jit(jnp.asarray(u0)), n_eval)
    t_g, _, _ = timed_first(lambda: g_jit(jnp.asarray(u0)), n_eval)

    def fun(u):
        return float(f_jit(jnp.asarray(u)))

    def jac(u):
        return np.asarray(g_jit(jnp.asarray(u)))

    bounds = [(0.0, 1.0)] * len(u0)

    def slsqp(**kw):
        opts = {**slsqp_opts, **kw.pop("options", {})}
        return so.minimize(fun, u0, method="SLSQP", bounds=bounds, options=opts, **kw)

    def row(t, first, r):
        x = np.asarray(to_x(jnp.asarray(r.x)))
        return {"seconds": t, "first_call_s": first, "objective": objective(x), "success": bool(r.success),
                "message": str(r.message), "iterations": int(r.nit), "nfev": int(r.nfev), "njev": int(r.njev),
                "x": dict(zip(p.names, map(float, x)))}

    peers = {
        "slsqp_fd": row(*timed_first(lambda: slsqp(), repeats)),
        f"slsqp_fd_step_{FD_STEP:g}": row(*timed_first(lambda: slsqp(options={"eps": FD_STEP}), repeats)),
        "slsqp_exact": row(*timed_first(lambda: slsqp(jac=jac), repeats)),
    }
    # how SLSQP-FD's end depends on its step (one run each)
    sweep = []
    for h in (FD_STEPS[:1] if smoke else FD_STEPS):
        t0 = time.perf_counter()
        r = slsqp(options={"eps": h})
        sweep.append({"step": h, "seconds": time.perf_counter() - t0, "objective": objective(to_x(jnp.asarray(r.x))),
                      "nfev": int(r.nfev), "success": bool(r.success)})

    # the floor at rotorjax's optimum under relative changes of the parameters far below any step (its jumps)
    signs = np.where(np.asarray(o.x) <= p.lo * (1 + 1e-9), 1.0, -1.0)   # into the box
    jitter = [{"relative_change": t, "objective": objective(np.asarray(o.x) * (1 + t * signs))}
              for t in (0.0, 1e-12, 1e-10, 1e-8, 1e-6)]

    best = max([rj["objective"]] + [v["objective"] for v in peers.values()])
    rj["reached_optimum"] = abs(rj["objective"] - best) <= REACHED * abs(best)
    for v in peers.values():
        v["reached_optimum"] = abs(v["objective"] - best) <= REACHED * abs(best)
        v["objective_minus_rotorjax"] = v["objective"] - rj["objective"]
    ratios = {f"{k}_over_rotorjax": v["seconds"] / t_rj for k, v in peers.items()}
    # the goal: SLSQP with finite differences to convergence, over rotorjax (the first FD row that converged)
    fd = next((k for k in ("slsqp_fd", f"slsqp_fd_step_{FD_STEP:g}") if peers[k]["reached_optimum"]), None)
    goal = {"target": 20.0, "peer": fd,
            "ratio_call": None if fd is None else ratios[f"{fd}_over_rotorjax"]}
    goal["met_by_call"] = goal["ratio_call"] is not None and goal["ratio_call"] >= 20
    out = {"benchmark": "optimize 8 bearing coefficients of ross_compare.toml (k, c of both bearings) for the "
                        "largest least log decrement over 0..1000 rad/s: rotorjax.design.optimize_rotor against "
                        "scipy SLSQP (finite-difference and exact gradients) on the same jitted objective, same "
                        "scaled variables, bounds and start",
           "machine": machine(), "jax": jax.__version__, "scipy": scipy.__version__,
           "case": {"rotor": "ross_compare", "sets": SETS, "objective": "min-log-dec (maximised)",
                    "speed_range": list(SPEED_RANGE), "n_modes": N_MODES, "settings": p.settings,
                    "objective_scale": scale,
                    "bounds": {n: [float(a), float(b)] for n, a, b in zip(p.names, p.lo, p.hi)},
                    "log_scaled": dict(zip(p.names, map(bool, p.log))),
                    "start": dict(zip(p.names, map(float, x0))),
                    "tol": tol, "max_outer": max_outer},
           "setup_s": setup, "objective_eval_ms": 1e3 * t_f, "gradient_eval_ms": 1e3 * t_g,
           "rotorjax": rj, "peer_compile_s": peer_compile, **peers, "fd_step_sweep": sweep,
           "ratios": ratios, "goal": goal, "objective_jitter_at_optimum": jitter, "repeats": repeats,
           "cpu": watch.report(), "explored": EXPLORED,
           "note": "times: median of repeats after a first call (rotorjax's search runs its loops on the host "
                   "around one compiled, cached evaluation of the objective, constraints and gradient, as SLSQP "
                   "does); SLSQP's default "
                   "finite-difference step (1.5e-8) meets the log-dec floor's jumps (1e-6 to 2e-4 absolute under "
                   "relative parameter changes down to 1e-12, objective_jitter_at_optimum: the Hermite "
                   "stationary-point candidates of a near-linear interval flip between its two end values and the "
                   "soft minimum counts every candidate), its gradients then point nowhere and it stops early "
                   "claiming success; with a 1e-4 step it converges"}

    def line(name, t, obj, evals, flag):
        print(f"  {name:<28} {t:9.3f} s  min-log-dec {obj:.6f}  {evals:<22} {flag}")

    print(json.dumps({k: out[k] for k in ("case", "ratios", "goal", "objective_jitter_at_optimum")}, indent=1))
    print(f"start: min-log-dec {rj['objective_before']:.6f}; one objective {1e3 * t_f:.1f} ms, its gradient "
          f"{1e3 * t_g:.1f} ms (compiled)")
    line("rotorjax optimize_rotor", t_rj, rj["objective"], f"{rj['evaluations']} evaluations",
         f"converged={rj['converged']} (first call {first_rj:.2f} s)")
    for k, v in peers.items():
        line(k, v["seconds"], v["objective"], f"nfev {v['nfev']} njev {v['njev']}",
             f"success={v['success']} reached optimum={v['reached_optimum']}")
    for s in sweep:
        print(f"  SLSQP-FD step {s['step']:.1e}: {s['seconds']:.2f} s, min-log-dec {s['objective']:.6f}, "
              f"nfev {s['nfev']}")
    if smoke:
        print("smoke run: nothing written")
        return
    write_results("design", out)


if __name__ == "__main__":
    main()
