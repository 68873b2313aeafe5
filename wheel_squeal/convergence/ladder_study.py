"""The convergence study: the speed/accuracy trade of the modal solvers and the
integrator, and the fidelity presets it supports.

For one wheel design at the default operating point (800 RPM, Vc = 0.39 m/s, the (3,0)
axial mode), :func:`run_convergence` runs the FE ladders (:mod:`.ladders`) for every
method of ``fem.solvers`` and the integrator ladders, compares every rung with its
reference, marks the Pareto fronts and chooses the presets (:mod:`.choice`), and writes
``convergence.csv``, ``convergence_fe.png``, ``convergence_integrator.png``,
``summary.json`` and ``presets.md`` (:mod:`.report`).

References: FE rungs against the finest axisymmetric rung, curved P2 with
``REFERENCE_ETW`` (10) elements across the web (6 with ``quick=True``); its own
uncertainty is estimated by its change from the next-coarser curved rung and from the
straight-P2 rung of the same size, and it is cross-checked against the finest 3-D P2
rungs (gmsh and cyclic). Integrator rungs against DOP853 at rtol 1e-10 on the same
duration. Errors are signed, ``value / reference - 1``. The time to saturation is the
start of a cycle, so it moves in steps of one period (about 0.2 % of 0.4 s). Times are
medians of repeated runs in forked children; on a busy shared machine they are noisy (a
few 10 %); the errors are deterministic.
"""

from __future__ import annotations

import math
import os
import time
from collections.abc import Callable
from pathlib import Path
from typing import TYPE_CHECKING

from reduced.model import STEPS_PER_PERIOD as PRODUCTION_STEPS_PER_PERIOD
from wheel_squeal import api

from ..design import Design, as_design
from ..outputs import write_json
from ..presets import DEFAULT_CRAB_VELOCITY_M_S, DEFAULT_FMAX_HZ, DEFAULT_RPM
from .choice import (
    ERROR_KEYS,
    VALUE_KEYS,
    as_number,
    choose_presets,
    fill_errors,
    mark_pareto,
    percent,
    presets_table,
    presets_verdict,
)
from .ladders import (
    CROSSCHECK_STEPS_PER_PERIOD,
    IVP_METHOD,
    QUICK,
    FERung,
    Ladders,
    fe_ladder,
    integrator_ladder,
)
from .preset_report import write_csv, write_plots

if TYPE_CHECKING:
    from reduced import ModalDOF

__all__ = ["ConvergenceError", "run_convergence"]


class ConvergenceError(RuntimeError):
    """The study could not produce its reference (nothing to compare against)."""


def _warm_up(design: Design) -> None:
    """Import and exercise the code paths once in this process so each child starts
    warm (imports, numba caches, lazily loaded libraries are not timed)."""
    import reduced
    from fem.axisym import solve_axisymmetric
    from fem.cyclic import solve_cyclic  # noqa: F401
    from fem.eigen import available_factorizations, small_problem_factorization
    from fem.solid import solve_solid  # noqa: F401
    from geometry.gmsh_mesh import mesh_profile

    small_problem_factorization()
    available_factorizations()
    solve_axisymmetric(
        design.wheel, mesh_profile(design.wheel, elements_through_web=1, order=1), fmax_hz=1500.0
    )
    law = api.contact_law(design)
    op = api.operating_point(design)
    reduced.load_compiled_kernels()  # every timed simulation then runs compiled
    reduced.limit_cycle(reduced.simulate(reduced.ModalDOF(3.1, 1.6e8, 42.0), law, op, 0.01))


def run_convergence(
    design: Design,
    out_dir: Path,
    *,
    quick: bool = False,
    progress: Callable[[str], None] | None = None,
    isolate: bool = True,
) -> list[dict]:
    """Run the convergence study on ``design`` and write its files into ``out_dir``.

    ``design``: a ``Design`` (or a TOML path / None for Table 1). ``quick``: only
    the cheapest rungs (reference: curved axisym P2, 6 per web). ``progress``: called
    with one line of text per step. ``isolate``: measure each run in a forked child
    (peak memory); False runs in-process (memory NaN). Returns the rows of
    ``convergence.csv`` (dicts keyed by :data:`COLUMNS`).
    """
    if design is None or isinstance(design, (str, Path)):
        design = api.load_design(design)
    design = as_design(design)
    out_dir = Path(out_dir)
    out_dir.mkdir(parents=True, exist_ok=True)
    say = progress or (lambda _s: None)
    t_start = time.perf_counter()
    lad = QUICK if quick else Ladders()

    say(f"design {design.name}: warming up (imports, numba) ...")
    _warm_up(design)

    # 1. FE rungs: reference first (nothing can be compared without it)
    fe_rows, modes = fe_ladder(design, _fe_rungs(lad, quick), isolate=isolate, progress=say)
    ref = fe_rows[0]
    if ref["frequency_hz"] is None or ref["amplitude_m_s"] is None:
        raise ConvergenceError(f"reference rung failed: {ref['note']}")
    fill_errors(fe_rows, ref)
    reference_info = _reference_info(fe_rows, lad.reference_etw)
    _say_reference(reference_info, ref, say)

    # 2. integrator rungs on the reference's (m, k, c), same duration as its run
    ref_mode = modes[0]
    dof = api.modal_dof(ref_mode, design)
    contact = api.contact_law(design)
    op = api.operating_point(design, rpm=DEFAULT_RPM, crabbing_velocity_m_s=DEFAULT_CRAB_VELOCITY_M_S)
    duration = float(ref["simulated_s"])
    it_rows = integrator_ladder(
        dof,
        contact,
        op,
        duration,
        rk4=lad.rk4,
        rtols=lad.rtols,
        reference_rtol=lad.reference_rtol,
        crosscheck_steps=None if quick else CROSSCHECK_STEPS_PER_PERIOD,
        isolate=isolate,
        progress=say,
    )
    it_ref = next((r for r in it_rows if r["reference"]), None)
    if it_ref is None or it_ref["amplitude_m_s"] is None:
        raise ConvergenceError("integrator reference failed: " + (it_ref or {}).get("note", ""))
    fill_errors(it_rows, it_ref, keys=("amplitude", "time_to_saturation"))

    rows = fe_rows + it_rows
    mark_pareto(rows)
    presets = choose_presets(rows)
    verdict = presets_verdict(presets)
    integrator_info = _integrator_info(it_rows, it_ref, dof, duration)
    summary = {
        "design": design.name,
        "quick": quick,
        "operating_point": {
            "rpm": DEFAULT_RPM,
            "crabbing_velocity_m_s": DEFAULT_CRAB_VELOCITY_M_S,
            "rolling_speed_m_s": op.rolling_speed_m_s,
        },
        "fmax_hz": DEFAULT_FMAX_HZ,
        "fe_reference": reference_info,
        "integrator": integrator_info,
        "presets": presets,
        "verdict": verdict,
        "machine": {
            "nproc": os.cpu_count(),
            "loadavg": list(os.getloadavg()) if hasattr(os, "getloadavg") else None,
        },
        "seconds_total": time.perf_counter() - t_start,
    }
    write_csv(rows, out_dir / "convergence.csv")
    write_plots(rows, out_dir)
    write_json(out_dir / "summary.json", summary)
    (out_dir / "presets.md").write_text(
        f"Presets measured on {design.name} (reference: {reference_info['rung']}; "
        f"{DEFAULT_RPM:g} RPM, Vc {DEFAULT_CRAB_VELOCITY_M_S:g} m/s; errors relative to the reference):\n\n"
        + presets_table(presets)
        + "\n\n"
        + "\n".join(f"- {v}" for v in verdict)
        + "\n"
    )
    for v in verdict:
        say(v)
    say(f"done in {time.perf_counter() - t_start:.0f} s")
    return rows


def _fe_rungs(lad: Ladders, quick: bool) -> list[FERung]:
    rungs = [FERung("axisym-P2-curved", lad.reference_etw, reference=True)]
    rungs += [FERung("axisym-P2", e) for e in lad.axisym]
    rungs += [FERung("axisym-P2-curved", e) for e in lad.axisym_curved]
    rungs += [FERung("3d-tet-P1", e) for e in lad.p1]
    rungs += [FERung("3d-tet-P2", e) for e in lad.p2]
    rungs += [FERung("3d-P2", e) for e in lad.cyclic]
    if not quick:
        rungs.append(FERung("3d-tet-P2-straight", 1))
    return rungs


def _reference_info(fe_rows: list[dict], ref_etw: int) -> dict:
    """The FE reference, its own convergence and its 3-D cross-checks (summary.json)."""
    ref = fe_rows[0]

    def rel(a: dict, key: str) -> float | None:
        v, r = as_number(a.get(VALUE_KEYS[key])), as_number(ref.get(VALUE_KEYS[key]))
        return v / r - 1 if math.isfinite(v) and math.isfinite(r) else None

    def finest(method: str) -> dict | None:
        return max((r for r in finer if r["method"] == method), key=lambda r: r["parameter"], default=None)

    def crosscheck(row: dict | None, method: str) -> dict | None:
        if row is None:
            return None
        return {
            "rung": f"{method}, {row['parameter']} per web",
            "dofs": row["dofs"],
            **{f"{k}_rel_difference": rel(row, k) for k in ERROR_KEYS},
        }

    finer = [r for r in fe_rows if not r["reference"] and r["frequency_hz"] is not None]
    next_curved = finest("axisym-P2-curved")
    straight_same = next((r for r in finer if r["method"] == "axisym-P2" and r["parameter"] == ref_etw), None)
    info = {
        "rung": f"axisym-P2-curved, {ref_etw} elements across the web",
        **{k: ref[k] for k in ("dofs", "seconds", "frequency_hz", "modal_mass_kg", "amplitude_m_s")},
        "time_to_saturation_s": ref["time_to_saturation_s"],
        "mode": ref["mode"],
        "self_convergence": {
            "vs": (f"axisym-P2-curved, {next_curved['parameter']} per web" if next_curved else None),
            **(
                {f"{k}_rel_change": rel(next_curved, k) for k in ("frequency", "modal_mass")}
                if next_curved
                else {}
            ),
        },
        "crosscheck_3d_p2": crosscheck(finest("3d-tet-P2"), "3d-tet-P2"),
        "crosscheck_3d_cyclic": crosscheck(finest("3d-P2"), "3d-P2"),
    }
    if straight_same is not None:
        info["straight_p2_same_mesh"] = {
            f"{k}_rel_difference": rel(straight_same, k) for k in ("frequency", "modal_mass")
        }
    return info


def _say_reference(info: dict, ref: dict, say: Callable[[str], None]) -> None:
    say(
        f"reference: {info['rung']}: {ref['frequency_hz']:.4f} Hz, "
        f"m = {ref['modal_mass_kg']:.6f} kg, amplitude {ref['amplitude_m_s']:.6f} m/s"
    )
    sc = info["self_convergence"]
    if sc["vs"]:
        say(
            f"  reference self-convergence (vs {sc['vs']}): frequency {percent(sc['frequency_rel_change'])}, "
            f"modal mass {percent(sc['modal_mass_rel_change'])}"
        )
    for cc in (info["crosscheck_3d_p2"], info["crosscheck_3d_cyclic"]):
        if cc:
            say(
                f"  cross-check {cc['rung']} ({cc['dofs']} DOFs): frequency "
                f"{percent(cc['frequency_rel_difference'])}, "
                f"modal mass {percent(cc['modal_mass_rel_difference'])}, "
                f"amplitude {percent(cc['amplitude_rel_difference'])}"
            )


def _integrator_info(it_rows: list[dict], it_ref: dict, dof: ModalDOF, duration: float) -> dict:
    """The integrator reference and the errors of the cross-check and production RK4."""
    keys = ("amplitude", "time_to_saturation")

    def rk4(steps: int) -> dict | None:
        return next((r for r in it_rows if r["method"] == "rk4" and r["parameter"] == steps), None)

    cross, prod = rk4(CROSSCHECK_STEPS_PER_PERIOD), rk4(PRODUCTION_STEPS_PER_PERIOD)
    return {
        "reference": f"solve_ivp {IVP_METHOD} rtol {it_ref['parameter']:g}",
        "duration_s": duration,
        "mode": {
            "mass_kg": dof.mass_kg,
            "stiffness_n_m": dof.stiffness_n_m,
            "damping_ns_m": dof.damping_ns_m,
            "frequency_hz": dof.frequency_hz,
        },
        "crosscheck_rk4_256": ({k: cross[f"{k}_rel_error"] for k in keys} if cross else None),
        "production_rk4_48": (
            {k: prod[f"{k}_rel_error"] for k in keys} | {"seconds": prod["seconds"]} if prod else None
        ),
    }
