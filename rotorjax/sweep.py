"""Evaluate a per-point function over a parameter grid with vmap."""

import dataclasses
import math
from typing import Callable

import equinox as eqx
import jax
import jax.numpy as jnp
import numpy as np

from .models._validate import InputError, as_count, check_choice, show


@dataclasses.dataclass(frozen=True)
class SweepResult:
    """Labelled values of a sweep.

    - `axes`: `{name: 1-D values}` (product grids: one axis per name, in order;
      zipped grids: a single axis `"point"` and `points` holds the values).
    - `points`: `{name: values}` at every grid point, shaped `shape`.
    - `values`: the function's output pytree, each leaf shaped `shape + leaf_shape`.
    - `shape`: the grid's shape.
    """

    axes: dict
    points: dict
    values: object
    shape: tuple

    def __getitem__(self, key):
        return self.values[key]


def _grid(grid: dict, mode: str):
    check_choice("mode", mode, ("product", "zip"))
    if not isinstance(grid, dict) or not grid:
        raise InputError(f"grid must be a non-empty dict {{name: array of values}}, got {show(grid)}")
    arrays = {}
    for name, v in grid.items():
        if not isinstance(name, str):
            raise InputError(f"grid names must be strings, got {name!r}")
        try:
            a = np.asarray(v, dtype=np.float64)
        except (TypeError, ValueError):
            raise InputError(f"grid[{name!r}] must be an array of numbers, got {show(v)}") from None
        if mode == "product" and a.ndim != 1:
            raise InputError(f"grid[{name!r}] must be 1-D for a product grid, got shape {a.shape}")
        if a.ndim == 0 or a.shape[0] == 0:
            raise InputError(f"grid[{name!r}] must hold at least one value, got shape {a.shape}")
        if not np.all(np.isfinite(a)):
            bad = np.flatnonzero(~np.isfinite(a.reshape(-1)))
            raise InputError(f"grid[{name!r}] must be finite, got {a.reshape(-1)[bad[0]]} at index {int(bad[0])}")
        arrays[name] = a
    if mode == "product":
        shape = tuple(a.shape[0] for a in arrays.values())
        mesh = np.meshgrid(*arrays.values(), indexing="ij")
        points = {k: m for k, m in zip(arrays, mesh)}
        return arrays, points, shape
    shapes = {k: a.shape[0] for k, a in arrays.items()}
    if len(set(shapes.values())) != 1:
        raise InputError(f"zipped grid arrays must have equal length, got {shapes}")
    n = next(iter(shapes.values()))
    return {"point": np.arange(n)}, arrays, (n,)


def sweep(
    fn: Callable,
    grid: dict,
    mode: str = "product",
    chunk_size: int | None = 256,
    progress: bool | None = None,
    shard: bool = False,
) -> SweepResult:
    """Evaluate `fn(point)` at every point of `grid`, vmapped.

    **Arguments:**
    - `fn`: takes `{name: scalar}` for one point, returns a pytree of arrays. Pure,
      unbatched: write it for one point, `sweep` lifts it.
    - `grid`: `{name: values}`.
    - `mode`: `"product"` (cartesian grid over the named axes) or `"zip"` (equal-length
      arrays, one point per index).
    - `chunk_size`: points per vmapped call, to bound memory (`None`: all at once).
      Smaller chunks also group neighbouring points, which cuts the lock-step cost
      of adaptive solvers under vmap. The last chunk is padded, so one compilation.
    - `progress`: show a tqdm bar (default: when there is more than one chunk).
    - `shard`: split each chunk over all local devices (`jax.sharding`); the chunk
      is padded to a multiple of the device count.

    **Returns:** a `SweepResult` whose `values` leaves have the grid's shape in front.
    """
    if not callable(fn):
        raise InputError(f"fn must be a function of one grid point, got {fn!r}")
    axes, points, shape = _grid(grid, mode)
    total = math.prod(shape)
    flat = {k: jnp.asarray(v.reshape(-1)) for k, v in points.items()}
    chunk_size = total if chunk_size is None else as_count("chunk_size", chunk_size, minimum=1)
    chunk = min(chunk_size, total)
    sharding = None
    if shard:
        devices = jax.local_devices()
        nd = len(devices)
        chunk = int(math.ceil(chunk / nd) * nd)
        mesh = jax.sharding.Mesh(np.array(devices), ("points",))
        sharding = jax.sharding.NamedSharding(mesh, jax.sharding.PartitionSpec("points"))
    n_chunks = int(math.ceil(total / chunk))
    batched = eqx.filter_jit(eqx.filter_vmap(fn))

    starts = range(0, n_chunks * chunk, chunk)
    if progress is None:
        progress = n_chunks > 1
    if progress:
        from tqdm.auto import tqdm

        starts = tqdm(starts, total=n_chunks, desc="sweep", unit="chunk")
    outs = []
    for s in starts:
        idx = np.minimum(np.arange(s, s + chunk), total - 1)  # pad by repeating the last point
        part = {k: v[idx] for k, v in flat.items()}
        if sharding is not None:
            part = jax.device_put(part, sharding)
        outs.append(jax.tree_util.tree_map(np.asarray, batched(part)))
    values = jax.tree_util.tree_map(
        lambda *xs: np.concatenate(xs, axis=0)[:total].reshape(shape + xs[0].shape[1:]), *outs
    )
    return SweepResult(axes=axes, points=points, values=values, shape=shape)
