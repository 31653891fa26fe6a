"""Reading a rotor file: the TOML text, the messages' vocabulary (an entry named as
the file names it), and overrides (`--set`) applied before anything is checked."""

import difflib
import importlib.resources
import json
import os
import pathlib
import re
import tomllib

import jax
import numpy as np

from .._errors import InputError
from .._units import to_si
from ..models._plausibility import warn
from ..models._validate import is_concrete
from ._schema import SCHEMA, SINGLE_KEY_ALIASES


class Ctx:
    """The file being read: its label (the path as given) and the entries set by
    overrides (named in messages as well)."""

    def __init__(self, label):
        self.label = label
        self.overridden = {}
        self.warnings = []

    def _note(self, loc):
        return f" (set by the override {self.overridden[loc]})" if loc in self.overridden else ""

    def fail(self, msg, loc=None):
        raise InputError(f"{self.label}: {msg}{self._note(loc)}")

    def warn(self, msg, loc=None):
        """Note a plausibility warning; issued once the whole file is valid."""
        text = f"{self.label}: {msg}{self._note(loc)}"
        if text not in self.warnings:
            self.warnings.append(text)

    def issue_warnings(self):
        for text in self.warnings:
            warn(text)


def location(table, index, key=None):
    s = table if index is None else f"{table}[{index}]"
    return s if key is None else f"{s}.{key}"


def toml_repr(value):
    """A value as TOML would write it (for messages)."""
    if isinstance(value, bool):
        return "true" if value else "false"
    if isinstance(value, str):
        return json.dumps(value, ensure_ascii=False)
    if isinstance(value, float):
        return repr(value)
    if isinstance(value, list):
        return "[" + ", ".join(toml_repr(v) for v in value) + "]"
    if isinstance(value, dict):
        return "{" + ", ".join(f"{k} = {toml_repr(v)}" for k, v in value.items()) + "}"
    return str(value)


def describe_value(value):
    """`value`'s TOML type in words, with the value."""
    if isinstance(value, bool):
        return f"a boolean ({toml_repr(value)})"
    if isinstance(value, str):
        return f"a string ({toml_repr(value)})"
    if isinstance(value, list):
        return f"a list ({toml_repr(value)})"
    if isinstance(value, dict):
        return "a table"
    if isinstance(value, (int, float)):
        return f"the number {toml_repr(value)}"
    return f"a {type(value).__name__} ({value})"


def _closest(name, known):
    """The key `name` most likely meant, or `None`: a doubled last letter (`kx` ->
    `kxx`, `cy` -> `cyy`: the direct coefficient before a cross one), the first key
    that starts with it (`spee` -> `speed`), a different case (`ip` -> `Ip`), else
    the nearest by `difflib` (`kzz` -> `kxx`)."""
    known = list(known)
    if not isinstance(name, str) or not name:
        return None
    if name + name[-1] in known:
        return name + name[-1]
    prefixed = [k for k in known if k.startswith(name)]
    if prefixed:
        return prefixed[0]
    folded = [k for k in known if k.lower() == name.lower()]
    if folded:
        return folded[0]
    close = difflib.get_close_matches(name, known, n=1)
    return close[0] if close else None


def suggest(name, known):
    close = _closest(name, known)
    return f" (did you mean {close!r}?)" if close else ""


def read_toml(path):
    """The file's label and its parsed TOML."""
    if not isinstance(path, (str, os.PathLike)):
        raise InputError(f"rotor file: expected a path, got {type(path).__name__}")
    label = os.fspath(path)
    p = pathlib.Path(label)
    if not p.exists() and os.sep not in label and label.endswith(".toml"):
        try:  # a bare name of a shipped rotor file (`flexible_rig.toml`), as the CLI finds it
            p = shipped_rotor(label)
        except InputError:
            pass
    if not p.exists():
        raise InputError(f"{label}: no such rotor file")
    if not p.is_file():
        raise InputError(f"{label}: not a file (a rotor file is a TOML file)")
    try:
        raw = p.read_bytes()
    except OSError as e:
        raise InputError(f"{label}: cannot be read ({e.strerror})") from None
    try:
        text = raw.decode("utf-8")
    except UnicodeDecodeError as e:
        raise InputError(f"{label}: not UTF-8 text (byte 0x{raw[e.start]:02x} at offset {e.start}); "
                         f"a rotor file is UTF-8 TOML") from None
    if text.startswith("\ufeff"):
        text = text[1:]
    try:
        doc = tomllib.loads(text)
    except tomllib.TOMLDecodeError as e:
        raise InputError(f"{label}: not valid TOML: {e}") from None
    return label, doc


# --- overrides ------------------------------------------------------------------------
OVERRIDE_KEY = re.compile(r"^([a-z_]+?)(\d+)?\.([A-Za-z_][A-Za-z0-9_]*)$")


def _parse_override_key(ctx, okey):
    """`(table, index, key)` of an override key (`bearing0.kxx`, `gravity.g`, `speed`)."""
    if not isinstance(okey, str):
        ctx.fail(f"override key {okey!r} must be a string such as 'bearing0.kxx'")
    if okey in SINGLE_KEY_ALIASES:
        return SINGLE_KEY_ALIASES[okey]
    m = OVERRIDE_KEY.match(okey)
    if not m:
        ctx.fail(f"override {okey}: expected <table><index>.<key> (e.g. bearing0.kxx) or <table>.<key> "
                 f"(e.g. gravity.g)")
    table, index, key = m.group(1), m.group(2), m.group(3)
    if table not in SCHEMA:
        ctx.fail(f"override {okey}: unknown table {table!r}{suggest(table, list(SCHEMA))}; "
                 f"known: {', '.join(SCHEMA)}")
    spec = SCHEMA[table]
    if spec.array and index is None:
        ctx.fail(f"override {okey}: [[{table}]] has one entry per item: name it as {table}<index>.{key} "
                 f"(e.g. {table}0.{key})")
    if not spec.array and index is not None:
        ctx.fail(f"override {okey}: [{table}] is a single table: name it as {table}.{key}")
    if key not in spec.keys:
        ctx.fail(f"override {okey}: unknown key {key!r} of [{'[' if spec.array else ''}{table}"
                 f"{']' if spec.array else ''}]{suggest(key, list(spec.keys))}; known: {', '.join(spec.keys)}")
    return table, None if index is None else int(index), key


def _override_value(ctx, okey, spec, value):
    """An override's value as the file would hold it (strings parsed for numeric keys)."""
    if isinstance(value, (np.ndarray, np.generic, jax.Array)):
        if not is_concrete(value):
            ctx.fail(f"override {okey}: a traced value cannot be written into a rotor file; "
                     f"overrides are concrete")
        value = value.tolist()
    if isinstance(value, tuple):
        value = list(value)
    if isinstance(value, str) and spec.kind in ("number", "count", "node", "index", "number_or_numbers"):
        text = value.strip()
        try:
            value = int(text) if spec.kind in ("count", "node", "index") else float(text)
        except ValueError:
            try:
                value = float(text)
            except ValueError:
                if spec.kind in ("count", "node", "index"):
                    ctx.fail(f"override {okey}={value}: must be a number")
                try:   # a number with a unit, "1.5e7 N/m": in SI, or the reason it is not
                    value = to_si(text, spec.unit, f"override {okey}")
                except InputError as e:
                    ctx.fail(str(e))
    if spec.kind in ("count", "node", "index") and isinstance(value, float) and value.is_integer():
        value = int(value)
    return value


def apply_overrides(ctx, doc, overrides):
    if not overrides:
        return doc
    if not isinstance(overrides, dict):
        ctx.fail(f"overrides must be a dict such as {{'bearing0.kxx': 2e7}}, got {type(overrides).__name__}")
    doc = {k: ([dict(e) if isinstance(e, dict) else e for e in v] if isinstance(v, list)
               else dict(v) if isinstance(v, dict) else v) for k, v in doc.items()}
    for okey, value in overrides.items():
        table, index, key = _parse_override_key(ctx, okey)
        spec = SCHEMA[table]
        if table not in doc:
            if table == "rotor":
                ctx.fail(f"override {okey}: the file has no [rotor] table")
            ctx.fail(f"override {okey}: the file has no {'[[' if spec.array else '['}{table}"
                     f"{']]' if spec.array else ']'} table (overrides change entries, they do not add them)")
        entries = doc[table]
        if spec.array:
            if not isinstance(entries, list) or not all(isinstance(e, dict) for e in entries):
                continue  # reported by the validation
            if not index < len(entries):
                have = f"{table}0..{table}{len(entries) - 1}" if len(entries) > 1 else f"{table}0"
                ctx.fail(f"override {okey}: the file has {len(entries)} [[{table}]] "
                         f"entr{'y' if len(entries) == 1 else 'ies'} ({have})")
            entry = entries[index]
        else:
            if not isinstance(entries, dict):
                continue
            entry = entries
        entry[key] = _override_value(ctx, okey, spec.keys[key], value)
        ctx.overridden[location(table, index, key)] = f"{okey}={toml_repr(entry[key])}"
    return doc


def shipped_rotor(name: str) -> pathlib.Path:
    """The path of a rotor file shipped with rotorjax (`"ross_compare"`, ...; the
    `.toml` suffix is optional)."""
    files = importlib.resources.files("rotorjax.rotors")
    known = sorted(p.name[:-5] for p in files.iterdir() if p.name.endswith(".toml"))
    stem = name[:-5] if isinstance(name, str) and name.endswith(".toml") else name
    if stem not in known:
        raise InputError(f"unknown shipped rotor {name!r}; known: {', '.join(known)}")
    return pathlib.Path(str(files / f"{stem}.toml"))
