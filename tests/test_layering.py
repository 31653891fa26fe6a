"""The package's layers: imports run one way, models -> io -> solve -> analysis/identify ->
presets -> cli, with no cycles between packages (`io`: rotor files, read into scenes and
written from them; each part's table is declared by its component, in `models`).

Every module under `rotorjax/` is parsed (imports inside functions included) and each
import of another part of rotorjax is checked against the part's rank. Where the
loose modules sit, after reading them: `sweep.py` (a vmapped evaluator of any
function over a grid, used by `analysis._critical`) with `solve/`; `plot/` (figures
from result objects, and the rotor drawn from its scene's parts) above the analyses and below the
presets, so that no analysis draws; `demo.py` with the CLI; the facade
`rotorjax/__init__.py` on top: nothing inside the package imports it.
"""

import ast
import pathlib

import pytest

ROOT = pathlib.Path(__file__).resolve().parents[1] / "rotorjax"

#: the parts of the package and their layers (an import may only go to a rank <= its own)
RANK = {
    # rotors/: shipped rotor files (data)
    "_errors": 0, "_config": 0, "_autodiff": 0, "_newton": 0, "_sincos": 0, "_units": 0, "rotors": 0,
    "models": 1,
    "io": 1.5,  # rotor files: read into scenes, written from them (each part's table declared in models/)
    "solve": 2, "sweep": 2, "_distributed": 2,
    "analysis": 3, "identify": 3, "flexible": 3, "contact": 3,
    "uncertainty": 3.2,  # distributions of a scene's quantities (analysis, io, sweep)
    "design": 3.2,  # a scene's parameters chosen against its margins (analysis, io)
    "plot": 3.5,
    "presets": 4,
    "bench": 4.5,  # the headline comparisons (`rotorjax bench`): presets against their peers
    "demo": 5, "cli": 5,
    "rotorjax": 6,  # the facade, rotorjax/__init__.py
}

#: component classes (rotorjax.models) that no analysis may import: an analysis takes a scene
COMPONENTS = ("AutoBalancer", "Supports", "Limiters", "RigidRotor")


def _modules():
    for path in sorted(ROOT.rglob("*.py")):
        parts = path.relative_to(ROOT.parent).with_suffix("").parts
        if parts[-1] == "__init__":
            parts = parts[:-1]
        yield path, parts


def _part(parts):
    """The part of rotorjax a module (given as its dotted name's parts) belongs to."""
    return parts[1] if len(parts) > 1 else "rotorjax"


def _exists(parts):
    base = ROOT.parent.joinpath(*parts)
    return base.with_suffix(".py").exists() or (base / "__init__.py").exists()


def _imports(path, parts):
    """`(line, target parts, imported names)` of every import of rotorjax in a module."""
    package = parts if path.name == "__init__.py" else parts[:-1]
    for node in ast.walk(ast.parse(path.read_text(), str(path))):
        if isinstance(node, ast.Import):
            for a in node.names:
                if a.name.split(".")[0] == "rotorjax":
                    yield node.lineno, tuple(a.name.split(".")), ()
        elif isinstance(node, ast.ImportFrom):
            if node.level:
                base = package[:len(package) - node.level + 1]
                target = base + (tuple(node.module.split(".")) if node.module else ())
            elif node.module and node.module.split(".")[0] == "rotorjax":
                target = tuple(node.module.split("."))
            else:
                continue
            names = tuple(a.name for a in node.names)
            if len(target) == 1:  # `from rotorjax import x` / `from .. import x`: x may be a part
                for n in names:
                    yield node.lineno, target + (n,) if _exists(target + (n,)) else target, (n,)
            else:
                yield node.lineno, target, names


def _edges():
    for path, parts in _modules():
        src = _part(parts)
        for line, target, names in _imports(path, parts):
            yield path, line, src, _part(target), target, names


def test_every_part_has_a_rank():
    parts = {_part(p) for _, p in _modules()}
    assert parts <= set(RANK), f"give these parts of rotorjax a layer in RANK: {sorted(parts - set(RANK))}"


def test_no_import_goes_up():
    bad = [f"{path.relative_to(ROOT.parent)}:{line}: {src} (rank {RANK[src]}) imports {'.'.join(target)} "
           f"({dst}, rank {RANK[dst]})"
           for path, line, src, dst, target, _ in _edges() if src != dst and RANK[dst] > RANK[src]]
    assert not bad, "imports that go up the layers:\n" + "\n".join(bad)


def test_no_cycles_between_parts():
    graph = {}
    for _, _, src, dst, _, _ in _edges():
        if src != dst:
            graph.setdefault(src, set()).add(dst)
    # Tarjan's strongly connected components
    index, low, stack, on, cycles = {}, {}, [], set(), []

    def visit(v):
        index[v] = low[v] = len(index)
        stack.append(v)
        on.add(v)
        for w in graph.get(v, ()):
            if w not in index:
                visit(w)
                low[v] = min(low[v], low[w])
            elif w in on:
                low[v] = min(low[v], index[w])
        if low[v] == index[v]:
            comp = []
            while True:
                w = stack.pop()
                on.discard(w)
                comp.append(w)
                if w == v:
                    break
            if len(comp) > 1:
                cycles.append(sorted(comp))

    for v in list(graph):
        if v not in index:
            visit(v)
    assert not cycles, f"import cycles between parts of rotorjax: {cycles}"


def test_analyses_take_scenes_not_components():
    bad = [f"{path.relative_to(ROOT.parent)}:{line}: imports {', '.join(set(names) & set(COMPONENTS))}"
           for path, line, src, _, _, names in _edges() if src == "analysis" and set(names) & set(COMPONENTS)]
    assert not bad, "analysis modules importing component classes:\n" + "\n".join(bad)


@pytest.mark.parametrize("src,text,dst", [
    (("rotorjax", "identify", "_make_data"), "from ..presets import balancing_machine", "presets"),
    (("rotorjax", "cli", "_main"), "from .. import identify", "identify"),
    (("rotorjax", "demo"), "from . import simulate", "rotorjax"),
    (("rotorjax", "models"), "from .. import _config", "_config"),
])
def test_imports_are_resolved(tmp_path, src, text, dst):
    """The checks above see relative imports, and `from rotorjax import x` as the part `x`
    where `x` is one (else the facade)."""
    path = tmp_path / ("__init__.py" if src == ("rotorjax", "models") else "m.py")
    path.write_text(text + "\n")
    ((_, target, _),) = list(_imports(path, src))
    assert _part(target) == dst


# --- one analysis layer (issue 29) -------------------------------------------------------

#: the compatibility namespaces: re-exports for users' code, imported by nothing inside rotorjax
SHIMS = ("flexible", "contact")


def test_nothing_inside_imports_the_compatibility_namespaces():
    """`rotorjax.flexible` and `rotorjax.contact` re-export what lives in `models/` and
    `analysis/`; only the facade (`rotorjax/__init__.py`, for `rotorjax.flexible.x` in
    users' code) names them."""
    bad = [f"{path.relative_to(ROOT.parent)}:{line}: imports {'.'.join(target)}"
           for path, line, src, dst, target, _ in _edges()
           if dst in SHIMS and src not in SHIMS and src != "rotorjax"]
    assert not bad, "modules importing a compatibility namespace:\n" + "\n".join(bad)


def test_shims_only_re_export():
    """The compatibility namespaces define nothing: every statement is an import (or the docstring)."""
    for name in SHIMS:
        path = ROOT / name / "__init__.py"
        body = ast.parse(path.read_text()).body
        bad = [n.lineno for n in body if not isinstance(n, (ast.Import, ast.ImportFrom))
               and not (isinstance(n, ast.Expr) and isinstance(n.value, ast.Constant))]
        assert not bad, f"{path.relative_to(ROOT.parent)} defines something at lines {bad}"
        assert sorted(p.name for p in (ROOT / name).glob("*.py")) == ["__init__.py"]


def _calls(name):
    for path, _ in _modules():
        for node in ast.walk(ast.parse(path.read_text(), str(path))):
            if isinstance(node, ast.Call) and isinstance(node.func, ast.Name) and node.func.id == name:
                yield path, node


def test_no_capability_probing():
    """Capabilities are declared by type (`AbstractLinearScene`, `AbstractShaftModel`,
    ...) and checked with `isinstance`/`require`: no `hasattr`, no `getattr` with a
    default (an argparse namespace's options excepted), no `getattr(x, "rotor", x)`."""
    bad = [f"{path.relative_to(ROOT.parent)}:{node.lineno}: hasattr" for path, node in _calls("hasattr")]
    for path, node in _calls("getattr"):
        obj = node.args[0] if node.args else None
        if len(node.args) > 2 and not (isinstance(obj, ast.Name) and obj.id == "args"):
            bad.append(f"{path.relative_to(ROOT.parent)}:{node.lineno}: getattr with a default")
    assert not bad, "attribute probing (declare a capability class instead):\n" + "\n".join(bad)


def test_fe_analyses_take_capabilities_not_concrete_rotors():
    """The analyses check what they get by capability class, not by concrete scene
    or rotor type (`isinstance(x, RotorScene)` would make a second scene contract)."""
    concrete = {"RotorScene", "FlexibleRotor", "ReducedRotor", "CantileverScene", "ModalBalancerRotor",
                "BalancingScene", "Scene"}
    bad = []
    for path, node in _calls("isinstance"):
        if path.relative_to(ROOT).parts[0] != "analysis" or len(node.args) < 2:
            continue
        types = node.args[1].elts if isinstance(node.args[1], ast.Tuple) else [node.args[1]]
        names = {t.id for t in types if isinstance(t, ast.Name)}
        if names & concrete:
            bad.append(f"{path.relative_to(ROOT.parent)}:{node.lineno}: isinstance(..., {sorted(names & concrete)})")
    assert not bad, "analyses branching on concrete types:\n" + "\n".join(bad)


def test_presets_are_data():
    """A preset holds nothing callable but `build` (no hooks: every analysis is a library
    function of the built scene or its reference motion), nested values included."""
    import dataclasses

    from rotorjax import presets

    def callables(value, where):
        if callable(value):
            yield where
        elif isinstance(value, dict):
            for k, v in value.items():
                yield from callables(v, f"{where}[{k!r}]")
        elif isinstance(value, (tuple, list)):
            for i, v in enumerate(value):
                yield from callables(v, f"{where}[{i}]")

    for preset in presets.PRESETS.values():
        found = [w for f in dataclasses.fields(preset) for w in callables(getattr(preset, f.name), f.name)]
        assert found == ["build"], (preset.name, found)


#: names of analyses (issue 29): defined in `analysis/`, as functions of a scene or system
ANALYSES = frozenset({
    "stability_margin", "linear_margin", "margin", "eigenvalues", "state_matrix", "modes", "damped_frequencies",
    "natural_frequencies", "whirl_direction", "campbell", "critical_speed", "critical_speeds", "hopf_points",
    "unbalance_response", "response", "frf", "floquet_multipliers",
})

#: the parts below the analyses (they cannot call them, so an analysis there would be a second copy)
BELOW_ANALYSIS = ("models", "solve", "sweep", "_distributed")

#: model primitives that carry an analysis's name, and why they stay
PRIMITIVES = {
    ("models/_contract.py", "LinearMatrices.state_matrix"):
        "the first-order form of the scene's own linear matrices (what every eigen-analysis starts from)",
}


def _warns_deprecation(node, helpers=frozenset()):
    """Whether a function's body calls `warnings.warn(..., DeprecationWarning, ...)` (or a
    helper of its module that does)."""
    for call in ast.walk(node):
        if not isinstance(call, ast.Call):
            continue
        f = call.func
        name = f.attr if isinstance(f, ast.Attribute) else f.id if isinstance(f, ast.Name) else None
        if name in helpers:
            return True
        if name == "warn" and any(isinstance(a, ast.Name) and a.id == "DeprecationWarning"
                                  for a in (*call.args, *(k.value for k in call.keywords))):
            return True
    return False


def _analyses_defined(source, where):
    """Qualified names of the functions and methods in `source` named like an analysis
    (`ANALYSES`) that are not deprecated aliases (bodies that warn) nor `PRIMITIVES`."""
    tree = ast.parse(source, where)
    helpers = frozenset(n.name for n in tree.body if isinstance(n, ast.FunctionDef) and _warns_deprecation(n))
    found = []

    def visit(body, prefix):
        for n in body:
            if isinstance(n, ast.ClassDef):
                visit(n.body, f"{prefix}{n.name}.")
            elif isinstance(n, (ast.FunctionDef, ast.AsyncFunctionDef)):
                name = f"{prefix}{n.name}"
                if (n.name in ANALYSES and (where, name) not in PRIMITIVES
                        and not _warns_deprecation(n, helpers)):
                    found.append((n.lineno, name))
                visit(n.body, f"{name}.<locals>.")

    visit(tree.body, "")
    return found


def test_no_analysis_is_defined_below_the_analysis_layer():
    """One analysis layer (issue 29): `models/`, `solve/` (and the loose modules with them)
    define no function or method named like an analysis (`ANALYSES`: `modes`,
    `stability_margin`, `unbalance_response`, `response`, ...): those are functions of
    a scene in `analysis/`. A model's old analysis method may stay one release as a
    deprecated alias (its body warns with `DeprecationWarning`); model primitives that
    carry such a name are listed in `PRIMITIVES` with the reason. Above the analyses
    (identify, presets, plot, bench, cli) the code calls them; presets hold no hooks
    (`test_presets_are_data`) and the shims define nothing (`test_shims_only_re_export`)."""
    bad = []
    for path, parts in _modules():
        if _part(parts) not in BELOW_ANALYSIS:
            continue
        where = path.relative_to(ROOT).as_posix()
        bad += [f"rotorjax/{where}:{line}: {name}" for line, name in _analyses_defined(path.read_text(), where)]
    assert not bad, ("analyses defined outside rotorjax/analysis/ (move them there; keep an old method one "
                     "release as an alias that warns with DeprecationWarning):\n" + "\n".join(bad))


@pytest.mark.parametrize("source,found", [
    ("class R:\n    def stability_margin(self, speed):\n        return 0.0\n", [(2, "R.stability_margin")]),
    ("def modes(scene, speed):\n    return scene\n", [(1, "modes")]),
    ("import warnings\nclass R:\n    def response(self, speed):\n"
     "        warnings.warn('R.response is deprecated', DeprecationWarning, stacklevel=2)\n        return 0\n", []),
    ("import warnings\ndef _old(m):\n    warnings.warn(m, category=DeprecationWarning)\n"
     "class R:\n    def eigenvalues(self, speed):\n        _old('use modes')\n        return 0\n", []),
    ("import warnings\nclass R:\n    def response(self, speed):\n"
     "        warnings.warn('slow', UserWarning)\n        return 0\n", [(3, "R.response")]),
    ("class LinearMatrices:\n    def state_matrix(self):\n        return 0\n", []),
    ("class R:\n    def influence_matrix(self, speed, planes):\n        return 0\n", []),
])
def test_the_analysis_rule_can_fail(source, found):
    where = "models/_contract.py" if "LinearMatrices" in source else "models/_x.py"
    assert _analyses_defined(source, where) == found
