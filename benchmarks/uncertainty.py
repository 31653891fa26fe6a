"""Monte Carlo of a rotor file's critical speeds and log decrements under bearing
scatter: `rotorjax.uncertainty` against a numpy/scipy loop doing the same work, and
against ROSS (its `ST_Rotor` and a plain loop of its analyses) on the same samples.

The case (issue 34): `ross_compare.toml` (ROSS's example rotor) with its bearings
given damping (`cxx = cyy = 500 N s/m`) and 8 random bearing coefficients (kxx,
kyy, cxx, cyy of both, lognormal, 10 % sd); outputs: the forward 1x critical speeds
below 1000 rad/s and the log decrements of the first three modes at 500 rad/s.

- rotorjax: `rotor_quantities` + `propagate` on 10 000 samples (the CLI's default;
  vmapped through `rotorjax.sweep` in chunks of 128: each sample's rotor set through
  the parameters' leaves, each critical speed the fixed point `Omega = omega_k(Omega)`
  from the nominal one by 4 Newton steps on the nominal eigenpair (bordered solves
  of the quadratic eigenproblem) and one eigenvalue problem, its residual;
  the samples where the followed mode changed rank among the sorted frequencies
  again by the secant path (`fallback`); the first-order moments included).
- the peer: the strongest plain loop a user could write for the same numbers: the
  full matrices assembled once by rotorjax and the bearings' coefficients added to
  them in numpy (they enter affinely: one unit matrix per coefficient), then per
  sample the same Newton steps (`scipy.linalg.solve`, 29 x 29) and residual
  (`scipy.linalg.eigvals` on the first-order matrix), a sample whose residual is
  large by 6 fixed-point iterations. Its outputs equal rotorjax's to 1e-8 (checked
  on the first samples).
- ROSS (`_ross_st_rotor.run_ross_mc`, in ROSS's own interpreter: `--ross-python`,
  else `$ROTORJAX_ROSS_PYTHON`, else this one when it has `ross`; skipped with a
  note when there is none, or with `--no-ross`): the first `--ross-samples` (16) of
  the input samples rotorjax drew (`input_samples`, identical values), two ways:
  (a) `ross.stochastic.ST_Rotor.run_campbell` over 101 speeds 0..1000 rad/s, the
  forward 1x crossings interpolated linearly between them, the log decrements at
  500 rad/s read off the scan; (b) per sample `Rotor.run_critical_speed` (ROSS's
  Newton, rtol 0.005) + `run_modal(500)`. Each path timed once, everything
  included (building the rotors, the analyses, reading the results off) except
  ROSS's import and its first `run_modal` (numba compiling its mode-shape code,
  5-8 s: `ross.warmup_s`, excluded); BLAS pinned to 1 thread in ROSS's process.
  Recorded per path: seconds per sample and their ratio to rotorjax's (rotorjax's
  per sample from its 10 000-sample vmapped run), the parity per output (largest
  relative difference to rotorjax's outputs for the same inputs), and the Monte
  Carlo statistics (mean, std of each output over the samples all three
  answered) of ROSS's samples next to rotorjax's over the same samples: the
  inputs being identical, they agree to the parity (a std's relative difference
  up to the parity times mean/std). `--smoke`: 2 samples, a 21-speed scan.

rotorjax and the peer timed after a first call (rotorjax's compiles); per-sample
times and their ratio.
"""

import argparse
import json
import os
import sys
import time

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from _common import CpuWatch, machine, timed_first, write_results  # noqa: E402

COEFS = ("kxx", "kyy", "cxx", "cyy")
SETS = {"bearing0.cxx": 500.0, "bearing0.cyy": 500.0, "bearing1.cxx": 500.0, "bearing1.cyy": 500.0}
HI, SPEED, N_MODES, SCATTER = 1000.0, 500.0, 3, 0.1
ROSS_SPEEDS, ROSS_SPEEDS_SMOKE = 101, 21  # path (a)'s scan: this many speeds 0..HI


def _stats(Y, outputs):
    """`{"mean": {output: value}, "std": {...}}` over the rows of `Y` (std with ddof=1,
    as `propagate`'s); None for fewer than 2 rows."""
    Y = np.asarray(Y, dtype=float)
    if Y.shape[0] < 2:
        return {"mean": None, "std": None}
    return {"mean": dict(zip(outputs, Y.mean(axis=0).tolist())),
            "std": dict(zip(outputs, Y.std(axis=0, ddof=1).tolist()))}


def ross_comparison(args, res, q, per_rj):
    """ROSS on the first `args.ross_samples` of rotorjax's input samples (see the
    module) -> the `ross` part of the results, or None (with a printed note) when no
    ROSS interpreter is found or `--no-ross`."""
    from _ross_st_rotor import run_ross_mc

    from rotorjax.bench import ross_python

    if args.no_ross:
        print("ROSS not run (--no-ross)")
        return None
    python = ross_python(args.ross_python)
    if not python:
        print("ROSS not available: pass --ross-python or set $ROTORJAX_ROSS_PYTHON (ROSS runs in its own "
              "interpreter); ROSS not run")
        return None
    n = max(1, min(int(args.ross_samples), res.input_samples.shape[0]))
    X, Y = np.asarray(res.input_samples[:n], dtype=float), np.asarray(res.samples[:n], dtype=float)
    n_speeds = ROSS_SPEEDS_SMOKE if args.smoke else ROSS_SPEEDS
    n_crit = len(q.critical)
    watch = CpuWatch()
    try:
        r = run_ross_mc(python, X, np.linspace(0.0, HI, n_speeds), log_dec_speed=SPEED, hi=HI,
                        n_log_dec=N_MODES, blas_threads=1, timeout=300 if args.smoke else 3600)
    except RuntimeError as e:
        raise SystemExit(f"ROSS failed: {e}") from None
    outputs = list(q.outputs)
    out = {"version": r["version"], "python": python, "samples": n, "blas_threads": 1,
           "scan_speeds_a": int(r["n_speeds"]), "scan_range_a": [0.0, HI], "frequencies_a": r["frequencies"],
           "num_modes_b": r["num_modes"], "rtol_b": r["rtol"], "warmup_s": r["warmup_s"],
           "cpu_while_ross_ran": watch.report()}
    Z = {}
    for path in ("a", "b"):
        p = r.get(path) or {"error": "not run"}
        if "error" in p:
            raise SystemExit(f"ROSS path ({path}) failed: {p['error']}")
        Z[path] = z = np.full_like(Y, np.nan)
        count_mismatch = 0
        for i in range(n):
            cs, ld = p["critical_speeds"][i], p["log_dec"][i][:N_MODES]
            if len(cs) == n_crit:
                z[i, :n_crit] = cs
            else:
                count_mismatch += 1
            z[i, n_crit:n_crit + len(ld)] = ld
        rel = np.abs(z / Y - 1)
        parity = {o: (float(np.nanmax(rel[:, j])) if np.any(np.isfinite(rel[:, j])) else None)
                  for j, o in enumerate(outputs)}
        finite = [v for v in parity.values() if v is not None]
        out[path] = {"seconds": p["seconds"], "per_sample_s": p["per_sample_s"],
                     "ratio_over_rotorjax": p["per_sample_s"] / per_rj,
                     "parity_max_rel": parity, "parity_max_rel_all": max(finite) if finite else None,
                     "samples_compared": int(np.sum(np.all(np.isfinite(rel), axis=1))),
                     "critical_speed_count_mismatches": count_mismatch}
        if path == "b":
            out[path]["mixed_crossings_resolved_by_orbits"] = sum(len(m) for m in p.get("mixed", []))
    # the statistics over the samples all three answered (finite outputs)
    common = np.all(np.isfinite(Y), axis=1) & np.all(np.isfinite(Z["a"]), axis=1) & np.all(np.isfinite(Z["b"]), axis=1)
    stats = {"samples": int(common.sum()), "rotorjax": _stats(Y[common], outputs)}
    for path in ("a", "b"):
        stats[f"ross_{path}"] = st = _stats(Z[path][common], outputs)
        ref = stats["rotorjax"]
        if st["mean"] and ref["mean"]:
            stats[f"ross_{path}_rel_diff"] = {
                k: {o: abs(st[k][o] / ref[k][o] - 1) for o in outputs} for k in ("mean", "std")}
    out["mc_stats"] = stats
    out["ross_a_per_sample_s"] = out["a"]["per_sample_s"]
    out["ross_b_per_sample_s"] = out["b"]["per_sample_s"]
    out["ratio_ross_a_over_rotorjax"] = out["a"]["ratio_over_rotorjax"]
    out["ratio_ross_b_over_rotorjax"] = out["b"]["ratio_over_rotorjax"]
    return out


class NumpyPeer:
    """The peer (see the module): affine bearing matrices in numpy, scipy eigenvalues."""

    def __init__(self, file, names, nominal, critical):
        import jax.numpy as jnp

        from rotorjax.models._parameters import parts_of, with_values
        from rotorjax.uncertainty._rotor import NEWTON_STEPS

        parts = parts_of(file.scene)
        paths = [file.path(n) for n in names]

        def mats(values):
            lm = with_values(parts, paths, jnp.asarray(values)).rotor.linear_matrices(1.0)
            return [np.asarray(a) for a in (lm.M, lm.C, lm.G, lm.K)]

        self.M, self.C0, self.G1, self.K0 = mats(nominal)
        self.dC, self.dK = [], []
        for i in range(len(names)):
            v = np.array(nominal, dtype=float)
            v[i] += 1.0
            _, C, _, K = mats(v)
            self.dC.append(C - self.C0)
            self.dK.append(K - self.K0)
        self.dC, self.dK = np.stack(self.dC), np.stack(self.dK)
        self.nominal, self.critical = np.asarray(nominal, dtype=float), critical
        self.Minv = np.linalg.inv(self.M)
        self.steps = NEWTON_STEPS

        self.pairs = []
        for W, k in critical:
            lam, vec = np.linalg.eig(self._state(self.C0, self.K0, W))
            up = np.flatnonzero(lam.imag > 0)
            i = up[np.argsort(lam.imag[up])][k]
            u = vec[: self.M.shape[0], i]
            self.pairs.append((lam[i], u / np.linalg.norm(u)))

    def _state(self, C, K, speed):
        n = self.M.shape[0]
        return np.block([[np.zeros((n, n)), np.eye(n)], [-self.Minv @ K, -self.Minv @ (C + speed * self.G1)]])

    def _freqs(self, C, K, speed):
        import scipy.linalg

        lam = scipy.linalg.eigvals(self._state(C, K, speed), check_finite=False)
        lam = lam[np.imag(lam) > 0]
        return lam[np.argsort(np.imag(lam))]

    def _newton(self, C, K, W, pair):
        """rotorjax's eigenpair Newton (`critical_speed(..., pair=)`: the quadratic
        eigenproblem's bordered solves), in numpy/scipy."""
        import scipy.linalg

        lam, u = pair
        c, n, w = np.conj(u), u.size, W
        for _ in range(self.steps):
            D = C + w * self.G1
            border = np.zeros((n + 1, n + 1), complex)
            t = lam**2 * self.M + lam * D + K
            border[:n, :n], border[:n, n], border[n, :n] = t, (2 * lam * self.M + D) @ u, c
            rhs = np.stack([np.append(-(t @ u), 1.0 - c @ u), np.append(-lam * (self.G1 @ u), 0.0)], axis=1)
            s = scipy.linalg.solve(border, rhs, check_finite=False)
            dw = (w - np.imag(lam + s[n, 0])) / (np.imag(s[n, 1]) - 1.0)
            u, lam, w = u + s[:n, 0] + dw * s[:n, 1], lam + s[n, 0] + dw * s[n, 1], w + dw
        return w

    def __call__(self, values):
        d = np.asarray(values, dtype=float) - self.nominal
        C = self.C0 + np.tensordot(d, self.dC, 1)
        K = self.K0 + np.tensordot(d, self.dK, 1)
        out = []
        for (W, k), pair in zip(self.critical, self.pairs):
            w = self._newton(C, K, W, pair)
            res = float(np.imag(self._freqs(C, K, w)[k])) - w
            if not abs(res) <= 1e-8 * abs(w):   # the followed mode changed rank: the secant path's fixed point
                w = W
                for _ in range(6):
                    w = float(np.imag(self._freqs(C, K, w)[k]))
                res = float(np.imag(self._freqs(C, K, w)[k])) - w
            out.append(w if abs(res) <= 1e-8 * abs(w) else np.nan)
        lam = self._freqs(C, K, SPEED)[:N_MODES]
        out.extend(-2 * np.pi * np.real(lam) / np.imag(lam))
        return np.array(out)


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--smoke", action="store_true", help="tiny sizes, nothing written")
    ap.add_argument("--ross-samples", type=int, default=None,
                    help="how many of rotorjax's input samples ROSS runs (default 16; --smoke: 2)")
    ap.add_argument("--ross-python", default=None,
                    help="ROSS's interpreter (default $ROTORJAX_ROSS_PYTHON, else this one when it has ross)")
    ap.add_argument("--no-ross", action="store_true", help="do not run ROSS")
    args = ap.parse_args()
    if args.ross_samples is None:
        args.ross_samples = 2 if args.smoke else 16
    import jax

    from rotorjax.io import read_rotor_file, shipped_rotor
    from rotorjax.uncertainty import LogNormal, propagate, rotor_quantities

    n_rj, n_peer, repeats = (16, 4, 0) if args.smoke else (10_000, 128, 1)
    file = read_rotor_file(str(shipped_rotor("ross_compare")), SETS)
    names = [f"bearing{b}.{c}" for b in (0, 1) for c in COEFS]
    nominal = [float(file.entries[n].value) if n in file.entries else SETS[n] for n in names]
    inputs = {n: LogNormal(v, SCATTER * v) for n, v in zip(names, nominal)}
    watch = CpuWatch()
    t0 = time.perf_counter()
    q = rotor_quantities(file, inputs, hi=HI, speed=SPEED, n_modes=N_MODES)
    setup = time.perf_counter() - t0
    t_rj, first, res = timed_first(lambda: propagate(q.fn, inputs, samples=n_rj, seed=0, names=q.outputs,
                                                     fallback=q.fallback), repeats)
    peer = NumpyPeer(file, names, q.nominal, q.critical)
    X = res.input_samples
    parity = max(float(np.max(np.abs(peer(X[i]) / res.samples[i] - 1))) for i in range(min(4, n_rj)))
    if parity > 1e-7:
        raise SystemExit(f"the peer does not reproduce rotorjax's outputs (max relative difference {parity:.1e})")
    t_peer, _, _ = timed_first(lambda: [peer(X[i]) for i in range(n_peer)], 0 if args.smoke else 1)
    per_rj, per_peer = t_rj / n_rj, t_peer / n_peer
    cpu = watch.report()
    ross = ross_comparison(args, res, q, per_rj)
    out = {"benchmark": "Monte Carlo of ross_compare.toml's critical speeds and log decrements, 8 bearing "
                        "coefficients lognormal (10 %)",
           "machine": machine(), "jax": jax.__version__, "outputs": list(q.outputs),
           "nominal_critical_speeds": [w for w, _ in q.critical], "samples": n_rj, "peer_samples": n_peer,
           "setup_s": setup, "rotorjax_first_call_s": first, "rotorjax_s": t_rj,
           "rotorjax_per_sample_ms": 1e3 * per_rj, "peer_per_sample_ms": 1e3 * per_peer,
           "ratio_peer_over_rotorjax": per_peer / per_rj, "parity_max_rel": parity,
           "mean": dict(zip(q.outputs, res.mean.tolist())), "std": dict(zip(q.outputs, res.std.tolist())),
           "first_order_std": dict(zip(q.outputs, res.fosm_std.tolist())),
           "finite_samples": int(np.sum(res.finite)), "cpu_while_rotorjax_and_peer_ran": cpu, "ross": ross,
           "retried_samples": res.retried,
           "note": "peer: numpy affine bearing matrices, rotorjax's Newton steps on the nominal eigenpair "
                   "(scipy.linalg.solve) and scipy.linalg.eigvals for the residual, in a Python loop. ROSS (its own "
                   "interpreter, BLAS pinned to 1 thread: OPENBLAS/OMP/MKL_NUM_THREADS=1) "
                   "on the first `ross.samples` of rotorjax's input samples (the same values): (a) "
                   "ST_Rotor.run_campbell over `ross.scan_speeds_a` speeds 0..1000 rad/s, 1x crossings "
                   "interpolated linearly; (b) a loop of Rotor.run_critical_speed + run_modal; each timed once "
                   "with everything included but ROSS's import and its first run_modal (numba compiling, "
                   "`ross.warmup_s`, excluded); ratios: ROSS's seconds per sample over rotorjax's (from its "
                   "10 000-sample run); parity: largest relative difference to rotorjax's outputs for the same "
                   "inputs; mc_stats: mean, std over those samples from each (a std's relative difference can "
                   "reach the parity times mean/std); cpu_while_*: other processes' load (CpuWatch) during each part"}
    print(json.dumps({k: v for k, v in out.items() if k not in ("machine",)}, indent=1))
    if args.smoke:
        print("smoke run: nothing written")
        return
    write_results("uncertainty", out)


if __name__ == "__main__":
    main()
