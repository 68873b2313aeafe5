"""The convergence study's files: ``convergence.csv``, the error-vs-time plots and the
plain-text table."""

from __future__ import annotations

import csv
from pathlib import Path
from typing import Any

from wheel_squeal import outputs

from ..present.canvas import PLOT_DPI
from .choice import ACCURATE_MAX_ERROR, FAST_MAX_ERROR, as_number, pareto_front
from .ladders import COLUMNS, IVP_METHOD, REFERENCE_RTOL

__all__ = ["read_csv", "write_csv", "write_plots"]


def write_csv(rows: list[dict], path: Path) -> None:
    """convergence.csv: the :data:`COLUMNS` of every rung (flags as 1/0)."""
    flags = [{k: int(v) if isinstance(v, bool) else v for k in COLUMNS for v in [r.get(k)]} for r in rows]
    outputs.write_csv(path, flags, COLUMNS)


def read_csv(path: Path) -> list[dict]:
    """Rows of a convergence.csv (numbers as floats, empty cells None)."""
    out = []
    with open(path, newline="") as f:
        for r in csv.DictReader(f):
            row: dict[str, Any] = {}
            for k, v in r.items():
                if v == "":
                    row[k] = None
                elif k in ("study", "method", "parameter_name", "mode", "pareto", "note"):
                    row[k] = v
                elif k == "reference":
                    row[k] = v == "1"
                else:
                    row[k] = float(v)
            out.append(row)
    return out


ERROR_FLOOR = 1e-9  # plotted in place of an exact zero (log axis)


def _plot_panel(ax: Any, rows: list[dict], key: str, title: str) -> None:
    methods = [m for m in dict.fromkeys(r["method"] for r in rows)]
    pts_all, rows_all = [], []
    for method in methods:
        rs = [
            r
            for r in rows
            if r["method"] == method
            and not r["reference"]
            and r.get("seconds") is not None
            and r.get(f"{key}_rel_error") is not None
        ]
        if not rs:
            continue
        rs.sort(key=lambda r: as_number(r["parameter"]), reverse=(method.startswith("solve_ivp")))
        t = [as_number(r["seconds"]) for r in rs]
        e = [max(abs(as_number(r[f"{key}_rel_error"])), ERROR_FLOOR) for r in rs]
        ax.plot(t, e, "o-", label=method, ms=4)
        for r, ti, ei in zip(rs, t, e):
            p = as_number(r["parameter"])
            ax.annotate(f"{p:g}", (ti, ei), textcoords="offset points", xytext=(3, 3), fontsize=6)
        pts_all += list(zip(t, e))
        rows_all += rs
    front = pareto_front(pts_all)
    if front:
        ft = [pts_all[i][0] for i in front]
        fe = [pts_all[i][1] for i in front]
        ax.step(ft, fe, "k--", where="post", lw=1, label="Pareto front")
    if key in ("frequency", "modal_mass") and rows and rows[0]["study"] == "fe":
        ax.axhline(FAST_MAX_ERROR, color="grey", ls=":", lw=1)
        ax.axhline(ACCURATE_MAX_ERROR, color="grey", ls=":", lw=1)
        ax.text(
            0.99,
            FAST_MAX_ERROR,
            "fast aim 1 %",
            transform=ax.get_yaxis_transform(),
            ha="right",
            va="bottom",
            fontsize=7,
            color="grey",
        )
        ax.text(
            0.99,
            ACCURATE_MAX_ERROR,
            "accurate aim 0.1 %",
            transform=ax.get_yaxis_transform(),
            ha="right",
            va="bottom",
            fontsize=7,
            color="grey",
        )
    ax.set_xscale("log")
    ax.set_yscale("log")
    ax.set(xlabel="wall time [s]", ylabel="|relative error|", title=title)
    ax.grid(True, which="both", alpha=0.3)


def write_plots(rows: list[dict], out_dir: Path) -> list[Path]:
    from matplotlib.figure import Figure

    paths = []
    fe = [r for r in rows if r["study"] == "fe"]
    if fe:
        fig = Figure(figsize=(12, 9))
        axes = fig.subplots(2, 2)
        for ax, (k, title) in zip(
            axes.flat,
            [
                ("frequency", "(3,0) mode frequency"),
                ("modal_mass", "contact modal mass"),
                ("amplitude", "limit-cycle amplitude (same RK4 for all)"),
                ("time_to_saturation", "time to saturation (1 period = ~0.2 %)"),
            ],
        ):
            _plot_panel(ax, fe, k, title)
        axes[0, 0].legend(fontsize=7)
        fig.suptitle(
            "Modal solvers: error vs wall time (mesh + modes <= 5 kHz); "
            "labels: elements across the web; zero errors drawn at 1e-9",
            fontsize=10,
        )
        fig.tight_layout()
        p = out_dir / "convergence_fe.png"
        fig.savefig(p, dpi=PLOT_DPI)
        paths.append(p)
    it = [r for r in rows if r["study"] == "integrator"]
    if it:
        fig = Figure(figsize=(12, 4.6))
        axes = fig.subplots(1, 2)
        _plot_panel(axes[0], it, "amplitude", "limit-cycle amplitude")
        _plot_panel(axes[1], it, "time_to_saturation", "time to saturation")
        axes[0].legend(fontsize=7)
        fig.suptitle(
            f"Time integrator: error vs wall time (reference {IVP_METHOD} rtol "
            f"{REFERENCE_RTOL:g}); labels: steps per period / rtol",
            fontsize=10,
        )
        fig.tight_layout()
        p = out_dir / "convergence_integrator.png"
        fig.savefig(p, dpi=PLOT_DPI)
        paths.append(p)
    return paths
