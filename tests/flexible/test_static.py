"""Static deflection under gravity: against ROSS 2.3.0's `run_static` (reference
numbers from `ross_static_reference.py`, stored in `data/ross_static.json`), a
closed form, and the balance of forces.

ROSS's conventions: its shear force and bending moment are the negatives of ours
(ours: a simply supported beam has `V(0) = +R` and a sagging `M = +w L^2 / 8`,
checked against the closed form below), and its deformation is computed with the
bearings made rigid (`k = 1e20`): with two bearings the shaft's deflection relative
to the line through the bearing nodes is the same as ours.
"""

import json
import os

import numpy as np
import pytest

from rotorjax._errors import NumericalError
from rotorjax.flexible import FlexibleRotor, static
from rotorjax.models import RotorScene
from rotorjax.models._validate import InputError

DATA = os.path.join(os.path.dirname(__file__), "data", "ross_static.json")


@pytest.fixture(scope="module")
def reference():
    with open(DATA) as f:
        return json.load(f)


def _rotor(spec, **kw):
    return FlexibleRotor(np.array(spec["lengths"]), spec["d_out"], E=spec["E"], G=spec["G"], rho=spec["rho"],
                         disks=[tuple(d) for d in spec["disks"]], bearings=[tuple(b) for b in spec["bearings"]],
                         **kw)


def _close(ours, ref, rtol=1e-8):
    ours, ref = np.asarray(ours, dtype=float), np.asarray(ref, dtype=float)
    np.testing.assert_allclose(ours, ref, rtol=rtol, atol=rtol * np.abs(ref).max())


@pytest.mark.parametrize("case", ["rotor_example", "overhung_disk"])
def test_static_matches_ross(reference, case):
    ref = reference["cases"][case]
    spec = ref["rotor"]
    res = static(_rotor(spec), gravity=reference["gravity"])
    b_nodes = [b[0] for b in spec["bearings"]]
    # reactions: the force each bearing exerts on the shaft (up: +y), as ROSS
    _close(np.asarray(res.bearing_reactions)[:, 1], [ref["bearing_forces"][f"node_{n}"] for n in b_nodes])
    np.testing.assert_allclose(np.asarray(res.bearing_reactions)[:, 0], 0.0, atol=1e-9)
    # disks: ROSS gives the weight's magnitude
    _close(-np.asarray(res.disk_forces)[:, 1], [ref["disk_forces"][f"node_{d[0]}"] for d in spec["disks"]])
    # shear and moment at both ends of each element: ROSS's are -V, -M
    _close(np.asarray(res.element_ends).ravel(), ref["shear_positions"])
    _close(np.asarray(res.shear)[:, :, 1].ravel(), -np.asarray(ref["shear"]))
    _close(np.asarray(res.moment)[:, :, 1].ravel(), -np.asarray(ref["moment"]))
    # deflection relative to the line through the two bearing nodes (ROSS: rigid bearings)
    z, y = np.asarray(res.positions), np.asarray(res.displacement)[:, 1]
    i, j = b_nodes
    line = y[i] + (y[j] - y[i]) * (z - z[i]) / (z[j] - z[i])
    _close(y - line, ref["deformation_y"])
    # the total weight: ROSS's shaft weight plus the disks'
    _close(-np.asarray(res.weight)[1], ref["shaft_weight"] + sum(ref["disk_forces"].values()))


def test_simply_supported_uniform_beam_closed_form():
    """Pinned ends (fixed x, y at both end nodes), Euler-Bernoulli: reactions W/2,
    mid-span moment w L^2 / 8 (sagging, positive), deflection -5 w L^4 / (384 E I)."""
    n, L, d, E, rho, g = 8, 1.2, 0.04, 2.1e11, 7800.0, 9.81
    rotor = FlexibleRotor([L / n] * n, d, E=E, G=8e10, rho=rho, theory="euler-bernoulli",
                          fixed_dofs=[(0, 0), (0, 1), (n, 0), (n, 1)])
    res = static(rotor, gravity=g)
    A, I = np.pi * d**2 / 4, np.pi * d**4 / 64
    w = rho * A * g
    W = w * L
    cons = np.asarray(res.constraint_reactions)
    # the constraint holds the shaft up: the force it exerts is +W/2 at each end
    np.testing.assert_allclose(cons[[0, n], 1], [W / 2, W / 2], rtol=1e-10)
    mid = n // 2
    np.testing.assert_allclose(np.asarray(res.moment)[mid - 1, 1, 1], w * L**2 / 8, rtol=1e-10)
    np.testing.assert_allclose(np.asarray(res.moment)[mid, 0, 1], w * L**2 / 8, rtol=1e-10)
    np.testing.assert_allclose(np.asarray(res.shear)[0, 0, 1], W / 2, rtol=1e-10)
    np.testing.assert_allclose(np.asarray(res.shear)[-1, 1, 1], -W / 2, rtol=1e-10)
    np.testing.assert_allclose(np.asarray(res.displacement)[mid, 1], -5 * w * L**4 / (384 * E * I), rtol=1e-10)
    np.testing.assert_allclose(np.asarray(res.moment)[[0, -1], [0, 1], 1], 0.0, atol=1e-9 * W * L)


def _three_bearing_rotor(**kw):
    return FlexibleRotor([0.2] * 8, 0.06, disks=[(3, 15.0, 0.05, 0.1), (8, 8.0, 0.02, 0.04)],
                         bearings=[(0, 5e7, 4e7, 0, 0), (4, 2e7, 2e7, 0, 0), (7, 3e7, 3e7, 0, 0, 1e6, -1e6, 0, 0)],
                         **kw)


def test_reactions_balance_the_weight_and_shear_jumps_are_point_loads():
    """Statically indeterminate (three bearings, cross-coupled stiffness): the
    reactions sum to the weight; the shear jumps at a node by the point loads there;
    the moment is continuous; dM/dz = V on average over each element."""
    rotor = _three_bearing_rotor()
    res = static(rotor)
    np.testing.assert_allclose(np.asarray(res.bearing_reactions).sum(0), -np.asarray(res.weight),
                               rtol=1e-10, atol=1e-8)
    V, Mb = np.asarray(res.shear)[:, :, 1], np.asarray(res.moment)[:, :, 1]
    loads = np.zeros(rotor.n_nodes)
    for node, r in zip(rotor.bearing_nodes, np.asarray(res.bearing_reactions)[:, 1]):
        loads[node] += r
    for node, f in zip(rotor.disk_nodes, np.asarray(res.disk_forces)[:, 1]):
        loads[node] += f
    np.testing.assert_allclose(V[1:, 0] - V[:-1, 1], loads[1:-1], atol=1e-8 * np.abs(loads).max())
    np.testing.assert_allclose(Mb[1:, 0], Mb[:-1, 1], atol=1e-8 * np.abs(Mb).max())
    L = np.asarray(rotor.lengths)
    np.testing.assert_allclose((Mb[:, 1] - Mb[:, 0]) / L, V.mean(axis=1), atol=1e-8 * np.abs(V).max())
    # the free end (node 8, overhung disk) carries no moment, its shear is the disk's weight
    assert abs(Mb[-1, 1]) < 1e-8 * np.abs(Mb).max()
    np.testing.assert_allclose(V[-1, 1], -loads[-1], rtol=1e-10)   # V = 0 beyond the free end


def test_axis_x_mirrors_axis_y_and_a_scene_uses_its_rotor():
    rotor = FlexibleRotor([0.25] * 6, 0.05, disks=[(2, 30.0, 0.2, 0.3)], bearings=[(0, 1e6, 1e6, 0, 0),
                                                                                   (6, 1e6, 1e6, 0, 0)])
    ry, rx = static(rotor, axis="y"), static(rotor, axis="x")
    np.testing.assert_allclose(np.asarray(rx.displacement)[:, 0], np.asarray(ry.displacement)[:, 1], rtol=1e-12)
    np.testing.assert_allclose(np.asarray(rx.moment)[:, :, 0], np.asarray(ry.moment)[:, :, 1], rtol=1e-12)
    rs = static(RotorScene(rotor, 100.0))
    np.testing.assert_allclose(np.asarray(rs.displacement), np.asarray(ry.displacement), rtol=1e-14)
    assert float(ry.residual) < 1e-12


def test_static_bad_input_and_unsupported_rotor():
    rotor = FlexibleRotor([0.25] * 4, 0.05)
    with pytest.raises(NumericalError, match=r"the stiffness matrix is singular \(the rotor is not supported\)"):
        static(rotor)
    one = FlexibleRotor([0.25] * 4, 0.05, bearings=[(2, 1e6, 1e6, 0, 0)])   # free to tilt about the bearing
    with pytest.raises(NumericalError, match="singular"):
        static(one)
    ok = FlexibleRotor([0.25] * 4, 0.05, bearings=[(0, 1e6, 1e6, 0, 0), (4, 1e6, 1e6, 0, 0)])
    with pytest.raises(InputError, match="axis"):
        static(ok, axis="z")
    with pytest.raises(InputError, match="gravity"):
        static(ok, gravity=float("nan"))
    with pytest.raises(InputError, match="rotor must be"):
        static("rotor")


def test_supports_point_masses_taper_and_bearing_mass():
    """A tapered shaft, point masses (one heavier in y than in x), a bearing with a
    mass coefficient (an added mass, not a weight) standing on a pedestal: the
    reactions on the shaft balance the weight of shaft (exact for the linear taper:
    rho pi/4 L/3 (d1^2 + d1 d2 + d2^2) per element), disk and point masses (y
    masses); the pedestal's own weight goes to the ground."""
    from rotorjax.models._fe_rotor import Bearing, Support

    rotor = FlexibleRotor([0.25] * 6, [[0.05, 0.06]] * 3 + [[0.06, 0.05]] * 3, disks=[(2, 20.0, 0.1, 0.2)],
                          bearings=[Bearing(0, kxx=1e7, mxx=3.0), (6, 2e7, 2e7, 0, 0)],
                          point_masses=[(3, 5.0), (5, 2.0, 4.0)], supports=[Support(0, 50.0, 5e6)])
    res = static(rotor)
    shaft = 7810.0 * np.pi / 4 * 0.25 / 3 * (0.05**2 + 0.05 * 0.06 + 0.06**2) * 6
    np.testing.assert_allclose(-float(res.weight[1]), 9.80665 * (shaft + 20.0 + 5.0 + 4.0), rtol=1e-12)
    np.testing.assert_allclose(np.asarray(res.bearing_reactions).sum(0), -np.asarray(res.weight), atol=1e-9)
    assert float(res.residual) < 1e-12
