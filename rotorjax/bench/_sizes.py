"""How big each headline comparison is: `QUICK` (`rotorjax bench --quick`, under two
minutes on a laptop), `FULL` (`rotorjax bench`, the sizes of `benchmarks/`), `SMOKE`
(the test suite: tiny, one repeat, no timing claims)."""

from dataclasses import dataclass


@dataclass(frozen=True)
class Sizes:
    # model 001 sweep (speeds n in [0.5, 10], tau in [0, t_end])
    sweep_speeds: int
    sweep_subset: int            # speeds with a tight reference: the errors, the scipy loop
    sweep_rtols: tuple           # rotorjax's ladder (Dopri8, atol = rtol * 1e-3)
    scipy_rtols: tuple           # scipy DOP853's ladder (stops once rotorjax's tightest error is bracketed)
    numba_steps: tuple           # numba RK4's step ladder
    numba_timing_speeds: int     # speeds a numba rung is timed on (fixed steps: the cost per speed is even)
    t_end: float
    # model 001 Floquet map (speeds x weight damping mu_w)
    floquet_speeds: int
    floquet_mu_w: int
    floquet_subset: int          # grid points with a tight reference: the errors, the scipy loop
    floquet_rtols: tuple
    # Campbell diagram of `ross-compare` (ROSS's rotor_example)
    campbell_speeds: int
    campbell_modes: int
    repeats: int


QUICK = Sizes(sweep_speeds=100, sweep_subset=8, sweep_rtols=(1e-6, 1e-9),
              scipy_rtols=(1e-5, 1e-6, 1e-7, 1e-8, 1e-9, 1e-10, 1e-11),
              numba_steps=(10_000, 20_000, 40_000, 80_000, 160_000, 320_000), numba_timing_speeds=8, t_end=200.0,
              floquet_speeds=40, floquet_mu_w=10, floquet_subset=12, floquet_rtols=(1e-6, 1e-8),
              campbell_speeds=50, campbell_modes=8, repeats=3)

FULL = Sizes(sweep_speeds=1000, sweep_subset=40, sweep_rtols=(1e-5, 1e-6, 1e-7, 1e-8, 1e-9, 1e-10),
             scipy_rtols=(1e-5, 1e-6, 1e-7, 1e-8, 1e-9, 1e-10, 1e-11, 1e-12),
             numba_steps=(5_000, 10_000, 20_000, 40_000, 80_000, 160_000, 320_000, 640_000),
             numba_timing_speeds=100, t_end=200.0, floquet_speeds=200, floquet_mu_w=50, floquet_subset=30,
             floquet_rtols=(1e-6, 1e-8, 1e-10), campbell_speeds=50, campbell_modes=8, repeats=3)

SMOKE = Sizes(sweep_speeds=6, sweep_subset=3, sweep_rtols=(1e-6,), scipy_rtols=(1e-5, 1e-7),
              numba_steps=(1_000, 2_000), numba_timing_speeds=3, t_end=10.0, floquet_speeds=3, floquet_mu_w=2,
              floquet_subset=2, floquet_rtols=(1e-6,), campbell_speeds=4, campbell_modes=4, repeats=1)
