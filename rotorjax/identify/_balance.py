"""Balancing with influence coefficients (model 002, eqs. 18-23) and beyond:
trial-weight estimation, two-plane and weighted least-squares corrections,
splitting onto holes, ISO 21940-11 grades, and a simulated balancing procedure
that counts runs (scalar vs vector coefficients).

Unbalances and correction weights are complex `U = mass * radius * e^{i angle}`
(kg m), angles from the once-per-revolution mark in the direction of rotation.
"""

import dataclasses

import numpy as np

from ..models._validate import InputError, as_count, as_numpy, check_choice, check_type
from ._machine import BalancingMachine


def influence_from_trials(X0, X_trials, trials):
    """Influence matrix from a run without and one run per trial weight (eqs. 20,
    22): `K[:, j] = (X_j - X0) / T_j`. `X0`: `(n_sensors,)`; `X_trials`:
    `(n_planes, n_sensors)`; `trials`: `(n_planes,)` complex trial unbalances."""
    X0 = as_numpy("X0", X0, dtype=np.complex128, ndim=1)
    X_trials = as_numpy("X_trials", X_trials, dtype=np.complex128, ndim=2)
    trials = as_numpy("trials", trials, dtype=np.complex128, ndim=1)
    if X0.size < 1 or trials.size < 1:
        raise InputError(f"X0 and trials need >= 1 sensor and >= 1 trial weight, got X0 shape {X0.shape}, "
                         f"trials shape {trials.shape}")
    if X_trials.shape != (trials.shape[0], X0.shape[0]):
        raise InputError(f"X_trials must have shape (n_planes, n_sensors) = ({trials.shape[0]}, {X0.shape[0]}) "
                         f"to match {trials.shape[0]} trial weights and {X0.shape[0]} sensors, got shape "
                         f"{X_trials.shape}")
    if np.any(trials == 0):
        raise InputError(f"trials: trial weight {int(np.argmax(trials == 0))} is zero (every trial must "
                         f"add a non-zero unbalance)")
    return ((X_trials - X0[None, :]) / trials[:, None]).T


def unbalance_from_vibration(K, X):
    """The unbalances that explain `X` (eq. 23 with square `K`; least squares otherwise)."""
    K = as_numpy("K", K, dtype=np.complex128, ndim=2)
    X = as_numpy("X", X, dtype=np.complex128)
    if K.shape[0] < 1 or K.shape[1] < 1 or X.shape[:1] != (K.shape[0],) or X.ndim > 2:
        raise InputError(f"K must be (n_measurements, n_planes) and X (n_measurements,) or "
                         f"(n_measurements, k), got K shape {K.shape}, X shape {X.shape}")
    if K.shape[0] == K.shape[1]:
        return np.linalg.solve(K, X)
    return np.linalg.lstsq(K, X, rcond=None)[0]


def least_squares_correction(K, X, weights=None):
    """Weighted least-squares correction for more sensors x speeds than planes:
    `W = -(K^H Q K)^-1 K^H Q X` with `Q = diag(weights)` (Goodman's method).
    `K`: `(n_measurements, n_planes)` stacked over speeds and sensors; `X`:
    `(n_measurements,)`. Minimises `sum Q |X + K W|^2`."""
    K = as_numpy("K", K, dtype=np.complex128, ndim=2)
    X = as_numpy("X", X, dtype=np.complex128)
    if K.shape[0] < 1 or K.shape[1] < 1 or X.shape != (K.shape[0],):
        raise InputError(f"K {K.shape} and X {X.shape}: K must be (measurements, planes), X (measurements,)")
    if weights is None:
        q = np.ones(K.shape[0])
    else:
        q = as_numpy("weights", weights, sign="nonnegative")
        if q.shape != (K.shape[0],):
            raise InputError(f"weights must be one non-negative number per measurement ({K.shape[0]}), "
                             f"got shape {q.shape}")
    if np.count_nonzero(q) < K.shape[1]:
        raise InputError(f"weights: {np.count_nonzero(q)} measurement(s) with a non-zero weight cannot "
                         f"determine {K.shape[1]} plane corrections")
    KhQ = K.conj().T * q[None, :]
    return -np.linalg.solve(KhQ @ K, KhQ @ X)


def split_onto_holes(W, hole_angles):
    """Split a correction `W` (complex) onto the two neighbouring holes of a plane
    (angles in rad): non-negative masses `(m_a, m_b)` at `(angle_a, angle_b)` whose
    vector sum is `W` (same units as `W`)."""
    W = complex(as_numpy("W", W, dtype=np.complex128, shape=()))
    h = np.sort(np.mod(as_numpy("hole_angles", hole_angles, ndim=1), 2 * np.pi))
    if h.size < 2:
        raise InputError(f"hole_angles: need at least two hole positions, got {h.size}")
    a = np.mod(np.angle(W), 2 * np.pi)
    i = np.searchsorted(h, a) % h.size
    lo, hi = h[i - 1], h[i]
    span = np.mod(hi - lo, 2 * np.pi)
    if span == 0 or span >= np.pi:
        raise InputError(f"hole_angles: the holes around the correction's angle ({float(a):.4g} rad) are at "
                         f"{float(lo):.4g} and {float(hi):.4g} rad, pi or more apart (or coincide): the "
                         f"split is not unique/positive")
    # W = m_a e^{i lo} + m_b e^{i hi}
    M = np.array([[np.cos(lo), np.cos(hi)], [np.sin(lo), np.sin(hi)]])
    m = np.linalg.solve(M, [W.real, W.imag])
    return (float(m[0]), float(lo)), (float(m[1]), float(hi))


def permissible_unbalance(G, mass, omega):
    """ISO 21940-11 permissible residual unbalance `U_per = 1000 G m / Omega` in
    g mm, for grade `G` (mm/s), rotor mass `m` (kg), speed `Omega` (rad/s)."""
    for name, v in (("G", G), ("mass", mass), ("omega", omega)):
        as_numpy(name, v, sign="positive")
    return 1000.0 * G * mass / omega


ISO_GRADES = (0.4, 1.0, 2.5, 6.3, 16.0, 40.0, 100.0, 250.0, 630.0, 1600.0, 4000.0)


def grade_reached(residual_gmm, mass, omega):
    """The finest ISO grade whose permissible unbalance holds the residual (g mm)."""
    as_numpy("residual_gmm", residual_gmm, sign="nonnegative", shape=())
    for name, v in (("mass", mass), ("omega", omega)):
        as_numpy(name, v, sign="positive", shape=())
    for G in ISO_GRADES:
        if residual_gmm <= permissible_unbalance(G, mass, omega):
            return G
    return None


@dataclasses.dataclass(frozen=True)
class BalancingRun:
    """Outcome of a simulated balancing procedure."""

    method: str
    runs: int
    balanced: bool
    residual: np.ndarray      # complex residual unbalance per plane (kg m)
    history: list             # |vibration| per run


def simulate_balancing(machine, planes, speed, unbalance, tolerance, method="vector", noise=0.0, seed=0,
                       max_runs=20, K_known=None):
    """Balance a simulated rotor, counting the machine runs (each measurement is a run).

    - "vector": the complex influence matrix `K_known` (from a previous item, as in
      the paper's batch production; default the model's) -> run 1 measures, the
      correction is `-K^-1 X` (eq. 23), the next run checks; repeat until the
      residual unbalance per plane is within `tolerance` (kg m).
    - "scalar": real coefficients `|K|` (eq. 4) and the unbalance taken along the
      measured vibration (model (1)): each correction uses `(|K|^-1 |X|) e^{i arg X}`.
    Sensor noise: complex Gaussian, `noise` times the initial vibration amplitude."""
    check_type("machine", machine, BalancingMachine, "a rotorjax.identify.BalancingMachine")
    check_choice("method", method, ("vector", "scalar"))
    planes = as_numpy("planes", planes, shape=(2,))
    as_numpy("speed", speed, sign="positive", shape=())
    U = as_numpy("unbalance", unbalance, dtype=np.complex128, shape=(2,)).copy()
    tolerance = float(as_numpy("tolerance", tolerance, sign="positive", shape=()))
    noise = float(as_numpy("noise", noise, sign="nonnegative", shape=()))
    max_runs = as_count("max_runs", max_runs, minimum=1)
    rng = np.random.default_rng(seed)
    K_true = np.asarray(machine.influence_matrix(speed, planes))
    K = K_true if K_known is None else as_numpy("K_known", K_known, dtype=np.complex128, shape=(2, 2))
    scale = np.max(np.abs(K_true @ U))
    history = []
    for run in range(1, max_runs + 1):
        X = K_true @ U + noise * scale * (rng.normal(size=2) + 1j * rng.normal(size=2)) / np.sqrt(2)
        history.append(float(np.max(np.abs(X))))
        if np.all(np.abs(U) <= tolerance):
            return BalancingRun(method, run, True, U, history)
        if method == "vector":
            D = np.linalg.solve(K, X)
        else:
            D = np.linalg.solve(np.abs(K), np.abs(X)) * np.exp(1j * np.angle(X))
        U = U - D
    return BalancingRun(method, max_runs, False, U, history)
