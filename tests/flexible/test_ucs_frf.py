"""UCS map, frequency-response functions and several unbalances at once, against
ROSS 2.3.0 on its `rotor_example` (our `ross-compare`) and variants.

The reference numbers come from `tests/flexible/ross_ucs_frf_reference.py` (run it
with an interpreter that has ROSS) stored in `data/ross_ucs_frf.json`.
"""

import json
import os

import jax
import jax.numpy as jnp
import numpy as np
import pytest

from rotorjax.flexible import (deflected_shape, frf, synchronous_critical_speeds, ucs, ucs_frequencies,
                               unbalance_response, unbalance_response_many)
from rotorjax.models import Bearing, FlexibleRotor, RotorScene
from rotorjax.models._validate import InputError

DATA = os.path.join(os.path.dirname(__file__), "data", "ross_ucs_frf.json")


@pytest.fixture(scope="module")
def ref():
    with open(DATA) as f:
        return json.load(f)


def _rotor(ref, bearing):
    r = ref["rotor"]
    bearings = [(0, *bearing), (6, *bearing)] if not callable(bearing) else [bearing(0), bearing(6)]
    return FlexibleRotor(np.array(r["lengths"]), r["d_out"], E=r["E"], G=r["G"], rho=r["rho"],
                         disks=[tuple(d) for d in r["disks"]], bearings=bearings)


def _complex(a):
    a = np.asarray(a)
    return a[..., 0] + 1j * a[..., 1]


@pytest.fixture(scope="module")
def example(ref):
    return _rotor(ref, [1e6, 0.8e6, 0.0, 0.0])


@pytest.fixture(scope="module")
def damped(ref):
    return _rotor(ref, ref["damped_bearing"])


# ---- UCS ----

@pytest.mark.parametrize("key,sync", [("speed0", False), ("synchronous", True)])
def test_ucs_map_equals_ross(ref, example, key, sync):
    """ROSS's `run_ucs(stiffness_range=(5, 10), num=30, num_modes=16)`: 4 curves, to 1e-6
    (they agree to ~1e-10)."""
    r = ref["ucs"][key]
    k = np.array(r["stiffness"])
    u = ucs(example, (k[0], k[-1]), len(k), n_modes=4, synchronous=sync)
    np.testing.assert_allclose(np.asarray(u.stiffness), k, rtol=1e-12)
    np.testing.assert_allclose(np.asarray(u.frequencies).T, r["wn"], rtol=1e-6)


def test_ucs_synchronous_is_the_forward_half_of_the_synchronous_determinant(example):
    """Independent: the forward synchronous critical speeds at k are among the roots of
    det(K - W^2 (M - i G1)) of the same rotor on isotropic k springs."""
    k = 3e7
    iso = _rotor_like(example, [k, k, 0.0, 0.0])
    both = np.asarray(synchronous_critical_speeds(iso))
    ours = np.asarray(ucs_frequencies(example, k, 4, synchronous=True))
    for w in ours:
        assert np.min(np.abs(both - w)) < 1e-8 * w
    at_rest = np.asarray(ucs_frequencies(example, k, 4))
    assert np.all(ours > at_rest)  # forward gyroscopic stiffening


def test_ucs_constant_bearings_intersections_are_the_modes_at_rest(example):
    """With constant bearings a curve meets `k = kxx` at the map's value there: for
    kxx = 1e6, kyy = 0.8e6 (undamped, speed 0) ROSS's modal `wn` 91.7966 (kyy) and
    96.2890 (kxx) rad/s."""
    u = ucs(example, (1e5, 1e9), 20)
    first = [i for i in u.intersections if i.mode == 0]
    np.testing.assert_allclose([i.speed for i in first], [91.79655318, 96.28899977], rtol=1e-8)
    assert [i.coefficient for i in first] == ["kyy", "kxx"]
    assert all(i.residual < 1e-6 for i in u.intersections)


def test_ucs_speed_dependent_intersections_match_ross(ref):
    """Bearings with kxx, kyy linear in speed (exact for both interpolations): the
    intersections inside the table equal ROSS's (its polyline on 1500 points: 1e-6)."""
    sd = ref["ucs"]["speed_dependent"]
    rotor = _rotor(ref, lambda n: Bearing(n, kxx=sd["kxx"], kyy=sd["kyy"], speeds=sd["table"]))
    u = ucs(rotor, (1e6, 1e8), 30)
    ours = sorted((i.speed, i.k) for i in u.intersections)
    theirs = sorted(zip(sd["intersections_speed"], sd["intersections_k"]))
    assert len(ours) == len(theirs) == 4
    np.testing.assert_allclose(np.array(ours), np.array(theirs), rtol=1e-6)
    # the overlay: each bearing's kxx, kyy at the map's speeds
    s = np.asarray(u.bearing_speeds)
    np.testing.assert_allclose(np.asarray(u.bearing_k)[0, 0], 2e6 + 4e4 * s, rtol=1e-12)
    np.testing.assert_allclose(np.asarray(u.bearing_k)[1, 1], 1e6 + 2e4 * s, rtol=1e-12)


def test_ucs_map_is_one_vmapped_call_and_differentiable(example):
    k = jnp.logspace(6, 9, 7)
    batched = np.asarray(ucs_frequencies(example, k, 3))
    loop = np.stack([np.asarray(ucs_frequencies(example, float(v), 3)) for v in k])
    np.testing.assert_allclose(batched, loop, rtol=1e-12)
    # d omega_1 / d k > 0 (stiffer bearings, higher critical speed), by autodiff = FD
    g = jax.grad(lambda v: ucs_frequencies(example, v, 1)[0])(1e7)
    fd = (ucs_frequencies(example, 1e7 * (1 + 1e-6), 1)[0] - ucs_frequencies(example, 1e7 * (1 - 1e-6), 1)[0]) \
        / 2e1
    assert g > 0
    np.testing.assert_allclose(g, fd, rtol=1e-5)


def test_ucs_bad_input(example):
    with pytest.raises(InputError, match="stiffness_range must be positive"):
        ucs(example, (0.0, 1e6))
    with pytest.raises(InputError, match="stiffness_range"):
        ucs(example, (1e7, 1e6))
    with pytest.raises(InputError, match="n_modes"):
        ucs(example, (1e6, 1e7), n_modes=0)


# ---- FRF ----

@pytest.mark.parametrize("case", ["example", "damped"])
@pytest.mark.parametrize("kind", ["displacement", "velocity", "acceleration"])
def test_frf_equals_ross_run_freq_response(ref, example, damped, case, kind):
    """Synchronous (`speed=None`: ROSS's `run_freq_response`): magnitude and phase at
    seven frequencies, four input/output pairs, to 1e-8 (they agree to ~1e-12)."""
    rotor = {"example": example, "damped": damped}[case]
    w = np.array(ref["frf"]["frequencies"])
    for row in ref["frf"]["cases"][case]["pairs"]:
        h = np.asarray(frf(rotor, tuple(row["input"]), tuple(row["output"]), w, kind).values)
        theirs = _complex(row[kind])
        np.testing.assert_allclose(np.abs(h), np.abs(theirs), rtol=1e-8)
        np.testing.assert_allclose(np.angle(h / theirs), 0.0, atol=1e-8)


@pytest.mark.parametrize("case", ["example", "damped"])
def test_frf_at_a_fixed_speed_equals_ross_transfer_matrix(ref, example, damped, case):
    rotor = {"example": example, "damped": damped}[case]
    w = np.array(ref["frf"]["frequencies"])
    fixed = np.array(ref["frf"]["cases"][case]["fixed_speed_300"])  # (n_w, n_pairs, 2)
    for p, row in enumerate(ref["frf"]["cases"][case]["pairs"]):
        h = np.asarray(frf(rotor, tuple(row["input"]), tuple(row["output"]), w, speed=300.0).values)
        theirs = _complex(fixed[:, p])
        np.testing.assert_allclose(np.abs(h), np.abs(theirs), rtol=1e-8)
        np.testing.assert_allclose(np.angle(h / theirs), 0.0, atol=1e-8)


def test_frf_reciprocity_at_rest_and_kinds(damped):
    """At speed 0 with symmetric matrices H_ij = H_ji; the kinds are i w H and -w^2 H."""
    damped0 = _rotor_like(damped, [1e6, 0.8e6, 300.0, 200.0])
    w = np.linspace(20.0, 900.0, 9)
    a = frf(damped0, (2, "x"), (4, "y"), w, speed=0.0).values
    b = frf(damped0, (4, "y"), (2, "x"), w, speed=0.0).values
    np.testing.assert_allclose(np.asarray(a), np.asarray(b), rtol=1e-9)
    d = np.asarray(frf(damped, (2, "x"), (2, "x"), w).values)
    v = np.asarray(frf(damped, (2, "x"), (2, "x"), w, "velocity").values)
    acc = np.asarray(frf(damped, (2, "x"), (2, "x"), w, "acceleration").values)
    np.testing.assert_allclose(v, 1j * w * d, rtol=1e-12)
    np.testing.assert_allclose(acc, -w**2 * d, rtol=1e-12)


def _rotor_like(rotor, bearing):
    return FlexibleRotor(rotor.lengths, rotor.d_out, disks=[(n, *p) for n, p in zip(rotor.disk_nodes,
                                                                                     np.asarray(rotor.disk_params))],
                         bearings=[(0, *bearing), (6, *bearing)])


def test_frf_speed_dependent_bearings_at_the_running_speed(ref):
    """Tabulated bearings: the FRF at a fixed speed equals a constant-bearing rotor with
    the coefficients at that speed; synchronous, each frequency uses its own."""
    table = [0.0, 500.0, 1000.0]
    rotor = _rotor(ref, lambda n: Bearing(n, kxx=[1e6, 2e6, 3e6], cxx=[100.0, 200.0, 300.0], speeds=table))
    w = np.array([100.0, 400.0, 800.0])
    h = np.asarray(frf(rotor, (2, "x"), (2, "x"), w, speed=250.0).values)
    h_const = np.asarray(frf(_rotor(ref, [1.5e6, 1.5e6, 150.0, 150.0]), (2, "x"), (2, "x"), w, speed=250.0).values)
    np.testing.assert_allclose(h, h_const, rtol=1e-10)
    sync = np.asarray(frf(rotor, (2, "x"), (2, "x"), w).values)
    for i, wi in enumerate(w):
        k, c = 1e6 + 2e3 * wi, 100.0 + 0.2 * wi
        one = np.asarray(frf(_rotor(ref, [k, k, c, c]), (2, "x"), (2, "x"), [wi]).values)[0]
        np.testing.assert_allclose(sync[i], one, rtol=1e-10)


def test_frf_takes_a_scene_and_a_reduced_rotor(example):
    w = np.array([50.0, 150.0])
    full = np.asarray(frf(example, (2, "x"), (2, "x"), w).values)
    np.testing.assert_allclose(np.asarray(frf(RotorScene(example), (2, "x"), (2, "x"), w).values), full, rtol=1e-10)
    red = np.asarray(frf(example.reduce(20), (2, "x"), (2, "x"), w).values)
    np.testing.assert_allclose(red, full, rtol=1e-3)


@pytest.mark.parametrize("kw,match", [
    (dict(input=(99, "x")), "input: node"), (dict(input=(2, "z")), "input: the direction"),
    (dict(output=5), "output must be"), (dict(output="2x"), "output: node"), (dict(kind="jerk"), "kind"),
])
def test_frf_bad_input(example, kw, match):
    args = dict(input=(2, "x"), output=(2, "x"), frequencies=[1.0, 2.0])
    args.update(kw)
    with pytest.raises(InputError, match=match):
        frf(example, **args)


# ---- several unbalances ----

def test_unbalance_response_many_equals_ross_two_unbalances(ref, damped):
    u = ref["unbalance"]
    X, Y = unbalance_response_many(damped, [tuple(v) for v in u["unbalances"]], u["speeds"])
    for ours, theirs in ((X, u["x"]), (Y, u["y"])):
        theirs = _complex(theirs).T
        np.testing.assert_allclose(np.abs(np.asarray(ours)), np.abs(theirs), rtol=1e-8)
        np.testing.assert_allclose(np.asarray(ours), theirs, rtol=1e-8, atol=1e-8 * np.abs(theirs).max())


def test_unbalance_response_many_is_the_sum_of_single_ones(damped):
    unb = [(2, 1e-3, 0.3), (4, 5e-4, -1.0), (3, 2e-4, 2.0)]
    w = np.linspace(30.0, 900.0, 12)
    X, Y = unbalance_response_many(damped, unb, w, probe_nodes=[1, 3, 5])
    sx = sum(np.asarray(unbalance_response(damped, n, m, p, w, probe_nodes=[1, 3, 5])[0]) for n, m, p in unb)
    sy = sum(np.asarray(unbalance_response(damped, n, m, p, w, probe_nodes=[1, 3, 5])[1]) for n, m, p in unb)
    np.testing.assert_allclose(np.asarray(X), sx, rtol=1e-10)
    np.testing.assert_allclose(np.asarray(Y), sy, rtol=1e-10)


def test_deflected_shape_major_axis_equals_ross(ref, damped):
    u = ref["unbalance"]
    unb = [tuple(v) for v in u["unbalances"]]
    for s, major in zip(u["speeds"], u["major_axis"]):
        shape = deflected_shape(damped, unb, s)
        np.testing.assert_allclose(np.asarray(shape.major), major, rtol=1e-8)
        # the orbit sampled over a period: its largest radius is the major semi-axis
        t = np.linspace(0, 2 * np.pi, 4001)
        x = np.real(np.asarray(shape.x)[:, None] * np.exp(1j * t))
        y = np.real(np.asarray(shape.y)[:, None] * np.exp(1j * t))
        np.testing.assert_allclose(np.hypot(x, y).max(axis=1), np.asarray(shape.major), rtol=1e-6)
        np.testing.assert_allclose(np.hypot(x, y).min(axis=1), np.asarray(shape.minor), rtol=1e-5,
                                   atol=1e-6 * float(np.max(shape.major)))


@pytest.mark.parametrize("unb,match", [
    ([], "at least one"), ([(2, 1e-3)], r"unbalances\[0\] must be"), ([(9, 1e-3, 0.0)], r"unbalances\[0\]"),
    ([(2, -1.0, 0.0)], "magnitude"), ([(2, 1e-3, float("nan"))], "phase"),
])
def test_unbalances_bad_input(example, unb, match):
    with pytest.raises(InputError, match=match):
        unbalance_response_many(example, unb, [100.0])
