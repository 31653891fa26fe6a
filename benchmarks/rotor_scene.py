"""Finite-element rotor scene: `rotorjax.simulate` of a `RotorScene` vs CPU peers.

The scene: ROSS's example rotor (`ross-compare`, kyy = 1e6, cxx = cyy = 2000 N s/m;
28 free dofs), an unbalance of 1e-3 kg m at node 2, cubic bearings (k3 = 1e12 N/m^3)
at nodes 0 and 6, spun at 150 rad/s, from rest, for 0.5 s; the full rotor and
`rotor.reduce(8)` (modal linear part, the nonlinear forces at physical dofs).

(1) Speed against error: rotorjax (Tsit5, Dopri8) and the peers, each at rtol in
`RTOLS` with atol = rtol * 1e-4 (m, m/s, rad: the orbit is ~5e-5 m, so atol sits
near rtol times the orbit), the final state only. Error: max |node x, y at t = 0.5
- reference| over all nodes, divided by the orbit amplitude (the largest node
orbit radius over the run); the reference is rotorjax Dopri8 at rtol 1e-12
(atol 1e-16), checked against the numba DOP853 peer at the same tolerance. Each
model is measured against its own reference (integration error); the reduced
model's distance from the full one is reported beside it (reduction error).
(2) Batch: 64 speeds spread over 100..200 rad/s at rtol 1e-8: the batch path,
`simulate_batch` (its default: the vectorised stepper, lanes refilled from the
queue, the matrices equal at every speed applied to all lanes at once) on one
device (one core) and with `shard=True` over the two host devices (two cores,
against the peer's 2-thread loop; XLA_FLAGS set below, before jax is imported), and
`eqx.filter_vmap` over `simulate` (compiled ahead of time, then timed), vs a loop
of the peers; the reduced rotor again at `--large-batch` (512) speeds, where both
devices' lanes fill (64 speeds leave 32 lanes a device, where its right-hand side
costs twice as much a lane: benchmarks/step_cost.py). Vmapped adaptive solves run
in lock-step (every lane pays the slowest lane's steps): the per-lane step counts
are reported, and where the waste (max / mean) exceeds 10 % four calls of 16
neighbouring speeds are timed too. Errors on 8 lanes
against numba DOP853 at rtol 1e-12 (itself checked against rotorjax in (1)).

The peers integrate the same matrices (taken from the scene, so the comparison is
of integration, not assembly). The model is linear apart from forces at three
nodes with a constant mass matrix, M q'' = F0 + E^T f(t, E q) - C q' - K q (E:
the rows of the expansion to those nodes' x, y), so the strong form for a CPU
solver is the first-order system with M^-1 applied once, before the run:
q'' = M^-1 F0 + (M^-1 E^T) f - [M^-1 K, M^-1 C] (q, q'); no solve per step,
and the force needs only the six physical displacements. Peers:
- scipy `solve_ivp` DOP853, numpy right-hand side (the one matrix-vector product);
- the same with a numba `njit` right-hand side;
- scipy `ode('dop853')` (Hairer's Fortran DOP853) with the numba right-hand side;
- numba DOP853: scipy's DOP853 (same tableau, error estimate, step controller and
  initial step) compiled whole with numba: no Python per step or stage. In the
  batch also with `prange` over the speeds, two threads.
Diagnostics: microseconds per right-hand-side evaluation (inside one compiled
loop) for rotorjax, one state and vmapped over 64 states and times, and numba; and
microseconds per step of every run (time / steps).
Ratios are peer time / rotorjax time (> 1: rotorjax faster), at the same rtol and
at matched error (the peer's time at rotorjax's error, log-log interpolated on the
peer's ladder). Times are medians of `--repeats` runs after a first, compiling
call; rotorjax is timed through its public `simulate` (Python checks included).

Run: python benchmarks/rotor_scene.py [--quick | --smoke] [--repeats 3] [--batch 64]
Writes benchmarks/results/rotor_scene.json (`--quick`: two tolerances, one
repeat, a batch of 8; prints, writes nothing; `--smoke`: as `--quick`, but 0.02 s
of motion, one tolerance (1e-6), one call per timing, and everything (work-precision,
the right-hand-side costs over 4 states, a batch of 2 with grouped calls whatever the
lock-step waste) on the reduced scene only; the full one is built).
"""

import argparse
import math
import os
import platform
import sys
import time

import numpy as np

# Two host devices, one core each, so that `simulate_batch(..., shard=True)` runs on both
# cores against the peer's 2-thread `prange` loop, and the one-device runs on one core
# (no Eigen threads): must precede jax's import.
os.environ.setdefault("XLA_FLAGS", "--xla_force_host_platform_device_count=2 --xla_cpu_multi_thread_eigen=false")
sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from _common import machine, numba_dop853, write_results  # noqa: E402
from rotorjax.bench._matching import interpolate_cost  # noqa: E402

T_END = 0.5
SMOKE_T_END = 0.02     # --smoke: the span (replaces T_END)
SPEED = 150.0
RTOLS = (1e-4, 1e-6, 1e-8, 1e-10)
ATOL_PER_RTOL = 1e-4
REF_RTOL, REF_ATOL = 1e-12, 1e-16
BATCH_RTOL = 1e-8
MAX_STEPS = 1_000_000
UNBALANCE = (2, 1e-3)          # node, kg m
CUBIC = ((0, 1e12), (6, 1e12))  # node, N/m^3
FORCE_NODES = (CUBIC[0][0], UNBALANCE[0], CUBIC[1][0])


# ------------------------------------------------------------------------------- scene
def build_scene(n_modes=None, speed=SPEED):
    from rotorjax.models import CubicBearing, RotorScene, Unbalance
    from rotorjax.presets import _ross_compare as rc

    rotor = rc.build_rotor(rc.PRESET.params({"kyy": 1e6, "cxx": 2000.0, "cyy": 2000.0}))
    if n_modes is not None:
        rotor = rotor.reduce(n_modes)
    comps = (Unbalance(*UNBALANCE),) + tuple(CubicBearing(n, k3) for n, k3 in CUBIC)
    return RotorScene(rotor, speed, comps)


class PeerModel:
    """The scene's matrices for the peers (see the module docstring)."""

    def __init__(self, scene):
        ns = scene.n_shaft
        self.ns = ns
        self.E_all = np.asarray(scene.expand(np.eye(ns)))            # all dofs x coordinates
        rows = [4 * n + k for n in FORCE_NODES for k in (0, 1)]
        self.E6 = np.ascontiguousarray(self.E_all[rows])              # (6, ns)
        Minv = np.asarray(scene.Minv)
        self.Minv, self.C, self.G1 = Minv, np.asarray(scene.C), np.asarray(scene.G1)
        self.K, self.Ks = np.asarray(scene.K), np.asarray(scene.Ks)
        self.W = np.ascontiguousarray(Minv @ self.E6.T)               # (ns, 6)
        self.g0 = Minv @ np.asarray(scene.F0)
        self.U = UNBALANCE[1]
        self.k3a, self.k3b = CUBIC[0][1], CUBIC[1][1]

    def params(self, w, phase=0.0):
        """Per-speed arrays `(L, W, E6, g0, coefficients)`; `L = M^-1 [K_w, C_w]`."""
        L = np.ascontiguousarray(np.hstack([self.Minv @ (self.K + w * self.Ks),
                                            self.Minv @ (self.C + w * self.G1)]))
        coef = np.array([self.U, w, phase, self.k3a, self.k3b])
        return L, self.W, self.E6, self.g0, coef

    def nodes_xy(self, y):
        """Node x, y displacements (all nodes) from a state."""
        x = self.E_all @ np.asarray(y)[:self.ns]
        return np.concatenate([x[0::4], x[1::4]])


# ------------------------------------------------------------------------------- peers
def rhs_numpy(t, y, L, W, E6, g0, coef):
    U, w, phase, k3a, k3b = coef
    ns = g0.shape[0]
    u = E6 @ y[:ns]
    a = w * t + phase
    ra, rb = k3a * (u[0] * u[0] + u[1] * u[1]), k3b * (u[4] * u[4] + u[5] * u[5])
    f = np.array([-ra * u[0], -ra * u[1], U * w * w * math.cos(a), U * w * w * math.sin(a),
                  -rb * u[4], -rb * u[5]])
    return np.concatenate((y[ns:], g0 + W @ f - L @ y))


def make_numba():
    """Compile-on-demand numba kernels: the right-hand side (in place, and
    allocating for scipy), scipy's DOP853 loop, and a prange batch of it."""
    import numba

    @numba.njit(cache=False, fastmath=False)
    def rhs_into(t, y, out, L, W, E6, g0, coef):
        ns = g0.shape[0]
        U, w, phase, k3a, k3b = coef[0], coef[1], coef[2], coef[3], coef[4]
        u = np.zeros(6)
        for r in range(6):
            s = 0.0
            for j in range(ns):
                s += E6[r, j] * y[j]
            u[r] = s
        a = w * t + phase
        ra = k3a * (u[0] * u[0] + u[1] * u[1])
        rb = k3b * (u[4] * u[4] + u[5] * u[5])
        f0, f1 = -ra * u[0], -ra * u[1]
        f2, f3 = U * w * w * math.cos(a), U * w * w * math.sin(a)
        f4, f5 = -rb * u[4], -rb * u[5]
        n2 = 2 * ns
        for i in range(ns):
            out[i] = y[ns + i]
            s = g0[i] + W[i, 0] * f0 + W[i, 1] * f1 + W[i, 2] * f2 + W[i, 3] * f3 + W[i, 4] * f4 + W[i, 5] * f5
            for j in range(n2):
                s -= L[i, j] * y[j]
            out[ns + i] = s

    @numba.njit
    def rhs_alloc(t, y, L, W, E6, g0, coef):
        out = np.empty_like(y)
        rhs_into(t, y, out, L, W, E6, g0, coef)
        return out

    @numba.njit
    def rhs_args(t, y, out, args):
        L, W, E6, g0, coef = args
        rhs_into(t, y, out, L, W, E6, g0, coef)

    core = numba_dop853(rhs_args)

    @numba.njit
    def dop853(y0, t0, t1, rtol, atol, L, W, E6, g0, coef, max_steps):
        """scipy's DOP853 compiled whole (`benchmarks._common.numba_dop853`): returns (y(t1), steps, fevals, ok)."""
        return core(y0, t0, t1, rtol, atol, (L, W, E6, g0, coef), max_steps)

    @numba.njit(parallel=True)
    def dop853_batch(y0, t1, rtol, atol, Ls, W, E6, g0, coefs, max_steps):
        nb = Ls.shape[0]
        out = np.empty((nb, y0.shape[0]))
        steps = np.empty(nb, dtype=np.int64)
        for b in numba.prange(nb):
            yb, st, _, _ = dop853(y0, 0.0, t1, rtol, atol, Ls[b], W, E6, g0, coefs[b], max_steps)
            out[b] = yb
            steps[b] = st
        return out, steps

    @numba.njit
    def rhs_loop(y, k, L, W, E6, g0, coef):
        out, z = np.empty_like(y), y.copy()
        for i in range(k):
            rhs_into(0.01, z, out, L, W, E6, g0, coef)
            z += 1e-12 * out
        return z

    return {"rhs_alloc": rhs_alloc, "rhs_loop": rhs_loop, "dop853": dop853, "dop853_batch": dop853_batch,
            "numba": numba}


def run_solve_ivp(fun, y0, rtol, atol):
    from scipy.integrate import solve_ivp

    sol = solve_ivp(fun, (0.0, T_END), y0, method="DOP853", rtol=rtol, atol=atol, t_eval=[T_END])
    return sol.y[:, -1], {"nfev": int(sol.nfev), "success": bool(sol.success)}


def run_fortran(fun, y0, rtol, atol):
    from scipy.integrate import ode

    r = ode(fun).set_integrator("dop853", rtol=rtol, atol=atol, nsteps=10**8)
    r.set_initial_value(y0, 0.0)
    y = r.integrate(T_END)
    return y, {"success": bool(r.successful())}


# ------------------------------------------------------------------------------- timing
def timed(fn, repeats, warm=True):
    """`(median s, first-call s, result, every repeat's s)`; `warm`: a first call,
    outside the median (compiles); `repeats=0` (--smoke): the warm call only (or one
    call, without `warm`), its time as the median."""
    import jax

    def once():
        t0 = time.perf_counter()
        r = jax.block_until_ready(fn())
        return time.perf_counter() - t0, r

    first, r = once() if warm else (None, None)
    ts = []
    for _ in range(repeats if warm else max(1, repeats)):
        dt, r = once()
        ts.append(dt)
    return float(np.median(ts or [first])), first, r, ts


# ------------------------------------------------------------------------------- (1)
def work_precision(label, scene, rtols, repeats, nb):
    import jax.numpy as jnp

    import rotorjax as rj

    pm = PeerModel(scene)
    y0 = np.asarray(scene.rest_state())
    y0j = jnp.asarray(y0)
    ref = rj.simulate(scene, y0j, (0.0, T_END), saveat=1001, solver="dopri8", rtol=REF_RTOL, atol=REF_ATOL,
                      max_steps=MAX_STEPS)
    assert int(ref.code) == 0, ref.message
    ref_xy = pm.nodes_xy(ref.ys[-1])
    amplitude = float(np.max(ref.outputs["whirl_amplitude"]))
    L, W, E6, g0, coef = pm.params(SPEED)
    y_nb, *_ = nb["dop853"](y0, 0.0, T_END, REF_RTOL, REF_ATOL, L, W, E6, g0, coef, 10**7)
    ref_check = float(np.max(np.abs(pm.nodes_xy(y_nb) - ref_xy)) / amplitude)

    def err(y):
        return float(np.max(np.abs(pm.nodes_xy(y) - ref_xy)) / amplitude)

    rows = {}
    for solver in ("tsit5", "dopri8"):
        name = f"rotorjax {solver.capitalize()}"
        ladder, compile_first = [], None
        for rtol in rtols:
            fn = lambda: rj.simulate(scene, y0j, (0.0, T_END), solver=solver, rtol=rtol,  # noqa: E731
                                     atol=rtol * ATOL_PER_RTOL, max_steps=MAX_STEPS)
            t, first, r, ts = timed(fn, repeats)
            compile_first = first if compile_first is None else compile_first
            steps = int(r.stats["num_steps"])
            ladder.append({"rtol": rtol, "s": t, "error": err(r.ys[-1]), "steps": steps,
                           "us_per_step": t / steps * 1e6, "code": int(r.code), "repeats_s": ts})
        rows[name] = {"first_call_s": compile_first, "ladder": ladder}

    fun_np = lambda t, y: rhs_numpy(t, y, L, W, E6, g0, coef)  # noqa: E731
    fun_nb = lambda t, y: nb["rhs_alloc"](t, y, L, W, E6, g0, coef)  # noqa: E731
    assert np.allclose(fun_np(0.01, y0 + 1e-5), fun_nb(0.01, y0 + 1e-5), rtol=1e-12, atol=1e-12)
    def run_numba(r):
        y, steps, nfev, ok = nb["dop853"](y0, 0.0, T_END, r, r * ATOL_PER_RTOL, L, W, E6, g0, coef, 10**7)
        return y, {"steps": int(steps), "nfev": int(nfev), "success": bool(ok)}

    peers = {
        "scipy solve_ivp DOP853, numpy RHS": lambda r: run_solve_ivp(fun_np, y0, r, r * ATOL_PER_RTOL),
        "scipy solve_ivp DOP853, numba RHS": lambda r: run_solve_ivp(fun_nb, y0, r, r * ATOL_PER_RTOL),
        "scipy ode dop853 (Fortran), numba RHS": lambda r: run_fortran(fun_nb, y0, r, r * ATOL_PER_RTOL),
        "numba DOP853 (whole integrator)": run_numba,
    }
    for name, run in peers.items():
        ladder = []
        for i, rtol in enumerate(rtols):
            # numba is compiled above (the reference check); scipy needs no warm-up
            t, _, (y, info), ts = timed(lambda: run(rtol), repeats, warm=False)
            row = {"rtol": rtol, "s": t, "error": err(y), **info, "repeats_s": ts}
            if "nfev" in info:
                row["us_per_step"] = t / (info["nfev"] / 12) * 1e6
            ladder.append(row)
        rows[name] = {"ladder": ladder}
    for name, v in rows.items():
        for row in v["ladder"]:
            print(f"  [{label}] {name:<40} rtol {row['rtol']:.0e}: {row['s'] * 1e3:9.2f} ms  "
                  f"err {row['error']:.2e}")

    # ratios: peer / rotorjax, at the same rtol and at matched error
    ratios = []
    for rj_name in ("rotorjax Dopri8", "rotorjax Tsit5"):
        for i, rrow in enumerate(rows[rj_name]["ladder"]):
            for peer in peers:
                pl = rows[peer]["ladder"]
                cost, how = interpolate_cost([p["error"] for p in pl], [p["s"] for p in pl], rrow["error"])
                ratios.append({"rotorjax": rj_name, "rtol": rrow["rtol"], "rotorjax_error": rrow["error"],
                               "peer": peer, "same_rtol": pl[i]["s"] / rrow["s"],
                               "matched_error": cost / rrow["s"], "match": how})
    return {"state_size": scene.state_size, "orbit_amplitude_m": amplitude,
            "reference": {"solver": "rotorjax Dopri8", "rtol": REF_RTOL, "atol": REF_ATOL,
                          "steps": int(ref.stats["num_steps"]),
                          "numba_dop853_vs_reference": ref_check},
            "reference_final_nodes_xy": ref_xy.tolist(), "runs": rows, "ratios": ratios}


def rhs_cost(scene, nb, n_batch=64, evals=200):
    """Microseconds per right-hand-side evaluation, inside one compiled loop (no
    dispatch): rotorjax's `vector_field` for one state and vmapped over `n_batch`
    states and times (as under a vmapped `simulate`); the numba peer's."""
    import jax
    import jax.numpy as jnp

    rng = np.random.default_rng(0)
    Y = jnp.asarray(rng.normal(size=(n_batch, scene.state_size)) * 1e-5)
    T = jnp.linspace(0.01, 0.02, n_batch)

    def loop(f, y):
        return jax.lax.fori_loop(0, evals, lambda i, y: y + 1e-12 * f(y), y)
    one = jax.jit(lambda y: loop(lambda y: scene.vector_field(T[0], y), y))
    many = jax.jit(lambda y: loop(lambda y: jax.vmap(scene.vector_field)(T, y), y))
    out = {}
    for name, fn, arg, k in (("rotorjax_single", one, Y[0], 20), (f"rotorjax_vmap_{n_batch}", many, Y, 5)):
        t, _, _, _ = timed(lambda: fn(arg), k)
        out[name] = t / evals * 1e6
    pm = PeerModel(scene)
    L, W, E6, g0, coef = pm.params(SPEED)
    y = np.asarray(Y[0])
    nb["rhs_loop"](y, evals, L, W, E6, g0, coef)
    t, _, _, _ = timed(lambda: nb["rhs_loop"](y, evals * 10, L, W, E6, g0, coef), 20, warm=False)
    out["numba_single"] = t / (evals * 10) * 1e6
    out[f"rotorjax_vmap_{n_batch}_per_state"] = out[f"rotorjax_vmap_{n_batch}"] / n_batch
    return out


# ------------------------------------------------------------------------------- (2)
def batch(label, scene, n_batch, repeats, nb, n_check=8, group_if_waste=1.1):
    """(2): one vmapped call over all speeds; four calls of neighbouring speeds
    where the one call's lock-step waste (max / mean steps) exceeds
    `group_if_waste` (below it grouping cannot gain more than that); the peers."""
    import equinox as eqx
    import jax
    import jax.numpy as jnp

    import rotorjax as rj

    pm = PeerModel(scene)
    y0 = np.asarray(scene.rest_state())
    y0j = jnp.asarray(y0)
    speeds = np.linspace(100.0, 200.0, n_batch)
    rtol, atol = BATCH_RTOL, BATCH_RTOL * ATOL_PER_RTOL

    @eqx.filter_jit
    def vmapped(ws):
        def one(w):
            s = eqx.tree_at(lambda sc: sc.speed.constant, scene, w)
            r = rj.simulate(s, y0j, (0.0, T_END), solver="dopri8", rtol=rtol, atol=atol, max_steps=MAX_STEPS)
            return r.ys[-1], r.stats["num_steps"], r.code
        return eqx.filter_vmap(one)(ws)

    def compiled(ws):
        """Ahead-of-time compile (no run): `(compile s, executable)`."""
        t0 = time.perf_counter()
        exe = vmapped.lower(ws).compile()
        return time.perf_counter() - t0, exe

    ws_all = jnp.asarray(speeds)
    c_one, exe_one = compiled(ws_all)
    t_one, _, (ys, steps, codes), ts_one = timed(lambda: exe_one(ws_all), repeats, warm=False)
    ys, steps = np.asarray(ys), np.asarray(steps)
    res = {"n_batch": n_batch, "speeds": [float(speeds[0]), float(speeds[-1])], "rtol": rtol, "atol": atol,
           "rotorjax_vmap_one_call": {"s": t_one, "compile_s": c_one, "repeats_s": ts_one,
                                      "us_per_batched_step": t_one / int(steps.max()) * 1e6,
                                      "failed": int(np.sum(np.asarray(codes) != 0)),
                                      "steps_mean": float(steps.mean()), "steps_max": int(steps.max()),
                                      "lockstep_max_over_mean": float(steps.max() / steps.mean())}}
    ratios = {}
    # the batch path (`simulate_batch`, its default method: the vectorised stepper, lanes
    # refilled from the queue; the matrices equal at every speed pass once, unbatched)
    from rotorjax.solve import simulate_batch

    scenes = eqx.filter_vmap(lambda w: eqx.tree_at(lambda sc: sc.speed.constant, scene, w))(ws_all)
    y0s = jnp.tile(y0j, (n_batch, 1))

    def batched(shard=False):
        r = simulate_batch(scenes, y0s, (0.0, T_END), solver="dopri8", rtol=rtol, atol=atol, max_steps=MAX_STEPS,
                           shard=shard)
        return r.ys[:, -1], r.stats["num_steps"], r.code, r.solver
    t_buf, first_buf, (ys_b, steps_b, codes_b, how), ts_buf = timed(batched, repeats)
    ys_b, steps_b = np.asarray(ys_b), np.asarray(steps_b)
    res["rotorjax_batch"] = {"s": t_buf, "first_call_s": first_buf, "repeats_s": ts_buf, "method": how,
                             "lanes": n_batch, "failed": int(np.sum(np.asarray(codes_b) != 0)),
                             "steps_mean": float(steps_b.mean()), "steps_max": int(steps_b.max()),
                             "us_per_lane_step": t_buf / int(steps_b.sum()) * 1e6}
    best_rj = min(t_one, t_buf)
    n_dev = len(jax.local_devices())
    if n_dev > 1:  # the same batch split over the host devices (one core each), against the 2-thread loop
        t_sh, first_sh, (ys_sh, _, codes_sh, _), ts_sh = timed(lambda: batched(shard=True), repeats)
        res[f"rotorjax_batch_{n_dev}_devices"] = {
            "s": t_sh, "first_call_s": first_sh, "repeats_s": ts_sh, "devices": n_dev,
            "failed": int(np.sum(np.asarray(codes_sh) != 0)),
            "max_abs_diff_from_one_device": float(np.max(np.abs(np.asarray(ys_sh) - ys_b)))}
    chunk = max(1, n_batch // 4)
    if steps.max() / steps.mean() > group_if_waste:
        parts = [jnp.asarray(speeds[i:i + chunk]) for i in range(0, n_batch, chunk)]
        c_grp, exe_grp = compiled(parts[0])
        t_grp, _, outs, _ = timed(lambda: [exe_grp(w) for w in parts], repeats, warm=False)
        sg = [np.asarray(o[1]) for o in outs]
        res[f"rotorjax_vmap_{len(parts)}_calls_of_{chunk}"] = {
            "s": t_grp, "compile_s": c_grp, "steps_max_per_call": [int(x.max()) for x in sg],
            "lane_steps_paid_over_mean": float(sum(x.max() * x.size for x in sg) / steps.sum())}
        ratios["rotorjax_one_call_over_grouped"] = t_one / t_grp
        best_rj = min(best_rj, t_grp)
    else:
        t_grp = None
        res["grouped_calls"] = (f"not timed: lock-step waste {steps.max() / steps.mean():.3f} <= "
                                f"{group_if_waste} (grouping cannot gain more)")

    params = [pm.params(w) for w in speeds]
    Ls = np.ascontiguousarray(np.stack([p[0] for p in params]))
    coefs = np.stack([p[4] for p in params])
    _, W, E6, g0, _ = params[0]

    def numba_loop():
        out, st = [], []
        for i in range(n_batch):
            # the per-speed matrices are built inside the loop, as rotorjax forms C + w G1 at run time
            y, n_steps, _, _ = nb["dop853"](y0, 0.0, T_END, rtol, atol, pm.params(speeds[i])[0], W, E6, g0,
                                            coefs[i], 10**7)
            out.append(y)
            st.append(n_steps)
        return np.stack(out), np.asarray(st)
    t_nb, _, (ys_nb, steps_nb), ts_nb = timed(numba_loop, repeats, warm=False)
    threads = min(2, nb["numba"].config.NUMBA_NUM_THREADS)
    nb["numba"].set_num_threads(threads)
    nb["dop853_batch"](y0, 1e-3, rtol, atol, Ls[:2], W, E6, g0, coefs[:2], 10**7)  # compile, short span
    t_par, _, _, ts_par = timed(lambda: nb["dop853_batch"](y0, T_END, rtol, atol, Ls, W, E6, g0, coefs, 10**7),
                        repeats, warm=False)

    # scipy: a loop over a subset (a Python loop is linear in the count), scaled
    sub = np.unique(np.linspace(0, n_batch - 1, min(4, n_batch)).astype(int))

    def scipy_loop():
        for i in sub:
            L, _, _, _, coef = pm.params(speeds[i])
            run_solve_ivp(lambda t, y: nb["rhs_alloc"](t, y, L, W, E6, g0, coef), y0, rtol, atol)
    t_sp_sub, _, _, _ = timed(scipy_loop, 1, warm=False)
    t_sp = t_sp_sub / len(sub) * n_batch

    # errors on a subset of lanes against numba DOP853 at rtol 1e-12 (validated in (1))
    chk = np.unique(np.linspace(0, n_batch - 1, min(n_check, n_batch)).astype(int))
    errs_rj, errs_b, errs_nb = [], [], []
    for i in chk:
        yr, *_ = nb["dop853"](y0, 0.0, T_END, REF_RTOL, REF_ATOL, Ls[i], W, E6, g0, coefs[i], 10**7)
        ref = pm.nodes_xy(yr)
        amp = np.max(np.abs(ref))
        errs_rj.append(np.max(np.abs(pm.nodes_xy(ys[i]) - ref)) / amp)
        errs_b.append(np.max(np.abs(pm.nodes_xy(ys_b[i]) - ref)) / amp)
        errs_nb.append(np.max(np.abs(pm.nodes_xy(ys_nb[i]) - ref)) / amp)
    res.update({
        "numba_dop853_loop_1_thread": {"s": t_nb, "repeats_s": ts_nb, "steps_mean": float(steps_nb.mean()),
                                       "steps_max": int(steps_nb.max())},
        f"numba_dop853_prange_{threads}_threads": {"s": t_par, "repeats_s": ts_par},
        "scipy_solve_ivp_dop853_numba_rhs_loop": {"s": t_sp, "timed_on_lanes": int(len(sub)), "repeats": 1,
                                                  "note": "timed on a subset, scaled to the batch"},
        "error_lanes": chk.tolist(),
        "rotorjax_error_max": float(np.max(errs_rj)), "rotorjax_batch_error_max": float(np.max(errs_b)),
        "numba_error_max": float(np.max(errs_nb)),
        "error_note": "max |node x,y - ref| / max |node x,y of ref| at t = 0.5 over the checked lanes; "
                      "ref: numba DOP853 rtol 1e-12",
    })
    ratios.update({"numba_loop_over_rotorjax_one_call": t_nb / t_one,
                   "numba_loop_over_rotorjax_batch": t_nb / t_buf,
                   f"numba_prange_{threads}_threads_over_rotorjax_batch": t_par / t_buf,
                   "numba_loop_over_rotorjax_best": t_nb / best_rj,
                   f"numba_prange_{threads}_threads_over_rotorjax_best": t_par / best_rj,
                   "scipy_loop_over_rotorjax_best": t_sp / best_rj})
    if n_dev > 1:
        ratios[f"numba_prange_{threads}_threads_over_rotorjax_batch_{n_dev}_devices"] = t_par / t_sh
    res["ratios"] = ratios
    grp = "" if t_grp is None else f", {n_batch // chunk} calls of {chunk} {t_grp:.3f} s"
    print(f"  [{label}] batch {n_batch}: rotorjax vmap {t_one:.3f} s (steps mean {steps.mean():.0f}, max "
          f"{steps.max()}){grp}, simulate_batch ({how}) {t_buf:.3f} s"
          f"{f' ({n_dev} devices {t_sh:.3f} s)' if n_dev > 1 else ''}; numba loop {t_nb:.3f} s, prange "
          f"{threads} thr {t_par:.3f} s; "
          f"scipy loop {t_sp:.2f} s (scaled from {len(sub)}); err rotorjax {np.max(errs_rj):.1e} "
          f"(batch {np.max(errs_b):.1e}), "
          f"numba {np.max(errs_nb):.1e}")
    return res


# ------------------------------------------------------------------------------- main
def print_table(out):
    print("\nspeed vs error (ms; error = max node |dx| at t=0.5 / orbit amplitude)")
    for label, wp in out["work_precision"].items():
        names = list(wp["runs"])
        print(f"\n{label} (state {wp['state_size']}, orbit {wp['orbit_amplitude_m']:.3g} m)")
        print(f"{'rtol':>7} " + " ".join(f"{n[:26]:>26}" for n in names))
        for i, rtol in enumerate(wp["runs"][names[0]]["ladder"]):
            cells = [f"{wp['runs'][n]['ladder'][i]['s'] * 1e3:9.1f} ({wp['runs'][n]['ladder'][i]['error']:.1e})"
                     for n in names]
            print(f"{rtol['rtol']:>7.0e} " + " ".join(f"{c:>26}" for c in cells))
        print("  ratio peer/rotorjax Dopri8 at matched error:")
        for r in wp["ratios"]:
            if r["rotorjax"] == "rotorjax Dopri8":
                print(f"    rtol {r['rtol']:.0e} err {r['rotorjax_error']:.1e}  {r['peer']:<40} "
                      f"{r['matched_error']:7.2f}  (same rtol {r['same_rtol']:.2f}) {r['match']}")


def main():
    global T_END
    ap = argparse.ArgumentParser()
    ap.add_argument("--quick", action="store_true", help="two tolerances, one repeat, batch of 8; write nothing")
    ap.add_argument("--smoke", action="store_true",
                    help=f"as --quick, t_end {SMOKE_T_END}, one tolerance, one call each, the reduced scene, "
                         "batch of 2; write nothing")
    ap.add_argument("--repeats", type=int, default=3)
    ap.add_argument("--batch", type=int, default=64)
    ap.add_argument("--reduced-modes", type=int, default=8)
    ap.add_argument("--large-batch", type=int, default=512,
                    help="the reduced rotor's batch timed again at this many speeds (0: not)")
    args = ap.parse_args()
    args.quick = args.quick or args.smoke
    rtols = (RTOLS[1],) if args.smoke else (RTOLS[0], RTOLS[2]) if args.quick else RTOLS
    repeats = 0 if args.smoke else 1 if args.quick else args.repeats
    n_batch = 2 if args.smoke else 8 if args.quick else args.batch
    rhs_batch = 4 if args.smoke else 64
    if args.smoke:
        T_END = SMOKE_T_END

    import diffrax
    import equinox
    import jax
    import scipy

    import rotorjax  # noqa: F401

    t_start = time.perf_counter()
    nb = make_numba()
    scenes = {"full (28 dofs)": build_scene(None),
              f"reduced ({args.reduced_modes} modes)": build_scene(args.reduced_modes)}
    out = {"benchmark": "rotor_scene (ross-compare FE rotor, unbalance + cubic bearings)",
           "machine": {**machine(), "processor": platform.processor(), "jax_backend": jax.default_backend()},
           "versions": {"jax": jax.__version__, "diffrax": diffrax.__version__, "equinox": equinox.__version__,
                        "numpy": np.__version__, "scipy": scipy.__version__, "numba": nb["numba"].__version__,
                        "python": platform.python_version()},
           "setup": {"preset": "ross-compare", "params": {"kyy": 1e6, "cxx": 2000.0, "cyy": 2000.0},
                     "unbalance": UNBALANCE, "cubic_bearings": CUBIC, "speed_rad_s": SPEED, "t_end_s": T_END,
                     "initial_state": "rest", "atol": f"rtol * {ATOL_PER_RTOL}", "repeats": repeats,
                     "max_steps": MAX_STEPS, "xla_flags": os.environ.get("XLA_FLAGS")},
           "work_precision": {}, "batch": {}}
    # --smoke: everything on the reduced scene only (the same code as the full one, which is built)
    run_scenes = dict(list(scenes.items())[1:]) if args.smoke else scenes
    for label, scene in run_scenes.items():
        print(f"work-precision: {label}")
        out["work_precision"][label] = work_precision(label, scene, rtols, repeats, nb)
        out["work_precision"][label]["rhs_us_per_eval"] = rhs_cost(scene, nb, rhs_batch)
        print(f"  [{label}] us per RHS evaluation: {out['work_precision'][label]['rhs_us_per_eval']}")
    if len(run_scenes) == 2:
        full, red = (out["work_precision"][k] for k in scenes)
        out["reduction_error"] = {
            "reduced_vs_full_reference": float(np.max(np.abs(np.asarray(red["reference_final_nodes_xy"])
                                                             - np.asarray(full["reference_final_nodes_xy"])))
                                               / full["orbit_amplitude_m"]),
            "note": "final node displacements, reduced reference vs full reference, / full orbit amplitude"}
    for label, scene in run_scenes.items():
        print(f"batch: {label}")
        # --smoke: grouped calls whatever the lock-step waste (to run that path too)
        out["batch"][label] = batch(label, scene, n_batch, repeats, nb, group_if_waste=1.0 if args.smoke else 1.1)
    if not args.quick and args.large_batch:  # the small rotor with enough speeds to fill both devices' lanes
        label = list(scenes)[1]
        print(f"batch: {label}, {args.large_batch} speeds")
        out["batch"][f"{label}, {args.large_batch} speeds"] = batch(label, scenes[label], args.large_batch, repeats,
                                                                     nb)
    out["total_wall_s"] = time.perf_counter() - t_start
    print_table(out)
    print("\nbatch (s; ratio = peer / best rotorjax):")
    for label, b in out["batch"].items():
        print(f"  {label}: " + ", ".join(f"{k} {v['s']:.3f}" for k, v in b.items()
                                        if isinstance(v, dict) and "s" in v))
        print("    " + ", ".join(f"{k} {v:.2f}" for k, v in b["ratios"].items()))
        print(f"    lock-step max/mean steps {b['rotorjax_vmap_one_call']['lockstep_max_over_mean']:.3f}; "
              f"error rotorjax {b['rotorjax_error_max']:.1e}, numba {b['numba_error_max']:.1e}")
    if "reduction_error" in out:
        print(f"\nreduction error (8 modes vs full, final node displacements / orbit): "
              f"{out['reduction_error']['reduced_vs_full_reference']:.2e}")
    print(f"total {out['total_wall_s']:.0f} s")
    if args.smoke:
        print("smoke run: nothing written")
    elif not args.quick:
        write_results("rotor_scene", out)


if __name__ == "__main__":
    main()
