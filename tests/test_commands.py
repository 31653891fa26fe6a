"""Issue 29: which commands apply to a preset follows from its built scene's
capabilities and reference motion (`rotorjax.cli._common.COMMAND_NEEDS`), not from
its name or a kind string; the lists equal what each preset offered before, model
004 gaining the finite-element analyses its `RotorScene` composition now has, and
every preset with a traceable reference motion `uncertainty` and `optimize` (issue
34: its stability thresholds and stable speed range)."""

import pytest

from rotorjax import presets
from rotorjax.cli._common import COMMAND_NEEDS, applicable, wrong_kind

PLANAR = ["simulate", "steady", "critical-speeds", "stability-map", "continue", "uncertainty", "optimize"]
FE = ["campbell", "response", "critical-speeds", "static", "modes", "ucs", "frf", "level1"]
EXPECTED = {
    "elliptic-abb": PLANAR,
    "anisotropic-abb": PLANAR,
    "ross-compare": FE,
    "flexible-abb": ["steady", "critical-speeds", "stability-map", "continue", "uncertainty", "optimize"],
    "cantilever-limiters": ["simulate", "campbell", "response", "critical-speeds", "stability-map", "continue",
                            "hopf", "bifurcation", "static", "modes", "ucs", "frf", "level1", "uncertainty",
                            "optimize"],
    "balancing-machine": ["balance", "identify"],
    "rotorjax/rotors/ross_compare.toml": ["simulate", *FE, "balance", "identify", "uncertainty", "optimize"],
}
# issue 35: every scene is drawn; a finite-element rotor's report
EXPECTED = {name: [*commands, "draw", *(["report"] if "modes" in commands else [])]
            for name, commands in EXPECTED.items()}


@pytest.mark.parametrize("name", list(EXPECTED))
def test_the_commands_of_each_preset_follow_from_its_scene(name):
    assert applicable(presets.get(name)) == EXPECTED[name]


def test_a_refusal_says_what_is_needed_and_what_applies():
    msg = str(wrong_kind(presets.get("balancing-machine"), "simulate"))
    assert msg == ("`simulate` does not apply to 'balancing-machine': it needs an initial state to run from; "
                   "use `balance`, `identify`, `draw`")
    assert set(COMMAND_NEEDS) >= {c for cs in EXPECTED.values() for c in cs}
