"""The shipped measurement files, reachable by name.

`resolve_data("runup")` is the shipped run-up; any other argument is a path to a
measurement file of one's own (CSV with a header row, or `.npz`; the columns are
documented in `rotorjax.identify._signals`). The files are synthetic, generated
by the seeded script `rotorjax.identify._make_data`.
"""

import os

import numpy as np

from .._errors import InputError

DATA_DIR = os.path.join(os.path.dirname(os.path.abspath(__file__)), "data")

#: name -> (file name in `DATA_DIR`, one-line description)
DATASETS = {
    "runup": ("runup.csv", "run-up of the balancing-machine rotor from 20 to 400 rad/s in 20 s, "
              "sensors x1 and x2, 20 000 samples at 1 kHz, 1 % noise (for `identify`)"),
    "balancing-runs": ("balancing_runs.csv", "three steady runs at 120 rad/s, sensors x1 and x2: "
                       "no trial weight, 1e-4 kg m at 0 deg in plane 0, at 90 deg in plane 1 (for `balance`)"),
    "flexible-runup": ("flexible_runup.csv", "1x phasors of the flexible_rig rotor (as built) at 50 speeds from 30 to "
                       "460 rad/s through two criticals, x and y at the bearings (nodes 0, 6), 1 % noise (200 rows)"),
    "flexible-trials": ("flexible_trials.csv", "1x phasors of the flexible_rig rotor at 70, 103, 220, 340 rad/s: "
                        "run 0 as is, run 1 trial weight at node 2, run 2 at node 4 (48 rows)"),
}

#: The balancing machine the shipped datasets simulate (SI: kg, kg m^2, m, N/m, N s/m, kg m, deg,
#: rad/s): a cardan-shaft-sized rotor, supports 0.8 m apart, correction planes 0.15 m and 0.65 m from
#: support 1, unbalances 2e-4 kg m at 30 deg and 3e-4 kg m at 200 deg, balancing speed 120 rad/s. The
#: `balancing-machine` preset's defaults are these values.
RIG = {"m": 10.0, "I": 0.5, "l": 0.8, "k1": 2e5, "k2": 3e5, "c1": 150.0, "c2": 200.0, "a1": 0.15,
       "a2": 0.65, "D1": 2e-4, "D1_angle": 30.0, "D2": 3e-4, "D2_angle": 200.0, "speed": 120.0}

#: other spellings accepted for a dataset name
ALIASES = {"balancing_runs": "balancing-runs", "flexible_runup": "flexible-runup",
           "flexible_trials": "flexible-trials"}


def _canonical(name):
    if not isinstance(name, str):
        return None
    if name in DATASETS:
        return name
    return ALIASES.get(name)


def _names():
    return ", ".join(DATASETS)


def dataset_path(name) -> str:
    """Absolute path of the shipped dataset `name` (a key of `DATASETS`, or an
    alias such as `balancing_runs`).

    **Raises:** `InputError` naming the unknown name and listing the datasets."""
    key = _canonical(name)
    if key is None:
        raise InputError(f"unknown dataset {name!r}: the shipped datasets are {_names()}")
    return os.path.join(DATA_DIR, DATASETS[key][0])


def resolve_data(name_or_path) -> str:
    """A shipped dataset's name, or a path to a measurement file, as an absolute path.

    **Arguments:**
    - `name_or_path`: a key of `DATASETS` (or an alias): that shipped file;
      anything else is a path (`str` or `os.PathLike`) that must name an existing file.

    **Returns:** the absolute path (`str`).

    **Raises:** `InputError` naming the argument as given, for a path that does not
    exist (listing the dataset names) or that is a directory."""
    key = _canonical(name_or_path)
    if key is not None:
        return dataset_path(key)
    try:
        path = os.fspath(name_or_path)
    except TypeError:
        raise InputError(f"{name_or_path!r} is neither a dataset name ({_names()}) nor a file path") from None
    if isinstance(path, bytes):
        path = os.fsdecode(path)
    if not path:
        raise InputError(f"empty file name: give a measurement file (CSV or .npz) or a dataset name ({_names()})")
    if not os.path.exists(path):
        raise InputError(f"{path}: no such file, and not a shipped dataset name ({_names()})")
    if os.path.isdir(path):
        raise InputError(f"{path}: is a directory, not a measurement file (CSV with a header row, or .npz)")
    return os.path.abspath(path)


# ---- the rig as a model (parameters with the keys of `RIG`) ----

def machine_from(p):
    """The `BalancingMachine` of parameters `p` (the keys of `RIG`)."""
    from ..models._balancing_machine import BalancingMachine

    return BalancingMachine(p["m"], p["I"], p["l"], p["k1"], p["k2"], p["c1"], p["c2"])


def planes_from(p):
    """The correction planes `(a1, a2)` (m from support 1), checked to be distinct and within the span."""
    a1, a2 = p["a1"], p["a2"]
    if not (0 <= a1 <= p["l"] and 0 <= a2 <= p["l"]) or a1 == a2:
        raise InputError(f"correction planes a1={a1}, a2={a2} must be distinct positions within the span "
                         f"[0, l={p['l']}] (distances from support 1)")
    return np.array([a1, a2])


def unbalances_from(p):
    """The unbalances `D1, D2` (kg m, complex, angles in degrees from the mark)."""
    return np.array([p["D1"] * np.exp(1j * np.radians(p["D1_angle"])),
                     p["D2"] * np.exp(1j * np.radians(p["D2_angle"]))])


def rig_scene(p=None, speed=None):
    """The rig (`RIG`, or parameters `p` with its keys) as a `BalancingScene`: the
    machine, its two correction planes and unbalances, at the constant speed
    `p["speed"]` (or a speed profile `speed`)."""
    from ..models._balancing_machine import BalancingScene

    p = RIG if p is None else p
    return BalancingScene(machine_from(p), planes_from(p), unbalances_from(p),
                          p["speed"] if speed is None else speed)
