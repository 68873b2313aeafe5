"""The fields of the rail and of curves, in the field reference (:mod:`wheel_squeal.fields`
takes them): the track command's receptances and fits, a verdict on a track, the rail's
part of a limit cycle, and the curve command's cases. Each is (unit, meaning)."""

from __future__ import annotations

__all__ = ["CURVE_COLUMNS", "RAIL_FIELDS", "RECEPTANCE_COLUMNS"]

#: receptance.csv's columns after the frequency: each direction and position, in parts
RECEPTANCE_COLUMNS = tuple(
    f"{d}_{at}_{part}"
    for d in ("vertical", "lateral")
    for at in ("support", "midspan")
    for part in ("re", "im")
)
#: curve.csv's columns
CURVE_COLUMNS = (
    "radius_m",
    "train_speed_km_h",
    "axle",
    "rail",
    "lateral_shift_mm",
    "angle_of_attack_rad",
    "flange_contact",
    "contacts",
    "deciding_contact",
    "contact_angle_deg",
    "flange_angle_deg",
    "wheel_load_n",
    "normal_force_n",
    "lateral_force_n",
    "longitudinal_creepage",
    "lateral_creepage",
    "spin_creepage_1_m",
    "crabbing_velocity_m_s",
    "rolling_speed_m_s",
    "squeals",
    "verdict_mode",
    "mechanism",
    "tone_hz",
    "growth_rate_1_s",
    "amplitude_m_s",
    "amplitude_method",
    "harmonic_distortion",
    "amplitude_note",
    "passby_lpamax_dba",
    "passby_sel_dba",
    "bogie_lpmax_db",
    "bogie_lpamax_dba",
    "bogie_sel_dba",
    "bogie_lpamax_ground_dba",
)
_WHERE = {"support": "a sleeper", "midspan": "midspan"}
_PART = {"re": "real", "im": "imaginary"}

#: name -> (unit, meaning)
RAIL_FIELDS: dict[str, tuple[str, str]] = {
    **{
        c: (
            "m/N",
            f"{_PART[c.split('_')[2]]} part of the rail's {c.split('_')[0]} receptance at "
            f"{_WHERE[c.split('_')[1]]}",
        )
        for c in RECEPTANCE_COLUMNS
    },
    "band_hz": ("Hz", "the band fitted"),
    "convention": ("-", "the receptances' sign convention"),
    "counter_body_effect_1_s": (
        "1/s",
        "with a counter-body that moves (a rail, a roller with modes): what it adds to the fastest"
        " growth rate",
    ),
    "counter_body_growth_rate_1_s": ("1/s", "the counter-body's own eigenvalue's growth (null: none)"),
    "frequency_range_hz": ("Hz", "the frequency grid's ends"),
    "max_relative_error": (
        "",
        "the fit's largest |fit - alpha| / |alpha| over the band (largest where the "
        "weights are small: below 50 Hz, above 1 kHz)",
    ),
    "pinned_pinned_lateral_hz": ("Hz", "the lateral pinned-pinned frequency (a simply supported bay)"),
    "pinned_pinned_vertical_hz": ("Hz", "the vertical pinned-pinned frequency (a simply supported bay)"),
    "states": ("-", "the rational fit's states (two per complex pole pair)"),
    "weighted_error": (
        "",
        "the fit's largest error in the norm of its weights (towards the rail's mobility), relative",
    ),
    "position": ("-", "where in the sleeper bay the contact is"),
    "angle_of_attack_rad": (
        "rad",
        "the wheelset's angle of attack psi in the steady curving (positive: rolling outward of the curve)",
    ),
    "lateral_shift_mm": (
        "mm",
        "the wheelset's lateral shift in the steady curving, positive toward the outer rail",
    ),
    "flange_contact": (
        "-",
        "whether one of the wheel's contacts is on its flange (contact angle over 45 deg)",
    ),
    "contacts": ("-", "how many contacts the wheel has: 1, or 2 in a two-point (tread and flange) contact"),
    "deciding_contact": (
        "-",
        "the contact whose verdict is the wheel's (its squeal grows fastest): tread or flange",
    ),
    "flange_angle_deg": ("deg", "the flange contact's angle where the flange touches (null: it does not)"),
    "wheel_load_n": (
        "N",
        "the rail's vertical force on the wheel, all its contacts (with the load transfer)",
    ),
    "normal_force_n": ("N", "the normal force of the contact whose verdict is the wheel's"),
    "lateral_force_n": (
        "N",
        "the rail's lateral force on the wheel, all its contacts, positive toward the curve's centre",
    ),
    "longitudinal_creepage": ("", "the longitudinal creepage in the contact plane of the deciding contact"),
    "spin_creepage_1_m": ("1/m", "the spin creepage sin(gamma) / r of the deciding contact"),
    "radius_m": ("m", "the curve's radius"),
    "train_speed_km_h": ("km/h", "the train's speed"),
    "axle": ("-", "the bogie's axle: leading or trailing"),
    "rail": ("-", "the wheel's rail: inner or outer"),
    "lateral_creepage": (
        "",
        "the lateral creepage in the contact plane of the deciding contact, -psi / cos(gamma)",
    ),
    "passby_lpamax_dba": (
        "dB(A) re 20 uPa",
        "the wheel's own L_pAmax passing 7.5 m away, 1.2 m above the rail head, in free field",
    ),
    "passby_sel_dba": ("dB(A) re 20 uPa^2 s", "the wheel's own A-weighted sound exposure level there"),
    "bogie_lpmax_db": ("dB re 20 uPa", "the bogie's L_pmax there (its wheels in energy), free field"),
    "bogie_lpamax_dba": ("dB(A) re 20 uPa", "the bogie's L_pAmax there, free field"),
    "bogie_sel_dba": ("dB(A) re 20 uPa^2 s", "the bogie's A-weighted sound exposure level there, free field"),
    "bogie_lpamax_ground_dba": ("dB(A) re 20 uPa", "the bogie's L_pAmax over the ground (null: none asked)"),
    "amplitude_method": ("-", "how the squeal's amplitude was found: harmonic balance or time domain"),
    "harmonic_distortion": ("", "the harmonic balance's contact-force distortion (< 0.1: within a few %)"),
    "distance_m": ("m", "the pass-by microphone's distance from the track centre line"),
    "height_m": ("m", "the pass-by microphone's height above the rail head"),
    "ground": ("-", "the ground under the pass-by: free field, or its depth and reflection factor"),
    "file": ("-", "the sound file of the loudest pass-by"),
    "peak_pa": ("Pa", "the pressure at the sound file's full scale"),
    "sample_rate_hz": ("Hz", "the sound file's sample rate"),
    "amplitude_note": ("-", "what the amplitude left out (mode coupling alone, a lower bound, not radiated)"),
    "findings": ("-", "where squeal stops per train speed, beside the field's anchors"),
    "lpmax_db": ("dB re 20 uPa", "the largest level over the pass-by in the band"),
    "lpamax_dba": ("dB(A) re 20 uPa", "the largest A-weighted level over the pass-by in the band"),
    "wheelbase_m": ("m", "the bogie's wheelbase 2a"),
    "cant_mm": ("mm", "the curves' installed cant"),
    "recommended": ("-", "the treatment that leaves the fewest cases squealing (null: nothing squeals)"),
    "words": ("-", "the remedy in one line, as the printed text and the report lead with it"),
    "name": ("-", "the treatment's name"),
    "design_file": (
        "-",
        "the design with the treatment applied, in the result folder (null: the design as it is)",
    ),
    "paste": ("-", "the treatment's changes as TOML tables to paste into the design"),
    "cases_squealing_before": (
        "-",
        "the map's cases (one wheel at one radius and speed) that squeal as it is",
    ),
    "cases_still_squealing": ("-", "the cases that squeal with the treatment, the map run again with it"),
    "still_squealing": ("-", "what still squeals with the treatment, in words"),
    "loudest_lpamax_before_dba": ("dB(A) re 20 uPa", "the map's loudest bogie L_pAmax as it is"),
    "loudest_lpamax_after_dba": ("dB(A) re 20 uPa", "the loudest with the treatment (null: none heard)"),
    "lpamax_reduction_db": ("dB", "how much quieter the loudest pass-by is (null: not known)"),
    "figure": ("-", "the loudest pass-by's level over time and spectrogram"),
    "primary_yaw_stiffness_n_m_rad": ("N m/rad", "the bogie's primary yaw stiffness per wheelset"),
    "primary_lateral_stiffness_n_m": ("N/m", "the bogie's primary lateral stiffness per wheelset"),
    "centre_of_gravity_height_m": ("m", "the height of the mass on the wheels above the rail heads"),
    "contact_velocity_rms_m_s": ("m/s", "rms slip velocity at the contact, the record's last quarter"),
    "counter_body_velocity_rms_m_s": ("m/s", "rms of the counter-body's own lateral velocity there"),
    "counter_body_velocity_share": ("", "the counter-body's velocity over the slip velocity (rms)"),
    "counter_body_power_w": ("W", "mean power the contact force puts into the counter-body there"),
    "counter_body_energy_share": ("", "the counter-body's share of the limit cycle's vibration energy"),
    "v_counter_body_m_s": ("m/s", "the counter-body's own lateral velocity at the contact (0: rigid)"),
}
