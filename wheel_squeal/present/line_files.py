"""The files of a line for the noise-mapping tools: line.csv (one row per curve, the
emission per band per period), line.geojson (a LineString per curve with those
properties, where the line has coordinates), line.nc, line.png (along the line) and
report.html."""

from __future__ import annotations

import json
import math
from collections.abc import Sequence
from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np

if TYPE_CHECKING:
    from track.alignment import LineCurve

    from ..line import LineResult, LineSpec

__all__ = [
    "GEOJSON_PROPERTY_BYTES",
    "check_geojson_size",
    "geojson_bytes",
    "line_columns",
    "line_rows",
    "write_line_files",
]

#: The most one property of line.geojson takes [bytes]: its name, a number's repr (at most
#: 24 characters) or an id (at most ``track.alignment.MAX_ID_CHARACTERS``, escaped), punctuation
GEOJSON_PROPERTY_BYTES = 64
#: The most one feature takes beyond its properties and positions [bytes]
GEOJSON_FEATURE_BYTES = 200 + 6 * 100


def _band_name(prefix: str, centre: float) -> str:
    return f"{prefix}{centre:g}hz_db"


def line_columns() -> tuple[str, ...]:
    """line.csv's columns: the curve, its squeal, levels, CNOSSOS-EU's correction and the
    day's emission per octave and per third (the evening's and night's are in line.nc)."""
    from acoustics.emission import CNOSSOS_OCTAVES_HZ, CNOSSOS_THIRDS

    return (
        "id",
        "radius_m",
        "length_m",
        "cant_mm",
        "train_speed_km_h",
        "squeal_probability",
        "bogie_lpamax_dba",
        "bogie_sel_dba",
        "laeq_day_dba",
        "laeq_evening_dba",
        "laeq_night_dba",
        "cnossos_correction_db",
        "sel_from_emission_dba",
        *(_band_name("lw_m_", f) for f in CNOSSOS_OCTAVES_HZ),
        *(_band_name("lw_m_third_", b.label_hz) for b in CNOSSOS_THIRDS),
    )


def _finite(x: float | None) -> float | None:
    return None if x is None or not math.isfinite(x) else round(float(x), 2)


def line_rows(results: Sequence[LineResult]) -> list[dict[str, Any]]:
    """One row per curve (line.csv's, the day's emission; no emission: empty)."""
    from acoustics.emission import CNOSSOS_OCTAVES_HZ, CNOSSOS_THIRDS

    rows = []
    for r in results:
        c = r.curve
        row: dict[str, Any] = {
            "id": c.id,
            "radius_m": c.radius_m,
            "length_m": c.length_m,
            "cant_mm": c.cant_mm,
            "train_speed_km_h": c.train_speed_km_h,
            "squeal_probability": round(r.emission.probability, 6),
            "bogie_lpamax_dba": _finite(r.emission.lpamax_dba),
            "bogie_sel_dba": _finite(r.emission.sel_dba),
            **{f"laeq_{p}_dba": _finite(r.emission.laeq_dba[p]) for p in ("day", "evening", "night")},
            "cnossos_correction_db": r.cnossos_correction_db,
            "sel_from_emission_dba": _finite(r.emission.sel_from_emission_dba),
        }
        row |= {
            _band_name("lw_m_", f): _finite(x)
            for f, x in zip(CNOSSOS_OCTAVES_HZ, r.emission.octaves_db["day"])
        }
        row |= {
            _band_name("lw_m_third_", b.label_hz): _finite(x)
            for b, x in zip(CNOSSOS_THIRDS, r.emission.thirds_db["day"])
        }
        rows.append(row)
    return rows


def geojson_bytes(curves: Sequence[LineCurve]) -> int:
    """line.geojson's size for ``curves`` [bytes], at most: each position as it is written
    (``[x, y], ``, the numbers' shortest repr, which ``json`` writes), each property
    (:data:`GEOJSON_PROPERTY_BYTES`) and feature (:data:`GEOJSON_FEATURE_BYTES`); 0 when
    no curve has coordinates (no file)."""
    placed = [c for c in curves if c.coordinates]
    positions = sum(len(repr(x)) + len(repr(y)) + 6 for c in placed for x, y in c.coordinates)
    per_feature = GEOJSON_FEATURE_BYTES + GEOJSON_PROPERTY_BYTES * len(line_columns())
    return positions + per_feature * len(placed) + (1000 if placed else 0)


def check_geojson_size(curves: Sequence[LineCurve]) -> None:
    """Refuse (``RequestError``) a line whose line.geojson would exceed the largest file a
    command writes (``budget.MAX_FILE_BYTES``), before any work."""
    from ..runtime.budget import MAX_FILE_BYTES
    from ..runtime.request_errors import RequestError

    size = geojson_bytes(curves)
    if size > MAX_FILE_BYTES:
        raise RequestError(
            f"the line's coordinates would make line.geojson {size / 1e6:,.0f} MB, over the "
            f"{MAX_FILE_BYTES / 1e6:.0f} MB a file may take: split the line, or give fewer positions"
        )


def _geojson(results: Sequence[LineResult], rows: Sequence[dict], crs: str | None) -> dict[str, Any] | None:
    """A FeatureCollection of the curves with coordinates (None: none has any)."""
    features = [
        {
            "type": "Feature",
            "geometry": {"type": "LineString", "coordinates": [list(p) for p in r.curve.coordinates]},
            "properties": row,
        }
        for r, row in zip(results, rows)
        if r.curve.coordinates
    ]
    if not features:
        return None
    out: dict[str, Any] = {"type": "FeatureCollection", "features": features}
    if crs:
        out["crs"] = {"type": "name", "properties": {"name": crs}}
    return out


def _dataset(results: Sequence[LineResult], spec: LineSpec) -> Any:
    import xarray as xr

    from acoustics.emission import CNOSSOS_OCTAVES_HZ, CNOSSOS_THIRDS

    from ..line import PERIODS

    ids = [r.curve.id for r in results]
    periods = [p for p, _ in PERIODS]

    def per(attr: str) -> np.ndarray:
        return np.array([[getattr(r.emission, attr)[p] for p in periods] for r in results], float)

    def value(x: float | None) -> float:
        return math.nan if x is None else float(x)

    ds = xr.Dataset(
        {
            "radius_m": ("curve", [r.curve.radius_m for r in results]),
            "train_speed_km_h": ("curve", [r.curve.train_speed_km_h for r in results]),
            "squeal_probability": ("curve", [r.emission.probability for r in results]),
            "bogie_lpamax_dba": ("curve", [value(r.emission.lpamax_dba) for r in results]),
            "bogie_sel_dba": ("curve", [value(r.emission.sel_dba) for r in results]),
            "cnossos_correction_db": ("curve", [r.cnossos_correction_db for r in results]),
            "laeq_dba": (
                ("curve", "period"),
                np.array([[value(r.emission.laeq_dba[p]) for p in periods] for r in results]),
            ),
            "lw_m_db": (("curve", "period", "octave_hz"), per("octaves_db")),
            "lw_m_third_db": (("curve", "period", "third_hz"), per("thirds_db")),
        },
        coords={
            "curve": ids,
            "period": periods,
            "octave_hz": list(CNOSSOS_OCTAVES_HZ),
            "third_hz": [b.label_hz for b in CNOSSOS_THIRDS],
        },
    )
    units = {
        "radius_m": "m",
        "train_speed_km_h": "km/h",
        "squeal_probability": "1",
        "bogie_lpamax_dba": "dB(A) re 20 uPa",
        "bogie_sel_dba": "dB(A) re 20 uPa^2 s",
        "cnossos_correction_db": "dB",
        "laeq_dba": "dB(A) re 20 uPa",
        "lw_m_db": "dB re 1 pW/m",
        "lw_m_third_db": "dB re 1 pW/m",
    }
    for k, u in units.items():
        ds[k].attrs["units"] = u
    ds["lw_m_db"] = ds["lw_m_db"].where(np.isfinite(ds["lw_m_db"]))
    ds["lw_m_third_db"] = ds["lw_m_third_db"].where(np.isfinite(ds["lw_m_third_db"]))
    ds.attrs = {
        "title": "squeal emission of a railway line",
        "bogies_per_train": spec.bogies_per_train,
        "modifier_share": spec.modifier_share,
        "source_height_m": 0.05,
    }
    return ds


def _plot(path: Path, results: Sequence[LineResult]) -> None:
    from matplotlib.figure import Figure

    from .canvas import PLOT_DPI

    chainage = np.cumsum([0.0, *(r.curve.length_m for r in results)])[:-1] / 1000.0
    fig = Figure(figsize=(9, 5))
    top, bottom = fig.subplots(2, 1, sharex=True)
    widths = [r.curve.length_m / 1000 for r in results]
    top.bar(chainage, [r.emission.probability for r in results], width=widths, align="edge")
    top.set_ylabel("squeal probability")
    top.set_ylim(0, 1.05)
    laeq = [np.nan if r.emission.laeq_dba["day"] is None else r.emission.laeq_dba["day"] for r in results]
    end = chainage[-1] + results[-1].curve.length_m / 1000.0
    bottom.step([*chainage, end], [*laeq, laeq[-1]], where="post", label="L_Aeq,day at 7.5 m")
    bottom.set_ylabel("L_Aeq,day [dB(A)]")
    bottom.set_xlabel("chainage [km] (the curves end to end)")
    bottom.legend(loc="best")
    fig.suptitle("squeal along the line")
    fig.tight_layout()
    fig.savefig(path, dpi=PLOT_DPI)


def write_line_files(
    folder: Path, design: str, results: Sequence[LineResult], spec: LineSpec, crs: str | None
) -> list[dict[str, Any]]:
    """Every file of the line command in ``folder``; returns line.csv's rows."""
    from geometry.files import write_atomic

    from ..outputs import write_csv, write_json
    from .html import listing_report, table

    rows = line_rows(results)
    write_csv(folder / "line.csv", rows, line_columns())
    geo = _geojson(results, rows, crs)
    if geo is not None:
        write_atomic(folder / "line.geojson", json.dumps(geo, allow_nan=False))
    _dataset(results, spec).to_netcdf(folder / "line.nc", engine="scipy")
    _plot(folder / "line.png", results)
    squealing = [r for r in rows if r["squeal_probability"] > 0]
    summary = {
        "design": design,
        "curves": len(rows),
        "squealing_curves": len(squealing),
        "traffic": {"trains_per_hour": spec.trains_per_hour, "bogies_per_train": spec.bogies_per_train},
        "friction": {
            "friction_coefficients": list(spec.friction_coefficients),
            "friction_weights": list(spec.friction_weights),
            "modifier_share": spec.modifier_share,
        },
    }
    write_json(folder / "summary.json", summary)
    lines = [
        f"{design}: {len(squealing)} of {len(rows)} curves squeal some of the time",
        "emission: sound power per metre of track per band, at CNOSSOS-EU's wheel/rail source height "
        "(0.05 m), the traffic and the squeal's share of time in it; beside it CNOSSOS-EU's flat correction",
    ]
    columns = [(k, k) for k in line_columns()[:13]]
    listing_report(
        folder,
        f"{design}: a line",
        "wheel-squeal line",
        lines,
        [("design", design), ("curves", len(rows)), ("crs", crs or "none given")],
        [("Curves that squeal", table(squealing, columns) if squealing else "<p>No curve squeals.</p>")],
    )
    return rows
