"""Issue 28: on an engineer's own rotor every answer is right or refused.

One rotor layout for the whole file (the user's: 36 dofs, tapered elements, two
speed-tabulated bearings, an unbalance of 2e-4 kg m at node 3, an operating speed
of 600 rad/s): `tapered_two_material.toml` with its unbalance moved and a speed
added. Each table row failed before the fix (the row says how)."""

import json
import os
import re
import subprocess
import sys

import numpy as np
import pytest

import rotorjax
from rotorjax.cli import main
from rotorjax.flexible import frf, unbalance_response_many
from rotorjax.io import load_rotor

SHIPPED = os.path.join(os.path.dirname(rotorjax.__file__), "rotors", "tapered_two_material.toml")


def _pump_text(unbalance=True):
    text = open(SHIPPED).read()
    text = text.replace('theory = "timoshenko"', 'theory = "timoshenko"\nspeed = 600.0', 1)
    old = "[[unbalance]]\nnode = 2\nmagnitude = 5e-4"
    assert old in text
    return text.replace(old, "[[unbalance]]\nnode = 3\nmagnitude = 2e-4") if unbalance else text[:text.index(old)]


@pytest.fixture(scope="module")
def rotors(tmp_path_factory):
    d = tmp_path_factory.mktemp("rotors")
    (d / "pump.toml").write_text(_pump_text())
    (d / "bare.toml").write_text(_pump_text(unbalance=False))   # no unbalance: disks at nodes 2 (15 kg), 6 (20 kg)
    return {"pump": str(d / "pump.toml"), "bare": str(d / "bare.toml")}


def _run(argv, tmp_path, capsys, code=0):
    rc = main([*argv, "--json", "--out", str(tmp_path)])
    cap = capsys.readouterr()
    assert rc == code, cap.err
    assert "Traceback" not in cap.err
    return json.loads(cap.out), cap.err


def _sub(argv, rotors):
    return [rotors.get(a[1:], a) if a.startswith("@") else a for a in argv]


# ---- item 1 and 5: what the file says is used (before: node 2, 1e-3 kg m, probe 2, speed 0) ----
USED = [
    (["response", "@pump", "--range", "10", "1500", "--n", "200"],
     {"node": 3, "unbalances": [{"node": 3, "magnitude": 2e-4, "phase": 0.0}], "unbalance_source": "the rotor file",
      "probe_source": "largest response"}),
    (["response", "@pump", "--range", "10", "1500", "--n", "200", "--unbalance", "1e-3"],
     {"node": 3, "unbalances": [{"node": 3, "magnitude": 1e-3, "phase": 0.0}]}),
    (["response", "@pump", "--range", "10", "1500", "--n", "200", "--phase", "0.5"],
     {"unbalances": [{"node": 3, "magnitude": 2e-4, "phase": 0.5}]}),
    (["response", "@pump", "--range", "10", "1500", "--n", "200", "--probe", "5"], {"probe": 5, "probe_source": "--probe"}),
    (["response", "@bare", "--range", "10", "1500", "--n", "200", "--unbalance", "1e-3"],
     {"node": 6, "unbalance_source": "--unbalance at the heaviest disk"}),
    (["modes", "@pump"], {"speed": 600.0, "speed_source": "[rotor] speed of the file"}),
    (["modes", "@pump", "--speed", "100"], {"speed": 100.0, "speed_source": "--speed"}),
    (["level1", "@pump", "--n", "5"], {"speed": 600.0, "speed_source": "[rotor] speed of the file"}),
]


@pytest.mark.parametrize("argv,expect", USED, ids=[" ".join(a[:5]) for a, _ in USED])
def test_the_rotor_file_is_used(argv, expect, rotors, tmp_path, capsys):
    out, _ = _run(_sub(argv, rotors), tmp_path, capsys)
    for key, value in expect.items():
        assert out[key] == value, key


def test_the_default_probe_is_the_node_of_largest_response(rotors, tmp_path, capsys):
    out, _ = _run(["response", rotors["pump"], "--range", "10", "1500", "--n", "200"], tmp_path, capsys)
    scene = load_rotor(rotors["pump"])
    X, Y = (np.asarray(a) for a in unbalance_response_many(scene, [(3, 2e-4, 0.0)], np.linspace(10, 1500, 200)))
    assert out["probe"] == int(np.argmax(np.max(np.abs(X) ** 2 + np.abs(Y) ** 2, axis=0)))


# ---- item 6: peaks located exactly (before: the grid's maximum, 23 % low on this rotor) ----
def _response_amplitude(scene, probe):
    def amp(w):
        X, Y = unbalance_response_many(scene, [(3, 2e-4, 0.0)], w, [probe])
        return np.sqrt(np.abs(np.asarray(X[:, 0])) ** 2 + np.abs(np.asarray(Y[:, 0])) ** 2)
    return amp


def _frf_magnitude(scene, probe):
    return lambda w: np.abs(np.asarray(frf(scene, (2, "x"), (4, "y"), w).values))


PEAKS = [
    (["response", "@pump", "--range", "10", "1500", "--n", "200"], "peaks", "peak_amplitudes", _response_amplitude),
    (["frf", "@pump", "--input", "2,x", "--output", "4,y", "--range", "10", "1200", "--n", "150"], "peaks",
     "peak_magnitudes", _frf_magnitude),
]


@pytest.mark.parametrize("argv,xkey,ykey,curve", PEAKS, ids=[a[0] for a, *_ in PEAKS])
def test_peaks_equal_a_fine_grid_maximum(argv, xkey, ykey, curve, rotors, tmp_path, capsys):
    out, _ = _run(_sub(argv, rotors), tmp_path, capsys)
    scene = load_rotor(rotors["pump"])
    f = curve(scene, out.get("probe"))
    lo, hi, n = float(argv[argv.index("--range") + 1]), float(argv[argv.index("--range") + 2]), \
        int(argv[argv.index("--n") + 1])
    step = (hi - lo) / (n - 1)
    assert out[xkey], "no peak found"
    grid_max = np.max(f(np.linspace(lo, hi, n)))
    for x, y in zip(out[xkey], out[ykey]):
        fine = np.linspace(x - step, x + step, 20001)
        top = np.max(f(fine))
        assert abs(y - top) <= 1e-6 * top, (x, y, top)
    if "max_amplitude" in out:
        assert out["max_amplitude"] == pytest.approx(max(out[ykey]), rel=1e-12)
        assert out["max_amplitude"] > 1.2 * grid_max   # the grid alone misses the top of the resonance here


# ---- item 3: plausibility warnings reach stderr and the JSON ----
def test_a_bearing_table_used_outside_its_speeds_is_a_warning(rotors, tmp_path, capsys):
    out, err = _run(["campbell", rotors["pump"], "--range", "0", "1500", "--n-speeds", "10"], tmp_path, capsys)
    assert len(out["warnings"]) == 2 and all("outside its table (0..1000 rad/s)" in w for w in out["warnings"])
    assert err.count("rotorjax: warning:") == 2
    with open(os.path.join(tmp_path, "campbell_pump.json")) as f:
        assert json.load(f)["warnings"] == out["warnings"]
    out, err = _run(["campbell", rotors["pump"], "--range", "0", "900", "--n-speeds", "10"], tmp_path, capsys)
    assert out["warnings"] == [] and "warning" not in err


# ---- item 7: any grid length, bounded memory, a few compiled programs ----
def test_chunked_evaluation_equals_one_call(rotors):
    from rotorjax.flexible import campbell
    from rotorjax.sweep import bucket_size, map_chunked

    scene = load_rotor(rotors["pump"])
    speeds = np.linspace(0.0, 1000.0, 37)
    whole = np.asarray(campbell(scene, speeds, 4).frequencies)
    parts = map_chunked(lambda s, sc: campbell(sc, s, 4).frequencies, speeds, scene, chunk=16)
    np.testing.assert_allclose(parts, whole, rtol=1e-12)
    assert [bucket_size(n) for n in (1, 17, 100, 2000, 10**9)] == [16, 32, 128, 2048, 2048]


# ---- item 8: the persistent compilation cache ----
def test_the_cli_uses_a_persistent_compilation_cache(monkeypatch, tmp_path):
    import jax

    from rotorjax._config import enable_compilation_cache

    names = ("jax_compilation_cache_dir", "jax_persistent_cache_min_compile_time_secs",
             "jax_persistent_cache_min_entry_size_bytes")
    before = {name: getattr(jax.config, name) for name in names}
    try:
        monkeypatch.setenv("ROTORJAX_NO_COMPILATION_CACHE", "1")
        assert enable_compilation_cache() is None
        monkeypatch.delenv("ROTORJAX_NO_COMPILATION_CACHE")
        monkeypatch.setenv("ROTORJAX_CACHE_DIR", str(tmp_path / "cache"))
        assert enable_compilation_cache() == str(tmp_path / "cache")
        assert jax.config.jax_compilation_cache_dir == str(tmp_path / "cache") and (tmp_path / "cache").is_dir()
    finally:
        for name, value in before.items():
            jax.config.update(name, value)


def test_importing_rotorjax_turns_off_the_cpu_scheduler_that_deadlocked_unless_the_user_set_it():
    """`rotorjax._config` adds the XLA option to `XLA_FLAGS` (a vmapped gradient
    through many eigenvalue solves deadlocked with XLA's concurrency-optimised CPU
    scheduler on: `tests/design/test_design.py`'s separation-constrained search hung
    every run), and keeps the user's own setting of that option."""
    code = "import os, rotorjax; print(os.environ['XLA_FLAGS'])"
    for given, want in [("", "--xla_cpu_enable_concurrency_optimized_scheduler=false"),
                        ("--xla_cpu_enable_concurrency_optimized_scheduler=true",
                         "--xla_cpu_enable_concurrency_optimized_scheduler=true")]:
        env = {**os.environ, "XLA_FLAGS": given}
        out = subprocess.run([sys.executable, "-c", code], env=env, capture_output=True, text=True, check=True)
        assert out.stdout.split() == [want]


_POOL = """
import collections, os, sys
import rotorjax, jax
names = collections.Counter(open(f"/proc/self/task/{t}/comm").read().strip() for t in os.listdir("/proc/self/task"))
every = os.sched_getaffinity(0)
print(names["tf_XLAEigen"], len(every), all(os.sched_getaffinity(int(t)) == every for t in os.listdir("/proc/self/task")))
"""

# six batched Cholesky factorisations side by side (one program, 1024 matrices of 20 x 20 each), with XLA's
# concurrency-optimised scheduler on: on 2 cores with XLA's own thread pool it hung every run of 5
_CHOLESKY = """
import numpy as np
import rotorjax, jax, jax.numpy as jnp
A = np.random.default_rng(0).normal(size=(1024, 20, 20))
A = A @ A.transpose(0, 2, 1) + 20 * np.eye(20)
f = jax.jit(jax.vmap(lambda a: sum(jnp.linalg.cholesky(a + i).sum() for i in range(6))))
for r in range(10):
    f(A + r).block_until_ready()
print("done")
"""


@pytest.mark.skipif(not sys.platform.startswith("linux"), reason="thread affinity and /proc: Linux")
def test_importing_rotorjax_starts_the_cpu_backend_with_one_intra_op_thread_and_every_cpu():
    """`rotorjax._config` starts XLA's CPU backend while its thread may run on one
    CPU (one intra-op thread), then gives every thread back the process's CPUs;
    `ROTORJAX_CPU_THREADS=all` keeps XLA's pool (one thread per CPU)."""
    def run(**env):
        out = subprocess.run([sys.executable, "-c", _POOL], env={**os.environ, **env}, capture_output=True,
                             text=True, check=True, timeout=120)
        return out.stdout.split()
    pool, cpus, same = run()
    assert (pool, same) == ("1", "True")
    pool, cpus, same = run(ROTORJAX_CPU_THREADS="all")
    assert (pool, same) == (cpus, "True")


@pytest.mark.skipif(not sys.platform.startswith("linux"), reason="thread affinity: Linux")
def test_batched_lapack_calls_side_by_side_finish():
    """jaxlib 0.10.2 splits a batched LAPACK call across XLA's intra-op pool and
    blocks its thread on the parts; with as many such calls at once as the pool has
    threads, every thread waited for ever (the Monte Carlo's secant path over 128
    samples hung CI). Here six batched Cholesky factorisations side by side, with
    XLA's concurrency-optimised scheduler on (which had hidden the case): with
    rotorjax's one intra-op thread they finish."""
    env = {**os.environ, "XLA_FLAGS": "--xla_cpu_enable_concurrency_optimized_scheduler=true"}
    out = subprocess.run([sys.executable, "-c", _CHOLESKY], env=env, capture_output=True, text=True, timeout=300)
    assert out.stdout.split() == ["done"], out.stderr[-2000:]


# ---- item 9: small defects ----
def test_a_closed_pipe_is_not_an_error():
    proc = subprocess.run(f"{sys.executable} -m rotorjax.cli presets | head -1", shell=True, capture_output=True,
                          text=True, timeout=120)
    assert proc.stdout.count("\n") == 1 and proc.stderr == "", proc.stderr


def test_ucs_numbers_modes_from_zero_like_modes(rotors, tmp_path, capsys):
    assert main(["ucs", rotors["pump"], "--n", "12", "--out", str(tmp_path)]) == 0
    text = capsys.readouterr().out
    with open(os.path.join(tmp_path, "ucs_pump.json")) as f:
        modes = [i["mode"] for i in json.load(f)["intersections"]]
    printed = [int(m) for m in re.findall(r"mode (\d+) meets", text)]
    assert printed == modes and min(printed) == 0


def test_python_finds_the_shipped_rotor_files_by_name():
    from rotorjax.identify._fe_params import rotor_model

    assert load_rotor("flexible_rig.toml").n_nodes == 7
    assert rotor_model("flexible_rig.toml").label == "flexible_rig.toml"


def test_the_readme_documents_critical_speed_as_it_is():
    import inspect

    from rotorjax.flexible import critical_speed

    from .helpers import documentation

    readme = documentation()
    documented = re.findall(r"`critical_speed\(([^)]*)\)`", readme)
    assert documented, "the README no longer documents critical_speed"
    params = ", ".join(str(p) for p in inspect.signature(critical_speed).parameters.values())
    assert all(d == params for d in documented), (documented, params)
