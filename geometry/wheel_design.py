"""Wheels: the cross-section and the material, SI parameters with Table 1 defaults,
validation, their TOML sections and hashing.

A wheel is a flat, frozen dataclass. In a design file its fields are the sections
``[wheel]`` (or ``[profile]``) and ``[material]``; every key is checked, so a typo cannot
pass silently. The other sections of a design file (the roller, the contact, the
damping, the observed squeal) belong to the squeal model and are read by the
application (``wheel_squeal.design``): this package knows the wheel, not the squeal.

The wheel's cross-section is given one of two ways: by the parameters of ``[wheel]``
(a web between a hub or the bore and a rim with a crowned tread; the web may taper,
be conical and have fillets), or as an outline of points, straight segments and arcs
in ``[profile]`` (:mod:`geometry.outline`), for any axisymmetric wheel.
"""

from __future__ import annotations

import dataclasses
import hashlib
import json
import math
from dataclasses import dataclass, fields
from pathlib import Path
from typing import Any

from .errors import DesignError
from .files import check_label
from .outline import Outline, OutlineError, outline_from_mapping
from .parametric import parametric_outline

#: TOML section of every field (``name`` and ``description`` live at the top level).
SECTIONS: dict[str, tuple[str, ...]] = {
    "wheel": (
        "rolling_radius",
        "crown_radius",
        "rim_width",
        "rim_depth",
        "web_thickness",
        "bore_radius",
        "web_offset",
        "web_thickness_rim",
        "web_offset_rim",
        "hub_radius",
        "hub_width",
        "fillet_rim",
        "fillet_hub",
    ),
    "material": ("youngs_modulus", "poissons_ratio", "density"),
}

#: Fields that determine the mesh and the eigenmodes: every field but the name and the
#: description.
STRUCTURAL_FIELDS: tuple[str, ...] = SECTIONS["wheel"] + SECTIONS["material"] + ("profile",)

#: [wheel] keys of the extended parametric shape, and the value that means "absent"
#: (the flat web of constant thickness): absent keys are neither written nor hashed, so
#: a design that does not use them keeps its file and its cache entries.
OPTIONAL_FIELDS: dict[str, float | None] = {
    "web_thickness_rim": None,
    "web_offset_rim": None,
    "hub_radius": 0.0,
    "hub_width": 0.0,
    "fillet_rim": 0.0,
    "fillet_hub": 0.0,
}
#: Fields an outline design derives from its [profile] (the contact geometry, the bore,
#: the thinnest wall and the axial extent), and the parametric-only fields it has not.
_DERIVED = ("rolling_radius", "crown_radius", "bore_radius", "web_thickness", "rim_width")
_PARAMETRIC_ONLY = tuple(k for k in SECTIONS["wheel"] if k not in _DERIVED)
#: An outline's rim width is measured at this fraction of the rolling radius.
RIM_WIDTH_AT = 0.95


@dataclass(frozen=True)
class WheelDesign:
    """A test-rig lower wheel (the squealing one): its cross-section and material. All
    values in SI units; the defaults are the Table 1 wheel of ``designs/table1.toml``.

    ``name`` is a label (a safe file-name stem: letters, digits, ``_ . + -``, at most 64
    characters, not starting with a dot), used to name result folders; it never
    addresses a path.

    The parametric half-profile (r, z) is a web (plate) from the bore (or a hub) to the
    rim, and a rim whose outer surface (the tread) is a crown arc of radius
    ``crown_radius`` with its apex at ``r = rolling_radius, z = 0``. The rim spans
    ``|z| <= rim_width / 2`` and ``rolling_radius - rim_depth <= r <= tread(z)``; the web
    spans ``bore_radius <= r <= rolling_radius - rim_depth`` (from ``hub_radius`` with a
    hub) with its thickness and mid-surface position going linearly from
    ``web_thickness``, ``web_offset`` at the hub end to ``web_thickness_rim``,
    ``web_offset_rim`` at the rim (the same values when not given: a flat web). A hub is
    ``bore_radius <= r <= hub_radius``, ``|z - web_offset| <= hub_width / 2``;
    ``fillet_rim`` and ``fillet_hub`` round the web's corners at the rim and the hub.

    An outline design gives ``profile`` (:class:`geometry.outline.Outline`) instead; then
    ``rolling_radius`` (the contact point's radius), ``crown_radius`` (the tread's
    transverse radius there, ``inf`` on a straight tread), ``bore_radius``,
    ``web_thickness`` (the thinnest wall, :meth:`Outline.wall_thickness`) and
    ``rim_width`` (twice the largest ``|z|`` of the material at ``RIM_WIDTH_AT`` times
    the rolling radius: the rim just below the tread) are derived from it, and the
    other [wheel] fields do not apply.
    """

    name: str = "table1"
    description: str = ""
    # wheel geometry [m]
    rolling_radius: float = 0.213  #: R1, radius at the tread apex (contact point) [m]
    crown_radius: float = 0.300  #: R1t, transverse radius of the tread [m]
    rim_width: float = 0.026  #: axial width of the rim [m]
    #: radial depth of the rim from the tread apex [m]; not in the paper: calibrated to
    #: Table 1's modal data (1143 Hz, 3.1 kg) from the 0.030 m starting value (README)
    rim_depth: float = 0.0335
    web_thickness: float = 0.015  #: axial thickness of the web [m]
    bore_radius: float = 0.0325  #: R1', inner radius, clamped [m]
    web_offset: float = 0.0  #: axial offset of the web mid-plane from the rim centre [m]
    web_thickness_rim: float | None = None  #: web thickness at the rim [m] (taper)
    web_offset_rim: float | None = None  #: web mid-plane offset at the rim [m] (a conical web)
    hub_radius: float = 0.0  #: outer radius of the hub [m]; 0 for no hub
    hub_width: float = 0.0  #: axial width of the hub, centred on the web [m]
    fillet_rim: float = 0.0  #: fillet radius where the web meets the rim [m]
    fillet_hub: float = 0.0  #: fillet radius where the web meets the hub [m]
    #: the cross-section as an outline ([profile]); None for the parametric shape
    profile: Outline | None = None
    # material
    youngs_modulus: float = 175e9  #: E [Pa]
    poissons_ratio: float = 0.28  #: nu [-]
    density: float = 7800.0  #: rho [kg/m^3]

    def __post_init__(self) -> None:
        if self.profile is not None:
            if not isinstance(self.profile, Outline):
                raise DesignError(f"profile must be an Outline, got {type(self.profile).__name__}")
            o = self.profile
            # a hoop shallower than 5 % of its radius: measured half way to the bore
            at = max(RIM_WIDTH_AT * o.contact[0], 0.5 * (o.bore_radius + o.contact[0]))
            try:
                zlo, zhi = o.axial_extent(at)
                thinnest = o.wall_thickness()
            except OutlineError as exc:
                raise DesignError(f"profile: {exc}") from None
            derived = {
                "rolling_radius": float(o.contact[0]),
                "crown_radius": o.contact_crown_radius(),
                "bore_radius": o.bore_radius,
                "web_thickness": thinnest,
                "rim_width": 2 * max(abs(zlo), abs(zhi)),
            }
            for key, value in derived.items():
                object.__setattr__(self, key, value)
            for key in _PARAMETRIC_ONLY:  # meaningless for an outline: their defaults
                object.__setattr__(self, key, _FIELD_DEFAULTS[key])
        validate(self)

    # -- derived geometry -------------------------------------------------------------
    @property
    def is_outline(self) -> bool:
        """True when the cross-section is given as an outline ([profile])."""
        return self.profile is not None

    @property
    def rim_inner_radius(self) -> float:
        """Radius where the web meets the rim [m] (an outline design: 0.85 x the rolling
        radius, Table 1's proportion, used only by the cost estimates)."""
        if self.profile is not None:
            return 0.85 * self.rolling_radius
        return self.rolling_radius - self.rim_depth

    @property
    def wall_thickness(self) -> float:
        """The thinnest wall [m]: the web's smaller thickness (at the hub or at the rim),
        or an outline's thinnest wall. Meshes are sized by elements across it."""
        if self.web_thickness_rim is None:
            return self.web_thickness
        return min(self.web_thickness, self.web_thickness_rim)

    @property
    def tread_edge_radius(self) -> float:
        """Radius of the tread at the rim faces ``z = +-rim_width/2`` [m]."""
        return tread_radius(self, self.rim_width / 2)

    @property
    def shear_modulus(self) -> float:
        """G = E / 2(1 + nu) [Pa]."""
        return self.youngs_modulus / (2.0 * (1.0 + self.poissons_ratio))

    # -- copies and hashes ------------------------------------------------------------
    def replace(self, **changes: Any) -> WheelDesign:
        """A validated copy with some fields changed."""
        if self.profile is not None and "profile" not in changes:
            fixed = sorted(set(changes) & set(SECTIONS["wheel"]))
            if fixed:
                verb = "is" if len(fixed) == 1 else "are"
                raise DesignError(
                    f"design {self.name!r} is an outline: {', '.join(fixed)} {verb} set by its "
                    "[profile]; change the outline instead"
                )
        return dataclasses.replace(self, **changes)

    def scaled(self, factor: float) -> WheelDesign:
        """The same wheel with every length multiplied by ``factor``."""
        if self.profile is not None:
            return self.replace(profile=self.profile.scaled(factor))
        wheel = {k: getattr(self, k) for k in SECTIONS["wheel"]}
        return self.replace(**{k: v if v is None else v * factor for k, v in wheel.items()})

    def to_dict(self) -> dict[str, Any]:
        """The design's values (an outline's as its [profile] mapping; absent optional
        parametric keys and an outline's parametric-only keys left out)."""
        out = {}
        for f in fields(self):
            v = getattr(self, f.name)
            if f.name == "profile":
                if v is not None:
                    out["profile"] = v.to_mapping()
            elif not _absent(self, f.name):
                out[f.name] = v
        return out

    def content_hash(self, which: str = "all") -> str:
        """Stable SHA-256 (hex, 16 chars) of the design's values.

        ``which="all"`` and ``which="structure"`` (what mesh and modes depend on) are the
        same fields now that a wheel holds only its geometry and material; both names
        are kept so that cache keys stay. ``name`` and ``description`` are never hashed,
        so renaming a file does not invalidate a cache.
        """
        if which == "structure":
            keys = STRUCTURAL_FIELDS
        elif which == "all":
            keys = tuple(f.name for f in fields(self) if f.name not in ("name", "description"))
        else:
            raise ValueError(f"which must be 'all' or 'structure', not {which!r}")
        keys = tuple(k for k in keys if not _absent(self, k))
        # repr(float) is the shortest round-trip form: stable across platforms.
        payload = json.dumps({k: _hashable(getattr(self, k)) for k in keys}, sort_keys=True)
        return hashlib.sha256(payload.encode()).hexdigest()[:16]

    # -- TOML -------------------------------------------------------------------------
    @classmethod
    def from_mapping(
        cls,
        data: dict[str, Any],
        default_name: str = "design",
        source: str = "design",
        base: Path | None = None,
    ) -> WheelDesign:
        """Build from a nested mapping shaped like the TOML file's wheel sections
        (``name``, ``description``, ``[wheel]`` or ``[profile]``, ``[material]``; ``base``:
        the folder a [profile] file name is relative to)."""
        values: dict[str, Any] = {}
        if "profile" in data and "wheel" in data:
            raise DesignError(
                f"{source}: give the cross-section either by [wheel] parameters or by a [profile] "
                "outline, not both"
            )
        for key, value in data.items():
            if key == "profile":
                try:
                    values["profile"] = outline_from_mapping(value, source, base)
                except OutlineError as exc:
                    raise DesignError(str(exc)) from None
            elif key in ("name", "description"):
                if not isinstance(value, str):
                    raise DesignError(f"{source}: '{key}' must be a string")
                values[key] = value
            elif key in SECTIONS:
                if not isinstance(value, dict):
                    raise DesignError(f"{source}: [{key}] must be a table")
                allowed = {f: f for f in SECTIONS[key]}
                for sub, v in value.items():
                    if sub not in allowed:
                        raise DesignError(
                            f"{source}: unknown key '{sub}' in [{key}]; allowed: "
                            + ", ".join(sorted(allowed))
                        )
                    values[allowed[sub]] = v
            else:
                raise DesignError(
                    f"{source}: unknown key or section '{key}'; allowed: name, description, "
                    + ", ".join(f"[{s}]" for s in SECTIONS)
                    + ", [profile]"
                )
        values.setdefault("name", default_name)
        for key, v in values.items():
            if key in ("name", "description", "profile"):
                continue
            # bool is an int subclass: reject it explicitly.
            if isinstance(v, bool) or not isinstance(v, (int, float)):
                raise DesignError(f"{source}: '{key}' must be a number, got {type(v).__name__} {v!r}")
            values[key] = float(v)
        return cls(**values)

    def to_toml(self) -> str:
        """The wheel's part of a design file as TOML text (round-trips exactly through
        :meth:`from_mapping` of the parsed text)."""
        lines = [f"name = {json.dumps(self.name)}"]
        if self.description:
            lines.append(f"description = {json.dumps(self.description)}")
        if self.profile is not None:
            p = self.profile.to_mapping()
            lines.append("\n[profile]")
            lines.append(
                "points = [\n"
                + "".join(f"  [{toml_float(r)}, {toml_float(z)}],\n" for r, z in p["points"])
                + "]"
            )
            lines.append("bulges = [" + ", ".join(toml_float(b) for b in p["bulges"]) + "]")
            lines.append("clamp = [" + ", ".join(str(i) for i in p["clamp"]) + "]")
            lines.append(f"contact = [{toml_float(p['contact'][0])}, {toml_float(p['contact'][1])}]")
        for section, keys in SECTIONS.items():
            if section == "wheel" and self.profile is not None:
                continue
            lines.append(f"\n[{section}]")
            for k in keys:
                if not _absent(self, k):
                    lines.append(f"{k} = {toml_float(getattr(self, k))}")
        return "\n".join(lines) + "\n"


def _absent(d: WheelDesign, key: str) -> bool:
    """An optional parametric key at its "absent" value, or a [wheel] key an outline
    design does not have: neither written, nor hashed, nor reported."""
    if d.profile is not None:
        return key in _PARAMETRIC_ONLY
    if key == "profile":
        return True
    return key in OPTIONAL_FIELDS and getattr(d, key) == OPTIONAL_FIELDS[key]


_FIELD_DEFAULTS: dict[str, Any] = {f.name: f.default for f in fields(WheelDesign)}


def _hashable(v: Any) -> Any:
    if isinstance(v, Outline):
        return json.loads(json.dumps(v.to_mapping()))
    if isinstance(v, str):
        return v
    if isinstance(v, tuple):
        return [[key, repr(float(x))] for key, x in v]
    return repr(float(v))


def toml_float(x: float) -> str:
    """A float as TOML writes it (round-trips exactly; a whole number keeps its .0)."""
    text = repr(float(x))
    return text if ("." in text or "e" in text or "inf" in text or "nan" in text) else text + ".0"


def tread_radius(design: WheelDesign, z: float) -> float:
    """Radius of the crowned tread at axial position ``z`` [m]."""
    R = design.crown_radius
    return design.rolling_radius - R + math.sqrt(R * R - z * z)


#: Plausible ranges of a wheel's material and size, in SI units: outside them a value is
#: almost certainly typed in another unit (GPa, mm, g/cm^3), and would mesh or solve for
#: minutes or fail deep inside the eigen-solver. (low, high, unit guesses as
#: (factor to SI, unit name) tried in turn).
_UNIT_RANGES: dict[str, tuple[float, float, tuple[tuple[float, str], ...]]] = {
    "youngs_modulus": (1e9, 1e13, ((1e9, "GPa"), (1e6, "MPa"), (1e3, "kPa"))),
    "density": (100.0, 1e5, ((1e3, "g/cm^3"), (1e-3, "g/m^3"))),
}
#: Largest size of a wheel or roller [m] before it reads as millimetres (the crown radii
#: are curvatures, not sizes: a nearly flat tread has a very large one).
MAX_LENGTH_M = 10.0
_SIZES = tuple(k for k in SECTIONS["wheel"] if k != "crown_radius")
#: The smallest size of any part of a wheel [m] (a fillet or a hub may be 0: none).
MIN_LENGTH_M = 1e-4
#: Lengths that are positions, not sizes: any small value is a small offset.
_OFFSETS = ("web_offset", "web_offset_rim")


def _unit_hint(
    name: str, value: float, low: float, high: float, guesses: tuple[tuple[float, str], ...], unit: str
) -> str:
    for factor, guess in guesses:
        if low <= value * factor <= high:
            return (
                f"{name} = {value:g} {unit} is outside the range of wheel materials "
                f"({low:g} to {high:g} {unit}): it looks like {guess}; write {value * factor:g}"
            )
    return f"{name} = {value:g} {unit} is outside the range of wheel materials ({low:g} to {high:g} {unit})"


def validate(d: WheelDesign) -> None:
    """Raise :class:`DesignError` naming the first invalid parameter and its allowed range."""
    for f in fields(d):
        v = getattr(d, f.name)
        if f.name in ("name", "description"):
            if not isinstance(v, str):
                raise DesignError(f"{f.name} must be a string")
            if f.name == "name":
                check_label(v, "design name", DesignError)
            elif not v.replace("\n", " ").replace("\t", " ").isprintable():
                raise DesignError(
                    "description must be plain text: no control characters (they would reach the terminal)"
                )
            continue
        if f.name == "profile" or (f.name in OPTIONAL_FIELDS and v is None):
            continue
        if f.name == "crown_radius" and d.profile is not None and v == math.inf:
            continue  # a straight (conical or flat) tread
        if isinstance(v, bool) or not isinstance(v, (int, float)):
            raise DesignError(f"{f.name} must be a number, got {type(v).__name__} {v!r}")
        if not math.isfinite(v):
            raise DesignError(f"{f.name} must be finite, got {v}")
        if f.name in ("web_offset", "web_offset_rim"):
            continue
        if f.name in ("hub_radius", "hub_width", "fillet_rim", "fillet_hub"):
            if v < 0:
                raise DesignError(f"{f.name} must be >= 0 (0: none), got {v}")
            continue
        if f.name == "poissons_ratio":
            if not -1.0 < v < 0.5:
                raise DesignError(f"poissons_ratio must be in (-1, 0.5), got {v}")
            continue
        if v <= 0:
            raise DesignError(f"{f.name} must be positive, got {v}")
    for key, (low, high, guesses) in _UNIT_RANGES.items():
        v = getattr(d, key)
        if not low <= v <= high:
            unit = "Pa" if key == "youngs_modulus" else "kg/m^3"
            raise DesignError(_unit_hint(key, v, low, high, guesses, unit))
    for key in _SIZES:
        v = getattr(d, key)
        if v is not None and abs(v) > MAX_LENGTH_M:
            raise DesignError(
                f"{key} = {v:g} m is longer than any wheel ({MAX_LENGTH_M:g} m): "
                f"it looks like millimetres; write {v / 1000:g}"
            )
        if v is not None and 0.0 < abs(v) < MIN_LENGTH_M and key not in _OFFSETS:
            raise DesignError(
                f"{key} = {v:g} m is shorter than any part of a wheel ({MIN_LENGTH_M:g} m): "
                "it would need a mesh finer than any machine holds"
            )
    if d.profile is None:
        _validate_parametric(d)


def _validate_parametric(d: WheelDesign) -> None:
    """The relations between the [wheel] parameters, then the outline they make."""
    if d.rim_depth >= d.rolling_radius:
        raise DesignError(f"rim_depth must be below rolling_radius ({d.rolling_radius} m), got {d.rim_depth}")
    if d.crown_radius < d.rim_width / 2:
        raise DesignError(
            f"crown_radius must be at least rim_width/2 = {d.rim_width / 2} m, got {d.crown_radius}"
        )
    if d.bore_radius >= d.rim_inner_radius:
        raise DesignError(
            "bore_radius must be below the rim inner radius "
            f"(rolling_radius - rim_depth = {d.rim_inner_radius:.6g} m), got {d.bore_radius}"
        )
    t_rim = d.web_thickness if d.web_thickness_rim is None else d.web_thickness_rim
    o_rim = d.web_offset if d.web_offset_rim is None else d.web_offset_rim
    if d.web_thickness > d.rim_width and d.hub_radius == 0:
        raise DesignError(f"web_thickness must not exceed rim_width ({d.rim_width} m), got {d.web_thickness}")
    if t_rim > d.rim_width:
        raise DesignError(f"web_thickness_rim must not exceed rim_width ({d.rim_width} m), got {t_rim}")
    limit = (d.rim_width - t_rim) / 2
    name = "web_offset" if d.web_offset_rim is None else "web_offset_rim"
    if abs(o_rim) > limit * (1 + 1e-12):
        raise DesignError(
            f"{name} must be within +-(rim_width - web thickness at the rim)/2 = +-{limit:.6g} m "
            f"so that the web stays inside the rim, got {o_rim}"
        )
    if d.hub_width > 0 and d.hub_radius == 0:
        raise DesignError("hub_width needs hub_radius (the hub's outer radius)")
    if d.hub_radius > 0:
        if not d.bore_radius < d.hub_radius < d.rim_inner_radius:
            raise DesignError(
                f"hub_radius must lie between bore_radius ({d.bore_radius} m) and the rim inner "
                f"radius ({d.rim_inner_radius:.6g} m), got {d.hub_radius}"
            )
        if d.hub_width < d.web_thickness:
            raise DesignError(
                f"hub_width must be at least the web thickness at the hub ({d.web_thickness} m), "
                f"got {d.hub_width}"
            )
    elif d.fillet_hub > 0:
        raise DesignError("fillet_hub needs a hub (hub_radius, hub_width)")
    # The rim must keep material between its inner radius and the tread at the faces.
    if tread_radius(d, d.rim_width / 2) <= d.rim_inner_radius:
        raise DesignError(
            "rim_depth too small for the crown: the tread at the rim faces "
            f"(r = {tread_radius(d, d.rim_width / 2):.6g} m) lies inside the rim inner radius "
            f"({d.rim_inner_radius:.6g} m); increase rim_depth or crown_radius"
        )
    try:  # the outline the parameters make: the fillets fit, nothing overlaps
        parametric_outline(d)
    except OutlineError as exc:
        raise DesignError(f"design {d.name!r}: {exc}") from None


__all__ = [
    "DesignError",
    "MAX_LENGTH_M",
    "WheelDesign",
    "SECTIONS",
    "OPTIONAL_FIELDS",
    "STRUCTURAL_FIELDS",
    "toml_float",
    "tread_radius",
    "validate",
]
