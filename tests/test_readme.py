"""The README's examples are tests: every `rotorjax ...` command in its bash blocks
runs (exit 0) and every Python block executes, so the documentation cannot drift
from the code. What they print is checked too: a Python block's printed claim
(`... : True`) must hold, and the numbers the README states next to a block or a
command are read from the README's text and compared with what the block prints or
the command writes (`CLAIMS`, `BLOCK_CLAIMS`). `response`, `modes` and `ucs` are only
run here: their numbers are compared with the Python API in `test_cli.py`.

Quick settings: grids, scans and run lengths are capped (`QUICK`) so that the whole
file runs in a few minutes; the commands are otherwise run as written (in-process,
with `--out` in a temporary folder). `rotorjax demo` runs in `test_cli.py`, `rotorjax
bench` (at its smoke sizes) in `test_bench.py`."""

import contextlib
import io
import json
import os
import re
import shlex

import numpy as np

import pytest

from rotorjax.cli import main

README = os.path.join(os.path.dirname(__file__), "..", "README.md")

#: caps on sizes: option -> (index of the value after the option, cap)
QUICK = {"--x": (3, 3), "--y": (3, 3), "--param": (3, 3), "--n-scan": (0, 12), "--n-speeds": (0, 10),
         "--n": (0, 200), "--max-points": (0, 4), "--t-end": (0, 100.0), "--n-save": (0, 400)}
#: `--set` values capped the same way
QUICK_SETS = {"revolutions": 20, "nu_end": 2.0}
#: options added when absent, per command
QUICK_DEFAULTS = {"critical-speeds": ["--n-scan", "12"], "hopf": ["--n-scan", "12"],
                  "continue": ["--max-points", "4"], "campbell": ["--n-speeds", "10"],
                  "simulate": ["--n-save", "400"]}


def _text():
    with open(README) as f:
        return f.read()


def _blocks(kind):
    return re.findall(rf"```{kind}\n(.*?)```", _text(), flags=re.S)


def stated(pattern):
    """The numbers the README states where `pattern` (a regex whose groups are the
    numbers; any whitespace matches a line break) matches its text."""
    m = re.search(pattern.replace(" ", r"\s+"), _text())
    assert m, f"the README no longer states /{pattern}/"
    return [float(g) for g in m.groups()]


def _abb_exact_check(out):
    exact = stated(r"root finding: \*\*([\d.]+), ([\d.]+), ([\d.]+)\*\*")
    assert [round(c, 6) for c in out["critical_speeds"]] == exact


def _abb_modal_check(out):
    from rotorjax.flexible import exact_critical_speeds   # eq. (17), checked against the paper in _abb_exact_check

    exact = np.asarray(exact_critical_speeds(1.0, 0.5, lo=0.1, hi=25.0))
    errors = stated(r"\(20 modes: errors ([\d.e-]+), ([\d.e-]+), ([\d.e-]+);")
    got = np.asarray(out["critical_speeds"][:3]) - np.asarray(exact)
    assert [float(f"{e:.1e}") for e in got] == errors, got   # from above: errors positive


def _ross_critical_check(out):
    backward, forward = stated(r"first two critical speeds \(([\d.]+) backward, ([\d.]+) forward rad/s\)")
    first = out["critical_speeds"][:2]
    assert [(round(c["speed"], 3), c["whirl"]) for c in first] == [(backward, "backward"), (forward, "forward")]


def _balance_check(out):
    m0, a0, m1, a1 = stated(r"shipped runs: ([\d.]+) g at (\d+) deg, ([\d.]+) g at (\d+) deg")
    got = [(round(c["mass_g"], 1), round(c["angle_deg"] % 360)) for c in out["corrections"]]
    assert got == [(m0, a0), (m1, a1)]


#: README command -> a check of its JSON output (the command is run with `--json`)
#: against the numbers the README states for it
CLAIMS = {
    "rotorjax critical-speeds flexible-abb --range 0.1 25 --exact": _abb_exact_check,
    "rotorjax critical-speeds flexible-abb --range 0.1 25 --modes 20": _abb_modal_check,
    "rotorjax critical-speeds ross-compare --range 10 1000": _ross_critical_check,
    "rotorjax critical-speeds rotorjax/rotors/ross_compare.toml --range 10 1000": _ross_critical_check,
    "rotorjax balance --json": _balance_check,
}


def commands():
    out = []
    for block in _blocks("bash"):
        for line in block.splitlines():
            line = line.split("  #")[0].strip()
            if line.startswith("rotorjax ") and not line.startswith(("rotorjax demo", "rotorjax bench")):
                out.append(line)
    return out


def quick(argv):
    argv = list(argv)
    for i, a in enumerate(argv):
        if a in QUICK and not (a == "--param" and argv[0] != "bifurcation"):
            k, cap = QUICK[a]
            j = i + 1 + k
            if j < len(argv):
                argv[j] = str(type(cap)(min(float(argv[j]), cap)))
        if a == "--set" and i + 1 < len(argv):
            key, _, value = argv[i + 1].partition("=")
            if key in QUICK_SETS:
                argv[i + 1] = f"{key}={min(float(value), QUICK_SETS[key]):g}"
    extra = QUICK_DEFAULTS.get(argv[0], [])
    if extra and extra[0] not in argv:
        argv += extra
    if len(argv) > 1 and argv[1] == "cantilever-limiters" and argv[0] in ("simulate", "bifurcation") \
            and not any(a.startswith("revolutions=") for a in argv):
        argv += ["--set", f"revolutions={QUICK_SETS['revolutions']}"]
    return argv


def test_readme_has_examples():
    assert len(commands()) >= 20 and len(_blocks("python")) >= 2
    assert set(CLAIMS) <= set(commands()), set(CLAIMS) - set(commands())
    for c in commands():
        assert "[" not in c, f"README command with optional-part brackets cannot be copied: {c}"


@pytest.mark.parametrize("line", commands())
def test_readme_command(line, tmp_path, capsys):
    argv = quick(shlex.split(line)[1:])
    if "--out" in argv:
        argv[argv.index("--out") + 1] = str(tmp_path / "out")
    elif argv[0] not in ("presets", "data"):
        argv += ["--out", str(tmp_path / "out")]
    check = CLAIMS.get(line)
    if check is not None and "--json" not in argv:
        argv.append("--json")
    rc = main(argv)
    cap = capsys.readouterr()
    assert rc == 0, f"{line}\n{cap.err}"
    if check is not None:
        check(json.loads(cap.out))


def _hopf_check(printed, ns):
    assert re.fullmatch(r"FE [\d.]+ rad/s, Jeffcott [\d.]+ rad/s", printed), printed
    fe, k = float(ns["hopf"].speed), ns["k"]
    jeffcott = np.sqrt(k / 32.59) * (1 + 92.0 / (2e-4 * k))
    # the README: the FE threshold approaches Jeffcott's at first order in the shaft/disk
    # mass ratio, by the shaft's Rayleigh mass (-17/70 of the ratio): -2.2e-4 here
    ratio = 10.0 * np.pi * 0.05 ** 2 / 4 * 1.5 / 32.59
    assert abs((fe / jeffcott - 1) / (-17 / 70 * ratio) - 1) < 0.1, (fe, jeffcott)


def _limiters_check(printed, ns):
    (free,) = stated(r"free response ([\d.]+) mm, clearance")
    (clearance,) = stated(r"free response [\d.]+ mm, clearance ([\d.]+) mm")
    radius = float(re.match(r"max radius ([\d.]+) mm", printed).group(1))
    assert clearance < radius < free       # rubbing, and bounded well below the free response
    assert printed.endswith("energy balance to 1e-6: True")


def _fold_check(printed, ns):
    folds = json.loads(re.fullmatch(r"folds at (\[.*\]) rad/s", printed).group(1))
    assert sorted(folds) == stated(r"folding twice \(([\d.]+) and ([\d.]+) rad/s")


def _balancer_check(printed, ns):
    verdict, whirl, margin = re.fullmatch(r"(\w+): whirl (\S+) m, margin (\S+) 1/s", printed).groups()
    # "stable by the autodiff Jacobian at 1.5x the critical speed": shaft straight, margin negative
    assert verdict == "stable" and float(whirl) < 1e-12 and float(margin) < 0


#: a distinctive line of a README Python block -> a check of (its printed text, its namespace)
BLOCK_CLAIMS = {
    "result.success\n": lambda printed, ns: bool(ns["result"].success),
    "failed points have code != 0": lambda printed, ns: (np.shape(ns["res"]["whirl"]) == (8, 2)
                                                         and not np.any(np.asarray(ns["res"]["code"]))),
    "r.outputs[\"whirl_amplitude\"][:, -1], r.code": lambda printed, ns: (np.shape(ns["r"].ys) == (12, 50, 8)
                                                                       and not np.any(np.asarray(ns["r"].code))),
    "regime.verdict": _balancer_check,
    "hopf_points(scene": _hopf_check,
    "energy balance to 1e-6": _limiters_check,
    "synchronous_branch(": _fold_check,
}


@pytest.mark.parametrize("i", range(len(_blocks("python"))))
def test_readme_python_block(i, tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)
    block = _blocks("python")[i]
    out, ns = io.StringIO(), {}
    with contextlib.redirect_stdout(out):
        exec(compile(block, f"README python block {i}", "exec"), ns)
    printed = out.getvalue().strip()
    for line in printed.splitlines():  # a printed claim that does not hold
        assert not re.search(r"\bFalse\b", line), f"README python block {i} prints: {line}"
    for key, check in BLOCK_CLAIMS.items():
        if key in block:
            assert check(printed, ns) is not False, f"README python block {i} prints: {printed}"


def test_every_block_claim_has_its_block():
    blocks = _blocks("python")
    for key in BLOCK_CLAIMS:
        assert sum(key in b for b in blocks) == 1, key
