"""Flexible rotor linear analyses: rotorjax vs ROSS on `ross-compare`.

(a) Campbell diagram, 100 speeds, 8 modes; (b) unbalance response, 2000 speeds;
(c) first critical speed of 10 000 random designs (bearing stiffness, disk
positions as element lengths) in one vmapped call, vs a ROSS loop timed on a subset
and extrapolated. (a) and (b) are also timed on the rotor reduced to its lowest
`--reduced-modes` undamped modes, with the reduction error against the full model
(speed against error); (c) uses the roots of the synchronous determinant (one
Hermitian eigenproblem per design) and, for comparison, the fixed point on the
damped frequencies. ROSS runs in its own interpreter (`--ross-python`, default
$ROTORJAX_ROSS_PYTHON), in the same benchmark run; it is not a rotorjax dependency.

Run: python benchmarks/flexible.py [--ross-python PATH] [--smoke]; writes
benchmarks/results/flexible.json (`--smoke`: 5 speeds, 50 frequencies, 8 designs (2
for ROSS), one repeat; prints, writes nothing).
"""

import argparse
import json
import os
import subprocess

import numpy as np
from _common import machine, timed_first, write_results

ROSS_WORKER = r'''
import json, sys, time, warnings
warnings.filterwarnings("ignore")
import numpy as np, ross as rs
cfg = json.loads(sys.argv[1])
out = {"version": rs.__version__}
rotor = rs.rotor_example()
def timed(fn, repeats=cfg.get("repeats", 3)):
    fn()
    ts = []
    for _ in range(repeats):
        t0 = time.perf_counter(); r = fn(); ts.append(time.perf_counter() - t0)
    return float(np.median(ts)), r
speeds = np.linspace(0, 1000, cfg["n_campbell"])
t, camp = timed(lambda: rotor.run_campbell(speeds, frequencies=8))
out["campbell_s"] = t
out["campbell_wd"] = np.asarray(camp.wd).tolist()
freq = np.linspace(10, 1200, cfg["n_response"])
t, resp = timed(lambda: rotor.run_unbalance_response(node=2, unbalance_magnitude=0.001,
                                                     unbalance_phase=0.0, frequency=freq))
out["response_s"] = t
out["response_x_node2"] = np.abs(resp.forced_resp[rotor.number_dof * 2, :]).tolist()
designs = cfg["designs"]
steel = rotor.shaft_elements[0].material
t0 = time.perf_counter()
crit = []
for kb, z1, z2 in designs:
    lengths = [z1 / 2, z1 / 2, (z2 - z1) / 2, (z2 - z1) / 2, (1.5 - z2) / 2, (1.5 - z2) / 2]
    shaft = [rs.ShaftElement(L, 0.0, 0.05, material=steel) for L in lengths]
    disks = [rs.DiskElement(n=n, m=d.m, Id=d.Id, Ip=d.Ip) for n, d in zip((2, 4), rotor.disk_elements)]
    brgs = [rs.BearingElement(n=0, kxx=kb, kyy=0.8 * kb, cxx=0), rs.BearingElement(n=6, kxx=kb, kyy=0.8 * kb, cxx=0)]
    r = rs.Rotor(shaft, disks, brgs)
    crit.append(float(np.sort(r.run_critical_speed(num_modes=12).wn())[0]))
out["designs_s_per_design"] = (time.perf_counter() - t0) / len(designs)
out["designs_critical"] = crit
print(json.dumps(out))
'''


def _peaks(freq, amp, n=2):
    """Frequencies of the `n` largest local maxima, ascending."""
    i = np.where((amp[1:-1] > amp[:-2]) & (amp[1:-1] > amp[2:]))[0] + 1
    top = i[np.argsort(amp[i])[::-1][:n]]
    return np.sort(np.asarray(freq)[top])


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--ross-python", default=os.environ.get("ROTORJAX_ROSS_PYTHON"))
    ap.add_argument("--n-designs", type=int, default=10_000)
    ap.add_argument("--ross-designs", type=int, default=20)
    ap.add_argument("--reduced-modes", type=int, default=20)
    ap.add_argument("--smoke", action="store_true",
                    help="5 speeds, 50 frequencies, 8 designs, one repeat; print, write nothing")
    args = ap.parse_args()
    if args.smoke:
        args.n_designs, args.ross_designs = 8, 2
    n_campbell, n_response, R = (5, 50, 1) if args.smoke else (100, 2000, 3)

    import jax
    import jax.numpy as jnp

    import rotorjax  # noqa: F401
    from rotorjax.flexible import (FlexibleRotor, campbell, critical_speed, synchronous_critical_speeds,
                                   unbalance_response)
    from rotorjax.presets import ross_compare

    p = dict(ross_compare.PRESET.defaults)
    rotor = ross_compare.build_rotor(p)
    rng = np.random.default_rng(0)
    designs = np.stack([rng.uniform(5e5, 2e6, args.n_designs), rng.uniform(0.3, 0.7, args.n_designs),
                        rng.uniform(0.8, 1.2, args.n_designs)], axis=1)
    disk = (p["disk_mass"], p["disk_It"], p["disk_Ip"])

    def design_rotor(kb, z1, z2):
        lengths = jnp.stack([z1 / 2, z1 / 2, (z2 - z1) / 2, (z2 - z1) / 2, (1.5 - z2) / 2, (1.5 - z2) / 2])
        return FlexibleRotor(lengths, 0.05, E=p["E"], G=p["G"], rho=p["rho"],
                             disks=((2,) + disk, (4,) + disk),
                             bearings=((0, kb, 0.8 * kb, 0.0, 0.0), (6, kb, 0.8 * kb, 0.0, 0.0)))

    speeds = np.linspace(0, 1000, n_campbell)
    camp_fn = jax.jit(lambda s: campbell(rotor, s, 8).frequencies)
    t_camp, c_camp, camp = timed_first(lambda: camp_fn(speeds), repeats=R)
    freq = np.linspace(10, 1200, n_response)
    resp_fn = jax.jit(lambda w: unbalance_response(rotor, 2, 1e-3, 0.0, w, probe_nodes=[2])[0])
    t_resp, c_resp, resp = timed_first(lambda: resp_fn(freq), repeats=R)
    red = rotor.reduce(args.reduced_modes)
    camp_red_fn = jax.jit(lambda s: campbell(red, s, 8).frequencies)
    t_camp_red, _, camp_red = timed_first(lambda: camp_red_fn(speeds), repeats=R)
    resp_red_fn = jax.jit(lambda w: unbalance_response(red, 2, 1e-3, 0.0, w, probe_nodes=[2])[0])
    t_resp_red, _, resp_red = timed_first(lambda: resp_red_fn(freq), repeats=R)
    full_amp, red_amp = np.abs(np.asarray(resp[:, 0])), np.abs(np.asarray(resp_red[:, 0]))
    reduction = {"modes": args.reduced_modes, "campbell_s": t_camp_red, "response_s": t_resp_red,
                 "campbell_max_rel_vs_full": float(np.max(np.abs(np.asarray(camp_red) / np.asarray(camp) - 1))),
                 # undamped rotor: amplitudes are unbounded at the peaks, so the median
                 # relative error, plus the peak frequencies
                 "response_median_rel_vs_full": float(np.median(np.abs(red_amp / full_amp - 1))),
                 "response_peak_freqs_rel_vs_full": float(np.max(np.abs(
                     _peaks(freq, red_amp) / _peaks(freq, full_amp) - 1)))}
    crit_fn = jax.jit(jax.vmap(lambda d: synchronous_critical_speeds(design_rotor(d[0], d[1], d[2]), 1)[0]))
    t_crit, c_crit, crit = timed_first(lambda: crit_fn(jnp.asarray(designs)), repeats=R)
    fp_fn = jax.jit(jax.vmap(lambda d: critical_speed(design_rotor(d[0], d[1], d[2]), 0, 90.0)))
    t_fp, _, (crit_fp, crit_residual) = timed_first(lambda: fp_fn(jnp.asarray(designs)), repeats=1)
    out = {"benchmark": "flexible (ross-compare)",
           "machine": machine(),
           "versions": {"jax": jax.__version__},
           "rotorjax": {"campbell_s": t_camp, "campbell_first_call_s": c_camp, "response_s": t_resp,
                        "response_first_call_s": c_resp, "designs_s": t_crit,
                        "designs_first_call_s": c_crit, "n_designs": args.n_designs,
                        "designs_s_per_design": t_crit / args.n_designs,
                        "designs_fixed_point_s": t_fp,
                        "designs_max_fixed_point_residual": float(np.max(np.abs(np.asarray(crit_residual)))),
                        "designs_fixed_point_vs_determinant_max_rel": float(np.max(np.abs(
                            np.asarray(crit_fp) / np.asarray(crit) - 1))),
                        "reduced": reduction}}
    if args.ross_python:
        cfg = {"n_campbell": n_campbell, "n_response": n_response, "designs": designs[:args.ross_designs].tolist()}
        if args.smoke:
            cfg["repeats"] = R
        proc = subprocess.run([args.ross_python, "-c", ROSS_WORKER, json.dumps(cfg)],
                              capture_output=True, text=True, timeout=300 if args.smoke else 3000)
        if proc.returncode != 0:
            raise SystemExit(proc.stderr[-3000:])
        ross = json.loads(proc.stdout.strip().splitlines()[-1])
        # ROSS's shaft elements also carry axial and torsional dofs: its Campbell list
        # has speed-independent modes that a lateral model has not. Match each ROSS
        # frequency to the nearest of ours; count the unmatched (> 2 % away).
        wd = np.asarray(ross["campbell_wd"])
        ours = np.asarray(camp)
        rel = np.min(np.abs(wd[:, :, None] / ours[:, None, :] - 1), axis=-1)
        matched = np.all(rel < 0.02, axis=0)
        camp_err = float(np.max(rel[:, matched]))
        resp_err = float(np.max(np.abs(np.abs(np.asarray(resp[:, 0])) / np.asarray(ross["response_x_node2"]) - 1)))
        crit_err = float(np.max(np.abs(np.asarray(crit[:args.ross_designs]) / np.asarray(ross["designs_critical"]) - 1)))
        out["ross"] = {"version": ross["version"], "campbell_s": ross["campbell_s"],
                       "response_s": ross["response_s"], "designs_s_per_design": ross["designs_s_per_design"],
                       "designs_subset": args.ross_designs}
        out["ross"]["campbell_modes_not_lateral"] = int(np.sum(~matched))
        out["ratios"] = {"campbell": ross["campbell_s"] / t_camp, "response": ross["response_s"] / t_resp,
                         "campbell_reduced": ross["campbell_s"] / t_camp_red,
                         "response_reduced": ross["response_s"] / t_resp_red,
                         "designs": ross["designs_s_per_design"] / (t_crit / args.n_designs)}
        ross_amp = np.asarray(ross["response_x_node2"])
        out["agreement"] = {"campbell_max_rel": camp_err, "response_max_rel": resp_err,
                            "response_peak_freqs_rel": float(np.max(np.abs(
                                _peaks(freq, full_amp) / _peaks(freq, ross_amp) - 1))),
                            "critical_speed_max_rel": crit_err}
    print(json.dumps({k: v for k, v in out.items() if k != "machine"}, indent=2))
    if args.smoke:
        print("smoke run: nothing written")
    else:
        write_results("flexible", out)


if __name__ == "__main__":
    main()
