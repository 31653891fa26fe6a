"""Balancing and identification from measured vibration: model 002's balancing
machine, and any finite-element rotor file (phasor files, `identify_rotor`,
`balance_rotor`)."""

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
from ._balance import ISO_GRADES as ISO_GRADES
from ._balance import grade_reached as grade_reached
from ._balance import influence_from_trials as influence_from_trials
from ._balance import least_squares_correction as least_squares_correction
from ._balance import permissible_unbalance as permissible_unbalance
from ._balance import simulate_balancing as simulate_balancing
from ._balance import split_onto_holes as split_onto_holes
from ._balance import unbalance_from_vibration as unbalance_from_vibration
from ._fit import Identification as Identification
from ._fit import identify as identify
from ._fit import RunupIdentification as RunupIdentification
from ._fit import identify_runup as identify_runup
from ._fit import FITTABLE as FITTABLE
from ._lm import levenberg_marquardt as levenberg_marquardt
from ._fit import optax_fit as optax_fit
from ._fit import residual_fn as residual_fn
from ._fit import response_band as response_band
from ._phasor_file import PhasorData as PhasorData
from ._phasor_file import read_phasors as read_phasors
from ._phasor_file import write_phasors as write_phasors
from ._phasor_file import make_phasors as make_phasors
from ._phasor_file import phasors_from_signals as phasors_from_signals
from ._fe_params import RotorModel as RotorModel
from ._fe_params import rotor_model as rotor_model
from ._fe_identify import FEIdentification as FEIdentification
from ._fe_identify import identify_rotor as identify_rotor
from ._fe_identify import estimates_jacobian as estimates_jacobian
from ._fe_balance import FEBalancing as FEBalancing
from ._fe_balance import balance_rotor as balance_rotor
from ._fe_balance import influence_from_phasor_runs as influence_from_phasor_runs
from ._fe_balance import model_influence as model_influence
from ._fe_balance import least_squares_balance as least_squares_balance
from ._fe_balance import minmax_balance as minmax_balance

#: The shipped synthetic measurements (see `rotorjax.identify._make_data` and
#: `_make_fe_data`; by name: `DATASETS`).
BALANCING_RUNS = dataset_path("balancing-runs")
RUNUP = dataset_path("runup")
FLEXIBLE_RUNUP = dataset_path("flexible-runup")
FLEXIBLE_TRIALS = dataset_path("flexible-trials")
