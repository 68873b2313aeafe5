"""A design file: the wheel (``geometry.WheelDesign``, which owns the wheel's shape and
material) and the squeal model's sections (:mod:`wheel_squeal.model_sections`), each a
section of the one schema (``geometry.schema``):

    name = "table1"
    [wheel] or [profile], [material]   the wheel            (geometry.WheelDesign)
    [counter_body]  kind = "roller"   what it rolls on     (a class per kind; older files: [roller])
    [contact]                         load and friction     (Contact)
    [damping]                         every mode's ratio    (Damping)
    [squeal]                          what the rig showed   (Squeal: ``mode``,
    [squeal.damping]                  and measured ratios by mode, in Damping)
    [vehicle]                         the bogie in curves   (VehicleSection)

Every key is checked and missing ones take the Table 1 values; a mistake is one
``geometry.DesignError``. A number is also known by one flat name (:data:`FIELDS`:
``rim_depth``, ``roller_rolling_radius``, ``normal_load``...), which studies and
calibration vary. :class:`Design` reads, writes, hashes, changes and scales by asking
each section in turn: a new section (or counter-body kind) needs nothing here.
"""

from __future__ import annotations

import dataclasses
import functools
import hashlib
import json
import warnings
from dataclasses import dataclass, field
from pathlib import Path
from typing import TYPE_CHECKING, Any

from contact.frames import ContactFrame, ContactPointError, contact_frame
from geometry import SECTIONS, DesignError, WheelDesign
from geometry.files import LABEL_PATTERN, LABEL_RULE, read_toml
from geometry.schema import Fields, toml_value

from .model_sections import (
    COUNTER_BODIES,
    DAMPING_KEYS,
    Contact,
    CounterBodySection,
    Damping,
    Roller,
    Squeal,
    VehicleSection,
    counter_body_from_file,
    mode_key,
)

if TYPE_CHECKING:
    from fem.modes import Mode

__all__ = [
    "FIELDS",
    "FIELD_UNITS",
    "Contact",
    "ContactSite",
    "Damping",
    "Design",
    "Roller",
    "Squeal",
    "as_design",
    "mode_key",
]

#: The sections after the wheel, in file order: (attribute, class).
_PARTS: tuple[tuple[str, type[Fields]], ...] = (
    ("contact", Contact),
    ("damping", Damping),
    ("squeal", Squeal),
    ("vehicle", VehicleSection),
)

#: Every numeric field of a design by its flat name: (section attribute, field name).
FIELDS: dict[str, tuple[str, str]] = {
    **{k: ("wheel", k) for keys in SECTIONS.values() for k in keys},
    **{
        flat: ("counter_body", name)
        for kind in COUNTER_BODIES.values()
        for flat, (name, _) in kind.flat_fields().items()
    },
    **{flat: (attr, name) for attr, cls in _PARTS for flat, (name, _) in cls.flat_fields().items()},
}
#: The unit of every numeric design field by its flat name ("" dimensionless).
FIELD_UNITS: dict[str, str] = {
    **dict.fromkeys(SECTIONS["wheel"], "m"),
    "youngs_modulus": "Pa",
    "poissons_ratio": "",
    "density": "kg/m^3",
    **{flat: unit for kind in COUNTER_BODIES.values() for flat, (_, unit) in kind.flat_fields().items()},
    **{flat: unit for _, cls in _PARTS for flat, (_, unit) in cls.flat_fields().items()},
}
#: The names :meth:`Design.replace` takes beyond :data:`FIELDS`: (section, field).
_WORDS = {
    "name": ("wheel", "name"),
    "description": ("wheel", "description"),
    "friction_law": ("contact", "friction_law"),
    "normal_contact": ("contact", "normal_contact"),
    "transient_creep": ("contact", "transient_creep"),
    "wheel_profile": ("contact", "wheel_profile"),
    "squeal_mode": ("squeal", "mode"),
    "mode_damping": ("damping", "by_mode"),
}


@dataclass(frozen=True)
class ContactSite:
    """Where a curving puts a wheel's contact, instead of the design's own contact point:
    the frame on the running surface (``contact.frames.frame_on_running_surface``) and
    the transverse radius of the wheel's and the rail's relative curvature there [m] (the
    Hertz ellipse's across the rolling direction; the rail's own radius is in it)."""

    frame: ContactFrame
    relative_transverse_radius_m: float


@dataclass(frozen=True)
class Design:
    """A design: the wheel and the squeal model's inputs (see the module docstring).

    Attributes
    ----------
    wheel : geometry.WheelDesign
        The wheel's shape and material (lengths in m, E in Pa, density in kg/m^3).
    counter_body : CounterBodySection
        What it rolls on ([counter_body]: a kind, its fields).
    contact : Contact
        Normal load [N], creep coefficient, friction, contact angle [rad], normal
        contact, transient creep.
    damping : Damping
        Every mode's damping ratio, and measured ones by mode.
    squeal : Squeal
        The mode the rig was seen to squeal in ("": none).
    vehicle : VehicleSection
        The bogie it runs in through curves.
    contact_site : ContactSite, optional
        Where a curving has put the contact (None: the design's own contact point).

    Examples
    --------
    >>> import wheel_squeal as ws
    >>> d = ws.load_design("table1")
    >>> d.name, d.counter_body.KIND, d.contact.normal_load
    ('table1', 'roller', 1000.0)
    >>> d.replace(normal_load=1500.0).get("normal_load")
    1500.0
    """

    wheel: WheelDesign = field(default_factory=WheelDesign)
    counter_body: CounterBodySection = field(default_factory=Roller)
    contact: Contact = field(default_factory=Contact)
    damping: Damping = field(default_factory=Damping)
    squeal: Squeal = field(default_factory=Squeal)
    vehicle: VehicleSection = field(default_factory=VehicleSection)
    contact_site: ContactSite | None = None

    def __post_init__(self) -> None:
        self.contact_frame  # noqa: B018 (an angle the tread cannot take is refused here)

    @property
    def name(self) -> str:
        return self.wheel.name

    @functools.cached_property
    def contact_frame(self) -> ContactFrame:
        """Where the wheel touches its counter-body and the contact's frame there
        (``contact.frames``: the tread apex unless [contact] contact_angle moves it;
        an outline's contact point sets its own; a curving's :class:`ContactSite`
        replaces it)."""
        if self.contact_site is not None:
            return self.contact_site.frame
        try:
            return contact_frame(self.wheel, self.contact.contact_angle)
        except ContactPointError as exc:
            raise DesignError(f"{self.name}: {exc}") from None

    def damping_ratio_of(self, mode: Mode) -> float:
        """A mode's modal damping ratio (:meth:`damping_source`)."""
        return self.damping_source(mode)[0]

    def damping_source(self, mode: Mode) -> tuple[float, str]:
        """A mode's modal damping ratio and where it comes from: the design's for its
        label ([squeal.damping], a modal model's mode: a remedy pasted in overrides the
        modal test), else its own (a modal test's: "measured"), else the design's for its
        (n, c), its family or ``modal_damping_ratio`` (``Damping.source``)."""
        return self.damping.of_mode(mode)

    @property
    def rolling_radius(self) -> float:
        """The radius the contact rolls on [m] (R1 at the tread apex): rpm <-> V0."""
        return self.contact_frame.rolling_radius_m

    @property
    def description(self) -> str:
        return self.wheel.description

    def _sections(self) -> dict[str, Fields]:
        return {"counter_body": self.counter_body, **{attr: getattr(self, attr) for attr, _ in _PARTS}}

    def get(self, name: str) -> Any:
        """A field by its flat name (:data:`FIELDS`)."""
        part, attr = _field(name)
        owner = getattr(self, part)
        if not hasattr(owner, attr):
            raise DesignError(
                f"{name!r} is not a field of {self.name}'s counter-body ({self.counter_body.KIND})"
            )
        return getattr(owner, attr)

    def replace(self, **changes: Any) -> Design:
        """A validated copy with fields changed, by their flat names (:data:`FIELDS`), or
        ``name``, ``description``, ``squeal_mode``, ``mode_damping``, the [contact] words
        and switches, the counter-body's other fields by their own names (its flat names,
        ``roller_rolling_radius``, where they clash with the wheel's), or ``counter_body``
        (a whole section)."""
        parts: dict[str, dict[str, Any]] = {}
        body_fields = {f.name for f in self.counter_body.specs()}
        new_body = changes.pop("counter_body", None)
        for name, value in changes.items():
            if name in _WORDS:
                part, attr = _WORDS[name]
            elif name in FIELDS or name not in body_fields:  # flat names first: the wheel's radii
                part, attr = _field(name)
            else:
                part, attr = "counter_body", name
            parts.setdefault(part, {})[attr] = value
        new: dict[str, Any] = {"counter_body": new_body} if new_body is not None else {}
        for part, values in parts.items():
            owner = new.get(part, getattr(self, part))
            if part == "counter_body" and not set(values) <= body_fields:
                bad = sorted(set(values) - body_fields)[0]
                raise DesignError(f"{bad!r} is not a field of {self.name}'s counter-body ({owner.KIND})")
            new[part] = owner.replace(**values)
        return dataclasses.replace(self, **new)

    def scaled(self, factor: float) -> Design:
        """The same design with every length of the wheel and its counter-body times
        ``factor``."""
        return dataclasses.replace(
            self, wheel=self.wheel.scaled(factor), counter_body=self.counter_body.scaled(factor)
        )

    @property
    def own(self) -> Design:
        """The design at its own contact point (without a curving's :class:`ContactSite`):
        what its modes are solved and cached for."""
        return self if self.contact_site is None else dataclasses.replace(self, contact_site=None)

    def content_hash(self) -> str:
        """Stable SHA-256 (16 hex) of every value but the name and the description (the
        wheel's modes depend on ``wheel.content_hash("structure")`` alone)."""
        payload: dict[str, Any] = {"wheel": self.wheel.content_hash("all")}
        if self.contact_site is not None:
            f = self.contact_site.frame
            payload["contact_site"] = [
                f.r_m,
                f.z_m,
                f.angle_rad,
                repr(f.crown_radius_m),
                self.contact_site.relative_transverse_radius_m,
            ]
        body = self.counter_body
        payload[body.HASH_KEY] = body.hash_payload() | (
            {} if body.HASH_KEY == "roller" else {"kind": body.KIND}
        )
        payload |= {
            attr: section.hash_payload()
            for attr, section in self._sections().items()
            if attr != "counter_body" and (attr != "vehicle" or section.to_mapping())
        }  # a design that leaves [vehicle] at its defaults hashes as one without the section
        return hashlib.sha256(json.dumps(payload, sort_keys=True).encode()).hexdigest()[:16]

    def to_dict(self) -> dict[str, Any]:
        """Every value, flat (:data:`FIELDS` names; the outline as its mapping; the
        counter-body's other fields as ``counter_body_NAME``)."""
        body = self.counter_body
        flat_of = {name: flat for flat, (name, _) in body.flat_fields().items()}
        return {
            **self.wheel.to_dict(),
            "counter_body_kind": body.KIND,
            **{flat_of.get(k, f"counter_body_{k}"): v for k, v in body.to_mapping().items()},
            **{
                flat: self.get(flat)
                for flat, (part, _) in FIELDS.items()
                if part not in ("wheel", "counter_body")
            },
            "friction_law": self.contact.friction_law,
            "normal_contact": self.contact.normal_contact,
            "transient_creep": self.contact.transient_creep,
            "squeal_mode": self.squeal.mode,
            "mode_damping": [list(x) for x in self.damping.by_mode],
        }

    # -- the file ---------------------------------------------------------------------
    @classmethod
    def from_toml(cls, path: str | Path) -> Design:
        """Read and check a design file; missing keys take the Table 1 values."""
        path = Path(path)
        _, data = read_toml(path, "design file", DesignError)
        if "name" not in data and not LABEL_PATTERN.fullmatch(path.stem):
            raise DesignError(
                f"{path}: the file name {path.stem!r} is not a usable design name ({LABEL_RULE}); "
                'set name = "..." in the file'
            )
        design = cls.from_mapping(data, default_name=path.stem, source=str(path), base=path.parent)
        if not set(data) - {"name", "description"}:
            warnings.warn(
                f"design file {path} gives no [wheel], [profile], [material], [counter_body], [contact], "
                "[damping] or [squeal] values: it is the default Table 1 wheel",
                stacklevel=2,
            )
        return design

    @classmethod
    def from_mapping(
        cls,
        data: dict[str, Any],
        default_name: str = "design",
        source: str = "design",
        base: Path | None = None,
    ) -> Design:
        """A design from a mapping shaped like the file (``base``: the folder a
        [profile] file name is relative to)."""
        wheel_keys = {"name", "description", "profile", *SECTIONS}
        known = wheel_keys | {"roller", "counter_body", "contact", "damping", "squeal", "vehicle"}
        for key in data:
            if key not in known:
                raise DesignError(
                    f"{source}: unknown key or section '{key}'; allowed: name, description, [wheel], "
                    "[profile], [material], [counter_body], [contact], [damping], [squeal], [vehicle]"
                )
        wheel = WheelDesign.from_mapping(
            {k: v for k, v in data.items() if k in wheel_keys}, default_name, source, base
        )
        squeal = data.get("squeal", {})
        if not isinstance(squeal, dict):
            raise DesignError(f"{source}: [squeal] must be a table")
        for sub in squeal:
            if sub not in ("mode", "damping"):
                raise DesignError(f"{source}: unknown key '{sub}' in [squeal]; allowed: damping, mode")
        mode = squeal.get("mode", "")
        damping = Damping.from_mapping(data.get("damping", {}), source)
        return cls(
            wheel=wheel,
            counter_body=counter_body_from_file(data, source),
            contact=Contact.from_mapping(data.get("contact", {}), source),
            damping=damping.replace(by_mode=_measured_damping(squeal.get("damping", {}), source)),
            squeal=Squeal(mode.replace(" ", "") if isinstance(mode, str) else mode),
            vehicle=VehicleSection.from_mapping(data.get("vehicle", {}), source),
        )

    def to_toml(self) -> str:
        """The design file's text (round-trips through :meth:`from_toml`)."""
        body = self.counter_body
        lines = [self.wheel.to_toml().rstrip(), "", "[counter_body]", f"kind = {toml_value(body.KIND)}"]
        lines += body.toml_lines()
        lines += ["", "[contact]", *self.contact.toml_lines(), "", "[damping]", *self.damping.toml_lines()]
        if self.squeal.mode or self.damping.by_mode:
            lines += ["", "[squeal]", *self.squeal.toml_lines()] if self.squeal.mode else ["", "[squeal]"]
            if self.damping.by_mode:
                lines += [
                    "",
                    "[squeal.damping]",
                    *(f"{json.dumps(k)} = {toml_value(v)}" for k, v in self.damping.by_mode),
                ]
        if self.vehicle.to_mapping():
            lines += ["", "[vehicle]", *self.vehicle.toml_lines()]
        return "\n".join(lines) + "\n"


def _field(name: str) -> tuple[str, str]:
    try:
        return FIELDS[name]
    except KeyError:
        raise DesignError(f"{name!r} is not a design parameter; choose from {', '.join(FIELDS)}") from None


def _measured_damping(table: Any, source: str) -> tuple[tuple[str, float], ...]:
    if not isinstance(table, dict):
        raise DesignError(
            f"{source}: [squeal.damping] must be a table of key = ratio, the keys {DAMPING_KEYS}"
        )
    items: dict[str, tuple[str, float]] = {}
    for label, ratio in table.items():
        if isinstance(ratio, bool) or not isinstance(ratio, int | float):
            raise DesignError(f"{source}: [squeal.damping] {label!r} must be a number")
        key = mode_key(label, source)
        if key in items:
            first = items[key][0]
            raise DesignError(
                f"{source}: [squeal.damping] {first!r} and {label!r} name the same mode ({key})"
            )
        items[key] = (label, float(ratio))
    return tuple(sorted((k, r) for k, (_, r) in items.items()))


def as_design(design: Design | WheelDesign) -> Design:
    """A design from a design or a bare wheel (the Table 1 roller, contact and damping)."""
    if isinstance(design, Design):
        return design
    if isinstance(design, WheelDesign):
        return Design(wheel=design)
    raise TypeError(f"expected a Design or a WheelDesign, got {type(design).__name__}")
