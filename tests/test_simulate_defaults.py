"""Every preset and shipped rotor file simulates with the CLI's default settings
(issue 32, item 6), and the automatic choice behind it is checked against what it
estimates.

Each run is 0.5% of the default run (1 of 200 revolutions) with the step budget
scaled alike (2 500 of 500 000 steps): the plan's decisions (the modes kept, the solver) are
those of the default run, whose estimate scales with the span. A rotor file at speed 0
runs at 50 rad/s (`--speed 50`, as a user must give it). The full FE rotors ring at
their top modes from rest and are reduced; the journal rig's films decay too fast for
Dopri8's budget and take Kvaerno5."""

import json
import os

import diffrax
import jax.numpy as jnp
import numpy as np
import pytest

import rotorjax
from rotorjax import presets
from rotorjax.analysis import plan_run
from rotorjax.analysis._plan import BUDGET_FRACTION, EXCITATION_MARGIN
from rotorjax.cli import main
from rotorjax.solve import dopri8_stability_radius, estimate_stiffness, jacobian_at, simulate

ROTORS = os.path.join(os.path.dirname(rotorjax.__file__), "rotors")
SCALE, SAVES = 0.005, 200
MAX_STEPS = int(SCALE * 500_000)
#: (preset or rotor file, --speed where the default is 0, the modes "auto" keeps, the solver "auto" takes)
CASES = [("elliptic-abb", None, None, "Dopri8"), ("anisotropic-abb", None, None, "Dopri8"),
         ("cantilever-limiters", None, None, "Dopri8"),
         ("cubic_rig.toml", None, None, "Dopri8"), ("flexible_rig.toml", None, None, "Dopri8"),
         ("journal_rig.toml", None, None, "Kvaerno5"), ("rig_nonlinear.toml", None, None, "Dopri8"),
         ("ross_compare.toml", 50.0, "reduced", "Dopri8"), ("tapered_two_material.toml", 50.0, "reduced", "Dopri8")]


def _preset(name):
    return os.path.join(ROTORS, name) if name.endswith(".toml") else name


@pytest.fixture(scope="module")
def runs(tmp_path_factory):
    """Each case's CLI run (exit code, JSON, saved outputs)."""
    out = {}
    for name, speed, _, _ in CASES:
        preset = presets.get(_preset(name))
        params = preset.params({} if speed is None else {preset.speed_key: speed})
        t_end = SCALE * preset.build(params).t_end
        tmp = tmp_path_factory.mktemp(name.replace(".", "_"))
        argv = ["simulate", _preset(name), "--t-end", repr(t_end), "--max-steps", str(MAX_STEPS),
                "--n-save", str(SAVES), "--out", str(tmp), "--json"]
        if speed is not None:
            argv += ["--speed", repr(speed)]
        rc = main(argv)
        stem = os.path.splitext(os.path.basename(name))[0] if name.endswith(".toml") else name
        summary = json.loads((tmp / f"{stem}.json").read_text())
        out[name] = (rc, summary, dict(np.load(tmp / f"{stem}.npz")), t_end)
    return out


def test_the_list_holds_every_simulated_preset_and_shipped_rotor_file():
    files = {f for f in os.listdir(ROTORS) if f.endswith(".toml")}
    simulated = {n for n, p in presets.PRESETS.items() if p.kind in ("planar", "contact")}   # the others refuse
    assert {c[0] for c in CASES} == files | simulated


@pytest.mark.parametrize("name,speed,modes,solver", CASES, ids=[c[0] for c in CASES])
def test_defaults_simulate(name, speed, modes, solver, runs):
    rc, summary, _, _ = runs[name]
    assert rc == 0 and summary["success"], summary["message"]
    plan = summary["integration"]
    assert summary["solver"] == solver == plan["auto_solver"]
    assert summary["stats"]["num_steps"] <= MAX_STEPS
    if modes is None:
        assert plan["modes"] is None
    else:   # reduced: the kept modes fit half the budget, the full model would not fit it
        assert plan["modes"] < plan["coordinates"]
        assert plan["estimated_explicit_steps_full"] > MAX_STEPS
        assert plan["estimated_explicit_steps"] <= BUDGET_FRACTION * MAX_STEPS
        assert plan["cutoff_frequency"] >= EXCITATION_MARGIN * speed
        assert summary["stats"]["num_steps"] <= plan["estimated_explicit_steps"]   # it errs towards more steps


@pytest.fixture(scope="module")
def ross(runs):
    """ross_compare.toml at 50 rad/s: the scene, its start, the span."""
    setup = presets.get(_preset("ross_compare.toml")).build(
        presets.get(_preset("ross_compare.toml")).params({"speed": 50.0}))
    return setup.scene, setup.y0, runs["ross_compare.toml"][3]


def test_reduced_run_is_close_to_the_full_model(ross, runs):
    """The chosen path's error: the reduced run's node displacements against the full
    model's (Dopri8 at rtol 1e-10, the budget it needs): within 1e-3 of their largest
    value (measured 2e-5; benchmarks/stiff_defaults.py has the 200-revolution figures)."""
    scene, y0, t_end = ross
    full = simulate(scene, y0, (0.0, t_end), saveat=SAVES, rtol=1e-10, atol=1e-12, max_steps=50 * MAX_STEPS,
                    solver="dopri8")
    assert full.success
    ref = np.concatenate([np.asarray(full.outputs["node_x"]), np.asarray(full.outputs["node_y"])], axis=-1)
    _, _, saved, _ = runs["ross_compare.toml"]
    got = np.concatenate([saved["node_x"], saved["node_y"]], axis=-1)
    err = np.max(np.abs(got - ref)) / np.max(np.abs(ref))
    assert err < 1e-3
    # the full model's steps against the estimate (it errs towards more steps, by at most 2.5x)
    est = estimate_stiffness(scene, y0, 0.0, t_end, 1e-8).explicit_steps
    taken = simulate(scene, y0, (0.0, t_end), saveat=SAVES, rtol=1e-8, atol=1e-10, max_steps=50 * MAX_STEPS,
                     solver="dopri8").stats["num_steps"]
    assert taken <= est <= 2.5 * taken


def test_reduction_maps_project_the_linearisation(ross):
    """`P E = I`, and the projected Jacobian `P J E` has the reduced scene's own
    eigenvalues (exact here: the unbalance does not depend on the state)."""
    scene, y0, _ = ross
    E, P = (np.asarray(a) for a in scene.reduction_maps(6))
    assert np.allclose(P @ E, np.eye(E.shape[1]), atol=1e-10)
    reduced = scene.reduce(6)
    lam_red = np.linalg.eigvals(jacobian_at(reduced, P @ y0))
    lam_proj = np.linalg.eigvals(P @ jacobian_at(scene, y0) @ E)
    scale = np.max(np.abs(lam_red))
    assert np.allclose(np.sort(lam_red.imag), np.sort(lam_proj.imag), rtol=1e-9, atol=1e-9 * scale)
    assert np.max(np.abs(lam_red.real)) < 1e-9 * scale and np.max(np.abs(lam_proj.real)) < 1e-9 * scale  # undamped
    plan = plan_run(scene, y0, 1.0, 1e-8, 1000, modes=6)
    assert plan.modes == 6 and plan.scene.state_size == 12 and np.allclose(plan.y0, P @ y0)
    assert plan.cutoff_frequency == pytest.approx(scene.reduction_basis()[0][5])


@pytest.mark.parametrize("angle", [np.pi, 0.8 * np.pi, 0.6 * np.pi])
def test_dopri8_stability_radius_against_diffrax_steps(angle):
    """Independent of the polynomial: diffrax's own Dopri8 at a fixed step on
    `y' = lambda y` (the real 2x2 form) decays at 0.97 of the radius along the ray
    and grows at 1.03 of it."""
    r = float(dopri8_stability_radius(angle))
    a, b = np.cos(angle), np.sin(angle)
    term = diffrax.ODETerm(lambda t, y, args: jnp.array([[a, -b], [b, a]]) @ y)

    def growth(h):
        sol = diffrax.diffeqsolve(term, diffrax.Dopri8(), 0.0, 400 * h, h, jnp.array([1.0, 0.0]),
                                  stepsize_controller=diffrax.ConstantStepSize(), max_steps=401)
        return float(jnp.linalg.norm(sol.ys[-1]))

    assert 4.5 < r < 6.5
    assert growth(0.97 * r) < 1.0 < growth(1.03 * r)
