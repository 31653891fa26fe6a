"""`rotorjax bench`: the headline comparisons, run on the user's own machine.

- the model-001 speed sweep against numba RK4 and scipy DOP853 loops,
- the model-001 Floquet stability map against a scipy loop,
- the Campbell diagram of ROSS's example rotor against ROSS,

each compared at matched error (a peer's cost read off its own ladder at rotorjax's
error), with the work-precision diagram drawn from the same numbers (`plot_bench`).
Peers that are not installed (numba, ROSS) are skipped with a note. `benchmarks/`
holds the larger studies these come from, and their measured results.

`run_bench(sizes, device, ...)` -> a JSON-ready dict; `QUICK`, `FULL`, `SMOKE` sizes.
"""

import datetime
import os
import platform

from ._campbell import campbell_comparison, campbell_rows, ross_python
from ._model001 import floquet_comparison, matched_rows, numba_available, sweep_comparison
from ._sizes import FULL, QUICK, SMOKE, Sizes

__all__ = ["run_bench", "resolve_device", "QUICK", "FULL", "SMOKE", "Sizes", "STAGES", "numba_available",
           "ross_python"]

#: the stages `run_bench` reports to `progress`, in order
STAGES = ("model 001 sweep: references", "model 001 sweep: rotorjax", "model 001 sweep: scipy",
          "model 001 sweep: numba", "Floquet map: references", "Floquet map: rotorjax", "Floquet map: scipy",
          "Campbell: rotorjax", "Campbell: ROSS")


def resolve_device(kind):
    """The first JAX device of `kind` ("cpu" or "gpu"); `ValueError` naming what JAX
    sees when there is none."""
    import jax

    if kind not in ("cpu", "gpu"):
        raise ValueError(f"device {kind!r}: expected cpu or gpu")
    try:
        devices = jax.devices(kind)
    except RuntimeError:
        devices = []
    if not devices:
        seen = sorted({d.platform for d in jax.devices()})
        raise ValueError(f"device {kind}: JAX sees no {kind} device here (it sees: {', '.join(seen)}); a GPU needs "
                         "a CUDA build of jax (pip install 'jax[cuda12]')")
    return devices[0]


def machine(device):
    import jax

    return {"platform": platform.platform(), "processor": platform.processor(), "cpu_count": os.cpu_count(),
            "jax": jax.__version__, "device": f"{device.platform}: {device.device_kind}",
            "date": datetime.datetime.now(datetime.timezone.utc).strftime("%Y-%m-%d %H:%M UTC")}


def run_bench(sizes=QUICK, device="cpu", ross_py=None, progress=None):
    """Run the three headline comparisons at `sizes` on the JAX `device` ("cpu" or
    "gpu"; the peers run on the CPU). `progress(stage)` is called as each of `STAGES`
    starts. Returns a dict: `machine`, `sizes`, `comparisons` (curves, notes, skipped
    peers, checks, per comparison) and `table` (the ratios at matched error: a peer's
    cost at rotorjax's error over rotorjax's cost)."""
    import dataclasses

    import jax

    dev = resolve_device(device)
    progress = progress or (lambda stage: None)
    with jax.default_device(dev):
        comps = [sweep_comparison(sizes, progress, sizes.repeats),
                 floquet_comparison(sizes, progress, sizes.repeats),
                 campbell_comparison(sizes, progress, sizes.repeats, ross_py)]
    for c in comps[:2]:
        c.rows = matched_rows(c)
    comps[2].rows = campbell_rows(comps[2])
    return {"machine": machine(dev), "sizes": dataclasses.asdict(sizes),
            "comparisons": [c.to_json() for c in comps], "table": [r for c in comps for r in c.rows]}
