"""Where the commands write (issue 29, item 6): under `./rotorjax-out` of the current
directory, or `--out`; never into the installed package, beside a shipped rotor file."""

import json
import pathlib

import rotorjax
from rotorjax.cli import build_parser, main
from rotorjax.cli._common import DEFAULT_OUT

PACKAGE = pathlib.Path(rotorjax.__file__).resolve().parent
ROTORS = PACKAGE / "rotors"


def _files(folder):
    return sorted(str(p.relative_to(folder)) for p in folder.rglob("*") if p.is_file() and "__pycache__" not in p.parts)


def test_every_out_option_defaults_to_rotorjax_out():
    """Each command that writes a folder of files takes `--out DIR`, by default
    `rotorjax-out` (a relative path: in the current directory). `phasors --out` and
    `import-ross --out` name the one file each writes: phasors' has no default,
    import-ross's is beside the file it reads."""
    assert DEFAULT_OUT == "rotorjax-out"
    parser = build_parser()
    sub = next(a for a in parser._actions if a.__class__.__name__ == "_SubParsersAction")
    with_out = {}
    for name, p in sub.choices.items():
        for action in p._actions:
            if "--out" in action.option_strings:
                with_out[name] = action.default
    assert with_out.pop("phasors") is None and with_out.pop("import-ross") is None
    assert with_out and set(with_out.values()) == {DEFAULT_OUT}, with_out
    for command in ("static", "modes", "campbell", "simulate", "balance", "identify", "bench", "demo"):
        assert with_out.get(command) == DEFAULT_OUT, command


def test_a_shipped_rotor_writes_under_rotorjax_out(tmp_path, monkeypatch):
    """`rotorjax static ross_compare.toml` (the shipped rotor file, found by its name)
    run in a folder writes its PNG and JSON to `./rotorjax-out` there, and nothing
    beside the rotor file (it once wrote `ross_compare.toml.json` into the package)."""
    before = _files(ROTORS)
    monkeypatch.chdir(tmp_path)
    assert main(["static", "ross_compare.toml", "--json"]) == 0
    assert _files(tmp_path) == ["rotorjax-out/static_ross_compare.json", "rotorjax-out/static_ross_compare.png"]
    assert _files(ROTORS) == before
    assert not any(name.startswith("ross_compare.toml.") for name in before)   # no generated file shipped
    out = json.loads((tmp_path / "rotorjax-out" / "static_ross_compare.json").read_text())
    assert out["files"] == {"plot": "rotorjax-out/static_ross_compare.png"}    # relative, as the default is
    assert (tmp_path / "rotorjax-out" / "static_ross_compare.png").read_bytes()[:4] == b"\x89PNG"


def test_out_keeps_its_meaning(tmp_path, monkeypatch):
    """`--out DIR` still chooses the folder; nothing goes to `./rotorjax-out` then."""
    monkeypatch.chdir(tmp_path)
    assert main(["static", "ross_compare.toml", "--out", "elsewhere", "--json"]) == 0
    assert _files(tmp_path) == ["elsewhere/static_ross_compare.json", "elsewhere/static_ross_compare.png"]
