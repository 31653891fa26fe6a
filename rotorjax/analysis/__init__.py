"""Analyses: stationary regimes, stability, Floquet multipliers, critical speeds."""

from ._rotating import check_autonomous as check_autonomous
from ._rotating import rotating_field as rotating_field
from ._rotating import to_fixed as to_fixed
from ._rotating import to_rotating as to_rotating
from ._steady import Regime as Regime
from ._steady import stability as stability
from ._steady import steady_state as steady_state
from ._steady import steady_states as steady_states
from ._floquet import FloquetResult as FloquetResult
from ._floquet import floquet as floquet
from ._floquet import monodromy as monodromy
from ._floquet import periodic_orbit as periodic_orbit
from ._critical import CriticalSpeed as CriticalSpeed
from ._critical import critical_speed_gradient as critical_speed_gradient
from ._critical import critical_speeds as critical_speeds
from ._hopf import HopfPoint as HopfPoint
from ._hopf import hopf_points as hopf_points
from ._hopf import hopf_speed_gradient as hopf_speed_gradient
from ._precession import Precession as Precession
from ._precession import precession as precession
