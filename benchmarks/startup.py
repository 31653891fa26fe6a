"""Start-up cost of the everyday commands (issue 28): each README command on the
shipped rotors, and on the 36-dof rotor (`tapered_two_material.toml`: tapered elements,
speed-tabulated bearings), run as a user runs it (`rotorjax ...` in a fresh process),
first with an empty compilation cache (the first run after installing) and then again
(the cache filled by the first run: every later run). Wall time of the whole process:
import, rotor file, compilation or cache load, computing, plots, JSON.

    python benchmarks/startup.py [--smoke]

Writes `benchmarks/results/startup.json` (the README's start-up table quotes it)."""

import argparse
import os
import subprocess
import sys
import tempfile
import time

import numpy as np

from _common import CpuWatch, machine, write_results

TAPERED = "rotorjax/rotors/tapered_two_material.toml"
ROSS = "rotorjax/rotors/ross_compare.toml"
#: (label, argv): the README's linear commands, on the 36-dof rotor and on ROSS's example rotor (28 dofs)
COMMANDS = [
    ("modes 36 dofs", ["modes", TAPERED, "--speed", "400"]),
    ("campbell 36 dofs", ["campbell", TAPERED, "--range", "0", "1000"]),
    ("critical-speeds 36 dofs", ["critical-speeds", TAPERED, "--range", "10", "1000"]),
    ("response 36 dofs", ["response", TAPERED, "--range", "10", "1000"]),
    ("frf 36 dofs", ["frf", TAPERED, "--input", "2,x", "--output", "6,y", "--range", "10", "1000"]),
    ("ucs 36 dofs", ["ucs", TAPERED]),
    ("level1 36 dofs", ["level1", TAPERED, "--speed", "800"]),
    ("static 36 dofs", ["static", TAPERED]),
    ("modes 28 dofs", ["modes", ROSS]),
    ("campbell 28 dofs", ["campbell", "ross-compare", "--range", "0", "1000"]),
    ("critical-speeds 28 dofs", ["critical-speeds", "ross-compare", "--range", "10", "1000"]),
    ("response 28 dofs", ["response", "ross-compare", "--range", "10", "1200"]),
]
#: the issue's targets (s): a cached run of these commands, and any first run
CACHED_TARGET, FIRST_TARGET = 5.0, 15.0
TARGETED = ("modes", "campbell", "critical-speeds", "response")


def run(argv, cache, out):
    """Seconds of wall time of `rotorjax ARGV` in a fresh interpreter (exit 0 required)."""
    env = dict(os.environ, ROTORJAX_CACHE_DIR=cache, MPLBACKEND="Agg")
    for name in ("JAX_COMPILATION_CACHE_DIR", "JAX_PERSISTENT_CACHE_MIN_COMPILE_TIME_SECS",
                 "JAX_PERSISTENT_CACHE_MIN_ENTRY_SIZE_BYTES", "ROTORJAX_NO_COMPILATION_CACHE",
                 "XLA_FLAGS"):   # the test suite's: a user's command has none of them
        env.pop(name, None)
    t0 = time.perf_counter()
    proc = subprocess.run([sys.executable, "-m", "rotorjax.cli", *argv, "--out", out, "--json"], env=env,
                          capture_output=True, text=True, cwd=ROOT)
    wall = time.perf_counter() - t0
    if proc.returncode != 0:
        raise RuntimeError(f"rotorjax {' '.join(argv)} failed ({proc.returncode}): {proc.stderr[-600:]}")
    return wall


ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))


def table(out) -> str:
    """The README's start-up table (markdown) from the results."""
    lines = ["| command | first run (empty cache) | cached run |", "|---|---|---|"]
    for r in out["commands"]:
        lines.append(f"| `rotorjax {' '.join(r['argv'])}` | {r['first_s']:.1f} s | {r['cached_s']:.1f} s |")
    return "\n".join(lines)


def main(argv=None):
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--smoke", action="store_true", help="one command, one run each way, nothing written")
    p.add_argument("--repeats", type=int, default=3, help="cached runs per command (median)")
    p.add_argument("--table", action="store_true", help="print the README's table from the stored results")
    args = p.parse_args(argv)
    if args.table:
        import json

        with open(os.path.join(ROOT, "benchmarks", "results", "startup.json")) as f:
            print(table(json.load(f)))
        return None
    commands = COMMANDS[:1] if args.smoke else COMMANDS
    repeats = 1 if args.smoke else args.repeats
    watch = CpuWatch()
    rows = []
    with tempfile.TemporaryDirectory() as tmp:
        for label, cmd in commands:
            cache = os.path.join(tmp, "cache-" + label.replace(" ", "-"))   # empty: a first run
            first = run(cmd, cache, tmp)
            cached = float(np.median([run(cmd, cache, tmp) for _ in range(repeats)]))
            rows.append({"command": label, "argv": cmd, "first_s": first, "cached_s": cached})
            print(f"{label:26s} first {first:6.2f} s   cached {cached:6.2f} s", flush=True)
    out = {"machine": machine(), "load": watch.report(), "repeats": repeats, "commands": rows,
           "targets": {"cached_s": CACHED_TARGET, "first_s": FIRST_TARGET, "cached_commands": list(TARGETED)}}
    if args.smoke:
        print("smoke run: nothing written")
    else:
        write_results("startup", out)
    return out


if __name__ == "__main__":
    main()
