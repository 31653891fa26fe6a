"""Flexible rotors: finite-element shafts with disks and bearings, linear analyses;
model 003's modal shaft (closed forms, balancer regimes). The models themselves
live in `rotorjax.models` and are re-exported here under their old names."""

from ._linear import Modes as Modes
from ._linear import campbell as campbell
from ._linear import critical_speed as critical_speed
from ._linear import critical_speeds_1x as critical_speeds_1x
from ._linear import damped_frequencies as damped_frequencies
from ._linear import modes as modes
from ._linear import state_matrix as state_matrix
from ._linear import synchronous_critical_speeds as synchronous_critical_speeds
from ._linear import unbalance_response as unbalance_response
from ..models._fe_rotor import FlexibleRotor as FlexibleRotor
from ..models._fe_rotor import cowper_shear_coefficient as cowper_shear_coefficient
from ..models._fe_reduction import ReducedRotor as ReducedRotor
from ..models._fe_reduction import undamped_modes as undamped_modes
from ..models._modal import ModalShaft as ModalShaft
from ._modal import closed_form_sums as closed_form_sums
from ._modal import critical_speed_function as critical_speed_function
from ._modal import exact_critical_speeds as exact_critical_speeds
from ._balancer003 import BalancerRegime as BalancerRegime
from ..models._modal_balancer import ModalBalancerRotor as ModalBalancerRotor
from ._balancer003 import balanced_regime as balanced_regime
from ._balancer003 import unbalanced_regimes as unbalanced_regimes
from ._balancer003 import pseudo_balanced_speeds as pseudo_balanced_speeds
from ..models._cantilever import CantileverRotor as CantileverRotor
from ..models._cantilever import PAPER_SI as PAPER_SI
from ..models._cantilever import groups_from_si as groups_from_si
from ..models._cantilever import limiter_groups_from_si as limiter_groups_from_si
