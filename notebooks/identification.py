# ---
# jupyter:
#   jupytext:
#     formats: py:percent
#   kernelspec:
#     name: python3
#     display_name: Python 3
# ---

# %% [markdown]
# # Identify the balancing machine, then balance the rotor (model 002)
#
# From the shipped measured dataset (`rotorjax.identify.RUNUP`: a 20 000-sample
# run-up with a once-per-revolution tacho, 1 % sensor noise) we extract one 1x
# phasor per revolution, fit the supports' stiffness and damping (and the
# unbalances) by Levenberg-Marquardt with autodiff Jacobians, and then balance
# from the three shipped steady runs with trial weights.

# %%
import os

import matplotlib

matplotlib.use("Agg")
import jax
import matplotlib.pyplot as plt
import numpy as np

import rotorjax  # noqa: F401
from rotorjax import identify as idf
from rotorjax.presets import balancing_machine as bm

OUT = os.environ.get("ROTORJAX_NOTEBOOK_OUT", "notebook-out")
os.makedirs(OUT, exist_ok=True)
p = dict(bm.PRESET.defaults)
_, planes, U = bm._build(p)

# %%
cols = idf.read_signals(idf.RUNUP)
speeds, X = idf.order_track(cols["time"], np.stack([cols["x1"], cols["x2"]], axis=1), tacho=cols["tacho"])
print(f"{speeds.size} revolutions, {speeds.min():.1f} to {speeds.max():.1f} rad/s")

# %%
start = bm.build_machine(dict(p, k1=1.5e5, k2=3.75e5, c1=100.0, c2=266.0))
res = idf.identify(start, speeds, X, planes, fit=("k1", "k2", "c1", "c2"), unbalances=None)
for k in res.names:
    lo, hi = res.intervals[k]
    print(f"{k}: {res.estimates[k]:.6g}  95% [{lo:.6g}, {hi:.6g}]   (true {p[k]:.6g})")
print("warnings:", res.warnings or "none")

# %%
fitted = bm.build_machine(dict(p, **res.estimates))
model = np.asarray(jax.vmap(lambda w: fitted.response(w, planes, res.unbalances))(speeds))
fig, ax = plt.subplots(figsize=(7, 4))
for i in range(2):
    ax.plot(speeds, np.abs(X[:, i]) * 1e6, ".", ms=2, label=f"measured, support {i + 1}")
    ax.plot(speeds, np.abs(model[:, i]) * 1e6, "-", label=f"fitted model, support {i + 1}")
ax.set_xlabel("speed (rad/s)")
ax.set_ylabel("1x amplitude (um)")
ax.legend()
fig.savefig(os.path.join(OUT, "identification.png"), dpi=100)

# %% [markdown]
# ## Balancing from the steady runs with trial weights

# %%
runs = idf.runs_from_signals(idf.read_signals(idf.BALANCING_RUNS))
X0 = runs[0]["X"]
K = idf.influence_from_trials(X0, np.stack([r["X"] for r in runs[1:]]), np.array([r["trial"][1] for r in runs[1:]]))
W = -idf.unbalance_from_vibration(K, X0)
for j, w in enumerate(W):
    print(f"plane {j}: add {abs(w) / 0.01 * 1e3:.2f} g at {np.degrees(np.angle(w)) % 360:.1f} deg (radius 10 mm)")
# the model with the identified parameters predicts the same correction
W_model = -np.linalg.solve(np.asarray(fitted.influence_matrix(runs[0]["speed"], planes)), X0)
print("model-based correction differs by", float(np.max(np.abs(W_model - W)) / np.max(np.abs(W))))
assert np.allclose(W, -U, rtol=0.02)
