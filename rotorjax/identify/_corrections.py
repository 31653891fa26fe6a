"""Corrections from an influence matrix, for every scene: the exact solve (as many
measurements as planes, model 002's eq. 23), weighted least squares (Goodman's
method) and min-max (the smallest worst residual, a second-order cone program);
and a correction split onto the two nearest of a plane's holes.
"""

import numpy as np

from .._errors import InputError, NumericalError
from ..models._validate import as_numpy


def unbalance_from_vibration(K, X):
    """The unbalances that explain `X` (eq. 23 with square `K`; least squares otherwise)."""
    K = as_numpy("K", K, dtype=np.complex128, ndim=2)
    X = as_numpy("X", X, dtype=np.complex128)
    if K.shape[0] < 1 or K.shape[1] < 1 or X.shape[:1] != (K.shape[0],) or X.ndim > 2:
        raise InputError(f"K must be (n_measurements, n_planes) and X (n_measurements,) or "
                         f"(n_measurements, k), got K shape {K.shape}, X shape {X.shape}")
    if K.shape[0] == K.shape[1]:
        return np.linalg.solve(K, X)
    return np.linalg.lstsq(K, X, rcond=None)[0]


def least_squares_correction(K, X, weights=None):
    """Weighted least-squares correction for more sensors x speeds than planes:
    `W = -(K^H Q K)^-1 K^H Q X` with `Q = diag(weights)` (Goodman's method).
    `K`: `(n_measurements, n_planes)` stacked over speeds and sensors; `X`:
    `(n_measurements,)`. Minimises `sum Q |X + K W|^2`."""
    K = as_numpy("K", K, dtype=np.complex128, ndim=2)
    X = as_numpy("X", X, dtype=np.complex128)
    if K.shape[0] < 1 or K.shape[1] < 1 or X.shape != (K.shape[0],):
        raise InputError(f"K {K.shape} and X {X.shape}: K must be (measurements, planes), X (measurements,)")
    if weights is None:
        q = np.ones(K.shape[0])
    else:
        q = as_numpy("weights", weights, sign="nonnegative")
        if q.shape != (K.shape[0],):
            raise InputError(f"weights must be one non-negative number per measurement ({K.shape[0]}), "
                             f"got shape {q.shape}")
    if np.count_nonzero(q) < K.shape[1]:
        raise InputError(f"weights: {np.count_nonzero(q)} measurement(s) with a non-zero weight cannot "
                         f"determine {K.shape[1]} plane corrections")
    KhQ = K.conj().T * q[None, :]
    return -np.linalg.solve(KhQ @ K, KhQ @ X)


def _check_system(A, X0, weights):
    A = as_numpy("A (influence matrix)", A, dtype=np.complex128, ndim=2)
    X0 = as_numpy("X0 (baseline vibration)", X0, dtype=np.complex128, ndim=1)
    if A.shape[0] != X0.shape[0] or A.shape[1] < 1 or A.shape[0] < 1:
        raise InputError(f"A must be (measurements, planes) and X0 (measurements,), got A shape {A.shape}, "
                         f"X0 shape {X0.shape}")
    if weights is None:
        return A, X0, np.ones(X0.shape[0])
    w = np.atleast_1d(np.asarray(weights, dtype=float))
    if w.shape != X0.shape:
        raise InputError(f"weights must be one number per measurement ({X0.shape[0]}), got shape {w.shape}")
    bad = np.flatnonzero(~(np.isfinite(w) & (w > 0)))
    if bad.size:
        raise InputError(f"weights must be finite and > 0; weight {int(bad[0])} is {w[bad[0]]!r}")
    return A, X0, w


def least_squares_balance(A, X0, weights=None):
    """Corrections `W` (complex, per plane) minimising `sum_i (w_i |X0_i + A_i W|)^2`
    (`_balance.least_squares_correction` with `Q = w^2`). `weights` `w`: > 0, one
    per measurement (None: all 1)."""
    A, X0, w = _check_system(A, X0, weights)
    if A.shape[0] < A.shape[1]:
        raise InputError(f"{A.shape[0]} measurement(s) cannot determine {A.shape[1]} plane corrections "
                         f"(underdetermined: measure more speeds or sensors, or use fewer planes)")
    return least_squares_correction(A, X0, w**2)


def minmax_balance(A, X0, weights=None):
    """Corrections `W` minimising the worst weighted residual `max_i w_i |X0_i + A_i W|`,
    exactly, as the second-order cone program

        minimise t  over (Re W, Im W, t)  s.t.  ||w_i (Re, Im)(X0_i + A_i W)||_2 <= t,

    solved by Clarabel (variables scaled to order one). Returns `(W, t)`, `t` the
    optimal max weighted residual (evaluated at `W`).

    **Raises:** `NumericalError` naming the solver status when it is not Solved."""
    import clarabel
    from scipy import sparse

    A, X0, w = _check_system(A, X0, weights)
    m, n = A.shape
    sx = float(np.max(w * np.abs(X0)))
    if sx == 0.0:
        return np.zeros(n, dtype=np.complex128), 0.0
    colmax = np.max(w[:, None] * np.abs(A), axis=0)
    if np.any(colmax == 0):
        raise NumericalError(f"minmax_balance: plane {int(np.argmax(colmax == 0))} has no influence on any "
                             f"measurement (a zero column of A)")
    s = sx / colmax                                  # W_p = s_p y_p
    g = w[:, None] * A * s[None, :] / sx             # scaled influence
    c = w * X0 / sx                                  # scaled baseline
    rows = np.zeros((3 * m, 2 * n + 1))
    b = np.zeros(3 * m)
    rows[0::3, 2 * n] = -1.0                         # s_t = t
    rows[1::3, :n], rows[1::3, n:2 * n] = -g.real, g.imag     # s_re = Re c + Re g a - Im g b
    rows[2::3, :n], rows[2::3, n:2 * n] = -g.imag, -g.real    # s_im = Im c + Im g a + Re g b
    b[1::3], b[2::3] = c.real, c.imag
    q = np.zeros(2 * n + 1)
    q[-1] = 1.0
    settings = clarabel.DefaultSettings()
    settings.verbose = False
    for name in ("tol_gap_abs", "tol_gap_rel", "tol_feas"):
        setattr(settings, name, 1e-10)
    P = sparse.csc_matrix((2 * n + 1, 2 * n + 1))
    solver = clarabel.DefaultSolver(P, q, sparse.csc_matrix(rows), b, [clarabel.SecondOrderConeT(3)] * m,
                                    settings)
    sol = solver.solve()
    status = str(sol.status)
    if status.split(".")[-1] != "Solved":
        raise NumericalError(f"minmax_balance: the cone program was not solved (Clarabel status {status})")
    x = np.asarray(sol.x)
    W = (x[:n] + 1j * x[n:2 * n]) * s
    if not np.all(np.isfinite(W)):
        raise NumericalError("minmax_balance: the corrections are not finite")
    return W, float(np.max(w * np.abs(X0 + A @ W)))


def split_onto_holes(W, hole_angles):
    """Split a correction `W` (complex) onto the two neighbouring holes of a plane
    (angles in rad): non-negative masses `(m_a, m_b)` at `(angle_a, angle_b)` whose
    vector sum is `W` (same units as `W`)."""
    W = complex(as_numpy("W", W, dtype=np.complex128, shape=()))
    h = np.sort(np.mod(as_numpy("hole_angles", hole_angles, ndim=1), 2 * np.pi))
    if h.size < 2:
        raise InputError(f"hole_angles: need at least two hole positions, got {h.size}")
    a = np.mod(np.angle(W), 2 * np.pi)
    i = np.searchsorted(h, a) % h.size
    lo, hi = h[i - 1], h[i]
    span = np.mod(hi - lo, 2 * np.pi)
    if span == 0 or span >= np.pi:
        raise InputError(f"hole_angles: the holes around the correction's angle ({float(a):.4g} rad) are at "
                         f"{float(lo):.4g} and {float(hi):.4g} rad, pi or more apart (or coincide): the "
                         f"split is not unique/positive")
    # W = m_a e^{i lo} + m_b e^{i hi}
    M = np.array([[np.cos(lo), np.cos(hi)], [np.sin(lo), np.sin(hi)]])
    m = np.linalg.solve(M, [W.real, W.imag])
    return (float(m[0]), float(lo)), (float(m[1]), float(hi))
