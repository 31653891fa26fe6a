"""`rotorjax periodic` with its defaults (issue 62, item 4: `--harmonics auto`) against
the former default, eight harmonics everywhere, on two rotors:

- the shipped `cubic_rig.toml` (ROSS's example rotor on isotropic cubic bearings),
  through both folds over 100..106 rad/s, by the CLI: cold (a fresh interpreter with
  an empty compilation cache: import, compile, run; `rotorjax periodic ... --json` as a
  subprocess) and warm
  (`rotorjax.cli.main` a second time in one process, the median of repeats). Its
  orbits are circles: auto takes one harmonic everywhere; the folds of both runs
  are compared.
- the anisotropic variant of `tests/validation/test_periodic_auto_harmonics.py`
  (bearing 0 stiffer in y, a tenth of the cubic stiffness, a quarter of the
  unbalance) over 90..110 rad/s by `periodic_branch`: auto (1e-6) against the most
  harmonics auto used, fixed; first call and warm.

- the jump boundary of `cubic_rig.toml` (issue 62, item 7): the same branch with
  `--param2 cubic_bearing0.k3 --range2 1e12 6e12` (both folds continued in (speed, k3),
  the amplitude's derivative in k3 at every point), cold and warm.

- the stability exponents of one motion of the anisotropic variant at 100 rad/s with
  8, 16 and 32 harmonics: Hill's eigenvalues against the Magnus monodromy that a
  branch uses above `HILL_MAX` unknowns (warm), each margin against the integrated
  monodromy's (`floquet` at rtol 1e-11).

- one harmonic-balance solve of the anisotropic variant at 100 rad/s with 8, 16 and
  32 harmonics: the whole balance against the balance condensed to the cubic
  bearings' node displacements (`rotorjax.analysis._condensed`), warm.

Errors: the folds' difference between the two runs (cubic_rig), each branch's
largest truncation error estimate (`truncation_error`), the fold curves' largest
relative distance from `synchronous_branch`'s folds at three interior points each.

Run: python benchmarks/periodic_defaults.py [--repeats 3] [--smoke]
Writes benchmarks/results/periodic_defaults.json (`--smoke`: cubic_rig over 100..100.5
in process against 2 harmonics, one call per timing, its jump boundary there (no fold:
the derivative only), the variant over 99.5..100 with at most 2 harmonics, the exponents with 2; prints,
writes nothing).
"""

import argparse
import io
import json
import os
import subprocess
import sys
import tempfile
import time
from contextlib import redirect_stderr, redirect_stdout

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.dirname(os.path.abspath(__file__))))   # tests.validation
sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))

from _common import machine, timed_first, today, write_results  # noqa: E402


def cli_argv(lo, hi, harmonics, out):
    argv = ["periodic", "cubic_rig.toml", "--param", "speed", "--range", str(lo), str(hi), "--json", "--out", out]
    return argv + ([] if harmonics == "auto" else ["--harmonics", str(harmonics)])


def cli_in_process(argv):
    from rotorjax.cli import main

    stdout = io.StringIO()
    with redirect_stdout(stdout), redirect_stderr(io.StringIO()):
        rc = main(argv)
    assert rc == 0, rc
    return json.loads(stdout.getvalue())


def cli_cold(argv):
    """A fresh interpreter with an empty compilation cache of its own (the CLI's, in the user's cache folder,
    would otherwise hold an earlier run's programs)."""
    cli = "import sys; from rotorjax.cli import main; sys.exit(main(sys.argv[1:]))"
    with tempfile.TemporaryDirectory() as cache:
        t0 = time.perf_counter()
        run = subprocess.run([sys.executable, "-c", cli] + argv, capture_output=True, text=True,
                             env=dict(os.environ, ROTORJAX_CACHE_DIR=cache))
        seconds = time.perf_counter() - t0
    assert run.returncode == 0, run.stderr[-2000:]
    return seconds, json.loads(run.stdout)


def folds(d):
    return sorted(e["speed"] for e in d["bifurcations"] if e["kind"] == "fold")


def cubic_rig(lo, hi, repeats, cold, former=8):
    out = {}
    with tempfile.TemporaryDirectory() as tmp:
        for h in ("auto", former):
            argv = cli_argv(lo, hi, h, tmp)
            row = {}
            if cold:
                row["cold_s"], d = cli_cold(argv)
            warm, first, d = timed_first(lambda: cli_in_process(argv), repeats)
            b = d["branches"][0]
            row.update(warm_s=warm, first_in_process_s=first, points=b["n_points"], folds=folds(d),
                       harmonics=sorted(set(b["harmonics"])), truncation_max=max(b["truncation"]))
            out[str(h)] = row
    ours, theirs = out["auto"]["folds"], out[str(former)]["folds"]
    out["folds_difference"] = (float(np.max(np.abs(np.subtract(ours, theirs)))) if len(ours) == len(theirs) > 0
                               else None)
    return out


#: the jump boundary (issue 62, item 7): the folds in (speed, this stiffness), the amplitude's derivative in it
K3 = "cubic_bearing0.k3"


def jump_boundary(lo, hi, range2, repeats, cold, checked=3):
    """`periodic ... --param2 cubic_bearing0.k3`: cold and warm as `cubic_rig`, and the
    error of the fold curves: at `checked` interior points of each, the relative
    distance of its speed to the nearest fold of `synchronous_branch` (the rotating
    frame's rest points, a different problem) solved at that point's k3."""
    from rotorjax import presets
    from rotorjax.analysis import synchronous_branch

    with tempfile.TemporaryDirectory() as tmp:
        argv = cli_argv(lo, hi, "auto", tmp) + ["--node", "1", "--param2", K3, "--range2", *map(str, range2)]
        row = {}
        if cold:
            row["cold_s"], d = cli_cold(argv)
        warm, first, d = timed_first(lambda: cli_in_process(argv), repeats)
    preset = presets.get("cubic_rig.toml")
    errors = []
    for c in d["fold_curves"]:
        speed, k3 = np.array(c["speed"]), np.array(c[K3])
        for i in np.linspace(0, len(k3) - 1, checked + 2).astype(int)[1:-1]:
            scene = preset.build(dict(preset.params(), **{K3: float(k3[i])})).scene
            ref = [e.p for e in synchronous_branch(scene, (lo, hi)).events if e.kind == "fold"]
            errors.append(min(abs(r / speed[i] - 1) for r in ref))
    row.update(warm_s=warm, first_in_process_s=first, branch_points=d["branches"][0]["n_points"],
               fold_curves=[{"from": c["from"]["speed"], "points": c["n_points"], "stop": c["stop"],
                             "speed": [min(c["speed"]), max(c["speed"])], K3: [min(c[K3]), max(c[K3])],
                             "residual_max": c["residual_max"]} for c in d["fold_curves"]],
               fold_error_max=max(errors) if errors else None, checked_points=len(errors),
               d_amplitude_d_k3=[min(d["branches"][0]["d_amplitude_d_param2"]),
                                 max(d["branches"][0]["d_amplitude_d_param2"])])
    return row


def anisotropic(lo, hi, repeats, max_harmonics=32):
    from rotorjax.analysis import periodic_branch

    scene_at, n = anisotropic_scene()

    def branch(h):
        return periodic_branch(scene_at, lo, np.zeros(n), (lo, hi), h, name="speed",
                               max_harmonics=max_harmonics)

    out = {}
    warm, first, (br, _) = timed_first(lambda: branch("auto"), repeats)
    H = int(np.max(br.harmonics))
    out["auto"] = {"warm_s": warm, "first_s": first, "points": int(br.p.size),
                   "harmonics": {str(k): int(np.sum(br.harmonics == k)) for k in sorted(set(br.harmonics.tolist()))},
                   "truncation_max": float(np.max(br.truncation))}
    warm, first, (br, _) = timed_first(lambda: branch(H), repeats)
    out[f"fixed_{H}"] = {"warm_s": warm, "first_s": first, "points": int(br.p.size),
                         "truncation_max": float(np.max(br.truncation))}
    out["fixed_harmonics"] = H
    return out


def anisotropic_scene():
    """The anisotropic variant of `tests/validation/test_periodic_auto_harmonics.py`:
    `speed -> scene`."""
    import equinox as eqx

    from rotorjax import presets
    from tests.validation.test_periodic_auto_harmonics import SHIPPED, variant

    with tempfile.TemporaryDirectory() as tmp:
        path = os.path.join(tmp, "anisotropic_cubic.toml")
        with open(SHIPPED) as f, open(path, "w") as g:
            g.write(variant(f.read()))
        preset = presets.get(path)
        scene = preset.build(preset.params()).scene

    def scene_at(w):
        return eqx.tree_at(lambda s: s.speed.constant, scene, w)

    return scene_at, scene.state_size


def exponents(speed, harmonics, repeats):
    """A branch point's stability exponents on the anisotropic variant at `speed`:
    Hill's (the eigenvalues of the balance's Jacobian, `(2H + 1) n` of them) against
    the Magnus monodromy of the reconstructed orbit (`magnus_exponents`, what a
    branch uses above `HILL_MAX` unknowns), warm, at each of `harmonics`; each
    margin's distance from the integrated monodromy's (`floquet`, rtol 1e-11)."""
    import jax

    from rotorjax.analysis import floquet
    from rotorjax.analysis._harmonic_balance import (_physical_exponents, balance_residual, harmonic_balance,
                                                     magnus_exponents)

    scene_at, n = anisotropic_scene()
    sc, T = scene_at(speed), 2 * np.pi / speed
    out, sol = {}, np.zeros(n)
    for H in harmonics:
        for h in [k for k in (1, 2, 4, 8, 16, 32) if k < H] + [H]:    # each from the one before
            sol = harmonic_balance(sc, T, sol, h, stability=False)
        assert int(sol.code) == 0, H
        Y = sol.coefficients
        hill = jax.jit(lambda Y: _physical_exponents(
            jax.jacfwd(lambda x: -balance_residual(sc, x.reshape(Y.shape), T).ravel())(Y.ravel()), n, speed))
        magnus = jax.jit(lambda Y: magnus_exponents(sc, Y, T))
        t_hill, _, e_hill = timed_first(lambda: hill(Y), repeats)
        t_magnus, _, e_magnus = timed_first(lambda: magnus(Y), repeats)
        ref = float(floquet(sc, sol.initial_state(), T, 0.0, rtol=1e-11, atol=1e-13).margin)
        out[str(H)] = {"unknowns": int(Y.size), "hill_s": t_hill, "magnus_s": t_magnus, "ratio": t_hill / t_magnus,
                       "floquet_margin": ref,
                       "hill_margin_error": abs(float(np.max(np.real(e_hill))) - ref) / abs(ref),
                       "magnus_margin_error": abs(float(np.max(np.real(e_magnus))) - ref) / abs(ref),
                       "time_residual": float(sol.time_residual)}
    return out


def condensed(speed, harmonics, repeats):
    """One harmonic-balance solve of the anisotropic variant at `speed` with each of
    `harmonics`, from the motion with the next fewer (warm): the whole balance
    (`(2H + 1) n` unknowns) against the balance condensed to the cubic bearings' node
    displacements (`(2H + 1) m`, what `harmonic_balance` and `periodic_branch` run on
    such a rotor), and their coefficients' largest difference."""
    import jax.numpy as jnp

    from rotorjax.analysis._harmonic_balance import _guess_coefficients, _solve, harmonic_balance

    scene_at, n = anisotropic_scene()
    sc, T = scene_at(speed), 2 * np.pi / speed
    m = int(sc.local_forces().S.shape[0])
    out, sol = {}, harmonic_balance(sc, T, np.zeros(n), 4, stability=False)
    for H in harmonics:
        Y0 = _guess_coefficients(sol, H, n)

        def solve(condense):
            r = _solve(sc, Y0, T, jnp.asarray(0.0), None, 1e-10, 30, None, condense)
            r.coefficients.block_until_ready()
            return r

        t_whole, first_whole, whole = timed_first(lambda: solve(False), repeats)
        t_cond, first_cond, sol = timed_first(lambda: solve(True), repeats)
        assert int(sol.code) == int(whole.code) == 0, H
        Y, Yw = np.asarray(sol.coefficients), np.asarray(whole.coefficients)
        out[str(H)] = {"unknowns_whole": (2 * H + 1) * n, "unknowns_condensed": (2 * H + 1) * m,
                       "whole_s": t_whole, "condensed_s": t_cond, "ratio": t_whole / t_cond,
                       "whole_first_s": first_whole, "condensed_first_s": first_cond,
                       "iterations": [int(whole.iterations), int(sol.iterations)],
                       "difference": float(np.max(np.abs(Y - Yw)) / np.max(np.abs(Yw))),
                       "time_residual": float(sol.time_residual)}
    return out


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--repeats", type=int, default=3)
    ap.add_argument("--smoke", action="store_true")
    args = ap.parse_args()
    if args.smoke:
        res = {"cubic_rig": cubic_rig(100.0, 100.5, 0, cold=False, former=2),
               "jump_boundary": jump_boundary(100.0, 100.5, (2.9e12, 3.1e12), 0, cold=False),
               "anisotropic": anisotropic(99.5, 100.0, 0, max_harmonics=2),
               "exponents": exponents(100.0, (2,), 0),
               "condensed": condensed(100.0, (2,), 0)}
        print(json.dumps(res, indent=1))
        print("smoke run: nothing written")
        return
    res = {"benchmark": "periodic_defaults", "machine": machine(), "date": today(),
           "cubic_rig": cubic_rig(100.0, 106.0, args.repeats, cold=True),
           "jump_boundary": jump_boundary(100.0, 106.0, (1e12, 6e12), args.repeats, cold=True),
           "anisotropic": anisotropic(90.0, 110.0, args.repeats),
           "exponents": exponents(100.0, (8, 16, 32), args.repeats),
           "condensed": condensed(100.0, (8, 16, 32), args.repeats)}
    c, j = res["cubic_rig"], res["jump_boundary"]
    res["headline"] = {"cubic_rig_cold_s": {"auto": c["auto"]["cold_s"], "8": c["8"]["cold_s"]},
                       "cubic_rig_warm_s": {"auto": c["auto"]["warm_s"], "8": c["8"]["warm_s"]},
                       "cold_ratio": c["8"]["cold_s"] / c["auto"]["cold_s"],
                       "warm_ratio": c["8"]["warm_s"] / c["auto"]["warm_s"],
                       "jump_boundary": {"cold_s": j["cold_s"], "warm_s": j["warm_s"],
                                         "fold_error_max": j["fold_error_max"]},
                       "exponents_hill_over_magnus": {H: e["ratio"] for H, e in res["exponents"].items()},
                       "whole_over_condensed": {H: e["ratio"] for H, e in res["condensed"].items()}}
    print(json.dumps(res["headline"], indent=1))
    write_results("periodic_defaults", res)


if __name__ == "__main__":
    main()
