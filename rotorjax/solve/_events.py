"""Event-located integration of a scene with switching contacts.

The scene provides `vector_field(t, y, active)` (smooth for a fixed contact set
`active`), `contact_indicator(t, y)` (one value per contact, positive exactly
where it acts) and `n_contacts`. The integration runs over blocks of output times;
diffrax's events stop it where an indicator changes sign (located by a
Newton root find on the dense output), the contact set is switched and the
integration restarts from there. Each smooth piece is integrated to the requested
tolerance: no step straddles a switch.
"""

import diffrax
import equinox as eqx
import jax
import jax.numpy as jnp
import optimistix as optx

from ..models._contract import require
from ..models._validate import InputError, as_count
from ._results import MAX_STEPS_REACHED, NONFINITE, SOLVER_FAILURE, SUCCESSFUL, SimulationResult
from ._simulate import _check_inputs, _split_span, _y0
from ._stiffness import choose_solver


def simulate_events(scene, y0, t_span, saveat=2000, solver="dopri8", rtol=1e-8, atol=1e-10,
                    max_steps=100_000, max_events=1_000_000, block=64) -> SimulationResult:
    """Integrate `scene` with event-located contact switching (see the module
    docstring), saving `saveat` equally spaced states over `t_span` (integrated
    `block` output intervals at a time between switches). Returns a
    `SimulationResult` whose `stats` add `num_events`; `code` (see `RESULTS`):
    `successful`, `max_steps_reached` (the step or the event budget exhausted),
    `nonfinite` (a non-finite state) or `solver_failure`."""
    t0, t1 = _split_span(t_span)
    y0 = _y0(y0)
    max_steps = _check_inputs(scene, y0, t0, t1, rtol, atol, max_steps)
    require(scene, "contact_indicator", "simulate_events")
    if scene.n_contacts < 1:
        raise InputError("scene: simulate_events needs a scene with contacts (limiters); use simulate")
    saveat = as_count("saveat (number of saved states)", saveat, minimum=2)
    block = as_count("block", block, minimum=1)
    max_events = as_count("max_events", max_events, minimum=1)
    solver = choose_solver(scene, y0, t0, solver)
    ts = jnp.linspace(jnp.float64(t0), jnp.float64(t1), int(saveat))
    return _solve(scene, y0, ts, solver, jnp.float64(rtol), jnp.float64(atol), max_steps,
                  max_events, block)


@eqx.filter_jit
def _solve(scene, y0, ts, solver, rtol, atol, max_steps, max_events, block):
    n_c = scene.n_contacts
    term = diffrax.ODETerm(lambda t, y, active: scene.vector_field(t, y, active))

    def cond_k(k):
        # +g while k is out of contact, -g while in: an up-crossing is always a switch
        def cond(t, y, args, **kwargs):  # args: the contact set
            return jnp.where(args[k], -1.0, 1.0) * scene.contact_indicator(t, y)[k]
        return cond

    event = diffrax.Event([cond_k(k) for k in range(n_c)], direction=True,
                          root_finder=optx.Newton(rtol=1e-10, atol=1e-12))
    controller = diffrax.PIDController(rtol=rtol, atol=atol)
    n_ts = ts.shape[0]
    ys = jnp.full((n_ts, y0.shape[0]), jnp.nan).at[0].set(y0)
    active0 = scene.contact_indicator(ts[0], y0) > 0
    zero = jnp.array(0)
    init = (jnp.array(1), ts[0], y0, active0, ys, zero, zero, zero, zero, jnp.int32(SUCCESSFUL))

    def cond_fun(c):
        i, _, _, _, _, n_ev, _, _, _, code = c
        return (i < n_ts) & (code == SUCCESSFUL) & (n_ev < max_events)

    def body(c):
        # integrate over the next `block` output times, or up to the next switch
        i, t, y, active, ys, n_ev, n_steps, n_acc, n_rej, code = c
        idx = jnp.minimum(i + jnp.arange(block), n_ts - 1)
        sol = diffrax.diffeqsolve(term, solver, t0=t, t1=ts[idx[-1]], dt0=None, y0=y, args=active,
                                  saveat=diffrax.SaveAt(ts=ts[idx], t1=True), stepsize_controller=controller,
                                  max_steps=max_steps, event=event, throw=False)
        # the state at the end (t1 or the switch) follows the output times reached
        last = jnp.sum(jnp.isfinite(sol.ts)) - 1
        t_new, y_new = sol.ts[last], sol.ys[last]
        switched = jnp.stack([jnp.asarray(m) for m in sol.event_mask])
        # an event whose root find stopped at its iteration cap still sits at the
        # switch to within the event function's rounding: accept it
        hit = jnp.any(switched) & ((sol.result == diffrax.RESULTS.event_occurred)
                                   | (sol.result == diffrax.RESULTS.nonlinear_max_steps_reached))
        ok = (sol.result == diffrax.RESULTS.successful) | hit
        active = jnp.where(hit, active ^ switched, active)
        finite = jnp.all(jnp.isfinite(y_new))
        reached = (ts[idx] <= t_new) & ok & finite
        ys = ys.at[idx].set(jnp.where(reached[:, None], sol.ys[:block], ys[idx]))
        code = jnp.where(~ok, jnp.where(sol.result == diffrax.RESULTS.max_steps_reached, MAX_STEPS_REACHED,
                                        SOLVER_FAILURE),
                         jnp.where(finite, SUCCESSFUL, NONFINITE)).astype(jnp.int32)
        i_new = jnp.where(ok & finite, jnp.searchsorted(ts, t_new, side="right"), i)
        return (i_new, t_new, y_new, active, ys, n_ev + hit, n_steps + sol.stats["num_steps"],
                n_acc + sol.stats["num_accepted_steps"], n_rej + sol.stats["num_rejected_steps"], code)

    i, t, y, active, ys, n_ev, n_steps, n_acc, n_rej, code = jax.lax.while_loop(cond_fun, body, init)
    # the event budget exhausted: reported as the step budget is
    code = jnp.where((code == SUCCESSFUL) & (i < ts.shape[0]), MAX_STEPS_REACHED, code).astype(jnp.int32)
    outputs = jax.vmap(scene.outputs)(ts, ys)
    stats = {"num_steps": n_steps, "num_accepted_steps": n_acc, "num_rejected_steps": n_rej,
             "num_events": n_ev}
    return SimulationResult(ts=ts, ys=ys, outputs=outputs, code=code, stats=stats,
                            solver=type(solver).__name__ + "+events")
