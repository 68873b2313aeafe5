"""A study's results as an xarray Dataset, and its files (NetCDF, CSV, PNG).

Dimensions: one per varied quantity of a grid study (or ``sample``), then
``crab_velocity`` [m/s] and ``rpm``. Per design: ``status`` (ok | invalid | failed),
``reason`` (the one-line reason when not ok), ``mass_kg``, ``modes`` and the value of
every design field the study changes (``design_<field>``). Per design and operating
point, the verdict there (:mod:`wheel_squeal.verdict`): ``verdict_mode`` (the label of
the mode that squeals, "" where none), ``squeals``, ``saturated`` (False: still growing
at the end of the run, not a limit cycle), ``tone_hz``, ``growth_rate_1_s`` (the
squealing mode's; where none squeals the largest of all, <= 0),
``amplitude_m_s`` (contact velocity), ``spl_db`` and ``spl_dba`` (at the default
microphone) and ``sound_power_level_db``; the model's own pick (``model_pick`` and its
``model_pick_growth_rate_1_s``) and, when the base design names a mode (the attribute
``named_mode``), that mode's ``override_growth_rate_1_s``.
"""

from __future__ import annotations

import datetime as _dt
from pathlib import Path
from typing import Any

import numpy as np

from ..fields import unit_of
from ..present.canvas import PLOT_DPI
from ..runtime.provenance import CODE_PACKAGES, code_version
from .spec import StudySpec
from .task import FLAG_FIELDS, LABEL_FIELDS, RESULT_FIELDS

__all__ = ["loudest", "study_dataset", "study_summary", "write_study_files"]

#: the variables that carry a unit (from :mod:`wheel_squeal.fields`)
_UNITS = {k: unit_of(k) for k in (*RESULT_FIELDS, "mass_kg")}


def study_dataset(spec: StudySpec, results: list[dict]) -> Any:
    """The Dataset of ``results`` (one per case of ``spec``, in case order)."""
    import xarray as xr

    cases = spec.cases()
    if spec.samples:
        design_dims = ["sample"]
        shape: tuple[int, ...] = (spec.samples,)
        coords: dict[str, Any] = {"sample": np.arange(spec.samples)}
    else:
        design_dims = [d.name for d in spec.dimensions]
        shape = tuple(len(d.values) for d in spec.dimensions)
        coords = {d.name: np.asarray(d.values) for d in spec.dimensions}
    op_dims = ["crab_velocity", "rpm"]
    coords |= {"crab_velocity": np.asarray(spec.crabbing_velocities_m_s), "rpm": np.asarray(spec.rpm)}
    n_op = (len(spec.crabbing_velocities_m_s), len(spec.rpm))

    status = np.empty(shape, dtype=object)
    reason = np.empty(shape, dtype=object)
    mass = np.full(shape, np.nan)
    modes = np.zeros(shape, dtype=np.int64)
    per_op = {k: np.full(shape + n_op, np.nan) for k in RESULT_FIELDS}
    flags = {k: np.zeros(shape + n_op, dtype=bool) for k in FLAG_FIELDS}
    labels = {k: np.full(shape + n_op, "", dtype=object) for k in LABEL_FIELDS}
    changed = sorted({k for c in cases for k, _ in c.changes})
    fields_ = {k: np.full(shape, np.nan) for k in changed}
    sampled = {d.name: np.full(shape, np.nan) for d in spec.dimensions} if spec.samples else {}
    for case, r in zip(cases, results):
        at = case.index
        status[at], reason[at] = r["status"], r.get("reason", "")
        for k, v in case.changes:
            fields_[k][at] = v
        for d, v in zip(spec.dimensions, case.values):
            if spec.samples:
                sampled[d.name][at] = v
        if r["status"] != "ok":
            continue
        mass[at], modes[at] = r["mass_kg"], r["modes"]
        for k in RESULT_FIELDS:
            per_op[k][at] = np.asarray(r[k], dtype=float)
        for k in FLAG_FIELDS:
            flags[k][at] = np.asarray(r[k], dtype=bool)
        for k in LABEL_FIELDS:
            labels[k][at] = np.asarray(r[k], dtype=object)

    data = {
        "status": (design_dims, status.astype(str)),
        "reason": (design_dims, reason.astype(str)),
        "mass_kg": (design_dims, mass),
        "modes": (design_dims, modes),
    }
    data |= {k: (design_dims + op_dims, v.astype(str)) for k, v in labels.items()}
    data |= {k: (design_dims + op_dims, v) for k, v in flags.items()}
    data |= {k: (design_dims + op_dims, v) for k, v in per_op.items()}
    data |= {f"design_{k}": (design_dims, v) for k, v in fields_.items()}
    if spec.samples:  # the drawn values of each sampled quantity, as coordinates
        coords |= {d: ("sample", v) for d, v in sampled.items()}
    ds = xr.Dataset(data, coords=coords)
    for k, unit in _UNITS.items():
        ds[k].attrs["units"] = unit
    for axis in ("crab_velocity", "rpm"):
        ds[axis].attrs["units"] = unit_of(axis)
    ds.attrs = {
        "title": f"wheel-squeal study {spec.name}",
        "description": spec.description,
        "kind": spec.kind,
        "base_design": spec.base.name,
        "fidelity": spec.fidelity,
        "fmax_hz": spec.fmax_hz,
        "named_mode": spec.base.squeal.mode,
        "spec": spec.source,
        "code_version": code_version(*CODE_PACKAGES),
        "created": _dt.datetime.now(_dt.UTC).isoformat(timespec="seconds"),
    }
    return ds


def write_study_files(ds: Any, spec: StudySpec, folder: Path) -> list[str]:
    """``study.nc`` (NetCDF), ``study.csv`` (one row per design and operating point), the
    spec (``study.toml``), plots and ``report.html``; returns the file names."""
    from ..present.html import REPORT_NAME, study_report

    ds.to_netcdf(folder / "study.nc", engine="scipy")
    ds.to_dataframe().reset_index().to_csv(folder / "study.csv", index=False, float_format="%.10g")
    (folder / "study.toml").write_text(spec.source)
    names = ["study.nc", "study.csv", "study.toml"]
    names += _plots(ds, spec, folder)
    inputs = [
        ("spec", spec.name),
        ("description", spec.description),
        ("base design", spec.base.name),
        ("fidelity", spec.fidelity),
        ("fmax", f"{spec.fmax_hz:g} Hz"),
        ("compute", ", ".join(spec.compute)),
    ]
    study_report(folder, spec.name, study_summary(ds, spec), inputs)
    return names + [REPORT_NAME]


#: A colour or axis scale spans at least this much (a smaller spread is drawn as it is,
#: not stretched over the whole scale): Hz for tones, dB for levels, m/s for amplitudes
MIN_SPAN = {"tone_hz": 5.0, "spl_dba": 2.0, "spl_db": 2.0, "amplitude_m_s": 0.01, "growth_rate_1_s": 1.0}


def _level_var(ds: Any, spec: StudySpec) -> str:
    """How loud or strong a squeal is, as the plots and the summary show it: the
    A-weighted SPL where sound is computed, else the contact velocity amplitude of the
    limit cycle, else (the stability alone) the linear growth rate."""
    if "sound" in spec.compute:
        return "spl_dba"
    return "amplitude_m_s" if "limit_cycle" in spec.compute else "growth_rate_1_s"


def loudest(ds: Any, spec: StudySpec) -> Any:
    """Per design (an xarray Dataset over the design dimensions): its ``level`` at its
    loudest operating point (NaN: no squeal anywhere), the ``tone_hz`` there, and the
    share of its operating grid where it squeals (``squealing_share``)."""
    import xarray as xr

    var = _level_var(ds, spec)
    ok = ds["status"] == "ok"
    stacked = ds[[var, "tone_hz", "squeals"]].where(ok).stack(point=("crab_velocity", "rpm"))
    level = stacked[var].where(stacked["squeals"] > 0.5)  # its squealing points (a float after where)
    best = level.fillna(-np.inf).argmax("point")
    loud = level.isel(point=best).drop_vars(["point", "crab_velocity", "rpm"], errors="ignore")
    tone = stacked["tone_hz"].isel(point=best).drop_vars(["point", "crab_velocity", "rpm"], errors="ignore")
    share = ds["squeals"].where(ok).mean(["crab_velocity", "rpm"])
    return xr.Dataset({"level": loud, "tone_hz": tone, "squealing_share": share})


def _span(values: Any, name: str) -> tuple[float, float]:
    """Axis or colour limits of ``values``: their range, widened about its middle to
    :data:`MIN_SPAN`."""
    v = np.asarray(values, float)
    v = v[np.isfinite(v)]
    if not len(v):
        return 0.0, 1.0
    lo, hi = float(v.min()), float(v.max())
    span = 1.1 * max(hi - lo, MIN_SPAN.get(name, 0.0))  # 5 % room on each side
    mid = 0.5 * (lo + hi)
    return mid - span / 2, mid + span / 2


def _label(ds: Any, name: str) -> str:
    from ..design import FIELD_UNITS

    unit = ds[name].attrs.get("units") if name in ds else None
    unit = unit if unit is not None else FIELD_UNITS.get(name, "")
    return f"{name.replace('_', ' ')} ({unit})" if unit else name.replace("_", " ")


def study_summary(ds: Any, spec: StudySpec) -> list[str]:
    """The study in a few lines: the designs, how many squeal, the spread of their tone
    and level (P5, P50, P95 over the designs' loudest points), and the worst design."""
    per = loudest(ds, spec)
    var = _level_var(ds, spec)
    unit = unit_of(var)
    status = ds["status"].values.ravel()
    n, ok = status.size, int((status == "ok").sum())
    level = per["level"].values.ravel()
    squealing = np.isfinite(level)  # its loudest squealing point (none: no squeal anywhere)
    grid = f"{ds.sizes['crab_velocity']} crabbing velocities x {ds.sizes['rpm']} speeds"
    lines = [f"{n} designs ({ok} valid) x {grid}"]
    lines.append(f"{int(squealing.sum())} of {ok} valid designs squeal somewhere on the operating grid")
    if squealing.any():
        tone = per["tone_hz"].values.ravel()[squealing]
        lv = level[squealing]
        p = np.percentile(tone, [5, 50, 95])
        q = np.percentile(lv, [5, 50, 95])
        lines.append(f"tone at each design's loudest point: P5 {p[0]:.1f}, P50 {p[1]:.1f}, P95 {p[2]:.1f} Hz")
        lines.append(
            f"{var} at each design's loudest point: P5 {q[0]:.4g}, P50 {q[1]:.4g}, P95 {q[2]:.4g} {unit}"
        )
        worst = int(np.nanargmax(np.where(np.isfinite(level), level, -np.inf)))
        at = np.unravel_index(worst, per["level"].shape)
        where = ", ".join(
            f"{d} = {per[d].values[i]:.4g}" for d, i in zip(per["level"].dims, at) if d in per.coords
        )
        tone_there = per["tone_hz"].values.ravel()[worst]
        lines.append(
            f"the loudest design: {where or f'#{worst}'}: {level[worst]:.4g} {unit} at {tone_there:.1f} Hz"
        )
    return lines


def _plots(ds: Any, spec: StudySpec, folder: Path) -> list[str]:
    """study_tone_level.png: tone and level at each design's loudest point against the
    varied parameters (grids: lines or maps with units; samples: histograms with P5, P50,
    P95 and the loudest design, and the level against each sampled parameter)."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    per = loudest(ds, spec)
    var = _level_var(ds, spec)
    names = {"tone_hz": "tone at the loudest point", "level": f"{var} at the loudest point"}
    units = {"tone_hz": "Hz", "level": unit_of(var)}
    spans = {"tone_hz": "tone_hz", "level": var}
    if spec.samples:
        params = [d.name for d in spec.dimensions]
        fig, axes = plt.subplots(
            2, max(2, len(params)), figsize=(4.2 * max(2, len(params)), 7.4), squeeze=False
        )
        for ax, key in zip(axes[0], ("tone_hz", "level")):
            values = per[key].values.ravel()
            values = values[np.isfinite(values)]
            ax.hist(values, bins=min(40, max(5, len(values) // 5)) if len(values) else 5, color="#3060a0")
            ax.set_xlim(*_span(values, spans[key]))
            if len(values):
                for q, style in zip(np.percentile(values, [5, 50, 95]), (":", "-", ":")):
                    ax.axvline(q, color="k", ls=style, lw=1)
                worst = float(values.max()) if key == "level" else None
                if worst is not None:
                    ax.axvline(worst, color="C3", lw=1.5, label=f"loudest design {worst:.4g}")
                    ax.legend(fontsize=8)
                p = np.percentile(values, [5, 50, 95])
                ax.set_title(f"P5 {p[0]:.4g}, P50 {p[1]:.4g}, P95 {p[2]:.4g} {units[key]}", fontsize=9)
            ax.set(xlabel=f"{names[key]} ({units[key]})", ylabel="designs")
        for ax in axes[0][2:]:
            ax.axis("off")
        for ax, name in zip(axes[1], params):
            ax.plot(ds[name].values, per["level"].values, "o", ms=3, color="#3060a0")
            ax.set_ylim(*_span(per["level"].values, var))
            ax.set(xlabel=_label(ds, name), ylabel=f"{names['level']} ({units['level']})")
            ax.grid(alpha=0.3)
        for ax in axes[1][len(params) :]:
            ax.axis("off")
        fig.suptitle(
            f"{spec.name}: {spec.samples} sampled designs ({int((ds['status'] == 'ok').sum())} valid)"
        )
    else:
        dims = [d.name for d in spec.dimensions]
        fig, axes = plt.subplots(1, 2, figsize=(12, 4.8))
        for ax, key in zip(axes, ("tone_hz", "level")):
            values = per[key]
            lo, hi = _span(values.values, spans[key])
            finite = values.values[np.isfinite(values.values)]
            label = (
                f"{names[key]}: {finite.min():.4g} to {finite.max():.4g} {units[key]}"
                if len(finite)
                else names[key]
            )
            if len(dims) >= 2:
                grid = values.max(dims[2:]) if len(dims) > 2 else values
                im = ax.pcolormesh(
                    ds[dims[1]],
                    ds[dims[0]],
                    grid.transpose(dims[0], dims[1]).values,
                    shading="nearest",
                    cmap="magma",
                    vmin=lo,
                    vmax=hi,
                )
                fig.colorbar(im, ax=ax, label=units[key])
                ax.set(xlabel=_label(ds, dims[1]), ylabel=_label(ds, dims[0]), title=label)
            else:
                ax.plot(ds[dims[0]], values.values, "o-")
                ax.set_ylim(lo, hi)
                ax.set(xlabel=_label(ds, dims[0]), ylabel=units[key], title=label)
                ax.grid(alpha=0.3)
        fig.suptitle(f"{spec.name}: the loudest squeal of each design over the operating grid (blank: none)")
    name = "study_tone_level.png"
    fig.tight_layout()
    fig.savefig(folder / name, dpi=PLOT_DPI)
    plt.close(fig)
    return [name]
