"""The cost plans of the field's commands: the rail's receptances (``track``,
:func:`track_plan`) and a curve map (``curve``, :func:`curve_plan`: radii x speeds x
wheels, their verdicts, the time domain's steps, the sound solves, the pass-by, the memory
it keeps and the files it writes)."""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass
from typing import TYPE_CHECKING

from ..api import simulation_seconds
from ..budget import CostPlan
from ..design import Design
from ..stability import contact_dofs
from .fe import estimated_modes, radiation_seconds

if TYPE_CHECKING:
    from fem.modes import Mode
    from reduced import ContactLaw, ModalDOF, OperatingPoint

    from ..presets import Fidelity

__all__ = ["CurveSize", "check_curve_files", "curve_plan", "time_domain_axle_seconds", "track_plan"]

#: One receptance of the rail at one frequency (a banded solve of the finite rail, 160
#: bays of 10 elements) [s], and the modal fits of both directions (once per track) [s]:
#: measured 0.47 ms and 1.5 s.
RECEPTANCE_SECONDS, TRACK_FIT_SECONDS = 5e-4, 1.5
#: Bytes per frequency the track command keeps and writes (four complex receptances, the
#: CSV row, the figure's points)
TRACK_BYTES_PER_FREQUENCY = 400


def track_plan(points: int) -> CostPlan:
    """The ``track`` command: the rail's four receptances at ``points`` frequencies and
    the fits the squeal model takes."""
    plan = CostPlan()
    plan.add(
        f"the rail's receptances at {points:,} frequencies (vertical and lateral, at a sleeper and midspan)",
        4 * points * RECEPTANCE_SECONDS,
        TRACK_BYTES_PER_FREQUENCY * points,
        remedy="ask for fewer frequencies",
    )
    plan.add("the fits of the rail's receptances", TRACK_FIT_SECONDS)
    return plan


#: One radius and speed's wheels beyond their eigen-solves: the harmonic balance of each
#: squealing axle, the sources and the bogie's pass-by over its duration, and the record
#: [s] (measured 25 ms on railway_920_track)
CURVE_SECONDS_PER_CURVE = 0.025
#: Memory a curve keeps per radius and speed until its files are written (the wheels'
#: analyses and pass-by) [bytes]: measured 0.9 MB
CURVE_BYTES_PER_CURVE = 1.0e6
#: Bytes of curve.csv and of curve.nc per row (one wheel at one radius and speed)
CURVE_FILE_BYTES_PER_ROW = 500
#: Modes whose radiation a curve map solves (each squealing mode once): one or two
RADIATED_MODES = 2
#: The frequency of a radiated mode, as a fraction of the band's top: the modes that
#: squeal are the low ones (the (2,0) of a railway wheel at 330 Hz below 5 kHz)
RADIATED_FRACTION = 0.1
#: The curve's record per wheel: that many (the WHEELS of ``track.curving``)
WHEELS_PER_BOGIE = 4


@dataclass(frozen=True)
class CurveSize:
    """What a curve map asks: its radii x speeds, the axles of a bogie whose wheels are
    analysed (each at its own operating point) and how many of them slide laterally (the
    ones that can squeal, which the time domain integrates)."""

    radii: int
    speeds: int
    axles: int = 2
    sliding_axles: int = 1

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
    time_domain_seconds: float | None = None,
) -> CostPlan:
    """The ``curve`` command: every radius x speed x wheel (``size``), by the harmonic
    balance or the ``time_domain``, with ``passbys`` pass-bys per curve (free field and
    over a ground).

    Before the modes are solved ``wheel_dofs`` is None and the modes are counted from the
    FE's estimate (``fem.cost``): a request far beyond the budget is refused before any
    work. With the wheel's excitable modes (``wheel_dofs``) and the time domain's seconds
    per sliding axle (``time_domain_seconds``, from the modes: :func:`time_domain_axle_seconds`)
    the plan is the one the map runs by."""
    from reduced import ModalDOF
    from reduced.stability import eigen_solve_seconds

    if wheel_dofs is None:
        wheel_dofs = [ModalDOF(1.0, 1.0, 0.0)] * estimated_modes(design, fidelity, fmax_hz)
    body = [ModalDOF(1.0, 1.0, 0.0)] * design.counter_body.dof_count()
    coupled = design.contact.normal_contact == "hertz"
    every = eigen_solve_seconds([*wheel_dofs, *body])
    rigid = eigen_solve_seconds(wheel_dofs) if body else 0.0
    verdict = every * (1.0 + (1.4 if coupled else 0.0)) + rigid
    plan = CostPlan()
    hint = "ask for fewer radii or train speeds"
    n_axles = size.curves * size.axles
    plan.add(
        f"{n_axles:,} axles' stability ({len(wheel_dofs)} modes, {len(body)} of the counter-body's)",
        n_axles * verdict,
        remedy=hint,
    )
    plan.add(
        f"{size.curves:,} curves' amplitudes and pass-bys", size.curves * passbys * CURVE_SECONDS_PER_CURVE
    )
    plan.add(f"the {size.curves:,} curves' records", 0.0, size.curves * CURVE_BYTES_PER_CURVE, remedy=hint)
    radiated = radiation_seconds(design, fidelity, fmax_hz, RADIATED_FRACTION)
    plan.add("the sound of the squealing modes", RADIATED_MODES * radiated)
    if time_domain:
        per_axle = time_domain_seconds if time_domain_seconds is not None else 0.0
        plan.add(
            f"the time domain of {size.curves * size.sliding_axles:,} sliding axles",
            size.curves * size.sliding_axles * per_axle,
            remedy="leave out the time domain (the harmonic balance is the fast method), or " + hint,
        )
    return plan


def check_curve_files(size: CurveSize, max_file_bytes: float) -> None:
    """Refuse a curve map whose files would exceed ``max_file_bytes`` each."""
    from ..errors import RequestError

    rows = size.curves * WHEELS_PER_BOGIE
    if rows * CURVE_FILE_BYTES_PER_ROW > max_file_bytes:
        raise RequestError(
            f"the curve map ({size.curves:,} curves x {WHEELS_PER_BOGIE} wheels) would write curve.csv and "
            f"curve.nc of about {rows * CURVE_FILE_BYTES_PER_ROW / 1e6:,.0f} MB each, beyond the "
            f"{max_file_bytes / 1e6:.0f} MB a file may take: ask for fewer radii or speeds"
        )


def time_domain_axle_seconds(
    design: Design, modes: Sequence[Mode], contact: ContactLaw, ops: Sequence[OperatingPoint]
) -> float:
    """The time domain of one sliding axle, the largest over ``ops`` [s]: the decision
    integrates at most ``presets.MAX_MULTIMODE`` modes of the growing eigenvalues (here
    the lowest excitable ones) with the counter-body, from rest, for the first run."""
    from ..presets import MAX_MULTIMODE

    group = contact_dofs(list(modes)[:MAX_MULTIMODE], design)
    return max((simulation_seconds(group, contact, op) for op in ops), default=0.0)
