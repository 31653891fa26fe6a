"""RESULTS: one enumeration of outcomes for the package; results are immutable data."""

import dataclasses

import diffrax
import equinox as eqx
import jax
import jax.numpy as jnp
import numpy as np
import pytest

import rotorjax as rj
from rotorjax._errors import NumericalError
from rotorjax.presets import anisotropic_abb
from rotorjax.solve import RESULTS, SimulationResult, as_result, code_of
from rotorjax.solve._results import result_code

GROUPS_001 = {k: rj.presets.get("anisotropic-abb").defaults[k] for k in anisotropic_abb.GROUPS}


def _failed_run():
    s = anisotropic_abb.scene_from_groups(**GROUPS_001, n=3.0)
    return rj.simulate(s, s.rest_state(np.array([2.2, 4.1])), (0.0, 100.0), saveat=5, max_steps=20)


def test_names_codes_and_messages():
    assert issubclass(RESULTS, eqx.Enumeration) and rj.RESULTS is RESULTS
    # the historical codes of SimulationResult.code are kept; new outcomes are appended
    names = ("successful", "max_steps_reached", "nonfinite", "solver_failure", "root_not_converged",
             "harmonics_insufficient", "max_points_reached")
    assert [code_of(getattr(RESULTS, k)) for k in names] == list(range(len(names))) and len(RESULTS) == len(names)
    assert RESULTS[RESULTS.successful] == ""
    assert "max_steps" in RESULTS[RESULTS.max_steps_reached]
    assert "non-finite" in RESULTS[RESULTS.nonfinite]
    assert "solver failure" in RESULTS[RESULTS.solver_failure]
    assert "did not converge" in RESULTS[RESULTS.root_not_converged]
    assert "harmonics do not resolve" in RESULTS[RESULTS.harmonics_insufficient]
    assert "max_points" in RESULTS[RESULTS.max_points_reached]
    with pytest.raises(TypeError, match="RESULTS"):
        code_of(diffrax.RESULTS.successful)


def test_result_messages_is_a_deprecated_alias_derived_from_results():
    with pytest.warns(DeprecationWarning, match="RESULTS"):
        from rotorjax.solve import RESULT_MESSAGES
    assert RESULT_MESSAGES[0] == "success"
    assert RESULT_MESSAGES[code_of(RESULTS.nonfinite)] == RESULTS[RESULTS.nonfinite]
    assert sorted(RESULT_MESSAGES) == list(range(len(RESULTS)))
    with pytest.raises(TypeError):
        RESULT_MESSAGES[0] = "changed"                       # read-only


def test_a_failed_simulation_carries_the_results_code():
    r = _failed_run()
    assert int(r.code) == code_of(RESULTS.max_steps_reached) and not bool(r.success)
    assert bool(r.result == RESULTS.max_steps_reached) and not bool(r.result == RESULTS.successful)
    assert RESULTS[r.result] == RESULTS[RESULTS.max_steps_reached]
    assert r.message.startswith(RESULTS[RESULTS.max_steps_reached])
    with pytest.raises(NumericalError, match="max_steps"):
        r.raise_if_failed()


def test_diffrax_outcomes_map_onto_results():
    finite, blown = jnp.ones((2, 2)), jnp.array([[0.0, 1.0], [jnp.nan, 0.0]])
    cases = [(diffrax.RESULTS.successful, finite, RESULTS.successful),
             (diffrax.RESULTS.successful, blown, RESULTS.nonfinite),
             (diffrax.RESULTS.max_steps_reached, blown, RESULTS.max_steps_reached),
             (diffrax.RESULTS.singular, finite, RESULTS.solver_failure)]
    for dr, ys, expected in cases:
        assert int(result_code(dr, ys)) == code_of(expected)
    # a pytree of saved values (a state and its variational equations)
    assert int(result_code(diffrax.RESULTS.successful, (finite, jnp.array([jnp.inf])))) == code_of(RESULTS.nonfinite)


def test_batched_codes_as_results_and_their_message():
    codes = jnp.array([0, 1, 1, 3], dtype=jnp.int32)
    res = as_result(codes)
    np.testing.assert_array_equal(res == RESULTS.max_steps_reached, [False, True, True, False])
    compare = jax.jit(lambda c: as_result(c) == RESULTS.solver_failure)
    np.testing.assert_array_equal(compare(codes), [False, False, False, True])
    r = SimulationResult(ts=jnp.zeros((4, 1)), ys=jnp.zeros((4, 1, 2)), outputs={}, code=codes, stats={},
                         solver="test")
    np.testing.assert_array_equal(r.success, [True, False, False, False])
    assert r.message == (f"{RESULTS[RESULTS.max_steps_reached]} (2 of 4); "
                         f"{RESULTS[RESULTS.solver_failure]} (1 of 4)")


def test_results_are_immutable():
    r = _failed_run()
    with pytest.raises(dataclasses.FrozenInstanceError):
        r.code = jnp.int32(0)
    with pytest.raises(dataclasses.FrozenInstanceError):
        r.ys = r.ys * 0
