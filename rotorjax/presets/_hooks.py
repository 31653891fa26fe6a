"""What several presets offer alike: the JSON rows of planar regimes, the
`regimes` hook of scenes `steady_states` solves, and the critical speeds of a
finite-element rotor (the `ross-compare` preset and rotor files)."""

import numpy as np

from .._errors import InputError


def regime_row(r) -> dict:
    """A planar scene's stationary regime (`rotorjax.analysis.Regime`) as a JSON row."""
    return {
        "whirl_amplitude": float(r.whirl_amplitude),
        "weight_angles": [float(a) for a in np.asarray(r.weight_angles)],
        "max_eigenvalue_real_part": float(r.margin),
        "verdict": r.verdict,
        "kind": r.kind,
        "residual": float(r.residual),
        "state_rotating_frame": [float(v) for v in np.asarray(r.z)],
    }


def scene_regimes(build, constant_speed: dict):
    """A `regimes` hook for presets whose scene `steady_states` solves: every
    stationary regime of `build(params).scene` with `constant_speed` (e.g. a zero
    run-up rate) applied."""

    def regimes(params, n_angles=16, stage=None):
        from ..analysis import steady_states

        stage = stage or (lambda text: None)
        stage("building the scene")
        scene = build(dict(params, **constant_speed)).scene
        stage(f"Newton from {n_angles} starts per weight angle, stability by autodiff (one compiled call)")
        return [regime_row(r) for r in steady_states(scene, n_angles=n_angles)], []

    return regimes


def fe_rotor(scene):
    """The `FlexibleRotor` (or `ReducedRotor`) of a finite-element rotor scene."""
    from ..models import RotorScene

    if not isinstance(scene, RotorScene):
        raise InputError(f"needs a finite-element rotor (RotorScene), got {type(scene).__name__}")
    return scene.rotor


def rotor_dofs(rotor) -> int:
    """Free degrees of freedom of a `FlexibleRotor` (or a reduced one, or a
    `RotorScene`'s shaft coordinates)."""
    if hasattr(rotor, "n_shaft"):
        return int(rotor.n_shaft)
    return int(np.asarray(rotor.reduced_matrices()[0]).shape[0])


def _components_add_nothing(scene, rotor) -> bool:
    """The scene's linear part is the bare rotor's (no component adds damping or
    stiffness), so the rotor-only analyses apply to it."""
    full = getattr(rotor, "rotor", rotor)
    return all(c.linear_part(full) is None for c in scene.components)


def fe_critical_speeds(build, params, lo, hi, n_scan=200, n_modes=None, exact=False, progress=True,
                       name="the rotor") -> dict:
    """Critical speeds of a finite-element rotor in `[lo, hi]` (rad/s): the 1x
    crossings of its first `n_modes` (default 8) damped natural frequencies, each
    with its whirl direction, and for an undamped rotor with symmetric stiffness the
    roots of the synchronous determinant too; `"campbell"` holds the diagram to plot
    (the scan's `n_scan` speeds), `"present"` its unit and title. A rotor with rigid-body modes is
    refused (`check_supported`; `name` names it in the message)."""
    from ..flexible import check_supported, critical_speeds_1x, modes, synchronous_critical_speeds
    from ..models import check_speeds

    scene = build(params).scene
    rotor = fe_rotor(scene)   # the linear analyses take the scene: components' linearisations count
    check_supported(scene, hi, what=name)
    check_speeds(scene, [lo, hi])
    n_modes = n_modes or 8
    n = 2 * rotor_dofs(rotor)
    if n_modes > n:
        raise InputError(f"--modes {n_modes}: the rotor has {n} modes")
    found, (speeds, camp) = critical_speeds_1x(scene, lo, hi, n_scan=n_scan, n_modes=n_modes, return_scan=True)
    fwd = [bool(modes(scene, s, n_modes).forward[k]) for s, k in found]
    out = {"unit": "rad/s", "critical_speeds": [{"speed": s, "mode": k, "whirl": "forward" if f else "backward"}
                                                for (s, k), f in zip(found, fwd)]}
    M, C, _, K = (np.asarray(a) for a in rotor.reduced_matrices())
    if (not getattr(rotor, "speed_dependent", False) and not np.any(C) and _components_add_nothing(scene, rotor)
            and np.allclose(K, K.T, rtol=1e-12, atol=1e-12 * np.abs(K).max())):
        roots = np.asarray(synchronous_critical_speeds(rotor))
        out["synchronous_determinant_roots"] = [float(r) for r in roots if lo <= r <= hi]
    out["campbell"] = (speeds, np.asarray(camp.frequencies), np.asarray(camp.forward))   # the scan's
    out["present"] = {"unit": "rad/s", "title": "critical speeds (1x crossings)"}
    return out
