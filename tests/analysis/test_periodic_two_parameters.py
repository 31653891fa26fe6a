"""Periodic motions in two parameters on the forced Duffing oscillator
`x'' + C x' + W0^2 x + BETA x^3 = f cos(om t)` (forcing frequency and amplitude):

- the fold of the frequency response continued in `(om, f)` (`periodic_fold_curve`)
  is, with one harmonic, the closed form of the first-order balance: with
  `s = A^2`, `d = W0^2 - om^2`, `b = 3 BETA / 4`, the response
  `s [(d + b s)^2 + C^2 om^2] = f^2` folds where its derivative in `s` vanishes,
  `3 b^2 s^2 + 4 b d s + d^2 + C^2 om^2 = 0`, so `f(om)` in closed form;
- the fold's sensitivity `d om*/d f` by the implicit function theorem
  (`periodic_fold_gradient`) equals the closed form's slope and finite
  differences of refined folds;
- a grid of `(om, f)` solved as one compiled program (`balance_grid`: a sweep up
  in `om` per column, the columns vmapped) follows the upper branch up to its fold
  and then the lower one, as a slow run-up does: the closed form's largest
  amplitude below the fold, its smallest above."""

import jax.numpy as jnp
import numpy as np
import pytest

from rotorjax.analysis import balance_grid, periodic_branch, periodic_fold_curve, periodic_fold_gradient
from rotorjax.models import AbstractScene, ConstantSpeed

C, W0, BETA = 0.1, 1.0, 1.0
B = 0.75 * BETA


class Duffing(AbstractScene):
    speed: ConstantSpeed
    f: float

    def __init__(self, om, f):
        self.speed = ConstantSpeed(om)
        self.f = jnp.asarray(f, dtype=jnp.float64)

    @property
    def state_size(self):
        return 2

    def vector_field(self, t, y, args=None):
        x, v = y
        om = self.speed.constant
        return jnp.stack([v, self.f * jnp.cos(om * t) - C * v - W0**2 * x - BETA * x**3])

    def outputs(self, t, y):
        return {"x": y[0]}

    def describe(self):
        return "Duffing oscillator"


def fold_forcing(om):
    """The closed form: the forcing amplitudes at which the one-harmonic response
    folds at `om` (upper fold first), and the amplitudes there."""
    d = W0**2 - om**2
    disc = 16 * B * B * d * d - 12 * B * B * (d * d + C * C * om * om)
    s = (-4 * B * d + np.array([1.0, -1.0]) * np.sqrt(disc)) / (6 * B * B)
    return np.sqrt(s * ((d + B * s) ** 2 + C * C * om * om)), np.sqrt(s)


def amplitudes(om, f):
    """All amplitudes of the one-harmonic response at `(om, f)`."""
    d = W0**2 - om**2
    s = np.roots([B * B, 2 * d * B, d * d + C * C * om * om, -f * f])
    return np.sort(np.sqrt(s[(np.abs(s.imag) < 1e-12) & (s.real > 0)].real))


F0 = 0.2


@pytest.fixture(scope="module")
def branch():
    br, coefs = periodic_branch(lambda om: Duffing(om, F0), 1.0, jnp.zeros(2), (1.0, 2.0), harmonics=1)
    folds = sorted((e for e in br.events if e.kind == "fold"), key=lambda e: e.p)
    assert len(folds) == 2
    return folds, coefs.shape[1:]


def test_fold_curve_is_the_closed_form(branch):
    folds, shape = branch
    upper = folds[1]                                      # the jump down of a run-up
    curve = periodic_fold_curve(Duffing, (upper.p, F0), np.reshape(upper.u, shape), bounds=((1.0, 0.1), (2.5, 0.4)),
                                ds=0.02, ds_max=0.05, max_points=80, names=("om", "f"))
    om, f = curve.x[:, -2], curve.x[:, -1]
    assert len(om) > 10 and f.min() < 0.15 and f.max() > 0.35
    closed = np.array([fold_forcing(w)[0] for w in om])   # (upper, lower) fold forcing at each om
    err = np.min(np.abs(closed - f[:, None]), axis=1)
    assert np.max(err) < 1e-8


def test_fold_gradient_equals_the_closed_form_and_finite_differences(branch):
    folds, shape = branch
    for e in folds:
        d = periodic_fold_gradient(Duffing, (e.p, F0), np.reshape(e.u, shape))
        # the closed form's slope: f(om) along the fold, inverted
        h = 1e-6
        which = int(np.argmin(np.abs(fold_forcing(e.p)[0] - F0)))
        dfdom = (fold_forcing(e.p + h)[0][which] - fold_forcing(e.p - h)[0][which]) / (2 * h)
        assert abs(d - 1 / dfdom) < 1e-6 * max(1.0, abs(d))


def test_grid_sweeps_up_like_a_run_up():
    oms = np.linspace(1.0, 2.0, 41)
    fs = np.array([0.1, 0.2, 0.3])
    coefs, code, tres, amp = balance_grid(Duffing, oms, fs, jnp.zeros(2), harmonics=1, rows=(0, 1))
    assert coefs.shape == (3, 41, 3, 2) and np.all(np.asarray(code) == 0)
    for j, f in enumerate(fs):
        for i, om in enumerate(oms):
            a = amplitudes(om, f)
            x_amp = np.hypot(coefs[j, i, 1, 0], coefs[j, i, 2, 0])
            if len(a) == 1:
                assert abs(x_amp - a[0]) < 1e-8
            else:   # between the folds: still on the upper branch (the sweep has not jumped yet)
                assert abs(x_amp - a[-1]) < 1e-8
    # above the upper fold the motion is the lower one: the jump happened
    assert np.hypot(coefs[2, -1, 1, 0], coefs[2, -1, 2, 0]) < 0.5 * np.max(np.hypot(coefs[2, :, 1, 0],
                                                                                     coefs[2, :, 2, 0]))
