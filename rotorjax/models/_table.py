"""A rotor-file table as the component it builds declares it.

A component module states its table once, beside the component (`TABLE =
ComponentTable(...)`): the table's name, its keys (kind, unit, meaning, domain,
default), how an entry becomes the component (`from_table`) and the component an
entry (`to_table`), the checks across keys or entries (`complete`), and what a key
sets in the scene (`leaves`, `followers`, `refused`). The registry
(`rotorjax.models._registry.TABLES`) lists the tables; the rotor-file reader,
writer, overrides and parameter paths (`rotorjax.io`) iterate it, so adding a
component is its module, one registry line and its tests.
"""

import dataclasses
from typing import Callable

import numpy as np

#: a key without a default: required, or completed by the table's `complete`
NO_DEFAULT = object()


@dataclasses.dataclass(frozen=True)
class Key:
    """One key of a table. `kind`: "number", "count" (an integer), "node", "index",
    "string", "numbers" (a list), "number_or_numbers" or "strings"; `sign` for
    numbers (and every entry of a list): "positive", "nonnegative" or "any";
    `default` the value a left-out key takes (`NO_DEFAULT`: none); `plausible` the
    quantity ("length", "radius", ...) whose plausible SI range flags a unit slip."""

    kind: str
    unit: str = ""
    meaning: str = ""
    sign: str = "any"
    required: bool = False
    choices: tuple = ()
    domain: str = ""  # a preset domain when the sign does not say it (nu, inertia_factor)
    default: object = NO_DEFAULT
    plausible: str = ""  # the quantity whose plausible range a value is judged by (`_plausibility.RANGES`)


def node_key(what) -> Key:
    """The `node` key of a table of parts at a node."""
    return Key("node", "node", f"node of the {what}", required=True)


@dataclasses.dataclass(frozen=True)
class Table:
    """A table's shape: one entry (`[name]`) or an array of them (`[[name]]`), its keys
    and what an entry is."""

    array: bool
    keys: dict
    meaning: str


@dataclasses.dataclass(frozen=True)
class ComponentTable(Table):
    """A table that builds one part of the scene per entry.

    - `name`: the table's name in the file.
    - `builds`: the class of what an entry builds (the writer finds a part's table by it).
    - `from_table(entry)`: the part of a checked, completed entry (a dict of plain values).
    - `to_table(part)`: the entry that rebuilds `part` exactly (keys in writing order).
    - `complete(entries, where)`: checks across keys and entries, and values derived from
      others, in place; `where.fail(message, loc)`, `where.warn(message, loc)` and
      `where.loc(index, key)` name the entry as the file does.
    - `part`: "component" (a scene component, in the registry's order) or "bearing" (a
      linear element of the rotor, tabulated against speed like a bearing's coefficients,
      after the file's `[[bearing]]` entries).
    - `leaves`: key -> the path of its leaf in the component, where it is not the field of
      the key's name; `spread`: key -> the keys whose leaves it sets together; `followers`:
      key -> `(follower key, rule)` pairs: leaves that follow the key where the entry leaves
      the follower out (`rule`: "value", the same value, or one of `_parameters.RULES`);
      `refused`: key -> why it is not a parameter.
    """

    name: str = ""
    builds: type = object
    from_table: Callable = None
    to_table: Callable = None
    complete: Callable = None
    part: str = "component"
    leaves: dict = dataclasses.field(default_factory=dict)
    spread: dict = dataclasses.field(default_factory=dict)
    followers: dict = dataclasses.field(default_factory=dict)
    refused: dict = dataclasses.field(default_factory=dict)

    @property
    def head(self) -> str:
        return f"[[{self.name}]]" if self.array else f"[{self.name}]"


def one_or_each(a):
    """An array as a file holds it: one float when every entry is the same, else a list."""
    a = np.ravel(np.asarray(a, dtype=np.float64))
    return float(a[0]) if np.all(a == a[0]) else [float(x) for x in a]


def floats(a) -> list:
    """An array as a list of floats."""
    return [float(x) for x in np.ravel(np.asarray(a, dtype=np.float64))]
