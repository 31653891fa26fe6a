"""Generate the shipped flexible-rotor measurements (a documented, seeded script):

    python -m rotorjax.identify._make_fe_data

The machine: the shipped rotor file `flexible_rig` (`rotorjax/rotors/flexible_rig.toml`)
is the DESIGN (nominal) rotor. The TRUE (as-built) machine is that file with the
bearing coefficients `TRUTH` (each 0.4 to 2.5 times its nominal value, some up,
some down) and the residual unbalances `UNBALANCES` at the two disks (nodes 2 and 4).
The measurements are steady 1x vibration phasors (the unbalance response of the
linear FE rotor, `rotorjax.flexible.unbalance_response_many`, `x = Re(X e^{i W t})`)
at the `SENSORS` (x and y at the bearings, nodes 0 and 6).

Noise model: each phasor is `X + NOISE |X| (e1 + i e2) / sqrt(2)` with `e1, e2`
independent standard normal draws (complex Gaussian, 1 % of the phasor's
magnitude: sd `NOISE |X| / sqrt(2)` per real and imaginary part), drawn from
`numpy.random.default_rng(seed)` in row order.

Writes into `rotorjax/identify/data/` (phasor files, columns as
`rotorjax.identify._phasor_file`; floats written with `%.17g`, exactly):
- `flexible_runup.csv` (dataset `flexible-runup`, seed 16): one run (run 0) at
  the 50 `RUNUP_SPEEDS` from 30 rad/s to the service speed 460 rad/s, denser
  around the two forward critical speeds; 200 rows, columns
  `speed,node,direction,real,imag,run`.
- `flexible_trials.csv` (dataset `flexible-trials`, seed 17): a trial-weight
  balancing session at the 4 `TRIAL_SPEEDS` (below the 1st critical, near it,
  between the two, near the 2nd): run 0 the machine as it is, run 1 with the
  trial weight `TRIALS[1]` at node 2, run 2 with `TRIALS[2]` at node 4 (each
  run alone on the machine); 48 rows, columns
  `speed,node,direction,real,imag,run,trial_node,trial_magnitude,trial_phase`
  (the trial cells empty for run 0).
Rows are ordered by run, then speed, then sensor.
"""

import os

import numpy as np

DATA = os.path.join(os.path.dirname(os.path.abspath(__file__)), "data")

#: the shipped rotor file of the design
ROTOR = "flexible_rig"

#: the as-built bearing coefficients (N/m, N s/m); the design's are, for bearing 0
#: (node 0) kxx 1.2e6, kyy 0.9e6, cxx 1000, cyy 800, for bearing 1 (node 6) kxx 1.0e6,
#: kyy 0.8e6, cxx 2000, cyy 1600: factors 0.5, 1.6, 1.5, 1.5 and 1.8, 0.7, 0.65, 0.625.
#: The damping is large enough that every coefficient shows in the run-up (1 % noise:
#: relative standard deviations 0.05-0.6 %, the dampers' the largest); the as-built
#: forward critical speeds are about 108.6 and 355.6 rad/s (modal damping ratios 5 % and 18 %)
TRUTH = {
    "bearing0.kxx": 6.0e5, "bearing0.kyy": 1.44e6, "bearing0.cxx": 1500.0, "bearing0.cyy": 1200.0,
    "bearing1.kxx": 1.8e6, "bearing1.kyy": 5.6e5, "bearing1.cxx": 1300.0, "bearing1.cyy": 1000.0,
}

#: the machine's residual unbalances: (node, kg m, rad from the reference mark)
UNBALANCES = [(2, 2e-4, 0.5), (4, 3e-4, 2.6)]

#: run-up speeds (rad/s): 50, from 30 to the service speed 460, denser around the
#: true forward critical speeds (about 108.6 and 355.6 rad/s; the design's 115.2 and 364.1)
RUNUP_SPEEDS = np.concatenate([
    np.linspace(30.0, 90.0, 7),     # step 10
    np.linspace(95.0, 123.0, 15),   # step 2, around the 1st critical
    np.linspace(135.0, 285.0, 6),   # step 30
    np.linspace(296.0, 380.0, 15),  # step 6, around the 2nd critical
    np.linspace(400.0, 460.0, 7),   # step 10
])

#: balancing speeds (rad/s): below the 1st critical, near it, between the two,
#: near the 2nd (off the resonance peaks)
TRIAL_SPEEDS = np.array([70.0, 103.0, 220.0, 340.0])

#: trial weight of each trial run: run -> (node, kg m, rad)
TRIALS = {1: (2, 1e-3, 0.0), 2: (4, 1e-3, 1.5708)}

#: relative noise (of each phasor's magnitude)
NOISE = 0.01

#: the vibration sensors: (node, direction), proximity probes at the two bearings
SENSORS = [(0, "x"), (0, "y"), (6, "x"), (6, "y")]

RUNUP_SEED = 16
TRIALS_SEED = 17

RUNUP_COLUMNS = ("speed", "node", "direction", "real", "imag", "run")
TRIALS_COLUMNS = RUNUP_COLUMNS + ("trial_node", "trial_magnitude", "trial_phase")


def true_rotor():
    """The as-built machine: the shipped design with the bearing coefficients `TRUTH`."""
    from ..io import load_rotor, shipped_rotor

    return load_rotor(shipped_rotor(ROTOR), overrides=TRUTH).rotor


def clean_phasors(rotor, unbalances, speeds, sensors):
    """Noise-free 1x phasors (m), complex `(n_speeds, n_sensors)`: the unbalance
    response of `rotor` to `unbalances` [(node, kg m, rad)] at `speeds` (rad/s),
    at `sensors` [(node, "x" or "y")]."""
    from ..analysis._frf import unbalance_response_many

    nodes = sorted({n for n, _ in sensors})
    X, Y = (np.asarray(a) for a in unbalance_response_many(rotor, unbalances, np.asarray(speeds, float), nodes))
    cols = [(X if d == "x" else Y)[:, nodes.index(n)] for n, d in sensors]
    return np.stack(cols, axis=1)


def _noisy(X, rng):
    """`X` with the complex Gaussian noise of the module docstring (draws in row order)."""
    e = rng.standard_normal(X.shape + (2,))
    return X + NOISE * np.abs(X) / np.sqrt(2.0) * (e[..., 0] + 1j * e[..., 1])


def _rows(X, speeds, run, trial=None):
    """Rows `(speed, node, direction, real, imag, run[, trial...])`, speed-major."""
    out = []
    for i, w in enumerate(speeds):
        for j, (node, d) in enumerate(SENSORS):
            row = (float(w), node, d, float(X[i, j].real), float(X[i, j].imag), run)
            if trial is not False:
                row += (None, None, None) if trial is None else (trial[0], float(trial[1]), float(trial[2]))
            out.append(row)
    return out


def runup_rows(seed=RUNUP_SEED):
    """The rows of `flexible_runup.csv` (columns `RUNUP_COLUMNS`)."""
    rng = np.random.default_rng(seed)
    X = clean_phasors(true_rotor(), UNBALANCES, RUNUP_SPEEDS, SENSORS)
    return _rows(_noisy(X, rng), RUNUP_SPEEDS, 0, trial=False)


def trial_rows(seed=TRIALS_SEED):
    """The rows of `flexible_trials.csv` (columns `TRIALS_COLUMNS`; `None` for the
    empty trial cells of run 0)."""
    rng = np.random.default_rng(seed)
    rotor = true_rotor()
    out = []
    for run, trial in [(0, None)] + sorted(TRIALS.items()):
        unbalances = list(UNBALANCES) + ([] if trial is None else [trial])
        X = clean_phasors(rotor, unbalances, TRIAL_SPEEDS, SENSORS)
        out += _rows(_noisy(X, rng), TRIAL_SPEEDS, run, trial)
    return out


def _cell(v):
    if v is None:
        return ""
    if isinstance(v, float):
        return "%.17g" % v
    return str(v)


def write_rows(path, columns, rows):
    """Write `rows` as a CSV with a header row (floats `%.17g`, `None` empty)."""
    with open(path, "w", encoding="utf-8", newline="") as f:
        f.write(",".join(columns) + "\n")
        for row in rows:
            f.write(",".join(_cell(v) for v in row) + "\n")
    return path


def main():
    from .. import _config  # noqa: F401  (float64)

    os.makedirs(DATA, exist_ok=True)
    write_rows(os.path.join(DATA, "flexible_runup.csv"), RUNUP_COLUMNS, runup_rows(RUNUP_SEED))
    write_rows(os.path.join(DATA, "flexible_trials.csv"), TRIALS_COLUMNS, trial_rows(TRIALS_SEED))
    print(f"wrote {DATA}/flexible_runup.csv and flexible_trials.csv")


if __name__ == "__main__":
    main()
