"""Uncertainty: parameters as distributions, outputs as distributions (vmapped Monte
Carlo and first-order moments from autodiff gradients), violation probabilities
with their intervals, and each parameter's share of an output's variance; for any
JAX function of a scene's parameters, and for a rotor file's critical speeds and log
decrements (`rotor_quantities`), and for a preset's stability thresholds and stable
speed range (`preset_quantities`)."""

from ._distributions import LogNormal as LogNormal
from ._distributions import Normal as Normal
from ._distributions import Uniform as Uniform
from ._distributions import distribution as distribution
from ._distributions import parse_distribution as parse_distribution
from ._distributions import reaches_zero as reaches_zero
from ._distributions import support as support
from ._propagate import CHUNK_SIZE as CHUNK_SIZE
from ._propagate import Propagation as Propagation
from ._propagate import draw as draw
from ._propagate import propagate as propagate
from ._propagate import wilson as wilson
from ._rotor import RotorQuantities as RotorQuantities
from ._rotor import rotor_quantities as rotor_quantities
from ._preset import preset_quantities as preset_quantities
