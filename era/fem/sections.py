"""Cross-section and material properties of a bar, in SI units."""

from __future__ import annotations

from dataclasses import dataclass

from ..errors import EraError


@dataclass(frozen=True)
class BeamSection:
    """Material and section constants of a straight bar (SI units).

    Attributes
    ----------
    E, G : float
        Young's and shear moduli, Pa.
    rho : float
        Density, kg/m³.
    area : float
        Cross-section area A, m².
    i_out : float
        Second moment of area for bending out of the structure's plane (about the bar's in-plane
        transverse axis), m⁴. For a flat bar lying in the plane this is the weak axis, w t³/12.
    i_in : float
        Second moment of area for bending in the plane (strong axis of a flat bar), m⁴.
    j_torsion : float
        St-Venant torsion constant J, m⁴.
    i_polar : float
        Polar second moment of area i_out + i_in, m⁴ (torsional inertia ρ I_p and the Wagner term N I_p / A).
    """

    E: float
    G: float
    rho: float
    area: float
    i_out: float
    i_in: float
    j_torsion: float
    i_polar: float

    @property
    def mass_per_length(self) -> float:
        """ρ A, kg/m."""
        return self.rho * self.area


def flat_bar(width_m: float, thickness_m: float, E: float, nu: float, rho: float) -> BeamSection:
    """A flat strip of ``width_m`` in the plane and ``thickness_m`` out of it.

    The torsion constant is the thin-rectangle series J = w t³/3 (1 - 0.63 t/w + 0.052 (t/w)⁵)
    (Roark, Table 10.1 case 4), accurate to < 0.5 % for every aspect ratio.
    """
    if not (width_m > 0 and thickness_m > 0 and E > 0 and rho > 0 and -1 < nu < 0.5):
        raise EraError("flat_bar: width, thickness, E and rho must be positive and -1 < nu < 0.5.")
    w, t = max(width_m, thickness_m), min(width_m, thickness_m)
    j = w * t**3 / 3 * (1 - 0.63 * t / w + 0.052 * (t / w) ** 5)
    i_out = width_m * thickness_m**3 / 12
    i_in = thickness_m * width_m**3 / 12
    return BeamSection(E=E, G=E / (2 * (1 + nu)), rho=rho, area=width_m * thickness_m,
                   i_out=i_out, i_in=i_in, j_torsion=j, i_polar=i_out + i_in)
