"""A rotor file (`.toml`) as a preset: what lets every CLI command that takes a
preset take a rotor file in its place.

The `--set` keys are the file's scalar numeric entries, `table<index>.key` for
array tables (`bearing0.kxx`, `shaft3.od`, `disk1.m`, `limiters0.clearance`),
`table.key` for single tables (`gravity.g`, `internal_damping.relaxation_time`,
`rotor.n_modes`), and `speed` (rad/s, the file's `[rotor] speed`, default 0).
Integer entries (nodes, counts) are topology keys. Entries the file leaves at
their defaults are not keys (set them in the file: `kyy` defaults to `kxx`, and
follows it).
"""

import math

from ..analysis import StraightRunning
from ..models import has_films, static_equilibrium
from ..io import file_parameters_and_scene, load_rotor
from ._base import Preset, Setup

#: revolutions in a default run of a rotor file (`t_end` at a positive speed)
REVOLUTIONS = 200


#: the reference motion of a rotor on fluid films (`rotorjax hopf`: the oil-whirl onset)
FILM_REFERENCE = "the static equilibrium in the fluid-film bearings"


def _start(scene, speed):
    """A run's initial state on fluid films: the static equilibrium at the running
    speed (at rest, or where it is not found, the straight shaft: the rotor then
    settles into its bearings)."""
    y0 = scene.rest_state()
    if not speed > 0:
        return y0
    eq = static_equilibrium(scene, speed)
    return y0.at[:scene.n_shaft].set(eq.q) if bool(eq.converged) else y0


def preset_from_file(path) -> Preset:
    """The preset of the rotor file at `path` (checked whole, now): kind `"rotor"`,
    named by the path as given, its source the file's `[rotor] name`.

    `build(params)` reads the file again with the changed entries applied and
    returns a `Setup`: the `RotorScene` at `ConstantSpeed(params["speed"])`, its
    rest state, and `t_end` = 200 revolutions at that speed (None at speed <= 0);
    `extras` holds `revolutions` and `rotor_file` (the path). A rotor on fluid films
    starts from its static equilibrium at the speed, which is also its reference
    motion (`StraightRunning` of its linearisation there: `rotorjax hopf` gives the
    oil-whirl onset)."""
    label, rotor_name, entries, as_given = file_parameters_and_scene(path)
    defaults = {k: e.value for k, e in entries.items()}

    def build(params) -> Setup:
        params = dict(defaults, **(params or {}))
        changed = {k: v for k, v in params.items() if k in defaults and v != defaults[k]}
        scene = load_rotor(path, changed) if changed else as_given   # the file as it is: built once already
        speed = float(params["speed"])
        t_end = REVOLUTIONS * 2 * math.pi / speed if speed > 0 else None
        extras = {"revolutions": REVOLUTIONS if speed > 0 else None, "rotor_file": label}
        if not has_films(scene):
            return Setup(scene, scene.rest_state(), t_end, extras)
        return Setup(scene, _start(scene, speed), t_end, extras,
                     reference=StraightRunning(scene, speed, label=FILM_REFERENCE))

    integer = tuple(k for k, e in entries.items() if e.integer)
    return Preset(
        name=label,
        source=rotor_name,
        defaults=defaults,
        build=build,
        describe_params={k: e.meaning for k, e in entries.items()},
        time_unit="s",
        length_unit="m",
        integer_keys=integer,
        speed_key="speed",
        topology_keys=integer,
        kind="rotor",
        units={k: e.unit for k, e in entries.items()},
        domains={k: e.domain for k, e in entries.items()},
    )
