"""The convergence study's files: ``convergence.csv``, the error-vs-time plots and the
plain-text table."""

from __future__ import annotations

import csv
import math
from pathlib import Path

from .choice import ACCURATE_MAX_ERROR, FAST_MAX_ERROR, as_number, pareto_front, percent
from .ladders import COLUMNS, IVP_METHOD, REFERENCE_RTOL

__all__ = ["format_table", "read_csv", "write_csv", "write_plots"]


def _csv_value(v) -> str:
    if v is None:
        return ""
    if isinstance(v, bool):
        return "1" if v else "0"
    if isinstance(v, float):
        return "" if not math.isfinite(v) else repr(v)
    return str(v)


def write_csv(rows: list[dict], path: Path) -> None:
    with open(path, "w", newline="") as f:
        w = csv.writer(f)
        w.writerow(COLUMNS)
        for r in rows:
            w.writerow([_csv_value(r.get(k)) for k in COLUMNS])


def read_csv(path: Path) -> list[dict]:
    """Rows of a convergence.csv (numbers as floats, empty cells None)."""
    out = []
    with open(path, newline="") as f:
        for r in csv.DictReader(f):
            row = {}
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


def _plot_panel(ax, rows: list[dict], key: str, title: str) -> None:
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
        fig.savefig(p, dpi=110)
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
        fig.savefig(p, dpi=110)
        paths.append(p)
    return paths


def format_table(rows: list[dict]) -> str:
    """A plain-text table of the rows."""
    head = (
        f"{'study':<10} {'method':<20} {'param':>7} {'DOFs':>7} {'time s':>8} {'MB':>6} "
        f"{'f Hz':>10} {'df/f':>10} {'m kg':>8} {'dm/m':>10} {'amp m/s':>9} {'damp':>10} "
        f"{'tsat s':>7} {'dtsat':>9} front"
    )
    lines = [head]

    def g(r: dict, k: str, fmt: str) -> str:
        v = as_number(r.get(k))
        return format(v, fmt) if math.isfinite(v) else "-"

    for r in rows:
        lines.append(
            f"{r['study']:<10} {r['method'] + ('*' if r['reference'] else ''):<20} "
            f"{as_number(r['parameter']):>7g} {g(r, 'dofs', '7.0f'):>7} {g(r, 'seconds', '8.3f'):>8} "
            f"{g(r, 'peak_memory_mb', '6.0f'):>6} {g(r, 'frequency_hz', '10.3f'):>10} "
            f"{percent(r.get('frequency_rel_error')) if r['study'] == 'fe' else '-':>10} "
            f"{g(r, 'modal_mass_kg', '8.4f'):>8} "
            f"{percent(r.get('modal_mass_rel_error')) if r['study'] == 'fe' else '-':>10} "
            f"{g(r, 'amplitude_m_s', '9.6f'):>9} {percent(r.get('amplitude_rel_error')):>10} "
            f"{g(r, 'time_to_saturation_s', '7.4f'):>7} {percent(r.get('time_to_saturation_rel_error')):>9} "
            f"{r.get('pareto') or ''}" + (f"  [{r['note']}]" if r.get("note") else "")
        )
    lines.append("* reference rung; errors are value/reference - 1")
    return "\n".join(lines)
