"""Building finite-element rotors: tapered (conical) elements against ROSS 2.3.0,
materials, point masses, bearings with speed tables and mass coefficients, pedestal
supports, the table spline, and the errors for bad input.

ROSS's numbers come from `ross_fe_building_reference.py` (run with an interpreter
that has ROSS) and are stored in `data/ross_fe_building.json`.
"""

import json
import os

import jax
import jax.numpy as jnp
import numpy as np
import pytest
from scipy.interpolate import CubicSpline
from scipy.linalg import eigh

from rotorjax.flexible import damped_frequencies, modes
from rotorjax.models import MATERIALS, Bearing, FlexibleRotor, Support, material
from rotorjax.models._validate import InputError
from rotorjax.models._fe_elements import element_matrices, rotary_mass, stiffness, translational_mass
from rotorjax.models._fe_rotor import cowper_shear_coefficient
from rotorjax.models._interpolate import spline
from tests.helpers import central_difference

DATA = os.path.join(os.path.dirname(__file__), "data", "ross_fe_building.json")

# ROSS's element dofs (x, y, z, alpha, beta, theta) per node -> ours (x, y, sx, sy):
# sx = beta, sy = -alpha; z and theta (axial, torsion) are uncoupled from bending.
ROSS_INDEX = np.array([0, 1, 4, 3, 6, 7, 10, 9])
ROSS_SIGN = np.array([1, 1, 1, -1, 1, 1, 1, -1], dtype=float)
THEORY = {(True, True): "timoshenko", (False, True): "rayleigh", (False, False): "euler-bernoulli"}


@pytest.fixture(scope="module")
def reference():
    with open(DATA) as f:
        return json.load(f)


def _ross_to_ours(a):
    a = np.asarray(a)
    return ROSS_SIGN[:, None] * a[np.ix_(ROSS_INDEX, ROSS_INDEX)] * ROSS_SIGN[None, :]


def _relative(a, b):
    return np.max(np.abs(np.asarray(a) - np.asarray(b))) / np.max(np.abs(np.asarray(b)))


# --- elements ----------------------------------------------------------------------------

@pytest.mark.parametrize("k", range(6))
def test_element_matrices_equal_ross(reference, k):
    """Tapered hollow and solid elements, Timoshenko / Rayleigh / Euler-Bernoulli:
    M, G, K equal ROSS 2.3.0's to 1e-12 (relative to the largest entry), directly
    and as a one-element `FlexibleRotor` builds them (its own Cowper kappa)."""
    e = reference["elements"][k]
    theory = THEORY[(e["shear_effects"], e["rotary_inertia"])]
    ross = [_ross_to_ours(e[name]) for name in ("M", "G_matrix", "K")]
    lateral = np.zeros(12, dtype=bool)
    lateral[ROSS_INDEX] = True
    for name in ("M", "G_matrix", "K"):   # nothing couples bending to ROSS's other dofs
        assert np.all(np.asarray(e[name])[np.ix_(lateral, ~lateral)] == 0)
    d_out, d_in = [e["odl"], e["odr"]], [e["idl"], e["idr"]]
    kappa = cowper_shear_coefficient(e["nu"], np.mean(d_out), np.mean(d_in))
    if e["kappa"] is not None:
        np.testing.assert_allclose(kappa, e["kappa"], rtol=1e-14)
    ours = element_matrices(e["E"], e["G"], e["rho"], jnp.array(d_out), jnp.array(d_in), e["L"], kappa,
                            theory == "timoshenko", theory != "euler-bernoulli")
    rotor = FlexibleRotor([e["L"]], [d_out], [d_in], E=e["E"], G=e["G"], rho=e["rho"], theory=theory)
    assert rotor.tapered
    built = [a[0] for a in rotor.element_matrices()]
    for a, b, c in zip(ours, built, ross):
        assert _relative(a, c) < 1e-12
        assert _relative(b, c) < 1e-12


@pytest.mark.parametrize("theory", ["timoshenko", "rayleigh", "euler-bernoulli"])
def test_cylindrical_tapered_element_is_the_cylindrical_element(theory):
    """Left == right: Genta's element is the Przemieniecki / Friswell closed form,
    and a rotor given `(left, right)` pairs equals one given diameters."""
    E, G, rho, L, do, di = 205e9, 79e9, 7900.0, 0.17, 0.07, 0.025
    kappa = cowper_shear_coefficient(E / (2 * G) - 1, do, di)
    shear, rotary = theory == "timoshenko", theory != "euler-bernoulli"
    M, G1, K = element_matrices(E, G, rho, jnp.array([do, do]), jnp.array([di, di]), L, kappa, shear, rotary)
    A, I = np.pi / 4 * (do**2 - di**2), np.pi / 64 * (do**4 - di**4)
    phi = 12 * E * I / (kappa * G * A * L**2) if shear else 0.0
    ix, iy = [0, 2, 4, 6], [1, 3, 5, 7]
    mp = translational_mass(rho, A, L, phi) + (rotary_mass(rho, I, L, phi) if rotary else 0.0)
    for a in (np.asarray(M)[np.ix_(ix, ix)], np.asarray(M)[np.ix_(iy, iy)]):
        assert _relative(a, mp) < 1e-14
    assert _relative(np.asarray(K)[np.ix_(ix, ix)], stiffness(E, I, L, phi)) < 1e-14
    assert _relative(np.asarray(G1)[np.ix_(ix, iy)], rotary_mass(rho, 2 * I, L, phi)) < 1e-14
    lengths, d = [0.1, 0.2, 0.15], [0.05, 0.06, 0.04]
    plain = FlexibleRotor(lengths, d, 0.01, theory=theory, bearings=[(0, 1e7, 1e7, 0, 0), (3, 1e7, 1e7, 0, 0)])
    pairs = FlexibleRotor(lengths, [[x, x] for x in d], 0.01, theory=theory,
                          bearings=[(0, 1e7, 1e7, 0, 0), (3, 1e7, 1e7, 0, 0)])
    assert not plain.tapered and pairs.tapered and pairs.d_in.shape == (3, 2)
    for a, b in zip(plain.matrices(), pairs.matrices()):
        np.testing.assert_allclose(b, a, rtol=1e-14, atol=1e-14 * float(jnp.max(jnp.abs(a))))


def _split(lengths, d_out, d_in, n):
    """Each tapered element cut into `n` (the diameters' taper is linear: exact geometry)."""
    L, do, di = [], [], []
    for l, (o0, o1), (i0, i1) in zip(lengths, d_out, d_in):
        t = np.linspace(0, 1, n + 1)
        o, i = o0 + (o1 - o0) * t, i0 + (i1 - i0) * t
        L += [l / n] * n
        do += [[o[j], o[j + 1]] for j in range(n)]
        di += [[i[j], i[j + 1]] for j in range(n)]
    return np.array(L), np.array(do), np.array(di)


@pytest.mark.parametrize("theory, rate, last", [("euler-bernoulli", 8.0, 1e-4), ("timoshenko", 2.5, 4e-3)])
def test_tapered_shaft_frequencies_converge_as_elements_split(theory, rate, last):
    """A pinned-pinned, strongly tapered hollow shaft: the first three frequencies'
    errors against a 64-way split fall monotonically as each element is cut into
    2, 4, 8. Euler-Bernoulli converges fast (14x from 4 to 8 elements per element);
    Timoshenko at second order only (2.7x here, 4x asymptotically): Genta's
    element takes `phi` and Cowper's `kappa` from the mid-length section."""
    lengths = [0.3, 0.4, 0.3]
    d_out, d_in = [[0.04, 0.08], [0.08, 0.06], [0.06, 0.03]], [[0.01, 0.03], [0.03, 0.02], [0.02, 0.0]]

    def freqs(n):
        L, do, di = _split(lengths, d_out, d_in, n)
        r = FlexibleRotor(L, do, di, theory=theory, fixed_dofs=((0, 0), (0, 1), (len(L), 0), (len(L), 1)))
        M, _, _, K = (np.asarray(a) for a in r.reduced_matrices())
        # the symmetric solver: the fine reference's stiffness is ill-conditioned
        return np.sqrt(eigh(K, M, eigvals_only=True)[:6:2])   # x and y planes pair up

    ref = freqs(64)
    errors = np.array([np.abs(freqs(n) / ref - 1) for n in (1, 2, 4, 8)])
    assert np.all(errors[1:] < errors[:-1])
    assert np.all(errors[-1] * rate < errors[-2])
    assert errors[-1].max() < last


# --- against ROSS: rotors --------------------------------------------------------------

def _our_rotor(ref, name):
    r = ref["rotors"][name]
    data, mats = r["data"], r["materials"]
    per = {k: np.array([mats[m][k] for m in data["materials"]]) for k in ("E", "G", "rho", "nu")}
    bearings = []
    for b in data["bearings"]:
        kw = {k: v for k, v in b.items() if k != "node"}
        bearings.append(Bearing(b["node"], **kw))
    supports = [Support(s["bearing"], s["m"], s["kxx"], s["kyy"], s["cxx"], s["cyy"]) for s in data["supports"]]
    return FlexibleRotor(data["lengths"], data["d_out"], data["d_in"], E=per["E"], G=per["G"], rho=per["rho"],
                         nu=per["nu"], disks=[tuple(d) for d in data["disks"]], bearings=bearings,
                         point_masses=[tuple(p) for p in data["point_masses"]], supports=supports)


@pytest.mark.parametrize("name", ["tapered_supported", "bearing_mass"])
def test_damped_modes_match_ross(reference, name):
    """Tapered elements of two materials, a point mass, bearings with 4-speed tables
    (and, in `bearing_mass`, mass coefficients), a bearing on a pedestal: the first
    eight damped natural frequencies and log decrements at three speeds inside the
    tables agree with ROSS's lateral modes (relative 1e-9 and 1e-7: the same
    matrices; the brief asked for 1e-6)."""
    r = reference["rotors"][name]
    rotor = _our_rotor(reference, name)
    assert rotor.tapered and rotor.speed_dependent
    assert rotor.n_dofs == 4 * rotor.n_nodes + 2 * len(r["data"]["supports"])
    assert r["largest_nonlateral_share"] < 1e-9
    for speed, wd, logdec in zip(r["data"]["speeds"], r["damped_frequencies"], r["log_dec"]):
        m = modes(rotor, speed, len(wd))
        np.testing.assert_allclose(np.asarray(m.frequencies), wd, rtol=1e-9)   # measured: 1e-12
        np.testing.assert_allclose(np.asarray(m.log_dec), logdec, rtol=1e-7)   # measured: 7e-10


def test_scene_takes_tabulated_bearings_at_the_asked_speed(reference):
    """A `RotorScene` built at one speed gives the rotor's own linear matrices at
    another (the tables re-evaluated)."""
    from rotorjax.models import RotorScene

    rotor = _our_rotor(reference, "tapered_supported")
    scene = RotorScene(rotor, 500.0)
    for speed in (500.0, 900.0):
        np.testing.assert_allclose(damped_frequencies(scene, speed, 6), damped_frequencies(rotor, speed, 6),
                                   rtol=1e-11)


def test_speed_table_moves_the_frequencies_and_differentiates(reference):
    """The coefficients follow the running speed, and a frequency's derivative with
    respect to the speed (through the tables) is finite and matches a difference."""
    rotor = _our_rotor(reference, "tapered_supported")
    f = lambda s: damped_frequencies(rotor, s, 4)[0]
    K0 = np.asarray(rotor.reduced_matrices(0.0)[3])
    assert not np.allclose(K0, np.asarray(rotor.reduced_matrices(1000.0)[3]))
    g = jax.grad(f)(700.0)
    assert np.isfinite(g)
    np.testing.assert_allclose(g, central_difference(f, 700.0, 1e-2), rtol=1e-5)


# --- bearings, supports, point masses --------------------------------------------------------

def test_bearing_defaults_and_coefficients_at_table_speeds():
    speeds = [0.0, 100.0, 250.0, 400.0, 700.0]
    kxx = [1e6, 1.3e6, 1.2e6, 1.8e6, 2.0e6]
    b = Bearing(1, kxx=kxx, kxy=[0, 1e4, 2e4, 3e4, 5e4], cxx=50.0, mxx=[1, 2, 3, 4, 5], myx=0.3, speeds=speeds)
    rotor = FlexibleRotor([0.2, 0.2], 0.05, bearings=[(0, 1e7, 2e7, 10.0, 20.0), b])
    assert rotor.speed_dependent and not rotor.tapered
    assert np.all(np.isnan(np.asarray(rotor.bearing_params[1])))
    np.testing.assert_array_equal(rotor.bearing_params[0], [1e7, 2e7, 0, 0, 10, 20, 0, 0])
    for i, s in enumerate(speeds):
        c = np.asarray(rotor.bearing_coefficients(s))
        np.testing.assert_allclose(c[0], [1e7, 2e7, 0, 0, 10, 20, 0, 0, 0, 0, 0, 0])
        # kyy = kxx, cyy = cxx, myy = mxx by default
        np.testing.assert_allclose(c[1], [kxx[i], kxx[i], 1e4 * [0, 1, 2, 3, 5][i], 0, 50, 50, 0, 0,
                                          i + 1, i + 1, 0, 0.3], rtol=1e-12, atol=1e-9)
    M0 = np.asarray(FlexibleRotor([0.2, 0.2], 0.05).matrices()[0])
    M = np.asarray(rotor.matrices(250.0)[0])
    np.testing.assert_allclose((M - M0)[4:6, 4:6], [[3.0, 0.0], [0.3, 3.0]], atol=1e-12)
    assert np.all((M - M0)[:4] == 0)


def test_tuple_and_constant_bearing_build_the_same_rotor():
    a = FlexibleRotor([0.3, 0.3], 0.05, bearings=[(0, 1e6, 2e6, 10, 20, 1e5, -1e5, 1, 2), (2, 1e6, 1e6, 5, 5)])
    b = FlexibleRotor([0.3, 0.3], 0.05, bearings=[
        Bearing(0, kxx=1e6, kyy=2e6, kxy=1e5, kyx=-1e5, cxx=10, cyy=20, cxy=1, cyx=2), Bearing(2, kxx=1e6, cxx=5)])
    assert not b.speed_dependent
    for x, y in zip(a.matrices(), b.matrices(123.0)):
        np.testing.assert_array_equal(x, y)


def test_point_masses_add_translational_mass_only():
    base = FlexibleRotor([0.3, 0.3], 0.05)
    r = FlexibleRotor([0.3, 0.3], 0.05, point_masses=[(1, 2.0), (2, 1.0, 3.0)])
    dM = np.asarray(r.matrices()[0] - base.matrices()[0])
    expected = np.zeros_like(dM)
    expected[4, 4] = expected[5, 5] = 2.0
    expected[8, 8], expected[9, 9] = 1.0, 3.0
    np.testing.assert_allclose(dM, expected, rtol=0, atol=1e-13)


def test_support_pedestal_dofs_and_stiff_support_limit():
    """A support adds the pedestal's (x, y) after the shaft's dofs, the bearing acts
    on the relative motion; a light, very stiff pedestal gives the grounded rotor."""
    bearings = [(0, 1e7, 1.5e7, 100.0, 100.0), (4, 2e7, 2e7, 200.0, 150.0)]
    args = ([0.2] * 4, 0.06)
    ground = FlexibleRotor(*args, disks=[(2, 10.0, 0.05, 0.1)], bearings=bearings)
    r = FlexibleRotor(*args, disks=[(2, 10.0, 0.05, 0.1)], bearings=bearings,
                      supports=[(1, 5.0, 3e7, 4e7, 10.0, 20.0)])
    assert r.n_dofs == ground.n_dofs + 2 and r.support_dofs(0) == (20, 21)
    M, C, G1, K = (np.asarray(a) for a in r.matrices())
    K = K - np.asarray(r.shaft_matrices()[2])
    assert M[20, 20] == M[21, 21] == 5.0
    np.testing.assert_allclose(K[np.ix_([16, 17, 20, 21], [16, 17, 20, 21])],
                               [[2e7, 0, -2e7, 0], [0, 2e7, 0, -2e7], [-2e7, 0, 5e7, 0], [0, -2e7, 0, 6e7]])
    np.testing.assert_allclose(C[20, 20], 210.0)
    assert np.all(G1[20:] == 0) and np.array_equal(K, K.T)
    stiff = FlexibleRotor(*args, disks=[(2, 10.0, 0.05, 0.1)], bearings=bearings,
                          supports=[Support(1, 1e-3, 1e13, cxx=0.0)])
    np.testing.assert_allclose(damped_frequencies(stiff, 300.0, 4), damped_frequencies(ground, 300.0, 4),
                               rtol=1e-5)
    assert r.supports[0].bearing == 1 and float(r.supports[0].kyy) == 4e7


# --- materials -------------------------------------------------------------------------------

def test_materials_library():
    assert set(MATERIALS) >= {"steel", "stainless", "aluminium", "titanium"}
    steel = material("Steel")
    assert (steel.E, steel.G, steel.rho) == (211e9, 81.2e9, 7810.0)
    for m in MATERIALS.values():
        assert m.source and 1e3 < m.rho < 1e4 and 0 < m.nu < 0.5
        np.testing.assert_allclose(m.G, m.E / (2 * (1 + m.nu)), rtol=1e-12)
    r = FlexibleRotor([0.1, 0.1], 0.05, **material("aluminium").shaft())
    assert float(r.rho) == 2700.0 and float(r.nu) == 0.33
    with pytest.raises(InputError, match="unknown material 'unobtainium'; known: aluminium, stainless, steel"):
        material("unobtainium")


# --- the table spline ---------------------------------------------------------------------------

@pytest.mark.parametrize("n", [2, 3, 4, 5, 8])
def test_spline_is_not_a_knot_inside_and_linear_outside(n):
    rng = np.random.default_rng(n)
    x = np.sort(rng.uniform(0, 1000, n))
    y = rng.normal(size=(2, n)) * 1e6
    cs = CubicSpline(x, y, axis=1, bc_type="not-a-knot")
    inside = np.linspace(x[0], x[-1], 41)
    ours = np.asarray(jax.vmap(lambda s: spline(x, y, s))(inside)).T
    np.testing.assert_allclose(ours, cs(inside), rtol=1e-12, atol=1e-9)
    d = cs.derivative()
    for s, end in ((x[0] - 150.0, x[0]), (x[-1] + 300.0, x[-1])):
        np.testing.assert_allclose(spline(x, y, s), cs(end) + d(end) * (s - end), rtol=1e-11)
    if n == 3:   # the parabola through the points
        np.testing.assert_allclose(ours[0], np.polyval(np.polyfit(x, y[0], 2), inside), rtol=1e-9)


def test_tables_pass_through_their_points_where_ross_smooths(reference):
    """With 5 speeds ROSS's `UnivariateSpline` (smoothing `s = 5`) misses its own
    table points (by 0.29 kg of 3.5 kg on mxx, 1.5 of 90 N s/m on cxx); ours
    returns the table's values at its speeds."""
    t = reference["table_5_speeds"]
    b = Bearing(0, kxx=1e7, cxx=t["values"]["cxx"], mxx=t["values"]["mxx"], speeds=t["speeds"])
    rotor = FlexibleRotor([0.2], 0.05, bearings=[b])
    ours = np.array([rotor.bearing_coefficients(s)[0] for s in t["speeds"]])
    np.testing.assert_allclose(ours[:, 4], t["values"]["cxx"], rtol=1e-13)
    np.testing.assert_allclose(ours[:, 8], t["values"]["mxx"], rtol=1e-13)
    ross_miss = np.abs(np.array(t["ross_at_speeds"]["mxx"]) - t["values"]["mxx"]) / t["values"]["mxx"]
    assert ross_miss.max() > 0.05


def test_spline_gradients_are_finite_and_right():
    x = np.array([0.0, 200.0, 500.0, 900.0, 1000.0])
    y = np.array([1.0, 3.0, 2.0, 5.0, 4.0])
    d = CubicSpline(x, y).derivative()
    for s in (-50.0, 0.0, 200.0, 333.0, 1000.0, 1200.0):
        g = jax.grad(lambda t: spline(x, y, t))(s)
        assert np.isfinite(g)
        np.testing.assert_allclose(g, d(np.clip(s, x[0], x[-1])), rtol=1e-10, atol=1e-14)
    gy = jax.grad(lambda v: spline(x, v, 333.0))(jnp.asarray(y))
    fd = [central_difference(lambda h: float(spline(x, y + h * np.eye(5)[i], 333.0)), 0.0, 1e-3) for i in range(5)]
    np.testing.assert_allclose(gy, fd, rtol=1e-7, atol=1e-10)
    gx = jax.grad(lambda v: spline(v, y, 333.0))(jnp.asarray(x))
    assert np.all(np.isfinite(gx))


# --- bad input ------------------------------------------------------------------------------------

def _rotor(**kw):
    base = dict(lengths=[0.2, 0.2], d_out=0.05)
    base.update(kw)
    return FlexibleRotor(**base)


BAD = [
    (dict(bearings=[Bearing(0, kxx=[1e6, 2e6, 3e6], speeds=[0.0, 2.0, 1.0])]),
     r"bearings\[0\] speeds must be strictly increasing"),
    (dict(bearings=[(0, 1e6, 1e6, 0, 0), Bearing(1, kxx=[1e6, 2e6], speeds=[3.0, 3.0])]),
     r"bearings\[1\] speeds must be strictly increasing"),
    (dict(bearings=[Bearing(0, kxx=[1e6, 2e6, 3e6], speeds=[0.0, 1.0, 2.0, 3.0])]),
     r"bearings\[0\] kxx has 3 values but speeds has 4"),
    (dict(bearings=[Bearing(0, kxx=1e6, cyy=[1.0, 2.0], speeds=[0.0, 1.0, 2.0])]),
     r"bearings\[0\] cyy has 2 values but speeds has 3"),
    (dict(bearings=[Bearing(0, kxx=1e6, speeds=[5.0])]), r"bearings\[0\] speeds must be a 1-D list of >= 2 speeds"),
    (dict(bearings=[Bearing(0, kxx=[1e6, 2e6])]), r"bearings\[0\] kxx must be one value \(give speeds for a table\)"),
    (dict(bearings=[Bearing(0, kxx=[1e6, -2e6], speeds=[0.0, 1.0])]), r"bearings\[0\] kxx must be >= 0"),
    (dict(bearings=[Bearing(0, kxx=1e6, mxy=float("nan"))]), r"bearings\[0\] mxy must be finite"),
    (dict(bearings=[Bearing(7, kxx=1e6)]), r"bearings\[0\]: bearing at node 7 does not exist"),
    (dict(bearings=[3.0]), r"bearings\[0\] must be a Bearing or a tuple"),
    (dict(bearings=[(0, 1e6, 1e6, 0)]), r"bearings\[0\] must be \(node, kxx, kyy, cxx, cyy"),
    (dict(bearings=[(0, 1e6, 1e6, 0, 0), (2, 1e6, 1e6, 0, 0)], supports=[(5, 1.0, 1e6, 1e6, 0, 0)]),
     r"supports\[0\] bearing index 5 out of range \(2 bearings\)"),
    (dict(bearings=[(0, 1e6, 1e6, 0, 0)], supports=[Support(0, 0.0, 1e6)]),
     r"supports\[0\] m \(pedestal mass\) must be > 0"),
    (dict(bearings=[(0, 1e6, 1e6, 0, 0)], supports=[Support(0, 1.0, 1e6), Support(0, 2.0, 1e6)]),
     r"supports\[1\]: bearing 0 already stands on supports\[0\]"),
    (dict(bearings=[(0, 1e6, 1e6, 0, 0)], supports=[(0, 1.0, 1e6)]),
     r"supports\[0\] must be \(bearing_index, m, kxx, kyy, cxx, cyy\), got 3 values"),
    (dict(bearings=[(0, 1e6, 1e6, 0, 0)], supports=[Support(0, 1.0, 1e6, cyy=-1.0)]),
     r"supports\[0\] cyy must be >= 0"),
    (dict(bearings=[(0, 1e6, 1e6, 0, 0)], supports=[Support(0.5, 1.0, 1e6)]),
     r"supports\[0\] bearing index must be an integer"),
    (dict(point_masses=[(1, 2.0, 3.0, 4.0)]), r"point_masses\[0\] must be \(node, m\) or \(node, mx, my\)"),
    (dict(point_masses=[(1, 2.0), (3, 2.0)]), r"point_masses\[1\]: point mass at node 3 does not exist"),
    (dict(point_masses=[(1, -2.0)]), r"point_masses\[0\] m must be >= 0"),
    (dict(point_masses=[(1, 2.0, float("inf"))]), r"point_masses\[0\] my must be finite"),
    (dict(d_out=[[0.05, 0.06, 0.07], [0.05, 0.06, 0.07]]),
     r"(?s)d_out \(outer diameter\) must be a scalar or one value per element \(2\).*\(left, right\)"),
    (dict(d_out=[[0.05, 0.06], [0.06, 0.04]], d_in=[[0.01, 0.02], [0.02, 0.04]]),
     r"d_in \(inner diameter\) must be smaller than d_out .*\(element 1\)"),
    (dict(d_out=[[0.05, -0.06], [0.06, 0.04]]), r"d_out \(outer diameter\) must be > 0"),
]


@pytest.mark.parametrize("kwargs, message", BAD, ids=[m.split(" ")[0].replace("\\", "") for _, m in BAD])
def test_bad_input_names_the_argument(kwargs, message):
    with pytest.raises(InputError, match=message):
        _rotor(**kwargs)
