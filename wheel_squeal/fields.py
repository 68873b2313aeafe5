"""Every field the tool writes, with its unit and meaning: the one home the reference
documentation is generated from (``docs/reference/outputs.md``, with the files of
:mod:`.output_files`) and the study dataset takes its units from. A test runs the commands
and fails on a written field that is not here, or on a field here that nothing writes.

Fields are named by their key (the last part of a JSON path, or a CSV column); the same
key means the same quantity in every file. ``GROUPS`` are the JSON objects that hold
fields; ``FREE_GROUPS`` hold keys that name things (stages, designs) rather than fields.
"""

from __future__ import annotations

from dataclasses import dataclass

from .rail_fields import RAIL_FIELDS

__all__ = [
    "FIELDS",
    "FREE_GROUPS",
    "GROUPS",
    "Field",
    "unit_of",
]


@dataclass(frozen=True)
class Field:
    """A written quantity: its ``unit`` ("" for dimensionless numbers, "-" for labels,
    flags and text) and what it means."""

    unit: str
    description: str


#: key -> Field, alphabetical
FIELDS: dict[str, Field] = {
    "N_N": Field("N", "normal contact force (0 where the wheel and the roller have separated)"),
    "P_W": Field("W", "power the contact force puts into the modes, Q v minus the modal damping losses"),
    "Q_N": Field("N", "lateral contact (creep) force on the wheel"),
    "amplitude_m_s": Field("m/s", "contact velocity amplitude of the limit cycle (or the last cycle)"),
    "at_crabbing_velocity_m_s": Field("m/s", "crabbing velocity where the required damping binds"),
    "at_rpm": Field("rev/min", "wheel speed where the required damping binds"),
    "c22": Field("", "Kalker's lateral creep coefficient C22 used"),
    "centre_hz": Field("Hz", "the one-third-octave band's exact centre frequency, 1000 * 10^(k/10)"),
    "columns": Field("-", "the file's columns, in order"),
    "contact_lost_fraction": Field("", "share of the record's last quarter with the surfaces apart (N = 0)"),
    "contact_angle_deg": Field("deg", "the contact angle: the contact normal's angle from radial"),
    "contact_angle_rad": Field("rad", "the contact angle"),
    "crab_velocity": Field("m/s", "crabbing velocity of the operating point (a study's axis)"),
    "crabbing_velocity_m_s": Field("m/s", "crabbing velocity Vc of the operating point"),
    "crown_radius_m": Field("m", "the tread's transverse radius at the contact (null: straight)"),
    "creepage": Field("", "quasi-static lateral creepage Vc / V0 (or the instantaneous one in a record)"),
    "critical_damping_ratio": Field("", "damping ratio below which the mode grows here"),
    "critical_friction_slope": Field("", "creep-curve slope dmu/dzeta below which the mode grows here"),
    "damped_frequency_hz": Field("Hz", "frequency of the mode's linear eigenvalue with the contact"),
    "damping_ns_m": Field("N s/m", "viscous damping c of the mode at the contact"),
    "damping_ratio": Field("", "the mode's damping ratio now"),
    "damping_source": Field(
        "-",
        "where the squeal mode's damping ratio comes from: its key in "
        "[squeal.damping] (a mode, n>=2,axial, n>=2, ...), modal_damping_ratio or measured",
    ),
    "design": Field("-", "the design's name"),
    "dim": Field("-", "mesh dimension: 2 (profile) or 3 (solid)"),
    "dofs": Field("-", "degrees of freedom of the FE model (summed over harmonics)"),
    "duration_s": Field("s", "simulated time per point"),
    "elements": Field("-", "number of elements"),
    "energy_share": Field(
        "", "the share of the limit cycle's vibration energy the carrying eigenvalue's modes hold"
    ),
    "frequency_hz_now": Field("Hz", "the higher partner's natural frequency now"),
    "friction_coefficient_now": Field("", "the friction coefficient mu_s now"),
    "friction_slope_now": Field("", "the creep curve's slope dmu/dzeta at the quasi-static creepage now"),
    "growing_modes": Field(
        "-", "the modes of every growing eigenvalue, integrated together for the model's outcome"
    ),
    "integrated_with_it": Field(
        "-", "the named mode and the modes sharing its eigenvalue, integrated together"
    ),
    "kind": Field("-", "the counter-body's kind ([counter_body] kind)"),
    "left_out": Field("-", "modes of growing eigenvalues beyond the most integrated together"),
    "named_mode": Field("-", "the mode the request or the design names (null: none)"),
    "partner": Field("-", "the lower partner of a coupled pair"),
    "sample_stride": Field("-", "k: the file holds every k-th sample of the record (1: all)"),
    "stop_after": Field("-", "the chain's last stage: stability, limit_cycle or sound"),
    "rolling_radius": Field("m", "the counter-body's rolling radius"),
    "crown_radius": Field("m", "the counter-body's transverse radius"),
    "exact_volume_m3": Field("m^3", "the design's exact volume (revolved outline)"),
    "family": Field("-", "mode family: axial (out of plane), radial or circumferential"),
    "fastest_mode": Field("-", "label of the fastest-growing mode"),
    "fastest_mode_frequency_hz": Field("Hz", "its damped frequency"),
    "fastest_mode_index": Field("-", "its index in the mode list"),
    "fidelity": Field("-", "the speed/accuracy preset"),
    "flux_power_w": Field("W", "radiated power through a circle in the air (check of surface_power_w)"),
    "frequency_hz": Field("Hz", "natural (or limit-cycle, or radiated) frequency"),
    "friction_coefficient": Field("", "friction coefficient mu_s = mu_0"),
    "friction_damping_ns_m": Field(
        "N s/m", "linearised friction damping g = W/V0 dmu/dzeta (negative: destabilising)"
    ),
    "friction_slope": Field("", "the creep curve's slope dmu/dzeta at the quasi-static creepage now"),
    "friction_law": Field("-", "the creep law: falling (the paper's) or constant (no falling friction)"),
    "friction_slope_at_rpm": Field("rev/min", "wheel speed where the required friction slope binds"),
    "hertz_approach_m": Field("m", "the static Hertz approach delta0 under W (null: constant normal load)"),
    "growth_rate_1_s": Field(
        "1/s", "linear growth rate (negative: decays); the largest where no mode squeals"
    ),
    "envelope_growth_rate_1_s": Field(
        "1/s",
        "the record's envelope growth over its exponential phase, fitted (null: none); the linear "
        "growth rate measured in the time domain",
    ),
    "hits": Field("-", "stages read from the cache"),
    "index": Field("-", "the mode's index in frequency order"),
    "label": Field("-", "mode label (n,c) family"),
    "label_hz": Field("Hz", "the band's nominal centre frequency (IEC 61260-1)"),
    "lateral_component": Field(
        "1/sqrt(kg)", "the mode's mass-normalised displacement at the contact along t"
    ),
    "loudest_angle_deg": Field("deg", "meridian angle from the +z axis of the far field's largest intensity"),
    "mass_kg": Field("kg", "modal mass at the contact (a study: the wheel's mass)"),
    "measured_frequency_hz": Field("Hz", "the measured squeal frequency (empty: not measured)"),
    "measured_spl_db": Field("dB re 20 uPa", "the measured SPL at the microphone"),
    "mechanism": Field("-", "what makes it grow: falling friction, mode coupling, or both (only together)"),
    "mesh_volume_m3": Field("m^3", "volume of the mesh (revolved for a profile)"),
    "microphone_m": Field("m", "microphone position (r, z) and angle theta [rad]"),
    "misses": Field("-", "stages computed (not in the cache)"),
    "modal_damping_ns_m": Field("N s/m", "viscous damping of the mode at the contact"),
    "modal_mass_kg": Field("kg", "modal mass at the contact, lateral (null: a node at the contact)"),
    "modal_stiffness_n_m": Field("N/m", "modal stiffness at the contact"),
    "mode": Field("-", "mode label, or (mitigation) mode index"),
    "mode_frequency_hz": Field("Hz", "natural frequency of the verdict's mode"),
    "mode_index": Field("-", "index of the verdict's mode"),
    "model_pick": Field("-", "the mode the model alone picks (fastest-growing, or multi-mode carrier)"),
    "model_pick_growth_rate_1_s": Field("1/s", "its growth rate"),
    "modes": Field("-", "number of modes found below fmax"),
    "nodal_circles": Field("-", "number of nodal circles"),
    "nodal_diameters": Field("-", "number of nodal diameters"),
    "nodes": Field("-", "number of mesh nodes"),
    "normal_stiffness_n_m": Field(
        "N/m", "the linearised Hertz spring k_H = 3W / (2 delta0); 0: constant load"
    ),
    "normal_component": Field("1/sqrt(kg)", "the mode's mass-normalised displacement at the contact along n"),
    "normal_contact": Field(
        "-", "hertz (the normal force follows the normal motion) or constant (fixed load)"
    ),
    "order": Field("-", "element (mesh) order"),
    "order_k": Field("-", "the harmonic's order k (its frequency k f0)"),
    "override_growth_rate_1_s": Field("1/s", "growth rate of the named mode"),
    "override_mode": Field("-", "the named mode (an override of the model's pick)"),
    "partners": Field("-", "the modes that take part in the mode's fastest eigenvalue, itself first"),
    "predicted_spl_db": Field("dB re 20 uPa", "the sweep's SPL there (empty: no limit cycle around it)"),
    "predicted_tone_hz": Field("Hz", "the sweep's tone there"),
    "points": Field("-", "number of operating points"),
    "radiation_efficiency": Field("", "radiated power over rho0 c0 S <vn^2>"),
    "r_m": Field("m", "radius of the contact point"),
    "reason": Field("-", "why, in words"),
    "relaxation_length_m": Field("m", "transient creep's relaxation length L (0: steady creep)"),
    "relaxation_time_s": Field("s", "its lag L / V0 at the operating point"),
    "required_damping_ratio": Field("", "damping ratio that keeps the mode stable over the envelope"),
    "required_friction_slope": Field("", "creep-curve slope that keeps every mode stable over the envelope"),
    "rim_depth": Field("m", "a study's design axis (any design field may be one)"),
    "rolling_speed_m_s": Field("m/s", "rolling speed V0 at the contact"),
    "rotation": Field("-", "whether the wheel's rotation is modelled"),
    "rpm": Field("rev/min", "wheel speed"),
    "saturated": Field("-", "whether the oscillation reached its limit cycle within the run"),
    "share": Field("", "the mode's share of the eigenvalue's vibration energy"),
    "seconds": Field("s", "wall time"),
    "semi_axis_a_m": Field("m", "Hertz contact semi-axis in the rolling direction"),
    "semi_axis_b_m": Field("m", "Hertz contact semi-axis across (lateral)"),
    "settled": Field("-", "whether the bounds converged: with them nothing grows"),
    "solver": Field("-", "modal solver"),
    "sound_power_level_db": Field("dB re 1 pW", "sound power level (all harmonics radiated)"),
    "sound_power_level_dba": Field("dB(A) re 1 pW", "A-weighted sound power level (IEC 61672-1)"),
    "spl_db": Field("dB re 20 uPa", "sound pressure level at the microphone (all harmonics; a band's)"),
    "spl_dba": Field("dB(A) re 20 uPa", "A-weighted sound pressure level at the microphone (IEC 61672-1)"),
    "spl_1m_db": Field("dB re 20 uPa", "SPL 1 m from the wheel centre in the loudest direction"),
    "spl_1m_axis_db": Field(
        "dB re 20 uPa", "SPL 1 m from the wheel centre on its axis (null: n >= 1, silent)"
    ),
    "spl_7_5m_db": Field("dB re 20 uPa", "SPL 7.5 m from the wheel centre in the loudest direction"),
    "spl_7_5m_axis_db": Field("dB re 20 uPa", "SPL 7.5 m from the wheel centre on its axis (null: silent)"),
    "spl_difference_db": Field("dB", "prediction minus measurement"),
    "squeal": Field("-", "whether the limit cycle is a self-sustained oscillation"),
    "squealing_points": Field("-", "operating points that squeal"),
    "squeals": Field("-", "the verdict: whether the wheel squeals"),
    "state": Field(
        "-",
        "what the record shows at its end: limit cycle, still growing, not settled (a sustained "
        "oscillation that is not a clean limit cycle) or quiet",
    ),
    "status": Field("-", "a study case's outcome: ok, invalid or failed"),
    "still_growing_points": Field("-", "squealing points whose run ended before saturation"),
    "stiffness_n_m": Field("N/m", "modal stiffness k at the contact"),
    "surface_power_w": Field("W", "radiated power from the surface integral"),
    "t_s": Field("s", "time"),
    "time_domain": Field(
        "-", "the state of the verdict's modes integrated with the remedy's damping (quiet: it decays)"
    ),
    "time_to_saturation_s": Field("s", "when the oscillation reached its limit cycle"),
    "tone_difference_hz": Field("Hz", "predicted tone minus measured frequency"),
    "tone_hz": Field("Hz", "the tone a stationary microphone hears"),
    "u_n_m": Field("m", "normal approach of the wheel to the roller at the contact (the modes' share)"),
    "unstable": Field("-", "whether the mode grows here"),
    "v_m_s": Field("m/s", "lateral velocity of the wheel at the contact"),
    "velocity_amplitude_m_s": Field("m/s", "contact velocity amplitude"),
    "velocity_energy_share": Field("", "share of the contact velocity's energy the radiated harmonics hold"),
    "verdict_mode": Field("-", "the verdict's mode (empty: no squeal)"),
    "wave": Field("-", "standing, forward or backward (travelling wave with rotation)"),
    "wav_full_scale_pa": Field("Pa", "the pressure of squeal.wav's full scale (its peak sample)"),
    "web_thickness": Field("m", "a study's design axis"),
    "what": Field("-", "what the file holds; a treatment of the curve's remedy: what it is, in words"),
    "wheel_profile": Field("-", "curve: the profile the wheel touches its rail with (outline or S1002)"),
    "wheel_speed_rad_s": Field("rad/s", "wheel speed Omega = V0 / R1"),
    "why": Field("-", "why this mode"),
    "words": Field("-", "the same, in words"),
    "y_m": Field("m", "lateral displacement of the wheel at the contact"),
    "z_m": Field("m", "axial position of the contact point"),
}

FIELDS |= {k: Field(*v) for k, v in RAIL_FIELDS.items()}

#: JSON objects that hold fields
GROUPS: dict[str, str] = {
    "cache": "cache hits and misses of the run's stages",
    "checks": "independent checks of the radiated power",
    "contact": "the contact: its point and angle, the Hertz ellipse and spring, the creep law, the roller",
    "damping": "per mode: the damping that stops squeal over the envelope",
    "designs": "one row per design (as compare.csv)",
    "eigenvalues": "every eigenvalue of the linear system, fastest-growing first (mechanism null: decays)",
    "limit_cycle": "the limit cycle of the simulated mode",
    "mitigation": "what stops squeal over the envelope (rotation off and on)",
    "modal_parameters": "m, k, c of the simulated mode at the contact",
    "mode": "the mode",
    "model_pick": "the model's own pick (as the verdict's fields)",
    "modes": "every mode below fmax",
    "counter_body": "what the wheel rolls on: its kind and its values ([counter_body])",
    "decision": "what the verdict integrated: the named mode and those with it, the modes that grow together",
    "operating_point": "the operating point",
    "override": "the named mode's own result (as the verdict's fields)",
    "per_unit_velocity": "levels at 1 m/s contact velocity (the fundamental)",
    "third_octave_bands": "the microphone's one-third-octave band levels over the limit cycle (null: empty)",
    "harmonics": "each radiated harmonic of the contact velocity: order, frequency, amplitude, levels",
    "fit_vertical": "the modal fit of the rail's vertical receptance at the contact (poles, band, error)",
    "fit_lateral": "the modal fit of the rail's lateral receptance at the contact (poles, band, error)",
    "remedy": "with squeal: what stops every growing mode (damping per mode, friction, separation), checked; "
    "curve: each treatment checked over the map, and the recommended one",
    "separations": "per coupled pair: the frequency its higher partner must reach for the pair to decay",
    "counter_body_motion": "the counter-body at the end of the record: its velocity, power and energy shares",
    "cases": "curve: one per radius, train speed and wheel (as curve.csv, with its verdict)",
    "loudest": "curve: the loudest pass-by, its sound file and one-third-octave bands",
    "bands": "curve: the loudest pass-by's largest level in each one-third-octave band holding a tone",
    "microphone": "curve: the pass-by microphone (ISO 3095)",
    "vehicle": "curve: the bogie in the steady curving (wheelbase, primary stiffnesses, centre of gravity)",
    "treatments": "curve: each treatment of the remedy, checked by running the map again with it",
    "timeseries_csv": "what timeseries.csv holds (its columns, SI units, and its sample stride)",
    "rotation_off": "mitigation with the wheel's rotation left out",
    "rotation_on": "mitigation with rotation",
    "selected_mode": "the mode the command selected",
    "sound": "the sound of the verdict's mode at its amplitude",
    "participants": "the modes holding at least 5 % of one eigenvalue's energy, with their shares",
    "stability": "every excitable mode's linear stability",
    "verdict": "the one answer: whether, in which mode, at what tone, how loud, why",
    "winner": "the leading mode, the verdict's: the one holding most of the fastest-growing eigenvalue (its "
    "growth rate, frequency and mechanism)",
}

#: JSON objects whose keys name things: stages (seconds each) or designs (a verdict each)
FREE_GROUPS: dict[str, str] = {
    "damping": "the remedy's damping ratio [-] per mode, keyed by its label (the envelope's is a list)",
    "damping_now": "each mode's damping ratio now [-], keyed by its label",
    "paste": "the remedy as [squeal.damping] keys (n=N,c=C or a modal model's label) to damping ratios [-]",
    "energy_shares": "each degree of freedom's share of the limit cycle's energy, keyed by its label",
    "operating_points": "each design's operating point (at its own wheel radius), keyed by the design's name",
    "timings_s": "seconds per stage, keyed by the stage's name",
    "verdicts": "the verdict of each design, keyed by its name",
}


def unit_of(key: str) -> str:
    """The unit of field ``key`` ("" dimensionless, "-" none)."""
    return FIELDS[key].unit
