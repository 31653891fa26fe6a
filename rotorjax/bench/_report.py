"""What a headline comparison returns, and how a call is timed."""

import time
from dataclasses import asdict, dataclass, field


@dataclass
class Point:
    """One rung of a method's ladder: its tolerance (or step) label, its error against
    the reference, its cost (seconds per speed / point / analysis)."""
    tol: str
    error: float
    cost: float
    first_call_s: float | None = None
    failed: int = 0


@dataclass
class Comparison:
    name: str
    what: str
    cost_unit: str
    error_label: str
    curves: dict = field(default_factory=dict)   # method -> [Point]
    rotorjax: str = ""                           # the rotorjax curve's name
    peers: list = field(default_factory=list)    # the peers' curve names
    skipped: list = field(default_factory=list)  # (peer, why)
    notes: list = field(default_factory=list)
    checks: dict = field(default_factory=dict)   # computed agreements, fractions
    rows: list = field(default_factory=list)     # ratios at matched error

    def add(self, method, point):
        self.curves.setdefault(method, []).append(point)

    def to_json(self):
        d = asdict(self)
        d["skipped"] = [{"peer": p, "why": w} for p, w in self.skipped]
        return d


def timed(fn, repeats, warm=True):
    """`fn()` once (compiling, when `warm`), then `repeats` times ->
    `(first_call_s, median_s, last result)`; JAX results are waited for by `fn`."""
    first = None
    if warm:
        t0 = time.perf_counter()
        fn()
        first = time.perf_counter() - t0
    walls, out = [], None
    for _ in range(max(1, repeats)):
        t0 = time.perf_counter()
        out = fn()
        walls.append(time.perf_counter() - t0)
    walls.sort()
    return first, walls[len(walls) // 2], out
