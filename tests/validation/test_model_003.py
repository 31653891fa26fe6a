"""Model 003 (Kovachev): the modal shaft, the closed-form sums and eq. (17)."""

import jax
import jax.numpy as jnp
import numpy as np
import pytest

from rotorjax.analysis import modal003_natural_frequencies, modal003_response
from rotorjax.flexible import ModalShaft, closed_form_sums, exact_critical_speeds
from tests.helpers import central_difference

PUBLISHED = [0.705801, 7.276434, 21.484371]


def test_closed_form_critical_speeds_match_published():
    """Point-mass disk, m = 1, z0 = 0.5: 0.705801, 7.276434, 21.484371 (units of omega_1)."""
    roots = exact_critical_speeds(1.0, 0.5, 0.0, lo=0.1, hi=25.0)
    np.testing.assert_allclose(roots, PUBLISHED, atol=1e-6)


def test_modal_model_converges_to_closed_form_at_third_order():
    exact = np.array(exact_critical_speeds(1.0, 0.5, 0.0, lo=0.1, hi=25.0))
    errors = []
    for n in (10, 20, 40, 80):
        f, excited = modal003_natural_frequencies(ModalShaft(n, 1.0, 0.5))
        errors.append(np.asarray(f)[np.asarray(excited)][:3] - exact)
    errors = np.array(errors)
    assert np.all(errors > 0) and np.all(np.diff(errors, axis=0) < 0)  # from above, decreasing
    assert abs(errors[1, 0]) < 1e-5 and abs(errors[1, 1]) / exact[1] < 1e-4   # 20 modes
    assert abs(errors[1, 2]) / exact[2] < 1e-3
    order = np.log2(errors[-2] / errors[-1])
    np.testing.assert_allclose(order, 3.0, atol=0.05)


def test_closed_form_sums_are_the_limit_of_the_modal_sums():
    for d in (0.0, 0.3):
        for w in (0.5, 3.3, 10.7):
            s_modal = ModalShaft(20000, 1.0, 0.37, d=d).sums(w)
            s_exact = closed_form_sums(w, 0.37, d)
            np.testing.assert_allclose(complex(s_modal[0]), complex(s_exact[0]), rtol=1e-8)
            np.testing.assert_allclose(complex(s_modal[1]), complex(s_exact[1]), rtol=1e-7)
            # S22's tail is ~ 1/(2n)
            assert abs(complex(s_modal[2]) - complex(s_exact[2])) < 1e-3


def test_response_equals_a_direct_modal_solve():
    """The rank-2 (Woodbury) response of eqs. (10)-(13) against solving
    (diag(k^4 - w^2 + i d w) - w^2 (m a a^T + J b b^T)) W = m0 w^2 a directly."""
    shaft = ModalShaft(12, 0.8, 0.3, Jt=0.02, Jp=0.01, d=0.05, m0=0.01)
    a, b, k = (np.asarray(v) for v in shaft.mode_vectors())
    J = float(shaft.J)
    for w in (0.4, 2.0, 7.5):
        lhs = np.diag(k**4 - w**2 + 1j * 0.05 * w) - w**2 * (0.8 * np.outer(a, a) + J * np.outer(b, b))
        W = np.linalg.solve(lhs, 0.01 * w**2 * a)
        disk, tilt = modal003_response(shaft, w)
        np.testing.assert_allclose(complex(disk), a @ W, rtol=1e-10)
        np.testing.assert_allclose(complex(tilt), b @ W, rtol=1e-10)


def test_gradient_of_response_peak_wrt_disk_position():
    """d(peak disk amplitude near the first critical speed)/d(z0): the envelope
    theorem (the peak is a stationary point in w) against finite differences of the
    located peak."""
    def amp(w, z0):
        return jnp.abs(modal003_response(ModalShaft(20, 1.0, z0, d=0.05, m0=0.01), w)[0])

    def peak(z0):
        ws = np.linspace(0.4, 1.0, 601)
        w = float(ws[np.argmax(np.asarray(jax.vmap(lambda v: amp(v, z0))(jnp.asarray(ws))))])
        d1 = jax.grad(amp, argnums=0)
        d2 = jax.grad(d1, argnums=0)
        for _ in range(30):
            w -= float(d1(w, z0)) / float(d2(w, z0))
        return w, float(amp(w, z0))

    z0 = 0.4
    w_star, _ = peak(z0)
    g = float(jax.grad(amp, argnums=1)(w_star, z0))
    fd = central_difference(lambda z: peak(z)[1], z0, 1e-5)
    assert g == pytest.approx(fd, rel=1e-5)


@pytest.mark.parametrize("kw,match", [({"n_modes": 0}, "n_modes"), ({"z0": 1.2}, "z0"),
                                      ({"m": -1.0}, "m .* must be >= 0"), ({"d": -0.1}, "d .*must be >= 0")])
def test_bad_input(kw, match):
    args = dict(n_modes=5, m=1.0, z0=0.5)
    args.update(kw)
    with pytest.raises(ValueError, match=match):
        ModalShaft(**args)
