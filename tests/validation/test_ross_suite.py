"""ROSS's own test suite, ported: the numbers typed in ROSS's tests, checked on the
same rotors built with rotorjax.

Each test names the ROSS test it comes from (`file::function`, ROSS 2.3.0, the
version in `/tmp/rossenv`; the same tests are in ROSS 3.x unless said). ROSS 2.x has
6 dofs per node (x, y, z, alpha, beta, theta), rotorjax 4 (x, y, sx, sy): we compare
the lateral part. ROSS's alpha is the rotation about x and beta about y, so
`(x, y, alpha, beta) = (x, y, -sy, sx)` (`_ross_order` below); with this map our
element matrices equal ROSS's to the printed digits. The axial and torsional dofs
are uncoupled from the lateral ones in these linear models, so lateral eigenvalues,
responses and static deflections are the same in both; where ROSS's typed list holds
an axial or torsional frequency we leave it out and say so. Where a typed number
cannot be reproduced from the typed data alone, the reference comes from ROSS 2.3.0
itself via `tests/validation/ross_suite_reference.py` (stored in
`data/ross_suite.json`).

Tolerances: ROSS's own (`assert_allclose` default rtol 1e-7, `decimal=n` as
`abs < 1.5 10^-n`) or tighter.
"""

import json
import os

import equinox as eqx
import jax
import jax.numpy as jnp
import numpy as np
import pytest
from numpy.testing import assert_allclose, assert_almost_equal

from rotorjax.flexible import (FlexibleRotor, campbell, damped_frequencies, modes,
                               state_matrix, synchronous_critical_speeds, unbalance_response, undamped_modes)

DATA = os.path.join(os.path.dirname(__file__), "data", "ross_suite.json")
STEEL = dict(E=211e9, G=81.2e9, rho=7810.0)   # ross.materials.steel

# compiled once per rotor topology: a rotor's arrays and the speeds are traced (as arrays),
# counts stay static
_f64 = lambda v: jnp.asarray(v, dtype=jnp.float64)
_freqs_j = eqx.filter_jit(damped_frequencies)
_modes_j = eqx.filter_jit(modes)
_state_j = eqx.filter_jit(state_matrix)
_unb_j = eqx.filter_jit(lambda r, node, u, ph, speeds, probe: unbalance_response(r, node, u, ph, speeds, probe))
_matrices_j = eqx.filter_jit(lambda rotor, *speed: rotor.matrices(*speed))
_sync = eqx.filter_jit(synchronous_critical_speeds)


def _freqs(r, speed, n=None):
    return _freqs_j(r, _f64(speed), n)


def _modes(r, speed, n=None):
    return _modes_j(r, _f64(speed), n)


def _state(r, speed):
    return _state_j(r, _f64(speed))


def _unb(r, node, u, phase, speeds, probe_nodes=None):
    return _unb_j(r, node, _f64(u), _f64(phase), _f64(speeds), None if probe_nodes is None else tuple(probe_nodes))


def _matrices(rotor, *speed):
    return _matrices_j(rotor, *(_f64(v) for v in speed))


def _reference():
    with open(DATA) as f:
        return json.load(f)


# ---------------------------------------------------------------------------------------
# helpers: ROSS's dof order, disks from geometry, orbits


def _ross_order(a, n_nodes):
    """A rotorjax matrix (dofs x, y, sx, sy per node) in ROSS's lateral order
    (x, y, alpha, beta) = (x, y, -sy, sx)."""
    T = np.zeros((4 * n_nodes, 4 * n_nodes))
    for i in range(n_nodes):
        b = 4 * i
        T[b, b] = T[b + 1, b + 1] = 1.0
        T[b + 2, b + 3] = -1.0
        T[b + 3, b + 2] = 1.0
    return T @ np.asarray(a) @ T.T


def disk_from_geometry(node, width, i_d, o_d, rho=STEEL["rho"]):
    """`(node, m, Id, Ip)` of a solid disk as ROSS's `DiskElement.from_geometry`
    (rotorjax has no such constructor; the formulas are ROSS's: m = rho pi w (do^2 - di^2)/4,
    Ip = m (do^2 + di^2)/8, Id = Ip/2 + m w^2/12)."""
    m = rho * np.pi * width * (o_d**2 - i_d**2) / 4
    ip = m * (o_d**2 + i_d**2) / 8
    return (node, m, ip / 2 + m * width**2 / 12, ip)


def _orbit(X, Y):
    """Major and minor axis and ROSS's kappa (minor/major, + forward) of the orbit
    `x = Re(X e^{i w t})`, `y = Re(Y e^{i w t})`."""
    rf, rb = np.abs(X + 1j * Y) / 2, np.abs(X - 1j * Y) / 2
    return rf + rb, np.abs(rf - rb), (rf - rb) / (rf + rb)


def _shaft(n, L=0.25, d=0.05, **kw):
    return dict(lengths=[L] * n, d_out=d, **STEEL, **kw)


# ---------------------------------------------------------------------------------------
# ROSS's fixture rotors (tests/test_rotor_assembly.py)

D0 = disk_from_geometry(None, 0.07, 0.05, 0.28)[1:]
D1 = disk_from_geometry(None, 0.07, 0.05, 0.35)[1:]


def rotor1():
    return FlexibleRotor(**_shaft(2))


def rotor2(k=1e6):
    return FlexibleRotor(**_shaft(2), disks=[(1,) + D0], bearings=[(0, k, k, 0.0, 0.0), (2, k, k, 0.0, 0.0)])


def rotor3(n=6, kx=1e6, ky=0.8e6, c=0.0, disk_nodes=(2, 4)):
    """rotor3 (kyy 0.8e6), rotor4 (the same from sections), rotor7 (kx = ky = 1e6, c = 1e3);
    `n` elements of 1.5/n m (the mesh-convergence refinement)."""
    return FlexibleRotor(**_shaft(n, L=1.5 / n), disks=[(disk_nodes[0],) + D0, (disk_nodes[1],) + D1],
                         bearings=[(0, kx, ky, c, c), (n, kx, ky, c, c)])


def rotor5(disk_nodes=(4, 6)):
    """rotor5; rotor6 is `rotor5(disk_nodes=(5, 10))` (overhung)."""
    return FlexibleRotor(**_shaft(10), disks=[(disk_nodes[0],) + D0, (disk_nodes[1],) + D1],
                         bearings=[(2, 1e6, 1e6, 0.0, 0.0), (8, 1e6, 1e6, 0.0, 0.0)])


def rotor7():
    return rotor3(kx=1e6, ky=1e6, c=1e3)


# ---------------------------------------------------------------------------------------
# tests/test_disk_element.py, tests/test_materials.py, tests/test_point_mass.py


def test_disk_from_geometry_values():
    # ROSS 2.3.0 tests/test_disk_element.py::test_mass_matrix_disk1 (m, Id, Ip to 5 decimals) and
    # tests/test_rotor_assembly.py::test_rotor_it (the disks' m and It typed to 17 digits)
    assert_almost_equal(D0, [32.58973, 0.17809, 0.32956], decimal=5)
    assert_allclose(D0[:2], [32.58972765304033, 0.17808928257067666], rtol=1e-13)
    assert_allclose(D1[:2], [51.5252611115262, 0.42358058405433824], rtol=1e-13)


def _node_blocks(rotor, node, speed=None):
    M, C, G1, K = _matrices(rotor) if speed is None else _matrices(rotor, speed)
    s = slice(4 * node, 4 * node + 4)
    return [_ross_order(np.asarray(a)[s, s], 1) for a in (M, C, G1, K)]


def test_disk_mass_and_gyroscopic_matrices():
    # ROSS 2.3.0 tests/test_disk_element.py::test_mass_matrix_disk and ::test_gyroscopic_matrix_disk
    # (DiskElement(0, m=0.07, Id=0.05, Ip=0.32956), lateral block of its 6x6): the disk's part of
    # the assembled matrices is the rotor's minus the bare shaft's.
    shaft = FlexibleRotor(**_shaft(1))
    with_disk = FlexibleRotor(**_shaft(1), disks=[(0, 0.07, 0.05, 0.32956)])
    Md, _, Gd, _ = (a - b for a, b in zip(_node_blocks(with_disk, 0), _node_blocks(shaft, 0)))
    assert_almost_equal(Md, np.diag([0.07, 0.07, 0.05, 0.05]), decimal=5)
    Gd1 = np.zeros((4, 4))
    Gd1[2, 3], Gd1[3, 2] = 0.32956, -0.32956    # alpha-beta block of ROSS's Gd1
    assert_almost_equal(Gd, Gd1, decimal=5)


def test_disk_from_geometry_matrices():
    # ROSS 2.3.0 tests/test_disk_element.py::test_mass_matrix_disk1 and ::test_gyroscopic_matrix_disk1
    shaft = FlexibleRotor(**_shaft(1))
    with_disk = FlexibleRotor(**_shaft(1), disks=[(0,) + D0])
    Md, _, Gd, _ = (a - b for a, b in zip(_node_blocks(with_disk, 0), _node_blocks(shaft, 0)))
    assert_almost_equal(Md, np.diag([32.58973, 32.58973, 0.17809, 0.17809]), decimal=5)
    assert_almost_equal(Gd[2, 3], 0.32956, decimal=5)
    assert_almost_equal(Gd[3, 2], -0.32956, decimal=5)


def test_poisson_ratio_from_E_and_G():
    # ROSS 2.3.0 tests/test_materials.py::test_Poisson / ::test_E_G_s_Poisson (AISI4140: E 203.2e9,
    # G 80e9 -> Poisson 0.27) and tests/test_shaft_element.py::test_parameters_eb (steel: 0.29926108)
    r = FlexibleRotor([0.25], 0.05, E=203.2e9, G=80e9, rho=7850.0)
    assert_allclose(r.nu, 0.27)
    assert_almost_equal(FlexibleRotor(**_shaft(1)).nu, 0.29926108)


def test_steel_material():
    # ROSS 2.3.0 tests/test_shaft_element.py::test_parameters_eb (material=steel: E 211e9,
    # G_s 81.2e9, rho 7810, Poisson 0.29926108)
    from rotorjax.models import MATERIALS, material

    steel = material("steel")
    assert steel is MATERIALS["steel"]
    assert (steel.E, steel.G, steel.rho) == (211e9, 81.2e9, 7810)
    assert_almost_equal(steel.nu, 0.29926108)


def test_point_mass():
    # ROSS 2.3.0 tests/test_point_mass.py::test_point_mass (PointMass(n=0, m=10): M = 10 I, no K, C, G)
    shaft = FlexibleRotor(**_shaft(1))
    with_mass = FlexibleRotor(**_shaft(1), point_masses=[(0, 10.0)])
    d = [a - b for a, b in zip(_node_blocks(with_mass, 0), _node_blocks(shaft, 0))]
    assert_allclose(d[0], np.diag([10.0, 10.0, 0.0, 0.0]), atol=1e-12)
    for a in d[1:]:
        assert_allclose(a, 0.0, atol=1e-12)
    # ROSS 2.3.0 tests/test_point_mass.py::test_local_index (mx = 1, my = 2): the x and y masses
    two = FlexibleRotor(**_shaft(1), point_masses=[(0, 1.0, 2.0)])
    d = _node_blocks(two, 0)[0] - _node_blocks(shaft, 0)[0]
    assert_allclose(d, np.diag([1.0, 2.0, 0.0, 0.0]), atol=1e-12)


# ---------------------------------------------------------------------------------------
# tests/test_shaft_element.py: element matrices (one element = a one-element rotor)


def _element(theory="timoshenko", L=0.25, d_out=0.05, d_in=0.0):
    M, _, G1, K = _matrices(FlexibleRotor([L], d_out, d_in, theory=theory, **STEEL))
    return [_ross_order(a, 2) for a in (M, G1, K)]


def test_shaft_parameters_tim():
    # ROSS 2.3.0 tests/test_shaft_element.py::test_parameters_tim: A, Ie, Poisson, phi of the
    # Timoshenko element (L 0.25, d 0.05); phi = 12 E I / (kappa G A L^2) with our kappa (Cowper's)
    r = FlexibleRotor(**_shaft(1))
    A, Ie = np.pi * 0.05**2 / 4, np.pi * 0.05**4 / 64
    assert_almost_equal(A, 0.00196349)
    assert_almost_equal(Ie * 1e7, 3.06796157)
    phi = 12 * 211e9 * Ie / (float(r.kappa[0]) * 81.2e9 * A * 0.25**2)
    assert_almost_equal(phi, 0.08795566)


EB_M = np.array([
    [1.42395, 0., 0., 0.0502, 0.49291, 0., 0., -0.02967],
    [0., 1.42395, -0.0502, 0., 0., 0.49291, 0.02967, 0.],
    [0., -0.0502, 0.00228, 0., 0., -0.02967, -0.00171, 0.],
    [0.0502, 0., 0., 0.00228, 0.02967, 0., 0., -0.00171],
    [0.49291, 0., 0., 0.02967, 1.42395, 0., 0., -0.0502],
    [0., 0.49291, -0.02967, 0., 0., 1.42395, 0.0502, 0.],
    [0., 0.02967, -0.00171, 0., 0., 0.0502, 0.00228, 0.],
    [-0.02967, 0., 0., -0.00171, -0.0502, 0., 0., 0.00228]])


def test_mass_matrix_eb():
    # ROSS 2.3.0 tests/test_shaft_element.py::test_mass_matrix_eb (M0e_eb_4, decimal=5):
    # shear_effects=False, rotary_inertia=False = our "euler-bernoulli"
    M, _, _ = _element("euler-bernoulli")
    assert_almost_equal(M, EB_M, decimal=5)


def test_stiffness_matrix_eb():
    # ROSS 2.3.0 tests/test_shaft_element.py::test_stiffness_matrix_eb (K0e_eb_4 / 1e7, decimal=5)
    K0e = np.array([
        [4.97157, 0., 0., 0.62145, -4.97157, 0., 0., 0.62145],
        [0., 4.97157, -0.62145, 0., 0., -4.97157, -0.62145, 0.],
        [0., -0.62145, 0.10357, 0., 0., 0.62145, 0.05179, 0.],
        [0.62145, 0., 0., 0.10357, -0.62145, 0., 0., 0.05179],
        [-4.97157, 0., 0., -0.62145, 4.97157, 0., 0., -0.62145],
        [0., -4.97157, 0.62145, 0., 0., 4.97157, 0.62145, 0.],
        [0., -0.62145, 0.05179, 0., 0., 0.62145, 0.10357, 0.],
        [0.62145, 0., 0., 0.05179, -0.62145, 0., 0., 0.10357]])
    for theory in ("euler-bernoulli", "rayleigh"):   # no shear: the same stiffness
        _, _, K = _element(theory)
        assert_almost_equal(K / 1e7, K0e, decimal=5)


def test_mass_matrix_tim():
    # ROSS 2.3.0 tests/test_shaft_element.py::test_mass_matrix_tim (M0e_tim_4, decimal=5)
    M0e = np.array([
        [1.42051, 0., 0., 0.04932, 0.49635, 0., 0., -0.03055],
        [0., 1.42051, -0.04932, 0., 0., 0.49635, 0.03055, 0.],
        [0., -0.04932, 0.00231, 0., 0., -0.03055, -0.00178, 0.],
        [0.04932, 0., 0., 0.00231, 0.03055, 0., 0., -0.00178],
        [0.49635, 0., 0., 0.03055, 1.42051, 0., 0., -0.04932],
        [0., 0.49635, -0.03055, 0., 0., 1.42051, 0.04932, 0.],
        [0., 0.03055, -0.00178, 0., 0., 0.04932, 0.00231, 0.],
        [-0.03055, 0., 0., -0.00178, -0.04932, 0., 0., 0.00231]])
    M, _, _ = _element()
    assert_almost_equal(M, M0e, decimal=5)


def test_stiffness_matrix_tim():
    # ROSS 2.3.0 tests/test_shaft_element.py::test_stiffness_matrix_tim (K0e_tim_4 / 1e7, decimal=5)
    K0e = np.array([
        [4.56964, 0., 0., 0.57121, -4.56964, 0., 0., 0.57121],
        [0., 4.56964, -0.57121, 0., 0., -4.56964, -0.57121, 0.],
        [0., -0.57121, 0.09729, 0., 0., 0.57121, 0.04551, 0.],
        [0.57121, 0., 0., 0.09729, -0.57121, 0., 0., 0.04551],
        [-4.56964, 0., 0., -0.57121, 4.56964, 0., 0., -0.57121],
        [0., -4.56964, 0.57121, 0., 0., 4.56964, 0.57121, 0.],
        [0., -0.57121, 0.04551, 0., 0., 0.57121, 0.09729, 0.],
        [0.57121, 0., 0., 0.04551, -0.57121, 0., 0., 0.09729]])
    _, _, K = _element()
    assert_almost_equal(K / 1e7, K0e, decimal=5)


def test_gyroscopic_matrix_tim():
    # ROSS 2.3.0 tests/test_shaft_element.py::test_gyroscopic_matrix_tim (G0e_tim_4 * 1e3, decimal=5)
    G0e = np.array([
        [-0., 19.43344, -0.22681, -0., -0., -19.43344, -0.22681, -0.],
        [-19.43344, -0., -0., -0.22681, 19.43344, -0., -0., -0.22681],
        [0.22681, -0., -0., 0.1524, -0.22681, -0., -0., -0.04727],
        [-0., 0.22681, -0.1524, -0., -0., -0.22681, 0.04727, -0.],
        [-0., -19.43344, 0.22681, -0., -0., 19.43344, 0.22681, -0.],
        [19.43344, -0., -0., 0.22681, -19.43344, -0., -0., 0.22681],
        [0.22681, -0., -0., -0.04727, -0.22681, -0., -0., 0.1524],
        [-0., 0.22681, 0.04727, -0., -0., -0.22681, -0.1524, -0.]])
    _, G, _ = _element()
    assert_almost_equal(G * 1e3, G0e, decimal=5)


# tapered elements: ROSS's `tap_tim` (L 0.4, d 0.25 -> 0.10, solid) and `tap_tim_hollow` (bore 0.05)


def _tapered(d_in=0.0):
    M, _, G1, K = _matrices(FlexibleRotor([0.4], [[0.25, 0.10]], [[d_in, d_in]], **STEEL))
    return [_ross_order(a, 2) for a in (M, G1, K)]


def test_mass_matrix_tap_tim():
    # ROSS 2.3.0 tests/test_shaft_element.py::test_mass_matrix_tap_tim (decimal=5)
    M0e = np.array([
        [41.84146162, 0., 0., 1.85735573, 10.27465893, 0., 0., -1.16147981],
        [0., 41.84146162, -1.85735573, 0., 0., 10.27465893, 1.16147981, 0.],
        [0., -1.85735573, 0.18686024, 0., 0., -1.04154454, -0.10311193, 0.],
        [1.85735573, 0., 0., 0.18686024, 1.04154454, 0., 0., -0.10311193],
        [10.27465893, 0., 0., 1.04154454, 17.35069604, 0., 0., -1.1330391],
        [0., 10.27465893, -1.04154454, 0., 0., 17.35069604, 1.1330391, 0.],
        [0., 1.16147981, -0.10311193, 0., 0., 1.1330391, 0.09851808, 0.],
        [-1.16147981, 0., 0., -0.10311193, -1.1330391, 0., 0., 0.09851808]])
    M, _, _ = _tapered()
    assert_almost_equal(M, M0e, decimal=5)


def test_stiffness_matrix_tap_tim():
    # ROSS 2.3.0 tests/test_shaft_element.py::test_stiffness_matrix_tap_tim (assert_allclose, rtol 1e-7)
    a, b, c, d, e, f = 1.91471213e09, 5.45588167e08, 2.20296684e08, 1.75017153e08, 4.32181136e07, 4.49005599e07
    K0e = np.array([
        [a, 0, 0, b, -a, 0, 0, c],
        [0, a, -b, 0, 0, -a, -c, 0],
        [0, -b, d, 0, 0, b, e, 0],
        [b, 0, 0, d, -b, 0, 0, e],
        [-a, 0, 0, -b, a, 0, 0, -c],
        [0, -a, b, 0, 0, a, c, 0],
        [0, -c, e, 0, 0, c, f, 0],
        [c, 0, 0, e, -c, 0, 0, f]])
    _, _, K = _tapered()
    assert_allclose(K, K0e, rtol=1e-7, atol=1e-6)


def test_gyroscopic_matrix_tap_tim():
    # ROSS 2.3.0 tests/test_shaft_element.py::test_gyroscopic_matrix_tap_tim (decimal=5)
    a, b, c, d, e, f = 1.23853234, 0.15544731, 0.03173553, 0.11850408, 0.01563679, 0.01089192
    G0e = np.array([
        [0, a, b, 0, 0, -a, -c, 0],
        [-a, 0, 0, b, a, 0, 0, -c],
        [-b, 0, 0, d, b, 0, 0, -e],
        [0, -b, -d, 0, 0, b, e, 0],
        [0, -a, -b, 0, 0, a, c, 0],
        [a, 0, 0, -b, -a, 0, 0, c],
        [c, 0, 0, -e, -c, 0, 0, f],
        [0, c, e, 0, 0, -c, -f, 0]])
    _, G, _ = _tapered()
    assert_almost_equal(G, G0e, decimal=5)


def test_mass_matrix_tap_tim_hollow():
    # ROSS 2.3.0 tests/test_shaft_element.py::test_mass_matrix_tap_tim_hollow (decimal=5)
    a, b, c, d, e, f = 39.26343318, 1.701278, 9.66844022, 1.11365499, 0.17815913, 0.96970348
    g, h, i, j = 0.09540863, 15.00720225, 0.99985206, 0.08959186
    M0e = np.array([
        [a, 0, 0, b, c, 0, 0, -d],
        [0, a, -b, 0, 0, c, d, 0],
        [0, -b, e, 0, 0, -f, -g, 0],
        [b, 0, 0, e, f, 0, 0, -g],
        [c, 0, 0, f, h, 0, 0, -i],
        [0, c, -f, 0, 0, h, i, 0],
        [0, d, -g, 0, 0, i, j, 0],
        [-d, 0, 0, -g, -i, 0, 0, j]])
    M, _, _ = _tapered(0.05)
    assert_almost_equal(M, M0e, decimal=5)


def test_stiffness_matrix_tap_tim_hollow():
    # ROSS 2.3.0 tests/test_shaft_element.py::test_stiffness_matrix_tap_tim_hollow (rtol 1e-7)
    a, b, c, d, e, f = 1.72061778e09, 4.94146120e08, 1.94100990e08, 1.62042273e08, 3.56161745e07, 4.20242215e07
    K0e = np.array([
        [a, 0, 0, b, -a, 0, 0, c],
        [0, a, -b, 0, 0, -a, -c, 0],
        [0, -b, d, 0, 0, b, e, 0],
        [b, 0, 0, d, -b, 0, 0, e],
        [-a, 0, 0, -b, a, 0, 0, -c],
        [0, -a, b, 0, 0, a, c, 0],
        [0, -c, e, 0, 0, c, f, 0],
        [c, 0, 0, e, -c, 0, 0, f]])
    _, _, K = _tapered(0.05)
    assert_allclose(K, K0e, rtol=1e-7, atol=1e-6)


def test_gyroscopic_matrix_tap_tim_hollow():
    # ROSS 2.3.0 tests/test_shaft_element.py::test_gyroscopic_matrix_tap_tim_hollow (decimal=5)
    a, b, c, d, e, f = 1.04768554, 0.16077186, 0.01188345, 0.12336918, 0.01335772, 0.00994601
    G0e = np.array([
        [0, a, b, 0, 0, -a, -c, 0],
        [-a, 0, 0, b, a, 0, 0, -c],
        [-b, 0, 0, d, b, 0, 0, -e],
        [0, -b, -d, 0, 0, b, e, 0],
        [0, -a, -b, 0, 0, a, c, 0],
        [a, 0, 0, -b, -a, 0, 0, c],
        [c, 0, 0, -e, -c, 0, 0, f],
        [0, c, e, 0, 0, -c, -f, 0]])
    _, G, _ = _tapered(0.05)
    assert_almost_equal(G, G0e, decimal=5)


def test_tapered_with_equal_ends_is_cylindrical():
    # ROSS 2.3.0 tests/test_shaft_element.py::test_match_mass_matrix, ::test_match_stiffness_matrix,
    # ::test_match_gyroscopic_matrix (tap2 vs tim2: L 0.4, d 0.25, decimal=5; we ask for 1e-10 relative)
    cyl = _matrices(FlexibleRotor([0.4], 0.25, **STEEL))
    tap = _matrices(FlexibleRotor([0.4], [[0.25, 0.25]], **STEEL))
    for a, b in zip(cyl, tap):
        assert_allclose(np.asarray(b), np.asarray(a), rtol=1e-10, atol=1e-10 * float(np.max(np.abs(a))))


# ---------------------------------------------------------------------------------------
# tests/test_rotor_assembly.py: assembled matrices

M4R1 = np.array([
    [1.421, 0., 0., 0.049, 0.496, 0., 0., -0.031, 0., 0., 0., 0.],
    [0., 1.421, -0.049, 0., 0., 0.496, 0.031, 0., 0., 0., 0., 0.],
    [0., -0.049, 0.002, 0., 0., -0.031, -0.002, 0., 0., 0., 0., 0.],
    [0.049, 0., 0., 0.002, 0.031, 0., 0., -0.002, 0., 0., 0., 0.],
    [0.496, 0., 0., 0.031, 2.841, 0., 0., 0., 0.496, 0., 0., -0.031],
    [0., 0.496, -0.031, 0., 0., 2.841, 0., 0., 0., 0.496, 0.031, 0.],
    [0., 0.031, -0.002, 0., 0., 0., 0.005, 0., 0., -0.031, -0.002, 0.],
    [-0.031, 0., 0., -0.002, 0., 0., 0., 0.005, 0.031, 0., 0., -0.002],
    [0., 0., 0., 0., 0.496, 0., 0., 0.031, 1.421, 0., 0., -0.049],
    [0., 0., 0., 0., 0., 0.496, -0.031, 0., 0., 1.421, 0.049, 0.],
    [0., 0., 0., 0., 0., 0.031, -0.002, 0., 0., 0.049, 0.002, 0.],
    [0., 0., 0., 0., -0.031, 0., 0., -0.002, -0.049, 0., 0., 0.002]])


def test_mass_matrix_rotor1():
    # ROSS 2.3.0 tests/test_rotor_assembly.py::test_mass_matrix_rotor1 (M4r1, decimal=3)
    M = _ross_order(_matrices(rotor1())[0], 3)
    assert_almost_equal(M, M4R1, decimal=3)


def test_mass_matrix_rotor2():
    # ROSS 2.3.0 tests/test_rotor_assembly.py::test_mass_matrix_rotor2 (M4r2, decimal=3): rotor1 plus
    # the disk at node 1 (35.431 = 2.841 + 32.590; 0.183 = 0.005 + 0.178)
    M4R2 = M4R1.copy()
    M4R2[4, 4] = M4R2[5, 5] = 35.431
    M4R2[6, 6] = M4R2[7, 7] = 0.183
    M = _ross_order(_matrices(rotor2())[0], 3)
    assert_almost_equal(M, M4R2, decimal=3)


def test_mass_matrix_rotor2_with_bearing_mass():
    # ROSS 2.3.0 tests/test_rotor_assembly.py::test_mass_matrix_rotor2_with_bearing_mass (bearings
    # BearingElement(n, kxx=1e6, cxx=0, mxx=20e-3) at nodes 0 and 2: 1.441 = 1.421 + 0.020)
    from rotorjax.models import Bearing

    r = FlexibleRotor(**_shaft(2), disks=[(1,) + D0],
                      bearings=[Bearing(0, kxx=1e6, cxx=0.0, mxx=20e-3), Bearing(2, kxx=1e6, cxx=0.0, mxx=20e-3)])
    M4R2 = M4R1.copy()
    M4R2[4, 4] = M4R2[5, 5] = 35.431
    M4R2[6, 6] = M4R2[7, 7] = 0.183
    for i in (0, 1, 8, 9):
        M4R2[i, i] = 1.441
    assert_almost_equal(_ross_order(_matrices(r)[0], 3), M4R2, decimal=3)


def test_state_matrix_rotor2():
    # ROSS 2.3.0 tests/test_rotor_assembly.py::test_a0_0_matrix_rotor2, ::test_a0_1_matrix_rotor2,
    # ::test_a1_0_matrix_rotor2 (lateral block / 1e7, decimal=3), ::test_a1_1_matrix_rotor2.
    # ROSS's A = [[0, I], [-M^-1 K, -M^-1 (C + speed G)]], ours the same on (q, q'): the
    # lateral block of ROSS's -M^-1 K is ours in ROSS's order (M and K do not couple the
    # lateral dofs to the axial/torsional ones).
    A1_0 = np.array([
        [20.63, -0., 0., 4.114, -20.958, 0., 0., 1.11, 0.056, -0., -0., -0.014],
        [0., 20.63, -4.114, 0., -0., -20.958, -1.11, 0., -0., 0.056, 0.014, 0.],
        [0., 697.351, -131.328, 0., -0., -705.253, -44.535, 0., -0., 2.079, 0.596, 0.],
        [-697.351, 0., -0., -131.328, 705.253, -0., -0., -44.535, -2.079, 0., 0., 0.596],
        [0.442, 0., -0., 0.072, -0.887, -0., -0., -0., 0.442, 0., 0., -0.072],
        [0., 0.442, -0.072, 0., -0., -0.887, 0., 0., 0., 0.442, 0.072, -0.],
        [0., 6.457, -0.837, 0., -0., 0., -1.561, 0., -0., -6.457, -0.837, -0.],
        [-6.457, -0., 0., -0.837, 0., 0., 0., -1.561, 6.457, 0., 0., -0.837],
        [0.056, -0., 0., 0.014, -20.958, 0., 0., -1.11, 20.63, 0., 0., -4.114],
        [0., 0.056, -0.014, 0., -0., -20.958, 1.11, 0., 0., 20.63, 4.114, -0.],
        [-0., -2.079, 0.596, -0., 0., 705.253, -44.535, -0., -0., -697.351, -131.328, 0.],
        [2.079, 0., -0., 0.596, -705.253, -0., 0., -44.535, 697.351, 0., 0., -131.328]])
    A = np.asarray(_state(rotor2(), 0.0))
    n = 12
    assert_almost_equal(A[:n, :n], np.zeros((n, n)), decimal=3)
    assert_almost_equal(A[:n, n:], np.eye(n), decimal=3)
    assert_almost_equal(_ross_order(A[n:, :n], 3) / 1e7, A1_0, decimal=3)
    assert_almost_equal(A[n:, n:] / 1e7, np.zeros((n, n)), decimal=3)


def test_rotor_mass():
    # ROSS 2.3.0 tests/test_rotor_assembly.py::test_rotor_attributes (rotor1.m = 7.6674495701675891,
    # nodes at 0, 0.25, 0.5) and ::test_rotor_m (rotor3.m equals the sum of the mass matrix's
    # x-translation block, rel 1e-8): the x block of our M sums to the typed mass.
    r1 = rotor1()
    assert_allclose(np.asarray(r1.node_positions), [0.0, 0.25, 0.5])
    assert_allclose(np.asarray(_matrices(r1)[0])[0::4, 0::4].sum(), 7.6674495701675891, rtol=1e-13)
    r3 = rotor3()
    m3 = 7.6674495701675891 * 3 + D0[0] + D1[0]
    assert_allclose(np.asarray(_matrices(r3)[0])[0::4, 0::4].sum(), m3, rtol=1e-12)


def test_rotor_center_of_gravity():
    # ROSS 2.3.0 tests/test_rotor_assembly.py::test_rotor_CG (CG = (column sums of the x block of M)
    # . node positions / m, rel 1e-8) against the CG of shaft and disks (shaft at 0.75 m, disks at
    # 0.5 m and 1.0 m): ROSS's Rotor.CG is that weighted mean.
    r3 = rotor3()
    mm = np.asarray(_matrices(r3)[0])[0::4, 0::4]
    cg = np.sum(mm, axis=0) @ np.asarray(r3.node_positions) / mm.sum()
    m_shaft = 7.6674495701675891 * 3
    expected = (m_shaft * 0.75 + D0[0] * 0.5 + D1[0] * 1.0) / (m_shaft + D0[0] + D1[0])
    assert_allclose(cg, expected, rtol=1e-8)


# ---------------------------------------------------------------------------------------
# tests/test_rotor_assembly.py: modal analysis


def test_evals_sorted_rotor2():
    # ROSS 2.3.0 tests/test_rotor_assembly.py::test_evals_sorted_rotor2. At speed 0 (rtol 1e-3) the
    # eigenvalues are 215.37, 598.02, 3956.22 rad/s, each twice (the x and y planes). At 10000
    # rad/s ROSS types 34.82, 215.37 (twice), 3470.9, 3850.2, 3990.2 with rtol 1e-1 and real parts
    # up to +-0.5 and +41.8: that is ROSS's sparse shift-invert eigensolver (ARPACK) on a
    # matrix of norm ~1e10; the rotor is undamped and gyroscopic with K > 0, so its eigenvalues
    # are exactly imaginary (Thomson-Tait). We check the frequencies at ROSS's tolerance and
    # the real parts at zero to 1e-6 of the frequency (the side that is right).
    lam0 = np.asarray(_modes(rotor2(), 0.0, 6).eigenvalues)
    assert_allclose(lam0.imag, [215.3707255735, 215.3707255733, 598.0247411492, 598.0247411456,
                                3956.2249777612, 3956.2249797838], rtol=1e-3)
    lam = np.asarray(_modes(rotor2(), 10000.0, 6).eigenvalues)
    assert_allclose(lam.imag, [34.822138, 215.369011, 215.369011, 3470.897616, 3850.212629, 3990.22903],
                    rtol=1e-1)
    assert np.all(np.abs(lam.real) < 1e-6 * np.abs(lam.imag))
    assert np.all(np.abs(lam0.real) < 1e-6 * np.abs(lam0.imag))


@pytest.fixture(scope="module")
def rotor3_modes():
    r = rotor3()
    one = jax.jit(lambda s: _modes(r, s, 4))
    return {s: one(float(s)) for s in (0.0, 2000.0)}


def _kappa(m, node, mode):
    s = np.asarray(m.shapes)
    return _orbit(s[4 * node, mode], s[4 * node + 1, mode])


def test_kappa_rotor3(rotor3_modes):
    # ROSS 2.3.0 tests/test_rotor_assembly.py::test_kappa_rotor3 (rtol 1e-3): frequency of mode 0
    # at speed 0 and of modes 0, 1 at 2000 rad/s, ROSS's kappa (minor/major, + forward) at node
    # 0 and 1, and the major axes' ratio node 1 / node 0 of mode 1 (ROSS's major and minor axes
    # depend on its mode normalisation; their ratios do not).
    m0, m2 = rotor3_modes[0.0], rotor3_modes[2000.0]
    assert_allclose(float(m0.frequencies[0]), 82.653037, rtol=1e-3)
    assert_allclose(_kappa(m0, 0, 0)[2], 0.0, atol=1e-6)
    assert_allclose(np.asarray(m2.frequencies[:2]), [77.37957042, 88.98733511566752], rtol=1e-3)
    assert_allclose(_kappa(m2, 0, 0)[2], -0.6148843693807821, rtol=1e-3)
    assert_allclose(_kappa(m2, 0, 0)[1] / _kappa(m2, 0, 0)[0], 0.23617 / 0.384089, rtol=1e-3)
    assert_allclose(_kappa(m2, 0, 1)[2], 0.8456866641084784, rtol=1e-3)
    assert_allclose(_kappa(m2, 1, 1)[2], 0.7597878964314968, rtol=1e-3)
    assert_allclose(_kappa(m2, 1, 1)[0] / _kappa(m2, 0, 1)[0], 0.671776 / 0.353984, rtol=1e-3)
    assert_allclose(_kappa(m2, 1, 1)[1] / _kappa(m2, 0, 1)[0], 0.510407 / 0.353984, rtol=1e-3)


def test_kappa_mode_rotor3(rotor3_modes):
    # ROSS 2.3.0 tests/test_rotor_assembly.py::test_kappa_mode_rotor3 (kappa at the 7 nodes, modes 0
    # and 1 at 2000 rad/s, rtol 1e-3)
    m2 = rotor3_modes[2000.0]
    k0 = [_kappa(m2, n, 0)[2] for n in range(7)]
    k1 = [_kappa(m2, n, 1)[2] for n in range(7)]
    assert_allclose(k0, [-0.614884, -0.696056, -0.723983, -0.729245, -0.708471, -0.656976, -0.513044], rtol=1e-3)
    assert_allclose(k1, [0.845687, 0.759788, 0.734308, 0.737393, 0.778295, 0.860137, 0.948157], rtol=1e-3)


def test_campbell_rotor4():
    # ROSS 2.3.0 tests/test_rotor_assembly.py::test_campbell (rotor4 = rotor3 built from sections;
    # wd at 0, 150, 300 rad/s, rtol 1e-7). ROSS's rows hold 650.40786626 at every speed: a
    # torsional mode of its 6-dof model (speed-independent; our lateral model has no such mode,
    # and the lateral frequencies nearest are 679.5, 652.9, 614.1), left out here.
    speeds = np.array([0.0, 150.0, 300.0])
    wd = np.asarray(jax.jit(lambda s: campbell(rotor3(), s, 6).frequencies)(speeds))
    ross = np.array([
        [82.65303734, 86.65811435, 254.52047828, 274.31285391, 650.40786626, 679.48903239],
        [82.60929602, 86.68625235, 251.70037114, 276.87787937, 650.40786627, 652.85679897],
        [82.48132723, 86.76734307, 245.49092844, 282.33294699, 650.40786626, 614.05536277]])
    lateral = np.sort(np.delete(ross, 4, axis=1), axis=1)
    assert_allclose(wd[:, :5], lateral, rtol=1e-7)
    assert np.all(np.abs(wd - 650.40786626) > 1.0)   # no lateral mode at the torsional frequency


def test_mesh_convergence():
    # ROSS 2.3.0 tests/test_rotor_assembly.py::test_mesh_convergence: rotor3 refined until the first
    # natural frequency converges (err_max 1e-8) ends with 96 elements of 0.015625 m, disks at nodes
    # 32 and 64, bearings at 0 and 96, and wn[0] = 82.653037335 (atol 1e-2). That typed value is
    # the 6-element rotor's (ours: 82.6530373354); ROSS 2.3.0's own 96-element rotor gives
    # 82.65294777 (ross_suite_reference.py, full eigensolver on the 4-dof model), which is what
    # the refinement converges to (6, 12, ..., 96 elements: 82.65304, 82.65296, 82.652950,
    # 82.6529481, 82.6529477). We check ROSS's typed value at its tolerance and ROSS's 96-element
    # value at 5e-9 (the two eigensolvers' round-off at 388 dofs is ~1e-9).
    ref = _reference()["mesh_convergence"]
    r = rotor3(n=96, disk_nodes=(32, 64))
    assert_allclose(np.asarray(r.lengths)[0], 0.015625, atol=1e-6)
    # speed 0, undamped: the first natural frequency from the symmetric pencil (K, M)
    w96 = float(np.sqrt(eqx.filter_jit(lambda r: undamped_modes(*r.reduced_matrices()[::3])[0])(r)[0]))
    assert_allclose(w96, 82.653037335, atol=1e-2)
    assert_allclose(w96, ref["wn0_96_elements"], rtol=5e-9)
    assert_allclose(float(_freqs(rotor3(), 0.0, 1)[0]), 82.653037335, rtol=1e-10)


def test_run_critical_speed():
    # ROSS 2.3.0 tests/test_rotor_assembly.py::test_run_critical_speed (rotor5, rotor6: wn of the
    # 6 first critical speeds, decimal=4; undamped, so wd = wn and log dec = 0). ROSS finds them by
    # Newton on wn(speed) = speed from the 12 lowest modes; ours are the roots of the synchronous
    # determinant, forward and backward branches alike (as ROSS lists them).
    wn5 = [86.10505193, 86.60492546, 198.93259257, 207.97165539, 244.95609413, 250.53522782]
    wn6 = [61.52110644, 63.72862198, 117.49491374, 118.55829416, 233.83724523, 236.40346235]
    for r, wn in ((rotor5(), wn5), (rotor5(disk_nodes=(5, 10)), wn6)):
        crit = np.asarray(_sync(r, 6))
        assert_almost_equal(crit, wn, decimal=4)


def test_whirl_values_rotor7():
    # ROSS 2.3.0 tests/test_rotor_assembly.py::test_whirl_values (rotor7, 10 speeds 50..500 rad/s:
    # the 6 lowest lateral modes have whirl_values 1, 0, 1, 0, 1, 0 and whirl_direction Backward,
    # Forward, Backward, Forward, Backward, Forward; ROSS's other modes there are axial/torsional,
    # whirl value nan). Checked on Modes.whirl_value, .whirl and .forward.
    from rotorjax.analysis._linear import whirl_labels

    r = rotor7()
    camp = jax.jit(lambda s: campbell(r, s, 6))(np.linspace(50, 500, 10))
    assert np.all(np.asarray(camp.whirl_value) == np.array([1.0, 0.0, 1.0, 0.0, 1.0, 0.0]))
    assert np.all(whirl_labels(camp.whirl_value) == np.array(["backward", "forward"] * 3))
    assert np.all(np.asarray(camp.forward) == np.array([False, True, False, True, False, True]))


@pytest.fixture(scope="module")
def rotor7_modes():
    r = rotor7()
    one = jax.jit(lambda s: _modes(r, s, 3))
    return {s: one(float(s)) for s in (50.0, 100.0, 200.0, 250.0, 400.0, 500.0)}


def test_kappa_mode_rotor7(rotor7_modes):
    # ROSS 2.3.0 tests/test_rotor_assembly.py::test_kappa_mode (rotor7 at 100, 250, 500 rad/s: kappa
    # -1, +1, -1 to 1e-10 at every node for modes 0, 1, 2, rtol 1e-7): equal bearings, so circular
    # whirl, backward, forward, backward.
    for s in (100.0, 250.0, 500.0):
        m = rotor7_modes[s]
        for mode, sign in ((0, -1.0), (1, 1.0), (2, -1.0)):
            k = [_kappa(m, n, mode)[2] for n in range(7)]
            assert_allclose(k, sign * np.ones(7), rtol=1e-7)


def test_kappa_axes_values_rotor7(rotor7_modes):
    # ROSS 2.3.0 tests/test_rotor_assembly.py::test_kappa_axes_values (rotor7 at 50, 200, 400 rad/s:
    # at node 3 the major and minor axes of modes 0 and 1 are 1 and of mode 2 0.128085, 0.132574,
    # 0.131419, atol 1e-6, ROSS normalising each mode's largest major axis to 1): the ratio of
    # node 3's axes to the largest over the nodes.
    for s, third in ((50.0, 0.128085), (200.0, 0.132574), (400.0, 0.131419)):
        m = rotor7_modes[s]
        for mode, expected in ((0, 1.0), (1, 1.0), (2, third)):
            axes = np.array([_kappa(m, n, mode)[:2] for n in range(7)])
            assert_allclose(axes[3] / axes[:, 0].max(), [expected, expected], atol=1e-6)


def test_modal_fig_orientation_rotor3():
    # ROSS 2.3.0 tests/test_rotor_assembly.py::test_modal_fig_orientation (rotor3 at 900 RPM, mode 1:
    # the major axis along the shaft normalised to 1, decimal=7). ROSS's curve has 5 points per
    # element, nodes at indices 0, 5, 10, ..., 29; we check the nodes.
    m = _modes(rotor3(), 900 * np.pi / 30, 2)
    major = np.array([_kappa(m, n, 1)[0] for n in range(7)])
    ross = [0.3330699, 0.65594162, 0.90030229, 1.0, 0.93122548, 0.70057879, 0.38022502]
    assert_almost_equal(major / major.max(), ross, decimal=7)


# ---------------------------------------------------------------------------------------
# tests/test_rotor_assembly.py: forced response


def test_freq_response_w_force_rotor4():
    # ROSS 2.3.0 tests/test_rotor_assembly.py::test_freq_response_w_force (rotor4, unbalance 0.001 kg m
    # at node 2, phase 0, at 0, 150, 300, 450 rad/s: |x|, |y|, |alpha|, |beta| at node 0, rtol 1e-7;
    # then two unbalances 0.001 at nodes 2 and 3).
    mag_exp = np.array([
        [0.0, 1.14259057e-06, 1.88932819e-04, 4.50376020e-05],
        [0.0, 3.02252319e-06, 1.50551126e-04, 4.98323245e-05],
        [0.0, 1.97842812e-05, 5.19405022e-05, 2.80824236e-05],
        [0.0, 2.02593969e-05, 1.64498124e-05, 1.06100461e-05]])
    mag_exp_2_unb = np.array([
        [0.0, 4.80337594e-06, 2.31170438e-04, 6.90062268e-05],
        [0.0, 3.15307288e-06, 1.87793923e-04, 8.08531462e-05],
        [0.0, 3.79692673e-05, 5.97050225e-05, 5.48105215e-05],
        [0.0, 4.16812885e-05, 1.38592416e-05, 2.20209089e-05]])
    r = rotor3()
    w = np.linspace(0.0, 450.0, 4)

    def node0(unbalances):
        q = 0.0
        for node in unbalances:   # linear: the sum of the single responses
            q = q + _full_response(r, node, 0.001, 0.0, w)
        return np.abs(np.asarray([q[:, 0], q[:, 1], -q[:, 3], q[:, 2]]))   # x, y, alpha, beta

    assert_allclose(node0([2]), mag_exp, rtol=1e-7, atol=1e-20)
    assert_allclose(node0([2, 3]), mag_exp_2_unb, rtol=1e-7, atol=1e-20)


def _full_response(r, node, u, phase, speeds):
    """Complex amplitudes of all 4 dofs of node 0 (x, y, sx, sy) over `speeds`: from the
    unbalance response at node 0 (x, y) and the rotations by the same solve."""
    from rotorjax.models import frequency_response

    M, C, G1, K = (np.asarray(a) for a in _matrices(r))
    out = []
    for s in speeds:
        F = np.zeros(r.n_dofs, complex)
        F[4 * node], F[4 * node + 1] = u * s**2 * np.exp(1j * phase), -1j * u * s**2 * np.exp(1j * phase)
        q = np.asarray(frequency_response(jnp.asarray(M), jnp.asarray(C + s * G1), jnp.asarray(K), jnp.asarray(F), s))
        out.append(q[:4])
    return np.array(out)


def test_unbalance_rotor3():
    # ROSS 2.3.0 tests/test_rotor_assembly.py::test_unbalance (rotor3, unbalance 1 kg m at node 0,
    # phase 0, at 50 and 100 rad/s; rtol 1e-4): the response of a probe at node 0 at 45 deg
    # (amplitude and phase), and the major axis of the orbit (amplitude).
    X, Y = _unb(rotor3(), 0, 1.0, 0.0, np.array([50.0, 100.0]), probe_nodes=[0])
    X, Y = np.asarray(X[:, 0]), np.asarray(Y[:, 0])
    probe = X * np.cos(np.pi / 4) + Y * np.sin(np.pi / 4)
    assert_allclose(np.abs(probe), [0.003158927232913641, 0.004620055491206476], rtol=1e-4)
    # ROSS's phase is a lag, 2 pi - mod(angle, 2 pi) (ross/results.py, Orbit.calculate_amplitude)
    assert_allclose(2 * np.pi - np.mod(np.angle(probe), 2 * np.pi), [0.9096239298802793, 1.0057118170915373],
                    rtol=1e-4)
    assert_allclose(_orbit(X, Y)[0], [0.0035259958428500164, 0.005518031001232163], rtol=1e-4)


def test_deflected_shape_rotor7():
    # ROSS 2.3.0 tests/test_rotor_assembly.py::test_deflected_shape (rotor7 with kyy 2e6, unbalance
    # 1 kg m at node 0, 50 rad/s: the major-axis vector of the orbits along the shaft, rtol 1e-4;
    # ROSS plots it at 4 points per element, nodes 0 and 1 at indices 0 and 4).
    r = FlexibleRotor(**_shaft(6), disks=[(2,) + D0, (4,) + D1],
                      bearings=[(0, 1e6, 2e6, 1e3, 1e3), (6, 1e6, 2e6, 1e3, 1e3)])
    X, Y = _unb(r, 0, 1.0, 0.0, np.array([50.0]), probe_nodes=[0, 1])
    X, Y = np.asarray(X[0]), np.asarray(Y[0])
    a, b = (X + 1j * Y) / 2, (np.conj(X) + 1j * np.conj(Y)) / 2   # r = a e^{iwt} + b e^{-iwt}
    vec = (np.abs(a) + np.abs(b)) * np.exp(1j * (np.angle(a) + np.angle(b)) / 2)
    vec = vec * np.sign(vec.real)   # the axis, either way round
    expected = np.array([0.00274183 + 4.91340990e-05j, 0.00252877 + 4.58914054e-05j])
    assert_allclose(vec.real, expected.real, rtol=1e-4)
    assert_allclose(vec.imag, expected.imag, rtol=1e-4)


# ---------------------------------------------------------------------------------------
# tests/test_bearing_seal_element.py: bearings with speed tables

KXX0 = [8.5e07, 1.1e08, 1.3e08, 1.6e08, 1.8e08, 2.0e08, 2.3e08, 2.5e08, 2.6e08]
KYY0 = [9.2e07, 1.1e08, 1.4e08, 1.6e08, 1.9e08, 2.1e08, 2.3e08, 2.5e08, 2.6e08]
CXX0 = [226837, 211247, 197996, 185523, 174610, 163697, 153563, 144209, 137973]
CYY0 = [235837, 211247, 197996, 185523, 174610, 163697, 153563, 144209, 137973]
MXX1 = [1e-3, 1.1e-3, 1.2e-3, 1.3e-3, 1.4e-3, 1.5e-3, 1.6e-3, 1.7e-3, 1.8e-3]
WB = [314.2, 418.9, 523.6, 628.3, 733.0, 837.8, 942.5, 1047.2, 1151.9]
# bearing_coefficients(speed) columns (SPEC): kxx, kyy, kxy, kyx, cxx, cyy, cxy, cyx, mxx, myy, mxy, myx
KXX, KYY, KXY, KYX, CXX, CYY, CXY, CYX, MXX, MYY = range(10)


def _one_bearing_rotor(bearing):
    return FlexibleRotor(**_shaft(4), bearings=[bearing])


def test_bearing_interpolation_at_table_ends():
    # ROSS 2.3.0 tests/test_bearing_seal_element.py::test_bearing_interpol_kxx, ::_kyy, ::_cxx, ::_cyy
    # and ::test_bearing1_interpol_* (bearing0 / bearing1 at 314.2 and 1151.9 rad/s: the table's
    # values; ROSS checks kxx, kyy at rtol 1e-7, the others with rtol=1e5, i.e. not at all:
    # we check all at 1e-9)
    from rotorjax.models import Bearing

    r = _one_bearing_rotor(Bearing(4, kxx=KXX0, kyy=KYY0, cxx=CXX0, cyy=CYY0, mxx=MXX1, speeds=WB))
    for speed, i in ((314.2, 0), (1151.9, -1)):
        c = np.asarray(r.bearing_coefficients(speed))[0]
        assert_allclose(c[[KXX, KYY, CXX, CYY, MXX, MYY]], [KXX0[i], KYY0[i], CXX0[i], CYY0[i], MXX1[i], MXX1[i]],
                        rtol=1e-9)


def test_bearing1_matrices():
    # ROSS 2.3.0 tests/test_bearing_seal_element.py::test_bearing1_matrices (K, C, M of bearing1 at
    # 314.2 rad/s, rtol 1e-5; ROSS's smoothing spline puts 85000000.043 for the table's 8.5e7),
    # here as the bearing's blocks of the assembled matrices at that speed.
    from rotorjax.models import Bearing

    b = Bearing(4, kxx=KXX0, kyy=KYY0, cxx=CXX0, cyy=CYY0, mxx=MXX1, speeds=WB)
    with_b, bare = _one_bearing_rotor(b), FlexibleRotor(**_shaft(4))
    d = [a - c for a, c in zip(_node_blocks(with_b, 4, 314.2), _node_blocks(bare, 4, 314.2))]
    assert_allclose(d[3][:2, :2], np.diag([85000000.043218, 91999999.891728]), rtol=1e-5)
    assert_allclose(d[1][:2, :2], np.diag([226836.917649, 235836.850213]), rtol=1e-5)
    # ROSS types M as 0.00099999 (5 digits, cut): the table's 1e-3 is 1.00001e-5 away; rtol 2e-5
    assert_allclose(d[0][:2, :2], np.diag([0.00099999, 0.00099999]), rtol=2e-5)


def test_bearing_spline_between_table_speeds():
    # ROSS 2.3.0 tests/test_bearing_seal_element.py::test_plot (bearing0's kxx and cxx curves at
    # 343.09 .. 429.74 rad/s, typed) and the whole curve (30 speeds, ross_suite_reference.py).
    # ROSS fits scipy's UnivariateSpline (a smoothing spline, s = number of points); ours is the
    # interpolating not-a-knot cubic. They agree to 5e-9 on kxx (~1e8) and 1e-5 on cxx (~2e5:
    # ROSS's smoothing is absolute, so it shows on the smaller values); ours passes through the
    # table exactly (ROSS's 226836.918 for the table's 226837).
    from rotorjax.models import Bearing

    ref = _reference()["bearing0"]
    r = _one_bearing_rotor(Bearing(4, kxx=KXX0, kyy=KYY0, cxx=CXX0, cyy=CYY0, speeds=WB))
    coef = np.array([np.asarray(r.bearing_coefficients(s))[0] for s in ref["speeds"]])
    assert_allclose(coef[1:5, KXX], [9.39094443e07, 1.00985975e08, 1.06782950e08, 1.11853726e08], rtol=1e-8)
    assert_allclose(coef[1:5, CXX], [222164.94925285, 217802.8600443, 213700.3582994, 209807.15229442], rtol=1e-5)
    assert_allclose(coef[:, KXX], ref["kxx"], rtol=1e-8)
    assert_allclose(coef[:, CXX], ref["cxx"], rtol=2e-5)


@pytest.mark.parametrize("case", ["bearing_len_2", "bearing_len_3"])
def test_bearing_short_tables(case):
    # ROSS 2.3.0 tests/test_bearing_seal_element.py::test_bearing_len_2 and ::test_bearing_len_3
    # (2 and 3 table speeds: interp1d linear and quadratic; ROSS checks kxx(115.19) = 481) and the
    # values between the speeds from ROSS 2.3.0 (ross_suite_reference.py), rtol 1e-12.
    from rotorjax.models import Bearing

    ref = _reference()[case]
    if case == "bearing_len_2":
        b = Bearing(0, kxx=[481, 4810], cxx=[3.13, 10.81], kyy=[481, 4810], kxy=[194, 2078], kyx=[-194, -2078],
                    cyy=[3.13, 10.81], cxy=[0.276, 0.69], cyx=[-0.276, -0.69], speeds=[115.19, 345.575])
        cols = {"kxx": KXX, "kxy": KXY, "kyx": KYX, "cxy": CXY}
    else:
        b = Bearing(0, kxx=[481, 4810, 18810], cxx=[3.13, 10.81, 22.99], kyy=[481, 4810, 18810],
                    kxy=[194, 2078, 8776], kyx=[-194, -2078, -8776], cyy=[3.13, 10.81, 22.99],
                    cxy=[0.276, 0.69, 1.19], cyx=[-0.276, -0.69, -1.19], speeds=[115.19, 345.575, 691.15])
        cols = {"kxx": KXX, "kxy": KXY, "kyx": KYX, "cxx": CXX}
    r = _one_bearing_rotor(b)
    coef = np.array([np.asarray(r.bearing_coefficients(s))[0] for s in ref["speeds"]])
    assert_allclose(coef[0, KXX], 481.0, rtol=1e-12)
    for name, col in cols.items():
        assert_allclose(coef[:, col], ref[name], rtol=1e-12, atol=1e-12)


def test_bearing_constant_coefficients():
    # ROSS 2.3.0 tests/test_bearing_seal_element.py::test_bearing6 (kxx 1e6, kyy 0.8e6, cxx 2e2,
    # cyy 1.5e2: K, C diagonal, M = 0) and ::test_bearing_constant (kxx 8e7 at any speed)
    bare = FlexibleRotor(**_shaft(1))
    r = FlexibleRotor(**_shaft(1), bearings=[(0, 1e6, 0.8e6, 2e2, 1.5e2)])
    d = [a - b for a, b in zip(_node_blocks(r, 0), _node_blocks(bare, 0))]
    assert_allclose(d[3][:2, :2], np.diag([1e6, 0.8e6]), rtol=1e-12)
    assert_allclose(d[1][:2, :2], np.diag([2e2, 1.5e2]), rtol=1e-12)
    assert_allclose(d[0], 0.0, atol=1e-12)
    from rotorjax.models import Bearing

    rc = _one_bearing_rotor(Bearing(4, kxx=8e7, cxx=0.0))
    assert_allclose(np.asarray(rc.bearing_coefficients(314.2))[0, KXX], 8e7)


def test_cylindrical_hydrodynamic():
    # ROSS 2.3.0 tests/test_bearing_seal_element.py::test_cylindrical_hydrodynamic: the short plain
    # journal bearing (CylindricalBearing: load 525 N, L 30 mm, D 100 mm, c 0.1 mm, 0.1 Pa s, at
    # 1500 and 2000 RPM): Sommerfeld number (ROSS's = mu N L D (R/c)^2 / W, N in rev/s) and
    # eccentricity at rtol 1e-5, K and C at 1500 RPM.
    # ROSS's attitude angle, typed 0.198931 and 0.161713 rad, is arctan(pi sqrt(1 - e^2) / 4 * e):
    # an operator-precedence bug for the short-bearing attitude arctan(pi sqrt(1 - e^2) / (4 e))
    # (Friswell et al. 2010, eq. 5.70), 1.2322 and 1.3010 rad. We check the correct formula.
    # ROSS states K and C in a frame tied to the load line (its u, v); we compare what does not
    # depend on the frame: trace and determinant of K and of C.
    from rotorjax.models._journal_bearing import plain_journal

    speeds = np.array([1500.0, 2000.0]) * np.pi / 30
    jc = plain_journal(speeds, load=525.0, viscosity=0.1, length=0.03, diameter=0.1, clearance=1e-4, method="short")
    assert_allclose(np.asarray(jc.sommerfeld), [3.571429, 4.761905], rtol=1e-6)
    e = np.asarray(jc.eccentricity)
    assert_allclose(e, [0.266298, 0.212571], rtol=1e-5)
    assert_allclose(np.asarray(jc.attitude), np.arctan(np.pi * np.sqrt(1 - e**2) / (4 * e)), rtol=1e-10)
    k_ross = np.array([[12.80796, 16.393593], [-25.060393, 8.815303]]) * 1e6
    c_ross = np.array([[232.89693, -81.924371], [-81.924371, 294.911619]]) * 1e3
    k, c = np.asarray(jc.k)[0], np.asarray(jc.c)[0]
    assert_allclose([np.trace(k), np.linalg.det(k)], [np.trace(k_ross), np.linalg.det(k_ross)], rtol=1e-5)
    assert_allclose([np.trace(c), np.linalg.det(c)], [np.trace(c_ross), np.linalg.det(c_ross)], rtol=1e-5)


# ---------------------------------------------------------------------------------------
# tests/test_rotor_assembly.py: static analysis (ROSS: gravity 9.8065 m/s^2 in -y, rigid supports
# at the bearings for the deflection; with two bearings the reactions do not depend on the
# bearings' stiffness, and ROSS's deflection is ours less the rigid-body line through the bearings)


def _static(rotor):
    from rotorjax.flexible import static

    return eqx.filter_jit(static)(rotor, gravity=9.8065)


def _bent(res, rotor, bearing_nodes):
    """The y deflection relative to the line through the two bearing nodes."""
    z = np.asarray(rotor.node_positions)
    y = np.asarray(res.displacement)[:, 1]
    i, j = bearing_nodes
    return y - (y[i] + (y[j] - y[i]) * (z - z[i]) / (z[j] - z[i]))


def _ends(values, n_el):
    """ROSS's shear and moment are listed at both ends of each element; ours at the element
    ends (n_el, 2) or (2 n_el,), or at the nodes (expanded to the element ends)."""
    v = np.asarray(values, dtype=float)
    if v.ndim == 3:   # (n_el, 2 ends, 2 planes xz, yz): gravity bends the yz plane
        v = v[..., 1]
    if v.shape == (n_el + 1,):
        return np.repeat(v, 2)[1:-1]
    return v.reshape(2 * n_el)


def _same_up_to_sign(ours, ross, decimal):
    """ROSS's sign convention for shear and moment: the comparison allows either sign
    of the whole curve (one sign for all points)."""
    s = np.sign(np.dot(ours, ross)) or 1.0
    assert_almost_equal(s * ours, ross, decimal=decimal)


def test_static_analysis_rotor3():
    # ROSS 2.3.0 tests/test_rotor_assembly.py::test_static_analysis_rotor3: deflection (rtol 1e-7;
    # the bearing nodes' 1e-18 of ROSS's are zero, atol 1e-13), shear force Vx (rtol 1e-7),
    # bending moment Bm (decimal 7), "Shaft weight = 225.57N"
    r = rotor3()
    res = _static(r)
    expected = [-4.942745e-18, -4.512491e-04, -7.884209e-04, -9.181142e-04, -8.085602e-04, -4.687889e-04,
                -5.561716e-18]
    assert_allclose(_bent(res, r, (0, 6)), expected, rtol=1e-6, atol=1e-13)
    vx = [-494.274533, -456.679111, -456.679111, -419.083689, -99.492525, -61.897103, -61.897103,
          -24.301681, 480.980792, 518.576214, 518.576214, 556.171636]
    bm = [0.0, -118.8692056, -118.8692056, -228.3395557, -228.3395557, -248.5132592, -248.5132592,
          -259.2881072, -259.2881072, -134.3434813, -134.3434813, 0.0]
    _same_up_to_sign(_ends(res.shear, 6), np.array(vx), decimal=5)
    _same_up_to_sign(_ends(res.moment, 6), np.array(bm), decimal=6)
    assert_allclose(7.6674495701675891 * 3 * 9.8065, 225.57, atol=5e-3)
    assert_allclose(np.sum(np.asarray(res.bearing_reactions)[:, 1]), (7.6674495701675891 * 3 + D0[0] + D1[0]) * 9.8065,
                    rtol=1e-10)


def test_static_analysis_rotor5():
    # ROSS 2.3.0 tests/test_rotor_assembly.py::test_static_analysis_rotor5 (bearings at nodes 2, 8,
    # overhangs: deflection decimal=6, Vx and Bm decimal=3)
    r = rotor5()
    res = _static(r)
    expected = [8.12651626e-04, 4.08939282e-04, -5.69465378e-12, -4.05876595e-04, -7.15824882e-04,
                -8.36443708e-04, -7.35964234e-04, -4.23416398e-04, -6.31362481e-12, 4.28859620e-04,
                8.52492302e-04]
    assert_almost_equal(_bent(res, r, (2, 8)), expected, decimal=6)
    assert_allclose(_bent(res, r, (2, 8)), expected, rtol=1e-6, atol=1e-10)
    vx = [0.0, 37.5954, 37.5954, 75.1908, -494.2745, -456.6791, -456.6791, -419.0837, -99.4925, -61.8971,
          -61.8971, -24.3017, 480.9808, 518.5762, 518.5762, 556.1716, -75.1908, -37.5954, -37.5954, -0.0]
    bm = [0.0, 4.6994, 4.6994, 18.7977, 18.7977, -100.0715, -100.0715, -209.5418, -209.5418, -229.7155,
          -229.7155, -240.4904, -240.4904, -115.5458, -115.5458, 18.7977, 18.7977, 4.6994, 4.6994, 0.0]
    _same_up_to_sign(_ends(res.shear, 10), np.array(vx), decimal=3)
    _same_up_to_sign(_ends(res.moment, 10), np.array(bm), decimal=3)


def test_static_analysis_rotor6():
    # ROSS 2.3.0 tests/test_rotor_assembly.py::test_static_analysis_rotor6 (overhung disk at node 10:
    # deflection decimal=6, Vx and Bm decimal=3)
    r = rotor5(disk_nodes=(5, 10))
    res = _static(r)
    expected = [-1.03951876e-04, -4.93624668e-05, -1.79345202e-12, 3.74213098e-05, 7.66066703e-05,
                1.29084322e-04, 1.85016673e-04, 1.72933811e-04, -1.02148266e-11, -3.96409257e-04,
                -9.20006704e-04]
    assert_almost_equal(_bent(res, r, (2, 8)), expected, decimal=6)
    assert_allclose(_bent(res, r, (2, 8)), expected, rtol=1e-6, atol=1e-10)
    vx = [-0.0, 37.5954, 37.5954, 75.1908, -104.1544, -66.5589, -66.5589, -28.9635, -28.9635, 8.6319,
          328.2231, 365.8185, 365.8185, 403.4139, 403.4139, 441.0093, -580.4733, -542.8779, -542.8779,
          -505.2825]
    bm = [0.0, 4.6994, 4.6994, 18.7977, 18.7977, -2.5415, -2.5415, -14.4818, -14.4818, -17.0232, -17.0232,
          69.732, 69.732, 165.886, 165.886, 271.439, 271.439, 131.0201, 131.02, 0.0]
    _same_up_to_sign(_ends(res.shear, 10), np.array(vx), decimal=3)
    _same_up_to_sign(_ends(res.moment, 10), np.array(bm), decimal=3)


def test_static_analysis_high_stiffness():
    # ROSS 2.3.0 tests/test_rotor_assembly.py::test_static_analysis_high_stiffness (rotor2 with 1e6
    # and with 1e14 N/m bearings: the reactions sum to m g and node 0 carries 197.39100421969422 N,
    # decimal=7)
    m = 7.6674495701675891 + D0[0]
    for k in (1e6, 1e14):
        f = np.asarray(_static(rotor2(k)).bearing_reactions)[:, 1]
        assert_allclose(np.sum(f), m * 9.8065, rtol=1e-7)
        assert_almost_equal(f[0], 197.39100421969422, decimal=7)


def test_static_bearing_with_disks():
    # ROSS 2.3.0 tests/test_rotor_assembly.py::test_static_bearing_with_disks (rotor3 plus a 1 kg
    # disk at bearing node 0, ROSS issue #845: reactions sum to m g, node 0 carries
    # 504.08103349786404 N (decimal=7), deflection rtol 1e-7)
    r = FlexibleRotor(**_shaft(6), disks=[(2,) + D0, (4,) + D1, (0, 1.0, 0.0, 0.0)],
                      bearings=[(0, 1e6, 0.8e6, 0.0, 0.0), (6, 1e6, 0.8e6, 0.0, 0.0)])
    res = _static(r)
    f = np.asarray(res.bearing_reactions)[:, 1]
    assert_allclose(np.sum(f), (7.6674495701675891 * 3 + D0[0] + D1[0] + 1.0) * 9.8065, rtol=1e-7)
    assert_almost_equal(f[0], 504.08103349786404, decimal=7)
    expected = [-5.04081033e-18, -4.51249080e-04, -7.88420862e-04, -9.18114186e-04, -8.08560214e-04,
                -4.68788883e-04, -5.56171636e-18]
    assert_allclose(_bent(res, r, (0, 6)), expected, rtol=1e-7, atol=1e-13)


# ---------------------------------------------------------------------------------------
# tests/test_rotor_assembly.py: undamped critical speed maps (ROSS replaces every bearing by
# kxx = kyy = k, converts to 4 dofs and takes the 4 lowest forward natural frequencies at
# speed 0; `synchronous=True`: the forward synchronous critical speeds)

UCS_ROTOR2 = np.array([
    [215.37072557, 283.80994851, 366.86912206, 460.53914551, 555.6339197, 640.32650515, 706.0780713,
     751.34310872, 779.83176945, 796.72990074, 806.39721162, 811.81289519, 814.81102149, 816.45987555,
     817.36339085, 817.85749941, 818.1274194, 818.27478247, 818.35520922, 818.39909624],
    [598.02474114, 799.46636352, 1057.70436175, 1373.74248509, 1729.64320906, 2079.77186424,
     2367.99373458, 2567.69744007, 2690.52418862, 2761.4174174, 2801.13738888, 2823.0913233,
     2835.14811303, 2841.74862093, 2845.35623074, 2847.32634838, 2848.40174108, 2848.98860223,
     2849.30882097, 2849.4835338],
    [3956.224973, 4062.07552707, 4249.58400228, 4573.6000451, 5112.58991935, 5963.9057796, 7227.66815371,
     8977.98586645, 11209.15347504, 13742.89203466, 16175.83274873, 18056.34394912, 19282.21914334,
     20006.24626009, 20414.15343628, 20639.66981718, 20763.42435719, 20831.12561174, 20868.11080392,
     20888.30264105],
    [4965.28982295, 5025.38045612, 5136.67510967, 5343.17672239, 5723.17881707, 6398.10091437,
     7508.44360294, 9150.62680727, 11311.73143116, 13795.63516793, 16186.47408516, 18081.26060018,
     19332.61770536, 20072.40777584, 20489.35934417, 20719.90875241, 20846.4293277, 20915.646125,
     20953.45866009, 20974.10006581]])
UCS_ROTOR2_SYNC = np.array([
    [2.15371329e02, 2.83812357e02, 3.66877867e02, 4.60566615e02, 5.55704705e02, 6.40471324e02,
     7.06315117e02, 7.51667171e02, 7.80222437e02, 7.97164913e02, 8.06859321e02, 8.12290756e02,
     8.15297782e02, 8.16951585e02, 8.17857830e02, 8.18353436e02, 8.18624175e02, 8.18771986e02,
     8.18852657e02, 8.18896678e02],
    [1.88802037e03, 2.28476088e03, 2.78000154e03, 3.41117879e03, 4.23129187e03, 5.31089177e03,
     6.73193403e03, 8.56265868e03, 1.08004453e04, 1.32860389e04, 1.56703469e04, 1.75831951e04,
     1.88890430e04, 1.96891387e04, 2.01514788e04, 2.04110573e04, 2.05547675e04, 2.06337750e04,
     2.06770552e04, 2.07007192e04],
    [4.00701928e03, 4.11399080e03, 4.30342165e03, 4.63058499e03, 5.17436636e03, 6.03219769e03,
     7.30332537e03, 9.05967180e03, 1.12948065e04, 1.38430517e04, 1.63370844e04, 1.83684523e04,
     1.97674949e04, 2.06278515e04, 2.11255558e04, 2.14050391e04, 2.15597608e04, 2.16448157e04,
     2.16914058e04, 2.17168786e04],
    [3.75678825e04, 3.75949522e04, 3.76446065e04, 3.77357411e04, 3.79031768e04, 3.82113096e04,
     3.87797759e04, 3.98314192e04, 4.17770276e04, 4.53362190e04, 5.16143414e04, 6.19874527e04,
     7.79184129e04, 1.01059654e05, 1.33577562e05, 1.78470328e05, 2.39880642e05, 3.23483351e05,
     4.37008883e05, 5.90956828e05]])


def test_ucs_calc_rotor2_by_hand():
    # ROSS 2.3.0 tests/test_rotor_assembly.py::test_ucs_calc_rotor2 (rotor2, k = logspace(6, 11, 20),
    # rtol 1e-6), with the map built by hand: rotor2 with bearings k, the natural frequencies at
    # speed 0 (each twice: x and y planes), every other one.
    # (every 4th stiffness; the ucs test below checks all 20)
    k = np.logspace(6, 11, 20)[::4]
    wn = np.array([np.asarray(_freqs(rotor2(kk), 0.0, 8))[::2] for kk in k]).T
    assert_allclose(wn, UCS_ROTOR2[:, ::4], rtol=1e-6)


def test_ucs_calc_rotor2_synchronous_by_hand():
    # ROSS 2.3.0 tests/test_rotor_assembly.py::test_ucs_calc_rotor2 (run_ucs(synchronous=True): the
    # forward synchronous critical speeds, rtol 1e-7). Ours (synchronous_critical_speeds) are the
    # roots of the synchronous determinant on both branches, forward and backward: every one of
    # ROSS's forward speeds is among them.
    for j, kk in list(enumerate(np.logspace(6, 11, 20)))[::4]:   # every 4th stiffness
        ours = np.asarray(_sync(rotor2(kk)))
        ours = ours[np.isfinite(ours)]
        for wn in UCS_ROTOR2_SYNC[:, j]:
            assert np.min(np.abs(ours / wn - 1)) < 1e-7, (kk, wn)


def test_ucs_calc_rotor2():
    # ROSS 2.3.0 tests/test_rotor_assembly.py::test_ucs_calc_rotor2 with rotorjax's ucs (ROSS's
    # stiffness_range (6, 11) holds exponents: ours (1e6, 1e11)); non-synchronous rtol 1e-6,
    # synchronous rtol 1e-7 (ROSS's)
    from rotorjax.flexible import ucs

    res = ucs(rotor2(), (1e6, 1e11), 20, 4)
    assert_allclose(np.asarray(res.stiffness), np.logspace(6, 11, 20), rtol=1e-12)
    assert_allclose(np.asarray(res.frequencies).T, UCS_ROTOR2, rtol=1e-6)
    res = ucs(rotor2(), (1e6, 1e11), 20, 4, synchronous=True)
    assert_allclose(np.asarray(res.frequencies).T, UCS_ROTOR2_SYNC, rtol=1e-7)


def test_ucs_calc_rotor8():
    # ROSS 2.3.0 tests/test_rotor_assembly.py::test_ucs_calc (rotor8: rotor3's shaft and disks on
    # speed-dependent bearings kxx = kyy = [1e7, 1.5e7], c = [1e3, 1.5e3] at [50, 5000] rad/s; the map
    # replaces them by k = logspace(6, 11, 20), rtol 1e-7): first column and the first row's start,
    # which ROSS types (86.65811435, 95.66057326, 101.86825429, ...)
    from rotorjax.flexible import ucs
    from rotorjax.models import Bearing

    b = [Bearing(n, kxx=[1e7, 1.5e7], kyy=[1e7, 1.5e7], cxx=[1e3, 1.5e3], cyy=[1e3, 1.5e3], speeds=[50.0, 5000.0])
         for n in (0, 6)]
    r8 = FlexibleRotor(**_shaft(6), disks=[(2,) + D0, (4,) + D1], bearings=b)
    res = ucs(r8, (1e6, 1e11), 20, 4)
    first = [86.65811435, 95.66057326, 101.86825429, 105.77854216, 108.09888143, 109.42658356, 110.17043717,
             110.58225348, 110.80874181, 110.93285112, 111.00072364, 111.03780095, 111.05804338,
             111.06909117, 111.07511968, 111.07840898, 111.0802036, 111.08118271, 111.08171688]
    assert_allclose(np.asarray(res.frequencies)[:19, 0], first, rtol=1e-7)
    # the same first branch by hand (rotor3's geometry with bearings k)
    k = np.logspace(6, 11, 20)[:3]
    by_hand = [float(_freqs(rotor3(kx=kk, ky=kk), 0.0, 1)[0]) for kk in k]
    assert_allclose(by_hand, first[:3], rtol=1e-7)


# ---------------------------------------------------------------------------------------
# tests/test_rotor_assembly.py: a tapered rotor


def test_rotor_conical_frequencies():
    # ROSS 2.3.0 tests/test_rotor_assembly.py::test_rotor_conical_frequencies (4 conical elements,
    # 0.5 m, d 0.1 -> 0.01 m in steps of 0.0225, bearings 1e20 at both ends, speed 0: wn, rtol 1e-5)
    d = np.linspace(0.1, 0.01, 5)
    r = FlexibleRotor([0.125] * 4, np.stack([d[:-1], d[1:]], axis=1),
                      bearings=[(0, 1e20, 1e20, 0.0, 0.0), (4, 1e20, 1e20, 0.0, 0.0)], **STEEL)
    wn = np.asarray(_freqs(r, 0.0, 6))
    assert_allclose(wn, [1630.7509182, 1630.75091824, 9899.54379138, 9899.54396231, 21074.45440319,
                         21074.45440372], rtol=1e-5)


# ---------------------------------------------------------------------------------------
# tests/test_rotor_assembly.py: several unbalances, deflected shape (rotorjax's API)


def test_freq_response_two_unbalances():
    # ROSS 2.3.0 tests/test_rotor_assembly.py::test_freq_response_w_force, last part: unbalances
    # 0.001 kg m at nodes 2 and 3, phase 0, at 0, 150, 300, 450 rad/s: |x|, |y| at node 0 (rtol 1e-7)
    from rotorjax.flexible import unbalance_response_many

    X, Y = unbalance_response_many(rotor3(), [(2, 0.001, 0.0), (3, 0.001, 0.0)], np.linspace(0.0, 450.0, 4),
                                   probe_nodes=[0])
    assert_allclose(np.abs(np.asarray(X[:, 0])), [0.0, 4.80337594e-06, 2.31170438e-04, 6.90062268e-05],
                    rtol=1e-7, atol=1e-20)
    assert_allclose(np.abs(np.asarray(Y[:, 0])), [0.0, 3.15307288e-06, 1.87793923e-04, 8.08531462e-05],
                    rtol=1e-7, atol=1e-20)


def test_deflected_shape_api():
    # ROSS 2.3.0 tests/test_rotor_assembly.py::test_deflected_shape with rotorjax's deflected_shape:
    # the major axis at nodes 0 and 1 (0.00274183, 4.9134099e-05) and (0.00252877, 4.58914054e-05)
    # as length and angle from x (rtol 1e-4)
    from rotorjax.flexible import deflected_shape

    r = FlexibleRotor(**_shaft(6), disks=[(2,) + D0, (4,) + D1],
                      bearings=[(0, 1e6, 2e6, 1e3, 1e3), (6, 1e6, 2e6, 1e3, 1e3)])
    ds = deflected_shape(r, [(0, 1.0, 0.0)], 50.0)
    expected = np.array([0.00274183 + 4.91340990e-05j, 0.00252877 + 4.58914054e-05j])
    assert_allclose(np.asarray(ds.major)[:2], np.abs(expected), rtol=1e-4)
    assert_allclose(np.mod(np.asarray(ds.angle)[:2], np.pi), np.angle(expected), rtol=1e-4)


# ---------------------------------------------------------------------------------------
# tests/test_rotor_assembly.py::test_rotor_it: the rotor's transverse moment of inertia about
# its centre of gravity. rotorjax has no `It` attribute; the kinetic energy of a rigid tilt
# about the CG is exact in the element space, so `It = u^T M u` with u the unit rigid tilt
# (x = z - CG, sx = 1), which is what ROSS's formula computes.


def _rigid_tilt_inertia(rotor):
    M = np.asarray(_matrices(rotor)[0])
    z = np.asarray(rotor.node_positions)
    mx = M[0::4, 0::4]
    cg = np.sum(mx, axis=0) @ z / mx.sum()
    u = np.zeros(rotor.n_dofs)
    u[0::4], u[2::4] = z - cg, 1.0
    return u @ M @ u, cg


def test_rotor_it():
    # ROSS 2.3.0 tests/test_rotor_assembly.py::test_rotor_it (rel 2e-8): rotor1 and rotor3a (no
    # disks): m (3 r^2 + L^2) / 12; rotor3b (both disks at the centre node 3): plus the disks' It;
    # rotor3c (massless shaft, disks at the ends 0 and 1.5 m): the disks' It + m d^2; rotor3:
    # the parallel-axis sum of all. (rho = 0 is not accepted: rotor3c's shaft has rho 1e-12.)
    r = 0.05 / 2
    it1, _ = _rigid_tilt_inertia(rotor1())
    m1 = 7.6674495701675891
    assert it1 == pytest.approx(m1 / 12 * (3 * r**2 + 0.5**2), rel=2e-8)
    m3a = 3 * m1
    it3a = m3a / 12 * (3 * r**2 + 1.5**2)
    bearings = [(0, 1e6, 0.8e6, 0.0, 0.0), (6, 1e6, 0.8e6, 0.0, 0.0)]
    assert _rigid_tilt_inertia(FlexibleRotor(**_shaft(6), bearings=bearings))[0] == pytest.approx(it3a, rel=2e-8)
    it3b, _ = _rigid_tilt_inertia(rotor3(disk_nodes=(3, 3)))
    assert it3b == pytest.approx(it3a + 0.17808928257067666 + 0.42358058405433824, rel=2e-8)
    r3c = FlexibleRotor([0.25] * 6, 0.05, E=211e9, G=211e9 / 2.6, rho=1e-12, disks=[(0,) + D0, (6,) + D1],
                        bearings=bearings)
    it3c, cg = _rigid_tilt_inertia(r3c)
    expected = (0.17808928257067666 + 32.58972765304033 * (0 - cg) ** 2 + 0.42358058405433824
                + 51.5252611115262 * (1.5 - cg) ** 2)
    assert it3c == pytest.approx(expected, rel=2e-8)
    it3, cg = _rigid_tilt_inertia(rotor3())
    expected = ((it3a + (cg - 0.75) ** 2 * m3a) + 0.17808928257067666 + 32.58972765304033 * (0.5 - cg) ** 2
                + 0.42358058405433824 + 51.5252611115262 * (1.0 - cg) ** 2)
    assert it3 == pytest.approx(expected, rel=2e-8)


# ---------------------------------------------------------------------------------------
# tests/test_results.py::test_campbell_plot: the Campbell diagram's crossings with the 1x and 2x
# lines for ROSS's rotor_example (rotor3's shaft, two equal disks at nodes 2 and 4, bearings
# kxx 1e6, kyy 0.8e6), frequencies between 2000 and 10000 RPM.


def test_campbell_crossings_rotor_example():
    # ROSS 2.3.0 tests/test_results.py::test_campbell_plot (rtol 1e-7 on ROSS's values): ROSS finds
    # the crossings by linear interpolation of wd on its 101-point speed grid (0..400 rad/s, step
    # 4); ours are the exact crossings (scan and bisection), which agree with ROSS's to 4e-7 (the
    # interpolation's error); we check at 1e-6.
    rpm = np.pi / 30
    r = FlexibleRotor(**_shaft(6), disks=[(2,) + D0, (4,) + D0], bearings=[(0, 1e6, 0.8e6, 0.0, 0.0),
                                                                            (6, 1e6, 0.8e6, 0.0, 0.0)])
    freqs = jax.jit(lambda s: campbell(r, s, 8).frequencies)
    one = jax.jit(lambda s: _freqs(r, s, 8))
    grid = np.linspace(1.0, 400.0, 400)
    f = np.asarray(freqs(grid))
    found = []
    for h in (1, 2):
        for k in range(8):
            g = f[:, k] - h * grid
            for i in np.nonzero(np.sign(g[:-1]) != np.sign(g[1:]))[0]:
                lo, hi = grid[i], grid[i + 1]
                for _ in range(60):
                    mid = 0.5 * (lo + hi)
                    if np.sign(float(one(mid)[k]) - h * mid) == np.sign(g[i]):
                        lo = mid
                    else:
                        hi = mid
                s = 0.5 * (lo + hi)
                if 2000 * rpm <= h * s <= 10000 * rpm:
                    found.append((s / rpm, h * s / rpm))
    found = np.array(sorted(found))
    ross = np.array(sorted(zip([2590.2641754, 1306.51513941, 2868.14592367, 1420.76907353, 3264.81334336],
                               [2590.2641754, 2613.03027882, 2868.14592367, 2841.53814705, 6529.62668672])))
    assert found.shape == ross.shape
    assert_allclose(found, ross, rtol=1e-6)
