"""Evaluate a per-point function over a parameter grid: vmapped, or, for a function that
returns an initial-value problem (`rotorjax.IVP`), integrated in one buffered batch."""

import dataclasses
import functools
import math
from typing import Callable

import equinox as eqx
import jax
import jax.numpy as jnp
import numpy as np

from ._distributed import check_initialized, gather, local_range, on_each_device
from .models._validate import InputError, as_count, check_choice, show
from .solve._batch import IVP, METHODS, compiler_option_pairs, simulate_batch


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
    distributed: bool = False,
    lanes: int | None = None,
    steps_per_round: int = 8,
    batch: str = "auto",
    compiler_options: dict | None = None,
) -> SweepResult:
    """Evaluate `fn(point)` at every point of `grid`, vmapped.

    **Arguments:**
    - `fn`: takes `{name: scalar}` for one point, returns a pytree of arrays. Pure,
      unbatched: write it for one point, `sweep` lifts it. A function that returns
      a `rotorjax.IVP(scene, y0, t_span, ...)` has the whole grid integrated by
      `rotorjax.solve.simulate_batch` (no lane waits for the slowest one) and the
      sweep's `values` are the batched `SimulationResult`.
    - `grid`: `{name: values}`.
    - `mode`: `"product"` (cartesian grid over the named axes) or `"zip"` (equal-length
      arrays, one point per index).
    - `chunk_size`: points per vmapped call, to bound memory (`None`: all at once).
      Smaller chunks also group neighbouring points, which cuts the lock-step cost
      of adaptive solvers under vmap. The last chunk is padded, so one compilation.
    - `progress`: show a tqdm bar (default: when there is more than one chunk, on
      process 0 only).
    - `shard`: split each chunk over all local devices, each running its share as
      its own program, all at once; the chunk is padded to a multiple of the
      device count.
    - `distributed`: split the grid over the processes of a `jax.distributed` run
      (call `jax.distributed.initialize()` first in every process; on CPU with
      `jax_cpu_collectives_implementation="gloo"`). Each process evaluates one
      contiguous slice of the points, chunk by chunk on its own local devices
      (`shard=True` still splits each chunk over them); the slices are then
      all-gathered, so every process returns the whole result, in grid order. With
      one process it is the ordinary sweep. Raises `InputError` if a launcher
      (srun, mpirun) started several processes but `jax.distributed` was not
      initialized.
    - `lanes`, `steps_per_round`, `batch`: for a function returning an `IVP` (see
      `simulate_batch`): points integrated at once (default `min(points, 128)`),
      steps between refills, and the method ("auto": "vectorised" for an explicit
      Runge-Kutta solver without events, else "buffered"; "vectorised",
      "buffered", "pallas", or "vmap": the lock-step `simulate` under vmap, chunk
      by chunk). `chunk_size` and `progress` apply to the "vmap" method and to
      other functions; `shard=True` gives each local device its own buffer of lanes.
    - `compiler_options`: XLA options for the compiled calls (see `simulate_batch`),
      e.g. `rotorjax.analysis.CPU_COMPILER_OPTIONS` for a function that differentiates
      a right-hand side forward (a Floquet margin) on the CPU.

    **Returns:** a `SweepResult` whose `values` leaves have the grid's shape in front.
    """
    if not callable(fn):
        raise InputError(f"fn must be a function of one grid point, got {fn!r}")
    axes, points, shape = _grid(grid, mode)
    total = math.prod(shape)
    flat = {k: jnp.asarray(v.reshape(-1)) for k, v in points.items()}
    chunk_size = total if chunk_size is None else as_count("chunk_size", chunk_size, minimum=1)
    if distributed:
        check_initialized()
    start, stop = local_range(total) if distributed else (0, total)  # this process's points
    # every process uses the chunk shape of the largest slice: one compilation
    chunk = min(chunk_size, -(-total // jax.process_count()) if distributed else total)
    nd = len(jax.local_devices()) if shard else 1
    chunk = int(math.ceil(chunk / nd) * nd)
    n_chunks = max(int(math.ceil((stop - start) / chunk)), 1)  # an empty slice still yields shapes
    check_choice("batch", batch, METHODS)
    if batch != "vmap" and isinstance(eqx.filter_eval_shape(fn, {k: v[0] for k, v in flat.items()}), IVP):
        values = _integrate(fn, flat, start, stop, lanes, steps_per_round, batch, shard, compiler_options)
        if distributed:
            values = gather(values, total)
        values = jax.tree_util.tree_map(lambda x: x.reshape(shape + x.shape[1:]), values)
        return SweepResult(axes=axes, points=points, values=values, shape=shape)
    batched = _vmapped(fn, simulated=True, options=compiler_option_pairs(compiler_options))

    starts = range(0, n_chunks * chunk, chunk)
    if progress is None:
        progress = n_chunks > 1 and jax.process_index() == 0
    if progress:
        from tqdm.auto import tqdm

        starts = tqdm(starts, total=n_chunks, desc="sweep", unit="chunk")
    outs = []
    for s in starts:
        idx = np.minimum(np.arange(start + s, start + s + chunk), stop - 1)  # pad: repeat the last point
        part = {k: v[idx] for k, v in flat.items()}
        if shard:  # each device its own share of the chunk
            per = chunk // nd
            shares = on_each_device(batched, [({k: v[i * per:(i + 1) * per] for k, v in part.items()},)
                                              for i in range(nd)])
            out = jax.tree_util.tree_map(lambda *xs: np.concatenate(xs, axis=0), *shares)
        else:
            out = jax.tree_util.tree_map(np.asarray, batched(part))
        outs.append(out)
    values = jax.tree_util.tree_map(lambda *xs: np.concatenate(xs, axis=0)[:stop - start], *outs)
    if distributed:
        values = gather(values, total)
    values = jax.tree_util.tree_map(lambda x: x.reshape(shape + x.shape[1:]), values)
    return SweepResult(axes=axes, points=points, values=values, shape=shape)


def _vmapped(fn, simulated, options=()):
    """`fn` vmapped and jitted (with the XLA `options`, pairs), the same object for the
    same `fn`, so that sweeping one function again does not compile it again."""
    try:
        return _vmapped_cached(fn, simulated, options)
    except TypeError:  # an unhashable callable (e.g. a module holding arrays)
        return _vmapped_cached.__wrapped__(fn, simulated, options)


@functools.lru_cache(maxsize=32)
def _vmapped_cached(fn, simulated, options=()):
    return eqx.filter_jit(eqx.filter_vmap(_simulated(fn) if simulated else fn), compiler_options=dict(options) or None)


def _simulated(fn):
    """`fn`, with an `IVP` it returns integrated by `simulate` (the lock-step path). A
    `Partial` rather than a closure: for an `fn` that holds arrays (an `eqx.Partial`,
    which `_vmapped` cannot cache), equal structures then share one compilation, the
    arrays being the program's inputs."""
    return eqx.Partial(_simulated_point, fn)


def _simulated_point(fn, point):
    out = fn(point)
    if isinstance(out, IVP):
        from .solve import simulate

        if out.events:
            from .solve import simulate_events

            return simulate_events(out.scene, out.y0, out.t_span, saveat=out.saveat or 2, solver=out.solver,
                                   rtol=out.rtol, atol=out.atol, max_steps=out.max_steps)
        return simulate(out.scene, out.y0, out.t_span, saveat=out.saveat, solver=out.solver,
                        rtol=out.rtol, atol=out.atol, max_steps=out.max_steps)
    return out


def _integrate(fn, flat, start, stop, lanes, steps_per_round, method, shard, compiler_options):
    """The points `[start, stop)` of `fn`'s initial-value problems, integrated in one batch
    (an empty slice integrates the last point once, for the shapes)."""
    idx = np.arange(start, stop) if stop > start else np.array([stop - 1])
    problems = _vmapped(fn, simulated=False)({k: v[idx] for k, v in flat.items()})
    res = simulate_batch(problems.scene, problems.y0, problems.t_span, saveat=problems.saveat,
                         solver=problems.solver, rtol=problems.rtol, atol=problems.atol,
                         max_steps=problems.max_steps, lanes=lanes, steps_per_round=steps_per_round,
                         method=method, shard=shard, events=problems.events, compiler_options=compiler_options)
    return jax.tree_util.tree_map(lambda x: np.asarray(x)[:stop - start], res)


#: points per compiled call of `map_chunked` (memory per call stays bounded)
CHUNK = 2048


def bucket_size(n: int, chunk: int = CHUNK) -> int:
    """The padded length of a call over `n` points: the next power of two (at least 16),
    at most `chunk`. Grids of any length then compile one of a few programs."""
    n = max(int(n), 1)
    return min(chunk, max(16, 1 << (n - 1).bit_length()))


def available_memory() -> int:
    """Bytes of memory available to this process now (`MemAvailable`; else the
    physical memory; else 4 GiB)."""
    import os

    try:
        with open("/proc/meminfo") as f:
            for line in f:
                if line.startswith("MemAvailable:"):
                    return int(line.split()[1]) * 1024
    except OSError:
        pass
    try:
        return int(os.sysconf("SC_PHYS_PAGES") * os.sysconf("SC_PAGE_SIZE"))
    except (ValueError, OSError, AttributeError):
        return 4 << 30


def largest_grid(bytes_per_point: float, fraction: float = 0.25) -> int:
    """The most points whose results (`bytes_per_point` each, as the caller keeps and
    writes them) fit in `fraction` of the memory available now."""
    return max(int(fraction * available_memory() // max(bytes_per_point, 1.0)), 1)


def check_grid_size(what: str, n: int, bytes_per_point: float):
    """Refuse, before any work, a grid of `n` points whose results would not fit in
    memory (`largest_grid`): an `InputError` naming `what` (the option as the user
    typed it) and the largest size this machine allows now."""
    most = largest_grid(bytes_per_point)
    if n > most:
        gib = n * bytes_per_point / 2**30
        raise InputError(f"{what} {n}: the results would need about {gib:.3g} GiB; this machine allows at most "
                         f"{most} points now (compute the range in parts)")
    return n


@eqx.filter_jit
def _call(fn, xs, args):
    return fn(xs, *args)


def map_chunked(fn: Callable, xs, *args, chunk: int = CHUNK, size: int | None = None):
    """`fn(xs, *args)` for a batched `fn` (one that takes a 1-D array of points and
    returns a pytree of arrays with the points in front, e.g. `campbell(rotor, speeds,
    n)`), evaluated over fixed-size chunks of `xs`: memory stays bounded whatever the
    length, and the chunks are padded to `bucket_size`, so any length compiles one of a
    few programs. `args` are traced arguments (a rotor is an argument, not a constant:
    one compilation per rotor layout). `size`: the call length (default
    `bucket_size(len(xs), chunk)`), to share one program between calls of different
    lengths. Returns numpy arrays."""
    xs = np.asarray(xs, dtype=np.float64)
    if xs.ndim != 1 or xs.size == 0:
        raise InputError(f"xs must be a non-empty 1-D array of points, got shape {xs.shape}")
    n = xs.shape[0]
    size = bucket_size(n, chunk) if size is None else as_count("size", size, minimum=1)
    outs = []
    for start in range(0, n, size):
        idx = np.minimum(np.arange(start, start + size), n - 1)  # pad: repeat the last point
        out = _call(fn, jnp.asarray(xs[idx]), args)
        outs.append(jax.tree_util.tree_map(lambda a: np.asarray(a)[: min(size, n - start)], out))
    return jax.tree_util.tree_map(lambda *a: np.concatenate(a, axis=0), *outs)
