"""Measurement files: every malformed file gets an InputError naming the file and the
culprit (column, row); the balancing's own checks; shipped datasets by name."""

import io
import os
import zipfile

import numpy as np
import pytest

from rotorjax import identify as idf
from rotorjax._errors import InputError
from tests.helpers import set_csv_field

F, FS, N = 20.0, 1000.0, 500          # 20 rev/s sampled at 1 kHz, 0.5 s (10 revolutions) per run


def _run(label, plane=-1, unbalance=0.0, angle=0.0, f=F, t0=0.0, X=None, sensors=2):
    t = t0 + np.arange(N) / FS
    theta = 2 * np.pi * f * (t - t0)
    k = np.floor(theta / (2 * np.pi) + 1e-9)
    tacho = np.zeros(N)
    tacho[1:][np.diff(k) > 0] = 1.0
    if X is None:
        X = np.array([1.0, 0.5j]) + (plane + 1) * np.array([0.3, 0.2 - 0.1j]) * np.exp(1j * np.radians(angle))
    cols = {"time": t, "tacho": tacho}
    for m in range(sensors):
        cols[f"x{m + 1}"] = 1e-6 * np.real(X[m] * np.exp(1j * theta))
    cols.update(run=np.full(N, float(label)), trial_plane=np.full(N, float(plane)),
                trial_unbalance=np.full(N, unbalance), trial_angle=np.full(N, angle))
    return cols


def _runs(*specs, sensors=2):
    """Runs back to back in time; `specs`: keyword dicts of `_run` (label = position)."""
    runs = [_run(i, t0=i * N / FS, sensors=sensors, **s) for i, s in enumerate(specs)]
    return {k: np.concatenate([r[k] for r in runs]) for k in runs[0]}


BALANCING = ({}, dict(plane=0, unbalance=1e-4), dict(plane=1, unbalance=1e-4, angle=90.0))


def _csv_text(cols):
    buf = io.StringIO()
    np.savetxt(buf, np.stack(list(cols.values()), 1), delimiter=",", fmt="%.12g")
    return ",".join(cols) + "\n" + buf.getvalue()


def _steady():
    """One steady run without run or trial columns."""
    c = _run(0)
    return {k: c[k] for k in ("time", "tacho", "x1", "x2")}


def _write(tmp_path, name, content):
    path = tmp_path / name
    if isinstance(content, bytes):
        path.write_bytes(content)
    else:
        path.write_text(content)
    return str(path)


def _csv(cols=None, edit=None, name="bad.csv"):
    """A builder: the CSV of `cols` (default: one steady run), its lines passed through `edit`."""
    def build(tmp_path):
        lines = _csv_text(_steady() if cols is None else cols()).split("\n")
        if edit is not None:
            lines = edit(lines)
        return _write(tmp_path, name, "\n".join(lines))
    return build


_set = set_csv_field


def _npz(cols, name="bad.npz"):
    def build(tmp_path):
        path = str(tmp_path / name)
        np.savez(path, **cols())
        return path
    return build


def _with(**changes):
    """One steady run with columns replaced (None: removed)."""
    def cols():
        c = _steady()
        for k, v in changes.items():
            if v is None:
                c.pop(k)
            else:
                c[k] = v(c) if callable(v) else v
        return c
    return cols


def _balancing(*specs, sensors=2, mutate=None):
    def cols():
        c = _runs(*specs, sensors=sensors)
        if mutate is not None:
            mutate(c)
        return c
    return cols


def _truncated_npz(tmp_path):
    path = str(tmp_path / "cut.npz")
    np.savez(path, **_steady())
    raw = open(path, "rb").read()
    open(path, "wb").write(raw[: len(raw) // 2])
    return path


def _npz_without_arrays(tmp_path):
    path = str(tmp_path / "none.npz")
    with zipfile.ZipFile(path, "w") as z:
        z.writestr("readme.txt", "no arrays here")
    return path


read = idf.read_signals
balance = idf.balancing_runs

# (id, builder(tmp_path) -> path, function, fragments the message must hold besides the path)
CASES = [
    ("nonexistent", lambda p: str(p / "missing.csv"), read, ["no such file", "runup", "balancing-runs"]),
    ("directory", lambda p: str(p), read, ["is a directory"]),
    ("empty", lambda p: _write(p, "empty.csv", b""), read, ["empty file (0 bytes)", "header row"]),
    ("blank lines only", lambda p: _write(p, "blank.csv", "\n \n"), read, ["empty file"]),
    ("header only", lambda p: _write(p, "head.csv", "time,tacho,x1\n"), read,
     ["no data rows", "time, tacho, x1"]),
    ("binary as csv", lambda p: _write(p, "bin.csv", bytes(range(256)) * 4), read,
     ["binary data", "offset 0", ".npz"]),
    ("xlsx renamed csv", lambda p: _write(p, "book.csv", b"PK\x03\x04\x14\x00\x00\x00\x08\x00"), read,
     ["a zip archive", "Excel", "export the sheet as CSV"]),
    ("latin-1 header", lambda p: _write(p, "latin.csv", "time,tacho,x1,x2 \xb5m\n0,0,1,2\n".encode("latin-1")),
     read, ["not UTF-8", "0xb5", "line 1"]),
    ("utf-16", lambda p: _write(p, "wide.csv", "time,tacho,x1\n0,0,1\n".encode("utf-16")), read, ["UTF-16"]),
    ("truncated last row", _csv(edit=lambda ls: ls[:-1][:-1] + [ls[-2][:5]]), read,
     [f"data row {N} (line {N + 1})", "1 field(s)", "4 columns", "truncated"]),
    ("ragged row", _csv(edit=_set(6, 2, "1,2")), read, ["data row 5 (line 6)", "5 field(s)"]),
    ("non-numeric cell", _csv(edit=_set(4, 2, "abc")), read, ["column 'x1'", "data row 3 (line 4)", "'abc'"]),
    ("empty cell", _csv(edit=_set(9, 3, " ")), read, ["column 'x2'", "data row 8 (line 9)", "empty cell"]),
    ("units in a cell", _csv(edit=_set(3, 0, "0.001 s")), read, ["column 'time'", "data row 2", "'0.001 s'"]),
    ("txt extension", _csv(name="run.txt"), read, ["'.txt'", "CSV", ".npz"]),
    ("xlsx extension", lambda p: _write(p, "runs.xlsx", b"PK\x03\x04"), read, ["'.xlsx'", "CSV", ".npz"]),
    ("no extension", _csv(name="runs"), read, ["no extension", ".npz"]),
    ("npz not a zip", lambda p: _write(p, "text.npz", "time,tacho\n0,1\n"), read, ["not a valid .npz"]),
    ("npz truncated", _truncated_npz, read, ["not a valid .npz", "truncated"]),
    ("npz without arrays", _npz_without_arrays, read, ["holds no arrays of numbers", "readme.txt"]),
    ("npz missing tacho", _npz(_with(tacho=None)), read, ["missing column(s) tacho", "found time, x1, x2"]),
    ("npz different lengths", _npz(_with(x2=lambda c: c["x2"][:-1])), read,
     ["different lengths", f"x1 {N}", f"x2 {N - 1}"]),
    ("npz 2-D array", _npz(_with(x1=lambda c: np.stack([c["x1"], c["x1"]], 1))), read, ["'x1'", "shape"]),
    ("npz text array", _npz(_with(x1=lambda c: c["x1"].astype(str))), read, ["'x1'", "dtype"]),
    ("npz NaN", _npz(_with(x1=lambda c: np.where(np.arange(N) == 7, np.nan, c["x1"]))), read,
     ["column 'x1'", "sample index 7 (0-based)"]),
    ("duplicate column", _csv(edit=_set(1, 3, "x1")), read, ["duplicate column name 'x1'", "columns 3 and 4"]),
    ("unnamed column", _csv(edit=lambda ls: [ls[0] + ","] + [ln + ",0" for ln in ls[1:] if ln]), read,
     ["column 5 of the header", "no name"]),
    ("semicolons", _csv(edit=lambda ls: [ln.replace(",", ";") for ln in ls]), read, ["semicolons", "commas"]),
    ("no header", _csv(edit=lambda ls: ls[1:]), read, ["line 1 is data", "not a header"]),
    ("missing time", _csv(_with(time=None)), read, ["missing column(s) time", "found tacho, x1, x2"]),
    ("capitalised names", _csv(edit=_set(1, 0, "Time")), read, ["missing column(s) time", "found Time, tacho",
                                                                  "case-sensitive"]),
    ("missing sensor asked for", lambda p: _csv()(p), lambda path: read(path, sensors=["x1", "x3"]),
     ["missing column(s) x3"]),
    ("no sensor columns", _csv(_with(x1=None, x2=None, y1=lambda c: c["time"])), read,
     ["no sensor columns", "found time, tacho, y1"]),
    ("NaN", _csv(edit=_set(9, 3, "nan")), read, ["column 'x2'", "NaN", "data row 8 (line 9)"]),
    ("inf", _csv(edit=_set(12, 1, "inf")), read, ["column 'tacho'", "data row 11 (line 12)"]),
    ("time not increasing", _csv(edit=_set(7, 0, "0.003")), read,
     ["time is not strictly increasing", "data row 6 (line 7)", "0.003 after 0.004"]),
    ("runs without a run column", _csv(lambda: {k: v for k, v in _runs({}, {}).items() if k in ("time", "tacho",
     "x1")}, edit=_set(N + 2, 0, "0")), read, [f"data row {N + 1} (line {N + 2})", "need a 'run' column"]),
    ("time not increasing in a run", _csv(_balancing(*BALANCING), edit=_set(N + 5, 0, "0")), read,
     ["time is not strictly increasing in run 1", f"data row {N + 4} (line {N + 5})"]),
    ("constant tacho", _csv(_with(tacho=lambda c: np.zeros(N))), read, ["tacho channel is constant"]),
    ("one pulse", _csv(_with(tacho=lambda c: (np.arange(N) == 60).astype(float))), read,
     ["1 rising edge", "at least 2 pulses"]),
    ("constant tacho in one run", _csv(_balancing(*BALANCING, mutate=lambda c: c["tacho"].__setitem__(
        slice(N, 2 * N), 0.0))), read, ["run 1", "tacho channel is constant"]),
    ("trial columns partial", _csv(_balancing(*BALANCING, mutate=lambda c: c.pop("trial_angle"))), read,
     ["incomplete trial-weight columns", "found trial_plane, trial_unbalance", "trial_angle"]),
    ("run label not integer", _csv(_balancing(*BALANCING), edit=_set(N + 2, 4, "1.5")), read,
     ["column 'run'", f"data row {N + 1}", "1.5 is not an integer run label"]),
    ("trial plane -2", _csv(_balancing(*BALANCING, mutate=lambda c: c["trial_plane"].__setitem__(
        slice(2 * N, 3 * N), -2.0))), read, ["column 'trial_plane'", f"data row {2 * N + 1}", "-2 is not a plane",
                                             "-1 (none)"]),
    ("trial plane 0.5", _csv(_balancing(*BALANCING), edit=_set(2, 5, "0.5")), read,
     ["column 'trial_plane'", "data row 1 (line 2)", "0.5 is not a plane"]),
    ("trial weight changes in a run", _csv(_balancing(*BALANCING), edit=_set(N + 11, 7, "45")), read,
     ["column 'trial_angle' changes within run 1", f"data row {N + 10} (line {N + 11})"]),
    ("trial unbalance zero", _csv(_balancing({}, dict(plane=0, unbalance=0.0))), read,
     ["column 'trial_unbalance'", f"data row {N + 1}", "run 1", "must be > 0"]),
    ("trial unbalance negative", _csv(_balancing({}, dict(plane=0, unbalance=-1e-4))), balance,
     ["trial_unbalance", "must be > 0"]),
    ("trial unbalance inf", _csv(_balancing({}, dict(plane=0, unbalance=np.inf))), balance,
     ["column 'trial_unbalance'", "NaN or infinite"]),
    # the balancing's own checks
    ("no run without trial", _csv(_balancing(dict(plane=0, unbalance=1e-4), dict(plane=1, unbalance=1e-4))),
     balance, ["need exactly one run without a trial weight", "found 0"]),
    ("two runs without trial", _csv(_balancing(*BALANCING, {})), balance,
     ["need exactly one run without a trial weight", "found 2 (runs 0, 3)"]),
    ("no trial runs", _csv(), balance, ["no runs with a trial weight"]),
    ("fewer sensors than planes", _csv(_balancing(*BALANCING, sensors=1)), balance,
     ["has 1 sensor column (x1) but 2 trial planes: need at least as many sensors as planes"]),
    ("two trial runs in one plane", _csv(_balancing(*BALANCING, dict(plane=0, unbalance=2e-4))), balance,
     ["runs 1 and 3 both have a trial weight in plane 0"]),
    ("plane without trial run", _csv(_balancing(*BALANCING)), lambda path: balance(path, planes=[0, 5]),
     ["no trial run for plane(s) [5]", "trial planes in the file: [0, 1]"]),
    ("trial run at another speed", _csv(_balancing({}, dict(plane=0, unbalance=1e-4, f=1.2 * F))), balance,
     ["run 1 (trial weight in plane 0) turns at 150.", "run 0 (no trial weight) at 125.7 rad/s"]),
    ("trial changed nothing", _csv(_balancing({}, dict(plane=0, unbalance=1e-4, X=np.array([1.0, 0.5j])))),
     balance, ["run 1 (trial weight in plane 0) has the same 1x vibration as run 0"]),
    ("too few samples in a run", _csv(_balancing(*BALANCING, mutate=lambda c: c["tacho"].__setitem__(
        slice(0, N), np.isin(np.arange(N), (1, 5)).astype(float)))), balance,
     ["run 0: 4 samples lie within whole revolutions: at least 8 are needed"]),
]


@pytest.mark.parametrize("build,func,fragments", [c[1:] for c in CASES], ids=[c[0] for c in CASES])
def test_bad_files_get_an_input_error_naming_file_and_culprit(tmp_path, build, func, fragments):
    path = build(tmp_path)
    with pytest.raises(InputError) as e:
        func(path)
    msg = str(e.value)
    assert isinstance(e.value, ValueError)
    assert msg.startswith(path), msg
    for f in fragments:
        assert f in msg, (f, msg)
    assert "\n" not in msg and "Traceback" not in msg


def test_planes_argument_is_checked(tmp_path):
    path = _csv(_balancing(*BALANCING))(tmp_path)
    for planes, fragment in (("0,a", "comma-separated plane numbers, got '0,a'"), ([0.5], "integers"),
                             ([0, 0], "given more than once"), ([], "at least one plane")):
        with pytest.raises(InputError, match="planes"):
            balance(path, planes=planes)
        try:
            balance(path, planes=planes)
        except InputError as e:
            assert fragment in str(e)


def test_valid_files_csv_npz_and_plane_selection(tmp_path):
    cols = _runs(*BALANCING)
    csv = _csv(lambda: cols, name="good.csv")(tmp_path)
    npz = _npz(lambda: cols, name="good.npz")(tmp_path)
    a, b = idf.read_signals(csv), idf.read_signals(npz)
    assert a["sensors"] == b["sensors"] == ["x1", "x2"] and a["path"] == csv
    for k in cols:
        np.testing.assert_allclose(a[k], b[k], rtol=1e-11, atol=1e-18)
    data = idf.balancing_runs(csv)
    assert data.planes == (0, 1) and data.sensors == ("x1", "x2") and data.n_samples_base == N
    assert data.speed == pytest.approx(2 * np.pi * F, rel=1e-3)
    np.testing.assert_allclose(data.trial_unbalances, [1e-4, 1e-4j], atol=1e-18)
    assert data.X_trials.shape == (2, 2)
    one = idf.balancing_runs(csv, planes="1")          # one plane needs only one sensor
    assert one.planes == (1,) and list(one.trials_by_plane) == [1]
    single = _csv(_balancing(*BALANCING[:2], sensors=1), name="one.csv")(tmp_path)
    assert idf.balancing_runs(single).planes == (0,)


def test_savetxt_default_comment_header_and_crlf(tmp_path):
    """`np.savetxt(..., header=...)` comments the header out; Windows line ends."""
    c = _steady()
    path = str(tmp_path / "commented.csv")
    np.savetxt(path, np.stack(list(c.values()), 1), delimiter=",", header=",".join(c))
    assert idf.read_signals(path)["sensors"] == ["x1", "x2"]
    crlf = _write(tmp_path, "crlf.csv", _csv_text(c).replace("\n", "\r\n").encode())
    np.testing.assert_allclose(idf.read_signals(crlf)["x2"], c["x2"], rtol=1e-11, atol=1e-18)


def test_sensor_columns_in_numeric_order(tmp_path):
    c = _steady()
    cols = {"time": c["time"], "tacho": c["tacho"], **{f"x{m}": c["x1"] for m in (10, 2, 1)}}
    assert idf.read_signals(_csv(lambda: cols)(tmp_path))["sensors"] == ["x1", "x2", "x10"]


def test_signal_functions_raise_input_errors():
    t = np.arange(100) / FS
    with pytest.raises(InputError, match="sample index 5"):
        idf.phasors(t, np.where(np.arange(100) == 5, np.nan, 0.0), pulses=np.array([0.0, 0.05]))
    with pytest.raises(InputError, match="strictly increasing"):
        idf.phasors(t, np.zeros(100), pulses=np.array([0.05, 0.0]))
    with pytest.raises(InputError, match="tacho channel or the pulse times"):
        idf.order_track(t, np.zeros(100))
    with pytest.raises(InputError, match="revolutions_per_block"):
        idf.order_track(t, np.zeros(100), pulses=np.array([0.0, 0.05]), revolutions_per_block=0)


# --- shipped datasets by name --------------------------------------------------

@pytest.mark.parametrize("name,expected", [("runup", "RUNUP"), ("balancing-runs", "BALANCING_RUNS"),
                                           ("balancing_runs", "BALANCING_RUNS")])
def test_dataset_names_resolve_to_the_shipped_files(name, expected):
    path = idf.resolve_data(name)
    assert path == idf.dataset_path(name) == getattr(idf, expected)
    assert os.path.isabs(path) and os.path.isfile(path) and os.path.dirname(path) == idf.DATA_DIR


def test_datasets_table():
    assert set(idf.DATASETS) == {"runup", "balancing-runs", "flexible-runup", "flexible-trials"}
    for name, (filename, description) in idf.DATASETS.items():
        assert os.path.isfile(os.path.join(idf.DATA_DIR, filename))
        assert description and "\n" not in description


def test_paths_resolve_to_absolute_paths(tmp_path, monkeypatch):
    path = _csv(name="mine.csv")(tmp_path)
    assert idf.resolve_data(path) == path
    import pathlib
    assert idf.resolve_data(pathlib.Path(path)) == path
    monkeypatch.chdir(tmp_path)
    assert idf.resolve_data("mine.csv") == path
    assert idf.read_signals("mine.csv")["path"] == "mine.csv"


@pytest.mark.parametrize("arg", ["runupp", "no/such/file.csv", ""])
def test_unknown_names_list_the_datasets(arg):
    with pytest.raises(InputError) as e:
        idf.resolve_data(arg)
    assert arg in str(e.value) and "runup" in str(e.value) and "balancing-runs" in str(e.value)
    with pytest.raises(InputError, match="unknown dataset"):
        idf.dataset_path(arg)


def test_shipped_datasets_read_by_name():
    data = idf.balancing_runs("balancing-runs")
    assert data.path == "balancing-runs" and data.planes == (0, 1) and data.n_samples_base == 4000
    assert data.speed == pytest.approx(120.0, rel=1e-3)
    assert idf.read_signals("runup")["sensors"] == ["x1", "x2"]
