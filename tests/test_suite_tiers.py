"""The quick tier (`python3 -m pytest -m "not slow"`, docs/developing.md) keeps a check against an
independent reference in every subsystem the issue that made it names, and lists only files that exist;
the suite's profile tool reads a junit file and the compile events as documented."""

import collections
import json
import os
import subprocess
import sys

from tests.conftest import QUICK_TIER

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(HERE)
SUBSYSTEMS = ("seed models", "finite elements against ROSS", "identification and balancing", "continuation",
              "periodic motions", "fluid films", "design and uncertainty", "CLI errors")


def test_every_subsystem_has_a_quick_file_with_its_reference():
    assert set(SUBSYSTEMS) <= set(QUICK_TIER)
    for subsystem, entries in QUICK_TIER.items():
        assert entries, subsystem
        for path, reference in entries:
            assert os.path.isfile(os.path.join(HERE, path)), path
            assert os.path.basename(path).startswith("test_") and reference.strip(), path


def test_the_markers_split_the_suite(tmp_path):
    """`-m "not slow"` collects exactly the quick tier's files, and `-m slow` the others."""
    def collected(mark):
        run = subprocess.run([sys.executable, "-m", "pytest", "--collect-only", "-q", "-p", "no:xdist",
                              "-o", "addopts=", "-m", mark, os.path.join(HERE, "test_suite_tiers.py"),
                              os.path.join(HERE, "test_layering.py")],
                             capture_output=True, text=True, cwd=ROOT, timeout=300)
        assert run.returncode in (0, 5), run.stdout[-2000:] + run.stderr[-2000:]
        return {line.split("::")[0] for line in run.stdout.splitlines() if "::" in line}

    quick = {f for entries in QUICK_TIER.values() for f, _ in entries}
    assert collected("not slow") == {f"tests/{f}" for f in ("test_suite_tiers.py", "test_layering.py")
                                     if f in quick}
    assert collected("slow") == {f"tests/{f}" for f in ("test_suite_tiers.py", "test_layering.py")
                                 if f not in quick}


def test_the_profile_joins_junit_and_compile_events(tmp_path):
    sys.path.insert(0, os.path.join(ROOT, "tools"))
    try:
        import suite_profile
    finally:
        sys.path.pop(0)
    (tmp_path / "junit.xml").write_text(
        '<testsuites><testsuite name="pytest">'
        '<testcase classname="tests.analysis.test_a" name="t1" time="2.5"/>'
        '<testcase classname="tests.analysis.test_a.TestX" name="t2" time="1.5"><failure message="x"/></testcase>'
        '<testcase classname="tests.test_b" name="t3" time="0.5"/>'
        '</testsuite></testsuites>')
    events = tmp_path / "events"
    events.mkdir()
    (events / "1.json").write_text(json.dumps({"analysis/test_a.py": {"trace": 0.5, "lower": 0.25, "compile": 1.0,
                                                                      "programs": 3}}))
    (events / "2.json").write_text(json.dumps({"analysis/test_a.py": {"compile": 1.0, "programs": 1},
                                               "benchmarks/x.py": {"compile": 7.0, "programs": 2}}))
    out = suite_profile.build(str(tmp_path / "junit.xml"), str(events), wall=10.0)
    rows = {r["file"]: r for r in out["files"]}
    a = rows["analysis/test_a.py"]
    assert (a["tests"], a["failed"], a["wall_s"], a["programs"], a["compile"]) == (2, 1, 4.0, 4, 2.0)
    assert a["execute_other_s"] == 4.0 - 0.5 - 0.25 - 2.0
    assert rows["test_b.py"]["wall_s"] == 0.5 and rows["test_b.py"]["programs"] == 0
    assert out["benchmark_scripts"] == [{"script": "benchmarks/x.py", "compile": 7.0, "programs": 2}]
    assert out["total_worker_s"]["wall_s"] == 4.5 and out["total_worker_s"]["tests"] == 3
    # the programs by name and caller, summed over the processes, the most compile time first
    (events / "programs-1.json").write_text(json.dumps({"jit(march) <- a.py:f": [2, 3.0], "jit(add) <- ?": [9, 0.5]}))
    (events / "programs-2.json").write_text(json.dumps({"jit(march) <- a.py:f": [1, 2.0]}))
    out = suite_profile.build(str(tmp_path / "junit.xml"), str(events), wall=10.0)
    assert out["programs_by_name"]["top"] == [{"name": "jit(march) <- a.py:f", "programs": 3, "compile": 5.0},
                                              {"name": "jit(add) <- ?", "programs": 9, "compile": 0.5}]
    assert out["programs_by_name"]["all"] == {"names": 2, "programs": 12, "compile": 5.5}


def test_the_profile_names_each_program_and_its_caller(monkeypatch):
    """The listener charges a compile to the program's name and the innermost rotorjax function that asked
    for it (a lifted program is named after its function)."""
    import jax
    import jax.numpy as jnp

    from rotorjax.solve._lift import call, lift
    from tests import suite_profile

    monkeypatch.setattr(suite_profile, "_programs", collections.defaultdict(lambda: [0, 0.0]))
    monkeypatch.setattr(suite_profile, "_totals", collections.defaultdict(lambda: collections.defaultdict(float)))
    jax.monitoring.register_event_duration_secs_listener(suite_profile._listen)
    try:
        f = lift(lambda x: jnp.sin(x) * 1.2345, jnp.ones(3))
        call(f, jnp.ones(3) * 0.5)
    finally:
        jax.monitoring.unregister_event_duration_listener(suite_profile._listen)
    assert "jit(call) <- rotorjax/solve/_lift.py:run < tests/test_suite_tiers.py:" \
        "test_the_profile_names_each_program_and_its_caller" in suite_profile._programs


def test_the_developing_page_states_what_the_suite_sets():
    from tests.conftest import MAPS_SHARE, RSS_LIMIT
    from tests.helpers import documentation

    page = " ".join(documentation("docs/developing.md").split())
    assert f"{MAPS_SHARE:.0%}".replace("%", " %") in page and f"{RSS_LIMIT / 2**30:.0f} GiB" in page
    for subsystem, entries in QUICK_TIER.items():   # the page's table is the conftest's
        assert subsystem in page, subsystem
        for path, reference in entries:
            assert f"tests/{path}" in page and " ".join(reference.split()) in page, path


def test_the_developing_page_states_the_committed_profile():
    """The run the page quotes is the committed `benchmarks/results/suite_profile.json`:
    its tests, pytest's wall time, the workers' time and what of it was compiling."""
    from tests.helpers import documentation

    root = os.path.join(os.path.dirname(__file__), "..")
    with open(os.path.join(root, "benchmarks", "results", "suite_profile.json")) as f:
        profile = json.load(f)
    total = profile["total_worker_s"]
    page = " ".join(documentation("docs/developing.md").split())

    def n(x):   # the page's thousands separator
        return f"{x:,.0f}".replace(",", " ")

    wall = profile["run_wall_s"]
    stated = (f"{n(total['tests'])} tests in {wall / 60:.1f} minutes of pytest ({n(wall)} s; "
              f"`.ci/run` {n(profile['ci_run_s'])} s in all), {n(total['wall_s'])} s of the two workers' time, "
              f"{n(total['compile'])} s of it XLA compiling {n(total['programs'])} programs, {n(total['trace'])} s "
              f"tracing and {n(total['lower'])} s lowering")
    assert stated in page, stated
    top = {r["name"]: r for r in profile["programs_by_name"]["top"]}
    march = top["jit(march) <- rotorjax/solve/_lift.py:run"]
    assert (f"`jit(march) <- rotorjax/solve/_lift.py:run` ({march['programs']} programs, "
            f"{march['compile']:.0f} s") in page
    for name, words in (("jit(Partial) <- rotorjax/sweep.py:sweep", "the vmapped scans of `rotorjax.sweep`"),
                        ("jit(_buffered_impl) <- rotorjax/solve/_batch.py:simulate_batch", "the batch integrator"),
                        ("jit(_solve) <- rotorjax/solve/_simulate.py:simulate", "`simulate`")):
        assert f"{words} ({top[name]['programs']} programs, {top[name]['compile']:.0f} s)" in page, name
