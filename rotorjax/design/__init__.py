"""Design with gradients: a scene's parameters chosen within bounds to minimise or
maximise one of its quantities subject to limits on others, by one mechanism
(`minimize`: an augmented Lagrangian on JAX gradients, multi-start vmapped); for a
rotor file, its margins (`rotor_problem`, `optimize_rotor`); for a preset, its
reference motion's stable speed range (`preset_problem`)."""

from ._optimize import Optimum as Optimum
from ._optimize import latin_starts as latin_starts
from ._optimize import minimize as minimize
from ._rotor import RotorDesign as RotorDesign
from ._rotor import RotorProblem as RotorProblem
from ._rotor import file_values as file_values
from ._rotor import optimize_rotor as optimize_rotor
from ._rotor import parse_constraint as parse_constraint
from ._rotor import preset_problem as preset_problem
from ._rotor import rotor_problem as rotor_problem
