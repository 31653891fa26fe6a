# ---
# jupyter:
#   jupytext:
#     formats: py:percent
#   kernelspec:
#     name: python3
#     display_name: Python 3
# ---

# %% [markdown]
# # Stability boundaries by continuation
#
# 1. Model 001: the boundary of the auto-balancing main motion in the plane
#    (speed `n`, weight damping `mu_w`), traced by pseudo-arclength continuation of
#    the Floquet margin's zero set, against a coarse grid map and the paper's
#    empirical criterion.
# 2. Model 003: the boundary of the balanced regime in (damping `d`, speed `omega`),
#    like the paper's Fig. 5.

# %%
import os

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt
import numpy as np

import rotorjax  # noqa: F401
from rotorjax.analysis import floquet_crossings, trace_boundary
from rotorjax.presets import anisotropic_abb as ab
from rotorjax.presets import flexible_abb as fa
from rotorjax.sweep import sweep

OUT = os.environ.get("ROTORJAX_NOTEBOOK_OUT", "notebook-out")
os.makedirs(OUT, exist_ok=True)
p = dict(ab.PRESET.defaults)
G = {k: p[k] for k in ab.GROUPS}


def margin(n, mu):
    return ab.main_motion_floquet(dict(G, mu_w=mu), n, p["K"]).margin


# %%
crossings = floquet_crossings(lambda n: ab.main_motion_floquet(G, n, p["K"]), 0.5, 10.0, n_scan=30)
for c in crossings:
    print(f"n = {c['p']:.6f}: {c['kind']} leaves the unit circle ({c['stable_side']} is stable)")

# %%
curves = []
for c in crossings[:2]:
    for direction in (1.0, -1.0):
        curves.append(trace_boundary(margin, (c["p"], G["mu_w"]), bounds=(np.array([0.5, 0.3]), np.array([10.0, 0.9])),
                                     ds=0.05, ds_max=0.15, max_points=8, gradient="fd", direction=(0.0, direction)))
print([cv.stopped for cv in curves])

# %%
grid = sweep(lambda q: margin(q["n"], q["mu_w"]), {"n": np.linspace(0.5, 6.0, 23), "mu_w": np.linspace(0.3, 0.9, 4)},
             chunk_size=23, progress=False)
fig, ax = plt.subplots(figsize=(7, 4))
ax.contourf(grid.axes["n"], grid.axes["mu_w"], np.asarray(grid.values).T < 0, levels=[-0.5, 0.5, 1.5],
            colors=["#f4cccc", "#d9ead3"])
for cv in curves:
    ax.plot(cv.x[:, 0], cv.x[:, 1], "k.-", lw=1)
for r in ab.criterion_roots(p["n_eta"], p["mu_xi"], p["mu_eta"], 0.5, 6.0):
    ax.axvline(r, color="b", ls=":", lw=0.8)
ax.set_xlabel("speed n")
ax.set_ylabel("mu_w")
ax.set_title("model 001: traced boundary (black), grid map (green stable), criterion (blue)")
fig.savefig(os.path.join(OUT, "boundary_001.png"), dpi=100)

# %% [markdown]
# ## Model 003: the balanced regime in (d, omega)

# %%
q = dict(fa.PRESET.defaults, n_balls=2, modes=6, d=0.1)


def margin_003(d, omega):
    return fa.PRESET.margin(dict(q, d=d, omega=omega))


start_omega = float(q["omega"])
m0 = float(margin_003(q["d"], start_omega))
print("margin of the balanced regime at the preset's point:", m0)
scan = sweep(lambda s: margin_003(s["d"], s["omega"]), {"d": np.array([q["d"]]), "omega": np.linspace(0.3, 3.0, 28)},
             chunk_size=28, progress=False)
ms = np.asarray(scan.values)[0]
idx = [i for i in range(ms.size - 1) if np.isfinite(ms[i]) and np.isfinite(ms[i + 1]) and np.sign(ms[i]) != np.sign(ms[i + 1])]
print("sign changes of the margin along omega at d =", q["d"], ":", [float(scan.axes["omega"][i]) for i in idx])
if idx:
    om0 = float(scan.axes["omega"][idx[0]])
    # the boundary as omega(d): corrected along omega, traced in d
    b = trace_boundary(lambda om, d: margin_003(d, om), (om0, q["d"]), bounds=(np.array([0.1, 1e-4]), np.array([5.0, 0.5])),
                       ds=0.02, ds_max=0.05, max_points=12, direction=(0.0, 1.0))
    print("003 boundary:", b.stopped, b.x[:3])
    fig, ax = plt.subplots(figsize=(6, 4))
    ax.plot(b.x[:, 1], b.x[:, 0], "k.-")
    ax.set_xlabel("external damping d")
    ax.set_ylabel("speed omega")
    fig.savefig(os.path.join(OUT, "boundary_003.png"), dpi=100)
