"""A wheel design in curves: for each curve radius, train speed and wheel of a two-axle
bogie, the kinematics (``track.curving``), the chain's verdict at that operating point,
and with the sound the level of the bogie's pass-by at the ISO 3095 position
(``acoustics.passby``).

The two wheels of an axle share its angle of attack and, here, its tread contact and its
load (no flange contact, no cant deficiency: ``track.curving``): one analysis per axle
answers for both; the inner and outer wheels differ in the pass-by, on the rails nearer
and farther from the microphone (on the curve's outer side).
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass, replace
from typing import TYPE_CHECKING, Any

from .analysis import Analysis, ChainOptions
from .design import Design
from .errors import RequestError
from .outputs import finite_or_none
from .types import Stage

if TYPE_CHECKING:
    from acoustics.passby import PassbyResult
    from track.curving import Bogie, WheelKinematics

    from .context import RunContext

__all__ = ["CurveCase", "curve"]


@dataclass(frozen=True)
class CurveCase:
    """One wheel at one radius and train speed: its kinematics, the chain's analysis and
    (with the sound) the bogie's pass-by it takes part in."""

    radius_m: float
    train_speed_km_h: float
    wheel: WheelKinematics
    analysis: Analysis
    passby: PassbyResult | None = None

    def to_record(self) -> dict[str, Any]:
        """curve.csv's row and summary.json's case."""
        v, w = self.analysis.verdict, self.wheel
        return {
            "radius_m": self.radius_m,
            "train_speed_km_h": self.train_speed_km_h,
            "axle": w.axle,
            "rail": w.rail,
            "angle_of_attack_rad": w.angle_of_attack_rad,
            "lateral_creepage": w.lateral_creepage,
            "crabbing_velocity_m_s": w.crabbing_velocity_m_s,
            "rolling_speed_m_s": w.rolling_speed_m_s,
            "squeals": v.squeals,
            "verdict_mode": v.get("mode") or "",
            "mechanism": v.get("mechanism") or "",
            "tone_hz": v.get("tone_hz"),
            "growth_rate_1_s": v.get("growth_rate_1_s"),
            "amplitude_m_s": v.get("amplitude_m_s"),
            "passby_lpamax_dba": finite_or_none(self.passby.lpamax_dba) if self.passby is not None else None,
            "passby_sel_dba": finite_or_none(self.passby.sel_dba) if self.passby is not None else None,
        }


def _sources(case: CurveCase, wheelbase_m: float, rolling_radius_m: float) -> list[Any]:
    """The wheel as pass-by sources, one per radiated harmonic of its limit cycle (none
    where it does not squeal or was not heard)."""
    from acoustics.farfield import DIRECTIVITY_ANGLES
    from acoustics.levels import a_weighting_db
    from acoustics.passby import HALF_TRACK_M, PassbySource

    o = case.analysis.verdict.outcome
    if o is None or o.sound is None:
        return []
    along = 0.5 * wheelbase_m if case.wheel.axle == "leading" else -0.5 * wheelbase_m
    across = HALF_TRACK_M if case.wheel.rail == "outer" else -HALF_TRACK_M  # the microphone outside the curve
    return [
        PassbySource(
            along,
            across,
            rolling_radius_m,
            f,
            h.velocity_amplitude_m_s * h.radiation.directivity_pa_m,
            DIRECTIVITY_ANGLES,
            o.mode.nodal_diameters,
            float(a_weighting_db(f)),
        )  # fmt: skip
        for h, f in zip(o.sound.harmonics, o.sound.frequencies_hz)
    ]


def curve(
    design: Design,
    radii_m: Sequence[float],
    train_speeds_km_h: Sequence[float],
    bogie: Bogie,
    *,
    stop_after: Stage = "stability",
    context: RunContext | None = None,
    ground_reflection: float = 0.0,
) -> list[CurveCase]:
    """Every wheel of ``bogie`` at every radius and train speed (module docstring).

    Parameters
    ----------
    design : Design
        The wheel and what it rolls on (a track, for the field).
    radii_m, train_speeds_km_h : sequence of float
        Curve radii [m] and train speeds [km/h].
    bogie : track.curving.Bogie
    stop_after : {"stability", "limit_cycle", "sound"}
        How far each verdict goes: the linear verdict, the limit cycle, or its sound and
        the pass-by level.
    ground_reflection : float
        The ground's reflection factor at the pass-by (0: free field).

    Returns
    -------
    list of CurveCase
        Radius by radius, speed by speed, the four wheels in ``track.curving.WHEELS`` order.
    """
    from acoustics.passby import passby
    from track.curving import wheel_kinematics

    from .api import compute_modes
    from .chain import analyse
    from .context import RunContext

    if design.counter_body.KIND != "track":
        raise RequestError(
            f"{design.name} rolls on a {design.counter_body.KIND}: a curve needs a design on a track"
        )
    ctx = context or RunContext.of("balanced")
    modes = compute_modes(design, ctx.fidelity, fmax_hz=ctx.fmax_hz, cache=ctx.cache, progress=ctx.progress,
                          budget=ctx.budget)  # fmt: skip
    options = ChainOptions(mode="model", stop_after=stop_after, remedy=False)
    from reduced import OperatingPoint

    cases: list[CurveCase] = []
    for radius in radii_m:
        for speed in train_speeds_km_h:
            wheels = wheel_kinematics(float(radius), float(speed), bogie)
            by_axle: dict[str, Analysis] = {}
            group = []
            for w in wheels:
                if w.axle not in by_axle:
                    op = OperatingPoint(w.rolling_speed_m_s, w.crabbing_velocity_m_s)
                    by_axle[w.axle] = analyse(design, op=op, options=options, context=ctx, modes=modes)
                group.append(CurveCase(float(radius), float(speed), w, by_axle[w.axle]))
            if stop_after == "sound":
                sources = [s for c in group for s in _sources(c, bogie.wheelbase_m, design.rolling_radius)]
                result = passby(sources, speed / 3.6, reflection=ground_reflection) if sources else None
                group = [replace(c, passby=result) for c in group]
            cases += group
    return cases
