"""What a preset is: a published scene with named parameters and defaults."""

import dataclasses
from typing import Callable

import numpy as np


@dataclasses.dataclass(frozen=True)
class Preset:
    """A published scene.

    - `name`: the CLI name (`elliptic-abb`, ...).
    - `source`: the publication.
    - `defaults`: the published parameter set; these names are the `--set` keys.
    - `build(params) -> (scene, y0, t_end)`: the scene in the paper's
      dimensionless units, its initial state and default end time.
    - `time_unit`, `length_unit`: what one dimensionless unit is.
    - `speed_key`: the parameter that is the (dimensionless) speed.
    - `margin(params) -> scalar`: stability margin of the preset's reference regime
      (`regime` says which), traceable in the parameters (for maps and critical
      speeds); < 0 is stable.
    - `topology_keys`: parameters that change the scene's structure (not sweepable).
    """

    name: str
    source: str
    defaults: dict
    build: Callable
    describe_params: dict
    time_unit: str
    length_unit: str
    integer_keys: tuple = ()
    speed_key: str = "n"
    margin: Callable = None
    regime: str = ""
    topology_keys: tuple = ()
    kind: str = "planar"  # "planar" (a Scene), "flexible" (a FlexibleRotor) or "modal" (a ModalShaft)

    def params(self, overrides=None) -> dict:
        """Defaults with `overrides` applied; unknown keys and non-numbers raise."""
        params = dict(self.defaults)
        for key, value in (overrides or {}).items():
            if key not in self.defaults:
                raise ValueError(
                    f"unknown parameter {key!r} for preset {self.name!r}; "
                    f"known: {', '.join(sorted(self.defaults))}"
                )
            try:
                value = float(value)
            except (TypeError, ValueError):
                raise ValueError(f"parameter {key!r} must be a number, got {value!r}") from None
            if not np.isfinite(value):
                raise ValueError(f"parameter {key!r} must be finite, got {value!r}")
            if key in self.integer_keys:
                if value != int(value) or value < 0:
                    raise ValueError(f"parameter {key!r} must be a non-negative integer, got {value!r}")
                value = int(value)
            params[key] = value
        return params
