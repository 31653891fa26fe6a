# ---
# jupyter:
#   jupytext:
#     formats: ipynb,py:percent
#   kernelspec:
#     name: python3
#     display_name: Python 3
# ---

# %% [markdown]
# # A rotor on fluid films: equilibrium, and the onset of oil whirl
#
# The shipped `journal_rig.toml`: ROSS's example rotor on two short plain journal
# bearings (D = 50 mm, L = 20 mm, radial clearance 50 um, 0.03 Pa s), carrying its own
# weight. A journal bearing is a force, not a table: the rotor's equilibrium moves
# with speed, and so do the films' coefficients about it. Here: the journals'
# equilibrium locus, and the speed where the equilibrium loses stability (oil
# whirl), with its whirl frequency.

# %%
import json
import os

import matplotlib.pyplot as plt
import numpy as np
import scipy.linalg

from rotorjax.analysis import bearing_equilibrium, hopf_points
from rotorjax.io import load_rotor, shipped_rotor

OUT = os.environ.get("ROTORJAX_NOTEBOOK_OUT", "notebook-out")
os.makedirs(OUT, exist_ok=True)
scene = load_rotor(shipped_rotor("journal_rig"))
claims = {}

# %% [markdown]
# ## The equilibrium locus
#
# At each speed, Newton on the whole finite-element rotor finds where the films carry
# the load. A faster journal sits nearer the centre, and turns: the classical
# half-circle of the short bearing.

# %%
speeds = np.geomspace(40.0, 1200.0, 14)
locus = [bearing_equilibrium(scene, w).films[0] for w in speeds]
eps = np.array([f.eccentricity for f in locus])
attitude = np.array([f.attitude for f in locus])
claims["locus"] = {"speeds": speeds.tolist(), "eccentricity": eps.tolist(), "load": [f.load for f in locus],
                   "attitude": attitude.tolist()}
fig, ax = plt.subplots(figsize=(5, 5))
ax.plot(eps * np.sin(attitude), -eps * np.cos(attitude), "o-")
for w, e, a in zip(speeds[::3], eps[::3], attitude[::3]):
    ax.annotate(f"{w:.0f} rad/s", (e * np.sin(a), -e * np.cos(a)), fontsize=8, xytext=(4, 4),
                textcoords="offset points")
t = np.linspace(0, 2 * np.pi, 200)
ax.plot(np.cos(t), np.sin(t), "k:", lw=0.8)
ax.set_aspect("equal")
ax.set_xlabel("x / clearance")
ax.set_ylabel("y / clearance")
ax.set_title("journal 0: equilibrium locus (load downwards)")
fig.savefig(os.path.join(OUT, "fluid_films_locus.png"), dpi=90)
plt.show()
print("eccentricity from", round(eps[0], 4), "at", speeds[0], "rad/s to", round(eps[-1], 4), "at", speeds[-1])

# %% [markdown]
# ## Oil whirl
#
# The equilibrium's stability: the largest real part of the eigenvalues of the
# linearised rotor (the films' eight coefficients about the equilibrium, by
# autodiff) against speed, and the speed where it crosses zero: a Hopf point,
# whirling forward near half the running speed.

# %%
(onset,) = hopf_points(scene, 100.0, 400.0)


def largest_real_part(w):
    """max Re lambda of the state matrix at speed `w`, by scipy (not the Hopf search's own path)."""
    m = scene.linear_matrices(w)
    M, C, K = (np.asarray(a) for a in (m.M, m.C + m.G, m.K))
    n = M.shape[0]
    A = np.block([[np.zeros((n, n)), np.eye(n)], [-np.linalg.solve(M, K), -np.linalg.solve(M, C)]])
    return float(scipy.linalg.eigvals(A).real.max())


scan = np.linspace(120.0, 320.0, 21)
margin = np.array([largest_real_part(w) for w in scan])
claims["onset"] = {"speed": onset.speed, "frequency": onset.frequency, "ratio": onset.frequency / onset.speed,
                   "margin_below": largest_real_part(0.99 * onset.speed),
                   "margin_above": largest_real_part(1.01 * onset.speed), "scan": scan.tolist(),
                   "margin": margin.tolist()}
fig, ax = plt.subplots(figsize=(7, 4))
ax.plot(scan, margin, "o-")
ax.axhline(0, color="k", lw=0.8)
ax.axvline(onset.speed, color="r", ls="--", label=f"onset {onset.speed:.2f} rad/s")
ax.set_xlabel("speed (rad/s)")
ax.set_ylabel("largest Re lambda (1/s)")
ax.legend()
fig.savefig(os.path.join(OUT, "fluid_films_onset.png"), dpi=90)
plt.show()
print(f"oil whirl from {onset.speed:.2f} rad/s, whirling at {onset.frequency:.2f} rad/s "
      f"(ratio {onset.frequency / onset.speed:.3f})")

with open(os.path.join(OUT, "fluid_films_claims.json"), "w") as f:
    json.dump(claims, f, indent=1)
