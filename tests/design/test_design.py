"""Design with gradients (`rotorjax.design`): the one mechanism (`minimize`) against
a closed form, a rotor file's design against a vmapped brute-force grid, the
gradients of every quantity against finite differences, and the bad input. One
rotor: ROSS's example rotor (`ross_compare.toml`) with 500 N s/m bearing damping."""

import jax
import jax.numpy as jnp
import numpy as np
import pytest

from rotorjax._errors import InputError
from rotorjax.design import latin_starts, minimize, optimize_rotor, parse_constraint, rotor_problem
from rotorjax.io import read_rotor_file, shipped_rotor
from rotorjax.uncertainty import LogNormal, Normal, draw

SETS = {"bearing0.cxx": 500.0, "bearing0.cyy": 500.0, "bearing1.cxx": 500.0, "bearing1.cyy": 500.0}


@pytest.fixture(scope="module")
def file():
    return read_rotor_file(str(shipped_rotor("ross_compare")), SETS)


def test_the_mechanism_meets_a_closed_form(capsys):
    """min (x - 2)^2 + (y - 1)^2 on the disc x^2 + y^2 <= 1 within a box: the optimum
    (2, 1) / sqrt(5) and its multiplier `(2 - x) / x` (from `grad f = -lambda grad c`),
    from 6 starts at once; and a bound-held optimum (Rosenbrock with x <= 0.8: (0.8,
    0.64)). With `progress`, a bar over the outer iterations on stderr."""
    def fn(v):
        return (v[0] - 2) ** 2 + (v[1] - 1) ** 2, jnp.array([v[0] ** 2 + v[1] ** 2 - 1.0])

    lo, hi = np.array([-3.0, -3.0]), np.array([3.0, 3.0])
    o = minimize(fn, lo, hi, latin_starts(lo, hi, 6, first=[0.0, 0.0]), progress=True)
    assert "optimize" in capsys.readouterr().err
    x = 2 / np.sqrt(5)
    assert o.converged and o.feasible and o.end_converged.all()
    np.testing.assert_allclose(o.x, [x, x / 2], atol=1e-6)
    assert o.multipliers[0] == pytest.approx((2 - x) / x, rel=1e-5)
    assert o.objective == pytest.approx((x - 2) ** 2 + (x / 2 - 1) ** 2, rel=1e-7)
    assert o.history.shape[1] == 6 and o.history[-1, 1] <= 1e-6

    def rosen(v):
        return 100 * (v[1] - v[0] ** 2) ** 2 + (1 - v[0]) ** 2, jnp.zeros(0)

    o = minimize(rosen, np.array([-2.0, -1.0]), np.array([0.8, 2.0]), np.array([[-1.5, 1.5], [0.0, 0.0]]))
    np.testing.assert_allclose(o.x, [0.8, 0.64], atol=1e-5)


def test_a_two_parameter_design_equals_the_brute_force_grid(file):
    """Maximise the least log decrement (first three modes, 0..600 rad/s) over the
    two bearings' damping `cxx` in 100..5000 N s/m: the optimum is at least the best
    of a vmapped 24 x 24 grid of the same quantity, and the grid's values near it agree
    (an independent search of the same function)."""
    vary = {"bearing0.cxx": (100.0, 5000.0), "bearing1.cxx": (100.0, 5000.0)}
    p = rotor_problem(file, vary, "min-log-dec", speed_range=(0.0, 600.0), n_modes=3, n_grid=17)
    d = optimize_rotor(p, n_starts=3)
    assert d.optimum.converged and d.optimum.feasible
    a = np.geomspace(100.0, 5000.0, 24)
    A, B = np.meshgrid(a, a, indexing="ij")
    grid = np.asarray(jax.jit(jax.vmap(lambda x: p.quantities(x)["min-log-dec"]))(
        jnp.asarray(np.stack([A.ravel(), B.ravel()], axis=1))))
    best = float(np.max(grid))
    opt = d.quantities_after["min-log-dec"]
    assert opt >= best - 1e-9
    assert opt <= best + 0.05 * abs(best)          # the grid is 18 % apart: near, not far below
    assert d.quantities_after["min-log-dec"] > d.quantities_before["min-log-dec"]


@pytest.mark.parametrize("name", ["min-log-dec", "separation-margin", "response", "mass"])
def test_each_quantity_has_the_gradient_of_its_finite_differences(file, name):
    """The gradient of each quantity (autodiff through the eigenvalues, the followed
    critical speeds, the responses) against central differences, in three parameters
    of different kinds: a stiffness, a damping, a disk's mass."""
    vary = {"bearing0.kxx": (5e5, 2e6), "bearing1.cxx": (100.0, 2000.0), "disk0.m": (20.0, 40.0)}
    p = rotor_problem(file, vary, name, speed_range=(0.0, 1000.0), n_modes=3, operating=(400.0, 600.0),
                      n_grid=33 if name != "response" else 200)
    q = jax.jit(lambda v: p.quantities(v)[name])
    x0 = p.nominal
    g = np.asarray(jax.jit(jax.grad(lambda v: p.quantities(v)[name]))(jnp.asarray(x0)))
    for i in range(3):
        h = 1e-4 * x0[i]
        e = np.eye(3)[i] * h
        fd = (float(q(jnp.asarray(x0 + e))) - float(q(jnp.asarray(x0 - e)))) / (2 * h)
        assert g[i] == pytest.approx(fd, rel=2e-4, abs=1e-7 * abs(float(q(jnp.asarray(x0)))) / x0[i]), (name, i)


def test_an_active_separation_constraint_holds_with_its_multiplier(file):
    """Lighten the two disks (minimise the mass) while the API 684 separation margins
    from an operating range of 400..600 rad/s hold: lighter disks raise the second
    critical speed (300 rad/s) towards the range, so the margin ends active (its slack
    0 within 1e-4 percent) with a positive multiplier, and the disks lighter than at
    the start; the slack there equals API 684's formula at the critical speed and
    amplification factor the analyses give independently."""
    from rotorjax.analysis import (amplification_factor, critical_speed, damped_eigenvalues,
                                   required_separation_margin)

    vary = {"disk0.m": (15.0, 40.0), "disk1.m": (15.0, 40.0)}
    p = rotor_problem(file, vary, "mass", [("separation-margin", ">=", 0.0)], operating=(400.0, 600.0))
    d = optimize_rotor(p, n_starts=2)
    row, = d.constraint_rows
    assert d.optimum.converged and row["met"] and abs(row["value"]) < 1e-4 and row["multiplier"] > 0
    assert d.quantities_after["mass"] < d.quantities_before["mass"] - 5.0
    rotor = read_rotor_file(str(shipped_rotor("ross_compare")),
                            {**SETS, **{k: v for k, v in d.after.items()}}).scene.full_rotor
    w, _ = critical_speed(rotor, 3, 340.0)
    af = amplification_factor(damped_eigenvalues(rotor, w, 4)[3])
    slack = 100 * (400.0 - float(w)) / 400.0 - float(required_separation_margin(af, True))
    assert slack == pytest.approx(0.0, abs=0.05)     # the soft minimum over the three critical speeds: within 0.05


def test_a_robust_design_holds_its_constraint_k_standard_deviations_out(file):
    """The disks lightened as above, but the bearings' stiffnesses scatter (lognormal, 10
    %): the separation margin's mean less 2 standard deviations over 8 common samples
    must stay >= 0. The robust optimum is heavier than the nominal one (64.9 kg); its
    constraint is active with a positive multiplier; and the statistic equals the mean
    less 2 sample standard deviations of the margin evaluated independently, sample by
    sample, by the problem that varies the bearings' stiffnesses as parameters."""
    scatter = {"bearing0.kxx": LogNormal(1e6, 1e5), "bearing1.kxx": LogNormal(1e6, 1e5)}
    vary = {"disk0.m": (15.0, 40.0), "disk1.m": (15.0, 40.0)}
    p = rotor_problem(file, vary, "mass", [("separation-margin", ">=", 0.0)], operating=(400.0, 600.0),
                      scatter=scatter, robust_k=2.0, robust_samples=8)
    d = optimize_rotor(p, n_starts=1)
    row, = d.constraint_rows
    assert d.optimum.converged and row["met"] and abs(row["value"]) < 1e-4 and row["multiplier"] > 0
    assert d.quantities_after["mass"] > 67.0 and row["sd"] > 0.5
    plain = rotor_problem(file, {**vary, "bearing0.kxx": (5e5, 2e6), "bearing1.kxx": (5e5, 2e6)},
                          "separation-margin", operating=(400.0, 600.0))
    X = np.concatenate([np.tile([d.after["disk0.m"], d.after["disk1.m"]], (8, 1)), draw(scatter, 8, seed=0)], axis=1)
    each = np.array([float(jax.jit(plain.quantities)(jnp.asarray(x))["separation-margin"]) for x in X])
    assert row["value"] == pytest.approx(each.mean() - 2 * each.std(ddof=1), abs=1e-6)
    assert row["mean"] == pytest.approx(each.mean(), abs=1e-6)


@pytest.mark.parametrize("call, match", [
    (lambda f: rotor_problem(f, {"bearing9.kxx": (1e5, 1e6)}, "mass"), r"--vary bearing9\.kxx: not a parameter"),
    (lambda f: rotor_problem(f, {"bearing0.kxx": (1e6, 1e5)}, "mass"),
     r"--vary bearing0\.kxx=1e\+06:100000: .*LO < HI"),
    (lambda f: rotor_problem(f, {"disk0.m": (0.0, 40.0)}, "mass"), r"--vary disk0\.m=0:40: disk0\.m must be >0"),
    (lambda f: rotor_problem(f, {"bearing0.kxx": (-1e5, 1e6)}, "mass"), r"bearing0\.kxx must be >=0"),
    (lambda f: rotor_problem(f, {}, "mass"), r"--vary: give at least one parameter"),
    (lambda f: rotor_problem(f, {"bearing0.node": (1.0, 3.0)}, "mass"),
     r"--vary bearing0\.node: an integer that shapes the scene"),
    (lambda f: rotor_problem(f, {"disk0.m": (20.0, 40.0)}, "stiffness"), r"--objective stiffness: unknown"),
    (lambda f: rotor_problem(f, {"disk0.m": (20.0, 40.0)}, "separation-margin"), r"--operating: separation-margin"),
    (lambda f: rotor_problem(f, {"disk0.m": (20.0, 40.0)}, "onset", speed_range=(0.0, 1000.0)),
     r"onset: .* has no stability onset"),
    (lambda f: optimize_rotor(rotor_problem(f, {"disk0.m": (20.0, 40.0)}, "min-log-dec", [("mass", "<=", 1.0)],
                                            speed_range=(0.0, 600.0), n_grid=9), n_starts=1),
     r"--constraint: no start of 1 met mass<=1"),
    (lambda f: rotor_problem(f, {"disk0.m": (20.0, 40.0)}, "mass", scatter={"disk0.m": LogNormal(30.0, 1.0)}),
     r"--scatter disk0\.m: also given to --vary"),
    (lambda f: rotor_problem(f, {"disk0.m": (20.0, 40.0)}, "mass", scatter={"disk9.m": LogNormal(30.0, 1.0)}),
     r"--scatter disk9\.m: not a parameter"),
    (lambda f: rotor_problem(f, {"disk0.m": (20.0, 40.0)}, "mass", scatter={"disk1.m": Normal(30.0, 10.0)}),
     r"--scatter disk1\.m=normal\(30, 10\): disk1\.m is a positive quantity"),
    (lambda f: rotor_problem(f, {"disk0.m": (20.0, 40.0)}, "mass", robust_k=1.0), r"--robust: give the parameters"),
    (lambda f: rotor_problem(f, {"disk0.m": (20.0, 40.0)}, "mass", scatter={"disk1.m": LogNormal(30.0, 1.0)},
                             robust_k=-1.0), r"--robust -1: the number of standard deviations must be >= 0"),
    (lambda f: rotor_problem(f, {"disk0.m": (20.0, 40.0)}, "mass", scatter={"disk1.m": LogNormal(30.0, 1.0)},
                             robust_samples=1), r"--robust-samples 1: at least 2"),
    (lambda f: parse_constraint("mass=3"), r"--constraint 'mass=3': give NAME>=VALUE"),
    (lambda f: parse_constraint("mass<=heavy"), r"'heavy' is not a number"),
    (lambda f: parse_constraint("weight<=3"), r"unknown quantity 'weight'"),
])
def test_bad_input_names_the_item(file, call, match):
    with pytest.raises(InputError, match=match):
        call(file)
