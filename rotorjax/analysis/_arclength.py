"""The compiled continuation core: pseudo-arclength steps along `G(x) = 0`
(`G: R^{k+1} -> R^k`, a `Lifted` JAX function) in one direction, in one
`lax.while_loop`, the points written to a buffer of `CHUNK` rows: no Python per
point or per Newton iteration (the per-point driver, its dispatch and its array
conversions were most of a small branch's wall time).

Each pass of the loop makes one attempt at the next point, in one of three modes:

- a step: the Euler predictor `x + ds t` corrected by Newton (`rotorjax._newton`)
  on `[G(y); t . (y - x - ds t)] = 0`;
- a landing on the box's edge that the predictor would cross (`x + s t`, `s` the
  step to that bound), corrected with that coordinate held at the bound;
- a landing where a corrected step left the box (where the chord crosses it).

The tangent at a corrected point is the bordered solve `[G'(y); t^T] v = e`
normalized, which also orients it along the way the curve goes. A step is halved
where the corrector fails (or meets non-finite values) and where the tangent turns
by more than `max_turn` (at most `MAX_TURN_HALVINGS` times a point: at a singular
point the tangent may jump); it grows by 1.5 after at most three Newton iterations,
stays after five and halves after more, capped by the turning. Each accepted
interval's interpolation error is estimated (the Newton correction of its cubic
Hermite midpoint, `_interval_error`); with a target (`dense_tol`) a step above it
is cut and the next one sized for it (the error goes as the step's fourth power).
The loop stops on
the box's edge, at a closed loop (the step runs into `other`, the last point of the
trace going the other way), at `budget` points, when the buffer is full (the
driver goes on with a new call), where the step falls below `ds_min`, after
`MAX_NONFINITE` successive steps cut short by non-finite values, or where
`watch(x) > 0` at a new point (the caller's own reason, e.g. a truncation error
estimate past its target).

`march` is compiled once per structure of `G` and of `watch` (`solve._lift`):
another branch of the same equations reuses it. The driver and the stop reasons'
words are `_continuation._trace`'s."""

from typing import NamedTuple

import jax
import jax.numpy as jnp

from .._newton import newton
from ..solve._lift import compiled

#: rows of the point buffer one call fills at most (the driver calls again from the last point)
CHUNK = 64

#: at a singular point the tangent may jump: a step is accepted after this many halvings for turning
MAX_TURN_HALVINGS = 6
#: successive steps cut short by non-finite G: the curve runs into where G is undefined
MAX_NONFINITE = 3
#: steps cut for the interpolation error before one is accepted regardless
MAX_DENSE_CUTS = 12
#: an error along an axis nearly tangent to the curve is capped at 1 / AXIS_FLOOR times the orthogonal one
AXIS_FLOOR = 0.05
#: attempts one call may make at most (a guard: each halves the step or moves on)
MAX_ATTEMPTS = 64 * CHUNK

# why a call stopped
GO, EDGE, FAILED, NONFINITE, CLOSED, FULL, PAUSE, WATCH = range(8)


class March(NamedTuple):
    """What one call of `march` returns: the first `n` rows of the buffers are new
    points (`x`, unit tangents `t` along the way, `residuals` max |G|, `steps`,
    Newton `iterations`, interpolation `errors` from the point before); `stop` (a
    code above), `stop_k` (the coordinate of an edge, or the watch's code),
    `stop_b` (the edge's bound), `bad` (the last point where G was not finite), and
    what the next call starts from (the last point's Jacobian `J`, `ds`,
    `nonfinite`)."""

    x: jax.Array
    t: jax.Array
    residuals: jax.Array
    steps: jax.Array
    iterations: jax.Array
    errors: jax.Array
    n: jax.Array
    stop: jax.Array
    stop_k: jax.Array
    stop_b: jax.Array
    bad: jax.Array
    J: jax.Array
    ds: jax.Array
    nonfinite: jax.Array


def _to_box(x, t, lo, hi):
    """The step along `t` from `x` to the first bound it meets: `(step, coordinate, bound)`
    (an infinite step where it meets none)."""
    up = (t > 0) & jnp.isfinite(hi)
    down = (t < 0) & jnp.isfinite(lo)
    bound = jnp.where(up, hi, lo)
    safe = jnp.where(up | down, t, 1.0)
    s = jnp.where(up | down, jnp.maximum(0.0, (bound - x) / safe), jnp.inf)
    k = jnp.argmin(s)
    return s[k], k, bound[k]


def _interval_error(G, x, tx, Jx, y, ty, Jy, axis):
    """The interpolation error estimate on `x -> y` (unit tangents `tx`, `ty` along
    it, Jacobians `Jx`, `Jy`): the length of the minimum-norm Newton correction of
    the cubic Hermite midpoint with the mean Jacobian; for `axis >= 0` (a curve in
    two coordinates) divided by the size of that Jacobian's row along `axis`,
    relative (floored at `AXIS_FLOOR`)."""
    h = jnp.linalg.norm(y - x)
    mid = 0.5 * (x + y) + 0.125 * h * (tx - ty)
    J = 0.5 * (Jx + Jy)
    err = jnp.linalg.norm(J.T @ jnp.linalg.solve(J @ J.T, -G(mid)))
    nu = jnp.abs(J[0, jnp.maximum(axis, 0)]) / jnp.maximum(jnp.linalg.norm(J[0]), 1e-300)
    err = jnp.where(axis >= 0, err / jnp.maximum(nu, AXIS_FLOOR), err)
    return jnp.where(jnp.isfinite(err), err, jnp.inf)


@compiled
def march(G, watch, x, t, J, ds, nonfinite, other, other_t, other_J, other_r, budget, pause, lo, hi, knobs):
    """Points along `G = 0` from `x` (unit tangent `t`, Jacobian `J`, next step `ds`)
    until a stop (see the module docstring): at most `budget` points (then `FULL`),
    pausing after `pause` (at most `CHUNK`; then `PAUSE`: the driver shares the
    points between two directions round by round). `knobs`: `(ds_min, ds_max, tol,
    gtol, max_turn, max_newton, target, axis)`, `target` the interpolation error a
    step is kept below (infinite: not controlled), `axis` the coordinate it is
    measured along (-1: orthogonally to the curve). `lo`, `hi`: the box (infinite:
    no bound); `watch`: None or a lifted function of a point returning an integer
    (0: go on). `other`, `other_t`, `other_J`, `other_r`: the other direction's last
    point, its tangent, Jacobian and residual (a step that reaches it closes the loop)."""
    ds_min, ds_max, tol, gtol, max_turn, max_newton, target, axis = knobs
    axis = axis.astype(int)
    m = x.size
    eps = 1e-12 * jnp.maximum(1.0, jnp.maximum(jnp.abs(jnp.where(jnp.isfinite(lo), lo, 0.0)),
                                               jnp.abs(jnp.where(jnp.isfinite(hi), hi, 0.0))))

    def outside(y):
        return jnp.any(y < lo - eps) | jnp.any(y > hi + eps)

    def correct(xp, row, c):
        def R(y):
            return jnp.concatenate([G(y), (row @ y - c)[None]])

        # G and its Jacobian at the corrected point come from the corrector's last evaluation (each place G is
        # called is a copy of it in the program)
        y, (step, it, r, J) = newton(R, xp, tol, max_newton, floor=1e3 * tol, final=True)
        return y, step, it, r[:-1], J[:-1]

    def closes(x, y, t):
        """The chord `x -> y` (tangent `t` at `y`) runs into `other`, coming the other way."""
        d = y - x
        dd = d @ d
        s = (other - x) @ d / jnp.where(dd > 0, dd, 1.0)
        near = jnp.linalg.norm(x + s * d - other) <= 0.1 * jnp.sqrt(dd)
        return (dd > 0) & (s > 0) & (s <= 1.1) & near & (t @ other_t < -0.5)

    def coarse(err, cuts):
        return (err > target) & (cuts < MAX_DENSE_CUTS)

    def shrink(err):
        """The step factor that brings an interpolation error `err` to about the target (error ~ step^4)."""
        return jnp.where(jnp.isfinite(err), jnp.clip(0.9 * (target / err) ** 0.25, 0.2, 0.9), 0.2)

    zero, none = jnp.asarray(0), jnp.asarray(False)
    state = dict(
        x=jnp.zeros((CHUNK, m)), t=jnp.zeros((CHUNK, m)), residuals=jnp.zeros(CHUNK), steps=jnp.zeros(CHUNK),
        iterations=jnp.zeros(CHUNK, int), errors=jnp.zeros(CHUNK), n=zero,
        at=x, along=t, J=J, ds=ds, nonfinite=nonfinite, stop=jnp.asarray(GO), stop_k=zero, stop_b=jnp.float64(0.0),
        bad=jnp.full(m, jnp.nan), attempts=zero,
        # this point's attempts: non-finite values met, halvings for turning, cuts for the interpolation error,
        # a landing pending where the last step left the box (from xc, on coordinate kc at bound bc, within
        # reach), the edge landing tried and missed
        seen=none, turns=zero, cuts=zero, cross=none, xc=x, kc=zero, bc=jnp.float64(0.0), reach=jnp.float64(0.0),
        tried=none)

    def body(s):
        x, t, ds = s["at"], s["along"], s["ds"]
        s_edge, ke, be = _to_box(x, t, lo, hi)
        heads_out = s_edge <= 1e-12 * jnp.maximum(1.0, jnp.max(jnp.abs(x)))
        cross = s["cross"]
        edge_first = ~cross & (s_edge <= ds) & ~s["tried"]
        landing = cross | edge_first
        k_fix = jnp.where(cross, s["kc"], ke)
        b_fix = jnp.where(cross, s["bc"], be)
        xp = jnp.where(cross, s["xc"], jnp.where(edge_first, x + s_edge * t, x + ds * t))
        reach = jnp.where(cross, s["reach"], s_edge)
        row = jnp.where(landing, jnp.zeros(m).at[k_fix].set(1.0), t)
        y, step, it, Gy, Jy = correct(xp, row, jnp.where(landing, b_fix, t @ xp))
        y = jnp.where(landing, y.at[k_fix].set(b_fix), y)
        r = jnp.max(jnp.abs(Gy))
        finite = jnp.isfinite(r) & jnp.all(jnp.isfinite(y))
        Jy = jnp.where(finite, Jy, s["J"])
        v = jnp.linalg.solve(jnp.concatenate([Jy, t[None, :]]), jnp.zeros(m).at[-1].set(1.0))
        tn = v / jnp.linalg.norm(v)      # the unit tangent at y along t
        ok = finite & (step <= 1e3 * tol) & (r <= gtol) & jnp.all(jnp.isfinite(tn))
        iters = (it - (step > tol)).astype(int)
        angle = jnp.arccos(jnp.clip(tn @ t, -1.0, 1.0))
        turning = (angle > max_turn) & (s["turns"] < MAX_TURN_HALVINGS) & (ds / 2 >= ds_min)
        inside = ~outside(y)
        seen = s["seen"] | ~finite

        # a landing on the edge; a step, which may leave the box, turn too far or close the loop
        landed = landing & ok & inside & ((y - x) @ t > 0) & (jnp.linalg.norm(y - x) <= 2 * reach)
        stepped = ~landing & ok
        left = stepped & ~inside
        closed = stepped & inside & ~turning & closes(x, y, tn)
        # the accepted point's interpolation error, too coarse for the target
        z = jnp.where(closed, other, y)
        tz, Jz = jnp.where(closed, -other_t, tn), jnp.where(closed, other_J, Jy)
        err = _interval_error(G, x, t, s["J"], z, tz, Jz, axis)
        too_coarse = coarse(err, s["cuts"]) & (landing | (ds * shrink(err) >= ds_min))
        land_accept = landed & ~turning & ~too_coarse
        closed = closed & ~too_coarse
        step_accept = stepped & inside & ~turning & ~closed & ~too_coarse
        accept = land_accept | closed | step_accept

        # the pending landing where the step left the box: where the chord first crosses it
        over = (y > hi + eps) | (y < lo - eps)
        bound = jnp.where(y > hi, hi, lo)
        frac_i = jnp.where(over, (bound - x) / jnp.where(over, y - x, 1.0), jnp.inf)
        k_new = jnp.argmin(frac_i)

        # the next step: halved where the corrector failed or the tangent turned (a step that left the box keeps
        # its length for the pending landing, halved if that misses; a missed edge landing is followed by a
        # step of the same length), cut for the interpolation error where too coarse, grown after an easy one
        cut = (landed | (stepped & inside)) & ~turning & too_coarse
        halve = (~landing & ~ok) | (stepped & inside & turning) | (cross & ~land_accept & ~cut)
        ds_next = jnp.where(edge_first & landed & turning, 0.5 * s_edge, jnp.where(halve, 0.5 * ds, ds))
        short = jnp.where(edge_first, s_edge, jnp.where(cross, jnp.linalg.norm(s["xc"] - x), ds))
        ds_next = jnp.where(cut, short * shrink(err), ds_next)
        grow = jnp.where(iters <= 3, 1.5, jnp.where(iters <= 5, 1.0, 0.5))
        grow = jnp.where(angle > 0, jnp.minimum(grow, 0.8 * max_turn / jnp.maximum(angle, 1e-300)), grow)
        grow = jnp.where(jnp.isfinite(target) & (err > 0), jnp.minimum(grow, 0.9 * (target / err) ** 0.25), grow)
        grown = jnp.clip(ds * jnp.maximum(grow, 0.25), ds_min, ds_max)
        nonfinite = jnp.where(step_accept, jnp.where(seen, s["nonfinite"] + 1, 0), s["nonfinite"])
        ds_next = jnp.where(step_accept, jnp.where(seen, ds, grown), ds_next)

        # the accepted point, written at row n
        n = s["n"]
        i = jnp.minimum(n, CHUNK - 1)
        new = dict(x=z, t=tz, residuals=jnp.where(closed, other_r, r),
                   steps=jnp.where(step_accept, ds, jnp.linalg.norm(z - x)), iterations=iters, errors=err)
        out = {k: jnp.where(accept, s[k].at[i].set(v), s[k]) for k, v in new.items()}
        n_next = n + accept
        code = jnp.asarray(0) if watch is None else jnp.asarray(watch(z)).astype(int)
        watched = accept & ~closed & (code > 0)

        # why it stops (the first that applies); a stop before the attempt keeps the state as it was
        early = heads_out | (n >= budget) | (ds < ds_min) | (s["attempts"] >= MAX_ATTEMPTS)
        stop = jnp.select(
            [heads_out, n >= budget, ds < ds_min, s["attempts"] >= MAX_ATTEMPTS, watched, closed, land_accept,
             step_accept & (nonfinite >= MAX_NONFINITE), accept & (n_next >= budget),
             accept & (n_next >= jnp.minimum(pause, CHUNK))],
            [EDGE, FULL, jnp.where(seen, NONFINITE, FAILED), FAILED, WATCH, CLOSED, EDGE, NONFINITE, FULL, PAUSE], GO)
        out.update(
            n=n_next, at=jnp.where(accept, z, x), along=jnp.where(accept, tz, t), J=jnp.where(accept, Jz, s["J"]),
            ds=ds_next, nonfinite=nonfinite, bad=jnp.where(finite, s["bad"], y), seen=seen & ~accept,
            turns=jnp.where(accept, 0, s["turns"] + (landed & turning) + (stepped & inside & turning)),
            cuts=jnp.where(accept, 0, s["cuts"] + cut), cross=left, xc=x + frac_i[k_new] * (y - x), kc=k_new,
            bc=bound[k_new], reach=jnp.maximum(ds, jnp.linalg.norm(y - x)),
            tried=~accept & (s["tried"] | (edge_first & ~landed)))
        out = {k: jnp.where(early, s[k], v) for k, v in out.items()}
        out.update(stop=stop, stop_k=jnp.where(heads_out, ke, jnp.where(watched, code, k_fix)),
                   stop_b=jnp.where(heads_out, be, b_fix), attempts=s["attempts"] + 1)
        return out

    s = jax.lax.while_loop(lambda s: s["stop"] == GO, body, state)
    return March(s["x"], s["t"], s["residuals"], s["steps"], s["iterations"], s["errors"], s["n"], s["stop"],
                 s["stop_k"], s["stop_b"], s["bad"], s["J"], s["ds"], s["nonfinite"])
