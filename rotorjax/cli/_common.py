"""What every command shares: option types that check their values, the range and
grid checks, output folders, presets with `--set`, progress bars.

Every check raises `InputError` (exit 2) with one line that names the option,
`--set` key, file, column or row as the user typed it, and what would be valid.
"""

import argparse
import math
import os
import re
import sys
from typing import NamedTuple

from .._errors import InputError, NumericalError  # noqa: F401  (re-exported for the commands)

def _fe(setup, preset):
    from ..models import provides

    return provides(setup.scene, "shaft")


def _regimes(setup, preset):
    from ..models import ModalBalancerRotor, provides

    scene = setup.scene
    return isinstance(scene, ModalBalancerRotor) or (provides(scene, "to_rotating")
                                                      and len(scene.weight_coordinates()[0]) > 0)


def _traceable(setup, preset):
    """A reference motion whose margin is a traceable function of the parameters: a
    preset's (a rotor file is read from text: its reference, a rotor's equilibrium on
    fluid films, serves `hopf` at its own parameters)."""
    return setup.reference is not None and preset.kind != "rotor"


def _critical(setup, preset):
    from ..models import ModalBalancerRotor

    return isinstance(setup.scene, ModalBalancerRotor) or setup.reference is not None or _fe(setup, preset)


def _hopf(setup, preset):
    from ..analysis import StraightRunning

    return isinstance(setup.reference, StraightRunning)


def _measured(setup, preset):
    from ..models import BalancingScene

    return "rotor_file" in setup.extras or isinstance(setup.scene, BalancingScene)


#: what each command needs of a preset's built `Setup` (its scene's capabilities, its
#: reference motion, its data), and in words for the message when it is missing; the
#: commands that apply to a preset are listed in this order
COMMAND_NEEDS = {
    "simulate": ("an initial state to run from", lambda s, p: s.y0 is not None),
    "steady": ("balancing weights in a rotating frame", _regimes),
    "campbell": ("a finite-element rotor", _fe),
    "response": ("a finite-element rotor", _fe),
    "critical-speeds": ("a reference motion or a finite-element rotor", _critical),
    "stability-map": ("a reference motion traceable in its parameters (a preset)", lambda s, p: _traceable(s, p)),
    "continue": ("a reference motion traceable in its parameters (a preset)", lambda s, p: _traceable(s, p)),
    "hopf": ("straight-line rotation with linear equations", _hopf),
    "bifurcation": ("contacts and sweepable parameters", lambda s, p: s.scene.n_contacts > 0 and bool(p.sweepable)),
    "static": ("a finite-element rotor", _fe),
    "modes": ("a finite-element rotor", _fe),
    "ucs": ("a finite-element rotor", _fe),
    "frf": ("a finite-element rotor", _fe),
    "level1": ("a finite-element rotor", _fe),
    "balance": ("measurements to work from: a rotor file or the balancing machine", _measured),
    "identify": ("measurements to work from: a rotor file or the balancing machine", _measured),
    "uncertainty": ("a rotor file, or a reference motion traceable in its parameters (a preset)",
                    lambda s, p: "rotor_file" in s.extras or _traceable(s, p)),
    "optimize": ("a rotor file, or a reference motion traceable in its parameters (a preset)",
                 lambda s, p: "rotor_file" in s.extras or _traceable(s, p)),
    "draw": ("a scene", lambda s, p: True),
    "report": ("a finite-element rotor", _fe),
}


# ---- option types (argparse reports their errors with the option's name, exit 2) ----

class Given:
    """An option's value given with a unit (`--speed 3600rpm`): converted to the
    target's unit once the target is known (`resolve_units`), then checked as the
    option's bare numbers are (`check`: `finite`, `positive`, `nonnegative`)."""

    def __init__(self, text, check=None, unit=None):
        self.text, self.check, self.unit = text, check, unit

    def __repr__(self):
        return f"Given({self.text!r})"


def _number(text):
    try:
        value = float(text)
    except ValueError:
        if re.match(r"\s*[-+]?(\d|\.\d)", str(text)):
            return Given(str(text).strip())
        raise argparse.ArgumentTypeError(f"expected a number, got {text!r}") from None
    if not math.isfinite(value):
        raise argparse.ArgumentTypeError(f"must be finite, got {text!r}")
    return value


def finite(text):
    """A finite float."""
    return _number(text)


def positive(text):
    """A finite float > 0."""
    value = _number(text)
    if isinstance(value, Given):
        value.check = positive
        return value
    if not value > 0:
        raise argparse.ArgumentTypeError(f"must be > 0, got {text!r}")
    return value


def nonnegative(text):
    """A finite float >= 0."""
    value = _number(text)
    if isinstance(value, Given):
        value.check = nonnegative
        return value
    if not value >= 0:
        raise argparse.ArgumentTypeError(f"must be >= 0, got {text!r}")
    return value


class SpanAction(argparse.Action):
    """`LO HI`, with an optional unit for both (`--range 0 12000 rpm`, `--range "0
    12000 rpm"`) or each (`--range 0rpm 12000rpm`): two values (`Given` where a unit is
    given, else floats). `unit`: the option's own unit, where it is not the target's
    speed unit (`ucs --range`, a stiffness)."""

    def __init__(self, *args, check=None, unit=None, **kwargs):
        super().__init__(*args, **kwargs)
        self.check = finite if check is None else check
        self.unit = unit

    def __call__(self, parser, namespace, values, option_string=None):
        tokens = " ".join(values).split()
        if len(tokens) == 3 and _bare(tokens[2]) is None and not re.match(r"[-+]?(\d|\.\d)", tokens[2]):
            tokens = [f"{tokens[0]} {tokens[2]}", f"{tokens[1]} {tokens[2]}"]
        if len(tokens) != 2:
            raise argparse.ArgumentError(self, f"expected LO HI, optionally with a unit (e.g. {option_string} 0 12000 "
                                               f"rpm), got {' '.join(values)!r}")
        try:
            values = [self.check(t) for t in tokens]
        except argparse.ArgumentTypeError as e:
            raise argparse.ArgumentError(self, str(e)) from None
        for v in values:
            if isinstance(v, Given):
                v.unit = self.unit
        setattr(namespace, self.dest, values)


def _bare(text):
    try:
        return float(text)
    except ValueError:
        return None


#: options whose value is kept under another name (argparse's `dest`)
OPTION_OF = {"start": "--from"}


def option_of(dest):
    """The command-line option that sets `dest`."""
    return OPTION_OF.get(dest, "--" + dest.replace("_", "-"))


def resolve_units(args, units):
    """Every option value given with a unit (`Given`) in `args`, converted in place to
    the option's own unit (`Given.unit`) or else the one `units(dest)` names (None: the
    option takes no unit for this target, an `InputError` naming it) and checked as a
    bare number would be."""
    from rotorjax._units import to_si

    for dest, value in vars(args).items():
        values = value if isinstance(value, list) else [value]
        if not any(isinstance(v, Given) for v in values):
            continue
        option = option_of(dest)
        out = []
        for v in values:
            if isinstance(v, Given):
                unit = v.unit or units(dest)
                if unit is None or unit in ("dimensionless", ""):
                    raise InputError(f"{option} {v.text}: this value has no unit here ({units.why(dest)}); give a "
                                     "number")
                si = to_si(v.text, unit, option, joiner=" ")
                try:
                    v = v.check(repr(si)) if v.check is not None else si
                except argparse.ArgumentTypeError as e:
                    raise InputError(f"{option} {v.text}: {str(e).split(', got')[0]} (it is {si:g} {unit})") \
                        from None
            out.append(v)
        setattr(args, dest, out if isinstance(value, list) else out[0])


def tolerance(text):
    """A relative/absolute tolerance: 0 < tol < 1."""
    value = _number(text)
    if not 0 < value < 1:
        raise argparse.ArgumentTypeError(f"must be in (0, 1), got {text!r}")
    return value


def _word_or_count(words, what):
    """A parser of one of `words` or an integer >= 1 (`what`: "a number of modes")."""
    alternatives = ", ".join(repr(w) for w in words)

    def parse(text):
        if text in words:
            return text
        try:
            value = int(text)
        except ValueError:
            raise argparse.ArgumentTypeError(f"expected {alternatives} or {what}, got {text!r}") from None
        if value < 1:
            raise argparse.ArgumentTypeError(f"must be {alternatives} or an integer >= 1, got {text!r}")
        return value

    return parse


#: 'auto', 'all' or an integer >= 1 (`simulate --modes`)
mode_count = _word_or_count(("auto", "all"), "a number of modes")
#: 'auto' or an integer >= 1 (`periodic --harmonics`)
harmonic_count = _word_or_count(("auto",), "a number of harmonics")


def at_least(lo):
    """An integer >= `lo`."""
    def parse(text):
        try:
            value = int(text)
        except ValueError:
            raise argparse.ArgumentTypeError(f"expected an integer, got {text!r}") from None
        if value < lo:
            raise argparse.ArgumentTypeError(f"must be an integer >= {lo}, got {text!r}")
        return value
    parse.__name__ = f"integer >= {lo}"
    return parse


# ---- ranges, grids, lists ----

def check_range(option, lo, hi, positive_lo=False):
    """`LO HI` of a speed or parameter range: finite, `LO < HI`, and `LO >= 0`
    (`LO > 0` with `positive_lo`)."""
    text = f"{option} {lo:g} {hi:g}"
    if not (math.isfinite(lo) and math.isfinite(hi)):
        raise InputError(f"{text}: LO and HI must be finite")
    if positive_lo and not lo > 0:
        raise InputError(f"{text}: LO must be > 0 (the speed)")
    if not lo >= 0:
        raise InputError(f"{text}: LO must be >= 0")
    if not lo < hi:
        raise InputError(f"{text}: need LO < HI")
    return lo, hi


def param_span(option, preset, key, lo, hi):
    """`LO HI` of a range of the preset parameter `key` (`--range`, `--to`,
    `--range2`): finite, `LO < HI`, each inside the key's valid values."""
    text = f"{option} {lo:g} {hi:g}"
    if not (math.isfinite(lo) and math.isfinite(hi)):
        raise InputError(f"{text}: LO and HI must be finite")
    if not lo < hi:
        raise InputError(f"{text}: need LO < HI")
    for v in (lo, hi):
        try:
            preset.check(key, v)
        except InputError as e:
            raise InputError(f"{text}: {e}") from None
    return lo, hi


def grid_spec(option, spec, preset, params, min_points=2, allowed=None):
    """`KEY LO HI N` of a grid over one preset parameter: the key exists and can be
    varied (not structural), `LO < HI` finite and inside the key's valid values,
    `N >= min_points` an integer."""
    key, lo, hi, n = spec
    text = f"{option} {' '.join(spec)}"
    if key not in preset.defaults:
        raise InputError(f"{text}: unknown parameter {key!r} for {preset.name}; known: "
                         f"{', '.join(sorted(preset.defaults))}")
    if allowed is not None and key not in allowed:
        raise InputError(f"{text}: {key!r} cannot be varied here; one of {', '.join(allowed)}")
    if key in preset.topology_keys or key in preset.integer_keys:
        raise InputError(f"{text}: {key!r} changes the scene's structure and cannot be varied")
    values = []
    for what, raw in (("LO", lo), ("HI", hi)):
        try:
            values.append(preset.check(key, raw))
        except InputError as e:
            raise InputError(f"{text}: {what} {e}") from None
    lo, hi = values
    if not lo < hi:
        raise InputError(f"{text}: need LO < HI")
    try:
        n = int(n)
    except ValueError:
        raise InputError(f"{text}: the number of points must be an integer, got {spec[3]!r}") from None
    if n < min_points:
        raise InputError(f"{text}: the number of points must be >= {min_points}")
    return key, float(lo), float(hi), n


def int_list(option, text, lo=0):
    """A comma-separated list of distinct integers >= `lo` (`--planes 0,1`)."""
    try:
        values = [int(v) for v in text.split(",") if v.strip()]
    except ValueError:
        raise InputError(f"{option} {text}: expected comma-separated integers") from None
    if not values:
        raise InputError(f"{option} {text!r}: empty list")
    if any(v < lo for v in values):
        raise InputError(f"{option} {text}: values must be >= {lo}")
    if len(set(values)) != len(values):
        raise InputError(f"{option} {text}: a value is repeated")
    return values


def name_list(option, text, known):
    """A comma-separated list of distinct names from `known` (`--fit k1,k2`)."""
    names = [v.strip() for v in text.split(",") if v.strip()]
    if not names:
        raise InputError(f"{option} {text!r}: empty list; choose from {', '.join(known)}")
    unknown = [v for v in names if v not in known]
    if unknown:
        raise InputError(f"{option} {text}: unknown {', '.join(map(repr, unknown))}; choose from "
                         f"{', '.join(known)}")
    repeated = sorted({v for v in names if names.count(v) > 1})
    if repeated:
        raise InputError(f"{option} {text}: {', '.join(repeated)} given more than once")
    return tuple(names)


# ---- output ----

#: where a command writes its files without `--out`: a folder in the current directory, never the
#: installed package nor the folder of a shipped rotor file
DEFAULT_OUT = "rotorjax-out"


def use_agg():
    """Matplotlib's non-interactive backend (Agg) for the command's pictures. The CLI
    chooses it (`rotorjax.plot` chooses none), before its first figure, so that a
    command run without a display never tries to open one."""
    import matplotlib

    matplotlib.use("Agg")


def save_figure(fig, path, **kwargs):
    """Write `fig` (a `rotorjax.plot` figure) as a PNG at `path` (120 dpi unless
    `kwargs` say otherwise), close it, and return `path`."""
    import matplotlib.pyplot as plt

    kwargs.setdefault("dpi", 120)
    try:
        fig.savefig(path, **kwargs)
    finally:
        plt.close(fig)
    return path


def prepare_out(path, option="--out"):
    """Create the output folder `path` (before any computing) or say why it cannot be;
    the command will draw, so matplotlib's backend is set to Agg (`use_agg`)."""
    use_agg()
    if os.path.exists(path) and not os.path.isdir(path):
        raise InputError(f"{option} {path}: exists and is not a folder")
    try:
        os.makedirs(path, exist_ok=True)
    except OSError as e:
        raise InputError(f"{option} {path}: cannot create the folder ({e.strerror})") from None
    if not os.access(path, os.W_OK | os.X_OK):
        raise InputError(f"{option} {path}: the folder is not writable")
    return path


# ---- presets ----

def parse_sets(items):
    """`--set KEY=VALUE` items as a dict; repeated keys keep the last."""
    out = {}
    for item in items or ():
        if "=" not in item:
            raise InputError(f"--set expects KEY=VALUE, got {item!r}")
        key, value = item.split("=", 1)
        if not key.strip():
            raise InputError(f"--set {item!r}: empty KEY")
        out[key.strip()] = value.strip()
    return out


def preset_params(preset, sets, extra=None):
    """The preset's parameters with `--set` (and `extra`, e.g. `{speed_key: --speed}`)
    applied, every value checked against its domain."""
    sets = parse_sets(sets)
    try:
        params = preset.params(sets)
    except InputError as e:
        raise InputError(f"--set {e}") from None
    for key, (option, value) in (extra or {}).items():
        try:
            params[key] = preset.check(key, value)
        except InputError as e:
            raise InputError(f"{option} {value:g}: {str(e).split(': ', 1)[1]}") from None
    return params


def get_preset(name):
    """A preset by name, or a rotor file's (a path ending in `.toml`)."""
    from .. import presets

    try:
        return presets.get(name)
    except InputError as e:
        if str(e).startswith("unknown preset"):
            raise InputError(f"{e} (`rotorjax presets` lists them)") from None
        raise


def is_rotor_file(preset) -> bool:
    """Whether `preset` is a rotor file's (its `Setup.extras` names the file)."""
    return "rotor_file" in build(preset, preset.params()).extras


def applicable(preset, setup=None) -> list:
    """The commands that apply to `preset` (built at its defaults unless `setup` is
    given), in `COMMAND_NEEDS`' order."""
    setup = build(preset, preset.params()) if setup is None else setup
    return [c for c, (_, needs) in COMMAND_NEEDS.items() if needs(setup, preset)]


def wrong_kind(preset, command, setup=None):
    """`command` does not apply to `preset`: what it needs, and the commands that do."""
    what = COMMAND_NEEDS[command][0]
    ok = applicable(preset, setup)
    use = ("use " + ", ".join(f"`{c}`" for c in ok)) if ok else "no command applies to it"
    return InputError(f"`{command}` does not apply to {preset.name!r}: it needs {what}; {use}")


def preset_and_params(args, command, speed_option=None):
    """The preset named on the command line, checked to offer what `command` needs
    (`COMMAND_NEEDS`, on the preset built at its defaults), and its parameters with
    the `--set` overrides applied (and `--speed`, when `speed_option` is given, as the
    preset's speed key)."""
    preset = get_preset(args.preset)
    setup = build(preset, preset.params())
    if not COMMAND_NEEDS[command][1](setup, preset):
        raise wrong_kind(preset, command, setup)
    extra = None if speed_option is None else {preset.speed_key: ("--speed", speed_option)}
    return preset, preset_params(preset, args.set, extra)


def build(preset, params):
    """`preset.build(params)` (a `Setup`); an invalid combination of values is bad input."""
    try:
        return preset.build(params)
    except ZeroDivisionError:
        raise InputError(f"{preset.name}: the --set values make a degenerate scene (a division by zero)") \
            from None


def fe_rotor(scene):
    """The `FlexibleRotor` (or `ReducedRotor`) of a finite-element rotor scene."""
    from rotorjax.models import RotorScene

    if not isinstance(scene, RotorScene):
        raise InputError(f"needs a finite-element rotor (RotorScene), got {type(scene).__name__}")
    return scene.rotor


class Study(NamedTuple):
    """What the stability commands ask of a preset at its parameters, from its
    reference motion (`Setup.reference`): the margin as a function of the
    parameters, the regime's name, how boundary tangents are differentiated, and
    (where the reference is of that kind) its branch as a root problem or its
    Floquet analysis along a parameter."""

    margin: object
    margins: object
    regime: str
    gradient: str
    branch_problem: object = None
    floquet_family: object = None
    published: tuple = ()


def stability_study(preset, params, setup=None):
    """The preset's `Study` at `params` (`setup`: the preset built there already), or
    None where its scene has no reference motion."""
    from rotorjax.analysis import PeriodicOrbit, branch_problem, floquet_family, stability_margin, stability_margins

    setup = build(preset, params) if setup is None else setup
    ref = setup.reference
    if not _traceable(setup, preset):
        return None

    def at(p):
        return preset.build(p).reference

    periodic = isinstance(ref, PeriodicOrbit)
    return Study(
        margin=lambda p: stability_margin(at(p)),
        margins=lambda points, chunk, bar: stability_margins(lambda p: at(dict(params, **p)), points, chunk, bar),
        regime=ref.label,
        gradient=margin_gradient_of(ref),
        branch_problem=None if periodic else (
            lambda q, key: branch_problem(lambda v: at(dict(q, **{key: v})), q[key])),
        floquet_family=(lambda q, key: floquet_family(lambda v: at(dict(q, **{key: v})))) if periodic else None,
        published=setup.published)


def margin_gradient_of(ref) -> str:
    from rotorjax.analysis import NoReference, margin_gradient

    return "autodiff" if isinstance(ref, NoReference) else margin_gradient(ref)


def speed_warnings(system, lo, hi=None):
    """Plausibility warnings for the speeds an analysis uses (`lo` to `hi`, rad/s): a
    speed-tabulated bearing used outside its table (`rotorjax.models.check_speeds`);
    and the refusal of speeds <= 0 on journal bearings (no equilibrium to linearise
    about: the film carries its load only while the shaft spins)."""
    from ..models import RotorScene, check_speeds
    from ..models._equilibrium import films

    if isinstance(system, RotorScene) and not lo > 0 and any(c.spins for c in films(system)):
        raise InputError(f"speed {lo:g} rad/s: a rotor on journal bearings has linear equations only while it "
                         f"spins (its equilibrium in the films needs a speed > 0); start the speeds above 0")
    return check_speeds(system, [lo] if hi is None else [lo, hi])


def operating_speed(preset, params):
    """The rotor's operating speed (rad/s): a rotor file's `[rotor] speed` (with `--set
    speed=`), 0 for a preset without one."""
    return float(params.get(preset.speed_key, 0.0)) if preset.speed_key else 0.0


# ---- presenting ----

def progress(total, desc, enabled=True):
    """A tqdm bar on stderr (a no-op object when disabled)."""
    from tqdm.auto import tqdm

    return tqdm(total=total, desc=desc, disable=not enabled, file=sys.stderr, leave=False)


class Stages:
    """Progress through the named stages of a command whose work is a few long
    compiled calls (a bar on stderr that advances as each stage starts; silent when
    `enabled` is false, e.g. with `--json`)."""

    def __init__(self, command, n_stages, enabled=True):
        self.bar = progress(n_stages, command, enabled)
        self.started = False

    def __call__(self, stage):
        if self.started:
            self.bar.update(1)
        self.started = True
        self.bar.set_postfix_str(stage, refresh=True)

    def close(self):
        self.bar.update(self.bar.total - self.bar.n)
        self.bar.close()


def design_target(args, command):
    """`(preset, params, overrides)` of `optimize` and `uncertainty`: the target (a rotor
    file, its parameters addressed by their rotor-file names; or a preset with a
    reference motion, by its `--set` keys), its parameters with the `--set` values
    applied, and those that differ from its own."""
    preset, params = preset_and_params(args, command)
    return preset, params, {k: v for k, v in params.items() if v != preset.defaults.get(k)}


def out_stem(folder, preset, prefix="", suffix=""):
    """`folder/PREFIX NAME SUFFIX`, the stem of a command's output files; a rotor
    file's preset is named by its path, of which the file name without `.toml` is used."""
    name = os.path.basename(preset.name)
    name = name[:-len(".toml")] if name.endswith(".toml") else name
    return os.path.join(folder, f"{prefix}{name}{suffix}")


#: the plausibility warnings of the running command (`collect_warnings`), in order
WARNINGS = []


def collect_warnings():
    """Route `PlausibilityWarning`s (and the other `UserWarning`s rotorjax issues) to
    stderr as one line each, `rotorjax: warning: ...`, and to `WARNINGS`, which
    `write_json` adds to every JSON output. Returns the `warnings.catch_warnings`
    context to enter around a command."""
    import warnings

    from .._errors import PlausibilityWarning

    ctx = warnings.catch_warnings()

    class _Collect:
        def __enter__(self):
            ctx.__enter__()
            WARNINGS.clear()
            warnings.simplefilter("always", PlausibilityWarning)
            other = warnings.showwarning

            def show(message, category, filename, lineno, file=None, line=None):
                if not issubclass(category, PlausibilityWarning):
                    return other(message, category, filename, lineno, file, line)
                text = str(message)
                if text not in WARNINGS:
                    WARNINGS.append(text)
                    print(f"rotorjax: warning: {text}", file=sys.stderr)

            warnings.showwarning = show
            return self

        def __exit__(self, *exc):
            return ctx.__exit__(*exc)

    return _Collect()


def with_warnings(obj):
    """`obj` (a JSON object) with the command's plausibility warnings added to its
    `warnings` list (created when absent)."""
    if WARNINGS and isinstance(obj, dict):
        have = list(obj.get("warnings") or [])
        obj["warnings"] = have + [w for w in WARNINGS if w not in have]
    elif isinstance(obj, dict) and "warnings" not in obj:
        obj["warnings"] = []
    return obj


def write_json(path, obj, **kwargs):
    """Write `obj` as JSON, with the command's warnings (`with_warnings`); `obj` is
    updated in place, so a later `print(json.dumps(obj))` shows them too."""
    import json

    with_warnings(obj)
    with open(path, "w") as f:
        json.dump(obj, f, **kwargs)
