"""A rotor file's design problem: its parameters (by their rotor-file names, the
`--set` keys, as identification and uncertainty address them) within bounds, one of
its quantities as the objective, limits on others as constraints, solved by the one
mechanism (`minimize`).

The quantities (each a smooth function of the parameters, pure JAX), and whether a
design wants them large (max) or small (min) unless told:

- `min-log-dec` (max): a lower bound on the least log decrement over `speed_range`
  (`log_dec_floor`) of the modes whose damped frequency is below `max_frequency`
  (default: a cut between the nominal rotor's `n_modes`-th mode and the next one
  clear of it, `mode_cut`, a near pair counted whole): a design may move a mode out
  of that band;
- `separation-margin` (max): the least API 684 slack (percent: the margin had less
  the margin required) of the forward 1x critical speeds in `critical_range` from
  `operating` (`separation_slack`);
- `response` (min): the largest unbalance-response amplitude (m) at the probes over
  `speed_range` (a soft maximum on `n_grid` speeds; the file's `[[unbalance]]`);
- `onset` (max): the stability threshold in `speed_range` where the rotor turns
  unstable (`onset_speed`);
- `mass` (min): the rotor's mass, kg.

**Robust design** (`scatter`, `robust_k`): parameters that are not designed but
scatter (bearing coefficients, a disk's mass: `{name: distribution}`, as
`rotorjax.uncertainty` takes them) are drawn once, `robust_samples` of them (common
random numbers: the same samples at every design, so the statistics are smooth
functions of the design and their gradients exact), and every quantity becomes its
sample mean and standard deviation over them. The objective is the mean moved by `k`
standard deviations the bad way (`mean - k sd` for a quantity maximised, `mean + k
sd` for one minimised), and so is each constraint (`mean - k sd >= limit`, `mean + k
sd <= limit`): with normal outputs, `k = 1.645` holds a limit at 95 %.

Critical speeds and the onset are followed from the file's own values (the nominal
rotor's, by `secant_root`): a design where one is lost (no longer converges) is a
non-finite point, which the search steps back from.
"""

import dataclasses

import jax
import jax.numpy as jnp
import numpy as np

from .._errors import InputError, NumericalError
from ..analysis import (amplification_factor, critical_speed, critical_speeds_1x, damped_eigenvalues, linear_margin,
                        log_dec_floor, mode_cut, onset_speed, scene_unbalance_response, separation_slack, soft_min,
                        stability_thresholds)
from ..io import read_rotor_file
from ..models import Unbalance
from ..models._fe_rotor import DOFS_PER_NODE
from ..models._parameters import parts_of, scene_from, value_of, with_values
from ._optimize import latin_starts, minimize

#: the quantities, and whether a design wants them large (+1) or small (-1)
SENSES = {"min-log-dec": 1, "separation-margin": 1, "response": -1, "onset": 1, "mass": -1}
#: their units, for the messages and reports
UNITS = {"min-log-dec": "", "separation-margin": "%", "response": "m", "onset": "rad/s", "mass": "kg"}
#: a followed root whose residual exceeds this (relative) is lost
ROOT_TOLERANCE = 1e-8


@dataclasses.dataclass(frozen=True, eq=False)
class RotorProblem:
    """A rotor file's design problem (see the module): `fn(x) -> (f, c)` scaled for
    `minimize`, `quantities(x) -> {name: value}` unscaled, the parameters' `names`,
    bounds `lo`, `hi`, `nominal` values and `log` scaling, the `objective` and its
    `sense`, the `constraints` `[(name, op, limit)]`, the followed `critical` speeds
    `[(speed, mode)]` and `onset` guess, and the settings."""

    file: object
    names: tuple
    paths: tuple
    lo: np.ndarray
    hi: np.ndarray
    nominal: np.ndarray
    log: np.ndarray
    objective: str
    sense: int
    constraints: tuple
    quantities: object
    fn: object
    scales: dict
    settings: dict
    robust: dict | None = None

    def value(self, q, name, worse):
        """A quantity's value in the problem's terms from `quantities(x)`'s `q`: itself,
        or (robust) its mean moved by `k` standard deviations towards `worse` (+1: up,
        -1: down)."""
        if self.robust is None:
            return q[name]
        return q[name] + worse * self.robust["k"] * q[f"{name} sd"]


def parse_constraint(text, option="--constraint"):
    """`NAME>=VALUE` or `NAME<=VALUE` -> `(name, op, value)`."""
    for op in (">=", "<="):
        if op in text:
            name, _, value = text.partition(op)
            name = name.strip()
            try:
                limit = float(value)
            except ValueError:
                raise InputError(f"{option} {text!r}: {value.strip()!r} is not a number") from None
            if name not in SENSES:
                raise InputError(f"{option} {text!r}: unknown quantity {name!r}; known: {', '.join(SENSES)}")
            if not np.isfinite(limit):
                raise InputError(f"{option} {text!r}: the limit must be finite")
            return name, op, limit
    raise InputError(f"{option} {text!r}: give NAME>=VALUE or NAME<=VALUE, e.g. 'min-log-dec>=0.1'")


def _path(file, name, option):
    """The parameter path of the rotor-file name `name`, or `InputError` naming it."""
    path = file.path(name)
    if path is None:
        raise InputError(f"{option} {name}: not a parameter of {file.label}; `rotorjax presets {file.label}` lists "
                         "its keys")
    if path.refusal:
        raise InputError(f"{option} {name}: {path.refusal}")
    return path


def _bounds(file, vary, option):
    names, paths, lo, hi, nominal, log = [], [], [], [], [], []
    for name, (a, b) in vary.items():
        path = _path(file, name, option)
        if not (np.isfinite(a) and np.isfinite(b) and a < b):
            raise InputError(f"{option} {name}={a:g}:{b:g}: the bounds need LO < HI")
        domain = file.entries[name].domain if name in file.entries else (">=0" if file.signed(name) else ">0")
        if (domain == ">0" and a <= 0) or (domain == ">=0" and a < 0):
            raise InputError(f"{option} {name}={a:g}:{b:g}: {name} must be {domain}, so LO too")
        names.append(name)
        paths.append(path)
        lo.append(float(a))
        hi.append(float(b))
        log.append(a > 0 and b / a >= 10)
    parts = parts_of(file.scene)
    nominal = [float(value_of(parts, p)) for p in paths]
    return tuple(names), tuple(paths), np.array(lo), np.array(hi), np.array(nominal), np.array(log)


def rotor_problem(rotor, vary, objective, constraints=(), *, speed_range=None, n_modes=3, operating=None,
                  critical_range=None, probes=None, n_grid=None, overrides=None, sense=None, max_frequency=None,
                  scatter=None, robust_k=None, robust_samples=32, seed=0, option="--vary") -> RotorProblem:
    """The design problem of the rotor file `rotor` (a path or a `RotorFile`).

    - `vary`: `{name: (lo, hi)}` (rotor-file names; a positive quantity's bounds above
      0; a range of a decade or more is searched in its logarithm);
    - `objective`: a quantity's name (see the module); `sense`: +1 (maximise) or -1
      (default the quantity's own); `constraints`: `[(name, ">=" | "<=", limit)]`;
    - `speed_range` `(lo, hi)` rad/s: of the log decrements, the response and the
      onset (default 0 to 1.5 x the file's speed); `n_modes`; `operating` `(lo, hi)`
      rad/s, the operating range of the separation margins; `critical_range`: the
      critical speeds checked against it (default 0 to twice its top);
    - `probes`: the response's nodes (default every node); `n_grid`: speeds of the
      log-dec floor (33) and the response (400); `max_frequency` (rad/s): the log
      decrements counted are the modes' below it (default: a cut above the nominal
      rotor's `n_modes`-th mode, `mode_cut`);
    - `scatter`: `{name: distribution}` of parameters not varied, `robust_k` (default 1
      with `scatter`), `robust_samples`, `seed`: a robust design (see the module);
    - `overrides`: `--set` values; `option`: the option the names came with.
    """
    file = read_rotor_file(rotor, overrides) if isinstance(rotor, str) else rotor
    if not vary:
        raise InputError(f"{option}: give at least one parameter to vary, e.g. {option} bearing0.kxx=1e5:1e7")
    names, paths, lo, hi, nominal, log = _bounds(file, vary, option)
    noise_paths, noise, robust = _scatter(file, names, scatter, robust_k, robust_samples, seed)
    wanted = [objective] + [c[0] for c in constraints]
    for name in wanted:
        if name not in SENSES:
            raise InputError(f"--objective {name}: unknown; known: {', '.join(SENSES)}")
    sense = SENSES[objective] if sense is None else int(sense)
    speed = float(file.entries["speed"].value)
    ranged = bool({"min-log-dec", "response", "onset"} & set(wanted))
    if speed_range is None and ranged:
        if not speed > 0:
            raise InputError(f"--range: {file.label} has no operating speed ([rotor] speed); give --range LO HI")
        speed_range = (0.0, 1.5 * speed)
    s_lo, s_hi = (0.0, 1.0) if speed_range is None else (float(v) for v in speed_range)
    if not 0 <= s_lo < s_hi:
        raise InputError(f"--range {s_lo:g} {s_hi:g}: needs 0 <= LO < HI (rad/s)")
    parts = parts_of(file.scene)
    rotor0 = file.scene    # the file's linear(ised) rotor
    n_dof = file.scene.n_coordinates
    if not 1 <= int(n_modes) <= n_dof:
        raise InputError(f"--modes {n_modes}: between 1 and {file.label}'s {n_dof} free dofs")
    settings = {"range": [s_lo, s_hi] if ranged else None, "modes": int(n_modes)}
    crit, onset0, probe_nodes = (), None, None
    if "separation-margin" in wanted:
        if operating is None:
            raise InputError("--operating: separation-margin needs the operating range, --operating LO HI (rad/s)")
        op_lo, op_hi = (float(v) for v in operating)
        if not 0 < op_lo <= op_hi:
            raise InputError(f"--operating {op_lo:g} {op_hi:g}: needs 0 < LO <= HI (rad/s)")
        c_lo, c_hi = (0.0, 2.0 * op_hi) if critical_range is None else (float(v) for v in critical_range)
        crit = tuple((float(W), int(k)) for W, k in critical_speeds_1x(rotor0, c_lo, c_hi, n_modes=min(12, n_dof),
                                                                      whirl="forward"))
        if not crit:
            raise InputError(f"separation-margin: {file.label} has no forward 1x critical speed in {c_lo:g}..{c_hi:g} "
                             "rad/s to separate from the operating range")
        settings.update(operating=[op_lo, op_hi], critical_range=[c_lo, c_hi], critical_speeds=[w for w, _ in crit])
    if "onset" in wanted:
        found = [t for t in stability_thresholds(lambda s: linear_margin(rotor0, s), s_lo, s_hi)
                 if t.stable_side == "below"]
        if not found:
            raise InputError(f"onset: {file.label} has no stability onset (stable below, unstable above) in --range "
                             f"{s_lo:g} {s_hi:g}")
        onset0 = found[0].speed
        lam = np.asarray(damped_eigenvalues(rotor0, onset0))
        whirl = float(np.imag(lam[np.argmax(np.real(lam))]))    # the mode that turns unstable there
        settings.update(onset=onset0, onset_frequency=whirl)
    if "response" in wanted:
        if not any(isinstance(c, Unbalance) for c in parts.components):
            raise InputError(f"response: {file.label} has no [[unbalance]] to respond to")
        n_nodes = parts.rotor.n_nodes
        probe_nodes = tuple(range(n_nodes)) if probes is None else tuple(int(p) for p in probes)
        for p in probe_nodes:
            if not 0 <= p < n_nodes:
                raise InputError(f"--probe {p}: {file.label} has nodes 0..{n_nodes - 1}")
        settings["probes"] = list(probe_nodes)
    n_floor = 33 if n_grid is None else int(n_grid)
    n_resp = 400 if n_grid is None else int(n_grid)
    if n_floor < 2:
        raise InputError(f"--grid {n_floor}: at least 2")
    if "min-log-dec" in wanted:
        # the modes counted: those below a cut between the nominal rotor's n-th mode and the next one
        # clear of it (a near pair counted whole), so a design cannot drop a mode by reordering
        if max_frequency is None:
            counted, n_eig, cut = mode_cut(rotor0, s_lo, s_hi, int(n_modes), n_floor)
        else:
            if not max_frequency > 0:
                raise InputError(f"--max-frequency {max_frequency:g}: must be > 0 (rad/s)")
            cut = np.full(n_floor, float(max_frequency))
            f0 = np.imag(np.asarray(damped_eigenvalues(rotor0, s_hi, min(n_dof, 40))))
            counted = int(np.sum(f0 < max_frequency))
            n_eig = min(n_dof, counted + 4)
        settings.update(log_dec_modes_counted=counted, log_dec_max_frequency=[float(np.min(cut)), float(np.max(cut))])

    def at(values, which):
        p = with_values(parts, paths + noise_paths, values)
        scene = scene_from(p, file.scene)   # the file's linear(ised) rotor: fluid films, seals, reduction
        out = {}
        for name in which:
            if name == "min-log-dec":
                out[name] = log_dec_floor(scene, s_lo, s_hi, n_eig, n_grid=n_floor, cut=cut)
            elif name == "mass":
                out[name] = p.rotor.mass()
            elif name == "separation-margin":
                out[name] = _separation(scene, crit, *settings["operating"])
            elif name == "onset":
                w, res = onset_speed(scene, onset0, whirl)
                out[name] = jnp.where(jnp.abs(res) <= ROOT_TOLERANCE * jnp.abs(w), w, jnp.nan)
            elif name == "response":
                out[name] = _response(scene, probe_nodes, s_lo, s_hi, n_resp)
        return out

    def quantities(x, which=tuple(dict.fromkeys(wanted))):
        if robust is None:
            return at(x, which)
        each = jax.vmap(lambda xi: at(jnp.concatenate([x, xi]), which))(jnp.asarray(noise))
        out = {name: jnp.mean(v) for name, v in each.items()}
        out.update({f"{name} sd": _sd(v) for name, v in each.items()})
        return out

    q0 = jax.jit(quantities)(jnp.asarray(np.clip(nominal, lo, hi)))
    bad = [k for k, v in q0.items() if not np.isfinite(float(v)) and not k.endswith(" sd")]
    if bad:
        raise NumericalError(f"{file.label}: {', '.join(bad)} not finite at the starting design")
    scales = {k: max(abs(float(v)), 1e-12) for k, v in q0.items()}
    for name, op, limit in constraints:
        scales[name] = max(scales[name], abs(limit), 1e-3 if UNITS[name] in ("", "%") else 1e-12)

    problem = RotorProblem(file, names, paths, lo, hi, nominal, log, objective, sense, tuple(constraints),
                           quantities, None, scales, settings, robust)

    def fn(x):
        q = quantities(x)
        f = -sense * problem.value(q, objective, -sense) / scales[objective]
        c = [(limit - problem.value(q, name, -1)) / scales[name] if op == ">="
             else (problem.value(q, name, 1) - limit) / scales[name] for name, op, limit in constraints]
        return f, jnp.stack(c) if c else jnp.zeros(0)

    return dataclasses.replace(problem, fn=fn)


def _sd(v):
    """The sample standard deviation, with a finite derivative where it is 0 (a
    quantity the scatter does not move, such as the mass under bearing scatter)."""
    var = jnp.sum((v - jnp.mean(v)) ** 2) / (v.shape[0] - 1)
    pos = var > 0
    return jnp.where(pos, jnp.sqrt(jnp.where(pos, var, 1.0)), 0.0)


def _scatter(file, varied, scatter, k, n, seed):
    """The scattered parameters' paths, their `(n, m)` samples and the robust settings
    (or `(), None, None` without `scatter`)."""
    if not scatter:
        if k is not None:
            raise InputError("--robust: give the parameters that scatter, --scatter KEY=lognormal(MEAN,SD) ...")
        return (), None, None
    from ..uncertainty import draw, reaches_zero

    k = 1.0 if k is None else float(k)
    if not (np.isfinite(k) and k >= 0):
        raise InputError(f"--robust {k:g}: the number of standard deviations must be >= 0")
    if not isinstance(n, (int, np.integer)) or n < 2:
        raise InputError(f"--robust-samples {n}: at least 2")
    paths = []
    for name, dist in scatter.items():
        if name in varied:
            raise InputError(f"--scatter {name}: also given to --vary; a designed parameter cannot scatter (give "
                             "the scatter of another parameter)")
        path = _path(file, name, "--scatter")
        if not file.signed(name) and reaches_zero(dist):
            raise InputError(f"--scatter {name}={dist.text()}: {name} is a positive quantity and this distribution "
                             "reaches 0 or below; give lognormal(MEAN, SD), or a narrower one")
        paths.append(path)
    samples = draw(scatter, int(n), seed=seed)
    return tuple(paths), samples, {"k": k, "samples": int(n), "seed": int(seed),
                                   "scatter": {name: d.text() for name, d in scatter.items()}}


def _separation(r, crit, op_lo, op_hi):
    slacks = []
    for W, k in crit:
        w, res = critical_speed(r, k, W)
        w = jnp.where(jnp.abs(res) <= ROOT_TOLERANCE * jnp.abs(w), w, jnp.nan)
        af = amplification_factor(damped_eigenvalues(r, w, k + 1)[k])
        slacks.append(separation_slack(w, af, op_lo, op_hi))
    return soft_min(jnp.stack(slacks), 0.05)


def _response(scene, probes, lo, hi, n):
    speeds = jnp.asarray(np.linspace(max(lo, 1e-3 * hi), hi, n))
    Q = scene_unbalance_response(scene, speeds)                       # (n, n_coords)
    full = scene.expand(Q.T)                                          # (n_dofs, n)
    idx = np.asarray(probes) * DOFS_PER_NODE
    amp = jnp.sqrt(jnp.abs(full[idx]) ** 2 + jnp.abs(full[idx + 1]) ** 2)
    return jnp.exp(-soft_min(-jnp.log(amp), 1e-3))


@dataclasses.dataclass(frozen=True, eq=False)
class RotorDesign:
    """An optimised rotor file: the `problem`, the `optimum` (`Optimum`), the
    parameters' values before and after (`{name: value}`), the quantities before and
    after, and each constraint's row (`name`, `op`, `limit`, `value`, `met`,
    `multiplier`)."""

    problem: RotorProblem
    optimum: object
    before: dict
    after: dict
    quantities_before: dict
    quantities_after: dict
    constraint_rows: list

    def campbell(self, speeds, n_modes=8):
        """`(speeds, before, after)`: the Campbell diagrams (`Modes` over `speeds`) of the
        starting design and the optimum (the file's linear(ised) rotor)."""
        from ..analysis import campbell

        p = self.problem
        parts = parts_of(p.file.scene)
        out = []
        for values in (self.before, self.after):
            x = jnp.asarray([values[k] for k in p.names])
            out.append(campbell(scene_from(with_values(parts, p.paths, x), p.file.scene), speeds, n_modes))
        return np.asarray(speeds), out[0], out[1]

    def overrides(self) -> dict:
        """The optimum as `--set` values for the file."""
        return dict(self.after)

    def as_dict(self) -> dict:
        o, p = self.optimum, self.problem
        objective = {"name": p.objective, "sense": "max" if p.sense > 0 else "min",
                     "before": float(p.value(self.quantities_before, p.objective, -p.sense)),
                     "after": float(p.value(self.quantities_after, p.objective, -p.sense)), "unit": UNITS[p.objective]}
        if p.robust is not None:
            objective.update({f"{w} {s}": q[f"{p.objective}{t}"] for w, q in (("before", self.quantities_before),
                                                                              ("after", self.quantities_after))
                              for s, t in (("mean", ""), ("sd", " sd"))})
        return {"objective": objective,
                "parameters": {k: {"before": self.before[k], "after": self.after[k], "lo": float(a), "hi": float(b),
                                   "log_scaled": bool(g)}
                               for k, a, b, g in zip(p.names, p.lo, p.hi, p.log)},
                "constraints": self.constraint_rows, "quantities_before": self.quantities_before,
                "quantities_after": self.quantities_after, "converged": o.converged, "feasible": o.feasible,
                "reason": o.reason, "iterations": o.iterations, "evaluations": o.evaluations,
                "starts": int(o.starts.shape[0]), "best_start": o.best,
                "history": [{"objective": float(h[0]), "violation": float(h[1]), "mu": float(h[2]),
                             "projected_gradient": float(h[3]), "steps": int(h[4])} for h in o.history],
                "steps": [{"objective": -p.sense * float(f) * p.scales[p.objective], "violation": float(v)}
                          for f, v in o.steps],
                "settings": p.settings, "robust": p.robust}


def optimize_rotor(problem: RotorProblem, n_starts=8, seed=0, tol=1e-6, max_outer=30) -> RotorDesign:
    """Solve `problem` from the file's values (clipped into the bounds) and
    `n_starts - 1` Latin-hypercube starts. Raises `InputError` when no start meets
    the constraints (naming those violated at the least-violating end)."""
    if int(n_starts) < 1:
        raise InputError(f"--starts {n_starts}: at least 1")
    p = problem
    starts = latin_starts(p.lo, p.hi, int(n_starts), first=p.nominal, log=p.log, seed=seed)
    o = minimize(p.fn, p.lo, p.hi, starts, log=p.log, tol=tol, max_outer=max_outer)
    q = jax.jit(p.quantities)
    before = {k: float(v) for k, v in q(jnp.asarray(starts[0])).items()}
    after = {k: float(v) for k, v in q(jnp.asarray(o.x)).items()}
    rows = [{"name": name, "op": op, "limit": limit, "value": float(p.value(after, name, -1 if op == ">=" else 1)),
             "unit": UNITS[name], "met": bool(o.constraints[j] <= tol), "multiplier": float(o.multipliers[j])}
            for j, (name, op, limit) in enumerate(p.constraints)]
    if p.robust is not None:
        for r in rows:
            r.update(mean=after[r["name"]], sd=after[f"{r['name']} sd"])
    if not o.feasible:
        broken = [f"{r['name']}{r['op']}{r['limit']:g} (best {r['value']:.4g})" for r in rows if not r["met"]]
        raise InputError(f"--constraint: no start of {len(starts)} met {', '.join(broken) or 'the constraints'}: "
                         "they may be infeasible within the bounds")
    return RotorDesign(p, o, dict(zip(p.names, map(float, starts[0]))), dict(zip(p.names, map(float, o.x))),
                       before, after, rows)
