"""Identification of the 8 bearing coefficients of a finite-element rotor from
200 measured 1x phasors: rotorjax's `identify` vs scipy.optimize.least_squares
with finite-difference Jacobians on the same problem, in the same run.

The problem: the shipped rotor file `flexible_rig` (7 nodes, 28 free dofs, two
anisotropic damped bearings at nodes 0 and 6) and the shipped dataset
`flexible-runup` (50 speeds x 4 sensors = 200 phasors, 1 % noise); fitted: kxx,
kyy, cxx, cyy of both bearings (`_make_fe_data.TRUTH`) and the unbalances at
nodes 2 and 4 (complex); relative weights (sigma = |X| floored at 1e-3 of the
largest, `_fe_identify._sigma`). A few seeded starts, each coefficient 2-5x off
the truth (up or down at random).

- rotorjax: the whole `identify(rotor_model(path, start), "flexible-runup",
  fit, fit_unbalance=(2, 4))` call (the rotor file read with the start as its
  overrides, the problem set up, the fit, covariance, 95 % intervals, the fitted
  rotor's critical speeds), with the default 32-start global search and with
  `n_starts=1` (a local fit); compiled first (its first calls reported apart).
- scipy: `least_squares(method="lm" | "trf", jac="2-point")` on the same residual
  in plain numpy: the FE matrices of the nominal rotor taken from rotorjax once
  (outside the timing), the bearing coefficients set at their dofs per parameter
  vector, one batched `numpy.linalg.solve` of `K - W^2 M + i W (C + W G1)` over the
  50 speeds with the two unit-unbalance loads; parameters: log-coefficients and
  the unbalances' real and imaginary parts (scaled by the start's unbalance), the
  unbalances started at their weighted linear least-squares values. Checked
  against rotorjax's `FEResidual` at the truth before timing. Local fits from the
  same starts, and (the global search's peer) scipy LM from each of the same 32
  starts rotorjax's global stage uses (`_engine.starts`) around the first
  random start, the best kept.
- rotorjax fit only (the same work as scipy's fits): `_fe_identify.problem` built once
  per random start outside the timing (its `rotor_model` as above), then
  `_engine.lm_batch(r, th0, center)` timed alone, `th0 = _engine.starts(center,
  params, n, 10.0)` with n = 1 (a local fit: scipy LM/TRF's peer) and n = 32 (scipy LM
  from the same 32 starts' peer); compiled first, then the median of repeats per start
  and the median over the starts. The whole call's time is also split into stages
  (rotor file read, problem set-up, fit, critical speeds, the rest: data read, optimum
  Jacobian, covariance, intervals, other minima) from timers around those functions.
- One residual + Jacobian evaluation of each: rotorjax `_lm._res_jac` (forward
  autodiff; the unbalances projected out: 400 x 8) and numpy residual + 2-point
  finite differences (400 x 12, as least_squares computes it).

"Converged to the truth": every coefficient within 5 % of the truth (the noise
gives ~0.6 %; a spurious minimum is off by factors). Times are medians (over the
starts; res+jac over repeats) after compilation.

Run: python benchmarks/fe_identification.py [--starts 3] [--smoke];
writes benchmarks/results/fe_identification.json (`--smoke`: one start, the
local fits only, one call per timing, prints and writes nothing).
"""

import argparse
import datetime
import json
import os
import sys
import time

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from _common import machine, timed, timed_first, write_results  # noqa: E402

FIT_UNBALANCE = (2, 4)
DATASET = "flexible-runup"
CONVERGED_REL = 0.05
WHOLE_CALL = ("whole identify call = rotor file read + problem set-up + fit + covariance/intervals + "
              "critical speeds with intervals")
SEED = 2024
TOL = 1e-10


def random_starts(truth, n, seed=SEED):
    """`n` starts: each coefficient `truth * f^(+-1)`, f uniform in log over [2, 5], the sign at random."""
    rng = np.random.default_rng(seed)
    out = []
    for _ in range(n):
        f = np.exp(rng.uniform(np.log(2.0), np.log(5.0), len(truth))) ** rng.choice([-1.0, 1.0], len(truth))
        out.append({k: float(v * ff) for (k, v), ff in zip(truth.items(), f)})
    return out


class NumpyModel:
    """The 1x unbalance response of the rows in plain numpy: the nominal rotor's
    reduced matrices with the fitted bearing coefficients replaced, one batched
    solve over the distinct speeds."""

    def __init__(self, rotor, data, fit, fit_unbalance, sigma):
        from rotorjax.models._fe_rotor import BEARING_COEFFICIENTS, DOFS_PER_NODE

        M, C, G1, K = (np.array(a) for a in rotor.reduced_matrices())
        free = {int(d): i for i, d in enumerate(np.asarray(rotor.free_dofs))}
        nominal = np.asarray(rotor.bearing_params)
        self.kpos, self.kidx, self.cpos, self.cidx = [], [], [], []
        for i, name in enumerate(fit):
            table, key = name.split(".")
            b = int(table[len("bearing"):])
            if key not in ("kxx", "kyy", "cxx", "cyy"):
                raise SystemExit(f"the numpy peer models direct bearing coefficients only, not {name}")
            pos = free[DOFS_PER_NODE * rotor.bearing_nodes[b] + (0 if key[1] == "x" else 1)]
            A = K if key[0] == "k" else C
            A[pos, pos] -= nominal[b, BEARING_COEFFICIENTS.index(key)]     # the nominal bearing out
            (self.kpos if key[0] == "k" else self.cpos).append(pos)
            (self.kidx if key[0] == "k" else self.cidx).append(i)
        self.kpos, self.kidx, self.cpos, self.cidx = (np.array(a, dtype=int) for a in
                                                      (self.kpos, self.kidx, self.cpos, self.cidx))
        self.K, self.C = K, C
        w, self.point = np.unique(data.speed, return_inverse=True)
        self.point = self.point.ravel()
        self.out = np.array([free[DOFS_PER_NODE * int(n) + int(d)] for n, d in zip(data.node, data.direction)])
        n = K.shape[0]
        self.F = np.zeros((w.size, n, len(fit_unbalance)), dtype=complex)
        for j, node in enumerate(fit_unbalance):       # unit unbalance: F_x = W^2, F_y = -i W^2
            self.F[:, free[DOFS_PER_NODE * node], j] = w**2
            self.F[:, free[DOFS_PER_NODE * node + 1], j] = -1j * w**2
        self.Zw = -(w**2)[:, None, None] * M[None] + 1j * (w**2)[:, None, None] * G1[None]   # -W^2 M + i W^2 G1
        self.iw = 1j * w[:, None, None]
        self.X, self.sigma = np.asarray(data.X), np.asarray(sigma)
        self.p, self.k = len(fit), len(fit_unbalance)

    def rows(self, values):
        """`(n_rows, n_unbalances)`: each row's response to a unit unbalance at each node."""
        K, C = self.K.copy(), self.C.copy()
        K[self.kpos, self.kpos] += values[self.kidx]
        C[self.cpos, self.cpos] += values[self.cidx]
        H = np.linalg.solve(K[None] + self.Zw + self.iw * C[None], self.F)
        return H[self.point, self.out]

    def predict(self, x, scale=1.0):
        """The rows' phasors at `x = (log values, Re u / scale, Im u / scale)`."""
        u = scale * (x[self.p:self.p + self.k] + 1j * x[self.p + self.k:])
        return self.rows(np.exp(x[:self.p])) @ u

    def residual(self, x, scale=1.0):
        d = (self.predict(x, scale) - self.X) / self.sigma
        return np.concatenate([d.real, d.imag])

    def unbalance_start(self, logp):
        """The weighted linear least-squares unbalances at the coefficients `exp(logp)`."""
        B = self.rows(np.exp(logp)) / self.sigma[:, None]
        return np.linalg.lstsq(B, self.X / self.sigma, rcond=None)[0]


def scipy_fit(nm, logp0, method):
    """least_squares from the log-coefficients `logp0`; returns `(values, cost, n_residuals,
    success)`, `n_residuals` the residual evaluations, finite differences included."""
    from scipy.optimize import least_squares

    count = [0]

    def res(x, s):
        count[0] += 1
        return nm.residual(x, s)

    u0 = nm.unbalance_start(logp0)
    s = float(np.max(np.abs(u0))) or 1.0
    x0 = np.concatenate([logp0, u0.real / s, u0.imag / s])
    sol = least_squares(res, x0, jac="2-point", method=method, args=(s,), xtol=TOL, ftol=TOL, gtol=TOL)
    return np.exp(sol.x[:nm.p]), float(2 * sol.cost), count[0], bool(sol.success)


def scipy_multistart(nm, th0):
    """scipy LM from each row of `th0` (log-coefficients); the lowest cost kept."""
    with np.errstate(all="ignore"):     # far starts overflow on the way (those lanes end non-finite)
        fits = [scipy_fit(nm, t, "lm") for t in th0]
    best = min(range(len(fits)), key=lambda i: fits[i][1] if np.isfinite(fits[i][1]) else np.inf)
    return fits[best][0], fits[best][1], sum(f[2] for f in fits), best


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--starts", type=int, default=3, help="seeded random starts (each coefficient 2-5x off)")
    ap.add_argument("--smoke", action="store_true", help="one start, local fits only; print, write nothing")
    args = ap.parse_args()
    n_random = 1 if args.smoke else args.starts

    import jax
    import jax.numpy as jnp
    from scipy.optimize._numdiff import approx_derivative

    import rotorjax
    from rotorjax.identify import _fe_identify as fi
    from rotorjax.identify import _engine as eng
    from rotorjax.identify import identify, read_phasors, rotor_model
    from rotorjax.identify._lm import _res_jac
    from rotorjax.identify._make_fe_data import TRUTH, UNBALANCES
    from rotorjax.io import shipped_rotor

    path = str(shipped_rotor("flexible_rig"))
    fit = list(TRUTH)
    truth = np.array([TRUTH[k] for k in fit])
    data = read_phasors(DATASET)
    rotor = rotor_model(path).rotor
    nm = NumpyModel(rotor, data, fit, FIT_UNBALANCE, fi._sigma(data, "relative"))
    starts = random_starts(TRUTH, n_random)

    def err(values):
        return float(np.max(np.abs(np.asarray(values) / truth - 1)))

    # --- the peer's residual against rotorjax's at the truth ---
    u_true = np.zeros(len(FIT_UNBALANCE), dtype=complex)
    for node, mag, ph in UNBALANCES:
        u_true[FIT_UNBALANCE.index(node)] = mag * np.exp(1j * ph)
    x_true = np.concatenate([np.log(truth), u_true.real, u_true.imag])
    _, _, r_nom, _ = fi.problem(rotor_model(path), DATASET, fit, FIT_UNBALANCE)
    res_rj = np.asarray(r_nom.full(jnp.asarray(x_true)))
    P_rj = np.asarray(r_nom.predict(jnp.asarray(x_true[:len(fit)]), jnp.asarray(u_true)))
    parity = {"residual_max_abs_diff": float(np.max(np.abs(nm.residual(x_true) - res_rj))),
              "phasor_max_rel_diff": float(np.max(np.abs(nm.predict(x_true) - P_rj)) / np.max(np.abs(P_rj))),
              "cost_at_truth": float(res_rj @ res_rj)}
    print("parity at the truth:", parity, flush=True)
    if parity["phasor_max_rel_diff"] > 1e-9:
        raise SystemExit("the numpy model does not reproduce rotorjax's phasors")

    # --- rotorjax: the whole identify call ---
    # stage timers: identify calls these through _fe_identify's globals; each wrapper
    # waits for its results so its time is its own
    stage = {}

    def timer(name, fn):
        def wrapped(*a, **k):
            t0 = time.perf_counter()
            r = jax.block_until_ready(fn(*a, **k))
            stage[name] = stage.get(name, 0.0) + time.perf_counter() - t0
            return r
        return wrapped

    # (module, name, stage): the LM runs in the engine, one lane (one start) or vmapped over the starts
    patched = ((fi, "problem", "problem_setup_s"), (eng, "lm_batch", "fit_lm_batch_s"),
               (eng, "levenberg_marquardt", "fit_lm_batch_s"), (fi, "_critical_speeds", "critical_speeds_s"))
    originals = {(m, n): getattr(m, n) for m, n, _ in patched}

    def rj_call(start, n_starts):
        stage.clear()
        t0 = time.perf_counter()
        model = rotor_model(path, start)
        stage["rotor_model_s"] = time.perf_counter() - t0
        for m, n, name in patched:
            setattr(m, n, timer(name, originals[m, n]))
        try:
            return identify(model, DATASET, fit, fit_unbalance=FIT_UNBALANCE, n_starts=n_starts)
        finally:
            for (m, n), f in originals.items():
                setattr(m, n, f)

    def rj_run(n_starts):
        t0 = time.perf_counter()
        rj_call(starts[0], n_starts)                        # compiles
        first = time.perf_counter() - t0
        runs = []
        for s in starts:
            t0 = time.perf_counter()
            res = rj_call(s, n_starts)
            t = time.perf_counter() - t0
            est = np.array([res.estimates[k] for k in fit])
            covered = [bool(res.intervals[k][0] <= TRUTH[k] <= res.intervals[k][1]) for k in fit]
            stages = dict(stage)
            stages["rest_s"] = t - sum(stages.values())
            runs.append({"s": t, "max_rel_error": err(est), "converged_to_truth": err(est) < CONVERGED_REL,
                         "stages": stages, "ci95_covered": int(sum(covered)), "ci95_all_cover": all(covered),
                         "not_covered": [k for k, c in zip(fit, covered) if not c],
                         "cost": res.cost, "converged": res.converged, "n_starts": res.n_starts,
                         "other_minima": len(res.minima)})
        stages = {k: float(np.median([r["stages"][k] for r in runs])) for k in runs[0]["stages"]}
        return {"what": WHOLE_CALL, "s": float(np.median([r["s"] for r in runs])), "first_call_s": first,
                "stages_median_s": stages, "runs": runs}

    out = {"benchmark": "FE identification (flexible_rig, 8 bearing coefficients, flexible-runup)",
           "machine": machine(), "date": datetime.datetime.now().isoformat(timespec="seconds"),
           "versions": {"jax": jax.__version__, "rotorjax": getattr(rotorjax, "__version__", ""),
                        "numpy": np.__version__, "scipy": __import__("scipy").__version__},
           "smoke": args.smoke, "n_rows": int(data.n), "n_speeds": int(np.unique(data.speed).size),
           "n_dofs": int(len(rotor.free_dofs)), "fit": fit, "fit_unbalance": list(FIT_UNBALANCE),
           "truth": TRUTH, "starts": starts, "converged_threshold_rel": CONVERGED_REL, "parity": parity}
    rj = out["rotorjax"] = {}
    for n_starts in ((1,) if args.smoke else (32, 1)):
        rj[f"n_starts_{n_starts}"] = rj_run(n_starts)
        print(f"rotorjax n_starts={n_starts}:", json.dumps(rj[f"n_starts_{n_starts}"]), flush=True)
    # reading the file, eagerly
    rj["rotor_model_s"], _ = timed(lambda: rotor_model(path, starts[0]), 0 if args.smoke else 3)
    if not args.smoke:     # where the time of one call goes (start 0, 32 starts; after compilation)
        model0 = rotor_model(path, starts[0])
        t0 = time.perf_counter()
        _, _, r0, c0 = fi.problem(model0, DATASET, fit, FIT_UNBALANCE)
        t_problem = time.perf_counter() - t0
        t0 = time.perf_counter()
        eng.lm_batch(r0, jnp.asarray(eng.starts(c0, model0.parameters(fit), 32, 10.0, 0)), jnp.asarray(c0))
        t_global = time.perf_counter() - t0
        t0 = time.perf_counter()
        identify(model0, DATASET, fit, fit_unbalance=FIT_UNBALANCE, critical_speeds=False)
        t_nocrit = time.perf_counter() - t0
        rj["breakdown_32_starts"] = {
            "rotor_model_s": rj["rotor_model_s"], "problem_setup_s": t_problem, "global_lm_batch_s": t_global,
            "identify_prebuilt_model_no_critical_speeds_s": t_nocrit,
            "note": "problem setup: phasor model + receptances at the start (one LU per speed, compiled once)"}
        print("rotorjax breakdown:", json.dumps(rj["breakdown_32_starts"]), flush=True)

    # --- rotorjax: the fit alone (lm_batch on a problem built outside the timing) ---
    repeats_fit = 0 if args.smoke else 3
    built = []
    for s in starts:
        _, params_s, r_s, center_s = fi.problem(rotor_model(path, s), data, fit, FIT_UNBALANCE)
        built.append((params_s, r_s, center_s))
    fo = out["rotorjax_fit_only"] = {}
    for n in ((1,) if args.smoke else (1, 32)):
        runs, first = [], None
        for params_s, r_s, center_s in built:
            th0 = eng.starts(center_s, params_s, n, 10.0)
            t, t_first, (ths, costs, done, it) = timed_first(
                lambda: eng.lm_batch(r_s, jnp.asarray(th0), jnp.asarray(center_s)), repeats_fit)
            first = t_first if first is None else first
            costs = np.asarray(costs)
            best = int(np.argmin(np.where(np.isfinite(costs), costs, np.inf)))
            est = [float(p.from_theta(v)) for p, v in zip(params_s, np.asarray(ths)[best])]
            runs.append({"s": t, "first_s": t_first, "max_rel_error": err(est),
                         "converged_to_truth": err(est) < CONVERGED_REL, "cost": float(costs[best]),
                         "iterations": int(it), "converged": bool(np.asarray(done)[best])})
        fo[f"n_starts_{n}"] = {"s": float(np.median([r["s"] for r in runs])), "first_call_s": first,
                               "runs": runs}
        print(f"rotorjax fit only, {n} start(s):", json.dumps(fo[f"n_starts_{n}"]), flush=True)
    fo["note"] = ("_engine.lm_batch alone on a problem built per start outside the timing; th0 = "
                  "_engine.starts(center, params, n, 10.0); first_call_s: start 0's first call (compiled "
                  "already by the whole-call runs when the shapes match); s: median over the starts of the "
                  f"median of {repeats_fit} repeat(s)")

    # --- scipy: local fits from the same starts, and LM from rotorjax's 32 global starts ---
    sp = out["scipy"] = {}
    for method in ("lm",) if args.smoke else ("lm", "trf"):
        runs = []
        for s in starts:
            logp0 = np.log([s[k] for k in fit])
            t, (est, cost, nfev, ok) = timed(lambda: scipy_fit(nm, logp0, method), repeats=0 if args.smoke else 3)
            runs.append({"s": t, "max_rel_error": err(est), "converged_to_truth": err(est) < CONVERGED_REL,
                         "cost": cost, "residual_evaluations": nfev, "success": ok})
        sp[method] = {"s": float(np.median([r["s"] for r in runs])), "runs": runs}
        print(f"scipy {method}:", json.dumps(sp[method]), flush=True)
    if not args.smoke:
        params = rotor_model(path).parameters(fit)
        runs = []
        for s in starts[:1]:     # one start set (each costs ~10-20 s)
            th0 = eng.starts(np.log([s[k] for k in fit]), params, 32, 10.0, 0)
            t0 = time.perf_counter()
            est, cost, nfev, best = scipy_multistart(nm, th0)
            runs.append({"s": time.perf_counter() - t0, "max_rel_error": err(est),
                         "converged_to_truth": err(est) < CONVERGED_REL, "cost": cost, "residual_evaluations": nfev,
                         "best_start": best})
        sp["lm_32_starts"] = {"s": float(np.median([r["s"] for r in runs])), "runs": runs,
                              "note": "scipy LM from each of the 32 starts of rotorjax's global stage (around the "
                                      "first random start), best kept"}
        print("scipy lm, 32 starts:", json.dumps(sp["lm_32_starts"]), flush=True)

    # --- one residual + Jacobian evaluation ---
    repeats = 0 if args.smoke else 20
    _, _, r, center = fi.problem(rotor_model(path, starts[0]), DATASET, fit, FIT_UNBALANCE)
    th = jnp.asarray(center)
    t_rj, (res0, J0) = timed(lambda: _res_jac(r, th), repeats)
    _, _, r_direct, _ = fi.problem(rotor_model(path, starts[0]), DATASET, fit, FIT_UNBALANCE, coupling=False)
    t_rj_direct, _ = timed(lambda: _res_jac(r_direct, th), repeats)
    u0 = nm.unbalance_start(center)
    s0 = float(np.max(np.abs(u0)))
    x0 = np.concatenate([center, u0.real / s0, u0.imag / s0])

    def np_res_jac():
        f0 = nm.residual(x0, s0)
        return f0, approx_derivative(nm.residual, x0, method="2-point", f0=f0, args=(s0,))

    t_np, (_, Jn) = timed(np_res_jac, repeats)
    t_np_res, _ = timed(lambda: nm.residual(x0, s0), repeats)
    out["res_jac"] = {"rotorjax_s": t_rj, "rotorjax_shape": list(np.shape(J0)),
                      "rotorjax_direct_solves_s": t_rj_direct,
                      "numpy_fd_s": t_np, "numpy_shape": list(Jn.shape), "numpy_residual_s": t_np_res,
                      "note": "rotorjax: receptance coupling (Woodbury) around the start, unbalances projected "
                              "out; direct: one LU per speed; numpy: residual + 2-point FD over "
                              "(8 log-coefficients, 4 unbalance parts)"}

    whole = {}
    for m in sp:
        whole[f"scipy_{m}_over_rotorjax_n_starts_1"] = sp[m]["s"] / rj["n_starts_1"]["s"]
        if "n_starts_32" in rj:
            whole[f"scipy_{m}_over_rotorjax_n_starts_32"] = sp[m]["s"] / rj["n_starts_32"]["s"]
    equal = {f"scipy_{m}_over_rotorjax_fit_only_1_start": sp[m]["s"] / fo["n_starts_1"]["s"]
             for m in ("lm", "trf") if m in sp}
    if "lm_32_starts" in sp:
        equal["scipy_lm_32_starts_over_rotorjax_fit_only_32_starts"] = sp["lm_32_starts"]["s"] / fo["n_starts_32"]["s"]
    ratios = {"res_jac": t_np / t_rj, "equal_work_fit_only": equal, "whole_call": whole}
    out["time_ratios_scipy_over_rotorjax"] = ratios
    out["time_ratios_note"] = ("> 1: rotorjax faster. equal_work_fit_only: scipy's fit against rotorjax's lm_batch "
                               "alone (problem built outside both timings); whole_call: scipy's fit only against "
                               "rotorjax's " + WHOLE_CALL + " (unequal work)")

    print(f"\n{out['n_rows']} phasors, {out['n_dofs']} dofs, {len(fit)} coefficients + "
          f"{len(FIT_UNBALANCE)} complex unbalances; {len(starts)} start(s) 2-5x off; medians after compilation")
    print(f"{'method':44s} {'time s':>9s} {'max rel err':>24s} {'to truth':>9s} {'CI95 cover':>11s}")
    rows = [(f"rotorjax whole call, {k[len('n_starts_'):]} start(s)", v) for k, v in rj.items()
            if k.startswith("n_starts_")]
    rows += [(f"rotorjax fit only (lm_batch), {k[len('n_starts_'):]} start(s)", v) for k, v in fo.items()
             if k.startswith("n_starts_")]
    rows += [(f"scipy least_squares {m}", v) for m, v in sp.items()]
    for name, v in rows:
        errs = ", ".join(f"{x['max_rel_error']:.2g}" for x in v["runs"])
        conv = sum(x["converged_to_truth"] for x in v["runs"])
        cover = (f"{sum(x['ci95_all_cover'] for x in v['runs'])}/{len(v['runs'])} all"
                 if "ci95_all_cover" in v["runs"][0] else "-")
        print(f"{name:44s} {v['s']:9.3f} {errs:>24s} {conv:>5d}/{len(v['runs'])} {cover:>11s}")
    for k, v in rj.items():
        if k.startswith("n_starts_"):
            print(f"rotorjax {k} first (compiling) call: {v['first_call_s']:.1f} s; whole-call stages (median s): "
                  + ", ".join(f"{a} {b:.3f}" for a, b in v["stages_median_s"].items()))
    rjj = out["res_jac"]
    print(f"residual+Jacobian: rotorjax {rjj['rotorjax_s'] * 1e3:.2f} ms (direct solves "
          f"{rjj['rotorjax_direct_solves_s'] * 1e3:.2f} ms), numpy+FD {rjj['numpy_fd_s'] * 1e3:.2f} ms")
    print("time ratios scipy/rotorjax: res+jac", round(ratios["res_jac"], 3))
    print("  equal work (fit only):", {k: round(v, 3) for k, v in equal.items()})
    print("  whole call (unequal work):", {k: round(v, 3) for k, v in whole.items()})
    if args.smoke:
        print("smoke run: nothing written")
    else:
        write_results("fe_identification", out)


if __name__ == "__main__":
    main()
