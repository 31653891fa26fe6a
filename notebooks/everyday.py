# ---
# jupyter:
#   jupytext:
#     formats: ipynb,py:percent
#   kernelspec:
#     name: python3
#     display_name: Python 3
# ---

# %% [markdown]
# # A machine from its rotor file: the everyday analyses
#
# The shipped `flexible_rig.toml`: a 1.5 m Timoshenko shaft with two disks on two
# damped anisotropic bearings, in service at 460 rad/s (4393 rpm). What an engineer
# checks first, in the order of API 684: the rotor as built, its weight on the
# bearings, its critical speeds and their amplification factors, the separation
# margins from the operating range, the unbalance response, and the level I
# stability screen. Everything is computed in SI and shown in rpm and micrometres
# peak-to-peak, as the CLI's `--units rpm-um` shows it.

# %%
import json
import os

import matplotlib.pyplot as plt
import numpy as np

import rotorjax.plot
from rotorjax.analysis import (api684_margins, campbell, critical_speeds_1x, level1, mid_span_node, modes,
                               response_curve, static)
from rotorjax.io import load_rotor, shipped_rotor

OUT = os.environ.get("ROTORJAX_NOTEBOOK_OUT", "notebook-out")
os.makedirs(OUT, exist_ok=True)
RPM = 30 / np.pi          # rpm per rad/s
UM_PP = 2e6               # micrometres peak-to-peak per metre of amplitude
scene = load_rotor(shipped_rotor("flexible_rig"))
SPEED = float(scene.speed.speed(0.0))      # the file's [rotor] speed, rad/s
OPERATING = (0.95 * SPEED, 1.0 * SPEED)     # the operating range: 95-100 % of the service speed
claims = {"speed": SPEED, "operating": OPERATING}
print(f"service speed {SPEED:g} rad/s = {SPEED * RPM:.0f} rpm; {scene.n_nodes} nodes")

# %% [markdown]
# ## The rotor as built
#
# Drawn to scale along the shaft (the radius magnified): the elements, the disks as
# solid disks of their mass and inertias, the bearings, and the node numbers.

# %%
layout = rotorjax.plot.rotor_layout(scene)
fig, ax = plt.subplots(figsize=(9, 3.5))
rotorjax.plot.rotor(scene, ax=ax, title="flexible_rig.toml")
fig.savefig(os.path.join(OUT, "everyday_rotor.png"), dpi=90)
plt.show()
claims["mass"] = float(layout["mass"])
print(f"length {layout['length']:g} m, mass {layout['mass']:.3f} kg, {len(layout['disks'])} disks, "
      f"{len(layout['bearings'])} bearings")

# %% [markdown]
# ## Weight on the bearings
#
# The static deflection under gravity, and the bearing reactions: together they carry
# the rotor's weight.

# %%
st = static(scene)
reactions = np.asarray(st.bearing_reactions)[:, 1]
claims["reactions"] = reactions.tolist()
claims["weight"] = float(abs(np.asarray(st.weight)[1]))
print("bearing reactions (N):", np.round(reactions, 3), f"sum {reactions.sum():.3f} N; weight "
      f"{claims['weight']:.3f} N; largest deflection {1e6 * np.abs(np.asarray(st.displacement)[:, 1]).max():.1f} um")

# %% [markdown]
# ## Campbell diagram and critical speeds
#
# The damped natural frequencies against speed (in cpm against rpm), and the 1x
# crossings: the critical speeds an unbalance excites.

# %%
speeds = np.linspace(0.0, 1.5 * SPEED, 60)
camp = campbell(scene, speeds, 6)
crit = critical_speeds_1x(scene, 1.0, 1.5 * SPEED, whirl="forward")
claims["critical_speeds"] = [float(w) for w, _ in crit]
fig, ax = plt.subplots(figsize=(8, 5))
rotorjax.plot.plot_campbell(speeds * RPM, np.asarray(camp.frequencies) * RPM, np.asarray(camp.forward),
                            critical=[w * RPM for w, _ in crit], unit="rpm", frequency_unit="cpm", ax=ax,
                            title="Campbell diagram")
fig.savefig(os.path.join(OUT, "everyday_campbell.png"), dpi=90)
plt.show()
print("forward critical speeds (rpm):", [round(w * RPM, 1) for w, _ in crit])

# %% [markdown]
# ## API 684: amplification factors and separation margins
#
# Each forward critical speed's amplification factor (from its mode's damping), the
# separation margin it has from the operating range, and the margin API 684 requires.

# %%
rows = api684_margins(scene, 1.0, 1.5 * SPEED, *OPERATING)
claims["api684"] = rows
for r in rows:
    print(f"{r['speed'] * RPM:8.1f} rpm  AF {r['af']:6.2f}  margin {r['margin']:6.1f} %  required "
          f"{r['required']:5.1f} %  {'meets' if r['meets'] else 'SHORT'}")

# %% [markdown]
# ## Unbalance response
#
# An unbalance of 1e-4 kg m at the heavier disk (node 2), read at mid-span, in
# micrometres peak-to-peak. Its half-power bandwidth at the first peak is API 684's
# own measure of the amplification factor: it should agree with the one from the
# mode's damping above.

# %%
node = mid_span_node(scene)


def half_power(rotor):
    """The response at `node` to the unbalance, and its first peak's half-power points."""
    curve = response_curve(rotor, [(2, 1e-4, 0.0)], np.linspace(5.0, 1.5 * SPEED, 1500), probe=node)
    w, amp = np.asarray(curve.speeds), np.asarray(curve.amplitude)
    first = curve.peaks[0]
    k = int(np.argmin(np.abs(w - first.x)))
    n1 = np.interp(first.y / np.sqrt(2), amp[:k + 1], w[:k + 1])      # rising through the half-power level
    n2 = np.interp(-first.y / np.sqrt(2), -amp[k:], w[k:])            # and falling through it
    return curve, first, (float(n1), float(n2))


curve, first, (n1, n2) = half_power(scene)
w, amp = np.asarray(curve.speeds), np.asarray(curve.amplitude)
claims["response"] = {"peaks": [p.x for p in curve.peaks], "peak_amplitudes": [p.y for p in curve.peaks],
                      "half_power": [n1, n2], "af_half_power": float(first.x / (n2 - n1))}
fig, ax = plt.subplots(figsize=(8, 4))
ax.semilogy(w * RPM, amp * UM_PP)
ax.plot([p.x * RPM for p in curve.peaks], [p.y * UM_PP for p in curve.peaks], "ro")
ax.axvspan(OPERATING[0] * RPM, OPERATING[1] * RPM, color="0.85", label="operating range")
ax.set_xlabel("speed (rpm)")
ax.set_ylabel(f"amplitude at node {node} (um pk-pk)")
ax.legend()
fig.savefig(os.path.join(OUT, "everyday_response.png"), dpi=90)
plt.show()
print(f"first peak {first.x * RPM:.1f} rpm, {first.y * UM_PP:.2f} um pk-pk; half-power AF "
      f"{claims['response']['af_half_power']:.2f} against {rows[0]['af']:.2f} from the mode's damping")

# %% [markdown]
# The two disagree, and the reason is the bearings: anisotropic, they split the first
# mode into a backward and a forward whirl 60 cpm apart (below), and the unbalance
# excites both, so the peak at the probe is wider than the forward mode's own. On
# isotropic bearings (`kyy = kxx`, `cyy = cxx`) the unbalance excites only forward
# whirl, and the two measures of the amplification factor agree.

# %%
iso = load_rotor(shipped_rotor("flexible_rig"), {"bearing0.kyy": 1.2e6, "bearing0.cyy": 1000.0,
                                                  "bearing1.kyy": 1.0e6, "bearing1.cyy": 2000.0})
_, first_iso, (m1, m2) = half_power(iso)
af_iso = api684_margins(iso, 1.0, 1.5 * SPEED, *OPERATING)[0]["af"]
claims["isotropic"] = {"peak": first_iso.x, "half_power": [m1, m2], "af_half_power": first_iso.x / (m2 - m1),
                       "af": af_iso}
print(f"isotropic bearings: half-power AF {first_iso.x / (m2 - m1):.2f} against {af_iso:.2f} from the mode's damping")

# %% [markdown]
# ## Modes at the service speed, and the level I screen
#
# The damped modes at the top of the operating range, and API 684's level I screen:
# the cross-coupled stiffness at mid-span that would bring the least damped forward
# mode to the edge of stability.

# %%
m = modes(scene, SPEED, 4)
for j in range(4):
    print(f"mode {j}: {float(m.frequencies[j]) * RPM:8.1f} cpm, log dec {float(m.log_dec[j]):.3f}, {m.whirl[j]}")
screen = level1(scene, SPEED)
claims["level1"] = {"q0": float(screen.q0), "log_dec_0": float(screen.log_dec_0), "node": int(node)}
print(f"level I: log dec at Q = 0 {float(screen.log_dec_0):.3f}; threshold Q0 = {float(screen.q0):.4g} N/m")

with open(os.path.join(OUT, "everyday_claims.json"), "w") as f:
    json.dump(claims, f, indent=1)
