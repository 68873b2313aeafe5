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

from reduced.report import PLOT_DPI

from ..cache import code_version
from ..fields import unit_of
from .spec import StudySpec
from .task import CODE_PACKAGES, FLAG_FIELDS, LABEL_FIELDS, RESULT_FIELDS

__all__ = ["study_dataset", "write_study_files"]

#: the variables that carry a unit (from :mod:`wheel_squeal.fields`)
_UNITS = {k: unit_of(k) for k in (*RESULT_FIELDS, "mass_kg")}


def study_dataset(spec: StudySpec, results: list[dict]):
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


def write_study_files(ds, spec: StudySpec, folder: Path) -> list[str]:
    """``study.nc`` (NetCDF), ``study.csv`` (one row per design and operating point), the
    spec (``study.toml``) and plots; returns the file names."""
    ds.to_netcdf(folder / "study.nc", engine="scipy")
    ds.to_dataframe().reset_index().to_csv(folder / "study.csv", index=False, float_format="%.10g")
    (folder / "study.toml").write_text(spec.source)
    names = ["study.nc", "study.csv", "study.toml"]
    names += _plots(ds, spec, folder)
    return names


def _plots(ds, spec: StudySpec, folder: Path) -> list[str]:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    amp = ds["amplitude_m_s"].fillna(0.0).max(["crab_velocity", "rpm"])
    out = []
    if spec.samples:
        fig, axes = plt.subplots(1, 2, figsize=(10, 4))
        ok = ds["status"] == "ok"
        for ax, var, xlabel in (
            (axes[0], "tone_hz", "squeal tone [Hz]"),
            (axes[1], "spl_db" if "sound" in spec.compute else "amplitude_m_s", None),
        ):
            values = ds[var].where(ok).values.ravel()
            values = values[np.isfinite(values)]
            ax.hist(values, bins=min(40, max(5, len(values) // 5)) if len(values) else 5, color="#3060a0")
            ax.set_xlabel(xlabel or f"{var} [{ds[var].attrs.get('units', '')}]")
            ax.set_ylabel("design x operating point")
        fig.suptitle(f"{spec.name}: {spec.samples} samples, {int(ok.sum())} valid")
        name = "study_histograms.png"
    else:
        unstable = (ds["growth_rate_1_s"] > 0).where(ds["status"] == "ok").mean(["crab_velocity", "rpm"])
        panels = (
            (unstable, "share of the operating grid where a mode grows", "viridis"),
            (amp, "largest limit-cycle amplitude over the operating grid [m/s]", "magma"),
        )
        fig, axes = plt.subplots(1, 2, figsize=(12, 4.8))
        dims = list(amp.dims)
        for ax, (values, what, cmap) in zip(axes, panels):
            if len(dims) >= 2:
                grid = values.max(dims[2:]) if len(dims) > 2 else values
                im = ax.pcolormesh(ds[dims[1]], ds[dims[0]], grid.values, shading="nearest", cmap=cmap)
                fig.colorbar(im, ax=ax, label=what)
                ax.set_xlabel(dims[1])
                ax.set_ylabel(dims[0])
            else:
                ax.plot(ds[dims[0]], values.values, "o-")
                ax.set_xlabel(dims[0])
                ax.set_ylabel(what)
        fig.suptitle(f"{spec.name}: squeal over the design grid")
        name = "study_amplitude.png"
    fig.tight_layout()
    fig.savefig(folder / name, dpi=PLOT_DPI)
    plt.close(fig)
    out.append(name)
    return out
