"""`rotorjax demo`: a short representative study (under two minutes on 2 CPU cores).

1. Model 000, run-up `nu = 0.16 tau` through resonance: no balancer, circular race,
   elliptic race (the paper's Fig. 3).
2. Model 001, a vmapped sweep of the main motion's fate over 96 speeds, against the
   paper's empirical criterion (eq. 18).
"""

import json
import os
import time

import jax.numpy as jnp
import numpy as np

from .solve import simulate
from .models import AutoBalancer, weights_at
from .plot import plot_curves
from .presets import anisotropic_abb, jeffcott_abb
from .sweep import sweep


def runup_000(nu_end=4.0, nu_dot=0.16, n_save=400):
    """Whirl amplitude against speed for the three rotors of the paper's Fig. 3."""
    base = dict(jeffcott_abb.PRESET.defaults)
    groups = {k: base[k] for k in jeffcott_abb.GROUPS}
    cases = {
        "no balancer": (groups, False),
        "circular race": (dict(groups, rho1=1.0, rho2=1.0), True),
        "elliptic race": (groups, True),
    }
    curves, info = {}, {}
    for label, (g, with_balancer) in cases.items():
        scene = jeffcott_abb.scene_from_groups(**g, nu_dot=nu_dot, with_balancer=with_balancer)
        if with_balancer:
            race = scene.find(AutoBalancer).race
            polar = g["alpha"] + base["psi1"] + np.arange(2) * base["psi_spacing"]
            y0 = scene.rest_state(weights_at(polar, race))
        else:
            y0 = scene.rest_state()
        r = simulate(scene, y0, (0.0, nu_end / nu_dot), saveat=n_save)
        curves[label] = np.asarray(r.outputs["whirl_amplitude"])
        speed = nu_dot * np.asarray(r.ts)
        above = speed > 2.5
        info[label] = {
            "success": bool(r.success), "message": r.message,
            "peak_amplitude": float(curves[label].max()),
            "speed_at_peak": float(speed[np.argmax(curves[label])]),
            "max_amplitude_above_nu_2.5": float(curves[label][above].max()),
        }
    return speed, curves, info


def sweep_001(n_lo=0.5, n_hi=10.0, n_speeds=96, t_end=200.0):
    """Largest whirl amplitude over the last 10 time units from a perturbed main
    motion, at each speed (vmapped over speeds)."""
    p = dict(anisotropic_abb.PRESET.defaults)
    groups = {k: p[k] for k in anisotropic_abb.GROUPS}
    N = anisotropic_abb.n_weights_from_sigma(p["sigma"])
    angles = anisotropic_abb.main_motion_angles(N, p["c"]) + p["perturbation"] * np.cos(
        np.arange(N) + 1.0
    )
    ts = jnp.linspace(t_end - 10.0, t_end, 64)

    def one(point):
        scene = anisotropic_abb.scene_from_groups(**groups, n=point["n"], K=p["K"])
        r = simulate(scene, scene.rest_state(angles), (0.0, t_end), saveat=ts, solver="dopri8",
                     rtol=1e-7, atol=1e-9)
        return {"amplitude": jnp.max(r.outputs["whirl_amplitude"]), "code": r.code}

    res = sweep(one, {"n": np.linspace(n_lo, n_hi, n_speeds)}, chunk_size=32, progress=False)
    return res


def _save(fig, path):
    """The demo's PNG (`rotorjax demo` has chosen matplotlib's Agg backend)."""
    import matplotlib.pyplot as plt

    fig.savefig(path, dpi=120)
    plt.close(fig)


def run_demo(out="rotorjax-out"):
    os.makedirs(out, exist_ok=True)
    summary = {}
    t0 = time.perf_counter()
    speed, curves, info = runup_000()
    _save(plot_curves(speed, curves, x_label="speed nu", y_label="whirl amplitude",
                      title="Model 000: run-up nu = 0.16 tau through resonance (paper Fig. 3)"),
          os.path.join(out, "runup_000.png"))
    summary["runup_000"] = info
    t1 = time.perf_counter()
    res = sweep_001()
    n = res.axes["n"]
    p = anisotropic_abb.PRESET.defaults
    crit = anisotropic_abb.criterion_polynomial(n, p["n_eta"], p["mu_xi"], p["mu_eta"])
    amp = res["amplitude"]
    _save(plot_curves(n, {"max whirl amplitude, last 10 time units": amp}, x_label="speed n",
                      y_label="whirl amplitude", log=True, shade=crit < 0,
                      title="Model 001: main motion after a perturbation, vs the criterion p(n) < 0"),
          os.path.join(out, "sweep_001.png"))
    t2 = time.perf_counter()
    summary["sweep_001"] = {
        "speeds": n.tolist(), "max_amplitude": amp.tolist(),
        "failed_points": int(np.sum(res["code"] != 0)),
        "balanced_speeds_fraction": float(np.mean(amp < 1e-3)),
    }
    summary["timings_s"] = {"runup_000": t1 - t0, "sweep_001": t2 - t1}
    with open(os.path.join(out, "demo_summary.json"), "w") as f:
        json.dump(summary, f, indent=2)
    print("Model 000 run-up (paper Fig. 3):")
    for label, i in info.items():
        print(f"  {label:14s} peak {i['peak_amplitude']:.4f} at nu = {i['speed_at_peak']:.2f}; "
              f"max above nu = 2.5: {i['max_amplitude_above_nu_2.5']:.4f}  [{i['message']}]")
    print(f"Model 001 sweep over {n.size} speeds: main motion kept (whirl < 1e-3) at "
          f"{100 * summary['sweep_001']['balanced_speeds_fraction']:.0f}% of speeds; "
          f"{summary['sweep_001']['failed_points']} failed points")
    print(f"wrote {out}/runup_000.png, {out}/sweep_001.png, {out}/demo_summary.json "
          f"({t2 - t0:.0f} s)")
    return summary
