"""The covariance of fitted parameters, for every identification (`identify`): at
the optimum, with `J` the Jacobian of the scaled residuals `r`,

- `classical`: `s^2 (J^T J)^-1`, `s^2` the residual variance: right for
  independent residuals of one variance (a steady sweep);
- `sandwich`: `(J^T J)^-1 (sum_b g_b g_b^T) (J^T J)^-1` with `g_b = J_b^T r_b` the
  score of speed point `b` (its Re/Im residuals of all sensors together):
  unequal variances;
- `hac` (Newey-West): the sandwich with the lagged products of neighbouring
  speed points, Bartlett weights over `L = floor(4 (n / 100)^(2/9))` lags: serial
  correlation along a sweep;

each times `n / (n - p)`. Residuals with structure (lag-1 autocorrelation or a
runs test on their signs, per sensor and Re/Im: a model that misses a systematic
effect), and classical intervals that a sandwich finds too narrow, are warnings.
"""

import numpy as np

COVARIANCES = ("auto", "classical", "sandwich", "hac")


def newey_west_lags(n):
    """The Newey-West (1994) rule of thumb, `floor(4 (n / 100)^(2/9))`."""
    return int(np.floor(4 * (n / 100.0) ** (2.0 / 9.0)))


def theta_covariance(J, res, method="classical", n_points=None, lags=None, J_prior=None):
    """The covariance of the fitted `theta` from the Jacobian `J` and the residuals
    `res` of a least-squares fit (`(n_res, p)` and `(n_res,)`, stacked as `identify`
    stacks them: all real parts, then all imaginary parts, each `(n_points,
    n_sensors)` row-major). `method`: `"classical"` (`s^2 (J^T J)^+`), `"sandwich"`
    (per speed point) or `"hac"` (Newey-West over neighbouring speed points, `lags`
    default `newey_west_lags`); see the module docstring.

    `J_prior`: the Jacobian of prior rows (whitened: unit variance, independent of
    the data), which enter the bread `(J^T J + J_p^T J_p)^+` and, as their own
    variance `J_p^T J_p`, the meat; their parameters are not counted in the degrees
    of freedom (each comes with its prior row)."""
    J, res = np.asarray(J, dtype=float), np.asarray(res, dtype=float)
    n_res, p = J.shape
    Jp = np.zeros((0, p)) if J_prior is None else np.asarray(J_prior, dtype=float)
    dof = max(n_res - (p - Jp.shape[0]), 1)
    bread = np.linalg.pinv(J.T @ J + Jp.T @ Jp)
    if method == "classical":
        return float(res @ res) / dof * bread
    if method not in ("sandwich", "hac"):
        raise ValueError(f"covariance method must be classical, sandwich or hac, got {method!r}")
    n = int(n_points if n_points is not None else n_res // 4)
    # the score of each speed point: its Re and Im residuals of all sensors together
    g = (J * res[:, None]).reshape(2, n, -1, p).sum(axis=(0, 2))         # (n, p)
    meat = g.T @ g
    if method == "hac":
        L = newey_west_lags(n) if lags is None else int(lags)
        for lag in range(1, min(L, n - 1) + 1):
            G = g[lag:].T @ g[:-lag]
            meat += (1 - lag / (L + 1)) * (G + G.T)
    return bread @ (n_res / dof * meat + Jp.T @ Jp) @ bread


def residual_structure(res):
    """Per channel (sensor and Re/Im) of residuals `res[part, point, sensor]` in
    speed order: the lag-1 autocorrelation `rho1`, the runs test on the signs
    (`runs_z`: (runs - expected) / sd; strongly negative: long runs of one sign),
    and the effective number of independent points `n_eff = n (1 - rho1) / (1 + rho1)`
    (an AR(1) reading)."""
    res = np.asarray(res, dtype=float)
    out = {}
    for part, pname in enumerate(("Re", "Im")):
        for m in range(res.shape[2]):
            e = res[part, :, m] - res[part, :, m].mean()
            n = e.size
            rho1 = float(e[1:] @ e[:-1] / max(e @ e, 1e-300)) if n > 2 else 0.0
            sgn = np.sign(e[e != 0])
            n_pos, n_neg = int(np.sum(sgn > 0)), int(np.sum(sgn < 0))
            nn = n_pos + n_neg
            if n_pos and n_neg and nn > 2:
                runs = 1 + int(np.sum(sgn[1:] != sgn[:-1]))
                mu = 2.0 * n_pos * n_neg / nn + 1
                var = 2.0 * n_pos * n_neg * (2.0 * n_pos * n_neg - nn) / (nn**2 * (nn - 1))
                z = float((runs - mu) / np.sqrt(max(var, 1e-300)))
            else:
                z = 0.0
            r1 = min(max(rho1, -0.999), 0.999)
            out[f"x{m + 1} {pname}"] = {"n": n, "rho1": rho1, "runs_z": z,
                                        "n_eff": float(n * (1 - r1) / (1 + r1))}
    return out


#: residuals show structure when a channel's lag-1 autocorrelation exceeds
#: `max(RHO1_LIMIT, 3 / sqrt(n))` or its runs test has |z| > RUNS_Z_LIMIT (p < 0.001)
RHO1_LIMIT = 0.2
RUNS_Z_LIMIT = 3.29
#: with the classical covariance, warn when a sandwich standard deviation exceeds the classical one this much
SANDWICH_RATIO_LIMIT = 1.5


def structure_warnings(structure, method, model):
    bad = {k: v for k, v in structure.items()
           if v["rho1"] > max(RHO1_LIMIT, 3 / np.sqrt(max(v["n"], 1))) or abs(v["runs_z"]) > RUNS_Z_LIMIT}
    if not bad:
        return []
    desc = "; ".join(f"{k}: lag-1 autocorrelation {v['rho1']:.2f}, runs test z {v['runs_z']:.1f}, "
                     f"about {v['n_eff']:.0f} of {v['n']} points independent" for k, v in bad.items())
    if method == "classical":
        advice = ("the classical intervals assume independent residuals and are too narrow: use "
                  "covariance='hac'" + ("" if model == "runup" else ", and for a run-up the run-up model "
                                        "(tracking=order_track(..., full=True))"))
    else:
        advice = (f"the {method} intervals allow for correlated residuals, but structure means the model misses "
                  "a systematic effect that also biases the estimates: coverage cannot be trusted")
    return [f"the residuals show structure ({desc}): {advice}"]


def variance_warnings(J, res, cov, names, n_points):
    """With the classical covariance `cov`: a warning when the sandwich standard
    deviation of a parameter (`names`: the first columns of `J`) exceeds the
    classical one `SANDWICH_RATIO_LIMIT` times: unequal residual variances make
    `s^2 (J^T J)^-1` too narrow where the noisy points weigh most."""
    if n_points <= 2 * J.shape[1] or not names:
        return []
    p = len(names)
    robust = theta_covariance(J, res, "sandwich", n_points=n_points)[:p, :p]
    ratio = np.sqrt(np.maximum(np.diag(robust), 0.0) / np.maximum(np.diag(cov)[:p], 1e-300))
    if np.max(ratio) <= SANDWICH_RATIO_LIMIT:
        return []
    k = names[int(np.argmax(ratio))]
    return [f"the residuals' variance is not uniform: the sandwich standard deviation of {k} is "
            f"{np.max(ratio):.1f} times the classical one, so the classical intervals are too "
            "narrow: give sigma per point or use covariance='sandwich'"]
