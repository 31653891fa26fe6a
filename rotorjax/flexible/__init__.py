"""Flexible rotors: finite-element shafts with disks and bearings, linear analyses."""

from ._linear import Modes as Modes
from ._linear import campbell as campbell
from ._linear import critical_speed as critical_speed
from ._linear import critical_speeds_1x as critical_speeds_1x
from ._linear import damped_frequencies as damped_frequencies
from ._linear import modes as modes
from ._linear import state_matrix as state_matrix
from ._linear import synchronous_critical_speeds as synchronous_critical_speeds
from ._linear import unbalance_response as unbalance_response
from ._rotor import FlexibleRotor as FlexibleRotor
from ._rotor import cowper_shear_coefficient as cowper_shear_coefficient
from ._reduction import ReducedRotor as ReducedRotor
from ._reduction import undamped_modes as undamped_modes
from ._modal import ModalShaft as ModalShaft
from ._modal import closed_form_sums as closed_form_sums
from ._modal import critical_speed_function as critical_speed_function
from ._modal import exact_critical_speeds as exact_critical_speeds
from ._balancer003 import BalancerRegime as BalancerRegime
from ._balancer003 import ModalBalancerRotor as ModalBalancerRotor
from ._balancer003 import balanced_regime as balanced_regime
from ._balancer003 import unbalanced_regimes as unbalanced_regimes
from ._balancer003 import pseudo_balanced_speeds as pseudo_balanced_speeds
from ._cantilever import CantileverRotor as CantileverRotor
from ._cantilever import PAPER_SI as PAPER_SI
from ._cantilever import groups_from_si as groups_from_si
from ._cantilever import limiter_groups_from_si as limiter_groups_from_si
