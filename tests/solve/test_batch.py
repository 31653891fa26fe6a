"""Batched integration (`simulate_batch`, `rotorjax.IVP` through `sweep`): every point
equals its own `simulate` / `simulate_events`, whatever the buffer's size, the steps
per round, the method or the split over devices; results come back in grid order."""

import os
import subprocess
import sys

import equinox as eqx
import jax
import jax.numpy as jnp
import numpy as np
import pytest

import rotorjax as rj
from rotorjax.presets import anisotropic_abb as ab
from rotorjax.solve import simulate_batch, simulate_events

P = dict(ab.PRESET.defaults)
GROUPS = {k: P[k] for k in ab.GROUPS}
Y0 = jnp.asarray(ab.PRESET.build(P).y0)
SPEEDS = np.array([0.7, 2.0, 3.1, 4.4, 5.2, 6.0, 9.5])  # well-conditioned over t in [0, 20]
T = 20.0
TOLS = dict(rtol=1e-9, atol=1e-12)


def scene(n):
    return ab.scene_from_groups(**GROUPS, n=n, K=P["K"])


@pytest.fixture(scope="module")
def batch():
    scenes = eqx.filter_vmap(scene)(jnp.asarray(SPEEDS))
    return scenes, jnp.tile(Y0, (SPEEDS.size, 1))


@pytest.fixture(scope="module")
def singles():
    return [rj.simulate(scene(n), Y0, (0.0, T), saveat=5, solver="dopri8", **TOLS) for n in SPEEDS]


@pytest.fixture(scope="module")
def buffered(batch):
    # 3 lanes for 7 points: every lane is refilled at least once, the last round half empty
    return simulate_batch(*batch, (0.0, T), saveat=5, solver="dopri8", lanes=3, steps_per_round=5,
                          method="buffered", **TOLS)


@pytest.fixture(scope="module")
def vectorised(batch):
    return simulate_batch(*batch, (0.0, T), saveat=5, solver="dopri8", lanes=3, steps_per_round=5, **TOLS)


def test_each_point_equals_its_own_simulate(buffered, singles):
    assert buffered.solver == "Dopri8+buffered"
    assert buffered.ys.shape == (SPEEDS.size, 5, Y0.size) and buffered.ts.shape == (SPEEDS.size, 5)
    np.testing.assert_array_equal(buffered.code, 0)
    for i, r in enumerate(singles):
        scale = np.max(np.abs(np.asarray(r.ys)))
        np.testing.assert_allclose(buffered.ys[i], r.ys, rtol=0, atol=1e-7 * scale)
        np.testing.assert_allclose(buffered.outputs["whirl_amplitude"][i], r.outputs["whirl_amplitude"],
                                   rtol=1e-6, atol=1e-9)
        # the same solver and controller; only the first step differs (diffrax's
        # diffeqsolve starts at dt0 = 0.01, the buffer with diffrax's initial-step rule)
        steps = int(r.stats["num_steps"])
        assert abs(int(buffered.stats["num_steps"][i]) - steps) <= max(3, 0.02 * steps)
    s = buffered.stats
    np.testing.assert_array_equal(s["num_steps"], s["num_accepted_steps"] + s["num_rejected_steps"])


def test_leaves_equal_at_every_point_pass_once(batch):
    """A speed sweep's scene: the speed keeps its batch axis, every other array leaf
    (equal at every point) passes once, without it (`_split_shared`); the fixtures'
    batches above run through the split."""
    from rotorjax.solve._batch import _split_shared

    scenes, _ = batch
    varying, shared = _split_shared(scenes)
    kept = [a for a in jax.tree_util.tree_leaves(varying) if eqx.is_array(a)]
    assert len(kept) == 1 and np.array_equal(kept[0], SPEEDS)
    every = [a for a in jax.tree_util.tree_leaves(scenes) if eqx.is_array(a)]
    once = [a for a in jax.tree_util.tree_leaves(shared) if eqx.is_array(a)]
    assert len(once) == len(every) - 1 and all(a.shape == b.shape[1:] for a, b in zip(once, [
        b for b in every if not np.array_equal(b, SPEEDS)]))


def test_the_vectorised_stepper_is_diffrax_s_step(buffered, vectorised, singles):
    """The default ("auto") steps the lanes as arrays of lanes: the same method and
    controller, its sums in another order. The error estimate is a difference of
    nearly equal sums, so rounding moves the step sizes (1e-4 relative here): the
    trajectories agree to the tolerance, the step counts within a few."""
    assert vectorised.solver == "Dopri8+vectorised"
    np.testing.assert_array_equal(vectorised.code, 0)
    scale = float(np.max(np.abs(np.asarray(buffered.ys))))
    np.testing.assert_allclose(vectorised.ys[:, -1], buffered.ys[:, -1], rtol=0, atol=1e-9 * scale)
    np.testing.assert_allclose(vectorised.ys, buffered.ys, rtol=0, atol=1e-7 * scale)  # dense output
    steps, ref = np.asarray(vectorised.stats["num_steps"]), np.asarray(buffered.stats["num_steps"])
    assert np.all(np.abs(steps - ref) <= np.maximum(3, 0.02 * ref))
    for i, r in enumerate(singles):
        np.testing.assert_allclose(vectorised.ys[i], r.ys, rtol=0, atol=1e-7 * float(np.max(np.abs(r.ys))))


@pytest.mark.parametrize("lanes,steps_per_round", [(1, 1), (7, 64), (16, 3)])
def test_buffer_size_and_round_length_do_not_change_the_answer(batch, buffered, vectorised, lanes,
                                                               steps_per_round):
    r = simulate_batch(*batch, (0.0, T), saveat=5, solver="dopri8", lanes=lanes, steps_per_round=steps_per_round,
                       method="buffered", **TOLS)
    np.testing.assert_allclose(r.ys, buffered.ys, rtol=1e-12, atol=1e-14)
    np.testing.assert_array_equal(r.stats["num_steps"], buffered.stats["num_steps"])
    if lanes != 7:
        return
    # the vectorised stepper's code (so its rounding, amplified by the error estimate)
    # may depend on the number of lanes: equal to the tolerance, not to rounding
    r = simulate_batch(*batch, (0.0, T), saveat=5, solver="dopri8", lanes=lanes, steps_per_round=steps_per_round,
                       **TOLS)
    scale = float(np.max(np.abs(np.asarray(r.ys))))
    np.testing.assert_allclose(r.ys[:, -1], vectorised.ys[:, -1], rtol=0, atol=1e-9 * scale)
    np.testing.assert_allclose(r.ys, vectorised.ys, rtol=0, atol=1e-7 * scale)
    steps, ref = np.asarray(r.stats["num_steps"]), np.asarray(vectorised.stats["num_steps"])
    assert np.all(np.abs(steps - ref) <= np.maximum(3, 0.02 * ref))


@pytest.mark.parametrize("solver", ["heun"])  # not first-same-as-last, its dense output from the stages
def test_the_vectorised_stepper_runs_every_explicit_tableau(batch, solver):
    """Other tableaus (first-same-as-last or not, their own dense output) through both
    steppers: the same answers to the tolerance."""
    import diffrax

    s = diffrax.Heun() if solver == "heun" else solver
    kw = dict(saveat=4, solver=s, lanes=4, rtol=1e-7, atol=1e-10)
    a = simulate_batch(*batch, (0.0, 2.0), method="buffered", **kw)
    b = simulate_batch(*batch, (0.0, 2.0), **kw)
    assert b.solver.endswith("+vectorised") and a.solver.endswith("+buffered")
    np.testing.assert_array_equal(b.code, 0)
    np.testing.assert_allclose(b.ys, a.ys, rtol=0, atol=1e-5 * float(np.max(np.abs(np.asarray(a.ys)))))
    steps, ref = np.asarray(b.stats["num_steps"]), np.asarray(a.stats["num_steps"])
    assert np.all(np.abs(steps - ref) <= np.maximum(3, 0.02 * ref))


def _to_tolerance(a, b):
    """The vectorised stepper's results across buffers: equal to the tolerance (see
    the test above)."""
    np.testing.assert_allclose(a, b, rtol=0, atol=1e-7 * float(np.max(np.abs(np.asarray(b)))))


def test_final_state_only_is_the_last_saved_state(batch, vectorised):
    ref = vectorised
    r = simulate_batch(*batch, (0.0, T), solver="dopri8", lanes=3, **TOLS)
    assert r.ys.shape == (SPEEDS.size, 1, Y0.size)
    np.testing.assert_allclose(r.ys[:, 0], ref.ys[:, -1], rtol=1e-12, atol=1e-14)  # the same lanes: the same steps
    np.testing.assert_array_equal(r.ts[:, 0], T)


def test_a_point_out_of_steps_is_marked_and_the_others_finish(batch, vectorised):
    ref = vectorised
    steps = np.asarray(ref.stats["num_steps"])
    hardest = int(np.argmax(steps))
    budget = int(np.sort(steps)[-2]) + 5  # all but the hardest finish
    assert budget < steps[hardest]
    r = simulate_batch(*batch, (0.0, T), saveat=5, solver="dopri8", lanes=2, max_steps=budget, **TOLS)
    assert int(r.code[hardest]) == 1 and np.all(np.isinf(r.ys[hardest, -1]))
    others = np.arange(SPEEDS.size) != hardest
    np.testing.assert_array_equal(r.code[others], 0)
    _to_tolerance(r.ys[others], ref.ys[others])
    assert "max_steps" in r.message


def test_lock_step_path_and_pallas_kernel_agree(batch, buffered):
    vm = simulate_batch(*batch, (0.0, T), saveat=5, solver="dopri8", method="vmap", **TOLS)
    np.testing.assert_allclose(vm.ys, buffered.ys, rtol=0, atol=1e-7 * float(np.max(np.abs(vm.ys))))
    pk = simulate_batch(*batch, (0.0, T), solver="dopri8", method="pallas", **TOLS)
    assert pk.solver == "Dopri8+pallas"
    np.testing.assert_allclose(pk.ys[:, 0], vm.ys[:, -1], rtol=1e-12, atol=1e-12)  # same steps as diffrax
    np.testing.assert_array_equal(pk.stats["num_steps"], vm.stats["num_steps"])


def test_implicit_solver_in_the_buffer():
    speeds = jnp.array([1.0, 6.0])
    scenes = eqx.filter_vmap(scene)(speeds)
    r = simulate_batch(scenes, jnp.tile(Y0, (2, 1)), (0.0, 3.0), solver="kvaerno5", lanes=1, rtol=1e-8,
                       atol=1e-11)
    assert r.solver == "Kvaerno5+buffered"
    for i, n in enumerate(speeds):
        one = rj.simulate(scene(n), Y0, (0.0, 3.0), solver="kvaerno5", rtol=1e-8, atol=1e-11)
        np.testing.assert_allclose(r.ys[i, 0], one.ys[-1], rtol=0, atol=1e-6 * float(np.max(np.abs(one.ys))))


def test_event_located_contact_in_the_buffer():
    """Model 004 kicked onto its limiters: the buffer's located switches equal
    `simulate_events` (the same switches, the same states between them)."""
    from rotorjax.presets import cantilever_limiters as cl

    p = dict(cl.PRESET.defaults, perturbation=0.02)
    sc = cl.build_scene(p)
    y0 = cl.initial_state(sc, p)
    t1 = 2 * np.pi / p["N"] * 3
    ref = simulate_events(sc, y0, (0.0, t1), saveat=11, rtol=1e-10, atol=1e-13)
    scenes = jax.tree_util.tree_map(lambda a: jnp.stack([a, a]) if eqx.is_array(a) else a, sc)
    r = simulate_batch(scenes, jnp.stack([y0, y0]), (0.0, t1), saveat=11, solver="dopri8", rtol=1e-10,
                       atol=1e-13, lanes=1, events=True)
    assert int(ref.stats["num_events"]) >= 2
    np.testing.assert_array_equal(r.stats["num_events"], int(ref.stats["num_events"]))
    np.testing.assert_array_equal(r.code, 0)
    scale = float(np.max(np.abs(ref.ys)))
    np.testing.assert_allclose(r.ys[0], ref.ys, rtol=0, atol=1e-8 * scale)
    np.testing.assert_array_equal(r.ys[0], r.ys[1])


def test_a_switch_in_the_last_step_does_not_stall_the_lane():
    """Spans that end just after a contact switch: the step that reaches `t1`
    crosses it, is cut there, and the lane must go on to `t1` (it used to restart
    with a zero step, clipped to `t1`, and stall until `max_steps`)."""
    from rotorjax.presets import cantilever_limiters as cl

    p = dict(cl.PRESET.defaults, perturbation=0.02)
    sc = cl.build_scene(p)
    y0 = cl.initial_state(sc, p)
    rev = 2 * np.pi / p["N"]
    t1s = np.linspace(0.3, 2.0, 24) * rev
    scenes = jax.tree_util.tree_map(lambda a: jnp.stack([a] * len(t1s)) if eqx.is_array(a) else a, sc)
    r = simulate_batch(scenes, jnp.tile(y0, (len(t1s), 1)), (0.0, t1s), solver="dopri8", rtol=1e-6,
                       atol=1e-6, lanes=8, events=True, max_steps=20_000)
    np.testing.assert_array_equal(r.code, 0)
    assert np.all(np.asarray(r.stats["num_steps"]) < 2_000)
    assert int(np.max(r.stats["num_events"])) >= 2
    for i in (0, len(t1s) // 2, len(t1s) - 1):  # the same end state as simulate_events
        ref = simulate_events(sc, y0, (0.0, t1s[i]), saveat=2, rtol=1e-6, atol=1e-6)
        np.testing.assert_allclose(r.ys[i, 0], ref.ys[-1], rtol=0, atol=1e-3 * float(np.max(np.abs(ref.ys))))


def test_sweep_of_initial_value_problems_keeps_grid_order(vectorised):
    def one(p):
        return rj.IVP(scene(p["n"]), Y0 * p["k"], (0.0, T), saveat=5, solver="dopri8", **TOLS)

    grid = {"n": SPEEDS[:3], "k": [1.0, 1.0]}
    res = rj.sweep(one, grid, lanes=2)
    assert res.shape == (3, 2) and res.values.ys.shape == (3, 2, 5, Y0.size)
    for i in range(3):
        for j in range(2):
            _to_tolerance(res.values.ys[i, j], vectorised.ys[i])
    lock = rj.sweep(one, grid, batch="vmap", chunk_size=4)
    np.testing.assert_allclose(lock.values.ys, res.values.ys, rtol=0, atol=1e-7 * float(np.max(np.abs(lock.values.ys))))


def test_each_host_device_runs_its_own_buffer():
    """`shard=True` over 2 host devices (a subprocess: the device count is fixed at
    start-up) equals one buffer on one device, in the points' order: the vectorised
    stepper to the tolerance, diffrax's step (with contact events, devices ending
    apart) to rounding."""
    code = (
        "import jax, jax.numpy as jnp, numpy as np, equinox as eqx\n"
        "from rotorjax.presets import anisotropic_abb as ab\n"
        "from rotorjax.solve import simulate_batch\n"
        "assert len(jax.local_devices()) == 2\n"
        "P = dict(ab.PRESET.defaults); G = {k: P[k] for k in ab.GROUPS}\n"
        "y0 = jnp.asarray(ab.PRESET.build(P).y0)\n"
        "sp = jnp.linspace(1.0, 6.0, 5)\n"
        "sc = eqx.filter_vmap(lambda n: ab.scene_from_groups(**G, n=n, K=P['K']))(sp)\n"
        "kw = dict(solver='dopri8', rtol=1e-9, atol=1e-12, lanes=4)\n"  # vectorised: to the tolerance
        "a = simulate_batch(sc, jnp.tile(y0, (5, 1)), (0.0, 10.0), shard=True, **kw)\n"
        "b = simulate_batch(sc, jnp.tile(y0, (5, 1)), (0.0, 10.0), **kw)\n"
        "assert a.solver == 'Dopri8+vectorised'\n"
        "np.testing.assert_allclose(a.ys, b.ys, rtol=0, atol=1e-8 * float(np.abs(b.ys).max()))\n"
        "from rotorjax.presets import cantilever_limiters as cl\n"  # contact events, devices ending apart
        "p = dict(cl.PRESET.defaults, perturbation=0.02); s = cl.build_scene(p); y = cl.initial_state(s, p)\n"
        "from rotorjax.models import with_leaf\n"
        "eps = jnp.array([0.0, 0.002, 0.001, 0.0])\n"
        "sc = eqx.filter_vmap(lambda e: with_leaf(s, cl.PRESET.sweepable['eps'], e))(eps)\n"
        "kw = dict(saveat=5, solver='dopri8', rtol=1e-7, atol=1e-9, lanes=2, events=True)\n"
        "span = (0.0, jnp.array([2.0, 0.2, 2.0, 0.2]))\n"  # device 1's points end far sooner
        "a = simulate_batch(sc, jnp.tile(y, (4, 1)), span, shard=True, **kw)\n"
        "b = simulate_batch(sc, jnp.tile(y, (4, 1)), span, **kw)\n"
        "assert int(a.stats['num_events'].sum()) > 0\n"
        "np.testing.assert_allclose(a.ys, b.ys, rtol=1e-12, atol=1e-14)\n"
        "print('ok')\n"
    )
    env = dict(os.environ, XLA_FLAGS="--xla_force_host_platform_device_count=2 --xla_cpu_multi_thread_eigen=false",
               JAX_PLATFORMS="cpu")
    out = subprocess.run([sys.executable, "-c", code], env=env, capture_output=True, text=True, timeout=300)
    assert out.returncode == 0 and "ok" in out.stdout, out.stderr[-3000:]


def test_a_time_span_per_point():
    """Three revolutions at each speed: the span follows the point (a count of saved
    states is spread over each point's own span)."""
    speeds = jnp.array([1.5, 4.0])

    def one(p):
        return rj.IVP(scene(p["n"]), Y0, (0.0, 3 * 2 * jnp.pi / p["n"]), saveat=4, solver="dopri8", **TOLS)

    res = rj.sweep(one, {"n": speeds}, lanes=1)
    for i, n in enumerate(np.asarray(speeds)):
        t1 = 3 * 2 * np.pi / n
        ref = rj.simulate(scene(n), Y0, (0.0, t1), saveat=4, solver="dopri8", **TOLS)
        np.testing.assert_allclose(res.values.ts[i], ref.ts, rtol=1e-15)
        np.testing.assert_allclose(res.values.ys[i], ref.ys, rtol=0, atol=1e-7 * float(np.max(np.abs(ref.ys))))
