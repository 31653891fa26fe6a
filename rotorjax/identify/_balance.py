"""The one balancing engine, for every linear scene (`balance`): model 002's
balancing machine from its runs, a rotor file's flexible rotor from its phasor
runs.

1. The runs: phasor runs (`PhasorData`: a baseline run, one trial run per plane);
   a balancing machine's runs (`BalancingData`) become phasor runs
   (`_influence.machine_runs`).
2. The influence matrix `A` (rows: the baseline's (speed, sensor) pairs; columns:
   the planes): from the trial runs, from the scene's model, or both (the trials'
   used, compared with the model's: a warning beyond 20 %) (`_influence`).
3. The corrections `W` (complex unbalances to ADD, kg m): least squares over every
   speed and sensor (the exact solve for as many measurements as planes) or min-max
   (`_corrections`).
4. The report: the vibration before and predicted after, the residual unbalance
   (the predicted vibration's equivalent unbalance, plus the corrections'
   uncertainty from the baseline's noise where the runs state it), ISO 21940-11's
   permissible unbalance and the grades before and after, ISO 21940-12's plane and
   speed counts from the model's critical speeds (`_iso`).
5. Presentation: a correction as a mass at a `radius` (g) and split onto the two
   nearest of `holes` equally spaced holes, for any scene.
"""

import dataclasses

import numpy as np

from .._errors import InputError, NumericalError
from ..models._balancing_machine import BalancingMachine
from ..models._validate import as_count, as_numpy, check_choice, check_type
from ._corrections import least_squares_balance, minmax_balance, split_onto_holes
from ._influence import (MACHINE_PHASES, _DIRS, _baseline_rows, _check_planes, _check_unbalance_data, _label, _row,
                         _same_speed, _speed_groups, influence_from_phasor_runs, machine_runs, model_influence)
from ._iso import ISO_GRADES, equivalent_unbalance, grade_reached, iso_12, permissible_unbalance, total_mass
from ._signals import BalancingData

#: the model's influence coefficients "agree" with the trial runs' within this (relative)
MODEL_TOLERANCE = 0.2
#: the phase convention of a rotor file's phasors
ROTOR_PHASES = ("unbalance phase as in unbalance_response: force U W^2 (cos(W t + phase), sin(W t + phase)); the "
                "corrections are weights to ADD")


@dataclasses.dataclass(frozen=True, eq=False)
class Balancing:
    """A balancing's corrections and report (see `balance`), for every scene.

    - `path`, `planes`, `speeds` `(m,)`, `sensors` (m `(node, dir)`): the measurements
      (a balancing machine's sensor `k` is node `k`; `sensor_names` name them as the
      file does); `plane_key`: what a plane is ("node" of a rotor file, "plane" of the
      machine); `phase_convention`;
    - `A` `(m, n_planes)` (the influence matrix used) and its `condition` (scaled
      columns), `X0`, `W` (complex corrections to ADD, kg m), `predicted = X0 + A W`;
      `weights` or None; `method`, `influence`; `objective`: the minimised value
      (least squares: `||w |predicted|||_2`; min-max: `max w |predicted|`);
    - `before_max`, `after_max`, `before_rms`, `after_rms` (m): `|X0|`, `|predicted|`;
    - `A_model`, `influence_difference` (`(n_speeds, n_planes)` relative difference
      of the model's columns from the trials', per distinct speed) or None;
    - ISO: `rotor_mass` (kg), `service_speed` (rad/s), `grade` (requested, mm/s),
      `permissible_gmm`, `residual_gmm` (the predicted vibration's equivalent
      unbalance plus `noise_gmm`, the corrections' uncertainty from the baseline's
      noise), `initial_gmm`, `grade_reached`, `grade_before`, `criticals` (forward
      critical speeds below 1.1 x service, rad/s, or None without a rotor model),
      `explanation` (sentences);
    - presentation: `radius` (m, a correction as a mass there) or None, `holes`;
    - `warnings`: sentences for the user.
    """

    path: str
    planes: tuple
    speeds: np.ndarray
    sensors: tuple
    A: np.ndarray
    X0: np.ndarray
    W: np.ndarray
    predicted: np.ndarray
    method: str
    influence: str
    weights: object
    objective: float
    condition: float
    before_max: float
    after_max: float
    before_rms: float
    after_rms: float
    A_model: object
    influence_difference: object
    rotor_mass: object
    service_speed: float
    grade: float
    permissible_gmm: object
    residual_gmm: float
    noise_gmm: float
    initial_gmm: float
    grade_reached: object
    grade_before: object
    criticals: object
    explanation: tuple
    warnings: tuple
    plane_key: str = "node"
    phase_convention: str = ROTOR_PHASES
    sensor_names: tuple = ()
    radius: float | None = None
    holes: int | None = None

    @property
    def corrections(self) -> tuple:
        """`(plane, magnitude kg m, phase rad)` per plane: the unbalance to ADD."""
        return tuple((p, float(abs(w)), float(np.angle(w))) for p, w in zip(self.planes, self.W))

    @property
    def balancing_speeds(self) -> list:
        """The distinct speeds balanced at (rad/s)."""
        return _speed_groups(self.speeds)

    @property
    def speed(self) -> float:
        """The service speed (rad/s; a balancing machine's: its base run's)."""
        return self.service_speed

    @property
    def K(self) -> np.ndarray:
        """The influence matrix (model 002's name for `A`)."""
        return self.A

    @property
    def masses_g(self) -> np.ndarray:
        """The corrections as masses at `radius`, g (complex: with their angles)."""
        if self.radius is None:
            raise InputError("masses_g: the balancing was not given a correction radius (radius=...)")
        return np.asarray(self.W) / self.radius * 1e3

    def correction_table(self) -> list:
        """One record per plane: the unbalance to add (kg m) and its angle, and with a
        `radius` the mass there (g) and its split onto the two nearest `holes`."""
        out = []
        for p, w in zip(self.planes, self.W):
            deg = float(np.degrees(np.angle(w)) % 360)
            c = {self.plane_key: p, "magnitude": float(abs(w)), "unbalance_kg_m": float(abs(w)), "phase_deg": deg,
                 "angle_deg": deg}
            if self.radius is not None:
                c.update(mass_g=float(abs(w) / self.radius * 1e3), radius_m=self.radius)
                if self.holes:
                    holes = np.arange(self.holes) * 2 * np.pi / self.holes
                    (ma, aa), (mb, ab) = split_onto_holes(w / self.radius * 1e3, holes)
                    c["holes"] = [{"angle_deg": float(np.degrees(aa)), "mass_g": ma},
                                  {"angle_deg": float(np.degrees(ab)), "mass_g": mb}]
            out.append(c)
        return out

    def as_dict(self) -> dict:
        n_crit = None if self.criticals is None else len(self.criticals)
        comparison = None
        if self.influence_difference is not None:
            comparison = [{"plane": p, "speed": s, "relative_difference": float(self.influence_difference[k, j])}
                          for k, s in enumerate(self.balancing_speeds) for j, p in enumerate(self.planes)]
        mass, service = self.rotor_mass, self.service_speed
        return {
            "data": self.path, "runs_file": self.path,
            "planes": list(self.planes),
            "speeds": self.balancing_speeds,
            "speed_rad_s": service, "speed_rpm": service * 30 / np.pi,
            "sensors": list(self.sensor_names) or [f"{n}{d}" for n, d in dict.fromkeys(self.sensors)],
            "phase_convention": self.phase_convention,
            "corrections": self.correction_table(),
            "influence_matrix": [[{"magnitude": float(abs(k)), "angle_deg": float(np.degrees(np.angle(k)))}
                                  for k in row] for row in self.A],
            "influence_condition_number": self.condition,
            "vibration_before": [float(abs(x)) for x in self.X0],
            "predicted_vibration_after": [float(abs(x)) for x in self.predicted],
            "residual": {
                "before_max": self.before_max, "after_max": self.after_max,
                "before_rms": self.before_rms, "after_rms": self.after_rms,
                "per_point": [{"speed": float(s), "node": n, "direction": d, "before": float(abs(b)),
                               "after": float(abs(a))}
                              for s, (n, d), b, a in zip(self.speeds, self.sensors, self.X0, self.predicted)],
            },
            "method": self.method,
            "objective": self.objective,
            "influence": self.influence,
            "influence_comparison": comparison,
            "residual_unbalance_g_mm": self.residual_gmm,
            "rotor_mass_kg": mass,
            "iso_grade_before": self.grade_before,
            "iso_grade_reached": self.grade_reached,
            "permissible_unbalance_g_mm": None if mass is None else
            {str(G): permissible_unbalance(G, mass, service) for G in (1.0, 2.5, 6.3, 16.0)},
            "iso": {
                "rotor_mass_kg": mass,
                "service_speed_rad_s": service,
                "grade_requested": self.grade,
                "permissible_unbalance_g_mm": self.permissible_gmm,
                "residual_unbalance_g_mm": self.residual_gmm,
                "noise_unbalance_g_mm": self.noise_gmm,
                "initial_unbalance_g_mm": self.initial_gmm,
                "grade_reached": self.grade_reached,
                "grade_before": self.grade_before,
                "critical_speeds_rad_s": None if self.criticals is None else list(self.criticals),
                "n_criticals": n_crit,
                "planes_needed_n_plane": n_crit,
                "planes_needed_n_plus_2": None if n_crit is None else n_crit + 2,
                "planes_used": len(self.planes),
                "explanation": list(self.explanation),
            },
            "warnings": list(self.warnings),
        }


def _influence(data, planes, speeds, influence, scene):
    """`(speeds, sensors, X0, A, A_model, difference, warnings)` of the runs (see `balance`)."""
    warnings, A_model, diff = [], None, None
    if influence == "model":
        _, _, _, sp, sensors, X0 = _baseline_rows(data, speeds)
    else:
        sp, sensors, X0, A = influence_from_phasor_runs(data, planes, speeds)
    if X0.size < len(planes):
        raise InputError(f"{_label(data)}: {X0.size} measurement(s) at the chosen speeds cannot determine "
                         f"{len(planes)} plane corrections (underdetermined: measure more speeds or sensors, or "
                         f"use fewer planes)")
    if influence != "trials":
        A_model = model_influence(scene, sp, sensors, planes)
        if influence == "model":
            A = A_model
        else:
            grid = _speed_groups(sp)
            diff = np.zeros((len(grid), len(planes)))
            for k, s in enumerate(grid):
                r = np.array([_same_speed(v, s) for v in sp])
                diff[k] = np.linalg.norm(A_model[r] - A[r], axis=0) / np.linalg.norm(A[r], axis=0)
            for j, p in enumerate(planes):
                bad = [(grid[k], diff[k, j]) for k in range(len(grid)) if diff[k, j] > MODEL_TOLERANCE]
                if bad:
                    warnings.append(f"plane {p}: the model's influence coefficients differ from the trial runs' "
                                    f"by " + ", ".join(f"{100 * d:.0f} % at {s:.4g} rad/s" for s, d in bad)
                                    + f" (> {100 * MODEL_TOLERANCE:.0f} %): the model does not represent the "
                                    f"machine there; the corrections use the trial runs'")
    return sp, sensors, X0, A, A_model, diff, warnings


def _noise_gmm(data, A, speeds, sensors):
    """The corrections' uncertainty from the baseline's noise (g mm, summed over the
    planes): `sigma_W = sqrt(|A^+|^2 sigma_X^2)`, 0 where the runs state no noise."""
    if data.sigma is None:
        return 0.0
    _, runs, rows, _, _, _ = _baseline_rows(data, None)
    sig = {(float(data.speed[i]), int(data.node[i]), _DIRS[int(data.direction[i])]): float(data.sigma[i])
           for i in rows}
    s = np.array([next(v for (w, n, d), v in sig.items() if _same_speed(w, ws) and (n, d) == sensor)
                  for ws, sensor in zip(speeds, sensors)])
    return float(np.sum(np.sqrt(np.abs(np.linalg.pinv(A)) ** 2 @ s**2))) * 1e6


def balance(data, planes=None, *, speeds=None, method="ls", influence="trials", scene=None, rotor_mass=None,
            service_speed=None, grade=None, weights=None, radius=None, holes=None) -> Balancing:
    """Correction weights for any linear scene from its runs (see the module).

    **Arguments:**
    - `data`: a rotor file's phasor runs (`PhasorData`: a baseline run without a
      trial weight and, for `influence` "trials" or "both", one trial run per plane),
      or a balancing machine's runs (`BalancingData`, `balancing_runs`).
    - `planes`: the correction planes (a rotor file's nodes; the machine's plane
      numbers); default every plane that carries a trial weight in the data.
    - `speeds`: the baseline's speeds to balance at (rad/s; None: all).
    - `method`: "ls" (least squares over all speeds and sensors; the exact solve for
      as many measurements as planes) or "minmax" (the smallest worst residual).
    - `influence`: "trials" (from the trial runs), "model" (from `scene`; only the
      baseline run is needed) or "both" (the trials' are used and compared with the
      model's: a warning when they differ by more than 20 %).
    - `scene`: the model: a rotor file's rotor (`FlexibleRotor`, `ReducedRotor`,
      `RotorScene`: the model influence, the critical speeds, the default rotor mass)
      or a `BalancingScene` (the model influence, the rotor mass).
    - `rotor_mass` (kg; default the model's), `service_speed` (rad/s; default the
      largest speed in the data), `grade` (ISO 21940-11, mm/s; default 2.5).
    - `weights`: > 0 per row (as `influence_from_phasor_runs` orders them), or None.
    - `radius` (m), `holes` (>= 2): present each correction as a mass at `radius`
      and split it onto the two nearest of `holes` equally spaced holes.

    **Returns:** a `Balancing`.

    **Raises:** `InputError` naming the plane, run, speed or option;
    `NumericalError` when no finite correction comes out."""
    from ..analysis._frf import full_rotor
    from ..models._balancing_machine import BalancingScene

    check_choice("method", method, ("ls", "minmax"))
    check_choice("influence", influence, ("trials", "model", "both"))
    key, names, phases = "node", (), ROTOR_PHASES
    if isinstance(data, BalancingData):
        key, names, phases = "plane", tuple(data.sensors), MACHINE_PHASES
        planes = data.planes if planes is None else planes
        data = machine_runs(data)
    elif planes is None:
        _check_unbalance_data(data)
        planes = sorted({int(n) for n in data.trial_node if n >= 0})
        if not planes:
            raise InputError(f"planes: {data.path} has no trial runs to take the correction planes from; name "
                             "them, e.g. planes=[2, 4]")
    full = machine = None
    if isinstance(scene, BalancingScene):
        machine = scene
    elif scene is not None:
        scene = full_rotor(scene)
        full = scene.full_rotor
    if influence in ("model", "both") and scene is None:
        raise InputError(f"influence={influence!r} needs the scene's model (scene=...); use influence='trials' "
                         f"without one")
    planes = _check_planes(planes, full)
    if full is not None:
        _check_unbalance_data(data)
        node = np.asarray(data.node)
        bad = np.flatnonzero((node < 0) | (node >= full.n_nodes))
        if bad.size:
            i = int(bad[0])
            raise InputError(f"{_label(data)}: {_row(data, i)}: node {int(node[i])} is not a node of the rotor "
                             f"(0..{full.n_nodes - 1})")
    for name, v in (("rotor_mass", rotor_mass), ("service_speed", service_speed), ("grade", grade),
                    ("radius", radius)):
        if v is not None:
            as_numpy(name, v, sign="positive", shape=())
    holes = None if holes is None else as_count("holes", holes, minimum=2)
    grade = 2.5 if grade is None else float(grade)
    sp, sensors, X0, A, A_model, diff, warnings = _influence(data, planes, speeds, influence, scene)
    if weights is not None:
        from ._corrections import _check_system

        _check_system(A, X0, weights)
    if method == "ls":
        W = least_squares_balance(A, X0, weights)
    else:
        W, _ = minmax_balance(A, X0, weights)
    if not np.all(np.isfinite(W)):
        raise NumericalError("balance: the corrections are not finite (a singular influence matrix: do two planes "
                             "act alike on the sensors?)")
    cond = float(np.linalg.cond(A / np.linalg.norm(A, axis=0)[None, :]))
    if cond > 1e6:
        warnings.append(f"the influence matrix is ill-conditioned (condition number {cond:.2g} with scaled "
                        f"columns): the planes act almost alike on the sensors, so the corrections are uncertain")
    pred = X0 + A @ W
    w = np.ones(X0.size) if weights is None else np.asarray(weights, dtype=float)
    wr = w * np.abs(pred)
    objective = float(np.max(wr)) if method == "minmax" else float(np.sqrt(np.sum(wr**2)))
    service = float(np.max(np.asarray(data.speed))) if service_speed is None else float(service_speed)
    default_mass = total_mass(full) if full is not None else (float(machine.machine.m) if machine else None)
    mass = default_mass if rotor_mass is None else float(rotor_mass)
    noise = _noise_gmm(data, A, sp, sensors)
    residual, initial = equivalent_unbalance(A, pred) * 1e6 + noise, equivalent_unbalance(A, X0) * 1e6
    if key == "plane" or machine is not None:
        crit, text12 = None, ["A balancing machine's rotor is rigid: ISO 21940-11 applies (ISO 21940-12's plane "
                              "and speed counts are for flexible rotors)."]
    else:
        crit, text12 = iso_12(scene, planes, _speed_groups(sp), service)
    if mass is None:
        U_per = reached = before = None
        text11 = ["ISO 21940-11: give the rotor mass (or the rotor model) for the permissible residual "
                  "unbalance and the grade reached."]
    else:
        U_per = permissible_unbalance(grade, mass, service)
        reached, before = grade_reached(residual, mass, service), grade_reached(initial, mass, service)
        text11 = [f"ISO 21940-11: a {mass:.4g} kg rotor at {service:.4g} rad/s may keep U_per = {U_per:.4g} g mm "
                  f"for grade G{grade:g}; the predicted residual corresponds to {residual:.4g} g mm (before: "
                  f"{initial:.4g} g mm), "
                  + (f"grade G{reached:g} reached" if reached is not None else
                     f"coarser than G{ISO_GRADES[-1]:g}")
                  + (f" (before: G{before:g})." if before is not None else ".")]
    return Balancing(
        path=_label(data), planes=planes, speeds=np.asarray(sp), sensors=tuple(sensors), A=A, X0=X0, W=W,
        predicted=pred, method=method, influence=influence, weights=None if weights is None else w,
        objective=objective, condition=cond, before_max=float(np.max(np.abs(X0))),
        after_max=float(np.max(np.abs(pred))), before_rms=float(np.sqrt(np.mean(np.abs(X0) ** 2))),
        after_rms=float(np.sqrt(np.mean(np.abs(pred) ** 2))), A_model=A_model, influence_difference=diff,
        rotor_mass=mass, service_speed=service, grade=grade, permissible_gmm=U_per, residual_gmm=residual,
        noise_gmm=noise, initial_gmm=initial, grade_reached=reached, grade_before=before,
        criticals=None if crit is None else tuple(crit), explanation=tuple(text11 + text12),
        warnings=tuple(warnings), plane_key=key, phase_convention=phases, sensor_names=names,
        radius=None if radius is None else float(radius), holes=holes)


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
