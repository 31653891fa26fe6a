"""ROSS peer for the Monte Carlo benchmark on ROSS's example rotor with damped bearings.

The case: `ross.rotor_example()` (six 0.25 m Timoshenko steel elements, disks at
nodes 2 and 4, bearings at nodes 0 and 6) with the bearings' kxx, kyy, cxx, cyy
taken from given samples: an (n, 8) array in the order bearing0.kxx, bearing0.kyy,
bearing0.cxx, bearing0.cyy, bearing1.kxx, bearing1.kyy, bearing1.cxx, bearing1.cyy
(bearing0 at node 0, bearing1 at node 6; the nominal values are 1e6, 0.8e6, 500,
500 on both). Per sample: the forward 1x critical speeds of the damped rotor in
(0, hi] (hi: the last scan speed unless given) and the log decrements of the first
lateral modes (sorted by damped frequency, all whirl directions) at `log_dec_speed`.

ROSS runs in its own interpreter (`[python, "-c", ROSS_WORKER, json_cfg]`; the
worker prints one JSON line last), two ways a ROSS user would do it, each timed with
everything included (building the rotors, the analyses, reading the results off):

(a) `ross.stochastic`: one `ST_BearingElement` per bearing with the sample arrays
    (`is_random=["kxx", "kyy", "cxx", "cyy"]`), `ST_Rotor`, `run_campbell(speeds,
    frequencies)`. `log_dec_speed` is added to the scan when it is not in it. The
    1x crossings of each tracked lateral branch are interpolated linearly between
    scan speeds. ROSS 2.3.0's `ST_Rotor.run_campbell` keeps only `wd`, `log_dec` and
    the mode type (lateral/torsional/axial) at the first speed, not the whirl
    values, so a crossing counts as forward when its branch's frequency rises with
    speed across the bracketing interval (gyroscopic stiffening; backward branches
    fall, the torsional one is flat and is dropped by its mode type).
(b) a plain loop: per sample `rs.Rotor` with `rs.BearingElement`s,
    `run_critical_speed(num_modes, rtol)` (Newton on `speed - wd_i(speed)` for each
    of the first num_modes/2 modes; its `wd()` whose `whirl_direction` is "Forward"
    are the damped forward critical speeds) and `run_modal(log_dec_speed)`. ROSS
    calls a mode "Mixed" when its nodes' orbits do not all turn the same way, which
    with these anisotropic bearings happens to the second forward/backward pair in
    about half the samples; such a crossing is resolved with ROSS's own orbits at
    that speed (`run_modal(speed).shapes[i].orbits`): forward when the sum over the
    nodes of kappa * major_axis**2 (= forward minus backward whirl amplitude squared)
    is positive, the rule rotorjax uses for every mode. `mixed`: [speed, forward]
    of each such crossing, per sample.

Before the timed runs the worker calls `run_modal` once on the nominal rotor,
untimed (`warmup_s`): ROSS's first `run_modal` in a process compiles its numba
mode-shape/orbit code (5-8 s).
"""

import json
import os
import subprocess

import numpy as np

ROSS_WORKER = r'''
import json, sys, time, warnings
warnings.filterwarnings("ignore")
import numpy as np, ross as rs
import ross.stochastic as srs
cfg = json.loads(sys.argv[1])
S = np.asarray(cfg["samples"], dtype=float).reshape(-1, 8)
speeds = np.asarray(cfg["speeds"], dtype=float)
lds = float(cfg.get("log_dec_speed", 500.0))
if not np.any(np.abs(speeds - lds) <= 1e-9 * max(1.0, abs(lds))):
    speeds = np.union1d(speeds, [lds])
i_ld = int(np.argmin(np.abs(speeds - lds)))
hi = float(cfg.get("hi") or speeds.max())
R = max(1, int(cfg.get("repeats", 1)))
F = int(cfg.get("frequencies", 10))
NM = int(cfg.get("num_modes", 16))
rtol = float(cfg.get("rtol", 0.005))
n_ld = int(cfg.get("n_log_dec", 3))
paths = cfg.get("paths", ["a", "b"])
base = rs.rotor_example()
shaft, disks = list(base.shaft_elements), list(base.disk_elements)
NODES = (0, len(shaft))
KEYS = ("kxx", "kyy", "cxx", "cyy")
out = {"version": rs.__version__, "n_samples": int(S.shape[0]), "n_speeds": int(speeds.size),
       "speeds": speeds.tolist(), "hi": hi, "frequencies": F, "num_modes": NM, "rtol": rtol}
t0 = time.perf_counter()
base.run_modal(0.0, num_modes=NM)
out["warmup_s"] = time.perf_counter() - t0

def crossings(s, wd):
    """(speed, rising) of each 1x crossing of one tracked branch, linear between scan speeds."""
    d = wd - s
    res = []
    for k in range(len(s) - 1):
        a, b = d[k], d[k + 1]
        if not (np.isfinite(a) and np.isfinite(b)) or a == 0 or not (a * b < 0 or b == 0):
            continue
        x = s[k] + (s[k + 1] - s[k]) * a / (a - b)
        if 0 < x <= hi:
            res.append((float(x), bool(wd[k + 1] > wd[k])))
    return res

def path_a():
    brgs = [srs.ST_BearingElement(n=n, **{key: S[:, 4 * b + j].copy() for j, key in enumerate(KEYS)},
                                  is_random=list(KEYS)) for b, n in enumerate(NODES)]
    st = srs.ST_Rotor(list(shaft), list(disks), brgs)
    camp = st.run_campbell(speeds, frequencies=F)
    wd, ld, mt = np.asarray(camp.wd), np.asarray(camp.log_dec), np.asarray(camp.mode_type)
    cs, back, lds_ = [], [], []
    for i in range(S.shape[0]):
        lat = [j for j in range(wd.shape[0]) if str(mt[j, i]) == "Lateral"]
        xs = [c for j in lat for c in crossings(speeds, wd[j, :, i])]
        cs.append(sorted(x for x, rising in xs if rising))
        back.append(sorted(x for x, rising in xs if not rising))
        order = sorted(lat, key=lambda j: wd[j, i_ld, i])[:n_ld]
        lds_.append([float(ld[j, i_ld, i]) for j in order])
    return {"critical_speeds": cs, "backward_critical_speeds": back, "log_dec": lds_}

def path_b():
    cs, back, lds_, mixed_all = [], [], [], []
    for row in S:
        mixed = []
        mixed_all.append(mixed)
        brgs = [rs.BearingElement(n=n, **{key: float(row[4 * b + j]) for j, key in enumerate(KEYS)})
                for b, n in enumerate(NODES)]
        rotor = rs.Rotor(list(shaft), list(disks), brgs)
        c = rotor.run_critical_speed(num_modes=NM, rtol=rtol)
        w, wh = np.asarray(c.wd(), dtype=float), np.asarray(c.whirl_direction).astype(str)
        fwd = wh == "Forward"
        for i in np.flatnonzero((wh == "Mixed") & (w > 0) & (w <= hi)):
            orbits = rotor.run_modal(w[i], num_modes=NM).shapes[i].orbits
            fwd[i] = sum(o.kappa * o.major_axis ** 2 for o in orbits) > 0
            mixed.append([float(w[i]), bool(fwd[i])])
        keep = (w > 0) & (w <= hi) & (wh != "None")
        cs.append(np.sort(w[keep & fwd]).tolist())
        back.append(np.sort(w[keep & ~fwd]).tolist())
        m = rotor.run_modal(lds, num_modes=NM)
        lat = [j for j, sh in enumerate(m.shapes) if sh.mode_type == "Lateral"]
        order = sorted(lat, key=lambda j: m.wd[j])[:n_ld]
        lds_.append([float(m.log_dec[j]) for j in order])
    return {"critical_speeds": cs, "backward_critical_speeds": back, "log_dec": lds_, "mixed": mixed_all}

for name, fn in (("a", path_a), ("b", path_b)):
    if name not in paths:
        continue
    try:
        walls = []
        for _ in range(R):
            t0 = time.perf_counter()
            res = fn()
            walls.append(time.perf_counter() - t0)
        sec = float(np.median(walls))
        out[name] = dict(seconds=sec, per_sample_s=sec / max(1, S.shape[0]), walls=walls, **res)
    except Exception as e:
        out[name] = {"error": f"{type(e).__name__}: {e}"}
print(json.dumps(out))
'''


def run_ross_mc(python, samples, speeds, log_dec_speed=500.0, repeats=1, timeout=1800, *, paths=("a", "b"),
                hi=None, frequencies=10, num_modes=16, rtol=0.005, n_log_dec=3, blas_threads=None):
    """ROSS's Monte Carlo answers for `samples` ((n, 8), see the module docstring) in the
    interpreter `python` -> `{"version", "warmup_s", "speeds", ..., "a": {...}, "b": {...}}`,
    each path `{"seconds", "per_sample_s", "walls", "critical_speeds", "backward_critical_speeds",
    "log_dec"}` (per sample lists; (b) also `"mixed"`) or `{"error"}`. `speeds`: the Campbell scan of path (a)
    (`log_dec_speed` is added when missing); `hi`: the critical speeds' upper bound (default
    the last scan speed); `frequencies`: branches in (a)'s Campbell (ROSS's 6-dof model has
    a torsional one at 774 rad/s among them); `num_modes`, `rtol`: (b)'s `run_critical_speed`
    and `run_modal`; `blas_threads`: OpenBLAS/OpenMP/MKL threads of ROSS's process (None: this
    environment's; ROSS's eigenproblems are small, 84 x 84, and 1 thread was 2x faster per
    `run_modal` than the default on a loaded 2-core machine). Raises `RuntimeError` (with
    ROSS's last stderr line) when it fails."""
    samples = np.asarray(samples, dtype=float)
    if samples.ndim != 2 or samples.shape[1] != 8:
        raise ValueError(f"samples: an (n, 8) array expected, got shape {samples.shape}")
    cfg = {"samples": samples.tolist(), "speeds": list(map(float, speeds)), "log_dec_speed": float(log_dec_speed),
           "repeats": int(repeats), "paths": list(paths), "hi": None if hi is None else float(hi),
           "frequencies": int(frequencies), "num_modes": int(num_modes), "rtol": float(rtol),
           "n_log_dec": int(n_log_dec)}
    env = None
    if blas_threads is not None:
        n = str(int(blas_threads))
        env = dict(os.environ, OPENBLAS_NUM_THREADS=n, OMP_NUM_THREADS=n, MKL_NUM_THREADS=n)
    try:
        proc = subprocess.run([python, "-c", ROSS_WORKER, json.dumps(cfg)], capture_output=True, text=True,
                              timeout=timeout, env=env)
    except (OSError, subprocess.TimeoutExpired) as e:
        raise RuntimeError(f"cannot run ROSS with {python}: {e}") from None
    if proc.returncode != 0:
        last = (proc.stderr.strip().splitlines() or ["(no message)"])[-1]
        raise RuntimeError(f"ROSS failed in {python}: {last}")
    lines = proc.stdout.strip().splitlines()
    if not lines:
        raise RuntimeError(f"ROSS printed nothing in {python}")
    return json.loads(lines[-1])
