"""The design file's schema: a section is a frozen dataclass of fields, each with its
default, unit and meaning (:func:`spec`), checked when it is made; :class:`Fields` gives
every such section the same mapping in and out, TOML lines, content hash, copy with
changes and scaling, so that a design file's sections (the wheel's own in
``geometry.wheel_design``, the squeal model's in ``wheel_squeal.model_sections``) read, write and hash
one way, with one error type (:class:`~geometry.wheel_design.DesignError`).

    @dataclass(frozen=True)
    class Contact(Fields):
        TABLE = "contact"
        normal_load: float = spec(1000.0, "N", "the normal load W", flat="normal_load")
"""

from __future__ import annotations

import dataclasses
import math
from typing import Any, ClassVar, Self

from .errors import DesignError

__all__ = ["Fields", "spec", "toml_value"]


def spec(
    default: Any,
    unit: str,
    doc: str,
    *,
    flat: str | None = None,
    when_set: bool = False,
    length: bool = False,
    plausible: tuple[float, float] | None = None,
) -> Any:
    """A section's field: its ``default``, ``unit`` ("" a dimensionless number, "-" a word
    or a switch) and what it means (``doc``). ``flat``: the name a study or a calibration
    varies it by (None: not a design parameter). ``when_set``: written and hashed only
    when it differs from its default (a field added after the first designs: their files
    and hashes stay as they were). ``length``: a size, scaled with the wheel.
    ``plausible``: (low, high), the range a real value lies in; outside it the value is a
    typing error or a unit slip and :meth:`Fields.check_plausible` refuses it."""
    meta = dict(unit=unit, doc=doc, flat=flat, when_set=when_set, length=length, plausible=plausible)
    return dataclasses.field(default=default, metadata=meta)


def toml_value(x: Any) -> str:
    """A value as TOML writes it (floats in full, so that a file round-trips)."""
    if isinstance(x, bool):
        return "true" if x else "false"
    if isinstance(x, str):
        return '"' + x.replace("\\", "\\\\").replace('"', '\\"') + '"'
    if isinstance(x, float) and math.isinf(x):
        return "inf" if x > 0 else "-inf"
    return repr(float(x)) if isinstance(x, float) else repr(x)


class Fields:
    """The protocol of a design file's section (see the module docstring). Subclasses are
    frozen dataclasses whose fields are made by :func:`spec`; ``TABLE`` names the TOML
    table they are read from; ``__post_init__`` checks the values (:class:`DesignError`,
    one line naming the field and its range)."""

    TABLE: ClassVar[str] = ""

    @classmethod
    def specs(cls) -> tuple[dataclasses.Field, ...]:
        """The section's fields (those made by :func:`spec`)."""
        return tuple(f for f in dataclasses.fields(cls) if "unit" in f.metadata)  # type: ignore[arg-type]

    @classmethod
    def from_mapping(cls, table: Any, source: str = "design") -> Self:
        """The section from its TOML table (unknown keys and wrong types refused)."""
        if not isinstance(table, dict):
            raise DesignError(f"{source}: [{cls.TABLE}] must be a table")
        known = {f.name: f for f in cls.specs()}
        values: dict[str, Any] = {}
        for key, value in table.items():
            f = known.get(key)
            if f is None:
                allowed = ", ".join(sorted(known))
                raise DesignError(f"{source}: unknown key '{key}' in [{cls.TABLE}]; allowed: {allowed}")
            values[key] = _typed(source, cls.TABLE, f, value)
        return cls(**values)

    def to_mapping(self) -> dict[str, Any]:
        """The values a file holds (those left at a ``when_set`` default are left out)."""
        return {f.name: getattr(self, f.name) for f in self.specs() if self._written(f)}

    def toml_lines(self) -> list[str]:
        """``key = value`` lines of :meth:`to_mapping` (None: not written)."""
        return [f"{k} = {toml_value(v)}" for k, v in self.to_mapping().items() if v is not None]

    def hash_payload(self) -> dict[str, str]:
        """What the section's content hash takes: every written value's repr."""
        return {k: repr(v) for k, v in self.to_mapping().items()}

    def replace(self, **changes: Any) -> Self:
        """A checked copy with fields changed."""
        return dataclasses.replace(self, **changes)  # type: ignore[type-var]

    def scaled(self, factor: float) -> Self:
        """The same section with every size (``length``) times ``factor``."""
        sizes = {
            f.name: getattr(self, f.name) * factor
            for f in self.specs()
            if f.metadata["length"] and getattr(self, f.name) is not None
        }
        return self.replace(**sizes) if sizes else self

    @classmethod
    def flat_fields(cls) -> dict[str, tuple[str, str]]:
        """{flat name: (field name, unit)} of its design parameters."""
        return {f.metadata["flat"]: (f.name, f.metadata["unit"]) for f in cls.specs() if f.metadata["flat"]}

    def check_plausible(self) -> None:
        """Refuse a number outside its field's plausible range (:func:`spec`) in one line
        naming the field, its value and the range."""
        for f in self.specs():
            span = f.metadata.get("plausible")
            value = getattr(self, f.name)
            if span is None or value is None or isinstance(value, bool):
                continue
            low, high = span
            if not (isinstance(value, int | float) and math.isfinite(value) and low <= value <= high):
                unit = f" {f.metadata['unit']}" if f.metadata["unit"] not in ("", "-") else ""
                shown = f"{value:g}" if isinstance(value, int | float) else repr(value)
                raise DesignError(
                    f"[{self.TABLE}] {f.name} = {shown}{unit} is outside the plausible range of "
                    f"{f.metadata['doc']} ({low:g} to {high:g}{unit})"
                )

    def _written(self, f: dataclasses.Field) -> bool:
        return not (f.metadata["when_set"] and getattr(self, f.name) == f.default)


def _typed(source: str, table: str, f: dataclasses.Field, value: Any) -> Any:
    """``value`` as the field's kind takes it: a switch, a word or a number."""
    where = f"{source}: [{table}] {f.name}"
    if isinstance(f.default, bool):
        if not isinstance(value, bool):
            raise DesignError(f"{where} must be true or false, got {value!r}")
        return value
    if isinstance(f.default, str):
        if not isinstance(value, str):
            raise DesignError(f"{where} must be a word in quotes, got {value!r}")
        return value
    if isinstance(value, bool) or not isinstance(value, int | float):
        raise DesignError(f"{where} must be a number, got {value!r}")
    return float(value)
