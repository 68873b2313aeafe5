"""The rungs of the convergence study: modal solves over mesh ladders, and the time
integrator over steps per period and tolerances.

An FE rung is a method (``fem.solvers.method_label``: ``axisym-P2``,
``axisym-P2-curved``, ``3d-P2``, ``3d-tet-P1``, ``3d-tet-P2``, ``3d-tet-P2-straight``)
at a number of elements across the web. Per rung: DOFs, wall time (mesh + assembly +
eigen-solve + labels: what a cold ``compute_modes`` costs), peak memory, the (3,0)
mode's frequency and contact modal mass, and the limit cycle of the production
simulation with that rung's (m, k, c). Integrator rungs: raw fixed-step RK4 (no step
cap, no energy-balance refinement: the scheme's own error; the ``note`` column says
what the production path does there) and ``solve_ivp`` over a ladder of ``rtol``.
"""

from __future__ import annotations

import math
import statistics
import time
from collections.abc import Callable, Sequence
from dataclasses import dataclass
from typing import Any

from .. import api
from ..design import Design
from ..presets import DEFAULT_CRAB_VELOCITY_M_S, DEFAULT_FMAX_HZ, DEFAULT_RPM
from ..simulation import simulate
from .measure import REPEAT_BELOW_S, REPEATS, measure, measure_repeated

__all__ = ["COLUMNS", "FERung", "fe_ladder", "integrator_ladder"]

#: elements across the web of the axisymmetric ladders (the reference is finer still)
AXISYM_LADDER = (1, 2, 3, 4, 6, 8)
#: the reference: curved axisymmetric P2 with this many elements across the web
REFERENCE_ETW = 10
#: 3-D ladders (elements across the web); a 3-D P2 run at 2 per web is ~180k DOFs
SOLID_P1_LADDER = (1, 2, 3, 4)
SOLID_P2_LADDER = (1, 2)
#: cyclic 3-D P2 (fem.cyclic; default sector count): 4 per web is 1.3M DOFs
CYCLIC_LADDER = (1, 2, 4)
#: RK4 steps per period and solve_ivp rtol ladders; their reference
RK4_LADDER = (12, 16, 24, 32, 48, 64, 96, 128)
IVP_RTOLS = (1e-4, 1e-5, 1e-6, 1e-7, 1e-8, 1e-9)
IVP_METHOD = "DOP853"
REFERENCE_RTOL = 1e-10
CROSSCHECK_STEPS_PER_PERIOD = 256
#: solve_ivp output samples per period: the amplitude is read from sampled peaks
#: (parabolic refinement), whose error at the default 64 samples is ~2e-6, above the
#: reference's integration error; 256 puts the read-out error below 1e-8
IVP_SAMPLES_PER_PERIOD = 256


#: ``quick=True``: the cheapest rungs only (seconds in total on 2 cores)
@dataclass(frozen=True)
class Ladders:
    """The rungs of a convergence study: elements across the web per FE method, RK4
    steps per period, solve_ivp tolerances and the two references."""

    axisym: tuple[int, ...] = AXISYM_LADDER
    axisym_curved: tuple[int, ...] = AXISYM_LADDER
    reference_etw: int = REFERENCE_ETW
    p1: tuple[int, ...] = SOLID_P1_LADDER
    p2: tuple[int, ...] = SOLID_P2_LADDER
    cyclic: tuple[int, ...] = CYCLIC_LADDER
    rk4: tuple[int, ...] = RK4_LADDER
    rtols: tuple[float, ...] = IVP_RTOLS
    reference_rtol: float = REFERENCE_RTOL


QUICK = Ladders(
    axisym=(1, 2, 3),
    axisym_curved=(1, 2),
    reference_etw=6,
    p1=(1,),
    p2=(1,),
    cyclic=(1, 2),
    rk4=(16, 32, 48, 96),
    rtols=(1e-5, 1e-7),
    reference_rtol=1e-9,
)
COLUMNS = [
    "study",
    "method",
    "parameter_name",
    "parameter",
    "reference",
    "dofs",
    "seconds",
    "repeats",
    "peak_memory_mb",
    "frequency_hz",
    "modal_mass_kg",
    "amplitude_m_s",
    "time_to_saturation_s",
    "frequency_rel_error",
    "modal_mass_rel_error",
    "amplitude_rel_error",
    "time_to_saturation_rel_error",
    "growth_rate_1_s",
    "limit_cycle_frequency_hz",
    "simulated_s",
    "step_s",
    "mode",
    "pareto",
    "note",
]


@dataclass(frozen=True)
class FERung:
    """One modal solve: ``method`` (a ``fem.solvers.method_label``) with ``etw``
    elements across the web."""

    method: str
    etw: int
    reference: bool = False

    def solve(self, design: Design) -> Any:
        """The ModeSet of this rung (meshes the design itself)."""
        from fem.solvers import SOLVERS, parse_method, solve_modes
        from geometry import mesh_profile, mesh_wheel

        solver, order, mesh_order = parse_method(self.method)
        mesher = mesh_wheel if SOLVERS[solver].mesh_dim == 3 else mesh_profile
        mesh = mesher(design.wheel, elements_through_web=self.etw, order=mesh_order)
        return solve_modes(
            design.wheel, mesh, solver, order=order, fmax_hz=DEFAULT_FMAX_HZ, contact=design.contact_frame
        )


def _fe_job(design: Design, rung: FERung, mode: str) -> Callable[[], dict]:
    def job() -> dict:
        ms = rung.solve(design)
        m, why = api.pick_mode(ms, mode)
        return {"dofs": int(ms.dofs), "mode": m, "why": why, "solver": ms.solver}

    return job


def _simulate_row(row: dict, mode: Any, design: Design, contact: Any, op: Any) -> None:
    """Fill the limit-cycle columns of an FE row from the production simulation."""
    dof = api.modal_dof(mode, design)
    sim = simulate(dof, contact, op)
    lc = sim.limit_cycle
    row.update(
        {
            "amplitude_m_s": float(lc.velocity_amplitude_m_s),
            "time_to_saturation_s": float(lc.time_to_saturation_s),
            "growth_rate_1_s": float(lc.envelope_growth_rate_1_s),
            "limit_cycle_frequency_hz": float(lc.frequency_hz),
            "simulated_s": float(sim.history.t[-1]),
            "step_s": float(sim.history.step_s),
        }
    )
    if not lc.saturated:
        row["note"] = (row.get("note", "") + "; " if row.get("note") else "") + "limit cycle not saturated"


def _blank_row(study: str, method: str, parameter_name: str, parameter: Any) -> dict:
    row: dict[str, Any] = dict.fromkeys(COLUMNS)
    row.update(
        study=study,
        method=method,
        parameter_name=parameter_name,
        parameter=parameter,
        reference=False,
        note="",
    )
    return row


def fe_ladder(
    design: Design,
    rungs: Sequence[FERung],
    *,
    mode: str = "default",
    simulate: bool = True,
    isolate: bool = True,
    rpm: float = DEFAULT_RPM,
    crab_velocity: float = DEFAULT_CRAB_VELOCITY_M_S,
    progress: Callable[[str], None] | None = None,
) -> tuple[list[dict], dict]:
    """Run FE rungs; returns (rows, {row index: Mode}). Errors are not filled in here
    (see :func:`fill_errors`). A rung that fails gets a row with its message in
    ``note`` and empty results."""
    say = progress or (lambda _s: None)
    contact = api.contact_law(design)
    op = api.operating_point(design, rpm=rpm, crabbing_velocity_m_s=crab_velocity)
    rows, modes = [], {}
    for rung in rungs:
        row = _blank_row("fe", rung.method, "elements_through_web", rung.etw)
        row["reference"] = rung.reference
        say(f"{rung.method}, {rung.etw} per web{' (reference)' if rung.reference else ''} ...")
        try:
            out, sec, mem, n = measure_repeated(_fe_job(design, rung, mode), isolate)
        except Exception as exc:  # noqa: BLE001 - one failed rung must not end the study
            row["note"] = f"failed: {exc}"
            say(f"  failed: {exc}")
            rows.append(row)
            continue
        m = out["mode"]
        row.update(
            dofs=out["dofs"],
            seconds=sec,
            repeats=n,
            peak_memory_mb=mem,
            frequency_hz=float(m.frequency_hz),
            modal_mass_kg=float(m.modal_mass),
            mode=m.label(),
        )
        if simulate:
            try:
                _simulate_row(row, m, design, contact, op)
            except Exception as exc:  # noqa: BLE001
                row["note"] = f"simulate failed: {exc}"
        modes[len(rows)] = m
        rows.append(row)
        amp = row["amplitude_m_s"]
        say(
            f"  {row['dofs']} DOFs, {sec:.2f} s (median of {n}), {mem:.0f} MB: "
            f"{m.label()} {m.frequency_hz:.3f} Hz, m = {m.modal_mass:.5f} kg"
            + (f", amplitude {amp:.5f} m/s" if amp is not None else "")
        )
    return rows, modes


def _integrator_job(
    dof: Any, contact: Any, op: Any, duration: float, method: str, parameter: Any
) -> Callable[[], Any]:
    import reduced

    def job() -> Any:
        t = time.perf_counter()
        if method == "rk4":
            # raw fixed-step RK4: no step cap, no energy-balance refinement (the
            # production path refines coarse steps; see the "note" column)
            hist = reduced.simulate(
                dof,
                contact,
                op,
                duration,
                step_s=1.0 / (dof.frequency_hz * parameter),
                refine=False,
                energy_tolerance=math.inf,
            )
        else:
            hist = reduced.simulate_reference(
                dof,
                contact,
                op,
                duration,
                method=IVP_METHOD,
                rtol=float(parameter),
                samples_per_period=IVP_SAMPLES_PER_PERIOD,
            )
        dt = time.perf_counter() - t
        lc = reduced.limit_cycle(hist)
        return {
            "seconds": dt,
            "amplitude": float(lc.velocity_amplitude_m_s),
            "tsat": float(lc.time_to_saturation_s),
            "growth": float(lc.envelope_growth_rate_1_s),
            "freq": float(lc.frequency_hz),
            "step": float(hist.step_s),
            "saturated": bool(lc.saturated),
        }

    return job


def integrator_ladder(
    dof: Any,
    contact: Any,
    op: Any,
    duration: float,
    *,
    rk4: Sequence[float] = RK4_LADDER,
    rtols: Sequence[float] = IVP_RTOLS,
    reference_rtol: float = REFERENCE_RTOL,
    crosscheck_steps: int | None = CROSSCHECK_STEPS_PER_PERIOD,
    isolate: bool = True,
    progress: Callable[[str], None] | None = None,
) -> list[dict]:
    """RK4 over ``rk4`` steps per period and solve_ivp over ``rtols``, plus the
    reference (DOP853 at ``reference_rtol``, flagged ``reference``) and the RK4
    cross-check at ``crosscheck_steps``. The integration alone is timed (the
    limit-cycle reduction afterwards is the same for every rung)."""
    from reduced import simulate as reduced_simulate

    say = progress or (lambda _s: None)
    ivp = f"solve_ivp-{IVP_METHOD}"
    plan = [("rk4", "steps_per_period", s, False) for s in rk4]
    if crosscheck_steps:
        plan.append(("rk4", "steps_per_period", crosscheck_steps, False))
    plan += [(ivp, "rtol", r, False) for r in rtols]
    plan.append((ivp, "rtol", reference_rtol, True))
    rows = []
    for method, pname, p, ref in plan:
        row = _blank_row("integrator", method, pname, p)
        row["reference"] = ref
        say(f"{method} {pname} {p:g}{' (reference)' if ref else ''} ...")
        try:
            job = _integrator_job(dof, contact, op, duration, method, p)
            out, _, mem = measure(job, isolate)
            # the integration alone is timed (inside the job); quick runs are repeated
            secs, mems = [out["seconds"]], [mem]
            if out["seconds"] < REPEAT_BELOW_S:
                for _ in range((5 if method == "rk4" else REPEATS) - 1):
                    o, _, m_ = measure(job, isolate)
                    secs.append(o["seconds"])
                    mems.append(m_)
            mem = max(mems)
        except Exception as exc:  # noqa: BLE001
            row["note"] = f"failed: {exc}"
            say(f"  failed: {exc}")
            rows.append(row)
            continue
        row.update(
            seconds=statistics.median(secs),
            repeats=len(secs),
            peak_memory_mb=mem,
            amplitude_m_s=out["amplitude"],
            time_to_saturation_s=out["tsat"],
            growth_rate_1_s=out["growth"],
            limit_cycle_frequency_hz=out["freq"],
            simulated_s=duration,
            step_s=out["step"],
        )
        if method == "rk4":
            # what the production path (step cap + energy-balance refinement) does here
            try:
                prod = reduced_simulate(dof, contact, op, duration, steps_per_period=int(p))
                eff = 1.0 / (dof.frequency_hz * prod.step_s)
                if abs(eff - p) > 0.5:
                    row["note"] = f"production simulate(steps_per_period={p}) runs {eff:.0f} steps/period"
            except Exception as exc:  # noqa: BLE001
                row["note"] = f"production simulate refuses: {str(exc).splitlines()[0][:80]}"
        if not out["saturated"]:
            row["note"] = (row["note"] + "; " if row["note"] else "") + "limit cycle not saturated"
        rows.append(row)
        say(
            f"  {row['seconds'] * 1e3:.1f} ms (median of {len(secs)}), amplitude "
            f"{out['amplitude']:.7f} m/s, saturated at {out['tsat']:.4f} s"
        )
    return rows
