"""The curve map's remedy written down: each treatment's design file (the design with it,
ready to run), remedy.toml (the recommended treatment's changes, to paste into the design)
and summary.json's ``remedy``."""

from __future__ import annotations

import re
from pathlib import Path
from typing import TYPE_CHECKING, Any

if TYPE_CHECKING:
    from ..curve_remedy import CurveRemedy, TreatmentResult

__all__ = ["changes_toml", "write_curve_remedy"]


def _file_name(t: TreatmentResult) -> str:
    return "remedy_" + re.sub(r"[^a-z0-9]+", "_", t.treatment.name.lower()).strip("_") + ".toml"


def changes_toml(t: TreatmentResult) -> str:
    """A treatment's changes as TOML tables to paste into the design."""
    from geometry.schema import toml_value

    lines = [f"# {t.treatment.name}: {t.treatment.what}"]
    for section, values in t.changes.items():
        lines += ["", f"[{section}]"]
        lines += [f"{_key(k)} = {toml_value(v)}" for k, v in values.items()]
    return "\n".join(lines) + "\n"


def _key(key: str) -> str:
    return key if re.fullmatch(r"[A-Za-z0-9_]+", key) else f'"{key}"'


def write_curve_remedy(folder: Path, remedy: CurveRemedy) -> dict[str, Any]:
    """Each treatment's design file and remedy.toml in ``folder``; returns summary.json's
    ``remedy``."""
    from geometry.files import write_atomic

    best = remedy.recommended
    treatments = []
    for t in remedy.treatments:
        name = None
        if t.changes:
            name = _file_name(t)
            write_atomic(folder / name, t.design.replace(name=f"{t.design.name}_{name[7:-5]}").to_toml())
        treatments.append({**t.to_dict(name), "paste": changes_toml(t) if t.changes else ""})
    if best is not None and best.changes:
        write_atomic(folder / "remedy.toml", changes_toml(best))
    return {
        "recommended": best.treatment.name if best is not None else None,
        "words": remedy.words(),
        "treatments": treatments,
    }
