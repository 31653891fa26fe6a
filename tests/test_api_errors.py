"""Argument checking across the public API: bad input raises `InputError` (a
`ValueError`) naming the parameter as the caller passed it, the value and what is
valid; valid input still builds, and the checks never break tracing."""

import functools
import re

import diffrax
import equinox as eqx
import jax
import jax.numpy as jnp
import numpy as np
import pytest

import rotorjax as rj
from rotorjax import identify as idf
from rotorjax._errors import InputError
from rotorjax.contact import Limiters
from tests.reference.model_004_scene import CantileverScene
from rotorjax.flexible import (CantileverRotor, FlexibleRotor, ModalBalancerRotor, ModalShaft,
                               critical_speeds_1x, damped_frequencies, exact_critical_speeds,
                               pseudo_balanced_speeds, unbalance_response)
from rotorjax.models import (AutoBalancer, ConstantSpeed, Race, RigidRotor, RunUp, Scene, Supports,
                             balancing_angles)
from rotorjax.solve import simulate_events

P = functools.partial
ANGLES = 2 * np.pi / 3 * np.arange(3)
MACHINE = dict(m=10.0, I=0.5, l=1.0, k1=1e6, k2=1e6, c1=100.0, c2=100.0)


# --- small valid objects, built on first use -----------------------------------------
@functools.cache
def jeffcott():
    """A rotor on supports with a two-ball balancer: state size 8."""
    return Scene(RigidRotor(1.0, 0.01), ConstantSpeed(2.0),
                 (Supports.isotropic(1.0, 0.1), AutoBalancer([0.01, 0.01], Race.circular(1.0), 0.05)))


@functools.cache
def shaft():
    """Two elements (nodes 0..2) on bearings at the ends, a disk in the middle."""
    return FlexibleRotor(np.full(2, 0.2), 0.03, disks=((1, 5.0, 0.02, 0.04),),
                         bearings=((0, 1e7, 1e7, 0.0, 0.0), (2, 1e7, 1e7, 0.0, 0.0)))


@functools.cache
def cantilever():
    return CantileverRotor(0.7, 0.005, 0.03, 0.005, 0.025, n_elements=2)


@functools.cache
def contact_scene():
    return CantileverScene(cantilever(), 5.0, eps=1e-3, limiters=Limiters(ANGLES, 0.01, 850.0))


def modal_shaft(**kw):
    return ModalShaft(**dict(dict(n_modes=3, m=1.0, z0=0.5, m0=0.01), **kw))


def balls(**kw):
    return ModalBalancerRotor(**dict(dict(shaft=modal_shaft(), ball_mass=[0.01, 0.01], ball_radius=1.0,
                                          ball_drag=0.1, speed=ConstantSpeed(0.5)), **kw))


def simulate(**kw):
    s = jeffcott()
    args = dict(scene=s, y0=s.rest_state(np.array([1.0, 2.0])), t_span=(0.0, 1.0))
    return rj.simulate(**dict(args, **kw))


def events(**kw):
    s = contact_scene()
    args = dict(scene=s, y0=jnp.zeros(s.state_size), t_span=(0.0, 1.0), saveat=10)
    return simulate_events(**dict(args, **kw))


def sweep(**kw):
    args = dict(fn=lambda p: p["a"] ** 2, grid={"a": [1.0, 2.0]})
    return rj.sweep(**dict(args, **kw))


def batch(**kw):
    """Two jeffcott() scenes batched along a leading axis."""
    s = jeffcott()
    scenes = jax.tree_util.tree_map(lambda a: jnp.stack([a, a]) if eqx.is_array(a) else a, s)
    y0 = s.rest_state(np.array([1.0, 2.0]))
    args = dict(scenes=scenes, y0s=jnp.stack([y0, y0]), t_span=(0.0, 1.0))
    return rj.solve.simulate_batch(**dict(args, **kw))


def ivp_sweep(**kw):
    s = jeffcott()
    y0 = s.rest_state(np.array([1.0, 2.0]))
    args = dict(fn=lambda p: rj.IVP(s, y0 * p["a"], (0.0, 1.0)), grid={"a": [1.0, 2.0]})
    return rj.sweep(**dict(args, **kw))


def plan(**kw):
    """`plan_run` on a small finite-element rotor scene (shaft(): 12 free dofs)."""
    s = rj.models.RotorScene(shaft(), 10.0)
    args = dict(scene=s, y0=s.rest_state(), t_end=1.0, rtol=1e-8, max_steps=1000)
    return rj.analysis.plan_run(**dict(args, **kw))


def plan_reduced(**kw):
    s = rj.models.RotorScene(shaft().reduce(3), 10.0)
    return rj.analysis.plan_run(s, s.rest_state(), 1.0, 1e-8, 1000, **kw)


def limiters(**kw):
    return Limiters(**dict(dict(angles=ANGLES, clearance=0.01, stiffness=850.0), **kw))


def scene004(**kw):
    return CantileverScene(**dict(dict(rotor=cantilever(), N=5.0), **kw))


def trials(**kw):
    args = dict(X0=np.array([1.0, 1j]), X_trials=np.array([[2.0, 1j], [1.0, 2j]]), trials=np.array([1.0, 1j]))
    return idf.influence_from_trials(**dict(args, **kw))


def lsq(**kw):
    K = np.arange(8.0).reshape(4, 2) + 1j
    return idf.least_squares_correction(**dict(dict(K=K, X=np.ones(4)), **kw))


def balancing(**kw):
    args = dict(machine=idf.BalancingMachine(**MACHINE), planes=[0.2, 0.8], speed=100.0,
                unbalance=[1e-3, 1e-3j], tolerance=1e-5)
    return idf.simulate_balancing(**dict(args, **kw))


def ident(**kw):
    """`identify` on the balancing machine, from five phasors (the checks come first)."""
    scene = idf.BalancingScene(idf.BalancingMachine(**MACHINE), [0.2, 0.8], [1e-3, 1e-3j])
    args = dict(scene=scene, data=(np.linspace(50.0, 250.0, 5), np.ones((5, 2), dtype=complex)), params=("k1",))
    return idf.identify(**dict(args, **kw))


def ident_rotor(**kw):
    """`identify` on the shipped flexible rig's rotor file (the checks come first)."""
    args = dict(scene=str(rj.io.shipped_rotor("flexible_rig")), data="flexible-runup", params=("bearing0.kxx",))
    return idf.identify(**dict(args, **kw))


def orbit(**kw):
    """jeffcott()'s rest as a periodic reference, unbatched."""
    s = jeffcott()
    return rj.analysis.PeriodicOrbit(s, s.rest_state(np.array([1.0, 2.0])), 1.0)


def margins(**kw):
    args = dict(reference_at=lambda p: orbit(), points={"a": [1.0, 2.0]})
    return rj.analysis.stability_margins(**dict(args, **kw))


NAN, INF = float("nan"), float("inf")

# (callable, kwargs, regex): the regex names the parameter and, where it fits, the value
CASES = [
    # models: rigid rotor, supports, race, balancer, speed, scene
    (RigidRotor, dict(mass=0.0), r"mass must be > 0, got 0\.0"),
    (RigidRotor, dict(mass=NAN), r"mass must be finite, got nan"),
    (P(RigidRotor, 1.0), dict(eccentricity=-0.1), r"eccentricity must be >= 0, got -0\.1"),
    (RigidRotor, dict(mass=[1.0, 2.0]), r"mass must have shape \(\), got shape \(2,\)"),
    (P(Supports, ky=1.0), dict(kx=-1.0), r"kx must be > 0, got -1\.0"),
    (P(Supports, kx=1.0), dict(ky=INF), r"ky must be finite, got inf"),
    (P(Supports, 1.0, 1.0), dict(cx=-0.5), r"cx must be >= 0, got -0\.5"),
    (Supports.isotropic, dict(k=0.0), r"k \(support stiffness\) must be > 0, got 0\.0"),
    (P(Race, r2=1.0), dict(r1=NAN), r"r1 .* must be finite, got nan"),
    (P(Race, 1.0, 1.0), dict(center=(0.0, 0.0, 1.0)), r"center must have shape \(2,\), got shape \(3,\)"),
    (Race.circular, dict(radius=-1.0), r"radius .* must be > 0, got -1\.0"),
    (P(Race.eccentric, 1.0), dict(offset=-0.1), r"offset .* must be >= 0, got -0\.1"),
    (P(AutoBalancer, race=Race.circular(1.0)), dict(mass=[]),
     r"weight mass must be a 1-D array .*got shape \(0,\)"),
    (P(AutoBalancer, race=Race.circular(1.0)), dict(mass=[0.1, NAN]),
     r"weight mass must be finite, got \[0\.1, +nan\]"),
    (P(AutoBalancer, [0.1], Race.circular(1.0)), dict(inertia_factor=0.5),
     r"inertia_factor must be >= 1.*got 0\.5"),
    (P(AutoBalancer, [0.1], Race.circular(1.0)), dict(kind="cube"),
     r"weight kind must be one of 'ball', .*got 'cube'"),
    (P(AutoBalancer, [0.1, 0.1], Race.circular(1.0)), dict(drag=[0.1, 0.1]), r"weight drag must have shape \(\)"),
    (P(AutoBalancer, [0.1]), dict(race="circle"), r"race must be a rotorjax\.models\.Race, got str"),
    (ConstantSpeed, dict(omega=NAN), r"omega \(speed\) must be finite, got nan"),
    (P(RunUp, 0.0), dict(acceleration=INF), r"acceleration must be finite, got inf"),
    (P(Scene, RigidRotor(1.0), ConstantSpeed(1.0)), dict(components=(Supports(1.0, 1.0), 3.0)),
     r"components\[1\] must be a rotorjax component .*got float"),
    (P(Scene, RigidRotor(1.0), ConstantSpeed(1.0)), dict(equations="newton"),
     r"equations must be one of 'auto', 'lagrange'; got 'newton'"),
    (P(balancing_angles, c=0.5), dict(N=0), r"N \(number of weights\) must be an integer >= 1, got 0"),
    (P(balancing_angles, c=0.5), dict(N=2.5), r"N \(number of weights\) must be an integer >= 1, got 2\.5"),
    (P(balancing_angles, 2), dict(c=1.5), r"cannot cancel an imbalance c = 1\.5: need 0 <= c <= 1"),
    (lambda angles: jeffcott().rest_state(angles), dict(angles=[0.0, 1.0, 2.0]),
     r"angles must have shape \(2,\), got shape \(3,\)"),
    # flexible: the FE rotor and its analyses
    (P(FlexibleRotor, d_out=0.03), dict(lengths=[]), r"element lengths must be a 1-D array of >= 1 elements"),
    (P(FlexibleRotor, d_out=0.03), dict(lengths=[0.1, 0.0]), r"element lengths must be > 0, got \[0\.1, 0\. *\]"),
    (P(FlexibleRotor, [0.1, 0.1], 0.03), dict(d_in=0.03),
     r"d_in \(inner diameter\) must be smaller than d_out .*0\.03 >= d_out = 0\.03"),
    (P(FlexibleRotor, [0.1, 0.1]), dict(d_out=[0.03, 0.03, 0.03]),
     r"d_out \(outer diameter\) must be a scalar or one value per element \(2\), got shape \(3,\)"),
    (P(FlexibleRotor, [0.1, 0.1], 0.03), dict(disks=((7, 1.0, 0.0, 0.0),)),
     r"disks\[0\]: disk at node 7 does not exist: the shaft has nodes 0\.\.2"),
    (P(FlexibleRotor, [0.1, 0.1], 0.03), dict(disks=((1.5, 1.0, 0.0, 0.0),)),
     r"disks\[0\]: disk must be an integer node index in 0\.\.2, got 1\.5"),
    (P(FlexibleRotor, [0.1, 0.1], 0.03), dict(disks=((1, -1.0, 0.0, 0.0),)),
     r"disks\[0\] mass must be > 0, got -1\.0"),
    (P(FlexibleRotor, [0.1, 0.1], 0.03), dict(disks=(1, 1.0, 0.0, 0.0)), r"disks must be a tuple of tuples"),
    (P(FlexibleRotor, [0.1, 0.1], 0.03), dict(bearings=((0, 1e6, 1e6),)),
     r"bearings\[0\] must be \(node, kxx, kyy, cxx, cyy\) or \(node, kxx, kyy, cxx, cyy, kxy, kyx, cxy, cyx\), or a "
     r"Bearing; a tuple of 3 values is ambiguous"),
    (P(FlexibleRotor, [0.1, 0.1], 0.03), dict(bearings=((-1, 1e6, 1e6, 0.0, 0.0),)),
     r"bearings\[0\]: bearing at node -1 does not exist: the shaft has nodes 0\.\.2"),
    (P(FlexibleRotor, [0.1, 0.1], 0.03), dict(bearings=((0, 1e6, NAN, 0.0, 0.0),)),
     r"bearings\[0\] kyy must be finite"),
    (P(FlexibleRotor, [0.1, 0.1], 0.03), dict(E=NAN), r"E \(Young's modulus\) must be finite, got nan"),
    (P(FlexibleRotor, [0.1, 0.1], 0.03), dict(nu=0.7),
     r"nu \(Poisson's ratio\) must be in \(-1, 0\.5\], got 0\.7"),
    (P(FlexibleRotor, [0.1, 0.1], 0.03), dict(theory="beam"), r"theory must be one of 'timoshenko', .*got 'beam'"),
    (P(FlexibleRotor, [0.1, 0.1], 0.03), dict(fixed_dofs=((0, 4),)),
     r"fixed_dofs\[0\]: fixed dof must be 0\.\.3 .*got 4"),
    (lambda n_modes: shaft().reduce(n_modes), dict(n_modes=0),
     r"n_modes \(reduction\) must be an integer in 1\.\.12, got 0"),
    (lambda n_modes: shaft().reduce(n_modes), dict(n_modes=2.5),
     r"n_modes \(reduction\) must be an integer in 1\.\.12, got 2\.5"),
    (lambda n_modes: shaft().reduce(n_modes), dict(n_modes=13),
     r"n_modes \(reduction\) must be an integer in 1\.\.12, got 13"),
    (lambda node: unbalance_response(shaft(), node, 1e-4, 0.0, [100.0]), dict(node=9),
     r"node: unbalance at node 9 does not exist: the shaft has nodes 0\.\.2"),
    (lambda probe_nodes: unbalance_response(shaft(), 1, 1e-4, 0.0, [100.0], probe_nodes), dict(probe_nodes=[1, 5]),
     r"probe_nodes\[1\]: probe at node 5 does not exist"),
    (lambda lo, hi: critical_speeds_1x(shaft(), lo, hi), dict(lo=10.0, hi=5.0),
     r"lo must be < hi, got lo = 10\.0, hi = 5\.0"),
    (lambda n_scan: critical_speeds_1x(shaft(), 1.0, 10.0, n_scan=n_scan), dict(n_scan=1),
     r"n_scan must be an integer >= 2, got 1"),
    (lambda n_modes: damped_frequencies(shaft(), 0.0, n_modes), dict(n_modes=0),
     r"n_modes must be an integer >= 1, got 0"),
    (modal_shaft, dict(n_modes=0), r"n_modes must be an integer >= 1, got 0"),
    (modal_shaft, dict(z0=1.0), r"z0 \(disk position\) must be in \(0, 1\).*got 1\.0"),
    (modal_shaft, dict(gyroscopic="exact"), r"gyroscopic must be one of 'paper', 'standard'; got 'exact'"),
    (P(exact_critical_speeds, 1.0), dict(z0=0.0), r"z0 \(disk position\) must be in \(0, 1\)"),
    (lambda lo, hi: pseudo_balanced_speeds(modal_shaft(), lo, hi), dict(lo=5.0, hi=NAN),
     r"hi must be finite, got nan"),
    (balls, dict(ball_radius=[1.0, 1.0, 1.0]),
     r"ball_radius must be a scalar or one value per ball \(2\), got shape \(3,\)"),
    (balls, dict(ball_mass=[0.01, -0.01]), r"ball_mass must be > 0, got \[ ?0\.01, -0\.01\]"),
    (balls, dict(shaft="shaft"), r"shaft must be a rotorjax\.flexible\.ModalShaft, got str"),
    (P(CantileverRotor, 0.7, 0.005, 0.03, 0.005, 0.025), dict(n_elements=0),
     r"n_elements must be an integer >= 1, got 0"),
    (P(CantileverRotor, 0.7, 0.005, 0.03, 0.005, 0.025), dict(n_elements=2.5),
     r"n_elements must be an integer >= 1, got 2\.5"),
    (P(CantileverRotor, 0.7, d_ratio=0.03, eta_i=0.005, eta_e=0.025), dict(beta=-1.0),
     r"beta \(disk inertia\) must be >= 0"),
    (lambda n_modes: cantilever().modal_basis(n_modes), dict(n_modes=100),
     r"n_modes must be an integer in 1\.\.8, got 100"),
    # contact
    (limiters, dict(clearance=0.0), r"limiter clearance chi must be > 0, got 0\.0"),
    (limiters, dict(clearance=[0.01, 0.01]),
     r"limiter clearance chi must be a scalar or one value per limiter \(3\)"),
    (limiters, dict(angles=[0.0, NAN]), r"limiter angles must be finite, got \[ ?0\., +nan\]"),
    (limiters, dict(angles=[]), r"limiter angles must be a 1-D array of >= 1"),
    (limiters, dict(stiffness=[850.0, -1.0, 850.0]), r"limiter stiffness kappa must be >= 0"),
    (limiters, dict(smoothing=0.0), r"smoothing \(contact regularisation length\) must be > 0, got 0\.0"),
    (scene004, dict(N=NAN), r"N \(spin speed\) must be finite, got nan"),
    (scene004, dict(eps=-1e-3), r"eps \(eccentricity\) must be >= 0, got -0\.001"),
    (scene004, dict(rotor="rotor"), r"rotor must be a rotorjax\.flexible\.CantileverRotor, got str"),
    (scene004, dict(limiters=(0.0, 1.0)), r"limiters must be a rotorjax\.contact\.Limiters or None, got tuple"),
    (scene004, dict(n_modes=0), r"n_modes must be an integer in 1\.\.8, got 0"),
    # identify
    (idf.BalancingMachine, dict(MACHINE, m=0.0), r"m \(rotor mass\) must be > 0, got 0\.0"),
    (idf.BalancingMachine, dict(MACHINE, k1=NAN), r"k1 \(support 1 stiffness\) must be finite, got nan"),
    (idf.BalancingMachine, dict(MACHINE, c2=-1.0), r"c2 \(support 2 damping\) must be >= 0, got -1\.0"),
    (trials, dict(X_trials=np.ones((3, 2))),
     r"X_trials must have shape \(n_planes, n_sensors\) = \(2, 2\) .*got shape \(3, 2\)"),
    (trials, dict(trials=np.array([1.0, 0.0])), r"trials: trial weight 1 is zero"),
    (trials, dict(X0=np.array([1.0, NAN])), r"X0 must be finite, got \[ ?1\., +nan\]"),
    (lsq, dict(X=np.ones(3)), r"K \(4, 2\) and X \(3,\): K must be \(measurements, planes\), X \(measurements,\)"),
    (lsq, dict(weights=[1.0, -1.0, 1.0, 1.0]), r"weights must be >= 0, got \[ ?1\., -1\., +1\., +1\.\]"),
    (lsq, dict(weights=[1.0, 1.0]),
     r"weights must be one non-negative number per measurement \(4\), got shape \(2,\)"),
    (lsq, dict(weights=[1.0, 0.0, 0.0, 0.0]),
     r"weights: 1 measurement\(s\) with a non-zero weight cannot determine 2"),
    (P(idf.split_onto_holes, 1.0), dict(hole_angles=[0.5]),
     r"hole_angles: need at least two hole positions, got 1"),
    (P(idf.split_onto_holes, hole_angles=[0.0, 1.0]), dict(W=complex(NAN, 0.0)), r"W must be finite"),
    (P(idf.permissible_unbalance, mass=2.0, omega=100.0), dict(G=0.0), r"G must be > 0, got 0\.0"),
    (P(idf.permissible_unbalance, 2.5, omega=100.0), dict(mass=-2.0), r"mass must be > 0, got -2\.0"),
    (P(idf.permissible_unbalance, 2.5, 2.0), dict(omega=INF), r"omega must be finite, got inf"),
    (balancing, dict(tolerance=0.0), r"tolerance must be > 0, got 0\.0"),
    (balancing, dict(max_runs=0), r"max_runs must be an integer >= 1, got 0"),
    (balancing, dict(unbalance=[1e-3]), r"unbalance must have shape \(2,\), got shape \(1,\)"),
    (P(idf.scalar_influence_matrix, 1.0), dict(planes_a=(0.5, 0.5)),
     r"planes_a \(plane distances A, C\): the two planes coincide"),
    (ident, dict(scene=1.0), r"scene must be a BalancingScene, a rotor file or a RotorModel; got float"),
    (ident, dict(params=("k9",)), r"params must name some of k1, k2, c1, c2, m, I; got k9"),
    (ident, dict(data=[1.0]), r"data: the balancing machine is identified from \(speeds, X\), an OrderTrack"),
    (ident, dict(data=(np.ones(5), np.ones((4, 2)))), r"data: \(speeds, X\) with speeds 1-D and X of shape"),
    (ident, dict(covariance="robust"), r"covariance must be one of auto, classical, sandwich, hac, got 'robust'"),
    (ident, dict(reference="maybe"), r"reference must be 'joint' or 'none', got 'maybe'"),
    (ident, dict(sigma=-1.0), r"sigma must be finite and > 0"),
    (ident, dict(n_starts=0), r"n_starts must be at least 1, got 0"),
    (ident, dict(weights="uniform"), r"weights: does not apply to the balancing machine; its options"),
    (ident, dict(block=2), r"block: applies to a run-up signal file only"),
    (ident, dict(fit_unbalance=(2,)), r"fit_unbalance \(2,\): the balancing machine fits the unbalances of its"),
    (ident_rotor, dict(fit_unbalance=True), r"fit_unbalance: name the nodes of the unbalances to fit"),
    (ident_rotor, dict(reference="joint"), r"reference: does not apply to a rotor file"),
    (ident_rotor, dict(weights="square"), r"--weights square: expected one of relative, uniform"),
    # solve
    (simulate, dict(t_span=(1.0, 0.0)), r"t_span must be increasing \(t1 > t0\), got \(1\.0, 0\.0\)"),
    (simulate, dict(t_span=(0.0, NAN)), r"t_span\[1\] must be finite, got nan"),
    (simulate, dict(t_span=5.0), r"t_span must be a pair \(t0, t1\), got 5\.0"),
    (simulate, dict(saveat=0), r"saveat as a count must be >= 2, got 0"),
    (simulate, dict(saveat=2.5), r"saveat must be None, an integer count >= 2 or a 1-D array of times, got 2\.5"),
    (simulate, dict(saveat=[0.0, 2.0]), r"saveat times must lie in t_span = \(0\.0, 1\.0\)"),
    (simulate, dict(rtol=0.0), r"rtol must be > 0, got 0\.0"),
    (simulate, dict(atol=-1e-9), r"atol must be > 0, got -1e-09"),
    (simulate, dict(rtol=NAN), r"rtol must be finite, got nan"),
    (simulate, dict(max_steps=0), r"max_steps must be an integer >= 1, got 0"),
    (simulate, dict(max_steps=10.5), r"max_steps must be an integer >= 1, got 10\.5"),
    (simulate, dict(solver="rk4"), r"solver must be 'auto', one of 'dopri5', 'dopri8', .*got 'rk4'"),
    (simulate, dict(y0=np.zeros(5)), r"y0 must have shape \(8,\) .*got shape \(5,\)"),
    (simulate, dict(dt0=-0.1), r"dt0 must be > 0, got -0\.1"),
    (simulate, dict(scene=3.0), r"scene must be a rotorjax scene .*a float has no state_size"),
    (events, dict(saveat=1), r"saveat \(number of saved states\) must be an integer >= 2, got 1"),
    (events, dict(block=0), r"block must be an integer >= 1, got 0"),
    (events, dict(max_events=0.5), r"max_events must be an integer >= 1, got 0\.5"),
    (events, dict(scene=scene004()), r"scene: simulate_events needs a scene with contacts"),
    # sweep
    (sweep, dict(grid={}), r"grid must be a non-empty dict"),
    (sweep, dict(grid={"a": []}), r"grid\['a'\] must hold at least one value, got shape \(0,\)"),
    (sweep, dict(grid={"a": [1.0, NAN]}), r"grid\['a'\] must be finite, got nan at index 1"),
    (sweep, dict(grid={"a": ["x"]}), r"grid\['a'\] must be an array of numbers, got \['x'\]"),
    (sweep, dict(mode="diagonal"), r"mode must be one of 'product', 'zip'; got 'diagonal'"),
    (sweep, dict(chunk_size=0), r"chunk_size must be an integer >= 1, got 0"),
    (sweep, dict(fn=3.0), r"fn must be a function of one grid point, got 3\.0"),
    (sweep, dict(batch="lockstep"),
     r"batch must be one of 'auto', 'vectorised', 'buffered', 'pallas', 'vmap'; got 'lockstep'"),
    (ivp_sweep, dict(lanes=0), r"lanes must be an integer >= 1, got 0"),
    (ivp_sweep, dict(steps_per_round=1.5), r"steps_per_round must be an integer >= 1, got 1\.5"),
    # batched integration
    (batch, dict(y0s=np.zeros((2, 5))), r"y0s must have shape \(N, 8\) for this scene .*got shape \(2, 5\)"),
    (batch, dict(y0s=np.zeros(8)), r"y0s must have shape \(N, state_size\), got shape \(8,\)"),
    (batch, dict(y0s=np.zeros((3, 8))), r"scenes must carry the batch axis N = 3 \(len\(y0s\)\)"),
    (batch, dict(method="scan"),
     r"method must be one of 'auto', 'vectorised', 'buffered', 'pallas', 'vmap'; got 'scan'"),
    (batch, dict(method="vectorised", solver="kvaerno5"),
     r"method='vectorised' needs an explicit Runge-Kutta solver .*got Kvaerno5; use method='buffered'"),
    (batch, dict(lanes=-1), r"lanes must be an integer >= 1, got -1"),
    (batch, dict(rtol=0.0), r"rtol must be > 0, got 0\.0"),
    (batch, dict(t_span=(1.0, 0.0)), r"t_span must be increasing"),
    (batch, dict(t_span=(0.0, [1.0, 0.5, 2.0])), r"t_span\[1\] must be a number or an array of 2 \(one per point\)"),
    (batch, dict(t_span=(0.0, [1.0, 0.0])), r"t_span must be increasing \(t1 > t0\), got \(0\.0, 0\.0\) at point 1"),
    (batch, dict(t_span=(0.0, [1.0, 2.0]), saveat=[0.0, 0.5]), r"saveat: with a time span per point give a count"),
    (batch, dict(events=True), r"simulate_batch\(events=True\) needs a scene with `contact_indicator`"),
    (batch, dict(method="pallas", saveat=5), r"saveat: method='pallas' returns the final state only"),
    (batch, dict(method="pallas", solver="kvaerno5"), r"solver"),
    (batch, dict(compiler_options=["xla_cpu_use_fusion_emitters"]),
     r"compiler_options must be a dict of XLA option names to values .*got \['xla_cpu_use_fusion_emitters'\]"),
    (sweep, dict(compiler_options={"xla_cpu_use_fusion_emitters": [False]}), r"compiler_options must be a dict"),
    # the Floquet analysis of many periodic motions (issue 32, item 4)
    (lambda orbits: rj.analysis.floquet_batch(orbits), dict(orbits=jeffcott()),
     r"orbits must be a batch of PeriodicOrbit references .*got Scene"),
    (lambda orbits: rj.analysis.floquet_batch(orbits), dict(orbits=orbit()),
     r"orbits must carry one batch axis in front .*got y0 of shape \(8,\), period of shape \(\)"),
    (margins, dict(reference_at=5), r"reference_at must be a function of one point .*got 5"),
    (margins, dict(points={"a": [1.0, 2.0], "b": [1.0]}), r"points: every entry must hold the same number"),
    # a time run's plan (issue 32, item 6)
    (plan, dict(modes="some"), r"modes must be 'auto', 'all' or a number of modes 1\.\.12, got 'some'"),
    (plan, dict(modes=2.5), r"modes must be 'auto', 'all' or a number of modes 1\.\.12, got 2\.5"),
    (plan, dict(modes=True), r"modes must be 'auto', 'all' or a number of modes 1\.\.12, got True"),
    (plan, dict(modes=13), r"modes = 13: the shaft has 12 coordinates \(modes must be 1\.\.12, 'auto' or 'all'\)"),
    (plan, dict(modes=0), r"modes = 0: the shaft has 12 coordinates"),
    (plan_reduced, dict(modes=2), r"modes = 2: only a finite-element rotor with its full shaft .* can be reduced"),
    # the analyses of models 002-004 (issue 29)
    (lambda dofs: rj.analysis.least_stable_whirl(cantilever(), 5.0, dofs), dict(dofs=(0, 99)),
     r"dofs must be two coordinate indices \(x, y\) in 0\.\.7, got \(0, 99\)"),
    (lambda speed: rj.analysis.modal003_response(modal_shaft(), speed), dict(speed=NAN), r"speed must be finite"),
    (lambda unbalances: rj.analysis.balancing_response(idf.BalancingMachine(**MACHINE), 100.0, [0.2, 0.8],
                                                       unbalances),
     dict(unbalances=[1e-3]), r"unbalances must have shape \(2,\), got shape \(1,\)"),
]


def _bad_keys(kwargs):
    """The arguments a case gets wrong (for MACHINE's, the one that differs)."""
    return [k for k, v in kwargs.items() if k not in MACHINE or v is not MACHINE[k]]


def _id(case):
    fn, kwargs, _ = case
    name = getattr(getattr(fn, "func", fn), "__name__", "call").strip("<>")
    return f"{name}-{_bad_keys(kwargs)[0]}"


@pytest.mark.parametrize("fn,kwargs,match", CASES, ids=[_id(c) for c in CASES])
def test_bad_input_raises_input_error_naming_the_parameter(fn, kwargs, match):
    with pytest.raises(InputError) as info:
        fn(**kwargs)
    msg = str(info.value)
    assert isinstance(info.value, ValueError)
    assert re.search(match, msg), f"{msg!r} does not match {match!r}"
    # the message names the argument the caller passed
    assert any(re.search(rf"(?<![A-Za-z0-9_]){re.escape(k)}(?![A-Za-z0-9_])", msg) for k in _bad_keys(kwargs)), msg


def test_enough_cases():
    assert len(CASES) >= 40


def test_valid_inputs_still_build():
    s = jeffcott()
    assert s.state_size == 8
    r = shaft()
    assert r.n_nodes == 3 and r.disk_nodes == (1,) and r.bearing_nodes == (0, 2)
    # integral floats and numpy integers are accepted as counts and nodes
    assert CantileverRotor(0.7, 0.005, 0.03, 0.005, 0.025, n_elements=4.0).n_elements == 4
    assert FlexibleRotor([0.1, 0.1], 0.03, disks=((np.int64(2), 1.0, 0.0, 0.0),)).disk_nodes == (2,)
    assert r.reduce(np.int32(4)).n_modes == 4
    assert contact_scene().n_contacts == 3
    assert Limiters(ANGLES, [0.01, 0.02, 0.03], 850.0).clearance.shape == (3,)
    assert balls(ball_mass=[]).n_balls == 0  # the shaft without a balancer
    assert idf.permissible_unbalance(6.3, 2.0, 1000.0) > 0
    assert balancing_angles(3, 0.5).shape == (3,)
    res = rj.sweep(lambda p: p["a"] * p["b"], {"a": [1.0, 2.0], "b": [3.0]}, chunk_size=1.0, progress=False)
    np.testing.assert_array_equal(res.values, [[3.0], [6.0]])


def test_checks_do_not_break_vmap_or_jit_of_construction():
    # vmapped stiffness through Supports.isotropic and the Supports constructor
    kx = jax.vmap(lambda k: Supports.isotropic(k, 0.1 * k).kx)(jnp.array([1.0, 2.0, 3.0]))
    np.testing.assert_allclose(kx, [1.0, 2.0, 3.0])

    # a whole planar scene built from traced parameters, inside jit and vmap
    def field(m, k, r, c):
        s = Scene(RigidRotor(m, 0.01), ConstantSpeed(2.0),
                  (Supports(k, 2 * k, 0.1, 0.1),
                   AutoBalancer(jnp.stack([c, c]), Race(r, r), 0.05, inertia_factor=1.0 + c)))
        return s.vector_field(0.0, s.rest_state(jnp.array([1.0, 2.0])))

    out = jax.jit(jax.vmap(field))(jnp.array([1.0, 2.0]), jnp.array([1.0, 3.0]), jnp.array([1.0, 0.5]),
                                   jnp.array([0.01, 0.02]))
    assert out.shape == (2, 8) and bool(jnp.all(jnp.isfinite(out)))
    # balancing angles traced in c (two weights)
    psi = jax.vmap(lambda c: balancing_angles(2, c))(jnp.array([0.2, 0.4]))
    assert psi.shape == (2, 2)


def test_checks_do_not_break_vmap_of_fe_and_contact_construction():
    def first_frequency(kb, d, L):
        r = FlexibleRotor(jnp.stack([L, L]), d, disks=((1, 5.0, 0.02, 0.04),),
                          bearings=((0, kb, kb, 0.0, 0.0), (2, kb, kb, 0.0, 0.0)))
        return damped_frequencies(r, 0.0, 1)[0]

    f = jax.jit(jax.vmap(first_frequency))(jnp.array([1e7, 2e7]), jnp.array([0.03, 0.03]), jnp.array([0.2, 0.2]))
    assert bool(f[1] > f[0])

    def force(chi, kappa):
        lim = Limiters(ANGLES, chi, kappa, 0.1)
        return lim.force(jnp.array([0.02, 0.0]), jnp.zeros(2), 5.0, 0.1)[0]

    assert jax.jit(jax.vmap(force))(jnp.array([0.01, 0.015]), jnp.array([850.0, 900.0])).shape == (2, 2)
    margin = jax.jit(jax.vmap(lambda mu: rj.analysis.linear_margin(
        CantileverRotor(mu, 0.005, 0.03, 0.005, 0.025, n_elements=2), 5.0)))(jnp.array([0.6, 0.7]))
    assert margin.shape == (2,)
    infl = jax.jit(jax.vmap(lambda k1: idf.BalancingMachine(**dict(MACHINE, k1=k1)).influence(100.0, 0.2)))(
        jnp.array([1e6, 2e6]))
    assert infl.shape == (2, 2)


def test_traced_values_keep_static_shape_checks_and_simulate_traces():
    # a traced vector where a scalar belongs is still caught (shapes are static)
    with pytest.raises(InputError, match=r"kx must have shape \(\), got a traced value of shape \(2,\)"):
        jax.vmap(lambda k: Supports(k, 1.0).kx)(jnp.ones((3, 2)))
    # counts fix the topology: a traced count is refused with a clear message
    with pytest.raises(InputError, match=r"n_elements .* concrete integer"):
        jax.vmap(lambda n: CantileverRotor(0.7, 0.005, 0.03, 0.005, 0.025, n_elements=n))(jnp.array([2, 3]))

    # simulate under vmap over a support stiffness (the checks see tracers, skip them)
    def final_x(k):
        s = Scene(RigidRotor(1.0, 0.01), ConstantSpeed(2.0), (Supports.isotropic(k, 0.5),))
        return rj.simulate(s, jnp.zeros(4), (0.0, 1.0), solver=diffrax.Tsit5(), rtol=1e-6, atol=1e-8).ys[-1, 0]

    xs = eqx.filter_jit(jax.vmap(final_x))(jnp.array([1.0, 4.0]))
    assert xs.shape == (2,) and bool(jnp.all(jnp.isfinite(xs)))
