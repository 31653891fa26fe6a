"""Every command meets bad input with exit 2 and one line naming the culprit
(option, `--set` key, file, column or row), never a traceback; numerical failures
exit 3; an unexpected internal error is one line with a `--debug` hint.

One table: (argv, exit code, a regex the error line must match). Files are made in
a temporary folder; `{d}` in an argument is that folder."""

import json
import os
import re
import shutil

import pytest

import rotorjax
from rotorjax.cli import main
from rotorjax.identify import BALANCING_RUNS
from rotorjax.identify._datasets import dataset_path

#: the shipped rotor files
ROTORS = os.path.join(os.path.dirname(rotorjax.__file__), "rotors")
#: rotors saved by ROSS (tests/io/data/ross)
ROSS_SAVED = os.path.join(os.path.dirname(os.path.abspath(__file__)), "io", "data", "ross")

S, A, R, F, C, B = ("simulate", "elliptic-abb"), ("anisotropic-abb",), ("ross-compare",), ("flexible-abb",), \
    ("cantilever-limiters",), ("balancing-machine",)
FR, FU = ("flexible_rig.toml",), ("--fit-unbalance", "2,4")
#: the periodic branch of the shipped cubic rig, and its cubic stiffness (`--param2`)
P, K3 = ("cubic_rig.toml", "--param", "speed", "--range", "100", "106"), "cubic_bearing0.k3"

CASES = [
    # --- simulate: presets and --set ---
    (["simulate", "no-such-rotor"], 2, r"unknown preset 'no-such-rotor'"),
    ([*S, "--set", "zeta=1"], 2, r"unknown parameter 'zeta'"),
    ([*S, "--set", "chi"], 2, r"--set expects KEY=VALUE, got 'chi'"),
    ([*S, "--set", "=1"], 2, r"--set '=1': empty KEY"),
    ([*S, "--set", "chi=abc"], 2, r"--set chi=abc: must be a number"),
    ([*S, "--set", "chi=nan"], 2, r"--set chi=nan: must be finite"),
    ([*S, "--set", "chi=inf"], 2, r"--set chi=inf: must be finite"),
    ([*S, "--set", "chi=-1"], 2, r"--set chi=-1: must be > 0 \(ball mass / disk mass"),
    ([*S, "--set", "chi=0"], 2, r"--set chi=0: must be > 0"),
    ([*S, "--set", "rho1=-1"], 2, r"--set rho1=-1: must be > 0"),
    ([*S, "--set", "delta_n=-1"], 2, r"--set delta_n=-1: must be >= 0"),
    ([*S, "--set", "n_balls=1.5"], 2, r"--set n_balls=1.5: must be an integer in \[0,32\]"),
    ([*S, "--set", "n_balls=-1"], 2, r"--set n_balls=-1"),
    ([*S, "--set", "nu=0"], 2, r"--set nu=0: must be > 0"),
    ([*S, "--set", "nu_dot=-0.1"], 2, r"nu_end .* must be beyond nu0"),
    (["simulate", *A, "--set", "eps=0"], 2, r"--set eps=0: must be in \(0,1\)"),
    (["simulate", *A, "--set", "n_eta=-1"], 2, r"--set n_eta=-1: must be > 0"),
    (["simulate", *A, "--set", "sigma=0.4"], 2, r"sigma must be 1/N"),
    (["simulate", *A, "--set", "eps=0.5", "--set", "c=1"], 2, r"eps=0.5, c=1.0, K=1.0 leave no rotor mass"),
    (["simulate", *C, "--set", "revolutions=0"], 2, r"--set revolutions=0: must be an integer in \[1,1000000\]"),
    (["simulate", *C, "--set", "chi=0"], 2, r"--set chi=0: must be > 0 \(limiter clearance"),
    (["simulate", *C, "--set", "events=2"], 2, r"--set events=2: must be one of 0, 1"),
    (["simulate", *C, "--set", "n_modes=-1"], 2, r"--set n_modes=-1"),
    (["simulate", *C, "--set", "smoothing=0"], 2, r"--set smoothing=0"),
    (["simulate", *R], 2, r"`simulate` does not apply to 'ross-compare'"),
    (["simulate", *B], 2, r"`simulate` does not apply to 'balancing-machine'.*use `balance`, `identify`"),
    # --modes: a rotor file's full shaft only, 1..its coordinates
    (["simulate", *A, "--modes", "3"], 2, r"--modes: modes = 3: only a finite-element rotor with its full shaft"),
    (["simulate", "{rotors}/ross_compare.toml", "--speed", "50", "--modes", "29"], 2,
     r"--modes: modes = 29: the shaft has 28 coordinates \(modes must be 1\.\.28"),
    (["simulate", "{rotors}/ross_compare.toml", "--speed", "50", "--modes", "0"], 2,
     r"argument --modes: must be 'auto', 'all' or an integer >= 1, got '0'"),
    (["simulate", "{rotors}/ross_compare.toml", "--speed", "50", "--modes", "some"], 2,
     r"argument --modes: expected 'auto', 'all' or a number of modes, got 'some'"),
    # --- bench ---
    (["bench", "--device", "tpu"], 2, r"argument --device: invalid choice: 'tpu'"),
    (["bench", "--device", "gpu"], 2, r"--device gpu: JAX sees no gpu device here \(it sees: cpu\)"),
    (["bench", "--ross-python", "{d}/no-python"], 2, r"--ross-python .*no-python: no executable file there"),
    (["bench", "--ross-python", "/bin/sh"], 2, r"--ross-python /bin/sh: that interpreter cannot `import ross`"),
    (["bench", "--quick", "--out", "{d}/twotrial.csv"], 2, r"--out .*twotrial.csv: exists and is not a folder"),
    (["bench", "--quick", "fast"], 2, r"unrecognized arguments: fast"),
    (["bench", "--repeats", "3"], 2, r"unrecognized arguments: --repeats 3"),
    # --- simulate: options ---
    ([*S, "--t-end", "-3"], 2, r"argument --t-end: must be > 0"),
    ([*S, "--t-end", "nan"], 2, r"argument --t-end: must be finite"),
    ([*S, "--t-end", "abc"], 2, r"argument --t-end: expected a number"),
    ([*S, "--n-save", "0"], 2, r"argument --n-save: must be an integer >= 2"),
    ([*S, "--n-save", "1.5"], 2, r"argument --n-save: expected an integer"),
    ([*S, "--rtol", "0"], 2, r"argument --rtol: must be in \(0, 1\)"),
    ([*S, "--rtol", "2"], 2, r"argument --rtol"),
    ([*S, "--atol", "-1"], 2, r"argument --atol"),
    ([*S, "--max-steps", "0"], 2, r"argument --max-steps: must be an integer >= 1"),
    ([*S, "--solver", "rk99"], 2, r"argument --solver: invalid choice: 'rk99'"),
    ([*S, "--out", "{d}/afile"], 2, r"--out .*afile: exists and is not a folder"),
    # --- simulate --speed, rotor files ---
    ([*S, "--speed", "nan"], 2, r"argument --speed: must be finite"),
    ([*S, "--speed", "abc"], 2, r"argument --speed: expected a number"),
    ([*S, "--speed", "-1"], 2, r"--speed -1: must be > 0 \(speed / Omega"),
    (["simulate", *A, "--speed", "0"], 2, r"--speed 0: must be > 0"),
    (["simulate", *C, "--speed", "inf"], 2, r"argument --speed: must be finite"),
    (["simulate", *R, "--speed", "10"], 2, r"`simulate` does not apply to 'ross-compare'"),
    (["simulate", "{d}/nosuch.toml", "--speed", "10"], 2, r"nosuch\.toml"),
    (["simulate", "{rotors}/ross_compare.toml"], 2, r"no default run length at speed = 0; give --speed W"),
    (["simulate", "{rotors}/ross_compare.toml", "--speed", "10", "--set", "bearing0.kxx=-1"], 2,
     r"--set bearing0\.kxx=-1: must be >= 0"),
    (["simulate", "{rotors}/ross_compare.toml", "--speed", "10", "--set", "bearing9.kxx=1"], 2,
     r"unknown parameter 'bearing9\.kxx'"),
    (["hopf", "{rotors}/ross_compare.toml"], 2, r"`hopf` does not apply to .*ross_compare\.toml"),
    # the damping and probe tables: their values are --set keys, checked as the file's
    (["modes", "{d}/seal.toml", "--set", "seal0.mxx=-1"], 2,
     r"--set seal0.mxx=-1: must be >= 0 \(seal\[0\] at node 2: mass coefficient xx"),
    (["modes", "{d}/seal.toml", "--set", "seal0.kxy=1"], 2, r"--set unknown parameter 'seal0.kxy'.*seal0.kxx"),
    (["modes", "{d}/damped.toml", "--set", "disk_damping0.translational=-1"], 2,
     r"--set disk_damping0\.translational=-1: must be >= 0 \(disk_damping\[0\] at node 4"),
    (["modes", "{d}/damped.toml", "--set", "external_damping.coefficient=-2"], 2,
     r"--set external_damping\.coefficient=-2: must be >= 0 \(external_damping: viscous damping"),
    (["modes", "{rotors}/ross_compare.toml", "--set", "external_damping.coefficient=1"], 2,
     r"unknown parameter 'external_damping\.coefficient'"),
    (["modes", "{d}/probe9.toml"], 2, r"probe9\.toml: probe\[0\]\.node = 9: the shaft has nodes 0\.\.6"),
    # --- steady ---
    (["steady", "elliptic-abb"], 2, r"the following arguments are required: --speed"),
    (["steady", "elliptic-abb", "--speed", "-1"], 2, r"--speed -1: must be > 0"),
    (["steady", "elliptic-abb", "--speed", "nan"], 2, r"argument --speed: must be finite"),
    (["steady", "elliptic-abb", "--speed", "abc"], 2, r"argument --speed: expected a number"),
    (["steady", "elliptic-abb", "--speed", "1", "--n-angles", "0"], 2, r"argument --n-angles"),
    (["steady", *R, "--speed", "1"], 2, r"`steady` does not apply to 'ross-compare'"),
    (["steady", *A, "--speed", "3"], 2, r"Floquet"),
    (["steady", *F, "--speed", "1.2"], 2, r"--set n_balls=0: .*need balls"),
    (["steady", *F, "--speed", "1.2", "--set", "ball_mass=-1"], 2, r"--set ball_mass=-1: must be > 0"),
    # --- critical-speeds ---
    (["critical-speeds", *A, "--range", "0", "0"], 2, r"--range 0 0: LO must be > 0"),
    (["critical-speeds", *A, "--range", "5", "4"], 2, r"--range 5 4: need LO < HI"),
    (["critical-speeds", *A, "--range", "nan", "4"], 2, r"argument --range: must be finite"),
    (["critical-speeds", *R, "--range", "-1", "4"], 2, r"--range -1 4: LO must be >= 0"),
    (["critical-speeds", *R, "--range", "1000", "10"], 2, r"--range 1000 10: need LO < HI"),
    (["critical-speeds", *R, "--range", "0", "0"], 2, r"--range 0 0: need LO < HI"),
    (["critical-speeds", *B, "--range", "10", "400"], 2, r"`critical-speeds` does not apply to 'balancing-machine'"),
    (["critical-speeds", *A, "--range", "1", "4", "--n-scan", "1"], 2, r"argument --n-scan"),
    (["critical-speeds", *R, "--range", "1", "4", "--modes", "0"], 2, r"argument --modes"),
    (["critical-speeds", *R, "--range", "1", "4", "--modes", "500"], 2, r"--modes 500: the rotor has 56 modes"),
    (["critical-speeds", *A, "--range", "1", "4", "--exact"], 2, r"--exact"),
    (["critical-speeds", *A], 2, r"required: --range"),
    (["critical-speeds", *R, "--range", "1", "4", "--set", "disk1_node=9"], 2, r"disk1_node=9: the shaft has nodes 0..6"),
    (["critical-speeds", *R, "--range", "1", "4", "--set", "timoshenko=2"], 2, r"--set timoshenko=2"),
    # --- stability-map ---
    (["stability-map", *A, "--x", "zz", "0", "1", "3", "--y", "mu_w", "0.2", "0.6", "2"], 2,
     r"--x zz 0 1 3: unknown parameter 'zz'"),
    (["stability-map", *A, "--x", "sigma", "0.2", "0.5", "3", "--y", "n", "1", "2", "2"], 2,
     r"--x sigma .*changes the scene's structure"),
    (["stability-map", *A, "--x", "n", "2", "1", "3", "--y", "mu_w", "0.2", "0.6", "2"], 2, r"--x n 2 1 3: need LO < HI"),
    (["stability-map", *A, "--x", "n", "1", "2", "1", "--y", "mu_w", "0.2", "0.6", "2"], 2,
     r"--x n 1 2 1: the number of points must be >= 2"),
    (["stability-map", *A, "--x", "n", "1", "2", "abc", "--y", "mu_w", "0.2", "0.6", "2"], 2,
     r"--x n 1 2 abc: the number of points must be an integer"),
    (["stability-map", *A, "--x", "n", "0", "2", "3", "--y", "mu_w", "0.2", "0.6", "2"], 2, r"--x n 0 2 3: LO n=0"),
    (["stability-map", *A, "--x", "n", "1", "2", "3", "--y", "n", "1", "2", "3"], 2, r"need different parameters"),
    (["stability-map", *A, "--x", "n", "1", "2", "3", "--y", "mu_w", "nan", "1", "3"], 2, r"--y mu_w nan 1 3: LO"),
    (["stability-map", *A, "--x", "n", "1", "2", "3", "--y", "mu_w", "0.2", "1", "3", "--chunk", "0"], 2,
     r"argument --chunk"),
    (["stability-map", *R, "--x", "kxx", "1", "2", "3", "--y", "kyy", "1", "2", "3"], 2,
     r"`stability-map` does not apply to 'ross-compare'"),
    # --- campbell ---
    (["campbell", *R, "--range", "-1", "10"], 2, r"--range -1 10: LO must be >= 0"),
    (["campbell", *R, "--range", "10", "10"], 2, r"--range 10 10: need LO < HI"),
    (["campbell", *R, "--range", "0", "10", "--n-speeds", "1"], 2, r"argument --n-speeds"),
    (["campbell", *R, "--range", "0", "10", "--modes", "0"], 2, r"argument --modes"),
    (["campbell", *R, "--range", "0", "10", "--modes", "100"], 2, r"--modes 100: the rotor has 56 modes"),
    (["campbell", *R, "--range", "0", "10", "--reduce", "0"], 2, r"--reduce 0: n_modes \(reduction\)"),
    (["campbell", *R, "--range", "0", "10", "--reduce", "1000"], 2, r"--reduce 1000"),
    (["campbell", "elliptic-abb", "--range", "0", "10"], 2, r"`campbell` does not apply to 'elliptic-abb'"),
    (["campbell", *R, "--range", "0", "1000", "--set", "n_elements=0"], 2, r"--set n_elements=0"),
    (["campbell", *R, "--range", "0", "1000", "--set", "shaft_diameter=0"], 2, r"--set shaft_diameter=0"),
    (["campbell", *R, "--range", "0", "1000", "--set", "E=-1"], 2, r"--set E=-1"),
    # --- static ---
    (["static", *R, "--axis", "z"], 2, r"argument --axis: invalid choice: 'z'"),
    (["static", *R, "--gravity", "nan"], 2, r"argument --gravity: must be finite"),
    (["static", *R, "--gravity", "abc"], 2, r"argument --gravity: expected a number"),
    (["static", "elliptic-abb"], 2, r"`static` does not apply to 'elliptic-abb'"),
    (["static", "flexible-abb"], 2, r"`static` does not apply to 'flexible-abb'"),
    (["static", *R, "--set", "kxx=-1"], 2, r"--set kxx=-1: must be >= 0"),
    (["static", *R, "--set", "kxx=0", "--set", "kyy=0"], 3,
     r"static: the stiffness matrix is singular \(the rotor is not supported\)"),
    (["static", "{rotors}/ross_compare.toml", "--set", "bearing0.kyy=0", "--set", "bearing1.kyy=0"], 3,
     r"static: the stiffness matrix is singular \(the rotor is not supported\)"),
    # --- modes ---
    (["modes", *R, "--speed", "nan"], 2, r"argument --speed: must be finite"),
    (["modes", *R, "--speed", "-1"], 2, r"argument --speed: must be >= 0"),
    (["modes", *R, "--speed", "abc"], 2, r"argument --speed: expected a number"),
    (["modes", *R, "--n-modes", "0"], 2, r"argument --n-modes: must be an integer >= 1"),
    (["modes", *R, "--n-modes", "1.5"], 2, r"argument --n-modes: expected an integer"),
    (["modes", *R, "--n-modes", "100"], 2, r"--n-modes 100: the rotor has 28 modes"),
    (["modes", "elliptic-abb", "--speed", "1"], 2, r"`modes` does not apply to 'elliptic-abb'"),
    (["modes", "{rotors}/ross_compare.toml", "--set", "bearing0.kxx=-1"], 2, r"--set bearing0\.kxx=-1: must be >= 0"),
    # --- response ---
    (["response", *R, "--range", "0", "100"], 2, r"--range 0 100: LO must be > 0"),
    (["response", *R, "--range", "10", "100", "--node", "9"], 2, r"--node 9: the rotor has nodes 0..6"),
    (["response", *R, "--range", "10", "100", "--probe", "-1"], 2, r"argument --probe"),
    (["response", *R, "--range", "10", "100", "--unbalance", "0"], 2, r"argument --unbalance: must be > 0"),
    (["response", *R, "--range", "10", "100", "--n", "1"], 2, r"argument --n"),
    (["response", *R, "--range", "10", "100", "--phase", "inf"], 2, r"argument --phase: must be finite"),
    (["response", *R, "--range", "10", "100", "--unbalance", "2,1e-3"], 2,
     r"argument --unbalance: expected NODE,MAG,PHASE"),
    (["response", *R, "--range", "10", "100", "--unbalance", "a,1e-3,0"], 2,
     r"argument --unbalance: expected NODE,MAG"),
    (["response", *R, "--range", "10", "100", "--unbalance", "2,0,0"], 2, r"argument --unbalance: MAG must be"),
    (["response", *R, "--range", "10", "100", "--unbalance", "2,1e-3,nan"], 2,
     r"argument --unbalance: PHASE must be finite"),
    (["response", *R, "--range", "10", "100", "--unbalance=-1,1e-3,0"], 2, r"argument --unbalance: NODE must be >= 0"),
    (["response", *R, "--range", "10", "100", "--unbalance", "9,1e-3,0"], 2,
     r"--unbalance 9,0.001,0: the rotor has nodes 0..6"),
    (["response", *R, "--range", "10", "100", "--unbalance", "1e-3", "--unbalance", "2,1e-3,0"], 2,
     r"--unbalance: give one magnitude .* not both"),
    (["response", *R, "--range", "10", "100", "--unbalance", "1e-3", "--unbalance", "2e-3"], 2,
     r"--unbalance: a bare magnitude may be given once"),
    (["response", *R, "--range", "10", "100", "--shape-at", "0"], 2, r"argument --shape-at: must be > 0"),
    (["response", *R, "--range", "10", "100", "--shape-at", "nan"], 2, r"argument --shape-at: must be finite"),
    # --- ucs ---
    (["ucs", *R, "--range", "0", "1e6"], 2, r"--range 0 1e\+06: KLO must be > 0"),
    (["ucs", *R, "--range", "-1", "1e6"], 2, r"--range -1 1e\+06: KLO must be > 0"),
    (["ucs", *R, "--range", "1e7", "1e6"], 2, r"--range 1e\+07 1e\+06: need KLO < KHI"),
    (["ucs", *R, "--range", "1e6", "inf"], 2, r"argument --range: must be finite"),
    (["ucs", *R, "--n", "1"], 2, r"argument --n: must be an integer >= 2"),
    (["ucs", *R, "--n-modes", "0"], 2, r"argument --n-modes"),
    (["ucs", *R, "--n-modes", "100"], 2, r"--n-modes 100: the rotor has 14 forward modes"),
    (["ucs", "elliptic-abb"], 2, r"`ucs` does not apply to 'elliptic-abb'"),
    # --- frf ---
    (["frf", *R, "--input", "99,x", "--output", "2,x", "--range", "10", "100"], 2,
     r"--input 99,x: the rotor has nodes 0..6"),
    (["frf", *R, "--input", "2,x", "--output", "7,y", "--range", "10", "100"], 2,
     r"--output 7,y: the rotor has nodes 0..6"),
    (["frf", *R, "--input", "2,z", "--output", "2,x", "--range", "10", "100"], 2,
     r"argument --input: DIR must be x or y, got '2,z'"),
    (["frf", *R, "--input", "a,b", "--output", "2,x", "--range", "10", "100"], 2,
     r"argument --input: expected NODE,DIR with an integer NODE"),
    (["frf", *R, "--input", "2", "--output", "2,x", "--range", "10", "100"], 2, r"argument --input: expected NODE,DIR"),
    (["frf", *R, "--input", "2,x", "--output=-1,x", "--range", "10", "100"], 2,
     r"argument --output: NODE must be >= 0"),
    (["frf", *R, "--input", "2,x", "--output", "2,x", "--range", "10", "5"], 2, r"--range 10 5: need LO < HI"),
    (["frf", *R, "--input", "2,x", "--output", "2,x", "--range", "-1", "5"], 2, r"--range -1 5: LO must be >= 0"),
    (["frf", *R, "--input", "2,x", "--output", "2,x", "--range", "10", "100", "--kind", "foo"], 2,
     r"argument --kind: invalid choice: 'foo'"),
    (["frf", *R, "--input", "2,x", "--output", "2,x", "--range", "10", "100", "--speed", "-5"], 2,
     r"argument --speed: must be >= 0"),
    (["frf", *R, "--input", "2,x", "--output", "2,x", "--range", "10", "100", "--n", "1"], 2, r"argument --n"),
    (["frf", *R, "--output", "2,x", "--range", "10", "100"], 2, r"the following arguments are required: --input"),
    (["frf", "elliptic-abb", "--input", "2,x", "--output", "2,x", "--range", "10", "100"], 2,
     r"`frf` does not apply to 'elliptic-abb'"),
    # --- level1 ---
    (["level1", *R, "--speed", "nan"], 2, r"argument --speed: must be finite"),
    (["level1", *R, "--speed", "-1"], 2, r"argument --speed: must be >= 0"),
    (["level1", *R], 2, r"level1: give --speed .*ross-compare has no operating speed"),
    (["level1", *R, "--speed", "500", "--node", "9"], 2, r"--node 9: the rotor has nodes 0..6"),
    (["level1", *R, "--speed", "500", "--q-max", "0"], 2, r"argument --q-max: must be > 0"),
    (["level1", *R, "--speed", "500", "--n", "1"], 2, r"argument --n: must be an integer >= 2"),
    (["level1", *R, "--speed", "500"], 3, r"no threshold Q0 found: the log decrement at Q = 0 is .* not positive"),
    (["level1", *R, "--speed", "500", "--set", "cxx=1500", "--set", "cyy=1500", "--q-max", "1e3", "--n", "3"], 3,
     r"stays positive up to --q-max 1000 N/m \(raise --q-max\)"),
    (["level1", "elliptic-abb", "--speed", "1"], 2, r"`level1` does not apply to 'elliptic-abb'"),
    # --- hopf ---
    (["hopf", *R], 2, r"`hopf` does not apply to 'ross-compare'"),
    (["hopf", *C, "--range", "0", "10"], 2, r"--range 0 10: LO must be > 0"),
    (["hopf", *C, "--range", "20", "10"], 2, r"--range 20 10: need LO < HI"),
    (["hopf", *C, "--n-scan", "1"], 2, r"argument --n-scan"),
    (["hopf", *C, "--set", "eta_i=-1"], 2, r"--set eta_i=-1: must be >= 0"),
    # --- bifurcation ---
    (["bifurcation", *C, "--param", "mu_R", "0", "1", "2"], 2, r"--param mu_R 0 1 2: 'mu_R' cannot be varied here"),
    (["bifurcation", *C, "--param", "eps", "0.002", "0.001", "4"], 2, r"--param eps 0.002 0.001 4: need LO < HI"),
    (["bifurcation", *C, "--param", "eps", "0", "0.001", "1"], 2, r"--param eps 0 0.001 1: the number of points"),
    (["bifurcation", *C, "--param", "eps", "-1", "0", "3"], 2, r"--param eps -1 0 3: LO eps=-1: must be >= 0"),
    (["bifurcation", *C, "--param", "chi", "0.01", "0.02", "3", "--set", "n_limiters=0"], 2,
     r"--param chi: needs limiters"),
    (["bifurcation", *C, "--param", "eps", "0", "0.001", "3", "--set", "events=1", "--batch", "vmap"], 2,
     r"--set events=1: event-located contact runs in the buffered batch"),
    (["bifurcation", *C, "--param", "eps", "0", "0.001", "3", "--set", "events=1", "--batch", "vectorised"], 2,
     r"--set events=1: event-located contact runs in the buffered batch; drop --batch vectorised"),
    (["bifurcation", *C, "--param", "eps", "0", "0.001", "3", "--batch", "pallas"], 2, r"argument --batch"),
    (["bifurcation", *C, "--param", "eps", "0", "0.001", "3", "--lanes", "0"], 2, r"argument --lanes"),
    (["bifurcation", *C, "--param", "eps", "0", "0.001", "x"], 2, r"the number of points must be an integer"),
    (["bifurcation", *C, "--param", "eps", "0", "0.001", "3", "--chunk", "0"], 2, r"argument --chunk"),
    (["bifurcation", "elliptic-abb", "--param", "eps", "0", "0.001", "3"], 2,
     r"`bifurcation` does not apply to 'elliptic-abb'"),
    # --- continue ---
    (["continue", *A, "--param", "zz"], 2, r"--param zz: unknown parameter"),
    (["continue", *A, "--param", "n", "--param2", "mu_w", "--from", "5"], 2, r"--from needs 2 value\(s\)"),
    (["continue", *R, "--param", "kxx"], 2, r"'ross-compare' has no stationary branch"),
    (["continue", *A, "--param", "sigma"], 2, r"--param sigma: .*structure"),
    (["continue", *A, "--param", "n", "--param2", "n"], 2, r"the two parameters must differ"),
    (["continue", *A, "--param", "n", "--to", "6", "4"], 2, r"--to 6 4: need LO < HI"),
    (["continue", *A, "--param", "n", "--to", "-1", "4"], 2, r"--to -1 4: n=-1"),
    (["continue", *A, "--param", "n", "--param2", "mu_w", "--box", "1", "0.5", "0.3", "1"], 2, r"--box 1 0.5 0.3 1"),
    (["continue", *A, "--param", "n", "--ds", "0"], 2, r"argument --ds: must be > 0"),
    (["continue", *A, "--param", "n", "--ds", "0.5", "--ds-max", "0.1"], 2, r"--ds 0.5 --ds-max 0.1"),
    (["continue", *A, "--param", "n", "--max-points", "1"], 2, r"argument --max-points"),
    (["continue", *A, "--param", "n", "--direction", "sideways"], 2, r"argument --direction: invalid choice"),
    (["continue", *A, "--param", "n", "--param2", "mu_w", "--to", "1", "2"], 2, r"--to is for one-parameter"),
    (["continue", *A, "--param", "n", "--from", "nan"], 2, r"argument --from: must be finite"),
    (["continue", *A, "--param", "n", "--from", "-2"], 2, r"--from: n=-2"),
    (["continue", *A, "--param", "n", "--param2", "mu_w", "--switch"], 2,
     r"--switch: branch points are switched at on a one-parameter branch; a boundary \(--param2 mu_w\)"),
    (["continue", *A, "--param", "n", "--switch"], 2,
     r"--switch: anisotropic-abb is continued by the Floquet multipliers .* leave out --switch"),
    # --- balance ---
    (["balance", "--runs", "{d}/empty.csv"], 2, r"empty\.csv"),
    (["balance", "--runs", "{d}/missing.csv"], 2, r"missing\.csv"),
    (["balance", "--runs", "{d}/corrupt.npz"], 2, r"corrupt\.npz"),
    (["balance", "--runs", "{d}/nox2.csv"], 2, r"nox2\.csv has 1 sensor column \(x1\) but 2 trial planes"),
    (["balance", "--runs", "{d}/binary.csv"], 2, r"binary\.csv"),
    (["balance", "--runs", "{d}/latin1.csv"], 2, r"latin1\.csv"),
    (["balance", "--runs", "{d}/runs.txt"], 2, r"runs\.txt"),
    (["balance", "--runs", "{d}/nan.csv"], 2, r"nan\.csv.*x1.*row"),
    (["balance", "--radius", "-1"], 2, r"argument --radius: must be > 0"),
    (["balance", "--radius", "0"], 2, r"argument --radius: must be > 0"),
    (["balance", "--holes", "0"], 2, r"--holes 0"),
    (["balance", "--holes", "1"], 2, r"--holes 1"),
    (["balance", "--planes", "5"], 2, r"plane\(s\) \[5\]"),
    (["balance", "--planes", "0,0"], 2, r"--planes 0,0: a value is repeated"),
    (["balance", "--planes", "a"], 2, r"--planes a: expected comma-separated integers"),
    (["balance", "--rotor-mass", "0"], 2, r"argument --rotor-mass"),
    (["balance", "--out", "{d}/afile"], 2, r"--out .*afile: exists and is not a folder"),
    # --- identify ---
    (["identify", *B, "--fit", "k1,k1"], 2, r"--fit k1,k1: k1 given more than once"),
    (["identify", *B, "--fit", "k1,zz"], 2, r"--fit k1,zz: unknown 'zz'"),
    (["identify", *B, "--fit", ","], 2, r"--fit ',': empty list"),
    (["identify", *B, "--data", "{d}/empty.csv"], 2, r"empty\.csv"),
    (["identify", *B, "--data", "{d}/missing.csv"], 2, r"missing\.csv"),
    (["identify", *B, "--data", "{d}/corrupt.npz"], 2, r"corrupt\.npz"),
    (["identify", *B, "--block", "0"], 2, r"argument --block"),
    (["identify", *B, "--min-speed", "-1"], 2, r"argument --min-speed: must be >= 0"),
    (["identify", *B, "--min-speed", "1e9"], 2, r"above --min-speed 1e\+09"),
    (["identify", *B, "--set", "k1=-1"], 2, r"--set k1=-1: must be > 0"),
    (["identify", *R], 2, r"`identify` does not apply to 'ross-compare'"),
    (["identify", *B, "--data", "{d}/nox2.csv"], 2, r"two sensor columns"),
    (["identify", *B, "--set", "a1=0.5", "--set", "a2=0.5"], 2, r"a1=0.5, a2=0.5"),
    # --- identify on a rotor file ---
    (["identify", *FR, "--fit", "bearing0.kzz", *FU], 2,
     r"--fit bearing0\.kzz: not a parameter of this rotor file; a bearing's coefficients are kxx"),
    (["identify", *FR, "--fit", "bearing0.kxx,foo", *FU], 2, r"--fit foo: not a parameter of this rotor file"),
    (["identify", *FR, "--fit", "disk0.position", *FU], 2, r"--fit disk0\.position: a position is designed or "
     r"scatters"),
    (["identify", *FR, "--fit", "bearing0.node", *FU], 2,
     r"--fit bearing0\.node: an integer that shapes the scene .*it is not a value that can be fitted"),
    (["identify", *FR, "--fit", "shaft0.id", *FU], 2, r"--fit shaft0\.id: its start value is 0; a positive quantity"),
    (["identify", *FR, "--fit", "bearing0.kxx,bearing0.kxx", *FU], 2, r"--fit: bearing0\.kxx is named twice"),
    (["identify", *FR, "--fit", ",", *FU], 2, r"--fit ',': expected comma-separated names"),
    (["identify", *FR, "--fit-unbalance"], 2, r"--fit-unbalance: name the nodes of the unbalances .* 2,4"),
    (["identify", *FR, "--fit-unbalance", "2,99"], 2, r"--fit-unbalance 99: not a node of the rotor \(0\.\.6\)"),
    (["identify", *FR, "--fit-unbalance", "2,x"], 2, r"--fit-unbalance '2,x': expected comma-separated node"),
    (["identify", *FR, "--fit-unbalance=-1"], 2, r"--fit-unbalance '-1': node -1 is negative"),
    (["identify", *FR, "--fit-unbalance", "2,2"], 2, r"--fit-unbalance 2,2: a node is named twice"),
    (["identify", *B, "--fit-unbalance", "2,4"], 2,
     r"--fit-unbalance 2,4: the balancing machine fits its own unbalances; give --fit-unbalance without nodes"),
    (["identify", *FR, "--block", "2", *FU], 2, r"--block applies to the balancing machine's run-up signals"),
    (["identify", *FR, "--min-speed", "10", *FU], 2, r"--min-speed applies to the balancing machine"),
    (["identify", *B, "--weights", "uniform"], 2, r"--weights applies to a rotor file: `rotorjax identify ROTOR"),
    (["identify", *B, "--covariance", "sandwich"], 2, r"--covariance applies to a rotor file"),
    (["identify", *B, "--starts", "3"], 2, r"--starts applies to a rotor file"),
    (["identify", *B, "--spread", "3"], 2, r"--spread applies to a rotor file"),
    (["identify", *B, "--method", "optax"], 2, r"--method applies to a rotor file"),
    (["identify", *FR, *FU, "--spread", "0.5"], 2, r"--spread 0\.5: must be > 1"),
    (["identify", *FR, *FU, "--starts", "0"], 2, r"argument --starts: must be an integer >= 1"),
    (["identify", *FR, *FU, "--weights", "bogus"], 2, r"argument --weights: invalid choice: 'bogus'"),
    (["identify", *FR, *FU, "--method", "newton"], 2, r"argument --method: invalid choice: 'newton'"),
    (["identify", *FR, *FU, "--data", "{d}/missing.csv"], 2, r"missing\.csv: no such file, and not a shipped dataset"),
    (["identify", *FR, *FU, "--data", "{d}/empty.csv"], 2, r"empty\.csv: empty file"),
    (["identify", *FR, *FU, "--data", "{d}/unknowncol.csv"], 2, r"unknowncol\.csv: unknown column\(s\) 'foo'"),
    (["identify", *FR, *FU, "--data", "{d}/dirz.csv"], 2,
     r"dirz\.csv: column 'direction', data row 4 \(line 5\): 'z' is not a direction"),
    (["identify", *FR, *FU, "--data", "{d}/node99.csv"], 2,
     r"node99\.csv: data row 3 \(line 4\): node 99 is not a node of the rotor \(0\.\.6\)"),
    (["identify", *FR, *FU, "--data", "{d}/frf.csv"], 2,
     r"--fit-unbalance: .*frf\.csv holds receptances \(impact tests\), which no unbalance drives"),
    (["identify", "{d}/rig_copy.toml", *FU], 2, r"identify .*rig_copy\.toml: give the measurements with --data FILE"),
    (["identify", *FR], 2, r"flexible_rig\.toml has no \[\[unbalance\]\] .*no excitation; give --fit-unbalance NODES"),
    (["identify", "{rotors}/tapered_two_material.toml", "--data", "flexible-runup", "--fit", "bearing0.kxx"], 2,
     r"--fit bearing0\.kxx: bearing0 is tabulated against speed"),
    (["identify", *FR, *FU, "--set", "bearing0.kzz=1"], 2, r"unknown parameter 'bearing0\.kzz'"),
    (["identify", *FR, *FU, "--set", "bearing0.kxx=-1"], 2, r"--set bearing0\.kxx=-1: must be >= 0"),
    # --- optimize ---
    (["optimize", *FR], 2, r"--vary: give at least one parameter and its bounds"),
    (["optimize", *FR, "--vary", "bearing0.kxx"], 2, r"--vary 'bearing0\.kxx': give KEY=LO:HI"),
    (["optimize", *FR, "--vary", "bearing0.kxx=a:b"], 2, r"--vary 'bearing0\.kxx=a:b': 'a' and 'b' must be numbers"),
    (["optimize", *FR, "--vary", "bearing9.kxx=1e5:1e7"], 2, r"--vary bearing9\.kxx: not a parameter"),
    (["optimize", *FR, "--vary", "bearing0.kxx=1e7:1e5"], 2,
     r"--vary bearing0\.kxx=1e\+07:100000: the bounds need LO < HI"),
    (["optimize", *FR, "--vary", "disk0.m=0:20"], 2, r"--vary disk0\.m=0:20: disk0\.m must be >0"),
    (["optimize", *FR, "--vary", "disk0.m=5:20", "--vary", "disk0.m=6:20"], 2, r"disk0\.m is given twice"),
    (["optimize", *FR, "--vary", "disk0.m=5:20", "--objective", "cost"], 2, r"--objective: invalid choice: 'cost'"),
    (["optimize", *FR, "--vary", "disk0.m=5:20", "--constraint", "mass=3"], 2,
     r"--constraint 'mass=3': give NAME>=VALUE"),
    (["optimize", *FR, "--vary", "disk0.m=5:20", "--constraint", "cost<=3"], 2, r"unknown quantity 'cost'"),
    (["optimize", *FR, "--vary", "disk0.m=5:20", "--objective", "separation-margin"], 2,
     r"--operating: separation-margin needs the operating range"),
    (["optimize", *FR, "--vary", "disk0.m=5:20", "--objective", "separation-margin", "--operating", "600", "400"], 2,
     r"--operating 600 400: needs 0 < LO <= HI"),
    (["optimize", *FR, "--vary", "disk0.m=5:20", "--range", "500", "100"], 2, r"--range 500 100: needs 0 <= LO < HI"),
    (["optimize", *FR, "--vary", "disk0.m=5:20", "--modes", "0"], 2, r"--modes 0: between 1 and"),
    (["optimize", *FR, "--vary", "disk0.m=5:20", "--starts", "0"], 2, r"--starts 0: at least 1"),
    (["optimize", *FR, "--vary", "disk0.m=5:20", "--objective", "response"], 2,
     r"response: .* has no \[\[unbalance\]\]"),
    (["optimize", "ross_compare.toml", "--vary", "disk0.m=5:40", "--objective", "response", "--range", "0", "900",
      "--probe", "99"], 2,
     r"--probe 99: .* has nodes 0\.\.6"),
    (["optimize", *FR, "--vary", "disk0.m=5:20", "--objective", "onset"], 2, r"onset: .* has no stability onset"),
    (["optimize", *FR, "--vary", "bearing0.position=0.1:0.2"], 2,
     r"--vary bearing0\.position: bearing0 sits at node 0, the shaft's end"),
    (["optimize", *FR, "--vary", "disk0.position=0.3:0.8"], 2,
     r"--vary disk0\.position=0\.3:0\.8: .*between the nodes either side of its own, at 0\.25 and 0\.75 m"),
    (["optimize", *FR, "--vary", "disk0.m=9:11", "--objective", "min-log-dec", "--constraint", "mass<=1", "--starts",
      "1"], 2, r"--constraint: no start of 1 met mass<=1"),
    (["optimize", *FR, "--vary", "disk0.m=5:20", "--scatter", "disk1.m=normal(10)"], 2,
     r"--scatter 'disk1\.m=normal\(10\)': expected"),
    (["optimize", *FR, "--vary", "disk0.m=5:20", "--scatter", "disk1.m=lognormal(10,0)"], 2,
     r"the standard deviation must be > 0"),
    (["optimize", *FR, "--vary", "disk0.m=5:20", "--scatter", "disk0.m=lognormal(10,1)"], 2,
     r"--scatter disk0\.m: also given to --vary"),
    (["optimize", *FR, "--vary", "disk0.m=5:20", "--scatter", "disk1.m=lognormal(10,1)", "--scatter",
      "disk1.m=lognormal(11,1)"], 2, r"disk1\.m is given twice"),
    (["optimize", *FR, "--vary", "disk0.m=5:20", "--robust", "2"], 2, r"--robust: give the parameters that scatter"),
    (["optimize", *FR, "--vary", "disk0.m=5:20", "--scatter", "disk1.m=lognormal(10,1)", "--robust", "-1"], 2,
     r"--robust -1: .* must be >= 0"),
    (["optimize", *FR, "--vary", "disk0.m=5:20", "--scatter", "disk1.m=lognormal(10,1)", "--robust-samples", "1"],
     2, r"--robust-samples 1: at least 2"),
    (["optimize", "elliptic-abb", "--vary", "k=1:2"], 2, r"--vary k: not a parameter of elliptic-abb"),
    (["optimize", "ross-compare", "--vary", "shaft_length=1:2"], 2, r"`optimize` does not apply to 'ross-compare'"),
    (["optimize", *A, "--vary", "n=1:2", "--range", "0.3", "10"], 2, r"--vary n: the speed"),
    (["optimize", *A, "--vary", "mu_xi=0.1:1"], 2, r"--range: give the speeds over which anisotropic-abb's stable"),
    (["optimize", *A, "--vary", "mu_xi=0.1:1", "--range", "0.3", "10", "--objective", "mass"], 2,
     r"--objective mass: unknown for anisotropic-abb \(a preset\); known: stable-range"),
    (["optimize", *A, "--vary", "mu_xi=0.1:1", "--range", "0.3", "10", "--constraint", "onset>=2"], 2,
     r"--constraint onset: unknown for anisotropic-abb"),
    (["optimize", *A, "--vary", "eps=0:0.5", "--range", "0.3", "10"], 2, r"--vary eps=0:0.5: must be in \(0,1\)"),
    (["optimize", *A, "--vary", "sigma=0.2:1", "--range", "0.3", "10"], 2, r"--vary sigma: sets the model's structure"),
    (["optimize", "elliptic-abb", "--vary", "n_balls=1:3", "--range", "0.5", "6"], 2,
     r"--vary n_balls: sets the model's structure"),
    (["optimize", *A, "--vary", "mu_xi=0.1:1", "--range", "0.3", "10", "--scatter", "mu_eta=normal(0.5,0.2)"], 2,
     r"--scatter mu_eta=normal\(0\.5, ?0\.2\): mu_eta must be >=0 and this distribution reaches 0"),
    (["optimize", *A, "--vary", "mu_xi=0.1:1", "--range", "0.3", "10", "--scatter", "eps=uniform(0.5,1.2)"], 2,
     r"--scatter eps=uniform\(0\.5, ?1\.2\): reaches 1\.2 .*and eps must be in \(0,1\)"),
    (["optimize", "elliptic-abb", "--vary", "delta_n=0.1:1", "--range", "0.5", "6"], 2,
     r"an elliptic race \(rho1 != rho2\) has no balanced regime"),
    (["optimize", "ross_compare.toml", "--vary", "disk0.m=5:40", "--objective", "response"], 2,
     r"--range: .* has no operating speed"),
    # --- uncertainty ---
    (["uncertainty", *FR], 2, r"--dist: give at least one parameter's distribution"),
    (["uncertainty", *FR, "--dist", "bearing0.kxx=normal(1e6)"], 2, r"--dist 'bearing0\.kxx=normal\(1e6\)': expected"),
    (["uncertainty", *FR, "--dist", "bearing0.kxx=normal(1e6,0)"], 2, r"the standard deviation must be > 0"),
    (["uncertainty", *FR, "--dist", "bearing0.kxx=uniform(2e6,1e6)"], 2, r"needs LO < HI"),
    (["uncertainty", *FR, "--dist", "bearing9.kxx=lognormal(1e6,1e5)"], 2, r"--dist bearing9\.kxx: not a parameter"),
    (["uncertainty", *FR, "--dist", "bearing0.kxx=normal(1e6,3e5)"], 2, r"bearing0\.kxx is a positive quantity"),
    (["uncertainty", *FR, "--dist", "disk0.position=normal(0.5,0.1)"], 2,
     r"--dist disk0\.position=normal\(0\.5, 0\.1\): reaches 0 \.\. 1 m .*at 0\.25 and 0\.75 m"),
    (["uncertainty", *FR, "--dist", "disk0.m=lognormal(10,1)", "--dist", "disk0.m=lognormal(10,2)"], 2,
     r"disk0\.m is given twice"),
    (["uncertainty", *FR, "--dist", "disk0.m=lognormal(10,1)", "--samples", "1"], 2, r"--samples 1: at least 2"),
    (["uncertainty", *FR, "--dist", "disk0.m=lognormal(10,1)", "--range", "500", "100"], 2,
     r"--range 500 100: the critical speeds' range needs 0 <= LO < HI"),
    (["uncertainty", *FR, "--dist", "disk0.m=lognormal(10,1)", "--modes", "-1"], 2, r"--modes -1: at least 0"),
    (["uncertainty", "elliptic-abb", "--dist", "k=normal(1,0.1)"], 2, r"--dist k: not a parameter of elliptic-abb"),
    (["uncertainty", "ross-compare", "--dist", "shaft_length=normal(1,0.1)"], 2, r"`uncertainty` does not apply to"),
    (["uncertainty", *A, "--dist", "mu_xi=normal(0.25,0.1)", "--range", "0.3", "10"], 2,
     r"--dist mu_xi=normal\(0\.25, ?0\.1\): mu_xi must be >=0 and this distribution reaches 0"),
    (["uncertainty", *A, "--dist", "n=lognormal(3,0.1)", "--range", "0.3", "10"], 2, r"--dist n: the speed"),
    (["uncertainty", *A, "--dist", "eps=normal(0.6,0.1)", "--range", "0.3", "10"], 2,
     r"--dist eps=normal\(0\.6, ?0\.1\): reaches 1\.1 \(within 5 standard deviations.*eps must be in \(0,1\)"),
    (["uncertainty", *A, "--dist", "mu_xi=lognormal(0.25,0.01)"], 2, r"--range: give the speeds over which"),
    (["uncertainty", *A, "--dist", "mu_xi=lognormal(0.25,0.01)", "--range", "0.3", "10", "--output", "mass"], 2,
     r"--output: a rotor file's; anisotropic-abb \(a preset\)"),
    (["uncertainty", *FR, "--dist", "disk0.m=lognormal(10,1)", "--output", "response"], 2,
     r"response: .*flexible_rig\.toml has no \[\[unbalance\]\] to respond to"),
    (["uncertainty", *FR, "--dist", "disk0.m=lognormal(10,1)", "--output", "separation-margin"], 2,
     r"--operating: separation-margin needs the operating range"),
    (["uncertainty", *FR, "--dist", "disk0.m=lognormal(10,1)", "--output", "separation-margin", "--operating", "600",
      "400"], 2, r"--operating 600 400: needs 0 < LO <= HI"),
    (["uncertainty", *FR, "--dist", "disk0.m=lognormal(10,1)", "--output", "onset", "--range", "0", "500"], 2,
     r"onset: .*flexible_rig\.toml has no stability onset"),
    (["uncertainty", *FR, "--dist", "disk0.m=lognormal(10,1)", "--output", "margin"], 2,
     r"--output: invalid choice: 'margin'"),
    (["uncertainty", "tapered_two_material.toml", "--dist", "disk0.m=lognormal(10,1)"], 2,
     r"--range: .*tapered_two_material\.toml has no operating speed \(\[rotor\] speed\)"),
    # --- balance on a rotor file ---
    (["balance", *FR, "--runs", "balancing-runs"], 2, r"--runs applies to the balancing machine \(no ROTOR\)"),
    (["balance", *FR, "--holes", "4"], 2, r"--holes 4: a split onto holes needs the correction radius \(--radius M\)"),
    (["balance", "--set", "bearing0.kxx=1"], 2, r"--set applies to a rotor file: `rotorjax balance ROTOR\.toml"),
    (["balance", "--data", "flexible-trials"], 2, r"--data applies to a rotor file"),
    (["balance", "--speeds", "70"], 2,
     r"--speeds 70: 70 rad/s is not a speed of the baseline run of .*balancing_runs\.csv"),
    (["balance", "--planes", "0,1", "--influence", "model", "--speeds", "120"], 2, r"--speeds 120: 120 rad/s is not"),
    (["balance", *FR, "--planes", "2,3"], 2,
     r"flexible-trials: plane 3 has no trial run .*the trial weights are at node\(s\) 2, 4"),
    (["balance", *FR, "--planes", "2,x"], 2, r"--planes 2,x: expected comma-separated integers"),
    (["balance", *FR, "--planes", "2,99"], 2, r"--planes 2,99: node 99 is not a node of the rotor \(nodes 0\.\.6\)"),
    (["balance", *FR, "--planes", "2,2"], 2, r"--planes 2,2: a value is repeated"),
    (["balance", *FR, "--planes", "2,4", "--speeds", "70,75"], 2,
     r"--speeds 70,75: 75 rad/s is not a speed of the baseline run of flexible-trials \(its speeds: 70, 103"),
    (["balance", *FR, "--planes", "2,4", "--speeds", "70,70"], 2, r"--speeds 70,70: 70 rad/s is given twice"),
    (["balance", *FR, "--planes", "2,4", "--speeds", "70,abc"], 2, r"--speeds 70,abc: expected comma-separated"),
    (["balance", *FR, "--planes", "2,4", "--speeds=-5"], 2, r"--speeds -5: speeds must be finite and > 0"),
    (["balance", *FR, "--planes", "2,4", "--model", "--influence", "trials"], 2,
     r"--model and --influence trials contradict each other"),
    (["balance", *FR, "--planes", "2,4", "--method", "bogus"], 2, r"argument --method: invalid choice: 'bogus'"),
    (["balance", *FR, "--planes", "2,4", "--influence", "bogus"], 2, r"argument --influence: invalid choice"),
    (["balance", *FR, "--planes", "2,4", "--data", "flexible-runup"], 2,
     r"flexible-runup: plane 2 has no trial run .*no trial runs .*--influence model"),
    (["balance", *FR, "--data", "flexible-runup", "--influence", "model"], 2,
     r"--planes: flexible-runup has no trial runs to take the correction planes from"),
    (["balance", *FR, "--planes", "0,1,2,3,4,5,6", "--speeds", "70", "--influence", "model"], 2,
     r"flexible-trials: 4 measurement\(s\) at the chosen speeds cannot determine 7 plane corrections"),
    (["balance", *FR, "--planes", "2,4", "--data", "{d}/frf.csv"], 2,
     r"frf\.csv: an impact-test \(FRF\) file has no unbalance runs"),
    (["balance", *FR, "--planes", "2,4", "--data", "{d}/missing.csv"], 2, r"missing\.csv: no such file"),
    (["balance", *FR, "--planes", "2,4", "--data", "{d}/dirz.csv"], 2, r"dirz\.csv: column 'direction', data row 4"),
    (["balance", *FR, "--planes", "2,4", "--data", "{d}/node99.csv", "--influence", "model"], 2,
     r"node99\.csv: data row 3 \(line 4\): node 99 is not a node of the rotor"),
    (["balance", *FR, "--planes", "2,4", "--data", "{d}/nobase.csv"], 2,
     r"nobase\.csv: no baseline run .*runs 1, 2 all carry trial weights"),
    (["balance", *FR, "--planes", "2,4", "--data", "{d}/twobase.csv"], 2,
     r"twobase\.csv: runs 0, 3 have no trial weight; exactly one baseline run"),
    (["balance", *FR, "--planes", "2,4", "--data", "{d}/gap.csv"], 2,
     r"gap\.csv: run 1 \(trial weight at node 2\) has no measurement at speed 103 rad/s, node 0, direction y"),
    (["balance", *FR, "--planes", "2,4", "--data", "{d}/twotrial.csv"], 2,
     r"twotrial\.csv: plane 2 has 2 trial runs \(1, 3\)"),
    (["balance", *FR, "--planes", "2,4", "--set", "bearing0.kzz=1"], 2, r"unknown parameter 'bearing0\.kzz'"),
    (["balance", *FR, "--planes", "2,4", "--service-speed", "0"], 2, r"argument --service-speed: must be > 0"),
    (["balance", "elliptic-abb", "--planes", "2,4"], 2, r"`balance` does not apply to 'elliptic-abb'"),
    # --- issue 28, item 2: an unsupported rotor (rigid-body modes) is refused by every linear analysis ---
    *[([cmd, *R, *extra, "--set", "kxx=0", "--set", "kyy=0"], 2,
       r"ross-compare is not supported: it has 4 rigid-body modes .*add bearings")
      for cmd, extra in (("modes", []), ("campbell", ["--range", "0", "100"]),
                         ("critical-speeds", ["--range", "10", "100"]), ("response", ["--range", "10", "100"]),
                         ("frf", ["--input", "2,x", "--output", "2,x", "--range", "10", "100"]),
                         ("level1", ["--speed", "100"]))],
    (["modes", "{rotors}/ross_compare.toml", "--set", "bearing0.kxx=0", "--set", "bearing0.kyy=0", "--set",
      "bearing1.kxx=0", "--set", "bearing1.kyy=0"], 2, r"ross_compare.toml is not supported: it has 4 rigid-body"),
    # --- issue 28, item 1: response's unbalance comes from the rotor, or is refused ---
    (["response", "flexible_rig.toml", "--range", "10", "100"], 2,
     r"flexible_rig.toml has no unbalance .*give --unbalance NODE,MAG,PHASE"),
    (["response", *R, "--range", "10", "100", "--unbalance", "2,1e-3,0", "--node", "3"], 2,
     r"--node and --phase apply to a bare --unbalance MAG"),
    (["response", *R, "--range", "10", "100", "--unbalance", "-1e-3"], 2, r"argument --unbalance: must be > 0"),
    (["response", *R, "--range", "10", "100", "--probe", "7"], 2, r"--probe 7: the rotor has nodes 0..6"),
    # --- issue 28, item 7: grids larger than the machine's memory are refused up front ---
    (["response", *R, "--range", "10", "100", "--n", "100000000000"], 2,
     r"--n 100000000000: the results would need about .* GiB; this machine allows at most \d+ points"),
    (["campbell", *R, "--range", "0", "100", "--n-speeds", "10000000000"], 2,
     r"--n-speeds 10000000000: .*this machine allows at most \d+ points"),
    (["ucs", *R, "--n", "100000000000"], 2, r"--n 100000000000: .*this machine allows at most \d+ points"),
    (["frf", *R, "--input", "2,x", "--output", "2,x", "--range", "10", "100", "--n", "100000000000"], 2,
     r"--n 100000000000: .*this machine allows at most \d+ points"),
    # --- issue 28, item 9: negative numbers reach the option's own check ---
    (["modes", *R, "--speed", "-1e-3"], 2, r"argument --speed: must be >= 0"),
    (["campbell", *R, "--range", "-1e2", "100"], 2, r"--range -100 100: LO must be >= 0"),
    # --- values with units (issue 35) ---
    (["critical-speeds", *FR, "--range", "0", "12000", "kg"], 2, r"--range '0 kg': a mass \(kg\), and this value is a "
                                                                r"speed, in rad/s"),
    (["critical-speeds", "elliptic-abb", "--range", "0 5 rpm"], 2,
     r"--range 0 rpm: this value has no unit here \(elliptic-abb's nu is dimensionless\); give a number"),
    (["modes", *FR, "--speed", "3 furlongs"], 2, r"--speed '3 furlongs': a length \(m\), and this value is a speed"),
    (["modes", *FR, "--speed", "3 foo"], 2, r"--speed '3 foo': not a quantity \(unknown unit 'foo'\)"),
    (["critical-speeds", *FR, "--range", "0"], 2, r"--range: expected LO HI, optionally with a unit"),
    (["critical-speeds", *FR, "--range", "0", "1", "2", "3"], 2, r"--range: expected LO HI"),
    (["modes", *FR, "--speed=-3000 rpm"], 2, r"--speed -3000 rpm: must be >= 0 \(it is -314.159 rad/s\)"),
    # --- output units (--units, issue 35) ---
    (["modes", *FR, "--units", "furlongs"], 2, r"argument --units: invalid choice: 'furlongs' \(choose from "
                                              r"'si', 'rpm-um', 'rpm-mil'\)"),
    (["critical-speeds", "elliptic-abb", "--range", "0", "5", "--units", "rpm-um"], 2,
     r"--units rpm-um: elliptic-abb's nu is dimensionless .*use --units si"),
    (["critical-speeds", "flexible-abb", "--range", "0.5", "3", "--units", "rpm-mil"], 2,
     r"--units rpm-mil: flexible-abb's omega is dimensionless"),
    (["ucs", *FR, "--range", "1e5rpm", "1e9rpm"], 2, r"--range '1e5rpm': a speed \(rad/s\), and this value is a "
                                                   r"stiffness, in N/m"),
    (["report", *FR, "--operating", "3000", "3600", "N/m"], 2,
     r"--operating '3000 N/m': a stiffness \(N/m\), and this value is a speed, in rad/s"),
    (["report", *FR, "--speed-range", "0", "12000", "rpm", "--units", "rpm-foot"], 2,
     r"argument --units: invalid choice: 'rpm-foot'"),
    # --- report ---
    (["report", "elliptic-abb"], 2, r"`report` does not apply to 'elliptic-abb': it needs a finite-element rotor"),
    (["report", *FR, "--speed-range", "5", "1"], 2, r"--speed-range 5 1: needs 0 <= LO < HI"),
    (["report", *FR, "--operating", "0", "10"], 2, r"--operating 0 10: the operating range must satisfy 0 < LO <= HI"),
    (["report", *R, "--set", "bearing0.kxx=-1"], 2, r"bearing0.kxx"),
    # --- draw ---
    (["draw", "no-such-rotor"], 2, r"unknown preset 'no-such-rotor'"),
    (["draw", *R, "--set", "disk1_node=9"], 2, r"disk1_node=9: the shaft has nodes 0..6"),
    (["draw", *FR, "--set", "bearing0.kxx=-1"], 2, r"bearing0.kxx"),
    (["draw", "{d}/probe9.toml"], 2, r"probe9.toml.*probe\[0\].node = 9"),
    # --- import-ross: a rotor saved by ROSS ---
    (["import-ross", "{d}/nosuch.toml"], 2, r"nosuch.toml: no such file \(a rotor saved by ROSS's Rotor.save"),
    (["import-ross", "{d}/rig_copy.toml"], 2, r"rig_copy.toml: not a rotor saved by ROSS"),
    (["import-ross", "{d}/ross_bad.json"], 2, r"ross_bad.json: not valid JSON"),
    (["import-ross", os.path.join(ROSS_SAVED, "axial_force.toml")], 2,
     r"\[ShaftElement_Shaft Element 0\]: axial_force = 1000.0: a shaft axial force; rotorjax cannot represent it"),
    (["import-ross", os.path.join(ROSS_SAVED, "v3", "frequency_table.toml")], 2,
     r"frequency_table.toml: \[BearingElement_Bearing 0\]: coefficients over the excitation frequency"),
    (["import-ross", "{d}/ross3_damped.json"], 2,
     r"ross3_damped.json: \[parameters\]: default_damping_ratio = 0.01: modal damping of the whole rotor"),
    (["import-ross", os.path.join(ROSS_SAVED, "linked.toml"), "--out", "/nonexistent-dir/r.toml"], 2,
     r"--out /nonexistent-dir/r.toml: cannot be written"),
    # --- data, presets, the command line itself ---
    (["data", "path", "nosuch"], 2, r"nosuch"),
    (["data", "bogus"], 2, r"invalid choice: 'bogus'"),
    (["data", "path"], 2, r"needs a NAME"),
    (["presets", "nosuch"], 2, r"unknown preset 'nosuch'"),
    ([], 2, r"required: COMMAND"),
    (["frobnicate"], 2, r"invalid choice: 'frobnicate'"),
    # --- periodic ---
    (["periodic", "cubic_rig.toml", "--param", "speed", "--range", "100", "106", "--harmonics", "0"], 2,
     r"argument --harmonics: must be 'auto' or an integer >= 1, got '0'"),
    (["periodic", "cubic_rig.toml", "--param", "speed", "--range", "100", "106", "--harmonics", "many"], 2,
     r"argument --harmonics: expected 'auto' or a number of harmonics, got 'many'"),
    (["periodic", "cubic_rig.toml", "--param", "speed", "--range", "100", "106", "--truncation-tol", "0"], 2,
     r"argument --truncation-tol: must be in \(0, 1\), got '0'"),
    (["periodic", "cubic_rig.toml", "--param", "speed", "--range", "100", "106", "--max-harmonics", "0"], 2,
     r"argument --max-harmonics: must be an integer >= 1, got '0'"),
    (["periodic", "cubic_rig.toml", "--param", "speed", "--range", "100", "106", "--subharmonic", "0"], 2,
     r"argument --subharmonic: must be an integer >= 1, got '0'"),
    (["periodic", "cubic_rig.toml", "--param", "speed", "--range", "100", "106", "--from", "99"], 2,
     r"--range 100 106: the start --from speed = 99 lies outside"),
    (["periodic", "cubic_rig.toml", "--param", "speed", "--range", "100", "106", "--from", "2000rpm"], 2,
     r"--range 100 106: the start --from speed = 209\.44 lies outside"),
    (["periodic", "cubic_rig.toml", "--param", "speed", "--range", "100", "106", "--from", "100furlong"], 2,
     r"--from '100furlong': a length \(m\), and this value is a speed, in rad/s"),
    (["periodic", "cantilever-limiters", "--param", "N", "--range", "14", "16", "--from", "15rpm"], 2,
     r"--from 15rpm: this value has no unit here \(cantilever-limiters's N is dimensionless\)"),
    # a branch that ends inside the range, here at max_points, is a failure, with what to change
    (["periodic", "cubic_rig.toml", "--param", "speed", "--range", "100", "101", "--harmonics", "2",
      "--max-points", "2", "--out", "{d}"], 3,
     r"the branch stopped inside --range 100 101: max_points reached \(--max-points 2\) at speed = [\d.]+; "
     r"raise --max-points"),
    (["periodic", "cubic_rig.toml", "--param", "speed", "--range", "106", "100", "--from", "100"], 2,
     r"--range 106 100: need LO < HI"),
    (["periodic", "cubic_rig.toml", "--param", "speed", "--range", "100", "100"], 2, r"--range 100 100: need LO < HI"),
    (["periodic", "cubic_rig.toml", "--param", "speed", "--range", "-1", "106", "--from", "1"], 2,
     r"--range -1 106: the speed must stay > 0"),
    (["periodic", "cubic_rig.toml", "--param", "speed", "--range", "100", "106", "--node", "9"], 2,
     r"--node 9: the scene's nodes are 0\.\.3"),
    (["periodic", "cubic_rig.toml", "--param", "zeta", "--range", "1", "2"], 2,
     r"--param zeta: unknown parameter for .*cubic_rig\.toml; known: .*speed"),
    (["periodic", "cubic_rig.toml", "--param", "shaft0.od", "--range", "0.04", "0.06"], 2,
     r"--param shaft0\.od: the scene's arrays do not depend affinely on shaft0\.od"),
    (["periodic", "cubic_rig.toml", "--param", "disk0.m", "--range", "1", "40"], 2,
     r"--param disk0\.m: the scene's arrays do not depend affinely on disk0\.m"),
    (["periodic", "cubic_rig.toml", "--param", "disk0.node", "--range", "1", "2"], 2,
     r"--param disk0\.node: 'disk0\.node' changes the scene's structure"),
    (["periodic", "cantilever-limiters", "--param", "N", "--range", "14", "16", "--set", "events=1"], 2,
     r"--method hb: the exact \(event-located\) contact of --set events=1 is not offered"),
    (["periodic", "cubic_rig.toml", "--param", "speed", "--range", "100", "106", "--method", "shooting",
      "--steps", "0"], 2, r"--steps"),
    (["periodic", "cubic_rig.toml", "--param", "speed", "--range", "100", "106", "--max-time-residual", "0"], 2,
     r"--max-time-residual"),
    (["periodic", "cubic_rig.toml", "--param", "speed", "--range", "100", "101", "--harmonics", "2",
      "--max-time-residual", "1e-300", "--out", "{d}"], 3, r"harmonics insufficient: the time-domain residual"),
    (["periodic", "cubic_rig.toml", "--param", "speed", "--range", "100", "101", "--max-harmonics", "1",
      "--truncation-tol", "1e-300", "--out", "{d}"], 3,
     r"harmonics insufficient: the truncation error estimate is .* > --truncation-tol 1e-300 at speed = [\d.]+ "
     r"with --max-harmonics 1; raise --max-harmonics"),
    (["periodic", "cubic_rig.toml", "--param", "speed", "--range", "100", "106", "--method", "collocation"], 2,
     r"argument --method: invalid choice: 'collocation'"),
    (["periodic", "cubic_rig.toml", "--param", "speed", "--range", "100", "106", "--ds", "1", "--ds-max", "0.5"], 2,
     r"--ds 1 --ds-max 0\.5: need DS <= DS_MAX"),
    (["periodic", "flexible-abb", "--param", "omega", "--range", "1", "2"], 2,
     r"`periodic` starts from the scene's rest state; flexible-abb has none"),
    (["periodic", "elliptic-abb", "--param", "nu", "--range", "1", "2", "--set", "nu_dot=0.1"], 2,
     r"`periodic` needs a constant speed: elliptic-abb's scene runs at a RunUp"),
    (["periodic", "journal_rig.toml", "--param", "speed", "--range", "200", "210", "--from-hopf"], 2,
     r"--from-hopf: .*'s equations depend on time \(a forcing, such as an unbalance\): limit cycles need an "
     r"autonomous scene; set the forcing to zero \(--set unbalance0\.magnitude=0\)"),
    (["periodic", "cantilever-limiters", "--param", "N", "--range", "13", "15", "--from-hopf"], 2,
     r"--from-hopf: cantilever-limiters's equations depend on time .* set the forcing to zero \(--set eps=0\)"),
    (["periodic", "cubic_rig.toml", "--param", "speed", "--range", "100", "106", "--from-hopf"], 2,
     r"--from-hopf: .*cubic_rig\.toml has no reference motion with linear equations to find Hopf points of"),
    (["periodic", "journal_rig.toml", "--param", "bearing0.viscosity", "--range", "0.02", "0.04", "--from-hopf"], 2,
     r"--from-hopf: --param bearing0\.viscosity: Hopf points are found in the speed; give --param speed"),
    (["periodic", "journal_rig.toml", "--param", "speed", "--range", "200", "210", "--from-hopf", "--from", "0"], 2,
     r"--from-hopf: --from does not apply"),
    (["periodic", "journal_rig.toml", "--param", "speed", "--range", "200", "210", "--from-hopf", "--method",
      "shooting"], 2, r"--from-hopf: --method does not apply"),
    (["periodic", "cubic_rig.toml", "--param", "speed", "--range", "100", "106", "--method", "shooting",
      "--switch"], 2, r"--switch: branch points are switched at on a harmonic-balance branch of forced motions, "
                      r"not with --method shooting; leave out --switch"),
    (["periodic", "journal_rig.toml", "--param", "speed", "--range", "200", "210", "--from-hopf", "--switch"], 2,
     r"--switch: .* not with --from-hopf; leave out --switch"),
    (["periodic", "journal_rig.toml", "--param", "speed", "--range", "200", "210", "--hopf-amplitude", "1e-3"], 2,
     r"--hopf-amplitude 0\.001: it sizes the first cycle of --from-hopf; give --from-hopf too"),
    (["periodic", "journal_rig.toml", "--param", "speed", "--range", "200", "210", "--from-hopf",
      "--hopf-amplitude", "0"], 2, r"argument --hopf-amplitude: .*0"),
    (["periodic", "journal_rig.toml", "--param", "speed", "--range", "100", "150", "--from-hopf", "--set",
      "unbalance0.magnitude=0"], 2, r"--from-hopf: --range 100 150: .* has no Hopf point in it \(`rotorjax hopf "),
    # periodic --param2 / --range2: the jump boundary
    (["periodic", *P, "--range2", "1e12", "6e12"], 2, r"--range2 1e\+12 6e\+12: it is the range of --param2"),
    (["periodic", *P, "--param2", "zz"], 2, r"--param2 zz: unknown parameter"),
    (["periodic", *P, "--param2", "speed"], 2, r"--param2 speed: the two parameters must differ"),
    (["periodic", *P, "--param2", "disk0.node"], 2, r"--param2 disk0.node: .*structure"),
    (["periodic", "cubic_rig.toml", "--param", "cubic_bearing0.k3", "--range", "1e12", "6e12", "--param2",
      "bearing0.kxx"], 2, r"--param2 bearing0.kxx: the folds are continued in \(speed, bearing0.kxx\); give --param "
                          r"speed"),
    (["periodic", *P, "--param2", K3, "--method", "shooting"], 2, r"--param2 .*: --method shooting does not apply"),
    (["periodic", *P, "--param2", K3, "--from-hopf"], 2, r"--param2 .*: --from-hopf does not apply"),
    (["periodic", *P, "--param2", K3, "--range2", "6e12", "1e12"], 2, r"--range2 6e\+12 1e\+12: need LO < HI"),
    (["periodic", *P, "--param2", K3, "--range2", "-1", "6e12"], 2, r"--range2 -1 6e\+12: .*k3"),
    (["periodic", *P, "--param2", K3, "--range2", "4e12", "6e12"], 2,
     r"--range2 4e\+12 6e\+12: cubic_bearing0.k3 = 3e\+12 \(the branch's\) lies outside"),
    (["periodic", *P, "--param2", K3, "--range2", "1", "2", "rpm"], 2, r"--range2"),
    (["periodic", *P, "--param2", "shaft0.L"], 2, r"--param2 shaft0.L: .*(affinely|structure|shape)"),
]


@pytest.fixture(scope="module")
def files(tmp_path_factory):
    d = tmp_path_factory.mktemp("bad")
    (d / "empty.csv").write_bytes(b"")
    (d / "corrupt.npz").write_bytes(b"PK\x03\x04 not really a zip")
    (d / "binary.csv").write_bytes(bytes(range(256)) * 4)
    (d / "latin1.csv").write_bytes("time,tacho,x1,x2,d\xe9bit\n0,0,0,0,0\n".encode("latin-1"))
    (d / "runs.txt").write_text("time,tacho,x1\n0,0,0\n")
    (d / "afile").write_text("")
    lines = open(BALANCING_RUNS).read().splitlines()
    header = lines[0].split(",")
    keep = [i for i, h in enumerate(header) if h != "x2"]
    (d / "nox2.csv").write_text("\n".join(",".join(r.split(",")[i] for i in keep) for r in lines) + "\n")
    rows = lines[:10] + [lines[10].replace(lines[10].split(",")[2], "nan", 1)] + lines[11:20]
    (d / "nan.csv").write_text("\n".join(rows) + "\n")
    # phasor files (the shipped flexible-rig ones, spoilt) and a rotor file without a default dataset
    runup = open(dataset_path("flexible-runup")).read().splitlines()
    (d / "unknowncol.csv").write_text("\n".join([runup[0] + ",foo"] + [r + ",1" for r in runup[1:]]) + "\n")
    bad = runup[4].split(",")
    bad[2] = "z"
    (d / "dirz.csv").write_text("\n".join(runup[:4] + [",".join(bad)] + runup[5:]) + "\n")
    bad = runup[3].split(",")
    bad[1] = "99"
    (d / "node99.csv").write_text("\n".join(runup[:3] + [",".join(bad)] + runup[4:]) + "\n")
    (d / "frf.csv").write_text("speed,node,direction,real,imag,frequency,input_node,input_direction\n"
                               + "".join(f"0,{n},{x},{1e-7 * (i + 1)},-1e-7,{50 + 10 * i},2,x\n"
                                         for n, x in ((0, "x"), (6, "y")) for i in range(20)))
    trials = open(dataset_path("flexible-trials")).read().splitlines()
    head, body = trials[0], trials[1:]
    run = {r: [line for line in body if line.split(",")[5] == str(r)] for r in (0, 1, 2)}
    (d / "nobase.csv").write_text("\n".join([head] + run[1] + run[2]) + "\n")
    again = [",".join(line.split(",")[:5] + ["3", "", "", ""]) for line in run[0]]
    (d / "twobase.csv").write_text("\n".join([head] + body + again) + "\n")
    (d / "gap.csv").write_text("\n".join([head] + run[0] + run[1][:5] + run[1][6:] + run[2]) + "\n")
    again = [line.replace(",1,2,", ",3,2,") for line in run[1]]
    (d / "twotrial.csv").write_text("\n".join([head] + body + again) + "\n")
    shutil.copy(os.path.join(ROTORS, "flexible_rig.toml"), d / "rig_copy.toml")
    (d / "ross_bad.json").write_text('{"ShaftElement_Shaft Element 0": {"n": 0,')
    damped = json.load(open(os.path.join(ROSS_SAVED, "v3", "rotor_example.json")))
    damped["parameters"]["default_damping_ratio"] = 0.01
    (d / "ross3_damped.json").write_text(json.dumps(damped))
    ross = open(os.path.join(ROTORS, "ross_compare.toml")).read()
    (d / "damped.toml").write_text(ross + "\n[external_damping]\ncoefficient = 0.5\n\n[[disk_damping]]\nnode = 4\n"
                                   "translational = 10.0\n\n[[probe]]\nnode = 2\n")
    (d / "probe9.toml").write_text(ross + "\n[[probe]]\nnode = 9\n")
    (d / "seal.toml").write_text(ross + "\n[[seal]]\nnode = 2\nspeeds = [0.0, 500.0]\nkxx = -1e5\n"
                                 "kxy = [0.0, 3e5]\ncxx = 40.0\nmxx = 0.1\n")
    return d


@pytest.mark.parametrize("argv,code,match", CASES, ids=[" ".join(c[0])[:60] for c in CASES])
def test_bad_input(argv, code, match, files, capsys, tmp_path):
    argv = [a.replace("{d}", str(files)).replace("{rotors}", ROTORS) for a in argv]
    if argv and argv[0] not in ("data", "presets", "frobnicate") and "--out" not in argv:
        argv = argv + ["--out", str(tmp_path / "out")]
    rc = main(argv)
    cap = capsys.readouterr()
    assert rc == code, cap.err
    assert "Traceback" not in cap.err + cap.out
    assert re.search(match, cap.err), cap.err
    last = [line for line in cap.err.splitlines() if line.strip()][-1]
    assert re.search(match, last) or re.search(match, cap.err.split("error:", 1)[-1])


def test_enough_cases_per_command():
    per = {}
    for argv, _, _ in CASES:
        per[argv[0] if argv else "(none)"] = per.get(argv[0] if argv else "(none)", 0) + 1
    assert len(CASES) >= 80
    for command in ("simulate", "steady", "critical-speeds", "stability-map", "campbell", "response", "hopf",
                    "bifurcation", "continue", "balance", "identify", "static", "modes"):
        assert per.get(command, 0) >= 5, command


def test_numerical_failure_exits_3_without_a_final_state(tmp_path, capsys):
    rc = main(["simulate", "anisotropic-abb", "--t-end", "1e9", "--max-steps", "10", "--out", str(tmp_path)])
    out = capsys.readouterr().out
    assert rc == 3 and "max_steps" in out and "final whirl amplitude" not in out
    assert "no final state" in out


def test_internal_error_is_one_line_with_a_debug_hint(monkeypatch, capsys, tmp_path):
    from rotorjax.cli import _info

    def boom(args):
        raise KeyError("surprise")

    monkeypatch.setattr(_info, "run_demo", boom, raising=False)
    import rotorjax.demo

    monkeypatch.setattr(rotorjax.demo, "run_demo", boom)
    assert main(["demo", "--out", str(tmp_path)]) == 1
    err = capsys.readouterr().err
    assert "internal error: KeyError" in err and "--debug" in err and "Traceback" not in err
    with pytest.raises(KeyError):
        main(["demo", "--out", str(tmp_path), "--debug"])


def test_help_lists_every_option_with_meaning(capsys):
    from rotorjax.cli import build_parser

    parser = build_parser()
    sub = next(a for a in parser._actions if a.__class__.__name__ == "_SubParsersAction")
    for name, p in sub.choices.items():
        for action in p._actions:
            if action.option_strings and action.dest != "help":
                assert action.help, f"{name} {action.option_strings} has no help"
        assert main([name, "--help"]) == 0
        text = capsys.readouterr().out
        if "PRESET" in text and name not in ("presets",):
            assert "elliptic-abb" in text  # the preset positional lists its choices


def test_presets_name_lists_keys_units_and_ranges(capsys):
    assert main(["presets", "cantilever-limiters"]) == 0
    out = capsys.readouterr().out
    assert re.search(r"chi\s+0.0107\s+dimensionless\s+> 0\s+limiter clearance", out)
    assert re.search(r"n_limiters\s+3\s+count\s+an integer in \[0,64\]", out)
    assert main(["presets", "ross-compare"]) == 0
    assert re.search(r"kxx\s+1e\+06\s+N/m\s+>= 0", capsys.readouterr().out)


def test_shipped_data_by_name(capsys, tmp_path):
    assert main(["data", "list"]) == 0
    out = capsys.readouterr().out
    assert "runup" in out and "balancing-runs" in out
    assert main(["data", "path", "runup"]) == 0
    assert capsys.readouterr().out.strip().endswith("runup.csv")
    assert main(["balance", "--runs", "balancing-runs", "--json", "--out", str(tmp_path)]) == 0
