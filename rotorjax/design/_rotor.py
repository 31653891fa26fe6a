"""A rotor file's design problem: its parameters (by their rotor-file names, the
`--set` keys, as identification and uncertainty address them) within bounds, one of
its quantities as the objective, limits on others as constraints, solved by the one
mechanism (`minimize`).

The quantities (each a smooth function of the parameters, pure JAX, set up once on
the file's values by `rotorjax.analysis.scene_quantities`, which uncertainty shares),
and whether a design wants them large (max) or small (min) unless told:
`min-log-dec` (max), `separation-margin` (max, API 684's slack in percent),
`response` (min, m), `onset` (max, rad/s), `mass` (min, kg), `stable-range` (max,
rad/s: the speeds of the range where the rotor is stable).

**A preset's design problem** (`preset_problem`): its `--set` keys within bounds,
against `stable-range`, the length of the speed range over which its reference
motion is stable (an auto-balancer's main motion: the auto-balancing range; the
thresholds followed one by one, `rotorjax.analysis.StableSpeeds`).

**Robust design** (`scatter`, `robust_k`): parameters that are not designed but
scatter (bearing coefficients, a disk's mass: `{name: distribution}`, as
`rotorjax.uncertainty` takes them) are drawn once, `robust_samples` of them (common
random numbers: the same samples at every design, so the statistics are smooth
functions of the design and their gradients exact), and every quantity becomes its
sample mean and standard deviation over them. The objective is the mean moved by `k`
standard deviations the bad way (`mean - k sd` for a quantity maximised, `mean + k
sd` for one minimised), and so is each constraint (`mean - k sd >= limit`, `mean + k
sd <= limit`): with normal outputs, `k = 1.645` holds a limit at 95 %.

Critical speeds and the onset are followed from the file's own values: a design
where one is lost is a non-finite point, which the search steps back from.
"""

import dataclasses
import functools

import jax
import jax.numpy as jnp
import numpy as np

from .._errors import InputError, NumericalError
from ..analysis import scene_quantities
from ..analysis._quantities import SENSES, UNITS, stable_speeds
from ..io import read_rotor_file
from ..models._parameters import parts_of, scene_from, value_of, with_values
from ._optimize import latin_starts, minimize


@dataclasses.dataclass(frozen=True, eq=False)
class RotorProblem:
    """A rotor file's design problem (see the module): `fn(x) -> (f, c)` scaled for
    `minimize`, `quantities(x) -> {name: value}` unscaled, the parameters' `names`,
    bounds `lo`, `hi`, `nominal` values and `log` scaling, the `objective` and its
    `sense`, the `constraints` `[(name, op, limit)]`, the `scales` of `fn`'s terms,
    the `settings`, the quantities' `units`; for a preset (`file` None, `paths` its
    keys), `margins(x, speeds)`: its reference motion's stability margins, and
    `rescan(x)`: its stable range followed and found afresh (`_rescan`)."""

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
    units: dict = dataclasses.field(default_factory=lambda: dict(UNITS))
    margins: object = None
    rescan: object = None

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


def _bounds(file, vary, option):
    names, paths, lo, hi, log = [], [], [], [], []
    for name, (a, b) in vary.items():
        path = file.parameter_path(name, option)
        _check_bounds(name, a, b, option)
        between = file.interval(name)
        if between is not None and not between[0] < a < b < between[1]:
            raise InputError(f"{option} {name}={a:g}:{b:g}: {name} (m from node 0) must stay between the nodes either "
                             f"side of its own, at {between[0]:g} and {between[1]:g} m")
        domain = file.entries[name].domain if name in file.entries else ("any" if file.signed(name) else ">0")
        if (domain == ">0" and a <= 0) or (domain == ">=0" and a < 0):
            raise InputError(f"{option} {name}={a:g}:{b:g}: {name} must be {domain}, so LO too")
        names.append(name)
        paths.append(path)
        lo.append(float(a))
        hi.append(float(b))
        log.append(a > 0 and b / a >= 10 and between is None)
    file.check_together(names, option)
    parts = parts_of(file.scene)
    nominal = [float(value_of(parts, p)) for p in paths]
    return tuple(names), tuple(paths), np.array(lo), np.array(hi), np.array(nominal), np.array(log)


def _check_bounds(name, a, b, option):
    if not (np.isfinite(a) and np.isfinite(b) and a < b):
        raise InputError(f"{option} {name}={a:g}:{b:g}: the bounds need LO < HI")


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
    from ..uncertainty._rotor import file_scatter

    file = read_rotor_file(rotor, overrides) if isinstance(rotor, str) else rotor
    if not vary:
        raise InputError(f"{option}: give at least one parameter to vary, e.g. {option} bearing0.kxx=1e5:1e7")
    names, paths, lo, hi, nominal, log = _bounds(file, vary, option)
    noise_paths, noise, robust = _scatter(lambda name, dist: file_scatter(file, name, dist, "--scatter"),
                                          names, scatter, robust_k, robust_samples, seed)
    file.check_together(names + tuple(scatter or ()), "--vary/--scatter")
    wanted = _wanted(objective, constraints)
    parts = parts_of(file.scene)
    plan = scene_quantities(file.scene, wanted, label=file.label, speed=float(file.entries["speed"].value),
                            speed_range=speed_range, n_modes=n_modes, operating=operating,
                            critical_range=critical_range, probes=probes, n_grid=n_grid, max_frequency=max_frequency)
    settings = plan.settings

    def at(values):
        return plan.evaluate(with_values(parts, paths + noise_paths, values))

    problem = RotorProblem(file, names, paths, lo, hi, nominal, log, objective,
                           SENSES[objective] if sense is None else int(sense), tuple(constraints),
                           _robust(at, noise), None, None, settings, robust)
    return _assemble(problem, file.label)


def preset_problem(preset, params, vary, objective="stable-range", constraints=(), *, speed_range=None, sense=None,
                   scatter=None, robust_k=None, robust_samples=32, seed=0, n_scan=40,
                   option="--vary") -> RotorProblem:
    """The design problem of a preset with a reference motion (see the module): its
    `--set` keys `vary` `{key: (lo, hi)}` within bounds (each inside the key's domain;
    a decade or more searched in its logarithm) from `params` (the preset's values),
    against `stable-range` over `speed_range` `(lo, hi)` (the preset's speed unit),
    the thresholds set up on `n_scan` speeds; `scatter`, `robust_k`, `robust_samples`,
    `seed`: a robust design, as `rotor_problem`'s. `preset`: a `rotorjax.presets.Preset`
    (its `build`, `speed_key`, `domains`, `check`)."""
    from ..analysis import stability_margin
    from ..uncertainty._preset import preset_key, preset_scatter

    if not vary:
        raise InputError(f"{option}: give at least one parameter to vary, e.g. {option} "
                         "KEY=LO:HI (a --set key)")
    _wanted(objective, constraints, known=("stable-range",), what=f"{preset.name} (a preset)")
    names, lo, hi, log = [], [], [], []
    for name, (a, b) in vary.items():
        preset_key(preset, params, name, option)
        _check_bounds(name, a, b, option)
        for v in (a, b):
            try:
                preset.check(name, v)
            except InputError as e:
                raise InputError(f"{option} {name}={a:g}:{b:g}: {str(e).split(': ', 1)[1]}") from None
        names.append(name)
        lo.append(float(a))
        hi.append(float(b))
        log.append(a > 0 and b / a >= 10)
    if speed_range is None:
        raise InputError(f"--range: give the speeds over which {preset.name}'s stable range is measured, --range LO "
                         f"HI ({preset.speed_key}, {preset.units.get(preset.speed_key, '')})")
    names = tuple(names)

    def resolve(name, dist):
        preset_scatter(preset, params, name, dist, "--scatter")
        return name

    noise_keys, noise, robust = _scatter(resolve, names, scatter, robust_k, robust_samples, seed)
    keys = names + tuple(noise_keys)

    def margin(values, speed):
        return stability_margin(preset.build({**params, **dict(zip(keys, values)), preset.speed_key: speed}).reference)

    full = jnp.asarray([float(params[k]) for k in keys])
    stable = stable_speeds(margin, full, speed_range, n_scan=n_scan, label=preset.name,
                           unit=preset.units.get(preset.speed_key, ""))

    def at(values):
        return {"stable-range": stable.evaluate(values)["stable-range"]}

    def margins(x, speeds):
        values = jnp.concatenate([jnp.asarray(x), full[len(names):]])
        return jax.vmap(lambda s: margin(values, s))(jnp.asarray(speeds))

    unit = preset.units.get(preset.speed_key, "")
    settings = {"range": list(stable.speed_range), "speed_key": preset.speed_key, **stable.settings()}
    problem = RotorProblem(None, names, names, np.array(lo), np.array(hi), np.array([float(params[k]) for k in names]),
                           np.array(log), objective, SENSES[objective] if sense is None else int(sense),
                           tuple(constraints), _robust(at, noise), None, None, settings, robust,
                           units={"stable-range": "" if unit == "dimensionless" else unit}, margins=margins,
                           rescan=functools.partial(_rescan, stable, full, max(4 * n_scan, 100)))
    return _assemble(problem, preset.name)


def _rescan(stable, full, n_scan, x, followed=None) -> dict:
    """A preset design's stable range at `x` (the scattering keys at their nominal
    values) followed from the nominal thresholds (`followed`, if known) and found
    afresh on `n_scan` speeds, and whether they agree to 1e-6 of the range (a band
    that opened or closed unseen, they do not)."""
    values = jnp.concatenate([jnp.asarray(x, dtype=jnp.float64), full[len(x):]])
    if followed is None:
        followed = float(jax.jit(stable.evaluate)(values)["stable-range"])
    scanned, thresholds = stable.scanned_length(values, n_scan)
    lo, hi = stable.speed_range
    return {"followed": followed, "scanned": scanned, "thresholds": thresholds,
            "agree": bool(abs(scanned - followed) <= 1e-6 * (hi - lo))}


def _wanted(objective, constraints, known=tuple(SENSES), what=""):
    wanted = [objective] + [c[0] for c in constraints]
    for j, name in enumerate(wanted):
        if name not in known:
            option = "--objective" if j == 0 else "--constraint"
            raise InputError(f"{option} {name}: unknown{' for ' + what if what else ''}; known: {', '.join(known)}")
    return wanted


def _robust(at, noise):
    """`quantities(x)`: `at(x)`, or (robust) each quantity's mean and sd over the noise
    samples (`at` of `x` and a sample's values)."""
    def quantities(x):
        if noise is None:
            return at(x)
        each = jax.vmap(lambda xi: at(jnp.concatenate([x, xi])))(jnp.asarray(noise))
        out = {name: jnp.mean(v) for name, v in each.items()}
        out.update({f"{name} sd": _sd(v) for name, v in each.items()})
        return out

    return quantities


def _assemble(problem, label):
    """`problem` with its `scales` (each quantity's magnitude at the starting design)
    and `fn` (the scaled objective and constraints `minimize` takes); `NumericalError`
    where a quantity is not finite at the starting design."""
    p = problem
    q0 = jax.jit(p.quantities)(jnp.asarray(np.clip(p.nominal, p.lo, p.hi)))
    bad = [k for k, v in q0.items() if not np.isfinite(float(v)) and not k.endswith(" sd")]
    if bad:
        where = "" if p.robust is None else (
            f" (the mean over the {p.robust['samples']} samples of --scatter: not finite in at least one of them: a "
            "sample without the motion or the threshold the quantity measures, say; give a narrower --scatter)")
        raise NumericalError(f"{label}: {', '.join(bad)} not finite at the starting design{where}")
    scales = {k: max(abs(float(v)), 1e-12) for k, v in q0.items()}
    for name, op, limit in p.constraints:
        scales[name] = max(scales[name], abs(limit), 1e-3 if p.units[name] in ("", "%") else 1e-12)
    problem = dataclasses.replace(p, scales=scales)
    objective, sense, constraints = p.objective, p.sense, p.constraints

    def fn(x):
        q = p.quantities(x)
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


def _scatter(resolve, varied, scatter, k, n, seed):
    """The scattered parameters' paths, their `(n, m)` samples and the robust settings
    (or `(), None, None` without `scatter`); `resolve(name, dist) -> path`, which checks `dist`
    against the parameter's domain (`file_scatter`, `preset_scatter`)."""
    if not scatter:
        if k is not None:
            raise InputError("--robust: give the parameters that scatter, --scatter KEY=lognormal(MEAN,SD) ...")
        return (), None, None
    from ..uncertainty import draw

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
        paths.append(resolve(name, dist))
    samples = draw(scatter, int(n), seed=seed)
    return tuple(paths), samples, {"k": k, "samples": int(n), "seed": int(seed),
                                   "scatter": {name: d.text() for name, d in scatter.items()}}


@dataclasses.dataclass(frozen=True, eq=False)
class RotorDesign:
    """An optimised rotor file: the `problem`, the `optimum` (`Optimum`), the
    parameters' values before and after (`{name: value}`), the quantities before and
    after, and each constraint's row (`name`, `op`, `limit`, `value`, `met`,
    `multiplier`); for a preset, `rescan`: the optimum's stable range found afresh
    (`followed`, `scanned`, their `thresholds`, whether they `agree` to 1e-6 of the
    range)."""

    problem: RotorProblem
    optimum: object
    before: dict
    after: dict
    quantities_before: dict
    quantities_after: dict
    constraint_rows: list
    rescan: dict | None = None

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

    def margins(self, speeds):
        """`(speeds, before, after)`: a preset's reference-motion stability margins over
        `speeds` at the starting design and the optimum."""
        p = self.problem
        f = jax.jit(p.margins)
        return (np.asarray(speeds),) + tuple(np.asarray(f(jnp.asarray([v[k] for k in p.names]), jnp.asarray(speeds)))
                                             for v in (self.before, self.after))

    def overrides(self) -> dict:
        """The optimum as `--set` values for the file (`file_values`)."""
        p = self.problem
        if p.file is None:
            return dict(self.after)
        return file_values(p.file, p.paths, [self.after[k] for k in p.names])

    def as_dict(self) -> dict:
        o, p = self.optimum, self.problem
        objective = {"name": p.objective, "sense": "max" if p.sense > 0 else "min",
                     "before": float(p.value(self.quantities_before, p.objective, -p.sense)),
                     "after": float(p.value(self.quantities_after, p.objective, -p.sense)),
                     "unit": p.units[p.objective]}
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
                "settings": p.settings, "robust": p.robust, **({"rescan": self.rescan} if self.rescan else {})}


def file_values(file, paths, values) -> dict:
    """The parameters `paths` (of the `RotorFile` `file`) at `values` as `--set` values
    for the file: each by its name, a position (`disk0.position`) as the lengths of the
    elements either side of its node, as the parameter set them."""
    parts = with_values(parts_of(file.scene), paths, jnp.asarray(values, dtype=jnp.float64))
    out = {}
    for path, v in zip(paths, values):
        t = path.targets[0]
        if t.rule == "node_position":
            out.update({f"shaft{j}.L": float(parts.rotor.lengths[j]) for j in t.index[0]})
        else:
            out[path.name] = float(v)
    return out


def optimize_rotor(problem: RotorProblem, n_starts=8, seed=0, tol=1e-6, max_outer=30, progress=False) -> RotorDesign:
    """Solve `problem` from the file's values (clipped into the bounds) and
    `n_starts - 1` Latin-hypercube starts (`progress`: `minimize`'s bar). Raises
    `InputError` when no start meets the constraints (naming those violated at the
    least-violating end)."""
    if int(n_starts) < 1:
        raise InputError(f"--starts {n_starts}: at least 1")
    p = problem
    starts = latin_starts(p.lo, p.hi, int(n_starts), first=p.nominal, log=p.log, seed=seed)
    o = minimize(p.fn, p.lo, p.hi, starts, log=p.log, tol=tol, max_outer=max_outer, progress=progress)
    q = jax.jit(p.quantities)
    before = {k: float(v) for k, v in q(jnp.asarray(starts[0])).items()}
    after = {k: float(v) for k, v in q(jnp.asarray(o.x)).items()}
    rows = [{"name": name, "op": op, "limit": limit, "value": float(p.value(after, name, -1 if op == ">=" else 1)),
             "unit": p.units[name], "met": bool(o.constraints[j] <= tol), "multiplier": float(o.multipliers[j])}
            for j, (name, op, limit) in enumerate(p.constraints)]
    if p.robust is not None:
        for r in rows:
            r.update(mean=after[r["name"]], sd=after[f"{r['name']} sd"])
    if not o.feasible:
        broken = [f"{r['name']}{r['op']}{r['limit']:g} (best {r['value']:.4g})" for r in rows if not r["met"]]
        raise InputError(f"--constraint: no start of {len(starts)} met {', '.join(broken) or 'the constraints'}: "
                         "they may be infeasible within the bounds")
    rescan = None
    if p.rescan is not None:
        rescan = p.rescan(o.x, after["stable-range"] if p.robust is None else None)
    return RotorDesign(p, o, dict(zip(p.names, map(float, starts[0]))), dict(zip(p.names, map(float, o.x))),
                       before, after, rows, rescan)
