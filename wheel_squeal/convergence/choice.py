"""From the rungs to the presets: relative errors, the Pareto front of error against
time, and the cheapest rung that meets each preset's aim."""

from __future__ import annotations

import math
from collections.abc import Iterable, Sequence
from typing import Any

from ..presets import FIDELITIES

__all__ = [
    "ERROR_KEYS",
    "as_number",
    "choose_presets",
    "fill_errors",
    "mark_pareto",
    "pareto_front",
    "percent",
    "presets_table",
    "presets_verdict",
]

#: preset aims: fast -> modes < 2 s, frequency error < 1 %; accurate ->
#: errors < 0.1 %; accurate keeps a safety factor on that aim (other designs, the
#: reference's own error); balanced is the cheapest rung meeting the plain 0.1 % aim.
FAST_MAX_SECONDS = 2.0
FAST_MAX_ERROR = 0.01
ACCURATE_MAX_ERROR = 1e-3
ACCURATE_SAFETY = 3.0
#: run times within this fraction, or this many seconds, of the quickest count as a
#: tie (then fewer DOFs wins): the repeat spread of sub-second runs on a shared machine
#: is larger than the differences between the coarse axisymmetric rungs, whose cost is
#: mostly fixed (meshing, harmonics, shapes)
TIME_TIE = 0.15
TIME_TIE_S = 0.1
ERROR_KEYS = ("frequency", "modal_mass", "amplitude", "time_to_saturation")


def as_number(x: Any) -> float:
    """``float(x)``, or NaN for None and text that is not a number (empty CSV cells)."""
    try:
        v = float(x)
    except (TypeError, ValueError):
        return float("nan")
    return v


VALUE_KEYS = {
    "frequency": "frequency_hz",
    "modal_mass": "modal_mass_kg",
    "amplitude": "amplitude_m_s",
    "time_to_saturation": "time_to_saturation_s",
}


def fill_errors(rows: list[dict], reference: dict, keys: Iterable[str] = ERROR_KEYS) -> None:
    """``<key>_rel_error = value / reference value - 1`` for each row (None if missing)."""
    for row in rows:
        for k in keys:
            v, r = as_number(row.get(VALUE_KEYS[k])), as_number(reference.get(VALUE_KEYS[k]))
            row[f"{k}_rel_error"] = (
                (v / r - 1.0) if (math.isfinite(v) and math.isfinite(r) and r != 0) else None
            )


def pareto_front(points: Sequence[tuple[float, float]]) -> list[int]:
    """Indices of the points (time, error) no other point beats in both (>= in both,
    > in one); sorted by time."""
    idx = [i for i, (t, e) in enumerate(points) if math.isfinite(t) and math.isfinite(e)]
    front = []
    for i in idx:
        ti, ei = points[i]
        dominated = any(
            points[j][0] <= ti and points[j][1] <= ei and (points[j][0] < ti or points[j][1] < ei)
            for j in idx
            if j != i
        )
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
            pts = [(as_number(r["seconds"]), abs(as_number(r[f"{k}_rel_error"]))) for r in cand]
            for i in pareto_front(pts):
                cand[i]["pareto"] = ";".join(filter(None, [cand[i]["pareto"], k]))


def _max_error(row: dict, keys: Iterable[str]) -> float:
    vals = [abs(as_number(row.get(f"{k}_rel_error"))) for k in keys]
    return max(vals) if vals and all(math.isfinite(v) for v in vals) else float("inf")


def _cheapest(rows: list[dict]) -> dict | None:
    """The quickest row; times within TIME_TIE / TIME_TIE_S of the quickest are a tie
    (timing noise), broken by fewer DOFs (deterministic), then the smaller
    frequency/modal-mass error."""
    if not rows:
        return None
    tmin = min(as_number(r["seconds"]) for r in rows)
    ties = [r for r in rows if as_number(r["seconds"]) <= max(tmin * (1 + TIME_TIE), tmin + TIME_TIE_S)]
    return min(ties, key=lambda r: (as_number(r["dofs"]), _max_error(r, ("frequency", "modal_mass"))))


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
    fe = [
        r
        for r in rows
        if r["study"] == "fe" and not r["reference"] and math.isfinite(as_number(r.get("seconds")))
    ]
    rules = {
        "fast": (
            lambda r: (
                as_number(r["seconds"]) < FAST_MAX_SECONDS
                and _max_error(r, ("frequency", "modal_mass")) < FAST_MAX_ERROR
            ),
            f"modes < {FAST_MAX_SECONDS:g} s, frequency and modal mass errors < {FAST_MAX_ERROR:.0%}",
        ),
        "balanced": (
            lambda r: (
                as_number(r["seconds"]) < FAST_MAX_SECONDS
                and _max_error(r, ("frequency", "modal_mass")) < ACCURATE_MAX_ERROR
            ),
            f"modes < {FAST_MAX_SECONDS:g} s, frequency and modal mass errors < {ACCURATE_MAX_ERROR:.1%}",
        ),
        "accurate": (
            lambda r: (
                _max_error(r, ("frequency", "modal_mass", "amplitude")) < ACCURATE_MAX_ERROR / ACCURATE_SAFETY
            ),
            f"frequency, modal mass and amplitude errors < {ACCURATE_MAX_ERROR:.1%} "
            f"/ {ACCURATE_SAFETY:g} (safety factor)",
        ),
    }
    out = {}
    for name, (ok, text) in rules.items():
        pick = _cheapest([r for r in fe if ok(r)])
        cur = FIDELITIES.get(name)
        cur_method = None
        if cur is not None:
            cur_method = cur.method
            cur_text = (
                f"{cur.solver} P{cur.order}, {cur.elements_through_web} per web, mesh order {cur.mesh_order}"
            )
        else:  # pragma: no cover
            cur_text = "(none)"
        entry: dict[str, Any] = {
            "rule": text,
            "current": cur_text,
            "method": None,
            "elements_through_web": None,
            "matches_current": False,
        }
        if pick is not None:
            entry.update(
                method=pick["method"],
                elements_through_web=int(pick["parameter"]),
                seconds=as_number(pick["seconds"]),
                dofs=pick["dofs"],
                **{f"{k}_rel_error": pick[f"{k}_rel_error"] for k in ERROR_KEYS},
            )
            entry["matches_current"] = bool(
                cur is not None
                and pick["method"] == cur_method
                and int(pick["parameter"]) == cur.elements_through_web
            )
        # the measured errors of the current preset, for the table
        if cur is not None:
            now = [
                r
                for r in fe
                if r["method"] == cur_method and int(as_number(r["parameter"])) == cur.elements_through_web
            ]
            if now:
                entry["current_measured"] = {
                    "seconds": as_number(now[0]["seconds"]),
                    "dofs": now[0]["dofs"],
                    **{f"{k}_rel_error": now[0][f"{k}_rel_error"] for k in ERROR_KEYS},
                    "meets_rule": bool(ok(now[0])),
                }
        out[name] = entry
    return out


def percent(x: Any) -> str:
    """A relative error as a signed percentage (``+0.135 %``), ``n/a`` when missing."""
    v = as_number(x)
    if not math.isfinite(v):
        return "n/a"
    return f"{v * 100:+.3f} %" if abs(v) >= 5e-6 else f"{v * 100:+.1e} %"


def presets_table(presets: dict) -> str:
    """Markdown table of the recommended presets (for the README)."""
    lines = [
        "| preset | method | typical time (modes, 2 cores) | DOFs | frequency error | "
        "modal mass error | amplitude error | time-to-saturation error |",
        "|---|---|---|---|---|---|---|---|",
    ]
    for name, p in presets.items():
        if p.get("method") is None:
            lines.append(f"| {name} | (no rung meets: {p['rule']}) | | | | | | |")
            continue
        meth = p["method"]
        lines.append(
            f"| {name} | {meth}, {p['elements_through_web']} element(s) across the web | "
            f"{p['seconds']:.2f} s | {int(as_number(p['dofs']))} | {percent(p['frequency_rel_error'])} | "
            f"{percent(p['modal_mass_rel_error'])} | {percent(p['amplitude_rel_error'])} | "
            f"{percent(p['time_to_saturation_rel_error'])} |"
        )
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
            out.append(
                f"{name}: the current preset ({p['current']}) meets the rule "
                f"({p['rule']}) but {p['method']} with {p['elements_through_web']} per web "
                f"is cheaper ({p['seconds']:.2f} s vs {cm['seconds']:.2f} s)."
            )
        elif cm is None:
            out.append(
                f"{name}: {p['method']} with {p['elements_through_web']} per web fits "
                f"({p['rule']}); the current preset ({p['current']}) was not measured."
            )
        else:
            out.append(
                f"{name}: change {p['current']} to {p['method']} with "
                f"{p['elements_through_web']} per web (the current one does not meet: "
                f"{p['rule']})."
            )
    return out
