"""Results as data: a solve returns values, a result code, statistics and checks."""

import equinox as eqx
import jax
import jax.numpy as jnp
import numpy as np

from .._errors import NumericalError

#: Result codes of `SimulationResult.code` (an int array, batched under vmap).
RESULT_MESSAGES = {
    0: "success",
    1: "max_steps reached before the end of the time span (later saved states are inf)",
    2: "non-finite values in the solution",
    3: "solver failure (step size collapsed or implicit solve did not converge)",
}


class SimulationResult(eqx.Module):
    """What `simulate` returns.

    - `ts`, `ys`: saved times and states (`ys[i]` is the state at `ts[i]`).
    - `outputs`: named outputs at the saved times (`whirl_amplitude`,
      `residual_imbalance`, `weight_angles`, ...).
    - `code`: 0 success, 1 max steps, 2 non-finite values, 3 solver failure
      (see `RESULT_MESSAGES`); `success` is `code == 0`.
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
    def success(self) -> jax.Array:
        return self.code == 0

    @property
    def message(self) -> str:
        codes = np.atleast_1d(np.asarray(self.code))
        bad = sorted(set(int(c) for c in codes if c != 0))
        if not bad:
            return "success"
        return "; ".join(
            f"{RESULT_MESSAGES[c]} ({int(np.sum(codes == c))} of {codes.size})" for c in bad
        )

    def raise_if_failed(self) -> "SimulationResult":
        if not bool(np.all(np.asarray(self.success))):
            raise NumericalError(f"simulation failed: {self.message}")
        return self


def result_code(diffrax_result, ys) -> jax.Array:
    import diffrax

    finite = jnp.all(jnp.isfinite(ys))
    ok = diffrax_result == diffrax.RESULTS.successful
    max_steps = diffrax_result == diffrax.RESULTS.max_steps_reached
    # After a failed step diffrax fills the remaining saved states with inf, so
    # non-finite values mean a blow-up only when diffrax itself reports success.
    return jnp.where(ok, jnp.where(finite, 0, 2), jnp.where(max_steps, 1, 3)).astype(jnp.int32)
