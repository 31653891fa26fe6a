"""The parameters of a rotor file that identification can fit, by their rotor-file
names, and the map from a parameter vector to the rotor they make.

Names (the `--set` keys of the file): `bearingI.COEF` (the I-th `[[bearing]]`, COEF
in kxx, kyy, kxy, kyx, cxx, cyy, cxy, cyx, mxx, myy, mxy, myx), `supportI.KEY`
(m, kxx, kyy, cxx, cyy), `diskI.KEY` (m, Id, Ip), `point_massI.KEY` (m, mx, my),
`materialI.KEY` (E, G, rho, nu), `shaftI.KEY` (L, od, id),
`unbalanceJ.magnitude` / `unbalanceJ.phase`. Each resolves once to the leaves of
the scene it sets (`rotorjax.models._parameters`, by the rotor file's loader, which
knows what the name means), so the fitted rotor is the one `--set` would build.

A value the file leaves at its default follows the one it defaults to (`kyy`
follows `kxx`, `cyy` follows `cxx`, `myy` follows `mxx`; a point mass's `m` is both
`mx` and `my`; a material's `G` or `nu`, whichever it leaves out, follows `E`), as
`--set` treats it. Positive quantities are fitted as logarithms (positivity by
reparametrisation, and a factor error is one step); signed ones (cross-coupled
coefficients, phases) linearly, scaled by their start (or 1 when it is 0).
Coefficients tabulated against speed and plain journals' (computed) cannot be
fitted coefficient by coefficient.
"""

import dataclasses


from .._errors import InputError
from ..models._fe_rotor import BEARING_COEFFICIENTS
from ..models._parameters import SceneParts, parts_of, value_of
from ..io import read_rotor_file
from ..io._schema import SCHEMA
from ..models._unbalance import Unbalance
from ._engine import Parameter

def _on_linear_model(path, scene):
    """Whether `path` sets only what the linear 1x model holds: the rotor, or an unbalance."""
    return bool(path.targets) and all(
        t.leaf[0] == "rotor" or (t.leaf[0] == "components" and isinstance(scene.components[t.leaf[1]], Unbalance))
        for t in path.targets)


def _fittable(file):
    """The names of the file's entries the linear 1x model holds (of every table: the
    rotor's, a seal's, the unbalances)."""
    out = []
    for table, spec in SCHEMA.items():
        for i, _ in file.raw.get(table, []):
            for key, k in spec.keys.items():
                name = f"{table}{i}.{key}" if spec.array else f"{table}.{key}"
                if k.kind in ("number", "number_or_numbers"):
                    path = file.path(name)
                    if path is not None and not path.refusal and _on_linear_model(path, file.scene):
                        out.append(name)
    return out


def parameter(name, file, parts, option="--fit"):
    """The `Parameter` called `name` of the `RotorFile` `file`, its start the value in
    `parts` (the `SceneParts` of the file's scene)."""
    path = file.path(name) if isinstance(name, str) else None
    table = name.partition(".")[0].rstrip("0123456789") if isinstance(name, str) else None
    if path is None or not path.refusal and not _on_linear_model(path, file.scene):
        known = _fittable(file)
        hint = f"; fittable here: {', '.join(known[:12])}{', ...' if len(known) > 12 else ''}" if known else ""
        if table == "bearing" and path is None and f"{name.partition('.')[0]}.node" in file.entries:
            hint = f"; a bearing's coefficients are {', '.join(BEARING_COEFFICIENTS)}"
        elif path is not None:
            hint = ": it is not part of the linear rotor and unbalances the 1x model fits" + hint
        raise InputError(f"{option} {name}: not a parameter of this rotor file{hint}")
    if path.refusal:
        raise InputError(f"{option} {name}: {path.refusal}")
    if path.targets[0].rule == "node_position":
        raise InputError(f"{option} {name}: a position is designed or scatters (optimize --vary, uncertainty --dist), "
                         "not fitted: the fit does not hold it between the nodes either side of its own; give the "
                         "measured one in the file")
    start = float(value_of(parts, path))
    signed = file.signed(name)
    if not signed and not start > 0:
        raise InputError(f"{option} {name}: its start value is {start:g}; a positive quantity is fitted as a "
                         f"logarithm and needs a start > 0 (give one in the rotor file, or with --set "
                         f"{name}=VALUE where the file gives it)")
    return Parameter(name, path, not signed, abs(start) if signed and start != 0 else 1.0, start)


@dataclasses.dataclass(frozen=True, eq=False)
class RotorModel:
    """A rotor file's linear rotor (`FlexibleRotor`, the full one when the file
    reduces it) and its unbalances, at the file's values (with `overrides`), and the
    fittable parameters' names."""

    label: str
    file: object               # the `RotorFile`
    parts: SceneParts          # the scene's full rotor and components: what parameters set
    entries: dict              # name -> FileParameter (what the file gives)
    nonlinear: tuple           # names of the file's other components (not modelled by the 1x fit)

    @property
    def rotor(self):
        return self.parts.rotor

    @property
    def unbalances(self) -> tuple:
        """The file's `Unbalance` components."""
        return tuple(c for c in self.parts.components if isinstance(c, Unbalance))

    @property
    def unbalance_places(self) -> tuple:
        """The unbalances' places among the scene's components."""
        return tuple(j for j, c in enumerate(self.parts.components) if isinstance(c, Unbalance))

    def parameters(self, names, option="--fit"):
        out = []
        for n in names:
            if n in [p.name for p in out]:
                raise InputError(f"{option}: {n} is named twice")
            out.append(parameter(n, self.file, self.parts, option))
        return tuple(out)

    @property
    def fittable(self):
        return _fittable(self.file)


def rotor_model(path, overrides=None) -> RotorModel:
    """The `RotorModel` of the rotor file at `path` with `--set` `overrides` (read,
    checked and built once)."""
    file = read_rotor_file(path, overrides)
    scene = file.scene
    other = tuple(type(c).__name__ for c in scene.components if not isinstance(c, Unbalance))
    return RotorModel(file.label, file, parts_of(scene), file.entries, other)
