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
import hashlib
import json
import math
import warnings
from dataclasses import dataclass, field, fields
from pathlib import Path
from typing import Any

from geometry import SECTIONS, DesignError, WheelDesign
from geometry.contact import ContactFrame, ContactPointError, contact_frame
from geometry.design import MAX_LENGTH_M, NAME_PATTERN, NAME_RULE, toml_float
from geometry.files import read_toml
from reduced.creep import FRICTION_LAWS, TABLE1_C22

from .errors import RequestError

__all__ = ["FIELDS", "Contact", "Damping", "Design", "Roller", "Squeal", "as_design", "mode_key"]


def mode_key(label: str, source: str = "design") -> str:
    """``n=N,c=C`` of a mode named by nodal diameters and circles, written the one way
    (``"n = 01, c = 0"`` is ``"n=1,c=0"``); the grammar is ``fem.modes.ModeSelection``'s."""
    from fem.modes import ModeSelection

    try:
        sel = ModeSelection.parse(str(label))
    except ValueError:
        sel = None
    if sel is None or sel.nodal_diameters is None or "c" not in str(label).replace(" ", ""):
        raise RequestError(
            f'{source}: [squeal.damping] key {label!r}: use "n=N,c=C" (nodal diameters, circles)'
        )
    return f"n={sel.nodal_diameters},c={sel.nodal_circles}"


def _positive(owner: str, name: str, value: float, *, length: bool = False) -> None:
    if (
        isinstance(value, bool)
        or not isinstance(value, int | float)
        or not math.isfinite(value)
        or value <= 0
    ):
        raise RequestError(f"[{owner}] {name} must be a positive number, got {value!r}")
    if length and value > MAX_LENGTH_M:
        raise RequestError(
            f"[{owner}] {name} = {value:g} m is longer than any wheel ({MAX_LENGTH_M:g} m): "
            f"it looks like millimetres; write {value / 1000:g}"
        )


#: The counter-body's modal degrees of freedom: per direction at the contact, its
#: frequency [Hz], damping ratio [-] and modal mass [kg] (all three, or none: rigid).
ROLLER_MODAL = ("frequency_hz", "damping_ratio", "modal_mass_kg")


@dataclass(frozen=True)
class Roller:
    """The counter-body: the upper wheel of the rig. rolling_radius: R2 [m];
    crown_radius: its transverse radius R2t [m]. Rigid and fixed unless a direction
    gives its modal degree of freedom at the contact: ``normal_frequency_hz``,
    ``normal_damping_ratio``, ``normal_modal_mass_kg`` (along the contact normal) and
    the same three ``lateral_`` ones (along the lateral tangent), in series with the
    contact."""

    rolling_radius: float = 0.085
    crown_radius: float = 0.040
    normal_frequency_hz: float | None = None
    normal_damping_ratio: float | None = None
    normal_modal_mass_kg: float | None = None
    lateral_frequency_hz: float | None = None
    lateral_damping_ratio: float | None = None
    lateral_modal_mass_kg: float | None = None

    def __post_init__(self) -> None:
        _positive("roller", "rolling_radius", self.rolling_radius, length=True)
        _positive("roller", "crown_radius", self.crown_radius)
        for direction in ("normal", "lateral"):
            given = [k for k in ROLLER_MODAL if getattr(self, f"{direction}_{k}") is not None]
            if given and len(given) < len(ROLLER_MODAL):
                missing = [f"{direction}_{k}" for k in ROLLER_MODAL if k not in given]
                raise RequestError(
                    f"[roller] a {direction} modal degree of freedom needs {', '.join(missing)} too "
                    "(frequency, damping ratio and modal mass; none of them: rigid)"
                )
            for k in given:
                value = getattr(self, f"{direction}_{k}")
                if k == "damping_ratio":
                    if isinstance(value, bool) or not 0.0 <= value < 1.0:
                        raise RequestError(f"[roller] {direction}_{k} = {value!r}: a damping ratio in [0, 1)")
                else:
                    _positive("roller", f"{direction}_{k}", value)

    def modal(self, direction: str) -> tuple[float, float, float] | None:
        """(frequency [Hz], damping ratio, modal mass [kg]) of the roller's modal degree
        of freedom along ``direction`` ("normal" or "lateral"), None where it is rigid."""
        values = tuple(getattr(self, f"{direction}_{k}") for k in ROLLER_MODAL)
        return None if values[0] is None else values


#: The paper's friction law, the default of every design
DEFAULT_FRICTION_LAW = "falling"
#: How the normal force follows the contact's normal motion: "hertz" (the nonlinear
#: Hertz spring, the default) or "constant" (the paper's fixed normal load)
NORMAL_CONTACTS = ("hertz", "constant")
#: The numeric fields of [contact] (a design parameter each, see :data:`FIELDS`)
CONTACT_NUMBERS = ("normal_load", "c22", "friction_coefficient")
#: The optional numeric fields of [contact], written and hashed only when set
CONTACT_OPTIONAL_NUMBERS = ("contact_angle", "relaxation_length")


@dataclass(frozen=True)
class Contact:
    """The contact of the wheel on the roller. normal_load: W [N]; c22: Kalker's creep
    coefficient C22 [-] (the paper's 3.14); friction_coefficient: mu_s = mu_0 [-];
    friction_law: a name of ``reduced.FRICTION_LAWS`` ("falling", the paper's, or
    "constant": no falling friction); contact_angle: where on the tread the contact
    lies [rad] (``geometry.contact``: 0 the apex); normal_contact: "hertz" or
    "constant" (:data:`NORMAL_CONTACTS`); transient_creep: the creep force lags its
    steady value by L / V0 (False: the paper's steady law), with the relaxation length
    L = relaxation_length [m] (0: the Hertz semi-axis a along rolling)."""

    normal_load: float = 1000.0
    c22: float = TABLE1_C22
    friction_coefficient: float = 0.3
    friction_law: str = DEFAULT_FRICTION_LAW
    contact_angle: float = 0.0
    normal_contact: str = "hertz"
    transient_creep: bool = False
    relaxation_length: float = 0.0

    def __post_init__(self) -> None:
        for name in CONTACT_NUMBERS:
            _positive("contact", name, getattr(self, name))
        if self.friction_law not in FRICTION_LAWS:
            raise RequestError(
                f"[contact] friction_law must be one of {', '.join(map(repr, FRICTION_LAWS))}, "
                f"got {self.friction_law!r}"
            )
        if self.normal_contact not in NORMAL_CONTACTS:
            raise RequestError(
                f"[contact] normal_contact must be one of {', '.join(map(repr, NORMAL_CONTACTS))}, "
                f"got {self.normal_contact!r}"
            )
        if isinstance(self.contact_angle, bool) or not math.isfinite(self.contact_angle):
            raise RequestError(f"[contact] contact_angle must be an angle in rad, got {self.contact_angle!r}")
        if abs(self.contact_angle) > 0.5 * math.pi:
            raise RequestError(
                f"[contact] contact_angle = {self.contact_angle:g} is over pi/2: it is in rad "
                f"(write {math.radians(self.contact_angle):.4g} for {self.contact_angle:g} deg)"
            )
        if not isinstance(self.transient_creep, bool):
            raise RequestError(
                f"[contact] transient_creep must be true or false, got {self.transient_creep!r}"
            )
        if self.relaxation_length != 0.0:
            _positive("contact", "relaxation_length", self.relaxation_length, length=True)
            if not self.transient_creep:
                raise RequestError("[contact] relaxation_length needs transient_creep = true")


@dataclass(frozen=True)
class Damping:
    """The modes' viscous damping: ``modal_damping_ratio`` [-] for every mode without a
    measured one, ``by_mode`` the measured ratios (("n=N,c=C", ratio), ...), sorted."""

    modal_damping_ratio: float = 9.4e-4
    by_mode: tuple[tuple[str, float], ...] = ()

    def __post_init__(self) -> None:
        for name, ratio in (("modal_damping_ratio", self.modal_damping_ratio), *self.by_mode):
            if isinstance(ratio, bool) or not isinstance(ratio, int | float) or not 0.0 <= ratio < 1.0:
                raise RequestError(f"damping ratio {name} = {ratio!r}: a modal damping ratio in [0, 1)")
        keys = [k for k, _ in self.by_mode]
        for k in keys:
            if mode_key(k) != k:
                raise RequestError(f'[squeal.damping] key {k!r}: use "n=N,c=C" (nodal diameters, circles)')
        if len(set(keys)) != len(keys):
            raise RequestError("[squeal.damping] names a mode twice")

    def ratio(self, nodal_diameters: int, nodal_circles: int) -> float:
        """The (n, c) mode's damping ratio: its measured one, else the common one."""
        return dict(self.by_mode).get(f"n={nodal_diameters},c={nodal_circles}", self.modal_damping_ratio)


@dataclass(frozen=True)
class Squeal:
    """What the rig showed: ``mode``, the mode seen to squeal (``n=3,c=0``, an index or
    ``f=HZ``; "" for none). A named mode is an override (:mod:`wheel_squeal.verdict`)."""

    mode: str = ""

    def __post_init__(self) -> None:
        if not isinstance(self.mode, str):
            raise RequestError(f'[squeal] mode must be a string like "n=3,c=0", got {self.mode!r}')
        if self.mode:
            from fem.modes import ModeSelection

            try:
                ModeSelection.parse(self.mode)
            except ValueError:
                raise RequestError(f"[squeal] mode {self.mode!r}: use n=N[,c=C], an index or f=HZ") from None


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

    @property
    def contact_frame(self) -> ContactFrame:
        """Where the wheel touches the roller and the contact's frame there
        (``geometry.contact``: the tread apex unless [contact] contact_angle moves it;
        an outline's contact point sets its own)."""
        try:
            return contact_frame(self.wheel, self.contact.contact_angle)
        except ContactPointError as exc:
            raise RequestError(f"{self.name}: {exc}") from None

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
        if "name" not in data and not NAME_PATTERN.fullmatch(path.stem):
            raise DesignError(
                f"{path}: the file name {path.stem!r} is not a usable design name ({NAME_RULE}); "
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
