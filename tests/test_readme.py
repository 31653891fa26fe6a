"""The README's examples are tests: every `rotorjax ...` command in its bash blocks
runs (exit 0) and every Python block executes, so the documentation cannot drift
from the code.

Quick settings: grids, scans and run lengths are capped (`QUICK`) so that the whole
file runs in a few minutes; the commands are otherwise run as written (in-process,
with `--out` in a temporary folder). `rotorjax demo` runs in `test_cli.py`, `rotorjax
bench` (at its smoke sizes) in `test_bench.py`."""

import os
import re
import shlex

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


def _blocks(kind):
    text = open(README).read()
    return re.findall(rf"```{kind}\n(.*?)```", text, flags=re.S)


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
    for c in commands():
        assert "[" not in c, f"README command with optional-part brackets cannot be copied: {c}"


@pytest.mark.parametrize("line", commands())
def test_readme_command(line, tmp_path, capsys):
    argv = quick(shlex.split(line)[1:])
    if "--out" in argv:
        argv[argv.index("--out") + 1] = str(tmp_path / "out")
    elif argv[0] not in ("presets", "data"):
        argv += ["--out", str(tmp_path / "out")]
    rc = main(argv)
    cap = capsys.readouterr()
    assert rc == 0, f"{line}\n{cap.err}"


@pytest.mark.parametrize("i", range(len(_blocks("python"))))
def test_readme_python_block(i, tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)
    exec(compile(_blocks("python")[i], f"README python block {i}", "exec"), {})
