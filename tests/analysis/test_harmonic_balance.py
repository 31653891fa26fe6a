"""Harmonic balance (`rotorjax.analysis.harmonic_balance`) on the forced Duffing
oscillator: the one-harmonic balance against its closed form, many harmonics
against shooting on the time integration, Floquet stability against Liouville's
formula and the jump structure of the three coexisting branches."""

import equinox as eqx
import jax
import jax.numpy as jnp
import numpy as np
import pytest

from rotorjax.analysis import PeriodicSolution, floquet, harmonic_balance, orbit_amplitude, periodic_orbit
from rotorjax._errors import InputError
from rotorjax.models import AbstractScene, ConstantSpeed
from rotorjax.solve import RESULTS, code_of

C, W0, BETA, F = 0.1, 1.0, 1.0, 0.2   # x'' + C x' + W0^2 x + BETA x^3 = F cos(om t)
OM = 1.4                             # inside the hardening Duffing's three-solution band


class Duffing(AbstractScene):
    """The forcing's frequency is the scene's (constant) speed."""

    speed: ConstantSpeed

    def __init__(self, om):
        self.speed = ConstantSpeed(om)

    @property
    def om(self):
        return self.speed.constant

    @property
    def state_size(self):
        return 2

    def vector_field(self, t, y, args=None):
        x, v = y
        return jnp.stack([v, F * jnp.cos(self.om * t) - C * v - W0**2 * x - BETA * x**3])

    def outputs(self, t, y):
        return {"x": y[0]}

    def describe(self):
        return f"Duffing oscillator at om = {self.om}"


def first_order_amplitudes(om, beta=BETA):
    """Closed form of the one-harmonic balance: `A = |x_1|` solves
    `A^2 [(W0^2 - om^2 + 3/4 BETA A^2)^2 + C^2 om^2] = F^2` (a cubic in A^2)."""
    d = W0**2 - om**2
    b = 0.75 * beta
    # in s = A^2: b^2 s^3 + 2 d b s^2 + (d^2 + C^2 om^2) s - F^2 = 0
    s = np.roots([b * b, 2 * d * b, d * d + C * C * om * om, -F * F])
    return np.sort(np.sqrt(s[(np.abs(s.imag) < 1e-12) & (s.real > 0)].real))


def phase_guess(A, om):
    """The one-harmonic motion of amplitude A as coefficients `(c_0, a_1, b_1)` of
    `(x, v)`: `x = p cos + q sin` with `p, q` from the balance's two equations."""
    d = W0**2 - om**2 + 0.75 * BETA * A * A
    p = F * d / (d * d + C * C * om * om)         # cosine: d p + C om q = F
    q = F * C * om / (d * d + C * C * om * om)     # sine: d q - C om p = 0
    return jnp.array([[0.0, 0.0], [p, q * om], [q, -p * om]])


@pytest.fixture(scope="module")
def three():
    """The three coexisting motions at OM with 1 and with 16 harmonics."""
    scene = Duffing(OM)
    T = 2 * np.pi / OM
    amps = first_order_amplitudes(OM)
    assert amps.size == 3
    one = [harmonic_balance(scene, T, phase_guess(A, OM), harmonics=1) for A in amps]
    many = [harmonic_balance(scene, T, s, harmonics=16) for s in one]
    return scene, T, amps, one, many


def test_one_harmonic_equals_the_closed_form_balance(three):
    _, _, amps, one, _ = three
    for A, s in zip(amps, one):
        assert int(s.code) == code_of(RESULTS.successful)
        a1, b1 = np.asarray(s.coefficients[1:3, 0])
        assert abs(np.hypot(a1, b1) - A) < 1e-10 * A
        assert float(s.residual) < 1e-12


def test_many_harmonics_equal_shooting_and_the_residual_falls(three):
    scene, T, _, one, many = three
    for s1, s in zip(one, many):
        assert int(s.code) == code_of(RESULTS.successful)
        assert float(s.time_residual) < 1e-9 and float(s1.time_residual) > 5e-3   # the README: 6e-3 to 0.18 with one
        y0 = np.asarray(s.initial_state())
        y_shoot, closure, ok = periodic_orbit(scene, y0 + 1e-4, T)
        assert ok and closure < 1e-10
        np.testing.assert_allclose(np.asarray(y_shoot), y0, atol=1e-9)


def test_floquet_stability_of_the_three_motions(three):
    """Outer branches stable, the middle one a saddle (one multiplier > 1); the
    multipliers' product is Liouville's `exp(-C T)`."""
    _, T, _, _, many = three
    assert [bool(s.stable) for s in many] == [True, False, True]
    for s in many:
        mu = np.asarray(s.floquet.multipliers)
        assert abs(np.prod(mu).real - np.exp(-C * T)) < 1e-9
    assert np.max(np.abs(np.asarray(many[1].floquet.multipliers))) > 1.0


def test_amplitude_and_reconstruction(three):
    scene, T, _, _, many = three
    s = many[2]
    ts = np.linspace(0.0, T, 7)
    ys = np.asarray(s.state(ts))
    np.testing.assert_allclose(ys[0], ys[-1], atol=1e-12)
    # the orbit integrated from its initial state stays on the series
    import rotorjax as rj
    r = rj.simulate(scene, s.initial_state(), (0.0, T), saveat=ts, rtol=1e-12, atol=1e-14)
    np.testing.assert_allclose(np.asarray(r.ys), ys, atol=1e-9)
    # the amplitude of the pair (x, v) is the largest radius over the period
    xs = np.asarray(s.state(np.linspace(0, T, 20001)))
    assert abs(float(s.amplitude((0, 1))) / np.max(np.hypot(xs[:, 0], xs[:, 1])) - 1) < 1e-3


def test_vmapped_over_forcing_frequency_equals_one_by_one():
    """A grid of frequencies as one compiled Newton (no stability)."""
    oms = jnp.array([0.6, 0.8, 1.0, 1.2])

    def one(om):
        return harmonic_balance(Duffing(om), 2 * jnp.pi / om, jnp.zeros(2), harmonics=5, stability=False)

    batch = jax.jit(jax.vmap(one))(oms)
    for i, om in enumerate(np.asarray(oms)):
        s = one(float(om))
        np.testing.assert_allclose(np.asarray(batch.coefficients[i]), np.asarray(s.coefficients), atol=1e-12)
    assert np.all(np.asarray(batch.code) == 0)


def test_amplitude_gradient_by_the_implicit_function_theorem(three):
    """`jax.grad` of an orbit's amplitude through `harmonic_balance` (Newton is
    differentiated implicitly: one linear solve with the balance's Jacobian) in the
    forcing frequency (which moves both the field and the period) equals central
    differences, on each of the three coexisting motions."""
    _, _, _, _, many = three

    def amplitude(om, guess):
        s = harmonic_balance(Duffing(om), 2 * jnp.pi / om, guess, harmonics=16, stability=False)
        return orbit_amplitude(Duffing(om), s.coefficients, s.period, node=None, rows=(0, 1))

    h = 1e-6
    for s in many:
        d = float(jax.grad(amplitude)(OM, s))
        fd = (float(amplitude(OM + h, s)) - float(amplitude(OM - h, s))) / (2 * h)
        assert abs(d - fd) < 1e-6 * max(1.0, abs(d))


def test_periodic_orbit_by_either_method_is_the_same_motion(three):
    """`periodic_orbit(method=...)`: harmonic balance and shooting (Newton on the
    integrated closure, then the same series of its samples) give the same
    coefficients, multipliers and verdict; the former call still returns
    `(y0, closure, converged)`; an unknown method is refused by name."""
    scene, T, _, _, many = three
    for s in many:
        hb = periodic_orbit(scene, s, method="harmonic-balance", harmonics=16)
        sh = periodic_orbit(scene, s.initial_state() + 1e-3, method="shooting", harmonics=16)
        assert int(hb.code) == 0 and int(sh.code) == 0 and float(sh.residual) < 1e-11
        np.testing.assert_allclose(np.asarray(sh.coefficients), np.asarray(hb.coefficients), atol=1e-9)
        mu_hb = np.sort_complex(np.asarray(hb.floquet.multipliers))
        mu_sh = np.sort_complex(np.asarray(sh.floquet.multipliers))
        np.testing.assert_allclose(mu_sh, mu_hb, atol=1e-8)
        assert bool(sh.stable) == bool(hb.stable)
    y0, closure, ok = periodic_orbit(scene, many[0].initial_state(), T)
    assert ok and closure < 1e-11
    with pytest.raises(InputError, match="method 'collocation'"):
        periodic_orbit(scene, many[0], method="collocation")


def test_harmonics_adapted_to_the_truncation_estimate(three):
    """`harmonics="auto"`: 4, 8, 16, ... until the reported time-domain residual is
    below `truncation_tol`; the motion is the fixed-harmonics one; where the most
    harmonics allowed do not reach it, the code says so."""
    scene, T, _, one, many = three
    s = harmonic_balance(scene, T, one[2], "auto", truncation_tol=1e-8, stability=False)
    assert int(s.code) == 0 and float(s.time_residual) <= 1e-8 and s.harmonics in (8, 16)
    m = 2 * s.harmonics + 1
    np.testing.assert_allclose(np.asarray(s.coefficients), np.asarray(many[2].coefficients)[:m], atol=1e-8)
    short = harmonic_balance(scene, T, one[2], "auto", truncation_tol=1e-14, max_harmonics=4, stability=False)
    assert short.harmonics == 4 and int(short.code) == code_of(RESULTS.harmonics_insufficient)
    assert "harmonics do not resolve" in RESULTS[short.result]


def test_non_convergence_is_reported_not_returned_as_a_solution():
    s = harmonic_balance(Duffing(OM), 2 * np.pi / OM, jnp.array([3.0, 0.0]), harmonics=3, max_iter=1,
                         stability=False)
    assert int(s.code) == code_of(RESULTS.root_not_converged) and not bool(s.success)


class Walled(Duffing):
    """A spring that stiffens without bound towards a wall at `|x| = 1` (as a film's
    journal near its bearing's), its force not defined beyond: `x / (1 - x^2)`,
    forced at resonance, where the linear response (Newton's first step from rest)
    is far beyond the wall."""

    def vector_field(self, t, y, args=None):
        x, v = y
        spring = jnp.where(jnp.abs(x) < 1, x / (1 - x * x), jnp.nan)
        return jnp.stack([v, F * jnp.cos(self.om * t) - C * v - spring])


def test_newton_steps_through_a_wall_are_halved():
    """From rest at resonance the full first step puts the motion through the wall
    (the linear amplitude F / (C om) = 2); halved until the forces are defined
    there, Newton converges to the motion inside, which equals shooting's."""
    scene, period = Walled(1.0), 2 * np.pi
    assert F / C > 1
    s = harmonic_balance(scene, period, jnp.zeros(2), harmonics=8, stability=False)
    assert int(s.code) == 0 and float(s.residual) < 1e-9
    ts = np.linspace(0.0, period, 64, endpoint=False)

    def amplitude(sol):
        return max(abs(float(sol.state(t)[0])) for t in ts)

    amp = amplitude(s)
    assert 0.1 < amp < 1
    shot = periodic_orbit(scene, s.initial_state(), period, method="shooting", harmonics=8)
    assert int(shot.code) == 0 and amplitude(shot) == pytest.approx(amp, rel=1e-3)


@pytest.mark.parametrize("kwargs, match", [
    ({"harmonics": 0}, "harmonics must be an integer >= 1"),
    ({"harmonics": 2.5}, "harmonics must be an integer >= 1"),
    ({"harmonics": 4, "n_samples": 8}, "n_samples must be an integer >= 9"),
    ({"period": -1.0}, "period must be"),
    ({"guess": jnp.zeros(3)}, r"guess must be a state of shape \(2,\)"),
    ({"guess": jnp.zeros((4, 2))}, r"guess must be .* got shape \(4, 2\)"),
    ({"scene": "duffing"}, "scene must be a scene"),
    ({"max_iter": 0}, "max_iter must be an integer >= 1"),
    ({"tol": 0.0}, "tol must be"),
])
def test_bad_input_is_refused_by_name(kwargs, match):
    call = {"scene": Duffing(OM), "period": 2 * np.pi / OM, "guess": jnp.zeros(2), "harmonics": 3,
            "stability": False} | kwargs
    with pytest.raises(InputError, match=match):
        harmonic_balance(**call)


@pytest.mark.parametrize("kwargs, match", [
    ({"method": "harmonic-balance", "events": True}, "events: event-located contact is for method='shooting'"),
    ({"method": "shooting", "events": True}, "needs a scene with `contact_indicator`"),
])
def test_event_located_shooting_refused_where_it_does_not_apply(kwargs, match):
    """`periodic_orbit(events=True)`: shooting only, on a scene with contacts
    (tests/validation/test_model004_whirl_cycle.py runs it on model 004)."""
    with pytest.raises(InputError, match=match):
        periodic_orbit(Duffing(OM), jnp.zeros(2), 2 * np.pi / OM, **kwargs)


def test_stable_without_stability_is_refused():
    s = harmonic_balance(Duffing(0.5), 2 * np.pi / 0.5, jnp.zeros(2), harmonics=2, stability=False)
    assert isinstance(s, PeriodicSolution) and s.floquet is None
    with pytest.raises(InputError, match="stability=False"):
        s.stable


def fold_frequencies(beta=BETA):
    """Where the one-harmonic balance's cubic in `A^2` has a double root: zeros of
    its discriminant (closed form), bracketed by the root count."""
    from scipy.optimize import brentq

    def disc(om):
        d, b = W0**2 - om**2, 0.75 * beta
        a3, a2, a1, a0 = b * b, 2 * d * b, d * d + C * C * om * om, -F * F
        return (18 * a3 * a2 * a1 * a0 - 4 * a2**3 * a0 + a2**2 * a1**2 - 4 * a3 * a1**3
                - 27 * a3**2 * a0**2)

    grid = np.linspace(1.0, 2.0, 201)
    counts = [first_order_amplitudes(om, beta).size for om in grid]
    return [brentq(disc, grid[i], grid[i + 1], xtol=1e-14) for i in range(200) if counts[i] != counts[i + 1]]


def test_branch_through_the_folds_equals_the_closed_form_and_floquet():
    """The frequency response continued in the forcing frequency: with one
    harmonic its folds are the closed form's to 1e-8; with eight, Hill's margin
    along the branch equals Floquet's at the same orbits, and the part between the
    folds is unstable."""
    from rotorjax.analysis import periodic_branch

    folds_cf = fold_frequencies()
    assert len(folds_cf) == 2
    br1, _ = periodic_branch(Duffing, 1.0, jnp.zeros(2), (1.0, 2.0), harmonics=1, ds=0.05, ds_max=0.1)
    folds = sorted(e.p for e in br1.events if e.kind == "fold")
    np.testing.assert_allclose(folds, folds_cf, rtol=1e-8)
    assert br1.curve.stops == ("box edge (p = 1.0)", "box edge (p = 2.0)")

    br8, coefs = periodic_branch(Duffing, 1.0, jnp.zeros(2), (1.0, 2.0), harmonics=8, ds=0.05, ds_max=0.1)
    f8 = sorted(e.p for e in br8.events if e.kind == "fold")
    assert len(f8) == 2 and np.allclose(f8, folds_cf, rtol=2e-2)   # the higher harmonics move them a little
    for i in np.linspace(0, len(br8.p) - 1, 7).astype(int):
        om = float(br8.p[i])
        s = harmonic_balance(Duffing(om), 2 * np.pi / om, coefs[i], harmonics=8)
        np.testing.assert_allclose(np.asarray(s.coefficients), coefs[i], atol=1e-9)
        assert abs(float(br8.margin[i]) - float(s.floquet.margin)) < 1e-6
        assert bool(br8.stable[i]) == bool(s.stable)
    stable, p = np.asarray(br8.stable), np.asarray(br8.p)
    outside = (p < f8[0] - 1e-3) | (p > f8[1] + 1e-3)
    assert np.all(stable[outside]) and not np.all(stable[~outside])   # one motion outside, three between


class StiffnessDuffing(Duffing):
    """`Duffing` with the cubic stiffness a field (an array: the scene's data)."""

    beta: jax.Array

    def __init__(self, om, beta):
        self.speed, self.beta = ConstantSpeed(om), jnp.asarray(beta, dtype=jnp.float64)

    def vector_field(self, t, y, args=None):
        x, v = y
        return jnp.stack([v, F * jnp.cos(self.om * t) - C * v - W0**2 * x - self.beta * x**3])


def test_a_branch_of_other_values_compiles_nothing():
    """The branch's programs are compiled once per structure (`solve._lift`): a
    second branch with another cubic stiffness lowers and compiles nothing (it
    traces its equations, to compare them), and its
    folds are its own closed form's (no program of the first one answers for it)."""
    from rotorjax.analysis import periodic_branch

    events = []

    def listen(event, duration, **kwargs):
        if event in ("/jax/core/compile/jaxpr_to_mlir_module_duration", "/jax/core/compile/backend_compile_duration"):
            events.append(event)

    folds = {}
    for beta in (0.8, 1.3):
        jax.monitoring.register_event_duration_secs_listener(listen)
        try:
            b = jnp.asarray(beta)   # an array: a Python number closed over would be part of the program
            br, _ = periodic_branch(lambda om: StiffnessDuffing(om, b), 1.0, jnp.zeros(2), (1.0, 2.0),
                                    harmonics=1, ds=0.05, ds_max=0.1)
        finally:
            jax.monitoring.unregister_event_duration_listener(listen)
        folds[beta] = sorted(e.p for e in br.events if e.kind == "fold")
        if beta == 0.8:
            assert events   # the first compiles
            events.clear()
    assert events == []
    for beta, f in folds.items():
        np.testing.assert_allclose(f, fold_frequencies(beta), rtol=1e-8)


def test_shooting_branch_equals_the_harmonic_balance_branch():
    """`periodic_branch(method="shooting")`: the closure of 256 fixed Dopri8 steps
    per period continued in the forcing frequency; its folds and stability are the
    harmonic balance's (12 harmonics), and its orbits' series too."""
    from rotorjax.analysis import periodic_branch

    hb, c_hb = periodic_branch(Duffing, 1.2, jnp.zeros(2), (1.2, 1.6), harmonics=12)
    start = harmonic_balance(Duffing(1.2), 2 * np.pi / 1.2, jnp.zeros(2), harmonics=12)   # shooting's guess
    sh, c_sh = periodic_branch(Duffing, 1.2, start, (1.2, 1.6), harmonics=12, method="shooting")
    f_hb = sorted(e.p for e in hb.events if e.kind == "fold")
    f_sh = sorted(e.p for e in sh.events if e.kind == "fold")
    assert len(f_sh) == 2 and [e.kind for e in sh.events] == ["fold", "fold"]
    np.testing.assert_allclose(f_sh, f_hb, rtol=1e-9)
    for i in np.linspace(0, len(sh.p) - 1, 4).astype(int):
        om = float(sh.p[i])
        s = harmonic_balance(Duffing(om), 2 * np.pi / om, c_sh[i], harmonics=12)
        np.testing.assert_allclose(np.asarray(s.coefficients), c_sh[i], atol=1e-8)
        assert abs(float(sh.margin[i]) - float(s.floquet.margin)) < 1e-7
    assert sh.stops == hb.stops == ("box edge (p = 1.2)", "box edge (p = 1.6)")
    # auto by shooting: each point's series keeps the fewest harmonics whose left-out ones hold at most
    # truncation_tol of it, the rest the fixed run's
    sa, c_sa = periodic_branch(Duffing, 1.2, start, (1.2, 1.6), "auto", method="shooting", max_harmonics=12,
                               truncation_tol=1e-6)
    np.testing.assert_array_equal(sa.p, sh.p)
    kept = np.asarray(sa.harmonics)
    assert 1 < kept.min() and kept.max() < 12 and np.all(np.asarray(sa.truncation) <= 1e-6)
    for i, h in enumerate(kept):
        m = 2 * h + 1
        np.testing.assert_array_equal(c_sa[i, :m], c_sh[i, :m])
        assert np.all(c_sa[i, m:] == 0.0)
        tail = np.linalg.norm(c_sh[i, m - 2:]) / np.linalg.norm(c_sh[i])    # one harmonic fewer: too many left out
        assert tail > 1e-6


def test_hill_exponents_equal_floquet_multipliers(three):
    """Hill's exponents (no integration) against the monodromy's multipliers, on
    the three coexisting motions with 16 harmonics."""
    from rotorjax.analysis import hill_exponents

    scene, T, _, _, many = three
    for s in many:
        mu_hill = np.sort_complex(np.exp(np.asarray(hill_exponents(scene, s)) * T))
        mu = np.sort_complex(np.asarray(s.floquet.multipliers))
        np.testing.assert_allclose(mu_hill, mu, atol=1e-8)


def test_magnus_exponents_equal_floquet_multipliers(three):
    """The monodromy of the reconstructed orbit by Magnus propagators (what a branch
    uses where Hill's matrix is large) against the integrated monodromy's
    multipliers, on the three coexisting motions with 16 harmonics."""
    from rotorjax.analysis._harmonic_balance import magnus_exponents

    scene, T, _, _, many = three
    for s in many:
        mu_magnus = np.sort_complex(np.exp(np.asarray(magnus_exponents(scene, s.coefficients, T)) * T))
        mu = np.sort_complex(np.asarray(s.floquet.multipliers))
        np.testing.assert_allclose(mu_magnus, mu, atol=1e-8)


def test_a_branch_with_magnus_exponents_equals_hill_s(monkeypatch):
    """A branch whose Hill matrix is above `HILL_MAX` takes its exponents from the
    Magnus monodromy: the same stability and folds as Hill's, the margins within
    1e-6 (the two differ by the truncation: 4e-3 with 4 harmonics, 4e-7 with 12)."""
    from rotorjax.analysis import _periodic_branch, periodic_branch

    def branch():
        return periodic_branch(Duffing, 1.0, jnp.zeros(2), (1.0, 2.0), harmonics=12, ds=0.05, ds_max=0.1)[0]

    hill, hill_max = branch(), _periodic_branch.HILL_MAX
    monkeypatch.setattr(_periodic_branch, "HILL_MAX", 0)
    magnus = branch()
    np.testing.assert_allclose(magnus.p, hill.p, rtol=1e-12)
    np.testing.assert_allclose(magnus.margin, hill.margin, atol=1e-6)
    assert np.array_equal(magnus.stable, hill.stable) and not np.all(hill.stable)
    assert [(e.kind, e.between) for e in magnus.events] == [(e.kind, e.between) for e in hill.events]
    assert [e.kind for e in hill.events] == ["fold", "fold"]
    from tests.helpers import documentation

    text = " ".join(documentation("docs/periodic.md").split())
    assert (f"Above `HILL_MAX` ({hill_max}) unknowns" in text
            and "with 12 harmonics the two give the same stability and folds and margins within 1e-6" in text)


def test_truncation_estimate_is_the_error_of_the_left_out_harmonics(three):
    """`truncation_error` of a series of H harmonics against its actual distance
    from the 16-harmonic motion (round-off there), state by state relative to each
    state's size: within a factor 2 while the error is above round-off."""
    from rotorjax.analysis import truncation_error

    scene, T, _, one, many = three
    for s1, s16 in zip(one, many):
        ref = np.asarray(s16.coefficients)
        size = np.max(np.abs(ref), axis=0)
        for H in (1, 2, 4):
            s = harmonic_balance(scene, T, s1, H, stability=False)
            Y = np.zeros_like(ref)
            Y[:2 * H + 1] = np.asarray(s.coefficients)
            true = np.linalg.norm((Y - ref) / size) / np.linalg.norm(ref / size)
            est = float(truncation_error(scene, s.coefficients, T))
            assert true > 1e-12 and 0.5 < est / true < 2.0, (H, est, true)


def test_truncation_profile_predicts_the_estimate_with_more_harmonics(three):
    """`truncation_profile` of a series of H harmonics against `truncation_error` of
    the motion solved with h > H harmonics (up to 12), for each of the three motions
    and H = 1, 2, 4: its first entry is `truncation_error` itself; it is never above
    the estimate then solved (it holds the harmonics the series' own terms make, not
    those that the harmonics yet to be solved would make in turn), so a count it
    shows short would not have met the target; below three times the highest
    harmonic the series holds (a cubic's reach: the Duffing motions hold no even
    ones) it is within a factor 20 of it. `next_harmonics` reads the counts off it: from 1
    harmonic 4 and from 4, 8 for the largest motion at 1e-6, where the ladder
    climbs 1, 2, 4, 8."""
    from rotorjax.analysis import truncation_error
    from rotorjax.analysis._harmonic_balance import next_harmonics, truncation_profile
    from tests.helpers import documentation

    scene, T, _, one, _ = three
    for s1 in one:
        for H in (1, 2, 4):
            s = harmonic_balance(scene, T, s1, H, stability=False)
            profile = np.asarray(truncation_profile(scene, s.coefficients, T))
            Y = np.abs(np.asarray(s.coefficients))
            held = max(k for k in range(1, H + 1) if Y[2 * k - 1:2 * k + 1].max() > 1e-12 * Y.max())
            assert profile[0] == pytest.approx(float(truncation_error(scene, s.coefficients, T)), rel=1e-12)
            for h in range(H + 1, min(12, H + profile.size - 1) + 1):
                actual = float(truncation_error(scene, harmonic_balance(scene, T, s, h, stability=False).coefficients,
                                                T))
                assert profile[h - H] <= 1.01 * actual + 1e-15, (H, h, profile[h - H], actual)
                if h < 3 * held:
                    assert profile[h - H] >= actual / 20, (H, h, profile[h - H], actual)
    ladder = (2, 4, 8, 16)
    big = harmonic_balance(scene, T, one[-1], 1, stability=False)
    assert next_harmonics(truncation_profile(scene, big.coefficients, T), 1, ladder, 1e-6) == 4
    big = harmonic_balance(scene, T, one[-1], 4, stability=False)
    assert next_harmonics(truncation_profile(scene, big.coefficients, T), 4, ladder[2:], 1e-6) == 8
    profile = np.array([1e-2, 1e-4, 1e-5, 1e-7, 1e-9])
    assert next_harmonics(profile, 1, (2, 8, 16), 1e-6) == 8           # beyond what the profile sees
    assert next_harmonics(profile, 1, (2, 4), 1e-12) == 4              # nothing seen meets it: the last
    text = " ".join(documentation("docs/periodic.md").split())
    assert ("never above the estimate then solved, so a count it shows short would not have met the target, and "
            "below three times the highest harmonic the series holds (a cubic's reach) within a factor 20 of it"
            in text)


def test_branch_harmonics_adapted_along_the_branch():
    """`periodic_branch`'s default, `harmonics="auto"`: from the small motion at 2.0
    down through both folds, the harmonics go up where the motion grows and down
    again past the resonance; every point's estimate is below the target, and its
    actual error (against 32 harmonics solved at that point) within 5x of it; the
    pieces join into one curve without gaps, each fold between the two points where
    it turns back."""
    from rotorjax.analysis import periodic_branch

    br, coefs = periodic_branch(Duffing, 2.0, jnp.zeros(2), (1.0, 2.0), ds=0.05, ds_max=0.1)
    H = np.asarray(br.harmonics)
    assert br.stops == ("box edge (p = 1.0)", "box edge (p = 2.0)")
    assert H[-1] < H.max() and len(set(H.tolist())) >= 3 and coefs.shape[1] == 2 * H.max() + 1
    assert np.all(np.asarray(br.truncation) <= 1e-6)
    for i in np.linspace(0, len(H) - 1, 6).astype(int):
        om = float(br.p[i])
        ref = np.asarray(harmonic_balance(Duffing(om), 2 * np.pi / om, coefs[i], 32, stability=False).coefficients)
        size = np.max(np.abs(ref), axis=0)
        assert np.all(coefs[i, 2 * H[i] + 1:] == 0.0)
        err = np.linalg.norm((ref[:coefs.shape[1]] - coefs[i]) / size) / np.linalg.norm(ref / size)
        assert err <= 5e-6, (om, H[i], err)
    chords = np.diff(br.curve.x, axis=0)
    assert np.max(np.linalg.norm(chords, axis=1)) <= 0.1 * 1.01
    cos = np.sum(chords * br.curve.tangents[1:], axis=1) / np.linalg.norm(chords, axis=1)
    assert np.min(cos) > 0.9          # the tangents point along the branch across the joins
    folds = [e for e in br.events if e.kind == "fold"]
    assert len(folds) == 2
    for e in folds:      # between the two points where the branch turns back in p
        a, b = e.between
        dp = br.curve.tangents[[a, b], -1]
        assert b == a + 1 and dp[0] * dp[1] < 0 and abs(e.p - br.p[a]) < 0.1


@pytest.mark.parametrize("kwargs, match", [
    ({"p_bounds": 1.0}, r"p_bounds must be a pair \(lo, hi\)"),
    ({"p0": 3.0}, r"p0 = 3.0 must lie in p_bounds = \(1.0, 2.0\)"),
    ({"harmonics": 0}, "harmonics must be an integer >= 1"),
    ({"harmonics": "many"}, "harmonics must be an integer >= 1 or 'auto', got 'many'"),
    ({"harmonics": "auto", "max_harmonics": 0}, "max_harmonics must be an integer >= 1"),
    ({"harmonics": "auto", "truncation_tol": 0.0}, "truncation_tol must be"),
])
def test_periodic_branch_refuses_bad_input_by_name(kwargs, match):
    from rotorjax.analysis import periodic_branch

    call = {"p0": 1.4, "guess": jnp.zeros(2), "p_bounds": (1.0, 2.0), "harmonics": 1} | kwargs
    with pytest.raises(InputError, match=match):
        periodic_branch(Duffing, call["p0"], call["guess"], call["p_bounds"], call["harmonics"],
                        **{k: v for k, v in kwargs.items() if k in ("max_harmonics", "truncation_tol")})


def test_periodic_branch_start_that_fails_is_a_named_numerical_error():
    from rotorjax._errors import NumericalError
    from rotorjax.analysis import periodic_branch

    with pytest.raises(NumericalError, match=r"periodic_branch: no periodic motion at p = 1.4 .*non-finite"):
        periodic_branch(Duffing, 1.4, jnp.full(2, jnp.nan), (1.0, 2.0), harmonics=1)
