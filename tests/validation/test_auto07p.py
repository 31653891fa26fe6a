"""AUTO-07p side by side (issue 13, item 4): two continuation problems solved by
AUTO-07p and by rotorjax, their two-parameter curves compared to 1e-6.

(a) The forced Duffing oscillator's harmonic balance (`duffing` of
    tests/analysis/test_continuation.py; AUTO: tests/reference/auto07p/duffing.f90):
    the branch in the forcing frequency `om` at `f = 0.05` with its two folds (AUTO's
    LP), then the fold curve in `(om, f)` (AUTO: LP continuation, both ways from the
    first fold; rotorjax: `fold_curve`), both to the edges of the box `f = 0.2`.
(b) A Jeffcott rotor in the rotating frame: unit mass and stiffness, cubic hardening
    `BETA_J`, rotating (internal) damping `C_INT`, stationary (external) damping
    `c_ext`, eccentricity `ECC` (AUTO: tests/reference/auto07p/jeffcott.f90; rotorjax:
    a planar `Scene` with a shaft component below, its field from
    `rotorjax.analysis.rotating_field`). The synchronous-whirl branch in the speed `Om`
    from rest, its Hopf point (AUTO's HB; rotorjax: `continue_branch`'s event), then the
    Hopf curve in `(Om, c_ext)` (AUTO: HB continuation both ways; rotorjax:
    `trace_boundary` of the margin of `steady_state`). Without eccentricity both must
    give the closed form `Om = 1 + c_ext / C_INT`.

For each AUTO point `X` (state and parameters, read with AUTO's 11 digits) two
distances to rotorjax's curve are measured:

- `corrected`: rotorjax's defining system solved from `X` -- for (a) Newton on
  `[F; det F_u; t . (y - X)] = 0` with `t` the curve's tangent at `X` (the corrector of
  `fold_curve`, i.e. the orthogonal distance `|y - X|` to the fold curve, in the
  state and the parameters); for (b) Newton along `Om` on rotorjax's margin at AUTO's
  `c_ext` (as `boundary_points` does);
- `interpolated`: the distance from `X` to a quintic spline through the points rotorjax
  traced (chord-length parameter; for (b), `Om` as a function of `c_ext`).

Both must be below 1e-6 at every AUTO point, and the curves must end at the same
box edges. AUTO's tolerances (EPSL = EPSU = 1e-12, EPSS = 1e-10, DSMAX = 0.05) are in
its constants files. Skips, saying how to install it, where AUTO-07p (the Debian
package `auto-07p`, with gfortran) is absent. Times: benchmarks/auto07p.py.
"""

import jax
import jax.numpy as jnp
import numpy as np
import pytest
from scipy.interpolate import make_interp_spline
from scipy.optimize import minimize_scalar

from rotorjax.analysis import continue_branch, fold_curve, rotating_field, steady_state, trace_boundary
from rotorjax.models import AbstractComponent, ConstantSpeed, RigidRotor, Scene, Supports
from tests.analysis.test_continuation import BETA, C, W0, duffing, duffing_fold_forcing
from tests.reference.auto07p import driver

TOL = 1e-6
#: rotorjax's points against AUTO's, asserted within about 100x the agreement measured (2026-12-07, AUTO-07p
#: 0.9.2; issue 62): a point corrected onto AUTO's (5.8e-11 Duffing, 7.3e-11 Jeffcott), the folds and curve
#: ends (2.2e-11, 3.1e-11 and 2.9e-11), the Hopf point and frequency (1.0e-11, 2.6e-11), AUTO's Duffing points
#: against the closed form (9.8e-10); `TOL` stays for the dense curve between rotorjax's points (4.6e-8, 1.4e-7)
POINT_TOL, ENDS_TOL, HOPF_TOL, CLOSED_FORM_TOL = 5e-9, 3e-9, 2e-9, 5e-8

# (a) Duffing
F0 = 0.05                       # forcing amplitude of the one-parameter branch
OM_RANGE = (0.5, 2.0)
FOLD_BOX = ((0.8, 2.0), (0.005, 0.2))   # (om, f) box of the fold curves

# (b) Jeffcott rotor
C_INT, BETA_J, ECC = 0.2, 0.2, 0.05
C_EXT0 = 0.1                    # external damping of the one-parameter branch
HOPF_BOX = ((0.5, 4.0), (0.05, 0.4))    # (Om, c_ext) box of the Hopf curves


# --- AUTO ---------------------------------------------------------------------------

def auto_duffing(workdir, installation):
    """AUTO on (a): compile; the branch in `om`; the fold curve both ways from its
    first LP. Returns `{"equation", "branch", "folds": [run, run]}`."""
    eq = driver.Equation("duffing", workdir, installation)
    eq.compile()
    u0 = duffing_start()
    par = {1: OM_RANGE[0], 2: F0, 3: W0, 4: C, 5: BETA}
    branch = eq.run("duffing.branch", PAR=par, U={1: u0[0], 2: u0[1]}, UZSTOP={1: list(OM_RANGE)})
    runs = []
    if branch.label("LP"):
        for ds in (0.01, -0.01):
            runs.append(eq.run("duffing.fold", restart=branch, IRS=branch.label("LP")[0], DS=ds,
                               UZSTOP={1: list(FOLD_BOX[0]), 2: list(FOLD_BOX[1])}))
    return {"equation": eq, "branch": branch, "folds": runs}


def auto_jeffcott(workdir, installation, ecc=ECC):
    """AUTO on (b): compile; the branch in `Om` from rest; the Hopf curve both ways
    from its first HB. Returns `{"equation", "branch", "hopf": [run, run]}`."""
    eq = driver.Equation("jeffcott", workdir, installation)
    eq.compile()
    par = {1: 0.0, 2: C_EXT0, 3: C_INT, 4: BETA_J, 5: ecc}
    branch = eq.run("jeffcott.branch", PAR=par, UZSTOP={1: [2.5]})
    runs = []
    if branch.label("HB"):
        for ds in (0.01, -0.01):
            runs.append(eq.run("jeffcott.hopf", restart=branch, IRS=branch.label("HB")[0], DS=ds,
                               UZSTOP={1: list(HOPF_BOX[0]), 2: list(HOPF_BOX[1])}))
    return {"equation": eq, "branch": branch, "hopf": runs}


def auto_curve(runs, names):
    """The points of two-parameter runs traced both ways from one start, as rows of
    `names` columns, ordered from one end to the other (the start once)."""
    a, b = (r.branches[0] for r in runs)
    pa, pb = (np.array([br.point(i, names) for i in range(len(br.data))]) for br in (a, b))
    return np.concatenate([pb[::-1], pa[1:]])


# --- rotorjax -----------------------------------------------------------------------

def duffing_start():
    """The branch's start at `om = 0.5`, converged to machine precision (AUTO takes
    the first point as given)."""
    fun = jax.jit(lambda u: duffing(u, OM_RANGE[0], F0))
    jac = jax.jit(jax.jacfwd(lambda u: duffing(u, OM_RANGE[0], F0)))
    u = jnp.array([0.0665, 0.0022])
    for _ in range(30):
        u = u - jnp.linalg.solve(jac(u), fun(u))
    return np.asarray(u)


def rotorjax_duffing():
    """rotorjax on (a): the branch and the fold curve through its first fold."""
    br = continue_branch(lambda u, om: duffing(u, om, F0), duffing_start(), OM_RANGE[0], p_bounds=OM_RANGE,
                         ds=0.02, ds_max=0.05, max_points=400, name="om")
    fold = [e for e in br.events if e.kind == "fold"][0]
    fc = fold_curve(duffing, fold.u, (fold.p, F0), ds=0.01, ds_max=0.02, max_points=400, tol=1e-12,
                    bounds=(np.array([np.nan, np.nan, FOLD_BOX[0][0], FOLD_BOX[1][0]]),
                            np.array([np.nan, np.nan, FOLD_BOX[0][1], FOLD_BOX[1][1]])), names=("om", "f"))
    return br, fc


class HardeningShaft(AbstractComponent):
    """The shaft's cubic hardening and rotating damping (its linear stiffness and the
    stationary damping are the `Supports`): `V = beta r^4 / 4`, `D = c_int |C' - Om J C|^2 / 2`,
    the velocity of the rotor centre relative to the spinning shaft."""

    beta: jax.Array
    c_int: jax.Array

    def __init__(self, beta, c_int):
        self.beta = jnp.asarray(beta, dtype=jnp.float64)
        self.c_int = jnp.asarray(c_int, dtype=jnp.float64)

    def potential(self, kin, q):
        r2 = kin.x**2 + kin.y**2
        return 0.25 * self.beta * r2 * r2

    def dissipation(self, kin, q, qd):
        rx, ry = kin.xd + kin.theta_dot * kin.y, kin.yd - kin.theta_dot * kin.x
        return 0.5 * self.c_int * (rx * rx + ry * ry)

    def describe(self):
        return "hardening shaft with rotating damping"


def jeffcott(om, c_ext, ecc=ECC):
    return Scene(RigidRotor(1.0, ecc), ConstantSpeed(om), (Supports.isotropic(1.0, c_ext),
                                                          HardeningShaft(BETA_J, C_INT)))


def jeffcott_margin(om, c_ext, ecc=ECC):
    """Largest real part at the synchronous whirl, from Newton started at the linear
    unbalance response `w = ecc Om^2 / (1 - Om^2 + i c_ext Om)`."""
    w = ecc * om**2 / (1 - om**2 + 1j * c_ext * om)
    return steady_state(jeffcott(om, c_ext, ecc), jnp.stack([jnp.real(w), jnp.imag(w)])).margin


@jax.jit
@jax.vmap
def _margin_and_slope(om, c_ext, ecc):
    return jax.value_and_grad(jeffcott_margin)(om, c_ext, ecc)


def hopf_speeds(om_guess, c_ext, ecc=ECC, iters=4):
    """rotorjax's Hopf speed at each `c_ext`: Newton along `Om` on the margin from
    `om_guess` (what `boundary_points` does, with one compiled, batched margin and
    slope for every call: batches are padded to 256). Returns `(Om, |margin|)`."""
    om, c = np.asarray(om_guess, dtype=float), np.asarray(c_ext, dtype=float)
    n = om.size
    size = 256 * -(-n // 256)
    om, c = np.pad(om, (0, size - n), mode="edge"), np.pad(c, (0, size - n), mode="edge")
    om, c, e = jnp.asarray(om), jnp.asarray(c), jnp.full(size, float(ecc))
    for _ in range(iters):
        v, g = _margin_and_slope(om, c, e)
        om = om - v / g
    v, _ = _margin_and_slope(om, c, e)
    return np.asarray(om)[:n], np.abs(np.asarray(v))[:n]


def rotorjax_jeffcott():
    """rotorjax on (b): the branch in `Om` from rest and the Hopf curve through its
    Hopf point."""
    br = continue_branch(lambda z, om: rotating_field(jeffcott(om, C_EXT0), 0.0, z), np.zeros(4), 0.0,
                         p_bounds=(0.0, 2.0), ds=0.05, ds_max=0.2, name="Om")
    hopf = [e for e in br.events if e.kind == "hopf"][0]
    curve = trace_boundary(jeffcott_margin, (hopf.p, C_EXT0), bounds=tuple(np.array(b) for b in zip(*HOPF_BOX)),
                           ds=0.02, ds_max=0.05, tol=1e-12, names=("Om", "c_ext"))
    return br, curve


# --- distances ----------------------------------------------------------------------

def _fold_system(x):
    u, om, f = x[:2], x[2], x[3]
    return jnp.concatenate([duffing(u, om, f), jnp.linalg.det(jax.jacfwd(duffing)(u, om, f))[None]])


@jax.jit
@jax.vmap
def _project_on_fold_curve(xa):
    J = jax.jacfwd(_fold_system)
    t = jnp.linalg.svd(J(xa))[2][-1]        # the curve's tangent at X (null vector)
    y = xa
    for _ in range(8):
        A = jnp.concatenate([J(y), t[None, :]])
        y = y - jnp.linalg.solve(A, jnp.concatenate([_fold_system(y), jnp.dot(t, y - xa)[None]]))
    return y, jnp.max(jnp.abs(_fold_system(y)))


def _spline_distance(points, x):
    """Distances from rows `x` to a quintic spline through `points` (chord length)."""
    s = np.concatenate([[0.0], np.cumsum(np.linalg.norm(np.diff(points, axis=0), axis=1))])
    sp = make_interp_spline(s, points, k=5)
    out = []
    for xa in x:
        k = int(np.argmin(np.linalg.norm(points - xa, axis=1)))
        lo, hi = s[max(k - 1, 0)], s[min(k + 1, len(s) - 1)]
        r = minimize_scalar(lambda v: np.linalg.norm(sp(v) - xa), bounds=(lo, hi), method="bounded",
                            options={"xatol": 1e-14})
        out.append(r.fun)
    return np.array(out)


def duffing_deviation(auto, rj):
    """Distances of AUTO's fold-curve points (a) to rotorjax's, and of AUTO's folds to
    rotorjax's fold events."""
    br, fc = rj
    pts = auto_curve(auto["folds"], ["U(1)", "U(2)", "PAR(1)", "PAR(2)"])
    y, res = _project_on_fold_curve(jnp.asarray(pts))
    y = np.asarray(y)
    lp = [b.point(i, ["U(1)", "U(2)", "PAR(1)"]) for b, i in auto["branch"].points("LP")]
    ev = [np.concatenate([e.u, [e.p]]) for e in br.events if e.kind == "fold"]
    ends_auto = np.array([pts[0, 2:], pts[-1, 2:]])
    ends_rj = np.array(sorted([fc.x[0, 2:], fc.x[-1, 2:]], key=lambda p: p[0]))
    ends_auto = ends_auto[np.argsort(ends_auto[:, 0])]
    with np.errstate(invalid="ignore"):     # at the cusp the closed form's discriminant rounds below 0
        closed = [[abs(p[3] / v - 1) for v in duffing_fold_forcing(p[2]) if np.isfinite(v)] for p in pts]
    return {
        "auto_points": int(pts.shape[0]), "rotorjax_points": int(fc.x.shape[0]),
        "corrected_max": float(np.max(np.linalg.norm(y - pts, axis=1))),
        "corrected_params_max": float(np.max(np.linalg.norm(y[:, 2:] - pts[:, 2:], axis=1))),
        "corrector_residual_max": float(np.max(res)),
        "interpolated_max": float(np.max(_spline_distance(fc.x, pts))),
        "folds_auto": [p.tolist() for p in lp], "folds_rotorjax": [p.tolist() for p in ev],
        "fold_points_max": float(max(np.max(np.abs(a - b)) for a, b in zip(lp, ev))) if len(lp) == len(ev) else np.inf,
        "ends_auto": ends_auto.tolist(), "ends_rotorjax": ends_rj.tolist(),
        "ends_max": float(np.max(np.abs(ends_auto - ends_rj))),
        "auto_vs_closed_form_rel_max": float(max(min(c) for c in closed if c)),
        "closed_form_undefined_points": sum(not c for c in closed),
    }


def jeffcott_deviation(auto, rj):
    """Distances of AUTO's Hopf-curve points (b) to rotorjax's, and of AUTO's Hopf
    point (speed and frequency) to rotorjax's event."""
    br, curve = rj
    pts = auto_curve(auto["hopf"], ["PAR(1)", "PAR(2)"])
    om, res = hopf_speeds(pts[:, 0], pts[:, 1])
    order = np.argsort(curve.x[:, 1])
    sp = make_interp_spline(curve.x[order, 1], curve.x[order, 0], k=5)
    (hb,) = [auto["branch"].solutions[lab] for lab in auto["branch"].label("HB")]
    (ev,) = [e for e in br.events if e.kind == "hopf"]
    ends_auto = pts[[0, -1]][np.argsort(pts[[0, -1], 1])]
    ends_rj = curve.x[[0, -1]][np.argsort(curve.x[[0, -1], 1])]
    return {
        "auto_points": int(pts.shape[0]), "rotorjax_points": int(curve.x.shape[0]),
        "corrected_max": float(np.max(np.abs(np.asarray(om) - pts[:, 0]))),
        "corrector_residual_max": float(np.max(res)),
        "interpolated_max": float(np.max(np.abs(sp(pts[:, 1]) - pts[:, 0]))),
        "hopf_auto": {"Om": float(hb["par"][0]), "frequency": float(2 * np.pi / hb["par"][10])},
        "hopf_rotorjax": {"Om": ev.p, "frequency": float(ev.frequency)},
        "hopf_point": abs(float(hb["par"][0]) - ev.p),
        "hopf_frequency": abs(float(2 * np.pi / hb["par"][10]) - float(ev.frequency)),
        "ends_auto": ends_auto.tolist(), "ends_rotorjax": ends_rj.tolist(),
        "ends_max": float(np.max(np.abs(ends_auto - ends_rj))),
    }


# --- tests --------------------------------------------------------------------------

@pytest.fixture(scope="module")
def installation():
    inst, why = driver.find_auto()
    if inst is None:
        pytest.skip(why)
    return inst


def _assert_ran(result, kind):
    runs = [result["branch"], *result[kind]]
    assert len(runs) == 3, result["branch"].why()
    for r in runs:
        assert r.ok, r.why()


def test_duffing_fold_curve_agrees_with_auto(installation, tmp_path):
    auto = auto_duffing(tmp_path, installation)
    _assert_ran(auto, "folds")
    assert len(auto["branch"].label("LP")) == 2
    d = duffing_deviation(auto, rotorjax_duffing())
    assert d["auto_points"] > 50 and d["corrector_residual_max"] < 1e-12
    assert d["fold_points_max"] < ENDS_TOL, d
    assert d["corrected_max"] < POINT_TOL, d
    assert d["interpolated_max"] < TOL, d
    assert d["ends_max"] < ENDS_TOL and np.allclose(np.array(d["ends_auto"])[:, 1], FOLD_BOX[1][1], rtol=0,
                                                    atol=1e-9), d
    assert d["auto_vs_closed_form_rel_max"] < CLOSED_FORM_TOL and d["closed_form_undefined_points"] <= 2, d


def test_jeffcott_hopf_curve_agrees_with_auto(installation, tmp_path):
    auto = auto_jeffcott(tmp_path, installation)
    _assert_ran(auto, "hopf")
    d = jeffcott_deviation(auto, rotorjax_jeffcott())
    assert d["auto_points"] > 50 and d["corrector_residual_max"] < 1e-10
    assert d["hopf_point"] < HOPF_TOL and d["hopf_frequency"] < HOPF_TOL, d
    assert d["corrected_max"] < POINT_TOL, d
    assert d["interpolated_max"] < TOL, d
    assert d["ends_max"] < ENDS_TOL, d
    # the unbalance shifts the boundary off the linear closed form, by much more than TOL
    pts = auto_curve(auto["hopf"], ["PAR(1)", "PAR(2)"])
    assert np.max(np.abs(pts[:, 0] - (1 + pts[:, 1] / C_INT))) > 1e-3


def test_jeffcott_without_eccentricity_gives_the_closed_form_in_both(installation, tmp_path):
    auto = auto_jeffcott(tmp_path, installation, ecc=0.0)
    _assert_ran(auto, "hopf")
    pts = auto_curve(auto["hopf"], ["PAR(1)", "PAR(2)"])
    assert np.max(np.abs(pts[:, 0] - (1 + pts[:, 1] / C_INT))) < TOL
    om, res = hopf_speeds(pts[:, 0] + 0.01, pts[:, 1], ecc=0.0)
    assert np.max(np.abs(om - (1 + pts[:, 1] / C_INT))) < 1e-9 and np.max(res) < 1e-10
