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


def _loop(d):
    """The compiled loop for states of size `d` (the weights' count is static in the
    right-hand side), built once."""
    if d in _LOOPS:
        return _LOOPS[d]
    import numbalsoda

    n_w = (d - 4) // 2
    sig = types.void(types.double, types.CPointer(types.double), types.CPointer(types.double),
                     types.CPointer(types.double))

    @cfunc(sig)
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
    loop(speeds[:2], y0, 0.01, pars, 1e-6, 1e-9, 1000)  # compiled
    t0 = time.perf_counter()
    out, ok = loop(speeds, y0, float(t_end), pars, float(rtol), float(atol), MAX_STEPS)
    return out, time.perf_counter() - t0, bool(np.all(ok))
