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

from .. import api
from ..design import as_design
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
    AXISYM_LADDER,
    CROSSCHECK_STEPS_PER_PERIOD,
    CYCLIC_LADDER,
    IVP_METHOD,
    IVP_RTOLS,
    QUICK,
    REFERENCE_ETW,
    REFERENCE_RTOL,
    RK4_LADDER,
    SOLID_P1_LADDER,
    SOLID_P2_LADDER,
    FERung,
    fe_ladder,
    integrator_ladder,
)
from .report import write_csv, write_plots

__all__ = ["ConvergenceError", "run_convergence"]


class ConvergenceError(RuntimeError):
    """The study could not produce its reference (nothing to compare against)."""


def _warm_up(design) -> None:
    """Import and exercise the code paths once in this process so each child starts
    warm (imports, numba caches, lazily loaded libraries are not timed)."""
    import reduced
    from fem.axisym import solve_axisymmetric
    from fem.cyclic import solve_cyclic  # noqa: F401
    from fem.eigen import available_factorizations, small_problem_factorization
    from fem.solid import solve_solid  # noqa: F401

    small_problem_factorization()
    available_factorizations()
    solve_axisymmetric(design.wheel, elements_through_web=1, fmax_hz=1500.0)
    law = api.contact_law(design)
    op = api.operating_point(design)
    reduced.load_compiled_kernels()  # every timed simulation then runs compiled
    reduced.limit_cycle(reduced.simulate(reduced.ModalDOF(3.1, 1.6e8, 42.0), law, op, 0.01))


def run_convergence(
    design,
    out_dir,
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
    q = QUICK if quick else None
    axisym = q["axisym"] if q else AXISYM_LADDER
    curved = q["axisym_curved"] if q else AXISYM_LADDER
    ref_etw = q["reference_etw"] if q else REFERENCE_ETW
    p1 = q["p1"] if q else SOLID_P1_LADDER
    p2 = q["p2"] if q else SOLID_P2_LADDER
    cyclic = q["cyclic"] if q else CYCLIC_LADDER

    say(f"design {design.name}: warming up (imports, numba) ...")
    _warm_up(design)

    # 1. FE rungs: reference first (nothing can be compared without it)
    rungs = [FERung("axisym-P2-curved", ref_etw, reference=True)]
    rungs += [FERung("axisym-P2", e) for e in axisym]
    rungs += [FERung("axisym-P2-curved", e) for e in curved]
    rungs += [FERung("3d-tet-P1", e) for e in p1]
    rungs += [FERung("3d-tet-P2", e) for e in p2]
    rungs += [FERung("3d-P2", e) for e in cyclic]
    if not quick:
        rungs.append(FERung("3d-tet-P2-straight", 1))
    fe_rows, modes = fe_ladder(design, rungs, isolate=isolate, progress=say)
    ref = fe_rows[0]
    if ref["frequency_hz"] is None or ref["amplitude_m_s"] is None:
        raise ConvergenceError(f"reference rung failed: {ref['note']}")
    fill_errors(fe_rows, ref)

    # the reference's own uncertainty and the 3-D cross-check
    def _rel(a: dict, key: str) -> float | None:
        v, r = as_number(a.get(VALUE_KEYS[key])), as_number(ref.get(VALUE_KEYS[key]))
        return v / r - 1 if math.isfinite(v) and math.isfinite(r) else None

    finer = [r for r in fe_rows if not r["reference"] and r["frequency_hz"] is not None]
    next_curved = max(
        (r for r in finer if r["method"] == "axisym-P2-curved"), key=lambda r: r["parameter"], default=None
    )
    straight_same = next((r for r in finer if r["method"] == "axisym-P2" and r["parameter"] == ref_etw), None)
    p2_rows = [r for r in finer if r["method"] == "3d-tet-P2"]
    finest_p2 = max(p2_rows, key=lambda r: r["parameter"], default=None)
    finest_cyc = max((r for r in finer if r["method"] == "3d-P2"), key=lambda r: r["parameter"], default=None)
    reference_info = {
        "rung": f"axisym-P2-curved, {ref_etw} elements across the web",
        "dofs": ref["dofs"],
        "seconds": ref["seconds"],
        "frequency_hz": ref["frequency_hz"],
        "modal_mass_kg": ref["modal_mass_kg"],
        "amplitude_m_s": ref["amplitude_m_s"],
        "time_to_saturation_s": ref["time_to_saturation_s"],
        "mode": ref["mode"],
        "self_convergence": {
            "vs": (f"axisym-P2-curved, {next_curved['parameter']} per web" if next_curved else None),
            **(
                {f"{k}_rel_change": _rel(next_curved, k) for k in ("frequency", "modal_mass")}
                if next_curved
                else {}
            ),
        },
        "crosscheck_3d_p2": (
            {
                "rung": f"3d-tet-P2, {finest_p2['parameter']} per web",
                "dofs": finest_p2["dofs"],
                **{f"{k}_rel_difference": _rel(finest_p2, k) for k in ERROR_KEYS},
            }
            if finest_p2
            else None
        ),
        "crosscheck_3d_cyclic": (
            {
                "rung": f"3d-P2, {finest_cyc['parameter']} per web",
                "dofs": finest_cyc["dofs"],
                **{f"{k}_rel_difference": _rel(finest_cyc, k) for k in ERROR_KEYS},
            }
            if finest_cyc
            else None
        ),
    }
    if straight_same is not None:
        reference_info["straight_p2_same_mesh"] = {
            f"{k}_rel_difference": _rel(straight_same, k) for k in ("frequency", "modal_mass")
        }
    say(
        f"reference: {reference_info['rung']}: {ref['frequency_hz']:.4f} Hz, "
        f"m = {ref['modal_mass_kg']:.6f} kg, amplitude {ref['amplitude_m_s']:.6f} m/s"
    )
    if next_curved:
        sc = reference_info["self_convergence"]
        say(
            f"  reference self-convergence (vs {sc['vs']}): frequency {percent(sc['frequency_rel_change'])}, "
            f"modal mass {percent(sc['modal_mass_rel_change'])}"
        )
    for cc in (reference_info["crosscheck_3d_p2"], reference_info["crosscheck_3d_cyclic"]):
        if cc:
            say(
                f"  cross-check {cc['rung']} ({cc['dofs']} DOFs): frequency "
                f"{percent(cc['frequency_rel_difference'])}, "
                f"modal mass {percent(cc['modal_mass_rel_difference'])}, "
                f"amplitude {percent(cc['amplitude_rel_difference'])}"
            )

    # 2. integrator rungs on the reference's (m, k, c), same duration as its run
    ref_mode = modes[0]
    dof = api.modal_dof(ref_mode, design)
    contact = api.contact_law(design)
    op = api.operating_point(design, rpm=DEFAULT_RPM, crab_velocity=DEFAULT_CRAB_VELOCITY_M_S)
    duration = float(ref["simulated_s"])
    it_rows = integrator_ladder(
        dof,
        contact,
        op,
        duration,
        rk4=q["rk4"] if q else RK4_LADDER,
        rtols=q["rtols"] if q else IVP_RTOLS,
        reference_rtol=q["reference_rtol"] if q else REFERENCE_RTOL,
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
    cross = next(
        (r for r in it_rows if r["method"] == "rk4" and r["parameter"] == CROSSCHECK_STEPS_PER_PERIOD), None
    )
    prod = next((r for r in it_rows if r["method"] == "rk4" and r["parameter"] == 48), None)
    integrator_info = {
        "reference": f"solve_ivp {IVP_METHOD} rtol {it_ref['parameter']:g}",
        "duration_s": duration,
        "mode": {
            "mass_kg": dof.mass_kg,
            "stiffness_n_m": dof.stiffness_n_m,
            "damping_ns_m": dof.damping_ns_m,
            "frequency_hz": dof.frequency_hz,
        },
        "crosscheck_rk4_256": (
            {k: cross[f"{k}_rel_error"] for k in ("amplitude", "time_to_saturation")} if cross else None
        ),
        "production_rk4_48": (
            {k: prod[f"{k}_rel_error"] for k in ("amplitude", "time_to_saturation")}
            | {"seconds": prod["seconds"]}
            if prod
            else None
        ),
    }
    summary = {
        "design": design.name,
        "quick": quick,
        "operating_point": {
            "rpm": DEFAULT_RPM,
            "crab_velocity_m_s": DEFAULT_CRAB_VELOCITY_M_S,
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
        f"800 RPM, Vc 0.39 m/s; errors relative to the reference):\n\n"
        + presets_table(presets)
        + "\n\n"
        + "\n".join(f"- {v}" for v in verdict)
        + "\n"
    )
    for v in verdict:
        say(v)
    say(f"done in {time.perf_counter() - t_start:.0f} s")
    return rows
