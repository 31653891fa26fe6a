"""The two kinds of failure a user is told about.

- `InputError` (a `ValueError`): the input cannot be used — a parameter out of its
  domain, a malformed file, a range with `LO >= HI`. The message names what the
  user gave (the parameter, `--set` key, option, file, column or row) and what
  would be valid. The CLI exits with code 2.
- `NumericalError` (a `RuntimeError`): the input was valid but the computation
  failed — no convergence, the step budget spent, non-finite values. The CLI
  exits with code 3.

Both are raised outside `jit`; inside traced code a failure is a result code.
"""


class InputError(ValueError):
    """Bad input: the message names the culprit in the user's own words."""


class NumericalError(RuntimeError):
    """A valid input whose computation failed (non-convergence, step budget, NaN)."""


class PlausibilityWarning(UserWarning):
    """A valid but implausible input (a likely unit slip: `E = 205` Pa, `od = 60` m;
    a bearing table used outside its speeds). Issued with `warnings.warn` where the
    value is checked, outside `jit`; the CLI prints each on stderr and adds it to
    its JSON output's `warnings`."""
