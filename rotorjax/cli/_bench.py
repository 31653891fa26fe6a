"""`bench`: the headline comparisons on this machine (the work is `rotorjax.bench`;
this parses, shows progress and presents the ratio table)."""

import json
import os

from ._common import InputError, NumericalError, Stages, prepare_out, write_json


def _sizes(args):
    from rotorjax import bench

    return bench.SMOKE if args.smoke else bench.QUICK if args.quick else bench.FULL


def _check_ross_python(path):
    import subprocess

    if path is None:
        return None
    if not (os.path.isfile(path) and os.access(path, os.X_OK)):
        raise InputError(f"--ross-python {path}: no executable file there (give the Python interpreter that has "
                         "ROSS, e.g. /path/to/venv/bin/python)")
    try:
        ok = subprocess.run([path, "-c", "import ross"], capture_output=True, timeout=300).returncode == 0
    except (OSError, subprocess.TimeoutExpired):
        ok = False
    if not ok:
        raise InputError(f"--ross-python {path}: that interpreter cannot `import ross` (pip install "
                         "ross-rotordynamics there)")
    return path


def _fmt_cost(seconds):
    return f"{seconds * 1e3:.3g} ms" if seconds < 1 else f"{seconds:.3g} s"


def table_lines(report):
    """The ratio table and the notes, as printed."""
    lines = [f"{'comparison':<17} {'rotorjax tol':>12} {'error':>9}  {'peer':<36} {'peer cost':>10} "
             f"{'rotorjax':>10} {'ratio':>8}  unit"]
    for r in report["table"]:
        flag = "" if r["match"] == "interpolated" or r["match"].startswith("same") else " *"
        lines.append(f"{r['comparison']:<17} {r['rotorjax_tolerance']:>12} {r['error']:>9.1e}  {r['peer']:<36} "
                     f"{_fmt_cost(r['peer_cost']):>10} {_fmt_cost(r['rotorjax_cost']):>10} "
                     f"{r['ratio']:>7.3g}x  {r['cost_unit']}{flag}")
    lines.append("ratio: the peer's cost at rotorjax's error (read off the peer's own ladder) over rotorjax's "
                 "cost, compiled code timed after a first call")
    if any(not (r["match"] == "interpolated" or r["match"].startswith("same")) for r in report["table"]):
        lines.append("*: the peer's ladder does not reach rotorjax's error: its nearest rung's cost")
    for c in report["comparisons"]:
        for note in c["notes"]:
            lines.append(f"note ({c['name']}): {note}")
        for s in c["skipped"]:
            lines.append(f"skipped ({c['name']}): {s['peer']}: {s['why']}")
    return lines


def cmd_bench(args) -> int:
    from rotorjax import bench
    from rotorjax.plot import plot_bench
    from ._common import save_figure

    ross_py = _check_ross_python(args.ross_python)
    try:
        bench.resolve_device(args.device)
    except ValueError as e:
        raise InputError(f"--device {args.device}: {str(e).split(': ', 1)[1]}") from None
    prepare_out(args.out)
    stages = Stages("bench", len(bench.STAGES), enabled=not args.json)
    try:
        report = bench.run_bench(_sizes(args), args.device, ross_py, progress=stages)
    except FloatingPointError as e:
        raise NumericalError(str(e)) from None
    finally:
        stages.close()
    report["mode"] = "smoke" if args.smoke else "quick" if args.quick else "full"
    path_json = os.path.join(args.out, "bench.json")
    path_png = os.path.join(args.out, "bench.png")
    write_json(path_json, report, indent=2)
    save_figure(plot_bench(report), path_png)
    report["files"] = {"json": path_json, "diagram": path_png}
    if args.json:
        print(json.dumps(report, indent=2))
        return 0
    m = report["machine"]
    print(f"rotorjax bench ({report['mode']}): {m['device']}, {m['cpu_count']} CPU cores, jax {m['jax']}, "
          f"{m['date']}")
    print("\n".join(table_lines(report)))
    print(f"wrote {path_png} (work-precision diagram) and {path_json}")
    return 0
