"""The squeal model's sections of a design file, each a section of the one schema
(``geometry.schema.Fields``: fields with unit, default and check, the same mapping in and
out, TOML lines and hash): [counter_body] (what the wheel rolls on, one class per kind:
:data:`COUNTER_BODIES`), [contact] (load, friction, where and how the wheel touches it,
:class:`Contact`), [damping] (:class:`Damping`) and [squeal] (what the rig showed,
:class:`Squeal`). Every value is checked on construction, with a one-line
``geometry.DesignError`` naming it.

A counter-body kind is one class here (its fields, the radii of its surface at the
contact for Hertz, and the physics object of ``reduced.counter_body`` that gives its
degrees of freedom) registered in :data:`COUNTER_BODIES`; the rest of the tool reaches
it through :class:`CounterBodySection` only. Files before the tagged section said
``[roller]``: it is read as ``[counter_body] kind = "roller"``.
"""

from __future__ import annotations

import functools
import math
from dataclasses import dataclass, field
from typing import TYPE_CHECKING, Any, ClassVar

from geometry import DesignError
from geometry.design import MAX_LENGTH_M
from geometry.schema import Fields, spec
from reduced.creep import FRICTION_LAWS, TABLE1_C22

if TYPE_CHECKING:
    from reduced import CounterBody, ModalDOF

__all__ = [
    "C22_RANGE",
    "COUNTER_BODIES",
    "CounterBodySection",
    "DEFAULT_FRICTION_LAW",
    "MAX_RELAXATION_LENGTH_M",
    "NORMAL_CONTACTS",
    "ROLLER_MODAL",
    "ROLLER_RANGES",
    "Contact",
    "Damping",
    "Roller",
    "Squeal",
    "counter_body_from_file",
    "mode_key",
]


#: The longest label a [squeal.damping] key may be (a modal model's mode label)
MAX_DAMPING_LABEL_CHARS = 80


def mode_key(label: str, source: str = "design") -> str:
    """A ``[squeal.damping]`` key written the one way: ``n=N,c=C`` for an FE mode named by
    nodal diameters and circles (``"n = 01, c = 0"`` is ``"n=1,c=0"``; the grammar is
    ``fem.modes.ModeSelection``'s), or a modal model's mode label as it is."""
    from fem.modes import ModeSelection

    text = str(label)
    if "=" not in text:
        if text.strip() and text.isprintable() and len(text) <= MAX_DAMPING_LABEL_CHARS:
            return text
        raise DesignError(
            f"{source}: [squeal.damping] key {ascii(text[:40])}: a mode's label (printable, at most "
            f'{MAX_DAMPING_LABEL_CHARS} characters) or "n=N,c=C" (nodal diameters, circles)'
        )
    try:
        sel = ModeSelection.parse(text)
    except ValueError:
        sel = None
    if sel is None or sel.nodal_diameters is None or "c" not in text.replace(" ", ""):
        raise DesignError(
            f'{source}: [squeal.damping] key {label!r}: use "n=N,c=C" (nodal diameters, circles) or a '
            "modal model's mode label"
        )
    return f"n={sel.nodal_diameters},c={sel.nodal_circles}"


def _positive(owner: str, name: str, value: float, *, length: bool = False) -> None:
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
    contact (Hertz); :meth:`body` is its physics (``reduced.CounterBody``: degrees of
    freedom in series with the contact); :meth:`dof_labels` name those degrees of
    freedom. ``HASH_KEY``: the key of its values in a design's content hash."""

    TABLE: ClassVar[str] = "counter_body"
    KIND: ClassVar[str] = ""
    HASH_KEY: ClassVar[str] = "counter_body"
    #: Whether its degrees of freedom start the time domain in their static deflection
    #: under the steady creep force (a track, loaded long before); False: at rest at zero
    PRELOADED: ClassVar[bool] = False

    def contact_radii(self) -> tuple[float, float]:
        """(radius along rolling, radius across) of its surface at the contact [m]."""
        raise NotImplementedError

    def body(self) -> CounterBody:
        raise NotImplementedError

    def dofs(self) -> list[ModalDOF]:
        """Its degrees of freedom at the contact (``reduced.ModalDOF``, gains -1)."""
        return self.body().dofs()

    def dof_labels(self) -> list[str]:
        raise NotImplementedError

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
        _positive("counter_body", "rolling_radius", self.rolling_radius, length=True)
        _positive("counter_body", "crown_radius", self.crown_radius)
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
                _positive("counter_body", f"{direction}_{k}", value)
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

    def body(self) -> CounterBody:
        from reduced import ModalRoller, RigidCounterBody

        normal, lateral = self.modal("normal"), self.modal("lateral")
        return RigidCounterBody() if normal is None and lateral is None else ModalRoller(normal, lateral)

    def dof_labels(self) -> list[str]:
        return [f"roller {d}" for d in ("normal", "lateral") if self.modal(d) is not None]


#: Where the wheel touches the rail in the sleeper bay, by name (a fraction of the span
#: from a sleeper otherwise)
RAIL_POSITIONS = {"support": 0.0, "midspan": 0.5}
#: The band the rail's receptance is fitted over [Hz] and its frequencies per decade
TRACK_FIT_BAND_HZ, TRACK_FIT_POINTS_PER_DECADE = (20.0, 6000.0), 100


def _rail(default: float, unit: str, doc: str) -> Any:
    return spec(default, unit, doc)


@dataclass(frozen=True)
class Track(CounterBodySection):
    """A rail on discrete, periodic supports (``track``): the rail section (UIC60 by
    default), the sleepers and, per direction, pad and ballast. The contact's normal is
    the rail's vertical, its lateral tangent the rail's lateral (a contact on the rail
    head's crown; the rail's torsion is left out). ``position``: "support", "midspan" or a
    fraction of the span from a sleeper (in quotes: "0.3"); ``head_radius``: the rail
    head's transverse radius [m]."""

    KIND: ClassVar[str] = "track"
    HASH_KEY: ClassVar[str] = "track"
    PRELOADED: ClassVar[bool] = True

    rail: str = spec("UIC60", "-", "the rail section's name (its values below)")
    rail_youngs_modulus: float = _rail(210e9, "Pa", "the rail's Young's modulus E")
    rail_shear_modulus: float = _rail(81e9, "Pa", "the rail's shear modulus G")
    rail_density: float = _rail(7850.0, "kg/m^3", "the rail's density")
    rail_area: float = _rail(76.7e-4, "m^2", "the rail's cross-section A")
    rail_second_moment_vertical: float = _rail(3038.3e-8, "m^4", "I for vertical bending")
    rail_second_moment_lateral: float = _rail(512.7e-8, "m^4", "I for lateral bending")
    rail_shear_coefficient_vertical: float = _rail(0.4, "", "Timoshenko's shear coefficient, vertical")
    rail_shear_coefficient_lateral: float = _rail(0.538, "", "Timoshenko's shear coefficient, lateral")
    rail_loss_factor: float = _rail(0.01, "", "the rail's bending loss factor")
    head_radius: float = _rail(0.3, "m", "the rail head's transverse radius")
    sleeper_spacing: float = _rail(0.6, "m", "the distance between sleepers")
    sleeper_mass: float = _rail(162.0, "kg", "the sleeper's mass per rail seat")
    pad_stiffness_vertical: float = _rail(300e6, "N/m", "the rail pad's vertical stiffness")
    pad_loss_factor_vertical: float = _rail(0.25, "", "the rail pad's vertical loss factor")
    ballast_stiffness_vertical: float = _rail(50e6, "N/m", "the ballast's vertical stiffness per rail seat")
    ballast_loss_factor_vertical: float = _rail(1.0, "", "the ballast's vertical loss factor")
    pad_stiffness_lateral: float = _rail(50e6, "N/m", "the rail pad's lateral stiffness")
    pad_loss_factor_lateral: float = _rail(0.25, "", "the rail pad's lateral loss factor")
    ballast_stiffness_lateral: float = _rail(35e6, "N/m", "the ballast's lateral stiffness per rail seat")
    ballast_loss_factor_lateral: float = _rail(1.0, "", "the ballast's lateral loss factor")
    position: str = spec("midspan", "-", 'where in the sleeper bay: "support", "midspan" or a fraction')

    def __post_init__(self) -> None:
        for f in self.specs():
            value = getattr(self, f.name)
            if isinstance(value, float):
                if f.name.endswith("loss_factor") or "loss_factor" in f.name:
                    if not (math.isfinite(value) and 0.0 <= value <= 10.0):
                        raise DesignError(f"[counter_body] {f.name} = {value!r}: a loss factor in [0, 10]")
                    continue
                _positive("counter_body", f.name, value)
        if (
            not 0.0 < self.rail_shear_coefficient_vertical <= 1.0
            or not 0.0 < self.rail_shear_coefficient_lateral <= 1.0
        ):
            raise DesignError("[counter_body] a shear coefficient lies in (0, 1]")
        self.position_fraction()  # refused in one line if it is not a position

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
        from track import BeamSection

        common = (self.rail_youngs_modulus, self.rail_shear_modulus, self.rail_density, self.rail_area)
        return (
            BeamSection(*common, self.rail_second_moment_vertical, self.rail_shear_coefficient_vertical,
                        self.rail_loss_factor),
            BeamSection(*common, self.rail_second_moment_lateral, self.rail_shear_coefficient_lateral,
                        self.rail_loss_factor),
        )  # fmt: skip

    def supports(self) -> tuple[Any, Any]:
        """The supports vertically and laterally (``track.Supports``)."""
        from track import Supports

        return (
            Supports(self.sleeper_spacing, self.pad_stiffness_vertical, self.pad_loss_factor_vertical,
                     self.sleeper_mass, self.ballast_stiffness_vertical, self.ballast_loss_factor_vertical),
            Supports(self.sleeper_spacing, self.pad_stiffness_lateral, self.pad_loss_factor_lateral,
                     self.sleeper_mass, self.ballast_stiffness_lateral, self.ballast_loss_factor_lateral),
        )  # fmt: skip

    def contact_radii(self) -> tuple[float, float]:
        return math.inf, self.head_radius  # a straight rail: flat along rolling

    def fits(self) -> tuple[Any, Any]:
        """The rail's receptances at the contact fitted by modal terms (``track.ModalFit``,
        vertical and lateral) over :data:`TRACK_FIT_BAND_HZ`."""
        return _track_fits(self)

    def body(self) -> CounterBody:
        from reduced import ModalCounterBody

        vertical, lateral = self.fits()

        def terms(fit: Any) -> tuple[tuple[float, float, float], ...]:
            return tuple(
                zip(fit.frequency_hz.tolist(), fit.damping_ratio.tolist(), fit.modal_mass_kg.tolist())
            )

        return ModalCounterBody(terms(vertical), terms(lateral))

    def dof_labels(self) -> list[str]:
        vertical, lateral = self.fits()
        return [f"rail normal {f:.0f} Hz" for f in vertical.frequency_hz] + [
            f"rail lateral {f:.0f} Hz" for f in lateral.frequency_hz
        ]


@functools.lru_cache(maxsize=8)
def _track_fits(track: Track) -> tuple[Any, Any]:
    """The fits of a track's receptances, once per track in a process (a second each)."""
    import numpy as np

    from track import receptance
    from track.fit import fit_receptance

    lo, hi = TRACK_FIT_BAND_HZ
    f = np.geomspace(lo, hi, int(TRACK_FIT_POINTS_PER_DECADE * math.log10(hi / lo)) + 1)
    at = track.position_fraction()
    return tuple(
        fit_receptance(f, receptance(beam, support, f, at))
        for beam, support in zip(track.beams(), track.supports())
    )  # type: ignore[return-value]


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


# --------------------------------------------------------------------------------------
# the contact, the damping, what the rig showed
# --------------------------------------------------------------------------------------
#: The paper's friction law, the default of every design
DEFAULT_FRICTION_LAW = "falling"
#: How the normal force follows the contact's normal motion: "hertz" (the nonlinear
#: Hertz spring, the default) or "constant" (the paper's fixed normal load)
NORMAL_CONTACTS = ("hertz", "constant")
#: The plausible range of the creep coefficient C22 (Kalker's table spans about 2 to 10
#: for ellipses of axis ratio 0.1 to 10) and the longest relaxation length [m].
C22_RANGE = (0.1, 100.0)
MAX_RELAXATION_LENGTH_M = 1.0


@dataclass(frozen=True)
class Contact(Fields):
    """The contact of the wheel on its counter-body (module docstring; each field's
    meaning is its ``spec``)."""

    TABLE: ClassVar[str] = "contact"

    normal_load: float = spec(1000.0, "N", "the normal load W", flat="normal_load")
    c22: float = spec(TABLE1_C22, "", "Kalker's lateral creep coefficient C22 (the paper's 3.14)", flat="c22")
    friction_coefficient: float = spec(
        0.3, "", "the friction coefficient mu_s = mu_0", flat="friction_coefficient"
    )
    friction_law: str = spec(
        DEFAULT_FRICTION_LAW, "-", "a name of reduced.FRICTION_LAWS: falling (the paper's) or constant",
        when_set=True,
    )  # fmt: skip
    contact_angle: float = spec(
        0.0, "rad", "where on the tread the contact lies (0: the apex)", flat="contact_angle", when_set=True
    )
    normal_contact: str = spec(
        "hertz", "-", "hertz (the normal force follows the normal motion) or constant (fixed load)",
        when_set=True,
    )  # fmt: skip
    transient_creep: bool = spec(False, "-", "the creep force lags its steady value by L / V0", when_set=True)
    relaxation_length: float = spec(
        0.0, "m", "L of the transient creep (0: the Hertz semi-axis a along rolling)",
        flat="relaxation_length", when_set=True,
    )  # fmt: skip

    def __post_init__(self) -> None:
        for name in ("normal_load", "c22", "friction_coefficient"):
            _positive("contact", name, getattr(self, name))
        if not C22_RANGE[0] <= self.c22 <= C22_RANGE[1]:
            raise DesignError(
                f"[contact] c22 = {self.c22:g} is outside the range of Kalker's creep coefficients "
                f"({C22_RANGE[0]:g} to {C22_RANGE[1]:g}; 3.14 in the paper)"
            )
        if self.friction_law not in FRICTION_LAWS:
            raise DesignError(
                f"[contact] friction_law must be one of {', '.join(map(repr, FRICTION_LAWS))}, "
                f"got {self.friction_law!r}"
            )
        if self.normal_contact not in NORMAL_CONTACTS:
            raise DesignError(
                f"[contact] normal_contact must be one of {', '.join(map(repr, NORMAL_CONTACTS))}, "
                f"got {self.normal_contact!r}"
            )
        if isinstance(self.contact_angle, bool) or not math.isfinite(self.contact_angle):
            raise DesignError(f"[contact] contact_angle must be an angle in rad, got {self.contact_angle!r}")
        if abs(self.contact_angle) > 0.5 * math.pi:
            raise DesignError(
                f"[contact] contact_angle = {self.contact_angle:g} is over pi/2: it is in rad "
                f"(write {math.radians(self.contact_angle):.4g} for {self.contact_angle:g} deg)"
            )
        if not isinstance(self.transient_creep, bool):
            raise DesignError(
                f"[contact] transient_creep must be true or false, got {self.transient_creep!r}"
            )
        if self.relaxation_length != 0.0:
            _positive("contact", "relaxation_length", self.relaxation_length)
            if self.relaxation_length > MAX_RELAXATION_LENGTH_M:
                raise DesignError(
                    f"[contact] relaxation_length = {self.relaxation_length:g} m: the creep force builds up "
                    f"over about a contact length (a few mm), at most {MAX_RELAXATION_LENGTH_M:g} m"
                )
            if not self.transient_creep:
                raise DesignError("[contact] relaxation_length needs transient_creep = true")


@dataclass(frozen=True)
class Damping(Fields):
    """The modes' viscous damping: ``modal_damping_ratio`` [-] for every mode without a
    measured one; ``by_mode`` the measured ratios ((key, ratio), ...), sorted (the file's
    ``[squeal.damping]``; a key is "n=N,c=C" for an FE mode or a modal model's label)."""

    TABLE: ClassVar[str] = "damping"

    modal_damping_ratio: float = spec(
        9.4e-4, "", "the modal damping ratio of every mode without its own", flat="modal_damping_ratio"
    )
    by_mode: tuple[tuple[str, float], ...] = field(default=())

    def __post_init__(self) -> None:
        for name, ratio in (("modal_damping_ratio", self.modal_damping_ratio), *self.by_mode):
            if isinstance(ratio, bool) or not isinstance(ratio, int | float) or not 0.0 <= ratio < 1.0:
                raise DesignError(f"damping ratio {name} = {ratio!r}: a modal damping ratio in [0, 1)")
        keys = [k for k, _ in self.by_mode]
        for k in keys:
            if mode_key(k) != k:
                raise DesignError(f'[squeal.damping] key {k!r}: write it "{mode_key(k)}"')
        if len(set(keys)) != len(keys):
            raise DesignError("[squeal.damping] names a mode twice")

    def hash_payload(self) -> dict[str, str]:
        return {**super().hash_payload(), "by_mode": repr(self.by_mode)}

    def ratio(self, nodal_diameters: int, nodal_circles: int) -> float:
        """The (n, c) mode's damping ratio: its measured one, else the common one."""
        return dict(self.by_mode).get(f"n={nodal_diameters},c={nodal_circles}", self.modal_damping_ratio)

    def labelled(self, label: str) -> float | None:
        """The ratio ``[squeal.damping]`` gives a mode by its label (None: none)."""
        return dict(self.by_mode).get(label)


@dataclass(frozen=True)
class Squeal(Fields):
    """What the rig showed: ``mode``, the mode seen to squeal (``n=3,c=0``, an index or
    ``f=HZ``; "" for none). A named mode is an override (:mod:`wheel_squeal.verdict`)."""

    TABLE: ClassVar[str] = "squeal"

    mode: str = spec("", "-", "the mode the rig was seen to squeal in (an override of the model's pick)")

    def __post_init__(self) -> None:
        if not isinstance(self.mode, str):
            raise DesignError(f'[squeal] mode must be a string like "n=3,c=0", got {self.mode!r}')
        if self.mode:
            from fem.modes import ModeSelection

            try:
                ModeSelection.parse(self.mode)
            except ValueError:
                raise DesignError(f"[squeal] mode {self.mode!r}: use n=N[,c=C], an index or f=HZ") from None
