"""Bearing and disk positions as parameters (issue 34): `<table><i>.position`, the axial
position (m from node 0) of the node an entry sits at, moved between its neighbours by
the lengths of the two elements either side of it (the nodes beyond stay in place).

Checked three ways: against the file with those two lengths edited (the scene the
path sets is the scene the edited file loads, bit for bit, and `file_values` writes
that edit); against a closed form (a unit load on a simply supported Euler-Bernoulli
beam on springs: the deflection under it `a^2 b^2 / (3 E I L) + (b^2 + a^2) / (k
L^2)`, which Hermite beam elements give exactly at their nodes, and its derivative in
the position `a`, through the parameter); and an invariant (on a rotor symmetric
about mid-span, the first natural frequency is stationary in the disk's position
there). Refused, each saying why: a node at the shaft's end, a node across a step,
two parameters that set one length, bounds and distributions reaching a neighbouring
node."""

import jax
import jax.numpy as jnp
import numpy as np
import pytest

from rotorjax._errors import InputError
from rotorjax.analysis._linear import damped_frequencies
from rotorjax.design import file_values, rotor_problem
from rotorjax.io import load_rotor, read_rotor_file
from rotorjax.models._parameters import parts_of, set_parameters, value_of, with_values
from rotorjax.uncertainty import Normal, Uniform, rotor_quantities

from ..models.test_rotor_files import assert_identical

E, D, K = 2.11e11, 0.05, 1e9          # the shaft's Young's modulus and diameter; each bearing's stiffness
SHAFT = "\n".join(f'[[shaft]]\nL = 0.25\nod = {D}\nmaterial = "steel"\n' for _ in range(4))
ROTOR = f"""[rotor]
name = "positions"
theory = "euler-bernoulli"
speed = 100.0

[[material]]
name = "steel"
E = {E}
rho = 7810.0
nu = 0.3

{SHAFT}
[[disk]]
node = 2
m = 20.0
Id = 0.1
Ip = 0.2

[[bearing]]
node = 0
kxx = {K}
kyy = {K}

[[bearing]]
node = 4
kxx = {K}
kyy = {K}
"""


@pytest.fixture(scope="module")
def rotor(tmp_path_factory):
    path = tmp_path_factory.mktemp("positions") / "positions.toml"
    path.write_text(ROTOR)
    return str(path), read_rotor_file(str(path))


def test_a_position_sets_what_the_edited_file_sets(rotor):
    path, f = rotor
    p = f.path("disk0.position")
    assert float(value_of(parts_of(f.scene), p)) == 0.5 and f.interval("disk0.position") == (0.25, 0.75)
    edited = {"shaft1.L": 0.37 - 0.25, "shaft2.L": 0.75 - 0.37}
    assert file_values(f, [p], [0.37]) == pytest.approx(edited, rel=1e-15)
    assert_identical(set_parameters(f.scene, [p], [0.37]), load_rotor(path, file_values(f, [p], [0.37])))


def _deflection(rotor_file, a):
    """The x deflection of node 2 under a unit x load there, the node at `a` (m)."""
    parts = with_values(parts_of(rotor_file.scene), [rotor_file.path("disk0.position")], jnp.asarray([a]))
    K = parts.rotor.reduced_matrices(0.0)[3]
    return jnp.linalg.solve(K, jnp.zeros(K.shape[0]).at[8].set(1.0))[8]


def test_the_deflection_under_the_moved_node_is_the_beam_closed_form(rotor):
    _, f = rotor
    L, inertia = 1.0, np.pi * D**4 / 64

    def closed(a):
        b = L - a
        return a**2 * b**2 / (3 * E * inertia * L) + (a**2 + b**2) / (K * L**2)

    for a in (0.3, 0.5, 0.62):
        assert float(_deflection(f, a)) == pytest.approx(closed(a), rel=1e-9)
        assert float(jax.grad(lambda x: _deflection(f, x))(a)) == pytest.approx(
            float(jax.grad(closed)(a)), rel=1e-7)


def test_the_first_frequency_is_stationary_at_mid_span(rotor):
    """Symmetric about mid-span (one disk, equal bearings): the derivative of the first
    natural frequency in the disk's position vanishes there, and elsewhere equals a
    central difference of the edited file."""
    path, f = rotor
    p = f.path("disk0.position")

    def first(a):
        return damped_frequencies(with_values(parts_of(f.scene), [p], jnp.asarray([a])).rotor, 0.0, 1)[0]

    grad = jax.jit(jax.grad(first))
    g = float(grad(0.35))
    h = 1e-5
    fd = [float(damped_frequencies(load_rotor(path, file_values(f, [p], [0.35 + s * h])).full_rotor, 0.0, 1)[0])
          for s in (1, -1)]
    assert g == pytest.approx((fd[0] - fd[1]) / (2 * h), rel=1e-5)
    assert abs(float(grad(0.5))) < 1e-8 * abs(g)


@pytest.mark.parametrize("call, match", [
    (lambda path: rotor_problem(path, {"bearing0.position": (0.1, 0.2)}, "min-log-dec"),
     r"--vary bearing0\.position: bearing0 sits at node 0, the shaft's end"),
    (lambda path: rotor_problem(path, {"disk0.position": (0.2, 0.6)}, "min-log-dec"),
     r"--vary disk0\.position=0\.2:0\.6: .*must stay between the nodes either side of its own, at 0\.25 and 0\.75 m"),
    (lambda path: rotor_problem(path, {"disk0.position": (0.3, 0.6), "shaft2.L": (0.2, 0.3)}, "min-log-dec"),
     r"--vary disk0\.position and shaft2\.L: both set the length of shaft2"),
    (lambda path: rotor_quantities(path, {"disk0.position": Normal(0.5, 0.06)}, hi=500.0),
     r"--dist disk0\.position=normal\(0\.5, 0\.06\): reaches 0\.2 \.\. 0\.8 m .*at 0\.25 and 0\.75 m"),
    (lambda path: rotor_quantities(path, {"disk0.position": Uniform(0.3, 0.75)}, hi=500.0),
     r"--dist disk0\.position=uniform\(0\.3, 0\.75\): reaches 0\.3 \.\. 0\.75 m"),
    (lambda path: rotor_problem("rig_nonlinear.toml", {"bearing1.position": (0.5, 0.6)}, "min-log-dec"),
     r"bearing1 sits at node 5, where shaft4 and shaft5 differ \(a step"),
])
def test_refusals_say_why(rotor, call, match):
    with pytest.raises(InputError, match=match):
        call(rotor[0])
