"""Monte Carlo coverage of the identification's 95 % intervals (issue 13, item 3).

Data: run-ups like the shipped one (`rotorjax/identify/data/runup.csv`: the
`balancing-machine` preset, 20 -> 400 rad/s in 20 s sampled at 1 kHz, through
the first resonance and up to the second, 1 % sensor noise), from the documented
generator `rotorjax.identify._make_data.runup_dataset(seed)`. The noise-free
run-up is simulated in diffrax twice (for the unbalances `D` and `i D`) and
cached; per seed, the rotor's angle at the start `phi` (where the tacho pulses
fall between samples) and the sensor noise are drawn anew, and
`x = cos(phi) x_D + sin(phi) x_iD` is exact for a linear machine. So each data set
is a new draw of both error sources of a real run-up, the sensor noise and the
tacho's timing, without a diffrax run per data set.

Each data set is order-tracked (one phasor per revolution) and fitted four ways
(`k1, k2, c1, c2` and the two unbalances, from the notebook's start):

- `old`: the steady model, classical covariance `s^2 (J^T J)^-1`, on phasors
  tracked with the unweighted angle fit (`order_track(..., weighted=False)`):
  what the notebook and `rotorjax identify` did;
- `steady_hac`: the same with the Newey-West covariance (the covariance alone
  cannot fix a bias);
- `runup_noref`: the run-up model (transient-aware), phase reference (weighted
  angle fit) taken as exact;
- `new`: the run-up model with the phase reference fitted jointly (its prior from
  the tacho fit), HAC covariance: `identify(scene, order_track(...,
  full=True))`.

Per parameter and method: the coverage of the 95 % intervals with its binomial
95 % band around 0.95, the bias (mean relative error), the spread (standard
deviation of the relative error) and the mean reported standard deviation.
Times: the median wall time per fit after the first (compiling) one.

Run: python benchmarks/identification_coverage.py [--n 200] [--smoke] [--out DIR]
writes benchmarks/results/identification_coverage.json and .png (`--smoke`: 2
data sets, one call per timing; nothing written unless `--out` is given).
"""

import argparse
import json
import os
import sys
import time

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from _common import machine, timed_first, write_results  # noqa: E402

NAMES = ("k1", "k2", "c1", "c2")
METHODS = {
    "old": dict(unweighted=True),
    "steady_hac": dict(unweighted=True, covariance="hac"),
    "runup_noref": dict(tracking=True, reference="none", covariance="hac"),
    "new": dict(tracking=True),
}


def binomial_band(n, p=0.95, level=0.95):
    """The central `level` range of the coverage fraction of `n` intervals of true coverage `p`."""
    from scipy.stats import binom

    return float(binom.ppf((1 - level) / 2, n, p) / n), float(binom.ppf((1 + level) / 2, n, p) / n)


def fit(d, name, start, planes, idf):
    """Order tracking and the fit of one method."""
    kw = dict(METHODS[name])
    unweighted = kw.pop("unweighted", False)
    tr = idf.order_track(d["time"], np.stack([d["x1"], d["x2"]], axis=1), tacho=d["tacho"], full=True,
                         weighted=not unweighted)
    data = tr if kw.pop("tracking", False) else (tr.speeds, tr.X)
    scene = idf.BalancingScene(start, planes, np.zeros(len(planes), dtype=complex))
    return idf.identify(scene, data, NAMES, fit_unbalance=True, **kw)


def fit_all(d, start, planes, idf):
    out, times = {}, {}
    for name in METHODS:
        t0 = time.perf_counter()
        out[name] = fit(d, name, start, planes, idf)
        times[name] = time.perf_counter() - t0
    return out, times


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--n", type=int, default=200, help="data sets (default 200)")
    ap.add_argument("--smoke", action="store_true",
                    help="2 data sets, one call per timing (a quick check that it runs)")
    ap.add_argument("--out", default=None, help="write the JSON and PNG here instead of benchmarks/results")
    args = ap.parse_args()
    n = 2 if args.smoke else args.n

    import jax

    import rotorjax  # noqa: F401  (float64)
    from rotorjax import identify as idf
    from rotorjax.identify import _make_data as md
    from rotorjax.presets import balancing_machine as bm

    P = dict(bm.PRESET.defaults)
    planes = bm.planes(P)
    truth = np.array([P[k] for k in NAMES])
    start = bm.build_machine(dict(P, k1=1.5e5, k2=3.75e5, c1=100.0, c2=266.0))

    t0 = time.perf_counter()
    md.runup_dataset(0)
    t_clean = time.perf_counter() - t0
    # compile and run once: time one representative fit per method
    d0 = md.runup_dataset(0)
    fit_times = {}
    for name in METHODS:
        med, first, _ = timed_first(lambda name=name: fit(d0, name, start, planes, idf).estimates,
                                    repeats=0 if args.smoke else 3)
        fit_times[name] = {"first_call_s": first, "median_s": med}

    est = {m: np.empty((n, 4)) for m in METHODS}
    sd = {m: np.empty((n, 4)) for m in METHODS}
    lo = {m: np.empty((n, 4)) for m in METHODS}
    hi = {m: np.empty((n, 4)) for m in METHODS}
    warned = {m: 0 for m in METHODS}
    converged = {m: 0 for m in METHODS}
    per_fit = {m: [] for m in METHODS}
    t_loop = time.perf_counter()
    for seed in range(n):
        d = md.runup_dataset(seed)
        res, times = fit_all(d, start, planes, idf)
        for m, r in res.items():
            est[m][seed] = [r.estimates[k] for k in NAMES]
            sd[m][seed] = [r.std[k] for k in NAMES]
            lo[m][seed] = [r.intervals[k][0] for k in NAMES]
            hi[m][seed] = [r.intervals[k][1] for k in NAMES]
            warned[m] += bool(r.warnings)
            converged[m] += bool(r.converged)
            per_fit[m].append(times[m])
        if (seed + 1) % 20 == 0:
            print(f"  {seed + 1}/{n} data sets ({time.perf_counter() - t_loop:.0f} s)", flush=True)
    t_loop = time.perf_counter() - t_loop

    band = binomial_band(n)
    results = {}
    for m in METHODS:
        rel = est[m] / truth - 1
        cover = np.mean((lo[m] <= truth) & (truth <= hi[m]), axis=0)
        results[m] = {k: {"coverage": float(cover[i]), "bias_pct": float(100 * rel[:, i].mean()),
                          "bias_se_pct": float(100 * rel[:, i].std(ddof=1) / np.sqrt(n)) if n > 1 else None,
                          "spread_pct": float(100 * rel[:, i].std(ddof=1)) if n > 1 else None,
                          "mean_sd_pct": float(100 * np.mean(sd[m][:, i] / est[m][:, i])),
                          "coverage_in_band": bool(band[0] <= cover[i] <= band[1])}
                      for i, k in enumerate(NAMES)}
        results[m]["_fits"] = {"with_warnings": warned[m], "converged": converged[m],
                               "median_fit_s": float(np.median(per_fit[m]))}
    out = {"benchmark": "identification_coverage", "machine": machine(),
           "versions": {"jax": jax.__version__, "numpy": np.__version__},
           "setup": {"data_sets": n, "generator": "rotorjax.identify._make_data.runup_dataset(seed)",
                     "run_up": "20 -> 400 rad/s in 20 s, 1 kHz, 1 % noise (the shipped run-up's settings)",
                     "per_seed": "rotor angle at start (tacho timing) and sensor noise drawn anew; the noise-free "
                                 "response simulated once (diffrax) for D and iD and combined",
                     "fit": list(NAMES) + ["unbalances"], "truth": dict(zip(NAMES, truth.tolist())),
                     "start": {"k1": 1.5e5, "k2": 3.75e5, "c1": 100.0, "c2": 266.0},
                     "methods": {"old": "steady model, classical covariance, unweighted angle fit (as before)",
                                 "steady_hac": "steady model, Newey-West (HAC) covariance, unweighted angle fit",
                                 "runup_noref": "run-up model, phase reference taken as exact, HAC",
                                 "new": "run-up model, phase reference fitted jointly, HAC (identify(scene, track, "
                                        "tracking=order_track(..., full=True)))"}},
           "binomial_band_95": list(band), "results": results,
           "times": {"clean_simulations_s": t_clean, "monte_carlo_loop_s": t_loop, "per_method": fit_times}}
    print(f"{n} data sets; coverage band for 95 % intervals: [{band[0]:.3f}, {band[1]:.3f}]")
    for m in METHODS:
        row = "  ".join(f"{k} {results[m][k]['coverage']:.3f} ({results[m][k]['bias_pct']:+.3f} %, spread "
                        f"{results[m][k]['spread_pct'] or 0:.3f}, sd {results[m][k]['mean_sd_pct']:.3f})"
                        for k in NAMES)
        print(f"{m:12s} {row}")
    if args.smoke and not args.out:  # the figure is drawn (to a temporary file), nothing kept
        import tempfile

        with tempfile.TemporaryDirectory() as tmp:
            plot(out, os.path.join(tmp, "identification_coverage.png"))
        print("smoke run: nothing written")
        return
    if args.out:
        os.makedirs(args.out, exist_ok=True)
        path = os.path.join(args.out, "identification_coverage.json")
        with open(path, "w") as f:
            json.dump(out, f, indent=2)
        print(f"wrote {path}")
        png = os.path.join(args.out, "identification_coverage.png")
    else:
        path = write_results("identification_coverage", out)
        png = os.path.splitext(path)[0] + ".png"
    plot(out, png)
    print(f"wrote {png}")


def plot(out, path):
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    res, band, n = out["results"], out["binomial_band_95"], out["setup"]["data_sets"]
    methods = list(res)
    x = np.arange(len(NAMES))
    w = 0.8 / len(methods)
    fig, (a1, a2) = plt.subplots(1, 2, figsize=(11, 4))
    a1.axhspan(band[0], band[1], color="0.85", label=f"binomial 95 % band ({n} data sets)")
    a1.axhline(0.95, color="0.4", lw=0.8)
    for j, m in enumerate(methods):
        a1.bar(x + (j - (len(methods) - 1) / 2) * w, [res[m][k]["coverage"] for k in NAMES], w, label=m)
        a2.errorbar(x + (j - (len(methods) - 1) / 2) * w, [res[m][k]["bias_pct"] for k in NAMES],
                    yerr=[res[m][k]["spread_pct"] or 0 for k in NAMES], fmt="o", capsize=3, label=m)
    a1.set_xticks(x, NAMES)
    a1.set_ylim(0, 1.05)
    a1.set_ylabel("coverage of the 95 % intervals")
    handles, labels = a1.get_legend_handles_labels()
    a2.axhline(0, color="0.4", lw=0.8)
    a2.set_xticks(x, NAMES)
    a2.set_ylabel("relative error (%): mean, bars +- spread")
    fig.suptitle("identification from a 20 s run-up (1 kHz, 1 % noise): old vs new intervals")
    fig.legend(handles, labels, loc="lower center", ncol=len(labels), fontsize=8)
    fig.tight_layout(rect=(0, 0.08, 1, 1))
    fig.savefig(path, dpi=100)
    plt.close(fig)


if __name__ == "__main__":
    main()
