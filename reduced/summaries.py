"""What a squeal simulation's record says, as plain values: JSON-ready summaries of the
limit cycle, the operating point and the contact, the counter-body's part in the motion,
and the record's table of contact quantities (the application writes them)."""

from __future__ import annotations

import numpy as np

from contact.creep import ContactLaw

from .limit_cycle import LimitCycle
from .model import OperatingPoint, TimeHistory

__all__ = [
    "TIMESERIES_COLUMNS",
    "VELOCITY_REFERENCE_M_S",
    "counter_body_motion",
    "counter_body_velocity",
    "summary_dicts",
    "timeseries_table",
]

#: reference velocity for velocity levels, m/s (dB re 5e-8 m/s)
VELOCITY_REFERENCE_M_S = 5e-8


def summary_dicts(lc: LimitCycle, op: OperatingPoint, contact: ContactLaw) -> dict:
    """Dicts {'limit_cycle', 'operating_point', 'contact'} (SI units; NaN where a quantity
    is undefined, such as the frequency of no squeal: a JSON writer makes it null)."""
    return {
        "limit_cycle": {
            "squeal": bool(lc.squeal),
            "state": lc.state,
            "velocity_amplitude_m_s": float(lc.velocity_amplitude_m_s),
            "frequency_hz": float(lc.frequency_hz),
            "time_to_saturation_s": float(lc.time_to_saturation_s),
            "envelope_growth_rate_1_s": float(lc.envelope_growth_rate_1_s),
        },
        "operating_point": {
            "rolling_speed_m_s": float(op.rolling_speed_m_s),
            "crabbing_velocity_m_s": float(op.crabbing_velocity_m_s),
            "creepage": float(op.creepage),
        },
        "contact": {
            "semi_axis_a_m": float(contact.semi_axis_a_m),
            "semi_axis_b_m": float(contact.semi_axis_b_m),
            "c22": float(contact.c22),
            "friction_coefficient": float(contact.friction_coefficient),
            "friction_law": contact.friction_law,
        },
    }


#: timeseries.csv's columns (SI units: the suffix names the unit)
TIMESERIES_COLUMNS = ("t_s", "y_m", "v_m_s", "creepage", "Q_N", "P_W", "u_n_m", "N_N", "v_counter_body_m_s")


def counter_body_velocity(history: TimeHistory) -> np.ndarray:
    """The counter-body's own lateral velocity at the contact [m/s] (a rail's, a roller's
    mode's; the contact sees the wheel's velocity minus it); 0 where it is rigid."""
    return np.zeros(len(history.t)) if history.v_body is None else history.v_body


def counter_body_motion(history: TimeHistory) -> dict[str, float]:
    """The counter-body's part at the end of the record (its last quarter): the rms of
    the contact's slip velocity and of the counter-body's own velocity there [m/s], their
    ratio, and the mean power the contact force puts into the counter-body [W] (its
    fluctuating part: the steady creep force does no work on a body at rest)."""
    sel = history.t >= 0.75 * float(history.t[-1])
    v_cb = counter_body_velocity(history)[sel]
    v = history.v[sel] - history.v[sel].mean()
    q = history.Q[sel] - history.Q[sel].mean()
    rms_v, rms_cb = float(np.sqrt(np.mean(v**2))), float(np.sqrt(np.mean((v_cb - v_cb.mean()) ** 2)))
    return {
        "contact_velocity_rms_m_s": rms_v,
        "counter_body_velocity_rms_m_s": rms_cb,
        "counter_body_velocity_share": rms_cb / rms_v if rms_v > 0 else 0.0,
        "counter_body_power_w": float(np.mean(-q * (v_cb - v_cb.mean()))),
    }


def timeseries_table(history: TimeHistory) -> np.ndarray:
    """The record's :data:`TIMESERIES_COLUMNS`, one row per sample (the normal approach 0
    and the normal force the load where the model has none)."""
    zero = np.zeros(len(history.t))
    u_n = zero if history.u_n is None else history.u_n
    normal = zero + history.contact.normal_load_n if history.N is None else history.N
    return np.column_stack(
        [
            history.t,
            history.y,
            history.v,
            history.creepage,
            history.Q,
            history.P,
            u_n,
            normal,
            counter_body_velocity(history),
        ]
    )
