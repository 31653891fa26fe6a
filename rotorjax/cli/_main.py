"""The parser and the exit codes: 0 success, 2 bad input, 3 numerical failure,
1 an unexpected internal error (one line; `--debug` shows the traceback)."""

import argparse
import re
import sys

from ..analysis._quantities import SENSES
from ..identify import FITTABLE
from ..presets import PRESETS
from ._balance import cmd_balance, cmd_identify
from ._optimize import cmd_optimize
from ._uncertainty import cmd_uncertainty
from ._bench import cmd_bench
from ._output_units import UNITS_OPTION
from ._common import (InputError, NumericalError, SpanAction, at_least, collect_warnings, finite, get_preset,
                      harmonic_count, mode_count, nonnegative, option_of, positive, resolve_units, tolerance)
from ._contact import cmd_bifurcation
from ._continue import cmd_continue
from ._fe_analyses import cmd_modes, cmd_static
from ._fe_analyses import cmd_frf, cmd_level1, cmd_ucs, point_spec
from ._flexible import unbalance_spec
from ._flexible import cmd_campbell, cmd_response
from ._draw import cmd_draw
from ._report import cmd_report
from ._import import cmd_import_ross
from ._info import cmd_data, cmd_demo, cmd_presets
from ._periodic import cmd_periodic
from ._phasors import cmd_phasors
from ._simulate import cmd_simulate
from ._stability import HOPF_RANGE, cmd_critical_speeds, cmd_hopf, cmd_stability_map, cmd_steady

PRESET_NAMES = tuple(PRESETS)
#: the quantities `optimize` optimises and `uncertainty --output` propagates
QUANTITIES = tuple(SENSES)
#: the keys `bifurcation` can sweep (on the presets that sweep)
SWEEPABLE = tuple(dict.fromkeys(k for p in PRESETS.values() for k in p.sweepable))
SOLVERS = ("auto", "dopri8", "dopri5", "tsit5", "kvaerno5", "kvaerno3")


class _Parser(argparse.ArgumentParser):
    """argparse, with every number a value: `--unbalance -1e-3` and `--range -1e3 5`
    reach the option's own check (`must be > 0`) instead of argparse's "expected one
    argument" (argparse takes only `-1` and `-1.5` for numbers, not `-1e-3`)."""

    def __init__(self, *args, **kwargs):
        super().__init__(*args, **kwargs)
        self._negative_number_matcher = re.compile(r"^-(\d+\.?\d*|\.\d+)([eE][-+]?\d+)?$|^-(inf|nan)$", re.I)


class _Formatter(argparse.RawDescriptionHelpFormatter):
    """Helps with each option's default appended (when it has one)."""

    def _get_help_string(self, action):
        text = action.help or ""
        if "%(default)" not in text and action.default not in (None, False, argparse.SUPPRESS) \
                and action.option_strings:
            text += " (default: %(default)s)"
        return text


def _debug_flag(p):
    p.add_argument("--debug", action="store_true", default=argparse.SUPPRESS,
                   help="show the Python traceback of an internal error")


def _common_flags(p, out=True, json_help="print the result as JSON on stdout"):
    p.add_argument("--json", action="store_true", help=json_help)
    if out:
        p.add_argument("--out", default="rotorjax-out", metavar="DIR",
                       help="folder for the plots and data files (created if absent)")
    _debug_flag(p)


def _command(sub, name, help, fn, flags=(), kinds="", description=None):
    """A subcommand on a preset, with the shared `--set`, `--json`, `--out`."""
    p = sub.add_parser(name, help=help, formatter_class=_Formatter,
                       description=(description or help) + (f"\n\nApplies to: {kinds}." if kinds else "")
                       + "\n\nExit codes: 0 success, 2 bad input, 3 numerical failure.")
    p.add_argument("preset", metavar="PRESET",
                   help=f"one of: {', '.join(PRESET_NAMES)}, or a rotor file ROTOR.toml (`rotorjax presets NAME` "
                        "lists its --set keys)")
    p.add_argument("--set", action="append", metavar="KEY=VALUE",
                   help="override a preset parameter, in the preset's units (repeatable; a rotor file's keys "
                        "name their table, e.g. bearing0.kxx); `rotorjax presets PRESET` lists the keys, units "
                        "and valid values")
    _common_flags(p)
    for args, kwargs in flags:
        p.add_argument(*args, **kwargs)
    p.set_defaults(fn=fn)
    return p


def _range(required=True, help="speed range"):
    return (("--range",), dict(nargs="+", action=SpanAction, metavar=("LO", "HI"), required=required,
                               default=None, help=help + "; a unit may follow (0 12000 rpm)"))


class _OptionUnits:
    """The unit each option with a unit takes for the target on the command line: the
    speed options the target's speed unit (rad/s for a rotor file), `--range` of
    `continue` and `periodic` (and `periodic`'s `--from`) the unit of their `--param`."""

    SPEED = ("speed", "operating", "range", "speed_range", "shape_at")

    def __init__(self, args):
        self.args = vars(args)
        name = self.args.get("preset")
        self.preset = None if name is None else get_preset(name)
        self.command = self.args["fn"].__name__.removeprefix("cmd_")

    def _key(self, dest):
        if self.preset is None:
            return None
        if (dest == "range" and self.command in ("continue", "periodic")) or (dest, self.command) == ("start",
                                                                                                     "periodic"):
            return self.args.get("param")
        if (dest, self.command) == ("range2", "periodic"):
            return self.args.get("param2")
        return self.preset.speed_key if dest in self.SPEED else None

    def __call__(self, dest):
        key = self._key(dest)
        return None if key is None else self._unit(key)

    def _unit(self, key):
        """`key`'s unit; a speed that is no --set key (ross-compare's) is in rad/s."""
        return self.preset.units.get(key, "rad/s" if key == self.preset.speed_key else None)

    def why(self, dest):
        key = self._key(dest)
        if key is None:
            return f"{option_of(dest)} takes a number"
        return f"{self.preset.name}'s {key} is {self._unit(key) or 'without a unit'}"


def _integration(max_steps):
    return [
        (("--solver",), dict(default="auto", choices=SOLVERS,
                             help="ODE solver; auto picks Dopri8, or Kvaerno5 where a decaying eigenvalue makes "
                                  "the scene stiff over the run (said in the output)")),
        (("--rtol",), dict(type=tolerance, default=1e-8, help="relative tolerance of the step-size control")),
        (("--atol",), dict(type=tolerance, default=1e-10, help="absolute tolerance (state units)")),
        (("--max-steps",), dict(type=at_least(1), default=max_steps,
                                help="step budget; reaching it is reported as a failure (exit 3)")),
    ]


def build_parser():
    parser = _Parser(
        prog="rotorjax", formatter_class=_Formatter,
        description="Differentiable rotordynamics: published rotor models, their stationary regimes, "
                    "stability, simulation, balancing and identification.\n\n`rotorjax presets` lists the "
                    "presets; `rotorjax COMMAND --help` explains a command's options.",
        epilog="Exit codes: 0 success, 2 bad input, 3 numerical failure, 1 internal error.")
    parser.add_argument("--debug", action="store_true", help="show the Python traceback of an internal error")
    sub = parser.add_subparsers(dest="command", required=True, metavar="COMMAND")
    _command(sub, "simulate", "simulate a preset scene (or a rotor file's rotor) in time", cmd_simulate, [
        (("--speed",), dict(type=finite, default=None, metavar="W",
                            help="constant speed: rad/s for a rotor file, the preset's speed (nu, n, N) for a "
                                 "preset (default: the file's or preset's)")),
        (("--t-end",), dict(type=positive, default=None,
                            help="end time in the preset's time unit (default: the preset's)")),
        *_integration(500_000),
        (("--n-save",), dict(type=at_least(2), default=None,
                             help="saved states (default 4000; cantilever-limiters: 40 per revolution)")),
        (("--modes",), dict(type=mode_count, default="auto", metavar="auto|all|N",
                            help="a rotor file's shaft in the run: auto (reduced to its lower modes where the "
                                 "full shaft's top modes would make an explicit run pass the step budget; "
                                 "said in the output), all, or the N lowest modes")),
    ], kinds="elliptic-abb, anisotropic-abb, cantilever-limiters, rotor files")
    _command(sub, "steady", "all stationary regimes at a speed (rotating frame)", cmd_steady, [
        (("--speed",), dict(type=finite, required=True,
                            help="the preset's (dimensionless) speed: nu, n or omega")),
        (("--n-angles",), dict(type=at_least(1), default=16, help="starting guesses per weight angle")),
    ], kinds="elliptic-abb, flexible-abb (with --set n_balls=2)")
    _command(sub, "critical-speeds", "speeds where stability changes (planar, contact) or 1x crossings "
             "(flexible)", cmd_critical_speeds, [
                 _range(help="speed range, in the preset's speed unit (rad/s for ross-compare)"),
                 (("--n-scan",), dict(type=at_least(2), default=200,
                                      help="scan points before bisection (roots closer than a scan step "
                                           "may be missed)")),
                 (("--modes",), dict(type=at_least(1), default=None,
                                     help="modes tracked (ross-compare, default 8) or shaft modes "
                                          "(flexible-abb)")),
                 UNITS_OPTION,
                 (("--exact",), dict(action="store_true", help="flexible-abb: the closed-form equation (17)")),
             ], kinds="elliptic-abb, anisotropic-abb, ross-compare, flexible-abb, cantilever-limiters, rotor files")
    _command(sub, "stability-map", "stability margin over a 2-D parameter grid", cmd_stability_map, [
        (("--x",), dict(nargs=4, metavar=("KEY", "LO", "HI", "NX"), required=True,
                        help="the x axis: a --set key, its range and number of points (>= 2)")),
        (("--y",), dict(nargs=4, metavar=("KEY", "LO", "HI", "NY"), required=True,
                        help="the y axis: a --set key, its range and number of points (>= 2)")),
        (("--chunk",), dict(type=at_least(1), default=32, help="grid points per vmapped call")),
    ], kinds="elliptic-abb, anisotropic-abb, flexible-abb, cantilever-limiters")
    _command(sub, "campbell", "Campbell diagram of a flexible rotor", cmd_campbell, [
        _range(help="speed range, rad/s (LO >= 0)"),
        (("--n-speeds",), dict(type=at_least(2), default=100, help="speeds in the range")),
        UNITS_OPTION,
        (("--modes",), dict(type=at_least(1), default=8, help="modes shown")),
        (("--reduce",), dict(type=int, default=None, metavar="N",
                             help="reduce to the N lowest undamped modes first (ReducedRotor)")),
    ], kinds="ross-compare, rotor files")
    _command(sub, "response", "unbalance response of a flexible rotor", cmd_response, [
        _range(help="speed range, rad/s (LO > 0)"),
        (("--n",), dict(type=at_least(2), default=2000, help="number of speeds")),
        (("--node",), dict(type=at_least(0), default=None,
                           help="node of a bare --unbalance MAG (default: the rotor's unbalance's node, else its "
                                "heaviest disk's); alone, moves the rotor's single unbalance")),
        (("--probe",), dict(type=at_least(0), default=None,
                            help="node where the response is read (default: the node of largest response)")),
        (("--unbalance",), dict(type=unbalance_spec, action="append", default=None, metavar="U|NODE,MAG,PHASE",
                                help="unbalance magnitude, kg m, at --node with --phase; or NODE,MAG,PHASE (kg m, "
                                     "rad), repeatable: these unbalances act together (default: the rotor's own, "
                                     "a rotor file's [[unbalance]] tables)")),
        (("--phase",), dict(type=finite, default=None, help="phase of a bare --unbalance MAG, rad (default 0)")),
        UNITS_OPTION,
        (("--shape-at",), dict(type=positive, default=None, metavar="W",
                               help="also plot the deflected shape (orbit major axis along the shaft) at "
                                    "speed W, rad/s")),
        (("--reduce",), dict(type=int, default=None, metavar="N",
                             help="reduce to the N lowest undamped modes first (ReducedRotor)")),
    ], kinds="ross-compare, rotor files")
    _command(sub, "static", "static deflection, bearing reactions, shear and moment under gravity", cmd_static, [
        (("--gravity",), dict(type=finite, default=9.80665, metavar="G",
                              help="gravitational acceleration, m/s^2, acting along -AXIS")),
        UNITS_OPTION,
        (("--axis",), dict(default="y", choices=("x", "y"), help="the vertical axis")),
        (("--speed",), dict(type=positive, default=None, metavar="W",
                            help="running speed, rad/s, of a rotor on fluid-film bearings (default: the rotor "
                                 "file's [rotor] speed): the journals' equilibrium at that speed")),
    ], kinds="ross-compare, rotor files",
        description="static deflection under gravity (bearings at rest, supports included): the bearing "
                    "reactions (the force each bearing exerts on the shaft), and the shear force and bending "
                    "moment along the shaft (sagging positive, dM/dz = V; ROSS reports -V and -M)")
    _command(sub, "modes", "damped modes at a speed: frequencies, damping, whirl, mode shapes", cmd_modes, [
        (("--speed",), dict(type=nonnegative, default=None, metavar="W",
                            help="spin speed, rad/s (>= 0: the whirl labels refer to the positive spin; default: the "
                                 "rotor file's [rotor] speed, else 0)")),
        UNITS_OPTION,
        (("--n-modes",), dict(type=at_least(1), default=6, metavar="N", help="modes shown, lowest first")),
    ], kinds="ross-compare, rotor files")
    _command(sub, "ucs", "undamped critical speed map against bearing stiffness", cmd_ucs, [
        (("--range",), dict(nargs="+", action=SpanAction, unit="N/m", metavar=("KLO", "KHI"), default=(1e5, 1e10),
                            help="bearing stiffness range, N/m, or with a unit (1e5 1e10 N/m) (0 < KLO < KHI, "
                                 "log-spaced)")),
        UNITS_OPTION,
        (("--n",), dict(type=at_least(2), default=60, help="stiffness values")),
        (("--n-modes",), dict(type=at_least(1), default=4, metavar="M", help="critical speeds per stiffness")),
        (("--synchronous",), dict(action="store_true",
                                  help="forward synchronous critical speeds (It - Ip) instead of the "
                                       "frequencies at rest (ROSS's synchronous=True)")),
    ], kinds="ross-compare, rotor files",
        description="undamped critical speed map: every bearing replaced by an isotropic spring k (no damping, "
                    "cross-coupling or pedestal), critical speeds against k (ROSS's run_ucs), with the bearings' "
                    "kxx, kyy against speed and their intersections: the critical speeds on the real bearings")
    _command(sub, "frf", "frequency-response function between two dofs (Bode and polar plots)", cmd_frf, [
        (("--input",), dict(type=point_spec, required=True, metavar="NODE,DIR",
                            help="the force: node and direction x or y, e.g. 2,x")),
        (("--output",), dict(type=point_spec, required=True, metavar="NODE,DIR",
                             help="the response: node and direction x or y")),
        _range(help="excitation frequency range, rad/s (0 <= LO < HI)"),
        UNITS_OPTION,
        (("--n",), dict(type=at_least(2), default=1000, help="number of frequencies")),
        (("--kind",), dict(default="displacement", choices=("displacement", "velocity", "acceleration"),
                           help="response per unit force: displacement, velocity or acceleration")),
        (("--speed",), dict(type=nonnegative, default=None, metavar="W",
                            help="fixed running speed, rad/s (default: the rotor runs at the excitation "
                                 "frequency, as ROSS's run_freq_response); bearings at the running speed")),
    ], kinds="ross-compare, rotor files")
    _command(sub, "level1", "API 684 level I stability screening (cross-coupled stiffness at mid-span)",
             cmd_level1, [
                 (("--speed",), dict(type=nonnegative, default=None, metavar="W",
                                     help="running speed, rad/s (API 684: the maximum continuous speed; default: "
                                          "the rotor file's [rotor] speed)")),
                 (("--node",), dict(type=at_least(0), default=None, metavar="N",
                                    help="node of the cross-coupling (default: mid-span between the outer "
                                         "bearings)")),
                 (("--q-max",), dict(type=positive, default=None, metavar="Q",
                                     help="largest cross-coupled stiffness, N/m (default: the largest bearing "
                                          "stiffness)")),
                 (("--n",), dict(type=at_least(2), default=41, help="values of Q from 0 to --q-max")),
                 UNITS_OPTION,
             ], kinds="ross-compare, rotor files",
             description="API 684 level I screening: cross-coupled stiffness kxy = +Q, kyx = -Q (destabilising "
                         "forward whirl) at a node, the log decrement of the first forward mode against Q at the "
                         "running speed, and the threshold Q0 where it crosses zero (exit 3, q0 null in the "
                         "JSON, when it does not within --q-max)")
    _command(sub, "hopf", "Hopf point: straight-line rotation (internal friction), or the oil-whirl onset of a "
                          "rotor on fluid-film bearings", cmd_hopf, [
        _range(required=False, help=f"spin-speed range: N in units 1/T* for a preset (default: {HOPF_RANGE[0]:g} "
                                    f"{HOPF_RANGE[1]:g}), rad/s for a rotor file (required)"),
        (("--n-scan",), dict(type=at_least(2), default=80, help="scan points before bisection")),
    ], kinds="cantilever-limiters, rotor files with journal bearings")
    _command(sub, "bifurcation", "extrema diagram over a swept parameter (one batch of runs)", cmd_bifurcation, [
        (("--param",), dict(nargs=4, metavar=("KEY", "LO", "HI", "NP"), required=True,
                            help=f"the swept --set key (one of {', '.join(SWEEPABLE)}), its range and number "
                                 "of points (>= 2)")),
        *_integration(1_000_000),
        (("--batch",), dict(choices=("auto", "vectorised", "buffered", "vmap"), default="auto",
                            help="buffered: every run advances by its own adaptive steps in a fixed set of "
                                 "lanes refilled as runs finish; vectorised: the same, the lanes stepped "
                                 "together as arrays (explicit solvers, no events); auto: vectorised where it "
                                 "applies, else buffered (default); vmap: the previous lock-step chunks")),
        (("--lanes",), dict(type=at_least(1), default=None,
                            help="runs integrated at once by the buffered batch (default: all, up to 128)")),
        (("--chunk",), dict(type=at_least(1), default=None,
                            help="--batch vmap: lanes per vmapped call (default: up to 16, so that progress "
                                 "shows)")),
    ], kinds="cantilever-limiters")
    _command(sub, "continue", "continuation: a branch in one parameter, or a stability boundary in two",
             cmd_continue, [
                 (("--param",), dict(required=True, metavar="KEY", help="the continued --set key")),
                 (("--param2",), dict(default=None, metavar="KEY",
                                      help="second --set key: trace the stability boundary in (KEY, KEY2)")),
                 (("--from",), dict(dest="start", type=finite, nargs="+", default=None, metavar="VALUE",
                                    help="starting value(s) of --param (and --param2) (default: the preset's)")),
                 (("--to",), dict(type=finite, nargs=2, default=None, metavar=("LO", "HI"),
                                  help="range of --param, one-parameter continuation (default: the start "
                                       "halved and doubled)")),
                 (("--box",), dict(type=finite, nargs=4, default=None, metavar=("LO1", "HI1", "LO2", "HI2"),
                                   help="parameter box of a boundary (default: the start halved and doubled)")),
                 (("--ds",), dict(type=positive, default=0.02, help="first arclength step (parameter units)")),
                 (("--ds-max",), dict(type=positive, default=0.2, help="largest arclength step")),
                 (("--max-points",), dict(type=at_least(2), default=200, help="points per direction at most")),
                 (("--direction",), dict(default="both", choices=("both", "up", "down", "+1", "-1", "1"),
                                         help="trace from the start both ways, or towards increasing (up) "
                                              "or decreasing (down) --param2 (--param for a branch)")),
                 (("--gradient",), dict(default="auto", choices=("auto", "autodiff", "fd"),
                                        help="tangents by autodiff or central differences (Floquet margins)")),
                 (("--switch",), dict(action="store_true",
                                      help="one-parameter branch: also trace the branch that crosses it at each "
                                           "refined branch point (over the same range)")),
             ], kinds="all presets with a reference regime")
    _command(sub, "periodic", "periodic forced motions continued in one parameter (harmonic balance or "
             "shooting): amplitude, stability, folds and bifurcations", cmd_periodic, [
                 (("--param",), dict(required=True, metavar="KEY",
                                     help="the continued --set key (a rotor file: speed)")),
                 _range(help="range of --param (the start must lie in it)"),
                 (("--from",), dict(dest="start", type=finite, default=None, metavar="V",
                                    help="starting value of --param, a unit may follow as for --range (default: "
                                         "the preset's value where it lies in --range, else the range's end "
                                         "nearest to it)")),
                 (("--from-hopf",), dict(action="store_true",
                                         help="the limit cycles born at the lowest Hopf point of the reference "
                                              "motion in --range (a journal rotor's oil whirl): an autonomous "
                                              "scene (no unbalance), --param the speed; harmonic balance, "
                                              "--harmonics auto taking 8")),
                 (("--hopf-amplitude",), dict(type=positive, default=None, metavar="A",
                                              help="--from-hopf: the first cycle's first-harmonic amplitude in "
                                                   "the state where the critical mode is largest (default: 1e-2 "
                                                   "of the equilibrium's largest state)")),
                 (("--harmonics",), dict(type=harmonic_count, default="auto", metavar="H",
                                         help="harmonics of the Fourier series: a number, or auto (each point's "
                                              "fewest of 1, 2, 4, ... --max-harmonics whose truncation error "
                                              "estimate is below --truncation-tol)")),
                 (("--truncation-tol",), dict(type=tolerance, default=1e-6,
                                              help="--harmonics auto: the truncation error estimate each point is "
                                                   "held below (the left-out harmonics' correction, relative to "
                                                   "the motion); exit 3 where --max-harmonics do not reach it")),
                 (("--max-harmonics",), dict(type=at_least(1), default=32, metavar="H",
                                             help="--harmonics auto: the most harmonics a point may take")),
                 (("--method",), dict(default="hb", choices=("hb", "shooting"),
                                      help="hb: harmonic balance; shooting: Newton on the closure after one "
                                           "period, integrated in --steps fixed Dopri8 steps")),
                 (("--steps",), dict(type=at_least(1), default=256,
                                     help="--method shooting: fixed integration steps per period")),
                 (("--max-time-residual",), dict(type=positive, default=1e-3,
                                                 help="fixed --harmonics: the largest time-domain residual of a "
                                                      "point's reconstructed orbit (relative truncation error) "
                                                      "accepted before exit 3")),
                 (("--node",), dict(type=at_least(0), default=None, metavar="N",
                                    help="amplitude of this node's orbit (default: the scene's whirl_amplitude)")),
                 (("--subharmonic",), dict(type=at_least(1), default=1, metavar="K",
                                           help="period K times the forcing's (2 pi / speed)")),
                 (("--ds",), dict(type=positive, default=None,
                                  help="first arclength step (default: the range / 100)")),
                 (("--ds-max",), dict(type=positive, default=None,
                                      help="largest arclength step (default: the range / 10)")),
                 (("--max-points",), dict(type=at_least(2), default=300, help="points per direction at most")),
                 (("--switch",), dict(action="store_true",
                                      help="also trace the branch that crosses at each refined branch point (a "
                                           "symmetric motion's symmetry-breaking pitchfork), over the same "
                                           "range, with the harmonics of the point it crosses at")),
                 (("--param2",), dict(default=None, metavar="KEY",
                                      help="a second --set key (--param the speed): each fold of the branch "
                                           "continued in (speed, KEY), the jump boundary, and the amplitude's "
                                           "derivative in KEY at every point (harmonic balance)")),
                 (("--range2",), dict(nargs="+", action=SpanAction, metavar=("LO", "HI"), default=None,
                                      help="range of --param2 for the fold curves, a unit may follow (default: "
                                           "its value halved and doubled)")),
             ], kinds="rotor files (in speed); presets with a constant speed and a rest state",
             description="the branch of periodic motions forced at the speed (or a subharmonic of it), by harmonic "
                         "balance continued by pseudo-arclength through folds, from the rest state at --from: the "
                         "amplitude, Floquet stability (Hill's exponents) and the folds, branch points, period "
                         "doublings and Neimark-Sacker points along it; writes a CSV, a JSON summary and a plot. "
                         "Exit 3 when the start does not converge or the branch stops inside the range.")
    bal = sub.add_parser("balance", help="correction weights from runs with trial weights (balancing machine, "
                                         "or any rotor file: several planes and speeds)",
                         formatter_class=_Formatter,
                         description="Influence-coefficient balancing, one engine for every scene: corrections in "
                                     "--planes over all speeds and sensors of the runs, by weighted least squares or "
                                     "min-max, with influence coefficients from the trial runs, the model, or both "
                                     "(the model checked against the trials); ISO 21940-11 and -12 explained; "
                                     "a correction as a mass at --radius, split onto --holes.\n\nWithout ROTOR: "
                                     "model 002's balancing machine from a measurement file (time, tacho, x1, x2, "
                                     "..., run, trial_plane, trial_unbalance, trial_angle), --runs; its model is the "
                                     "balancing_machine preset.\n\nWith ROTOR (a rotor file): a phasor file (--data: "
                                     "speed, node, direction, real, imag, run, trial_node, trial_magnitude, "
                                     "trial_phase); planes are nodes."
                                     "\n\nExit codes: 0 success, 2 bad input, 3 numerical failure.")
    bal.add_argument("preset", metavar="ROTOR", nargs="?", default=None,
                     help="a rotor file ROTOR.toml (a shipped one by name, e.g. flexible_rig.toml); omit for the "
                          "balancing machine")
    bal.add_argument("--set", action="append", metavar="KEY=VALUE",
                     help="override an entry of ROTOR (e.g. bearing0.kxx=2e6); rotor files only")
    bal.add_argument("--runs", default=None, metavar="FILE",
                     help="balancing machine: CSV/.npz of runs, or a shipped dataset name (`rotorjax data list`; "
                          "default: balancing-runs)")
    bal.add_argument("--data", default=None, metavar="FILE",
                     help="ROTOR: phasor file, or a shipped dataset name (default for flexible_rig.toml: "
                          "flexible-trials)")
    bal.add_argument("--planes", default=None, help="comma-separated correction planes: plane numbers (balancing "
                                                    "machine) or nodes (ROTOR); default: every plane or node with "
                                                    "a trial run")
    bal.add_argument("--speeds", default=None, help="comma-separated speeds (rad/s) of the data to balance over "
                                                    "(default: every speed of the baseline run)")
    bal.add_argument("--method", default="ls", choices=("ls", "minmax"),
                     help="weighted least squares, or min-max (the largest residual vibration, exactly, as a "
                          "second-order cone program)")
    bal.add_argument("--influence", default=None, choices=("trials", "model", "both"),
                     help="influence coefficients from the trial runs, the model, or both (the model checked "
                          "against the trials) (default: trials)")
    bal.add_argument("--model", action="store_true", help="the same as --influence model")
    bal.add_argument("--service-speed", type=positive, default=None,
                     help="the service speed for ISO 21940, rad/s (default: the largest speed of the data)")
    bal.add_argument("--grade", type=positive, default=2.5, help="the ISO 21940-11 grade G (mm/s) to meet")
    bal.add_argument("--radius", type=positive, default=None,
                     help="present each correction as a mass at this radius, m (default: 0.01 for the balancing "
                          "machine; none for ROTOR: unbalances in kg m)")
    bal.add_argument("--holes", type=int, default=None, metavar="N",
                     help="split each correction onto the two nearest of N equally spaced holes (N >= 2; with "
                          "--radius)")
    bal.add_argument("--rotor-mass", type=positive, default=None,
                     help="rotor mass for the ISO grade, kg (default: 10 for the balancing machine, the model's "
                          "for ROTOR)")
    _common_flags(bal)
    bal.set_defaults(fn=cmd_balance)
    _command(sub, "identify", "identify support stiffness/damping (any rotor file: bearing, support, disk and "
             "unbalance parameters) from measured vibration", cmd_identify, [
        (("--data",), dict(default=None, metavar="FILE",
                           help="measurements, or a shipped dataset name (`rotorjax data list`): a run-up CSV/.npz "
                                "for the balancing machine (default: runup); a phasor file (speed, node, direction, "
                                "real, imag; receptances with input_node, input_direction, frequency) for a rotor "
                                "file (default for flexible_rig.toml: flexible-runup)")),
        (("--fit",), dict(default=None, help=f"comma-separated parameters to fit: from {', '.join(FITTABLE)} for "
                                             "the balancing machine (default k1,k2,c1,c2); a rotor file's names, "
                                             "e.g. bearing0.kxx,bearing1.cyy,material0.E,shaft2.od (default: the "
                                             "kxx, kyy, cxx, cyy its "
                                             "bearings give); the others stay at the file's and --set values, "
                                             "which are the start")),
        (("--fit-unbalance",), dict(nargs="?", const=True, default=None, metavar="NODES",
                                    help="also fit the unbalances: the preset's (balancing machine, no value), or "
                                         "complex unbalances at these comma-separated nodes (rotor file)")),
        (("--block",), dict(type=at_least(1), default=None, help="balancing machine: revolutions per 1x estimate "
                                                                 "(default 1)")),
        (("--min-speed",), dict(type=nonnegative, default=None,
                                help="balancing machine: drop revolutions below this speed, rad/s (default 0)")),
        (("--weights",), dict(default="relative", choices=("relative", "uniform"),
                              help="rotor file: each phasor weighted by 1/|X| (relative) or equally; a sigma column "
                                   "in the file overrides")),
        (("--covariance",), dict(default="classical", choices=("classical", "sandwich"),
                                 help="rotor file: the intervals' covariance")),
        (("--starts",), dict(type=at_least(1), default=32, help="rotor file: starts of the global search (1: a "
                                                                "local fit from the file's values)")),
        (("--spread",), dict(type=positive, default=10.0, help="rotor file: the starts span this factor either way "
                                                               "around the file's values (log-parameters)")),
        (("--method",), dict(default="lm", choices=("lm", "optax"), help="rotor file: Levenberg-Marquardt, or "
                                                                          "optax's Adam (gradient descent)")),
    ], kinds="balancing-machine, rotor files")
    _command(sub, "uncertainty", "a rotor file's critical speeds, log decrements, margins and responses, or a "
             "preset's stability thresholds and stable speed range, as distributions of its parameters' scatter "
             "(vmapped Monte Carlo and first-order moments)", cmd_uncertainty, [
        (("--dist",), dict(action="append", default=None, metavar="KEY=DIST(A,B)",
                           help="a parameter's distribution, by its rotor-file name (a preset: its --set key; "
                                "disk0.position: where the disk's node lies, m from node 0): normal(MEAN,SD), "
                                "lognormal(MEAN,SD) (the quantity's own mean and sd) or uniform(LO,HI); repeatable")),
        (("--samples",), dict(type=int, default=10_000, help="Monte Carlo samples (>= 2)")),
        _range(required=False, help="the range of the forward 1x critical speeds followed, rad/s (default 0 to 1.5 "
                                    "x the operating speed); a preset: of its stability thresholds, in its speed "
                                    "unit (needed)"),
        (("--speed",), dict(type=nonnegative, default=None, help="the speed of the log decrements, rad/s (default: "
                                                                 "the file's [rotor] speed)")),
        (("--modes",), dict(type=int, default=3, help="log decrements of this many modes (by frequency; 0: none)")),
        (("--output",), dict(action="append", default=None, choices=QUANTITIES,
                             help="also a design quantity over --range: min-log-dec (the floor of the first --modes "
                                  "modes), separation-margin (API 684 slack, percent; needs --operating), response "
                                  "(largest unbalance response at the probes, m), onset (rad/s), mass; repeatable")),
        (("--operating",), dict(nargs="+", action=SpanAction, metavar=("LO", "HI"), default=None,
                                help="--output separation-margin: the operating speed range, rad/s")),
        (("--probe",), dict(type=int, action="append", default=None, help="--output response: a probe node "
                                                                           "(default: every node); repeatable")),
        (("--seed",), dict(type=int, default=0, help="the random seed")),
        (("--n-scan",), dict(type=at_least(2), default=40, help="a preset: the speeds scanned for its stability "
                                                                "thresholds (over --range widened by a quarter)")),
    ], kinds="rotor files; presets with a reference motion (anisotropic-abb, elliptic-abb with rho1=rho2, "
             "cantilever-limiters)", description="A rotor file's forward 1x critical speeds (in --range) and the log "
       "decrements of its first --modes modes (at --speed) as distributions of its parameters' scatter "
       "(--dist KEY=normal(MEAN,SD) | lognormal(MEAN,SD) | uniform(LO,HI), parameters by their rotor-file "
       "names), and any --output design quantity (the same as optimize's): Monte Carlo means, standard "
       "deviations and 5/50/95 % quantiles, the first-order (FOSM) mean and standard deviation from autodiff "
       "gradients, each parameter's share of the variance, and the probabilities that a mode is unstable (log dec "
       "< 0) and that the separation margin falls short of API 684's, with their 95 % intervals; a histogram per "
       "output. A preset with a reference motion (an auto-balancer's main motion, straight running): the "
       "stability thresholds it has in --range (threshold_i) and stable-range, how much of --range it is stable "
       "over (the auto-balancing range), as distributions of its --set keys' scatter.")
    _command(sub, "optimize", "a rotor file's parameters chosen within bounds against its margins (min-log-dec, "
             "separation-margin, response, onset, mass, stable-range), written as a rotor file; a preset's against "
             "its stable speed range (an auto-balancer's auto-balancing range)", cmd_optimize, [
        (("--vary",), dict(action="append", default=None, metavar="KEY=LO:HI",
                           help="a parameter to choose, by its rotor-file name (a preset: its --set key; "
                                "disk0.position, bearing1.position: where the entry's node lies, m from node 0), "
                                "and its bounds; repeatable")),
        (("--objective",), dict(default=None, choices=QUANTITIES,
                                help="the quantity to optimise (maximised: min-log-dec, separation-margin, onset, "
                                     "stable-range; minimised: response, mass; --sense overrides); default "
                                     "min-log-dec, and a preset's stable-range (its only one)")),
        (("--sense",), dict(default=None, choices=("min", "max"), help="minimise or maximise the objective")),
        (("--constraint",), dict(action="append", default=None, metavar="NAME>=V",
                                 help="a limit on a quantity, NAME>=VALUE or NAME<=VALUE (units: rad/s, kg, m, "
                                      "percent for separation-margin); repeatable")),
        _range(required=False, help="the speed range of min-log-dec, response, onset and stable-range, rad/s "
                                    "(default 0 to 1.5 x the operating speed); a preset: in its speed unit (needed)"),
        (("--modes",), dict(type=int, default=3, help="min-log-dec: the modes counted (the first N, a near pair "
                                                      "whole; see --max-frequency)")),
        (("--max-frequency",), dict(type=positive, default=None, help="min-log-dec: count the modes below this "
                                                                      "damped frequency, rad/s")),
        (("--operating",), dict(nargs="+", action=SpanAction, metavar=("LO", "HI"), default=None,
                                help="separation-margin: the operating speed range, rad/s")),
        (("--probe",), dict(type=int, action="append", default=None, help="response: a probe node (default: every "
                                                                           "node); repeatable")),
        (("--starts",), dict(type=int, default=8, help="starts of the search (the file's values, then a Latin "
                                                       "hypercube), vmapped")),
        (("--seed",), dict(type=int, default=0, help="the random seed of the starts (and of --scatter's samples)")),
        (("--scatter",), dict(action="append", default=None, metavar="KEY=DIST",
                              help="robust design: a parameter not varied that scatters, KEY=normal(MEAN,SD) | "
                                   "lognormal(MEAN,SD) | uniform(LO,HI); repeatable")),
        (("--robust",), dict(type=float, default=None, metavar="K",
                             help="robust design: optimise and constrain each quantity's mean moved K standard "
                                  "deviations the bad way over the --scatter samples (default 1 with --scatter)")),
        (("--robust-samples",), dict(type=int, default=32, help="robust design: samples of the scatter (the same "
                                                                "at every design)")),
        (("--n-scan",), dict(type=at_least(2), default=40, help="stable-range of a preset: the speeds scanned for "
                                                                "its thresholds (over --range widened by a quarter)")),
    ], kinds="rotor files; presets with a reference motion (anisotropic-abb, elliptic-abb with rho1=rho2, "
             "cantilever-limiters)",
       description="A rotor file's parameters (--vary KEY=LO:HI, by their rotor-file names) "
       "chosen within their bounds to maximise or minimise one quantity (--objective) subject to limits on others "
       "(--constraint NAME>=V | NAME<=V): min-log-dec, a smooth lower bound on the least log decrement over --range "
       "of the first --modes modes; separation-margin, the least API 684 separation-margin slack (percent) of the "
       "forward 1x critical speeds from --operating; response, the largest unbalance response at the probes over "
       "--range; onset, the stability threshold in --range; mass; stable-range, how much of --range the rotor is "
       "stable over. A preset with a reference motion (--vary its --set keys): stable-range, the auto-balancing "
       "range of an auto-balancer's main motion, its thresholds followed by the implicit function theorem. One "
       "augmented-Lagrangian search on exact gradients from --starts starts at once; the convergence history, each "
       "constraint's value and multiplier, the optimised rotor written as a rotor file (a preset's, its --set "
       "values), a plot of the history and the Campbell diagram (a preset: its margin over the speed) before and "
       "after. "
       "Robust design: with --scatter, every quantity is its mean less (or plus) --robust standard deviations over "
       "--robust-samples samples of the scattering parameters.")
    ph = sub.add_parser("phasors", help="1x phasors of raw vibration signals, written as a phasor file",
                        formatter_class=_Formatter,
                        description="1x phasors from a raw measurement file (time, tacho, x1, x2, ..., run, "
                                    "trial_plane, trial_unbalance, trial_angle): one per sensor of a steady run, "
                                    "one per block of revolutions of a run-up; written as a phasor file (speed, "
                                    "node, direction, real, imag, run, trial_node, trial_magnitude, trial_phase)."
                                    "\n\nExit codes: 0 success, 2 bad input, 3 numerical failure.")
    ph.add_argument("raw", metavar="RAW", help="raw CSV/.npz measurement file, or a shipped dataset name")
    ph.add_argument("--map", default=None, metavar="TEXT",
                    help="the sensors' FE nodes and directions, e.g. x1=2:x,x2=2:y (default: the file's comment "
                         "line '# channels: x1=2:x, x2=2:y')")
    ph.add_argument("--out", required=True, metavar="FILE.csv", help="the phasor file to write")
    ph.add_argument("--revolutions", type=at_least(1), default=None, metavar="N",
                    help="revolutions per phasor of a run whose speed varies (default 1)")
    ph.add_argument("--json", action="store_true", help="print the summary as JSON on stdout")
    _debug_flag(ph)
    ph.set_defaults(fn=cmd_phasors)
    _command(sub, "draw", "the rotor drawn: shaft elements to scale, disks, bearings, components, nodes", cmd_draw,
             kinds="every preset and rotor file",
             description="The rotor drawn: a shaft's elements to scale along each axis (tapers and bores as they "
                         "are, materials coloured), disks (the solid disk with their mass and inertias), point "
                         "masses, bearings and seals, pedestals, every other component at its node named by its "
                         "rotor-file table (fluid films, limiters, probes, unbalances), and the node numbers; a "
                         "planar rotor in its end view, the balancing machine's rotor on its supports. Writes "
                         "draw_NAME.png and the layout as numbers (draw_NAME.json: node positions, elements, "
                         "materials, disks, bearings, components, mass).")
    _command(sub, "report", "one self-contained HTML page of the everyday analyses, to hand on", cmd_report,
             flags=[(("--speed-range",), dict(nargs="+", action=SpanAction, metavar=("LO", "HI"), default=None,
                                              help="the speeds of the Campbell diagram, critical speeds and "
                                                   "response, rad/s, or with a unit (0 12000 rpm) (default 0 to "
                                                   "1.5 x the operating speed)")),
                    (("--operating",), dict(nargs="+", action=SpanAction, metavar=("LO", "HI"), default=None,
                                            help="the operating speed range, rad/s, or with a unit (3000 3600 "
                                                 "rpm), for API 684's separation margins (default: the [rotor] "
                                                 "speed)")),
                    UNITS_OPTION],
             kinds="rotor files and presets with a finite-element rotor",
             description="One self-contained HTML page (report_NAME.html): the rotor drawn and its model, static "
                         "deflection and bearing loads, the undamped critical speed map, the Campbell diagram with "
                         "log decrements, the 1x critical speeds with API 684's amplification factors and "
                         "separation margins, the damped modes at the operating speed, the unbalance response and "
                         "the level I screen; each section the command of its name, run into "
                         "OUT/report_parts/, its numbers in tables and its figures embedded.")
    sub.choices["report"].set_defaults(cli_parser=build_parser)   # its sections run as the CLI runs them
    imp = sub.add_parser("import-ross", help="a rotor saved by ROSS (Rotor.save), as a rotor file",
                         formatter_class=_Formatter,
                         description="Reads a rotor saved by ROSS (`Rotor.save`: TOML, or JSON for .json; ROSS 1.x "
                                     "to 3.x) and writes it as a rotorjax rotor file: shaft elements (tapered, "
                                     "hollow), materials, disks, point masses, bearings and seals (their coefficients, "
                                     "constant or over the speed), pedestals (a bearing linked to a node with a mass "
                                     "and a bearing to the ground). What a rotor file cannot hold (axial or torsional "
                                     "terms, axial force, couplings, gears, ...) is refused by the section's name, "
                                     "not dropped.\n\nExit codes: 0 success, 2 bad input.")
    imp.add_argument("file", metavar="FILE", help="the file ROSS saved (.toml or .json)")
    imp.add_argument("--out", default=None, metavar="ROTOR.toml",
                     help="the rotor file to write (default: FILE's stem + _rotorjax.toml, beside it)")
    imp.add_argument("--name", default=None, help="the rotor's [rotor] name (default: FILE's stem)")
    imp.add_argument("--json", action="store_true", help="print the summary as JSON on stdout")
    _debug_flag(imp)
    imp.set_defaults(fn=cmd_import_ross)
    data = sub.add_parser("data", help="the shipped measurement datasets", formatter_class=_Formatter,
                          description="`rotorjax data list` lists the shipped datasets; `rotorjax data path NAME` "
                                      "prints a dataset's file path. `--data NAME` / `--runs NAME` take the "
                                      "names directly.")
    data.add_argument("action", choices=("list", "path"), help="list the datasets, or print one's path")
    data.add_argument("name", nargs="?", default=None, help="dataset name (for `path`)")
    _debug_flag(data)
    data.set_defaults(fn=cmd_data)
    bench = sub.add_parser(
        "bench", help="the headline speed comparisons on this machine", formatter_class=_Formatter,
        description="Runs the headline comparisons on this machine: the model-001 speed sweep against numba RK4 and "
                    "scipy DOP853 loops, the model-001 Floquet map against a scipy loop, the Campbell diagram of "
                    "ROSS's example rotor against ROSS; prints the ratios at matched error (a peer's cost at "
                    "rotorjax's error, read off its own tolerance ladder) and writes the work-precision diagram "
                    "(bench.png) and bench.json to --out. Peers that are not installed (numba, ROSS) are skipped "
                    "with a note. Without --quick it runs the sizes of benchmarks/ (many minutes)."
                    "\n\nExit codes: 0 success, 2 bad input, 3 numerical failure.")
    bench.add_argument("--quick", action="store_true", help="small sizes: under 2 minutes on a laptop")
    bench.add_argument("--smoke", action="store_true", help=argparse.SUPPRESS)  # tiny sizes, for the tests
    bench.add_argument("--device", choices=("cpu", "gpu"), default="cpu",
                       help="the JAX device rotorjax runs on (the peers run on the CPU)")
    bench.add_argument("--ross-python", default=None, metavar="PYTHON",
                       help="a Python interpreter that has ROSS (default: $ROTORJAX_ROSS_PYTHON, else this one "
                            "when ross is installed, else ROSS is skipped)")
    _common_flags(bench, json_help="print the report as JSON on stdout")
    bench.set_defaults(fn=cmd_bench)
    demo = sub.add_parser("demo", help="a short representative study with plots", formatter_class=_Formatter)
    demo.add_argument("--out", default="rotorjax-out", metavar="DIR", help="folder for the plots and summary")
    _debug_flag(demo)
    demo.set_defaults(fn=cmd_demo)
    pre = sub.add_parser("presets", help="list presets, or one preset's --set keys", formatter_class=_Formatter)
    pre.add_argument("name", nargs="?", default=None, metavar="PRESET",
                     help=f"one of: {', '.join(PRESET_NAMES)} (default: all, briefly)")
    pre.add_argument("--json", action="store_true", help="print the listing as JSON")
    _debug_flag(pre)
    pre.set_defaults(fn=cmd_presets)
    return parser


def _silence_stdout():
    """After a broken pipe: point stdout at devnull, so that Python's own flush at
    exit does not raise (and print) a second BrokenPipeError."""
    import os

    try:
        devnull = os.open(os.devnull, os.O_WRONLY)
        os.dup2(devnull, sys.stdout.fileno())
    except (OSError, ValueError):  # stdout is not a file (a test's capture)
        pass


def main(argv=None) -> int:
    parser = build_parser()
    try:
        args = parser.parse_args(argv)
    except SystemExit as e:  # --help (0) or a usage error argparse has printed (2)
        return e.code if isinstance(e.code, int) else 2
    from .._config import enable_compilation_cache

    enable_compilation_cache()
    try:
        with collect_warnings():
            resolve_units(args, _OptionUnits(args))
            return args.fn(args)
    except BrokenPipeError:  # `rotorjax presets | head -1`: the reader left; nothing more to say
        _silence_stdout()
        return 0
    except NumericalError as e:
        print(f"rotorjax: numerical failure: {e}", file=sys.stderr)
        return 3
    except (OverflowError, ZeroDivisionError, FloatingPointError) as e:
        print(f"rotorjax: numerical failure: {type(e).__name__}: {e} (are the --set values within a physical "
              "range? `rotorjax presets PRESET` lists them)", file=sys.stderr)
        return 3
    except (InputError, ValueError) as e:
        print(f"rotorjax: error: {e}", file=sys.stderr)
        return 2
    except KeyboardInterrupt:
        print("rotorjax: interrupted", file=sys.stderr)
        return 130
    except Exception as e:  # noqa: BLE001 - the last line of defence: no traceback reaches a user
        if getattr(args, "debug", False):
            raise
        first = str(e).strip().splitlines()[0] if str(e).strip() else ""
        print(f"rotorjax: internal error: {type(e).__name__}: {first[:300]} (rerun with --debug for the "
              "traceback, and please report it)", file=sys.stderr)
        return 1
