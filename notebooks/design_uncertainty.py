# ---
# jupyter:
#   jupytext:
#     formats: ipynb,py:percent
#   kernelspec:
#     name: python3
#     display_name: Python 3
# ---

# %% [markdown]
# # Design and uncertainty: a rotor's margins, chosen and scattered
#
# The shipped `ross_compare.toml`: ROSS's example rotor (a shaft, two disks, two
# bearings, stiffer horizontally than vertically) with light damping, 500 N s/m,
# in the bearings' horizontal direction only. Two questions an engineer asks of
# it:
#
# 1. The bearings' stiffnesses are known to 10 % at best. How far do the critical
#    speeds and the log decrements scatter, which parameter drives each, and how
#    likely is a mode to be too lightly damped?
# 2. How much damping should the bearings have to give the first modes the most
#    damping over the speed range?
#
# Both on exact gradients: the first-order moments are autodiff's, and the design is
# searched on the gradient of a smooth lower bound of the least log decrement.

# %%
import json
import os

import jax
import jax.numpy as jnp
import matplotlib.pyplot as plt
import numpy as np

import rotorjax.plot
from rotorjax.analysis import critical_speeds_1x, modes
from rotorjax.design import optimize_rotor, rotor_problem
from rotorjax.io import read_rotor_file, shipped_rotor
from rotorjax.uncertainty import LogNormal, draw, propagate, rotor_quantities, wilson

OUT = os.environ.get("ROTORJAX_NOTEBOOK_OUT", "notebook-out")
os.makedirs(OUT, exist_ok=True)
PATH = str(shipped_rotor("ross_compare"))
DAMPING = {"bearing0.cxx": 500.0, "bearing1.cxx": 500.0}
file = read_rotor_file(PATH, DAMPING)
print(f"{file.label}: " + ", ".join(f"{k} = {file.entries[k].value:.3g}" for k in (
    "bearing0.kxx", "bearing0.kyy", "bearing0.cxx")) + ", no cyy (and bearing1 the same)")

# %% [markdown]
# ## The stiffnesses scattered
#
# Each bearing's `kxx` and `kyy` lognormal about its value, 10 % standard deviation,
# independent. The outputs: the forward critical speeds below 1000 rad/s and the log
# decrements of the first three modes at the operating speed, 500 rad/s. Monte Carlo
# on 1000 samples (one vmapped, compiled function of the four stiffnesses), and the
# first-order moments from its Jacobian at the means.

# %%
STIFF = {f"bearing{i}.k{a}": LogNormal(k, 0.1 * k) for i in (0, 1) for a, k in (("xx", 1e6), ("yy", 8e5))}
q = rotor_quantities(file, STIFF, lo=0.0, hi=1000.0, speed=500.0, n_modes=3)
res = propagate(q.fn, STIFF, samples=1000, seed=1, names=q.outputs, fallback=q.fallback)
short = [k.replace("bearing", "b") for k in STIFF]
print(f"{'output':>16} {'mean':>9} {'sd':>8} {'1st-order mean':>15} {'sd':>8}   share of the variance: "
      + " ".join(f"{k:>6}" for k in short))
for j, name in enumerate(res.outputs):
    print(f"{name:>16} {res.mean[j]:9.4f} {res.std[j]:8.4f} {res.fosm_mean[j]:15.4f} {res.fosm_std[j]:8.4f}   "
          + " " * 22 + " ".join(f"{100 * s:5.1f}%" for s in res.shares[j]))
bias = np.max(np.abs(res.mean - res.fosm_mean) / res.std)
spread = np.max(np.abs(res.fosm_std / res.std - 1))
print(f"first order: means within {bias:.2f} sd of the sampled ones, sds within {100 * spread:.0f} %")
fig = rotorjax.plot.plot_uncertainty(result=res, title="bearing stiffnesses lognormal, 10 %")
fig.savefig(os.path.join(OUT, "design_uncertainty_scatter.png"), dpi=80)
plt.show()

# %% [markdown]
# The horizontal stiffnesses `kxx` set the first two forward critical speeds, the
# vertical ones `kyy` the damping of the first mode: the dampers act horizontally
# only, so a mode's damping depends on how far it leans that way. The first-order
# moments are close (the means differ by the curvature's bias, which Monte Carlo
# has and a linearisation has not).
#
# A sample is a rotor: the first, and the last, recomputed from the file read again
# with the sample's stiffnesses as `--set` values, by the analyses' own solvers
# (`critical_speeds_1x` scans and bisects; `modes` is a full eigenvalue solve). They
# equal the vmapped function's.

# %%
recomputed = []
for i in (0, res.samples.shape[0] - 1):
    rotor = read_rotor_file(PATH, {**DAMPING, **dict(zip(STIFF, res.input_samples[i]))}).scene.full_rotor
    crit = [w for w, _ in critical_speeds_1x(rotor, 0.0, 1000.0, whirl="forward")]
    again = np.concatenate([crit, np.asarray(modes(rotor, 500.0, 3).log_dec)])
    recomputed.append(float(np.max(np.abs(again - res.samples[i]) / np.abs(again))))
print(f"largest relative difference of the recomputed samples: {max(recomputed):.1e}")

# %% [markdown]
# ## How likely is a built rotor worse than its drawing?
#
# The weakest mode's log decrement on the nominal rotor, and the fraction of samples
# below it, with its 95 % Wilson interval. The interval's coverage is checked: 40
# more Monte Carlo runs of 100 samples each (the log decrements alone: one eigenvalue
# solve a sample), and how often each run's interval holds the estimate from all
# 4000 of their samples.

# %%
worst = int(np.argmin(res.mean[len(q.critical):])) + len(q.critical)
name = res.outputs[worst]
floor = float(q.fn(jnp.asarray(q.nominal))[worst])
p, (p_lo, p_hi) = res.probability(name, below=floor)
print(f"P({name} < {floor:.4f}, the nominal rotor's) = {p:.3f}, 95 % interval {p_lo:.3f} .. {p_hi:.3f}")
log_decs = rotor_quantities(file, STIFF, lo=0.0, hi=1.0, speed=500.0, n_modes=3)     # no critical speed below 1
X = draw(STIFF, 40 * 100, seed=2)
Y = np.asarray(jax.jit(jax.vmap(log_decs.fn))(jnp.asarray(X)))[:, worst - len(q.critical)].reshape(40, 100)
pooled = float(np.mean(Y < floor))
held = sum(a <= pooled <= b for a, b in (wilson(int(np.sum(y < floor)), y.size)[1] for y in Y))
print(f"{held} of 40 intervals from 100 samples hold the 4000-sample estimate, {pooled:.3f}")

# %% [markdown]
# ## Designing the bearings' damping
#
# Maximise the least log decrement of the first three modes over 0 .. 600 rad/s, the
# two bearings' `cxx` free in 100 .. 3000 N s/m (a range over a decade: searched in
# its logarithm), from the file's values and one Latin-hypercube start. Checked
# against brute force: a vmapped 12 x 12 grid of the same quantity.

# %%
vary = {"bearing0.cxx": (100.0, 3000.0), "bearing1.cxx": (100.0, 3000.0)}
problem = rotor_problem(file, vary, "min-log-dec", speed_range=(0.0, 600.0), n_modes=3)
design = optimize_rotor(problem, n_starts=2)
before, after = design.quantities_before["min-log-dec"], design.quantities_after["min-log-dec"]
print(f"least log decrement {before:.3f} -> {after:.3f}: "
      + ", ".join(f"{k} {design.before[k]:.0f} -> {design.after[k]:.0f} N s/m" for k in vary)
      + f" ({design.optimum.evaluations} evaluations)")
a = np.geomspace(100.0, 3000.0, 12)
A, B = np.meshgrid(a, a, indexing="ij")
grid = np.asarray(jax.jit(jax.vmap(lambda x: problem.quantities(x)["min-log-dec"]))(
    jnp.asarray(np.stack([A.ravel(), B.ravel()], axis=1))))
print(f"the best of the 12 x 12 grid: {grid.max():.3f}")
fig = rotorjax.plot.plot_design(design=design, campbell=design.campbell(np.linspace(0.0, 600.0, 60)),
                                title="ross_compare.toml: min-log-dec")
fig.savefig(os.path.join(OUT, "design_uncertainty_design.png"), dpi=80)
plt.show()

# %%
claims = {"outputs": list(res.outputs), "inputs": list(STIFF), "mean": res.mean.tolist(), "std": res.std.tolist(),
          "sem": res.sem.tolist(), "fosm_mean": res.fosm_mean.tolist(), "fosm_std": res.fosm_std.tolist(),
          "shares": res.shares.tolist(), "recomputed": max(recomputed), "probability": [p, p_lo, p_hi],
          "held": int(held), "pooled": pooled, "floor": floor, "design": [before, after], "after": design.after,
          "grid_best": float(grid.max()), "converged": bool(design.optimum.converged)}
with open(os.path.join(OUT, "design_uncertainty_claims.json"), "w") as f:
    json.dump(claims, f, indent=1)
