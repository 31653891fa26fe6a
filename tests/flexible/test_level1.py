"""API 684 level I screening: against ROSS 2.3.0's `Rotor.run_level1` (same
cross-coupling element, same "first non-backward mode"), the sign of the
destabilising cross-coupling, the threshold and its independent check, vmap
over designs."""

import json
import os

import jax
import jax.numpy as jnp
import numpy as np
import pytest

from rotorjax.flexible import level1, level1_log_dec, mid_span_node
from rotorjax.models import FlexibleRotor, RotorScene
from rotorjax.models._validate import InputError

DATA = os.path.join(os.path.dirname(__file__), "data", "ross_ucs_frf.json")


@pytest.fixture(scope="module")
def ref():
    with open(DATA) as f:
        return json.load(f)["level1"] | {"rotor": json.load(open(DATA))["rotor"]}


def _rotor(ref, cxx=None):
    r = ref["rotor"]
    kxx, kyy, c, _ = ref["bearing"]
    c = c if cxx is None else cxx
    return FlexibleRotor(np.array(r["lengths"]), r["d_out"], E=r["E"], G=r["G"], rho=r["rho"],
                         disks=[tuple(d) for d in r["disks"]],
                         bearings=[(0, kxx, kyy, c, c), (6, kxx, kyy, c, c)])


def test_level1_curve_equals_ross(ref):
    """ROSS `run_level1(n=3, stiffness_range=(0, 4e5), num=9)` at rated_w = 500 rad/s:
    to 1e-8 (they agree to ~1e-12)."""
    res = level1(_rotor(ref), ref["speed"], node=ref["node"], q_max=ref["Q"][-1], n=len(ref["Q"]))
    np.testing.assert_allclose(np.asarray(res.q), ref["Q"], rtol=1e-12)
    np.testing.assert_allclose(np.asarray(res.log_dec), ref["log_dec"], rtol=1e-8, atol=1e-10)
    # the threshold lies where ROSS's samples change sign, and is checked independently
    i = int(np.flatnonzero(np.diff(np.sign(ref["log_dec"])))[0])
    assert res.crossed and ref["Q"][i] < float(res.q0) < ref["Q"][i + 1]
    assert abs(float(res.real_part_at_q0)) < 1e-6
    assert abs(float(res.max_real_part_at_q0)) < 1e-6
    assert float(level1_log_dec(_rotor(ref), float(res.q0), ref["speed"], ref["node"])) == pytest.approx(0, abs=1e-8)


def test_cross_coupling_sign_destabilises_forward_whirl(ref):
    """kxy = +Q, kyx = -Q lowers the first forward mode's decrement; -Q raises it."""
    rotor = _rotor(ref)
    at = lambda q: float(level1_log_dec(rotor, q, ref["speed"], 3))  # noqa: E731
    assert at(2e4) < at(0.0) < at(-2e4)


def test_mid_span_node_and_defaults(ref):
    rotor = _rotor(ref)
    assert mid_span_node(rotor) == 3
    res = level1(rotor, 500.0, n=21)  # q_max: the largest bearing stiffness, 1e6
    assert res.node == 3 and float(res.q[-1]) == 1e6 and res.crossed
    np.testing.assert_allclose(float(res.log_dec_0), ref["log_dec"][0], rtol=1e-8)
    # a scene's linear part gives the same
    res_scene = level1(RotorScene(rotor), 500.0, n=21)
    np.testing.assert_allclose(float(res_scene.q0), float(res.q0), rtol=1e-8)


def test_no_crossing_is_reported_not_raised(ref):
    res = level1(_rotor(ref), 500.0, q_max=1e4, n=5)
    assert not res.crossed and np.isnan(float(res.q0)) and np.isnan(float(res.max_real_part_at_q0))


def test_log_dec_vmaps_over_designs_and_q(ref):
    cs = jnp.array([500.0, 1500.0, 3000.0])

    def design(c):
        return level1_log_dec(_rotor(ref, cxx=c), 3e4, 500.0, 3)

    batched = np.asarray(jax.vmap(design)(cs))
    loop = np.array([float(design(c)) for c in cs])
    np.testing.assert_allclose(batched, loop, rtol=1e-10)
    assert np.all(np.diff(batched) > 0)  # more bearing damping, more margin
    qs = jnp.linspace(0.0, 1e5, 5)
    rotor = _rotor(ref)
    np.testing.assert_allclose(np.asarray(jax.vmap(lambda q: level1_log_dec(rotor, q, 500.0, 3))(qs)),
                               [float(level1_log_dec(rotor, q, 500.0, 3)) for q in qs], rtol=1e-10)
    # and differentiates: d logdec / dQ < 0
    assert float(jax.grad(lambda q: level1_log_dec(rotor, q, 500.0, 3))(1e4)) < 0


@pytest.mark.parametrize("kw,match", [
    (dict(speed=float("nan")), "speed"), (dict(speed=500.0, node=9), "node"),
    (dict(speed=500.0, q_max=-1.0), "q_max"), (dict(speed=500.0, n=1), "n must"),
])
def test_level1_bad_input(ref, kw, match):
    with pytest.raises(InputError, match=match):
        level1(_rotor(ref), **kw)
