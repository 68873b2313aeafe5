"""The chain's options (what a request computes, :class:`ChainOptions`) and its record
(:class:`Analysis`: the verdict and what it rests on, and one flat record of it for a
row of compare.csv, a sweep's point or a study's case)."""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import TYPE_CHECKING, Any

from .api import modal_dof
from .decision import Decision
from .design import Design
from .listener import Listener
from .mode_stability import StabilityTable
from .presets import MAX_MULTIMODE, Fidelity
from .types import AmplitudeMethod, Stage
from .verdict import LEVELS, ModeOutcome, Verdict

if TYPE_CHECKING:
    from fem.modes import ModeSet
    from reduced import ContactLaw, OperatingPoint, StabilityResult

    from .mode_stability import ModeStabilityRow

__all__ = ["STAGES", "Analysis", "ChainOptions"]

#: The chain's stages in order (a request stops after one of them).
STAGES: tuple[Stage, ...] = ("stability", "limit_cycle", "sound")


@dataclass(frozen=True)
class ChainOptions:
    """What :func:`~wheel_squeal.chain.analyse` computes (every field a keyword of it too).

    Attributes
    ----------
    mode : str
        "auto" (the design's named mode, else the model's own outcome), "model" (the
        model's own outcome, whatever the design names) or a mode the request names (an
        index, ``n=3[,c=0]``, ``f=HZ``): an override, integrated as asked.
    rotation : bool
        Model the wheel's rotation (travelling waves).
    max_modes : int
        The most modes the model's own outcome integrates together.
    duration : float or None
        Simulated time [s] (None: until the outcome is known).
    stop_after : {"stability", "limit_cycle", "sound"}
        The last stage: the linear verdict, the limit cycle, or its sound too.
    listener : Listener or None
        Microphone and air (default: 0.05 m off the rim face, air at 20 degC).
    c22 : float, "kalker" or None
        The creep coefficient (None: the design's).
    friction_law : str or None
        A name of ``contact.creep.FRICTION_LAWS`` (None: the design's).
    remedy : bool
        What would stop the squeal (or, with none, how far it is from growing): some 20
        eigen-solves; False leaves it out (studies).
    simulate_stable : bool
        Integrate a named mode even where it is linearly stable (from rest it decays);
        False takes the linear answer for it.
    beside : bool
        Beside a named mode that squeals, the model's own outcome integrated too (False:
        its linear pick; sweeps and studies).
    amplitude : {"time domain", "harmonic balance"}
        How the limit cycle's amplitude is found: the time domain from rest of the modes
        the decision integrates (its harmonics radiated), or the harmonic balance of the
        squeal mode (fast: no time domain; the fundamental radiated).
    counter_body_effect : bool
        With a counter-body that moves (a rail, a roller with modes), what it adds to the
        fastest growth rate (one more eigen-solve, of the wheel on a rigid one); False
        leaves it out (a line, which reads neither it nor the reason's words).
    stable_rows : bool
        Where no eigenvalue grows, every mode's row of the stability table (its own
        eigenvalue, from the eigenvectors); False leaves them out there, the eigenvalues
        alone saying that nothing grows, at about half the cost (a curve map, which reads
        only its contacts' verdicts). A request that names a mode or asks for the remedy
        reads the rows: it has them whatever this says.

    Examples
    --------
    >>> from wheel_squeal import ChainOptions
    >>> ChainOptions(stop_after="stability").reaches("limit_cycle")
    False
    """

    mode: str = "auto"
    rotation: bool = False
    max_modes: int = MAX_MULTIMODE
    duration: float | None = None
    stop_after: Stage = "sound"
    listener: Listener | None = None
    c22: float | str | None = None
    friction_law: str | None = None
    remedy: bool = True
    simulate_stable: bool = True
    beside: bool = True
    amplitude: AmplitudeMethod = "time domain"
    counter_body_effect: bool = True
    stable_rows: bool = True

    def reaches(self, stage: Stage) -> bool:
        """Whether the request goes as far as ``stage``."""
        return STAGES.index(self.stop_after) >= STAGES.index(stage)


@dataclass
class Analysis:
    """The chain's result at one operating point: the verdict and what it rests on.

    Attributes
    ----------
    design : Design
    options : ChainOptions
        What was computed (the stage it stopped after, the mode named, ...).
    fidelity : Fidelity
        The FE preset of the modes.
    modeset : fem.ModeSet
        The modes (a modal model's, or the FE's up to the band).
    operating_point : reduced.OperatingPoint
        Rolling speed [m/s] and crabbing velocity [m/s].
    contact : reduced.ContactLaw
        The creep law at the contact.
    table : StabilityTable
        Every mode's linear stability (solved once).
    decision : Decision
        What the verdict integrated.
    verdict : Verdict
        The answer.
    wheel_speed_rad_s : float
        Omega, the rotation modelled [rad/s] (0: off).
    timings_s : dict
        Seconds per stage.

    Examples
    --------
    >>> import wheel_squeal as ws
    >>> a = ws.analyse(ws.load_design(), modes=ws.explicit_modes(3.1, 1.6e8, 42), stop_after="limit_cycle")
    >>> record = a.to_record()
    >>> record["squeals"], round(record["amplitude_m_s"], 3), record["mechanism"]
    (True, 0.367, 'falling friction')
    """

    design: Design
    options: ChainOptions
    fidelity: Fidelity
    modeset: ModeSet
    operating_point: OperatingPoint
    contact: ContactLaw
    table: StabilityTable
    decision: Decision
    verdict: Verdict
    wheel_speed_rad_s: float = 0.0
    timings_s: dict[str, float] = field(default_factory=dict)

    def __repr__(self) -> str:
        op = self.operating_point
        # a table without rows: nothing grows and the request left them out (stable_rows)
        eigenvalues = len(self.stability.eigenvalues)
        modes = f"{len(self.rows)} modes" if self.rows else f"{eigenvalues} eigenvalues, no rows"
        return (
            f"Analysis({self.design.name!r}, V0 = {op.rolling_speed_m_s:.4g} m/s, Vc = "
            f"{op.crabbing_velocity_m_s:.4g} m/s, {modes}, stopped after "
            f"{self.options.stop_after!r}: {self.verdict.headline()})"
        )

    def tail(self, seconds: float) -> Analysis:
        """The analysis with every record it holds (the squeal model's, the microphone
        signal) cut to its last ``seconds``, its metrics kept: what a map of many
        analyses keeps of each."""
        from dataclasses import replace

        def cut(o: ModeOutcome | None) -> ModeOutcome | None:
            if o is None:
                return None
            sound = o.sound
            if sound is not None and sound.signal is not None:
                sound = replace(sound, signal=sound.signal.tail(seconds))
            simulation = o.simulation.tail(seconds) if o.simulation is not None else None
            return replace(o, simulation=simulation, sound=sound)

        v = self.verdict
        return replace(self, verdict=replace(v, outcome=cut(v.outcome), named=cut(v.named), pick=cut(v.pick)))

    @property
    def rows(self) -> list[ModeStabilityRow]:
        return self.table.rows

    @property
    def stability(self) -> StabilityResult:
        return self.table.result

    @property
    def rotation(self) -> bool:
        return self.options.rotation

    @property
    def outcome(self) -> ModeOutcome | None:
        """The simulated outcome the verdict rests on: the squealing one, else the named
        one, else the model's (None when nothing was simulated)."""
        v = self.verdict
        for o in (v.outcome, v.named, v.pick):
            if o is not None and o.simulation is not None:
                return o
        return None

    def to_record(self) -> dict[str, Any]:
        """The verdict as one flat record (``wheel_squeal.fields`` names and units): a
        row of compare.csv, a point of a sweep, a case of a study."""
        v = self.verdict
        d = v.to_dict()
        o = v.outcome or v.named or v.pick
        dof = modal_dof(o.mode, self.design) if o is not None else None
        return {
            "design": self.design.name,
            "rolling_speed_m_s": self.operating_point.rolling_speed_m_s,
            "rpm": self.operating_point.rpm(self.design.rolling_radius),
            "crabbing_velocity_m_s": self.operating_point.crabbing_velocity_m_s,
            "squeals": v.squeals,
            "verdict_mode": d["mode"] or "",
            "mechanism": d["mechanism"] or "",
            "tone_hz": d["tone_hz"],
            "growth_rate_1_s": d["growth_rate_1_s"] if v.squeals else self.stability.growth_rate_1_s,
            "amplitude_m_s": d["amplitude_m_s"],
            "saturated": d["saturated"],
            **{k: d[k] for k in LEVELS},
            "override_mode": v.named.label if v.named else "",
            "override_growth_rate_1_s": v.named.growth_rate_1_s if v.named else None,
            "model_pick": v.pick.label if v.pick else "",
            "model_pick_growth_rate_1_s": v.pick.growth_rate_1_s if v.pick else None,
            "mode_frequency_hz": o.mode.frequency_hz if o else None,
            "modal_mass_kg": dof.mass_kg if dof else None,
            "modal_stiffness_n_m": dof.stiffness_n_m if dof else None,
            "modal_damping_ns_m": dof.damping_ns_m if dof else None,
            "reason": v.reason,
        }
