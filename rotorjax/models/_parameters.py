"""Parameters as leaves of a scene.

A parameter path (`bearing0.kxx`, `material0.E`, `shaft3.od`, `unbalance1.phase`:
a rotor file's `--set` keys) is resolved once, by whoever knows what the name
means (the rotor-file loader), into `Target`s: the array leaves of the scene it
sets, which entries, and how. Identification (and, next, design optimisation) sets
values through `with_values` / `set_parameters`: pure JAX, differentiable and
vmappable in the values, one mechanism (`eqx.tree_at`) for every component. A
`--set` reads the file again with the value; the two build the same scene, bit for
bit (`tests/models/test_parameters.py`).

A target's `leaf` is a path of attribute names and tuple indices from
`SceneParts` (the scene's full linear rotor, its speed profile and its
components): `("rotor", "E")`, `("rotor", "bearing_tables", 0, 1)`,
`("components", 3, "race", "r1")`. Its `index` picks entries of that array (None:
all of it). Its `rule` says what goes there: the value itself, or a quantity that
follows others and is recomputed from the leaves as they stand after the value was
set (`RULES`: a material's shear modulus from `E` and `nu`, or `nu` from `E` and
`G`; a clearance bearing's default smoothing from its clearance), or what the value
places: a node's axial position (`node_position`, a bearing's or a disk's
`position`) sets the lengths of the two elements either side of it, the nodes beyond
them staying where they are. The targets of one parameter are applied in order.

A scene's cached arrays (assembled matrices, a modal basis) are rebuilt from the
new leaves by `set_parameters`, exactly as the scene's constructor builds them.
"""

import dataclasses

import equinox as eqx
import jax.numpy as jnp
import numpy as np

from .._errors import InputError
from ._materials import poisson_ratio, shear_modulus
from ._nonlinear_bearings import ClearanceBearing


@dataclasses.dataclass(frozen=True)
class Target:
    """One array a parameter sets (see the module docstring)."""

    leaf: tuple
    index: tuple | None = None
    rule: str = "value"


@dataclasses.dataclass(frozen=True)
class ParameterPath:
    """A parameter of a scene by its name: the `targets` it sets, whether the scene's
    linear matrices are affine in it (`affine`: a bearing, pedestal, disk or point-mass
    value, which enters the matrices once; what receptance coupling needs), and, for
    a name that is not a leaf (it changes the scene's structure, or is computed when
    the scene is built), why (`refusal`; no targets)."""

    name: str
    targets: tuple = ()
    affine: bool = False
    refusal: str = ""


class SceneParts(eqx.Module):
    """What parameters address: the scene's full linear rotor (a `FlexibleRotor`), its
    speed profile and its components."""

    rotor: eqx.Module
    speed: eqx.Module
    components: tuple


def parts_of(scene) -> SceneParts:
    """The `SceneParts` of a `RotorScene`."""
    return SceneParts(scene.full_rotor, scene.speed, tuple(scene.components))


def _get(obj, leaf):
    for step in leaf:
        obj = obj[step] if isinstance(step, int) else getattr(obj, step)
    return obj


def _index(index):
    """An index as JAX takes it (a tuple of ints within it: those entries)."""
    return tuple(np.asarray(i) if isinstance(i, tuple) else i for i in index)


def _entries(a, index):
    a = jnp.asarray(a)
    return a if index is None or a.ndim == 0 else a[_index(index)]


def _put(a, index, v):
    a = jnp.asarray(a)
    v = jnp.asarray(v, dtype=a.dtype)
    if index is None or a.ndim == 0:
        return jnp.broadcast_to(v, a.shape) if a.ndim else v
    return a.at[_index(index)].set(v)


def _node_position(parts, leaf, index, v):
    """Node `n`'s position `v` (m from node 0; `index`: the elements `(n - 1, n)` either
    side of it): their lengths, nodes `n - 1` and `n + 1` kept in place."""
    lengths = jnp.asarray(_get(parts, leaf))
    a, b = index[0]
    return jnp.stack([v - jnp.sum(lengths[:a]), jnp.sum(lengths[:b + 1]) - v])


def _shear_modulus(parts, leaf, index, v):
    """A material that gives `nu` and not `G`: `G` from `E` and `nu`."""
    r = parts.rotor
    return shear_modulus(_entries(r.E, index), _entries(r.nu, index))


def _poisson(parts, leaf, index, v):
    """A material that gives `G` and not `nu`: `nu` from `E` and `G`."""
    r = parts.rotor
    return poisson_ratio(_entries(r.E, index), _entries(r.G, index))


def _smoothing(parts, leaf, index, v):
    """A clearance bearing that leaves its smoothing out: the default from its clearance."""
    return ClearanceBearing.default_smoothing(_get(parts, leaf[:-1] + ("clearance",)))


#: what goes where the value itself does not (`Target.rule`): the quantities that follow others, each computed
#: by the function its owner builds it with, and what a position places; `(parts, leaf, index, value)`
RULES = {"shear_modulus": _shear_modulus, "poisson": _poisson, "smoothing": _smoothing,
         "node_position": _node_position}


def _apply(parts, target, v):
    if target.rule != "value":
        v = RULES[target.rule](parts, target.leaf, target.index, v)
    new = _put(_get(parts, target.leaf), target.index, v)
    return eqx.tree_at(lambda p: _get(p, target.leaf), parts, new)


def with_values(parts: SceneParts, paths, values) -> SceneParts:
    """`parts` with each `ParameterPath` of `paths` set to its entry of `values`
    (pure JAX)."""
    for path, v in zip(paths, values):
        if path.refusal:
            raise InputError(f"{path.name}: {path.refusal}")
        for t in path.targets:
            parts = _apply(parts, t, v)
    return parts


def value_of(parts: SceneParts, path: ParameterPath):
    """The parameter's value in `parts` (its first target's first entry; a position's:
    its node's position)."""
    t = path.targets[0]
    if t.rule == "node_position":
        return jnp.sum(jnp.asarray(_get(parts, t.leaf))[:t.index[0][1]])
    return jnp.ravel(_entries(_get(parts, t.leaf), t.index))[0]


def scene_from(parts: SceneParts, like):
    """A `RotorScene` like `like` (its reduction, `track_work`) built from `parts`."""
    from ._fe_reduction import ReducedRotor
    from ._rotor_scene import RotorScene

    rotor = parts.rotor
    if isinstance(like.rotor, ReducedRotor):
        rotor = ReducedRotor(rotor, like.rotor.n_modes)
    return RotorScene(rotor, parts.speed, parts.components, like.track_work)


def set_parameters(scene, paths, values):
    """`scene` (a `RotorScene`) with the parameters `paths` set to `values`, rebuilt
    (pure JAX: differentiable and vmappable in `values`)."""
    return scene_from(with_values(parts_of(scene), paths, values), scene)
