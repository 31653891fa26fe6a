"""Balancing a flexible finite-element rotor from measured 1x phasors: several
correction planes (FE nodes), several speeds, several sensors.

- the influence matrix `A` from a baseline run and one trial run per plane
  (`influence_from_phasor_runs`), or from the rotor model (`model_influence`);
- the corrections `W` (complex unbalances to ADD, kg m, `U e^{i phase}` in the
  phase convention of `unbalance_response`) minimising the residual vibration
  `X0 + A W` in the least-squares sense (`least_squares_balance`, Goodman's
  method, `_balance.least_squares_correction`) or in the worst point
  (`minmax_balance`, a second-order cone program solved by Clarabel);
- `balance_rotor`: all of it from a phasor file, with the ISO 21940-11 grade of
  the residual and ISO 21940-12's plane and speed counts for flexible rotors.

Rows of `A` and `X0` are the (speed, sensor) pairs of the baseline run, sensors
`(node, "x" | "y")`, sorted by speed, node, direction.
"""

import dataclasses

import numpy as np

from .._errors import InputError, NumericalError
from ..models._fe_rotor import DOFS_PER_NODE
from ..models._validate import as_numpy, check_choice
from ._phasor_file import PhasorData
from ._balance import ISO_GRADES, grade_reached, least_squares_correction, permissible_unbalance

#: speeds of two runs are the same when they differ by at most this, relative
SPEED_RTOL = 1e-6
#: the model's influence coefficients "agree" with the trial runs' within this (relative)
MODEL_TOLERANCE = 0.2
_DIRS = ("x", "y")


def _same_speed(a, b):
    return abs(a - b) <= SPEED_RTOL * max(abs(a), abs(b))


def _label(data):
    return (data.path if isinstance(data, PhasorData) else None) or "phasor data"


def _row(data, i):
    return data.row(i) if isinstance(data, PhasorData) else f"data row {i + 1}"


def _check_unbalance_data(data):
    if not isinstance(data, PhasorData):
        raise InputError(f"data must be a PhasorData (read_phasors / make_phasors), got {type(data).__name__}")
    if data.frequency is not None:
        raise InputError(f"{_label(data)}: an impact-test (FRF) file has no unbalance runs to balance with; give "
                         f"a file of 1x unbalance phasors (a baseline run and trial runs)")


def _check_planes(planes, rotor=None):
    """Distinct integer nodes (of `rotor`, when given) as a tuple."""
    try:
        items = list(planes)
    except TypeError:
        items = [planes]
    if not items:
        raise InputError("planes: give at least one correction plane (an FE node)")
    out = []
    for p in items:
        try:
            ok = not isinstance(p, (bool, np.bool_, str, bytes)) and float(p) == int(p)
        except (TypeError, ValueError, OverflowError):
            ok = False
        if not ok:
            raise InputError(f"planes: {p!r} is not a node number (an integer)")
        p = int(p)
        if p < 0:
            raise InputError(f"planes: node {p} is not a node (nodes are numbered from 0)")
        if rotor is not None and p >= rotor.n_nodes:
            raise InputError(f"planes: node {p} is not a node of the rotor (nodes 0..{rotor.n_nodes - 1})")
        if p in out:
            raise InputError(f"planes: node {p} is given twice")
        out.append(p)
    return tuple(out)


def _runs(data):
    """`{run: (row indices, trial or None)}` with trial `(node, magnitude, phase)`."""
    run = np.asarray(data.run)
    out = {}
    for r in np.unique(run):
        idx = np.flatnonzero(run == r)
        tn = int(np.asarray(data.trial_node)[idx[0]])
        trial = None if tn < 0 else (tn, float(np.asarray(data.trial_magnitude)[idx[0]]),
                                     float(np.asarray(data.trial_phase)[idx[0]]))
        out[int(r)] = (idx, trial)
    return out


def _baseline(data, runs):
    base = [r for r, (_, t) in runs.items() if t is None]
    if not base:
        raise InputError(f"{_label(data)}: no baseline run (a run without a trial weight: empty trial_node, "
                         f"trial_magnitude, trial_phase cells); runs {', '.join(map(str, runs))} all carry trial "
                         f"weights")
    if len(base) > 1:
        raise InputError(f"{_label(data)}: runs {', '.join(map(str, base))} have no trial weight; exactly one "
                         f"baseline run is needed (give the others trial weights or remove them)")
    return base[0]


def _speed_groups(values):
    """Distinct speeds (the first of each cluster within SPEED_RTOL), sorted."""
    out = []
    for v in np.sort(np.asarray(values, dtype=float)):
        if not out or not _same_speed(out[-1], v):
            out.append(float(v))
    return out


def _select_speeds(data, available, speeds):
    if speeds is None:
        return available
    sel = np.atleast_1d(as_numpy("speeds", speeds, sign="positive"))
    if sel.ndim != 1 or sel.size < 1:
        raise InputError(f"speeds must be a list of >= 1 speeds (rad/s), got shape {sel.shape}")
    out = []
    for s in sel:
        match = [a for a in available if _same_speed(a, float(s))]
        if not match:
            raise InputError(f"speeds: {float(s):g} rad/s is not a speed of the baseline run of {_label(data)} "
                             f"(its speeds: {', '.join(f'{a:g}' for a in available)} rad/s)")
        if match[0] in out:
            raise InputError(f"speeds: {float(s):g} rad/s is given twice")
        out.append(match[0])
    return sorted(out)


def _baseline_rows(data, speeds=None):
    """`(run, rows, speeds, sensors, X0)`: the baseline run's rows at the selected speeds,
    sorted by (speed, node, direction); `speeds` and `sensors` per row."""
    _check_unbalance_data(data)
    runs = _runs(data)
    base = _baseline(data, runs)
    idx = runs[base][0]
    sp = np.asarray(data.speed, dtype=float)
    chosen = _select_speeds(data, _speed_groups(sp[idx]), speeds)
    keep = [i for i in idx if any(_same_speed(sp[i], s) for s in chosen)]
    node, direction = np.asarray(data.node), np.asarray(data.direction)
    keep.sort(key=lambda i: (sp[i], int(node[i]), int(direction[i])))
    rows = np.array(keep, dtype=int)
    sensors = tuple((int(node[i]), _DIRS[int(direction[i])]) for i in rows)
    return base, runs, rows, sp[rows], sensors, np.asarray(data.X, dtype=np.complex128)[rows]


def influence_from_phasor_runs(data, planes, speeds=None):
    """The influence matrix of correction `planes` (FE nodes) from a baseline run
    and one trial run per plane of a phasor file: `A[i, p] = (X_trial,i - X_base,i)
    / (U_t e^{i phi_t})`, measurements matched on (speed within 1e-6 relative,
    node, direction).

    **Arguments:** `data` (a `PhasorData` of unbalance phasors), `planes` (nodes,
    each with exactly one trial run whose trial weight is at that node; trial runs
    at other nodes are ignored), `speeds` (rad/s, a subset of the baseline's; None:
    all).

    **Returns:** `(speeds, sensors, X0, A)`: one row per (speed, sensor) of the
    baseline run, `speeds` `(m,)`, `sensors` `m` pairs `(node, "x" | "y")`, the
    baseline `X0` `(m,)` and `A` `(m, n_planes)`, complex.

    **Raises:** `InputError` naming the file, plane, run or measurement."""
    planes = _check_planes(planes)
    base, runs, rows, sp, sensors, X0 = _baseline_rows(data, speeds)
    label = _label(data)
    A = np.zeros((rows.size, len(planes)), dtype=np.complex128)
    speed_all, node_all = np.asarray(data.speed, dtype=float), np.asarray(data.node)
    dir_all, X_all = np.asarray(data.direction), np.asarray(data.X, dtype=np.complex128)
    for p, plane in enumerate(planes):
        trial_runs = [r for r, (_, t) in runs.items() if t is not None and t[0] == plane]
        if not trial_runs:
            at = sorted({t[0] for _, t in runs.values() if t is not None})
            where = (f"the trial weights are at node(s) {', '.join(map(str, at))}" if at else
                     "the file has no trial runs (no trial_node): take the influence coefficients from the "
                     "model (--influence model), or measure a trial run per plane")
            raise InputError(f"{label}: plane {plane} has no trial run (a run with its trial weight at node "
                             f"{plane}); {where}")
        if len(trial_runs) > 1:
            raise InputError(f"{label}: plane {plane} has {len(trial_runs)} trial runs "
                             f"({', '.join(map(str, trial_runs))}); exactly one per plane is needed")
        r = trial_runs[0]
        idx, (_, mag, phase) = runs[r]
        T = mag * np.exp(1j * phase)
        for k, (i, s, (n, d)) in enumerate(zip(rows, sp, sensors)):
            match = [j for j in idx if node_all[j] == n and _DIRS[int(dir_all[j])] == d
                     and _same_speed(speed_all[j], s)]
            if not match:
                raise InputError(f"{label}: run {r} (trial weight at node {plane}) has no measurement at speed "
                                 f"{s:g} rad/s, node {n}, direction {d}, which the baseline run {base} has "
                                 f"({_row(data, int(i))})")
            A[k, p] = (X_all[match[0]] - X0[k]) / T
    return sp, sensors, X0, A


def model_influence(rotor, speeds, sensors, planes):
    """The rotor model's influence matrix: `A[i, p]` = the response at `sensors[i]`
    (`(node, "x" | "y")`) and `speeds[i]` (rad/s) to a unit unbalance (1 kg m, phase
    0) at node `planes[p]`, by `rotorjax.flexible.unbalance_response_many` (the rows
    as `influence_from_phasor_runs` returns them). Returns `(m, n_planes)` complex."""
    from ..analysis._frf import full_rotor, unbalance_response_many

    model = full_rotor(rotor)
    full = model.full_rotor
    planes = _check_planes(planes, full)
    speeds = np.atleast_1d(as_numpy("speeds", speeds, sign="positive"))
    sensors = [tuple(s) for s in sensors]
    if speeds.ndim != 1 or len(sensors) != speeds.size or not sensors:
        raise InputError(f"speeds and sensors must be one per row (>= 1), got {speeds.size} speeds and "
                         f"{len(sensors)} sensors")
    nodes = sorted({int(n) for n, _ in sensors})
    for n, d in sensors:
        if not 0 <= int(n) < full.n_nodes or d not in _DIRS:
            raise InputError(f"sensors: ({n!r}, {d!r}) is not a (node, 'x' | 'y') of the rotor (nodes "
                             f"0..{full.n_nodes - 1})")
    grid = _speed_groups(speeds)
    where = [next(k for k, g in enumerate(grid) if _same_speed(g, s)) for s in speeds]
    col = [nodes.index(int(n)) for n, _ in sensors]
    A = np.zeros((speeds.size, len(planes)), dtype=np.complex128)
    for p, plane in enumerate(planes):
        X, Y = unbalance_response_many(rotor, [(plane, 1.0, 0.0)], np.asarray(grid), nodes)
        XY = (np.asarray(X), np.asarray(Y))
        for i, (k, c, (_, d)) in enumerate(zip(where, col, sensors)):
            A[i, p] = XY[_DIRS.index(d)][k, c]
    return A


def _check_system(A, X0, weights):
    A = as_numpy("A (influence matrix)", A, dtype=np.complex128, ndim=2)
    X0 = as_numpy("X0 (baseline vibration)", X0, dtype=np.complex128, ndim=1)
    if A.shape[0] != X0.shape[0] or A.shape[1] < 1 or A.shape[0] < 1:
        raise InputError(f"A must be (measurements, planes) and X0 (measurements,), got A shape {A.shape}, "
                         f"X0 shape {X0.shape}")
    if weights is None:
        return A, X0, np.ones(X0.shape[0])
    w = np.atleast_1d(np.asarray(weights, dtype=float))
    if w.shape != X0.shape:
        raise InputError(f"weights must be one number per measurement ({X0.shape[0]}), got shape {w.shape}")
    bad = np.flatnonzero(~(np.isfinite(w) & (w > 0)))
    if bad.size:
        raise InputError(f"weights must be finite and > 0; weight {int(bad[0])} is {w[bad[0]]!r}")
    return A, X0, w


def least_squares_balance(A, X0, weights=None):
    """Corrections `W` (complex, per plane) minimising `sum_i (w_i |X0_i + A_i W|)^2`
    (`_balance.least_squares_correction` with `Q = w^2`). `weights` `w`: > 0, one
    per measurement (None: all 1)."""
    A, X0, w = _check_system(A, X0, weights)
    if A.shape[0] < A.shape[1]:
        raise InputError(f"{A.shape[0]} measurement(s) cannot determine {A.shape[1]} plane corrections "
                         f"(underdetermined: measure more speeds or sensors, or use fewer planes)")
    return least_squares_correction(A, X0, w**2)


def minmax_balance(A, X0, weights=None):
    """Corrections `W` minimising the worst weighted residual `max_i w_i |X0_i + A_i W|`,
    exactly, as the second-order cone program

        minimise t  over (Re W, Im W, t)  s.t.  ||w_i (Re, Im)(X0_i + A_i W)||_2 <= t,

    solved by Clarabel (variables scaled to order one). Returns `(W, t)`, `t` the
    optimal max weighted residual (evaluated at `W`).

    **Raises:** `NumericalError` naming the solver status when it is not Solved."""
    import clarabel
    from scipy import sparse

    A, X0, w = _check_system(A, X0, weights)
    m, n = A.shape
    sx = float(np.max(w * np.abs(X0)))
    if sx == 0.0:
        return np.zeros(n, dtype=np.complex128), 0.0
    colmax = np.max(w[:, None] * np.abs(A), axis=0)
    if np.any(colmax == 0):
        raise NumericalError(f"minmax_balance: plane {int(np.argmax(colmax == 0))} has no influence on any "
                             f"measurement (a zero column of A)")
    s = sx / colmax                                  # W_p = s_p y_p
    g = w[:, None] * A * s[None, :] / sx             # scaled influence
    c = w * X0 / sx                                  # scaled baseline
    rows = np.zeros((3 * m, 2 * n + 1))
    b = np.zeros(3 * m)
    rows[0::3, 2 * n] = -1.0                         # s_t = t
    rows[1::3, :n], rows[1::3, n:2 * n] = -g.real, g.imag     # s_re = Re c + Re g a - Im g b
    rows[2::3, :n], rows[2::3, n:2 * n] = -g.imag, -g.real    # s_im = Im c + Im g a + Re g b
    b[1::3], b[2::3] = c.real, c.imag
    q = np.zeros(2 * n + 1)
    q[-1] = 1.0
    settings = clarabel.DefaultSettings()
    settings.verbose = False
    for name in ("tol_gap_abs", "tol_gap_rel", "tol_feas"):
        setattr(settings, name, 1e-10)
    P = sparse.csc_matrix((2 * n + 1, 2 * n + 1))
    solver = clarabel.DefaultSolver(P, q, sparse.csc_matrix(rows), b, [clarabel.SecondOrderConeT(3)] * m,
                                    settings)
    sol = solver.solve()
    status = str(sol.status)
    if status.split(".")[-1] != "Solved":
        raise NumericalError(f"minmax_balance: the cone program was not solved (Clarabel status {status})")
    x = np.asarray(sol.x)
    W = (x[:n] + 1j * x[n:2 * n]) * s
    if not np.all(np.isfinite(W)):
        raise NumericalError("minmax_balance: the corrections are not finite")
    return W, float(np.max(w * np.abs(X0 + A @ W)))


def total_mass(rotor):
    """Total mass of a `FlexibleRotor` (a `ReducedRotor`: its full rotor), kg: the shaft
    elements' (the consistent mass matrix's rigid translation, `sum rho A L`) plus the
    disks and point masses (pedestals are not the rotor's)."""
    full = rotor.full_rotor
    M, _, _ = full.shaft_matrices()
    e = np.zeros(full.n_dofs)
    e[0:DOFS_PER_NODE * full.n_nodes:DOFS_PER_NODE] = 1.0
    shaft = float(e @ np.asarray(M) @ e)
    disks = float(np.sum(np.asarray(full.disk_params)[:, 0])) if len(full.disk_nodes) else 0.0
    points = float(np.sum(np.asarray(full.point_mass_params)[:, 0])) if len(full.point_mass_nodes) else 0.0
    return shaft + disks + points


def equivalent_unbalance(A, X):
    """The residual unbalance (kg m) that vibration `X` corresponds to: the unbalance
    which, at a correction plane of the rotor's mean sensitivity (rms over the
    planes of `||A[:, p]||`), makes vibration as large (2-norm over the
    measurements) as `X`."""
    sens = np.sqrt(np.mean(np.sum(np.abs(A) ** 2, axis=0)))
    return float(np.linalg.norm(X) / sens) if sens > 0 else float("nan")


@dataclasses.dataclass(frozen=True, eq=False)
class FEBalancing:
    """A flexible rotor's balancing (see `balance_rotor`).

    - `path`, `planes`, `speeds` `(m,)`, `sensors` (m `(node, dir)`): the measurements;
    - `A` `(m, n_planes)` (the influence matrix used), `X0`, `W` (complex corrections to
      ADD, kg m), `predicted = X0 + A W`; `weights` or None; `objective`: the minimised
      value (least squares: `||w |predicted|||_2`; min-max: `max w |predicted|`);
    - `before_max`, `after_max`, `before_rms`, `after_rms` (m): `|X0|`, `|predicted|`;
    - `A_model`, `influence_difference` (`(n_speeds, n_planes)` relative difference
      of the model's columns from the trials', per distinct speed) or None;
    - ISO: `rotor_mass` (kg), `service_speed` (rad/s), `grade` (requested, mm/s),
      `permissible_gmm`, `residual_gmm`, `initial_gmm`, `grade_reached`,
      `grade_before`, `criticals` (forward critical speeds below 1.1 x service,
      rad/s, or None without a rotor), `explanation` (sentences);
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
    initial_gmm: float
    grade_reached: object
    grade_before: object
    criticals: object
    explanation: tuple
    warnings: tuple

    @property
    def corrections(self) -> tuple:
        """`(node, magnitude kg m, phase rad)` per plane: the unbalance to ADD."""
        return tuple((p, float(abs(w)), float(np.angle(w))) for p, w in zip(self.planes, self.W))

    @property
    def balancing_speeds(self) -> list:
        """The distinct speeds balanced at (rad/s)."""
        return _speed_groups(self.speeds)

    def as_dict(self) -> dict:
        n_crit = None if self.criticals is None else len(self.criticals)
        comparison = None
        if self.influence_difference is not None:
            comparison = [{"plane": p, "speed": s, "relative_difference": float(self.influence_difference[k, j])}
                          for k, s in enumerate(self.balancing_speeds) for j, p in enumerate(self.planes)]
        return {
            "data": self.path,
            "planes": list(self.planes),
            "speeds": self.balancing_speeds,
            "phase_convention": "unbalance phase as in unbalance_response: force U W^2 (cos(W t + phase), "
                                "sin(W t + phase)); the corrections are weights to ADD",
            "corrections": [{"node": p, "magnitude": m, "phase_deg": float(np.degrees(a) % 360)}
                            for p, m, a in self.corrections],
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
            "iso": {
                "rotor_mass_kg": self.rotor_mass,
                "service_speed_rad_s": self.service_speed,
                "grade_requested": self.grade,
                "permissible_unbalance_g_mm": self.permissible_gmm,
                "residual_unbalance_g_mm": self.residual_gmm,
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


def _fmt(values):
    return ", ".join(f"{v:.4g}" for v in values)


def _iso_12(rotor, planes, used, service):
    """`(criticals, sentences)`: ISO 21940-12's counts for the rotor model."""
    from ..analysis._linear import critical_speeds_1x

    if rotor is None:
        return None, ["No rotor model was given, so the critical speeds, and with them ISO 21940-12's number "
                      "of correction planes and balancing speeds for a flexible rotor, are not known."]
    n_dof = np.asarray(rotor.reduced_matrices(0.0)[0]).shape[0]
    crit = [float(s) for s, _ in critical_speeds_1x(rotor, 0.0, 1.1 * service, n_modes=min(12, n_dof),
                                                   whirl="forward")]
    N, n = len(crit), len(planes)
    text = [f"ISO 21940-12: the model has {N} forward critical speed(s) below 1.1 x the service speed "
            f"({1.1 * service:.4g} rad/s)" + (f": {_fmt(crit)} rad/s." if N else ".")]
    if N == 0:
        text.append("The rotor runs below its first critical speed: it behaves as a rigid rotor and two-plane "
                    "balancing at low speed (ISO 21940-11) suffices.")
    verdict = lambda k: "enough" if n >= k else f"{k - n} too few"  # noqa: E731
    text.append(f"The N-plane (modal) method needs N = {N} correction plane(s) and the N+2-plane method "
                f"{N + 2}; {n} plane(s) were used ({verdict(N)} for the N-plane method, {verdict(N + 2)} for "
                f"the N+2-plane method).")
    wanted = sorted(crit + [float(service)])
    missing = [s for s in wanted if not any(abs(u - s) <= 0.1 * s for u in used)]
    text.append(f"The procedure balances at each critical speed in range and at the service speed "
                f"({_fmt(wanted)} rad/s); the data's speeds were {_fmt(used)} rad/s"
                + (f", none within 10 % of {_fmt(missing)} rad/s." if missing else
                   ", one within 10 % of each of them."))
    return crit, text


def balance_rotor(data, planes, speeds=None, method="ls", influence="trials", rotor=None, rotor_mass=None,
                  service_speed=None, grade=None, weights=None) -> FEBalancing:
    """Correction weights for a flexible rotor from measured 1x phasors.

    **Arguments:**
    - `data`: a `PhasorData` (unbalance phasors) with a baseline run (no trial
      weight) and, for `influence` "trials" or "both", one trial run per plane.
    - `planes`: correction planes, FE nodes; `speeds`: the baseline's speeds to
      balance at (rad/s; None: all).
    - `method`: "ls" (least squares over all speeds and sensors) or "minmax" (the
      smallest worst residual, a cone program).
    - `influence`: "trials" (from the trial runs), "model" (from `rotor`; only the
      baseline run is needed) or "both" (the trials' are used and compared with the
      model's: a warning when they differ by more than 20 %).
    - `rotor`: the `FlexibleRotor` (or `ReducedRotor`, `RotorScene`) model: the
      model influence, the critical speeds, the default rotor mass.
    - `rotor_mass` (kg; default the model's), `service_speed` (rad/s; default the
      largest speed in the data), `grade` (ISO 21940-11, mm/s; default 2.5).
    - `weights`: > 0 per row (as `influence_from_phasor_runs` orders them), or None.

    **Returns:** a `FEBalancing`.

    **Raises:** `InputError` naming the plane, run, speed or option;
    `NumericalError` when no finite correction comes out."""
    check_choice("method", method, ("ls", "minmax"))
    check_choice("influence", influence, ("trials", "model", "both"))
    full = None
    if rotor is not None:
        from ..analysis._frf import full_rotor

        rotor = full_rotor(rotor)
        full = rotor.full_rotor
    if influence in ("model", "both") and rotor is None:
        raise InputError(f"influence={influence!r} needs the rotor model (rotor=...); use influence='trials' "
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
    for name, v in (("rotor_mass", rotor_mass), ("service_speed", service_speed), ("grade", grade)):
        if v is not None:
            as_numpy(name, v, sign="positive", shape=())
    grade = 2.5 if grade is None else float(grade)
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
        A_model = model_influence(rotor, sp, sensors, planes)
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
    if weights is not None:
        _check_system(A, X0, weights)
    if method == "ls":
        W = least_squares_balance(A, X0, weights)
    else:
        W, _ = minmax_balance(A, X0, weights)
    if not np.all(np.isfinite(W)):
        raise NumericalError("balance_rotor: the corrections are not finite (a singular influence matrix: do "
                             "two planes act alike on the sensors?)")
    cond = float(np.linalg.cond(A / np.linalg.norm(A, axis=0)[None, :]))
    if cond > 1e6:
        warnings.append(f"the influence matrix is ill-conditioned (condition number {cond:.2g} with scaled "
                        f"columns): the planes act almost alike on the sensors, so the corrections are uncertain")
    pred = X0 + A @ W
    w = np.ones(X0.size) if weights is None else np.asarray(weights, dtype=float)
    wr = w * np.abs(pred)
    objective = float(np.max(wr)) if method == "minmax" else float(np.sqrt(np.sum(wr**2)))
    service = float(np.max(np.asarray(data.speed))) if service_speed is None else float(service_speed)
    mass = (total_mass(full) if full is not None else None) if rotor_mass is None else float(rotor_mass)
    residual, initial = equivalent_unbalance(A, pred) * 1e6, equivalent_unbalance(A, X0) * 1e6
    crit, text12 = _iso_12(rotor, planes, _speed_groups(sp), service)
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
    return FEBalancing(
        path=_label(data), planes=planes, speeds=np.asarray(sp), sensors=tuple(sensors), A=A, X0=X0, W=W,
        predicted=pred, method=method, influence=influence, weights=None if weights is None else w,
        objective=objective, before_max=float(np.max(np.abs(X0))), after_max=float(np.max(np.abs(pred))),
        before_rms=float(np.sqrt(np.mean(np.abs(X0) ** 2))), after_rms=float(np.sqrt(np.mean(np.abs(pred) ** 2))),
        A_model=A_model, influence_difference=diff, rotor_mass=mass, service_speed=service, grade=grade,
        permissible_gmm=U_per, residual_gmm=residual, initial_gmm=initial, grade_reached=reached,
        grade_before=before, criticals=None if crit is None else tuple(crit),
        explanation=tuple(text11 + text12), warnings=tuple(warnings))

