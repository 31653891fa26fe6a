"""Balancing with influence coefficients (model 002, eqs. 18-23) and beyond:
trial-weight estimation, two-plane and weighted least-squares corrections,
splitting onto holes, ISO 21940-11 grades, and a simulated balancing procedure
that counts runs (scalar vs vector coefficients).

Unbalances and correction weights are complex `U = mass * radius * e^{i angle}`
(kg m), angles from the once-per-revolution mark in the direction of rotation.
"""

import dataclasses

import numpy as np


def influence_from_trials(X0, X_trials, trials):
    """Influence matrix from a run without and one run per trial weight (eqs. 20,
    22): `K[:, j] = (X_j - X0) / T_j`. `X0`: `(n_sensors,)`; `X_trials`:
    `(n_planes, n_sensors)`; `trials`: `(n_planes,)` complex trial unbalances."""
    X0, X_trials, trials = (np.asarray(a, dtype=complex) for a in (X0, X_trials, trials))
    if X_trials.ndim != 2 or X_trials.shape[0] != trials.shape[0] or X_trials.shape[1] != X0.shape[0]:
        raise ValueError(f"trial runs {X_trials.shape} do not match {trials.shape[0]} trial weights and "
                         f"{X0.shape[0]} sensors")
    if np.any(trials == 0):
        raise ValueError("a trial weight is zero")
    return ((X_trials - X0[None, :]) / trials[:, None]).T


def unbalance_from_vibration(K, X):
    """The unbalances that explain `X` (eq. 23 with square `K`; least squares otherwise)."""
    K, X = np.asarray(K, dtype=complex), np.asarray(X, dtype=complex)
    if K.shape[0] == K.shape[1]:
        return np.linalg.solve(K, X)
    return np.linalg.lstsq(K, X, rcond=None)[0]


def least_squares_correction(K, X, weights=None):
    """Weighted least-squares correction for more sensors x speeds than planes:
    `W = -(K^H Q K)^-1 K^H Q X` with `Q = diag(weights)` (Goodman's method).
    `K`: `(n_measurements, n_planes)` stacked over speeds and sensors; `X`:
    `(n_measurements,)`. Minimises `sum Q |X + K W|^2`."""
    K, X = np.asarray(K, dtype=complex), np.asarray(X, dtype=complex)
    if K.ndim != 2 or X.shape != (K.shape[0],):
        raise ValueError(f"K {K.shape} and X {X.shape}: K must be (measurements, planes), X (measurements,)")
    q = np.ones(K.shape[0]) if weights is None else np.asarray(weights, dtype=float)
    if q.shape != (K.shape[0],) or np.any(q < 0):
        raise ValueError("weights must be one non-negative number per measurement")
    KhQ = K.conj().T * q[None, :]
    return -np.linalg.solve(KhQ @ K, KhQ @ X)


def split_onto_holes(W, hole_angles):
    """Split a correction `W` (complex) onto the two neighbouring holes of a plane
    (angles in rad): non-negative masses `(m_a, m_b)` at `(angle_a, angle_b)` whose
    vector sum is `W` (same units as `W`)."""
    W = complex(W)
    h = np.sort(np.mod(np.asarray(hole_angles, dtype=float), 2 * np.pi))
    if h.size < 2:
        raise ValueError("need at least two hole positions")
    a = np.mod(np.angle(W), 2 * np.pi)
    i = np.searchsorted(h, a) % h.size
    lo, hi = h[i - 1], h[i]
    span = np.mod(hi - lo, 2 * np.pi)
    if span == 0 or span >= np.pi:
        raise ValueError("neighbouring holes are pi or more apart: the split is not unique/positive")
    # W = m_a e^{i lo} + m_b e^{i hi}
    M = np.array([[np.cos(lo), np.cos(hi)], [np.sin(lo), np.sin(hi)]])
    m = np.linalg.solve(M, [W.real, W.imag])
    return (float(m[0]), float(lo)), (float(m[1]), float(hi))


def permissible_unbalance(G, mass, omega):
    """ISO 21940-11 permissible residual unbalance `U_per = 1000 G m / Omega` in
    g mm, for grade `G` (mm/s), rotor mass `m` (kg), speed `Omega` (rad/s)."""
    for name, v in (("G", G), ("mass", mass), ("omega", omega)):
        if not np.all(np.asarray(v) > 0):
            raise ValueError(f"{name} must be > 0, got {v}")
    return 1000.0 * G * mass / omega


ISO_GRADES = (0.4, 1.0, 2.5, 6.3, 16.0, 40.0, 100.0, 250.0, 630.0, 1600.0, 4000.0)


def grade_reached(residual_gmm, mass, omega):
    """The finest ISO grade whose permissible unbalance holds the residual (g mm)."""
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
    if method not in ("vector", "scalar"):
        raise ValueError(f"method must be 'vector' or 'scalar', got {method!r}")
    rng = np.random.default_rng(seed)
    K_true = np.asarray(machine.influence_matrix(speed, planes))
    K = K_true if K_known is None else np.asarray(K_known)
    U = np.asarray(unbalance, dtype=complex).copy()
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
