"""Shaft materials: a small library of elastic constants with their sources.

`FlexibleRotor` takes `E`, `G`, `rho` (and optionally `nu`) per element; a
`Material` supplies them: `FlexibleRotor(..., **material("steel").shaft())`.
Where a source gives `E` and Poisson's ratio, `G = E / (2 (1 + nu))`, so that
the three constants are consistent (the shear coefficient uses `nu`, the shear
stiffness `G`).
"""

from typing import NamedTuple

from ._validate import InputError


class Material(NamedTuple):
    """An isotropic shaft material: `E` (Pa), `G` (Pa), `rho` (kg/m^3), `nu` (-)
    and the `source` of the numbers."""

    name: str
    E: float
    G: float
    rho: float
    nu: float
    source: str

    def shaft(self) -> dict:
        """The keyword arguments `E`, `G`, `rho`, `nu` of `FlexibleRotor`."""
        return {"E": self.E, "G": self.G, "rho": self.rho, "nu": self.nu}


def shear_modulus(E, nu):
    """`G = E / (2 (1 + nu))`: the one place it is computed (materials, rotor files,
    fitted parameters), so every path gives the same bits."""
    return E / (2 * (1 + nu))


def poisson_ratio(E, G):
    """`nu = E / (2 G) - 1` (likewise)."""
    return E / (2 * G) - 1


def _from_e_nu(name, E, nu, rho, source):
    return Material(name, E, shear_modulus(E, nu), rho, nu, source + "; G = E / (2 (1 + nu))")


MATERIALS = {
    "steel": Material("steel", 211e9, 81.2e9, 7810.0, poisson_ratio(211e9, 81.2e9),
                      "ROSS 2.3.0 ross/available_materials.toml, 'Steel' (E 211 GPa, G_s 81.2 GPa, "
                      "rho 7810 kg/m^3); nu = E / (2 G) - 1"),
    "stainless": _from_e_nu("stainless", 193e9, 0.29, 8000.0,
                            "AISI 304 annealed stainless steel, ASM Aerospace Specification Metals "
                            "(MatWeb): E 193 GPa, nu 0.29, rho 8.00 g/cm^3"),
    "aluminium": _from_e_nu("aluminium", 68.9e9, 0.33, 2700.0,
                            "aluminium 6061-T6, ASM Aerospace Specification Metals (MatWeb): "
                            "E 68.9 GPa, nu 0.33, rho 2.70 g/cm^3"),
    "titanium": _from_e_nu("titanium", 113.8e9, 0.342, 4430.0,
                           "Ti-6Al-4V (grade 5, annealed), ASM Aerospace Specification Metals (MatWeb): "
                           "E 113.8 GPa, nu 0.342, rho 4.43 g/cm^3"),
}


def material(name) -> Material:
    """The `Material` called `name` in `MATERIALS` (case-insensitive)."""
    key = name.lower() if isinstance(name, str) else name
    if key not in MATERIALS:
        raise InputError(f"material: unknown material {name!r}; known: {', '.join(sorted(MATERIALS))}")
    return MATERIALS[key]
