"""The two headline comparisons on model 001 (a rotor on anisotropic supports with
a two-weight auto-balancer, `anisotropic-abb`, Table 1's parameters):

- `sweep_comparison`: a speed sweep, final states at tau = t_end, rotorjax's public
  path (`rotorjax.sweep` over a function returning `rotorjax.IVP`: the buffered batch,
  Dopri8) against numba RK4 (1 thread and every core), Hairer's DOP853 in C
  (`numbalsoda`, numba right-hand side, a `prange` loop) and scipy DOP853 loops with the
  closed-form pure-Python right-hand side, each on its own ladder (tolerances, step
  counts), the error measured against a tight reference on a subset of the speeds;
- `floquet_comparison`: a Floquet stability map of the main motion (speeds x weight
  damping mu_w), rotorjax (`rotorjax.sweep` of `main_motion_floquet(...).margin`)
  against a scipy DOP853 loop over the augmented system (complex-step Jacobian), the
  error in the largest Floquet exponent against a tight reference.

Each returns a `Comparison`: the curves of the work-precision diagram (error against
cost per speed or per point, one curve per method) and the ratios at matched error
(the peer's cost read off its own ladder at rotorjax's error, `interpolate_cost`).
"""

import functools
import importlib.util
import os

import numpy as np

from ._matching import interpolate_cost
from ._report import Comparison, Point, timed

#: model 001's Floquet study (eps = 0.001, Table 1's other parameters) and its main motion
FLOQUET_BASE = dict(n_eta=7.0, mu_xi=0.25, mu_eta=0.5, sigma=0.5, c=0.5, eps=0.001, mu_w=0.25)
Y_MAIN = np.concatenate([[0.0, 0.0], 2 * np.pi / 3 * np.array([1.0, 2.0]), np.zeros(4)])
#: a speed whose final state two tight references (rotorjax, scipy) give alike to this is
#: well-conditioned; the others (~9% of the speeds, near n = 7.2..8.2: slipping weights)
#: are left out of the errors, as in `benchmarks/sweep_throughput.py`
CONDITIONED = 1e-9


def _preset():
    from rotorjax.presets import anisotropic_abb

    return anisotropic_abb


@functools.lru_cache(maxsize=None)
def _sweep_problem(rtol, t_end):
    """`point -> rotorjax.IVP` of the preset's perturbed main motion at speed `point["n"]`
    (one function object per `(rtol, t_end)`, so that `sweep` reuses its compilation)."""
    from rotorjax.solve import IVP

    A = _preset()
    p = dict(A.PRESET.defaults)
    groups = {k: p[k] for k in A.GROUPS}
    y0 = np.asarray(A.PRESET.build(p).y0)

    def one(point):
        scene = A.scene_from_groups(**groups, n=point["n"], K=p["K"])
        return IVP(scene, y0, (0.0, t_end), solver="dopri8", rtol=rtol, atol=rtol * 1e-3, max_steps=1_000_000)

    return one, groups, y0


def _final_states(fn, speeds):
    import jax

    from rotorjax.sweep import sweep

    res = sweep(fn, {"n": np.asarray(speeds)}, progress=False)
    v = jax.block_until_ready(res.values)
    code = np.asarray(v.code)
    if np.any(code != 0):
        bad = np.asarray(speeds)[code != 0]
        raise FloatingPointError(f"model 001 sweep: the integration failed at {bad.size} speed(s), first n = "
                                 f"{bad[0]:.4g} (code {int(code[code != 0][0])})")
    return np.asarray(v.ys)[:, -1]


def numba_available():
    return importlib.util.find_spec("numba") is not None


def sweep_comparison(sizes, progress, repeats):
    from . import _peers001

    speeds = np.linspace(0.5, 10.0, sizes.sweep_speeds)
    rng = np.random.default_rng(0)
    sub = np.sort(rng.choice(speeds.size, size=sizes.sweep_subset, replace=False))
    comp = Comparison(name="model 001 sweep", what=f"{speeds.size} speeds n in [0.5, 10], tau in [0, "
                      f"{sizes.t_end:g}], final states", cost_unit="s per speed",
                      error_label="max |final state - reference| (subset)")

    progress("model 001 sweep: references")
    ref_fn, groups, y0 = _sweep_problem(1e-12, sizes.t_end)
    ref = _final_states(ref_fn, speeds[sub])
    ref_scipy, _, _ = _peers001.scipy_loop(speeds[sub], y0, sizes.t_end, groups, "DOP853", 1e-12, 1e-15)
    cond = np.max(np.abs(ref - ref_scipy), axis=1) < CONDITIONED
    if not cond.any():
        raise FloatingPointError("model 001 sweep: no speed of the subset is well-conditioned (the two tight "
                                 "references disagree everywhere)")
    comp.notes.append(f"errors over {int(cond.sum())} of {cond.size} subset speeds on which rotorjax (rtol "
                      "1e-12) and scipy DOP853 (rtol 1e-12) agree to 1e-9 (the others are ill-conditioned)")

    def err(final):
        return float(np.max(np.abs(final[cond] - ref[cond])))

    progress("model 001 sweep: rotorjax")
    label = "rotorjax sweep (buffered Dopri8)"
    for rtol in sizes.sweep_rtols:
        fn, _, _ = _sweep_problem(rtol, sizes.t_end)
        first, run_s, final = timed(lambda: _final_states(fn, speeds), repeats)
        comp.add(label, Point(f"{rtol:.0e}", err(final[sub]), run_s / speeds.size, first_call_s=first))
    comp.rotorjax = label
    tightest = min(p.error for p in comp.curves[label])

    progress("model 001 sweep: scipy")
    peer = "scipy DOP853 loop, pure-Python rhs"
    for rtol in sizes.scipy_rtols:
        final, wall, failed = _peers001.scipy_loop(speeds[sub], y0, sizes.t_end, groups, "DOP853", rtol,
                                                   rtol * 1e-3)
        comp.add(peer, Point(f"{rtol:.0e}", err(final), wall / sub.size, failed=int(failed)))
        if comp.curves[peer][-1].error < tightest:
            break
    comp.peers.append(peer)

    progress("model 001 sweep: numba")
    if not numba_available():
        comp.skipped.append(("numba RK4", "numba is not installed (pip install numba, or rotorjax[bench])"))
        return comp
    from . import _numba001

    import numba

    threads = sorted({1, min(os.cpu_count() or 1, numba.config.NUMBA_NUM_THREADS)})
    # at least 4 speeds per thread, so that every core has work
    n_timing = min(speeds.size, max(sizes.numba_timing_speeds, 4 * threads[-1]))
    timing = speeds[np.linspace(0, speeds.size - 1, n_timing).astype(int)]
    for th in threads:
        name = f"numba RK4, {th} thread{'s' if th > 1 else ''}"
        for n_steps in sizes.numba_steps:
            final, _ = _numba001.numba_rk4(speeds[sub], y0, sizes.t_end, groups, n_steps, threads=th)
            walls = [_numba001.numba_rk4(timing, y0, sizes.t_end, groups, n_steps, threads=th)[1]
                     for _ in range(repeats)]
            e = err(final) if np.all(np.isfinite(final)) else float("inf")
            comp.add(name, Point(f"h={sizes.t_end / n_steps:.2g}", e, float(np.median(walls)) / timing.size))
        comp.peers.append(name)
    comp.notes.append(f"numba rungs timed on {timing.size} speeds (a fixed-step cost per speed is the same at "
                      "every speed)")

    progress("model 001 sweep: C DOP853")
    from . import _dop853_001

    if not _dop853_001.available():
        comp.skipped.append(("C DOP853", "numbalsoda is not installed (pip install numbalsoda, or rotorjax[bench])"))
        return comp
    for th in threads[-1:]:  # every core, as the numba peer's fastest
        name = f"C DOP853 (numbalsoda), {th} thread{'s' if th > 1 else ''}"
        for rtol in sizes.scipy_rtols:
            final, _, ok = _dop853_001.dop853_loop(speeds, y0, sizes.t_end, groups, rtol, rtol * 1e-3, th)
            walls = [_dop853_001.dop853_loop(speeds, y0, sizes.t_end, groups, rtol, rtol * 1e-3, th)[1]
                     for _ in range(repeats)]
            comp.add(name, Point(f"{rtol:.0e}", err(final[sub]), float(np.median(walls)) / speeds.size,
                                 failed=int(not ok)))
            if comp.curves[name][-1].error < tightest:
                break
        comp.peers.append(name)
    return comp


@functools.lru_cache(maxsize=None)
def floquet_reference_fn(rtol):
    """`point -> PeriodicOrbit`: the main motion at (n, mu_w), its Floquet analysis at
    `rtol` (atol `rtol * 1e-2`)."""
    A = _preset()

    def ref(p):
        return A.main_motion_reference(dict(FLOQUET_BASE, mu_w=p["mu_w"]), p["n"], 1.0, rtol, rtol * 1e-2)

    return ref


@functools.lru_cache(maxsize=None)
def floquet_margin_fn(rtol):
    """`point -> largest Floquet exponent` of the main motion at (n, mu_w) (one function
    object per `rtol`, so that `sweep` reuses its compilation)."""
    from rotorjax.analysis import floquet_of

    ref = floquet_reference_fn(rtol)

    def one(p):
        return floquet_of(ref(p)).margin

    return one


def _batch_margins(rtol, n, mu_w):
    """The main motion's largest Floquet exponent at the (n, mu_w) pairs, by
    `floquet_batch` (the variational equations on the batch kernel); NaN where a
    point failed."""
    import equinox as eqx
    import jax.numpy as jnp

    from rotorjax.analysis import floquet_batch

    res = floquet_batch(eqx.filter_vmap(floquet_reference_fn(rtol))({"n": jnp.asarray(n, dtype=jnp.float64),
                                                                     "mu_w": jnp.asarray(mu_w, dtype=jnp.float64)}))
    return np.asarray(res.checked_margin)


def _margins(rtol, speeds, mu_w):
    """The map over the product grid (speed-major), by `floquet_batch`."""
    n, mu = (a.reshape(-1) for a in np.meshgrid(speeds, mu_w, indexing="ij"))
    m = _batch_margins(rtol, n, mu)
    if not np.all(np.isfinite(m)):
        raise FloatingPointError(f"Floquet map: {int(np.sum(~np.isfinite(m)))} point(s) without a finite "
                                 "exponent")
    return m


def floquet_comparison(sizes, progress, repeats):
    from . import _peers001

    speeds = np.linspace(0.5, 10.0, sizes.floquet_speeds)
    mu_w = np.linspace(0.05, 1.0, sizes.floquet_mu_w)
    n_points = speeds.size * mu_w.size
    rng = np.random.default_rng(1)
    idx = np.sort(rng.choice(n_points, size=sizes.floquet_subset, replace=False))
    sub_n, sub_mu = speeds[idx // mu_w.size], mu_w[idx % mu_w.size]
    comp = Comparison(name="Floquet map", what=f"model 001 main motion, {speeds.size} speeds x {mu_w.size} "
                      "mu_w", cost_unit="s per point", error_label="max |Floquet exponent - reference| (subset)")

    progress("Floquet map: references")
    ref = _subset_margins(1e-12, sub_n, sub_mu)
    ref_scipy = np.array([_peers001.scipy_margin(dict(FLOQUET_BASE, mu_w=m), n, Y_MAIN, 1e-12)
                          for n, m in zip(sub_n, sub_mu)])
    agree = float(np.max(np.abs(ref - ref_scipy)))
    comp.notes.append(f"reference: rotorjax at rtol 1e-12 on {idx.size} grid points; scipy at rtol 1e-12 "
                      f"agrees with it to {agree:.1e}")
    comp.checks["references_agree"] = agree

    progress("Floquet map: rotorjax")
    label = "rotorjax floquet_batch (variational equations on the batch kernel)"
    for rtol in sizes.floquet_rtols:
        first, run_s, m = timed(lambda: _margins(rtol, speeds, mu_w), repeats)
        e = float(np.max(np.abs(m.reshape(-1)[idx] - ref)))
        comp.add(label, Point(f"{rtol:.0e}", e, run_s / n_points, first_call_s=first))
    comp.rotorjax = label
    comp.checks["stable_fraction"] = float(np.mean(m < 0))

    progress("Floquet map: scipy")
    peer = "scipy DOP853 loop, pure-Python rhs"
    for rtol in sorted({*sizes.floquet_rtols, min(sizes.floquet_rtols) * 1e-2}, reverse=True):
        first, wall, vals = timed(lambda: np.array([_peers001.scipy_margin(dict(FLOQUET_BASE, mu_w=m), n, Y_MAIN,
                                                                           rtol) for n, m in zip(sub_n, sub_mu)]),
                                  1, warm=False)
        comp.add(peer, Point(f"{rtol:.0e}", float(np.max(np.abs(vals - ref))), wall / idx.size))
    comp.peers.append(peer)

    from . import _dop853_001

    if not _dop853_001.available():
        comp.notes.append("C DOP853 (numbalsoda) over the variational equations: skipped, numbalsoda missing "
                          "(pip install numbalsoda)")
        return comp
    progress("Floquet map: C DOP853")
    peer = "C DOP853 (numbalsoda) loop, variational equations, 1 thread"
    for rtol in sorted({*sizes.floquet_rtols, min(sizes.floquet_rtols) * 1e-2}, reverse=True):
        n, mu = (a.reshape(-1) for a in np.meshgrid(speeds, mu_w, indexing="ij"))
        walls = []
        for _ in range(max(repeats, 1)):
            m, wall, ok = _dop853_001.floquet_loop(n, mu, Y_MAIN, FLOQUET_BASE, rtol, rtol * 1e-2)
            walls.append(wall)
        comp.add(peer, Point(f"{rtol:.0e}", float(np.max(np.abs(m[idx] - ref))), float(np.median(walls)) / n.size,
                             failed=int(not ok)))
    comp.peers.append(peer)
    return comp


def _subset_margins(rtol, sub_n, sub_mu):
    """Margins at the listed (n, mu_w) pairs (not their product)."""
    return _batch_margins(rtol, sub_n, sub_mu)


def matched_rows(comp):
    """The table: for each rotorjax rung and each peer, the peer's cost at rotorjax's error."""
    rows = []
    for p in comp.curves[comp.rotorjax]:
        for peer in comp.peers:
            ladder = comp.curves[peer]
            cost, how = interpolate_cost([q.error for q in ladder], [q.cost for q in ladder], p.error)
            rows.append({"comparison": comp.name, "rotorjax_tolerance": p.tol, "error": p.error, "peer": peer,
                         "peer_cost": cost, "rotorjax_cost": p.cost, "ratio": cost / p.cost, "match": how,
                         "cost_unit": comp.cost_unit})
    return rows
