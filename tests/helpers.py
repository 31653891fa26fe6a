import jax
import numpy as np


def tree_allclose(a, b, rtol=1e-10, atol=1e-12) -> bool:
    la, lb = jax.tree_util.tree_leaves(a), jax.tree_util.tree_leaves(b)
    if len(la) != len(lb):
        return False
    return all(np.allclose(np.asarray(x), np.asarray(y), rtol=rtol, atol=atol) for x, y in zip(la, lb))


def central_difference(f, x, h):
    """Central finite difference of scalar `f` at scalar `x` (error O(h^2)), as a
    Python float (numpy, for array-valued `f`): never a JAX array, which
    `pytest.approx` (9.2) cannot take as its expected value."""
    d = np.asarray((f(x + h) - f(x - h)) / (2 * h), dtype=float)
    return float(d) if d.ndim == 0 else d


def set_csv_field(line_no, field, value):
    """An edit of a CSV text's lines: field `field` (0-based) of line `line_no`
    (1-based) set to `value` (for the bad-file tables)."""
    def edit(lines):
        parts = lines[line_no - 1].split(",")
        parts[field] = value
        lines[line_no - 1] = ",".join(parts)
        return lines
    return edit


#: the benchmark scripts whose `--smoke` runs tests/test_benchmark_smoke*.py check, in three groups of about
#: 5-6 minutes each on the CI machine (one interpreter per group, each group a file, so on its own worker; measured
#: locally 2026-11-28: 317, 299 and about 330 s): one interpreter for all of them passed the 1200 s after which
#: pytest ends a worker (pyproject.toml) once ROSS and AUTO-07p were installed
SMOKE_GROUPS = (
    ("auto07p", "auto_balancing_range", "balance_grid", "continuation", "design", "fe_identification", "flexible",
     "threshold_scan"),
    ("gpu_batch", "harmonic_balance", "identification", "identification_coverage", "journal_bearings", "limiters",
     "peers_001", "periodic_defaults", "periodic_jaxcont"),
    ("ross_parity", "rotor_scene", "solver_choice", "stability_map", "startup", "step_cost", "stiff_defaults",
     "sweep_throughput", "uncertainty"),
)


#: the scripts whose smoke runs split work over two host devices (their runner starts JAX with them)
SMOKE_HOST_DEVICES = ("rotor_scene", "stability_map", "sweep_throughput")


def run_benchmark_smokes(tmp, names):
    """`python tests/benchmark_smoke_runner.py` on the benchmark scripts `names` (their
    `--smoke` runs, one after another in a fresh interpreter, in the folder `tmp`; those of
    `SMOKE_HOST_DEVICES` in a second one, with two host devices): `(runs, tail, untouched)`,
    `runs` the runners' report `{name: {"ok", "seconds", "tail"}}`, `tail` the end of their
    output, `untouched` whether `benchmarks/results/` is as it was."""
    import json
    import os
    import subprocess
    import sys
    import time
    from pathlib import Path

    here = Path(__file__).resolve().parent
    results = here.parent / "benchmarks" / "results"
    env = dict(os.environ, MPLBACKEND="Agg")
    # $ROTORJAX_ROSS_PYTHON passes through: the ROSS paths run where .ci/run installed ROSS
    before = {p.name: p.stat().st_mtime for p in results.iterdir()}
    runs, tails = {}, []
    end = time.monotonic() + 1000   # within the 1200 s after which pytest's faulthandler ends the worker
    for devices, part in ((None, [n for n in names if n not in SMOKE_HOST_DEVICES]),
                          (2, [n for n in names if n in SMOKE_HOST_DEVICES])):
        if not part:
            continue
        report = Path(tmp) / f"smoke-{devices or 1}.json"
        argv = [] if devices is None else ["--host-devices", str(devices)]
        try:
            proc = subprocess.run([sys.executable, str(here / "benchmark_smoke_runner.py"), *argv, str(report), *part],
                                  cwd=tmp, env=env, capture_output=True, text=True,
                                  timeout=max(1.0, end - time.monotonic()))
            tails.append(f"{proc.stdout[-1500:]}{proc.stderr[-1500:]}")
        except subprocess.TimeoutExpired as e:
            tails.append(f"the smoke runs passed 1000 s: {str(e.stdout or '')[-1500:]}")
        runs.update(json.loads(report.read_text()) if report.exists() else {})
    after = {p.name: p.stat().st_mtime for p in results.iterdir()}
    return runs, "\n".join(tails), before == after


def check_benchmark_smoke(name, smoke_runs):
    """The assertions on one script's smoke run (`run_benchmark_smokes`' result)."""
    runs, tail, untouched = smoke_runs
    assert name in runs, f"the runner stopped before {name}: {tail}"
    assert runs[name]["ok"], runs[name]["tail"]
    assert untouched, "a smoke run wrote into benchmarks/results/"


#: the documentation's pages, in the site's order: the README (the home page) and docs/*.md (its other pages);
#: their commands and code blocks run in tests/test_readme.py, their stated numbers are checked where they are
DOCS_PAGES = ("README.md", "docs/architecture.md", "docs/rotor-files.md", "docs/everyday.md", "docs/flexible.md",
              "docs/stationary.md", "docs/continuation.md", "docs/periodic.md", "docs/fluid-films.md",
              "docs/limiters.md", "docs/balancing.md", "docs/identification.md", "docs/uncertainty.md",
              "docs/design.md", "docs/published-models.md", "docs/cli.md", "docs/speed.md", "docs/developing.md")


def documentation(page=None):
    """The text of the documentation (every page of `DOCS_PAGES`, joined), or of one `page`."""
    import os

    root = os.path.join(os.path.dirname(__file__), "..")
    texts = []
    for p in DOCS_PAGES if page is None else (page,):
        with open(os.path.join(root, p), encoding="utf-8") as f:
            texts.append(f.read())
    return "\n\n".join(texts)


def cubic_rig_variant(folder, name, edit):
    """The scene of the shipped `cubic_rig.toml` edited by `edit(text)`, written to
    `folder / name` and read as a user's rotor file."""
    import os

    import rotorjax
    from rotorjax import presets

    with open(os.path.join(os.path.dirname(rotorjax.__file__), "rotors", "cubic_rig.toml")) as f:
        text = edit(f.read())
    path = folder / name
    path.write_text(text)
    preset = presets.get(str(path))
    return preset.build(preset.params()).scene


def at_speed(scene, w):
    """`scene` at the constant speed `w`, set as a float64 array, as the scene's own speed
    is: a program compiled at one speed serves them all (a Python number set into a
    scene is a static leaf of `eqx.filter_jit`, compiled again at each value)."""
    import equinox as eqx
    import jax.numpy as jnp

    return eqx.tree_at(lambda s: s.speed.constant, scene, jnp.asarray(w, dtype=jnp.float64))


def settled_orbit(scene, w, y0, revolutions, phases):
    """A motion settled in time: the states at `phases` of the last of `revolutions`
    revolutions of `scene` at the constant speed `w` from `y0` (Dopri8 at rtol 1e-10),
    `(phases, states)`; nothing of harmonic balance (the validation files' reference)."""
    import rotorjax

    period = 2 * np.pi / w
    res = rotorjax.simulate(at_speed(scene, w), y0, (0.0, revolutions * period),
                            saveat=(revolutions - 1) * period + np.asarray(phases) / w, solver="dopri8", rtol=1e-10,
                            atol=1e-14, max_steps=4_000_000).raise_if_failed()
    return np.asarray(res.ys)


def speed_branch(scene, bounds, phases):
    """`periodic_branch` of `scene` in its speed over `bounds` from rest at the low
    end, with the defaults: `(scene_at, branch, coefficients, orbits)`, `orbits` each point's
    states at `phases` of its period, `(points, phases, states)`."""
    from functools import partial

    from rotorjax.analysis import periodic_branch

    scene_at = partial(at_speed, scene)
    br, coefficients = periodic_branch(scene_at, bounds[0], np.zeros(scene.state_size), bounds, name="speed")
    return scene_at, br, coefficients, orbits_of(coefficients, phases)


def orbits_of(coefficients, phases):
    """States `(..., phases, states)` of Fourier coefficients `(..., 2H + 1, states)`
    at `phases` of the period."""
    import jax.numpy as jnp

    from rotorjax.analysis._fourier import _basis_at

    H = (np.shape(coefficients)[-2] - 1) // 2
    return np.einsum("pk,...kd->...pd", np.asarray(_basis_at(jnp.asarray(phases), H)), np.asarray(coefficients))


#: where the validation files' stored reference runs live (`stored_reference`)
REFERENCE_DATA = "validation/data"


def stored_reference(name):
    """A reference run stored by `store_reference` (`tests/validation/data/NAME.json`):
    its values, lists as float64 arrays. A reference that takes minutes to compute
    (a long time simulation, independent of the code a test checks) is computed once
    by its test file's `reference()` (`python -m tests.validation.FILE` writes it again)
    and read here, so the suite does not pay for it at every run."""
    import json
    from pathlib import Path

    path = Path(__file__).resolve().parent / REFERENCE_DATA / f"{name}.json"
    data = json.loads(path.read_text())
    return {k: np.asarray(v, dtype=float) if isinstance(v, list) else v for k, v in data["values"].items()}


def store_reference(name, values, command):
    """Write `values` (numbers and arrays) as `tests/validation/data/NAME.json`, with
    how they were made: `command`, the commit, the date, the versions of jax and diffrax."""
    import datetime
    import json
    import subprocess
    from pathlib import Path

    import diffrax

    here = Path(__file__).resolve().parent
    commit = subprocess.run(["git", "rev-parse", "--short", "HEAD"], cwd=here, capture_output=True, text=True)
    made = {"command": command, "commit": commit.stdout.strip(), "date": datetime.date.today().isoformat(),
            "jax": jax.__version__, "diffrax": diffrax.__version__}
    values = {k: np.asarray(v).tolist() if np.ndim(v) else float(v) for k, v in values.items()}
    (here / REFERENCE_DATA / f"{name}.json").write_text(json.dumps({"made": made, "values": values}, indent=1) + "\n")
