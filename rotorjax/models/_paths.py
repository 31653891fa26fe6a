"""Parameters as leaves of a scene, addressed by a path (data, not a function): a
preset's sweepable keys, and any study that sets one leaf of a built scene.

A path is dotted attribute names; `components[Type]` picks the first of the scene's
components of that class, e.g. `speed.constant`, `components[Unbalance].magnitude`,
`components[LimitersAt].limiters.clearance`.
"""

import re

import equinox as eqx

from ._validate import InputError

_PICK = re.compile(r"^(\w+)\[(\w+)\]$")


def _words(cls_name: str) -> str:
    """`LimitersAt` -> "limiters", `Unbalance` -> "unbalance" (for messages)."""
    return re.sub(r"At$", "", cls_name).lower()


def leaf_at(tree, path: str):
    """The leaf of `tree` at `path` (see the module docstring); `InputError` where a
    picked component is absent ("needs limiters (no LimitersAt in the scene's
    components)")."""
    obj = tree
    for part in path.split("."):
        m = _PICK.match(part)
        if m is None:
            obj = getattr(obj, part)
            continue
        seq, name = getattr(obj, m.group(1)), m.group(2)
        found = [c for c in seq if type(c).__name__ == name]
        if not found:
            raise InputError(f"needs {_words(name)} (no {name} in the scene's {m.group(1)})")
        obj = found[0]
    return obj


def with_leaf(tree, path: str, value):
    """`tree` with the leaf at `path` replaced by `value` (`eqx.tree_at`)."""
    return eqx.tree_at(lambda t: leaf_at(t, path), tree, value)
