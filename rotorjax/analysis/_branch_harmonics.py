"""Harmonics adapted along a branch of periodic motions
(`periodic_branch(harmonics="auto")`): each point's fewest harmonics whose
truncation error estimate (`truncation_error`) meets the target, the branch traced
in pieces of one count each (a piece ends where a point needs more, or could do
with fewer, and the next goes on from that point solved again), joined into one
`PeriodicBranch`."""

import dataclasses

import jax
import jax.numpy as jnp
import numpy as np

from ..solve._lift import batched, call, compiled, lift
from ..solve._results import RESULTS, code_of
from ._continuation import Branch, Curve
from ._harmonic_balance import _adapted, harmonic_balance, truncation_error, truncation_profile


#: `periodic_branch(harmonics="auto")`: the harmonics a point may take (a synchronous orbit of an
#: axisymmetric rotor needs one; each count is compiled once)
BRANCH_HARMONICS = (1, 2, 4, 8, 16, 32, 64)

#: fewer harmonics are tried where the series cut to them keeps the truncation error estimate below this fraction
#: of the target (a margin against going down and up again)
LOWER_MARGIN = 0.01

#: the stop reason of a piece of branch ended to change its harmonics (never a branch's own stop)
REHARMONIZE = "harmonics"


@dataclasses.dataclass(frozen=True)
class PeriodicBranch(Branch):
    """A `Branch` of periodic motions, with each point's number of harmonics
    (`harmonics`; adapted along the branch by `periodic_branch(harmonics="auto")`)
    and its truncation error estimate (`truncation`: `truncation_error`; by
    shooting, the size of the series' left-out harmonics, relative, or with fixed
    harmonics that of its highest one)."""

    harmonics: np.ndarray = None
    truncation: np.ndarray = None

    def as_dict(self):
        return dict(super().as_dict(), harmonics=np.asarray(self.harmonics).tolist(),
                    truncation=np.asarray(self.truncation).tolist())


def _measure(scene_at, period_at, p):
    """`measure(solution)` at `p` for `_adapted`: `truncation_profile`, compiled once
    per structure and harmonics."""
    def measure(sol):
        return np.asarray(call(lift(_truncation_of(scene_at, period_at), jnp.asarray(p), sol.coefficients),
                               jnp.asarray(p), sol.coefficients))

    return measure


def _truncation_of(scene_at, period_at):
    def one(p, Y):
        return truncation_profile(scene_at(p), Y, period_at(p))

    return one


def _truncations(scene_at, period_at, p, coefficients):
    """`truncation_profile` at every point of a piece of branch, `(points, entries)`
    (in batches of `solve._lift.ROWS` points: one program per structure); its first
    column is each point's `truncation_error`."""
    p, Y = np.asarray(p, dtype=float), np.asarray(coefficients, dtype=float)
    one = lift(_truncation_of(scene_at, period_at), jnp.asarray(p[0]), jnp.asarray(Y[0]))
    return batched(_rows, one, (p, Y))[0]


@compiled
def _rows(f, p, Y):
    return (jax.vmap(f)(p, Y),)


def _fields(br):
    """A `Branch`'s fields by name (to make a `PeriodicBranch` of it)."""
    return {f.name: getattr(br, f.name) for f in dataclasses.fields(Branch)}


def _watch(scene_at, period_at, coefficients, shape, target, higher, lower):
    """`watch` for `continue_branch` on a piece of `shape`'s harmonics
    (`coefficients(u, p)`: a point's from its unknowns): `"harmonics raised"` where
    the truncation error estimate exceeds `target` (when `higher`: more are
    allowed), `"harmonics lowered"` where the series cut to `lower` harmonics (None:
    not tried) keeps it below `LOWER_MARGIN target`."""
    cut = 2 * (lower or 0) + 1 if lower else shape[0]

    def code(x):
        Y, p = coefficients(x[:-1], x[-1]), x[-1]
        sc, T = scene_at(p), period_at(p)
        r = truncation_error(sc, Y, T)
        raised = higher & ~(r <= target)
        lowered = bool(lower) & (truncation_error(sc, Y[:cut], T) <= LOWER_MARGIN * target)
        return jnp.where(raised, 1, jnp.where(lowered, 2, 0))

    return code, (f"{REHARMONIZE} raised", f"{REHARMONIZE} lowered")


def _adaptive(piece, Y0, p0, options, target, ladder):
    """`periodic_branch(harmonics="auto")` by harmonic balance: pieces of branch of
    one count of harmonics each, each going on from where the one before ended,
    joined (see there)."""
    scene_at, period_at = piece.args[:2]

    def run(Y, p, opts, lower_ok=True):
        H = (Y.shape[0] - 1) // 2
        k = ladder.index(H) if H in ladder else len(ladder) - 1
        br, co = piece(Y, p, opts, watch=(target, H < ladder[-1], ladder[k - 1] if lower_ok and k > 0 else None))
        return br, co, H, _truncations(scene_at, period_at, br.p, co)

    first = run(Y0, p0, options)
    budget = options["max_points"] - first[0].p.size
    sides = []
    for side in (0, 1):                      # the low end, then the high end (or the far end, traced one way)
        pieces, last, stop, lower_ok = [], first, first[0].stops[side], True
        while stop.startswith(REHARMONIZE) and budget > 0:
            br, co, H, tr = last
            i = 0 if pieces == [] and side == 0 else -1
            Y, p = co[i], float(br.p[i])
            t = br.curve.tangents[i] * (-1.0 if i == 0 else 1.0)     # outward
            if stop.endswith("raised"):
                sol = _adapted(scene_at(p), period_at(p), Y, truncation_tol=target, max_harmonics=ladder[-1],
                               stability=False, ladder=ladder, above=H, measure=_measure(scene_at, period_at, p),
                               profile=tr[i], t0=0.0, tol=1e-10, max_iter=30, args=None)
            else:
                sol = harmonic_balance(scene_at(p), period_at(p), Y, ladder[ladder.index(H) - 1], stability=False)
                if not (int(sol.code) == 0 and _measure(scene_at, period_at, p)(sol)[0] <= target):
                    sol, lower_ok = None, False      # the motion needs H after all: go on with it, never lower
            if sol is not None and int(sol.code) not in (0, code_of(RESULTS.harmonics_insufficient)):
                stop = (f"no periodic motion with more harmonics than {H} at {options['name']} = {p:.8g} "
                        f"({RESULTS[sol.result]})")
                break
            Ynew = Y if sol is None else np.asarray(sol.coefficients)
            direction = np.concatenate([_resized(t[:-1].reshape(2 * H + 1, -1), Ynew.shape[0]).ravel(), t[-1:]])
            last = run(jnp.asarray(Ynew), p, dict(options, direction=direction, max_points=budget + 1), lower_ok)
            budget -= last[0].p.size - 1
            pieces.append(last)
            stop = last[0].stops[1]
        if stop.startswith(REHARMONIZE):
            stop = "max_points reached"
        sides.append((pieces, stop))
    return _joined(first, sides)


def _resized(Y, m):
    """Coefficients `Y` (`(2H + 1, ...)`) with `m` rows: cut, or padded with zeros."""
    Y = np.asarray(Y)
    return np.concatenate([Y[:m], np.zeros((max(m - Y.shape[0], 0),) + Y.shape[1:])])


def _joined(first, sides):
    """One `PeriodicBranch` of the first piece (traced both ways, or one way) and
    the pieces that went on from its ends (`sides`: `(pieces, stop)` at the low end
    and at the high end, each piece traced outward from the end before, whose
    point it repeats with other harmonics and replaces), the coefficients padded
    to the most harmonics."""
    br0, co0, H0, tr0 = first
    if all(not pieces for pieces, _ in sides) and tuple(stop for _, stop in sides) == tuple(br0.stops):
        return PeriodicBranch(**_fields(br0), harmonics=np.full(br0.p.size, H0), truncation=tr0[:, 0]), co0
    n = co0.shape[-1]
    rows = 2 * max([H0] + [pc[2] for pieces, _ in sides for pc in pieces]) + 1

    def padded(v, H):     # scaled unknowns and parameter, the unknowns padded to `rows` harmonics
        return np.concatenate([_resized(v[:-1].reshape(2 * H + 1, -1), rows).ravel(), v[-1:]])

    def record(br, co, H, tr, i, sign, into):
        c = br.curve
        return dict(p=float(br.p[i]), Y=_resized(co[i], rows), u=padded(np.append(br.u[i], 0.0), H)[:-1],
                    margin=float(br.margin[i]), stable=bool(br.stable[i]),
                    H=H, truncation=float(tr[i, 0]), residual=float(c.residuals[i]),
                    tangent=sign * padded(c.tangents[i], H), into=into)

    s0 = int(br0.curve.start)
    seqs, events = [], []
    for side, (pieces, _) in enumerate(sides):
        c = br0.curve
        if side == 0:      # from the start down to the low end, outward: the step into i is the one out of it
            seq = [record(br0, co0, H0, tr0, i, -1.0, (c.steps[i + 1], c.iterations[i + 1], c.errors[i + 1]) if i < s0
                          else (0.0, 0, 0.0)) for i in range(s0, -1, -1)]
        else:
            seq = [record(br0, co0, H0, tr0, i, 1.0, (c.steps[i], c.iterations[i], c.errors[i]) if i > s0
                          else (0.0, 0, 0.0)) for i in range(s0, br0.p.size)]
        for br, co, H, tr in pieces:
            base, replaced = len(seq) - 1, seq.pop()
            c = br.curve
            seq += [record(br, co, H, tr, i, 1.0, replaced["into"] if i == 0 else
                           (c.steps[i], c.iterations[i], c.errors[i])) for i in range(br.p.size)]
            events += [(e, side, (base + e.between[0], base + e.between[1])) for e in br.events]
        seqs.append(seq)
    for e in br0.events:
        a, b = e.between
        events.append((e, 0, (s0 - a, s0 - b)) if b <= s0 else (e, 1, (a - s0, b - s0)))
    low, high = seqs
    mid = len(low) - 1

    def at(side, q):
        return mid - q if side == 0 else mid + q

    pts = low[:0:-1] + high
    for p in low[:0:-1]:
        p["tangent"] = -p["tangent"]
    # the step into a low point, going up: the one into the point below it, going out
    into = [(0.0, 0, 0.0)] + [low[q]["into"] for q in range(len(low) - 1, 0, -1)] + [h["into"] for h in high[1:]]
    Y = np.stack([p["Y"] for p in pts])
    p_ = np.array([p["p"] for p in pts])
    u = np.stack([p["u"] for p in pts])
    steps, iters, errs = (np.array([v[k] for v in into]) for k in range(3))
    stops = tuple(stop for _, stop in sides)
    one_way = stops[0] == "start"
    curve = Curve(x=np.column_stack([u, p_]), residuals=np.array([p["residual"] for p in pts]), steps=steps,
                  iterations=iters.astype(int), stopped=(stops[1] if one_way else "closed loop"
                                                         if stops == ("closed loop", "closed loop") else
                                                         f"low end: {stops[0]}; high end: {stops[1]}"),
                  stops=stops, start=mid, tangents=np.stack([p["tangent"] for p in pts]), errors=errs)
    joined = []
    for e, side, (qa, qb) in events:
        ga, gb = sorted((at(side, qa), at(side, qb)))
        H = (np.asarray(e.u).size // n - 1) // 2
        joined.append(dataclasses.replace(e, u=_resized(np.reshape(e.u, (2 * H + 1, -1)), rows).ravel(),
                                          between=(ga, gb)))
    margin = np.array([p["margin"] for p in pts])
    br = PeriodicBranch(u=u, p=p_, margin=margin, stable=np.array([p["stable"] for p in pts]),
                        events=tuple(sorted(joined, key=lambda e: e.between)), curve=curve,
                        harmonics=np.array([p["H"] for p in pts]),
                        truncation=np.array([p["truncation"] for p in pts]))
    return br, Y


def _series_harmonics(coefficients, target):
    """Each point's fewest harmonics whose left-out ones (of `coefficients`,
    `(points, 2H + 1, n)`) hold at most `target` of the series' size (Frobenius)."""
    C = np.asarray(coefficients)
    H = (C.shape[1] - 1) // 2
    size = np.sqrt(np.sum(C ** 2, axis=(1, 2)))
    # tail[:, h]: the size of harmonics h + 1 .. H
    per = np.sum(C[:, 1:] ** 2, axis=2).reshape(len(C), H, 2).sum(axis=2)
    tail = np.sqrt(np.concatenate([np.cumsum(per[:, ::-1], axis=1)[:, ::-1], np.zeros((len(C), 1))], axis=1))[:, 1:]
    ok = tail <= target * size[:, None]
    return np.argmax(ok, axis=1) + 1


def _series_tail(coefficients, kept):
    """Each point's left-out harmonics (above `kept`; with all kept, its highest
    one) relative to its series (Frobenius)."""
    C = np.asarray(coefficients)
    size = np.sqrt(np.sum(C ** 2, axis=(1, 2)))
    cut = [2 * int(h) + 1 if 2 * int(h) + 1 < C.shape[1] else C.shape[1] - 2 for h in kept]
    return np.array([np.sqrt(np.sum(c[k:] ** 2)) for c, k in zip(C, cut)]) / np.maximum(size, np.finfo(float).tiny)


def _truncated(coefficients, kept):
    """`coefficients` with each point's harmonics above `kept` set to zero."""
    C = np.array(coefficients)
    for i, h in enumerate(kept):
        C[i, 2 * int(h) + 1:] = 0.0
    return C
