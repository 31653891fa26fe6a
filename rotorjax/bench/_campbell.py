"""The linear headline comparison: the Campbell diagram of ROSS's example rotor
(`ross-compare`, the shipped rotor file `ross_compare.toml`: 6 Timoshenko elements,
two disks, two bearings), rotorjax (`rotorjax.flexible.campbell`, vmapped over the
speeds, compiled once) against ROSS's `Rotor.run_campbell` on `ross.rotor_example()`,
in the same run. No tolerance ladder: one time per diagram each, and their agreement
(the largest relative difference of rotorjax's damped natural frequencies to ROSS's
nearest one at the same speed; ROSS's 6-dof model adds axial and torsional modes,
which rotorjax's lateral model has not, so ROSS is asked for more frequencies).

ROSS runs in its own interpreter (`ross_python`: `$ROTORJAX_ROSS_PYTHON`, else this
interpreter when `import ross` works); without one the peer is skipped with a note.
"""

import importlib.util
import json
import os
import subprocess
import sys

import numpy as np

from ._report import Comparison, Point, timed

SPEED_RANGE = (0.0, 1000.0)  # rad/s

ROSS_WORKER = r'''
import json, sys, time, warnings
warnings.filterwarnings("ignore")
import numpy as np, ross as rs
cfg = json.loads(sys.argv[1])
rotor = rs.rotor_example()
speeds = np.asarray(cfg["speeds"])
rotor.run_campbell(speeds[:2], frequencies=cfg["frequencies"])  # ROSS's first call (imports, caches) untimed
walls = []
for i in range(cfg["repeats"]):
    t0 = time.perf_counter()
    camp = rotor.run_campbell(speeds + 1e-6 * i, frequencies=cfg["frequencies"])
    walls.append(time.perf_counter() - t0)
print(json.dumps({"version": rs.__version__, "walls": walls, "wd": np.asarray(camp.wd).tolist()}))
'''


def ross_python(explicit=None):
    """The interpreter that has ROSS: `explicit`, else `$ROTORJAX_ROSS_PYTHON`, else this
    one when `ross` is importable, else None."""
    if explicit:
        return explicit
    if os.environ.get("ROTORJAX_ROSS_PYTHON"):
        return os.environ["ROTORJAX_ROSS_PYTHON"]
    return sys.executable if importlib.util.find_spec("ross") is not None else None


def run_ross(python, speeds, frequencies, repeats, timeout=900):
    """ROSS's Campbell diagram in `python` -> `{"version", "walls", "wd"}`; raises
    `RuntimeError` (with ROSS's last line) when that interpreter fails."""
    cfg = {"speeds": list(map(float, speeds)), "frequencies": int(frequencies), "repeats": int(repeats)}
    try:
        proc = subprocess.run([python, "-c", ROSS_WORKER, json.dumps(cfg)], capture_output=True, text=True,
                              timeout=timeout)
    except (OSError, subprocess.TimeoutExpired) as e:
        raise RuntimeError(f"cannot run ROSS with {python}: {e}") from None
    if proc.returncode != 0:
        last = (proc.stderr.strip().splitlines() or ["(no message)"])[-1]
        raise RuntimeError(f"ROSS failed in {python}: {last}")
    return json.loads(proc.stdout.strip().splitlines()[-1])


def nearest_relative_difference(ours, theirs):
    """Largest relative difference of each of `ours` (speeds x modes) to the nearest of
    `theirs` at the same speed."""
    ours, theirs = np.asarray(ours), np.asarray(theirs)
    d = np.abs(ours[:, :, None] - theirs[:, None, :]).min(axis=2)
    return float(np.max(d / np.maximum(np.abs(ours), 1e-12)))


def campbell_comparison(sizes, progress, repeats, ross_py=None):
    import jax

    from rotorjax.analysis import campbell
    from rotorjax.io import load_rotor, shipped_rotor

    speeds = np.linspace(*SPEED_RANGE, sizes.campbell_speeds)
    k = sizes.campbell_modes
    comp = Comparison(name="Campbell diagram", what=f"ross-compare (ROSS's rotor_example), {speeds.size} speeds "
                      f"in [0, {SPEED_RANGE[1]:g}] rad/s, {k} modes", cost_unit="s per diagram",
                      error_label="max relative difference to ROSS")
    progress("Campbell: rotorjax")
    scene = load_rotor(shipped_rotor("ross_compare"))
    fn = jax.jit(lambda s: campbell(scene, s, k).frequencies)
    first, run_s, wd = timed(lambda: np.asarray(jax.block_until_ready(fn(speeds))), repeats)
    comp.rotorjax = "rotorjax campbell"
    progress("Campbell: ROSS")
    python, ross = ross_python(ross_py), None
    if python is None:
        comp.skipped.append(("ROSS", "ROSS is not installed (pip install ross-rotordynamics, or set "
                                     "ROTORJAX_ROSS_PYTHON to a Python that has it)"))
    else:
        try:
            ross = run_ross(python, speeds, k + 6, max(1, min(repeats, 3)))
        except RuntimeError as e:
            comp.skipped.append(("ROSS", str(e)))
    if ross is None:
        comp.add(comp.rotorjax, Point("-", float("nan"), run_s, first_call_s=first))
        return comp
    agreement = nearest_relative_difference(wd, ross["wd"])
    comp.checks["agreement_max_rel"] = agreement
    comp.add(comp.rotorjax, Point("-", agreement, run_s, first_call_s=first))
    peer = f"ROSS {ross['version']} run_campbell"
    comp.add(peer, Point("-", agreement, float(np.median(ross["walls"]))))
    comp.peers.append(peer)
    comp.notes.append(f"rotorjax's {k} lowest damped natural frequencies agree with ROSS's nearest to "
                      f"{agreement:.1e} (relative) at every speed")
    return comp


def campbell_rows(comp):
    rows = []
    ours = comp.curves[comp.rotorjax][0]
    for peer in comp.peers:
        theirs = comp.curves[peer][0]
        rows.append({"comparison": comp.name, "rotorjax_tolerance": "-", "error": ours.error, "peer": peer,
                     "peer_cost": theirs.cost, "rotorjax_cost": ours.cost, "ratio": theirs.cost / ours.cost,
                     "match": "same analysis; error = agreement with the peer", "cost_unit": comp.cost_unit})
    return rows
