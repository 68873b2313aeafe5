"""The one answer to "does it squeal, in which mode, at what tone, how loud": the rule
and its result, the same for every command and the Python API.

The rule, at one operating point:

- no mode grows (the linear stability of every mode the contact sees): **no squeal**,
  with the margin: the least stable mode, how fast it decays, and the damping ratio or
  friction slope that would make it grow;
- otherwise the squeal mode is the fastest-growing one (with a multi-mode run: the mode
  that carries the multi-mode limit cycle, which the time domain decides);
- a mode named by the design (``[squeal] mode``) or by the user (``--mode``) is an
  **override**: it is simulated and reported as asked, and the model's own pick stands
  beside it. When the named mode is stable here and another grows, the verdict says so
  and reports the squeal (and level) of the model's pick: never "no squeal" while a mode
  grows.

Whether it squeals is the decision's (a mode grows at steady sliding), whatever the
amplitude method: where the time domain's record from rest dies out, the verdict still
squeals, without an amplitude, and says so. A run that ends still growing is a state of
its own (``saturated`` False): its level is "not a limit cycle".
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import TYPE_CHECKING, Any

from .outputs import finite_or_none
from .types import Mechanism, Wave

if TYPE_CHECKING:
    from fem.modes import Mode

    from .simulation import Simulation
    from .squeal_sound import SquealSound

__all__ = ["COUPLING_ONLY", "LEVELS", "LOWEST_SQUEAL_HZ", "Balance", "ModeOutcome", "Verdict", "wave_of"]

#: An oscillation below this frequency [Hz] (the lower limit of hearing) is an
#: instability, not a squeal: no level or sound file is given for it
LOWEST_SQUEAL_HZ = 20.0

#: The levels a verdict gives (summary.json's ``sound`` has more): at the microphone, the
#: sound power, and at the common distances from the wheel centre (1 m, 7.5 m: levels
#: that compare wheels of different sizes)
LEVELS = ("spl_db", "spl_dba", "sound_power_level_db", "sound_power_level_dba", "spl_1m_db", "spl_7_5m_db")


#: What is said of a squeal whose amplitude the harmonic balance cannot give
COUPLING_ONLY = "mode coupling alone: its amplitude needs the time domain"


@dataclass(frozen=True)
class Balance:
    """A squeal's limit cycle by harmonic balance, without a time domain
    (``wheel_squeal.chain``): the contact velocity amplitude [m/s] (None: the balance has
    none, ``note`` says why), the contact force's distortion (its rms beyond the
    fundamental over the modal force; under 0.1 the amplitude is within a few per cent of
    the time domain's) and a note where something was left out (a lower bound, mode
    coupling alone)."""

    amplitude_m_s: float | None
    distortion: float | None = None
    note: str = ""


def wave_of(mode: Mode, frequency_hz: float, wheel_speed_rad_s: float) -> Wave:
    """ "standing", or for a pair on a turning wheel the wave whose frequency
    (f0 -/+ n Omega / 2 pi) ``frequency_hz`` [Hz] is nearer: "backward" or "forward"."""
    if wheel_speed_rad_s == 0.0 or mode.nodal_diameters == 0:
        return "standing"
    return "backward" if frequency_hz < mode.frequency_hz else "forward"


@dataclass(frozen=True)
class ModeOutcome:
    """One mode at the operating point: its linear growth rate and frequency, and when
    integrated its limit cycle (``simulation``) and sound.

    Attributes
    ----------
    mode : fem.Mode
    growth_rate_1_s : float
        The linear growth rate [1/s] of the eigenvalue it holds (> 0: it grows).
    damped_frequency_hz : float
        The linear frequency at the contact [Hz].
    wave : {"standing", "backward", "forward"}
        How the contact sees it (:func:`wave_of`).
    simulation : Simulation or None
        The record it was integrated in (None: linear only).
    sound : SquealSound or None
        Its levels (None: not radiated).
    energy_share : float or None
        Its share of the limit cycle's vibration energy (None: integrated alone).
    mechanism : {"falling friction", "mode coupling", "both"} or None
        What makes its eigenvalue grow (None while it decays).
    group : tuple of fem.Mode
        The modes integrated together (empty: not integrated).
    shares : dict or None
        Every degree of freedom's share of the limit cycle's energy, by label.
    balance : Balance or None
        Its limit cycle by harmonic balance (the chain's faster amplitude method; None:
        the time domain's, or linear only).
    carrier_tone_hz : float or None
        In a multi-mode record, its own coordinates' strongest frequency [Hz]: the tone
        where the record is not one periodic motion (``reduced.modal_content``).

    Examples
    --------
    >>> import wheel_squeal as ws
    >>> a = ws.analyse(ws.load_design(), modes=ws.explicit_modes(3.1, 1.6e8, 42), stop_after="stability")
    >>> o = a.verdict.pick
    >>> o.grows, round(o.growth_rate_1_s, 2), o.state_words
    (True, 8.63, 'linear analysis only')
    """

    mode: Mode
    growth_rate_1_s: float
    damped_frequency_hz: float
    wave: Wave = "standing"
    simulation: Simulation | None = None
    sound: SquealSound | None = None
    energy_share: float | None = None
    mechanism: Mechanism | None = None
    group: tuple[Mode, ...] = ()
    shares: dict[str, float] | None = None
    balance: Balance | None = None
    carrier_tone_hz: float | None = None

    @property
    def label(self) -> str:
        return self.mode.label()

    @property
    def grows(self) -> bool:
        """Whether its linear growth rate is positive."""
        return self.growth_rate_1_s > 0.0

    @property
    def squeals(self) -> bool:
        """The time domain's answer (a self-sustained oscillation from rest) where it was
        simulated, the linear one otherwise."""
        if self.simulation is None:
            return self.grows
        return bool(self.simulation.limit_cycle.squeal)

    @property
    def saturated(self) -> bool:
        """Whether the simulated oscillation reached its limit cycle (False: still
        growing at the end of the run, or not simulated)."""
        return self.simulation is not None and bool(self.simulation.limit_cycle.saturated)

    @property
    def state_words(self) -> str:
        """What its record shows, in words: a limit cycle, still growing, not settled
        (a sustained oscillation that is not a clean limit cycle), or linear analysis only."""
        if self.simulation is None:
            if self.balance is not None:
                return "harmonic balance" if self.balance.amplitude_m_s is not None else self.balance.note
            return "linear analysis only"
        lc = self.simulation.limit_cycle
        end = f"after {self.duration_s:.3g} s"
        return {
            "limit cycle": "limit cycle",
            "still growing": f"still growing {end}: not a limit cycle",
            "not settled": f"not settled {end}: sustained, not a clean limit cycle",
            "quiet": f"quiet {end}",
        }[lc.state]

    @property
    def amplitude_m_s(self) -> float | None:
        """Contact velocity amplitude [m/s]: at the end of the run, or the harmonic
        balance's (None: neither)."""
        if self.simulation is None:
            return None if self.balance is None else finite_or_none(self.balance.amplitude_m_s)
        return finite_or_none(self.simulation.limit_cycle.velocity_amplitude_m_s)

    @property
    def amplitude_method(self) -> str:
        """How its amplitude was found: "time domain", "harmonic balance" or "" (none)."""
        if self.simulation is not None:
            return "time domain"
        return "harmonic balance" if self.amplitude_m_s is not None else ""

    @property
    def tone_hz(self) -> float:
        """The tone a fixed microphone hears [Hz]: the limit cycle's frequency where it
        squeals, else the linear frequency."""
        if self.simulation is not None and self.squeals:
            # several modes in a record that is not one periodic motion: the tone of the
            # mode named for it (a zero-crossing count would follow whichever dominates)
            if self.carrier_tone_hz is not None and self.simulation.limit_cycle.state == "not settled":
                return self.carrier_tone_hz
            f = finite_or_none(self.simulation.limit_cycle.frequency_hz)
            if f is not None:
                return f
        return self.damped_frequency_hz

    @property
    def duration_s(self) -> float | None:
        return None if self.simulation is None else float(self.simulation.history.t[-1])

    def levels(self) -> dict:
        """SPL at the microphone in dB and dB(A), and the sound power level [dB] (None
        without sound)."""
        s = self.sound.summary() if self.sound is not None else {}
        return {k: s.get(k) for k in LEVELS}

    def to_dict(self, levels: bool = True) -> dict:
        """JSON-ready fields; ``levels`` False leaves out :meth:`levels` (a far field each)."""
        return {
            "mode": self.label,
            "mode_index": self.mode.index,
            "squeals": self.squeals,
            "tone_hz": finite_or_none(self.tone_hz),
            "wave": self.wave,
            "growth_rate_1_s": finite_or_none(self.growth_rate_1_s),
            "mechanism": self.mechanism,
            "amplitude_m_s": self.amplitude_m_s,
            "amplitude_method": self.amplitude_method,
            "saturated": self.saturated,
            **(self.levels() if levels else {}),
            **({"energy_share": self.energy_share} if self.energy_share is not None else {}),
            **({"energy_shares": self.shares} if self.shares is not None else {}),
        }


@dataclass(frozen=True)
class Verdict:
    """The answer at one operating point (see the module docstring).

    Attributes
    ----------
    squeals : bool
    outcome : ModeOutcome or None
        The squealing mode's (None: no squeal).
    reason : str
        The rule applied, in words.
    named : ModeOutcome or None
        The outcome of the mode the design or the request named (None: none named).
    pick : ModeOutcome or None
        The model's own outcome (the modes that grow together, or its linear pick).
    margin : dict or None
        With no squeal: the least stable mode and what would make it grow.
    remedy : dict or None
        With a squeal: what would stop it.
    counter_body_effect_1_s : float or None
        With a counter-body that moves (a rail, a roller with modes): how much its own
        degrees of freedom add to the fastest growth rate [1/s] (negative: remove),
        against it rigid with the same contact.
    damping : (float, str) or None
        The squeal mode's damping ratio and where it comes from (the design's key for
        the mode, its family, ``modal_damping_ratio``, or "measured").

    Examples
    --------
    >>> import wheel_squeal as ws
    >>> a = ws.analyse(ws.load_design(), modes=ws.explicit_modes(3.1, 1.6e8, 42), stop_after="limit_cycle")
    >>> v = a.verdict
    >>> v.squeals, v.get("saturated"), round(v.get("tone_hz"))
    (True, True, 1143)
    """

    squeals: bool
    outcome: ModeOutcome | None
    reason: str
    named: ModeOutcome | None = None
    pick: ModeOutcome | None = None
    margin: dict | None = None
    remedy: dict | None = None
    counter_body_effect_1_s: float | None = None
    damping: tuple[float, str] | None = None

    def get(self, key: str) -> Any:
        """A field of the verdict's outcome (None without squeal)."""
        if self.outcome is None:
            return None
        if key in LEVELS:  # the levels alone: the other fields cost nothing, these a far field
            return self.outcome.levels().get(key)
        return self.outcome.to_dict(levels=False).get(key)

    @property
    def amplitude_m_s(self) -> float | None:
        """The squeal's contact velocity amplitude [m/s] (None: no squeal, or none found)."""
        return None if self.outcome is None else self.outcome.amplitude_m_s

    def headline(self) -> str:
        """The verdict in a few words: "squeals in MODE by MECHANISM at F Hz" or "no squeal"."""
        o = self.outcome
        if not self.squeals or o is None:
            return "no squeal"
        return f"squeals in {o.label} by {o.mechanism or 'an instability'} at {o.tone_hz:.1f} Hz"

    def to_dict(self) -> dict:
        """``summary.json``'s ``verdict``."""
        o = self.outcome
        out = {
            "squeals": self.squeals,
            "mode": o.label if o else None,
            "mode_index": o.mode.index if o else None,
            "tone_hz": finite_or_none(o.tone_hz) if o else None,
            "wave": o.wave if o else None,
            "growth_rate_1_s": finite_or_none(o.growth_rate_1_s) if o else None,
            "mechanism": o.mechanism if o else None,
            "amplitude_m_s": o.amplitude_m_s if o else None,
            "amplitude_method": o.amplitude_method if o else "",
            "saturated": o.saturated if o else False,
            **(o.levels() if o else dict.fromkeys(LEVELS)),
            "reason": self.reason,
        }
        if o is not None and o.shares is not None:
            out["energy_share"] = o.energy_share
            out["energy_shares"] = o.shares
        if self.named is not None:
            out["override"] = self.named.to_dict()
            out["model_pick"] = self.pick.to_dict() if self.pick is not None else None
        if self.margin is not None:
            out["margin"] = self.margin
        if self.remedy is not None:
            out["remedy"] = self.remedy
        if self.counter_body_effect_1_s is not None:
            out["counter_body_effect_1_s"] = self.counter_body_effect_1_s
        if self.damping is not None:
            out["damping_ratio"], out["damping_source"] = self.damping
        return out
