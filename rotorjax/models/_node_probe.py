"""A probe: a component that only reads the motion of a node (for outputs)."""

import equinox as eqx
import jax.numpy as jnp

from ._rotor_component import AbstractRotorComponent, node_index


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
