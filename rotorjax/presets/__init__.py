"""The published scenes, by CLI name."""

from . import _anisotropic_abb as anisotropic_abb
from . import _balancing_machine as balancing_machine
from . import _cantilever_limiters as cantilever_limiters
from . import _flexible_abb as flexible_abb
from . import _jeffcott_abb as jeffcott_abb
from . import _ross_compare as ross_compare
from .._errors import InputError
from ._base import Preset as Preset

PRESETS = {p.name: p for p in (jeffcott_abb.PRESET, anisotropic_abb.PRESET, ross_compare.PRESET,
                                flexible_abb.PRESET, cantilever_limiters.PRESET,
                                balancing_machine.PRESET)}


def get(name: str) -> Preset:
    """The preset called `name`; an unknown name raises, listing the known ones."""
    if name not in PRESETS:
        raise InputError(f"unknown preset {name!r}; known: {', '.join(sorted(PRESETS))}")
    return PRESETS[name]
