"""The registry of rotor-file tables: every part a rotor file can hold beyond the
shaft, each table declared by its component's module (`TABLE`), in the scene's order
(each table's entries in file order). The rotor-file reader and writer
(`rotorjax.io`) iterate it; adding a component adds one line here."""

from . import _external_damping, _fluid_film, _gravity, _internal_damping, _node_parts, _node_probe
from . import _nonlinear_bearings, _seal, _unbalance

TABLES = (
    _unbalance.TABLE,
    _internal_damping.TABLE,
    _external_damping.TABLE,
    _external_damping.DISK_TABLE,
    _gravity.TABLE,
    _fluid_film.FILM_TABLE,
    _nonlinear_bearings.CUBIC_TABLE,
    _nonlinear_bearings.CLEARANCE_TABLE,
    _node_parts.LIMITERS_TABLE,
    _node_parts.BALANCER_TABLE,
    _node_probe.TABLE,
    _seal.TABLE,
)
