"""Reference numbers from ROSS, live, for `tests/models/test_seal.py`: the seal of
`data/seal_rotor.toml` as ROSS's `SealElement` (its K, C, M at speeds at and between the
table's), and the rotor with it: its lateral damped natural frequencies and log
decrements at two speeds.

The seal's table has 3 speeds, which ROSS interpolates with `interp1d` (quadratic) and
rotorjax with the not-a-knot cubic, which through 3 points is that quadratic: the two
agree to rounding (ROSS smooths tables of 4 or more speeds; `test_ross_tapered.py`).
Run by `test_seal.py` through `tests.conftest.ross_compute` in ROSS's own interpreter
(which has no rotorjax: the script reads the rotor file itself); by hand:
`python tests/models/ross_seal_reference.py` prints the numbers.
"""

import importlib.util
import json
import pathlib
import tomllib
import warnings

import numpy as np

HERE = pathlib.Path(__file__).parent
FILE = HERE / "data" / "seal_rotor.toml"
SPEEDS = [0.0, 60.0, 250.0, 370.0, 500.0]
MODAL_SPEEDS = [150.0, 450.0]
KEYS = ("kxx", "kyy", "kxy", "kyx", "cxx", "cyy", "cxy", "cyx", "mxx", "myy", "mxy", "myx")
FOLLOWS = {"kyy": "kxx", "cyy": "cxx", "myy": "mxx"}


def seal_coefficients(entry):
    """The `[[seal]]` entry's 12 coefficients, each one value per table speed (the file's
    defaults: `kyy`, `cyy`, `myy` follow `kxx`, `cxx`, `mxx`; the rest 0)."""
    n = len(entry["speeds"])
    out = {}
    for k in KEYS:
        v = entry.get(k, entry.get(FOLLOWS.get(k), 0.0))
        out[k] = [float(x) for x in (v if isinstance(v, list) else [v] * n)]
    return out


def _sibling(folder, name):
    """A reference script of the tests beside this one, by its path (ROSS's interpreter
    runs this script alone, outside the tests' package)."""
    spec = importlib.util.spec_from_file_location(name[:-3], HERE.parent / folder / name)
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def compute():
    warnings.filterwarnings("ignore")
    import ross as rs

    doc = tomllib.loads(FILE.read_text())
    m = doc["material"][0]
    steel = rs.Material(name="rj_seal_steel", rho=m["rho"], E=m["E"], G_s=m["G"])
    shaft = [rs.ShaftElement(s["L"], s["id"], s["od"], material=steel, shear_effects=True, rotary_inertia=True,
                             gyroscopic=True) for s in doc["shaft"]]
    disks = [rs.DiskElement(n=d["node"], m=d["m"], Id=d["Id"], Ip=d["Ip"]) for d in doc["disk"]]
    bearings = [rs.BearingElement(n=b["node"], kxx=b["kxx"], kyy=b["kyy"], cxx=b["cxx"], cyy=b["cyy"])
                for b in doc["bearing"]]
    entry = doc["seal"][0]
    seal = rs.SealElement(n=entry["node"], frequency=entry["speeds"], **seal_coefficients(entry))
    out = {"ross_version": rs.__version__, "speeds": SPEEDS, "modal_speeds": MODAL_SPEEDS,
           "K": [np.asarray(seal.K(w))[:2, :2].tolist() for w in SPEEDS],
           "C": [np.asarray(seal.C(w))[:2, :2].tolist() for w in SPEEDS],
           "M": [np.asarray(seal.M(w))[:2, :2].tolist() for w in SPEEDS]}
    tapered = _sibling("validation", "ross_tapered_reference.py")
    out.update(tapered.lateral_modes(rs, shaft, disks, bearings + [seal], MODAL_SPEEDS, 6))
    return out


if __name__ == "__main__":
    print(json.dumps(compute(), indent=1))
