"""Planning a time run: model only what the span and the tolerance reach.

A full finite-element rotor carries modes far above anything its excitation
reaches (ross_compare.toml: 28 dofs up to 5.2e4 rad/s, run at 50 rad/s). Started
from rest under a load, those modes ring, and an explicit solver must follow them
at the tolerance: Dopri8 would take about a million steps for 200 revolutions. An
implicit solver is no cure (it must follow a ringing mode as closely to keep the
tolerance: over the first 20 revolutions there, at rtol 1e-8, Kvaerno5 took 114 557
steps in 49 s, Dopri8 93 877 in 6.5 s; a probe). The cure is the one an
engineer applies, the modal reduction: `plan_run` keeps the modes an explicit run
can follow within the step budget, never fewer than those up to
`EXCITATION_MARGIN` times the highest speed of the run, and says so. A stiffness
that decays (a fluid film's damping on a light journal) is left to the solver
choice, which takes the implicit solver (`rotorjax.solve.choose_solver`).
"""

from typing import NamedTuple

import numpy as np

from .._errors import InputError
from ..models import provides
from ..solve import StiffnessEstimate, estimate_stiffness, is_stiff, jacobian_at

#: a reduction is made where the full model's estimate passes the step budget, and
#: keeps the modes that fit this fraction of it (the estimate errs by up to ~2.5x:
#: it counts every mode as ringing)
BUDGET_FRACTION = 0.5

#: a reduction keeps every mode up to this many times the run's highest speed (the
#: excitation's harmonics a nonlinear part makes), or is not made
EXCITATION_MARGIN = 10.0


class RunPlan(NamedTuple):
    """The model and start state a time run integrates (see the module docstring)."""

    scene: object
    y0: object
    modes: int | None              # modes kept (None: the scene as given)
    coordinates: int | None        # the full shaft's coordinates (a finite-element rotor)
    cutoff_frequency: float | None  # highest kept mode's frequency (rad per time unit)
    estimate_full: StiffnessEstimate
    estimate: StiffnessEstimate    # of the scene integrated
    reason: str
    implicit: bool                 # whether solver "auto" takes the implicit solver (`is_stiff`)

    def as_dict(self) -> dict:
        """The plan for a JSON report."""
        return {"modes": self.modes, "coordinates": self.coordinates, "cutoff_frequency": self.cutoff_frequency,
                "estimated_explicit_steps_full": self.estimate_full.explicit_steps,
                "estimated_explicit_steps": self.estimate.explicit_steps,
                "limiting_eigenvalue": self.estimate_full.limiting,
                "spectral_radius": self.estimate_full.spectral_radius, "reason": self.reason,
                "auto_solver": "Kvaerno5" if self.implicit else "Dopri8",
                "auto_solver_reason": ("a decaying eigenvalue makes the run stiff for an explicit solver"
                                       if self.implicit else "explicit: no decay stiff enough to pay for an "
                                       "implicit solver")}


def _reducible(scene) -> bool:
    return provides(scene, "reduce") and scene.reducible


def _count(modes, scene, n_max):
    if isinstance(modes, str) and modes in ("auto", "all"):
        return modes
    what = f"1..{n_max}" if n_max else "a count (for a finite-element rotor's full shaft only)"
    text = modes.strip() if isinstance(modes, str) else modes
    try:
        n = int(text)
    except (TypeError, ValueError):
        n = None
    if isinstance(modes, bool) or n is None or (not isinstance(modes, str) and n != modes):
        raise InputError(f"modes must be 'auto', 'all' or a number of modes {what}, got {modes!r}")
    if n_max is None:
        raise InputError(f"modes = {n}: only a finite-element rotor with its full shaft (a rotor file without "
                         f"rotor.n_modes) can be reduced; this scene is a {scene.describe()}")
    if not 1 <= n <= n_max:
        raise InputError(f"modes = {n}: the shaft has {n_max} coordinates (modes must be 1..{n_max}, "
                         "'auto' or 'all')")
    return n


def _top_speed(scene, t0, t_end) -> float:
    ts = np.linspace(float(t0), float(t_end), 65)
    return float(max(abs(float(scene.speed.speed(np.float64(t)))) for t in ts))


def plan_run(scene, y0, t_end, rtol, max_steps, modes="auto", t0=0.0) -> RunPlan:
    """The scene to integrate over `(t0, t_end)` at `rtol` within `max_steps`.

    **Arguments:**
    - `modes`: "auto" (reduce a finite-element rotor's full shaft when Dopri8's
      estimated steps, `rotorjax.solve.estimate_stiffness`, pass `max_steps`
      because a mode rings too fast; keep the most modes that fit
      `BUDGET_FRACTION` of it, and at least those up to `EXCITATION_MARGIN` times
      the top speed, else keep all), "all" (the scene as given), or a number of
      modes.

    **Returns:** a `RunPlan`; its `y0` is `y0` projected on the kept modes."""
    freqs = scene.reduction_basis()[0] if _reducible(scene) else None
    n_all = None if freqs is None else freqs.size     # the full shaft's coordinates
    modes = _count(modes, scene, n_all)
    jac = jacobian_at(scene, y0, t0)

    def estimate(n=None):   # of the scene reduced to n modes: its linearisation projected
        if n is None:
            return estimate_stiffness(scene, y0, t0, t_end, rtol, np.linalg.eigvals(jac))
        E, P = (np.asarray(a) for a in scene.reduction_maps(n))
        return estimate_stiffness(scene, y0, t0, t_end, rtol, np.linalg.eigvals(P @ jac @ E))

    full = estimate()
    keep = lambda reason: RunPlan(scene, y0, None, n_all, None, full, full, reason,  # noqa: E731
                                  is_stiff(full, max_steps))
    if modes == "all":
        return keep("all coordinates, as asked")
    if modes == "auto":
        budget = BUDGET_FRACTION * max_steps
        if freqs is None:
            return keep("the scene as given")
        if full.explicit_steps <= max_steps:
            return keep("all coordinates: an explicit run fits the step budget")
        if full.limiting != "oscillation":
            return keep("all coordinates: the stiffness decays (the solver choice takes it)")
        floor = max(1, int(np.searchsorted(freqs, EXCITATION_MARGIN * _top_speed(scene, t0, t_end), side="right")))
        fits = lambda n: estimate(n).explicit_steps <= budget  # noqa: E731
        if floor >= n_all or not fits(floor):
            return keep(f"all coordinates: no reduction keeping the modes up to {EXCITATION_MARGIN:g}x the top "
                        "speed fits the step budget (raise max_steps, or give the number of modes)")
        lo, hi = floor, n_all      # fits(lo); the full model does not fit
        while hi - lo > 1:
            mid = (lo + hi) // 2
            lo, hi = (mid, hi) if fits(mid) else (lo, mid)
        modes = lo
        reason = (f"reduced to the {modes} lowest of {n_all} modes: with all of them Dopri8 would take about "
                  f"{full.explicit_steps:.3g} steps at rtol {float(rtol):g} (budget {max_steps}), ringing at "
                  f"{full.spectral_radius:.3g} rad per time unit")
    else:
        reason = f"reduced to the {modes} lowest of {n_all} modes, as asked"
    P = scene.reduction_maps(modes)[1]
    kept = estimate(modes)
    return RunPlan(scene.reduce(modes), P @ y0, modes, n_all, float(freqs[modes - 1]),
                   full, kept, reason, is_stiff(kept, max_steps))
