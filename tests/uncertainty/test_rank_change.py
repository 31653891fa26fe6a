"""The Monte Carlo's critical speeds on ROSS's example rotor (`ross_compare.toml`,
the benchmark's case: 8 bearing coefficients, 10 % lognormal): `fn`'s Newton steps on
the nominal eigenpair equal the secant path (`fallback`) wherever they converge, and
the samples at a close pair near the first critical speed (the followed mode
changed rank among the sorted frequencies, or converged slowly) are left NaN by `fn`
and filled by `propagate`'s fallback."""

import jax
import jax.numpy as jnp
import numpy as np
import pytest

from rotorjax.analysis import damped_frequencies
from rotorjax.io import read_rotor_file, shipped_rotor
from rotorjax.models import SpinMatrices
from rotorjax.models._parameters import parts_of, with_values
from rotorjax.uncertainty import LogNormal, draw, propagate, rotor_quantities

SETS = {f"bearing{b}.{c}": 500.0 for b in (0, 1) for c in ("cxx", "cyy")}
NAMES = [f"bearing{b}.{c}" for b in (0, 1) for c in ("kxx", "kyy", "cxx", "cyy")]


@pytest.fixture(scope="module")
def case():
    file = read_rotor_file(str(shipped_rotor("ross_compare")), SETS)
    nominal = [float(file.entries[n].value) if n in file.entries else SETS[n] for n in NAMES]
    inputs = {n: LogNormal(v, 0.1 * v) for n, v in zip(NAMES, nominal)}
    q = rotor_quantities(file, inputs, hi=1000.0, speed=500.0, n_modes=3)
    X = draw(inputs, 128, seed=0)
    newton = np.asarray(jax.jit(jax.vmap(q.fn))(jnp.asarray(X)))
    secant = np.asarray(jax.jit(jax.vmap(q.fallback))(jnp.asarray(X)))
    return file, inputs, q, X, newton, secant


def test_newton_equals_the_secant_path_where_it_converges(case):
    _, _, q, _, newton, secant = case
    ok = np.isfinite(newton)
    assert np.all(np.isfinite(secant)) and ok.mean() > 0.98
    np.testing.assert_allclose(newton[ok], secant[ok], rtol=1e-10)


def test_the_samples_newton_leaves_changed_rank_and_propagate_fills_them(case):
    """Each NaN of `fn` is at a close pair: the sample's rotor at the secant path's
    critical speed has another frequency within 5 % (the followed mode changed rank
    there, the `k`-th sorted frequency's fixed point being another branch's, or the
    pair slowed Newton down). `propagate` gives the secant path's values on every
    sample and counts them."""
    file, inputs, q, X, newton, secant = case
    bad = np.flatnonzero(~np.all(np.isfinite(newton), axis=1))
    assert bad.size >= 1
    parts = parts_of(file.scene)
    paths = [file.parameter_path(n, "--dist") for n in NAMES]
    for i in bad:
        rotor = SpinMatrices(*with_values(parts, paths, jnp.asarray(X[i])).rotor.reduced_matrices(0.0))
        for j, (W, k) in enumerate(q.critical):
            if np.isfinite(newton[i, j]):
                continue
            w = secant[i, j]
            freqs = np.asarray(damped_frequencies(rotor, w, k + 2))
            assert freqs[k] == pytest.approx(w, rel=1e-8)
            # the other member of the close pair is within 5 % (the ranks swapped between nominal and sample)
            assert min(abs(freqs[k - 1] - w), abs(freqs[k + 1] - w)) < 0.05 * w
    r = propagate(q.fn, inputs, samples=128, seed=0, names=q.outputs, fallback=q.fallback)
    assert r.retried == bad.size and r.n == 128
    np.testing.assert_allclose(r.samples, secant, rtol=1e-10)
