"""A preset's reference-motion quantities as functions of its `--set` keys, for
propagation: the stability thresholds its reference motion (an auto-balancer's main
motion, a rotor's straight running) has in a speed range, each followed from the
preset's values (`rotorjax.analysis.StableSpeeds`), and `stable-range`, how much of
the range the motion is stable over (an auto-balancer's auto-balancing range). A
sample where a threshold is lost, or two have crossed, gives NaN and is counted, not
averaged."""

import jax.numpy as jnp
import numpy as np

from .._errors import InputError, NumericalError
from ..analysis import stability_margin
from ..analysis._quantities import stable_speeds
from ._distributions import reaches_zero, support
from ._rotor import RotorQuantities


def preset_key(preset, params, name, option) -> bool:
    """Check that `name` is a `--set` key of `preset` that may scatter or be designed
    (continuous, not the speed: `InputError` naming it and `option` otherwise); returns
    whether it is a positive quantity."""
    if name not in params:
        raise InputError(f"{option} {name}: not a parameter of {preset.name}; its --set keys: {', '.join(params)}")
    if name == preset.speed_key:
        raise InputError(f"{option} {name}: the speed, over which the stability thresholds are found (--range); "
                         "give another key")
    domain = preset.domains.get(name, "any")
    if domain.startswith("int") or domain.startswith("{") or name in preset.topology_keys:
        raise InputError(f"{option} {name}: sets the model's structure (a count, a choice, its topology); only "
                         "continuous keys can be designed or scatter")
    return domain.startswith(">") or domain.startswith("(0") or domain.startswith("[0")


def preset_scatter(preset, params, name, dist, option) -> None:
    """Check that `name` may scatter (`preset_key`) as `dist` does: everything it draws
    (`support`) inside the key's domain, or an `InputError` naming `option`, the key and
    the value it would reach (`eps=normal(0.9, 0.1)` on a key in (0,1) reaches 1.4)."""
    positive = preset_key(preset, params, name, option)
    if positive and reaches_zero(dist):
        raise InputError(f"{option} {name}={dist.text()}: {name} must be {preset.domains[name]} and this "
                         "distribution reaches 0 or below; give lognormal(MEAN, SD), or a narrower one")
    for end in support(dist):
        try:
            preset.check(name, end)
        except InputError as e:
            raise InputError(f"{option} {name}={dist.text()}: reaches {end:g} (within 5 standard deviations, or "
                             f"the ends of a uniform one), and {name} {str(e).split(': ', 1)[1]}; give a narrower "
                             "distribution, or uniform(LO, HI) inside the domain") from None


def preset_quantities(preset, params, inputs, speed_range, *, n_scan=40, option="--dist") -> RotorQuantities:
    """The quantities of `preset` (a `rotorjax.presets.Preset` with a reference motion)
    at `params` as a function of the `--set` keys `inputs` (their names, or `{name:
    distribution}`: what each draws must lie in the key's domain, `preset_scatter`), over
    `speed_range` `(lo, hi)` in the preset's speed unit (the thresholds set up on
    `n_scan` speeds)."""
    names = tuple(inputs)
    for name in names:
        if isinstance(inputs, dict):
            preset_scatter(preset, params, name, inputs[name], option)
        else:
            preset_key(preset, params, name, option)
    if speed_range is None:
        raise InputError(f"--range: give the speeds over which {preset.name}'s thresholds are found, --range LO HI "
                         f"({preset.speed_key})")

    def margin(values, speed):
        return stability_margin(preset.build({**params, **dict(zip(names, values)),
                                              preset.speed_key: speed}).reference)

    nominal = np.array([float(params[k]) for k in names])
    stable = stable_speeds(margin, jnp.asarray(nominal), speed_range, n_scan=n_scan, label=preset.name,
                           unit=preset.units.get(preset.speed_key, ""))
    outputs = stable.outputs()

    def fn(values):
        q = stable.evaluate(values)
        return jnp.stack([q[k] for k in outputs])

    f0 = np.asarray(fn(jnp.asarray(nominal)))
    if not np.all(np.isfinite(f0)):
        raise NumericalError(f"{preset.name}: the nominal quantities are not finite "
                             f"({', '.join(n for n, v in zip(outputs, f0) if not np.isfinite(v))})")
    return RotorQuantities(fn, None, outputs, names, nominal, (), float(params[preset.speed_key]), preset.name,
                           {"range": list(stable.speed_range), "speed_key": preset.speed_key, **stable.settings()})
