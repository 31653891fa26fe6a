"""`identify(scene, data, params)`: one way into identification for every scene.

The scene says which model the data measure; the engine (`_engine`) is the same
for all: one Levenberg-Marquardt (vmapped over starts), one covariance path
(classical, sandwich, HAC), one set of intervals and warnings, one result type
(`Identification`).

| scene | data | model |
|---|---|---|
| `BalancingScene` (model 002's machine) | `(speeds, X)` | steady 1x response |
| | an `OrderTrack`, or a run-up signal file (read and order-tracked) | the order-tracked run-up |
| a rotor file (path) or `RotorModel` | a `PhasorData`, a phasor file or a dataset's name | 1x phasors or receptances |
"""

import os

from .._errors import InputError
from ..models._balancing_machine import BalancingScene
from ._engine import Identification
from ._fe_identify import identify_rotor
from ._fe_params import RotorModel
from ._fit import identify_machine, runup_data

#: the options each scene's model takes (besides `fit_unbalance`)
MACHINE_OPTIONS = ("sigma", "max_iter", "reference", "covariance", "hac_lags", "n_starts", "spread", "seed",
                   "band", "block", "min_speed", "stage")
ROTOR_OPTIONS = ("overrides", "weights", "covariance", "n_starts", "spread", "method", "max_iter", "seed",
                 "critical_speeds")


def _check_options(options, allowed, scene):
    bad = [k for k in options if k not in allowed]
    if bad:
        raise InputError(f"{', '.join(bad)}: {'does' if len(bad) == 1 else 'do'} not apply to {scene}; its "
                         f"options: fit_unbalance, {', '.join(allowed)}")


def identify(scene, data, params=None, *, fit_unbalance=None, **options) -> Identification:
    """Fit the parameters `params` of `scene` (and its unbalances, `fit_unbalance`)
    to the measurements `data`; see the module for the scenes and data.

    **Arguments:**

    - `scene`: a `BalancingScene` (its machine's values are the start; its planes;
      its unbalances unless fitted), or a rotor file or `RotorModel` (its values,
      with `overrides`, are the start).
    - `data`: what the scene's model predicts (see the module).
    - `params`: the names to fit: the machine's `k1, k2, c1, c2, m, I` (default the
      supports' four), or a rotor file's `--set` keys (`bearing0.kxx`,
      `material0.E`, `shaft2.od`, `seal0.kxy`, `unbalance1.phase`, ...).
    - `fit_unbalance`: the machine: `True` fits the unbalances in its planes; a rotor
      file: the nodes whose unbalances are fitted (projected out: linear least
      squares at each step).
    - `options`: the machine's `sigma`, `max_iter`, `reference` ("joint": the phase
      reference's error fitted with the run-up model), `covariance` ("auto",
      "classical", "sandwich", "hac"), `hac_lags`, `n_starts`/`spread`/`seed`,
      `band` (the fitted response's 95 % band), and for a run-up file `block`,
      `min_speed`, `stage` (progress); a rotor file's `overrides`, `weights`
      ("relative", "uniform"), `covariance`, `n_starts`/`spread`/`seed` (the global
      stage; default 32 starts), `method` ("lm", "optax"), `max_iter`,
      `critical_speeds`.

    **Returns:** an `Identification`. **Raises:** `InputError` naming the option,
    file, row or key; `NumericalError` when no start gives a finite fit.
    """
    if isinstance(scene, BalancingScene):
        _check_options(options, MACHINE_OPTIONS, "the balancing machine")
        fit = tuple(params) if params is not None else ("k1", "k2", "c1", "c2")
        if fit_unbalance not in (None, True, False):
            raise InputError(f"fit_unbalance {fit_unbalance!r}: the balancing machine fits the unbalances of "
                             "its planes or none (True or False)")
        run = {k: options.pop(k) for k in ("block", "min_speed", "stage") if k in options}
        if isinstance(data, (str, os.PathLike)):
            data = runup_data(data, run.get("block", 1), run.get("min_speed", 0.0), len(fit), run.get("stage"))
            if run.get("stage"):
                run["stage"]("Levenberg-Marquardt fit (autodiff Jacobians)")
        elif run:
            raise InputError(f"{', '.join(run)}: {'applies' if len(run) == 1 else 'apply'} to a run-up signal file "
                             "only (data is phasors here)")
        return identify_machine(scene, data, fit, fit_unbalance=bool(fit_unbalance), **options)
    if isinstance(scene, (str, os.PathLike, RotorModel)):
        _check_options(options, ROTOR_OPTIONS, "a rotor file")
        nodes = () if fit_unbalance in (None, False) else fit_unbalance
        if nodes is True:
            raise InputError("fit_unbalance: name the nodes of the unbalances to fit on a rotor file, e.g. (2, 4)")
        return identify_rotor(scene, data, () if params is None else params, fit_unbalance=nodes, **options)
    raise InputError(f"scene must be a BalancingScene, a rotor file or a RotorModel; got {type(scene).__name__}")
