"""Harmonic-balance continuation against brute-force time sweeps (issue 30): the
unbalance response of ROSS's example rotor on cubic (hardening) bearings, the
scene of tests/models/test_composition_cubic.py, at 200 constant speeds spread
over 60..140 rad/s, through both folds of the jump.

The model: the FE rotor reduced to its first `--modes` (8) bending modes at rest
(`rotor.reduce(8)`, as that test's run-up), the same model for both methods. Its
third bending mode (765 rad/s) has its nodes at the disks, where the dampers sit:
it decays at about 0.03 1/s and sets how long a time integration from rest must run.
(The modal basis is not closed under rotation, so the orbits are not exactly circular
and higher harmonics are not exactly zero: the harmonic ladder below is real.)

Methods, each giving the bearing-node (node 0) orbit radius at the 200 speeds:
- harmonic balance: `periodic_branch` (H harmonics, pseudo-arclength through the
  folds, Hill stability) over 60..140 with the library's default steps (`ds`, `ds_max`
  = L/100, L/10 of the range: what a user gets), then at every speed each crossing of the branch
  (three between the folds) is solved by `harmonic_balance` at that exact speed from
  the branch point before it (one vmapped, compiled call), and its amplitude taken by
  `orbit_amplitude`. Timed as a whole (branch + 200-speed curve): first call (compiles)
  and the median of repeats. H in `--harmonics` (1, 2, 3; 5 and 8 take longer).
- brute force: the project's buffered batch (`rotorjax.sweep` of `rotorjax.IVP`s,
  Dopri8) from rest at every constant speed to `t_end - 2 T`, then the last two
  periods saved (33 states a period) by a second sweep; the amplitude the largest radius
  over the last period. It lands on one of the coexisting motions between the folds.
  Ladder over (rtol, t_end). Its cost is linear in the number of speeds (buffered
  lanes, no lock-step), so each rung is run on `--subset` speeds (every k-th, plus the
  speeds nearest each fold: the slowest to settle) and its time scaled to 200 speeds;
  the error is its max over those speeds.
- reference: harmonic balance with `--ref-harmonics` (16) harmonics, Newton to 1e-13,
  at every crossing (started from the H = 5 branch, or the largest H run), checked
  against tight (rtol 1e-12, atol 1e-14) time integrations started on the reference
  orbit at three speeds (the orbit must not move: its radius over the last of 20
  periods) and one integration from rest
  (rtol 1e-10, 400 s) at 80 rad/s.
Errors: max over speeds of |amplitude / reference - 1| (the brute force against the
reference motion nearest to what it landed on; harmonic balance on every stable
branch point, and separately with the unstable middle branch).

The headline: the brute force's time over harmonic balance's at matched error (the
cheapest of each whose error is at most `--target`, 1e-4). Timings on a shared 2-core
machine: other processes' load is recorded (`other_cores_busy`).

Run: python benchmarks/harmonic_balance.py [--repeats 2] [--smoke]
(the results page's run: the defaults; every timing, brute force included, the median
of the repeats after a first, compiling call)
Writes benchmarks/results/harmonic_balance.json (`--smoke`: 4 speeds over 100..106,
H = 1, reference H = 2, one brute-force rung of 1 s on 3 speeds, one call per
timing; prints, writes nothing).
"""

import argparse
import json
import os
import sys
import time

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.dirname(os.path.abspath(__file__))))   # tests.reference
sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))

import equinox as eqx  # noqa: E402
import jax  # noqa: E402
import jax.numpy as jnp  # noqa: E402

import rotorjax  # noqa: E402
from rotorjax.analysis import harmonic_balance, orbit_amplitude, periodic_branch  # noqa: E402
from rotorjax.models import RotorScene  # noqa: E402
from tests.reference.cubic_rotor import K3, cubic_rotor  # noqa: E402
from _common import CpuWatch, machine, timed_first, write_results  # noqa: E402

NODE = 0   # the bearing node whose orbit radius is the amplitude


def build(modes):
    rotor, parts = cubic_rotor(K3)
    return (rotor.reduce(modes) if modes else rotor), parts


# ----------------------------------------------------------------------------- harmonic balance

_SOLVERS = {}


def _solver(rotor, parts, H, tol):
    """Compiled, vmapped: (speeds (K,), guesses (K, 2H+1, n)) -> (amplitudes, codes, time residuals)."""
    key = (H, tol)
    if key not in _SOLVERS:
        def one(w, guess):
            sc = RotorScene(rotor, w, parts)
            T = 2 * jnp.pi / w
            sol = harmonic_balance(sc, T, guess, harmonics=H, tol=tol, max_iter=40, stability=False)
            return orbit_amplitude(sc, sol.coefficients, T, node=NODE), sol.code, sol.time_residual
        _SOLVERS[key] = jax.jit(jax.vmap(one))
    return _SOLVERS[key]


def crossings(p, speeds):
    """(speed index, branch interval j, fraction s) for every crossing of each speed."""
    out = []
    for k, w in enumerate(speeds):
        for j in range(len(p) - 1):
            if (p[j] - w) * (p[j + 1] - w) <= 0 and p[j] != p[j + 1]:
                out.append((k, j, (w - p[j]) / (p[j + 1] - p[j])))
    return out


def curve_from_branch(rotor, parts, br, coeffs, speeds, H, tol, pad_to=None):
    """Every motion of the branch at every speed: solved at that speed from the
    branch (linear interpolation of the coefficients between the two points around it),
    -> (speed index (K,), amplitude (K,), stable (K,), code (K,), time residual (K,))."""
    cr = crossings(np.asarray(br.p), speeds)
    ks = np.array([c[0] for c in cr])
    guess = np.stack([(1 - s) * coeffs[j] + s * coeffs[j + 1] for _, j, s in cr])
    if pad_to is not None and pad_to > guess.shape[1]:   # more harmonics than the branch's
        guess = np.concatenate([guess, np.zeros((guess.shape[0], pad_to - guess.shape[1], guess.shape[2]))], 1)
    stable = np.array([bool(br.stable[j] and br.stable[j + 1]) for _, j, _ in cr])
    amp, code, tres = _solver(rotor, parts, H, tol)(jnp.asarray(speeds[ks]), jnp.asarray(guess))
    return {"k": ks, "amp": np.asarray(amp), "stable": stable, "code": np.asarray(code),
            "time_residual": np.asarray(tres)}


def hb_run(rotor, parts, speeds, H, box, tol):
    """The timed harmonic-balance path: branch + the curve at every speed. The branch
    takes the library's default steps (`ds`, `ds_max` = L/100, L/10 of the range), as a
    user gets it."""
    scene_at = lambda w: RotorScene(rotor, w, parts)  # noqa: E731
    br, co = periodic_branch(scene_at, box[0], scene_at(box[0]).rest_state(), box, harmonics=H, name="speed",
                             max_points=5000)
    return br, co, curve_from_branch(rotor, parts, br, co, speeds, H, tol)


def by_speed(curve, n):
    """{speed index: sorted amplitudes}, all motions and stable ones."""
    every = [sorted(curve["amp"][curve["k"] == k]) for k in range(n)]
    stable = [sorted(curve["amp"][(curve["k"] == k) & curve["stable"]]) for k in range(n)]
    return every, stable


def hb_error(curve, ref_every, n):
    """Max relative amplitude error against the reference, motion by motion (sorted by
    amplitude at each speed): (stable motions, all motions, missing motions)."""
    every, _ = by_speed(curve, n)
    e_all, e_stable, missing = 0.0, 0.0, 0
    for k in range(n):
        ref = ref_every[k]
        if len(every[k]) != len(ref["amp"]):
            missing += 1
            continue
        for a, r, st in zip(every[k], ref["amp"], ref["stable"]):
            e = abs(a / r - 1)
            e_all = max(e_all, e)
            if st:
                e_stable = max(e_stable, e)
    return e_stable, e_all, missing


# ----------------------------------------------------------------------------- brute force

def bf_run(rotor, parts, speeds, rtol, t_end, lanes):
    """From rest to t_end - 2T, then the last two periods saved; amplitude = max radius
    over the last period. Two buffered sweeps -> (amplitudes, steps per speed, codes)."""
    pre = lambda w: t_end - 2 * 2 * jnp.pi / w  # noqa: E731

    def first(pt):
        sc = RotorScene(rotor, pt["w"], parts)
        return rotorjax.IVP(sc, sc.rest_state(), (0.0, pre(pt["w"])), solver="dopri8", rtol=rtol,
                            atol=rtol * 1e-8, max_steps=4_000_000)

    r1 = rotorjax.sweep(first, {"w": speeds}, lanes=lanes, progress=False).values
    y1 = jnp.asarray(r1.ys)[:, -1]

    def last(pt):
        sc = RotorScene(rotor, pt["w"], parts)
        i = pt["i"].astype(jnp.int32)
        return rotorjax.IVP(sc, y1[i], (pre(pt["w"]), t_end), saveat=67, solver="dopri8", rtol=rtol,
                            atol=rtol * 1e-8, max_steps=100_000)

    r2 = rotorjax.sweep(last, {"w": speeds, "i": np.arange(len(speeds), dtype=float)}, mode="zip", lanes=lanes,
                        progress=False).values
    ys = np.asarray(r2.ys)[:, -34:]   # the last period (33 intervals)
    r = np.asarray(_radii_impl(rotor, parts, jnp.asarray(speeds), jnp.asarray(ys)))
    steps = np.asarray(r1.stats["num_steps"]) + np.asarray(r2.stats["num_steps"])
    code = np.maximum(np.asarray(r1.code), np.asarray(r2.code))
    return {"amp": r.max(axis=1), "steps": steps, "code": code}


def _node_r(rotor, parts, w, y):
    out = RotorScene(rotor, w, parts).outputs(0.0, y)
    return jnp.hypot(out["node_x"][NODE], out["node_y"][NODE])


@eqx.filter_jit
def _radii_impl(rotor, parts, ws, ys):
    return jax.vmap(lambda w, row: jax.vmap(lambda y: _node_r(rotor, parts, w, y))(row))(ws, ys)


def bf_error(amp, speeds_idx, ref_stable):
    """Max relative error against the nearest stable reference motion at each speed."""
    errs = []
    for a, k in zip(amp, speeds_idx):
        refs = np.asarray(ref_stable[k])
        errs.append(float(np.min(np.abs(a / refs - 1))))
    return max(errs), errs


# ----------------------------------------------------------------------------- main

def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--modes", type=int, default=8)
    ap.add_argument("--n-speeds", type=int, default=200)
    ap.add_argument("--harmonics", default="1,2,3")
    ap.add_argument("--ref-harmonics", type=int, default=16)
    ap.add_argument("--subset", type=int, default=20, help="brute-force speeds (every k-th + nearest the folds)")
    ap.add_argument("--rungs", default="1e-6:40,1e-7:160,1e-8:320",
                    help="brute-force ladder: rtol:t_end pairs")
    ap.add_argument("--target", type=float, default=1e-4)
    ap.add_argument("--repeats", type=int, default=2)
    ap.add_argument("--smoke", action="store_true", help="tiny sizes, one call each; print, write nothing")
    args = ap.parse_args()
    box = (60.0, 140.0)
    if args.smoke:
        box, args.n_speeds, args.harmonics, args.ref_harmonics = (100.0, 106.0), 4, "1", 2
        args.subset, args.rungs, args.repeats = 3, "1e-5:1", 0
    Hs = [int(h) for h in args.harmonics.split(",")]
    rungs = [(float(a), float(b)) for a, b in (r.split(":") for r in args.rungs.split(","))]
    rotor, parts = build(args.modes)
    speeds = np.linspace(*box, args.n_speeds)
    n = len(speeds)
    out = {"benchmark": "harmonic_balance", "machine": machine(), "smoke": args.smoke,
           "versions": {"jax": jax.__version__},
           "settings": {"scene": "ROSS example rotor (ross-compare preset), cubic bearings k3 = 3e12 N/m^3 at "
                                 "nodes 0 and 6, dampers 150 N s/m at nodes 2 and 4, unbalance 2e-3 kg m at 2 "
                                 "and 4", "modes": args.modes, "speeds": [float(box[0]), float(box[1]), n],
                        "amplitude": f"node {NODE} orbit radius (m)", "ds": f"default ({(box[1] - box[0]) / 100:g})",
                        "ds_max": f"default ({(box[1] - box[0]) / 10:g})",
                        "hb_tol": 1e-11, "ref_harmonics": args.ref_harmonics, "ref_tol": 1e-13,
                        "target_error": args.target, "repeats": args.repeats}}
    rep = args.repeats

    # 1. harmonic balance at each H (timed: branch + 200-speed curve)
    hb = {}
    curves = {}
    for H in Hs:
        watch = CpuWatch()
        t, t1, (br, co, cv) = timed_first(lambda: hb_run(rotor, parts, speeds, H, box, 1e-11),
                                          repeats=rep)
        folds = sorted(float(e.p) for e in br.events if e.kind == "fold" and box[0] <= e.p <= box[1])
        curves[H] = (br, co, cv)
        hb[H] = {"run_s": t, "first_call_s": t1, "points": int(len(br.p)), "folds": folds,
                 "fold_events_outside_box": [float(e.p) for e in br.events
                                             if e.kind == "fold" and not box[0] <= e.p <= box[1]],
                 "stops": list(br.stops), "motions": int(len(cv["k"])), "failed": int(np.sum(cv["code"] != 0)),
                 "time_residual_max": float(cv["time_residual"].max()),
                 "other_cores_busy": watch.report()["other_cores_busy"]}
        print(f"HB H={H}: {len(br.p)} points, {t:.2f} s (first {t1:.2f}), folds {folds}, "
              f"{len(cv['k'])} motions", flush=True)

    # 2. the reference: H_ref harmonics at every crossing, from the H = 5 (or largest) branch
    Hb = 5 if 5 in curves else max(curves)
    br, co, _ = curves[Hb]
    Href = args.ref_harmonics
    t0 = time.perf_counter()
    ref = curve_from_branch(rotor, parts, br, co, speeds, Href, 1e-13, pad_to=2 * Href + 1)
    t_ref = time.perf_counter() - t0
    ref_every = []
    for k in range(n):
        sel = ref["k"] == k
        o = np.argsort(ref["amp"][sel])
        ref_every.append({"amp": ref["amp"][sel][o], "stable": ref["stable"][sel][o]})
    _, ref_stable = by_speed(ref, n)
    out["reference"] = {"harmonics": Href, "s": t_ref, "motions": int(len(ref["k"])),
                        "failed": int(np.sum(ref["code"] != 0)),
                        "time_residual_max": float(ref["time_residual"].max())}
    print("reference:", out["reference"], flush=True)

    for H in Hs:
        e_st, e_all, missing = hb_error(curves[H][2], ref_every, n)
        hb[H].update(error_stable=e_st, error_all=e_all, speeds_with_other_motion_count=missing)
        print(f"HB H={H}: error {e_st:.2e} (stable), {e_all:.2e} (all)", flush=True)
    out["harmonic_balance"] = {str(H): v for H, v in hb.items()}

    # 3. the reference checked by tight time integrations
    checks = []
    chk = [0.5 * (box[0] + box[1]), box[1]] if args.smoke else [80.0, 103.4, 120.0]
    for w in chk:
        k = int(np.argmin(np.abs(speeds - w)))
        w = float(speeds[k])
        sc = RotorScene(rotor, w, parts)
        T = 2 * np.pi / w
        # the reference orbit's state at t = 0: re-solved (largest stable amplitude) to get the coefficients
        cr = [c for c in crossings(np.asarray(br.p), speeds[k:k + 1])]
        j, s = max(((c[1], c[2]) for c in cr), key=lambda js: np.abs(co[js[0]]).max())
        g = (1 - s) * co[j] + s * co[j + 1]
        g = np.concatenate([g, np.zeros((2 * Href + 1 - g.shape[0], g.shape[1]))])
        sol = harmonic_balance(sc, T, g, harmonics=Href, tol=1e-13, max_iter=40, stability=False)
        a_hb = float(orbit_amplitude(sc, sol.coefficients, T, node=NODE))
        periods = 3 if args.smoke else 20
        res = rotorjax.simulate(sc, sol.initial_state(), (0.0, periods * T),
                                saveat=np.linspace((periods - 1) * T, periods * T, 65), solver="dopri8",
                                rtol=1e-12, atol=1e-14, max_steps=2_000_000)
        rr = np.hypot(np.asarray(res.outputs["node_x"])[:, NODE], np.asarray(res.outputs["node_y"])[:, NODE])
        checks.append({"speed": w, "start": "on the reference orbit", "periods": periods,
                       "hb_amplitude": a_hb, "time_amplitude": float(rr.max()),
                       "rel_diff": float(abs(rr.max() / a_hb - 1))})
        print("check:", checks[-1], flush=True)
    if not args.smoke:   # from rest, long: the motion a sweep finds at 80 rad/s
        w = 80.0
        k = int(np.argmin(np.abs(speeds - w)))
        w = float(speeds[k])
        sc = RotorScene(rotor, w, parts)
        T = 2 * np.pi / w
        te = 400.0
        res = rotorjax.simulate(sc, sc.rest_state(), (0.0, te), saveat=np.linspace(te - T, te, 65),
                                solver="dopri8", rtol=1e-10, atol=1e-18, max_steps=4_000_000)
        rr = np.hypot(np.asarray(res.outputs["node_x"])[:, NODE], np.asarray(res.outputs["node_y"])[:, NODE])
        a_ref = float(max(ref_stable[k]))
        checks.append({"speed": w, "start": "rest", "t_end": te, "hb_amplitude": a_ref,
                       "time_amplitude": float(rr.max()), "rel_diff": float(abs(rr.max() / a_ref - 1))})
        print("check:", checks[-1], flush=True)
    out["reference"]["checks"] = checks

    # 4. brute force on a subset, time scaled to all speeds
    folds = hb[Hs[-1]]["folds"]
    sub = set(np.linspace(0, n - 1, args.subset).round().astype(int).tolist())
    for f in folds:   # the speeds nearest each fold, both sides
        i = int(np.searchsorted(speeds, f))
        sub.update(x for x in (i - 1, i) if 0 <= x < n)
    sub = np.array(sorted(sub))
    bf = []
    for rtol, te in rungs:
        watch = CpuWatch()
        lanes = len(sub)
        t, t1, r = timed_first(lambda: bf_run(rotor, parts, speeds[sub], rtol, te, lanes), repeats=rep)
        err, errs = bf_error(r["amp"], sub, ref_stable)
        worst = int(np.argmax(errs))
        row = {"rtol": rtol, "t_end": te, "speeds_run": int(len(sub)), "run_s": t, "first_call_s": t1,
               "s_per_speed": t / len(sub), "s_for_all_speeds": t / len(sub) * n, "error": err,
               "worst_speed": float(speeds[sub[worst]]), "error_median": float(np.median(errs)),
               "steps_mean": float(np.mean(r["steps"])), "steps_max": int(np.max(r["steps"])),
               "failed": int(np.sum(r["code"] != 0)),
               "landed_upper_between_folds": int(sum(1 for a, k in zip(r["amp"], sub) if len(ref_stable[k]) > 1
                                                     and abs(a - ref_stable[k][-1]) < abs(a - ref_stable[k][0]))),
               "other_cores_busy": watch.report()["other_cores_busy"]}
        bf.append(row)
        print(f"BF rtol {rtol:g} t_end {te:g}: error {err:.2e} (worst at {row['worst_speed']:.2f}), "
              f"{row['s_per_speed'] * 1e3:.1f} ms/speed, {row['s_for_all_speeds']:.1f} s for {n}", flush=True)
    out["brute_force"] = {"subset": [float(speeds[i]) for i in sub], "rungs": bf,
                          "note": "time per speed measured on the subset and scaled to all speeds (buffered "
                                  "batch: cost linear in the speeds); error = max over the subset"}

    # 5. matched error
    ok_hb = [(hb[H]["run_s"], H) for H in Hs if hb[H]["error_stable"] <= args.target]
    ok_bf = [(r["s_for_all_speeds"], r) for r in bf if r["error"] <= args.target]
    head = {"target": args.target}
    if ok_hb:
        t_hb, H = min(ok_hb)
        head.update(hb_harmonics=H, hb_s=t_hb, hb_error=hb[H]["error_stable"])
    if ok_bf:
        t_bf, r = min(ok_bf, key=lambda x: x[0])
        head.update(bf_rtol=r["rtol"], bf_t_end=r["t_end"], bf_s=t_bf, bf_error=r["error"])
    else:   # no rung reached the target: the cheapest rung below it bounds the cost from below
        r = max(bf, key=lambda x: x["s_for_all_speeds"])
        head.update(bf_note=f"no rung reached the target; the costliest rung ({r['s_for_all_speeds']:.1f} s, error "
                            f"{r['error']:.1e}) is a lower bound", bf_s_lower_bound=r["s_for_all_speeds"])
    if ok_hb:
        head["ratio"] = head.get("bf_s", head.get("bf_s_lower_bound")) / head["hb_s"]
        head["ratio_is_lower_bound"] = not ok_bf
    out["matched"] = head
    print("matched:", json.dumps(head), flush=True)
    if args.smoke:
        print("smoke run: nothing written")
    else:
        write_results("harmonic_balance", out)


if __name__ == "__main__":
    main()
