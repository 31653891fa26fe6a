"""ROSS parity: the everyday linear analyses on ROSS's `rotor_example`, and design
studies of 1 000 designs, rotorjax vs ROSS in the same run.

(1) One rotor (`ross-compare` = ROSS's `rotor_example`, 6 Timoshenko elements, two
disks, two bearings): damped modes at one speed; Campbell diagram at 50 speeds;
frequency response x(node 2) / F_x(node 2) at 200 frequencies (synchronous: the
rotor runs at the excitation frequency, as ROSS's `run_freq_response`); static
deflection under gravity. rotorjax is compiled first (its first call is reported
apart); ROSS gets a different speed on every repeat of `run_modal` (it caches by
speed). ROSS computes the whole FRF matrix per frequency where rotorjax solves the
pair asked for (what the `frf` command does).
(2) 1 000 designs (bearing stiffness 0.5..2e6 N/m, shaft diameter 0.045..0.055 m,
disk mass x 0.8..1.2), each analysed in one vmapped call:
- critical speeds: the first four roots of the synchronous determinant (undamped
  bearings) vs ROSS `run_critical_speed`;
- UCS map: 20 bearing stiffnesses 1e5..1e10 N/m, 4 modes, vs ROSS `run_ucs(num=20)`;
- API 684 level I: log decrement of the first non-backward mode at 500 rad/s
  against 9 cross-coupled stiffnesses 0..4e5 N/m at the mid-span node (bearings
  with 1500 N s/m damping), vs ROSS `run_level1(num=9)`.
Static analysis uses ROSS's g = 9.8065 m/s^2 for the agreement column.
ROSS is timed on the first `--ross-designs` designs and its time per design is
scaled to 1 000; its results on those designs give the error column (max relative
difference, lateral modes). ROSS runs in its own interpreter (`--ross-python`,
default $ROTORJAX_ROSS_PYTHON, else this interpreter when `import ross` works).

Run: python benchmarks/ross_parity.py [--ross-python PATH] [--designs 1000]
[--ross-designs 10] [--repeats 5] [--smoke]; writes benchmarks/results/ross_parity.json
(`--smoke`: 5 speeds, 10 frequencies, 4 designs (2 for ROSS), 4 UCS stiffnesses, 3
cross-couplings, one repeat; prints, writes nothing).
"""

import argparse
import json
import os
import subprocess
import sys

import numpy as np
from _common import machine, timed_first, write_results

from rotorjax.bench import ross_python

N_CAMPBELL, N_FRF = 50, 200
UCS_K = (5.0, 10.0, 20)          # log10 range and count
LEVEL1 = {"speed": 500.0, "node": 3, "q_max": 4e5, "num": 9, "c": 1500.0}

ROSS_WORKER = r'''
import json, sys, time, warnings
warnings.filterwarnings("ignore")
import numpy as np, ross as rs
cfg = json.loads(sys.argv[1])
out = {"version": rs.__version__}
rotor = rs.rotor_example()
steel = rotor.shaft_elements[0].material
def med(fn, repeats):
    ts = []
    for i in range(repeats):
        t0 = time.perf_counter(); r = fn(i); ts.append(time.perf_counter() - t0)
    return float(np.median(ts)), r
R = cfg["repeats"]
t, m = med(lambda i: rotor.run_modal(speed=500.0 + 1e-3 * i, num_modes=16), R)
out["modes_s"] = t
camp_speeds = np.linspace(0, 1000, cfg["n_campbell"])
out["campbell_s"], _ = med(lambda i: rotor.run_campbell(camp_speeds + 1e-6 * i, frequencies=8), max(1, R // 2))
freqs = np.linspace(10, 1200, cfg["n_frf"])
t, fr = med(lambda i: rotor.run_freq_response(speed_range=freqs + 1e-9 * i), max(1, R // 2))
out["frf_s"] = t
out["frf_x2_x2"] = [[float(z.real), float(z.imag)] for z in fr.freq_resp[12, 12, :]]
t, st = med(lambda i: rotor.run_static(), R)
out["static_s"] = t
out["static_bearing_forces"] = {str(k): np.ravel(np.asarray(v, dtype=float)).tolist() for k, v in dict(st.bearing_forces).items()}

def design(kb, d, ms, c=0.0, rated_w=None):
    shaft = [rs.ShaftElement(0.25, 0.0, d, material=steel) for _ in range(6)]
    disks = [rs.DiskElement(n=dk.n, m=ms * dk.m, Id=dk.Id, Ip=dk.Ip) for dk in rotor.disk_elements]
    brgs = [rs.BearingElement(n=n, kxx=kb, kyy=0.8 * kb, cxx=c, cyy=c) for n in (0, 6)]
    return rs.Rotor(shaft, disks, brgs, rated_w=rated_w)
designs = cfg["designs"]
t0 = time.perf_counter(); crit = []
for kb, d, ms in designs:
    wn = np.sort(np.asarray(design(kb, d, ms).run_critical_speed(num_modes=16).wn()))
    crit.append(wn[:8].tolist())
out["critical_s_per_design"] = (time.perf_counter() - t0) / len(designs)
out["critical"] = crit
lo, hi, num = cfg["ucs"]
t0 = time.perf_counter(); ucs = []
for kb, d, ms in designs:
    u = design(kb, d, ms).run_ucs(stiffness_range=(lo, hi), num=int(num), num_modes=16)
    ucs.append(np.asarray(u.wn).tolist())
out["ucs_s_per_design"] = (time.perf_counter() - t0) / len(designs)
out["ucs"] = ucs
lv = cfg["level1"]
t0 = time.perf_counter(); lev = []
for kb, d, ms in designs:
    r = design(kb, d, ms, c=lv["c"], rated_w=lv["speed"])
    lev.append(np.asarray(r.run_level1(n=lv["node"], stiffness_range=(0.0, lv["q_max"]), num=lv["num"]).log_dec).tolist())
out["level1_s_per_design"] = (time.perf_counter() - t0) / len(designs)
out["level1"] = lev
print(json.dumps(out))
'''


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--ross-python", default=os.environ.get("ROTORJAX_ROSS_PYTHON"))
    ap.add_argument("--designs", type=int, default=1000)
    ap.add_argument("--ross-designs", type=int, default=10)
    ap.add_argument("--repeats", type=int, default=5)
    ap.add_argument("--smoke", action="store_true", help="tiny sizes, one repeat; print, write nothing")
    args = ap.parse_args()
    if args.smoke:
        args.designs, args.ross_designs, args.repeats = 4, 2, 1
    n_campbell, n_frf = (5, 10) if args.smoke else (N_CAMPBELL, N_FRF)
    ucs_k = (UCS_K[0], UCS_K[1], 4) if args.smoke else UCS_K
    level1 = dict(LEVEL1, num=3) if args.smoke else LEVEL1

    import jax
    import jax.numpy as jnp

    import rotorjax
    from rotorjax import flexible as fx
    from rotorjax.io import load_rotor, shipped_rotor

    scene = load_rotor(shipped_rotor("ross_compare"))
    rotor = scene.rotor
    R = args.repeats
    out = {"benchmark": "ross parity (rotor_example; 1000 designs)", "machine": machine(),
           "versions": {"jax": jax.__version__, "rotorjax": getattr(rotorjax, "__version__", "")},
           "rotorjax": {}, "sizes": {"n_campbell": n_campbell, "n_frf": n_frf, "designs": args.designs}}
    rj = out["rotorjax"]

    # --- (1) one rotor ---
    modes_fn = jax.jit(lambda s: fx.modes(scene, s, 16).frequencies)
    rj["modes_s"], rj["modes_first_call_s"], _ = timed_first(lambda: modes_fn(500.0), R)
    camp_fn = jax.jit(lambda s: fx.campbell(scene, s, 8).frequencies)
    speeds = jnp.linspace(0.0, 1000.0, n_campbell)
    rj["campbell_s"], rj["campbell_first_call_s"], _ = timed_first(lambda: camp_fn(speeds), R)
    freqs = jnp.linspace(10.0, 1200.0, n_frf)
    frf_fn = jax.jit(lambda w: fx.frf(scene, (2, "x"), (2, "x"), w).values)
    rj["frf_s"], rj["frf_first_call_s"], h = timed_first(lambda: frf_fn(freqs), R)
    rj["frf_note"] = "one input/output pair; ROSS's run_freq_response computes every pair per frequency"
    static_fn = lambda: fx.static(scene, gravity=9.8065).bearing_reactions  # noqa: E731  (ROSS's g)
    rj["static_s"], rj["static_first_call_s"], reactions = timed_first(static_fn, R)

    # --- (2) designs ---
    rng = np.random.default_rng(0)
    designs = np.stack([rng.uniform(5e5, 2e6, args.designs), rng.uniform(0.045, 0.055, args.designs),
                        rng.uniform(0.8, 1.2, args.designs)], axis=1)
    disk = [(n, float(m), float(it), float(ip)) for n, (m, it, ip) in
            zip(rotor.disk_nodes, np.asarray(rotor.disk_params))]

    def design_rotor(kb, d, ms, c=0.0):
        return fx.FlexibleRotor(jnp.full(6, 0.25), d, 0.0, E=rotor.E, G=rotor.G, rho=rotor.rho,
                                disks=tuple((n, ms * m, it, ip) for n, m, it, ip in disk),
                                bearings=((0, kb, 0.8 * kb, c, c), (6, kb, 0.8 * kb, c, c)))

    D = jnp.asarray(designs)
    crit_fn = jax.jit(jax.vmap(lambda p: fx.synchronous_critical_speeds(design_rotor(*p), 4)))
    t, first, crit = timed_first(lambda: crit_fn(D), R)
    rj["critical"] = {"s": t, "first_call_s": first, "s_per_design": t / args.designs}
    k_grid = jnp.logspace(*ucs_k)
    ucs_fn = jax.jit(jax.vmap(lambda p: fx.ucs_frequencies(design_rotor(*p), k_grid, n_modes=4)))
    t, first, ucs = timed_first(lambda: ucs_fn(D), R)
    rj["ucs"] = {"s": t, "first_call_s": first, "s_per_design": t / args.designs}
    q = jnp.linspace(0.0, level1["q_max"], level1["num"])
    lev_fn = jax.jit(jax.vmap(lambda p: jax.vmap(lambda qq: fx.level1_log_dec(
        design_rotor(*p, c=level1["c"]), qq, level1["speed"], node=level1["node"]))(q)))
    t, first, lev = timed_first(lambda: lev_fn(D), R)
    rj["level1"] = {"s": t, "first_call_s": first, "s_per_design": t / args.designs}
    ross_py = ross_python(args.ross_python)
    if ross_py:
        n = args.ross_designs
        cfg = {"repeats": R, "n_campbell": n_campbell, "n_frf": n_frf, "designs": designs[:n].tolist(),
               "ucs": list(ucs_k), "level1": level1}
        proc = subprocess.run([ross_py, "-c", ROSS_WORKER, json.dumps(cfg)], capture_output=True, text=True,
                              timeout=300 if args.smoke else None)
        if proc.returncode != 0:
            raise SystemExit(f"ROSS worker failed:\n{proc.stderr[-3000:]}")
        ross = json.loads(proc.stdout.strip().splitlines()[-1])
        out["ross"] = {k: v for k, v in ross.items() if k.endswith("_s") or k.endswith("per_design")
                       or k == "version"}
        out["ross"]["designs_timed"] = n
        ratios = {k: ross[f"{k}_s"] / rj[f"{k}_s"] for k in ("modes", "campbell", "frf", "static")}
        for k in ("critical", "ucs", "level1"):
            ratios[k] = ross[f"{k}_s_per_design"] / rj[k]["s_per_design"]
        out["ratios_ross_over_rotorjax"] = ratios
        # agreement on the designs ROSS ran (lateral modes: each rotorjax value against
        # the nearest ROSS value, since ROSS's 6-dof model adds axial/torsional modes)
        def nearest_rel(ours, theirs):
            theirs = np.asarray(theirs, dtype=float).ravel()
            theirs = theirs[np.isfinite(theirs)]
            return float(max(np.min(np.abs(theirs / o - 1)) for o in np.ravel(ours) if np.isfinite(o)))
        crit = np.asarray(crit)
        ucs = np.asarray(ucs)
        lev = np.asarray(lev)
        ross_h = np.array([complex(a, b) for a, b in ross["frf_x2_x2"]])
        out["agreement"] = {
            "frf_max_rel": float(np.max(np.abs(np.asarray(h) / ross_h - 1))),
            "critical_max_rel": max(nearest_rel(crit[i], ross["critical"][i]) for i in range(n)),
            "ucs_max_rel": max(nearest_rel(ucs[i], ross["ucs"][i]) for i in range(n)),
            "level1_max_abs": float(np.max(np.abs(lev[:n] - np.asarray(ross["level1"])))),
            "level1_ross_log_dec_range": [float(np.min(ross["level1"])), float(np.max(ross["level1"]))],
            "static_bearing_forces_ross": ross["static_bearing_forces"],
            "static_bearing_reactions_rotorjax": np.asarray(reactions).tolist(),
        }
    else:
        out["ross"] = None
        print("ROSS not available: pass --ross-python (ROSS timed in its own interpreter)")
    print(json.dumps({k: out[k] for k in ("rotorjax", "ross", "ratios_ross_over_rotorjax", "agreement")
                      if k in out}, indent=1))
    if args.smoke:
        print("smoke run: nothing written")
    else:
        write_results("ross_parity", out)


if __name__ == "__main__":
    main()
