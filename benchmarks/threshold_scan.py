"""Stability thresholds on a CPU: the scan point by point with the bisection's compiled
program (`stability_thresholds(..., scan="points")`, the CPU default) against the vmapped
scan (`scan="vmap"`: the margin compiled a second time, vmapped, in chunks of 100).

Three margins, 200 scan speeds each, the thresholds bisected to the default `xtol`:
- the journal rig (`journal_rig.toml`: ROSS's example rotor on two short journal
  bearings, 28 dofs): the largest real part of the linearised films' eigenvalues,
  100-400 rad/s (oil whirl at ~207.6 rad/s);
- the 36-dof tapered two-material rotor (`tapered_two_material.toml`): its linear
  margin, 10-1000 rad/s (stable throughout: the scan alone);
- model 001 (anisotropic auto-balancer, the paper's parameters): the main motion's
  largest Floquet exponent, n in 0.5-10 (three crossings; each point integrates the
  variational equations over a period).

Each mode of each case runs in a fresh interpreter, so that its first call pays its own
compilations (`cold_s`); then the median of `--repeats` calls (`warm_s`). The thresholds
of the two modes must agree to 1e-9 (relative).

Run: python benchmarks/threshold_scan.py [--repeats 3] [--smoke]; writes
benchmarks/results/threshold_scan.json (`--smoke`: the journal rig only, 16 scan speeds,
no repeats; prints, writes nothing).
"""

import argparse
import json
import os
import subprocess
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from _common import CpuWatch, machine, write_results  # noqa: E402

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
CASES = ("journal_rig", "tapered_36", "model_001_floquet")
MODES = ("points", "vmap")

#: what a fresh interpreter runs: one case, one mode; prints a JSON line
CHILD = r"""
import json, sys, time
import equinox as eqx, jax.numpy as jnp, numpy as np
case, mode, n_scan, repeats = sys.argv[1], sys.argv[2], int(sys.argv[3]), int(sys.argv[4])
from rotorjax.analysis import linear_margin, stability_thresholds
if case == "model_001_floquet":
    import rotorjax.presets._anisotropic_abb as ab
    p = dict(ab.PRESET.defaults)
    G = {k: p[k] for k in ab.GROUPS}

    def floquet_margin(groups, n):
        return ab.main_motion_floquet(groups, n, p["K"]).margin

    margin, lo, hi = eqx.Partial(floquet_margin, G), 0.5, 10.0
else:
    from rotorjax.io import read_rotor_file, shipped_rotor
    name, (lo, hi) = {"journal_rig": ("journal_rig", (100.0, 400.0)),
                      "tapered_36": ("tapered_two_material", (10.0, 1000.0))}[case]
    margin = eqx.Partial(linear_margin, read_rotor_file(str(shipped_rotor(name))).scene)
times = []
for _ in range(1 + repeats):
    t0 = time.perf_counter()
    found = stability_thresholds(margin, lo, hi, n_scan=n_scan, scan=mode)
    times.append(time.perf_counter() - t0)
print(json.dumps({"cold_s": times[0], "warm_s": float(np.median(times[1:])) if repeats else times[0],
                  "thresholds": [t.speed for t in found]}))
"""


def run(case, mode, n_scan, repeats):
    r = subprocess.run([sys.executable, "-c", CHILD, case, mode, str(n_scan), str(repeats)], cwd=ROOT,
                       capture_output=True, text=True, env=dict(os.environ, PYTHONPATH=ROOT))
    if r.returncode:
        raise SystemExit(f"{case} {mode}: {r.stderr[-2000:]}")
    return json.loads(r.stdout.strip().splitlines()[-1])


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--repeats", type=int, default=3)
    ap.add_argument("--smoke", action="store_true", help="the journal rig, 16 speeds, one call; write nothing")
    args = ap.parse_args()
    cases, n_scan, repeats = (CASES[:1], 16, 0) if args.smoke else (CASES, 200, args.repeats)
    watch = CpuWatch()
    rows = []
    for case in cases:
        got = {mode: run(case, mode, n_scan, repeats) for mode in MODES}
        a, b = got["points"]["thresholds"], got["vmap"]["thresholds"]
        assert len(a) == len(b) and all(abs(x - y) <= 1e-9 * abs(y) for x, y in zip(a, b)), (case, a, b)
        row = {"case": case, "n_scan": n_scan, "thresholds": a,
               **{f"{mode}_{k}": got[mode][k] for mode in MODES for k in ("cold_s", "warm_s")}}
        row["cold_ratio_vmap_over_points"] = row["vmap_cold_s"] / row["points_cold_s"]
        row["warm_ratio_vmap_over_points"] = row["vmap_warm_s"] / row["points_warm_s"]
        rows.append(row)
        print(f"{case:18s} points: cold {row['points_cold_s']:6.2f} s, warm {row['points_warm_s']:6.3f} s;  "
              f"vmap: cold {row['vmap_cold_s']:6.2f} s, warm {row['vmap_warm_s']:6.3f} s;  "
              f"thresholds {', '.join(f'{t:.6g}' for t in a) or 'none'}")
    if args.smoke:
        print("smoke run: nothing written")
        return
    write_results("threshold_scan", {"machine": machine(), "load": watch.report(), "repeats": repeats,
                                     "cases": rows})


if __name__ == "__main__":
    main()
