"""Parameters as leaves of the scene (issue 33): every scalar entry of a rotor file,
set through the leaves its path resolves to, builds the scene the file loads with
that entry overridden, bit for bit (followers and derived constants included); a
parameter path is pure JAX (vmapped, differentiated against finite differences of
the file); what is not a leaf is refused, saying why."""

import pathlib

import jax
import jax.numpy as jnp
import numpy as np
import pytest

from rotorjax._errors import InputError
from rotorjax.analysis._linear import damped_frequencies
from rotorjax.models._parameters import ParameterPath, set_parameters, value_of, parts_of, with_values
from rotorjax.io import file_parameters_and_scene, load_rotor, read_rotor_file, save_rotor

from .test_rotor_files import assert_identical

FILE = str(pathlib.Path(__file__).parent / "data" / "every_table.toml")


@pytest.fixture(scope="module")
def entries():
    _, _, out, scene = file_parameters_and_scene(FILE)
    return out, scene


def _changed(p):
    return p.value * 1.1 if p.value else 0.1


def test_every_leaf_path_equals_the_file_overridden(entries):
    """For each scalar entry of a file with every table (two materials, one giving G
    and one nu; a taper; a tabulated bearing; a damper, a journal bearing, a pedestal,
    every nonlinear part): the scene with the value set through its path is the
    file's scene with `--set name=value`, leaf for leaf, exactly."""
    out, scene = entries
    paths = [p for p in out.values() if not p.path.refusal]
    assert len(paths) >= 50
    for p in paths:
        v = _changed(p)
        assert_identical(set_parameters(scene, [p.path], [v]), load_rotor(FILE, {p.path.name: v}))
        assert float(value_of(parts_of(scene), p.path)) == p.value


def test_every_table_round_trips(entries, tmp_path):
    """Saved state is complete: `save_rotor` then `load_rotor` gives the file's scene
    leaf for leaf, with every table (a damper written before a journal bearing keeps
    its place among the components: the writer once grouped films by type)."""
    _, scene = entries
    save_rotor(scene, tmp_path / "again.toml")
    again = load_rotor(tmp_path / "again.toml")
    assert [type(c).__name__ for c in again.components][5:7] == ["SqueezeFilmDamper", "JournalBearing"]
    assert_identical(again, scene)


def test_followers_are_needed(entries):
    """The test above can fail: without the values that follow (kyy after kxx, a
    material's nu or G, a clearance bearing's smoothing) the scenes differ."""
    out, scene = entries
    for name in ("bearing0.kxx", "support0.cxx", "material0.E", "material1.nu", "bearing2.kxx",
                 "clearance_bearing0.clearance"):
        p = out[name]
        assert len(p.path.targets) == 2, name
        alone = ParameterPath(name, p.path.targets[:1])
        a, b = set_parameters(scene, [alone], [_changed(p)]), load_rotor(FILE, {name: _changed(p)})
        with pytest.raises(AssertionError):
            assert_identical(a, b)


def test_reduced_scene_rebuilds_its_basis():
    """A modally reduced rotor (`n_modes`) gets its basis from the new leaves."""
    _, _, out, scene = file_parameters_and_scene(FILE)
    base = {"rotor.n_modes": 8}
    reduced = load_rotor(FILE, base)
    p = out["shaft2.od"].path
    assert_identical(set_parameters(reduced, [p], [0.065]), load_rotor(FILE, {**base, "shaft2.od": 0.065}))


def test_pure_jax_grad_and_vmap(entries):
    """The lowest damped frequency's derivative in E and a diameter through the
    leaves equals a central difference of the file overridden; vmapped values equal
    one by one."""
    out, scene = entries
    full = scene.full_rotor
    names = ("material0.E", "shaft3.od")

    def freq(values):
        parts = with_values(parts_of(scene), [out[n].path for n in names], values)
        return damped_frequencies(parts.rotor, 0.0, 1)[0]

    v0 = jnp.array([out[n].value for n in names])
    g = jax.grad(freq)(v0)
    for k, n in enumerate(names):
        h = 1e-5 * out[n].value
        fd = [float(damped_frequencies(load_rotor(FILE, {n: out[n].value + s * h}).full_rotor, 0.0, 1)[0])
              for s in (1, -1)]
        assert abs(float(g[k]) - (fd[0] - fd[1]) / (2 * h)) < 1e-6 * abs(float(g[k]))
    vs = v0[None, :] * jnp.array([[1.0, 1.0], [1.2, 0.9], [0.8, 1.1]])
    batched = jax.vmap(freq)(vs)
    assert np.allclose(batched, [float(freq(v)) for v in vs], rtol=1e-12, atol=0)
    assert float(freq(v0)) == pytest.approx(float(damped_frequencies(full, 0.0, 1)[0]), rel=1e-13)


@pytest.mark.parametrize("name, words", [
    ("material2.E", "no [[shaft]] element is made of material 'spare'"),
    ("bearing0.node", "an integer that shapes the scene"),
    ("limiters0.n", "an integer that shapes the scene"),
    ("limiters0.first_angle", "it places the limiters when the file is read"),
])
def test_refused_paths_say_why(entries, name, words):
    out, scene = entries
    p = out[name].path
    assert words in p.refusal and not p.targets
    with pytest.raises(InputError, match=name):
        set_parameters(scene, [p], [1.0])


def test_rotor_speed_is_the_speed():
    """`rotor.speed` (the key as the file writes it) resolves as `speed` does."""
    f = read_rotor_file(FILE)
    assert f.path("rotor.speed").targets == f.path("speed").targets == f.entries["speed"].path.targets
