"""rotorjax: differentiable rotordynamics in JAX.

Importing rotorjax enables float64 (`jax_enable_x64`); see `rotorjax._config`.
"""

from . import _config  # noqa: F401
from . import analysis as analysis
from . import flexible as flexible
from . import io as io
from . import models as models
from . import presets as presets
from . import solve as solve
from .models import RotorScene as RotorScene
from .models import Scene as Scene
from .io import load_rotor as load_rotor
from .io import save_rotor as save_rotor
from .solve import IVP as IVP
from .solve import RESULTS as RESULTS
from .solve import SimulationResult as SimulationResult
from .solve import simulate as simulate
from .sweep import SweepResult as SweepResult
from .sweep import sweep as sweep

__version__ = "0.1.0"
