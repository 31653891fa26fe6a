"""Generate the shipped synthetic measurements (a documented, seeded script):

    python -m rotorjax.identify._make_data

Writes into `rotorjax/identify/data/`:
- `balancing_runs.csv`: three steady runs of the rig `RIG` (the `balancing-machine` preset's rotor)
  at 120 rad/s (2 s each, 2 kHz): without a trial weight, with a trial weight of
  1e-4 kg m at 0 deg in plane 0, and at 90 deg in plane 1; sensor noise 1 % of the
  initial vibration (Gaussian, per sample);
- `runup.csv`: a run-up from 20 to 400 rad/s in 20 s sampled at 1 kHz (20 000
  samples), through the supports' resonances, simulated in the time domain, with 1 % noise.
Columns as documented in `rotorjax.identify._signals`; the tacho is a 1-sample
pulse train with one pulse per revolution at the mark (theta = 2 pi k).

Every signal is model 002 as a scene, `BalancingScene(machine, planes, unbalances,
speed)`, integrated by `rotorjax.simulate` (diffrax Dopri8, PID controller at
rtol 1e-10, atol 1e-14: `SOLVER`): a `ConstantSpeed` for the balancing runs (from
rest, the first 3 s of transient discarded), a `RunUp` for the run-ups (from the
steady response at the start speed, so that no start-up transient remains).

`runup_dataset(seed, ...)` makes more run-ups like the shipped one (for Monte
Carlo studies): per seed, the rotor's angle at the start (the mark's phase against
the sampling clock, which sets where the tacho pulses fall between samples) and
the sensor noise are drawn anew.
"""

import functools
import os

import jax.numpy as jnp
import numpy as np

from .._errors import NumericalError
from ..analysis._balancing002 import balancing_response
from ..models._balancing_machine import BalancingScene
from ..models._speed import ConstantSpeed, RunUp
from ..solve._simulate import simulate as simulate_scene
from ._datasets import RIG, machine_from, planes_from, unbalances_from

DATA = os.path.join(os.path.dirname(os.path.abspath(__file__)), "data")
SEED = 20161

#: How the synthetic signals are integrated (`rotorjax.simulate`'s keywords).
SOLVER = dict(solver="dopri8", rtol=1e-10, atol=1e-14, max_steps=10**7)


def _tacho(theta):
    k = np.floor(theta / (2 * np.pi))
    pulse = np.zeros_like(theta)
    pulse[1:][np.diff(k) > 0] = 1.0
    return pulse


def simulate(scene, t, y0=None):
    """The support displacements of a `BalancingScene` at the sample times `t`.

    **Arguments:** `scene` (its speed profile gives the rotor angle and the
    unbalance force of eq. 8), the times `t` (1-D, increasing; the integration
    runs from `t[0]` to `t[-1]`), the state `y0 = (x1, x2, x1', x2')` at `t[0]`
    (default: at rest).

    **Returns:** `(x1, x2)` at `t`, a NumPy array of shape `(len(t), 2)`, from
    `rotorjax.simulate` with `SOLVER`.

    **Raises:** `NumericalError` if the integration fails (step budget, NaN).
    """
    t = jnp.asarray(t, dtype=jnp.float64)
    y0 = jnp.zeros(scene.state_size) if y0 is None else y0
    r = simulate_scene(scene, y0, (t[0], t[-1]), saveat=t, **SOLVER)
    if not bool(r.success):
        raise NumericalError(f"the synthetic signal of the {scene.describe()} failed: {r.message}")
    return np.stack([np.asarray(r.outputs["x1"]), np.asarray(r.outputs["x2"])], axis=1)


def simulate_from(scene, t, w0):
    """`simulate(scene, t)` from the steady response at the constant speed `w0`
    (rad/s) and angle 0 (`scene.steady_state(w0)`): for a profile that starts at
    `w0` with `theta(t[0]) = 0`, no start-up transient."""
    return simulate(scene, t, scene.steady_state(w0))


def _write(path, cols):
    names = list(cols)
    table = np.stack([np.asarray(cols[k], dtype=float) for k in names], axis=1)
    np.savetxt(path, table, delimiter=",", header=",".join(names), comments="", fmt="%.10g")


def make_balancing_runs(p, rng):
    machine, planes, U = machine_from(p), planes_from(p), unbalances_from(p)
    w, fs, dur = 120.0, 2000.0, 2.0
    trials = [None, (0, 1e-4, 0.0), (1, 1e-4, 90.0)]
    cols = {k: [] for k in ("time", "tacho", "x1", "x2", "run", "trial_plane", "trial_unbalance", "trial_angle")}
    settle = 3.0  # s of transient discarded: the steady run is what a balancing machine measures
    t = np.arange(0.0, settle + dur, 1 / fs)
    X0 = np.asarray(balancing_response(machine, w, planes, U))
    noise = 0.01 * np.max(np.abs(X0))
    for run, trial in enumerate(trials):
        Ur = np.array(U, dtype=complex)
        if trial is not None:
            Ur[trial[0]] += trial[1] * np.exp(1j * np.radians(trial[2]))
        scene = BalancingScene(machine, planes, Ur, ConstantSpeed(w))
        x = simulate(scene, t)
        keep = t >= settle
        tt = t[keep] - settle + run * (dur + 1.0)
        theta = np.asarray(scene.speed.angle(t[keep]))
        cols["time"].append(tt)
        cols["tacho"].append(_tacho(theta))
        cols["x1"].append(x[keep, 0] + noise * rng.normal(size=keep.sum()))
        cols["x2"].append(x[keep, 1] + noise * rng.normal(size=keep.sum()))
        cols["run"].append(np.full(keep.sum(), run))
        cols["trial_plane"].append(np.full(keep.sum(), -1 if trial is None else trial[0]))
        cols["trial_unbalance"].append(np.full(keep.sum(), 0.0 if trial is None else trial[1]))
        cols["trial_angle"].append(np.full(keep.sum(), 0.0 if trial is None else trial[2]))
    _write(os.path.join(DATA, "balancing_runs.csv"), {k: np.concatenate(v) for k, v in cols.items()})


def _runup_scene(p, unbalances, duration, w0, w1):
    """The rig `p` with `unbalances` on the run-up from `w0` to `w1` (rad/s) in
    `duration` (s): `RunUp(w0, (w1 - w0) / duration)`, angle 0 at `t = 0`."""
    return BalancingScene(machine_from(p), planes_from(p), unbalances, RunUp(w0, (w1 - w0) / duration))


def make_runup(p, rng, fs=1000.0, duration=20.0, w0=20.0, w1=400.0):
    scene = _runup_scene(p, unbalances_from(p), duration, w0, w1)
    t = np.arange(0.0, duration, 1 / fs)
    x = simulate_from(scene, t, w0)
    noise = 0.01 * np.max(np.abs(x))
    cols = {"time": t, "tacho": _tacho(np.asarray(scene.speed.angle(t))),
            "x1": x[:, 0] + noise * rng.normal(size=t.size), "x2": x[:, 1] + noise * rng.normal(size=t.size)}
    _write(os.path.join(DATA, "runup.csv"), cols)


@functools.lru_cache(maxsize=4)
def _runup_clean(params, fs, duration, w0, w1):
    """`(t, x_D, x_iD)`: the noise-free run-up for the unbalances `D` and for `i D`
    (the response is real-linear in the unbalances), simulated once per setting
    (the two scenes share one compiled integration)."""
    p = dict(params)
    U = unbalances_from(p)
    t = np.arange(0.0, duration, 1 / fs)
    out = [simulate_from(_runup_scene(p, D, duration, w0, w1), t, w0) for D in (U, 1j * U)]
    return t, out[0], out[1]


def runup_dataset(seed, p=None, fs=1000.0, duration=20.0, w0=20.0, w1=400.0, noise=0.01):
    """One synthetic run-up like the shipped `runup.csv`, for a seed.

    The rotor's angle at `t = 0` is `phi`, drawn uniformly in `[0, 2 pi)`: the
    unbalance forcing is that of the unbalances `D e^{i phi}` on the sweep
    `theta_s(t) = w0 t + alpha t^2 / 2` (a `RunUp`), so `x = cos(phi) x_D + sin(phi) x_{iD}`
    from two simulations made once and cached (`BalancingScene` by `rotorjax.simulate`,
    `SOLVER`, from the steady response at `w0`), and the tacho pulses fall at
    `phi + theta_s = 2 pi k`, between samples in a new way for each seed. Sensor noise:
    Gaussian, per sample, `noise` times the peak of the noise-free signal, drawn anew.

    **Arguments:** `seed` (int), `p` (the rig's parameters, the keys of `RIG` as
    the `balancing-machine` preset's; default `RIG`), the sampling rate `fs` (Hz), the run-up's `duration`
    (s) from `w0` to `w1` (rad/s), the relative `noise`.

    **Returns:** `{"time", "tacho", "x1", "x2"}` (arrays, the columns of
    `runup.csv`), plus `"phi"` (rad) and `"noise_sd"` (m).
    """
    p = dict(RIG) if p is None else dict(p)
    t, xD, xiD = _runup_clean(tuple(sorted(p.items())), float(fs), float(duration), float(w0), float(w1))
    rng = np.random.default_rng(seed)
    phi = float(rng.uniform(0.0, 2 * np.pi))
    x = np.cos(phi) * xD + np.sin(phi) * xiD
    alpha = (w1 - w0) / duration
    sd = noise * float(np.max(np.abs(x)))
    return {"time": t, "tacho": _tacho(phi + w0 * t + 0.5 * alpha * t**2),
            "x1": x[:, 0] + sd * rng.normal(size=t.size), "x2": x[:, 1] + sd * rng.normal(size=t.size),
            "phi": phi, "noise_sd": sd}


def main():
    from .. import _config  # noqa: F401  (float64)

    os.makedirs(DATA, exist_ok=True)
    rng = np.random.default_rng(SEED)
    p = dict(RIG)
    make_balancing_runs(p, rng)
    make_runup(p, rng)
    print(f"wrote {DATA}/balancing_runs.csv and runup.csv")


if __name__ == "__main__":
    main()
