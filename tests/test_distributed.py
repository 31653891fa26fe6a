"""sweep(..., distributed=True): the grid split over `jax.distributed` processes and
gathered back, checked against the single-process sweep (two real processes on
localhost, CPU, gloo collectives)."""

import os
import socket
import subprocess
import sys
import textwrap

import jax
import jax.numpy as jnp
import numpy as np
import pytest

import rotorjax as rj
from rotorjax import _distributed as dist
from rotorjax.models._validate import InputError

GRID = {"a": np.linspace(0.0, 1.0, 5), "b": np.array([-1.0, 0.5, 2.0])}  # 15 points: 8 + 7


def f(p):
    a, b = p["a"], p["b"]
    return {"s": jnp.sin(a) * b + a ** 2, "v": jnp.stack([a, b, a * b]), "i": jnp.int32(3) * (b > 0)}


IVP_GRID = {"a": np.linspace(0.0, 1.0, 5)}  # 5 simulations: 3 + 2, each process's share over its 2 devices


def ivp(p):
    from rotorjax.presets import anisotropic_abb as ab

    P = dict(ab.PRESET.defaults)
    scene = ab.scene_from_groups(**{k: P[k] for k in ab.GROUPS}, n=1.0 + 4.0 * p["a"], K=P["K"])
    return rj.IVP(scene, jnp.asarray(ab.PRESET.build(P).y0), (0.0, 5.0), saveat=3, solver="dopri8",
                  rtol=1e-8, atol=1e-11)


#: each process: initialize, sweep (plain and sharded over its 2 local devices), save
WORKER = textwrap.dedent("""
    import sys
    import jax
    jax.config.update("jax_cpu_collectives_implementation", "gloo")
    port, pid, out = sys.argv[1], int(sys.argv[2]), sys.argv[3]
    jax.distributed.initialize(coordinator_address=f"localhost:{port}", num_processes=2, process_id=pid)
    import numpy as np
    import rotorjax as rj
    sys.path.insert(0, sys.argv[4])
    from test_distributed import GRID, f
    assert jax.process_count() == 2 and len(jax.local_devices()) == 2
    for name, kw in [("plain", {}), ("shard", {"shard": True}), ("tiny", {})]:
        grid = {"a": [0.5]} if name == "tiny" else GRID  # tiny: 1 point, process 1 holds none
        fn = (lambda p: {"x": p["a"] * 2.0}) if name == "tiny" else f
        res = rj.sweep(fn, grid, chunk_size=3, distributed=True, **kw)
        np.savez(f"{out}/{name}{pid}.npz", **res.values)
    from test_distributed import IVP_GRID, ivp  # simulations: the buffered batch, each device its own program
    res = rj.sweep(ivp, IVP_GRID, distributed=True, shard=True, lanes=2)
    np.savez(f"{out}/ivp{pid}.npz", ys=res.values.ys, code=res.values.code)
""")


def _free_port():
    with socket.socket() as s:
        s.bind(("localhost", 0))
        return s.getsockname()[1]


def test_two_processes_equal_single_process(tmp_path):
    env = {k: v for k, v in os.environ.items() if not k.startswith(("SLURM_", "OMPI_", "PMI_"))}
    env.update(JAX_PLATFORMS="cpu",  # two host devices; one thread each (see README: the Eigen pool can hang)
               XLA_FLAGS="--xla_force_host_platform_device_count=2 --xla_cpu_multi_thread_eigen=false")
    port = _free_port()
    procs = [subprocess.Popen([sys.executable, "-c", WORKER, str(port), str(i), str(tmp_path),
                               os.path.dirname(__file__)],
                              env=env, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
             for i in range(2)]
    try:
        outs = [p.communicate(timeout=120) for p in procs]
    finally:
        for p in procs:
            p.kill()
    for i, (p, (_, err)) in enumerate(zip(procs, outs)):
        assert p.returncode == 0, f"process {i} failed ({p.returncode}):\n{err[-4000:]}"

    ref = rj.sweep(f, GRID, chunk_size=3)
    for name in ("plain", "shard"):
        for i in range(2):
            got = np.load(tmp_path / f"{name}{i}.npz")
            assert set(got.files) == {"s", "v", "i"}
            for k in got.files:
                assert got[k].dtype == ref[k].dtype and got[k].shape == ref[k].shape, (name, i, k)
                np.testing.assert_array_equal(got[k], ref[k], err_msg=f"{name}, process {i}, {k}")
    one = rj.sweep(ivp, IVP_GRID).values  # the same simulations in one process, on one device
    for i in range(2):
        got = np.load(tmp_path / f"ivp{i}.npz")
        np.testing.assert_array_equal(got["code"], 0)
        # to the tolerance (rtol 1e-8), as every batch split: the lanes' widths differ (2 per device here, 5
        # in one process), and the compiled code for another width may round differently, which can move a
        # step-size decision (measured 1.1e-9 of the largest state)
        np.testing.assert_allclose(got["ys"], one.ys, rtol=0, atol=1e-7 * float(np.max(np.abs(one.ys))))
    # grid order: v holds the point itself
    got = np.load(tmp_path / "plain1.npz")
    np.testing.assert_array_equal(got["v"][..., 0], np.broadcast_to(GRID["a"][:, None], (5, 3)))
    np.testing.assert_array_equal(got["v"][..., 1], np.broadcast_to(GRID["b"][None, :], (5, 3)))
    for i in range(2):
        np.testing.assert_array_equal(np.load(tmp_path / f"tiny{i}.npz")["x"], [1.0])


@pytest.mark.parametrize("total,count", [(15, 2), (7, 3), (9, 3), (2, 4), (0, 2), (1, 1)])
def test_local_range_splits(total, count):
    ranges = [dist.local_range(total, p, count) for p in range(count)]
    sizes = [b - a for a, b in ranges]
    assert ranges[0][0] == 0 and ranges[-1][1] == total
    assert all(ranges[p][1] == ranges[p + 1][0] for p in range(count - 1))  # contiguous, in order
    assert sum(sizes) == total and max(sizes) - min(sizes) <= 1
    assert sizes == sorted(sizes, reverse=True)  # earlier processes take the remainder


def test_local_range_values_and_errors():
    assert [dist.local_range(7, p, 3) for p in range(3)] == [(0, 3), (3, 5), (5, 7)]
    assert dist.local_range(10) == (0, 10)  # this process, alone
    with pytest.raises(InputError, match="process_index"):
        dist.local_range(5, 2, 2)
    with pytest.raises(InputError, match="process_count"):
        dist.local_range(5, 0, 0)


def test_pad_and_unpad_uneven_parts():
    """What `gather` does around the all-gather, with the all-gather done by hand:
    7 points over 3 processes (3, 2, 2), leaves of several shapes and dtypes."""
    total, count = 7, 3
    full = {"s": np.arange(7.0), "v": np.arange(14).reshape(7, 2), "m": np.arange(7) % 2 == 0}
    length = dist.local_range(total, 0, count)[1]
    parts = [jax.tree_util.tree_map(lambda x: x[slice(*dist.local_range(total, p, count))], full)
             for p in range(count)]
    padded = [dist._pad(part, length) for part in parts]
    assert all(x.shape[0] == length for pad in padded for x in jax.tree_util.tree_leaves(pad))
    stacked = jax.tree_util.tree_map(lambda *xs: np.stack(xs), *padded)
    back = dist._unpad(stacked, total, count)
    for k in full:
        assert back[k].dtype == full[k].dtype
        np.testing.assert_array_equal(back[k], full[k])


def test_gather_single_process():
    tree = {"s": np.arange(4.0), "v": np.ones((4, 3))}
    out = dist.gather(tree, 4)
    np.testing.assert_array_equal(out["v"], tree["v"])
    with pytest.raises(InputError, match="4 points"):
        dist.gather({"s": np.arange(3.0)}, 4)


@pytest.mark.parametrize("kw", [{}, {"chunk_size": 4}, {"chunk_size": None, "mode": "zip"}])
def test_single_process_distributed_is_the_plain_sweep(kw):
    grid = {"a": np.linspace(0, 1, 3), "b": np.linspace(-1, 1, 3)} if kw.get("mode") == "zip" else GRID
    a = rj.sweep(f, grid, **kw)
    b = rj.sweep(f, grid, distributed=True, **kw)
    assert b.shape == a.shape
    for k in a.values:
        np.testing.assert_array_equal(b[k], a[k])


def test_launched_but_not_initialized(monkeypatch):
    monkeypatch.setenv("SLURM_STEP_NUM_TASKS", "4")
    with pytest.raises(InputError, match="jax.distributed.initialize"):
        rj.sweep(f, GRID, distributed=True)
    rj.sweep(f, GRID)  # without distributed: each process sweeps the whole grid, as asked
