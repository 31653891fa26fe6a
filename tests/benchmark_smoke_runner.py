"""Runs benchmark scripts' smoke modes one after another in this one interpreter
(`python tests/benchmark_smoke_runner.py [--host-devices N] OUT.json NAME...`): each as
`__main__` with `--smoke`, its output captured, its exit recorded; the imports (jax,
rotorjax, scipy, numba, matplotlib) and the compilations the scripts share are paid once.
Writes `{name: {"ok", "seconds", "tail"}}` to OUT.json. Used by
tests/test_benchmark_smoke*.py.

Without `--host-devices` the runner keeps the XLA flags it inherits (the test workers'), so
that the run's persistent compilation cache serves a program compiled by a worker to a
script and back: JAX keys its cache by the XLA flags too. With `--host-devices N` (the
scripts that split work over host devices: `tests.helpers.SMOKE_HOST_DEVICES`) it adds
N host devices and XLA's Eigen threads off, as those scripts set them themselves when run
alone."""

import contextlib
import io
import json
import os
import runpy
import sys
import time
import traceback

if len(sys.argv) > 2 and sys.argv[1] == "--host-devices":
    # before jax is imported; added to the flags this process inherits (pytest's, where importing rotorjax has
    # already set one: `rotorjax._config`)
    _FLAGS = os.environ.get("XLA_FLAGS", "")
    for _flag in (f"--xla_force_host_platform_device_count={int(sys.argv[2])}", "--xla_cpu_multi_thread_eigen=false"):
        if _flag.split("=")[0] not in _FLAGS:
            _FLAGS = f"{_FLAGS} {_flag}".strip()
    os.environ["XLA_FLAGS"] = _FLAGS
    del sys.argv[1:3]

BENCH = os.path.join(os.path.dirname(os.path.dirname(os.path.abspath(__file__))), "benchmarks")


def run(name):
    path = os.path.join(BENCH, f"{name}.py")
    buf = io.StringIO()
    argv, sys.argv = sys.argv, [path, "--smoke"]
    if sys.path[0] != BENCH:  # as `python benchmarks/NAME.py` puts the script's folder first
        sys.path.insert(0, BENCH)
    t0 = time.perf_counter()
    ok = True
    with contextlib.redirect_stdout(buf), contextlib.redirect_stderr(buf):
        try:
            runpy.run_path(path, run_name="__main__")
        except SystemExit as e:
            ok = e.code in (0, None)
            print(f"SystemExit({e.code!r})")
        except BaseException:  # noqa: BLE001 - recorded, then the next script runs
            ok = False
            traceback.print_exc()
    sys.argv = argv
    text = buf.getvalue()
    return {"ok": ok and "smoke run: nothing written" in text, "seconds": time.perf_counter() - t0,
            "tail": text[-4000:]}


def main():
    out, names = sys.argv[1], sys.argv[2:]
    sys.path.insert(0, os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
    from tests import suite_profile

    suite_profile.install()
    report = {}
    for name in names:
        suite_profile.current_file(f"benchmarks/{name}.py")
        report[name] = run(name)
        print(f"{name}: {'ok' if report[name]['ok'] else 'FAILED'} {report[name]['seconds']:.1f} s", flush=True)
        with open(out, "w") as f:
            json.dump(report, f, indent=1)


if __name__ == "__main__":
    main()
