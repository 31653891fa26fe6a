"""A finite-element rotor on fluid-film journal bearings: `rotorjax.simulate` vs CPU peers.

The scene: the shipped rotor file `journal_rig` (`rotorjax/rotors/journal_rig.toml`):
ROSS's example rotor (`ross_compare.toml`: six Timoshenko elements, two disks, 28
free dofs) on two short (Ocvirk, half-Sommerfeld) journal bearings at nodes 0 and 6
(D = 0.05 m, L = 0.02 m, c = 5e-5 m, mu = 0.03 Pa s), gravity along -y, an unbalance
of 1e-3 kg m at node 2. Its oil-whirl onset is ~207.6 rad/s (whirl ~123 rad/s).
Every run starts from the static equilibrium at its initial speed
(`rotorjax.models.static_equilibrium`), at rest. Two models of it:
- the full FE rotor (28 dofs, 56 states);
- the modal reduction an engineer would run: the same file with `[rotor] n_modes =
  `N_MODES` (the override `{"rotor.n_modes": 8}`: a `ReducedRotor`, the linear part in
  the 8 lowest undamped modes of the free shaft, 4 of them rigid, the film forces still
  at the physical journal nodes; 16 states). Its reduction error (the reduced
  reference's final node positions against the full one's, in clearances) is in the
  JSON's `reduction_error`.

(1) Constant speed: 300 rad/s (above the onset: the whirl grows out of the
equilibrium, excited by the unbalance) for 0.5 s.
(2) Run-up: a linear ramp 100 -> 400 rad/s over 1 s (`RunUp`, 300 rad/s^2),
through the onset at t ~ 0.36 s.

Each, per model: rotorjax (Dopri8, Tsit5) and the peers at rtol in `RTOLS` (full) or
`RTOLS_REDUCED` (reduced) with atol = rtol *
`ATOL_PER_RTOL` (m, m/s, rad: the shaft sags ~1e-4 m, the journals move ~1e-5 m), the final state only. Error:
max |node x, y at t_end - reference| over all nodes, divided by the largest node
displacement of the reference at t_end; the reference is rotorjax Dopri8 at rtol
1e-12 (atol 1e-16), checked against the numba DOP853 peer at the same tolerance.

The peers integrate the same equations from the scene's matrices (`scene.Minv, C, G1,
K, Ks, F0` and `scene.expand`: for the reduced rotor the modal ones, `expand` the mode
shapes), as benchmarks/rotor_scene.py does:
M q'' = F0 + E^T f(t, E q, E q') - (K + w(t) Ks) q - (C + w(t) G1) q', with M^-1
applied once before the run; `f` the two films' forces (speed w(t)) and the
unbalance's (its angle theta(t) = w0 t + alpha t^2 / 2 and the run-up's tangential
term U alpha (sin a, -cos a)). The short-bearing force is written here in numba from
the closed form, independently of `rotorjax.models.film_force` (the arc's sin cos
integral by the substitution u = 1 - eps cos, the others by the Sommerfeld
substitution with the end angles from atan2) and checked against it at random states
(eps 0.05..0.97) to 1e-10 (relative) before anything is timed; rotorjax evaluates it at the
journal's position moved by 1e-12 c along x (so that the centre has a direction),
which alone changes the force by up to ~2e-10: the check compares at that position too. Peers:
- scipy `solve_ivp` DOP853 with a numba `njit` right-hand side;
- scipy `ode('dop853')` (Hairer's Fortran DOP853) with the numba right-hand side;
- numba DOP853: scipy's DOP853 compiled whole with numba (copied from
  benchmarks/rotor_scene.py, whose kernel closes over its own right-hand side).
Ratios are peer time / rotorjax time (> 1: rotorjax faster), at the same rtol and at
matched error (the peer's time at rotorjax's error, log-log interpolated on the
peer's ladder, `rotorjax.bench._matching.interpolate_cost`). Times are medians of
`--repeats` runs after a compiling call on a short span (the span is an array:
the same program); the scipy peers (Python per step, tens of seconds) once.

The full FE rotor's highest shaft modes (undamped) bound the explicit solvers' steps
(~5e-6 s): every rtol here gives errors near the references' own disagreement, so
the work-precision curves are flat and "matched error" mostly extrapolates. The
JSON's `summary` therefore also gives, per method, the cheapest successful run within
`NOISE_FACTOR` x that disagreement (`at_noise_floor`) and the ratios of those. The
reduced rotor's steps are bounded only at loose rtol (by the films' damping, ~6e-5 s):
its ladder spreads over many decades of error and matched error interpolates.
Scipy's Fortran DOP853 stops at loose rtol on its stiffness test ("problem is
probably stiff"): such rungs are marked and left out of the ratios.

Each case records `cpu` (`CpuWatch`: how many cores other processes kept busy while
it ran): on a shared machine absolute times are slowed, ratios within a case less so.

Run: python benchmarks/journal_bearings.py [--smoke] [--repeats 3] [--all]
Runs the reduced cases and the full rotor at constant speed; the full rotor's run-up
(~10 min) only with `--all`, otherwise it is carried over from the JSON already
written (marked `carried_over`, with that run's date and load) if that holds it.
Writes benchmarks/results/journal_bearings.json (`--smoke`: the reduced run-up only,
`SMOKE_T` s of motion, one tolerance, rotorjax Dopri8 and the peers once each; the
full and reduced constant-speed right-hand sides checked; prints, writes nothing).
"""

import argparse
import json
import math
import os
import platform
import sys
import time

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from _common import CpuWatch, machine, numba_dop853, write_results  # noqa: E402

RTOLS = (1e-6, 1e-8, 1e-10)
ATOL_PER_RTOL = 1e-4
REF_RTOL, REF_ATOL = 1e-12, 1e-16
MAX_STEPS = 4_000_000
NOISE_FACTOR = 10.0               # summary: errors below this x the references' disagreement are noise
#: the film-force check's eccentricities, and the shift along x by which rotorjax's `film_force`
#: moves the journal (x clearance; a direction at the centre): up to ~2e-10 relative in the force
EPS_CHECK, FILM_SHIFT = (0.05, 0.97), 1e-12
SPEED = 300.0                      # (1), rad/s
T_CONST = 0.5
RAMP = (100.0, 400.0, 1.0)         # (2): from, to (rad/s), over (s)
SMOKE_T = 5e-4
FILM_NODES = (0, 6)
UNBALANCE_NODE = 2
FORCE_NODES = (FILM_NODES[0], UNBALANCE_NODE, FILM_NODES[1])

ROTOR_FILE = "journal_rig"          # rotorjax/rotors/journal_rig.toml
N_MODES = 8
RTOLS_REDUCED = (1e-4, 1e-5, 1e-6, 1e-7, 1e-8, 1e-10)


# ------------------------------------------------------------------------------- scene
def rotor_path():
    from rotorjax.io import shipped_rotor

    return str(shipped_rotor(ROTOR_FILE))


def build_scene(n_modes=None):
    """The shipped rotor; with `n_modes`, its modal reduction (`[rotor] n_modes`)."""
    from rotorjax.models import ReducedRotor
    from rotorjax.io import load_rotor

    scene = load_rotor(rotor_path(), None if n_modes is None else {"rotor.n_modes": n_modes})
    assert (n_modes is None) != isinstance(scene.rotor, ReducedRotor)
    return scene


def with_speed(scene, profile):
    from rotorjax.models import RotorScene

    return RotorScene(scene.rotor, profile, scene.components)


def film_params(scene):
    """`(viscosity, length, radius, clearance)` of the (identical) films, checked."""
    from rotorjax.models import JournalBearing, Unbalance

    jb = [c for c in scene.components if isinstance(c, JournalBearing)]
    assert tuple(c.node for c in jb) == FILM_NODES and all(c.model == "short" for c in jb)
    p = [(float(c.viscosity), float(c.length), 0.5 * float(c.diameter), float(c.clearance)) for c in jb]
    assert p[0] == p[1]
    ub = [c for c in scene.components if isinstance(c, Unbalance)]
    assert len(ub) == 1 and ub[0].node == UNBALANCE_NODE
    return p[0], float(ub[0].magnitude), float(ub[0].phase)


class PeerModel:
    """The scene's matrices for the peers (module docstring)."""

    def __init__(self, scene):
        ns = scene.n_shaft
        self.ns = ns
        self.E_all = np.asarray(scene.expand(np.eye(ns)))
        rows = [4 * n + k for n in FORCE_NODES for k in (0, 1)]
        self.E6 = np.ascontiguousarray(self.E_all[rows])
        Minv = np.asarray(scene.Minv)
        K, Ks, C, G1 = (np.asarray(a) for a in (scene.K, scene.Ks, scene.C, scene.G1))
        self.L0 = np.ascontiguousarray(np.hstack([Minv @ K, Minv @ C]))      # speed-free part
        self.L1 = np.ascontiguousarray(np.hstack([Minv @ Ks, Minv @ G1]))    # per unit speed
        self.W = np.ascontiguousarray(Minv @ self.E6.T)
        self.g0 = Minv @ np.asarray(scene.F0)
        (mu, length, radius, c), self.U, self.phase = film_params(scene)
        self.film = (mu, length, radius, c)

    def coef(self, w0, alpha):
        """`[U, w0, alpha, phase, mu, L, R, c]`: speed w0 + alpha t, angle w0 t + alpha t^2 / 2."""
        return np.array([self.U, w0, alpha, self.phase, *self.film])

    def args(self, w0, alpha):
        """The right-hand side's arguments; at constant speed (alpha = 0) one matrix
        `M^-1 [K + w Ks, C + w G1]`, as benchmarks/rotor_scene.py's peer."""
        L0 = self.L0 if alpha != 0.0 else np.ascontiguousarray(self.L0 + w0 * self.L1)
        return L0, self.L1, self.W, self.E6, self.g0, self.coef(w0, alpha)

    def nodes_xy(self, y):
        x = self.E_all @ np.asarray(y)[:self.ns]
        return np.concatenate([x[0::4], x[1::4]])


# ------------------------------------------------------------------------------- numba
def make_numba():
    """The numba kernels: the short film force, the right-hand side, scipy's DOP853 compiled."""
    import numba

    TWO_PI = 2.0 * math.pi

    @numba.njit(cache=False)
    def short_film(x, y, vx, vy, w, mu, length, radius, c):
        """Short-bearing (Ocvirk) pi-film force (N, global x, y) on the journal.
        Local frame: e_r along (x, y), e_t a quarter turn ahead. Integrated over z,
        p gives (F_r, F_t) = k int_arc (a sin b + b cos b) (cos b, sin b) / (1 - eps
        cos b)^3 db, k = mu R L^3 / (2 c^3), a = e w - 2 v_t, b = -2 v_r, the arc where
        a sin + b cos < 0: (pi - d, 2 pi - d), (cos d, sin d) = (a, b) / |(a, b)|."""
        e = math.sqrt(x * x + y * y)
        if e > 0.0:
            cr, sr = x / e, y / e
        else:
            cr, sr = 1.0, 0.0
        eps = e / c
        vr = cr * vx + sr * vy
        vt = -sr * vx + cr * vy
        a = e * w - 2.0 * vt
        b = -2.0 * vr
        rho = math.sqrt(a * a + b * b)
        if rho == 0.0:
            return 0.0, 0.0
        cd, sd = a / rho, b / rho
        s2 = 1.0 - eps * eps
        sq = math.sqrt(s2)
        # int sin cos / u^3 (u = 1 - eps cos): antiderivative (2u - 1) / (2 eps^2 u^2); over the
        # arc (cos at the ends -cd, +cd) it is 2 eps cos1^3 / (1 - eps^2 cos1^2)^2, cos1 = -cd
        c1 = -cd
        i_sc = 2.0 * eps * c1 * c1 * c1 / (1.0 - eps * eps * c1 * c1) ** 2
        # Sommerfeld substitution: cos g = (cos b - eps) / u, sin g = sqrt(1 - eps^2) sin b / u;
        # cos^2 / u^3 db = (cos g + eps)^2 / s2^2.5 dg, sin^2 / u^3 db = sin^2 g / s2^1.5 dg
        u1 = 1.0 + eps * cd          # beta1 = pi - d: cos = -cd, sin = sd
        u2 = 1.0 - eps * cd          # beta2 = 2 pi - d: cos = cd, sin = -sd
        cg1, sg1 = (-cd - eps) / u1, sq * sd / u1
        cg2, sg2 = (cd - eps) / u2, -sq * sd / u2
        dg = math.atan2(sg2, cg2) - math.atan2(sg1, cg1)
        # g increases with beta, by less than 2 pi over half a turn
        if dg < 0.0:
            dg += TWO_PI
        # antiderivatives: (cos g + eps)^2 -> (1/2 + eps^2) g + sin g cos g / 2 + 2 eps sin g;
        #                  sin^2 g -> g / 2 - sin g cos g / 2
        scd = 0.5 * (sg2 * cg2 - sg1 * cg1)
        i_cc = ((0.5 + eps * eps) * dg + scd + 2.0 * eps * (sg2 - sg1)) / (s2 * s2 * sq)
        i_ss = (0.5 * dg - scd) / (s2 * sq)
        k = mu * radius * length ** 3 / (2.0 * c ** 3)
        fr = k * (a * i_sc + b * i_cc)
        ft = k * (a * i_ss + b * i_sc)
        return fr * cr - ft * sr, fr * sr + ft * cr

    @numba.njit(cache=False)
    def rhs_into(t, y, out, L0, L1, W, E6, g0, coef):
        ns = g0.shape[0]
        U, w0, alpha, phase = coef[0], coef[1], coef[2], coef[3]
        mu, length, radius, c = coef[4], coef[5], coef[6], coef[7]
        w = w0 + alpha * t
        u = np.zeros(6)
        v = np.zeros(6)
        for r in range(6):
            s, sv = 0.0, 0.0
            for j in range(ns):
                s += E6[r, j] * y[j]
                sv += E6[r, j] * y[ns + j]
            u[r] = s
            v[r] = sv
        f0, f1 = short_film(u[0], u[1], v[0], v[1], w, mu, length, radius, c)
        f4, f5 = short_film(u[4], u[5], v[4], v[5], w, mu, length, radius, c)
        ang = w0 * t + 0.5 * alpha * t * t + phase
        ca, sa = math.cos(ang), math.sin(ang)
        f2 = U * (w * w * ca + alpha * sa)
        f3 = U * (w * w * sa - alpha * ca)
        n2 = 2 * ns
        for i in range(ns):
            out[i] = y[ns + i]
            s = g0[i] + W[i, 0] * f0 + W[i, 1] * f1 + W[i, 2] * f2 + W[i, 3] * f3 + W[i, 4] * f4 + W[i, 5] * f5
            s0 = 0.0
            for j in range(n2):
                s0 += L0[i, j] * y[j]
            if alpha != 0.0:   # run-up: the speed's part apart (constant speed: folded into L0)
                s1 = 0.0
                for j in range(n2):
                    s1 += L1[i, j] * y[j]
                s0 += w * s1
            out[ns + i] = s - s0

    @numba.njit
    def rhs_alloc(t, y, L0, L1, W, E6, g0, coef):
        out = np.empty_like(y)
        rhs_into(t, y, out, L0, L1, W, E6, g0, coef)
        return out

    @numba.njit
    def film_many(X, w, mu, length, radius, c):
        out = np.empty((X.shape[0], 2))
        for i in range(X.shape[0]):
            out[i, 0], out[i, 1] = short_film(X[i, 0], X[i, 1], X[i, 2], X[i, 3], w[i], mu, length, radius, c)
        return out

    @numba.njit
    def rhs_args(t, y, out, args):
        L0, L1, W, E6, g0, coef = args
        rhs_into(t, y, out, L0, L1, W, E6, g0, coef)

    core = numba_dop853(rhs_args)

    @numba.njit
    def dop853(y0, t0, t1, rtol, atol, L0, L1, W, E6, g0, coef, max_steps):
        """scipy's DOP853 compiled whole (`benchmarks._common.numba_dop853`)."""
        return core(y0, t0, t1, rtol, atol, (L0, L1, W, E6, g0, coef), max_steps)

    return {"short_film": short_film, "film_many": film_many, "rhs_alloc": rhs_alloc, "dop853": dop853,
            "numba": numba}


# ------------------------------------------------------------------------------- checks
def check_film(nb, pm, n=4000, seed=0):
    """The numba film force against `rotorjax.models.film_force` at random states:
    eps in `EPS_CHECK`, velocities from 1e-3 to 3 times e w; max relative difference."""
    import jax
    import jax.numpy as jnp

    from rotorjax.models import film_force

    mu, length, radius, c = pm.film
    rng = np.random.default_rng(seed)
    eps, ang = rng.uniform(EPS_CHECK[0], EPS_CHECK[1], n), rng.uniform(0.0, 2 * math.pi, n)
    w = rng.uniform(0.0, 500.0, n)
    vscale = c * 300.0 * rng.choice([1e-3, 0.1, 1.0, 3.0], (n, 2))
    X = np.stack([eps * c * np.cos(ang), eps * c * np.sin(ang), *(rng.normal(size=(2, n)) * vscale.T)], 1)
    f_rj = np.asarray(jax.jit(jax.vmap(lambda x, s: film_force(x[:2], x[2:], s, mu, length, 2 * radius, c)))(
        jnp.asarray(X), jnp.asarray(w)))

    def rel(f):
        return float(np.max(np.linalg.norm(f - f_rj, axis=1) / np.linalg.norm(f_rj, axis=1)))
    raw = rel(nb["film_many"](X, w, mu, length, radius, c))
    # rotorjax evaluates the film at the journal's position moved by FILM_SHIFT c along x (a direction
    # at the centre); the same position here separates the closed forms from that convention
    Xs = X.copy()
    Xs[:, 0] += FILM_SHIFT * c
    shifted = rel(nb["film_many"](Xs, w, mu, length, radius, c))
    best = min(raw, shifted)
    assert best < 1e-10, f"numba film force differs from rotorjax.models.film_force by {best:.2e}"
    return {"states": n, "eps_range": list(EPS_CHECK), "max_relative_difference": raw,
            f"max_relative_difference_position_shifted_{FILM_SHIFT:g}_c_along_x": shifted}


def check_rhs(nb, scene, pm, w0, alpha, y0, seed=1):
    """The peers' right-hand side against `scene.vector_field` near `y0` (max |diff| / max |q''|)."""
    import jax.numpy as jnp

    rng = np.random.default_rng(seed)
    ns = scene.n_shaft
    worst = 0.0
    for t in (0.0, 0.0123, 0.377):
        y = y0 + rng.normal(size=y0.size) * np.r_[np.full(ns, 1e-6), np.full(ns, 1e-3)]
        a = np.asarray(scene.vector_field(t, jnp.asarray(y)))
        b = nb["rhs_alloc"](t, y, *pm.args(w0, alpha))
        worst = max(worst, float(np.max(np.abs(a - b)) / np.max(np.abs(a[ns:]))))
    assert worst < 1e-10, f"peer right-hand side differs from the scene's by {worst:.2e}"
    return worst


# ------------------------------------------------------------------------------- timing
def timed(fn, repeats):
    """`(median s, result, every repeat's s)` over max(1, repeats) calls (no warm-up
    here: the callers compile on a short span first)."""
    import jax

    ts, r = [], None
    for _ in range(max(1, repeats)):
        t0 = time.perf_counter()
        r = jax.block_until_ready(fn())
        ts.append(time.perf_counter() - t0)
    return float(np.median(ts)), r, ts


def run_solve_ivp(fun, y0, t_end, rtol, atol):
    from scipy.integrate import solve_ivp

    sol = solve_ivp(fun, (0.0, t_end), y0, method="DOP853", rtol=rtol, atol=atol, t_eval=[t_end])
    return sol.y[:, -1], {"nfev": int(sol.nfev), "steps": int(round((sol.nfev - 2) / 12)),
                          "success": bool(sol.success)}


def run_fortran(fun, y0, t_end, rtol, atol):
    from scipy.integrate import ode

    r = ode(fun).set_integrator("dop853", rtol=rtol, atol=atol, nsteps=10**8)
    r.set_initial_value(y0, 0.0)
    y = r.integrate(t_end)
    return y, {"success": bool(r.successful())}


# ------------------------------------------------------------------------------- a case
def case(label, scene, w0, alpha, t_end, rtols, repeats, nb, scipy_repeats=1, solvers=("dopri8", "tsit5")):
    """Work-precision of one scenario (module docstring): the reference, rotorjax's
    ladders (`solvers`), the peers' ladders, ratios."""
    import rotorjax as rj
    from rotorjax.models import ReducedRotor, static_equilibrium

    watch = CpuWatch()
    pm = PeerModel(scene)
    eq = static_equilibrium(scene, w0)
    assert bool(eq.converged), f"static equilibrium at {w0} rad/s not found"
    y0j = scene.rest_state().at[:scene.n_shaft].set(eq.q)
    y0 = np.asarray(y0j)
    clearance = pm.film[3]
    eps0 = float(np.hypot(*(pm.E_all @ y0[:pm.ns])[[4 * FILM_NODES[0], 4 * FILM_NODES[0] + 1]]) / clearance)
    rhs_diff = check_rhs(nb, scene, pm, w0, alpha, y0)
    args = pm.args(w0, alpha)

    t0 = time.perf_counter()
    # the final state only: the program the Dopri8 ladder runs (no second compilation)
    ref = rj.simulate(scene, y0j, (0.0, t_end), solver="dopri8", rtol=REF_RTOL, atol=REF_ATOL,
                      max_steps=MAX_STEPS)
    ref_s = time.perf_counter() - t0
    assert int(ref.code) == 0, f"reference failed: code {int(ref.code)}"
    ref_xy = pm.nodes_xy(ref.ys[-1])
    y_nb, st_nb, _, ok = nb["dop853"](y0, 0.0, t_end, REF_RTOL, REF_ATOL, *args, 10**8)
    assert ok, "numba reference failed"

    def err(y):
        return float(np.max(np.abs(pm.nodes_xy(y) - ref_xy)) / clearance)
    ref_check = err(y_nb)
    eps_end = {k: float(np.asarray(v)[-1]) for k, v in ref.outputs.items() if k.endswith("_eccentricity")}
    print(f"  [{label}] equilibrium eps {eps0:.3f}; reference {int(ref.stats['num_steps'])} steps "
          f"({ref_s:.1f} s); numba DOP853 at rtol {REF_RTOL:g}: {ref_check:.1e} clearances from it; "
          f"journal eps at the end {', '.join(f'{v:.3f}' for v in eps_end.values())}")

    rows = {}
    for solver in solvers:
        name = f"rotorjax {solver.capitalize()}"
        fn = lambda r, t1: rj.simulate(scene, y0j, (0.0, t1), solver=solver, rtol=r,  # noqa: E731
                                       atol=r * ATOL_PER_RTOL, max_steps=MAX_STEPS)
        t0 = time.perf_counter()
        fn(rtols[0], min(t_end, 1e-3)).ys.block_until_ready()   # compiles (t1, rtol are arrays: one program)
        first = time.perf_counter() - t0
        ladder = []
        for rtol in rtols:
            t, r, ts = timed(lambda: fn(rtol, t_end), repeats)
            steps = int(r.stats["num_steps"])
            ladder.append({"rtol": rtol, "s": t, "error": err(r.ys[-1]), "steps": steps,
                           "rejected": int(r.stats["num_rejected_steps"]), "us_per_step": t / steps * 1e6,
                           "code": int(r.code), "repeats_s": ts})
        rows[name] = {"compile_call_s": first, "ladder": ladder}

    fun_nb = lambda t, y: nb["rhs_alloc"](t, y, *args)  # noqa: E731

    def run_numba(r):
        y, steps, nfev, ok = nb["dop853"](y0, 0.0, t_end, r, r * ATOL_PER_RTOL, *args, 10**8)
        return y, {"steps": int(steps), "nfev": int(nfev), "success": bool(ok)}

    peers = {
        "numba DOP853 (whole integrator)": (run_numba, repeats),
        "scipy solve_ivp DOP853, numba RHS": (lambda r: run_solve_ivp(fun_nb, y0, t_end, r, r * ATOL_PER_RTOL),
                                              scipy_repeats),
        "scipy ode dop853 (Fortran), numba RHS": (lambda r: run_fortran(fun_nb, y0, t_end, r, r * ATOL_PER_RTOL),
                                                  scipy_repeats),
    }
    for name, (run, reps) in peers.items():
        ladder = []
        for rtol in rtols:
            t, (y, info), ts = timed(lambda: run(rtol), reps)
            row = {"rtol": rtol, "s": t, "error": err(y), **info, "repeats_s": ts}
            if "steps" in info:
                row["us_per_step"] = t / max(info["steps"], 1) * 1e6
            ladder.append(row)
        rows[name] = {"ladder": ladder, "repeats": max(1, reps)}
    for name, v in rows.items():
        for row in v["ladder"]:
            print(f"  [{label}] {name:<40} rtol {row['rtol']:.0e}: {row['s']:8.3f} s  err {row['error']:.2e}"
                  f"  steps {row.get('steps', '-')}")

    reduced = isinstance(scene.rotor, ReducedRotor)
    return {"model": f"reduced ({scene.rotor.n_modes} modes)" if reduced else "full FE",
            "n_modes": scene.rotor.n_modes if reduced else None, "n_shaft": scene.n_shaft,
            "t_end_s": t_end, "speed0_rad_s": w0, "acceleration_rad_s2": alpha,
            "speed_end_rad_s": w0 + alpha * t_end, "state_size": scene.state_size,
            "equilibrium_eccentricity": eps0, "equilibrium_residual": float(eq.residual),
            "journal_eccentricity_at_end": eps_end,
            "peer_rhs_vs_scene_vector_field": rhs_diff,
            "reference": {"solver": "rotorjax Dopri8", "rtol": REF_RTOL, "atol": REF_ATOL,
                          "steps": int(ref.stats["num_steps"]), "s": ref_s,
                          "numba_dop853_vs_reference_clearances": ref_check, "numba_dop853_steps": int(st_nb)},
            "reference_final_nodes_xy_m": ref_xy.tolist(), "equilibrium_nodes_xy_m": pm.nodes_xy(y0).tolist(),
            "runs": rows, "ratios": ratios_of(rows), "cpu": watch.report()}


def _ok(row):
    return row.get("success", True) and row.get("code", 0) == 0


def ratios_of(rows):
    """Peer time / rotorjax time per rotorjax rung and peer: at the same rtol, and at
    matched error (the peer's ladder log-log interpolated at rotorjax's error; a rung
    that failed, e.g. Fortran DOP853 stopping on its stiffness test, is left out)."""
    from rotorjax.bench._matching import interpolate_cost

    ratios = []
    for rj_name in (n for n in rows if n.startswith("rotorjax")):
        for i, rrow in enumerate(rows[rj_name]["ladder"]):
            for peer in (n for n in rows if not n.startswith("rotorjax")):
                pl = rows[peer]["ladder"]
                errs = [p["error"] if _ok(p) else float("nan") for p in pl]
                cost, how = interpolate_cost(errs, [p["s"] for p in pl], rrow["error"])
                ratios.append({"rotorjax": rj_name, "rtol": rrow["rtol"], "rotorjax_error": rrow["error"],
                               "peer": peer, "same_rtol": pl[i]["s"] / rrow["s"] if _ok(pl[i]) else None,
                               "matched_error": cost / rrow["s"], "match": how})
    return ratios


def summary_of(c, rtol=1e-8):
    """The issue's headline, at `rtol`: rotorjax Dopri8 against each peer, and the
    error floor (how far the two references are apart: errors below it are noise)."""
    runs = c["runs"]
    rj_row = next(r for r in runs["rotorjax Dopri8"]["ladder"] if r["rtol"] == rtol)
    out = {"rtol": rtol, "rotorjax_dopri8_s": rj_row["s"], "rotorjax_dopri8_error": rj_row["error"],
           "rotorjax_dopri8_steps": rj_row["steps"],
           "error_floor_reference_disagreement": c["reference"]["numba_dop853_vs_reference_clearances"],
           "peers": {}}
    # errors within NOISE_FACTOR x the references' disagreement cannot be told apart: the
    # cheapest successful rung of each method below that, and ratios of those
    limit = NOISE_FACTOR * out["error_floor_reference_disagreement"]
    cheapest = {}
    for name, v in runs.items():
        good = [r for r in v["ladder"] if _ok(r) and r["error"] <= limit]
        cheapest[name] = min(good, key=lambda r: r["s"]) if good else None
    rj_best = min((n for n in cheapest if n.startswith("rotorjax") and cheapest[n]), key=lambda n: cheapest[n]["s"],
                  default=None)
    rj_d8 = cheapest.get("rotorjax Dopri8")
    out["at_noise_floor"] = {
        "error_limit": limit, "rule": f"cheapest successful rung with error <= {NOISE_FACTOR:g} x the references' "
                                      "disagreement (errors below it are indistinguishable)",
        "cheapest": {n: (None if r is None else {"rtol": r["rtol"], "s": r["s"], "error": r["error"]})
                     for n, r in cheapest.items()},
        "best_rotorjax": rj_best,
        "ratio_peer_over_rotorjax_dopri8": {n: cheapest[n]["s"] / rj_d8["s"]
                                            for n in runs if not n.startswith("rotorjax") and cheapest[n] and rj_d8},
        "ratio_peer_over_best_rotorjax": {n: cheapest[n]["s"] / cheapest[rj_best]["s"]
                                          for n in runs if not n.startswith("rotorjax") and cheapest[n] and rj_best}}
    for r in c["ratios"]:
        if r["rotorjax"] == "rotorjax Dopri8" and r["rtol"] == rtol:
            prow = next(p for p in runs[r["peer"]]["ladder"] if p["rtol"] == rtol)
            out["peers"][r["peer"]] = {"s": prow["s"], "error": prow["error"], "ok": _ok(prow),
                                       "ratio_same_rtol": r["same_rtol"],
                                       "ratio_matched_error": r["matched_error"], "match": r["match"]}
    return out


# ------------------------------------------------------------------------------- main
def print_table(out):
    print("\ntime (s) and error (max node |dx, dy| at t_end / clearance) per rtol")
    for label, c in out["cases"].items():
        names = list(c["runs"])
        print(f"\n{label}")
        print(f"{'rtol':>7} " + " ".join(f"{n[:30]:>30}" for n in names))
        for i, r0 in enumerate(c["runs"][names[0]]["ladder"]):
            cells = [f"{c['runs'][n]['ladder'][i]['s']:8.3f} ({c['runs'][n]['ladder'][i]['error']:.1e})"
                     + ("" if _ok(c["runs"][n]["ladder"][i]) else "!") for n in names]
            print(f"{r0['rtol']:>7.0e} " + " ".join(f"{x:>30}" for x in cells))
        print("  (!: the run failed: not at t_end)")
        print("  ratio peer / rotorjax Dopri8 (> 1: rotorjax faster), at matched error (same rtol):")
        for r in c["ratios"]:
            if r["rotorjax"] == "rotorjax Dopri8":
                same = "failed" if r["same_rtol"] is None else f"{r['same_rtol']:.3f}"
                print(f"    rtol {r['rtol']:.0e} err {r['rotorjax_error']:.1e}  {r['peer']:<40} "
                      f"{r['matched_error']:7.3f}  ({same})  {r['match']}")


def reduction_error(red, full, eq_full, eq_red, clearance):
    """The reduced model against the full one, same scenario: max |node x, y - full| over
    all nodes at t_end (the two references) and at the initial equilibrium, in clearances."""
    rf, rr = np.asarray(full["reference_final_nodes_xy_m"]), np.asarray(red["reference_final_nodes_xy_m"])
    d = float(np.max(np.abs(rr - rf)))
    return {"final_nodes_max_abs_diff_clearances": d / clearance,
            "final_nodes_diff_relative_to_largest_full_displacement": d / float(np.max(np.abs(rf))),
            "largest_full_displacement_clearances": float(np.max(np.abs(rf))) / clearance,
            "equilibrium_nodes_max_abs_diff_clearances": float(np.max(np.abs(eq_red - eq_full))) / clearance,
            "journal_eccentricity_at_end": {"full": full["journal_eccentricity_at_end"],
                                            "reduced": red["journal_eccentricity_at_end"]},
            "equilibrium_eccentricity": {"full": full["equilibrium_eccentricity"],
                                         "reduced": red["equilibrium_eccentricity"]},
            "full_case_carried_over": "carried_over" in full}


def previous_results():
    path = os.path.join(os.path.dirname(os.path.abspath(__file__)), "results", "journal_bearings.json")
    try:
        with open(path) as f:
            return json.load(f)
    except (OSError, ValueError):
        return None


def carry_over(prev, label, scenario):
    """The full rotor's `scenario` case from the previous JSON (the run before the
    reduced cases were added labelled it by the scenario alone), marked, or None."""
    if prev is None:
        return None
    c = prev.get("cases", {}).get(label) or prev.get("cases", {}).get(scenario)
    if c is None:
        return None
    c = json.loads(json.dumps(c))
    first = c.pop("carried_over", None)
    c.setdefault("model", "full FE")
    c.setdefault("n_modes", None)
    c["carried_over"] = first or {
        "date": prev.get("date"), "cpu_of_that_run": prev.get("cpu"),
        "note": "not re-run (about 10 min): taken from the previous run's JSON, timings as measured then "
                "(load: cpu_of_that_run, the whole run's); ratios recomputed by ratios_of"}
    c["ratios"] = ratios_of(c["runs"])
    return c


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--smoke", action="store_true",
                    help=f"the reduced run-up, {SMOKE_T} s of motion, one tolerance, one call per timing; "
                         "write nothing")
    ap.add_argument("--repeats", type=int, default=3)
    ap.add_argument("--all", action="store_true", help="also re-run the full rotor's run-up (~10 min)")
    args = ap.parse_args()
    repeats = 0 if args.smoke else args.repeats

    import diffrax
    import equinox
    import jax
    import scipy

    jax.config.update("jax_enable_x64", True)
    import rotorjax  # noqa: F401
    from rotorjax.models import RunUp, static_equilibrium

    watch = CpuWatch()
    t_start = time.perf_counter()
    prev = None if args.smoke or args.all else previous_results()
    nb = make_numba()
    scene = build_scene()
    reduced = build_scene(N_MODES)
    pm = PeerModel(scene)
    film_check = check_film(nb, pm, n=200 if args.smoke else 4000)
    print(f"numba film force vs rotorjax.models.film_force: {film_check['max_relative_difference']:.1e} "
          f"relative ({film_check['states']} random states); at the position rotorjax shifts by "
          f"{FILM_SHIFT:g} c: {film_check[f'max_relative_difference_position_shifted_{FILM_SHIFT:g}_c_along_x']:.1e}")
    w_a, w_b, t_ramp = RAMP
    alpha = (w_b - w_a) / t_ramp
    with open(rotor_path()) as f:
        rotor_toml = f.read()
    out = {"benchmark": "journal_bearings (ross_compare FE rotor on two short journal bearings, gravity, unbalance; "
                        f"full and reduced to {N_MODES} modes)",
           "machine": {**machine(), "processor": platform.processor(), "jax_backend": jax.default_backend()},
           "versions": {"jax": jax.__version__, "diffrax": diffrax.__version__, "equinox": equinox.__version__,
                        "numpy": np.__version__, "scipy": scipy.__version__, "numba": nb["numba"].__version__,
                        "python": platform.python_version()},
           "setup": {"rotor_file": f"rotorjax/rotors/{ROTOR_FILE}.toml", "rotor_toml": rotor_toml,
                     "reduced": {"override": {"rotor.n_modes": N_MODES}, "n_shaft": reduced.n_shaft,
                                 "rtols": list(RTOLS_REDUCED)},
                     "full": {"n_shaft": scene.n_shaft, "rtols": list(RTOLS)},
                     "film_nodes": FILM_NODES, "unbalance_node": UNBALANCE_NODE,
                     "film": dict(zip(("viscosity", "length", "radius", "clearance"), pm.film)),
                     "unbalance_kg_m": pm.U, "oil_whirl_onset_rad_s": 207.6,
                     "initial_state": "static equilibrium at the initial speed, at rest",
                     "atol": f"rtol * {ATOL_PER_RTOL}", "repeats": max(1, repeats), "scipy_repeats": 1,
                     "max_steps": MAX_STEPS,
                     "error": "max over nodes |x, y at t_end - reference| / bearing clearance (the reference: "
                              "the same model's)",
                     "peer_numba_dop853": "scipy's DOP853 compiled whole with numba, copied from "
                                          "benchmarks/rotor_scene.py (right-hand side changed)"},
           "film_force_check": film_check, "cases": {}}
    t_c, t_r = (SMOKE_T, SMOKE_T) if args.smoke else (T_CONST, t_ramp)
    const, ramp = f"constant speed {SPEED:g} rad/s, {t_c:g} s", f"run-up {w_a:g} -> {w_b:g} rad/s over {t_ramp:g} s"
    red_name, full_name = f"reduced ({N_MODES} modes)", "full FE"
    # (label, scene, w0, alpha, t_end, rtols, scenario)
    cases = [(f"{red_name}: {const}", reduced, SPEED, 0.0, t_c, RTOLS_REDUCED, const),
             (f"{red_name}: {ramp}", with_speed(reduced, RunUp(w_a, alpha)), w_a, alpha, t_r, RTOLS_REDUCED, ramp),
             (f"{full_name}: {const}", scene, SPEED, 0.0, t_c, RTOLS, const),
             (f"{full_name}: {ramp}", with_speed(scene, RunUp(w_a, alpha)), w_a, alpha, t_r, RTOLS, ramp)]
    solvers = ("dopri8", "tsit5")
    if args.smoke:   # the reduced run-up only (the same code); both constant-speed right-hand sides checked
        for sc in (scene, reduced):
            check_rhs(nb, sc, PeerModel(sc), SPEED, 0.0, np.asarray(sc.rest_state()))
        cases, solvers = cases[1:2], ("dopri8",)
        rtols_smoke = (RTOLS[0],)
    for label, sc, w0, al, t_end, rtols, scenario in cases:
        c = None
        if label.startswith(full_name) and scenario == ramp and not args.all:
            c = carry_over(prev, label, scenario)
            if c is None:
                print(f"case: {label}: skipped (no previous run to carry over; --all runs it)")
                continue
            print(f"case: {label}: carried over from the run of {c['carried_over']['date']}")
        else:
            print(f"case: {label}")
            c = case(label, sc, w0, al, t_end, rtols_smoke if args.smoke else rtols, repeats, nb, solvers=solvers)
        out["cases"][label] = c
    full_const = out["cases"].get(f"{full_name}: {const}")
    if full_const is not None and prev is not None:   # the carried-over run-up's model is this one
        old = prev.get("cases", {}).get(f"{full_name}: {const}") or prev.get("cases", {}).get(const)
        if old is not None:
            d = np.max(np.abs(np.asarray(old["reference_final_nodes_xy_m"])
                              - np.asarray(full_const["reference_final_nodes_xy_m"]))) / pm.film[3]
            out["full_constant_speed_reference_vs_previous_run_clearances"] = float(d)
            print(f"full rotor, constant speed: reference vs the previous run's: {d:.1e} clearances")
    if not args.smoke:
        out["summary"] = {label: summary_of(c) for label, c in out["cases"].items()}
        out["reduction_error"] = {}
        for scenario, w0 in ((const, SPEED), (ramp, w_a)):
            red, full = out["cases"].get(f"{red_name}: {scenario}"), out["cases"].get(f"{full_name}: {scenario}")
            if red is None or full is None:
                continue
            eqs = [PeerModel(sc).nodes_xy(np.asarray(sc.rest_state().at[:sc.n_shaft].set(
                static_equilibrium(sc, w0).q))) for sc in (scene, reduced)]
            out["reduction_error"][scenario] = reduction_error(red, full, *eqs, pm.film[3])
    out["total_wall_s"] = time.perf_counter() - t_start
    out["cpu"] = watch.report()
    print_table(out)
    for label, sm in out.get("summary", {}).items():
        f = sm["at_noise_floor"]
        print(f"\n{label}: cheapest run within {f['error_limit']:.1e} (noise floor rule): " + ", ".join(
            f"{n} {r['s']:.2f} s (rtol {r['rtol']:.0e})" for n, r in f["cheapest"].items() if r))
        print(f"  peer / best rotorjax ({f['best_rotorjax']}): " + ", ".join(
            f"{n} {v:.2f}" for n, v in f["ratio_peer_over_best_rotorjax"].items()))
        print("  peer / rotorjax Dopri8: " + ", ".join(
            f"{n} {v:.2f}" for n, v in f["ratio_peer_over_rotorjax_dopri8"].items()))
    for scenario, r in out.get("reduction_error", {}).items():
        print(f"\nreduction error ({N_MODES} modes), {scenario}: final nodes {r['final_nodes_max_abs_diff_clearances']:.2e} "
              f"clearances ({r['final_nodes_diff_relative_to_largest_full_displacement']:.1%} of the largest full "
              f"displacement, {r['largest_full_displacement_clearances']:.1f} clearances); equilibrium "
              f"{r['equilibrium_nodes_max_abs_diff_clearances']:.2e} clearances")
    print(f"\ntotal {out['total_wall_s']:.0f} s; other processes kept "
          f"{out['cpu'].get('other_cores_busy') or 0:.2f} cores busy")
    if args.smoke:
        print("smoke run: nothing written")
    else:
        write_results("journal_bearings", out)


if __name__ == "__main__":
    main()
