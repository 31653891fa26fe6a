"""Issue 62, validation: a rotor on a squeeze-film damper, by `periodic_branch` with
its defaults, on a rotor it was not built on: the shipped `cubic_rig.toml` with
bearing 3 softer in y (kyy = 0.6 kxx) and, in place of its cubic bearings and of
bearing 0, a squeeze-film damper at node 0 (pi film, D = 100 mm, L = 20 mm, c = 0.2
mm, 0.02 Pa s) on a centring spring of bearing 0's stiffness. Through 96..101 rad/s
the damper's journal orbits at eccentricities 0.79 to 0.84 on ellipses: the film
force is sharply peaked and cavitated, so the motion holds many harmonics.

- The start, from rest at 96 rad/s: Newton's full first step would put the journal
  through the damper's wall (the film force is not defined there); the step is
  halved until it stays inside (`_finite_step`), and the start converges.
- Independent reference: the motions settled in time (Dopri8 at rtol 1e-10, 300
  revolutions from rest, nothing of harmonic balance; stored in
  `tests/validation/data/`, made by `reference()`). With 32 harmonics (the
  default's most) they differ from the branch's orbits at node 0 by 1.6e-4 and
  1.5e-3 of the amplitude, and the branch's truncation error estimate there is the
  same size (1.9e-4 and 1.5e-3): the estimate is within a factor of 3 of the
  error both ways, so `periodic`'s exit 3 at the default target ("harmonics
  insufficient", the estimate 1.7e-3 > 1e-6) reports a real error, and a point
  within a target is within it."""

import re
import tempfile
from pathlib import Path

import numpy as np
import pytest

from rotorjax.analysis import harmonic_balance
from tests.helpers import cubic_rig_variant, orbits_of, settled_orbit, speed_branch, store_reference, stored_reference

pytestmark = pytest.mark.slow

RANGE = (96.0, 101.0)     # rad/s
CLEARANCE = 2e-4
PHASES = np.linspace(0.0, 2 * np.pi, 256, endpoint=False)
SETTLED = (96.5, 100.0)   # rad/s: the motions settled in time
REFERENCE = "periodic_sfd_settled"    # tests/validation/data/, made by `reference()`
SFD = ('[[bearing]]\nnode = 0\ntype = "sfd"\nfilm = "pi"\nviscosity = 0.02\nlength = 0.02\ndiameter = 0.1\n'
       f'clearance = {CLEARANCE}\nkxx = 1e6')


def damped(text):
    """cubic_rig.toml with bearing 3 at kyy = 0.6e6, bearing 0 a squeeze-film damper
    on a 1e6 N/m centring spring, no cubic bearings."""
    text, n = re.subn(r"(?m)^(node = 3\nkxx = 1e6)$", r"\1\nkyy = 0.6e6", text)
    text, m = re.subn(r"(?m)^\[\[bearing\]\]\nnode = 0\nkxx = 1e6.*$", SFD, text)
    assert n == m == 1
    return text[:text.index("[[cubic_bearing]]")]


@pytest.fixture(scope="module")
def rig(tmp_path_factory):
    scene = cubic_rig_variant(tmp_path_factory.mktemp("rotor"), "sfd.toml", damped)
    scene_at, br, coefficients, orbits = speed_branch(scene, RANGE, PHASES)
    return scene_at, br, coefficients, np.hypot(orbits[..., 0], orbits[..., 1]).max(axis=1)


def test_the_branch_starts_from_rest_and_reaches_the_range_s_end(rig):
    """From rest at 96 rad/s (the step halved while the journal would leave the
    damper), to 101; the journal at eccentricities 0.75 to 0.9; 32 harmonics."""
    _, br, _, radius = rig
    assert br.stops == (f"box edge (speed = {RANGE[0]})", f"box edge (speed = {RANGE[1]})")
    assert 0.75 < radius.min() / CLEARANCE and radius.max() / CLEARANCE < 0.9
    assert np.all(br.harmonics == 32)


def reference():
    """The motions settled in time (independent of harmonic balance) at `SETTLED`:
    300 revolutions from rest, Dopri8 at rtol 1e-10; node 0's x and y over the last
    one at `PHASES`. Stored (`python -m tests.validation.test_periodic_sfd`): the
    runs take most of a minute."""
    scene = cubic_rig_variant(Path(tempfile.mkdtemp()), "sfd.toml", damped)
    orbits = [settled_orbit(scene, w, np.zeros(scene.state_size), 300, PHASES)[:, :2] for w in SETTLED]
    return dict(speeds=np.asarray(SETTLED), orbits=np.asarray(orbits))


def test_settled_motions_differ_by_what_the_truncation_estimate_says(rig):
    """At 96.5 and 100 rad/s: the settled motion (`reference`) against the branch's
    orbit at node 0 (its nearest point solved again at that speed), relative to its
    amplitude, within a factor of 3 of the branch's truncation error estimate either
    way (measured 1.6e-4 against 1.9e-4, 1.5e-3 against 1.5e-3)."""
    scene_at, br, coefficients, radius = rig
    settled = stored_reference(REFERENCE)
    np.testing.assert_array_equal(settled["speeds"], SETTLED)
    for w, orbit in zip(SETTLED, settled["orbits"]):
        i = int(np.argmin(np.abs(np.asarray(br.p) - w)))
        sol = harmonic_balance(scene_at(w), 2 * np.pi / w, coefficients[i, :2 * int(br.harmonics[i]) + 1],
                               int(br.harmonics[i]), stability=False)
        assert int(sol.code) == 0
        err = np.abs(orbit - orbits_of(sol.coefficients, PHASES)[:, :2]).max() / radius[i]
        assert br.truncation[i] / 3 < err < 3 * br.truncation[i], (w, err, br.truncation[i])


def test_the_docs_state_these_checks():
    from tests.helpers import documentation

    text = " ".join(documentation("docs/periodic.md").split())
    assert f"no cubic bearings, over {RANGE[0]:g}..{RANGE[1]:g} rad/s with the defaults" in text
    assert "the branch takes 32 harmonics. The start from rest at 96 rad/s converges because Newton halves" in text
    assert ("differ from the branch's orbits by what the truncation error estimate says, within a factor of 3 either "
            "way (1.6e-4 against 1.9e-4, 1.5e-3 against 1.5e-3)" in text)


if __name__ == "__main__":
    import jax

    jax.config.update("jax_enable_x64", True)
    store_reference(REFERENCE, reference(), "python -m tests.validation.test_periodic_sfd")
