"""The published scenes, by CLI name; `get` also opens rotor files (`.toml`)."""

from . import _anisotropic_abb as anisotropic_abb
from . import _balancing_machine as balancing_machine
from . import _cantilever_limiters as cantilever_limiters
from . import _flexible_abb as flexible_abb
from . import _jeffcott_abb as jeffcott_abb
from . import _ross_compare as ross_compare
from .._errors import InputError
from ._affine import affine_scene as affine_scene
from ._base import Preset as Preset
from ._base import PublishedSpeeds as PublishedSpeeds
from ._base import Setup as Setup
from ._base import hopf_report as hopf_report

PRESETS = {p.name: p for p in (jeffcott_abb.PRESET, anisotropic_abb.PRESET, ross_compare.PRESET,
                                flexible_abb.PRESET, cantilever_limiters.PRESET,
                                balancing_machine.PRESET)}


def get(name) -> Preset:
    """The preset called `name`, or for a path ending in `.toml` the rotor file's
    preset (its `--set` keys are the file's scalar entries, e.g. `bearing0.kxx`); an
    unknown name raises, listing the known ones. A `.toml` name that is not a file
    but names a rotor file shipped with rotorjax (`flexible_rig.toml`) opens that one."""
    if str(name).endswith(".toml"):
        import os

        if not os.path.exists(name) and os.sep not in str(name):
            from ..io import shipped_rotor

            try:
                name = str(shipped_rotor(str(name)))
            except InputError:
                pass
        import importlib.util

        if importlib.util.find_spec(f"{__name__}._rotor_file") is None:
            raise InputError(f"{name}: rotor files (.toml) are not supported by this installation "
                             "(rotorjax.presets._rotor_file is missing)")
        from ._rotor_file import preset_from_file

        return preset_from_file(name)
    if name not in PRESETS:
        raise InputError(f"unknown preset {name!r}; known: {', '.join(sorted(PRESETS))}")
    return PRESETS[name]
