"""Margins over a speed range (`rotorjax.analysis._margins`) and the eigenvalues'
derivative they use, on one rotor: ROSS's example rotor (`ross_compare.toml`) with
500 N s/m of bearing damping."""

import jax
import jax.numpy as jnp
import numpy as np
import pytest

from rotorjax.analysis import (amplification_factor, damped_eigenvalues, log_dec_floor, required_separation_margin,
                               response_curve, separation_slack)
from rotorjax.analysis._linear import eigenvalues
from rotorjax.io import read_rotor_file, shipped_rotor
from rotorjax.models._parameters import parts_of, with_values

SETS = {"bearing0.cxx": 500.0, "bearing0.cyy": 500.0, "bearing1.cxx": 500.0, "bearing1.cyy": 500.0}
NAMES = ("bearing0.kxx", "bearing0.cxx", "disk0.m")


@pytest.fixture(scope="module")
def rotor():
    file = read_rotor_file(str(shipped_rotor("ross_compare")), SETS)
    parts, paths = parts_of(file.scene), [file.path(n) for n in NAMES]
    x0 = np.array([float(file.entries[n].value) if n in file.entries else SETS[n] for n in NAMES])
    return file, (lambda v: with_values(parts, paths, v).rotor), x0


def _sorted(lam):
    return lam[jnp.argsort(jnp.imag(lam) + 1e-3 * jnp.real(lam))]


def test_the_eigenvalues_derivative_equals_jaxs_own_rule(rotor):
    """The left-right eigenvector rule gives JAX's derivative (which inverts the
    eigenvector matrix) in forward and reverse mode, on a random matrix and on the
    rotor's first-order matrix."""
    file, _, _ = rotor
    a_rotor = file.scene.full_rotor.linear_matrices(300.0).state_matrix()
    rng = np.random.default_rng(0)
    for a in (jnp.asarray(rng.standard_normal((9, 9))), a_rotor):
        t = jnp.asarray(rng.standard_normal(a.shape))
        _, ours = jax.jvp(lambda m: _sorted(eigenvalues(m)), (a,), (t,))
        _, jaxs = jax.jvp(lambda m: _sorted(jnp.linalg.eigvals(m)), (a,), (t,))
        np.testing.assert_allclose(ours, jaxs, rtol=1e-8, atol=1e-9 * float(jnp.max(jnp.abs(jaxs))))
        w = jnp.asarray(rng.standard_normal(a.shape[0]))

        def scalar(f):
            return lambda m: jnp.sum(w * jnp.real(_sorted(f(m))))

        g = jax.grad(scalar(jnp.linalg.eigvals))(a)
        np.testing.assert_allclose(jax.grad(scalar(eigenvalues))(a), g, rtol=1e-7,
                                   atol=1e-8 * float(jnp.max(jnp.abs(g))))


def test_the_log_dec_floor_is_below_the_dense_minimum_and_close_to_it(rotor):
    """The floor of the first three modes' log decrements over 0..1000 rad/s (33
    speeds) lies below their least value on 2001 speeds, by less than its softness
    plus 1e-3; on a coarse grid (9 speeds) it is still below the dense minimum; and its
    gradient equals central differences."""
    _, make, x0 = rotor
    dense = np.linspace(0.0, 1000.0, 2001)
    lam = jax.jit(jax.vmap(lambda s: damped_eigenvalues(make(jnp.asarray(x0)), s, 3)))(jnp.asarray(dense))
    true_min = float(np.min(-2 * np.pi * np.real(lam) / np.imag(lam)))
    floor = jax.jit(lambda v: log_dec_floor(make(v), 0.0, 1000.0, 3))
    f0 = float(floor(jnp.asarray(x0)))
    assert true_min - 2e-3 - 1e-3 < f0 <= true_min
    assert float(log_dec_floor(make(jnp.asarray(x0)), 0.0, 1000.0, 3, n_grid=9)) <= true_min
    g = np.asarray(jax.jit(jax.grad(lambda v: log_dec_floor(make(v), 0.0, 1000.0, 3)))(jnp.asarray(x0)))
    for i in range(len(x0)):
        e = np.eye(len(x0))[i] * 1e-4 * x0[i]
        fd = (float(floor(jnp.asarray(x0 + e))) - float(floor(jnp.asarray(x0 - e)))) / (2e-4 * x0[i])
        assert g[i] == pytest.approx(fd, rel=1e-4, abs=1e-9 * abs(f0) / x0[i])


def test_api_684_separation_margins():
    """The required separation margins at chosen amplification factors (API 684's
    criteria: none below AF 2.5; `min(16, 17 (1 - 1/(AF - 1.5)))` below the operating
    range, `min(26, 10 + 17 (1 - 1/(AF - 1.5)))` above it), and the slack of critical
    speeds below, inside and above a range."""
    af = jnp.array([2.0, 3.5, 3.5, 100.0, 100.0])
    below = jnp.array([True, True, False, True, False])
    np.testing.assert_allclose(required_separation_margin(af, below), [0.0, 8.5, 18.5, 16.0, 26.0], rtol=1e-12)
    crit = jnp.array([240.0, 310.0, 390.0, 500.0])
    slack = separation_slack(crit, jnp.array([3.5, 3.5, 3.5, 3.5]), 300.0, 400.0)
    np.testing.assert_allclose(slack, [20.0 - 8.5, -10 / 3 - 8.5, -2.5 - 18.5, 25.0 - 18.5], rtol=1e-12)


def test_the_amplification_factor_equals_the_half_power_bandwidths():
    """API 684's amplification factor of the second forward critical speed (about 300
    rad/s; isotropic bearings, kyy = kxx) from its eigenvalue, `1 / (2 zeta)`, against the half-power method on the
    unbalance response at a disk to opposed unbalances at the two disks (this mode's
    shape; the symmetric first mode's response would otherwise lift the flanks),
    `N_c / (N_2 - N_1)`, peak and half-power points interpolated on a 0.01 rad/s
    grid: within 5 % (the half-power method is itself exact only as the damping goes to
    zero: here zeta = 0.05, and the unbalance force grows as the speed squared)."""
    from rotorjax.analysis import critical_speed, critical_speeds_1x

    isotropic = {**SETS, "bearing0.kyy": 1e6, "bearing1.kyy": 1e6}   # unbalance then excites the forward modes alone
    r = read_rotor_file(str(shipped_rotor("ross_compare")), isotropic).scene.full_rotor
    (W, k), = [c for c in critical_speeds_1x(r, 250.0, 350.0, whirl="forward")]
    w, _ = critical_speed(r, k, W)
    af = float(amplification_factor(damped_eigenvalues(r, w, k + 1)[k]))
    speeds = np.arange(float(w) - 40.0, float(w) + 40.0, 0.01)
    # the disks' unbalances opposed: the rotor is symmetric, so the symmetric modes stay unexcited
    curve = response_curve(r, [(2, 1e-3, 0.0), (4, 1e-3, np.pi)], speeds, probe=2)
    speeds, amp = np.asarray(curve.speeds), np.asarray(curve.amplitude)
    i = int(np.argmax(amp))
    half = amp[i] / np.sqrt(2)
    n1 = np.interp(half, amp[:i + 1], speeds[:i + 1])
    n2 = np.interp(half, amp[i:][::-1], speeds[i:][::-1])
    assert af == pytest.approx(speeds[i] / (n2 - n1), rel=0.05)
