"""What would stop a squeal, or start one, in the design's words.

- :func:`remedy_of`: with a squeal, the whole wheel's remedy at the operating point
  (``reduced.remedy``): the damping ratios with which no mode grows (every mode that
  would, by its label), the friction coefficient and the creep-curve slope below or above
  which nothing grows, and for mode coupling the frequency the higher partner must reach.
  The damping is checked by solving the stability again with the design as it would be
  once the remedy is pasted in (:func:`remedy_design`); the chain checks it once more by a
  time-domain run. :func:`remedy_toml` is the ``[squeal.damping]`` table to paste.
- :func:`margin_of`: with no squeal, how far the least stable mode is from growing.
"""

from __future__ import annotations

import json
import math
from collections.abc import Sequence
from typing import TYPE_CHECKING, Any

from geometry.schema import toml_value

from .design import Design
from .mode_stability import ModeStabilityRow, body_of, mode_dofs, wheel_speed_rad_s
from .model_sections import mode_key
from .outputs import bound_or_none, needed_or_none

if TYPE_CHECKING:
    from fem.modes import Mode
    from reduced import ContactLaw, ModalDOF, ModeStability, OperatingPoint

__all__ = ["bounds_seconds", "margin_of", "remedy_design", "remedy_of", "remedy_seconds", "remedy_toml"]


def bounds_seconds(dofs: Sequence[ModalDOF], rotation: bool = False, body_states: int = 0) -> float:
    """The estimated time of one mode's critical damping and friction slope among
    ``dofs`` and a counter-body of ``body_states`` states [s] (the margin of a quiet point)."""
    from reduced.stability import bound_solves, eigen_solve_seconds

    return bound_solves(len(dofs)) * eigen_solve_seconds(dofs, rotation, body_states)


def remedy_seconds(
    dofs: Sequence[ModalDOF], n_growing: int, rotation: bool = False, body_states: int = 0
) -> float:
    """The estimated time of :func:`remedy_of` among ``dofs`` and a counter-body of
    ``body_states`` states with ``n_growing`` growing eigenvalues [s]."""
    from reduced.remedy import remedy_solves
    from reduced.stability import eigen_solve_seconds

    return remedy_solves(len(dofs), n_growing) * eigen_solve_seconds(dofs, rotation, body_states)


def damping_key(mode: Mode) -> str:
    """The ``[squeal.damping]`` key of a mode: a modal model's label, else ``n=N,c=C``."""
    return (
        mode.name
        if mode.damping_ratio is not None and mode.name
        else mode_key(f"n={mode.nodal_diameters},c={mode.nodal_circles}")
    )


def remedy_design(design: Design, damping: dict[str, float]) -> Design:
    """``design`` with ``damping`` (``[squeal.damping]`` keys to ratios) pasted in: the
    table it has, each key raised to the larger ratio."""
    merged = dict(design.damping.by_mode)
    for key, ratio in damping.items():
        merged[key] = max(ratio, merged.get(key, 0.0))
    return design.replace(mode_damping=tuple(sorted(merged.items())))


def _slope_now(contact: ContactLaw, op: OperatingPoint) -> float:
    from reduced import friction_damping_ns_m

    return friction_damping_ns_m(contact, op) * op.rolling_speed_m_s / contact.normal_load_n


def remedy_of(
    design: Design,
    rows: Sequence[ModeStabilityRow],
    contact: ContactLaw,
    op: OperatingPoint,
    rotation: bool = False,
    mechanisms: Sequence[tuple[str | None, Sequence[int]]] = (),
) -> dict[str, Any]:
    """What stops every growing mode at ``op`` (the module docstring).

    Parameters
    ----------
    design : Design
    rows : sequence of ModeStabilityRow
        The stability table's rows (every mode the contact sees).
    contact : reduced.ContactLaw
    op : reduced.OperatingPoint
    rotation : bool
        Model the wheel's rotation.
    mechanisms : sequence of (mechanism, rows)
        Each growing eigenvalue's mechanism and the rows taking part in it: a coupled
        pair gets its frequency separation.

    Returns
    -------
    dict
        ``damping`` (label -> ratio, every mode raised), ``damping_now``, ``settled``,
        ``growth_rate_1_s`` (the largest with the damping pasted in, re-solved),
        ``friction_coefficient`` and ``friction_slope`` (None: no such lever), their
        values now, ``separations``, ``toml`` (the table to paste) and ``words``.
    """
    from reduced.remedy import (
        damping_to_stop,
        friction_coefficient_to_stop,
        friction_slope_to_stop,
        held_growth_rates,
        separation_to_stop,
    )

    modes = [r.mode for r in rows]
    omega = wheel_speed_rad_s(design, op, rotation)
    dofs = mode_dofs(modes, design)
    body = body_of(design)
    found = damping_to_stop(dofs, contact, op, omega, adjustable=range(len(modes)), body=body)
    by_key: dict[str, float] = {}
    damping, damping_now = {}, {}
    for k in found.raised:
        m = modes[k]
        damping[m.label()] = float(found.damping_ratio[k])
        damping_now[m.label()] = design.damping_ratio_of(m)
        key = damping_key(m)
        by_key[key] = max(by_key.get(key, 0.0), float(found.damping_ratio[k]))
    pasted = remedy_design(design, by_key)
    rate, own = held_growth_rates(mode_dofs(modes, pasted), contact, op, omega, range(len(modes)), body)
    # found aims at DECAY_RATE_1_S; once pasted (a (n, c) key damps every family alike)
    # it must leave nothing growing
    settled = found.settled and max(rate, own) < 0.0
    unsettled = found.reason or (
        f"with the table pasted an eigenvalue grows at {max(rate, own):.3g} 1/s" if not settled else ""
    )
    mu = friction_coefficient_to_stop(dofs, contact, op, omega, body)
    slope = friction_slope_to_stop(dofs, contact, op, omega, body)
    separations = []
    for mechanism, members in mechanisms:
        pair = [k for k in members if k < len(modes)][:2]
        if mechanism in ("mode coupling", "both") and len(pair) == 2:
            f = separation_to_stop(dofs, contact, op, (pair[0], pair[1]), omega, body)
            hi = max(pair, key=lambda k: modes[k].frequency_hz)
            lo = min(pair, key=lambda k: modes[k].frequency_hz)
            separations.append(
                {
                    "mode": modes[hi].label(),
                    "partner": modes[lo].label(),
                    "frequency_hz_now": modes[hi].frequency_hz,
                    "frequency_hz": f,
                }
            )
    out = {
        "damping": damping,
        "damping_now": damping_now,
        "settled": settled,
        "growth_rate_1_s": rate,
        "friction_coefficient": mu,
        "friction_coefficient_now": contact.friction_coefficient,
        "friction_slope": slope,
        "friction_slope_now": _slope_now(contact, op),
        "separations": separations,
        "paste": by_key,
        "counter_body_growth_rate_1_s": own if own > 0.0 else None,
    }
    out["words"] = remedy_words(out, unsettled)
    return out


def remedy_words(r: dict[str, Any], unsettled: str = "") -> str:
    """The remedy in one sentence."""
    ratios = ", ".join(f"{lab} {z:.2g} (now {r['damping_now'][lab]:.2g})" for lab, z in r["damping"].items())
    if r["settled"]:
        parts = [f"with these damping ratios no mode grows: {ratios}"]
    else:
        parts = [f"no damping of the wheel's modes alone ({unsettled})"]
    mu, slope = r["friction_coefficient"], r["friction_slope"]
    if mu is not None:
        parts.append(f"a friction coefficient below {mu:.2g} (now {r['friction_coefficient_now']:.2g})")
    if slope is not None:
        parts.append(
            f"a creep curve falling less steeply than dmu/dzeta = {slope:.3g} at the quasi-static "
            f"creepage (now {r['friction_slope_now']:.3g})"
        )
    for s in r["separations"]:
        if s["frequency_hz"] is not None:
            parts.append(
                f"{s['mode']} moved from {s['frequency_hz_now']:.1f} Hz to above {s['frequency_hz']:.1f} Hz "
                f"(away from {s['partner']})"
            )
    return "; or ".join(parts)


def remedy_toml(design: Design, remedy: dict[str, Any], where: str) -> str:
    """remedy.toml: the ``[squeal.damping]`` table to paste into the design (the table
    it has, raised), the friction levers as comments; ``where`` says the operating point."""
    table = dict(remedy_design(design, remedy["paste"]).damping.by_mode)
    checked = "the stability solved again with them"
    if "time_domain" in remedy:
        checked += ", and a time-domain run that decays"
    head = (
        "with these damping ratios no mode grows"
        if remedy["settled"]
        else "these damping ratios do NOT stop it"
    )
    lines = [
        f"# What stops the squeal of {design.name} at {where}:",
        f"# {head} ({checked}).",
        "# Paste the table into the design file in place of any [squeal.damping] it has.",
        "[squeal.damping]",
        *(f"{json.dumps(k)} = {toml_value(round(v, 12))}" for k, v in sorted(table.items())),
    ]
    if remedy["friction_coefficient"] is not None:
        lines += [
            "",
            "# or a friction modifier: in [contact],",
            f"# friction_coefficient = {remedy['friction_coefficient']:.2g}",
        ]
    return "\n".join(lines) + "\n"


def _bounds(
    design: Design,
    rows: Sequence[ModeStabilityRow],
    contact: ContactLaw,
    op: OperatingPoint,
    rotation: bool,
    i: int,
) -> tuple[ModeStability, float, float]:
    """(its stability with bounds, damping ratio now, friction slope now) of row ``i``
    (the row's own bounds where the table has them)."""
    from reduced import linear_stability

    slope_now = _slope_now(contact, op)
    known = rows[i].stability
    if not (math.isnan(known.critical_damping_ratio) or math.isnan(known.critical_friction_slope)):
        return known, design.damping_ratio_of(rows[i].mode), slope_now
    omega = wheel_speed_rad_s(design, op, rotation)
    dofs = mode_dofs([r.mode for r in rows], design)
    result = linear_stability(dofs, contact, op, omega, bounds=[i], body=body_of(design))
    return result.modes[i], design.damping_ratio_of(rows[i].mode), slope_now


def margin_of(
    design: Design,
    rows: Sequence[ModeStabilityRow],
    contact: ContactLaw,
    op: OperatingPoint,
    rotation: bool = False,
) -> dict:
    """How far from squeal a point where no mode grows is: the least stable mode, its
    growth rate [1/s], and the damping ratio below which (or the friction slope
    dmu/dzeta below which) it would grow, with the values now; ``words`` says it."""
    i = max(range(len(rows)), key=lambda k: rows[k].stability.growth_rate_1_s)
    m = rows[i].mode
    s, zeta_now, slope_now = _bounds(design, rows, contact, op, rotation, i)
    zeta_crit, slope_crit = needed_or_none(s.critical_damping_ratio), bound_or_none(s.critical_friction_slope)
    damping = (
        f"a damping ratio below {zeta_crit:.3g} (it has {zeta_now:.3g})" if zeta_crit else "no damping at all"
    )
    slope = (
        f" or a creep curve falling more steeply than dmu/dzeta = {slope_crit:.3g} (now {slope_now:.3g})"
        if slope_crit is not None
        else ""
    )
    rate = s.growth_rate_1_s
    how = (
        f"decays at {-rate:.3g} 1/s" if rate < 0 else f"grows at {rate:.3g} 1/s" if rate > 0 else "is neutral"
    )
    words = f"the least stable, {m.label()} at {s.damped_frequency_hz:.1f} Hz, {how}"
    if m.contact_components[0] != 0.0:  # else the friction's slope cannot act on it
        words += f"; it would grow with {damping}{slope}"
    return {
        "mode": m.label(),
        "mode_index": m.index,
        "growth_rate_1_s": s.growth_rate_1_s,
        "damping_ratio": zeta_now,
        "grows_below_damping_ratio": zeta_crit,
        "friction_slope": slope_now,
        "grows_below_friction_slope": slope_crit,
        "words": words,
    }
