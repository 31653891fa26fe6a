"""Sine and cosine of float64 arguments at arithmetic speed: written in `jnp`
(argument reduction and polynomials), so XLA fuses and vectorises them across
lanes like the rest of a right-hand side, where its own `sin`/`cos` are scalar
library calls that cost 10-20x the arithmetic of a small model.

- Reduction: `x = k pi/2 + r`, `|r| <= pi/4`, `k = round(2x / pi)`, `r` by
  Cody-Waite with pi/2 in four parts of 26 significant bits (each `k * part`
  exact for `|k| < 2^27`, 104 bits of pi/2 in all): accurate for `|x| <=
  REDUCTION_LIMIT` (~2.1e8 rad: 10 000 rad/s for 5.8 hours). Beyond it the result
  is NaN, which a run reports as non-finite: a fallback to `jnp.sin`/`jnp.cos`
  would be computed for every lane under `vmap` (a select, not a branch) and
  cost what this saves.
- Kernels: fdlibm's minimax polynomials on `[-pi/4, pi/4]` (`__kernel_sin`,
  `__kernel_cos`), the quadrant from `k mod 4`.
- Derivatives by `custom_jvp` (`d sin = cos dx`, `d cos = -sin dx`, from the same
  pair), not through the polynomials; the second and higher through them.

Accuracy (`tests/test_sincos.py`, 1e7 arguments): within 1 ulp of numpy's (the
C library's) values for |x| <= 1e6, within 2 ulp up to the limit. Speed: 2.6 ns
per lane for the pair against 9.4 ns for `jnp.sin` and `jnp.cos` (4096 lanes, one
core); model 001's sweep (its fast path and `rotate` on it) ran 2.0x faster in
a probe (1000 speeds, rtol 1e-6 and 1e-9; `benchmarks/sweep_throughput.py` is
still to be re-run on it).
"""

import jax
import jax.numpy as jnp
import numpy as np

#: the largest |x| reduced here (|k| < 2^27); beyond it NaN
REDUCTION_LIMIT = float(2.0**27 * np.pi / 2 * 0.999)


def _split_pio2():
    """pi/2 as four doubles of 26 significant bits (from a 160-bit value)."""
    from fractions import Fraction

    # pi to 50 digits, exact rational
    pi = Fraction("3.14159265358979323846264338327950288419716939937510582097494459")
    rest, parts = pi / 2, []
    for _ in range(4):
        f = float(rest)
        m, e = np.frexp(f)
        part = float(np.ldexp(np.round(m * 2.0**26), int(e) - 26))
        parts.append(part)
        rest -= Fraction(part)
    return tuple(parts)


_P1, _P2, _P3, _P4 = _split_pio2()
_TWO_OVER_PI = 0.63661977236758134308

# fdlibm k_sin.c / k_cos.c
_S1, _S2, _S3 = -1.66666666666666324348e-01, 8.33333333332248946124e-03, -1.98412698298579493134e-04
_S4, _S5, _S6 = 2.75573137070700676789e-06, -2.50507602534068634195e-08, 1.58969099521155010221e-10
_C1, _C2, _C3 = 4.16666666666666019037e-02, -1.38888888888741095749e-03, 2.48015872894767294178e-05
_C4, _C5, _C6 = -2.75573143513906633035e-07, 2.08757232129817482790e-09, -1.13596475577881948265e-11


def _kernels(r):
    """`(sin r, cos r)` for `|r| <= pi/4`."""
    z = r * r
    v = z * r
    s = r + v * (_S1 + z * (_S2 + z * (_S3 + z * (_S4 + z * (_S5 + z * _S6)))))
    poly = z * z * (_C1 + z * (_C2 + z * (_C3 + z * (_C4 + z * (_C5 + z * _C6)))))
    hz = 0.5 * z
    w = 1.0 - hz
    c = w + (((1.0 - w) - hz) + poly)
    return s, c


def _reduced(x):
    k = jnp.round(x * _TWO_OVER_PI)
    r = (((x - k * _P1) - k * _P2) - k * _P3) - k * _P4
    s, c = _kernels(r)
    q = k.astype(jnp.int64) & 3
    sin = jnp.where(q == 0, s, jnp.where(q == 1, c, jnp.where(q == 2, -s, -c)))
    cos = jnp.where(q == 0, c, jnp.where(q == 1, -s, jnp.where(q == 2, -c, s)))
    return sin, cos


def _sincos(x):
    x = jnp.asarray(x, dtype=jnp.float64)
    s, c = _reduced(x)
    out = jnp.abs(x) > REDUCTION_LIMIT
    return jnp.where(out, jnp.nan, s), jnp.where(out, jnp.nan, c)


@jax.custom_jvp
def sincos(x):
    """`(sin x, cos x)` of a float64 array, elementwise (see the module)."""
    return _sincos(x)


@sincos.defjvp
def _sincos_jvp(primals, tangents):
    # the pair from the plain evaluation, not from `sincos`: a rule that calls its own function holds a new
    # derivative rule object at every trace, and a program holding one is never shared (`solve._lift`) -- every
    # Jacobian of a rotating model compiled anew. Derivatives past the first are the polynomials' (to ~1e-15).
    (x,), (dx,) = primals, tangents
    s, c = _sincos(x)
    return (s, c), (c * dx, -s * dx)


def sin(x):
    """`sin x` by `sincos`."""
    return sincos(x)[0]


def cos(x):
    """`cos x` by `sincos`."""
    return sincos(x)[1]
