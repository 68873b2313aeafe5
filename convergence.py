"""Convergence study: the speed/accuracy trade of the modal solvers and the integrator.

For one wheel design at the default operating point (800 RPM, Vc = 0.39 m/s, the
(3,0) axial mode picked by :func:`pipeline.pick_mode`), :func:`run_convergence` runs

* the **modal solvers** over a ladder of mesh sizes (``elements_through_web``):
  axisymmetric P2 on straight triangles (``axisym-P2``, what the fidelity presets use),
  axisymmetric P2 on curved (isoparametric) triangles (``axisym-P2-curved``), 3-D P1
  (``3d-P1``, locks in bending), 3-D P2 on the curved second-order gmsh mesh
  (``3d-P2``, ``fem.solid.solve_solid``'s default) and 3-D P2 on the profile revolved
  in identical sectors, solved by cyclic symmetry (``3d-cyclic-P2``,
  ``fem.cyclic.solve_cyclic``; cheap enough to converge), all modes up to 5 kHz as the
  pipeline computes them. Per rung: DOFs, wall time (mesh + assembly + eigen-solve + labels: what a cold
  ``compute_modes`` costs), peak memory, the selected mode's frequency and contact
  modal mass, and the limit-cycle amplitude and time to saturation of
  :func:`pipeline.simulate` (production RK4) with that rung's (m, k, c);
* the **time integrator** on the reference rung's (m, k, c): fixed-step RK4 over a
  ladder of steps per period (raw: the production path's step cap and energy-balance
  refinement are off, so the ladder shows the scheme's own error; the ``note`` column
  says what production ``simulate`` does at that setting) and ``solve_ivp`` (DOP853)
  over a ladder of ``rtol``, amplitude and
  time to saturation against DOP853 at rtol 1e-10 (cross-checked with RK4 at 256
  steps per period).

References (stated in ``summary.json`` and the progress output):

* FE rungs: the **finest axisymmetric rung**, curved P2 with ``REFERENCE_ETW``
  (10) elements across the web (6 with ``quick=True``). Its own uncertainty is
  estimated by its change from the next-coarser curved rung and from the straight-P2
  rung of the same size; it is cross-checked against the finest 3-D P2 rungs (gmsh
  and cyclic). The
  amplitude and time-to-saturation errors of FE rungs use the same integrator for
  every rung, so they measure only the effect of the FE result on the squeal model.
* integrator rungs: DOP853 at rtol 1e-10 on the same duration.

Errors are signed relative errors ``value / reference - 1`` (CSV columns
``*_rel_error``); the plots show their magnitude. The time to saturation is the start
of a cycle (:mod:`reduced.limit_cycle`), so it moves in steps of one period (about
0.9 ms of about 0.4 s, i.e. 0.2 %): its error is either 0 or at least that quantum.

Wall time and memory are measured in a child process per run (``multiprocessing``
'fork' context): ``seconds`` is the median over ``repeats`` runs (3 for runs under
``REPEAT_BELOW_S``, else 1), ``peak_memory_mb`` the largest growth of the child's
peak RSS (``ru_maxrss``) over its starting value. On a busy shared machine the times
are noisy (a few 10 %); the errors are deterministic.

Outputs (written into ``out_dir``): ``convergence.csv`` (one row per rung),
``convergence_fe.png`` and ``convergence_integrator.png`` (error vs wall time,
log-log, one line per method, Pareto front dashed), ``summary.json`` (references,
cross-check, preset recommendation) and ``presets.md`` (the README table).

Run alone: ``python convergence.py [--design FILE] --out DIR [--quick]``.
"""

from __future__ import annotations

import argparse
import csv
import math
import os
import statistics
import sys
import time
from dataclasses import dataclass
from pathlib import Path
from typing import Any, Callable, Iterable, Sequence

import pipeline

# --------------------------------------------------------------------------------------
# ladders and targets
# --------------------------------------------------------------------------------------
#: elements across the web of the axisymmetric ladders (the reference is finer still)
AXISYM_LADDER = (1, 2, 3, 4, 6, 8)
#: the reference: curved axisymmetric P2 with this many elements across the web
REFERENCE_ETW = 10
#: 3-D ladders (elements across the web); a 3-D P2 run at 2 per web is ~180k DOFs
SOLID_P1_LADDER = (1, 2, 3, 4)
SOLID_P2_LADDER = (1, 2)
#: cyclic 3-D P2 (fem.cyclic; default sector count): 4 per web is 1.3M DOFs in ~5 s
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
QUICK = {
    "axisym": (1, 2, 3),
    "axisym_curved": (1, 2),
    "reference_etw": 6,
    "p1": (1,),
    "p2": (1,),
    "cyclic": (1, 2),
    "rk4": (16, 32, 48, 96),
    "rtols": (1e-5, 1e-7),
    "reference_rtol": 1e-9,
}

#: runs faster than this are repeated (median of REPEATS) to tame timing noise
REPEAT_BELOW_S = 2.0
REPEATS = 3

FMAX_HZ = 5000.0
DEFAULT_RPM = 800.0
DEFAULT_CRAB_VELOCITY = 0.39

#: preset aims (issue 6): fast -> modes < 2 s, frequency error < 1 %; accurate ->
#: errors < 0.1 %; accurate keeps a safety factor on that aim (other designs, the
#: reference's own error); balanced is the cheapest rung meeting the plain 0.1 % aim.
FAST_MAX_SECONDS = 2.0
FAST_MAX_ERROR = 0.01
ACCURATE_MAX_ERROR = 1e-3
ACCURATE_SAFETY = 3.0
#: run times within this fraction, or this many seconds, of the quickest count as a
#: tie (then fewer DOFs wins): the repeat spread of sub-second runs measured here on a
#: shared 2-core machine is about 0.05-0.1 s, larger than the differences between the
#: coarse axisymmetric rungs, whose cost is mostly fixed (meshing, harmonics, shapes)
TIME_TIE = 0.15
TIME_TIE_S = 0.1

ERROR_KEYS = ("frequency", "modal_mass", "amplitude", "time_to_saturation")

COLUMNS = [
    "study", "method", "parameter_name", "parameter", "reference", "dofs", "seconds",
    "repeats", "peak_memory_mb", "frequency_hz", "modal_mass_kg", "amplitude_m_s",
    "time_to_saturation_s", "frequency_rel_error", "modal_mass_rel_error",
    "amplitude_rel_error", "time_to_saturation_rel_error", "growth_rate_1_s",
    "limit_cycle_frequency_hz", "simulated_s", "step_s", "mode", "pareto", "note",
]

FE_METHODS = ("axisym-P2", "axisym-P2-curved", "3d-P1", "3d-P2", "3d-P2-straight", "3d-cyclic-P2")
METHOD_LABELS = {
    "axisym-P2": "axisym P2, straight (presets)",
    "axisym-P2-curved": "axisym P2, curved",
    "3d-P1": "3-D P1 (locks)",
    "3d-P2": "3-D P2, curved mesh",
    "3d-P2-straight": "3-D P2, straight mesh",
    "3d-cyclic-P2": "3-D P2, cyclic sectors",
    "rk4": "RK4 (numba), steps/period",
    f"solve_ivp-{IVP_METHOD}": f"solve_ivp {IVP_METHOD}, rtol",
}


class ConvergenceError(RuntimeError):
    """The study could not produce its reference (nothing to compare against)."""


# --------------------------------------------------------------------------------------
# measuring one run in a child process
# --------------------------------------------------------------------------------------
def _maxrss_mb() -> float:
    import resource

    return resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024.0  # KiB on Linux


def _fork_available() -> bool:
    import multiprocessing as mp

    try:
        import resource  # noqa: F401
    except ImportError:  # pragma: no cover - not POSIX
        return False
    return "fork" in mp.get_all_start_methods()


def measure(fn: Callable[[], Any], isolate: bool = True) -> tuple[Any, float, float]:
    """Run ``fn()`` and return ``(result, seconds, peak_memory_mb)``.

    With ``isolate`` (and a POSIX 'fork'), in a fresh child process: the peak memory is
    the growth of the child's peak RSS over its value at the start, so memory the
    parent already holds (imports, earlier rungs) is not counted. ``result`` must be
    picklable. Without isolation the memory is NaN. An exception in the child is
    re-raised in the parent as RuntimeError with the child's message; a child that
    dies (e.g. killed for memory) raises RuntimeError with its exit code.
    """
    if not (isolate and _fork_available()):
        t = time.perf_counter()
        out = fn()
        return out, time.perf_counter() - t, float("nan")
    import multiprocessing as mp

    ctx = mp.get_context("fork")
    recv, send = ctx.Pipe(duplex=False)

    def child() -> None:
        recv.close()
        try:
            base = _maxrss_mb()
            t = time.perf_counter()
            out = fn()
            dt = time.perf_counter() - t
            send.send((True, (out, dt, max(_maxrss_mb() - base, 0.0))))
        except BaseException as exc:  # noqa: BLE001 - reported to the parent
            msg = f"{type(exc).__name__}: {exc}".splitlines()[0]
            send.send((False, msg))
        finally:
            send.close()

    proc = ctx.Process(target=child, daemon=True)
    proc.start()
    send.close()
    try:
        msg = recv.recv()
    except EOFError:
        msg = None
    finally:
        recv.close()
        proc.join()
    if msg is None:
        raise RuntimeError(f"child process died (exit code {proc.exitcode}; out of memory?)")
    ok, payload = msg
    if not ok:
        raise RuntimeError(payload)
    return payload


def measure_repeated(fn: Callable[[], Any], isolate: bool = True,
                     repeat_below_s: float = REPEAT_BELOW_S, repeats: int = REPEATS):
    """:func:`measure` once, and ``repeats`` times in all if the first run was quick.

    Returns ``(result of the first run, median seconds, max peak memory MB, runs)``.
    """
    out, dt, mem = measure(fn, isolate)
    times, mems = [dt], [mem]
    if dt < repeat_below_s:
        for _ in range(repeats - 1):
            _, dt, mem = measure(fn, isolate)
            times.append(dt)
            mems.append(mem)
    finite = [m for m in mems if math.isfinite(m)]
    return out, statistics.median(times), (max(finite) if finite else float("nan")), len(times)


# --------------------------------------------------------------------------------------
# the rungs
# --------------------------------------------------------------------------------------
@dataclass(frozen=True)
class FERung:
    """One modal solve: ``method`` (see :data:`FE_METHODS`) with ``etw`` elements
    across the web."""

    method: str
    etw: int
    reference: bool = False

    def solve(self, design):
        """The ModeSet of this rung (meshes the design itself)."""
        if self.method in ("axisym-P2", "axisym-P2-curved"):
            from fem.axisym import solve_axisymmetric

            # curved=False: order-1 profile mesh + straight P2, as pipeline.compute_modes
            return solve_axisymmetric(design, order=2, elements_through_web=self.etw,
                                      curved=self.method.endswith("curved"), fmax_hz=FMAX_HZ)
        if self.method == "3d-cyclic-P2":
            from fem.cyclic import solve_cyclic

            return solve_cyclic(design, elements_through_web=self.etw, fmax_hz=FMAX_HZ)
        from fem.solid import solve_solid

        if self.method == "3d-P2-straight":
            from geometry.gmsh_mesh import mesh_wheel

            mesh = mesh_wheel(design, elements_through_web=self.etw, order=1)
            return solve_solid(design, mesh, order=2, fmax_hz=FMAX_HZ)
        order = {"3d-P1": 1, "3d-P2": 2}[self.method]
        return solve_solid(design, order=order, elements_through_web=self.etw, fmax_hz=FMAX_HZ)


def _fe_job(design, rung: FERung, mode: str) -> Callable[[], dict]:
    def job() -> dict:
        ms = rung.solve(design)
        m, why = pipeline.pick_mode(ms, mode)
        return {"dofs": int(ms.dofs), "mode": m, "why": why, "solver": ms.solver}

    return job


def _simulate_row(row: dict, mode, design, contact, op) -> None:
    """Fill the limit-cycle columns of an FE row from pipeline.simulate."""
    dof = pipeline.modal_dof(mode, design)
    sim = pipeline.simulate(dof, contact, op)
    lc = sim.limit_cycle
    row.update({
        "amplitude_m_s": float(lc.velocity_amplitude_m_s),
        "time_to_saturation_s": float(lc.time_to_saturation_s),
        "growth_rate_1_s": float(lc.growth_rate_1_s),
        "limit_cycle_frequency_hz": float(lc.frequency_hz),
        "simulated_s": float(sim.history.t[-1]),
        "step_s": float(sim.history.step_s),
    })
    if not lc.saturated:
        row["note"] = (row.get("note", "") + "; " if row.get("note") else "") + \
            "limit cycle not saturated"


def _blank_row(study: str, method: str, parameter_name: str, parameter) -> dict:
    row = {k: None for k in COLUMNS}
    row.update(study=study, method=method, parameter_name=parameter_name, parameter=parameter,
               reference=False, note="")
    return row


def fe_ladder(design, rungs: Sequence[FERung], *, mode: str = "auto", simulate: bool = True,
              isolate: bool = True, rpm: float = DEFAULT_RPM,
              crab_velocity: float = DEFAULT_CRAB_VELOCITY,
              progress: Callable[[str], None] | None = None) -> tuple[list[dict], dict]:
    """Run FE rungs; returns (rows, {row index: Mode}). Errors are not filled in here
    (see :func:`fill_errors`). A rung that fails gets a row with its message in
    ``note`` and empty results."""
    say = progress or (lambda _s: None)
    contact = pipeline.contact_law(design)
    op = pipeline.operating_point(design, rpm=rpm, crab_velocity=crab_velocity)
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
        row.update(dofs=out["dofs"], seconds=sec, repeats=n, peak_memory_mb=mem,
                   frequency_hz=float(m.frequency_hz), modal_mass_kg=float(m.modal_mass),
                   mode=m.label())
        if simulate:
            try:
                _simulate_row(row, m, design, contact, op)
            except Exception as exc:  # noqa: BLE001
                row["note"] = f"simulate failed: {exc}"
        modes[len(rows)] = m
        rows.append(row)
        amp = row["amplitude_m_s"]
        say(f"  {row['dofs']} DOFs, {sec:.2f} s (median of {n}), {mem:.0f} MB: "
            f"{m.label()} {m.frequency_hz:.3f} Hz, m = {m.modal_mass:.5f} kg"
            + (f", amplitude {amp:.5f} m/s" if amp is not None else ""))
    return rows, modes


def _integrator_job(dof, contact, op, duration: float, method: str, parameter) -> Callable[[], Any]:
    import reduced

    def job():
        t = time.perf_counter()
        if method == "rk4":
            # raw fixed-step RK4: no step cap, no energy-balance refinement (the
            # production path refines coarse steps; see the "note" column)
            hist = reduced.simulate(dof, contact, op, duration, step_s=1.0 / (dof.frequency_hz * parameter),
                                    refine=False, energy_tolerance=math.inf)
        else:
            hist = reduced.simulate_reference(dof, contact, op, duration, method=IVP_METHOD,
                                              rtol=float(parameter),
                                              samples_per_period=IVP_SAMPLES_PER_PERIOD)
        dt = time.perf_counter() - t
        lc = reduced.limit_cycle(hist)
        return {"seconds": dt, "amplitude": float(lc.velocity_amplitude_m_s),
                "tsat": float(lc.time_to_saturation_s), "growth": float(lc.growth_rate_1_s),
                "freq": float(lc.frequency_hz), "step": float(hist.step_s),
                "saturated": bool(lc.saturated)}

    return job


def integrator_ladder(dof, contact, op, duration: float, *, rk4=RK4_LADDER, rtols=IVP_RTOLS,
                      reference_rtol: float = REFERENCE_RTOL,
                      crosscheck_steps: int | None = CROSSCHECK_STEPS_PER_PERIOD,
                      isolate: bool = True,
                      progress: Callable[[str], None] | None = None) -> list[dict]:
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
        row.update(seconds=statistics.median(secs), repeats=len(secs), peak_memory_mb=mem,
                   amplitude_m_s=out["amplitude"], time_to_saturation_s=out["tsat"],
                   growth_rate_1_s=out["growth"], limit_cycle_frequency_hz=out["freq"],
                   simulated_s=duration, step_s=out["step"])
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
        say(f"  {row['seconds'] * 1e3:.1f} ms (median of {len(secs)}), amplitude "
            f"{out['amplitude']:.7f} m/s, saturated at {out['tsat']:.4f} s")
    return rows


# --------------------------------------------------------------------------------------
# errors, Pareto front, presets
# --------------------------------------------------------------------------------------
def _num(x) -> float:
    try:
        v = float(x)
    except (TypeError, ValueError):
        return float("nan")
    return v


_VALUE_KEYS = {"frequency": "frequency_hz", "modal_mass": "modal_mass_kg",
               "amplitude": "amplitude_m_s", "time_to_saturation": "time_to_saturation_s"}


def fill_errors(rows: list[dict], reference: dict, keys: Iterable[str] = ERROR_KEYS) -> None:
    """``<key>_rel_error = value / reference value - 1`` for each row (None if missing)."""
    for row in rows:
        for k in keys:
            v, r = _num(row.get(_VALUE_KEYS[k])), _num(reference.get(_VALUE_KEYS[k]))
            row[f"{k}_rel_error"] = (v / r - 1.0) if (math.isfinite(v) and math.isfinite(r)
                                                       and r != 0) else None


def pareto_front(points: Sequence[tuple[float, float]]) -> list[int]:
    """Indices of the points (time, error) no other point beats in both (>= in both,
    > in one); sorted by time."""
    idx = [i for i, (t, e) in enumerate(points) if math.isfinite(t) and math.isfinite(e)]
    front = []
    for i in idx:
        ti, ei = points[i]
        dominated = any(points[j][0] <= ti and points[j][1] <= ei and
                        (points[j][0] < ti or points[j][1] < ei) for j in idx if j != i)
        if not dominated:
            front.append(i)
    return sorted(front, key=lambda i: points[i][0])


def mark_pareto(rows: list[dict]) -> None:
    """Fill the ``pareto`` column: the error keys for which the row is on its study's
    front (references excluded: their error is zero by definition)."""
    for row in rows:
        row["pareto"] = ""
    for study in {r["study"] for r in rows}:
        cand = [r for r in rows if r["study"] == study and not r["reference"]]
        for k in ERROR_KEYS:
            pts = [(_num(r["seconds"]), abs(_num(r[f"{k}_rel_error"]))) for r in cand]
            for i in pareto_front(pts):
                cand[i]["pareto"] = ";".join(filter(None, [cand[i]["pareto"], k]))


def _max_error(row: dict, keys: Iterable[str]) -> float:
    vals = [abs(_num(row.get(f"{k}_rel_error"))) for k in keys]
    return max(vals) if vals and all(math.isfinite(v) for v in vals) else float("inf")


def _cheapest(rows: list[dict]) -> dict | None:
    """The quickest row; times within TIME_TIE / TIME_TIE_S of the quickest are a tie
    (timing noise), broken by fewer DOFs (deterministic), then the smaller
    frequency/modal-mass error."""
    if not rows:
        return None
    tmin = min(_num(r["seconds"]) for r in rows)
    ties = [r for r in rows if _num(r["seconds"]) <= max(tmin * (1 + TIME_TIE), tmin + TIME_TIE_S)]
    return min(ties, key=lambda r: (_num(r["dofs"]), _max_error(r, ("frequency", "modal_mass"))))


def choose_presets(rows: list[dict]) -> dict:
    """The fidelity presets from the measured front, and whether the current ones fit.

    Rules (FE rungs, references excluded; "errors" = frequency and contact modal mass,
    plus the limit-cycle amplitude for ``accurate``; the time to saturation is reported
    but not used, it moves in steps of one period, see the module docstring):

    * ``fast``: the cheapest rung with modes under ``FAST_MAX_SECONDS`` and frequency
      and modal-mass errors under ``FAST_MAX_ERROR`` (1 %);
    * ``balanced``: the cheapest rung with modes under ``FAST_MAX_SECONDS`` and errors
      under ``ACCURATE_MAX_ERROR`` (0.1 %), i.e. the accurate aim without margin;
    * ``accurate``: the cheapest rung with all three errors under
      ``ACCURATE_MAX_ERROR / ACCURATE_SAFETY`` (0.033 %), so the 0.1 % aim holds with a
      margin for other designs and for the reference's own error.

    "Cheapest": least wall time, times within ``TIME_TIE`` (15 %) or ``TIME_TIE_S``
    (0.1 s) of the quickest counting as equal (then fewer DOFs, then the smaller
    frequency/modal-mass error). Returns ``{preset: {method, elements_through_web, seconds, dofs,
    frequency_rel_error, modal_mass_rel_error, amplitude_rel_error,
    time_to_saturation_rel_error, current, matches_current, rule}}``; a preset no rung
    satisfies has ``method`` None.
    """
    fe = [r for r in rows if r["study"] == "fe" and not r["reference"]
          and math.isfinite(_num(r.get("seconds")))]
    rules = {
        "fast": (lambda r: _num(r["seconds"]) < FAST_MAX_SECONDS
                 and _max_error(r, ("frequency", "modal_mass")) < FAST_MAX_ERROR,
                 f"modes < {FAST_MAX_SECONDS:g} s, frequency and modal mass errors < "
                 f"{FAST_MAX_ERROR:.0%}"),
        "balanced": (lambda r: _num(r["seconds"]) < FAST_MAX_SECONDS
                     and _max_error(r, ("frequency", "modal_mass")) < ACCURATE_MAX_ERROR,
                     f"modes < {FAST_MAX_SECONDS:g} s, frequency and modal mass errors < "
                     f"{ACCURATE_MAX_ERROR:.1%}"),
        "accurate": (lambda r: _max_error(r, ("frequency", "modal_mass", "amplitude"))
                     < ACCURATE_MAX_ERROR / ACCURATE_SAFETY,
                     f"frequency, modal mass and amplitude errors < {ACCURATE_MAX_ERROR:.1%} "
                     f"/ {ACCURATE_SAFETY:g} (safety factor)"),
    }
    out = {}
    for name, (ok, text) in rules.items():
        pick = _cheapest([r for r in fe if ok(r)])
        cur = pipeline.FIDELITIES.get(name)
        cur_method = None
        if cur is not None:
            cur_method = ("axisym-P2" if cur.solver == "axisym" and cur.order == 2 else
                          f"{cur.solver}-P{cur.order}")
            cur_text = f"{cur.solver} P{cur.order}, {cur.elements_through_web} per web, mesh order {cur.mesh_order}"
        else:  # pragma: no cover
            cur_text = "(none)"
        entry = {"rule": text, "current": cur_text, "method": None, "elements_through_web": None,
                 "matches_current": False}
        if pick is not None:
            entry.update(method=pick["method"], elements_through_web=int(pick["parameter"]),
                         seconds=_num(pick["seconds"]), dofs=pick["dofs"],
                         **{f"{k}_rel_error": pick[f"{k}_rel_error"] for k in ERROR_KEYS})
            entry["matches_current"] = bool(
                cur is not None and pick["method"] == cur_method
                and int(pick["parameter"]) == cur.elements_through_web)
        # the measured errors of the current preset, for the table
        if cur is not None:
            now = [r for r in fe if r["method"] == cur_method
                   and int(_num(r["parameter"])) == cur.elements_through_web]
            if now:
                entry["current_measured"] = {
                    "seconds": _num(now[0]["seconds"]), "dofs": now[0]["dofs"],
                    **{f"{k}_rel_error": now[0][f"{k}_rel_error"] for k in ERROR_KEYS},
                    "meets_rule": bool(ok(now[0])),
                }
        out[name] = entry
    return out


def _pct(x) -> str:
    v = _num(x)
    if not math.isfinite(v):
        return "n/a"
    return f"{v * 100:+.3f} %" if abs(v) >= 5e-6 else f"{v * 100:+.1e} %"


def presets_table(presets: dict) -> str:
    """Markdown table of the recommended presets (for the README)."""
    lines = ["| preset | method | typical time (modes, 2 cores) | DOFs | frequency error | "
             "modal mass error | amplitude error | time-to-saturation error |",
             "|---|---|---|---|---|---|---|---|"]
    for name, p in presets.items():
        if p.get("method") is None:
            lines.append(f"| {name} | (no rung meets: {p['rule']}) | | | | | | |")
            continue
        meth = METHOD_LABELS.get(p["method"], p["method"])
        lines.append(
            f"| {name} | {meth}, {p['elements_through_web']} element(s) across the web | "
            f"{p['seconds']:.2f} s | {int(_num(p['dofs']))} | {_pct(p['frequency_rel_error'])} | "
            f"{_pct(p['modal_mass_rel_error'])} | {_pct(p['amplitude_rel_error'])} | "
            f"{_pct(p['time_to_saturation_rel_error'])} |")
    return "\n".join(lines)


def presets_verdict(presets: dict) -> list[str]:
    """One line per preset: supported by the measurements, or what to change."""
    out = []
    for name, p in presets.items():
        cm = p.get("current_measured")
        if p.get("method") is None:
            out.append(f"{name}: no measured rung meets the rule ({p['rule']}); keep {p['current']}.")
        elif p["matches_current"]:
            out.append(f"{name}: the measurements support the current preset ({p['current']}).")
        elif cm is not None and cm["meets_rule"]:
            out.append(f"{name}: the current preset ({p['current']}) meets the rule "
                       f"({p['rule']}) but {p['method']} with {p['elements_through_web']} per web "
                       f"is cheaper ({p['seconds']:.2f} s vs {cm['seconds']:.2f} s).")
        elif cm is None:
            out.append(f"{name}: {p['method']} with {p['elements_through_web']} per web fits "
                       f"({p['rule']}); the current preset ({p['current']}) was not measured.")
        else:
            out.append(f"{name}: change {p['current']} to {p['method']} with "
                       f"{p['elements_through_web']} per web (the current one does not meet: "
                       f"{p['rule']}).")
    return out


# --------------------------------------------------------------------------------------
# output files
# --------------------------------------------------------------------------------------
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
        rs = [r for r in rows if r["method"] == method and not r["reference"]
              and r.get("seconds") is not None and r.get(f"{key}_rel_error") is not None]
        if not rs:
            continue
        rs.sort(key=lambda r: _num(r["parameter"]), reverse=(method.startswith("solve_ivp")))
        t = [_num(r["seconds"]) for r in rs]
        e = [max(abs(_num(r[f"{key}_rel_error"])), ERROR_FLOOR) for r in rs]
        ax.plot(t, e, "o-", label=METHOD_LABELS.get(method, method), ms=4)
        for r, ti, ei in zip(rs, t, e):
            p = _num(r["parameter"])
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
        ax.text(0.99, FAST_MAX_ERROR, "fast aim 1 %", transform=ax.get_yaxis_transform(),
                ha="right", va="bottom", fontsize=7, color="grey")
        ax.text(0.99, ACCURATE_MAX_ERROR, "accurate aim 0.1 %", transform=ax.get_yaxis_transform(),
                ha="right", va="bottom", fontsize=7, color="grey")
    ax.set_xscale("log")
    ax.set_yscale("log")
    ax.set(xlabel="wall time [s]", ylabel="|relative error|", title=title)
    ax.grid(True, which="both", alpha=0.3)


def write_plots(rows: list[dict], out_dir: Path) -> list[Path]:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    paths = []
    fe = [r for r in rows if r["study"] == "fe"]
    if fe:
        fig, axes = plt.subplots(2, 2, figsize=(12, 9))
        for ax, (k, title) in zip(axes.flat, [
                ("frequency", "(3,0) mode frequency"), ("modal_mass", "contact modal mass"),
                ("amplitude", "limit-cycle amplitude (same RK4 for all)"),
                ("time_to_saturation", "time to saturation (1 period = ~0.2 %)")]):
            _plot_panel(ax, fe, k, title)
        axes[0, 0].legend(fontsize=7)
        fig.suptitle("Modal solvers: error vs wall time (mesh + modes <= 5 kHz); "
                     "labels: elements across the web; zero errors drawn at 1e-9", fontsize=10)
        fig.tight_layout()
        p = out_dir / "convergence_fe.png"
        fig.savefig(p, dpi=110)
        plt.close(fig)
        paths.append(p)
    it = [r for r in rows if r["study"] == "integrator"]
    if it:
        fig, axes = plt.subplots(1, 2, figsize=(12, 4.6))
        _plot_panel(axes[0], it, "amplitude", "limit-cycle amplitude")
        _plot_panel(axes[1], it, "time_to_saturation", "time to saturation")
        axes[0].legend(fontsize=7)
        fig.suptitle(f"Time integrator: error vs wall time (reference {IVP_METHOD} rtol "
                     f"{REFERENCE_RTOL:g}); labels: steps per period / rtol", fontsize=10)
        fig.tight_layout()
        p = out_dir / "convergence_integrator.png"
        fig.savefig(p, dpi=110)
        plt.close(fig)
        paths.append(p)
    return paths


# --------------------------------------------------------------------------------------
# the study
# --------------------------------------------------------------------------------------
def _warm_up(design) -> None:
    """Import and exercise the code paths once in this process so each child starts
    warm (imports, numba caches, lazily loaded libraries are not timed)."""
    import reduced
    from fem.axisym import small_problem_factorization, solve_axisymmetric
    from fem.eigen import available_factorizations
    from fem.cyclic import solve_cyclic  # noqa: F401
    from fem.solid import solve_solid  # noqa: F401

    small_problem_factorization()
    available_factorizations()
    solve_axisymmetric(design, elements_through_web=1, fmax_hz=1500.0)
    law = pipeline.contact_law(design)
    op = pipeline.operating_point(design)
    reduced.limit_cycle(reduced.simulate(reduced.ModalDOF(3.1, 1.6e8, 42.0), law, op, 0.01))


def run_convergence(design, out_dir, *, quick: bool = False,
                    progress: Callable[[str], None] | None = None,
                    isolate: bool = True) -> list[dict]:
    """Run the convergence study on ``design`` and write its files into ``out_dir``.

    ``design``: a ``WheelDesign`` (or a TOML path / None for Table 1). ``quick``: only
    the cheapest rungs (reference: curved axisym P2, 6 per web). ``progress``: called
    with one line of text per step. ``isolate``: measure each run in a forked child
    (peak memory); False runs in-process (memory NaN). Returns the rows of
    ``convergence.csv`` (dicts keyed by :data:`COLUMNS`).
    """
    if design is None or isinstance(design, (str, Path)):
        design = pipeline.load_design(design)
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
    rungs += [FERung("3d-P1", e) for e in p1]
    rungs += [FERung("3d-P2", e) for e in p2]
    rungs += [FERung("3d-cyclic-P2", e) for e in cyclic]
    if not quick:
        rungs.append(FERung("3d-P2-straight", 1))
    fe_rows, modes = fe_ladder(design, rungs, isolate=isolate, progress=say)
    ref = fe_rows[0]
    if ref["frequency_hz"] is None or ref["amplitude_m_s"] is None:
        raise ConvergenceError(f"reference rung failed: {ref['note']}")
    fill_errors(fe_rows, ref)

    # the reference's own uncertainty and the 3-D cross-check
    def _rel(a: dict, key: str) -> float | None:
        v, r = _num(a.get(_VALUE_KEYS[key])), _num(ref.get(_VALUE_KEYS[key]))
        return v / r - 1 if math.isfinite(v) and math.isfinite(r) else None

    finer = [r for r in fe_rows if not r["reference"] and r["frequency_hz"] is not None]
    next_curved = max((r for r in finer if r["method"] == "axisym-P2-curved"),
                      key=lambda r: r["parameter"], default=None)
    straight_same = next((r for r in finer if r["method"] == "axisym-P2"
                          and r["parameter"] == ref_etw), None)
    p2_rows = [r for r in finer if r["method"] == "3d-P2"]
    finest_p2 = max(p2_rows, key=lambda r: r["parameter"], default=None)
    finest_cyc = max((r for r in finer if r["method"] == "3d-cyclic-P2"),
                     key=lambda r: r["parameter"], default=None)
    reference_info = {
        "rung": f"axisym-P2-curved, {ref_etw} elements across the web",
        "dofs": ref["dofs"], "seconds": ref["seconds"],
        "frequency_hz": ref["frequency_hz"], "modal_mass_kg": ref["modal_mass_kg"],
        "amplitude_m_s": ref["amplitude_m_s"], "time_to_saturation_s": ref["time_to_saturation_s"],
        "mode": ref["mode"],
        "self_convergence": {
            "vs": (f"axisym-P2-curved, {next_curved['parameter']} per web" if next_curved else None),
            **({f"{k}_rel_change": _rel(next_curved, k) for k in ("frequency", "modal_mass")}
               if next_curved else {}),
        },
        "crosscheck_3d_p2": ({"rung": f"3d-P2, {finest_p2['parameter']} per web",
                              "dofs": finest_p2["dofs"],
                              **{f"{k}_rel_difference": _rel(finest_p2, k) for k in ERROR_KEYS}}
                             if finest_p2 else None),
        "crosscheck_3d_cyclic": ({"rung": f"3d-cyclic-P2, {finest_cyc['parameter']} per web",
                                  "dofs": finest_cyc["dofs"],
                                  **{f"{k}_rel_difference": _rel(finest_cyc, k) for k in ERROR_KEYS}}
                                 if finest_cyc else None),
    }
    if straight_same is not None:
        reference_info["straight_p2_same_mesh"] = {
            f"{k}_rel_difference": _rel(straight_same, k) for k in ("frequency", "modal_mass")}
    say(f"reference: {reference_info['rung']}: {ref['frequency_hz']:.4f} Hz, "
        f"m = {ref['modal_mass_kg']:.6f} kg, amplitude {ref['amplitude_m_s']:.6f} m/s")
    if next_curved:
        sc = reference_info["self_convergence"]
        say(f"  reference self-convergence (vs {sc['vs']}): frequency {_pct(sc['frequency_rel_change'])}, "
            f"modal mass {_pct(sc['modal_mass_rel_change'])}")
    if finest_p2:
        cc = reference_info["crosscheck_3d_p2"]
        say(f"  cross-check {cc['rung']} ({cc['dofs']} DOFs): frequency "
            f"{_pct(cc['frequency_rel_difference'])}, modal mass {_pct(cc['modal_mass_rel_difference'])}, "
            f"amplitude {_pct(cc['amplitude_rel_difference'])}")
    if finest_cyc:
        cc = reference_info["crosscheck_3d_cyclic"]
        say(f"  cross-check {cc['rung']} ({cc['dofs']} DOFs): frequency "
            f"{_pct(cc['frequency_rel_difference'])}, modal mass {_pct(cc['modal_mass_rel_difference'])}, "
            f"amplitude {_pct(cc['amplitude_rel_difference'])}")

    # 2. integrator rungs on the reference's (m, k, c), same duration as its run
    ref_mode = modes[0]
    dof = pipeline.modal_dof(ref_mode, design)
    contact = pipeline.contact_law(design)
    op = pipeline.operating_point(design, rpm=DEFAULT_RPM, crab_velocity=DEFAULT_CRAB_VELOCITY)
    duration = float(ref["simulated_s"])
    it_rows = integrator_ladder(
        dof, contact, op, duration, rk4=q["rk4"] if q else RK4_LADDER,
        rtols=q["rtols"] if q else IVP_RTOLS,
        reference_rtol=q["reference_rtol"] if q else REFERENCE_RTOL,
        crosscheck_steps=None if quick else CROSSCHECK_STEPS_PER_PERIOD,
        isolate=isolate, progress=say)
    it_ref = next((r for r in it_rows if r["reference"]), None)
    if it_ref is None or it_ref["amplitude_m_s"] is None:
        raise ConvergenceError("integrator reference failed: " + (it_ref or {}).get("note", ""))
    fill_errors(it_rows, it_ref, keys=("amplitude", "time_to_saturation"))

    rows = fe_rows + it_rows
    mark_pareto(rows)
    presets = choose_presets(rows)
    verdict = presets_verdict(presets)
    cross = next((r for r in it_rows if r["method"] == "rk4"
                  and r["parameter"] == CROSSCHECK_STEPS_PER_PERIOD), None)
    prod = next((r for r in it_rows if r["method"] == "rk4" and r["parameter"] == 48), None)
    integrator_info = {
        "reference": f"solve_ivp {IVP_METHOD} rtol {it_ref['parameter']:g}",
        "duration_s": duration,
        "mode": {"mass_kg": dof.mass_kg, "stiffness_n_m": dof.stiffness_n_m,
                 "damping_ns_m": dof.damping_ns_m, "frequency_hz": dof.frequency_hz},
        "crosscheck_rk4_256": ({k: cross[f"{k}_rel_error"] for k in ("amplitude", "time_to_saturation")}
                               if cross else None),
        "production_rk4_48": ({k: prod[f"{k}_rel_error"] for k in ("amplitude", "time_to_saturation")}
                              | {"seconds": prod["seconds"]} if prod else None),
    }
    summary = {
        "design": design.name, "quick": quick,
        "operating_point": {"rpm": DEFAULT_RPM, "crab_velocity_m_s": DEFAULT_CRAB_VELOCITY,
                            "rolling_speed_m_s": op.rolling_speed_m_s},
        "fmax_hz": FMAX_HZ, "fe_reference": reference_info, "integrator": integrator_info,
        "presets": presets, "verdict": verdict,
        "machine": {"nproc": os.cpu_count(), "loadavg": list(os.getloadavg())
                    if hasattr(os, "getloadavg") else None},
        "seconds_total": time.perf_counter() - t_start,
    }
    write_csv(rows, out_dir / "convergence.csv")
    write_plots(rows, out_dir)
    pipeline.write_json(out_dir / "summary.json", summary)
    (out_dir / "presets.md").write_text(
        f"Presets measured on {design.name} (reference: {reference_info['rung']}; "
        f"800 RPM, Vc 0.39 m/s; errors relative to the reference):\n\n"
        + presets_table(presets) + "\n\n" + "\n".join(f"- {v}" for v in verdict) + "\n")
    for v in verdict:
        say(v)
    say(f"done in {time.perf_counter() - t_start:.0f} s -> {out_dir}")
    return rows


def format_table(rows: list[dict]) -> str:
    """A plain-text table of the rows (what ``python convergence.py`` prints)."""
    head = (f"{'study':<10} {'method':<20} {'param':>7} {'DOFs':>7} {'time s':>8} {'MB':>6} "
            f"{'f Hz':>10} {'df/f':>10} {'m kg':>8} {'dm/m':>10} {'amp m/s':>9} {'damp':>10} "
            f"{'tsat s':>7} {'dtsat':>9} front")
    lines = [head]
    for r in rows:
        def g(k, fmt):
            v = _num(r.get(k))
            return format(v, fmt) if math.isfinite(v) else "-"
        lines.append(
            f"{r['study']:<10} {r['method'] + ('*' if r['reference'] else ''):<20} "
            f"{_num(r['parameter']):>7g} {g('dofs', '7.0f'):>7} {g('seconds', '8.3f'):>8} "
            f"{g('peak_memory_mb', '6.0f'):>6} {g('frequency_hz', '10.3f'):>10} "
            f"{_pct(r.get('frequency_rel_error')) if r['study'] == 'fe' else '-':>10} "
            f"{g('modal_mass_kg', '8.4f'):>8} "
            f"{_pct(r.get('modal_mass_rel_error')) if r['study'] == 'fe' else '-':>10} "
            f"{g('amplitude_m_s', '9.6f'):>9} {_pct(r.get('amplitude_rel_error')):>10} "
            f"{g('time_to_saturation_s', '7.4f'):>7} {_pct(r.get('time_to_saturation_rel_error')):>9} "
            f"{r.get('pareto') or ''}" + (f"  [{r['note']}]" if r.get("note") else ""))
    lines.append("* reference rung; errors are value/reference - 1")
    return "\n".join(lines)


def main(argv: Sequence[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--design", type=Path, help="design TOML (default designs/table1.toml)")
    ap.add_argument("--out", type=Path, required=True, help="output folder (written atomically)")
    ap.add_argument("--quick", action="store_true", help="only the cheapest rungs")
    ap.add_argument("--quiet", action="store_true")
    args = ap.parse_args(argv)
    design = pipeline.load_design(args.design)
    prog = pipeline.Progress(args.quiet)
    with pipeline.output_folder(args.out) as tmp:
        rows = run_convergence(design, tmp, quick=args.quick, progress=prog.say)
    print(format_table(rows))
    print()
    print((args.out / "presets.md").read_text())
    return 0


if __name__ == "__main__":
    sys.exit(main())
