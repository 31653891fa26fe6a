"""Influence coefficients, for every linear scene: from trial runs (a baseline run
and one trial run per plane: `A[:, p] = (X_p - X0) / T_p`, model 002's eqs. 20, 22,
one formula, `influence_from_trials`), from the scene's model (a rotor file's
finite-element rotor, or the balancing machine), or both.

Runs are phasor runs (`PhasorData`): one row per (speed, sensor) of each run,
sensors `(node, "x" | "y")`; a balancing machine's runs (`BalancingData`) become
phasor runs by `machine_runs` (sensor `k` as node `k`, direction x; the trial
weight of plane `p` at node `p`). Rows of `A` and `X0` are the (speed, sensor)
pairs of the baseline run, sorted by speed, node, direction.
"""

import numpy as np

from .._errors import InputError
from ..models._validate import as_numpy
from ._phasor_file import PhasorData, make_phasors

#: speeds of two runs are the same when they differ by at most this, relative
SPEED_RTOL = 1e-6


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
    X_trials = np.zeros((len(planes), rows.size), dtype=np.complex128)
    T = np.zeros(len(planes), dtype=np.complex128)
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
        T[p] = mag * np.exp(1j * phase)
        for k, (i, s, (n, d)) in enumerate(zip(rows, sp, sensors)):
            match = [j for j in idx if node_all[j] == n and _DIRS[int(dir_all[j])] == d
                     and _same_speed(speed_all[j], s)]
            if not match:
                raise InputError(f"{label}: run {r} (trial weight at node {plane}) has no measurement at speed "
                                 f"{s:g} rad/s, node {n}, direction {d}, which the baseline run {base} has "
                                 f"({_row(data, int(i))})")
            X_trials[p, k] = X_all[match[0]]
    return sp, sensors, X0, influence_from_trials(X0, X_trials, T)


def model_influence(rotor, speeds, sensors, planes):
    """The scene's model's influence matrix: `A[i, p]` = the response at `sensors[i]`
    (`(node, "x" | "y")`) and `speeds[i]` (rad/s) to a unit unbalance (1 kg m, phase
    0) in plane `planes[p]` (the rows as `influence_from_phasor_runs` returns them).
    A rotor file's rotor (`FlexibleRotor`, `ReducedRotor`, `RotorScene`): planes are
    nodes, by `rotorjax.flexible.unbalance_response_many`; a `BalancingScene`: plane
    `p` is the scene's `p`-th plane and sensor `(k, "x")` support `k`, by
    `BalancingMachine.influence_matrix`. Returns `(m, n_planes)` complex."""
    from ..analysis._frf import full_rotor, unbalance_response_many
    from ..models._balancing_machine import BalancingScene

    if isinstance(rotor, BalancingScene):
        return _machine_influence(rotor, speeds, sensors, planes)
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


def _machine_influence(scene, speeds, sensors, planes):
    """`model_influence` of a `BalancingScene` (see there)."""
    positions = np.asarray(scene.planes, dtype=float)
    planes = _check_planes(planes)
    bad = [p for p in planes if p >= positions.size]
    if bad:
        raise InputError(f"planes: plane {bad[0]} is not a plane of the balancing machine's scene (planes "
                         f"0..{positions.size - 1})")
    speeds = np.atleast_1d(as_numpy("speeds", speeds, sign="positive"))
    A = np.zeros((speeds.size, len(planes)), dtype=np.complex128)
    for i, (w, (k, d)) in enumerate(zip(speeds, sensors)):
        if d != "x" or int(k) not in (0, 1):
            raise InputError(f"sensors: ({k!r}, {d!r}) is not a support of the balancing machine (0 or 1, 'x')")
        A[i] = np.asarray(scene.machine.influence_matrix(float(w), positions[list(planes)]))[int(k)]
    return A


#: the phase convention of a balancing machine's runs
MACHINE_PHASES = "angles from the once-per-revolution mark, in the direction of rotation"


def machine_runs(data) -> PhasorData:
    """A balancing machine's runs (a `BalancingData`) as phasor runs: the base run and
    one trial run per plane, all at the base run's speed (the trial runs turn within
    `SPEED_TOLERANCE` of it and are taken at it), sensor `k` as node `k`, direction
    x, the trial weight of plane `p` at node `p`; `sigma` each phasor's noise from
    its run's sine fit, `residual rms sqrt(2 / samples)`."""
    runs = [data.base] + [data.trials_by_plane[p] for p in data.planes]
    n = len(data.sensors)
    X = np.concatenate([np.asarray(r["X"], dtype=complex) for r in runs])
    sigma = np.concatenate([np.asarray(r["residual_rms"], dtype=float) * np.sqrt(2.0 / max(r["samples"], 1))
                            for r in runs])
    trial = {j + 1: (p, float(abs(t)), float(np.angle(t)))
             for j, (p, t) in enumerate(zip(data.planes, data.trial_unbalances))}
    return make_phasors(data.speed, np.tile(np.arange(n), len(runs)), "x", X, np.repeat(np.arange(len(runs)), n),
                        trial, np.maximum(sigma, 1e-300), path=data.path)
