"""An undamped rotor (ROSS's example rotor as shipped, `ross_compare.toml`: no bearing
damping) conserves energy, so its eigenvalues lie on the imaginary axis. LAPACK
returns real parts of about 1e-13 of either sign there, which had been read as
physics: API 684 then asked an undamped critical speed for no separation margin (its
amplification factor negative), and the Monte Carlo of a stiffness's scatter called
about half the samples unstable (`P(log_dec_0 < 0) = 0.506`). `conservative` names
such a system from its matrices, and its real parts are exactly 0."""

import json

import jax
import jax.numpy as jnp
import numpy as np
import pytest

from rotorjax.analysis import (amplification_factor, api684_margins, conservative, damped_eigenvalues, log_decrement,
                               modes)
from rotorjax.analysis._linear import eigenvalues
from rotorjax.io import read_rotor_file, shipped_rotor
from rotorjax.models._parameters import parts_of
from rotorjax.uncertainty import rotor_quantities

PATH = str(shipped_rotor("ross_compare"))
SPEED = 300.0


@pytest.fixture(scope="module")
def file():
    return read_rotor_file(PATH)


def _matrices(overrides=None):
    rotor = parts_of(read_rotor_file(PATH, overrides).scene).rotor
    return rotor, rotor.linear_matrices(jnp.float64(SPEED))


def test_the_undamped_rotor_conserves_energy_and_its_eigenvalues_lie_on_the_axis():
    """The invariant, independently of any eigenvalue solver: with `P = diag(K, M)`
    (positive definite), `P A + (P A)^T = 0` for the first-order matrix `A` (the energy
    `q^T K q + q'^T M q'` is constant). The raw eigenvalues' real parts are rounding
    (below 1e-12 of the modulus), and those reported are exactly 0: log decrements and
    damping ratios +0."""
    rotor, m = _matrices()
    a = np.asarray(m.state_matrix())
    n = m.M.shape[0]
    p = np.block([[np.asarray(m.K), np.zeros((n, n))], [np.zeros((n, n)), np.asarray(m.M)]])
    pa = p @ a
    assert np.linalg.norm(pa + pa.T) <= 1e-12 * np.linalg.norm(pa)
    assert bool(conservative(m))
    raw = np.asarray(eigenvalues(a))
    assert np.all(np.abs(raw.real) <= 1e-12 * np.abs(raw)) and np.any(raw.real != 0)
    lam = np.asarray(damped_eigenvalues(rotor, SPEED, 6))
    assert np.all(lam.real == 0)
    np.testing.assert_allclose(lam.imag, np.sort(raw.imag[raw.imag > 0])[:6], rtol=1e-12)
    mo = modes(rotor, SPEED, 6)
    for values in (np.asarray(mo.log_dec), np.asarray(mo.damping_ratio), np.asarray(log_decrement(lam))):
        assert np.all(values == 0) and not np.any(np.signbit(values))


@pytest.mark.parametrize("change", ["damping", "cross-coupling", "soft"])
def test_damping_cross_coupling_or_an_unsupported_stiffness_is_not_conservative(change):
    """Not conservative, so nothing is set to 0: a bearing with 1e-3 N s/m of damping
    (every forward and backward mode then decays: real parts below 0), one with a
    cross-coupled stiffness `kxy = 1e4 N/m` (circulatory: `K` not symmetric), and a
    stiffness matrix made indefinite (a divergence instability can then have a real
    eigenvalue)."""
    if change == "soft":
        _, m = _matrices()
        m = m._replace(K=m.K - 2 * jnp.max(jnp.abs(m.K)) * jnp.eye(m.K.shape[0]))
        assert not bool(conservative(m))
        return
    rotor, m = _matrices({"bearing0.cxx": 1e-3} if change == "damping" else {"bearing0.kxy": 1e4})
    assert not bool(conservative(m))
    lam = np.asarray(damped_eigenvalues(rotor, SPEED, 6))
    if change == "damping":
        assert np.all(lam.real < 0)
    else:
        assert np.any(lam.real != 0)


def test_api_684_asks_an_undamped_critical_speed_for_the_whole_margin(file):
    """An undamped mode's amplification factor is infinite (so is an unstable one's:
    nothing damps it), so a critical speed below the operating range needs API 684's
    16 % (above it, 26 %): 96.3 rad/s under an operating range from 100 rad/s falls
    short. The report's JSON gives the infinite factor as null."""
    from rotorjax.cli._report import _json_row

    assert float(amplification_factor(jnp.complex128(0.0 + 96.0j))) == np.inf
    assert float(amplification_factor(jnp.complex128(0.5 + 96.0j))) == np.inf
    assert float(amplification_factor(jnp.complex128(-1.0 + 10.0j))) == pytest.approx(np.hypot(1.0, 10.0) / 2)
    rows = api684_margins(file.scene, 0.0, 1000.0, 100.0, 120.0)
    assert [r["af"] for r in rows] == [np.inf] * 3
    first = rows[0]
    assert first["speed"] == pytest.approx(96.2955, abs=1e-3) and first["below"]
    assert first["required"] == 16.0 and not first["meets"]
    assert [r["required"] for r in rows[1:]] == [26.0, 26.0]
    assert json.loads(json.dumps(_json_row(first), allow_nan=False))["af"] is None


def test_the_scatter_of_an_undamped_rotor_finds_no_unstable_sample(tmp_path, capsys):
    """`rotorjax uncertainty` of a bearing stiffness's 10 % scatter: every sample's log
    decrements are 0 (none below it: the probability of instability is 0, with its
    Wilson interval's upper end 3.84 / (n + 3.84)), reported as the same in every
    sample; the first-order derivative with respect to a damping coefficient at 0 is
    kept, equal to a forward difference."""
    from rotorjax.cli import main

    assert main(["uncertainty", PATH, "--dist", "bearing0.kxx=lognormal(1e6,1e5)", "--samples", "64", "--seed", "3",
                 "--range", "0", "1000", "--out", str(tmp_path)]) == 0
    text = capsys.readouterr().out
    out = json.loads((tmp_path / "uncertainty_ross_compare.json").read_text())
    for j in range(3):
        name = f"log_dec_{j}"
        stats = out["outputs"][name]
        assert stats["mean"] == 0 and stats["std"] == 0 and stats["quantiles"]["0.05"] == 0
        unstable = out["probability_unstable"][name]
        assert unstable["p"] == 0 and unstable["ci95"] == [0.0, pytest.approx(3.8415 / (64 + 3.8415), rel=1e-3)]
        assert f"{name}: mean 0 (+- 0), sd 0," in text and f"P({name} < 0) = 0, 95 % [0, 0.0566]" in text
    assert text.count("the same in every sample") == 3 and text.count("most from bearing0.kxx") == 3
    c = rotor_quantities(PATH, ["bearing0.cxx"], lo=0.0, hi=1000.0, n_modes=3)
    g = np.asarray(jax.jacfwd(c.fn)(jnp.array([0.0])))[3:, 0]
    h = 1e-3
    fd = (np.asarray(c.fn(jnp.array([h]))) - np.asarray(c.fn(jnp.array([0.0]))))[3:] / h
    assert np.all(g > 0)
    np.testing.assert_allclose(g, fd, rtol=1e-4)
