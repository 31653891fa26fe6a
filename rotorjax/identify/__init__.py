"""Balancing and identification from measured vibration: model 002's balancing
machine, and any finite-element rotor file (phasor files); `identify(scene, data,
params)` for every scene."""

from ..models._balancing_machine import BalancingMachine as BalancingMachine
from ..models._balancing_machine import BalancingScene as BalancingScene
from ..models._balancing_machine import scalar_influence_matrix as scalar_influence_matrix
from ._signals import Phasors as Phasors
from ._signals import OrderTrack as OrderTrack
from ._signals import order_track as order_track
from ._signals import phasors as phasors
from ._signals import pulse_times as pulse_times
from ._signals import read_signals as read_signals
from ._signals import runs_from_signals as runs_from_signals
from ._signals import BalancingData as BalancingData
from ._signals import balancing_runs as balancing_runs
from ._datasets import DATA_DIR as DATA_DIR
from ._datasets import DATASETS as DATASETS
from ._datasets import dataset_path as dataset_path
from ._datasets import resolve_data as resolve_data
from ._datasets import RIG as RIG
from ._datasets import rig_scene as rig_scene
from ._balance import Balancing as Balancing
from ._balance import BalancingRun as BalancingRun
from ._balance import balance as balance
from ._balance import simulate_balancing as simulate_balancing
from ._corrections import least_squares_balance as least_squares_balance
from ._corrections import least_squares_correction as least_squares_correction
from ._corrections import minmax_balance as minmax_balance
from ._corrections import split_onto_holes as split_onto_holes
from ._corrections import unbalance_from_vibration as unbalance_from_vibration
from ._influence import influence_from_phasor_runs as influence_from_phasor_runs
from ._influence import influence_from_trials as influence_from_trials
from ._influence import machine_runs as machine_runs
from ._influence import model_influence as model_influence
from ._iso import ISO_GRADES as ISO_GRADES
from ._iso import grade_reached as grade_reached
from ._iso import permissible_unbalance as permissible_unbalance
from ._identify import identify as identify
from ._engine import Identification as Identification
from ._engine import optax_fit as optax_fit
from ._fit import FITTABLE as FITTABLE
from ._fit import SweepData as SweepData
from ._fit import residual_fn as residual_fn
from ._fit import response_band as response_band
from ._lm import levenberg_marquardt as levenberg_marquardt
from ._phasor_file import PhasorData as PhasorData
from ._phasor_file import read_phasors as read_phasors
from ._phasor_file import write_phasors as write_phasors
from ._phasor_file import make_phasors as make_phasors
from ._phasor_file import phasors_from_signals as phasors_from_signals
from ._fe_params import RotorModel as RotorModel
from ._fe_params import rotor_model as rotor_model
from ._fe_identify import estimates_jacobian as estimates_jacobian

#: The shipped synthetic measurements (see `rotorjax.identify._make_data` and
#: `_make_fe_data`; by name: `DATASETS`).
BALANCING_RUNS = dataset_path("balancing-runs")
RUNUP = dataset_path("runup")
FLEXIBLE_RUNUP = dataset_path("flexible-runup")
FLEXIBLE_TRIALS = dataset_path("flexible-trials")
