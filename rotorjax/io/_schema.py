"""The rotor file's tables: the shaft's own (`[rotor]`, `[[material]]`, `[[shaft]]`,
`[[disk]]`, `[[bearing]]`, `[[point_mass]]`, `[[support]]`, `[[fixed]]`), declared here,
and every other part's, declared by its component (`rotorjax.models._registry.TABLES`)."""

from ..models._fluid_film import JOURNAL_MODELS, SFD_FILMS
from ..models._registry import TABLES
from ..models._table import Key, Table, node_key

DOF_NAMES = ("x", "y", "sx", "sy")
THEORIES = ("euler-bernoulli", "rayleigh", "timoshenko")
BEARING_TYPES = ("linear", "plain-journal", "journal", "sfd")
#: the [[bearing]] types that are nonlinear force components, not linear coefficients
FILM_TYPES = ("journal", "sfd")
FILM_KEYS = ("viscosity", "length", "diameter", "clearance")
JOURNAL_METHODS = ("short", "finite")
JOURNAL_KEYS = ("load", "viscosity", "length", "diameter", "clearance", "method")


_N, _S = "number", "string"
SCHEMA = {
    "rotor": Table(False, {
        "name": Key(_S, meaning="the rotor's name"),
        "theory": Key(_S, meaning="shaft element theory", required=True, choices=THEORIES),
        "n_modes": Key("count", "count", "modes kept by modal reduction of the linear part"),
        "speed": Key(_N, "rad/s", "operating speed"),
    }, "the rotor"),
    "material": Table(True, {
        "name": Key(_S, meaning="material name", required=True),
        "E": Key(_N, "Pa", "Young's modulus", "positive", True, plausible="E"),
        "G": Key(_N, "Pa", "shear modulus (or nu)", "positive", plausible="G"),
        "rho": Key(_N, "kg/m^3", "density", "positive", True, plausible="rho"),
        "nu": Key(_N, "dimensionless", "Poisson's ratio (Cowper's shear coefficient)", domain="(-1,0.5]"),
    }, "a shaft material"),
    "shaft": Table(True, {
        "L": Key(_N, "m", "element length", "positive", True, plausible="length"),
        "od": Key("number_or_numbers", "m", "outer diameter ([left, right]: tapered)", "positive", True,
                  plausible="diameter"),
        "id": Key("number_or_numbers", "m", "inner diameter ([left, right]: tapered)", "nonnegative",
                  plausible="bore"),
        "material": Key(_S, meaning="material (a [[material]] name or a built-in one)", required=True),
    }, "a shaft element"),
    "disk": Table(True, {
        "node": node_key("disk"),
        "m": Key(_N, "kg", "mass", "positive", True),
        "Id": Key(_N, "kg m^2", "diametral (transverse) inertia", "nonnegative", True),
        "Ip": Key(_N, "kg m^2", "polar inertia", "nonnegative", True),
    }, "a rigid disk"),
    "bearing": Table(True, {
        "node": node_key("bearing"),
        "kxx": Key("number_or_numbers", "N/m", "stiffness xx", "nonnegative"),
        "kyy": Key("number_or_numbers", "N/m", "stiffness yy", "nonnegative"),
        "kxy": Key("number_or_numbers", "N/m", "cross stiffness xy"),
        "kyx": Key("number_or_numbers", "N/m", "cross stiffness yx"),
        "cxx": Key("number_or_numbers", "N s/m", "damping xx", "nonnegative"),
        "cyy": Key("number_or_numbers", "N s/m", "damping yy", "nonnegative"),
        "cxy": Key("number_or_numbers", "N s/m", "cross damping xy"),
        "cyx": Key("number_or_numbers", "N s/m", "cross damping yx"),
        "mxx": Key("number_or_numbers", "kg", "mass coefficient xx", "nonnegative"),
        "myy": Key("number_or_numbers", "kg", "mass coefficient yy", "nonnegative"),
        "mxy": Key("number_or_numbers", "kg", "cross mass coefficient xy"),
        "myx": Key("number_or_numbers", "kg", "cross mass coefficient yx"),
        "type": Key(_S, meaning="bearing type", choices=BEARING_TYPES),
        "speeds": Key("numbers", "rad/s", "speeds of the coefficient table", "nonnegative"),
        "load": Key(_N, "N", "static load on a plain journal (along -y)", "positive"),
        "viscosity": Key(_N, "Pa s", "lubricant dynamic viscosity", "positive"),
        "length": Key(_N, "m", "journal bearing length", "positive", plausible="length"),
        "diameter": Key(_N, "m", "journal diameter", "positive", plausible="diameter"),
        "clearance": Key(_N, "m", "radial clearance", "positive"),
        "method": Key(_S, meaning="journal-bearing solution", choices=JOURNAL_METHODS),
        "model": Key(_S, meaning="journal-bearing film model", choices=JOURNAL_MODELS),
        "film": Key(_S, meaning="squeeze-film extent", choices=SFD_FILMS),
    }, "a bearing: linear (constant, speed-dependent, or a plain journal's coefficients), or a fluid film "
       "(journal bearing, squeeze-film damper) as a nonlinear force"),
    "point_mass": Table(True, {
        "node": node_key("point mass"),
        "m": Key(_N, "kg", "mass (x and y)", "nonnegative"),
        "mx": Key(_N, "kg", "mass in x", "nonnegative"),
        "my": Key(_N, "kg", "mass in y", "nonnegative"),
    }, "a point mass at a node"),
    "support": Table(True, {
        "bearing": Key("index", "index", "the [[bearing]] (index from 0) the pedestal carries", required=True),
        "m": Key(_N, "kg", "pedestal mass", "positive", True),
        "kxx": Key(_N, "N/m", "pedestal-to-ground stiffness xx", "nonnegative", True),
        "kyy": Key(_N, "N/m", "pedestal-to-ground stiffness yy", "nonnegative"),
        "cxx": Key(_N, "N s/m", "pedestal-to-ground damping xx", "nonnegative"),
        "cyy": Key(_N, "N s/m", "pedestal-to-ground damping yy", "nonnegative"),
    }, "a bearing pedestal (mass, stiffness and damping to ground)"),
    "fixed": Table(True, {
        "node": node_key("fixed dofs"),
        "dofs": Key("strings", meaning="dofs held at zero", choices=DOF_NAMES),
    }, "dofs held at zero"),
    **{table.name: table for table in TABLES if table.part != "film"},
}
SINGLE_KEY_ALIASES = {"speed": ("rotor", None, "speed")}
