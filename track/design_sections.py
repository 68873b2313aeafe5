"""The design file's sections of what the wheel runs on, each a section of the one schema
(``geometry.schema.Fields``):

- ``[counter_body]``: what the wheel rolls on, one class per kind registered in
  :data:`COUNTER_BODIES` (its fields, the radii of its surface at the contact for Hertz,
  and the physics object of ``reduced.counter_body`` that gives its degrees of freedom):
  the rig's roller (:class:`Roller`) and a rail on sleepers (:class:`Track`). A kind is
  reached through :class:`CounterBodySection` only. Files before the tagged section said
  ``[roller]``: it is read as ``[counter_body] kind = "roller"``.
- ``[vehicle]``: the bogie a wheel runs in through curves (:class:`VehicleSection`).
"""

from __future__ import annotations

import functools
import math
from dataclasses import dataclass
from typing import TYPE_CHECKING, Any, ClassVar

from geometry import DesignError
from geometry.schema import Fields, spec
from geometry.wheel_design import MAX_LENGTH_M

if TYPE_CHECKING:
    from reduced import BodyModel

    from .bogie_curving import Vehicle

__all__ = [
    "COUNTER_BODIES",
    "RAIL_POSITIONS",
    "ROLLER_MODAL",
    "ROLLER_RANGES",
    "TRACK_FIT_BAND_HZ",
    "CounterBodySection",
    "Roller",
    "Track",
    "VehicleSection",
    "check_positive",
    "counter_body_from_file",
]


def check_positive(owner: str, name: str, value: float, *, length: bool = False) -> None:
    if (
        isinstance(value, bool)
        or not isinstance(value, int | float)
        or not math.isfinite(value)
        or value <= 0
    ):
        raise DesignError(f"[{owner}] {name} must be a positive number, got {value!r}")
    if length and value > MAX_LENGTH_M:
        raise DesignError(
            f"[{owner}] {name} = {value:g} m is longer than any wheel ({MAX_LENGTH_M:g} m): "
            f"it looks like millimetres; write {value / 1000:g}"
        )


# --------------------------------------------------------------------------------------
# the counter-body: one section class per kind
# --------------------------------------------------------------------------------------
class CounterBodySection(Fields):
    """What the wheel rolls on, as a design file gives it: ``KIND`` names it in
    ``[counter_body] kind = ...``; :meth:`contact_radii` are its surface's radii at the
    contact (Hertz); :meth:`model` is its physics (``reduced.BodyModel``: its receptance
    at the contact, in series with it), named by its ``model().name``. ``HASH_KEY``: the
    key of its values in a design's content hash."""

    TABLE: ClassVar[str] = "counter_body"
    KIND: ClassVar[str] = ""
    HASH_KEY: ClassVar[str] = "counter_body"
    #: Whether its degrees of freedom start the time domain in their static deflection
    #: under the steady creep force (a track, loaded long before); False: at rest at zero
    PRELOADED: ClassVar[bool] = False

    def contact_radii(self) -> tuple[float, float]:
        """(radius along rolling, radius across) of its surface at the contact [m]."""
        raise NotImplementedError

    def model(self) -> BodyModel:
        """Its receptance at the contact (``reduced.BodyModel``; no terms: rigid)."""
        raise NotImplementedError

    def states(self) -> int:
        """The states :meth:`model` gives (for a cost plan: a bound where finding them is
        itself work)."""
        return self.model().states

    def model_seconds(self) -> float:
        """What making :meth:`model` takes in this process [s] (for a cost plan)."""
        return 0.0

    def summary(self) -> dict[str, Any]:
        """JSON-ready: its kind and values."""
        return {"kind": self.KIND, **self.to_mapping()}


#: The counter-body's modal degrees of freedom: per direction at the contact, its
#: frequency [Hz], damping ratio [-] and modal mass [kg] (all three, or none: rigid).
ROLLER_MODAL = ("frequency_hz", "damping_ratio", "modal_mass_kg")
#: Plausible ranges (low, high, unit) of a counter-body mode's frequency and modal mass:
#: outside them a value is a typing error (and would overflow the model).
ROLLER_RANGES = {"frequency_hz": (0.1, 1e6, "Hz"), "modal_mass_kg": (1e-6, 1e6, "kg")}


def _modal(direction: str, key: str) -> Any:
    unit = {"frequency_hz": "Hz", "damping_ratio": "", "modal_mass_kg": "kg"}[key]
    what = {"frequency_hz": "frequency", "damping_ratio": "damping ratio", "modal_mass_kg": "modal mass"}[key]
    along = "the contact normal" if direction == "normal" else "the lateral tangent"
    return spec(None, unit, f"the {what} of the roller's mode along {along} (none: rigid)", when_set=True)


@dataclass(frozen=True)
class Roller(CounterBodySection):
    """The rig's upper wheel: rolling_radius R2 [m], crown_radius R2t [m]. Rigid and fixed
    unless a direction gives its modal degree of freedom at the contact (frequency,
    damping ratio and modal mass along the contact normal and/or the lateral tangent, in
    series with the contact)."""

    KIND: ClassVar[str] = "roller"
    HASH_KEY: ClassVar[str] = "roller"

    rolling_radius: float = spec(
        0.085, "m", "R2, the roller's rolling radius", flat="roller_rolling_radius", length=True
    )
    crown_radius: float = spec(
        0.040, "m", "R2t, the roller's transverse (crown) radius", flat="roller_crown_radius", length=True
    )
    normal_frequency_hz: float | None = _modal("normal", "frequency_hz")
    normal_damping_ratio: float | None = _modal("normal", "damping_ratio")
    normal_modal_mass_kg: float | None = _modal("normal", "modal_mass_kg")
    lateral_frequency_hz: float | None = _modal("lateral", "frequency_hz")
    lateral_damping_ratio: float | None = _modal("lateral", "damping_ratio")
    lateral_modal_mass_kg: float | None = _modal("lateral", "modal_mass_kg")

    def __post_init__(self) -> None:
        check_positive("counter_body", "rolling_radius", self.rolling_radius, length=True)
        check_positive("counter_body", "crown_radius", self.crown_radius)
        for direction in ("normal", "lateral"):
            given = [k for k in ROLLER_MODAL if getattr(self, f"{direction}_{k}") is not None]
            if given and len(given) < len(ROLLER_MODAL):
                missing = [f"{direction}_{k}" for k in ROLLER_MODAL if k not in given]
                raise DesignError(
                    f"[counter_body] a {direction} modal degree of freedom needs {', '.join(missing)} too "
                    "(frequency, damping ratio and modal mass; none of them: rigid)"
                )
            for k in given:
                value = getattr(self, f"{direction}_{k}")
                if k == "damping_ratio":
                    if isinstance(value, bool) or not 0.0 <= value < 1.0:
                        raise DesignError(
                            f"[counter_body] {direction}_{k} = {value!r}: a damping ratio in [0, 1)"
                        )
                    continue
                check_positive("counter_body", f"{direction}_{k}", value)
                low, high, unit = ROLLER_RANGES[k]
                if not low <= value <= high:
                    raise DesignError(
                        f"[counter_body] {direction}_{k} = {value:g} {unit} is outside the plausible range "
                        f"of a counter-body's mode ({low:g} to {high:g} {unit})"
                    )

    def modal(self, direction: str) -> tuple[float, float, float] | None:
        """(frequency [Hz], damping ratio, modal mass [kg]) of its modal degree of freedom
        along ``direction`` ("normal" or "lateral"), None where it is rigid."""
        values = tuple(getattr(self, f"{direction}_{k}") for k in ROLLER_MODAL)
        return None if values[0] is None else values

    def contact_radii(self) -> tuple[float, float]:
        return self.rolling_radius, self.crown_radius

    def model(self) -> BodyModel:
        from reduced import ModalRoller

        return ModalRoller(self.modal("normal"), self.modal("lateral")).model()


#: Where the wheel touches the rail in the sleeper bay, by name (a fraction of the span
#: from a sleeper otherwise)
RAIL_POSITIONS = {"support": 0.0, "midspan": 0.5}
#: The band the rail's receptance is fitted over [Hz] (a decade below the lowest squeal
#: and beyond the modes' band) and its frequencies per decade
TRACK_FIT_BAND_HZ, TRACK_FIT_POINTS_PER_DECADE = (2.0, 8000.0), 100
#: The receptances on that grid and the rational fits of both directions, once per track
#: in a process [s]
TRACK_FIT_SECONDS = 1.0


def _rail(default: float | None, unit: str, doc: str, plausible: tuple[float, float]) -> Any:
    return spec(default, unit, doc, plausible=plausible, when_set=default is None)


def _section(unit: str, doc: str, plausible: tuple[float, float]) -> Any:
    """A value of the rail's cross-section: the named rail's (``track.rails.RAILS``) unless
    ``rail = "custom"``, which takes it from the design."""
    return _rail(None, unit, f"{doc} (a custom rail's; a named rail gives its own)", plausible)


#: The rail's cross-section values a custom rail gives, and where the named rail's are
#: (``track.rails.RailSection``'s field of each)
RAIL_SECTION_FIELDS = {
    "rail_area": "area_m2",
    "rail_second_moment_vertical": "second_moment_vertical_m4",
    "rail_second_moment_lateral": "second_moment_lateral_m4",
    "rail_shear_coefficient_vertical": "shear_coefficient_vertical",
    "rail_shear_coefficient_lateral": "shear_coefficient_lateral",
}


@dataclass(frozen=True)
class Track(CounterBodySection):
    """A rail on discrete, periodic supports (``track``): the rail (a section named in
    ``track.rails.RAILS``, UIC60 by default, or ``"custom"`` with its cross-section given),
    the sleepers and, per direction, pad and ballast. The contact's normal is the rail's
    vertical, its lateral tangent the rail's lateral (a contact on the rail head's crown;
    the rail's torsion is left out). ``position``: "support", "midspan" or a fraction of
    the span from a sleeper (in quotes: "0.3"); ``head_radius``: the rail head's
    transverse radius [m]. Every value is checked against the range real tracks span."""

    KIND: ClassVar[str] = "track"
    HASH_KEY: ClassVar[str] = "track"
    PRELOADED: ClassVar[bool] = True

    rail: str = spec("UIC60", "-", "the rail's name (a section of EN 13674-1) or custom")
    rail_youngs_modulus: float = _rail(210e9, "Pa", "the rail's Young's modulus E", (150e9, 250e9))
    rail_shear_modulus: float = _rail(81e9, "Pa", "the rail's shear modulus G", (50e9, 100e9))
    rail_density: float = _rail(7850.0, "kg/m^3", "the rail's density", (7000.0, 8500.0))
    rail_area: float | None = _section("m^2", "the rail's cross-section A", (15e-4, 150e-4))
    rail_second_moment_vertical: float | None = _section("m^4", "I for vertical bending", (200e-8, 1e-4))
    rail_second_moment_lateral: float | None = _section("m^4", "I for lateral bending", (30e-8, 3e-5))
    rail_shear_coefficient_vertical: float | None = _section(
        "", "Timoshenko's shear coefficient, vertical", (0.05, 1.0)
    )
    rail_shear_coefficient_lateral: float | None = _section(
        "", "Timoshenko's shear coefficient, lateral", (0.05, 1.0)
    )
    rail_loss_factor: float = _rail(0.01, "", "the rail's bending loss factor", (0.0, 0.5))
    head_radius: float = _rail(0.3, "m", "the rail head's transverse radius", (0.01, 1.0))
    sleeper_spacing: float = _rail(0.6, "m", "the distance between sleepers", (0.3, 1.2))
    sleeper_mass: float = _rail(162.0, "kg", "the sleeper's mass per rail seat", (10.0, 1000.0))
    pad_stiffness_vertical: float = _rail(300e6, "N/m", "the rail pad's vertical stiffness", (10e6, 5e9))
    pad_loss_factor_vertical: float = _rail(0.25, "", "the rail pad's vertical loss factor", (0.0, 2.0))
    ballast_stiffness_vertical: float = _rail(
        50e6, "N/m", "the ballast's vertical stiffness per rail seat", (5e6, 2e9)
    )
    ballast_loss_factor_vertical: float = _rail(1.0, "", "the ballast's vertical loss factor", (0.0, 4.0))
    pad_stiffness_lateral: float = _rail(50e6, "N/m", "the rail pad's lateral stiffness", (1e6, 2e9))
    pad_loss_factor_lateral: float = _rail(0.25, "", "the rail pad's lateral loss factor", (0.0, 2.0))
    ballast_stiffness_lateral: float = _rail(
        35e6, "N/m", "the ballast's lateral stiffness per rail seat", (1e6, 2e9)
    )
    ballast_loss_factor_lateral: float = _rail(1.0, "", "the ballast's lateral loss factor", (0.0, 4.0))
    position: str = spec("midspan", "-", 'where in the sleeper bay: "support", "midspan" or a fraction')

    def __post_init__(self) -> None:
        from .rails import CUSTOM_RAIL, RAILS

        if self.rail not in RAILS and self.rail != CUSTOM_RAIL:
            known = ", ".join(repr(k) for k in RAILS)
            raise DesignError(
                f"[counter_body] rail = {self.rail!r}: the rails known are {known}; for another one write "
                f'rail = "{CUSTOM_RAIL}" and give its cross-section ({", ".join(RAIL_SECTION_FIELDS)})'
            )
        given = [k for k in RAIL_SECTION_FIELDS if getattr(self, k) is not None]
        if self.rail == CUSTOM_RAIL and len(given) < len(RAIL_SECTION_FIELDS):
            missing = [k for k in RAIL_SECTION_FIELDS if k not in given]
            raise DesignError(f'[counter_body] rail = "{CUSTOM_RAIL}" needs its {", ".join(missing)}')
        if self.rail != CUSTOM_RAIL and given:
            raise DesignError(
                f"[counter_body] rail = {self.rail!r} has its own {', '.join(given)}: leave them out, or "
                f'write rail = "{CUSTOM_RAIL}" and give the whole cross-section'
            )
        self.check_plausible()
        self.position_fraction()  # refused in one line if it is not a position

    def section_value(self, name: str) -> float:
        """A cross-section value (a key of :data:`RAIL_SECTION_FIELDS`): the design's for a
        custom rail, else the named rail's."""
        from .rails import CUSTOM_RAIL, rail_section

        value = getattr(self, name)
        if self.rail == CUSTOM_RAIL:
            return float(value)
        return float(getattr(rail_section(self.rail), RAIL_SECTION_FIELDS[name]))

    def position_fraction(self) -> float:
        """Where the contact is in the bay, as a fraction of the span from a sleeper [-]."""
        if self.position in RAIL_POSITIONS:
            return RAIL_POSITIONS[self.position]
        try:
            fraction = float(self.position)
        except ValueError:
            fraction = math.nan
        if not 0.0 <= fraction < 1.0:
            raise DesignError(
                f'[counter_body] position = {self.position!r}: "support", "midspan" or a fraction of the '
                'span in [0, 1) in quotes, like "0.3"'
            )
        return fraction

    def beams(self) -> tuple[Any, Any]:
        """The rail bending vertically and laterally (``track.BeamSection``)."""
        from .beam import BeamSection

        area = self.section_value("rail_area")
        common = (self.rail_youngs_modulus, self.rail_shear_modulus, self.rail_density, area)
        return tuple(
            BeamSection(
                *common,
                self.section_value(f"rail_second_moment_{d}"),
                self.section_value(f"rail_shear_coefficient_{d}"),
                self.rail_loss_factor,
            )
            for d in ("vertical", "lateral")
        )  # type: ignore[return-value]

    def supports(self) -> tuple[Any, Any]:
        """The supports vertically and laterally (``track.Supports``)."""
        from .beam import Supports

        return tuple(
            Supports(
                self.sleeper_spacing,
                getattr(self, f"pad_stiffness_{d}"),
                getattr(self, f"pad_loss_factor_{d}"),
                self.sleeper_mass,
                getattr(self, f"ballast_stiffness_{d}"),
                getattr(self, f"ballast_loss_factor_{d}"),
            )
            for d in ("vertical", "lateral")
        )  # type: ignore[return-value]

    def contact_radii(self) -> tuple[float, float]:
        return math.inf, self.head_radius  # a straight rail: flat along rolling

    def model_seconds(self) -> float:
        return 0.0 if _track_fits.cache_info().currsize else TRACK_FIT_SECONDS

    def states(self) -> int:
        if _track_fits.cache_info().currsize:  # fitted in this process: the count itself
            return self.model().states
        from .fit import POLE_PAIRS

        return 2 * 2 * POLE_PAIRS  # at most: two directions of pairs

    def fits(self) -> tuple[Any, Any]:
        """The rail's receptances at the contact fitted by rational functions
        (``track.fit.RationalFit``, vertical and lateral) over :data:`TRACK_FIT_BAND_HZ`."""
        return _track_fits(self)

    def model(self) -> BodyModel:
        return _track_model(self)


@functools.lru_cache(maxsize=8)
def _track_model(track: Track) -> BodyModel:
    """The rail's state space from its fits, once per track in a process (every contact
    of a curve map takes it)."""
    from reduced import LATERAL, NORMAL, BodyModel

    vertical, lateral = track.fits()
    model = BodyModel.from_rational(
        [(NORMAL, vertical.poles, vertical.residues), (LATERAL, lateral.poles, lateral.residues)],
        "the rail",
    )
    for values in (model.order, model.direction, model.a0, model.a1, model.b0, model.b1):
        values.setflags(write=False)  # shared by every caller in the process
    return model


@functools.lru_cache(maxsize=8)
def _track_fits(track: Track) -> tuple[Any, Any]:
    """The fits of a track's receptances, once per track in a process (a second each)."""
    import numpy as np

    from .beam import receptance
    from .fit import fit_receptance

    lo, hi = TRACK_FIT_BAND_HZ
    f = np.geomspace(lo, hi, int(TRACK_FIT_POINTS_PER_DECADE * math.log10(hi / lo)) + 1)
    at = track.position_fraction()
    return tuple(
        fit_receptance(f, receptance(beam, support, f, at))
        for beam, support in zip(track.beams(), track.supports())
    )  # type: ignore[return-value]


@dataclass(frozen=True)
class VehicleSection(Fields):
    """The bogie a wheel runs in through curves ([vehicle]; read by ``curve`` alone): its
    wheelbase and primary suspension per wheelset, and the height of the mass on its wheels
    (``track.bogie_curving.Vehicle``). The defaults are of the order of a conventional
    passenger bogie's, not one vehicle's."""

    TABLE: ClassVar[str] = "vehicle"

    wheelbase: float = spec(
        2.5,
        "m",
        "2a, the distance between the bogie's axles",
        flat="wheelbase",
        when_set=True,
        plausible=(1.0, 20.0),
    )
    primary_yaw_stiffness: float = spec(
        1.0e7,
        "N m/rad",
        "k_psi, the primary suspension's yaw stiffness per wheelset",
        flat="primary_yaw_stiffness",
        when_set=True,
        plausible=(0.0, 1.0e11),
    )
    primary_lateral_stiffness: float = spec(
        5.0e6,
        "N/m",
        "k_y, the primary suspension's lateral stiffness per wheelset",
        flat="primary_lateral_stiffness",
        when_set=True,
        plausible=(1.0e4, 1.0e10),
    )
    centre_of_gravity_height: float = spec(
        1.5,
        "m",
        "h_cg, the height of the mass on the wheels above the rail heads",
        flat="centre_of_gravity_height",
        when_set=True,
        plausible=(0.3, 4.0),
    )

    def __post_init__(self) -> None:
        self.check_plausible()

    def vehicle(self) -> Vehicle:
        """The curving's record of these values."""
        from .bogie_curving import Vehicle

        return Vehicle(
            self.wheelbase,
            self.primary_yaw_stiffness,
            self.primary_lateral_stiffness,
            self.centre_of_gravity_height,
        )


#: Every counter-body kind a design file may give, by its ``kind``.
COUNTER_BODIES: dict[str, type[CounterBodySection]] = {"roller": Roller, "track": Track}


def counter_body_from_file(data: dict[str, Any], source: str) -> CounterBodySection:
    """The counter-body of a design file's mapping: ``[counter_body]`` with its ``kind``
    (default "roller"), or an older file's ``[roller]``."""
    if "roller" in data and "counter_body" in data:
        raise DesignError(f"{source}: give [counter_body] or the older [roller], not both")
    if "roller" in data:
        return Roller.from_mapping(data["roller"], source)
    table = data.get("counter_body", {})
    if not isinstance(table, dict):
        raise DesignError(f"{source}: [counter_body] must be a table")
    kind = table.get("kind", "roller")
    if kind not in COUNTER_BODIES:
        raise DesignError(
            f"{source}: [counter_body] kind = {kind!r}: the kinds are {', '.join(map(repr, COUNTER_BODIES))}"
        )
    return COUNTER_BODIES[kind].from_mapping({k: v for k, v in table.items() if k != "kind"}, source)
