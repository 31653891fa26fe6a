"""Results as data: a solve returns values, a result code, statistics and checks.

`RESULTS` is the one enumeration of outcomes for the whole package (in the manner
of `diffrax.RESULTS` and `optimistix.RESULTS`): every result module stores the
item's integer index in its `code` field (an int32 array, batched under vmap, so
that results stay plain arrays in JSON, CSV and `np.savez`); `as_result(code)`
turns it back into a `RESULTS` item and `code_of(item)` gives an item's integer.
The integers of the first four entries (0 to 3) are the historical codes of
`SimulationResult.code` and are kept; new outcomes are only ever appended.
"""

import types
import warnings

import equinox as eqx
import jax
import jax.numpy as jnp
import numpy as np

from .._errors import NumericalError


class RESULTS(eqx.Enumeration):
    """The outcomes of rotorjax's solves and analyses (`code` fields hold their
    integer index, see `code_of`):

    - `successful` (0).
    - `max_steps_reached` (1): the step budget (`max_steps`; for
      `simulate_events` also `max_events`) ran out before the end of the time
      span; the later saved states are inf.
    - `nonfinite` (2): non-finite values in the solution.
    - `solver_failure` (3): the step size collapsed or an implicit solve did not
      converge.
    - `root_not_converged` (4): a Newton iteration or root find stopped without
      reaching its tolerance.
    - `harmonics_insufficient` (5): harmonic balance converged, but its harmonics
      do not resolve the motion: the time-domain residual of the reconstructed
      orbit stays above its tolerance at the most harmonics allowed.
    - `max_points_reached` (6): a continuation's point budget (`max_points`) ran
      out before the branch reached the edge of its box (or closed).
    """

    successful = ""
    max_steps_reached = "max_steps reached before the end of the time span (later saved states are inf)"
    nonfinite = "non-finite values in the solution"
    solver_failure = "solver failure (step size collapsed or implicit solve did not converge)"
    root_not_converged = "Newton iteration or root find did not converge to its tolerance"
    harmonics_insufficient = ("the harmonics do not resolve the motion (time-domain residual above its tolerance at "
                              "the most harmonics allowed)")
    max_points_reached = "max_points reached before the branch reached the edge of its box"


def _items():
    """`(name, item)` for every entry of `RESULTS`, in the order of their codes."""
    return [(name, getattr(RESULTS, name)) for name in RESULTS._name_to_item]


def code_of(item) -> int:
    """The integer a result's `code` field stores for the `RESULTS` item `item`."""
    if not isinstance(item, RESULTS):
        raise TypeError(f"code_of takes an item of rotorjax.solve.RESULTS, got {item!r}")
    return int(np.asarray(jax.tree_util.tree_leaves(item)[0]))


def as_result(code):
    """The `RESULTS` item (batched like `code`) for an integer code array: supports
    `==` against `RESULTS` items, `RESULTS[item]` for the messages, `.error_if`."""
    code = jnp.asarray(code, dtype=jnp.int32)
    return jax.tree_util.tree_map(lambda _: code, RESULTS.successful)


def message_of(code) -> str:
    """The message of one integer code ("success" for `successful`)."""
    c = int(code)
    if not 0 <= c < len(RESULTS):
        return f"unknown result code {c}"
    return RESULTS._index_to_message[c] or "success"


def summary(code) -> str:
    """One line for a (batched) code array: `"success"`, or each failure's message
    with how many lanes it concerns."""
    codes = np.atleast_1d(np.asarray(code))
    bad = sorted(set(int(c) for c in codes.ravel() if c != 0))
    if not bad:
        return "success"
    return "; ".join(f"{message_of(c)} ({int(np.sum(codes == c))} of {codes.size})" for c in bad)


def deprecated_result_messages(stacklevel=3):
    """`RESULT_MESSAGES` (deprecated): `{code: message}` read-only, derived from `RESULTS`."""
    warnings.warn("RESULT_MESSAGES is deprecated: use rotorjax.solve.RESULTS (RESULTS[item] gives the "
                  "message, code_of(item) the integer)", DeprecationWarning, stacklevel=stacklevel)
    return types.MappingProxyType({code_of(item): message_of(code_of(item)) for _, item in _items()})


def __getattr__(name):
    if name == "RESULT_MESSAGES":
        return deprecated_result_messages()
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")


class AbstractOutcome(eqx.Module):
    """A result that carries its outcome as `code` (an index in `RESULTS`):
    `result` is it as a `RESULTS` item, `success` is `code == 0` (both batched
    like `code`)."""

    code: eqx.AbstractVar[jax.Array]

    @property
    def result(self):
        """`code` as a `RESULTS` item (batched like `code`)."""
        return as_result(self.code)

    @property
    def success(self) -> jax.Array:
        return self.code == code_of(RESULTS.successful)


class SimulationResult(AbstractOutcome):
    """What `simulate` returns.

    - `ts`, `ys`: saved times and states (`ys[i]` is the state at `ts[i]`).
    - `outputs`: named outputs at the saved times (`whirl_amplitude`,
      `residual_imbalance`, `weight_angles`, ...).
    - `code`: the outcome's index in `RESULTS`: 0 successful, 1 max steps
      reached, 2 non-finite values, 3 solver failure; `result` is the same as a
      `RESULTS` item (`result == RESULTS.max_steps_reached`), `success` is
      `code == 0`.
    - `stats`: accepted/rejected step counts and the number of steps.
    - `solver`: the diffrax solver's name (static).

    Under `vmap` every field gains a leading batch axis: a failed lane is marked
    by its code, not raised for the whole batch.
    """

    ts: jax.Array
    ys: jax.Array
    outputs: dict
    code: jax.Array
    stats: dict
    solver: str = eqx.field(static=True)

    @property
    def message(self) -> str:
        return summary(self.code)

    def raise_if_failed(self) -> "SimulationResult":
        if not bool(np.all(np.asarray(self.success))):
            raise NumericalError(f"simulation failed: {self.message}")
        return self


SUCCESSFUL = code_of(RESULTS.successful)
MAX_STEPS_REACHED = code_of(RESULTS.max_steps_reached)
NONFINITE = code_of(RESULTS.nonfinite)
SOLVER_FAILURE = code_of(RESULTS.solver_failure)


def result_code(diffrax_result, ys) -> jax.Array:
    """The `RESULTS` code of a diffrax solve that saved `ys` (an array or a pytree of
    arrays, e.g. the state and its variational equations)."""
    import diffrax

    finite = jnp.all(jnp.stack([jnp.all(jnp.isfinite(x)) for x in jax.tree_util.tree_leaves(ys)]))
    ok = diffrax_result == diffrax.RESULTS.successful
    max_steps = diffrax_result == diffrax.RESULTS.max_steps_reached
    # After a failed step diffrax fills the remaining saved states with inf, so
    # non-finite values mean a blow-up only when diffrax itself reports success.
    return jnp.where(ok, jnp.where(finite, SUCCESSFUL, NONFINITE),
                     jnp.where(max_steps, MAX_STEPS_REACHED, SOLVER_FAILURE)).astype(jnp.int32)
