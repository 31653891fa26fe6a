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
