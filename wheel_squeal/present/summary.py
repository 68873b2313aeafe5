"""summary.json: the JSON objects of every result (the verdict first, then what it rests
on), from the records; keys and units are :mod:`wheel_squeal.fields`'."""

from __future__ import annotations

from typing import TYPE_CHECKING, Any

from ..design import Design
from ..outputs import finite_or_none
from ..presets import Fidelity, rpm_to_speed
from .time_history import TIMESERIES_BYTES, timeseries_stride

if TYPE_CHECKING:
    from fem.modes import Mode, ModeSet
    from reduced import ContactLaw, ModalDOF, OperatingPoint

    from ..chain import Analysis

__all__ = ["analysis_summary", "contact_summary", "dof_summary", "modes_summary", "operating_point_summary"]


def dof_summary(dof: ModalDOF) -> dict[str, float]:
    """The modal parameters of a ``reduced.ModalDOF`` (SI units)."""
    return {
        "mass_kg": dof.mass_kg,
        "stiffness_n_m": dof.stiffness_n_m,
        "damping_ns_m": dof.damping_ns_m,
        "frequency_hz": dof.frequency_hz,
    }


def modes_summary(
    design: Design, modeset: ModeSet, selected: Mode | None, fid: Fidelity, why: str | None = None
) -> dict[str, Any]:
    """``summary.json``'s modal part: every mode with its labels and contact m, k, c, the
    selected mode (and why; None when no mode was selected), the solver, DOFs and timings."""

    def zeta(m: Mode) -> float:
        return design.damping_ratio_of(m)

    sel = selected.to_dict(zeta(selected)) if selected is not None else None
    if why is not None and sel is not None:
        sel["why"] = why
    return {
        "design": design.name,
        "fidelity": fid.name,
        "solver": modeset.solver,
        "dofs": int(modeset.dofs),
        "modes": [m.to_dict(zeta(m)) for m in modeset.modes],
        "selected_mode": sel,
        "timings_s": dict(modeset.timings_s),
    }


def operating_point_summary(op: OperatingPoint, design: Design) -> dict[str, float]:
    """The operating point (SI units, and the wheel speed in rev/min)."""
    return {
        "rolling_speed_m_s": op.rolling_speed_m_s,
        "rpm": op.rolling_speed_m_s / rpm_to_speed(1.0, design.rolling_radius),
        "crabbing_velocity_m_s": op.crabbing_velocity_m_s,
        "creepage": op.creepage,
        "wheel_speed_rad_s": op.wheel_speed_rad_s(design.rolling_radius),
    }


def contact_summary(design: Design, contact: ContactLaw, op: OperatingPoint) -> dict[str, Any]:
    """The contact as the stability sees it: its point and angle, the friction law and
    coefficient, the creep coefficient, the normal spring, transient creep and the
    counter-body (SI units)."""
    frame = design.contact_frame
    return {
        **frame.to_dict(),
        "friction_law": contact.friction_law,
        "friction_coefficient": contact.friction_coefficient,
        "c22": contact.c22,
        "normal_contact": design.contact.normal_contact,
        "normal_stiffness_n_m": contact.normal_stiffness_n_m,
        "hertz_approach_m": finite_or_none(contact.hertz_approach_m),
        "relaxation_length_m": contact.relaxation_length_m,
        "relaxation_time_s": contact.relaxation_time_s(op.rolling_speed_m_s),
        "counter_body": design.counter_body.summary(),
    }


def analysis_summary(a: Analysis, record_bytes: float = TIMESERIES_BYTES) -> dict[str, Any]:
    """``summary.json`` of the chain: the verdict first, then what it rests on (the
    modes, every mode's stability and every eigenvalue, the contact, the operating point,
    the decision, the limit cycle and its sound, and what timeseries.csv holds when it
    is written within ``record_bytes``)."""
    from ..api import modal_dof
    from ..mode_stability import eigenvalue_list

    o = a.outcome
    rows = [r.to_dict(a.design) for r in a.rows]
    d = a.decision
    out: dict[str, Any] = {
        "verdict": a.verdict.to_dict(),
        **modes_summary(a.design, a.modeset, o.mode if o else None, a.fidelity),
        "stability": rows,
        "winner": rows[a.table.fastest],
        "eigenvalues": eigenvalue_list(a.table),
        "decision": {
            "named_mode": d.named.label() if d.named else None,
            "integrated_with_it": [m.label() for m in d.named_group],
            "growing_modes": [m.label() for m in d.growing],
            "left_out": d.left_out,
            "model_pick": d.fastest.label() if d.fastest else None,
        },
        "rotation": a.rotation,
        "operating_point": operating_point_summary(a.operating_point, a.design),
        "contact": contact_summary(a.design, a.contact, a.operating_point),
        "stop_after": a.options.stop_after,
    }
    if o is not None and o.simulation is not None:
        sim = o.simulation.summary()
        out["limit_cycle"] = sim["limit_cycle"]
        from reduced.summaries import TIMESERIES_COLUMNS

        body = o.simulation.history.body
        if body is not None:
            from reduced.summaries import counter_body_motion

            out["counter_body_motion"] = {
                **counter_body_motion(o.simulation.history),
                "counter_body_energy_share": (o.shares or {}).get(body.name, 0.0),
            }
        out["timeseries_csv"] = {
            "columns": list(TIMESERIES_COLUMNS),
            "what": "the squeal model's time history at the contact point, SI units",
            "sample_stride": timeseries_stride(o.simulation.history, record_bytes),
        }
        out["contact"] |= sim["contact"]  # the creep law's values beside the contact's point
        out["modal_parameters"] = dof_summary(modal_dof(o.mode, a.design))
        if o.sound is not None:
            out["sound"] = o.sound.summary()
    return out
