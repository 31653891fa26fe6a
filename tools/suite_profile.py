"""Where the test suite's time goes, per test file: `benchmarks/results/suite_profile.json`.

    ROTORJAX_SUITE_PROFILE=/tmp/prof python3 -m pytest -q --junitxml=/tmp/suite.xml
    python3 tools/suite_profile.py /tmp/suite.xml /tmp/prof [--out benchmarks/results/suite_profile.json]
        [--wall SECONDS] [--ci-run SECONDS] [--label TEXT]

The junit file gives each test file's wall time (the sum of its tests' setup, call and teardown,
so a module fixture counts once); the profile folder (`tests/suite_profile.py`) gives JAX's
tracing, lowering and backend-compile seconds and the number of programs compiled in each file,
including the benchmark scripts' smoke runs (`benchmarks/NAME.py`, run in a subprocess of their
group's file). `execute_other` is what is left of a file's wall time: running the programs,
Python, subprocesses that JAX's events do not reach (the notebooks' kernels, ROSS, AUTO-07p)."""

import argparse
import collections
import glob
import json
import os
import platform
import sys
import xml.etree.ElementTree as ET

KEYS = ("trace", "lower", "compile", "cache_load", "cache_saved", "programs")


def junit_files(path):
    """`{test file: (seconds, tests, failures)}` from a pytest junit file."""
    out = collections.defaultdict(lambda: [0.0, 0, 0])
    for case in ET.parse(path).getroot().iter("testcase"):
        # classname "tests.analysis.test_x", or "tests.analysis.test_x.TestClass" for a test in a class
        module = [p for p in case.get("classname", "").split(".") if p != "tests"]
        while module and not module[-1].startswith("test_"):
            module.pop()
        name = "/".join(module) + ".py" if module else case.get("classname", "?")
        row = out[name]
        row[0] += float(case.get("time", 0.0))
        row[1] += 1
        row[2] += any(child.tag in ("failure", "error") for child in case)
    return out


def profile_events(folder):
    """`{file: {event: seconds}}` summed over the processes' JSON files."""
    out = collections.defaultdict(lambda: collections.defaultdict(float))
    for path in glob.glob(os.path.join(folder, "[0-9]*.json")):
        with open(path) as f:
            for name, events in json.load(f).items():
                for key, value in events.items():
                    out[name][key] += value
    return out


def program_names(folder, top=40):
    """The `top` program names by compile seconds, summed over the processes: `[{name, programs, compile}]`,
    and the totals over every name."""
    out = collections.defaultdict(lambda: [0, 0.0])
    for path in glob.glob(os.path.join(folder, "programs-*.json")):
        with open(path) as f:
            for name, (count, seconds) in json.load(f).items():
                out[name][0] += count
                out[name][1] += seconds
    rows = sorted(({"name": k, "programs": c, "compile": round(s, 2)} for k, (c, s) in out.items()),
                  key=lambda r: -r["compile"])
    return rows[:top], {"names": len(rows), "programs": sum(r["programs"] for r in rows),
                        "compile": round(sum(r["compile"] for r in rows), 1)}


def build(junit, folder, wall=None, label="", ci_run=None):
    files = junit_files(junit)
    events = profile_events(folder)
    rows = []
    for name, (seconds, tests, failures) in files.items():
        ev = events.get(name, {})
        jax_s = ev.get("trace", 0.0) + ev.get("lower", 0.0) + ev.get("compile", 0.0)
        rows.append({"file": name, "tests": tests, "failed": failures, "wall_s": round(seconds, 2),
                     **{k: round(ev.get(k, 0.0), 2) for k in KEYS},
                     "execute_other_s": round(max(seconds - jax_s, 0.0), 2)})
    rows.sort(key=lambda r: -r["wall_s"])
    scripts = [{"script": name, **{k: round(v, 2) for k, v in ev.items()}}
               for name, ev in sorted(events.items()) if name.startswith("benchmarks/")]
    total = {k: round(sum(r[k] for r in rows), 1) for k in ("wall_s", "trace", "lower", "compile",
                                                             "cache_load", "execute_other_s")}
    total["tests"] = sum(r["tests"] for r in rows)
    total["programs"] = int(sum(r["programs"] for r in rows))
    return {"label": label, "machine": {"platform": platform.platform(), "cpu_count": os.cpu_count(),
                                        "python": sys.version.split()[0]},
            "run_wall_s": wall, "ci_run_s": ci_run, "total_worker_s": total,
            "note": "wall_s sums each file's tests (setup + call + teardown) over the workers; the compile "
                    "columns are JAX's monitoring events in the workers and in the benchmark smoke runners "
                    "(the scripts' rows are also counted in their group file's row)",
            "files": rows, "benchmark_scripts": scripts,
            "programs_by_name": dict(zip(("top", "all"), program_names(folder)))}


def main(argv=None):
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("junit")
    p.add_argument("profile")
    p.add_argument("--out", default="benchmarks/results/suite_profile.json")
    p.add_argument("--wall", type=float, default=None, help="the run's wall time, seconds")
    p.add_argument("--ci-run", type=float, default=None, help="`.ci/run`'s wall time, installs included, seconds")
    p.add_argument("--label", default="")
    a = p.parse_args(argv)
    result = build(a.junit, a.profile, a.wall, a.label, a.ci_run)
    with open(a.out, "w") as f:
        json.dump(result, f, indent=1)
    print(f"wrote {a.out}: {len(result['files'])} files, {result['total_worker_s']}")


if __name__ == "__main__":
    main()
