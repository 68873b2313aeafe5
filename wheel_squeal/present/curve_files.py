"""What the ``curve`` command writes besides curve.csv and summary.json: curve.nc (the
cases on a radius x train speed x wheel grid, with units), the maps of squeal occurrence
and of each wheel's L_pAmax over radius and speed (PNG), the loudest pass-by as a WAV
file, and report.html."""

from __future__ import annotations

import dataclasses
import math
from collections.abc import Sequence
from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np

from ..fields import unit_of
from ..rail_fields import CURVE_COLUMNS

if TYPE_CHECKING:
    from track.bogie_curving import Vehicle

    from ..curve import CurveCase
    from ..curve_case import PassbySound
    from ..curve_remedy import CurveRemedy
    from ..design import Design
    from ..types import AmplitudeMethod

__all__ = [
    "CURVE_MAPS",
    "SPECTRUM_BANDS_HZ",
    "curve_dataset",
    "curve_table",
    "spectrum_bands",
    "curve_report",
    "write_curve_maps",
    "write_curve_netcdf",
    "write_curve_files",
]

#: The lowest and highest one-third-octave centres of curve.nc's spectra [Hz]
SPECTRUM_BANDS_HZ = (50.0, 10000.0)
#: The maps the curve command draws
CURVE_MAPS = ("occurrence.png", "lpamax.png")
#: The mechanisms in the occurrence map's colours (none first)
_MECHANISMS = ("", "falling friction", "mode coupling", "both")
_TEXT_VARIABLES = ("deciding_contact", "verdict_mode", "mechanism", "amplitude_method", "amplitude_note")
#: curve.nc's flags (0 or 1) on the (radius, speed, wheel) grid
_FLAG_VARIABLES = ("squeals", "flange_contact")
#: curve.nc's numbers on that grid: curve.csv's columns but the grid's own, the flags and the text
_GRID_VARIABLES = tuple(
    c
    for c in CURVE_COLUMNS
    if c not in ("radius_m", "train_speed_km_h", "axle", "rail", *_FLAG_VARIABLES, *_TEXT_VARIABLES)
)
#: The report's table of the remedy's treatments: (key, heading)
_TREATMENT_COLUMNS = (
    ("name", "treatment"),
    ("what", "what"),
    ("cases_squealing_before", "squealing before"),
    ("cases_still_squealing", "still squealing"),
    ("still_squealing", "how"),
    ("loudest_lpamax_after_dba", "loudest L_pAmax after [dB(A)]"),
    ("design_file", "design file"),
)
#: The report's table of squealing wheels: (key, heading)
_REPORT_COLUMNS = (
    ("radius_m", "R [m]"),
    ("train_speed_km_h", "V [km/h]"),
    ("axle", "axle"),
    ("rail", "rail"),
    ("angle_of_attack_rad", "psi [rad]"),
    ("deciding_contact", "contact"),
    ("contact_angle_deg", "angle [deg]"),
    ("lateral_creepage", "creepage"),
    ("verdict_mode", "mode"),
    ("mechanism", "mechanism"),
    ("tone_hz", "tone [Hz]"),
    ("growth_rate_1_s", "growth [1/s]"),
    ("amplitude_m_s", "amplitude [m/s]"),
    ("passby_lpamax_dba", "wheel L_pAmax [dB(A)]"),
    ("bogie_lpamax_dba", "bogie L_pAmax [dB(A)]"),
)


def _axes(rows: Sequence[dict]) -> tuple[list[float], list[float], list[str]]:
    """The radii, train speeds and wheels of the rows, in their order."""
    from track.curving import WHEELS

    radii = list(dict.fromkeys(r["radius_m"] for r in rows))
    speeds = list(dict.fromkeys(r["train_speed_km_h"] for r in rows))
    return radii, speeds, [f"{a} {r}" for a, r in WHEELS]


def _grid(rows: Sequence[dict], key: str, fill: Any = math.nan) -> np.ndarray:
    """``key`` of every row on the (radius, speed, wheel) grid."""
    radii, speeds, wheels = _axes(rows)
    out = np.full(
        (len(radii), len(speeds), len(wheels)), fill, dtype=object if isinstance(fill, str) else float
    )
    for r in rows:
        v = r.get(key)
        out[_cell(r, radii, speeds, wheels)] = fill if v is None else v
    return out


def _cell(row: dict, radii: list, speeds: list, wheels: list) -> tuple[int, int, int]:
    """A row's place on the (radius, speed, wheel) grid."""
    return (
        radii.index(row["radius_m"]),
        speeds.index(row["train_speed_km_h"]),
        wheels.index(f"{row['axle']} {row['rail']}"),
    )


def spectrum_bands() -> list:
    """The one-third-octave bands of curve.nc's spectra: 50 Hz to 10 kHz, the bands
    CNOSSOS-EU's railway source takes."""
    from acoustics.levels import third_octave_bands

    return third_octave_bands(SPECTRUM_BANDS_HZ[0], SPECTRUM_BANDS_HZ[1])


def curve_dataset(
    rows: Sequence[dict], attrs: dict[str, Any] | None = None, spectra: Sequence[np.ndarray] | None = None
) -> Any:
    """The cases (``CurveCase.to_record()`` rows) as an ``xarray.Dataset`` on the
    dimensions radius_m, train_speed_km_h and wheel, every variable with its units
    (missing numbers NaN) and ``attrs`` (the file's global attributes); with ``spectra``
    (each row's :meth:`CurveCase.band_lpamax_dba` at :data:`SPECTRUM_BANDS_HZ`), the
    variable ``band_lpamax_dba`` on a fourth dimension ``band_hz`` (no tone: NaN).

    Examples
    --------
    >>> import wheel_squeal as ws
    >>> d = ws.load_design("railway_920_track")
    >>> cases = ws.curve(d, [150.0], [40.0], context=ws.RunContext.of("fast"))
    >>> curve_dataset([c.to_record() for c in cases])["squeals"].shape
    (1, 1, 4)
    """
    import xarray as xr

    radii, speeds, wheels = _axes(rows)
    dims = ("radius_m", "train_speed_km_h", "wheel")
    data: dict[str, Any] = {flag: (dims, _grid(rows, flag, 0.0).astype(np.int8)) for flag in _FLAG_VARIABLES}
    data |= {k: (dims, _grid(rows, k)) for k in _GRID_VARIABLES}
    data |= {k: (dims, _grid(rows, k, "").astype(str)) for k in _TEXT_VARIABLES}
    ds = xr.Dataset(data, coords={"radius_m": radii, "train_speed_km_h": speeds, "wheel": wheels})
    for k in (*_GRID_VARIABLES, "radius_m", "train_speed_km_h"):
        ds[k].attrs["units"] = unit_of(k) or "1"
    if spectra is not None:
        bands = [b.label_hz for b in spectrum_bands()]
        grid = np.full((len(radii), len(speeds), len(wheels), len(bands)), np.nan)
        for r, spectrum in zip(rows, spectra):
            grid[_cell(r, radii, speeds, wheels)] = np.where(np.isfinite(spectrum), spectrum, np.nan)
        ds = ds.assign_coords(band_hz=bands)
        ds["band_lpamax_dba"] = ((*dims, "band_hz"), grid)
        ds["band_lpamax_dba"].attrs = {
            "units": "dB(A) re 20 uPa",
            "long_name": "the wheel's own L_pAmax per one-third-octave band at the pass-by, free field",
        }
        ds["band_hz"].attrs = {"units": "Hz", "long_name": "one-third-octave band (nominal centre)"}
    ds["squeals"].attrs = {"units": "1", "long_name": "1 where the wheel squeals"}
    ds["flange_contact"].attrs = {
        "units": "1",
        "long_name": "1 where one of the wheel's contacts is on its flange",
    }
    ds.attrs = dict(attrs or {})
    return ds


def write_curve_netcdf(
    path: Path, rows: Sequence[dict], attrs: dict[str, Any], spectra: Sequence[np.ndarray] | None = None
) -> Path:
    """curve.nc: :func:`curve_dataset` as NetCDF-3 (SciPy's writer: no HDF5 library)."""
    curve_dataset(rows, attrs, spectra).to_netcdf(path, engine="scipy")
    return Path(path)


def write_curve_maps(folder: Path, rows: Sequence[dict]) -> list[str]:
    """occurrence.png (each wheel's squeal and its mechanism over radius and train speed)
    and lpamax.png (each wheel's L_pAmax at the pass-by position, free field)."""
    from matplotlib.colors import ListedColormap
    from matplotlib.figure import Figure

    from .canvas import PLOT_DPI

    radii, speeds, wheels = _axes(rows)
    mechanism = _grid(rows, "mechanism", "")
    squeals = _grid(rows, "squeals", 0.0) > 0
    code = np.vectorize(lambda m: _MECHANISMS.index(m) if m in _MECHANISMS else 0)(mechanism)
    code = np.where(squeals, code, 0).astype(float)
    level = _grid(rows, "passby_lpamax_dba")
    finite = level[np.isfinite(level)]
    for name, data, title in (
        ("occurrence.png", code, "squeal by wheel: its mechanism"),
        ("lpamax.png", level, "each wheel's L_pAmax at 7.5 m, 1.2 m above the rail head [dB(A)], free field"),
    ):
        fig = Figure(figsize=(11, 7.5))
        axes = fig.subplots(2, 2, sharex=True, sharey=True).ravel()
        fig.subplots_adjust(left=0.09, right=0.8, bottom=0.09, top=0.9, hspace=0.18, wspace=0.08)
        if name == "occurrence.png":
            cmap = ListedColormap(["#e8e8e8", "#d62728", "#1f77b4", "#9467bd"])
            kw: dict[str, Any] = {"cmap": cmap, "vmin": -0.5, "vmax": 3.5}
        else:
            kw = {
                "cmap": "viridis",
                "vmin": finite.min() if len(finite) else 0,
                "vmax": finite.max() if len(finite) else 1,
            }
        for k, ax in enumerate(axes):
            ax.set_facecolor("#e8e8e8")  # silent cells (NaN) show the background
            im = ax.imshow(data[:, :, k].T, origin="lower", aspect="auto", **kw)
            ax.set_title(wheels[k], fontsize=10)
            ax.set_xticks(range(len(radii)), [f"{r:g}" for r in radii], rotation=90 if len(radii) > 8 else 0)
            ax.set_yticks(range(len(speeds)), [f"{v:g}" for v in speeds])
            if len(radii) * len(speeds) <= 60 and name == "lpamax.png":
                for i in range(len(radii)):
                    for j in range(len(speeds)):
                        if np.isfinite(data[i, j, k]):
                            ax.text(
                                i, j, f"{data[i, j, k]:.0f}", ha="center", va="center", fontsize=7, color="w"
                            )
        for ax in axes[2:]:
            ax.set_xlabel("curve radius R [m]")
        for ax in axes[::2]:
            ax.set_ylabel("train speed [km/h]")
        cax = fig.add_axes((0.82, 0.15, 0.02, 0.7))
        bar = fig.colorbar(im, cax=cax)
        if name == "occurrence.png":
            bar.set_ticks(range(4), labels=["no squeal", *_MECHANISMS[1:]])
        else:
            bar.set_label("L_pAmax [dB(A)] (grey: silent)")
        fig.suptitle(title)
        fig.savefig(folder / name, dpi=PLOT_DPI)
    return list(CURVE_MAPS)


def curve_assumptions(method: str) -> tuple[str, ...]:
    """What a curve map rests on, said in its report: the wheel, each wheel's contact, how
    its amplitude and sound were found (``method``), the pass-by."""
    from .html import ASSUMPTIONS

    amplitude = (
        "The amplitude of a squealing wheel is the harmonic balance of its squeal mode alone, its damping "
        "set so that its growth rate is the full linear model's with the rail and the other modes; its "
        "sound is that mode's radiation at the fundamental only (no harmonics, no other mode's content)."
        if method == "harmonic balance"
        else "The amplitude of a squealing wheel is the time domain's limit cycle from rest of the modes the "
        "decision integrates with the rail; its sound is the radiation of the mode holding most of its "
        "energy at each harmonic of the contact velocity."
    )
    return (
        ASSUMPTIONS[0],
        "Each wheel touches the rail where the bogie's steady curving puts it (its running surface on "
        "UIC60 at 1:40, the primary suspension, the cant deficiency's load transfer, Kalker's creep "
        "saturated by the friction): each contact, tread or flange, is analysed with its own normal force, "
        "Hertz ellipse, contact angle and lateral creepage, the friction the longitudinal creep leaves; "
        "spin's own effect on the squeal and flanging noise are left out; the two contacts of a flanging "
        "wheel are not coupled.",
        ASSUMPTIONS[2],
        "Whether a wheel squeals is the linear stability's decision about steady sliding.",
        amplitude,
        "The pass-by: each wheel a point source at its centre moving past the ISO 3095 microphone (7.5 m, "
        "1.2 m above the rail head) with its far-field directivity; the wheels add in energy (they squeal "
        "independently); free field unless a ground is asked for.",
    )


def curve_report(
    folder: Path, design: str, rows: Sequence[dict], summary: dict[str, Any], spectra: Sequence[np.ndarray]
) -> Path:
    """report.html: the remedy first, the cases that squeal with their one-third-octave
    spectra, the treatments checked, the loudest pass-by's bands and sound, the maps, the
    inputs."""
    from .html import audio, listing_report, table
    from .passby_files import PASSBY_WAV

    labels = [b.label_hz for b in spectrum_bands()]

    def heard(spectrum: np.ndarray) -> str:
        return "; ".join(f"{f:g} Hz {x:.1f}" for f, x in zip(labels, spectrum) if np.isfinite(x)) or "none"

    squealing = [{**r, "bands": heard(sp)} for r, sp in zip(rows, spectra) if r["squeals"]]
    radii, speeds, _ = _axes(rows)
    remedy = summary.get("remedy")
    lines = [
        *([remedy["words"]] if remedy else []),
        f"{design} on its track: {len(radii)} radii x {len(speeds)} train speeds x 4 wheels; "
        f"{len(squealing)} of {len(rows)} wheel cases squeal "
        f"(amplitudes by {summary['amplitude_method']}).",
        *summary["findings"],
    ]
    columns = [*_REPORT_COLUMNS, ("bands", "1/3-octave L_pAmax [Hz dB(A)]")]
    sections = [("Squealing wheels", table(squealing, columns) if squealing else "<p>No wheel squeals.</p>")]
    if remedy and remedy["treatments"]:
        treatments = [
            {**t, "design_file": t["design_file"] or "(the design as it is)"} for t in remedy["treatments"]
        ]
        sections.append(
            (
                "What stops it: each treatment checked over the map",
                table(treatments, _TREATMENT_COLUMNS),
            )
        )
    loud = summary.get("loudest")
    if loud:
        sections.append(
            (
                f"The loudest pass-by: R = {loud['radius_m']:g} m at {loud['train_speed_km_h']:g} km/h",
                table(
                    loud["bands"],
                    [
                        ("band_hz", "1/3-octave band [Hz]"),
                        ("lpmax_db", "L_pmax [dB]"),
                        ("lpamax_dba", "L_pAmax [dB(A)]"),
                    ],
                )
                + audio(folder / PASSBY_WAV),
            )
        )
    inputs = [(k, summary[k]) for k in ("design", "vehicle", "wheel_profile", "cant_mm", "amplitude_method")]
    inputs += [
        ("microphone", "7.5 m from the track centre line, 1.2 m above the rail head (ISO 3095)"),
        ("ground", summary["ground"]),
    ]
    return listing_report(
        folder,
        f"{design} in curves",
        "wheel-squeal curve",
        lines,
        inputs,
        sections,
        curve_assumptions(summary["amplitude_method"]),
    )


def write_curve_files(
    folder: Path,
    design: Design,
    vehicle: Vehicle,
    cant_mm: float,
    cases: Sequence[CurveCase],
    method: AmplitudeMethod,
    ground_reflection: float | None,
    remedy: CurveRemedy | None = None,
    heard: PassbySound | None = None,
) -> tuple[list[dict], dict[str, Any]]:
    """Every file of the curve command in ``folder`` (``heard``: the loudest pass-by's
    sound, written as passby.wav and passby.png); returns curve.csv's rows and
    summary.json without its cases."""
    from acoustics.passby import GROUND_DEPTH_M, MICROPHONE_DISTANCE_M, MICROPHONE_HEIGHT_M

    from ..curve_findings import findings
    from ..output_files import columns_of
    from ..outputs import write_csv, write_json
    from .passby_files import band_rows, write_passby_files
    from .remedy_files import write_curve_remedy

    rows = [c.to_record() for c in cases]
    q = ground_reflection
    summary: dict[str, Any] = {
        "design": design.name,
        "vehicle": dataclasses.asdict(vehicle),
        "wheel_profile": design.contact.wheel_profile,
        "cant_mm": cant_mm,
        "amplitude_method": method,
        "microphone": {"distance_m": MICROPHONE_DISTANCE_M, "height_m": MICROPHONE_HEIGHT_M},
        "ground": "free field" if q is None else f"{GROUND_DEPTH_M} m below the rail head, reflection {q:g}",
        "findings": findings(cases, vehicle.wheelbase_m),
    }
    if remedy is not None:
        summary["remedy"] = write_curve_remedy(folder, remedy)
    if heard is not None:
        summary["loudest"] = {**write_passby_files(folder, heard), "bands": band_rows(heard.cases[0])}
    write_csv(folder / "curve.csv", rows, columns_of("curve.csv"))
    attrs = {
        "title": f"{design.name} in curves",
        "amplitude_method": method,
        "wheelbase_m": vehicle.wheelbase_m,
        "primary_yaw_stiffness_n_m_rad": vehicle.primary_yaw_stiffness_n_m_rad,
        "cant_mm": cant_mm,
    }
    centres = [b.centre_hz for b in spectrum_bands()]
    spectra = [c.band_lpamax_dba(centres) for c in cases]
    write_curve_netcdf(folder / "curve.nc", rows, attrs, spectra)
    write_curve_maps(folder, rows)
    cases_json = [{**r, "verdict": c.analysis.verdict.to_dict()} for r, c in zip(rows, cases)]
    write_json(folder / "summary.json", {**summary, "cases": cases_json})
    curve_report(folder, design.name, rows, summary, spectra)
    return rows, summary


def curve_table(rows: Sequence[dict]) -> str:
    """Each wheel at each radius and train speed: its angle of attack, the contact whose
    verdict is the wheel's (tread or flange, its angle) and its creepage, the verdict,
    amplitude and its own and the bogie's pass-by level."""

    from .text import num_cell

    lines = [
        f"{'R [m]':>7} {'V [km/h]':>8} {'wheel':<15} {'psi [mrad]':>10} {'contact':<12} {'creepage':>8} "
        f"{'verdict':<14} {'mechanism':<16} {'tone [Hz]':>9} {'growth [1/s]':>12} {'v [m/s]':>7} "
        f"{'LpAmax wheel':>12} {'bogie':>6}"
    ]
    for r in rows:
        contact = f"{r['deciding_contact']} {r['contact_angle_deg']:.0f}deg"
        lines.append(
            f"{r['radius_m']:7.0f} {r['train_speed_km_h']:8.0f} {r['axle'] + ' ' + r['rail']:<15} "
            f"{1e3 * r['angle_of_attack_rad']:10.2f} {contact:<12} {r['lateral_creepage']:8.4f} "
            f"{(r['verdict_mode'] if r['squeals'] else 'no squeal'):<14} {r['mechanism'] or '-':<16} "
            f"{num_cell(r['tone_hz'], '.1f', 9)} {num_cell(r['growth_rate_1_s'], '.3g', 12)} "
            f"{num_cell(r['amplitude_m_s'], '.3f', 7)} {num_cell(r['passby_lpamax_dba'], '.1f', 12)} "
            f"{num_cell(r['bogie_lpamax_dba'], '.1f', 6)}"
        )
    lines.append(
        "contact: the one whose verdict is the wheel's (a flanging wheel has a tread and a flange contact); "
        "v: contact velocity amplitude; LpAmax [dB(A)]: the wheel's and the bogie's pass-by 7.5 m away, "
        "1.2 m above the rail head, free field"
    )
    return "\n".join(lines)
