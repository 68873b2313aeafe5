"""The cost plans of the field's commands: the rail's receptances (``track``,
:func:`track_plan`) and a curve map (``curve``, :func:`curve_plan`: radii x speeds x
wheels, their verdicts, the time domain's steps, the sound solves, the pass-by, the memory
it keeps and the files it writes)."""

from __future__ import annotations

from collections.abc import Callable, Sequence
from dataclasses import dataclass
from typing import TYPE_CHECKING

from reduced.integration_cost import simulation_bytes, simulation_seconds

from ..design import Design
from ..mode_stability import StabilityTable, body_of, mode_dofs
from ..runtime.budget import CostPlan
from .fe_cost import estimated_modes, radiation_seconds

if TYPE_CHECKING:
    from fem.modes import Mode, ModeSet
    from reduced import ContactLaw, ModalDOF, OperatingPoint

    from ..presets import Fidelity

__all__ = [
    "CurveSize",
    "SquealingAxles",
    "check_curve_files",
    "curve_plan",
    "line_plan",
    "squealing_axles",
    "track_plan",
]

#: One receptance of the rail at one frequency (a banded solve of the finite rail, 160
#: bays of 10 elements) [s]
RECEPTANCE_SECONDS = 5e-4
#: Bytes per frequency the track command keeps and writes (four complex receptances, the
#: CSV row, the figure's points)
TRACK_BYTES_PER_FREQUENCY = 400


def track_plan(points: int, fits_seconds: float) -> CostPlan:
    """The ``track`` command: the rail's four receptances at ``points`` frequencies and
    the fits the squeal model takes (``fits_seconds``: the counter-body's
    ``model_seconds``)."""
    plan = CostPlan()
    plan.add(
        f"the rail's receptances at {points:,} frequencies (vertical and lateral, at a sleeper and midspan)",
        4 * points * RECEPTANCE_SECONDS,
        TRACK_BYTES_PER_FREQUENCY * points,
        remedy="ask for fewer frequencies",
    )
    plan.add("the fits of the rail's receptances", fits_seconds)
    return plan


#: One radius and speed's wheels beyond their eigen-solves: the harmonic balance of each
#: squealing axle, the sources and the bogie's pass-by over its duration, and the record
#: [s] (on railway_920_track; ``benchmarks/bench_estimates.py`` checks the curve's plan)
CURVE_SECONDS_PER_CURVE = 0.025
#: One radius and speed's steady curving of the bogie (``track.bogie_curving``) [s], the
#: table of contact positions once per process besides (``benchmarks/curving_table.py``)
CURVING_SECONDS_PER_CURVE = 0.1
#: Memory a curve keeps per radius and speed until its files are written (the wheels'
#: analyses and pass-by) [bytes]
CURVE_BYTES_PER_CURVE = 1.0e6
#: Bytes of curve.csv and of curve.nc per row (one wheel at one radius and speed)
CURVE_FILE_BYTES_PER_ROW = 500
#: Before the stability is solved: the modes whose radiation a curve map solves (each
#: squealing mode once), and their frequency as a fraction of the band's top (the modes
#: that squeal are mostly the low ones). Once it is solved, the modes that lead are known
#: and each is priced at its own frequency (:func:`squealing_axles`).
RADIATED_MODES = 2
RADIATED_FRACTION = 0.1
#: A sliding axle's time domain over its first run's estimate: the run is continued
#: (doubled) until its outcome is known, and the record's setup and analysis come on top
#: (over a map of 100 curves of railway_920_track, 100-300 m and 20-60 km/h;
#: benchmarks/bench_estimates.py checks it)
RECORD_EXTENSION = 7.0
#: The curve's record per wheel: that many (the WHEELS of ``track.curving``)
WHEELS_PER_BOGIE = 4


@dataclass(frozen=True)
class CurveSize:
    """What a curve map asks: its radii x speeds and the contacts analysed per curve (the
    four wheels' own, each at its own operating point: a two-point contact adds one)."""

    radii: int
    speeds: int
    contacts: int = 4
    maps: int = 1  # the map run this many times: once, and again under each of the remedy's treatments

    @property
    def times(self) -> str:
        """How the plan's lines say the map is run again (empty: once)."""
        return f", x {self.maps} (the map and the remedy's treatments)" if self.maps > 1 else ""

    @property
    def curves(self) -> int:
        return self.radii * self.speeds


def curve_plan(
    design: Design,
    size: CurveSize,
    time_domain: bool,
    fidelity: Fidelity,
    fmax_hz: float,
    *,
    passbys: int = 1,
    wheel_dofs: Sequence[ModalDOF] | None = None,
    squealing: SquealingAxles | None = None,
) -> CostPlan:
    """The ``curve`` command: every radius x speed x wheel (``size``), by the harmonic
    balance or the ``time_domain``, with ``passbys`` pass-bys per curve (free field and
    over a ground).

    In three steps, each refusing what the budget cannot hold before the next: on counts
    alone (``wheel_dofs`` None: the modes counted from the FE's estimate), with the
    wheel's excitable modes (``wheel_dofs``), and with the linear stability of every
    contact (``squealing``, :func:`squealing_axles`): the contacts the time domain
    integrates and the modes whose sound is solved, each at its own cost."""
    from reduced import ModalDOF
    from reduced.stability import eigen_solve_seconds

    if wheel_dofs is None:
        wheel_dofs = [ModalDOF(1.0, 1.0, 0.0)] * estimated_modes(design, fidelity, fmax_hz)
    body = design.counter_body.states()
    coupled = design.contact.normal_contact == "hertz"
    every = eigen_solve_seconds(wheel_dofs, body_states=body)
    rigid = eigen_solve_seconds(wheel_dofs) if body else 0.0
    verdict = every * (1.0 + (1.4 if coupled else 0.0)) + rigid
    plan = CostPlan()
    hint = "ask for fewer radii or train speeds"
    n_contacts = size.curves * size.contacts
    plan.add(
        f"the steady curving of {size.curves:,} curves{size.times}",
        size.maps * size.curves * CURVING_SECONDS_PER_CURVE,
        remedy=hint,
    )
    # each contact's solved once: the analysis's table prices the rest (squealing_axles)
    solves = size.maps * n_contacts * verdict
    plan.add(
        f"{n_contacts:,} contacts' stability ({len(wheel_dofs)} modes, {body} states of the "
        f"counter-body){size.times}",
        solves,
        remedy=hint,
    )
    plan.add(
        f"{size.curves:,} curves' amplitudes and pass-bys{size.times}",
        size.maps * size.curves * passbys * CURVE_SECONDS_PER_CURVE,
    )
    plan.add(f"the {size.curves:,} curves' records", 0.0, size.curves * CURVE_BYTES_PER_CURVE, remedy=hint)
    if squealing is None:
        radiated = radiation_seconds(design, fidelity, fmax_hz, RADIATED_FRACTION)
        plan.add("the sound of the squealing modes", RADIATED_MODES * radiated)
        return plan
    for label, (seconds, memory) in squealing.sounds.items():
        plan.add(f"the sound of {label}", seconds, memory)
    if time_domain and squealing.time_domain_s:
        plan.add(
            f"the time domain of {len(squealing.time_domain_s):,} squealing contacts{size.times}",
            size.maps * sum(squealing.time_domain_s),
            squealing.record_bytes,
            remedy="leave out the time domain (the harmonic balance is the fast method), or " + hint,
        )
    return plan


@dataclass(frozen=True)
class SquealingAxles:
    """What a curve map's linear stability says it will compute: each growing contact's
    time domain [s] (its first run's estimate times :data:`RECORD_EXTENSION`), the largest
    record's memory [bytes] (one at a time) and the sound of each mode that leads somewhere
    at the frequency it would be radiated at (``acoustics.harmonics.radiation_frequency_hz`` of its
    linear frequency) and at every harmonic either method may radiate (up to
    ``acoustics.harmonics.MAX_HARMONICS`` and ``MAX_HARMONIC_HZ``: a bound, a clean limit cycle
    needs fewer), by label: (seconds, bytes) of its radiation (left out where the cache
    holds it)."""

    time_domain_s: tuple[float, ...]
    sounds: dict[str, tuple[float, float]]
    record_bytes: float = 0.0


def squealing_axles(
    sites: Sequence[tuple[Design, ModeSet, ContactLaw, OperatingPoint, StabilityTable]],
    time_domain: bool,
    cached: Callable[[Mode, float], bool],
) -> SquealingAxles:
    """Each contact of ``sites`` (a wheel's design at that contact, its modes read there,
    its contact law, operating point and linear stability, the analysis's own: solved once,
    read here to price the rest) priced as :class:`SquealingAxles` says;
    ``cached(mode, frequency_hz)`` tells a radiation the cache holds."""
    from acoustics.harmonics import MAX_HARMONIC_HZ, MAX_HARMONICS, radiation_frequency_hz

    from ..presets import MAX_MULTIMODE
    from ..sound import sound_cost

    seconds: list[float] = []
    sounds: dict[str, tuple[float, float]] = {}
    record = 0.0  # one record at a time: a map keeps each one's tail only
    for design, modeset, contact, op, table in sites:
        body = body_of(design)
        if not table.grows:
            continue
        row = table.rows[table.fastest]
        lead = row.mode
        radiated = radiation_frequency_hz(row.stability.damped_frequency_hz, lead.frequency_hz)
        if time_domain:
            group = mode_dofs([r.mode for r in table.rows][:MAX_MULTIMODE], design)
            seconds.append(RECORD_EXTENSION * simulation_seconds(group, contact, op, body=body))
            record = max(record, simulation_bytes(group, contact, op, body=body))
        # the harmonics are known once the record runs or the balance's distortion is found:
        # price every one they may need (either method radiates them)
        top = max(1, min(MAX_HARMONICS, int(MAX_HARMONIC_HZ / radiated)))
        for k in range(1, top + 1):
            f = k * radiated
            label = f"{lead.label()} at {f:.0f} Hz"
            if label in sounds or cached(lead, f):
                continue
            cost = sound_cost(design, modeset, lead, frequency_hz=f)
            if cost is not None:
                sounds[label] = (cost.seconds, cost.memory_bytes)
    return SquealingAxles(tuple(seconds), sounds, record)


def check_curve_files(size: CurveSize, max_file_bytes: float) -> None:
    """Refuse a curve map whose files would exceed ``max_file_bytes`` each."""
    from ..runtime.request_errors import RequestError

    rows = size.curves * WHEELS_PER_BOGIE
    if rows * CURVE_FILE_BYTES_PER_ROW > max_file_bytes:
        raise RequestError(
            f"the curve map ({size.curves:,} curves x {WHEELS_PER_BOGIE} wheels) would write curve.csv and "
            f"curve.nc of about {rows * CURVE_FILE_BYTES_PER_ROW / 1e6:,.0f} MB each, beyond the "
            f"{max_file_bytes / 1e6:.0f} MB a file may take: ask for fewer radii or speeds"
        )


#: One curve of a line in one friction state, on one process [s]: the steady curving and
#: its wheels' contacts' stability, balance and sound (railway_920_track, the first line of
#: ``benchmarks/bench_line.py``, which checks it)
LINE_SECONDS_PER_CURVE_STATE = 0.045
#: A tone the cache does not hold yet, radiated with its views [s], and how many a line
#: may radiate: at most this many per curve state, and a wheel's squealing modes on their
#: tone grid at most :data:`LINE_TONES_MOST` (``benchmarks/bench_line.py``)
LINE_TONE_SECONDS = 0.12
LINE_TONES_PER_CURVE_STATE = 0.3
LINE_TONES_MOST = 300
#: Once per line [s]: the wheel's modes, the rail's fits and the contact tables
LINE_FIXED_SECONDS = 3.0
#: Memory a line keeps per curve until its files are written (its results) [bytes]
LINE_BYTES_PER_CURVE = 2.0e4


def line_plan(curves: int, states: int, workers: int | None = 1) -> CostPlan:
    """The ``line`` command: ``curves`` curves, each in ``states`` friction states, on
    ``workers`` local processes (None: a cluster's, whose time is not priced here, as a
    study's is not)."""
    plan = CostPlan()
    hint = "split the line, give fewer friction states, or use more workers (a cluster)"
    count = curves * states
    tones = min(LINE_TONES_PER_CURVE_STATE * count, LINE_TONES_MOST)
    share = 0.0 if workers is None else 1.0 / max(workers, 1)
    plan.add(
        f"{curves:,} curves x {states} friction states on {workers or 'a cluster'} process(es)",
        share * (count * LINE_SECONDS_PER_CURVE_STATE + tones * LINE_TONE_SECONDS) + LINE_FIXED_SECONDS,
        curves * LINE_BYTES_PER_CURVE,
        remedy=hint,
    )
    return plan
