"""A design file: the wheel (``geometry.WheelDesign``, its cross-section and material)
and what the squeal model needs beyond it, each section a small dataclass of its own:

    name = "table1"
    [wheel] or [profile], [material]   the wheel            (geometry.WheelDesign)
    [roller]                          the counter-body      (:class:`Roller`)
    [contact]                         load and friction     (:class:`Contact`)
    [damping]                         every mode's ratio    (:class:`Damping`)
    [squeal]                          what the rig showed   (:class:`Squeal`: ``mode``,
    [squeal.damping]                  and measured ratios by mode, in :class:`Damping`)

Every key is checked and missing ones take the Table 1 values. A field is also known by
one flat name (:data:`FIELDS`: ``rim_depth``, ``roller_rolling_radius``,
``normal_load``...), which studies and calibration vary.
"""

from __future__ import annotations

import dataclasses
import functools
import hashlib
import json
import warnings
from dataclasses import dataclass, field, fields
from pathlib import Path
from typing import TYPE_CHECKING, Any

from geometry import SECTIONS, DesignError, WheelDesign
from geometry.contact import ContactFrame, ContactPointError, contact_frame
from geometry.design import toml_float
from geometry.files import LABEL_PATTERN, LABEL_RULE, read_toml

from .errors import RequestError
from .sections import (
    CONTACT_NUMBERS,
    CONTACT_OPTIONAL_NUMBERS,
    ROLLER_MODAL,
    Contact,
    Damping,
    Roller,
    Squeal,
    mode_key,
)

if TYPE_CHECKING:
    from fem.modes import Mode

__all__ = [
    "FIELDS",
    "FIELD_UNITS",
    "Contact",
    "Damping",
    "Design",
    "Roller",
    "Squeal",
    "as_design",
    "mode_key",
]


#: Fields hashed and written only when they differ from their default (added after the
#: first designs: those keep their hashes and files).
_HASHED_WHEN_SET = {
    "friction_law",
    "contact_angle",
    "normal_contact",
    "transient_creep",
    "relaxation_length",
    *(f"{d}_{k}" for d in ("normal", "lateral") for k in ROLLER_MODAL),
}

#: Every numeric field of a design by its flat name: (section attribute, field name).
FIELDS: dict[str, tuple[str, str]] = {
    **{k: ("wheel", k) for keys in SECTIONS.values() for k in keys},
    "roller_rolling_radius": ("roller", "rolling_radius"),
    "roller_crown_radius": ("roller", "crown_radius"),
    **{name: ("contact", name) for name in CONTACT_NUMBERS + CONTACT_OPTIONAL_NUMBERS},
    "modal_damping_ratio": ("damping", "modal_damping_ratio"),
}
#: The unit of every numeric design field by its flat name ("" dimensionless): lengths
#: in m unless said otherwise.
FIELD_UNITS: dict[str, str] = {
    **dict.fromkeys(FIELDS, "m"),
    "youngs_modulus": "Pa",
    "poissons_ratio": "",
    "density": "kg/m^3",
    "normal_load": "N",
    "c22": "",
    "friction_coefficient": "",
    "contact_angle": "rad",
    "modal_damping_ratio": "",
}

#: The sections of the file after the wheel's, and the dataclass each is read into.
_PARTS = {"roller": Roller, "contact": Contact, "damping": Damping}


@dataclass(frozen=True)
class Design:
    """A design: the wheel and the squeal model's inputs (see the module docstring)."""

    wheel: WheelDesign = field(default_factory=WheelDesign)
    roller: Roller = field(default_factory=Roller)
    contact: Contact = field(default_factory=Contact)
    damping: Damping = field(default_factory=Damping)
    squeal: Squeal = field(default_factory=Squeal)

    def __post_init__(self) -> None:
        self.contact_frame  # noqa: B018 (an angle the tread cannot take is refused here)

    @property
    def name(self) -> str:
        return self.wheel.name

    @functools.cached_property
    def contact_frame(self) -> ContactFrame:
        """Where the wheel touches the roller and the contact's frame there
        (``geometry.contact``: the tread apex unless [contact] contact_angle moves it;
        an outline's contact point sets its own)."""
        try:
            return contact_frame(self.wheel, self.contact.contact_angle)
        except ContactPointError as exc:
            raise RequestError(f"{self.name}: {exc}") from None

    def damping_ratio_of(self, mode: Mode) -> float:
        """A mode's modal damping ratio: its own (a modal test's), else the design's for its
        (n, c) ([squeal.damping]), else the design's ``modal_damping_ratio``."""
        if mode.damping_ratio is not None:
            return mode.damping_ratio
        return self.damping.ratio(mode.nodal_diameters, mode.nodal_circles)

    @property
    def rolling_radius(self) -> float:
        """The radius the contact rolls on [m] (R1 at the tread apex): rpm <-> V0."""
        return self.contact_frame.rolling_radius_m

    @property
    def description(self) -> str:
        return self.wheel.description

    def get(self, name: str) -> Any:
        """A field by its flat name (:data:`FIELDS`)."""
        part, attr = _field(name)
        return getattr(getattr(self, part), attr)

    def replace(self, **changes: Any) -> Design:
        """A validated copy with fields changed, by their flat names (:data:`FIELDS`), or
        ``name``, ``description``, ``squeal_mode``, ``mode_damping`` and the [contact] and
        [roller] fields that are not numbers (``friction_law``, ``normal_contact``,
        ``transient_creep``, the roller's modal degrees of freedom)."""
        parts: dict[str, dict[str, Any]] = {}
        for name, value in changes.items():
            if name in ("name", "description"):
                parts.setdefault("wheel", {})[name] = value
            elif name in ("friction_law", "normal_contact", "transient_creep"):
                parts.setdefault("contact", {})[name] = value
            elif name.startswith(("normal_", "lateral_")) and name.split("_", 1)[1] in ROLLER_MODAL:
                parts.setdefault("roller", {})[name] = value
            elif name == "squeal_mode":
                parts.setdefault("squeal", {})["mode"] = value
            elif name == "mode_damping":
                parts.setdefault("damping", {})["by_mode"] = value
            else:
                part, attr = _field(name)
                parts.setdefault(part, {})[attr] = value
        new = {
            p: getattr(self, p).replace(**v) if p == "wheel" else dataclasses.replace(getattr(self, p), **v)
            for p, v in parts.items()
        }
        return dataclasses.replace(self, **new)

    def scaled(self, factor: float) -> Design:
        """The same design with every length of the wheel and the roller times ``factor``."""
        roller = dataclasses.replace(
            self.roller,
            rolling_radius=self.roller.rolling_radius * factor,
            crown_radius=self.roller.crown_radius * factor,
        )
        return dataclasses.replace(self, wheel=self.wheel.scaled(factor), roller=roller)

    def content_hash(self) -> str:
        """Stable SHA-256 (16 hex) of every value but the name and the description (the
        wheel's modes depend on ``wheel.content_hash("structure")`` alone)."""

        def values(part: str) -> dict[str, str]:
            # a field added later is hashed only when it differs from its default, so the
            # designs before it keep their hashes
            obj = getattr(self, part)
            defaults = {f.name: f.default for f in fields(obj)}
            return {
                k: repr(v)
                for k, v in dataclasses.asdict(obj).items()
                if not (k in _HASHED_WHEN_SET and v == defaults[k])
            }

        payload = {"wheel": self.wheel.content_hash("all"),
                   **{p: values(p) for p in ("roller", "contact", "damping", "squeal")}}  # fmt: skip
        return hashlib.sha256(json.dumps(payload, sort_keys=True).encode()).hexdigest()[:16]

    def to_dict(self) -> dict[str, Any]:
        """Every value, flat (:data:`FIELDS` names; the outline as its mapping)."""
        return {
            **self.wheel.to_dict(),
            **{n: self.get(n) for n, (part, _) in FIELDS.items() if part != "wheel"},
            "friction_law": self.contact.friction_law,
            "normal_contact": self.contact.normal_contact,
            "transient_creep": self.contact.transient_creep,
            **{
                f"roller_{d}_{k}": getattr(self.roller, f"{d}_{k}")
                for d in ("normal", "lateral")
                if self.roller.modal(d)
                for k in ROLLER_MODAL
            },  # fmt: skip
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
                f"design file {path} gives no [wheel], [profile], [material], [roller], [contact], "
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
        known = wheel_keys | set(_PARTS) | {"squeal"}
        for key in data:
            if key not in known:
                raise RequestError(
                    f"{source}: unknown key or section '{key}'; allowed: name, description, [wheel], "
                    "[profile], [material], [roller], [contact], [damping], [squeal]"
                )
        wheel = WheelDesign.from_mapping(
            {k: v for k, v in data.items() if k in wheel_keys}, default_name, source, base
        )
        parts: dict[str, Any] = {"wheel": wheel}
        for section, cls_ in _PARTS.items():
            parts[section] = cls_(**_section(data.get(section, {}), section, cls_, source))
        squeal = data.get("squeal", {})
        if not isinstance(squeal, dict):
            raise RequestError(f"{source}: [squeal] must be a table")
        for sub in squeal:
            if sub not in ("mode", "damping"):
                raise RequestError(f"{source}: unknown key '{sub}' in [squeal]; allowed: damping, mode")
        mode = squeal.get("mode", "")
        parts["squeal"] = Squeal(mode.replace(" ", "") if isinstance(mode, str) else mode)
        measured = _measured_damping(squeal.get("damping", {}), source)
        parts["damping"] = dataclasses.replace(parts["damping"], by_mode=measured)
        return cls(**parts)

    def to_toml(self) -> str:
        """The design file's text (round-trips through :meth:`from_toml`)."""
        lines = [self.wheel.to_toml().rstrip()]
        lines.append("\n[roller]")
        lines += [_toml_line(self.roller, f) for f in fields(self.roller) if _written(self.roller, f)]
        lines.append("\n[contact]")
        lines += [_toml_line(self.contact, f) for f in fields(self.contact) if _written(self.contact, f)]
        lines.append(f"\n[damping]\nmodal_damping_ratio = {toml_float(self.damping.modal_damping_ratio)}")
        if self.squeal.mode or self.damping.by_mode:
            lines.append("\n[squeal]")
            if self.squeal.mode:
                lines.append(f"mode = {json.dumps(self.squeal.mode)}")
            if self.damping.by_mode:
                lines.append("\n[squeal.damping]")
                lines += [f"{json.dumps(k)} = {toml_float(v)}" for k, v in self.damping.by_mode]
        return "\n".join(lines) + "\n"


def _written(obj: Any, f: dataclasses.Field) -> bool:
    return not (f.name in _HASHED_WHEN_SET and getattr(obj, f.name) == f.default)


def _toml_line(obj: Any, f: dataclasses.Field) -> str:
    value = getattr(obj, f.name)
    if isinstance(value, bool):
        return f"{f.name} = {'true' if value else 'false'}"
    if isinstance(value, str):
        return f"{f.name} = {json.dumps(value)}"
    return f"{f.name} = {toml_float(value)}"


def _field(name: str) -> tuple[str, str]:
    try:
        return FIELDS[name]
    except KeyError:
        raise RequestError(f"{name!r} is not a design parameter; choose from {', '.join(FIELDS)}") from None


def _section(table: Any, section: str, cls_: type, source: str) -> dict[str, Any]:
    if not isinstance(table, dict):
        raise RequestError(f"{source}: [{section}] must be a table")
    allowed = {f.name for f in fields(cls_) if f.name != "by_mode"}
    out = {}
    for key, value in table.items():
        if key not in allowed:
            raise RequestError(
                f"{source}: unknown key '{key}' in [{section}]; allowed: {', '.join(sorted(allowed))}"
            )
        if cls_ is Contact and key in ("friction_law", "normal_contact", "transient_creep"):
            out[key] = value  # a name or a switch, checked by Contact
            continue
        if isinstance(value, bool) or not isinstance(value, int | float):
            raise RequestError(f"{source}: [{section}] {key} must be a number, got {value!r}")
        out[key] = float(value)
    return out


def _measured_damping(table: Any, source: str) -> tuple[tuple[str, float], ...]:
    if not isinstance(table, dict):
        raise RequestError(f'{source}: [squeal.damping] must be a table of "n=N,c=C" = ratio')
    items: dict[str, tuple[str, float]] = {}
    for label, ratio in table.items():
        if isinstance(ratio, bool) or not isinstance(ratio, int | float):
            raise RequestError(f"{source}: [squeal.damping] {label!r} must be a number")
        key = mode_key(label, source)
        if key in items:
            first = items[key][0]
            raise RequestError(
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
