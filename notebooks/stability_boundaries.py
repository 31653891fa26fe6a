# ---
# jupyter:
#   jupytext:
#     formats: ipynb,py:percent
#   kernelspec:
#     name: python3
#     display_name: Python 3
# ---

# %% [markdown]
# # Stability boundaries by continuation
#
# 1. Model 001 (planar rotor on anisotropic supports with a two-weight
#    auto-balancer): every boundary of the auto-balancing main motion in the plane
#    (dimensionless speed `n = w / wx`, weight damping `mu_w = b_w / (K m wx)`)
#    over the whole speed range, traced by pseudo-arclength continuation of the
#    zero set of the Floquet margin (`trace_boundaries`), checked against critical
#    speeds bisected independently along `n`, and compared with the paper's
#    empirical criterion (eq. 18), which ignores `mu_w`.
# 2. Model 003 (pinned-pinned shaft with a disk and a two-ball auto-balancer): the
#    boundary of the balanced regime in (external damping `d`, speed `omega`),
#    traced both ways, like the paper's Fig. 5.
#
# Every finding printed here is also written to `stability_boundaries_claims.json`
# (checked by `tests/notebook_checks/stability_boundaries.py`).

# %%
import json
import os

import equinox as eqx
import jax
import jax.numpy as jnp
import matplotlib.pyplot as plt
import numpy as np

import rotorjax  # noqa: F401
from rotorjax.analysis import critical_speeds, floquet_crossings, trace_boundaries
from rotorjax.presets import anisotropic_abb as ab
from rotorjax.presets import flexible_abb as fa

OUT = os.environ.get("ROTORJAX_NOTEBOOK_OUT", "notebook-out")
os.makedirs(OUT, exist_ok=True)
claims = {}
p = dict(ab.PRESET.defaults)
G = {k: p[k] for k in ab.GROUPS}
BOX = ab.PRESET.box                       # n in [0.5, 10], mu_w in [0.05, 1]
MU0 = p["mu_w"]                           # the preset's (the paper's) weight damping, 0.5


def margin(n, mu_w):
    """Largest Floquet exponent of the main motion (< 0: auto-balancing is stable)."""
    return ab.main_motion_floquet(dict(G, mu_w=mu_w), n, p["K"]).margin


# %% [markdown]
# ## Model 001: multipliers along the speed at the paper's `mu_w = 0.5`
#
# Where the main motion's Floquet multipliers cross the unit circle as `n`
# increases. The direction is checked on both sides of each crossing: a pair that
# *enters* the unit circle makes the main motion stable above that speed, one that
# *leaves* it makes it unstable.

# %%
crossings = floquet_crossings(lambda n: ab.main_motion_floquet(G, n, p["K"]), *BOX["n"], n_scan=40)
largest = jax.jit(lambda n: jnp.max(jnp.abs(ab.main_motion_floquet(G, n, p["K"]).multipliers)))
claims["floquet_crossings"] = []
for c in crossings:
    below, above = float(largest(c["p"] - 1e-4)), float(largest(c["p"] + 1e-4))
    direction = "enters" if below > 1 > above else "leaves" if below < 1 < above else "touches"
    wording = (f"a {c['kind']} {direction} the unit circle as n increases through {c['p']:.6f} "
               f"(max |multiplier| {below:.6f} at n - 1e-4, {above:.6f} at n + 1e-4): the main motion is "
               f"{'stable above' if direction == 'enters' else 'unstable above'}")
    print(wording)
    claims["floquet_crossings"].append({"n": c["p"], "kind": c["kind"], "direction": direction,
                                        "max_abs_multiplier_below": below, "max_abs_multiplier_above": above,
                                        "stable_side": c["stable_side"], "wording": wording})

# %% [markdown]
# ## Model 001: every boundary in the box
#
# Starts come from crossings located by scan and bisection round the box's edge and
# along three lines of constant `mu_w`; each branch is traced both ways to the box's
# edges, with steps controlled so that its dense curve (cubic Hermite between the
# points) is within 1e-6 of the boundary along `n`.

# %%
found = trace_boundaries(margin, (BOX["n"], BOX["mu_w"]), gradient="fd", names=("n", "mu_w"), dense_tol=1e-6,
                         ds=0.02, ds_max=0.2)
claims["model_001"] = {"box": {"n": list(BOX["n"]), "mu_w": list(BOX["mu_w"])}, "n_boundaries": len(found),
                       "boundaries": []}
print(f"{len(found)} boundaries of the main motion in n in {BOX['n']}, mu_w in {BOX['mu_w']}:")
for i, b in enumerate(found):
    d = b.dense(16)
    at_mu0 = b.meets(1, MU0)[:, 0]
    info = {"n_range": [float(d[:, 0].min()), float(d[:, 0].max())],
            "mu_w_range": [float(d[:, 1].min()), float(d[:, 1].max())], "stops": list(b.stops),
            "points": int(len(b.x)), "interpolation_error_max": float(b.errors.max()),
            "residual_max": float(b.residuals.max()), "n_at_preset_mu_w": at_mu0.tolist(),
            "n_at_mu_w": {f"{m:g}": b.meets(1, m)[:, 0].tolist() for m in (0.05, 0.53, 0.85, 1.0)},
            "n_range_for_mu_w_from_0.2": [float(d[d[:, 1] >= 0.2, 0].min()), float(d[d[:, 1] >= 0.2, 0].max())]}
    claims["model_001"]["boundaries"].append(info)
    print(f"  boundary {i + 1}: n from {info['n_range'][0]:.6f} to {info['n_range'][1]:.6f} over mu_w "
          f"{info['mu_w_range'][0]:g}..{info['mu_w_range'][1]:g} (n = {at_mu0[0]:.6f} at mu_w = {MU0:g}; "
          f"{info['n_at_mu_w']['0.53'][0]:.4f} at 0.53, {info['n_at_mu_w']['0.85'][0]:.4f} at 0.85); "
          f"{info['points']} points, interpolation error <= {info['interpolation_error_max']:.1e} along n; "
          f"ends: {', '.join(b.stops)}")
moves = [c["n_range_for_mu_w_from_0.2"][1] - c["n_range_for_mu_w_from_0.2"][0]
         for c in claims["model_001"]["boundaries"]]
claims["model_001"]["n_moves_for_mu_w_from_0.2"] = moves
print(f"  for mu_w from 0.2 to 1 the first two move by {moves[0]:.4f} and {moves[1]:.4f} in n, the third by "
      f"{moves[2]:.3f}")

# %% [markdown]
# ## Against critical speeds bisected independently
#
# At a few values of `mu_w` (none of them a point of the traced curves), one
# `critical_speeds` call per value scans `n` over the whole range on a fine grid
# and bisects every sign change to 1e-12; each is compared with the dense curve
# of the boundary through it.

# %%
def margin_at(mu_w, n):
    return margin(n, mu_w)


CHECK_MU = [0.13, MU0, 0.77]
rows = []
for mu in CHECK_MU:
    # mu_w an array leaf of the Partial: the bisection compiles once for every mu_w
    cs = critical_speeds(eqx.Partial(margin_at, jnp.float64(mu)), *BOX["n"], n_scan=200, xtol=1e-12)
    dense = sorted(float(v) for b in found for v in b.meets(1, mu)[:, 0])
    assert len(cs) == len(dense), (mu, cs, dense)
    for c, v in zip(cs, dense):
        rows.append({"mu_w": mu, "bisected_n": c.speed, "dense_n": v, "distance": abs(c.speed - v),
                     "stable_side": c.stable_side})
dist = max(r["distance"] for r in rows)
claims["model_001"]["bisection"] = {"mu_w": CHECK_MU, "n_scan": 200, "xtol": 1e-12, "points": rows,
                                    "crossings_per_mu_w": len(rows) // len(CHECK_MU), "distance_max": dist}
print(f"bisected critical speeds at mu_w = {CHECK_MU}: {len(rows) // len(CHECK_MU)} per value; largest distance "
      f"to the dense curves {dist:.1e} (along n)")

# %% [markdown]
# ## Against the paper's criterion
#
# The criterion (eq. 18) is a polynomial in `n` independent of `mu_w` and `eps`:
# balancing where `p(n) < 0`. Its roots against the boundaries:

# %%
roots = ab.criterion_roots(p["n_eta"], p["mu_xi"], p["mu_eta"], *BOX["n"])
claims["model_001"]["criterion_roots"] = roots
claims["model_001"]["criterion_error"] = []
print("criterion roots:", ", ".join(f"{r:.4f}" for r in roots))
for i, (b, r) in enumerate(zip(found, roots)):
    d = b.dense(16)
    err = {"root": r, "at_preset_mu_w": float(b.meets(1, MU0)[0, 0] - r),
           "over_box": [float((d[:, 0] - r).min()), float((d[:, 0] - r).max())],
           "over_mu_w_0.53_0.85": [float(b.meets(1, m)[0, 0] - r) for m in (0.53, 0.85)]}
    claims["model_001"]["criterion_error"].append(err)
    print(f"  boundary {i + 1} minus root {r:.4f}: {err['at_preset_mu_w']:+.4f} at mu_w = {MU0:g}; "
          f"{err['over_mu_w_0.53_0.85'][0]:+.3f} at 0.53, {err['over_mu_w_0.53_0.85'][1]:+.3f} at 0.85; from "
          f"{err['over_box'][0]:+.3f} to {err['over_box'][1]:+.3f} over the box")
near = max(abs(e["at_preset_mu_w"]) for e in claims["model_001"]["criterion_error"][:2])
print(f"  the criterion places the first two boundaries within {near:.3f} at mu_w = {MU0:g}, but the third one "
      f"at n = {roots[2]:.3f}, {claims['model_001']['criterion_error'][2]['at_preset_mu_w']:.2f} below where it is")

# %%
fig, ax = plt.subplots(figsize=(8, 5))


def n_of_mu(b, mu):
    """A boundary as n(mu_w) for shading (each of these runs monotonically in mu_w)."""
    d = b.dense(16)
    order = np.argsort(d[:, 1])
    return np.interp(mu, d[order, 1], d[order, 0])


# the stable regions between the boundaries, from the sides of the crossings on the middle line
mid = found.lines[len(found.lines) // 2]
on_mid = sorted((c for c in found.crossings if c.p2 == mid and c.along == "n"), key=lambda c: c.p1)
grid_mu = np.linspace(*BOX["mu_w"], 200)
shaded = False
for k, c in enumerate(on_mid):
    if c.stable_side == "above":
        right = n_of_mu(found[on_mid[k + 1].branch], grid_mu) if k + 1 < len(on_mid) else BOX["n"][1]
        ax.fill_betweenx(grid_mu, n_of_mu(found[c.branch], grid_mu), right, color="tab:green", alpha=0.12,
                         label=None if shaded else "main motion stable")
        shaded = True
for i, b in enumerate(found):
    d = b.dense(16)
    line, = ax.plot(d[:, 0], d[:, 1], lw=1.4, label=f"boundary {i + 1} (continuation, dense curve)")
    ax.plot(b.x[:, 0], b.x[:, 1], "o", ms=2.5, color=line.get_color())
ax.plot([r["bisected_n"] for r in rows], [r["mu_w"] for r in rows], "kx", ms=7,
        label="critical speeds bisected along n")
for j, r in enumerate(roots):
    ax.axvline(r, color="tab:blue", ls=":", lw=1.0, label="paper's criterion (eq. 18) roots" if j == 0 else None)
ax.axhline(MU0, color="0.5", lw=0.6, ls="--", label=f"the paper's mu_w = {MU0:g}")
ax.set_xlim(*BOX["n"])
ax.set_ylim(*BOX["mu_w"])
ax.set_xlabel("speed n = w / wx (dimensionless)")
ax.set_ylabel("weight damping mu_w = b_w / (K m wx) (dimensionless)")
ax.set_title("model 001: stability boundaries of the main motion in (n, mu_w)")
ax.legend(fontsize=7, loc="upper right")
ax.grid(alpha=0.3)
fig.tight_layout()
fig.savefig(os.path.join(OUT, "boundary_001.png"), dpi=100)
plt.show()

# %% [markdown]
# ## Model 003: the balanced regime in (d, omega)
#
# Two balls (mass 0.02 each), 6 shaft modes; `omega` in units of the first
# critical speed `omega_1`, `d` the external damping over `m_S omega_1`. The box is
# the preset's (`omega` in [0.3, 3], `d` in [0, 0.5]); every boundary in it is
# traced both ways.

# %%
q = dict(fa.PRESET.defaults, n_balls=2, modes=6)


def margin_003(omega, d):
    return fa.PRESET.margin(dict(q, d=d, omega=omega))


box3 = fa.PRESET.box
found3 = trace_boundaries(margin_003, (box3["omega"], box3["d"]), names=("omega", "d"), dense_tol=1e-6,
                          ds=0.02, ds_max=0.1)
claims["model_003"] = {"box": {"omega": list(box3["omega"]), "d": list(box3["d"])}, "n_boundaries": len(found3),
                       "boundaries": []}
print(f"model 003: {len(found3)} boundary(ies) of the balanced regime in omega in {box3['omega']}, "
      f"d in {box3['d']}")
for i, b in enumerate(found3):
    d = b.dense(16)
    side = [c.stable_side for c in found3.crossings if c.branch == i and c.along == "omega"]
    info = {"omega_range": [float(d[:, 0].min()), float(d[:, 0].max())],
            "d_range": [float(d[:, 1].min()), float(d[:, 1].max())], "stops": list(b.stops),
            "ends": [b.x[0].tolist(), b.x[-1].tolist()], "start": b.x[b.start].tolist(),
            "points": int(len(b.x)), "interpolation_error_max": float(b.errors.max()),
            "residual_max": float(b.residuals.max()),
            "stable_side_in_omega": side[0] if side else None,
            "omega_at_d": {f"{v:g}": b.meets(1, v)[:, 0].tolist() for v in (0.01, 0.1, 0.5)}}
    claims["model_003"]["boundaries"].append(info)
    print(f"  boundary {i + 1}: across the box, both ends on its edge, from (omega, d) = ({b.x[0, 0]:.4f}, "
          f"{b.x[0, 1]:.2e}) ({b.stops[0]}) to ({b.x[-1, 0]:.4f}, {b.x[-1, 1]:.2e}) ({b.stops[1]}); traced "
          f"both ways from the crossing the scan located at ({info['start'][0]:.4f}, {info['start'][1]:.2e}); "
          f"{info['points']} points, interpolation error <= {info['interpolation_error_max']:.1e} along omega")
    print(f"    omega = {info['omega_at_d']['0.5'][0]:.4f} at d = 0.5, {info['omega_at_d']['0.1'][0]:.4f} at "
          f"0.1, {info['omega_at_d']['0.01'][0]:.4f} at 0.01: the balanced regime is stable "
          f"{info['stable_side_in_omega']} the boundary in omega (auto-balancing above the first critical "
          "speed; the less external damping, the higher the speed it needs)")

fig, ax = plt.subplots(figsize=(7, 4.5))
for i, b in enumerate(found3):
    d = b.dense(16)
    if claims["model_003"]["boundaries"][i]["stable_side_in_omega"] == "above":
        ax.fill_between(d[:, 1], d[:, 0], box3["omega"][1], color="tab:green", alpha=0.12,
                        label="balanced regime stable")
    line, = ax.plot(d[:, 1], d[:, 0], lw=1.4, label=f"boundary {i + 1} (dense curve)")
    ax.plot(b.x[:, 1], b.x[:, 0], "o", ms=2.5, color=line.get_color(), label="continuation points")
    ax.plot(*b.x[b.start, ::-1], "k*", ms=9, label="start (crossing located by the scan)")
ax.set_xscale("log")
ax.set_xlim(1e-4, box3["d"][1])
ax.set_ylim(*box3["omega"])
ax.set_xlabel("external damping d / (m_S omega_1) (dimensionless, log scale)")
ax.set_ylabel("speed omega / omega_1 (dimensionless)")
ax.set_title("model 003: stability boundary of the balanced regime C (two balls)")
ax.legend(fontsize=8)
ax.grid(alpha=0.3, which="both")
fig.tight_layout()
fig.savefig(os.path.join(OUT, "boundary_003.png"), dpi=100)
plt.show()

# %%
with open(os.path.join(OUT, "stability_boundaries_claims.json"), "w") as f:
    json.dump(claims, f, indent=1)
