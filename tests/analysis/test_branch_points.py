"""Branch points: refined on Moore and Keller's extended system and switched onto
(`continue_branch`'s `"branch_point"` events, `switch_branch`; issue 62), on
systems whose crossing branches are known in closed form:

- a tilted pitchfork (the crossing at an angle that is not a right one, so the
  bifurcation equation, not the orthogonal direction, picks the other branch);
- a discretized buckled strut, `K u - p u + u^3 = 0` (`K` the second-difference
  matrix of 12 nodes): branch points at `K`'s eigenvalues `4 sin^2(k pi / 26)`,
  the crossing branches along its sine modes (Euler's buckling loads);
- a bead on a hoop spinning at `p` (the governor's pitchfork): the bead leaves the
  bottom at `p^2 = g / R` for `cos th = g / (R p^2)`, and stability passes from
  one branch to the other there."""

import jax.numpy as jnp
import numpy as np
import pytest

from rotorjax.analysis import BranchEvent, continue_branch, switch_branch

P0, TILT = 0.7, 0.3
N = 12
K = 2 * np.eye(N) - np.eye(N, k=1) - np.eye(N, k=-1)
G_OVER_R, DAMPING = 4.0, 0.3


def pitchfork(u, p):
    """The branch `u0 = TILT (p - P0)` and, crossing it at `p = P0`, `(u0 - TILT (p - P0))^2 = p - P0`;
    `u1 = u0^2` on both."""
    w = u[0] - TILT * (p - P0)
    return jnp.stack([w * (p - P0) - w ** 3, u[1] - u[0] ** 2])


def strut(u, p):
    return jnp.asarray(K) @ u - p * u + u ** 3


def hoop(u, p):
    """The bead's angle from the bottom and its rate: `th'' = sin th (p^2 cos th - g/R) - c th'`."""
    th, om = u[0], u[1]
    return jnp.stack([om, jnp.sin(th) * (p ** 2 * jnp.cos(th) - G_OVER_R) - DAMPING * om])


@pytest.fixture(scope="module")
def tilted():
    u0 = np.array([TILT * (0.2 - P0), (TILT * (0.2 - P0)) ** 2])
    return continue_branch(pitchfork, u0, 0.2, p_bounds=(0.2, 1.5))


def test_a_tilted_pitchfork_is_refined_to_its_closed_form_and_switched(tilted):
    """Refined exactly (the closed form's branch point and the other branch's tangent
    `(1, 0, 0)`, though it crosses the branch at 73 degrees: the bifurcation
    equation's root, not the direction orthogonal to the branch); the switched branch
    is the closed form's at every point, both of its halves (through the branch
    point), to the box's edge."""
    (e,) = [e for e in tilted.events if e.kind == "branch_point"]
    assert abs(e.p - P0) < 1e-10 and np.max(np.abs(e.u)) < 1e-10 and e.residual < 1e-12 and e.note is None
    np.testing.assert_allclose(e.tangent, [1.0, 0.0, 0.0], atol=1e-10)
    assert e.as_dict()["tangent"] == pytest.approx(list(e.tangent))
    assert tilted.stops == ("box edge (p = 0.2)", "box edge (p = 1.5)")

    other = switch_branch(pitchfork, e, p_bounds=(0.2, 1.5))
    w = other.u[:, 0] - TILT * (other.p - P0)
    assert np.max(np.abs(w ** 2 - (other.p - P0))) < 1e-12
    assert np.max(np.abs(other.u[:, 1] - other.u[:, 0] ** 2)) < 1e-12
    assert other.stops == ("box edge (p = 1.5)", "box edge (p = 1.5)")
    np.testing.assert_allclose([w.min(), w.max()], [-np.sqrt(1.5 - P0), np.sqrt(1.5 - P0)], atol=1e-12)


def test_the_buckled_strut_branch_points_are_eulers_loads_and_its_modes():
    """Along `u = 0` the branch points are `K`'s two lowest eigenvalues to 1e-10, each
    crossing branch's tangent is its sine mode (to 1e-8); the first buckled branch
    solves the strut's equations at every point and near the load rises as
    `p - p1 = a^2 sum(mode^4)` (`a` the mode's amplitude; to 1e-3 at its first point,
    `a^2 < 1e-3`)."""
    br = continue_branch(strut, np.zeros(N), 0.0, p_bounds=(0.0, 0.4), ds=0.03, ds_max=0.05)
    bps = [e for e in br.events if e.kind == "branch_point"]
    assert len(bps) == 2
    i = np.arange(1, N + 1)
    for k, e in enumerate(bps, start=1):
        assert abs(e.p - 4 * np.sin(k * np.pi / (2 * (N + 1))) ** 2) < 1e-10 and e.residual < 1e-12
        mode = np.sin(k * i * np.pi / (N + 1))
        mode /= np.linalg.norm(mode)
        assert abs(e.tangent[N]) < 1e-8
        assert abs(abs(e.tangent[:N] @ mode) - 1) < 1e-8

    other = switch_branch(strut, bps[0], p_bounds=(0.0, 0.4), ds=0.01, max_points=80)
    assert max(float(np.max(np.abs(strut(jnp.asarray(u), p)))) for u, p in zip(other.u, other.p)) < 1e-9
    # near the load, u = a mode and p - p1 = a^2 sum(mode^4) (the cubic term projected on the mode)
    mode = np.sin(i * np.pi / (N + 1))
    mode /= np.linalg.norm(mode)
    first = other.curve.start
    a2 = np.sum(other.u[first] ** 2)
    assert a2 < 1e-3 and abs((other.p[first] - bps[0].p) / a2 / np.sum(mode ** 4) - 1) < 1e-3


def test_the_spinning_hoop_bead_exchanges_stability_at_its_branch_point():
    """The bottom is stable below `p = sqrt(g / R)` and unstable above; the bead's
    branch from that branch point is `cos th = g / (R p^2)` at every point (to 1e-12)
    and stable."""
    br = continue_branch(hoop, np.zeros(2), 1.0, p_bounds=(1.0, 4.0))
    (e,) = [e for e in br.events if e.kind == "branch_point"]
    assert abs(e.p - np.sqrt(G_OVER_R)) < 1e-10
    assert np.all(br.stable[br.p < e.p - 1e-6]) and not np.any(br.stable[br.p > e.p + 1e-6])
    other = switch_branch(hoop, e, p_bounds=(1.0, 4.0))
    assert np.max(np.abs(np.cos(other.u[:, 0]) - G_OVER_R / other.p ** 2)) < 1e-12
    assert np.all(other.stable[other.p > e.p + 1e-6])


def test_switching_needs_a_refined_branch_point():
    fold = BranchEvent(kind="fold", p=1.0, u=np.zeros(2), residual=1e-14, between=(3, 4))
    with pytest.raises(ValueError, match="a refined branch point .* got a 'fold' event"):
        switch_branch(pitchfork, fold)
    located = BranchEvent(kind="branch_point", p=1.0, u=np.zeros(2), residual=1e-9, between=(3, 4),
                          note="located to the step; not refined (Newton on the branch point's extended system: "
                               "it left the step)")
    with pytest.raises(ValueError, match="it left the step"):
        switch_branch(pitchfork, located)


def test_a_branch_point_whose_refinement_fails_is_located_to_the_step():
    """As a fold's (`_refined_event`): the midpoint, the points' residual, the reason."""
    from rotorjax.analysis._continuation import _refined_event

    a, b = np.array([0.4, 1.0]), np.array([0.6, 1.1])
    e = _refined_event(np.array([0.5, 9.0]), 1e-14, a, b, 1, (3, 4), 1e-8, 2e-10, kind="branch_point",
                    system="the branch point's extended system")
    assert (e.kind, e.p, e.residual, e.tangent) == ("branch_point", 1.05, 2e-10, None)
    assert e.note == "located to the step; not refined (Newton on the branch point's extended system: it left the step)"


def test_the_docs_state_these_checks():
    from tests.helpers import documentation

    text = " ".join(documentation("docs/continuation.md").split())
    angle = np.degrees(np.arccos(TILT / np.hypot(1.0, TILT)))
    assert f"a tilted pitchfork crossing its branch at {angle:.0f} degrees" in text
    for claim in ("the branch point and the other branch's tangent to 1e-10, the switched branch to 1e-12",
                  f"a {N}-node strut `K u - p u + u^3 = 0`, branch points at Euler's loads "
                  f"`4 sin^2(k pi / {2 * (N + 1)})` to 1e-10, the tangents along the sine modes to 1e-8",
                  "`cos th = g / (R p^2)` (to 1e-12)"):
        assert claim in text


HOPF_AT = -0.01


def pitchfork_beside_a_hopf(u, p):
    """The rest state of `x' = p x - x^3` (a pitchfork at p = 0) beside the oscillator
    `y' = [[p - HOPF_AT, -1], [1, p - HOPF_AT]] y` (a Hopf point at p = HOPF_AT,
    frequency 1)."""
    a = p - HOPF_AT
    return jnp.stack([p * u[0] - u[0] ** 3, a * u[1] - u[2], u[1] + a * u[2]])


def test_two_events_in_one_step_are_each_found_and_refined():
    """A step of 0.3 from p = -0.25 passes the Hopf point (-0.01) and the branch point
    (0) at once; at its far end the least unstable exponent is the real one. Without
    the step cut into parts, the branch point alone was reported: three exponents crossed
    and the branch point explains one. Cut, each event is found in its own part and
    refined to its closed form."""
    br = continue_branch(pitchfork_beside_a_hopf, np.zeros(3), -0.55, p_bounds=(-0.55, 0.55), ds=0.3, ds_max=0.3,
                         direction=1)
    step = [i for i in range(br.p.size - 1) if br.p[i] < HOPF_AT and br.p[i + 1] > 0.0]
    assert step, br.p       # both in one step
    (hopf,) = [e for e in br.events if e.kind == "hopf"]
    (bp,) = [e for e in br.events if e.kind == "branch_point"]
    assert abs(hopf.p - HOPF_AT) < 1e-10 and abs(hopf.frequency - 1.0) < 1e-10 and hopf.crossing == 2
    assert abs(bp.p) < 1e-10 and bp.note is None and np.max(np.abs(bp.u)) < 1e-10
    assert hopf.between == bp.between == (step[0], step[0] + 1)
    from tests.helpers import documentation

    text = " ".join(documentation("docs/continuation.md").split())
    assert (f"an oscillator with a Hopf point at `p = {HOPF_AT:g}`: one step of 0.3 passes both" in text
            and f"the Hopf point at {HOPF_AT:g} and the branch point at 0 to 1e-10" in text)
