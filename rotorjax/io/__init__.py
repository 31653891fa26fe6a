"""Rotor files: a finite-element rotor scene as a TOML file (SI units).

`load_rotor(path)` reads a file into a `RotorScene`; `save_rotor(scene, path)`
writes one back (exactly: `load_rotor(save_rotor(scene))` has the same arrays).

Tables (array tables `[[...]]` hold one entry per item; indices in messages and
in override keys count from 0 in file order). A key with a default (after `=`)
may be left out; the others are required, except where two ways are offered
(`angles` or `n`, `masses` or `n_weights` + `mass`, `radius` or `r1` + `r2`):

| table                   | keys (defaults after `=`)                                                   |
|-------------------------|-----------------------------------------------------------------------------|
| `[rotor]`               | `name` (= file stem), `theory` ("euler-bernoulli", "rayleigh",             |
|                         | "timoshenko"), `n_modes` (optional: modal reduction), `speed` (rad/s, = 0) |
| `[[material]]`          | `name`, `E` (Pa), `G` (Pa; or `nu`), `rho` (kg/m^3), `nu` (= E / (2 G) - 1) |
| `[[shaft]]`             | `L` (m), `od` (m), `id` (m, = 0), `material` (a `[[material]]`'s name or a |
|                         | built-in one: steel, stainless, aluminium, titanium); `od`, `id` may be    |
|                         | `[left, right]` (a tapered element); element i joins nodes i and i + 1     |
| `[[disk]]`              | `node`, `m` (kg), `Id` (kg m^2, diametral), `Ip` (kg m^2, polar)            |
| `[[bearing]]`           | `node`, `kxx`, `kyy` (= kxx), `kxy`, `kyx` (= 0) (N/m), `cxx` (= 0),        |
|                         | `cyy` (= cxx), `cxy`, `cyx` (= 0) (N s/m), `mxx` (= 0), `myy` (= mxx),      |
|                         | `mxy`, `myx` (= 0) (kg); with `speeds = [...]` (rad/s) each coefficient     |
|                         | may be a list of the same length (evaluated at the running speed by a     |
|                         | not-a-knot cubic spline). `type = "plain-journal"` instead: `load` (N,     |
|                         | along -y), `viscosity` (Pa s), `length`, `diameter`, `clearance` (m),      |
|                         | `method` ("short", "finite"; = "short"), `speeds` (the table's speeds).   |
|                         | `type = "journal"`: a fluid-film journal bearing as a nonlinear force       |
|                         | (loaded by `[gravity]` and the rotor's own weight, no `load`): `model`     |
|                         | ("short", "finite", "long"; = "short"), `viscosity`, `length`,             |
|                         | `diameter`, `clearance`. `type = "sfd"`: a squeeze-film damper:            |
|                         | `viscosity`, `length`, `diameter`, `clearance`, `film` ("pi", "2pi";      |
|                         | = "pi"), a centring spring `kxx` (N/m, = 0), `kyy` (= kxx)                 |
| `[[point_mass]]`        | `node`, `m` (kg) or `mx` + `my`                                             |
| `[[support]]`           | `bearing` (index from 0), `m` (kg), `kxx`, `kyy` (= kxx) (N/m), `cxx`       |
|                         | (= 0), `cyy` (= cxx) (N s/m): a pedestal between the bearing and ground    |
| `[[fixed]]`             | `node`, `dofs` (= ["x", "y", "sx", "sy"])                                  |
| `[[unbalance]]`         | `node`, `magnitude` (kg m), `phase` (rad, = 0)                              |
| `[internal_damping]`    | `relaxation_time` (s, Voigt)                                                |
| `[external_damping]`    | `coefficient` (N s/m^2: viscous damping of the shaft's lateral motion per   |
|                         | unit length, by its surroundings)                                           |
| `[[disk_damping]]`      | `node`, `translational` (N s/m, on the node's x, y velocity), `angular`     |
|                         | (N m s, on its tilt rates; = 0)                                             |
| `[gravity]`             | `g` (m/s^2, = 9.81), `angle` (rad, = -pi/2: along -y)                       |
| `[[cubic_bearing]]`     | `node`, `k3` (N/m^3), `k` (N/m, = 0), `c` (N s/m, = 0)                      |
| `[[clearance_bearing]]` | `node`, `clearance` (m), `k` (N/m), `c` (N s/m, = 0),                       |
|                         | `smoothing` (m, = clearance / 1000)                                         |
| `[[limiters]]`          | `node`, `angles` (rad, list) or `n` + `first_angle` (= 0), `clearance` (m), |
|                         | `stiffness` (N/m), `damping` (N s/m, = 0), `friction` (= 0) (each a number  |
|                         | or one per limiter), `radius` (m, rim), `smoothing` (m, = 1e-6)             |
| `[[auto_balancer]]`     | `node`, `masses` (kg, list) or `n_weights` + `mass`, `radius` or `r1` +     |
|                         | `r2` (m), `center` (m, = [0, 0]), `drag` (N s/m, = 0), `kind` ("ball",      |
|                         | "roller", "pendulum"; = "ball") or `inertia_factor`                         |
| `[[probe]]`             | `node`, `name` (= "disk"; letters, digits, _): a sensor, outputs only:      |
|                         | `<name>_x`, `<name>_y`, `<name>_vx`, `<name>_vy` (m, m/s), `<name>_tilt_x`, |
|                         | `<name>_tilt_y` (rad), `<name>_radius` (m); names differ between probes     |
| `[[seal]]`              | `node`, the coefficients of a `[[bearing]]` (`kxx` required, may be < 0:   |
|                         | a labyrinth's), `speeds`: a linear seal (ROSS's `SealElement`), a bearing  |
|                         | of kind "seal" among the rotor's, after the `[[bearing]]` entries          |

Beyond the shaft's own tables (`[rotor]` to `[[fixed]]`, declared in `_schema.py`), each
table is declared by the component it builds, in that component's module (a
`rotorjax.models._table.ComponentTable`: keys, defaults, `from_table`, `to_table`,
its checks, its parameters' leaves), and listed once in the registry
(`rotorjax.models._registry.TABLES`); reading, overrides, parameter paths and
writing iterate it. The scene's components come in the registry's order, each
table's entries in file order: unbalances, internal damping, external damping, disk
damping, gravity, fluid films (`[[bearing]]` entries of type "journal" and "sfd", in
file order), cubic bearings, clearance bearings, limiters, auto-balancers (whose
weights' coordinates follow the shaft's in the state), probes. A shaft whose
elements all have the same material constants gets
scalar `E`, `G`, `rho`, `nu` (the exact arrays of a one-material `FlexibleRotor`);
otherwise they are per element.

Every check happens here, before anything is constructed, so an error names the
file, the table, the index and the key as the user wrote them
(`rotor.toml: shaft[4].od must be > id (got od = 0.05, id = 0.06)`), as an
`InputError`; so is a disk with `Ip > 2 Id` (beyond 5 %, for rounding: no rigid
body has it). Values that are valid but implausible in SI units, most likely a
unit slip, are `PlausibilityWarning`s issued once the file is valid, named the
same way and naming the slip (`rotor.toml: shaft[0].od = 60 m: outside the
plausible 0.5 mm..5 m for a diameter; did you mean mm (60 mm = 0.06 m)?`): `E`,
`G` outside 1e9..1e12 Pa, `rho` outside 500..25000 kg/m^3, lengths, diameters and
radii outside 0.5 mm..5 m (bores: above 5 m), an element's `L / od` outside
0.05..50, a disk's radius of gyration outside 0.5 mm..5 m
(`rotorjax.models._plausibility`).

Overrides (`load_rotor(path, {"bearing0.kxx": 2e7})`, the CLI's `--set`) name an
entry as `<table><index>.<key>` for array tables, `<table>.<key>` for single
tables, and `speed` for `[rotor] speed`.

The same names are parameter paths (`read_rotor_file(path).path(name)`): each
numeric key of an entry resolves, here, where the file's meaning is known, to the
leaves of the scene it sets (`rotorjax.models._parameters`), with the values that
follow it where the file leaves them out (`kyy` after `kxx`, a material's `G` or
`nu`, a clearance bearing's smoothing), so that setting it through the leaves builds
the scene the override builds. One more name per entry at a node is a parameter and
not a key: `<table><index>.position`, where that node lies (m from node 0), set
through the lengths of the two elements either side of it (`RotorFile.interval`: the
open interval it may take; `RotorFile.check_together`: two parameters setting one
length refused).
"""

from ._build import load_rotor as load_rotor
from ._paths import FileParameter as FileParameter
from ._paths import RotorFile as RotorFile
from ._paths import file_parameters as file_parameters
from ._paths import file_parameters_and_scene as file_parameters_and_scene
from ._paths import read_rotor_file as read_rotor_file
from ._read import shipped_rotor as shipped_rotor
from ._ross import import_ross as import_ross
from ._ross import ross_rotor_text as ross_rotor_text
from ._write import rotor_file_text as rotor_file_text
from ._write import save_rotor as save_rotor
