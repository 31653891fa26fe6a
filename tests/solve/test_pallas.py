"""simulate_pallas: one whole adaptive RK integration per lane in one Pallas kernel,
run here in interpret mode on CPU, against rotorjax.simulate (diffrax) lane by lane."""

import diffrax
import equinox as eqx
import jax
import jax.numpy as jnp
import numpy as np
import pytest

import rotorjax as rj
from rotorjax.models import ConstantSpeed
from rotorjax.models._contract import AbstractScene
from rotorjax.models._validate import InputError
from rotorjax.presets import anisotropic_abb
from rotorjax.solve._pallas import simulate_pallas

P = dict(anisotropic_abb.PRESET.defaults)
GROUPS = {k: P[k] for k in anisotropic_abb.GROUPS}
SPAN = (0.0, 5.0)
RTOL, ATOL = 1e-8, 1e-10
SPEEDS = np.linspace(2.0, 6.0, 6)  # 6 lanes: not a multiple of the blocks used below
STATS = ("num_steps", "num_accepted_steps", "num_rejected_steps")


def _scene(n):
    return anisotropic_abb.scene_from_groups(**GROUPS, n=n, K=P["K"])


@pytest.fixture(scope="module")
def batch():
    y0 = anisotropic_abb.PRESET.build(dict(P)).y0
    scenes = eqx.filter_vmap(_scene)(jnp.asarray(SPEEDS))
    return scenes, jnp.tile(y0, (len(SPEEDS), 1))


@pytest.fixture(scope="module")
def reference(batch):
    """`rotorjax.simulate` lane by lane (one compilation per solver)."""
    _, y0s = batch
    cache = {}

    def get(solver, max_steps=200_000):
        key = (type(solver).__name__, max_steps)
        if key not in cache:
            cache[key] = [rj.simulate(_scene(n), y0s[i], SPAN, solver=solver, rtol=RTOL, atol=ATOL,
                                      max_steps=max_steps) for i, n in enumerate(SPEEDS)]
        return cache[key]

    return get


@pytest.fixture(scope="module")
def dopri5(batch):
    scenes, y0s = batch
    return simulate_pallas(scenes, y0s, SPAN, solver=diffrax.Dopri5(), rtol=RTOL, atol=ATOL,
                           block=4)


def _assert_matches(result, refs):
    for i, ref in enumerate(refs):
        assert int(result.code[i]) == int(ref.code) == 0
        y, y_ref = np.asarray(result.ys[i, -1]), np.asarray(ref.ys[-1])
        np.testing.assert_allclose(y, y_ref, rtol=10 * RTOL, atol=10 * RTOL * np.max(np.abs(y_ref)))
        for k in STATS:  # the same step sequence as diffrax (within 1 %)
            assert abs(int(result.stats[k][i]) - int(ref.stats[k])) <= 0.01 * int(ref.stats[k]), k


def test_dopri5_lanes_match_simulate(batch, dopri5, reference):
    scenes, y0s = batch
    r = dopri5
    assert r.solver == "Dopri5+pallas"
    assert r.ts.shape == (6, 1) and r.ys.shape == (6, 1, 8) and r.code.shape == (6,)
    assert all(r.stats[k].shape == (6,) for k in STATS)
    np.testing.assert_array_equal(np.asarray(r.ts), SPAN[1])
    _assert_matches(r, reference(diffrax.Dopri5()))
    # Outputs are the scene's outputs at (t1, y(t1)), shaped (N, 1, ...).
    ref_out = reference(diffrax.Dopri5())[3].outputs
    for name, value in r.outputs.items():
        assert value.shape == (6,) + ref_out[name].shape
        np.testing.assert_allclose(value[3], ref_out[name], rtol=1e-6, atol=1e-9)


def test_dopri8_lanes_match_simulate(batch, reference):
    scenes, y0s = batch
    r = simulate_pallas(scenes, y0s, SPAN, solver=diffrax.Dopri8(), rtol=RTOL, atol=ATOL, block=4)
    assert r.solver == "Dopri8+pallas"
    _assert_matches(r, reference(diffrax.Dopri8()))


def test_block_size_does_not_change_the_result(batch, dopri5):
    scenes, y0s = batch
    r = simulate_pallas(scenes, y0s, SPAN, solver=diffrax.Dopri5(), rtol=RTOL, atol=ATOL, block=8)
    np.testing.assert_array_equal(np.asarray(r.code), np.asarray(dopri5.code))
    for k in STATS:
        np.testing.assert_array_equal(np.asarray(r.stats[k]), np.asarray(dopri5.stats[k]))
    np.testing.assert_allclose(np.asarray(r.ys), np.asarray(dopri5.ys), rtol=1e-12, atol=1e-14)


def test_one_lane_hits_max_steps_the_others_succeed(batch, dopri5, reference):
    scenes, y0s = batch
    steps = np.asarray(dopri5.stats["num_steps"])
    worst = int(np.argmax(steps))
    budget = int(np.sort(steps)[-2]) + 1  # enough for all lanes but the hardest
    assert budget < steps[worst]
    r = simulate_pallas(scenes, y0s, SPAN, solver=diffrax.Dopri5(), rtol=RTOL, atol=ATOL,
                        max_steps=budget, block=4)
    codes = np.asarray(r.code)
    assert codes[worst] == 1 and np.all(np.delete(codes, worst) == 0)
    assert int(r.stats["num_steps"][worst]) == budget
    # The stopped lane holds the state where diffrax stops too.
    ref = reference(diffrax.Dopri5(), max_steps=budget)[worst]
    assert int(ref.code) == 1
    assert float(r.ts[worst, 0]) == pytest.approx(float(ref.ts[-1]), rel=1e-9)
    np.testing.assert_allclose(r.ys[worst, 0], ref.ys[-1], rtol=1e-7, atol=1e-10)
    # The other lanes are untouched by the failure.
    ok = np.delete(np.arange(len(SPEEDS)), worst)
    np.testing.assert_array_equal(np.asarray(r.ys)[ok], np.asarray(dopri5.ys)[ok])


class _Quadratic(AbstractScene):
    """`y' = a y^2`, `y(0) = 1`: blows up at `t = 1/a` (a non-finite `a`: a NaN field)."""

    a: jax.Array
    speed: ConstantSpeed

    @property
    def state_size(self):
        return 1

    def vector_field(self, t, y, args=None):
        return self.a * y**2

    def outputs(self, t, y):
        return {"y": y[0]}

    def describe(self):
        return "y' = a y^2"


def test_nonfinite_field_and_step_collapse_are_coded():
    a = jnp.array([0.1, jnp.nan, 1.0])  # fine to t = 2, NaN field, blow-up at t = 1
    scenes = eqx.filter_vmap(lambda a: _Quadratic(a, ConstantSpeed(1.0)))(a)
    r = simulate_pallas(scenes, jnp.ones((3, 1)), (0.0, 2.0), solver=diffrax.Dopri5(), block=2,
                        max_steps=100_000)
    np.testing.assert_array_equal(np.asarray(r.code), [0, 2, 3])
    np.testing.assert_allclose(float(r.ys[0, 0, 0]), 1.0 / (1.0 - 0.2), rtol=1e-7)
    assert int(r.stats["num_steps"][1]) == 0  # stopped before any step
    # Near the pole the step shrinks until it collapses (diffrax would shrink it until
    # max_steps, code 1, and take 100 000 steps on the NaN lane as well).
    assert abs(float(r.ts[2, 0]) - 1.0) < 1e-6 and float(r.ys[2, 0, 0]) > 1e10
    assert int(r.stats["num_steps"][2]) < 10_000
    assert r.outputs["y"].shape == (3, 1)


def test_bad_input_is_rejected(batch):
    scenes, y0s = batch
    with pytest.raises(InputError, match="solver"):
        simulate_pallas(scenes, y0s, SPAN, solver=diffrax.Kvaerno5())
    with pytest.raises(InputError, match="y0s must be finite"):
        simulate_pallas(scenes, y0s.at[2, 1].set(jnp.nan), SPAN)
    with pytest.raises(InputError, match="y0s must have shape"):
        simulate_pallas(scenes, y0s[:, :4], SPAN)
    with pytest.raises(InputError, match="leading batch axis"):
        simulate_pallas(scenes, y0s[:5], SPAN)
    with pytest.raises(InputError, match="t_span"):
        simulate_pallas(scenes, y0s, (1.0, 0.0))
    with pytest.raises(InputError, match="block"):
        simulate_pallas(scenes, y0s, SPAN, block=0)


def test_initial_step_is_diffraxs_algorithm(batch):
    """The kernel's first step follows the installed diffrax: diffrax 0.7.2's
    diffeqsolve wraps its terms, skips `_select_initial_step` and starts at 0.01; the
    kernel's own copy of the algorithm (used if diffrax selects) equals diffrax's."""
    from diffrax._step_size_controller.pid import _select_initial_step
    from optimistix import rms_norm

    from rotorjax.solve import _pallas

    scenes, y0s = batch
    probe = _pallas.diffrax_selects_first_step()
    sol = diffrax.diffeqsolve(diffrax.ODETerm(lambda t, y, args: -y), diffrax.Dopri5(), 0.0, 1.0,
                              None, jnp.ones(1), saveat=diffrax.SaveAt(steps=True),
                              stepsize_controller=diffrax.PIDController(rtol=1e-3, atol=1e-6),
                              max_steps=1, throw=False)
    assert probe == (float(sol.ts[0]) != 0.01)
    lanes = jnp.array([0, 5])
    lane = jax.tree_util.tree_map(lambda x: x[lanes] if eqx.is_array(x) else x, scenes)
    field = lambda t, y: eqx.filter_vmap(lambda s, ti, yi: s.vector_field(ti, yi))(lane, t, y)  # noqa: E731
    t = jnp.zeros(2)
    ours = _pallas._initial_step(field, t, y0s[lanes], field(t, y0s[lanes]), RTOL, ATOL, 8.0)
    term = diffrax.ODETerm(lambda t, y, s: s.vector_field(t, y))
    for j, i in enumerate(np.asarray(lanes)):
        ref = _select_initial_step(term, 0.0, y0s[i], _scene(SPEEDS[i]),
                                   lambda te, t, y, a: te.vf(t, y, a), 8, RTOL, ATOL, rms_norm)
        assert float(ours[j]) == pytest.approx(float(ref), rel=1e-12)
