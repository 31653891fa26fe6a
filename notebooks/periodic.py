# ---
# jupyter:
#   jupytext:
#     formats: ipynb,py:percent
#   kernelspec:
#     name: python3
#     display_name: Python 3
# ---

# %% [markdown]
# # Periodic motions: a rotor on hardening bearings, and its jump
#
# The shipped `cubic_rig.toml`: ROSS's example rotor on isotropic bearings that
# harden (cubic stiffness), with an unbalance at each disk. Its unbalance response
# bends over with the hardening and folds twice: between the folds three motions
# coexist, the middle one unstable, and a run-up jumps down where a run-down jumps up.
#
# Harmonic balance traces the periodic motions in the speed through the folds, with
# Hill's stability at every point. The check: on isotropic bearings the synchronous
# orbit is circular, a rest point of the rotating frame, so continuation of those
# rest points (a different method, with no Fourier series at all) must find the same
# folds.

# %%
import json
import os

import equinox as eqx
import matplotlib.pyplot as plt
import numpy as np

import rotorjax.plot
from rotorjax.analysis import branch_amplitude, periodic_branch, synchronous_branch
from rotorjax.io import load_rotor, shipped_rotor

OUT = os.environ.get("ROTORJAX_NOTEBOOK_OUT", "notebook-out")
os.makedirs(OUT, exist_ok=True)
scene = load_rotor(shipped_rotor("cubic_rig"))      # at its [rotor] speed, 100 rad/s
NODE = 1                                            # the first disk


def scene_at(speed):
    """The rotor at `speed` (traceable in it: the continuation differentiates through it)."""
    return eqx.tree_at(lambda s: s.speed.constant, scene, speed)


# %% [markdown]
# ## The branch by harmonic balance
#
# One harmonic: a circular orbit under a cubic isotropic force is exactly
# synchronous (`|u|^2 u` of a circle is a circle), so one harmonic is the exact
# motion here, not an approximation.

# %%
branch, coefficients = periodic_branch(scene_at, 100.0, np.zeros(scene.state_size), (100.0, 106.0), 1,
                                       name="speed", ds=0.06, ds_max=0.6)
amplitude = branch_amplitude(scene_at, branch.p, coefficients, node=NODE)
folds = sorted(e.p for e in branch.events if e.kind == "fold")
fig, ax = plt.subplots(figsize=(8, 4.5))
rotorjax.plot.plot_periodic_branch(np.asarray(branch.p), 1e6 * np.asarray(amplitude), np.asarray(branch.stable),
                                   x_label="speed (rad/s)", y_label=f"largest radius of node {NODE}'s orbit (um)",
                                   ax=ax, title="harmonic balance: stable solid, unstable dashed")
for f in folds:
    ax.axvline(f, color="0.5", ls=":", lw=1)
fig.savefig(os.path.join(OUT, "periodic_branch.png"), dpi=90)
plt.show()
print(f"{branch.p.size} points; folds at " + " and ".join(f"{f:.4f}" for f in folds) + " rad/s")

# %% [markdown]
# ## Between the folds
#
# At a speed between the folds, three motions: the branch crosses it three times.
# The smallest and the largest are stable, the middle one is not.

# %%
w = 0.5 * (folds[0] + folds[1])
p, amp, stable = np.asarray(branch.p), np.asarray(amplitude), np.asarray(branch.stable)
crossings = [i for i in range(p.size - 1) if (p[i] - w) * (p[i + 1] - w) < 0]
t = [(w - p[i]) / (p[i + 1] - p[i]) for i in crossings]          # where each crossing lies in its step
three = sorted((float(amp[i] + f * (amp[i + 1] - amp[i])), bool(stable[i] and stable[i + 1]))
               for i, f in zip(crossings, t))
for a, s in three:
    print(f"at {w:.3f} rad/s: radius {1e6 * a:8.3f} um, {'stable' if s else 'unstable'}")

# %% [markdown]
# ## The same folds from the rotating frame
#
# `synchronous_branch` continues the rest points of the rotating frame: no harmonics,
# no time. Its folds are the harmonic balance's.

# %%
sync = synchronous_branch(scene, (100.0, 106.0), speed0=100.0)
sync_folds = sorted(e.p for e in sync.events if e.kind == "fold")
print("rotating frame: folds at " + " and ".join(f"{f:.4f}" for f in sync_folds) + " rad/s; harmonic balance "
      + " and ".join(f"{f:.4f}" for f in folds))
claims = {"folds": folds, "sync_folds": sync_folds, "between": w, "three": three,
          "stable_ends": [bool(stable[0]), bool(stable[-1])]}
with open(os.path.join(OUT, "periodic_claims.json"), "w") as f:
    json.dump(claims, f, indent=1)
