"""A rotor's static equilibrium in its fluid-film bearings, reported per bearing:
where each journal sits (eccentricity ratio, attitude angle, minimum film
thickness) and the load it carries.

The equilibrium is `rotorjax.models.static_equilibrium` (Newton on the whole
finite-element rotor). Each film's load is the force it exerts on the shaft, `F`;
the attitude angle is measured from the load line (the direction of `-F`, what the
journal presses the film with) to the line of centres, in the direction of
rotation; the minimum film thickness is `c - e`.
"""

import dataclasses

import numpy as np

from .._errors import InputError, NumericalError
from ..models._equilibrium import _state, films, static_equilibrium
from ..models._fe_rotor import DOFS_PER_NODE


@dataclasses.dataclass(frozen=True)
class FilmState:
    """One fluid film at the equilibrium (SI units, angles in rad)."""

    node: int
    kind: str
    eccentricity: float
    attitude: float
    min_film: float
    load: float
    force: tuple
    position: tuple

    def as_dict(self):
        return dataclasses.asdict(self)


@dataclasses.dataclass(frozen=True)
class BearingEquilibrium:
    """The static equilibrium at `speed` (rad/s): `displacement` `(x, y)` per node
    (m), the `films` (`FilmState`), Newton's `residual` and `iterations`, and `q`
    (the shaft coordinates, for a run or a linearisation to start from)."""

    speed: float
    displacement: np.ndarray
    films: tuple
    residual: float
    iterations: int
    q: np.ndarray


def bearing_equilibrium(scene, speed) -> BearingEquilibrium:
    """The static equilibrium of a `RotorScene` on fluid films at `speed` (rad/s, > 0).

    **Raises:** `InputError` for a scene without fluid films or a speed <= 0 with
    journal bearings (a film that does not spin carries no static load);
    `NumericalError` where Newton does not converge."""
    fl = films(scene)
    if not fl:
        raise InputError("bearing_equilibrium: the rotor has no fluid-film bearings ([[bearing]] of type \"journal\" "
                         "or \"sfd\"); its static deflection is `static`")
    speed = float(speed)
    if any(c.spins for c in fl) and not speed > 0:
        raise InputError(f"bearing_equilibrium: speed = {speed:g} rad/s: a journal bearing carries its load only "
                         f"while the shaft spins; give a speed > 0")
    eq = static_equilibrium(scene, speed)
    if not bool(eq.converged):
        raise NumericalError(f"static equilibrium at {speed:g} rad/s not found: relative residual "
                             f"{float(eq.residual):.2e} after {int(eq.iterations)} Newton steps (a journal may be "
                             f"pressed against its wall: the load is too high for the film at this speed)")
    zero = np.zeros(scene.n_shaft)
    s = _state(scene, eq.q, zero, speed)
    rows = []
    for c in fl:
        u = np.asarray(s.position(c.node))
        f = np.asarray(c.force(s, None, None).f)
        e = float(np.hypot(*u))
        load_dir = -f / max(np.hypot(*f), 1e-300)
        attitude = float(np.arctan2(load_dir[0] * u[1] - load_dir[1] * u[0], load_dir @ u))
        rows.append(FilmState(node=c.node, kind=c.kind, eccentricity=e / float(c.clearance), attitude=attitude,
                              min_film=float(c.clearance) - e, load=float(np.hypot(*f)),
                              force=(float(f[0]), float(f[1])), position=(float(u[0]), float(u[1]))))
    n = scene.n_nodes
    x = np.asarray(scene.E @ eq.q)
    disp = np.stack([x[0:DOFS_PER_NODE * n:DOFS_PER_NODE], x[1:DOFS_PER_NODE * n:DOFS_PER_NODE]], axis=1)
    return BearingEquilibrium(speed=speed, displacement=disp, films=tuple(rows), residual=float(eq.residual),
                              iterations=int(eq.iterations), q=np.asarray(eq.q))
