"""sweep: grids, chunking, labels, errors, sharding."""

import os
import subprocess
import sys

import jax.numpy as jnp
import numpy as np
import pytest

import rotorjax as rj


def f(point):
    return {"s": point["a"] * 10 + point["b"], "v": jnp.stack([point["a"], point["b"]])}


def test_product_grid_shapes_and_labels():
    res = rj.sweep(f, {"a": np.arange(3.0), "b": np.arange(4.0)}, chunk_size=5)
    assert res.shape == (3, 4)
    assert res["s"].shape == (3, 4) and res["v"].shape == (3, 4, 2)
    np.testing.assert_array_equal(res["s"], np.arange(3.0)[:, None] * 10 + np.arange(4.0)[None, :])
    np.testing.assert_array_equal(res.axes["a"], np.arange(3.0))
    np.testing.assert_array_equal(res.points["b"][2], np.arange(4.0))


def test_chunked_equals_unchunked():
    grid = {"a": np.linspace(0, 1, 7), "b": np.linspace(-1, 1, 3)}
    a = rj.sweep(f, grid, chunk_size=None)
    b = rj.sweep(f, grid, chunk_size=4, progress=True)
    np.testing.assert_array_equal(a["s"], b["s"])


def test_zip_grid():
    res = rj.sweep(f, {"a": [1.0, 2.0], "b": [5.0, 6.0]}, mode="zip")
    np.testing.assert_array_equal(res["s"], [15.0, 26.0])


@pytest.mark.parametrize("grid,mode,match", [
    ({"a": [1.0, 2.0], "b": [1.0]}, "zip", "equal length"),
    ({"a": [[1.0, 2.0]]}, "product", "must be 1-D"),
    ({"a": []}, "product", "at least one value"),
    ({"a": [np.nan]}, "product", "finite"),
    ({}, "product", "non-empty"),
    ({"a": [1.0]}, "diagonal", "mode"),
])
def test_bad_grids(grid, mode, match):
    with pytest.raises(ValueError, match=match):
        rj.sweep(f, grid, mode=mode)


def test_sweep_of_simulations():
    from rotorjax.presets import anisotropic_abb

    g = {k: anisotropic_abb.PRESET.defaults[k] for k in anisotropic_abb.GROUPS}

    def one(p):
        s = anisotropic_abb.scene_from_groups(**g, n=p["n"])
        r = rj.simulate(s, s.rest_state(np.array([2.2, 4.1])), (0.0, 10.0), solver="dopri8")
        return {"amp": r.outputs["whirl_amplitude"][-1], "code": r.code}

    res = rj.sweep(one, {"n": [1.5, 3.0, 4.5]}, chunk_size=2)
    assert np.all(res["code"] == 0) and np.all(res["amp"] > 0)


def test_sharded_over_four_host_devices():
    code = (
        "import numpy as np, rotorjax as rj, jax\n"
        "assert len(jax.local_devices()) == 4\n"
        "r = rj.sweep(lambda p: p['a'] ** 2, {'a': np.arange(10.0)}, chunk_size=6, shard=True)\n"
        "assert np.allclose(r.values, np.arange(10.0) ** 2), r.values\n"
        "print('ok')\n"
    )
    env = dict(os.environ, XLA_FLAGS="--xla_force_host_platform_device_count=4 --xla_cpu_multi_thread_eigen=false",
               JAX_PLATFORMS="cpu")
    out = subprocess.run([sys.executable, "-c", code], env=env, capture_output=True, text=True,
                         timeout=300)
    assert out.returncode == 0 and "ok" in out.stdout, out.stderr


def test_sweeping_a_function_again_does_not_compile_it_again():
    traced = []

    def f(p):
        traced.append(1)  # runs only while tracing: sweep's shape check, then compiling
        return p["a"] * 2.0

    np.testing.assert_array_equal(rj.sweep(f, {"a": np.arange(4.0)}).values, 2 * np.arange(4.0))
    n = len(traced)
    np.testing.assert_array_equal(rj.sweep(f, {"a": np.arange(4.0) + 1}).values, 2 * np.arange(4.0) + 2)
    assert len(traced) == n + 1  # the shape check alone
