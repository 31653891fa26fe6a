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
from ..models._balancing_machine import BalancingMachine


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


@dataclasses.dataclass(frozen=True, eq=False)
class Balancing:
    """Corrections from the runs of an influence-coefficient balancing (see `balance`).

    - `speed` (rad/s), `planes`, `sensors`, `runs_file`: what was measured;
    - `K`: the influence matrix `(n_sensors, n_planes)`; `condition`: its condition number;
    - `X0`, `predicted`: the vibration before and as predicted after the corrections;
    - `W`: the correction unbalances (kg m, complex, per plane);
    - `radius` (m), `holes` (or None), `rotor_mass` (kg): the correction radius, the
      number of equally spaced holes a correction is split onto, the rotor's mass;
    - `residual_gmm`, `initial_gmm`: the residual unbalance left by the phasors' noise
      (`sigma_X = rms residual sqrt(2 / samples)` propagated through `K^+`) and the
      corrected unbalance, g mm;
    - `warnings`: sentences for the user (an ill-conditioned `K`).
    """

    runs_file: str
    speed: float
    planes: tuple
    sensors: tuple
    K: np.ndarray
    condition: float
    X0: np.ndarray
    W: np.ndarray
    predicted: np.ndarray
    radius: float
    holes: object
    rotor_mass: float
    residual_gmm: float
    initial_gmm: float
    warnings: tuple

    @property
    def masses_g(self) -> np.ndarray:
        """Correction masses at `radius`, g (complex: with their angles)."""
        return np.asarray(self.W) / self.radius * 1e3

    def corrections(self) -> list:
        """One dict per plane: unbalance, angle, mass at the radius, and the split onto holes."""
        out = []
        for p, w in zip(self.planes, self.W):
            c = {"plane": p, "unbalance_kg_m": float(abs(w)), "angle_deg": float(np.degrees(np.angle(w)) % 360),
                 "mass_g": float(abs(w) / self.radius * 1e3), "radius_m": self.radius}
            if self.holes:
                holes = np.arange(self.holes) * 2 * np.pi / self.holes
                (ma, aa), (mb, ab) = split_onto_holes(w / self.radius * 1e3, holes)
                c["holes"] = [{"angle_deg": float(np.degrees(aa)), "mass_g": ma},
                              {"angle_deg": float(np.degrees(ab)), "mass_g": mb}]
            out.append(c)
        return out

    def as_dict(self) -> dict:
        speed = self.speed
        return {
            "runs_file": self.runs_file, "speed_rad_s": speed, "speed_rpm": speed * 30 / np.pi,
            "sensors": list(self.sensors),
            "phase_convention": "angles from the once-per-revolution mark, in the direction of rotation",
            "influence_matrix": [[{"magnitude": float(abs(k)), "angle_deg": float(np.degrees(np.angle(k)))}
                                  for k in row] for row in self.K],
            "corrections": self.corrections(), "vibration_before": [float(abs(x)) for x in self.X0],
            "predicted_vibration_after": [float(abs(x)) for x in self.predicted],
            "residual_unbalance_g_mm": self.residual_gmm, "influence_condition_number": self.condition,
            "warnings": list(self.warnings),
            "rotor_mass_kg": self.rotor_mass,
            "iso_grade_before": grade_reached(self.initial_gmm, self.rotor_mass, speed),
            "iso_grade_reached": grade_reached(self.residual_gmm, self.rotor_mass, speed),
            "permissible_unbalance_g_mm": {str(G): permissible_unbalance(G, self.rotor_mass, speed)
                                           for G in (1.0, 2.5, 6.3, 16.0)},
        }


def balance(data, radius=0.01, holes=None, rotor_mass=10.0) -> Balancing:
    """Correction weights from the runs of a balancing (a `BalancingData`, see
    `balancing_runs`): the influence matrix from the trial runs (eqs. 20, 22), the
    corrections (eq. 23 for as many sensors as planes, least squares otherwise), the
    predicted vibration after, and the residual unbalance and ISO 21940-11 grades.

    **Arguments:** `data`, the correction `radius` (m), `holes` (split each
    correction onto the two nearest of this many equally spaced holes, >= 2; None:
    no split), the `rotor_mass` (kg, for the ISO grades).

    **Raises:** `NumericalError` when the corrections are not finite (a singular
    influence matrix)."""
    from .._errors import NumericalError

    as_numpy("radius", radius, sign="positive", shape=())
    as_numpy("rotor_mass", rotor_mass, sign="positive", shape=())
    if holes is not None:
        holes = as_count("holes", holes, minimum=2)
    X0 = data.X0
    K = influence_from_trials(X0, data.X_trials, data.trial_unbalances)
    W = -unbalance_from_vibration(K, X0) if K.shape[0] == K.shape[1] else least_squares_correction(K, X0)
    if not np.all(np.isfinite(W)):
        raise NumericalError("balance: the corrections are not finite (a singular influence matrix: do two trial "
                             "planes act alike?)")
    warnings = []
    cond = float(np.linalg.cond(K))
    if cond > 1e6:
        warnings.append(f"the influence matrix is ill-conditioned (condition number {cond:.2g}): the planes act "
                        "almost alike on the sensors, so the corrections are uncertain")
    sigma_X = np.asarray(data.base["residual_rms"]) * np.sqrt(2.0 / max(data.n_samples_base, 1))
    sigma_U = np.sqrt(np.abs(np.linalg.pinv(K)) ** 2 @ sigma_X**2)
    return Balancing(runs_file=data.path, speed=data.speed, planes=tuple(data.planes), sensors=tuple(data.sensors),
                     K=K, condition=cond, X0=X0, W=W, predicted=X0 + K @ W, radius=float(radius), holes=holes,
                     rotor_mass=float(rotor_mass), residual_gmm=float(np.sum(sigma_U)) * 1e6,
                     initial_gmm=float(np.sum(np.abs(W))) * 1e6, warnings=tuple(warnings))
