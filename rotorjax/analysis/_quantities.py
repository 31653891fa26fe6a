"""A rotor's named scalar quantities, each a smooth function of its parameters (pure
JAX), set up once on the nominal rotor and evaluated at any other: what a design
optimises and constrains (`rotorjax.design`) and what uncertainty propagates
(`rotorjax.uncertainty`), one copy for both.

- `min-log-dec`: a lower bound on the least log decrement over `speed_range`
  (`log_dec_floor`) of the modes whose damped frequency is below `max_frequency`
  (default: a cut between the nominal rotor's `n_modes`-th mode and the next one
  clear of it, `mode_cut`, a near pair counted whole), so that a changed rotor may
  move a mode out of that band but not drop one by reordering;
- `separation-margin`: the least API 684 slack (percent: the margin had less the
  margin required) of the forward 1x critical speeds in `critical_range` from
  `operating` (`separation_slack`);
- `response`: the largest unbalance-response amplitude (m) at the probes over
  `speed_range` (the scene's `Unbalance`s): each probe's peak on `n_grid` speeds,
  located between them (33 finer speeds, then a parabola's vertex: `_response`), and
  a soft maximum over the probes;
- `onset`: the stability threshold in `speed_range` where the rotor turns unstable
  (`onset_speed`);
- `mass`: the rotor's mass, kg;
- `stable-range`: how much of `speed_range` the reference motion is stable over (the
  linearised rotor's straight running; an auto-balancer preset's main motion: its
  auto-balancing range), from its stability thresholds followed one by one
  (`StableSpeeds`).

Critical speeds and the onset are followed from the nominal rotor's values (by
`secant_root`): where one is lost (its residual above `ROOT_TOLERANCE` of the speed)
the quantity is NaN, which a search steps back from and a Monte Carlo counts out.
"""

import dataclasses

import equinox as eqx
import jax
import jax.numpy as jnp
import numpy as np

from .._errors import InputError
from ..models import Unbalance
from ..models._fe_rotor import DOFS_PER_NODE
from ..models._parameters import parts_of, scene_from
from ._critical import stability_thresholds
from ._linear import critical_speed, critical_speeds_1x, damped_eigenvalues
from ._margins import (amplification_factor, log_dec_floor, mode_cut, mode_real_part, onset_speed, separation_slack,
                       soft_min)
from ._response import linear_margin, scene_unbalance_response
from ._roots import secant_root

#: the quantities, and whether a design wants them large (+1) or small (-1)
SENSES = {"min-log-dec": 1, "separation-margin": 1, "response": -1, "onset": 1, "mass": -1, "stable-range": 1}
#: their units, for the messages and reports (a preset's speeds are in its own unit)
UNITS = {"min-log-dec": "", "separation-margin": "%", "response": "m", "onset": "rad/s", "mass": "kg",
         "stable-range": "rad/s"}
#: a followed root whose residual exceeds this (relative) is lost
ROOT_TOLERANCE = 1e-8


@dataclasses.dataclass(frozen=True, eq=False)
class SceneQuantities:
    """The quantities `names` of a scene set up on its nominal rotor (see the module):
    `evaluate(parts) -> {name: value}` at the scene's parts with other parameter
    values (`models._parameters.with_values`), and the `settings` they were set up
    with (ranges, the followed critical speeds and onset, the modes counted)."""

    names: tuple
    settings: dict
    template: object
    speed_range: tuple
    crit: tuple
    onset: tuple
    probes: tuple
    floor: tuple
    n_response: int
    stable: object = None

    def evaluate(self, parts) -> dict:
        scene = scene_from(parts, self.template)   # the linear(ised) rotor: fluid films, seals, reduction
        lo, hi = self.speed_range
        out = {}
        for name in self.names:
            if name == "min-log-dec":
                n_eig, n_floor, cut = self.floor
                out[name] = log_dec_floor(scene, lo, hi, n_eig, n_grid=n_floor, cut=cut)
            elif name == "mass":
                out[name] = parts.rotor.mass()
            elif name == "separation-margin":
                out[name] = _separation(scene, self.crit, *self.settings["operating"])
            elif name == "onset":
                w, res = onset_speed(scene, *self.onset)
                out[name] = jnp.where(jnp.abs(res) <= ROOT_TOLERANCE * jnp.abs(w), w, jnp.nan)
            elif name == "response":
                out[name] = _response(scene, self.probes, lo, hi, self.n_response)
            elif name == "stable-range":
                out[name] = self.stable.evaluate(parts)[name]
        return out


def scene_quantities(scene, names, *, label="the rotor", speed=0.0, speed_range=None, n_modes=3, operating=None,
                     critical_range=None, probes=None, n_grid=None, max_frequency=None) -> SceneQuantities:
    """Set up the quantities `names` (see the module) of `scene` on its nominal values.

    - `speed_range` `(lo, hi)` rad/s: of the log decrements, the response and the
      onset (default 0 to 1.5 x `speed`, the operating speed); `n_modes`;
    - `operating` `(lo, hi)` rad/s, the operating range of the separation margins;
      `critical_range`: the critical speeds checked against it (default 0 to twice
      its top);
    - `probes`: the response's nodes (default every node); `n_grid`: speeds of the
      log-dec floor (33) and the response (400); `max_frequency` (rad/s): the log
      decrements counted are the modes' below it (default: `mode_cut`'s);
    - `label`: the rotor's name in the messages (which name the CLI's options).
    """
    names = tuple(dict.fromkeys(names))
    for name in names:
        if name not in SENSES:
            raise InputError(f"{name}: unknown quantity; known: {', '.join(SENSES)}")
    ranged = bool({"min-log-dec", "response", "onset", "stable-range"} & set(names))
    if speed_range is None and ranged:
        if not speed > 0:
            raise InputError(f"--range: {label} has no operating speed ([rotor] speed); give --range LO HI")
        speed_range = (0.0, 1.5 * speed)
    s_lo, s_hi = (0.0, 1.0) if speed_range is None else (float(v) for v in speed_range)
    if not 0 <= s_lo < s_hi:
        raise InputError(f"--range {s_lo:g} {s_hi:g}: needs 0 <= LO < HI (rad/s)")
    parts = parts_of(scene)
    n_dof = scene.n_coordinates
    if not 1 <= int(n_modes) <= n_dof:
        raise InputError(f"--modes {n_modes}: between 1 and {label}'s {n_dof} free dofs")
    settings = {"range": [s_lo, s_hi] if ranged else None, "modes": int(n_modes)}
    crit, onset, probe_nodes, floor = (), (), (), ()
    if "separation-margin" in names:
        if operating is None:
            raise InputError("--operating: separation-margin needs the operating range, --operating LO HI (rad/s)")
        op_lo, op_hi = (float(v) for v in operating)
        if not 0 < op_lo <= op_hi:
            raise InputError(f"--operating {op_lo:g} {op_hi:g}: needs 0 < LO <= HI (rad/s)")
        c_lo, c_hi = (0.0, 2.0 * op_hi) if critical_range is None else (float(v) for v in critical_range)
        crit = tuple((float(W), int(k)) for W, k in critical_speeds_1x(scene, c_lo, c_hi, n_modes=min(12, n_dof),
                                                                      whirl="forward"))
        if not crit:
            raise InputError(f"separation-margin: {label} has no forward 1x critical speed in {c_lo:g}..{c_hi:g} "
                             "rad/s to separate from the operating range")
        settings.update(operating=[op_lo, op_hi], critical_range=[c_lo, c_hi], critical_speeds=[w for w, _ in crit])
    if "onset" in names:
        found = [t for t in stability_thresholds(lambda s: linear_margin(scene, s), s_lo, s_hi)
                 if t.stable_side == "below"]
        if not found:
            raise InputError(f"onset: {label} has no stability onset (stable below, unstable above) in --range "
                             f"{s_lo:g} {s_hi:g}")
        lam = np.asarray(damped_eigenvalues(scene, found[0].speed))
        whirl = float(np.imag(lam[np.argmax(np.real(lam))]))    # the mode that turns unstable there
        onset = (found[0].speed, whirl)
        settings.update(onset=onset[0], onset_frequency=whirl)
    if "response" in names:
        if not any(isinstance(c, Unbalance) for c in parts.components):
            raise InputError(f"response: {label} has no [[unbalance]] to respond to")
        n_nodes = parts.rotor.n_nodes
        probe_nodes = tuple(range(n_nodes)) if probes is None else tuple(int(p) for p in probes)
        for p in probe_nodes:
            if not 0 <= p < n_nodes:
                raise InputError(f"--probe {p}: {label} has nodes 0..{n_nodes - 1}")
        settings["probes"] = list(probe_nodes)
    n_floor = 33 if n_grid is None else int(n_grid)
    if n_floor < 2:
        raise InputError(f"--grid {n_floor}: at least 2")
    if "min-log-dec" in names:
        if max_frequency is None:
            counted, n_eig, cut = mode_cut(scene, s_lo, s_hi, int(n_modes), n_floor)
        else:
            if not max_frequency > 0:
                raise InputError(f"--max-frequency {max_frequency:g}: must be > 0 (rad/s)")
            cut = np.full(n_floor, float(max_frequency))
            f0 = np.imag(np.asarray(damped_eigenvalues(scene, s_hi, min(n_dof, 40))))
            counted = int(np.sum(f0 < max_frequency))
            n_eig = min(n_dof, counted + 4)
        floor = (n_eig, n_floor, cut)
        settings.update(log_dec_modes_counted=counted, log_dec_max_frequency=[float(np.min(cut)), float(np.max(cut))])
    stable = None
    if "stable-range" in names:
        stable = stable_speeds(eqx.Partial(_linear_margin, scene), parts, (s_lo, s_hi), label=label)
        # each threshold followed on its crossing mode's real part (the largest is kinked where modes overtake)
        freqs = []
        for t in stable.thresholds:
            lam = np.asarray(damped_eigenvalues(scene, t))
            freqs.append(float(np.imag(lam[np.argmax(np.real(lam))])))
        stable = dataclasses.replace(stable, follow=eqx.Partial(_crossing_mode, scene, jnp.asarray(freqs)))
        settings.update(stable.settings(), threshold_frequencies=freqs)
    return SceneQuantities(names, settings, scene, (s_lo, s_hi), crit, onset, probe_nodes, floor,
                           400 if n_grid is None else int(n_grid), stable)


def _linear_margin(template, parts, speed):
    return linear_margin(scene_from(parts, template), speed)


def _crossing_mode(template, frequencies, parts, speed, i):
    return mode_real_part(scene_from(parts, template), speed, frequencies[i])


@dataclasses.dataclass(frozen=True, eq=False)
class StableSpeeds:
    """How much of `speed_range` a reference motion is stable over, as a smooth
    function of its parameters: the stability thresholds the nominal motion has in the
    `scanned` range (wider than `speed_range`, so that a threshold moving in from
    outside is followed too), each followed by `secant_root` on `margin(params,
    speed)` (pure JAX; < 0 stable), or on `follow(params, speed, i)`, threshold `i`'s
    own smooth margin (a rotor's crossing mode: the largest real part is kinked where
    another mode leads), and `stable[i]`, whether the motion is stable between
    threshold `i - 1` and `i` (the scanned range's ends outside them).

    `evaluate(params) -> {"stable-range": length, "threshold_i": speed}` (the
    thresholds in `speed_range`): the length the sum of the stable intervals clipped
    to `speed_range` (its derivative the thresholds', by the implicit function
    theorem). An unstable band between two thresholds that has closed (both ends lost or
    crossed, and the motion stable at the band's nominal middle) counts as closed, its
    two thresholds reported at that middle; NaN where a threshold is lost otherwise (its
    last secant step above `TOLERANCE` of the speed) or two have crossed, which a
    search steps back from and a Monte Carlo counts out. A band that opens where the
    nominal motion had none is not seen: `scanned_length` checks a design afresh."""

    margin: object
    speed_range: tuple
    scanned: tuple
    thresholds: tuple
    stable: tuple
    unit: str = "rad/s"
    follow: object = None

    #: a followed threshold whose last secant step exceeds this (relative to the speed) is lost
    TOLERANCE = 1e-6

    def outputs(self) -> tuple:
        lo, hi = self.speed_range
        inside = [t for t in self.thresholds if lo <= t <= hi]
        return ("stable-range",) + tuple(f"threshold_{i}" for i in range(len(inside)))

    def settings(self) -> dict:
        return {"stable_range_scanned": list(self.scanned), "thresholds": list(self.thresholds),
                "stable_between_thresholds": list(self.stable)}

    def evaluate(self, params) -> dict:
        lo, hi = self.speed_range
        x = jnp.zeros(0)
        if self.thresholds:
            x, step = jax.vmap(lambda g, i: _followed(self._branch(i), params, g))(
                jnp.asarray(self.thresholds), jnp.arange(len(self.thresholds)))
            bad = ~jnp.isfinite(x) | (step > self.TOLERANCE * jnp.maximum(jnp.abs(x), 1.0))
            x = self._closed_bands(params, x, bad)
        edges = jnp.clip(jnp.concatenate([jnp.asarray(self.scanned[:1]), x, jnp.asarray(self.scanned[1:])]),
                         lo, hi)
        out = {"stable-range": jnp.sum(jnp.where(jnp.asarray(self.stable), jnp.diff(edges), 0.0))}
        inside = [i for i, t in enumerate(self.thresholds) if lo <= t <= hi]
        out.update({f"threshold_{j}": x[i] for j, i in enumerate(inside)})
        return out

    def _branch(self, i):
        """Threshold `i`'s margin, `(params, speed) -> value`."""
        if self.follow is None:
            return self.margin
        return lambda p, s: self.follow(p, s, i)

    def _closed_bands(self, params, x, bad):
        """The followed thresholds, an unstable band that has closed (its two ends lost
        or crossed, and the motion stable at the nominal band's middle) made one of
        zero width there; NaN where a threshold is lost otherwise, or two have crossed."""
        t = self.thresholds
        bands = [i for i in range(len(t) - 1) if not self.stable[i + 1]]
        if bands:
            mids = jnp.asarray([0.5 * (t[i] + t[i + 1]) for i in bands])
            frozen = jax.lax.stop_gradient(params)
            stable_mid = jax.vmap(lambda s: self.margin(frozen, s))(mids) < 0
            for j, i in enumerate(bands):
                closed = (bad[i] | bad[i + 1] | (x[i + 1] <= x[i])) & stable_mid[j]
                x = x.at[i].set(jnp.where(closed, mids[j], x[i])).at[i + 1].set(jnp.where(closed, mids[j], x[i + 1]))
                bad = bad.at[i].set(bad[i] & ~closed).at[i + 1].set(bad[i + 1] & ~closed)
        lost = jnp.any(bad) | jnp.any(jnp.diff(x) < 0)
        return jnp.where(lost, jnp.nan, x)

    def scanned_length(self, params, n_scan=200) -> tuple:
        """`(length, thresholds)` at `params` found afresh (`stability_thresholds` on
        `n_scan` speeds of the scanned range, bisection to 1e-10): what `evaluate`
        follows, to check it where a band may have opened or closed."""
        lo, hi = self.speed_range
        a, b = self.scanned
        found = stability_thresholds(eqx.Partial(_at_nominal, self.margin, params), a, b, n_scan=n_scan)
        if found:
            stable = [found[0].stable_side == "below"] + [f.stable_side == "above" for f in found]
        else:
            stable = [float(self.margin(params, jnp.float64(0.5 * (lo + hi)))) < 0]
        edges = np.clip([a] + [f.speed for f in found] + [b], lo, hi)
        return float(np.sum(np.where(stable, np.diff(edges), 0.0))), [f.speed for f in found]


#: margin evaluations per followed threshold (a threshold near the margin's extremum, its slope small at the
#: guess, took 8; a converged one stays put)
ITERS = 10


def _followed(margin, params, guess):
    """A threshold followed from `guess` (`secant_root`) and its last step's size."""
    x, _, step = secant_root(margin, params, guess, iters=ITERS, with_step=True)
    return x, step


def stable_speeds(margin, params, speed_range, *, n_scan=40, pad=0.25, label="the rotor",
                  unit="rad/s") -> StableSpeeds:
    """Set up `StableSpeeds` of `margin(params, speed)` on the nominal `params`: its
    thresholds in `speed_range` widened by `pad` of its width either side (above half
    its bottom), found by `stability_thresholds` on `n_scan` speeds."""
    lo, hi = (float(v) for v in speed_range)
    if not (np.isfinite(lo) and np.isfinite(hi) and 0 <= lo < hi):
        raise InputError(f"--range {lo:g} {hi:g}: stable-range needs 0 <= LO < HI ({unit})")
    width = hi - lo
    a, b = (max(lo - pad * width, 0.5 * lo) if lo > 0 else 0.0), hi + pad * width
    found = stability_thresholds(eqx.Partial(_at_nominal, margin, params), a, b, n_scan=n_scan)
    if found:
        stable = [found[0].stable_side == "below"] + [t.stable_side == "above" for t in found]
    else:
        m = float(margin(params, jnp.float64(0.5 * (lo + hi))))
        if not np.isfinite(m):
            raise InputError(f"stable-range: the stability margin of {label} is not finite at {0.5 * (lo + hi):g} "
                             f"{unit} (no reference motion there)")
        stable = [m < 0]
    return StableSpeeds(margin, (lo, hi), (a, b), tuple(t.speed for t in found), tuple(bool(v) for v in stable),
                        unit)


def _at_nominal(margin, params, speed):
    return margin(params, speed)


def _separation(r, crit, op_lo, op_hi):
    slacks = []
    for W, k in crit:
        w, res = critical_speed(r, k, W)
        w = jnp.where(jnp.abs(res) <= ROOT_TOLERANCE * jnp.abs(w), w, jnp.nan)
        af = amplification_factor(damped_eigenvalues(r, w, k + 1)[k])
        slacks.append(separation_slack(w, af, op_lo, op_hi))
    return soft_min(jnp.stack(slacks), 0.05)


def _response(scene, probes, lo, hi, n, fine=33):
    """The largest unbalance-response amplitude at the probes over `[lo, hi]`: each
    probe's peak on `n` speeds, then on `fine` speeds across the grid interval either
    side, then the vertex of the parabola through the log amplitude at the three
    speeds about that (a peak between grid speeds, to the parabola's error, so the
    quantity does not wobble as a resonance slides across the grid), then a soft
    maximum over the probes (at most 1e-3 of the log above). The traced counterpart
    of `_peaks.refine_maxima` (which zooms to 1e-10 on the host, and so neither vmaps
    nor differentiates); no loop: compiled loops around these solves' gradients
    deadlocked XLA's CPU runtime (a bisection did, in a vmapped Monte Carlo)."""
    speeds = np.linspace(max(lo, 1e-3 * hi), hi, n)
    idx = np.asarray(probes) * DOFS_PER_NODE
    rows = np.arange(len(probes))

    def log_amp(s):                                                  # s (m,) -> (probes, m)
        full = scene.expand(scene_unbalance_response(scene, s).T)    # (n_dofs, m)
        return 0.5 * jnp.log(jnp.abs(full[idx]) ** 2 + jnp.abs(full[idx + 1]) ** 2)

    grid = jnp.asarray(speeds)
    i = jnp.argmax(log_amp(grid), axis=1)                            # each probe's grid peak
    a, b = grid[jnp.maximum(i - 1, 0)], grid[jnp.minimum(i + 1, n - 1)]
    t = jnp.linspace(0.0, 1.0, fine)
    s = jax.lax.stop_gradient(a[:, None] + (b - a)[:, None] * t[None, :])          # (probes, fine)
    f = log_amp(s.ravel()).reshape(len(probes), len(probes), fine)[rows, rows]  # each probe at its own speeds
    k = jnp.clip(jnp.argmax(f, axis=1), 1, fine - 2)
    f0, f1, f2 = f[rows, k - 1], f[rows, k], f[rows, k + 1]
    curv = f0 - 2 * f1 + f2
    shift = jnp.clip(jnp.where(curv < 0, 0.5 * (f0 - f2) / jnp.where(curv < 0, curv, -1.0), 0.0), -1.0, 1.0)
    peaks = jnp.maximum(f1 - 0.25 * (f0 - f2) * shift, jnp.max(f, axis=1))
    return jnp.exp(-soft_min(-peaks, 1e-3))
