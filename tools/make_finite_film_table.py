"""Generate `rotorjax/models/data/finite_film.npz`: the finite plain journal's film force
`Fhat(eps, delta; L/D)` from `finite_bearing_state` (240 x 16 mesh) on the interpolation
grid of `rotorjax.models._finite_film`, and the interpolant's coefficients.

Grid: 24 Chebyshev-Gauss-Lobatto nodes in `t = sqrt(1 - eps)` over `0 <= eps <= 0.98`
(dense near both ends), 64 equispaced `delta` in `[0, 2 pi)`, 7 Chebyshev-Gauss-Lobatto
nodes in `L/D` over `[0.25, 1]`: 10 752 solves, one line of `delta` per task (each
solve warm-started from its neighbour's cavitated set), over `--workers` processes.

    python tools/make_finite_film_table.py [--workers 2] [--out PATH]
"""

import argparse
import multiprocessing as mp
import pathlib
import time

import numpy as np

N_EPS, N_DELTA, N_RATIO = 24, 64, 7
EPS_MAX = 0.98
RATIO_RANGE = (0.25, 1.0)
N_THETA, N_Z = 240, 16
T_RANGE = (float(np.sqrt(1.0 - EPS_MAX)), 1.0)


def lobatto(n):
    """Chebyshev-Gauss-Lobatto nodes on [-1, 1], ascending."""
    return -np.cos(np.pi * np.arange(n) / (n - 1))


def grids():
    u = lobatto(N_EPS)
    t = T_RANGE[0] + (T_RANGE[1] - T_RANGE[0]) * (u + 1.0) / 2.0
    eps = np.clip(1.0 - t * t, 0.0, None)      # descending in eps (u ascending)
    v = lobatto(N_RATIO)
    ratio = RATIO_RANGE[0] + (RATIO_RANGE[1] - RATIO_RANGE[0]) * (v + 1.0) / 2.0
    delta = 2.0 * np.pi * np.arange(N_DELTA) / N_DELTA
    return u, eps, v, ratio, delta


def line(args):
    """Fhat along the delta grid at one (eps, L/D), warm-started along delta."""
    from rotorjax.models._journal_bearing import finite_bearing_state

    eps, ratio, delta = args
    out = np.empty((delta.size, 2))
    cav = None
    for j, d in enumerate(delta):
        out[j], _, cav = finite_bearing_state(eps, 0.0, vx=-np.sin(d) / 2.0, vy=(eps - np.cos(d)) / 2.0,
                                              ratio=ratio, n_theta=N_THETA, n_z=N_Z, cavitated=cav)
    return out


def coefficients(force, u, v, eps, ratio, delta):
    """The tensor-product coefficients (2, n_eps, n_ratio, n_delta) of the correction
    `C = Fhat / Fhat_short` (complex; real and imaginary parts first)."""
    import jax
    import jax.numpy as jnp

    import rotorjax  # noqa: F401  (float64)
    from rotorjax.models._finite_film import short_film_force

    ee, rr, dd = np.meshgrid(eps, ratio, delta, indexing="ij")
    short = np.asarray(jax.vmap(short_film_force)(jnp.asarray(ee.ravel()), jnp.asarray(dd.ravel()),
                                                  jnp.asarray(rr.ravel()))).reshape(ee.shape + (2,))
    corr = (force[..., 0] + 1j * force[..., 1]) / (short[..., 0] + 1j * short[..., 1])
    parts = np.stack([corr.real, corr.imag])                     # (2, e, r, d)
    # periodic interpolant in delta: 1, cos d, sin d, ..., cos (n/2) d
    x = np.fft.rfft(parts, axis=-1) / N_DELTA
    fc = np.empty(parts.shape)
    fc[..., 0] = x[..., 0].real
    fc[..., 1:-1:2] = 2.0 * x[..., 1:N_DELTA // 2].real
    fc[..., 2:-1:2] = -2.0 * x[..., 1:N_DELTA // 2].imag
    fc[..., -1] = x[..., N_DELTA // 2].real
    # Chebyshev in u (eps) and v (L/D): invert the Vandermonde matrices T_i(node_j)
    ve = np.cos(np.arange(N_EPS)[None, :] * np.arccos(np.clip(u, -1, 1))[:, None])
    vr = np.cos(np.arange(N_RATIO)[None, :] * np.arccos(np.clip(v, -1, 1))[:, None])
    fc = np.einsum("ie,cerd->cird", np.linalg.inv(ve), fc)
    fc = np.einsum("jr,cird->cijd", np.linalg.inv(vr), fc)
    return fc, corr


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--workers", type=int, default=2)
    ap.add_argument("--out", default=str(pathlib.Path(__file__).resolve().parents[1]
                                         / "rotorjax" / "models" / "data" / "finite_film.npz"))
    args = ap.parse_args(argv)
    u, eps, v, ratio, delta = grids()
    tasks = [(float(e), float(r), delta) for e in eps for r in ratio]
    start = time.perf_counter()
    # spawn: the workers must not inherit a forked (multithreaded) JAX
    with mp.get_context("spawn").Pool(args.workers) as pool:
        lines = pool.map(line, tasks, chunksize=1)
    seconds = time.perf_counter() - start
    force = np.array(lines).reshape(N_EPS, N_RATIO, N_DELTA, 2)
    coef, _ = coefficients(force, u, v, eps, ratio, delta)
    np.savez_compressed(args.out, coef=coef, force=force, eps=eps, ratio=ratio, delta=delta,
                        t_range=np.array(T_RANGE), ratio_range=np.array(RATIO_RANGE),
                        mesh=np.array([N_THETA, N_Z]), seconds=np.array(seconds))
    size = pathlib.Path(args.out).stat().st_size
    print(f"{len(tasks) * N_DELTA} solves in {seconds:.0f} s on {args.workers} workers; "
          f"wrote {args.out} ({size / 1024:.0f} KiB)")


if __name__ == "__main__":
    main()
