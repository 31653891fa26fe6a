"""Contact: discrete visco-elastic limiters, and model 004's cantilever scene."""

from ._limiters import Limiters as Limiters
from ._scene import CantileverScene as CantileverScene
