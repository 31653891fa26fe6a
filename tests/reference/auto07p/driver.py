"""Run AUTO-07p from Python, non-interactively, and read its bifurcation diagrams.

AUTO-07p (Doedel et al.; Debian package `auto-07p`, installed by `.ci/install-auto07p`)
is a Fortran library: an equation file (`FUNC`, `STPNT`, ...) is compiled and linked
against it into an executable, which reads its constants on stdin and writes the
bifurcation diagram to `fort.7` (AUTO's `b.*` files), the labelled solutions to `fort.8`
(`s.*`) and diagnostics to `fort.9` (`d.*`). This is what AUTO's own `@r` command and its
Python shell do; here it is done directly (no `auto` shell, no display, no Tk), each
equation compiled once in a temporary directory:

    eq = Equation("duffing", workdir)          # copies duffing.f90 there
    eq.compile()                               # gfortran, AUTO's flags; seconds in eq.compile_seconds
    r1 = eq.run("duffing.branch", PAR={1: 0.5, 2: 0.05}, U={1: p0, 2: q0})
    r2 = eq.run("duffing.fold", restart=r1, IRS=r1.label("LP")[0])

Constants files (`c.<name>` next to this module) hold one `KEY = value` per line, in
AUTO-07p's keyword format; keyword arguments of `run` replace or add lines. A run is
`Run`: its branches (columns by AUTO's names: `PAR(1)`, `U(1)`, `L2-NORM`, ...; rows
with AUTO's full 11 significant digits), the special points, the wall time and AUTO's
own "Total Time", and `ok` (exit status 0 and every branch ended at a user stop (UZ)
or an end point (EP), none at a convergence failure (MX)).
"""

import dataclasses
import os
import re
import shutil
import subprocess
import time

import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
NOT_INSTALLED = "AUTO-07p not installed: .ci/install-auto07p installs it"

# AUTO's point types (the TY column of fort.7; in two-parameter runs the tens digit
# says which kind of point the curve was started from, e.g. -24: UZ on a fold curve)
TYPES = {1: "BP", 2: "LP", 3: "HB", 4: "RG", -4: "UZ", 5: "LP", 6: "BP", 7: "PD", 8: "TR", 9: "EP", -9: "MX",
         0: ""}


@dataclasses.dataclass(frozen=True)
class Installation:
    auto_dir: str
    fc: str
    fflags: str
    version: str


def _dpkg_version():
    try:
        out = subprocess.run(["dpkg-query", "-W", "-f=${Version}", "auto-07p"], capture_output=True, text=True,
                             timeout=10)
        return out.stdout.strip() or "unknown"
    except (OSError, subprocess.SubprocessError):
        return "unknown"


def find_auto():
    """`(Installation, None)` when AUTO-07p's library and a Fortran compiler are
    here, else `(None, why)`. `AUTO_DIR` (environment) overrides the Debian path."""
    auto_dir = os.environ.get("AUTO_DIR", "/usr/lib/auto-07p")
    lib = os.path.join(auto_dir, "lib")
    if not os.path.isfile(os.path.join(lib, "main.o")):
        return None, f"{NOT_INSTALLED} (no {lib}/main.o)"
    make = {}
    try:
        with open(os.path.join(auto_dir, "cmds", "cmds.make")) as f:
            for line in f:
                m = re.match(r"^(FC|FFLAGS|OPT)\s*=\s*(.*)$", line)
                if m:
                    make[m.group(1)] = m.group(2).strip()
    except OSError:
        pass
    fc = shutil.which(make.get("FC", "gfortran")) or shutil.which("gfortran")
    if fc is None:
        return None, f"{NOT_INSTALLED} (AUTO's library is there but no gfortran to link equation files)"
    fflags = " ".join([make.get("FFLAGS", "-O2 -fPIC -std=legacy -fopenmp"), make.get("OPT", "")])
    # the Debian flags name the package's build directory; harmless, but noise
    fflags = list(dict.fromkeys(re.sub(r"-ffile-prefix-map=\S+", "", fflags).split()))
    return Installation(auto_dir, fc, " ".join(fflags), _dpkg_version()), None


@dataclasses.dataclass
class Branch:
    """One branch of a bifurcation diagram: `columns` (AUTO's names) and `data`
    (one row per point), the point numbers `pt` (negative: stable, for ODE
    equilibria), the type codes `ty` and the labels `lab` (0: unlabelled)."""

    number: int
    columns: tuple
    data: np.ndarray
    pt: np.ndarray
    ty: np.ndarray
    lab: np.ndarray

    def __getitem__(self, name):
        return self.data[:, self.columns.index(name)]

    def kinds(self):
        return [TYPES.get(int(np.sign(t) * (abs(t) % 10)), str(t)) for t in self.ty]

    def special(self, kind):
        """Row indices of the points of one kind ("LP", "HB", "UZ", "EP", "MX", ...)."""
        return [i for i, k in enumerate(self.kinds()) if k == kind]

    def point(self, i, names):
        return np.array([self.data[i, self.columns.index(n)] for n in names])


def _number(v):
    """A Fortran number: `1.5E+000`, `1.5D+00`, or `1.5-100` (a three-digit exponent
    without its E), or an integer."""
    if not any(c in v for c in ".EeDd"):
        return int(v)
    v = v.replace("D", "E").replace("d", "E")
    return float(re.sub(r"(?<=[0-9.])([-+][0-9]+)$", r"E\1", v) if "E" not in v.upper() else v)


def _header(words):
    """Column names of a fort.7 header: a periodic problem's `MAX U(1)`, `MIN U(1)`
    and `INTEGRAL U(1)` are one name each (two words in the file)."""
    names, i = [], 0
    while i < len(words):
        if words[i] in ("MAX", "MIN", "INTEGRAL") and i + 1 < len(words):
            names.append(f"{words[i]} {words[i + 1]}")
            i += 2
        else:
            names.append(words[i])
            i += 1
    return names


def parse_b(text):
    """The branches of a fort.7 / b.* file."""
    branches, header, rows = [], None, []

    def flush():
        if rows:
            a = np.array(rows)
            branches.append(Branch(int(a[0, 0]), tuple(header), a[:, 4:], a[:, 1].astype(int),
                                   a[:, 2].astype(int), a[:, 3].astype(int)))
        rows.clear()

    for line in text.splitlines():
        f = line.split()
        if not f:
            continue
        if f[0] == "0":
            if len(f) > 4 and f[1:4] == ["PT", "TY", "LAB"]:
                flush()
                header = _header(f[4:])
            continue
        rows.append([_number(v) for v in f])
    flush()
    return branches


def parse_s(text):
    """The labelled solutions of a fort.8 / s.* file of an algebraic or equilibrium
    problem: `{label: {"type": TY, "u": U, "par": PAR(1..NPAR)}}` (PAR(11) is the
    period 2 pi / omega at a Hopf point)."""
    lines, out, i = text.splitlines(), {}, 0
    while i < len(lines):
        head = [int(v) for v in lines[i].split()]
        nrow, npar = head[8], head[11]
        block = [[_number(v) for v in ln.split()] for ln in lines[i + 1:i + 1 + nrow]]
        par_rows = -(-npar // 7)                 # PAR: the block's last lines, 7 a line
        par = [v for row in block[nrow - par_rows:] for v in row]
        out[head[3]] = {"type": head[2], "u": np.array(block[0][1:]), "par": np.array(par)}
        i += 1 + nrow
    return out


def parse_d_multipliers(text):
    """The Floquet multipliers a periodic run (IPS = 2, ISP = 2) prints in its
    fort.9 / d.* file: `{(branch, point): complex array}`, the point numbers as in
    the b-file (unsigned), in AUTO's order (the one nearest 1 first). AUTO writes
    them with 6 significant digits (`PVLS` can copy them into parameters, which
    the b-file prints with 11: `GETP('EIG', ...)`); a point corrected twice (a
    special point located) keeps its last."""
    out, current = {}, {}
    for line in text.splitlines():
        m = re.match(r"^\s*(-?\d+)\s+(-?\d+)\s+Multiplier\s+(\d+)\s+(\S+)\s+(\S+)\s+Abs\. Val\.", line)
        if m:
            key = (abs(int(m.group(1))), abs(int(m.group(2))))
            k = int(m.group(3))
            if k == 1:
                current[key] = []
            current[key].append(complex(_number(m.group(4)), _number(m.group(5))))
            out[key] = np.array(current[key])
    return out


@dataclasses.dataclass
class Run:
    name: str
    constants: str
    returncode: int
    stdout: str
    stderr: str
    seconds: float          # wall time of the executable
    auto_seconds: float     # AUTO's own "Total Time"
    branches: list
    solutions: dict         # from the s-file: label -> {"type", "u", "par"}
    diagnostics: str = ""   # the d-file's text (`parse_d_multipliers` reads a periodic run's multipliers)

    @property
    def ok(self):
        if self.returncode != 0 or not self.branches:
            return False
        return all(b.kinds()[-1] in ("UZ", "EP") and not b.special("MX") for b in self.branches)

    def label(self, kind):
        """Labels of the special points of one kind, in order along the run."""
        return [int(b.lab[i]) for b in self.branches for i in b.special(kind)]

    def points(self, kind):
        return [(b, i) for b in self.branches for i in b.special(kind)]

    def why(self):
        """A short account for an assertion message."""
        ends = [b.kinds()[-1] or "regular" for b in self.branches]
        return (f"AUTO run {self.name}: exit {self.returncode}, branch ends {ends}; "
                f"stdout tail: {self.stdout[-400:]!r}; stderr tail: {self.stderr[-400:]!r}")


def _value(v):
    if isinstance(v, bool):
        return str(int(v))
    if isinstance(v, (int, np.integer)):
        return str(int(v))
    if isinstance(v, (float, np.floating)):
        return repr(float(v))
    if isinstance(v, str):
        return repr(v)
    if isinstance(v, dict):
        return "{" + ", ".join(f"{_value(k)}: {_value(x)}" for k, x in v.items()) + "}"
    if isinstance(v, (list, tuple, np.ndarray)):
        return "[" + ", ".join(_value(x) for x in v) + "]"
    raise TypeError(f"cannot write {v!r} as an AUTO constant")


def constants(name, **overrides):
    """The text of constants file `c.<name>` with `overrides` (KEY=value) applied."""
    with open(os.path.join(HERE, f"c.{name}")) as f:
        lines = [ln.rstrip("\n") for ln in f]
    keys = {}
    for i, ln in enumerate(lines):
        m = re.match(r"^\s*([A-Za-z][A-Za-z0-9]*)\s*=", ln)
        if m:
            keys[m.group(1)] = i
    for k, v in overrides.items():
        ln = f"{k} = {_value(v)}"
        if k in keys:
            lines[keys[k]] = ln
        else:
            lines.append(ln)
    return "\n".join(lines) + "\n"


class Equation:
    """An AUTO equation file (`<name>.f90` next to this module), compiled in `workdir`."""

    def __init__(self, name, workdir, installation=None):
        if installation is None:
            installation, why = find_auto()
            if installation is None:
                raise RuntimeError(why)
        self.name, self.workdir, self.inst = name, str(workdir), installation
        os.makedirs(self.workdir, exist_ok=True)
        shutil.copy(os.path.join(HERE, f"{name}.f90"), self.workdir)
        self.exe = os.path.join(self.workdir, f"{name}.exe")
        self.compile_seconds = None
        self._runs = 0

    def compile(self):
        """Compile and link against AUTO's library (as AUTO's cmds.make does); seconds."""
        lib = os.path.join(self.inst.auto_dir, "lib")
        objs = sorted(os.path.join(lib, f) for f in os.listdir(lib) if f.endswith(".o"))
        flags = self.inst.fflags.split()
        t0 = time.perf_counter()
        for cmd in ([self.inst.fc, *flags, "-c", f"{self.name}.f90", "-o", f"{self.name}.o"],
                    [self.inst.fc, *flags, f"{self.name}.o", "-o", self.exe, *objs]):
            p = subprocess.run(cmd, cwd=self.workdir, capture_output=True, text=True, timeout=120)
            if p.returncode != 0:
                raise RuntimeError(f"compiling {self.name} for AUTO failed: {' '.join(cmd)}\n{p.stderr}")
        self.compile_seconds = time.perf_counter() - t0
        return self.compile_seconds

    def run(self, cfile, restart=None, name=None, timeout=120, **overrides):
        """Run with constants `c.<cfile>` and `overrides`; `restart`, a previous `Run`
        of this equation, supplies the solutions that `IRS` labels."""
        if self.compile_seconds is None:
            self.compile()
        self._runs += 1
        name = name or f"{cfile}.{self._runs}"
        text = constants(cfile, **overrides)
        if restart is not None:
            text = f"s='{restart.name}'\n" + text
        with open(os.path.join(self.workdir, f"c.{name}"), "w") as f:
            f.write(text)
        for k in ("fort.7", "fort.8", "fort.9"):
            if os.path.exists(os.path.join(self.workdir, k)):
                os.remove(os.path.join(self.workdir, k))
        env = dict(os.environ, OMP_NUM_THREADS="1")
        t0 = time.perf_counter()
        p = subprocess.run([self.exe], input=text, cwd=self.workdir, capture_output=True, text=True,
                           timeout=timeout, env=env)
        seconds = time.perf_counter() - t0
        for fort, kind in (("fort.7", "b"), ("fort.8", "s"), ("fort.9", "d")):
            src = os.path.join(self.workdir, fort)
            if os.path.exists(src):
                os.replace(src, os.path.join(self.workdir, f"{kind}.{name}"))
        bpath = os.path.join(self.workdir, f"b.{name}")
        branches = []
        if os.path.exists(bpath):
            with open(bpath) as f:
                branches = parse_b(f.read())
        spath = os.path.join(self.workdir, f"s.{name}")
        solutions = {}
        if os.path.exists(spath):
            with open(spath) as f:
                solutions = parse_s(f.read())
        dpath = os.path.join(self.workdir, f"d.{name}")
        diagnostics = ""
        if os.path.exists(dpath):
            with open(dpath) as f:
                diagnostics = f.read()
        m = re.search(r"Total Time\s+(\S+)", p.stdout)
        auto_seconds = _number(m.group(1)) if m else float("nan")
        return Run(name, text, p.returncode, p.stdout, p.stderr, seconds, auto_seconds, branches, solutions,
                   diagnostics)
