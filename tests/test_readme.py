"""The README's examples are tests: every `rotorjax ...` command in its bash blocks
runs (exit 0) and every Python block executes, so the documentation cannot drift
from the code. What they print is checked too: a Python block's printed claim
(`... : True`) must hold, and the numbers the README states next to a block or a
command are read from the README's text and compared with what the block prints or
the command writes (`CLAIMS`, `BLOCK_CLAIMS`). The linear FE commands' key outputs
(`OUTPUTS`: response and FRF peaks, modes, static reactions, UCS intersections, the
level I threshold, Campbell critical speeds) are compared with computations that do
not go through the command's code path (scipy eigensolvers and maximisers on the
assembled matrices, statics by the lever rule, the stored ROSS reference), at what
the README states, and never with a number the command produced before.

Quick settings: grids, scans and run lengths are capped (`QUICK`) so that the whole
file runs in a few minutes; the commands are otherwise run as written (in-process,
with `--out` in a temporary folder). `rotorjax demo` runs in `test_cli.py`, `rotorjax
bench` (at its smoke sizes) in `test_bench.py`, and the commands of `RUN_ELSEWHERE`, as
written, in the files named there (on those files' shared computations)."""

import contextlib
import io
import json
import os
import re
import shlex

import jax

import numpy as np

import pytest

from rotorjax.cli import main

from .helpers import documentation


#: caps on sizes: option -> (index of the value after the option, cap)
QUICK = {"--x": (3, 3), "--y": (3, 3), "--param": (3, 3), "--n-scan": (0, 12), "--n-speeds": (0, 10),
         "--n": (0, 200), "--max-points": (0, 4), "--t-end": (0, 100.0), "--n-save": (0, 400),
         "--starts": (0, 1)}
#: `--set` values capped the same way
QUICK_SETS = {"revolutions": 20, "nu_end": 2.0}
#: options added when absent, per command
QUICK_DEFAULTS = {"critical-speeds": ["--n-scan", "12"], "hopf": ["--n-scan", "12"],
                  "continue": ["--max-points", "4"], "campbell": ["--n-speeds", "10"],
                  "simulate": ["--n-save", "400"]}


def _text():
    """The README and the documentation site's pages (`tests.helpers.DOCS_PAGES`)."""
    return documentation()


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


def _journal_rig():
    import tomllib

    from rotorjax.io import shipped_rotor

    with open(shipped_rotor("journal_rig"), "rb") as f:
        return tomllib.load(f)


def _film_static_check(out, printed, argv):
    """The journal rig is symmetric: each journal carries half the weight (shaft and
    disks, from the file's masses); Ocvirk's load equation, solved here by brentq,
    gives the eccentricity at that load."""
    from scipy.optimize import brentq

    rotor = _journal_rig()
    steel = rotor["material"][0]
    mass = sum(steel["rho"] * np.pi / 4 * e["od"] ** 2 * e["L"] for e in rotor["shaft"])
    mass += sum(d["m"] for d in rotor["disk"])
    b = rotor["bearing"][0]
    w, speed = 9.81 * mass / 2, out["speed"]
    ss = b["viscosity"] * speed * b["diameter"] * b["length"] ** 3 / (8 * b["clearance"] ** 2 * w)
    eps = brentq(lambda e: ss * e * np.sqrt(np.pi ** 2 * (1 - e * e) + 16 * e * e) / (1 - e * e) ** 2 - 1, 1e-9,
                 1 - 1e-12, xtol=1e-15)
    stated_eps, stated_speed = stated(r"sits at eccentricity ([\d.]+) at ([\d.]+) rad/s")
    assert speed == stated_speed
    for row in out["bearings"]:
        assert row["load"] == pytest.approx(w, rel=1e-9)
        assert row["eccentricity"] == pytest.approx(eps, rel=1e-9)
        assert round(row["eccentricity"], 4) == stated_eps


def _film_hopf_check(out):
    """The onset as the README states it, and the equilibrium's largest real part
    changing sign across it (numpy's eigenvalues of the state matrix)."""
    from rotorjax.io import load_rotor
    from rotorjax.io import shipped_rotor

    onset, whirl, ratio = stated(r"loses stability at ([\d.]+) rad/s, whirling forward at ([\d.]+) rad/s "
                                 r"\(ratio ([\d.]+)\)")
    h = out["hopf_points"][0]
    assert len(out["hopf_points"]) == 1 and h["whirl"] == "forward"
    assert (round(h["speed"], 2), round(h["frequency"], 2), round(h["whirl_frequency_ratio"], 3)) == (
        onset, whirl, ratio)
    scene = load_rotor(shipped_rotor("journal_rig"))
    margin = [np.max(np.linalg.eigvals(np.asarray(scene.linear_matrices(f * h["speed"]).state_matrix())).real)
              for f in (0.999, 1.001)]
    assert margin[0] < 0 < margin[1]


#: README command -> a check of its JSON output (the command is run with `--json`)
#: against the numbers the README states for it
def _optimize_check(out):
    before, after, bound = stated(r"over 0..600 rad/s \(from ([\d.]+) to ([\d.]+), both dampers at their "
                                  r"([\d.]+) N s/m")
    assert round(out["objective"]["before"], 3) == before and round(out["objective"]["after"], 3) == after
    assert out["converged"] and all(p["after"] == pytest.approx(bound) for p in out["parameters"].values())


CLAIMS = {
    "rotorjax critical-speeds flexible-abb --range 0.1 25 --exact": _abb_exact_check,
    "rotorjax critical-speeds flexible-abb --range 0.1 25 --modes 20": _abb_modal_check,
    "rotorjax critical-speeds ross-compare --range 10 1000": _ross_critical_check,
    "rotorjax critical-speeds rotorjax/rotors/ross_compare.toml --range 10 1000": _ross_critical_check,
    "rotorjax balance --json": _balance_check,
    "rotorjax hopf journal_rig.toml --range 100 400": _film_hopf_check,
    "rotorjax optimize ross_compare.toml --set bearing0.cxx=500 --set bearing1.cxx=500 --vary bearing0.cxx=100:3000 "
    "--vary bearing1.cxx=100:3000 --objective min-log-dec --range 0 600 --starts 2": _optimize_check,
}


# ---- the linear FE commands: key outputs against independent computations ----
#
# Each check gets the JSON the command wrote under --out, what it printed, and its
# argv (after `quick`: none of these commands has its grid capped except `campbell`,
# whose critical speeds do not depend on the grid). Peaks are compared with a
# fine-grid maximum of the Python API's curve refined by scipy (to 1e-6 relative,
# the located peaks being exact to 1e-10 of the speed); poles of an undamped rotor
# with the synchronous critical speeds (a Hermitian eigenproblem); eigenvalues with
# scipy's on the assembled matrices. A peak's height at a pole of an undamped
# rotor is only as large as the refinement makes it: not compared.

def _system(argv):
    """The command's rotor (a preset or rotor file with its `--set` values), built
    through the Python API."""
    from rotorjax.presets import get

    preset = get(argv[1])
    params = dict(preset.defaults)
    for i, a in enumerate(argv):
        if a == "--set":
            key, _, value = argv[i + 1].partition("=")
            params[key] = float(value)
    return preset.build(params).scene


def _toml(argv):
    import tomllib

    with open(argv[1], "rb") as f:
        return tomllib.load(f)


def _amplitudes(system, unbalances, speeds, probe=None):
    """sqrt(|X|^2 + |Y|^2) at `probe` (all nodes when None), shape (n_speeds,) or (n_speeds, n_nodes)."""
    from rotorjax.flexible import unbalance_response_many

    X, Y = unbalance_response_many(system, unbalances, speeds, probe_nodes=None if probe is None else [probe])
    a = jax.numpy.sqrt(jax.numpy.abs(X) ** 2 + jax.numpy.abs(Y) ** 2)   # traced under jit
    return a if probe is None else a[:, 0]


def _fine_maxima(f, w):
    """The interior local maxima of the scalar function `f` (of an array of speeds)
    on the grid `w`, each refined by scipy's bounded Brent search between the grid
    maximum's neighbours. `[(x, f(x)), ...]`."""
    from scipy.optimize import minimize_scalar

    a = np.asarray(f(w))
    out = []
    for i in np.nonzero((a[1:-1] > a[:-2]) & (a[1:-1] >= a[2:]))[0] + 1:
        r = minimize_scalar(lambda x: -float(f(np.array([x]))[0]), bounds=(w[i - 1], w[i + 1]), method="bounded",
                            options={"xatol": 1e-11 * w[i]})
        out.append((float(r.x), float(-r.fun)))
    return out


def _unbalance_triples(out):
    return [(u["node"], u["magnitude"], u["phase"]) for u in out["unbalances"]]


def _response_reference(system, out):
    """`(amplitudes, probe)`: the amplitude at every node on a grid 4 times finer than
    the command's (whose points it contains), and the node of largest response on
    the command's own grid (the README's, uncapped)."""
    grid = np.linspace(*out["range"], 4 * out["n"] - 3)
    every = np.asarray(jax.jit(lambda w: _amplitudes(system, _unbalance_triples(out), w))(grid))
    return grid, every, int(np.argmax(every[::4].max(axis=0)))


def _damped_peaks_check(system, out):
    """Damped rotor: every peak, its height and the largest amplitude equal the
    maxima of `unbalance_response_many` at the probe on the fine grid, refined by
    scipy, to 1e-6. Returns the node of largest response."""
    grid, every, largest = _response_reference(system, out)
    at_probe = jax.jit(lambda w: _amplitudes(system, _unbalance_triples(out), w, out["probe"]))
    ref = _fine_maxima(lambda w: every[:, out["probe"]] if w is grid else np.asarray(at_probe(w)), grid)
    assert len(out["peaks"]) == len(ref), (out["peaks"], ref)
    np.testing.assert_allclose(out["peaks"], [x for x, _ in ref], rtol=1e-6)
    np.testing.assert_allclose(out["peak_amplitudes"], [y for _, y in ref], rtol=1e-6)
    top = max(ref, key=lambda p: p[1])
    assert out["max_amplitude"] == pytest.approx(top[1], rel=1e-6)
    assert out["speed_at_max"] == pytest.approx(top[0], rel=1e-6)
    return largest


def _printed_peaks_check(out, printed):
    m = re.search(r"peaks at (.*); largest (\S+) m at ([\d.]+) rad/s", printed)
    assert m, printed
    shown = [float(x) for x in re.findall(r"([\d.]+) rad/s \(", m.group(1))]
    assert shown == [round(p, 3) for p in out["peaks"]], (shown, out["peaks"])
    assert float(m.group(3)) == round(out["speed_at_max"], 3)


def _poles(system, lo, hi):
    """The synchronous critical speeds in [lo, hi] (undamped: the response's and the
    synchronous FRF's poles), from the Hermitian eigenproblem, not a scan."""
    from rotorjax.flexible import synchronous_critical_speeds

    s = np.asarray(synchronous_critical_speeds(getattr(system, "rotor", system)))
    return s[(s >= lo) & (s <= hi)]


def _response_ross_compare_check(out, printed, argv):
    mass_g, node = stated(r"--set cyy=100 # its unbalance: ([\d.]+) g m at node (\d+)")
    assert out["unbalances"] == [{"node": node, "magnitude": mass_g * 1e-3, "phase": 0.0}]
    assert out["unbalance_source"] == "the ross-compare preset" and out["warnings"] == []
    assert (out["probe"], out["probe_source"]) == (int(argv[argv.index("--probe") + 1]), "--probe")
    _damped_peaks_check(_system(argv), out)
    _printed_peaks_check(out, printed)


def _response_rotor_file_check(out, printed, argv):
    """The file's [[unbalance]] tables (read here with tomllib), the probe of largest
    response, the peaks."""
    given = [{"node": u["node"], "magnitude": u["magnitude"], "phase": u.get("phase", 0.0)}
             for u in _toml(argv)["unbalance"]]
    assert out["unbalances"] == given and out["unbalance_source"] == "the rotor file"
    assert out["warnings"] == []
    system = _system(argv)
    assert out["probe_source"] == "largest response"
    assert out["probe"] == _damped_peaks_check(system, out)
    _printed_peaks_check(out, printed)


def _response_several_check(out, printed, argv):
    """Undamped `ross-compare`, two unbalances: the peaks are the synchronous critical
    speeds; the deflected shape's semi-axes are the singular values of each node's
    orbit matrix [[Re X, -Im X], [Re Y, -Im Y]]."""
    given = [tuple(float(v) for v in argv[i + 1].split(",")) for i, a in enumerate(argv) if a == "--unbalance"]
    assert _unbalance_triples(out) == given and out["unbalance_source"] == "--unbalance"
    system = _system(argv)
    assert (out["probe"], out["probe_source"]) == (_response_reference(system, out)[2], "largest response")
    np.testing.assert_allclose(out["peaks"], _poles(system, *out["range"]), rtol=1e-8)
    shape = out["deflected_shape"]
    assert shape["speed"] == float(argv[argv.index("--shape-at") + 1])
    from rotorjax.flexible import unbalance_response_many

    X, Y = (np.asarray(a)[0] for a in unbalance_response_many(system, given, [shape["speed"]]))
    axes = [np.linalg.svd([[x.real, -x.imag], [y.real, -y.imag]], compute_uv=False) for x, y in zip(X, Y)]
    np.testing.assert_allclose(shape["major"], [a[0] for a in axes], rtol=1e-9)
    np.testing.assert_allclose(shape["minor"], [a[1] for a in axes], rtol=1e-9, atol=1e-12 * max(shape["major"]))


def _frf_check(out, printed, argv):
    """Undamped `ross-compare`, rotor at the excitation frequency: the peaks are the
    synchronous critical speeds, the first two the README's (91.788 backward, 96.296
    forward)."""
    assert out["speed"] is None and out["warnings"] == []
    np.testing.assert_allclose(out["peaks"], _poles(_system(argv), *map(float, argv[-2 - 2:-2])), rtol=1e-8)
    backward, forward = stated(r"first two critical speeds \(([\d.]+) backward, ([\d.]+) forward rad/s\)")
    assert [round(p, 3) for p in out["peaks"][:2]] == [backward, forward]


def _state_eigenvalues(system, speed, coupling=None):
    """scipy's eigenvalues (Im > 0, sorted by Im) of the first-order form of
    `M q'' + (C + W G) q' + K q = 0` at `speed`, with `coupling = (node, Q)` adding
    kxy = Q, kyx = -Q at a node (API 684 level I)."""
    import scipy.linalg

    lm = system.linear_matrices(speed)
    M, C, K = (np.array(a) for a in (lm.M, lm.C + lm.G, lm.K))
    if coupling is not None:
        node, q = coupling
        K[4 * node, 4 * node + 1] += q
        K[4 * node + 1, 4 * node] -= q
    n = len(M)
    A = np.block([[np.zeros((n, n)), np.eye(n)], [-np.linalg.solve(M, K), -np.linalg.solve(M, C)]])
    lam = scipy.linalg.eigvals(A)
    lam = lam[lam.imag > 0]
    return lam[np.argsort(lam.imag)]


def _ross_tapered():
    path = os.path.join(os.path.dirname(__file__), "validation", "data", "ross_tapered.json")
    with open(path) as f:
        return json.load(f)


def _modes_check(out, printed, argv):
    """ROSS 2.3.0's damped frequencies and log decrements (stored in
    `tests/validation/data/ross_tapered.json`, with the bearing table interpolated)
    at the README's speed, to the tolerances the README states."""
    speed = float(argv[argv.index("--speed") + 1])
    assert (out["speed"], out["speed_source"]) == (speed, "--speed")
    rtol_wd, rtol_ld = stated(r"\(asserted: ([\d.e-]+) and ([\d.e-]+)\) at 100, 400 and 850 rad/s")
    data = _ross_tapered()
    ref = data["ross_interpolating"]
    k = data["speeds"].index(speed)
    got = out["modes"]
    assert [m["mode"] for m in got] == list(range(len(got)))
    np.testing.assert_allclose([m["damped_frequency"] for m in got], ref["wd"][k][:len(got)], rtol=rtol_wd)
    np.testing.assert_allclose([m["log_dec"] for m in got], ref["log_dec"][k][:len(got)], rtol=rtol_ld)


def _static_check(out, printed, argv):
    """Two bearings carry the rotor statically determinately: the reactions follow
    from the masses and their centres (the tapered hollow elements integrated here
    by Gauss quadrature, densities from the materials table) by the lever rule, and
    they sum to the weight, whatever the stiffnesses."""
    from rotorjax.models import MATERIALS

    rotor = _toml(argv)
    x_gauss, w_gauss = np.polynomial.legendre.leggauss(4)
    mass = moment = start = 0.0
    for e in rotor["shaft"]:
        L = e["L"]
        od, bore = np.broadcast_to(e["od"], 2), np.broadcast_to(e.get("id", 0.0), 2)
        s, w = (x_gauss + 1) / 2 * L, w_gauss * L / 2
        area = np.pi / 4 * ((od[0] + (od[1] - od[0]) * s / L) ** 2 - (bore[0] + (bore[1] - bore[0]) * s / L) ** 2)
        rho = MATERIALS[e["material"]].rho
        mass, moment, start = mass + rho * (w @ area), moment + rho * (w @ (area * (start + s))), start + L
    x = np.concatenate([[0.0], np.cumsum([e["L"] for e in rotor["shaft"]])])
    for d in rotor["disk"]:
        mass, moment = mass + d["m"], moment + d["m"] * x[d["node"]]
    g = out["gravity"]
    a, b = (x[bearing["node"]] for bearing in rotor["bearing"])
    right = g * (moment - mass * a) / (b - a)
    assert out["axis"] == "y" and out["weight"][1] == pytest.approx(-g * mass, rel=1e-12)
    np.testing.assert_allclose([r["y"] for r in out["bearing_reactions"]], [g * mass - right, right], rtol=1e-10)


def _campbell_undamped_check(out, printed, argv):
    """Undamped `ross-compare`: the 1x crossings are the synchronous critical speeds,
    the first two the README's."""
    np.testing.assert_allclose(out["critical_speeds"], _poles(_system(argv), 1e-6, out["speeds"][-1]), rtol=1e-8)
    backward, forward = stated(r"first two critical speeds \(([\d.]+) backward, ([\d.]+) forward rad/s\)")
    assert [round(c, 3) for c in out["critical_speeds"][:2]] == [backward, forward]


def _campbell_tapered_check(out, printed, argv):
    """Damped, speed-dependent bearings: each critical speed is a root of
    wd_k(W) = W, the damped frequencies from scipy's eigenvalues (brentq on a bracket
    of 1 % around it)."""
    from scipy.optimize import brentq

    system = _system(argv)
    crit = out["critical_speeds"]
    assert crit, printed
    for c in crit:
        k = int(np.argmin(np.abs(_state_eigenvalues(system, c).imag - c)))
        root = brentq(lambda w: _state_eigenvalues(system, w)[k].imag - w, 0.99 * c, 1.01 * c, xtol=1e-10 * c)
        assert c == pytest.approx(root, rel=1e-8)
    assert printed.endswith(", ".join(f"{c:.3f}" for c in crit))


def _ucs_check(out, printed, argv):
    """Modes numbered from 0, the same in the text and the JSON; at each
    intersection, k is the bearing's not-a-knot cubic spline through its table
    (scipy's) at the speed, and the speed is mode `mode`'s natural frequency at rest
    with every bearing replaced by that k (scipy's eigh; the x/y pair)."""
    import scipy.linalg
    from scipy.interpolate import CubicSpline

    rows = re.findall(r"mode (\d+) meets bearing (\d+) (k\w\w) at ([\d.]+) rad/s \(k = (\S+) N/m\)", printed)
    inter = out["intersections"]
    assert rows and [(int(m), int(b), c, float(s)) for m, b, c, s, _ in rows] == \
        [(i["mode"], i["bearing"], i["coefficient"], round(i["speed"], 4)) for i in inter]
    assert min(i["mode"] for i in inter) == 0
    bearings = _toml(argv)["bearing"]
    system = _system(argv)
    M, _, _, K = (np.array(a) for a in system.rotor.reduced_matrices(0.0))
    for b in bearings:   # the bearings at rest out, the springs in
        n = b["node"]
        K[4 * n, 4 * n] -= b["kxx"][0]
        K[4 * n + 1, 4 * n + 1] -= b["kyy"][0]
    for i in inter:
        b = bearings[i["bearing"]]
        assert i["k"] == pytest.approx(float(CubicSpline(b["speeds"], b[i["coefficient"]])(i["speed"])), rel=1e-9)
        Kk = K.copy()
        for bb in bearings:
            Kk[4 * bb["node"], 4 * bb["node"]] += i["k"]
            Kk[4 * bb["node"] + 1, 4 * bb["node"] + 1] += i["k"]
        w = np.sqrt(scipy.linalg.eigh(Kk, M, eigvals_only=True))
        np.testing.assert_allclose(w[2 * i["mode"]:2 * i["mode"] + 2], i["speed"], rtol=1e-8)


def _level1_check(out, printed, argv):
    """Q at mid-span (between the file's bearings); the log decrement at Q = 0 is
    one of scipy's eigenvalues' (-2 pi Re/Im), and at Q0 that mode's real part is
    zero (scipy's eigenvalues with kxy = Q0, kyx = -Q0 added)."""
    speed = float(argv[argv.index("--speed") + 1])
    assert (out["speed"], out["speed_source"]) == (speed, "--speed") and out["warnings"] == []
    nodes = [b["node"] for b in _toml(argv)["bearing"]]
    assert out["node"] == (nodes[0] + nodes[-1]) // 2
    system = _system(argv)
    lam0 = _state_eigenvalues(system, speed)
    k = int(np.argmin(np.abs(-2 * np.pi * lam0.real / lam0.imag - out["log_dec_0"])))
    assert -2 * np.pi * lam0[k].real / lam0[k].imag == pytest.approx(out["log_dec_0"], rel=1e-8)
    lam = _state_eigenvalues(system, speed, (out["node"], out["q0"]))[k]
    assert abs(lam.real) < 1e-7 * abs(lam.imag), lam
    assert f"threshold Q0 = {out['q0']:.6g} N/m" in printed


#: README command -> a check of (the JSON it wrote under --out, what it printed, its
#: argv), the command run as written; the commands not here: see `UNCOMPARED`
OUTPUTS = {
    "rotorjax response ross-compare --range 10 1200 --probe 2 --set cxx=100 --set cyy=100":
        _response_ross_compare_check,
    "rotorjax response rotorjax/rotors/ross_compare.toml --range 10 1200 --set bearing0.cxx=100 "
    "--set bearing1.cxx=100": _response_rotor_file_check,
    "rotorjax response rotorjax/rotors/tapered_two_material.toml --range 10 1000": _response_rotor_file_check,
    "rotorjax response ross-compare --range 10 1200 --unbalance 2,1e-3,0 --unbalance 4,5e-4,1.0 --shape-at 300":
        _response_several_check,
    "rotorjax frf ross-compare --input 2,x --output 4,y --range 10 1200": _frf_check,
    "rotorjax modes rotorjax/rotors/tapered_two_material.toml --speed 400": _modes_check,
    "rotorjax static rotorjax/rotors/tapered_two_material.toml": _static_check,
    "rotorjax static journal_rig.toml": _film_static_check,
    "rotorjax campbell ross-compare --range 0 1000": _campbell_undamped_check,
    "rotorjax campbell rotorjax/rotors/ross_compare.toml --range 0 1000": _campbell_undamped_check,
    "rotorjax campbell rotorjax/rotors/tapered_two_material.toml --range 0 1000": _campbell_tapered_check,
    "rotorjax ucs rotorjax/rotors/tapered_two_material.toml": _ucs_check,
    "rotorjax level1 rotorjax/rotors/tapered_two_material.toml --speed 800": _level1_check,
}


def commands():
    out = []
    for block in _blocks("bash"):
        for line in block.splitlines():
            line = re.split(r"\s#", line)[0].strip()
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
    assert set(OUTPUTS) <= set(commands()), set(OUTPUTS) - set(commands())
    for c in commands():
        assert "[" not in c, f"README command with optional-part brackets cannot be copied: {c}"


#: documented commands run as written by another test file, on that file's shared computations (no double work):
#: command -> (file, the constant there that holds the command)
RUN_ELSEWHERE = {
    "rotorjax continue elliptic-abb --param eps --set rho2=1.28 --set eps=0.02 --to 0.005 0.1 --switch":
        ("tests/analysis/test_balancer_pitchfork.py", "DOCS_COMMAND"),
    "rotorjax optimize elliptic-abb --set rho1=1.2 --vary delta_n=0.05:1 --vary delta_b=5:400 --range 0.5 6 "
    "--starts 3": ("tests/design/test_stable_range.py", "README_OPTIMIZE"),
    "rotorjax periodic cubic_rig.toml --param speed --range 100 106": ("tests/test_cli_periodic.py", "DOCS_COMMAND"),
    "rotorjax periodic cubic_rig.toml --param speed --range 100 106 --node 1 --param2 cubic_bearing0.k3 --range2 "
    "1e12 6e12": ("tests/test_cli_periodic.py", "JUMP_COMMAND"),
    "rotorjax periodic journal_rig.toml --param speed --range 200 210 --from-hopf --set unbalance0.magnitude=0 "
    "--node 2": ("tests/test_cli_from_hopf.py", "DOCS_COMMAND"),
}


@pytest.mark.parametrize("line", commands())
def test_readme_command(line, tmp_path, capsys):
    if line in RUN_ELSEWHERE:
        import importlib

        path, name = RUN_ELSEWHERE[line]
        module = importlib.import_module(path[:-3].replace("/", "."))
        assert getattr(module, name) == line    # that file runs it (its test of the command reads the constant)
        return
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
    compare = OUTPUTS.get(line)
    if compare is not None:
        written = sorted((tmp_path / "out").glob("*.json"))
        assert len(written) == 1, written
        compare(json.loads(written[0].read_text()), cap.out.strip(), argv)


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
