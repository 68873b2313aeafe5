"""Rail sections by name: the cross-section values of the flat-bottom rails of EN 13674-1
that the track model takes (its bending in the vertical and the lateral plane).

A design names its rail (``[counter_body] rail = "UIC60"``) and takes that section's
values; ``"custom"`` takes the values the design gives. The shear coefficients are those
of the rail's web-and-head shape (Thompson, *Railway Noise and Vibration*, ch. 3): about
0.4 for vertical bending and 0.53 laterally, for both sections.
"""

from __future__ import annotations

from dataclasses import dataclass

__all__ = ["CUSTOM_RAIL", "RAILS", "RailSection", "rail_section"]


@dataclass(frozen=True)
class RailSection:
    """One rail's cross-section.

    Attributes
    ----------
    area_m2 : float
        A [m^2].
    second_moment_vertical_m4, second_moment_lateral_m4 : float
        I for bending in the vertical and in the lateral plane [m^4].
    shear_coefficient_vertical, shear_coefficient_lateral : float
        Timoshenko's kappa [-].
    head_radius_m : float
        The head's transverse (crown) radius at its centre [m].
    """

    area_m2: float
    second_moment_vertical_m4: float
    second_moment_lateral_m4: float
    shear_coefficient_vertical: float
    shear_coefficient_lateral: float
    head_radius_m: float = 0.3


#: The rails a design may name, each by its EN 13674-1 name and its older UIC one
RAILS: dict[str, RailSection] = {
    "UIC60": RailSection(76.7e-4, 3038.3e-8, 512.7e-8, 0.4, 0.538),
    "UIC54": RailSection(69.77e-4, 2337.9e-8, 418.6e-8, 0.4, 0.538),
}
RAILS["60E1"], RAILS["54E1"] = RAILS["UIC60"], RAILS["UIC54"]
#: The name that takes the section's values from the design itself
CUSTOM_RAIL = "custom"


def rail_section(name: str) -> RailSection:
    """The section of the rail named ``name`` (KeyError with the names known)."""
    try:
        return RAILS[name]
    except KeyError:
        known = ", ".join(repr(k) for k in RAILS)
        raise KeyError(f"rail {name!r}: the rails known are {known} (or {CUSTOM_RAIL!r})") from None
