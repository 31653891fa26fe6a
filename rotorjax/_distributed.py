"""Split a sweep's flattened grid over the processes of a `jax.distributed` run, and
gather the parts back.

A multi-process run is JAX's own: every process calls
`jax.distributed.initialize(...)` before any JAX computation, then runs the same
script. `local_range` gives each process one contiguous slice of the grid's points;
`gather` all-gathers the evaluated slices (`process_allgather`) so that every process
ends with the whole result, in grid order.

On CPU the cross-process collectives need `jax_cpu_collectives_implementation =
"gloo"`, set before `jax.distributed.initialize` (the default in recent jax; older
versions need `jax.config.update("jax_cpu_collectives_implementation", "gloo")`).

With a single process (`jax.distributed` not initialized, or initialized with
`num_processes=1`) the slice is the whole grid and `gather` returns its input: a
distributed sweep is then exactly the ordinary one.

`on_each_device` runs one part of a batch on each of this process's devices.
"""

import os
from concurrent.futures import ThreadPoolExecutor

import jax
import numpy as np

from .models._validate import InputError, as_count

#: environment variables in which launchers state how many processes they started
#: (srun, Open MPI's mpirun, MPICH / Intel MPI)
_LAUNCH_SIZE = ("SLURM_STEP_NUM_TASKS", "OMPI_COMM_WORLD_SIZE", "PMI_SIZE")


def local_range(total: int, process_index: int | None = None, process_count: int | None = None) -> tuple:
    """The contiguous slice `[start, stop)` of `total` flattened grid points that one
    process evaluates. Balanced: slices differ by at most one point, the earlier
    processes taking the remainder; slice `p` comes before slice `p + 1`.

    **Arguments:**
    - `total`: number of points.
    - `process_index`, `process_count`: this process and the number of processes
      (default: `jax.process_index()`, `jax.process_count()`).

    **Returns:** `(start, stop)`; empty (`start == stop`) when `total < process_count`
    and this process is past the last point.
    """
    total = as_count("total", total, minimum=0)
    count = as_count("process_count", jax.process_count() if process_count is None else process_count)
    index = as_count("process_index", jax.process_index() if process_index is None else process_index,
                     minimum=0, maximum=count - 1)
    base, extra = divmod(total, count)
    start = index * base + min(index, extra)
    return start, start + base + (index < extra)


def _pad(tree, length: int):
    """Each leaf (a numpy array, leading axis = local points) padded with zeros to
    `length` points along its leading axis."""
    def pad(x):
        x = np.asarray(x)
        return np.concatenate([x, np.zeros((length - x.shape[0],) + x.shape[1:], x.dtype)], axis=0)
    return jax.tree_util.tree_map(pad, tree)


def _unpad(stacked, total: int, process_count: int):
    """The inverse of padding and stacking: leaves shaped `(process_count, length, ...)`
    (row `p`: process `p`'s padded slice) -> leaves shaped `(total, ...)` in grid order."""
    sizes = [stop - start for start, stop in
             (local_range(total, p, process_count) for p in range(process_count))]

    def unpad(x):
        x = np.asarray(x)
        return np.concatenate([x[p, :n] for p, n in enumerate(sizes)], axis=0)
    return jax.tree_util.tree_map(unpad, stacked)


def gather(tree, total: int):
    """The whole result from each process's part, on every process.

    **Arguments:**
    - `tree`: a pytree of numpy arrays whose leading axis is this process's points,
      `local_range(total)`. Every process must call `gather` (a collective), with the
      same tree structure, trailing shapes and dtypes.
    - `total`: number of points over all processes.

    **Returns:** the same pytree with leading axis `total`, the processes' parts
    concatenated in process order (that is, grid order).
    """
    count = jax.process_count()
    start, stop = local_range(total)
    for leaf in jax.tree_util.tree_leaves(tree):
        if np.shape(leaf)[:1] != (stop - start,):
            raise InputError(f"gather: every leaf must have this process's {stop - start} points "
                             f"in front, got shape {np.shape(leaf)}")
    if count == 1:
        return jax.tree_util.tree_map(np.asarray, tree)
    from jax.experimental import multihost_utils

    length = -(-total // count)  # the largest slice: process 0's
    stacked = multihost_utils.process_allgather(_pad(tree, length), tiled=False)
    return _unpad(stacked, total, count)


def check_initialized() -> None:
    """Raise `InputError` if a launcher started several processes but
    `jax.distributed` was not initialized: each process would otherwise evaluate
    the whole grid on its own. One process, initialized or not, is fine."""
    if jax.process_count() > 1 or jax.distributed.is_initialized():
        return
    for var in _LAUNCH_SIZE:
        try:
            n = int(os.environ.get(var, "1"))
        except ValueError:
            continue
        if n > 1:
            raise InputError(
                f"distributed=True: {var}={n} says {n} processes were launched, but jax.distributed "
                "is not initialized, so each would evaluate the whole grid. Call "
                "jax.distributed.initialize() first (with no arguments under SLURM or Open MPI), "
                "before any JAX computation; on CPU set "
                'jax.config.update("jax_cpu_collectives_implementation", "gloo") before it.')


def on_each_device(fn, parts) -> list:
    """`fn(*part)` for each of `parts` on its own local device (part `i` on device
    `i`), all at once. Each call is its own single-device program, and no collective
    joins them: a batch split by `jax.sharding` all-reduces its vmapped while loops'
    stopping tests at every step (on host CPU devices that rendezvous can hang), and
    `pmap` would span the processes of a distributed run. Known limit (XLA's CPU
    runtime, see README): two host devices running at once a program with both an
    adaptive integration and a LAPACK call can hang. -> the outputs, as numpy
    arrays, in the order of `parts`."""
    devices = jax.local_devices()
    if len(parts) > len(devices):
        raise ValueError(f"{len(parts)} parts for {len(devices)} local devices")

    def run(part, device):
        moved = jax.tree_util.tree_map(
            lambda a: jax.device_put(a, device) if isinstance(a, (jax.Array, np.ndarray)) else a, part)
        return jax.tree_util.tree_map(np.asarray, fn(*moved))

    if len(parts) == 1:
        return [run(parts[0], devices[0])]
    # a thread per device: a call may block until its result is ready (equinox's
    # `filter_jit` does), and the devices must run at once
    with ThreadPoolExecutor(max_workers=len(parts)) as pool:
        return list(pool.map(run, parts, devices[:len(parts)]))
