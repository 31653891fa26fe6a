"""AUTO-07p side by side on forced periodic motions (issue 30): rotorjax's
harmonic-balance continuation (`periodic_branch`) against AUTO-07p's collocation
continuation of periodic orbits, and the jumps of a slow run-up and run-down
against the folds both find.

The problem: a Jeffcott rotor on anisotropic supports with cubic (hardening)
bearing stiffness, unbalance-forced, dimensionless,

    x'' + C x' + KX x + BETA x (x^2 + y^2) = ECC Om^2 cos(Om t),
    y'' + C y' + KY y + BETA y (x^2 + y^2) = ECC Om^2 sin(Om t).

With `KX != KY` the synchronous orbit is an ellipse with odd harmonics, not a rest
point of any rotating frame, so only a periodic-orbit method sees it. Over `Om` in
`OM_RANGE` its branch bends over at both resonances (x near 1, y near sqrt(1.3)):
four folds, two unstable (saddle) segments between them.

- rotorjax: `periodic_branch(Jeffcott, ...)` with `H` harmonics (the truncation,
  `time_residual`, is below 1.2e-10 all along); folds are its `"fold"` events;
  Floquet multipliers from `floquet` (the variational equations along the
  orbit) and from Hill's exponents (`exp(s T)`, no integration).
- AUTO-07p (tests/reference/auto07p/jeffcott_forced.f90): the autonomous
  extension by the forcing oscillator `u' = u + Om v - u (u^2 + v^2)`,
  `v' = -Om u + v - v (u^2 + v^2)` (u = sin, v = cos of `Om t`), continued as
  periodic orbits (IPS = 2; the period PAR(11) is free and follows `2 pi / Om`),
  started from rotorjax's orbit at `Om = 0.5` written as data (AUTO's `dat`);
  folds are its LP points; its Floquet multipliers (ISP = 2) are copied by the
  equation's PVLS into PAR(12:23) and so come with 11 digits in the b-file (the
  d-file has 6; both are read and must agree). The extension adds two trivial
  multipliers, 1 and `exp(-2 T)`, removed before comparing. NWTN = ITNW (a fresh
  Jacobian at every Newton step): AUTO's multipliers come from its last
  Jacobian, which with NWTN = 3 is frozen at an earlier iterate and puts errors
  up to 2e-6 into them (2e-8 with NWTN = 7).

Compared (the fold speeds and the branch within about 100x the agreement measured,
`FOLD_TOL`, `BRANCH_TOL`; the multipliers to `TOL` = 1e-6): the fold speeds (relative); every AUTO point
`(Om, L2-NORM)` against rotorjax's branch (rotorjax's balance corrected from its
nearest branch point onto the normal through AUTO's point, the L2-norm of the
extended orbit from the Fourier coefficients by Parseval: the distance in the
`(Om, L2)` plane); the multipliers at points on each of the five segments
(stable and unstable). Then a slow run-up and run-down (`rotorjax.simulate`,
`RunUp`, `SWEEP` per time unit) must jump down just past the upper folds and up
just before the lower ones, within 1 % (`JUMP_TOL`). The AUTO parts skip,
saying how to install it, where AUTO-07p is absent; the jump test does not need
it. Times: benchmarks/auto07p.py, part (c).
"""

import os

import jax
import jax.numpy as jnp
import numpy as np
import pytest
from scipy.optimize import linear_sum_assignment

import rotorjax
from rotorjax.analysis import balance_residual, branch_amplitude, harmonic_balance, hill_exponents, periodic_branch
from rotorjax.models import AbstractScene, AbstractSpeedProfile, ConstantSpeed, RunUp
from tests.reference.auto07p import driver

TOL = 1e-6
#: asserted within about 100x the agreement measured (2026-12-07, AUTO-07p 0.9.2; issue 62): the folds 3.5e-11,
#: the branch 5.9e-11 (`TOL` stays for the multipliers, which AUTO's own Jacobian limits: 3.4e-8), Floquet's
#: multipliers against Hill's 7.5e-12, the trivial ones 1.8e-14
FOLD_TOL, BRANCH_TOL, HILL_TOL, TRIVIAL_TOL = 3e-9, 5e-9, 5e-10, 1e-12
KX, KY, C, BETA, ECC = 1.0, 1.3, 0.02, 0.5, 0.01
OM_RANGE = (0.5, 2.0)
H = 9                        # harmonics: time_residual <= 1.2e-10 at every point of the branch
SWEEP = 5e-6                 # run-up / run-down rate, d Om / dt
SWEEP_RANGE = (0.95, 1.3)    # past all four folds
JUMP_TOL = 0.01


class Jeffcott(AbstractScene):
    """The forced rotor; state `(x, y, x', y')`. The forcing follows the speed
    profile's angle (an unbalance: `ECC (w^2 cos th + w' sin th, w^2 sin th - w' cos th)`),
    so a `RunUp` profile gives the run-up of the same equations."""

    speed: AbstractSpeedProfile

    def __init__(self, om):
        self.speed = om if isinstance(om, AbstractSpeedProfile) else ConstantSpeed(om)

    @property
    def state_size(self):
        return 4

    def vector_field(self, t, y, args=None):
        x, yy, xd, yd = y
        th, w, a = self.speed.angle(t), self.speed.speed(t), self.speed.acceleration(t)
        r2 = x * x + yy * yy
        fx = ECC * (w * w * jnp.cos(th) + a * jnp.sin(th))
        fy = ECC * (w * w * jnp.sin(th) - a * jnp.cos(th))
        return jnp.stack([xd, yd, fx - C * xd - KX * x - BETA * x * r2, fy - C * yd - KY * yy - BETA * yy * r2])

    def outputs(self, t, y):
        return {"node_x": y[:1], "node_y": y[1:2], "whirl_amplitude": jnp.hypot(y[0], y[1])}

    def describe(self):
        return "anisotropic Jeffcott rotor with cubic bearing stiffness"


def period(om):
    return 2 * np.pi / om


# --- rotorjax -----------------------------------------------------------------------

def rotorjax_branch():
    """rotorjax's branch over `OM_RANGE` from rest: `(branch, coefficients)`."""
    return periodic_branch(Jeffcott, OM_RANGE[0], np.zeros(4), OM_RANGE, harmonics=H, name="Om", scale=0.2,
                           ds=0.02, ds_max=0.2, max_points=600)


def start_orbit(om=OM_RANGE[0], n=401):
    """rotorjax's orbit at `om` as AUTO's starting data: rows `(t, x, y, x', y', u, v)`
    over one period (phase origin 0, so `u = sin(om t)`, `v = cos(om t)`)."""
    s = harmonic_balance(Jeffcott(om), period(om), np.zeros(4), harmonics=H, stability=False)
    ts = np.linspace(0.0, period(om), n)
    return np.column_stack([ts, np.asarray(s.state(ts)), np.sin(om * ts), np.cos(om * ts)])


def l2_norm(Y):
    """AUTO's L2-NORM of the extended orbit, `sqrt(int_0^1 |U|^2)` over its six
    states, from the coefficients `(2H + 1, 4)` (Parseval; `u^2 + v^2 = 1`)."""
    return jnp.sqrt(1.0 + jnp.sum(Y[0] ** 2) + 0.5 * jnp.sum(Y[1:] ** 2))


@jax.jit
@jax.vmap
def _project(Y0, om0, target, tangent):
    """rotorjax's balance `R(Y, Om) = 0` with `tangent . ((Om, L2(Y)) - target) = 0`
    (the normal through AUTO's point in the `(Om, L2)` plane), Newton from
    `(Y0, om0)`. Returns `(Y, Om, max |residual|)`."""
    shape = Y0.shape

    def F(x):
        Y, om = x[:-1].reshape(shape), x[-1]
        r = balance_residual(Jeffcott(om), Y, 2 * jnp.pi / om).ravel()
        return jnp.concatenate([r, (tangent[0] * (om - target[0]) + tangent[1] * (l2_norm(Y) - target[1]))[None]])

    x = jnp.concatenate([Y0.ravel(), om0[None]])
    for _ in range(10):
        x = x - jnp.linalg.solve(jax.jacfwd(F)(x), F(x))
    return x[:-1].reshape(shape), x[-1], jnp.max(jnp.abs(F(x)))


def multipliers(om, Y):
    """rotorjax's Floquet multipliers at `om` (the balance solved there from `Y`):
    `(from floquet, from Hill's exponents, time_residual)`."""
    sol = harmonic_balance(Jeffcott(om), period(om), Y, harmonics=H, rtol=1e-12, atol=1e-14)
    hill = np.exp(np.asarray(hill_exponents(Jeffcott(om), sol)) * period(om))
    return np.asarray(sol.floquet.multipliers), hill, float(sol.time_residual)


# --- AUTO ---------------------------------------------------------------------------

def auto_forced(workdir, installation):
    """AUTO on the branch: compile; write rotorjax's starting orbit as data; one run
    over `OM_RANGE`. Returns `{"equation", "branch", "runs": []}` (the layout
    benchmarks/auto07p.py times)."""
    eq = driver.Equation("jeffcott_forced", workdir, installation)
    eq.compile()
    np.savetxt(os.path.join(str(workdir), "start.dat"), start_orbit(), fmt="%.17e")
    par = {1: OM_RANGE[0], 2: KX, 3: KY, 4: C, 5: BETA, 6: ECC}
    branch = eq.run("jeffcott_forced", dat="start", PAR=par, UZSTOP={1: list(OM_RANGE)})
    return {"equation": eq, "branch": branch, "runs": []}


def auto_multipliers(br, i):
    """AUTO's six multipliers at row `i` (from PAR(12:23))."""
    v = br.point(i, [f"PAR({k})" for k in range(12, 24)])
    return v[0::2] + 1j * v[1::2]


def physical(mu):
    """AUTO's multipliers less the extension's two: the smallest (the forcing
    oscillator's radial `exp(-2 T)`) and then the one nearest 1 (the phase). Returns
    `(the four, the two removed)`."""
    mu = np.asarray(mu)
    i = int(np.argmin(np.abs(mu)))
    rest = np.delete(mu, i)
    j = int(np.argmin(np.abs(rest - 1.0)))
    return np.delete(rest, j), np.array([mu[i], rest[j]])


def match(a, b):
    """Largest distance between two sets of multipliers, paired to minimise it."""
    d = np.abs(np.asarray(a)[:, None] - np.asarray(b)[None, :])
    r, c = linear_sum_assignment(d)
    return float(np.max(d[r, c]))


# --- comparison ---------------------------------------------------------------------

def deviation(auto, rj):
    """AUTO's run against rotorjax's branch: folds, every point's distance in the
    `(Om, L2)` plane, and the multipliers mid-way along each segment."""
    br_rj, Y_rj = rj
    run = auto["branch"]
    (b,) = run.branches
    rows = np.arange(1, len(b.data))      # the first row is the data as read, before AUTO corrects it
    pts = np.column_stack([b["PAR(1)"], b["L2-NORM"]])[rows]

    folds_auto = np.array([b.data[i, 0] for i in b.special("LP")])
    folds_rj = np.array([e.p for e in br_rj.events if e.kind == "fold"])

    # rotorjax's curve in the (Om, L2) plane; for each AUTO point its nearest point and tangent there
    curve = np.column_stack([br_rj.p, np.asarray(jax.vmap(l2_norm)(jnp.asarray(Y_rj)))])
    near = np.argmin(np.linalg.norm(curve[None, :, :] - pts[:, None, :], axis=2), axis=1)
    tan = curve[np.minimum(near + 1, len(curve) - 1)] - curve[np.maximum(near - 1, 0)]
    tan /= np.linalg.norm(tan, axis=1, keepdims=True)
    Y, om, res = _project(jnp.asarray(Y_rj[near]), jnp.asarray(br_rj.p[near]), jnp.asarray(pts), jnp.asarray(tan))
    Y, om = np.asarray(Y), np.asarray(om)
    l2 = np.asarray(jax.vmap(l2_norm)(jnp.asarray(Y)))
    dist = np.hypot(om - pts[:, 0], l2 - pts[:, 1])

    # multipliers mid-way along each segment between AUTO's folds (and ends)
    edges = [0, *b.special("LP"), len(b.data) - 1]
    picks = sorted({(lo + hi) // 2 for lo, hi in zip(edges[:-1], edges[1:])} | {edges[1] + 2, edges[-2] - 2})
    d_file = driver.parse_d_multipliers(run.diagnostics)
    mult = []
    for i in picks:
        k = int(np.where(rows == i)[0][0])
        mu_auto = auto_multipliers(b, i)
        four, trivial = physical(mu_auto)
        fq, hill, tres = multipliers(float(b.data[i, 0]), Y[k])
        mu_d = d_file[(abs(b.number), abs(int(b.pt[i])))]
        mult.append({
            "Om": float(b.data[i, 0]), "auto_stable": bool(b.pt[i] < 0),
            "rotorjax_stable": bool(np.all(np.abs(fq) < 1)),
            "max_modulus": float(np.max(np.abs(fq))),
            "floquet": match(four, fq), "hill": match(four, hill), "floquet_vs_hill": match(fq, hill),
            "b_vs_d_file": match(mu_auto, mu_d) / max(1.0, float(np.max(np.abs(mu_d)))),
            "trivial": [abs(trivial[0] - np.exp(-2 * period(b.data[i, 0]))), abs(trivial[1] - 1.0)],
            "time_residual": tres,
        })

    amp = branch_amplitude(Jeffcott, br_rj.p, Y_rj)
    return {
        "auto_points": int(len(rows)), "rotorjax_points": int(br_rj.p.size),
        "folds_auto": folds_auto.tolist(), "folds_rotorjax": folds_rj.tolist(),
        "folds_rel_max": float(np.max(np.abs(folds_auto / folds_rj - 1))) if folds_auto.size == folds_rj.size
        else np.inf,
        "branch_max": float(np.max(dist)), "branch_argmax_Om": float(pts[np.argmax(dist), 0]),
        "corrector_residual_max": float(np.max(np.asarray(res))),
        "period_rel_max": float(np.max(np.abs(b["PERIOD"][rows] * b["PAR(1)"][rows] / (2 * np.pi) - 1))),
        "max_amplitude": float(np.max(amp)),
        "multipliers": mult,
        "multipliers_max": float(max(max(m["floquet"], m["hill"]) for m in mult)),
    }


# --- run-up and run-down ------------------------------------------------------------

def sweep(om0, om1, rate=SWEEP, window=32, dt=0.25):
    """Simulate the sweep from `om0` to `om1` at `rate`, started on the periodic
    motion at `om0`: `(speed, envelope)`, the largest whirl radius over windows of
    `window` samples `dt` apart."""
    a = rate * np.sign(om1 - om0)
    t_end = (om1 - om0) / a
    y0 = harmonic_balance(Jeffcott(om0), period(om0), np.zeros(4), harmonics=H, stability=False).initial_state()
    ts = np.arange(0.0, t_end, dt)
    r = rotorjax.simulate(Jeffcott(RunUp(om0, a)), y0, (0.0, t_end), saveat=ts, solver="tsit5", rtol=1e-6,
                          atol=1e-9, max_steps=2_000_000).raise_if_failed()
    rad = np.asarray(r.outputs["whirl_amplitude"])
    k = rad.size // window
    env = rad[:k * window].reshape(k, window).max(axis=1)
    om = om0 + a * ts[:k * window].reshape(k, window).mean(axis=1)
    return om, env


def jumps(om, env, fraction=0.3, gap=0.01):
    """The jumps of an envelope: clusters (closer than `gap` in speed) of steps
    larger than `fraction` of the largest, each as `(speed, step)` at its steepest."""
    d = np.diff(env)
    big = np.where(np.abs(d) > fraction * np.max(np.abs(d)))[0]
    groups = np.split(big, np.where(np.abs(np.diff(om[big])) > gap)[0] + 1)
    return [(float(0.5 * (om[g[np.argmax(np.abs(d[g]))]] + om[g[np.argmax(np.abs(d[g]))] + 1])),
             float(d[g[np.argmax(np.abs(d[g]))]])) for g in groups if g.size]


# --- tests --------------------------------------------------------------------------

@pytest.fixture(scope="module")
def rotorjax_result():
    return rotorjax_branch()


@pytest.fixture(scope="module")
def installation():
    inst, why = driver.find_auto()
    if inst is None:
        pytest.skip(why)
    return inst


@pytest.fixture(scope="module")
def compared(installation, rotorjax_result, tmp_path_factory):
    auto = auto_forced(tmp_path_factory.mktemp("auto07p_forced"), installation)
    assert auto["branch"].ok, auto["branch"].why()
    return auto, deviation(auto, rotorjax_result)


def test_rotorjax_branch_has_four_folds_and_converged_harmonics(rotorjax_result):
    br, Y = rotorjax_result
    assert br.p[-1] == pytest.approx(OM_RANGE[1]) and br.p.size < 600
    folds = [e.p for e in br.events if e.kind == "fold"]
    assert len(folds) == 4 and [e.kind for e in br.events] == ["fold"] * 4, br.events
    # the truncation: at the largest orbit and at a fold
    amp = branch_amplitude(Jeffcott, br.p, Y)
    for i in (int(np.argmax(amp)), int(np.argmin(np.abs(br.p - folds[0])))):
        s = harmonic_balance(Jeffcott(br.p[i]), period(br.p[i]), Y[i], harmonics=H, stability=False)
        assert float(s.time_residual) < 1e-8 and float(s.residual) < 1e-10


def test_folds_agree_with_auto(compared):
    _, d = compared
    assert len(d["folds_auto"]) == 4 and d["folds_rel_max"] < FOLD_TOL, d


def test_branch_agrees_with_auto(compared):
    _, d = compared
    assert d["auto_points"] > 50 and d["corrector_residual_max"] < 1e-10, d
    assert d["branch_max"] < BRANCH_TOL, d
    assert d["period_rel_max"] < 1e-9, d      # AUTO's free period follows 2 pi / Om


def test_floquet_multipliers_agree_with_auto(compared):
    _, d = compared
    m = d["multipliers"]
    assert sum(not x["auto_stable"] for x in m) >= 2 and sum(x["auto_stable"] for x in m) >= 3, m
    for x in m:
        assert x["auto_stable"] == x["rotorjax_stable"], x
        assert x["floquet"] < TOL and x["hill"] < TOL and x["floquet_vs_hill"] < HILL_TOL, x
        assert x["b_vs_d_file"] < 1e-5, x          # PVLS saw the point's own multipliers (d-file: 6 digits)
        assert x["trivial"][0] < TRIVIAL_TOL and x["trivial"][1] < TRIVIAL_TOL, x


def test_run_up_and_run_down_jump_at_the_folds(rotorjax_result):
    """Run-up: down just past each upper fold; run-down: up just before each lower one."""
    br, _ = rotorjax_result
    f = sorted(e.p for e in br.events if e.kind == "fold")      # x: lower, upper; y: lower, upper
    upper, lower = [f[1], f[3]], [f[0], f[2]]
    up = jumps(*sweep(*SWEEP_RANGE))
    down = jumps(*sweep(*SWEEP_RANGE[::-1]))
    assert len(up) == 2 and all(s < 0 for _, s in up), up
    assert len(down) == 2 and all(s > 0 for _, s in down), down
    for (w, _), fold in zip(sorted(up), upper):
        assert 0 < w / fold - 1 < JUMP_TOL, (w, fold)
    for (w, _), fold in zip(sorted(down), lower):
        assert 0 < 1 - w / fold < JUMP_TOL, (w, fold)
