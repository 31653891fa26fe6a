"""`phasors`: a raw measurement file (time, tacho, x1, ...) to a phasor file (one 1x phasor per row)."""

import json
import os

from ._common import InputError


def _check_out(out):
    """`--out FILE.csv`: a .csv file name whose folder exists (checked before any computing)."""
    if os.path.isdir(out):
        raise InputError(f"--out {out}: is a folder: give a file name such as {os.path.join(out, 'phasors.csv')}")
    if os.path.splitext(out)[1].lower() != ".csv":
        raise InputError(f"--out {out}: a phasor file is CSV: give a file name ending in .csv")
    folder = os.path.dirname(out)
    if folder and not os.path.isdir(folder):
        raise InputError(f"--out {out}: the folder {folder} does not exist")


def _runs_summary(data):
    import numpy as np

    out = []
    for r in data.runs():
        sel = data.run == r
        speeds = np.unique(data.speed[sel])
        trial = data.trial(r)
        out.append({"run": r, "rows": int(sel.sum()), "speeds": int(speeds.size),
                    "speed_range": [float(speeds.min()), float(speeds.max())],
                    "trial": None if trial is None else {"node": trial[0], "magnitude": trial[1],
                                                         "phase": trial[2]}})
    return out


def cmd_phasors(args) -> int:
    from rotorjax import identify as idf

    _check_out(args.out)
    data = idf.phasors_from_signals(args.raw, args.map, args.revolutions)
    try:
        idf.write_phasors(args.out, data)
    except InputError as e:
        raise InputError(f"--out {e}") from None
    runs = _runs_summary(data)
    lo, hi = float(data.speed.min()), float(data.speed.max())
    if args.json:
        print(json.dumps({"file": args.out, "rows": data.n, "runs": runs, "speed_range": [lo, hi]}, indent=2))
        return 0
    print(f"{data.path}: {len(runs)} run(s), {data.n} phasors, speeds {lo:.4g} to {hi:.4g} rad/s")
    for r in runs:
        how = "steady" if r["speeds"] == 1 else f"order-tracked, {r['speeds']} blocks"
        a, b = r["speed_range"]
        speed = f"{a:.4g} rad/s" if r["speeds"] == 1 else f"{a:.4g} to {b:.4g} rad/s"
        t = r["trial"]
        trial = "no trial weight" if t is None else \
            f"trial weight {t['magnitude']:.4g} kg m at node {t['node']}, {t['phase']:.4g} rad"
        print(f"  run {r['run']}: {how}, {speed}, {r['rows']} phasors, {trial}")
    print(f"  wrote {args.out}")
    return 0
