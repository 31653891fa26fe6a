"""`report`: one self-contained HTML page of a rotor's everyday analyses, to hand on.

The page is the commands themselves, run on the same target into `OUT/report_parts/`
(their JSON and their figures), put together: the drawing and the model (`draw`), the
static deflection and bearing loads (`static`), the undamped critical speed map
(`ucs`), the Campbell diagram with log decrements (`campbell`), the 1x critical speeds
(`critical-speeds`) with API 684's amplification factors and separation margins against
the operating range (`rotorjax.analysis.api684_margins`), the damped modes at the
operating speed (`modes`), the unbalance response (`response`) and the level I
stability screen (`level1`). Every number in a table is read from a command's JSON;
every figure is embedded (base64 PNG), so the page needs nothing beside it."""

import base64
import contextlib
import html
import io
import json
import math
import os
import sys

import numpy as np

from ._output_units import SYSTEMS, Units, units_for
from ._common import InputError, NumericalError, build, out_stem, prepare_out, preset_and_params

#: the sections, in the page's order: (command, title)
SECTIONS = (("draw", "The rotor"), ("static", "Static deflection and bearing loads"),
            ("ucs", "Undamped critical speed map"), ("campbell", "Campbell diagram and log decrements"),
            ("critical-speeds", "Critical speeds and API 684 separation margins"),
            ("modes", "Damped modes at the operating speed"), ("response", "Unbalance response"),
            ("level1", "Level I stability screening (API 684)"))


def _run(parser, argv):
    """A command run as the CLI runs it (`parser`: the CLI's), its JSON printed to a
    buffer: its result."""
    args = parser.parse_args([*argv, "--json"])
    buf = io.StringIO()
    with contextlib.redirect_stdout(buf):
        args.fn(args)
    return json.loads(buf.getvalue())


def _pngs(files):
    """The PNG files a command wrote, embedded."""
    out = []
    for path in (v for v in (files or {}).values() if isinstance(v, str) and v.endswith(".png")):
        with open(path, "rb") as f:
            out.append(f'<img alt="{html.escape(os.path.basename(path))}" src="data:image/png;base64,'
                       f'{base64.b64encode(f.read()).decode()}">')
    return out


def _json_row(row):
    """An API 684 row for JSON: an undamped mode's infinite amplification factor as null."""
    return {**row, "af": row["af"] if math.isfinite(row["af"]) else None}


def _table(header, rows):
    head = "".join(f"<th>{html.escape(h)}</th>" for h in header)
    body = "".join("<tr>" + "".join(f"<td>{html.escape(_cell(c))}</td>" for c in row) + "</tr>" for row in rows)
    return f"<table><thead><tr>{head}</tr></thead><tbody>{body}</tbody></table>"


def _cell(c):
    return f"{c:.6g}" if isinstance(c, float) else str(c)


def _unit(out, kind):
    """The unit of `kind` in a command's JSON (its `"units"`, `--units`)."""
    return out.get("units", {}).get(kind, SYSTEMS["si"][kind][0])


def _tables(command, out):
    """The section's numbers, as tables (in the units each command's JSON states)."""
    speed, freq = _unit(out, "speed"), _unit(out, "frequency")
    if command == "draw":
        lay = out["layout"]
        yield _table(["length (m)", "mass (kg)", "elements", "theory", "disks", "bearings and seals"],
                     [[lay["length"], lay["mass"], len(lay["elements"]), lay["theory"], len(lay["disks"]),
                       len(lay["bearings"])]])
        yield _table(["disk", "node", "position (m)", "mass (kg)", "Id (kg m^2)", "Ip (kg m^2)"],
                     [[i, d["node"], d["x"], d["m"], d["Id"], d["Ip"]] for i, d in enumerate(lay["disks"])])
        yield _table(["bearing", "node", "position (m)", "kind"],
                     [[b["index"], b["node"], b["x"], b["kind"]] for b in lay["bearings"]])
    elif command == "static":
        yield _table(["bearing", "node", "reaction x (N)", "reaction y (N)"],
                     [[r["bearing"], r["node"], r["x"], r["y"]] for r in out["bearing_reactions"]])
        yield _table([f"largest deflection ({_unit(out, 'deflection')})", "at node"],
                     [[out["max_deflection"]["value"], out["max_deflection"]["node"]]])
    elif command == "ucs":
        yield _table(["mode", "bearing", "coefficient", "bearing stiffness (N/m)", f"speed ({speed})"],
                     [[r["mode"], r["bearing"], r["coefficient"], r["k"], r["speed"]] for r in out["intersections"]])
    elif command == "campbell":
        yield _table([f"1x critical speed ({speed})"], [[w] for w in out["critical_speeds"]])
        log_dec = list(zip(*out["log_dec"]))          # per mode (sorted), over the speeds
        yield _table(["mode", "least log dec over the range", f"at speed ({speed})"],
                     [[j, min(ld), out["speeds"][ld.index(min(ld))]] for j, ld in enumerate(log_dec)])
    elif command == "critical-speeds":
        shown = Units(out.get("units", {}).get("system", "si"))
        yield _table([f"critical speed ({speed})", "mode", "AF", "margin (%)", "required (%)", "meets"],
                     [[shown.value(r["speed"], "speed"), r["mode"], r["af"], r["margin"], r["required"],
                       "yes" if r["meets"] else "NO"]
                      for r in out["api684"]["rows"]])
    elif command == "modes":
        yield _table(["mode", f"damped frequency ({freq})", "log dec", "damping ratio", "whirl"],
                     [[m["mode"], m["damped_frequency"], m["log_dec"], m["damping_ratio"], m["whirl"]]
                      for m in out["modes"]])
    elif command == "response":
        yield _table([f"peak speed ({speed})", f"amplitude ({_unit(out, 'amplitude')})"],
                     list(zip(out["peaks"], out["peak_amplitudes"])))
    elif command == "level1":
        named = {"speed": f"speed ({speed})", "q0": "q0 (N/m)"}
        yield _table(["quantity", "value"], [[named.get(k, k), v] for k, v in out.items()
                                             if isinstance(v, (int, float)) and not isinstance(v, bool)])


def _traces(command, out):
    """`(traces, x label, y label, log x, log y)` of a section's interactive figure
    (`rotorjax.plot.Trace`s from its command's JSON), or None where it has none."""
    from rotorjax.plot import Trace

    speed, freq = _unit(out, "speed"), _unit(out, "frequency")
    if command == "campbell":
        t = out["tracked"]
        f, whirl = np.asarray(t["frequencies"], dtype=float), np.asarray(t["whirl"])
        traces = [Trace(f"mode {k}", out["speeds"], f[:, k], mode="lines+markers",
                        dash="dash" if np.mean(whirl[:, k] == "backward") > 0.5 else "solid",
                        values=np.asarray(t["log_dec"])[:, k], values_label="log dec",
                        labels=[f"{w} whirl" for w in whirl[:, k]]) for k in range(f.shape[1])]
        traces += [Trace("1x", out["speeds"], out["speeds"], dash="dot", colour="black"),
                   Trace("1x crossing", out["critical_speeds"], out["critical_speeds"], mode="markers",
                         colour="red")]
        return traces, f"speed ({speed})", f"damped natural frequency ({freq})", False, False
    if command == "ucs":
        f = np.asarray([[np.nan if v is None else v for v in row] for row in out["critical_speeds"]], dtype=float)
        traces = [Trace(f"mode {j + 1}", out["stiffness"], f[:, j]) for j in range(f.shape[1])]
        for name in ("kxx", "kyy"):
            traces += [Trace(f"bearing {b} {name}", k, out["bearing_speeds"], dash="dash" if name == "kxx" else "dot",
                             colour="black") for b, k in enumerate(out[f"bearing_{name}"])]
        traces.append(Trace("critical speed on the bearings", [i["k"] for i in out["intersections"]],
                            [i["speed"] for i in out["intersections"]], mode="markers", colour="red"))
        return traces, "bearing stiffness (N/m)", f"critical speed ({speed})", True, True
    if command == "response":
        c = out["curve"]
        traces = [Trace(f"node {out['probe']}: {name}", c["speeds"], c[key])
                  for name, key in (("amplitude", "amplitude"), ("|x|", "x_abs"), ("|y|", "y_abs"))]
        traces.append(Trace("peaks", out["peaks"], out["peak_amplitudes"], mode="markers", colour="red"))
        return traces, f"speed ({speed})", f"amplitude ({_unit(out, 'amplitude')})", False, True
    if command == "static":
        p = ("x", "y").index(out["axis"])
        return ([Trace(f"deflection {out['axis']}", out["positions"], np.asarray(out["displacement"])[:, p],
                       mode="lines+markers")], "axial position (m)", f"deflection ({_unit(out, 'deflection')})",
                False, False)
    if command == "level1":
        traces = [Trace("log dec of the least damped forward mode", out["q"], out["log_dec"], mode="lines+markers")]
        if out["q0"] is not None:
            traces.append(Trace("threshold Q0", [out["q0"]], [0.0], mode="markers", colour="red"))
        return traces, "cross-coupled stiffness Q (N/m)", "log decrement", False, False
    return None


def _figures(command, out, interactive):
    """The section's figures: an interactive one (plotly, where `interactive`) with its
    static PNGs as the fallback without scripts, else the PNGs."""
    pngs = _pngs(out.get("files"))
    spec = _traces(command, out) if interactive else None
    if spec is None:
        return pngs
    from rotorjax.plot import figure_html, lines_figure

    traces, x_label, y_label, log_x, log_y = spec
    fig = lines_figure(traces, x_label, y_label, log_x=log_x, log_y=log_y)
    return [f'<div class="interactive">{figure_html(fig, f"figure-{command}")}</div>',
            "<noscript>" + "".join(pngs) + "</noscript>"]


def page(title, results, interactive=None):
    """The HTML page of the `results` (`{command: its JSON}`, in `SECTIONS`' order):
    interactive figures where plotly is installed (or `interactive` says), plotly.js
    inlined once, so the page needs nothing beside it."""
    from rotorjax.plot import interactive_available, plotly_js

    interactive = interactive_available() if interactive is None else interactive
    parts = [f"<h1>{html.escape(title)}</h1>", "<nav><ol>"]
    parts += [f'<li><a href="#{c}">{html.escape(t)}</a></li>' for c, t in SECTIONS if c in results]
    parts.append("</ol></nav>")
    for command, heading in SECTIONS:
        if command not in results:
            continue
        out = results[command]
        parts.append(f'<section id="{command}"><h2>{html.escape(heading)}</h2>')
        parts.append(f"<p class=\"cmd\">rotorjax {html.escape(command)}</p>")
        if "failed" in out:
            parts.append(f'<p class="failed">Not computed: {html.escape(out["failed"])}</p>')
        else:
            parts += list(_tables(command, out)) + _figures(command, out, interactive)
        parts.append("</section>")
    style = ("body{font-family:sans-serif;max-width:1100px;margin:2em auto;color:#222}"
             "table{border-collapse:collapse;margin:.5em 0}td,th{border:1px solid #bbb;padding:2px 8px;"
             "text-align:right}img{max-width:100%}.cmd{color:#777;font-family:monospace}.failed{color:#b00}")
    script = f'<script type="text/javascript">{plotly_js()}</script>' if interactive else ""
    return (f"<!DOCTYPE html><html lang=\"en\"><head><meta charset=\"utf-8\"><title>{html.escape(title)}</title>"
            f"<style>{style}</style>{script}</head><body>{''.join(parts)}</body></html>\n")


def cmd_report(args) -> int:
    from rotorjax.analysis import api684_margins

    preset, params = preset_and_params(args, "report")
    units = units_for(args, preset)
    speed = float(params.get(preset.speed_key, 0.0))
    op = args.operating or ((speed, speed) if speed > 0 else None)
    if op is None:
        raise InputError(f"--operating: {preset.name} has no operating speed ([rotor] speed); give --operating LO "
                         "HI (rad/s)")
    if not 0 < op[0] <= op[1]:
        raise InputError(f"--operating {op[0]:g} {op[1]:g}: the operating range must satisfy 0 < LO <= HI (rad/s)")
    lo, hi = args.speed_range or (0.0, 1.5 * max(op[1], speed))
    if not 0 <= lo < hi:
        raise InputError(f"--speed-range {lo:g} {hi:g}: needs 0 <= LO < HI (rad/s)")
    scene = build(preset, params).scene     # bad input (a --set value) is refused here, before any section runs
    prepare_out(args.out)
    parts = os.path.join(args.out, "report_parts")
    common = [preset.name, *sum((["--set", s] for s in args.set or []), []), "--out", parts]
    shown = ["--units", units.system]
    span = ["--range", repr(lo), repr(hi)]
    options = {"campbell": span, "critical-speeds": span, "modes": ["--speed", repr(op[1])],
               "response": ["--range", repr(max(lo, 1e-3 * hi)), repr(hi)], "level1": ["--speed", repr(op[1])]}
    results, failed, skipped = {}, {}, {}
    cli = args.cli_parser()
    for command, _ in SECTIONS:
        try:
            results[command] = _run(cli, [command, *common[:1], *options.get(command, []), *common[1:],
                                          *(shown if command != "draw" else [])])
        except NumericalError as e:   # the page says so in its section; the command exits 3
            results[command], failed[command] = {"failed": str(e)}, str(e)
        except InputError as e:       # a section the rotor gives nothing to (no unbalance to respond to)
            results[command], skipped[command] = {"failed": str(e)}, str(e)
    rows = api684_margins(scene, lo, hi, *op)
    results["critical-speeds"]["api684"] = {"operating": list(op), "rows": rows}
    path = out_stem(args.out, preset, "report_") + ".html"
    with open(path, "w", encoding="utf-8") as f:
        f.write(page(f"{preset.name}: rotordynamic report", results))
    summary = units.convert({"target": preset.name, "report": path, "speed_range": [lo, hi], "operating": list(op),
                             "sections": [c for c, _ in SECTIONS], "failed": failed, "skipped": skipped,
                             "api684": [_json_row(r) for r in rows]},
                            {"speed_range": "speed", "operating": "speed", "api684.*.speed": "speed"})
    if args.json:
        print(json.dumps(summary, indent=2))
        return 3 if failed else 0
    short = [r for r in rows if not r["meets"]]
    print(f"{preset.name}: report of {len(SECTIONS)} sections -> {path}")
    print(f"  API 684: {len(rows)} forward 1x critical speeds in {summary['speed_range'][0]:g}.."
          f"{summary['speed_range'][1]:g} {units.label('speed')}, "
          + (f"{len(short)} short of their separation margin" if short else "every one meets its separation margin"))
    for command, why in skipped.items():
        print(f"  section {command} not computed: {why}")
    for command, why in failed.items():
        print(f"rotorjax: numerical failure: report section {command} not computed: {why}", file=sys.stderr)
    return 3 if failed else 0
