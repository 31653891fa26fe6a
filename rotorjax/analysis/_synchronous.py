"""The synchronous response of a nonlinear rotor, traced through speed.

For a scene that is autonomous in the rotating frame at constant speed (an
isotropic rotor: isotropic bearings, nonlinear or not, an unbalance), the
synchronous orbit is a rest point `z(speed)` of the rotating-frame equations.
`synchronous_branch` starts from the linear unbalance response, corrects it onto
the nonlinear equations by Newton, and continues it in the speed with the
pseudo-arclength continuation of `continue_branch`: folds (the jumps of a
hardening bearing's response), their stability and Hopf points come with it.
"""

import dataclasses

import equinox as eqx
import jax.numpy as jnp
import numpy as np

from .._errors import InputError, NumericalError
from .._newton import newton
from ..models._contract import require
from ..models._speed import ConstantSpeed
from ..models._validate import check_span
from ._continuation import Branch, continue_branch, physical_stops
from ._response import scene_unbalance_response
from ._rotating import rotating_field


def synchronous_branch(scene, speed_range, speed0=None, ds=0.05, ds_max=0.5, max_points=200,
                       tol=1e-11) -> Branch:
    """The branch of synchronous orbits of `scene` (its speed replaced by
    `ConstantSpeed(speed)`) from `speed0` (default: the range's low end) within
    `speed_range = (lo, hi)`.

    Returns a `Branch` in physical units: `p` the speeds, `u` the rotating-frame
    states (`scene.to_fixed(0, u)` is the fixed-frame state at `t = 0`), `stable`,
    and `events` (`BranchEvent`s: "fold" with its refined speed, "hopf" with its
    whirl frequency in rad/s; their residuals are those of the scaled system). The
    continuation runs on scaled variables (lengths by the largest linear response in
    the range, speed and time by `speed0`) so that the arclength weighs both alike;
    `margin` is in 1/s.
    """
    try:
        lo, hi = speed_range
    except (TypeError, ValueError):
        raise InputError(f"speed_range must be a pair (lo, hi), got {speed_range!r}") from None
    lo, hi = check_span("speed_range[0]", lo, "speed_range[1]", hi)
    speed0 = lo if speed0 is None else float(speed0)
    if not lo <= speed0 <= hi:
        raise InputError(f"speed0 = {speed0} must lie in speed_range = ({lo}, {hi})")
    require(scene, "to_rotating", "synchronous_branch")
    require(scene, "unbalance_load", "synchronous_branch")

    def make_scene(w):
        return eqx.tree_at(lambda s: s.speed, scene, ConstantSpeed(w))

    scene0 = make_scene(speed0)
    Q = np.asarray(scene_unbalance_response(scene0, jnp.array([float(speed0)])))[0]
    y_lin = scene0.state_from_response(Q, float(speed0))
    n = scene0.n_dof
    # the length scale: the largest linear response over the range (the resonance)
    su = float(np.max(np.abs(np.asarray(scene_unbalance_response(scene0, jnp.linspace(lo, hi, 65))))))
    su = max(su, 1e-300)
    sp = float(speed0)
    scale = jnp.concatenate([jnp.full(n, su), jnp.full(scene0.state_size - n, su * sp)])

    def F(u, p):
        # time in units of 1/sp, lengths by su: a similarity transform, so the
        # Jacobian's eigenvalues are the physical ones divided by sp
        return rotating_field(make_scene(sp * p), 0.0, u * scale) / (scale * sp)

    z0 = np.asarray(scene0.to_rotating(0.0, y_lin)) / np.asarray(scale)
    z0, _ = newton(lambda z: F(z, 1.0), jnp.asarray(z0), 1e-12, 30, floor=1e-10, unit=1.0)
    r = float(jnp.max(jnp.abs(F(z0, 1.0))))
    if not r < 1e-8:
        raise NumericalError(f"synchronous_branch: Newton from the linear response at speed {sp} did not "
                             f"converge (residual {r:.2e})")
    br = continue_branch(F, z0, 1.0, p_bounds=(lo / sp, hi / sp), ds=ds, ds_max=ds_max, max_points=max_points,
                         tol=tol, name="speed")
    # back to physical units: a Hopf frequency, as the margin, is an eigenvalue of the scaled field (times 1/sp)
    events = [dataclasses.replace(e, p=e.p * sp, u=np.asarray(e.u) * np.asarray(scale),
                                  frequency=None if e.frequency is None else e.frequency * sp) for e in br.events]
    stops = physical_stops(br.curve.stops, "speed", lambda v: v * sp, lo, hi)
    curve = dataclasses.replace(br.curve, stops=stops)
    return Branch(u=br.u * np.asarray(scale), p=br.p * sp, margin=br.margin * sp, stable=br.stable,
                  events=events, curve=curve)
