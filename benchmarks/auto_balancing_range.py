"""The auto-balancing range of model 001 (anisotropic-abb) maximised over the supports'
damping: `rotorjax.design` against scipy's L-BFGS-B with finite-difference gradients
on the same objective.

The case: `anisotropic-abb` at its published values (Filimonikhina et al. 2017, Table
1), the main motion's Floquet margin over the speed n in 0.3..10 (stable in 1.014..5.050
and above 8.322: a stable range of 5.713); varied: `mu_xi` and `mu_eta` in [0.05, 1]
(searched in their logarithms); the objective `stable-range`, maximised, from the
published values. Each evaluation follows the three thresholds (secant steps on the
Floquet margin, every step an integration of the variational equations over a period).

- rotorjax: `optimize_rotor(problem, n_starts=1)`, its first call (which compiles the
  search's program) and a second (the program cached), and the fresh rescan of the
  optimum that the command runs.
- the peer: `scipy.optimize.minimize(method="L-BFGS-B")` in the same scaled variables,
  bounds [0, 1], the same start, on the same objective compiled once with `jax.jit`
  (its first call timed apart), gradients by scipy's finite differences (the
  strongest way a user without autodiff of the Floquet thresholds has).

Times, objectives, evaluations and the ratio are written to
`results/auto_balancing_range.json`. `--smoke`: model 000 on a circular race
(`elliptic-abb`, rho1 = rho2, a stationary regime: cheap), one outer iteration,
nothing written.
"""

import argparse
import os
import sys
import time

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from _common import CpuWatch, machine, write_results  # noqa: E402


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--smoke", action="store_true", help="tiny sizes, nothing written")
    args = ap.parse_args()
    import jax

    jax.config.update("jax_enable_x64", True)
    import jax.numpy as jnp
    import scipy.optimize as so

    from rotorjax import presets
    from rotorjax.design import optimize_rotor, preset_problem
    from rotorjax.design._optimize import _ends, _to_u, _to_x

    smoke = args.smoke
    watch = CpuWatch()
    if smoke:
        preset = presets.get("elliptic-abb")
        params, vary, span = preset.params({"rho1": 1.2}), {"delta_n": (0.05, 1.0)}, (0.5, 6.0)
    else:
        preset = presets.get("anisotropic-abb")
        params, vary, span = preset.params(), {"mu_xi": (0.05, 1.0), "mu_eta": (0.05, 1.0)}, (0.3, 10.0)
    t0 = time.perf_counter()
    p = preset_problem(preset, params, vary, speed_range=span, n_scan=40)
    setup = time.perf_counter() - t0
    max_outer = 1 if smoke else 30

    t0 = time.perf_counter()
    d = optimize_rotor(p, n_starts=1, max_outer=max_outer)
    first = time.perf_counter() - t0
    second = first
    if not smoke:                                   # the search again, compiled: what a user's next call costs
        t0 = time.perf_counter()
        d = optimize_rotor(p, n_starts=1, max_outer=max_outer)
        second = time.perf_counter() - t0
    o = d.optimum

    a, b = _ends(p.lo, p.hi, p.log)
    scale = p.scales["stable-range"]
    objective = jax.jit(lambda u: p.fn(_to_x(u, a, b, p.log))[0])
    u0 = _to_u(np.clip(p.nominal, p.lo, p.hi), a, b, p.log)
    t0 = time.perf_counter()
    objective(jnp.asarray(u0)).block_until_ready()
    peer_compile = time.perf_counter() - t0
    calls = [0]

    def fun(u):
        calls[0] += 1
        v = float(objective(jnp.asarray(u)))
        return v if np.isfinite(v) else 1e3       # a lost threshold: a wall the search steps back from
    t0 = time.perf_counter()
    r = so.minimize(fun, u0, method="L-BFGS-B", bounds=[(0.0, 1.0)] * len(u0),
                    options={"maxiter": 2} if smoke else {})
    peer = time.perf_counter() - t0
    peer_value = -float(r.fun) * scale
    ours = d.quantities_after["stable-range"]
    out = {
        "case": {"preset": preset.name, "vary": {k: list(v) for k, v in vary.items()}, "range": list(span),
                 "thresholds_at_start": p.settings["thresholds"]},
        "setup_s": setup,
        "rotorjax": {"first_call_s": first, "seconds": second, "evaluations": int(o.evaluations),
                     "converged": bool(o.converged), "before": d.quantities_before["stable-range"], "after": ours,
                     "x": d.after, "rescan": d.rescan},
        "lbfgsb_fd": {"seconds": peer, "compile_s": peer_compile, "evaluations": calls[0], "after": peer_value,
                      "x": dict(zip(p.names, map(float, np.asarray(_to_x(jnp.asarray(r.x), a, b, p.log))))),
                      "message": str(r.message)},
        "ratio_lbfgsb_fd_over_rotorjax": peer / second,
        "machine": machine(), "cpu": watch.report(),
    }
    print(f"{preset.name}: stable range {d.quantities_before['stable-range']:.6g} -> rotorjax {ours:.6g} "
          f"({o.evaluations} evaluations, {second:.3g} s; first call {first:.3g} s), L-BFGS-B with differences "
          f"{peer_value:.6g} ({calls[0]} evaluations, {peer:.3g} s): {peer / second:.2g}x")
    if smoke:
        print("smoke run: nothing written")
        return
    write_results("auto_balancing_range", out)


if __name__ == "__main__":
    main()
