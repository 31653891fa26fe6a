"""Issue 62, item 3: a branch point met on a rotor, refined and switched onto, by
`continue_branch` / `switch_branch` and `rotorjax continue --switch` with their
defaults. Model 000 (two balls in a circular race, `rho1 = rho2`), its balanced
regime continued in the unbalance `eps`: the balls part to cancel the unbalance
until, at the balancing capacity, they meet. There the balanced branch turns back
(its other half is the same regime with the balls exchanged) and the regime of the
balls together crosses it: a pitchfork of the ball-exchange symmetry, which a
continuation sees as a turn of its tangent in `eps` and the bordered determinant's
sign change, not as a fold.

Independent references: the closed form of the capacity, `eps* = n_balls chi rho`
(the balls' static moment, in the model's length unit), which the refined branch
point equals to round-off; the symmetry, which holds the balls together (`psi1 =
psi2`) at every point of the switched branch; and the exchange of stability the
theory of the auto-balancer gives (Blekhman; Ryzhik, Sperling and Duckstein): the
balls together opposite the unbalance, unstable below the capacity, are the stable
regime above it."""

import json

import numpy as np
import pytest

from rotorjax import presets
from rotorjax.analysis import continue_branch, switch_branch
from rotorjax.cli import main
from rotorjax.cli._common import stability_study

SET = {"rho2": 1.28, "eps": 0.02}            # a circular race (rho1 = 1.28), below the capacity
RANGE = (0.005, 0.1)
#: `rotorjax continue` with --switch, as docs/continuation.md shows it (run here: test_readme defers to this file)
DOCS_COMMAND = "rotorjax continue elliptic-abb --param eps --set rho2=1.28 --set eps=0.02 --to 0.005 0.1 --switch"


@pytest.fixture(scope="module")
def problem():
    preset = presets.get("elliptic-abb")
    params = dict(preset.params(), **SET)
    F, u0 = stability_study(preset, params).branch_problem(params, "eps")
    capacity = params["n_balls"] * params["chi"] * params["rho1"]
    return F, u0, capacity


@pytest.fixture(scope="module")
def branches(problem):
    F, u0, _ = problem
    br = continue_branch(F, u0, SET["eps"], p_bounds=RANGE, name="eps")
    point, = [e for e in br.events if e.kind == "branch_point"]
    return br, point, switch_branch(F, point, p_bounds=RANGE, name="eps")


def test_the_balls_meet_at_a_branch_point_at_the_balancing_capacity(problem, branches):
    """The branch point, refined on Moore and Keller's system, is the closed form's
    capacity to 1e-16 (measured: 1.4e-17), reported once and not as a fold; the
    balls coincide there; the crossing branch's tangent keeps them together."""
    _, _, capacity = problem
    br, point, _ = branches
    assert [e.kind for e in br.events] == ["branch_point"]
    assert abs(point.p - capacity) < 1e-16 and point.residual < 1e-12 and point.note is None
    assert abs(point.u[2] - point.u[3]) < 1e-8
    assert abs(point.tangent[2] - point.tangent[3]) < 1e-10 and abs(point.tangent[2]) > 0.1
    # the balanced branch turns back there: both its ends on the lower edge
    assert br.stops == ("box edge (eps = 0.005)", "box edge (eps = 0.005)")
    assert np.all(br.p <= capacity + 1e-12)


def test_the_switched_branch_holds_the_balls_together_and_takes_over_stability(problem, branches):
    """Every point of the switched branch has `psi1 = psi2` (to 1e-13; measured 2e-14;
    to 1e-8 at a point within 1e-8 of the branch point, where the two branches are that
    close: measured 3.9e-9 at 3.9e-9 from it)
    and it reaches the range's upper end; it passes through the same branch point;
    on its sheet through that point the balls' regime is unstable below the capacity
    and stable above it, as the balanced regime is stable below it."""
    _, _, capacity = problem
    br, point, sw = branches
    apart = np.abs(sw.u[:, 2] - sw.u[:, 3])
    at_the_point = np.abs(sw.p - point.p) < 1e-8
    assert apart[~at_the_point].max() < 1e-13 and apart.max() < 1e-8
    assert RANGE[1] in (sw.p[0], sw.p[-1])
    again = [e for e in sw.events if e.kind == "branch_point"]
    assert len(again) == 1 and abs(again[0].p - capacity) < 1e-12
    near = np.abs(sw.u[:, 2] - point.u[2]) < 0.5            # the sheet through the branch point
    below = near & (sw.p < capacity - 0.005)
    above = near & (sw.p > capacity + 0.005)
    assert below.any() and above.any()
    assert np.all(sw.margin[below] > 0) and np.all(sw.margin[above] < 0)
    assert np.all(br.stable[br.p < capacity - 0.005])


def test_continue_switch_reports_the_crossing_branch(tmp_path, capsys, branches):
    """`rotorjax continue ... --switch` (the docs' command, its JSON): the branch
    point, and the switched branch from it with the API's events and ends."""
    _, point, sw = branches
    argv = DOCS_COMMAND.split()[1:] + ["--out", str(tmp_path), "--json"]
    assert main(argv) == 0
    out = json.loads(capsys.readouterr().out)
    assert [e["kind"] for e in out["events"]] == ["branch_point"]
    (switched,) = out["switched"]
    assert switched["at"] == pytest.approx(point.p, abs=1e-14)
    # its own steps (the CLI's --ds), the same refined events: the switched branch's fold and branch point
    assert [e["kind"] for e in switched["events"]] == [e.kind for e in sw.events]
    np.testing.assert_allclose([e["p"] for e in switched["events"]], [e.p for e in sw.events], atol=1e-10)
    assert switched["stops"] == list(sw.stops)
    header = open(out["files"]["data"]).readline().strip()
    assert header == "eps,margin,residual,branch"


def test_the_docs_state_these_checks(problem):
    from tests.helpers import documentation

    text = " ".join(documentation("docs/continuation.md").split())
    assert DOCS_COMMAND in text
    assert "the capacity `eps* = n_balls chi rho` (0.0512) to 1e-16" in text
    assert ("the balls together (`psi1 = psi2` to 1e-13 at every point, to 1e-8 at a point that lands within 1e-8 of "
            "the branch point, where the two branches are that close)" in text)


def test_switch_warns_at_an_unrefined_branch_point_and_fails_where_no_branch_starts():
    """`--switch` at a branch point located to the step only: a warning, no branch;
    at one whose crossing branch has no first point (its equations undefined
    there): exit 3 (`NumericalError`) naming the point and what to change."""
    import argparse
    import warnings

    import jax.numpy as jnp

    from rotorjax._errors import NumericalError, PlausibilityWarning
    from rotorjax.analysis import BranchEvent
    from rotorjax.analysis._continuation import Branch
    from rotorjax.cli._continue import _switched

    def F(u, p):                 # u = sqrt(p): undefined below p = 0
        return jnp.sqrt(p) - u

    args = argparse.Namespace(ds=0.02, ds_max=0.2, max_points=20, json=True)
    unrefined = BranchEvent(kind="branch_point", p=0.0, u=np.zeros(1), residual=1e-3, between=(0, 1),
                            note="located to the step; not refined (Newton on ...: it left the step)")
    br = Branch(u=np.zeros((2, 1)), p=np.zeros(2), margin=np.zeros(2), stable=np.ones(2, bool), events=(unrefined,),
                curve=None)
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        assert _switched(F, br, (-1.0, 1.0), args, "q") == []
    assert any(issubclass(w.category, PlausibilityWarning) and "was not switched at" in str(w.message)
               for w in caught)
    down = BranchEvent(kind="branch_point", p=0.0, u=np.zeros(1), residual=0.0, between=(0, 1),
                       tangent=np.array([0.0, -1.0]))
    br = Branch(u=np.zeros((2, 1)), p=np.zeros(2), margin=np.zeros(2), stable=np.ones(2, bool), events=(down,),
                curve=None)
    with pytest.raises(NumericalError, match=r"--switch: the branch crossing at q = 0 did not start: .*--ds"):
        _switched(F, br, (-1.0, 1.0), args, "q")
