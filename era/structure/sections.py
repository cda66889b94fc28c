"""The section and material of a frame's members (SI units): :class:`Section` from its constants or from a shape
(rectangle, circle, tube, square_tube) and a material of :data:`MATERIALS`.

A section is given by its constants (``ip``, the polar moment, defaults to iy + iz) or by ``shape`` with that
helper's keywords. ``Section.iy`` is about the member's local y (bending that moves the member along z),
``Section.iz`` about local z; a rectangle's ``depth`` runs along local z (era.structure.frame for the local axes).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, fields

from ..errors import DataError

MATERIALS = {   # nominal handbook values: E (Pa), Poisson's ratio, density (kg/m³)
    "steel": (200e9, 0.29, 7850.0), "stainless_steel": (193e9, 0.29, 8000.0),
    "aluminium": (68.9e9, 0.33, 2700.0), "aluminum": (68.9e9, 0.33, 2700.0), "titanium": (114e9, 0.34, 4430.0),
}


def _material(material, e, g, density) -> dict:
    """{e (Pa), g (Pa), density (kg/m³)} of a material of MATERIALS, each overridden when given (g from E and
    Poisson's ratio otherwise). DataError for an unknown material."""
    if material not in MATERIALS:
        raise DataError(f"Section: unknown material {material!r}; known: {sorted(MATERIALS)} (or give e, g, density).")
    e0, nu, rho0 = MATERIALS[material]
    e = e0 if e is None else e
    return dict(e=e, g=e / (2 * (1 + nu)) if g is None else g, density=rho0 if density is None else density)


@dataclass(frozen=True)
class Section:
    """Section and material constants of a member, SI units.

    The helpers :meth:`rectangle`, :meth:`circle`, :meth:`tube` and :meth:`square_tube` compute them from a shape
    and a material.

    Parameters
    ----------
    area : float
        A, m².
    iy : float
        Second moment about the local y axis (bending that moves the member along z), m⁴.
    iz : float
        Second moment about the local z axis, m⁴.
    j : float
        St-Venant torsion constant, m⁴.
    e : float
        Young's modulus, Pa.
    g : float
        Shear modulus, Pa.
    density : float
        ρ, kg/m³.
    ip : float, optional
        Polar moment for the torsional inertia ρ I_p and the Wagner term, m⁴ (default iy + iz).

    Raises
    ------
    era.DataError
        For a constant that is not a positive, finite number (or an unknown shape or material in the helpers).

    Examples
    --------
    >>> bar = era.Section.rectangle(0.05, 0.01)  # steel, 50 mm wide, 10 mm deep
    >>> round(bar.area * 1e6), round(bar.iy * 1e12), round(bar.mass_per_length, 3)
    (500, 4167, 3.925)
    >>> era.Section(area=1e-4, iy=1e-9, iz=1e-9, j=2e-9, e=70e9, g=26e9, density=2700).ip
    2e-09
    """

    area: float
    iy: float
    iz: float
    j: float
    e: float
    g: float
    density: float
    ip: float | None = None

    def __post_init__(self):
        for f in fields(self):
            v = getattr(self, f.name)
            if f.name == "ip" and v is None:
                v = float(self.iy) + float(self.iz)
            try:
                v = float(v)
            except (TypeError, ValueError):
                raise DataError(f"Section: {f.name} must be a number, got {v!r}.") from None
            if not (math.isfinite(v) and v > 0):
                raise DataError(f"Section: {f.name} must be positive and finite, got {v!r}.")
            object.__setattr__(self, f.name, v)

    @property
    def mass_per_length(self) -> float:
        """ρ A, kg/m."""
        return self.density * self.area

    @classmethod
    def rectangle(cls, width: float, depth: float, material: str = "steel", *, e=None, g=None, density=None):
        """Solid width (along local y) × depth (along local z), m. J of a solid rectangle from Roark's Formulas for
        Stress and Strain (torsion table): J = a b³ (1/3 - 0.21 (b/a)(1 - b⁴/(12 a⁴))), a ≥ b the sides, within
        0.5 %.

        Parameters
        ----------
        width : float
            Along local y, m.
        depth : float
            Along local z, m.
        material : str, optional
            A name of MATERIALS (default "steel"): its E, G and density.
        e : float, optional
            Young's modulus, Pa, instead of the material's.
        g : float, optional
            Shear modulus, Pa, instead of the material's.
        density : float, optional
            kg/m³, instead of the material's.
        """
        a, b = max(width, depth), min(width, depth)
        j = a * b**3 * (1 / 3 - 0.21 * b / a * (1 - b**4 / (12 * a**4)))
        return cls(area=width * depth, iy=width * depth**3 / 12, iz=depth * width**3 / 12, j=j,
                   **_material(material, e, g, density))

    @classmethod
    def circle(cls, diameter: float, material: str = "steel", *, e=None, g=None, density=None):
        """Solid round bar of this diameter (m): I = π d⁴/64, J = I_p = 2I.

        Parameters
        ----------
        diameter : float
            m.
        material : str, optional
            A name of MATERIALS (default "steel"): its E, G and density.
        e : float, optional
            Young's modulus, Pa, instead of the material's.
        g : float, optional
            Shear modulus, Pa, instead of the material's.
        density : float, optional
            kg/m³, instead of the material's.
        """
        i = math.pi * diameter**4 / 64
        return cls(area=math.pi * diameter**2 / 4, iy=i, iz=i, j=2 * i, **_material(material, e, g, density))

    @classmethod
    def tube(cls, diameter: float, wall: float, material: str = "steel", *, e=None, g=None, density=None):
        """Round tube, outer diameter and wall thickness (m): I = π (D⁴ - d⁴)/64, J = I_p = 2I.

        Parameters
        ----------
        diameter : float
            Outer diameter, m.
        wall : float
            Wall thickness, m.
        material : str, optional
            A name of MATERIALS (default "steel"): its E, G and density.
        e : float, optional
            Young's modulus, Pa, instead of the material's.
        g : float, optional
            Shear modulus, Pa, instead of the material's.
        density : float, optional
            kg/m³, instead of the material's.
        """
        d = diameter - 2 * wall
        i = math.pi * (diameter**4 - d**4) / 64
        return cls(area=math.pi * (diameter**2 - d**2) / 4, iy=i, iz=i, j=2 * i, **_material(material, e, g, density))

    @classmethod
    def square_tube(cls, width: float, wall: float, material: str = "steel", *, e=None, g=None, density=None):
        """Square hollow section, outer width and wall (m): I = (b⁴ - (b-2t)⁴)/12; J = t (b-t)³ (Bredt, thin
        wall).

        Parameters
        ----------
        width : float
            Outer width, m.
        wall : float
            Wall thickness, m.
        material : str, optional
            A name of MATERIALS (default "steel"): its E, G and density.
        e : float, optional
            Young's modulus, Pa, instead of the material's.
        g : float, optional
            Shear modulus, Pa, instead of the material's.
        density : float, optional
            kg/m³, instead of the material's.
        """
        b, t = width, wall
        i = (b**4 - (b - 2 * t) ** 4) / 12
        return cls(area=b**2 - (b - 2 * t) ** 2, iy=i, iz=i, j=t * (b - t) ** 3, **_material(material, e, g, density))

    @classmethod
    def from_dict(cls, d: dict) -> "Section":
        """From the constants, or from {"shape": "rectangle" | "circle" | "tube" | "square_tube", ...keywords}.

        Parameters
        ----------
        d : dict
            {"area": ..., "iy": ..., ...} or {"shape": ..., keywords of that helper}.
        """
        d = dict(d)
        shape = d.pop("shape", None)
        try:
            if shape is None:
                return cls(**d)
            if shape not in ("rectangle", "circle", "tube", "square_tube"):
                raise DataError(f"Section: unknown shape {shape!r}; known: rectangle, circle, tube, square_tube.")
            return getattr(cls, shape)(**d)
        except TypeError as exc:
            raise DataError(f"Section: {exc}") from None
