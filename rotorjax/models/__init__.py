"""Components and scenes: rotor models from energies."""

from .. import _config  # noqa: F401  (float64)
from ._balancer import INERTIA_FACTORS as INERTIA_FACTORS
from ._balancer import AutoBalancer as AutoBalancer
from ._balancer import Race as Race
from ._balancer import balancing_angles as balancing_angles
from ._balancer import weights_at as weights_at
from ._base import AbstractComponent as AbstractComponent
from ._base import Kinematics as Kinematics
from ._lagrange import lagrange_accelerations as lagrange_accelerations
from ._rotor import RigidRotor as RigidRotor
from ._scene import Scene as Scene
from ._speed import AbstractSpeedProfile as AbstractSpeedProfile
from ._speed import ConstantSpeed as ConstantSpeed
from ._speed import CustomSpeed as CustomSpeed
from ._speed import RunUp as RunUp
from ._supports import Supports as Supports
