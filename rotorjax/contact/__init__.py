"""Contact (compatibility namespace): the limiters and model 004's scene live in
`rotorjax.models`."""

from ..models._cantilever_scene import CantileverScene as CantileverScene
from ..models._cantilever_scene import cantilever_scene as cantilever_scene
from ..models._cantilever_scene import energy_residual as energy_residual
from ..models._limiters import Limiters as Limiters
