"""A probe: a component that only reads the motion of a node (for outputs)."""

import json
import re

import equinox as eqx
import jax.numpy as jnp

from ._rotor_component import AbstractRotorComponent, node_index
from ._table import ComponentTable, Key, node_key


class NodeProbe(AbstractRotorComponent):
    """A sensor at `node`: adds nothing to the equations, only outputs
    `{name}_x`, `{name}_y`, `{name}_vx`, `{name}_vy` (the node centre's motion),
    `{name}_tilt_x`, `{name}_tilt_y` (its slopes) and `{name}_radius`. With the
    default name these are the disk outputs that the precession summaries read."""

    node_index: int = eqx.field(static=True)
    name: str = eqx.field(static=True)

    def __init__(self, node, name="disk"):
        self.node_index = node_index(node)
        self.name = str(name)

    @property
    def node(self):
        return self.node_index

    def outputs(self, s, q, qd):
        x, v, k = s.displacements(self.node), s.velocity(self.node), self.name
        return {f"{k}_x": x[0], f"{k}_y": x[1], f"{k}_vx": v[0], f"{k}_vy": v[1], f"{k}_tilt_x": x[2],
                f"{k}_tilt_y": x[3], f"{k}_radius": jnp.sqrt(x[0] ** 2 + x[1] ** 2)}

    def describe(self):
        return f"probe '{self.name}' at node {self.node}"


#: a probe's name: the prefix of output keys (`disk_x`), so a word
PROBE_NAME = re.compile(r"[A-Za-z_][A-Za-z0-9_]*")
#: the scene's own outputs a probe's would replace (`node_x`, `node_y`)
RESERVED_PROBE_NAMES = ("node",)


def _check_names(probes, where):
    """Each probe named by a word, not `node` (the scene's own `node_x`, `node_y`), and
    no two alike (their outputs would overwrite each other's)."""
    seen = {}
    for i, p in enumerate(probes):
        name, loc = p["name"], where.loc(i, "name")
        if not PROBE_NAME.fullmatch(name):
            where.fail(f"{loc} = {json.dumps(name, ensure_ascii=False)}: must be a word (letters, digits and _, not starting with a "
                       f"digit): it prefixes the probe's outputs ({name}_x, ...)", loc)
        if name in RESERVED_PROBE_NAMES:
            where.fail(f"{loc} = {json.dumps(name, ensure_ascii=False)}: its outputs {name}_x, {name}_y would replace the scene's own "
                       f"(every node's x, y); choose another name", loc)
        if name in seen:
            where.fail(f"{loc} = {json.dumps(name, ensure_ascii=False)}: probe[{seen[name]}] has that name already (their outputs "
                       f"would overwrite each other's); give each probe its own name", loc)
        seen[name] = i


#: its rotor-file table, `[[probe]]`
TABLE = ComponentTable(True, {
    "node": node_key("probe"),
    "name": Key("string", meaning="the probe's name, the prefix of its outputs (<name>_x, <name>_y, ...)",
                default="disk"),
}, "a sensor at a node (outputs only)", name="probe", builds=NodeProbe,
    from_table=lambda p: NodeProbe(p["node"], p["name"]), to_table=lambda p: {"node": p.node, "name": p.name},
    complete=_check_names)
