"""ISO 21940 reporting of a balancing, for every scene: ISO 21940-11's permissible
residual unbalance and the grade a residual reaches (rigid behaviour), and ISO
21940-12's counts for a flexible rotor (the N-plane and N+2-plane methods, the
balancing speeds), from the rotor model's critical speeds.
"""

import numpy as np

from ..models._validate import as_numpy


def permissible_unbalance(G, mass, omega):
    """ISO 21940-11 permissible residual unbalance `U_per = 1000 G m / Omega` in
    g mm, for grade `G` (mm/s), rotor mass `m` (kg), speed `Omega` (rad/s)."""
    for name, v in (("G", G), ("mass", mass), ("omega", omega)):
        as_numpy(name, v, sign="positive")
    return 1000.0 * G * mass / omega


ISO_GRADES = (0.4, 1.0, 2.5, 6.3, 16.0, 40.0, 100.0, 250.0, 630.0, 1600.0, 4000.0)


def grade_reached(residual_gmm, mass, omega):
    """The finest ISO grade whose permissible unbalance holds the residual (g mm)."""
    as_numpy("residual_gmm", residual_gmm, sign="nonnegative", shape=())
    for name, v in (("mass", mass), ("omega", omega)):
        as_numpy(name, v, sign="positive", shape=())
    for G in ISO_GRADES:
        if residual_gmm <= permissible_unbalance(G, mass, omega):
            return G
    return None


def total_mass(rotor):
    """Total mass of a `FlexibleRotor` (a `ReducedRotor`: its full rotor), kg
    (`FlexibleRotor.mass`: shaft, disks and point masses; pedestals are not the rotor's)."""
    return float(rotor.full_rotor.mass())


def equivalent_unbalance(A, X):
    """The residual unbalance (kg m) that vibration `X` corresponds to: the unbalance
    which, at a correction plane of the rotor's mean sensitivity (rms over the
    planes of `||A[:, p]||`), makes vibration as large (2-norm over the
    measurements) as `X`."""
    sens = np.sqrt(np.mean(np.sum(np.abs(A) ** 2, axis=0)))
    return float(np.linalg.norm(X) / sens) if sens > 0 else float("nan")


def fmt(values):
    return ", ".join(f"{v:.4g}" for v in values)


def iso_12(rotor, planes, used, service):
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
            f"({1.1 * service:.4g} rad/s)" + (f": {fmt(crit)} rad/s." if N else ".")]
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
                f"({fmt(wanted)} rad/s); the data's speeds were {fmt(used)} rad/s"
                + (f", none within 10 % of {fmt(missing)} rad/s." if missing else
                   ", one within 10 % of each of them."))
    return crit, text
