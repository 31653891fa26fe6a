# ---
# jupyter:
#   jupytext:
#     formats: ipynb,py:percent
#   kernelspec:
#     name: python3
#     display_name: Python 3
# ---

# %% [markdown]
# # Identify the balancing machine, then balance the rotor (model 002)
#
# From the shipped measured dataset (`rotorjax.identify.RUNUP`: a 20 000-sample
# run-up from 20 to 400 rad/s in 20 s with a once-per-revolution tacho, both
# sampled at 1 kHz, 1 % sensor noise) we extract one 1x phasor per revolution,
# fit the supports' stiffness and damping (and the unbalances) by
# Levenberg-Marquardt with autodiff Jacobians, and then balance from the three
# shipped steady runs with trial weights.
#
# The steady-response fit this notebook used to make gave 95 % intervals that all
# missed the truth. Below: why (three suspects, each measured on its own), and the
# fit that covers: the run-up model with the phase reference fitted jointly.

# %%
import json
import os

import jax
import matplotlib.pyplot as plt
import numpy as np

import rotorjax  # noqa: F401
from rotorjax import identify as idf
from rotorjax.analysis import balancing_response
from rotorjax.identify import _make_data as md
from rotorjax.presets import balancing_machine as bm

OUT = os.environ.get("ROTORJAX_NOTEBOOK_OUT", "notebook-out")
os.makedirs(OUT, exist_ok=True)
p = dict(bm.PRESET.defaults)
machine, planes, U = bm.build_machine(p), bm.planes(p), bm.unbalances(p)
NAMES = ("k1", "k2", "c1", "c2")
W0, W1, DURATION, FS = 20.0, 400.0, 20.0, 1000.0      # the shipped run-up (see `_make_data`)
ALPHA = (W1 - W0) / DURATION
claims = {"truth": {k: p[k] for k in NAMES}}


def steady(m, w):
    return np.asarray(jax.vmap(lambda ww: balancing_response(m, ww, planes, U))(np.asarray(w)))


def errors_pct(res):
    return {k: 100 * (res.estimates[k] / p[k] - 1) for k in NAMES}


def report(res, label):
    print(label)
    out = {"estimates": res.estimates, "intervals": res.intervals, "covers": {}, "error_pct": errors_pct(res),
           "error_in_sd": {}, "warnings": res.warnings}
    for k in NAMES:
        lo, hi = res.intervals[k]
        out["covers"][k] = bool(lo <= p[k] <= hi)
        out["error_in_sd"][k] = (res.estimates[k] - p[k]) / res.std[k]
        print(f"  {k}: {res.estimates[k]:.6g}  95% [{lo:.6g}, {hi:.6g}]  (true {p[k]:.6g}: error "
              f"{out['error_pct'][k]:+.3f} %, {out['error_in_sd'][k]:+.1f} sd; "
              f"{'covered' if out['covers'][k] else 'MISSED'})")
    print("  warnings:", res.warnings or "none")
    return out


# %%
cols = idf.read_signals(idf.RUNUP)
track = idf.order_track(cols["time"], np.stack([cols["x1"], cols["x2"]], axis=1), tacho=cols["tacho"], full=True)
speeds, X = track.speeds, track.X
print(f"{speeds.size} revolutions, {speeds.min():.1f} to {speeds.max():.1f} rad/s")
claims["n_revolutions"] = int(speeds.size)

# %% [markdown]
# ## The steady fit: intervals that miss
#
# As this notebook did before: the steady 1x response `X = K(w) D` at each
# revolution's speed, the classical covariance `s^2 (J^T J)^-1`, on phasors
# tracked with an unweighted fit of the tacho's angle.

# %%
start = bm.build_machine(dict(p, k1=1.5e5, k2=3.75e5, c1=100.0, c2=266.0))
speeds_u, X_u = idf.order_track(cols["time"], np.stack([cols["x1"], cols["x2"]], axis=1), tacho=cols["tacho"],
                                weighted=False)
# the scene: the start, the planes, and unbalances to be fitted (`fit_unbalance=True`)
scene = idf.BalancingScene(start, planes, np.zeros(len(planes), dtype=complex))
old = idf.identify(scene, (speeds_u, X_u), NAMES, fit_unbalance=True)
claims["old"] = report(old, "steady model, classical covariance (as before):")

# %% [markdown]
# ## Why: three suspects, each measured alone
#
# The generator's noise-free run-up (`_make_data`, the same simulation as the
# shipped file, without the noise) lets us take the error sources apart:
#
# - **(a) model error**: a steady response fitted to a run-up's transient. The
#   noise-free run-up, order-tracked with the *exact* angle: what bias remains is
#   the model's.
# - **(b) phasor extraction**: the quasi-static signal `Re(X_steady(w(t)) e^{i theta(t)})`
#   (no transient) order-tracked (i) with the exact angle: the averaging over a
#   revolution; (ii) with the shipped tacho: the phase reference. The tacho is
#   sampled at 1 kHz, so each pulse is timed to within half a sample (0.29 ms rms:
#   0.1 rad at 400 rad/s) and the angle fitted through 667 pulses is off by a
#   smooth error of a few mrad, the same for both sensors.
# - **(c) correlated residuals**: the autocorrelation of the steady fit's residuals
#   (per sensor, Re and Im, in speed order) and what it does to the covariance.

# %%
t, x_clean, _ = md._runup_clean(tuple(sorted(p.items())), FS, DURATION, W0, W1)
theta_true = W0 * t + 0.5 * ALPHA * t**2
k = 2 * np.pi * np.arange(1, 2 * speeds.size)
exact = (-W0 + np.sqrt(W0**2 + 2 * ALPHA * k)) / ALPHA
exact = exact[exact < t[-1]]
print(f"noise in the file: {np.std(cols['x1'] - x_clean[:, 0]):.3g} m rms "
      f"({np.std(cols['x1'] - x_clean[:, 0]) / np.max(np.abs(x_clean)):.2%} of the peak)")


def steady_fit_pct(w, Xw):
    return errors_pct(idf.identify(scene, (w, Xw), NAMES, fit_unbalance=True))


model_error = steady_fit_pct(*idf.order_track(t, x_clean, pulses=exact))
omega_true = W0 + ALPHA * t
x_qs = np.real(steady(machine, omega_true) * np.exp(1j * theta_true)[:, None])
averaging = steady_fit_pct(*idf.order_track(t, x_qs, pulses=exact))
reference_old = steady_fit_pct(*idf.order_track(t, x_qs, tacho=cols["tacho"], weighted=False))
both_old = steady_fit_pct(*idf.order_track(t, x_clean, tacho=cols["tacho"], weighted=False))
reference = steady_fit_pct(*idf.order_track(t, x_qs, tacho=cols["tacho"]))
both = steady_fit_pct(*idf.order_track(t, x_clean, tacho=cols["tacho"]))
angle_err = track.angle_derivatives(track.block_time) - (W0 * track.block_time
                                                         + 0.5 * ALPHA * track.block_time**2)
angle_err -= 2 * np.pi * np.round(angle_err / (2 * np.pi))       # the angle counts from the first pulse
V, _ = track.angle_sensitivity(track.block_time)
angle_sd = np.sqrt(np.einsum("ij,jk,ik->i", V, track.angle_cov, V))
print("bias of the steady fit to noise-free signals (%):")
for label, e in (("(a) run-up transient, exact angle (model error)", model_error),
                 ("(b-i) quasi-static, exact angle (averaging)", averaging),
                 ("(b-ii) quasi-static, shipped tacho, unweighted angle fit", reference_old),
                 ("run-up transient, shipped tacho, unweighted (a + b)", both_old),
                 ("(b-ii) quasi-static, shipped tacho, weighted angle fit", reference),
                 ("run-up transient, shipped tacho, weighted (a + b)", both)):
    print(f"  {label:58s}" + "  ".join(f"{k} {e[k]:+.3f}" for k in NAMES))
print(f"the tacho's angle error (weighted fit): {1e3 * np.max(np.abs(angle_err)):.1f} mrad at most (at "
      f"{track.speeds[np.argmax(np.abs(angle_err))]:.0f} rad/s), stated sd {1e3 * angle_sd[0]:.1f} to "
      f"{1e3 * angle_sd[-1]:.1f} mrad at the ends; pulse jitter {1e3 * track.pulse_jitter:.3f} ms rms")
print("(c) residuals of the steady fit to the shipped data:")
for ch, v in old.residual_structure.items():
    print(f"  {ch}: lag-1 autocorrelation {v['rho1']:+.3f}, runs test z {v['runs_z']:+.1f}, "
          f"effective points {v['n_eff']:.0f} of {v['n']}")
old_hac = idf.identify(scene, (speeds_u, X_u), NAMES, fit_unbalance=True, covariance="hac")
hac_ratio = {k: old_hac.std[k] / old.std[k] for k in NAMES}
print("  HAC / classical standard deviation: " + ", ".join(f"{k} {hac_ratio[k]:.2f}" for k in NAMES))
print("  the old errors in classical sd: " + ", ".join(f"{k} {claims['old']['error_in_sd'][k]:+.1f}"
                                                      for k in NAMES))
claims["diagnosis"] = {
    "model_error_pct": model_error, "averaging_bias_pct": averaging,
    "reference_bias_unweighted_pct": reference_old, "transient_and_reference_bias_unweighted_pct": both_old,
    "reference_bias_pct": reference, "transient_and_reference_bias_pct": both,
    "angle_error_max_mrad": float(1e3 * np.max(np.abs(angle_err))),
    "angle_sd_ends_mrad": [float(1e3 * angle_sd[0]), float(1e3 * angle_sd[-1])],
    "pulse_jitter_ms": 1e3 * track.pulse_jitter,
    "residual_rho1": {ch: v["rho1"] for ch, v in old.residual_structure.items()},
    "residual_n_eff": {ch: v["n_eff"] for ch, v in old.residual_structure.items()},
    "hac_over_classical_sd": hac_ratio}

# %% [markdown]
# So the steady fit's intervals miss because of **bias**, not because of the
# covariance: the transient (a) and the tacho's phase reference (b-ii) each bias
# the estimates by 0.1 to 1 %, several standard deviations, while the residuals are
# nearly independent (c: lag-1 autocorrelations within +-0.1; a HAC covariance
# widens the intervals by a few per cent only). The averaging over a revolution
# (b-i) is negligible.
#
# ## The fix: the run-up model, with the phase reference fitted jointly
#
# `identify(scene, track)` (an `OrderTrack`) fits the phasors the run-up produces: the
# machine's time response along the tacho's speed profile (exact for the linear
# machine: modal exponential integrator), order-tracked with the data's own block
# operator; each phasor weighted by its noise (`track.sigma`, larger at high
# speed where a revolution holds fewer samples). The error of the tacho's angle
# fit is fitted too, with the fit's own covariance as prior; the intervals use the
# Newey-West (HAC) covariance. That these intervals cover 95 % of the time, and
# the old ones do not, is shown over 200 run-ups like this one by
# `benchmarks/identification_coverage.py` (and over 40 shorter ones by
# `tests/identify/test_coverage.py`).

# %%
new = idf.identify(scene, track, NAMES, fit_unbalance=True)
claims["new"] = report(new, f"run-up model, phase reference fitted jointly, {new.covariance_method} covariance:")
# a constant error of the angle turns both unbalances alike, so the fit cannot tell it from their
# angles: compare the angle error and its fitted correction up to a constant
phase = new.phase_correction
shape_actual, shape_fitted = angle_err - angle_err.mean(), phase - phase.mean()
rms = {"actual": float(1e3 * np.sqrt(np.mean(shape_actual**2))),
       "fitted": float(1e3 * np.sqrt(np.mean(shape_fitted**2))),
       "difference": float(1e3 * np.sqrt(np.mean((shape_fitted - shape_actual) ** 2)))}
print(f"the tacho's angle error up to a constant: rms {rms['actual']:.2f} mrad; the fitted correction "
      f"{rms['fitted']:.2f} mrad, off by {rms['difference']:.2f} mrad rms")
unb_deg = np.degrees(np.angle(new.unbalances / U))
print("unbalances: magnitude error " + ", ".join(f"{100 * (abs(d) / abs(u) - 1):+.2f} %" for d, u in
                                                   zip(new.unbalances, U))
      + "; angle error " + ", ".join(f"{a:+.2f} deg" for a in unb_deg)
      + f" (the mean angle error of the tacho fit: {np.degrees(angle_err.mean()):+.2f} deg)")
claims["new"].update(model=new.model, covariance_method=new.covariance_method, phase_correction_rms_mrad=rms,
                     unbalance_angle_error_deg=unb_deg.tolist(),
                     angle_error_mean_deg=float(np.degrees(angle_err.mean())),
                     residual_rho1={ch: v["rho1"] for ch, v in new.residual_structure.items()})

# %%
fitted = bm.build_machine(dict(p, **new.estimates))
model_steady = np.asarray(jax.vmap(lambda w: balancing_response(fitted, w, planes, new.unbalances))(speeds))
fig, (ax, ax2) = plt.subplots(1, 2, figsize=(12, 4))
for i in range(2):
    ax.plot(speeds, np.abs(X[:, i]) * 1e6, ".", ms=2, label=f"measured (order-tracked), support {i + 1}")
    ax.plot(speeds, np.abs(model_steady[:, i]) * 1e6, "-", label=f"identified machine, steady, support {i + 1}")
ax.set_xlabel("speed (rad/s)")
ax.set_ylabel("1x amplitude (um)")
ax.legend(fontsize=7)
ax2.fill_between(speeds, -2e3 * angle_sd, 2e3 * angle_sd, color="0.85", label="tacho fit: +-2 sd (prior)")
ax2.plot(speeds, 1e3 * shape_actual, "k-", label="actual angle error of the tacho fit (less its mean)")
ax2.plot(speeds, 1e3 * shape_fitted, "r--", label="fitted jointly with k, c, D (less its mean)")
ax2.set_xlabel("speed (rad/s)")
ax2.set_ylabel("phase reference error (mrad)")
ax2.legend(fontsize=7)
fig.tight_layout()
fig.savefig(os.path.join(OUT, "identification.png"), dpi=100)

# %% [markdown]
# ## Balancing from the steady runs with trial weights

# %%
runs = idf.runs_from_signals(idf.read_signals(idf.BALANCING_RUNS))
X0 = runs[0]["X"]
K = idf.influence_from_trials(X0, np.stack([r["X"] for r in runs[1:]]), np.array([r["trial"][1] for r in runs[1:]]))
W = -idf.unbalance_from_vibration(K, X0)
claims["balancing"] = {"corrections": []}
for j, w in enumerate(W):
    g, ang = abs(w) / 0.01 * 1e3, np.degrees(np.angle(w)) % 360
    claims["balancing"]["corrections"].append({"plane": j, "mass_g": g, "angle_deg": ang})
    print(f"plane {j}: add {g:.2f} g at {ang:.1f} deg (radius 10 mm)")
# the model with the identified parameters predicts the same correction
W_model = -np.linalg.solve(np.asarray(fitted.influence_matrix(runs[0]["speed"], planes)), X0)
diff = float(np.max(np.abs(W_model - W)) / np.max(np.abs(W)))
claims["balancing"]["model_based_difference"] = diff
print("model-based correction differs by", diff)
assert np.allclose(W, -U, rtol=0.02)

with open(os.path.join(OUT, "identification_claims.json"), "w") as f:
    json.dump(claims, f, indent=2, default=float)

# %% [markdown]
# # A flexible rotor: identify the bearings, balance, and check the run-up after balancing
#
# The same steps on a finite-element rotor (issue 16). The machine is the shipped
# rotor file `flexible_rig` (a six-element Timoshenko shaft, two disks at nodes 2 and
# 4, two anisotropic damped bearings at nodes 0 and 6). The file holds the DESIGN
# (nominal) bearing coefficients; the as-built machine's differ by factors of 0.5 to
# 1.8 (`_make_fe_data.TRUTH`), and it carries residual unbalances at both disks. The
# shipped measurements (`_make_fe_data`): the `flexible-runup` dataset, 1x phasors at
# 50 speeds from 30 to 460 rad/s through both forward critical speeds, at x and y of
# both bearings, with 1 % noise; and the `flexible-trials` dataset, a trial-weight
# session at 4 speeds.
#
# 1. **Identify** the 8 bearing coefficients (`kxx, kyy, cxx, cyy` of both bearings)
#    and the unbalances at nodes 2 and 4 from the run-up, starting from the nominal
#    file (`identify`: a global Levenberg-Marquardt search over 32 starts, the
#    unbalances projected out as the linear least-squares part, delta-method intervals).

# %%
from rotorjax.identify import _make_fe_data as fe
from rotorjax.flexible import critical_speeds_1x

rig_path = str(rotorjax.io.shipped_rotor("flexible_rig"))
FE_NAMES = tuple(fe.TRUTH)
runup_data = idf.read_phasors("flexible-runup")
fe_fit = idf.identify(idf.rotor_model(rig_path), runup_data, FE_NAMES, fit_unbalance=[2, 4])
nominal = {q.name: q.start for q in idf.rotor_model(rig_path).parameters(FE_NAMES)}
flex = {"truth": dict(fe.TRUTH), "nominal": nominal, "estimates": fe_fit.estimates,
        "intervals": fe_fit.intervals, "error_pct": {}, "covers": {}, "warnings": list(fe_fit.warnings),
        "n_starts": fe_fit.n_starts, "residual_rms": fe_fit.rms_residual}
print(f"{len(FE_NAMES)} bearing coefficients and 2 unbalances fitted to {runup_data.n} phasors "
      f"({fe_fit.n_starts} starts, residual rms {fe_fit.rms_residual:.3g} m)")
for k in FE_NAMES:
    lo, hi = fe_fit.intervals[k]
    flex["error_pct"][k] = 100 * (fe_fit.estimates[k] / fe.TRUTH[k] - 1)
    flex["covers"][k] = bool(lo <= fe.TRUTH[k] <= hi)
    print(f"  {k:13s} {fe_fit.estimates[k]:.6g}  95% [{lo:.6g}, {hi:.6g}]  (true {fe.TRUTH[k]:.6g}, nominal "
          f"{nominal[k]:.6g}: error {flex['error_pct'][k]:+.3f} %, {'covered' if flex['covers'][k] else 'MISSED'})")
U_true = {node: mag * np.exp(1j * ph) for node, mag, ph in fe.UNBALANCES}
U_fit = {u["node"]: u["magnitude"] * np.exp(1j * u["phase"]) for u in fe_fit.unbalance_table}
flex["unbalances"] = []
for u in fe_fit.unbalance_table:
    n, ut = u["node"], U_true[u["node"]]
    rel = float(abs(U_fit[n] - ut) / abs(ut))
    flex["unbalances"].append({"node": n, "magnitude": u["magnitude"], "phase": u["phase"],
                               "magnitude_ci95": u["magnitude_ci95"], "phase_ci95": u["phase_ci95"],
                               "true_magnitude": float(abs(ut)), "true_phase": float(np.angle(ut)),
                               "relative_error": rel})
    print(f"  unbalance at node {n}: {1e6 * u['magnitude']:.2f} g mm at {u['phase']:.4f} rad  95% "
          f"[{1e6 * u['magnitude_ci95'][0]:.2f}, {1e6 * u['magnitude_ci95'][1]:.2f}] g mm, "
          f"[{u['phase_ci95'][0]:.4f}, {u['phase_ci95'][1]:.4f}] rad  (true {1e6 * abs(ut):.2f} g mm at "
          f"{np.angle(ut):.4f} rad: |error| {100 * rel:.3f} % of it)")
true_machine = fe.true_rotor()
design_machine = rotorjax.io.load_rotor(rig_path).rotor
lo_w, hi_w = float(runup_data.speed.min()), float(runup_data.speed.max())


def forward_criticals(rotor):
    return [float(s) for s, _ in critical_speeds_1x(rotor, lo_w, hi_w, n_modes=12, whirl="forward")]


crit_true, crit_design = forward_criticals(true_machine), forward_criticals(design_machine)
flex["critical_speeds"] = [{"speed": c["speed"], "ci95": c["ci95"], "true": t, "design": d}
                           for c, t, d in zip(fe_fit.critical_speeds, crit_true, crit_design)]
for c in flex["critical_speeds"]:
    print(f"  forward critical speed {c['speed']:.3f} rad/s  95% [{c['ci95'][0]:.3f}, {c['ci95'][1]:.3f}]  "
          f"(true machine {c['true']:.3f}, design {c['design']:.3f})")
print("  warnings:", fe_fit.warnings or "none")
claims["flexible"] = flex

# %% [markdown]
# 2. **Balance** in planes 2 and 4 from the trial-weight session: the influence
#    coefficients from the trial runs, the identified rotor as the model (its critical
#    speeds for ISO 21940-12's counts), the corrections by least squares over all
#    speeds and sensors and by min-max (the smallest worst residual). A perfect
#    correction is minus the machine's unbalance.

# %%
identified = rotorjax.io.load_rotor(rig_path, overrides=fe_fit.estimates).rotor
trials_data = idf.read_phasors("flexible-trials")
flex["balancing"] = {}
for method in ("ls", "minmax"):
    bal = idf.balance(trials_data, planes=[2, 4], method=method, influence="trials", scene=identified)
    out = {"corrections": [], "predicted_before_max": bal.before_max, "predicted_after_max": bal.after_max,
           "warnings": list(bal.warnings)}
    print(f"{method}: balancing speeds {', '.join(f'{s:g}' for s in bal.balancing_speeds)} rad/s")
    for node, w in zip(bal.planes, bal.W):
        cancel = float(abs(w + U_true[node]) / abs(U_true[node]))
        out["corrections"].append({"node": node, "magnitude": float(abs(w)), "phase": float(np.angle(w)),
                                   "cancel_rel": cancel})
        print(f"  node {node}: add {1e6 * abs(w):.2f} g mm at {np.degrees(np.angle(w)) % 360:.2f} deg  "
              f"(minus the true unbalance: {1e6 * abs(U_true[node]):.2f} g mm at "
              f"{np.degrees(np.angle(-U_true[node])) % 360:.2f} deg; |correction + U| = {100 * cancel:.2f} % of U)")
    print(f"  at the balancing speeds: max {1e6 * bal.before_max:.2f} um before, {1e6 * bal.after_max:.3f} um "
          f"after (predicted from the trials); warnings: {list(bal.warnings) or 'none'}")
    flex["balancing"][method] = out

# %% [markdown]
# 3. **The run-up after balancing, predicted vs "measured".** The "measured" run-up
#    after balancing is simulated on the TRUE machine (its bearing coefficients and
#    unbalances, plus the corrections, noise-free) at the run-up's speeds and sensors;
#    the prediction is the IDENTIFIED rotor with the identified unbalances plus the
#    same corrections. Before: the `flexible-runup` measurements.

# %%
n_sens = len(fe.SENSORS)
before = np.zeros((fe.RUNUP_SPEEDS.size, n_sens), complex)
for i, (w_, node, d, x_) in enumerate(zip(runup_data.speed, runup_data.node, runup_data.direction, runup_data.X)):
    before[np.argmin(np.abs(fe.RUNUP_SPEEDS - w_)), fe.SENSORS.index((int(node), "xy"[int(d)]))] = x_
before_max = float(np.max(np.abs(before)))
flex["runup"] = {"before_max": before_max}
after = {}
for method in ("ls", "minmax"):
    corr = [(c["node"], c["magnitude"], c["phase"]) for c in flex["balancing"][method]["corrections"]]
    measured = fe.clean_phasors(true_machine, list(fe.UNBALANCES) + corr, fe.RUNUP_SPEEDS, fe.SENSORS)
    predicted = fe.clean_phasors(identified, [(n, abs(u), float(np.angle(u))) for n, u in U_fit.items()] + corr,
                                 fe.RUNUP_SPEEDS, fe.SENSORS)
    after[method] = (measured, predicted)
    m_max, p_max = float(np.max(np.abs(measured))), float(np.max(np.abs(predicted)))
    diff = float(np.max(np.abs(predicted - measured)))
    flex["runup"][method] = {"measured_after_max": m_max, "predicted_after_max": p_max, "difference_max": diff,
                             "after_over_before": m_max / before_max, "difference_over_after": diff / m_max,
                             "difference_over_before": diff / before_max}
    print(f"{method}: max vibration over the run-up {1e6 * before_max:.2f} um before, {1e6 * m_max:.3f} um after "
          f"measured ({100 * m_max / before_max:.2f} % of before), {1e6 * p_max:.3f} um predicted; predicted - "
          f"measured at most {1e6 * diff:.3f} um: {100 * diff / m_max:.1f} % of the after level, "
          f"{100 * diff / before_max:.2f} % of the before level")

# %% [markdown]
# The intervals' coverage of the truth is printed, not asserted: one noisy data set
# cannot test a 95 % interval (each one misses 5 % of the time). What is asserted
# (`tests/notebook_checks/identification.py`): the estimates and unbalances within
# 2 % of the truth, corrections that cancel the true unbalances within 3 %, the
# run-up after balancing below 5 % of the run-up before, and the prediction from the
# identified rotor within 10 % of the before level of the "measured" after.

# %%
measured, predicted = after["ls"]
fig, axes = plt.subplots(2, 2, figsize=(12, 7), sharex=True)
for j, (ax, (node, d)) in enumerate(zip(axes.ravel(), fe.SENSORS)):
    ax.semilogy(fe.RUNUP_SPEEDS, 1e6 * np.abs(before[:, j]), "k.-", ms=4, lw=0.6, label="before (flexible-runup)")
    ax.semilogy(fe.RUNUP_SPEEDS, 1e6 * np.abs(predicted[:, j]), "r-", label="after LS balancing: predicted "
                "(identified rotor)")
    ax.semilogy(fe.RUNUP_SPEEDS, 1e6 * np.abs(measured[:, j]), "bo", ms=3, mfc="none",
                label='after: "measured" (true machine)')
    for c in fe_fit.critical_speeds:
        ax.axvline(c["speed"], color="0.7", lw=0.8, ls=":")
    ax.set_title(f"node {node}, {d}", fontsize=9)
    ax.set_ylabel("1x amplitude (um)")
    if j >= 2:
        ax.set_xlabel("speed (rad/s)")
axes[0, 0].legend(fontsize=7)
fig.tight_layout()
fig.savefig(os.path.join(OUT, "identification_flexible.png"), dpi=100)

with open(os.path.join(OUT, "identification_claims.json"), "w") as f:
    json.dump(claims, f, indent=2, default=float)
