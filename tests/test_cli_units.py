"""Issue 35 item 2 (the CLI's input side): options with a unit (`--range 0 12000 rpm`,
`--speed 3000rpm`) give the same answer as the same values in SI; an option whose
target has no unit for it (a dimensionless preset speed) refuses one."""

import json
import math

from rotorjax.cli import main


def _run(argv, tmp_path, capsys):
    assert main([*argv, "--out", str(tmp_path), "--json"]) == 0
    return json.loads(capsys.readouterr().out)


def test_a_range_in_rpm_is_the_range_in_rad_per_s(tmp_path, capsys):
    hi = 12000 * 2 * math.pi / 60
    a = _run(["critical-speeds", "ross_compare.toml", "--range", "0 12000 rpm"], tmp_path, capsys)
    b = _run(["critical-speeds", "ross_compare.toml", "--range", "0", repr(hi)], tmp_path, capsys)
    c = _run(["critical-speeds", "ross_compare.toml", "--range", "0rpm", "200Hz"], tmp_path, capsys)
    assert a == b == c


def test_a_speed_in_rpm_is_the_speed_in_rad_per_s(tmp_path, capsys):
    a = _run(["modes", "ross_compare.toml", "--speed", "3000rpm"], tmp_path, capsys)
    b = _run(["modes", "ross_compare.toml", "--speed", repr(100 * math.pi)], tmp_path, capsys)
    assert a["speed"] == b["speed"] == 100 * math.pi
    assert a["modes"] == b["modes"]


# ---- the output side: --units si | rpm-um | rpm-mil ----

import numpy as np  # noqa: E402
import pytest  # noqa: E402

from rotorjax._units import to_si  # noqa: E402
from rotorjax.cli._output_units import Units  # noqa: E402

#: one SI unit in each system's, by pint (an independent reference for the factors)
RPM = 1 / to_si("1 rpm", "rad/s", "rpm")
UM, MIL = 1 / to_si("1 um", "m", "um"), 1 / to_si("1 mil", "m", "mil")
EXPECTED = {"rpm-um": {"speed": RPM, "frequency": RPM, "amplitude": 2 * UM, "deflection": UM},
            "rpm-mil": {"speed": RPM, "frequency": RPM, "amplitude": 2 * MIL, "deflection": MIL}}

T = "ross_compare.toml"
#: each command on the one rotor (small grids), and its numbers' kinds (the paths `Units.convert` takes)
COMMANDS = {
    "campbell": (["--range", "0", "1200", "--n-speeds", "12", "--modes", "4"],
                 {"speeds": "speed", "critical_speeds": "speed", "frequencies": "frequency",
                  "tracked.frequencies": "frequency"}),
    "modes": (["--speed", "300", "--n-modes", "3"], {"speed": "speed", "modes.*.damped_frequency": "frequency",
                                                     "modes.*.natural_frequency": "frequency"}),
    "critical-speeds": (["--range", "0", "1200", "--n-scan", "40", "--modes", "4"],
                        {"range": "speed", "critical_speeds.*.speed": "speed",
                         "synchronous_determinant_roots": "speed"}),
    "response": (["--range", "10", "1200", "--n", "60", "--unbalance", "1e-4", "--shape-at", "300"],
                 {"range": "speed", "peaks": "speed", "peak_amplitudes": "amplitude", "max_amplitude": "amplitude",
                  "speed_at_max": "speed", "deflected_shape.speed": "speed", "deflected_shape.major": "deflection",
                  "curve.speeds": "speed", "curve.amplitude": "amplitude", "curve.x_abs": "amplitude"}),
    "static": ([], {"displacement": "deflection", "max_deflection.value": "deflection"}),
    "ucs": (["--n", "8", "--n-modes", "2"], {"critical_speeds": "speed", "bearing_speeds": "speed",
                                             "intersections.*.speed": "speed"}),
    "level1": (["--speed", "500", "--n", "5", "--q-max", "1e6", "--set", "bearing0.cxx=500", "--set",
                "bearing1.cxx=500"], {"speed": "speed"}),
    "frf": (["--input", "2,x", "--output", "2,x", "--range", "10", "1200", "--n", "40"],
            {"frequencies": "frequency", "peaks": "frequency"}),
}


def _at(out, path):
    """The numbers at a dotted path (`*`: every item), flattened."""
    nodes = [out]
    for key in path.split("."):
        nodes = [x for n in nodes for x in (n if key == "*" else [n[key]])]
    return np.asarray([np.nan if v is None else v for v in np.ravel(np.asarray(nodes, dtype=object))], dtype=float)


@pytest.mark.parametrize("command", list(COMMANDS))
def test_each_command_shows_its_si_numbers_in_the_units_asked(command, tmp_path, capsys):
    system = "rpm-um" if list(COMMANDS).index(command) % 2 else "rpm-mil"
    argv, fields = COMMANDS[command]
    si = _run([command, T, *argv], tmp_path, capsys)
    shown = _run([command, T, *argv, "--units", system], tmp_path, capsys)
    assert si["units"]["system"] == "si" and shown["units"]["system"] == system
    for path, kind in fields.items():
        a, b = _at(si, path), _at(shown, path)
        assert a.size and np.any(np.isfinite(a)), path
        np.testing.assert_allclose(b, a * EXPECTED[system][kind], rtol=1e-12, err_msg=path)
        assert shown["units"][kind] == Units(system).label(kind)
    # what is not a speed, a frequency or a displacement is left as it is
    rest = {k: v for k, v in si.items() if k not in {p.split(".")[0] for p in fields} | {"units", "unit", "files"}}
    assert rest == {k: shown[k] for k in rest}


def test_printed_tables_name_the_units(tmp_path, capsys):
    assert main(["response", T, "--range", "10", "1200", "--n", "60", "--unbalance", "1e-4", "--units", "rpm-um",
                 "--out", str(tmp_path)]) == 0
    text = capsys.readouterr().out
    assert "rpm (" in text and "um pk-pk" in text and "rad/s" not in text.split("peaks at")[1]
    assert main(["modes", T, "--speed", "3000 rpm", "--n-modes", "2", "--units", "rpm-mil", "--out",
                 str(tmp_path)]) == 0
    text = capsys.readouterr().out
    assert "damped modes at 3000 rpm" in text and "wd (cpm)" in text


def test_plot_axes_are_labelled_in_the_units_given():
    import matplotlib.pyplot as plt

    from rotorjax.plot import plot_campbell_tracked, plot_response

    w = np.linspace(1, 100, 5)
    fig = plot_response(w, w + 0j, w + 0j, speed_unit="rpm", amplitude_unit="mil pk-pk")
    assert fig.axes[0].get_ylabel() == "amplitude (mil pk-pk)" and fig.axes[1].get_xlabel() == "speed (rpm)"
    fig2 = plot_campbell_tracked(w, w[:, None], np.full((5, 1), "forward"), np.ones((5, 1)), unit="rpm",
                                 frequency_unit="cpm")
    assert fig2.axes[0].get_xlabel() == "speed (rpm)"
    assert fig2.axes[0].get_ylabel() == "damped natural frequency (cpm)"
    plt.close("all")


def test_convert_follows_paths_and_keeps_what_has_no_number():
    out = {"a": [1.0, None, [2.0]], "b": {"c": [{"d": 3.0}, {"d": None}]}, "e": "text", "f": 5.0}
    Units("rpm-mil").convert(out, {"a": "speed", "b.c.*.d": "deflection", "missing.x": "speed"})
    assert out["a"] == [pytest.approx(RPM), None, [pytest.approx(2 * RPM)]]
    assert out["b"]["c"][0]["d"] == pytest.approx(3 * MIL, rel=1e-15) and out["b"]["c"][1]["d"] is None
    assert out["e"] == "text" and out["f"] == 5.0
    assert out["units"] == {"system": "rpm-mil", "speed": "rpm", "deflection": "mil"}
