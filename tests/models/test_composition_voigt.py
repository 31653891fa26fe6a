"""Composition (b): Voigt internal damping on the FE rotor gives a Hopf threshold
that the Jeffcott limit checks.

Jeffcott rotor (disk mass `m` at mid-span of a massless shaft of stiffness `k`,
external damping `c_e` at the disk, internal damping `c_i`): in the fixed frame
`m z'' + (c_e + c_i) z' + (k - i speed c_i) z = 0` (`z = x + i y`), which loses
stability at `speed = w_n (1 + c_e / c_i)`, `w_n = sqrt(k / m)`, whirling at
`w_n`. The FE rotor tends to it as its shaft's mass goes to zero: one disk at
mid-span of a simply supported Euler-Bernoulli shaft (rigid supports: the cubic
elements give exactly `k = 48 E I / L^3` there), `InternalDamping(T_V)` so that
`c_i = T_V k`, a damper at the disk for `c_e`. The leading error is the shaft's
Rayleigh mass, `17/35` of its mass on the static deflection shape: relative error
`-17/70` times the shaft/disk mass ratio.
"""

import numpy as np
import pytest
from scipy.optimize import brentq

import rotorjax as rj
from rotorjax.analysis import hopf_points
from rotorjax.flexible import critical_speeds_1x, modes
from rotorjax.models import FlexibleRotor, InternalDamping, RotorScene
from rotorjax.presets import ross_compare

L, D, E, G = 1.5, 0.05, 211e9, 81.2e9
DISK = 32.59                         # kg
T_V = 2e-4                           # s
K_JEFFCOTT = 48 * E * (np.pi * D**4 / 64) / L**3
C_I = T_V * K_JEFFCOTT
C_E = 0.5 * C_I
W_N = np.sqrt(K_JEFFCOTT / DISK)
THRESHOLD = W_N * (1 + C_E / C_I)


def _jeffcott_rotor(mass_ratio, n_el=4):
    rho = mass_ratio * DISK / (np.pi * D**2 / 4 * L)
    mid = n_el // 2
    return FlexibleRotor(np.full(n_el, L / n_el), D, E=E, G=G, rho=rho, theory="euler-bernoulli",
                         disks=((mid, DISK, 0.0, 0.0),), bearings=((mid, 0.0, 0.0, C_E, C_E),),
                         fixed_dofs=((0, 0), (0, 1), (n_el, 0), (n_el, 1)))


def _hopf(scene, lo, hi):
    return hopf_points(lambda s: scene.linear_matrices(s).state_matrix(), lo, hi)


def _ross_rotor():
    return ross_compare.build_rotor(ross_compare.PRESET.params(
        {"kxx": 1e6, "kyy": 1e6, "cxx": 200.0, "cyy": 200.0}))


ROSS_T_V = 1e-3


def test_fe_shaft_has_the_jeffcott_stiffness_at_mid_span():
    rotor = _jeffcott_rotor(1e-3)
    K = np.asarray(rotor.reduced_matrices()[3])
    mid_x = list(rotor.free_dofs).index(4 * 2)
    assert np.isclose(1 / np.linalg.inv(K)[mid_x, mid_x], K_JEFFCOTT, rtol=1e-12)


def test_hopf_threshold_tends_to_jeffcott_as_shaft_mass_vanishes():
    ratios = (1e-2, 1e-3, 1e-4)
    errors, freq_errors = [], []
    for ratio in ratios:
        scene = RotorScene(_jeffcott_rotor(ratio), 0.0, (InternalDamping(T_V),))
        (hopf,) = _hopf(scene, 0.5 * THRESHOLD, 3 * THRESHOLD)
        errors.append(hopf.speed / THRESHOLD - 1)
        freq_errors.append(hopf.frequency / W_N - 1)
    errors, freq_errors = np.array(errors), np.array(freq_errors)
    # measured: -2.415e-3, -2.423e-4, -2.424e-5 (whirl frequency the same)
    assert np.all(errors < 0)
    assert np.all(np.abs(errors[1:]) < np.abs(errors[:-1]) / 9)
    assert np.allclose(errors / np.array(ratios), -17 / 70, rtol=1e-2)
    assert np.allclose(freq_errors, errors, rtol=1e-2)


def _hand_margin(rotor, t_v, bearing_k):
    """`max Re eig A(speed)` in numpy from `reduced_matrices()`, with the internal
    damping `C_i = T_V K_shaft` (bearings' stiffness removed) and its circulatory
    term `speed C_i J` (`J`: per node (x, y, sx, sy) -> (y, -x, sy, -sx)) built here."""
    M, C, G1, K = (np.asarray(a) for a in rotor.reduced_matrices())
    free = rotor.free_dofs
    K_shaft = K.copy()
    for node, k in bearing_k:
        for d in (4 * node, 4 * node + 1):
            K_shaft[list(free).index(d), list(free).index(d)] -= k
    J = np.zeros((rotor.n_dofs, rotor.n_dofs))
    for b in range(0, rotor.n_dofs, 2):
        J[b, b + 1], J[b + 1, b] = 1.0, -1.0
    J = J[np.ix_(free, free)]
    Ci = t_v * K_shaft
    n = M.shape[0]
    Minv = np.linalg.inv(M)

    def margin(speed):
        A = np.block([[np.zeros((n, n)), np.eye(n)],
                      [-Minv @ (K + speed * Ci @ J), -Minv @ (C + Ci + speed * G1)]])
        return np.max(np.linalg.eigvals(A).real)

    return margin


@pytest.mark.parametrize("case", ["jeffcott", "ross"])
def test_hopf_points_equal_brentq_on_hand_built_matrices(case):
    if case == "jeffcott":
        rotor, t_v, bearings, lo, hi = _jeffcott_rotor(1e-3), T_V, (), 0.5 * THRESHOLD, 3 * THRESHOLD
    else:
        rotor, t_v, bearings, lo, hi = _ross_rotor(), ROSS_T_V, ((0, 1e6), (6, 1e6)), 10.0, 3000.0
    (hopf,) = _hopf(RotorScene(rotor, 0.0, (InternalDamping(t_v),)), lo, hi)
    margin = _hand_margin(rotor, t_v, bearings)
    root = brentq(margin, 0.9 * hopf.speed, 1.1 * hopf.speed, xtol=1e-12, rtol=1e-15)
    assert abs(hopf.speed / root - 1) < 1e-8


def test_ross_rotor_threshold_above_first_critical_whirls_at_first_forward_mode():
    rotor = _ross_rotor()
    scene = RotorScene(rotor, 0.0, (InternalDamping(ROSS_T_V),))
    (hopf,) = _hopf(scene, 10.0, 3000.0)                        # measured 109.64 rad/s
    first_critical = critical_speeds_1x(rotor, 1.0, 1000.0, whirl="forward")[0][0]   # 96.50 rad/s
    assert hopf.speed > 1.1 * first_critical
    m = modes(rotor, hopf.speed, 4)
    forward = np.asarray(m.frequencies)[np.asarray(m.forward)][0]      # 96.529 rad/s
    backward = np.asarray(m.frequencies)[~np.asarray(m.forward)][0]    # 96.052 rad/s
    assert abs(hopf.frequency / forward - 1) < 1e-3                    # measured 1e-4
    assert abs(hopf.frequency - forward) < 0.1 * abs(hopf.frequency - backward)


def _growth_rate(speed, t_end=10.0):
    """Exponential rate of the whirl amplitude envelope (largest node radius per
    1 s window) of the full FE rotor perturbed at rest by 10 um at node 2, from
    the fourth window on (the other modes have died out by then)."""
    scene = RotorScene(_ross_rotor(), speed, (InternalDamping(ROSS_T_V),))
    y0 = np.zeros(scene.state_size)
    y0[4 * 2] = 1e-5
    res = rj.simulate(scene, y0, (0.0, t_end), saveat=np.linspace(0.0, t_end, 1001), max_steps=10**6)
    assert int(res.code) == 0, res.message
    ts, a = np.asarray(res.ts), np.asarray(res.outputs["whirl_amplitude"])
    envelope = np.array([a[(ts >= k) & (ts < k + 1)].max() for k in range(int(t_end))])
    rate = np.log(envelope[-1] / envelope[3]) / (len(envelope) - 4)
    predicted = np.max(np.linalg.eigvals(np.asarray(scene.linear_matrices(speed).state_matrix())).real)
    return rate, predicted


def test_simulation_grows_above_threshold_and_decays_below():
    rotor = _ross_rotor()
    (hopf,) = _hopf(RotorScene(rotor, 0.0, (InternalDamping(ROSS_T_V),)), 10.0, 3000.0)
    below, predicted_below = _growth_rate(0.95 * hopf.speed)
    above, predicted_above = _growth_rate(1.05 * hopf.speed)
    # measured: -0.1566 /s (eigenvalue -0.1562), +0.1560 /s (+0.1560)
    assert below < 0 < above
    assert abs(below / predicted_below - 1) < 0.05
    assert abs(above / predicted_above - 1) < 0.05
