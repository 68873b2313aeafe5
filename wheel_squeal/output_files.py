"""Every file the commands write: which commands write it, what it holds and its fields
(CSV columns in order; for JSON the top-level keys), each field one of
:data:`wheel_squeal.fields.FIELDS`; and a study case's result fields."""

from __future__ import annotations

from dataclasses import dataclass

from .rail_fields import CURVE_COLUMNS, RECEPTANCE_COLUMNS

__all__ = ["FILES", "FLAG_FIELDS", "LABEL_FIELDS", "RESULT_FIELDS", "OutputFile", "columns_of"]


@dataclass(frozen=True)
class OutputFile:
    """A file the commands write, and its fields (CSV columns in order; for JSON the
    top-level keys)."""

    commands: tuple[str, ...]
    description: str
    fields: tuple[str, ...]


#: a sweep point's verdict (the first columns of sweep.csv and sweep_spl.csv)
_SWEEP_POINT = (
    "crabbing_velocity_m_s",
    "rpm",
    "rolling_speed_m_s",
    "verdict_mode",
    "squeals",
    "saturated",
    "amplitude_m_s",
)

#: A study case's results per operating point, each (n_crab_velocities, n_rpm): numbers
#: (NaN where they do not apply), flags, and mode labels ("" where none).
RESULT_FIELDS = (
    "tone_hz",
    "growth_rate_1_s",
    "amplitude_m_s",
    "spl_db",
    "spl_dba",
    "sound_power_level_db",
    "model_pick_growth_rate_1_s",
    "override_growth_rate_1_s",
)
FLAG_FIELDS = ("squeals", "saturated")
LABEL_FIELDS = ("verdict_mode", "mechanism", "model_pick")

FILES: dict[str, OutputFile] = {
    "summary.json": OutputFile(
        ("run", "stability", "mesh", "modes", "simulate", "sweep", "sound", "compare"),
        "the command's result: the verdict first, then what it rests on (null: no value)",
        (),
    ),
    "timeseries.csv": OutputFile(
        ("run", "simulate"),
        "the time history at the contact (one header line; every k-th sample: summary.json)",
        ("t_s", "y_m", "v_m_s", "creepage", "Q_N", "P_W", "u_n_m", "N_N", "v_counter_body_m_s"),
    ),
    "sweep.csv": OutputFile(
        ("sweep",),
        "the verdict per operating point",
        (*_SWEEP_POINT, "tone_hz", "growth_rate_1_s", "time_to_saturation_s"),
    ),
    "measured.csv": OutputFile(
        ("sweep --sound --measured",),
        "measured levels beside the prediction at each measured point",
        (
            "crabbing_velocity_m_s",
            "rpm",
            "measured_spl_db",
            "predicted_spl_db",
            "spl_difference_db",
            "measured_frequency_hz",
            "predicted_tone_hz",
            "tone_difference_hz",
        ),
    ),
    "sweep_spl.csv": OutputFile(
        ("sweep --sound",),
        "the levels per operating point",
        (*_SWEEP_POINT, "spl_db", "sound_power_level_db"),
    ),
    "stability.csv": OutputFile(
        ("stability --envelope",),
        "the fastest-growing mode per operating point",
        (
            "crabbing_velocity_m_s",
            "rpm",
            "growth_rate_1_s",
            "unstable",
            "fastest_mode_index",
            "fastest_mode",
            "fastest_mode_frequency_hz",
        ),
    ),
    "receptance.csv": OutputFile(
        ("track",),
        "the rail's point receptances, exp(+i omega t)",
        ("frequency_hz", *RECEPTANCE_COLUMNS),
    ),
    "curve.csv": OutputFile(
        ("curve",), "each wheel of the bogie at each curve radius and train speed", CURVE_COLUMNS
    ),
    "compare.csv": OutputFile(
        ("compare",),
        "one row per design, loudest sound power first",
        (
            "design",
            "rolling_speed_m_s",
            "rpm",
            "crabbing_velocity_m_s",
            "squeals",
            "verdict_mode",
            "tone_hz",
            "growth_rate_1_s",
            "amplitude_m_s",
            "saturated",
            "sound_power_level_db",
            "sound_power_level_dba",
            "spl_1m_db",
            "spl_7_5m_db",
            "spl_db",
            "spl_dba",
            "override_mode",
            "override_growth_rate_1_s",
            "model_pick",
            "model_pick_growth_rate_1_s",
            "mode_frequency_hz",
            "modal_mass_kg",
            "modal_stiffness_n_m",
            "modal_damping_ns_m",
            "reason",
        ),
    ),
    "study.csv": OutputFile(
        ("study",),
        "one row per design and operating point (study.nc holds the same as an xarray Dataset: "
        "the design axes and crab_velocity x rpm as dimensions, units as attributes; the design "
        "axes come first, each named by its design field, then design_<field> with the values used)",
        (
            "crab_velocity",
            "rpm",
            "status",
            "reason",
            "mass_kg",
            "modes",
            *LABEL_FIELDS,
            *FLAG_FIELDS,
            *RESULT_FIELDS,
        ),
    ),
}


def columns_of(file_name: str) -> tuple[str, ...]:
    """The documented columns of a CSV file the tool writes, in order."""
    return FILES[file_name].fields
