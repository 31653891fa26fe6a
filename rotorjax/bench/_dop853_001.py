"""The compiled adaptive peer of model 001: Hairer's DOP853 in C (the `numbalsoda`
package) with a numba `cfunc` right-hand side (`_numba001._rhs_nb`, the structured
2x2 solve), the speeds in a numba `prange` loop: the forty lines a Python user
would write for a fast sweep. Needs numba and numbalsoda (`pip install
rotorjax[bench]`): import this module only when `available()`."""

import importlib.util
import time

import numba
import numpy as np
from numba import carray, cfunc, types

from ._numba001 import _KEYS, _rhs_nb


def available() -> bool:
    return importlib.util.find_spec("numba") is not None and importlib.util.find_spec("numbalsoda") is not None


#: the step budget per speed, rotorjax's in the benchmarks (numbalsoda's default, 10 000,
#: stops DOP853 at rtol 1e-11 on model 001's slipping-weight speeds)
MAX_STEPS = 1_000_000

_LOOPS = {}

#: numbalsoda's right-hand side: `rhs(t, u, du, data)`, pointers to doubles
_SIGNATURE = types.void(types.double, types.CPointer(types.double), types.CPointer(types.double),
                        types.CPointer(types.double))


def _loop(d):
    """The compiled loop for states of size `d` (the weights' count is static in the
    right-hand side), built once."""
    if d in _LOOPS:
        return _LOOPS[d]
    import numbalsoda

    n_w = (d - 4) // 2
    @cfunc(_SIGNATURE)
    def rhs(t, u_, du_, p_):
        u = carray(u_, (d,))
        du = carray(du_, (d,))
        p = carray(p_, (8,))
        _rhs_nb(t, u, du, p[0], p[1], p[2], p[3], p[4], p[5], p[6], p[7], n_w)

    address = rhs.address

    @numba.njit(parallel=True)
    def loop(speeds, y0, t_end, pars, rtol, atol, max_steps):
        out = np.empty((speeds.size, y0.size))
        ok = np.empty(speeds.size, np.bool_)
        span = np.array([0.0, t_end])
        for i in numba.prange(speeds.size):
            p = np.empty(8)
            p[0] = speeds[i]
            p[1:] = pars
            u, success = numbalsoda.dop853(address, y0.copy(), span, data=p, rtol=rtol, atol=atol,
                                           mxstep=max_steps)
            out[i] = u[-1]
            ok[i] = success
        return out, ok

    loop(np.ones(2), np.zeros(d), 0.01, np.ones(len(_KEYS)), 1e-6, 1e-9, 1000)  # compiled once, here
    _LOOPS[d] = (rhs, loop)  # the cfunc kept alive with its loop
    return _LOOPS[d]


def dop853_loop(speeds, y0, t_end, p, rtol, atol, threads=1):
    """C DOP853 at each speed (prange over `threads` threads) ->
    (final_states, wall_s excluding compilation, all succeeded)."""
    speeds = np.ascontiguousarray(speeds, dtype=np.float64)
    y0 = np.ascontiguousarray(y0, dtype=np.float64)
    pars = np.array([float(p[k]) for k in _KEYS], dtype=np.float64)
    _, loop = _loop(y0.size)
    numba.set_num_threads(int(threads))
    t0 = time.perf_counter()
    out, ok = loop(speeds, y0, float(t_end), pars, float(rtol), float(atol), MAX_STEPS)
    return out, time.perf_counter() - t0, bool(np.all(ok))


# ---- the Floquet map's peer: the same C DOP853 over the variational equations ----

#: the complex step of the peer's Jacobian (exact to rounding for an analytic right-hand side)
_H = 1e-30

_FLOQUET_LOOPS = {}


def _floquet_loop(d):
    """The compiled Floquet loop for states of size `d`: DOP853 over the augmented
    state `(y, Phi row by row, int tr J)` (`d (d + 1) + 1`), the Jacobian by complex
    step (`d` complex evaluations of `_rhs_nb`, as the scipy peer takes it), points in
    a `prange` loop; built once."""
    if d in _FLOQUET_LOOPS:
        return _FLOQUET_LOOPS[d]
    import numbalsoda

    n_w = (d - 4) // 2
    size = d * (d + 1) + 1
    @cfunc(_SIGNATURE)
    def rhs(t, u_, du_, p_):
        u = carray(u_, (size,))
        du = carray(du_, (size,))
        p = carray(p_, (8,))
        _rhs_nb(t, u[:d], du[:d], p[0], p[1], p[2], p[3], p[4], p[5], p[6], p[7], n_w)
        yc = np.empty(d, np.complex128)
        fc = np.empty(d, np.complex128)
        jac = np.empty((d, d))
        trace = 0.0
        for k in range(d):
            for i in range(d):
                yc[i] = u[i]
            yc[k] += 1j * _H
            _rhs_nb(t, yc, fc, p[0], p[1], p[2], p[3], p[4], p[5], p[6], p[7], n_w)
            for i in range(d):
                jac[i, k] = fc[i].imag / _H
            trace += jac[k, k]
        for i in range(d):  # (J Phi)[i, j], Phi row by row after the state
            for j in range(d):
                acc = 0.0
                for k in range(d):
                    acc += jac[i, k] * u[d + k * d + j]
                du[d + i * d + j] = acc
        du[size - 1] = trace

    address = rhs.address

    @numba.njit(parallel=True)
    def loop(pars, y0, periods, rtol, atol, max_steps):
        m = pars.shape[0]
        mono = np.empty((m, d, d))
        ok = np.empty(m, np.bool_)
        for i in numba.prange(m):
            u0 = np.zeros(size)
            u0[:d] = y0
            for k in range(d):
                u0[d + k * d + k] = 1.0
            span = np.array([0.0, periods[i]])
            u, success = numbalsoda.dop853(address, u0, span, data=pars[i].copy(), rtol=rtol, atol=atol,
                                           mxstep=max_steps)
            mono[i] = u[-1, d:d + d * d].reshape(d, d)
            ok[i] = success
        return mono, ok

    loop(np.ones((2, 8)), np.zeros(d), np.full(2, 1e-3), 1e-6, 1e-9, 1000)  # compiled once, here
    _FLOQUET_LOOPS[d] = (rhs, loop)
    return _FLOQUET_LOOPS[d]


def floquet_loop(speeds, mu_w, y0, p, rtol, atol, threads=1):
    """The largest Floquet exponent of the motion through `y0` at each (speed, `mu_w`)
    pair (period `2 pi / speed`): C DOP853 over the variational equations, `prange`
    over `threads` threads, the multipliers by numpy's `eigvals` ->
    (margins, wall_s excluding compilation, all succeeded)."""
    speeds = np.ascontiguousarray(speeds, dtype=np.float64)
    y0 = np.ascontiguousarray(y0, dtype=np.float64)
    mu_w = np.broadcast_to(np.asarray(mu_w, dtype=np.float64), speeds.shape)
    pars = np.array([[s, *(m if k == "mu_w" else float(p[k]) for k in _KEYS)] for s, m in zip(speeds, mu_w)])
    periods = 2 * np.pi / speeds
    _, loop = _floquet_loop(y0.size)
    numba.set_num_threads(int(threads))
    t0 = time.perf_counter()
    mono, ok = loop(pars, y0, periods, float(rtol), float(atol), MAX_STEPS)
    margins = np.max(np.log(np.abs(np.linalg.eigvals(mono))), axis=1) / periods
    return margins, time.perf_counter() - t0, bool(np.all(ok))
