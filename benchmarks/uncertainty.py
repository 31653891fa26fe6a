"""Monte Carlo of a rotor file's critical speeds and log decrements under bearing
scatter: `rotorjax.uncertainty` against a numpy/scipy loop doing the same work.

The case (issue 34): `ross_compare.toml` (ROSS's example rotor) with its bearings
given damping (`cxx = cyy = 500 N s/m`) and 8 random bearing coefficients (kxx,
kyy, cxx, cyy of both, lognormal, 10 % sd); outputs: the forward 1x critical speeds
below 1000 rad/s and the log decrements of the first three modes at 500 rad/s.

- rotorjax: `rotor_quantities` + `propagate` (vmapped through `rotorjax.sweep`:
  each sample's rotor set through the parameters' leaves, each critical speed the
  fixed point `Omega = omega_k(Omega)` from the nominal one, 6 iterations and a
  residual check, eigenvalues only).
- the peer: the strongest plain loop a user could write for the same numbers: the
  full matrices assembled once by rotorjax and the bearings' coefficients added to
  them in numpy (they enter affinely: one unit matrix per coefficient), then per
  sample the same fixed points with `scipy.linalg.eigvals` on the first-order
  matrix. Its outputs equal rotorjax's to 1e-8 (checked on the first samples).

Both timed after a first call (rotorjax's compiles); per-sample times and their
ratio. ROSS's `ST_Rotor` is not run here yet (issue 34).
"""

import argparse
import json
import os
import sys
import time

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from _common import machine, timed_first, write_results  # noqa: E402

COEFS = ("kxx", "kyy", "cxx", "cyy")
SETS = {"bearing0.cxx": 500.0, "bearing0.cyy": 500.0, "bearing1.cxx": 500.0, "bearing1.cyy": 500.0}
HI, SPEED, N_MODES, SCATTER = 1000.0, 500.0, 3, 0.1


class NumpyPeer:
    """The peer (see the module): affine bearing matrices in numpy, scipy eigenvalues."""

    def __init__(self, file, names, nominal, critical):
        import jax.numpy as jnp

        from rotorjax.models._parameters import parts_of, with_values

        parts = parts_of(file.scene)
        paths = [file.path(n) for n in names]

        def mats(values):
            lm = with_values(parts, paths, jnp.asarray(values)).rotor.linear_matrices(1.0)
            return [np.asarray(a) for a in (lm.M, lm.C, lm.G, lm.K)]

        self.M, self.C0, self.G1, self.K0 = mats(nominal)
        self.dC, self.dK = [], []
        for i in range(len(names)):
            v = np.array(nominal, dtype=float)
            v[i] += 1.0
            _, C, _, K = mats(v)
            self.dC.append(C - self.C0)
            self.dK.append(K - self.K0)
        self.dC, self.dK = np.stack(self.dC), np.stack(self.dK)
        self.nominal, self.critical = np.asarray(nominal, dtype=float), critical
        self.Minv = np.linalg.inv(self.M)

    def _freqs(self, C, K, speed):
        import scipy.linalg

        n = self.M.shape[0]
        A = np.block([[np.zeros((n, n)), np.eye(n)], [-self.Minv @ K, -self.Minv @ (C + speed * self.G1)]])
        lam = scipy.linalg.eigvals(A, check_finite=False)
        lam = lam[np.imag(lam) > 0]
        return lam[np.argsort(np.imag(lam))]

    def __call__(self, values):
        d = np.asarray(values, dtype=float) - self.nominal
        C = self.C0 + np.tensordot(d, self.dC, 1)
        K = self.K0 + np.tensordot(d, self.dK, 1)
        out = []
        for W, k in self.critical:
            w = W
            for _ in range(6):
                w = float(np.imag(self._freqs(C, K, w)[k]))
            res = float(np.imag(self._freqs(C, K, w)[k])) - w
            out.append(w if abs(res) <= 1e-8 * abs(w) else np.nan)
        lam = self._freqs(C, K, SPEED)[:N_MODES]
        out.extend(-2 * np.pi * np.real(lam) / np.imag(lam))
        return np.array(out)


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--smoke", action="store_true", help="tiny sizes, nothing written")
    args = ap.parse_args()
    import jax

    from rotorjax.io import read_rotor_file, shipped_rotor
    from rotorjax.uncertainty import LogNormal, propagate, rotor_quantities

    n_rj, n_peer, repeats = (16, 4, 0) if args.smoke else (1024, 128, 1)
    file = read_rotor_file(str(shipped_rotor("ross_compare")), SETS)
    names = [f"bearing{b}.{c}" for b in (0, 1) for c in COEFS]
    nominal = [float(file.entries[n].value) if n in file.entries else SETS[n] for n in names]
    inputs = {n: LogNormal(v, SCATTER * v) for n, v in zip(names, nominal)}
    t0 = time.perf_counter()
    q = rotor_quantities(file, inputs, hi=HI, speed=SPEED, n_modes=N_MODES)
    setup = time.perf_counter() - t0
    t_rj, first, res = timed_first(lambda: propagate(q.fn, inputs, samples=n_rj, seed=0, names=q.outputs), repeats)
    peer = NumpyPeer(file, names, q.nominal, q.critical)
    X = res.input_samples
    parity = max(float(np.max(np.abs(peer(X[i]) / res.samples[i] - 1))) for i in range(min(4, n_rj)))
    if parity > 1e-7:
        raise SystemExit(f"the peer does not reproduce rotorjax's outputs (max relative difference {parity:.1e})")
    t_peer, _, _ = timed_first(lambda: [peer(X[i]) for i in range(n_peer)], 0 if args.smoke else 1)
    per_rj, per_peer = t_rj / n_rj, t_peer / n_peer
    out = {"benchmark": "Monte Carlo of ross_compare.toml's critical speeds and log decrements, 8 bearing "
                        "coefficients lognormal (10 %)",
           "machine": machine(), "jax": jax.__version__, "outputs": list(q.outputs),
           "nominal_critical_speeds": [w for w, _ in q.critical], "samples": n_rj, "peer_samples": n_peer,
           "setup_s": setup, "rotorjax_first_call_s": first, "rotorjax_s": t_rj,
           "rotorjax_per_sample_ms": 1e3 * per_rj, "peer_per_sample_ms": 1e3 * per_peer,
           "ratio_peer_over_rotorjax": per_peer / per_rj, "parity_max_rel": parity,
           "mean": dict(zip(q.outputs, res.mean.tolist())), "std": dict(zip(q.outputs, res.std.tolist())),
           "first_order_std": dict(zip(q.outputs, res.fosm_std.tolist())),
           "note": "peer: numpy affine bearing matrices + scipy.linalg.eigvals per fixed-point iteration, in a "
                   "Python loop; ROSS ST_Rotor not run yet"}
    print(json.dumps({k: v for k, v in out.items() if k not in ("machine",)}, indent=1))
    if args.smoke:
        print("smoke run: nothing written")
        return
    write_results("uncertainty", out)


if __name__ == "__main__":
    main()
