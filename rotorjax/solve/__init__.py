"""Time integration (diffrax) and results."""

from ._results import RESULTS as RESULTS
from ._results import SimulationResult as SimulationResult
from ._results import as_result as as_result
from ._results import code_of as code_of
from ._simulate import simulate as simulate
from ._stiffness import STIFFNESS_THRESHOLD as STIFFNESS_THRESHOLD
from ._stiffness import StiffnessEstimate as StiffnessEstimate
from ._stiffness import choose_solver as choose_solver
from ._stiffness import dopri8_stability_radius as dopri8_stability_radius
from ._stiffness import estimate_stiffness as estimate_stiffness
from ._stiffness import is_stiff as is_stiff
from ._stiffness import jacobian_at as jacobian_at
from ._stiffness import stiffness_ratio as stiffness_ratio
from ._events import simulate_events as simulate_events
from ._batch import IVP as IVP
from ._batch import simulate_batch as simulate_batch


def __getattr__(name):
    if name == "RESULT_MESSAGES":  # deprecated: RESULTS
        from ._results import deprecated_result_messages

        return deprecated_result_messages()
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")
