"""Time integration (diffrax) and results."""

from ._results import RESULT_MESSAGES as RESULT_MESSAGES
from ._results import SimulationResult as SimulationResult
from ._simulate import simulate as simulate
from ._stiffness import STIFFNESS_THRESHOLD as STIFFNESS_THRESHOLD
from ._stiffness import choose_solver as choose_solver
from ._stiffness import stiffness_ratio as stiffness_ratio
from ._events import simulate_events as simulate_events
from ._batch import IVP as IVP
from ._batch import simulate_batch as simulate_batch
