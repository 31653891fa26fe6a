"""Phasor files: the round trip, every malformed file an InputError naming the file, column and
row; raw signals to phasors (steady runs and run-ups, trial weights); the `phasors` command."""

import json

import numpy as np
import pytest

from rotorjax import identify as idf
from rotorjax._errors import InputError
from rotorjax.cli import main
from tests.helpers import set_csv_field

FS = 1000.0                                   # samples per second
X_TRUE = np.array([2e-6 + 1e-6j, -0.5e-6 + 3e-6j])   # the sensors' 1x phasors (m)


# --- phasor files ------------------------------------------------------------------

HEADER = "speed,node,direction,real,imag,run"
ROWS = ["100,2,x,1e-5,2e-6,0", "100,2,y,3e-6,-1e-6,0", "200,2,x,4e-6,5e-6,1", "200,4,Y,-1e-6,0,1"]
TRIAL_HEADER = HEADER + ",trial_node,trial_magnitude,trial_phase"
TRIAL_ROWS = ["100,2,x,1e-5,2e-6,0,,,", "100,2,y,3e-6,-1e-6,0,,,", "100,2,x,4e-6,5e-6,1,2,1e-4,0.5",
              "100,2,y,-1e-6,0,1,2,1e-4,0.5"]
FRF_HEADER = "speed,node,direction,real,imag,frequency,input_node,input_direction"
FRF_ROWS = ["0,2,x,1e-7,-2e-7,50,2,x", "0,2,y,1e-8,3e-8,50,2,x", "0,2,x,2e-7,-1e-7,60,2,x"]


def _text(header=HEADER, rows=ROWS, edit=None):
    lines = [header] + list(rows)
    if edit is not None:
        lines = edit(lines)
    return "\n".join(lines) + "\n"


_set = set_csv_field


def _file(tmp_path, content, name="ph.csv"):
    path = tmp_path / name
    if isinstance(content, bytes):
        path.write_bytes(content)
    else:
        path.write_text(content)
    return str(path)


def test_round_trip_unbalance_trial_sigma(tmp_path):
    rng = np.random.default_rng(3)
    n = 12
    data = idf.make_phasors(rng.uniform(10, 500, n), rng.integers(0, 7, n), rng.integers(0, 2, n),
                            rng.normal(size=n) * 1e-5 + 1j * rng.normal(size=n) * 1e-5, run=np.arange(n) % 3,
                            trial={1: (2, 1.234567890123e-4, 0.1), 2: (4, 3e-4, -2.9)},
                            sigma=rng.uniform(1e-8, 1e-7, n))
    path = idf.write_phasors(str(tmp_path / "out.csv"), data)
    back = idf.read_phasors(path)
    assert back.path == path and back.kind == "unbalance" and back.n == n
    for name in ("speed", "node", "direction", "X", "run", "trial_node", "sigma"):
        np.testing.assert_array_equal(getattr(back, name), getattr(data, name), err_msg=name)
    np.testing.assert_array_equal(back.trial_magnitude, data.trial_magnitude)   # NaN where none
    np.testing.assert_array_equal(back.trial_phase, data.trial_phase)
    assert back.frequency is None and data.lines is None and back.lines[0] == 3     # a comment line, the header
    assert back.runs() == [0, 1, 2] and back.trial(0) is None and back.trial(2) == (4, 3e-4, -2.9)
    assert back.row(0) == "data row 1 (line 3)" and data.row(0) == "entry 0 (0-based)"
    sub = back.select(back.run == 1)
    assert sub.n == 4 and set(sub.run) == {1} and sub.lines == tuple(np.array(back.lines)[back.run == 1])


def test_round_trip_frf_and_reading(tmp_path):
    back = idf.read_phasors(_file(tmp_path, _text(FRF_HEADER, FRF_ROWS)))
    assert back.kind == "frf" and back.n == 3 and back.trial(0) is None
    np.testing.assert_array_equal(back.frequency, [50, 50, 60])
    np.testing.assert_array_equal(back.input_direction, [0, 0, 0])
    again = idf.read_phasors(idf.write_phasors(str(tmp_path / "frf2.csv"), back))
    for name in ("speed", "node", "direction", "X", "frequency", "input_node", "input_direction"):
        np.testing.assert_array_equal(getattr(again, name), getattr(back, name), err_msg=name)
    plain = idf.read_phasors(_file(tmp_path, _text(), name="plain.csv"))
    assert list(plain.direction) == [0, 1, 0, 1] and list(plain.node) == [2, 2, 2, 4]   # 'Y' accepted
    assert plain.X[0] == 1e-5 + 2e-6j and plain.sigma is None and list(plain.trial_node) == [-1] * 4
    trial = idf.read_phasors(_file(tmp_path, _text(TRIAL_HEADER, TRIAL_ROWS), name="trial.csv"))
    assert trial.trial(1) == (2, 1e-4, 0.5) and trial.trial(0) is None


EX = "speed,node,direction,real,imag"
# (id, file content, fragments the message must hold besides the path)
CASES = [
    ("missing column", _text("speed,node,direction,real,run", [r.rsplit(",", 2)[0] + ",0" for r in ROWS]),
     ["missing column(s) imag", "found speed, node, direction, real, run"]),
    ("unknown column", _text(HEADER + ",phase", [r + ",1" for r in ROWS]),
     ["unknown column(s) 'phase'", "speed, node, direction, real, imag (required)", "sigma"]),
    ("capitalised column", _text(edit=_set(1, 0, "Speed")), ["unknown column(s) 'Speed'", "lower case"]),
    ("non-numeric cell", _text(edit=_set(3, 3, "abc")), ["column 'real', data row 2 (line 3)", "'abc' is not a number"]),
    ("units in a cell", _text(edit=_set(2, 0, "100 rad/s")), ["column 'speed', data row 1 (line 2)", "'100 rad/s'"]),
    ("empty required cell", _text(edit=_set(4, 0, " ")), ["column 'speed', data row 3 (line 4)", "an empty cell"]),
    ("empty direction", _text(edit=_set(4, 2, "")), ["column 'direction', data row 3 (line 4)", "empty cell"]),
    ("nan cell", _text(edit=_set(5, 4, "nan")), ["column 'imag', data row 4 (line 5)", "not a finite number"]),
    ("direction z", _text(edit=_set(3, 2, "z")), ["column 'direction', data row 2 (line 3)", "'z' is not a direction",
                                                  "x or y"]),
    ("negative node", _text(edit=_set(2, 1, "-1")), ["column 'node', data row 1 (line 2)", "-1 is not an FE node"]),
    ("non-integer node", _text(edit=_set(5, 1, "2.5")), ["column 'node', data row 4 (line 5)", "2.5 is not",
                                                         "integer >= 0"]),
    ("run not integer", _text(edit=_set(4, 5, "1.5")), ["column 'run', data row 3 (line 4)", "1.5 is not a run label"]),
    ("speed 0 in an unbalance file", _text(edit=_set(3, 0, "0")), ["column 'speed', data row 2 (line 3)",
                                                                    "speed > 0"]),
    ("negative speed in an FRF file", _text(FRF_HEADER, FRF_ROWS, _set(3, 0, "-5")),
     ["column 'speed', data row 2 (line 3)", ">= 0"]),
    ("partial trial cells", _text(TRIAL_HEADER, TRIAL_ROWS, _set(4, 8, "")),
     ["column 'trial_phase', data row 3 (line 4)", "while trial_node, trial_magnitude are given", "all three empty"]),
    ("trial differs within a run", _text(TRIAL_HEADER, TRIAL_ROWS, _set(5, 7, "2e-4")),
     ["column 'trial_magnitude', data row 4 (line 5)", "run 1's trial weight", "data row 3 (line 4)",
      "same trial weight, or none"]),
    ("trial and none within a run", _text(TRIAL_HEADER, TRIAL_ROWS, lambda ls: _set(3, 6, "1")(
        _set(3, 7, "1e-4")(_set(3, 8, "0")(ls)))),
     ["column 'trial_node', data row 2 (line 3)", "run 0's trial weight is node 1", "but none in data row 1"]),
    ("trial magnitude zero", _text(TRIAL_HEADER, TRIAL_ROWS, lambda ls: _set(5, 7, "0")(_set(4, 7, "0")(ls))),
     ["column 'trial_magnitude', data row 3 (line 4)", "must be > 0"]),
    ("trial magnitude negative", _text(TRIAL_HEADER, TRIAL_ROWS, lambda ls: _set(5, 7, "-1e-4")(
        _set(4, 7, "-1e-4")(ls))), ["column 'trial_magnitude'", "-0.0001", "must be > 0"]),
    ("trial node -1", _text(TRIAL_HEADER, TRIAL_ROWS, lambda ls: _set(5, 6, "-1")(_set(4, 6, "-1")(ls))),
     ["column 'trial_node', data row 3 (line 4)", "-1 is not an FE node"]),
    ("incomplete trial columns", _text(HEADER + ",trial_node", [r + "," for r in ROWS]),
     ["incomplete trial-weight columns", "found trial_node", "trial_magnitude, trial_phase"]),
    ("duplicate rows", _text(edit=lambda ls: ls + [ls[1]]),
     ["data row 5 (line 6) repeats data row 1 (line 2)", "run 0, speed 100 rad/s, node 2, direction x"]),
    ("duplicate rows, direction case", _text(edit=lambda ls: ls + ["100,2,X,0,0,0"]),
     ["data row 5 (line 6) repeats data row 1 (line 2)"]),
    ("FRF file missing input_direction", _text(FRF_HEADER.rsplit(",", 1)[0], [r.rsplit(",", 1)[0] for r in FRF_ROWS]),
     ["incomplete FRF (impact test) columns", "found frequency, input_node", "not input_direction"]),
    ("FRF file with trial columns", _text(FRF_HEADER + ",trial_node,trial_magnitude,trial_phase",
                                          [r + ",,," for r in FRF_ROWS]), ["an FRF file", "trial-weight columns"]),
    ("frequency 0", _text(FRF_HEADER, FRF_ROWS, _set(4, 5, "0")), ["column 'frequency', data row 3 (line 4)",
                                                                     "must be > 0"]),
    ("input direction q", _text(FRF_HEADER, FRF_ROWS, _set(2, 7, "q")),
     ["column 'input_direction', data row 1 (line 2)", "'q' is not a direction"]),
    ("input node negative", _text(FRF_HEADER, FRF_ROWS, _set(3, 6, "-2")),
     ["column 'input_node', data row 2 (line 3)", "-2 is not an FE node"]),
    ("FRF duplicate", _text(FRF_HEADER, FRF_ROWS, lambda ls: ls + [ls[3]]),
     ["data row 4 (line 5) repeats data row 3 (line 4)", "frequency 60 rad/s"]),
    ("sigma 0", _text(HEADER + ",sigma", [r + ",1e-8" for r in ROWS], _set(5, 6, "0")),
     ["column 'sigma', data row 4 (line 5)", "must be > 0"]),
    ("sigma empty", _text(HEADER + ",sigma", [r + ",1e-8" for r in ROWS], _set(2, 6, "")),
     ["column 'sigma', data row 1 (line 2)", "an empty cell"]),
    ("ragged row", _text(edit=_set(3, 2, "x,7")), ["data row 2 (line 3) has 7 field(s)", "names 6 columns"]),
    ("utf-16", _text().encode("utf-16"), ["UTF-16", "UTF-8"]),
    ("empty file", b"", ["empty file (0 bytes)", EX, "one data row per phasor"]),
    ("header only", _text(rows=[]), ["no data rows", "one row per phasor"]),
    ("semicolon header", _text(edit=lambda ls: [ln.replace(",", ";") for ln in ls]), ["semicolons", EX]),
    ("no header", _text(edit=lambda ls: ls[1:]), ["line 1 is data", EX]),
    ("latin-1", _text(edit=_set(1, 5, "r\xfcn")).encode("latin-1"), ["not UTF-8", "line 1"]),
]


@pytest.mark.parametrize("content,fragments", [c[1:] for c in CASES], ids=[c[0] for c in CASES])
def test_bad_phasor_files(tmp_path, content, fragments):
    path = _file(tmp_path, content)
    with pytest.raises(InputError) as e:
        idf.read_phasors(path)
    msg = str(e.value)
    assert msg.startswith(path + ": "), msg
    for f in fragments:
        assert f in msg, (f, msg)
    assert "\n" not in msg


def test_enough_bad_file_cases():
    assert len(CASES) >= 20


@pytest.mark.parametrize("name,fragments", [("missing.csv", ["no such file"]), ("ph.txt", ["'.txt'", "CSV"])])
def test_bad_paths(tmp_path, name, fragments):
    if name.endswith(".txt"):
        _file(tmp_path, _text(), name)
    path = str(tmp_path / name)
    with pytest.raises(InputError) as e:
        idf.read_phasors(path)
    assert str(e.value).startswith(path) and all(f in str(e.value) for f in fragments), str(e.value)


@pytest.mark.parametrize("kwargs,fragment", [
    (dict(node=[1, 2, 3]), "arguments of different lengths"),
    (dict(direction=["x", "z"]), "direction[1]: 'z' is not a direction"),
    (dict(node=[2, -1]), "node[1]: -1 is not an FE node"),
    (dict(speed=[0.0, 1.0]), "speed[0]: 0: an unbalance response needs the rotor turning"),
    (dict(X=[np.nan, 1.0]), "X[0]: nan is not a finite number"),
    (dict(trial={5: (1, 1e-4, 0.0)}), "trial weight for run 5, but no phasor has that run"),
    (dict(trial={0: (1, -1e-4, 0.0)}), "trial[0]"),
    (dict(frequency=[1.0, 2.0]), "frequency given without input_node, input_direction"),
    (dict(speed=[5.0, 5.0]), "entry 1 (0-based) repeats entry 0 (0-based)"),
    (dict(sigma=[1e-8, 0.0]), "sigma[1]"),
])
def test_make_phasors_checks(kwargs, fragment):
    args = dict(speed=[5.0, 6.0], node=[2, 2], direction=["x", "x"], X=[1e-6, 2e-6])
    args.update(kwargs)
    with pytest.raises(InputError) as e:
        idf.make_phasors(**args)
    assert str(e.value).startswith("make_phasors: ") and fragment in str(e.value), str(e.value)


# --- raw signals to phasors -----------------------------------------------------------

def _raw_run(theta_of_t, duration, run=None, t0=0.0, X=X_TRUE, trial=(-1, 0.0, 0.0)):
    """Samples of one run: the rotor angle `theta_of_t(t - t0)`, a tacho whose rising zero
    crossings mark theta = 2 pi k (a sine: exact edges), sensors Re(X e^{i theta})."""
    t = t0 + np.arange(int(duration * FS)) / FS
    theta = theta_of_t(t - t0)
    cols = {"time": t, "tacho": np.sin(theta)}
    for m, Xm in enumerate(X):
        cols[f"x{m + 1}"] = np.real(Xm * np.exp(1j * theta))
    if run is not None:
        cols.update(run=np.full(t.size, float(run)), trial_plane=np.full(t.size, float(trial[0])),
                    trial_unbalance=np.full(t.size, trial[1]), trial_angle=np.full(t.size, trial[2]))
    return cols


def _steady(f=20.0):
    return lambda t: 2 * np.pi * f * t


def _runup(f0=10.0, rate=20.0):
    return lambda t: 2 * np.pi * (f0 * t + 0.5 * rate * t**2)


def _write_raw(tmp_path, cols, channels="x1=2:x, x2=2:y", name="raw.csv"):
    head = f"# channels: {channels}\n" if channels is not None else ""
    table = np.stack(list(cols.values()), 1)
    body = "\n".join(",".join(f"{v:.17g}" for v in row) for row in table)
    return _file(tmp_path, head + ",".join(cols) + "\n" + body + "\n", name)


def _cat(*runs):
    return {k: np.concatenate([r[k] for r in runs]) for k in runs[0]}


def test_steady_run_to_phasors(tmp_path):
    path = _write_raw(tmp_path, _raw_run(_steady(), 1.0))
    data = idf.phasors_from_signals(path)
    assert data.n == 2 and data.kind == "unbalance" and data.path == path and data.runs() == [0]
    np.testing.assert_array_equal(data.node, [2, 2])
    np.testing.assert_array_equal(data.direction, [0, 1])
    assert np.all(np.abs(data.X - X_TRUE) <= 1e-3 * np.abs(X_TRUE)), data.X
    assert data.speed[0] == pytest.approx(2 * np.pi * 20.0, rel=1e-6)
    assert data.trial(0) is None
    # the map as an argument overrides the file's line; a dict does as well
    swapped = idf.phasors_from_signals(path, "x1=4:y,x2=3:x")
    np.testing.assert_array_equal(swapped.node, [4, 3])
    np.testing.assert_array_equal(swapped.direction, [1, 0])
    as_dict = idf.phasors_from_signals(path, {"x1": (4, "y"), "x2": (3, "X")})
    np.testing.assert_array_equal(as_dict.X, swapped.X)


def test_runs_with_trial_weights_and_a_runup(tmp_path):
    cols = _cat(_raw_run(_steady(), 1.0, run=0),
                _raw_run(_steady(), 1.0, run=1, t0=1.0, X=2 * X_TRUE, trial=(2, 1e-4, 90.0)),
                _raw_run(_runup(), 2.0, run=2, t0=2.0, trial=(4, 2e-4, -30.0)))
    path = _write_raw(tmp_path, cols)
    data = idf.phasors_from_signals(path, revolutions_per_block=2)
    assert data.runs() == [0, 1, 2]
    assert data.trial(0) is None
    assert data.trial(1) == (2, 1e-4, pytest.approx(np.pi / 2))
    assert data.trial(2) == (4, 2e-4, pytest.approx(np.radians(-30.0)))
    r1 = data.select(data.run == 1)
    assert r1.n == 2 and np.all(np.abs(r1.X - 2 * X_TRUE) <= 1e-3 * np.abs(2 * X_TRUE))
    ramp = data.select(data.run == 2)
    n_blocks = ramp.n // 2
    # 10 rev/s rising by 20 rev/s^2 for 2 s: 60 revolutions, 30 blocks of 2 (the last one partial)
    assert 28 <= n_blocks <= 30 and len(np.unique(ramp.speed)) == n_blocks
    assert np.all(np.diff(ramp.speed[::2]) > 0)
    assert ramp.speed.min() > 2 * np.pi * 10 and ramp.speed.max() < 2 * np.pi * 50
    X = ramp.X.reshape(n_blocks, 2)
    assert np.all(np.abs(X - X_TRUE) <= 1e-3 * np.abs(X_TRUE)), np.max(np.abs(X - X_TRUE) / np.abs(X_TRUE))
    back = idf.read_phasors(idf.write_phasors(str(tmp_path / "ph.csv"), data))
    np.testing.assert_array_equal(back.X, data.X)


RAW_CASES = [
    (dict(mapping="x1=2:x,x3=2:y"), ["--map x1=2:x,x3=2:y: channel 'x3' is not a sensor column", "x1, x2"]),
    (dict(mapping="x1=2"), ["--map x1=2: 'x1=2' is not CHANNEL=NODE:DIR"]),
    (dict(mapping="x1=-1:x,x2=2:y"), ["--map", "node '-1' is not an FE node number"]),
    (dict(mapping="x1=1.5:x,x2=2:y"), ["--map", "node '1.5' is not an FE node number"]),
    (dict(mapping="x1=2:z,x2=2:y"), ["--map", "direction 'z' is not x or y"]),
    (dict(mapping="x1=2:x,,x2=2:y"), ["--map", "an empty item"]),
    (dict(mapping=""), ["--map ''", "empty channel map"]),
    (dict(mapping="x1=2:x,x2=2:x"), ["--map", "channels x1 and x2 both map to node 2, direction x"]),
    (dict(mapping="x1=2:x,x1=3:y"), ["--map", "channel x1 is mapped more than once"]),
    (dict(mapping="x1=2:x"), ["sensor column(s) x2 without a channel map entry"]),
    (dict(mapping={"x1": (2, "x"), "x2": 3}), ["mapping: 'x2': 3: expected (node, 'x' or 'y')"]),
    (dict(mapping={"x1": (2, "x"), "x2": (3, "w")}), ["mapping", "direction 'w' is not x or y"]),
    (dict(channels="x1=2:z, x2=2:y"), ["line 1 ('# channels: x1=2:z, x2=2:y')", "direction 'z' is not x or y"]),
    (dict(channels="x1=2:x"), ["sensor column(s) x2 without a channel map entry"]),
    (dict(channels=None), ["no channel map", "--map", "# channels:"]),
    (dict(revolutions_per_block=0), ["revolutions_per_block must be an integer >= 1"]),
]


@pytest.mark.parametrize("kwargs,fragments", RAW_CASES, ids=[str(c[0])[:50] for c in RAW_CASES])
def test_bad_channel_maps(tmp_path, kwargs, fragments):
    kwargs = dict(kwargs)
    about_file = "channels" in kwargs or any("channel map entry" in f or "no channel map" in f for f in fragments)
    path = _write_raw(tmp_path, _raw_run(_steady(), 0.5), channels=kwargs.pop("channels", "x1=2:x, x2=2:y"))
    with pytest.raises(InputError) as e:
        idf.phasors_from_signals(path, **kwargs)
    msg = str(e.value)
    for f in fragments:
        assert f in msg, (f, msg)
    assert msg.startswith(path) if about_file else msg.startswith(("--map", "mapping", "revolutions")), msg


# --- the `phasors` command ------------------------------------------------------------------

def test_cli_phasors(tmp_path, capsys):
    raw = _write_raw(tmp_path, _cat(_raw_run(_steady(), 1.0, run=0),
                                    _raw_run(_runup(), 2.0, run=1, t0=1.0, trial=(2, 1e-4, 45.0))))
    out = str(tmp_path / "ph.csv")
    assert main(["phasors", raw, "--out", out, "--revolutions", "4"]) == 0
    text = capsys.readouterr().out
    assert "2 run(s)" in text and "steady" in text and "order-tracked" in text and f"wrote {out}" in text
    data = idf.read_phasors(out)
    assert data.runs() == [0, 1] and data.trial(1)[0] == 2
    assert main(["phasors", raw, "--out", out, "--map", "x1=5:y,x2=6:y", "--json", "--revolutions", "4"]) == 0
    js = json.loads(capsys.readouterr().out)
    assert js["file"] == out and js["rows"] == idf.read_phasors(out).n == data.n
    assert data.n in (2 + 2 * 14, 2 + 2 * 15)        # 60 revolutions in blocks of 4 (the last may be cut)
    assert [r["speeds"] for r in js["runs"]] == [1, (data.n - 2) // 2]
    assert [r["run"] for r in js["runs"]] == [0, 1] and js["runs"][1]["trial"]["node"] == 2
    lo, hi = js["speed_range"]
    assert 2 * np.pi * 10 < lo < hi < 2 * np.pi * 50
    assert set(idf.read_phasors(out).node) == {5, 6}


@pytest.mark.parametrize("argv,match", [
    (["{d}/nosuch.csv", "--out", "{d}/o.csv"], "nosuch.csv: no such file"),
    (["{raw}", "--out", "{d}/o.csv", "--map", "x1=2:q,x2=2:y"], "--map x1=2:q,x2=2:y: 'x1=2:q': direction 'q'"),
    (["{raw}", "--out", "{d}/o.csv", "--map", "x1=2:x,x9=2:y"], "channel 'x9' is not a sensor column"),
    (["{raw}", "--out", "{d}/o.txt"], "--out .*o.txt: a phasor file is CSV"),
    (["{raw}", "--out", "{d}"], "--out .*: is a folder"),
    (["{raw}", "--out", "{d}/no/such/o.csv"], "--out .*the folder .* does not exist"),
    (["{raw}", "--out", "{d}/o.csv", "--revolutions", "0"], "argument --revolutions: must be an integer >= 1"),
    (["{raw}"], "the following arguments are required: --out"),
    (["{noheader}", "--out", "{d}/o.csv"], "no channel map"),
])
def test_cli_phasors_bad_input(tmp_path, capsys, argv, match):
    import re

    raw = _write_raw(tmp_path, _raw_run(_steady(), 0.5))
    noheader = _write_raw(tmp_path, _raw_run(_steady(), 0.5), channels=None, name="nomap.csv")
    argv = ["phasors"] + [a.replace("{d}", str(tmp_path)).replace("{raw}", raw).replace("{noheader}", noheader)
                          for a in argv]
    rc = main(argv)
    err = capsys.readouterr().err
    assert rc == 2, err
    assert re.search(match, err), err
    assert "Traceback" not in err
