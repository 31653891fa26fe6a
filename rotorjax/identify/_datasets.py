"""The shipped measurement files, reachable by name.

`resolve_data("runup")` is the shipped run-up; any other argument is a path to a
measurement file of one's own (CSV with a header row, or `.npz`; the columns are
documented in `rotorjax.identify._signals`). The files are synthetic, generated
by the seeded script `rotorjax.identify._make_data`.
"""

import os

from .._errors import InputError

DATA_DIR = os.path.join(os.path.dirname(os.path.abspath(__file__)), "data")

#: name -> (file name in `DATA_DIR`, one-line description)
DATASETS = {
    "runup": ("runup.csv", "run-up of the balancing-machine rotor from 20 to 400 rad/s in 20 s, "
              "sensors x1 and x2, 20 000 samples at 1 kHz, 1 % noise (for `identify`)"),
    "balancing-runs": ("balancing_runs.csv", "three steady runs at 120 rad/s, sensors x1 and x2: "
                       "no trial weight, 1e-4 kg m at 0 deg in plane 0, at 90 deg in plane 1 (for `balance`)"),
}

#: other spellings accepted for a dataset name
ALIASES = {"balancing_runs": "balancing-runs"}


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
