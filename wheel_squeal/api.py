"""The stages as a plain Python API (what the command line calls, and a notebook too).

design -> mesh -> modes -> squeal mode -> modal parameters (m, k, c) -> contact law and
operating point -> simulation or sweep. Every function takes and returns plain objects
of the packages below and :class:`~wheel_squeal.design.Design`: its ``wheel`` a
``geometry.WheelDesign``, meshes, ``fem.ModeSet`` and ``Mode``, ``reduced.ModalDOF``,
``ContactLaw``, ``OperatingPoint``, ``SweepResult``.
Bad input raises :class:`~wheel_squeal.runtime.request_errors.RequestError` in the API's own words;
expensive stages go through a :class:`~wheel_squeal.runtime.stage_cache.StageCache` when one is given
and are estimated against a :class:`~wheel_squeal.runtime.budget.Budget` before they start.
"""

from __future__ import annotations

import functools
import math
from pathlib import Path
from typing import TYPE_CHECKING

from .design import Design
from .fe_stages import (
    build_mesh,
    check_modes_budget,
    check_named_modes,
    compute_modes,
    mode_views,
    modes_cache_key,
    pick_mode,
)
from .model_sections import C22_RANGE, Damping
from .presets import (
    DEFAULT_CRAB_VELOCITY_M_S,
    DEFAULT_DESIGN,
    DEFAULT_RPM,
    designs_folder,
    rpm_to_speed,
)
from .runtime.request_errors import RequestError

if TYPE_CHECKING:
    from fem.modes import Mode
    from reduced import ContactLaw, HertzContact, ModalDOF, OperatingPoint

__all__ = [
    "build_mesh",
    "check_named_modes",
    "check_modes_budget",
    "compute_modes",
    "contact_law",
    "hertz_of",
    "load_design",
    "modal_dof",
    "mode_views",
    "modes_cache_key",
    "operating_point",
    "pick_mode",
    "shipped_designs",
]


def load_design(path: str | Path | None = None) -> Design:
    """A wheel design from TOML.

    Parameters
    ----------
    path : str, Path or None
        A design file, or the name of a design shipped with the tool (``"thin_web"``,
        from any folder; :func:`shipped_designs`); None gives the default, ``table1``.

    Returns
    -------
    Design

    Raises
    ------
    geometry.DesignError
        A bad design, in one line naming the problem.

    Examples
    --------
    >>> import wheel_squeal as ws
    >>> d = ws.load_design("thin_web")
    >>> d.name, d.wheel.web_thickness
    ('thin_web', 0.01)
    """

    if path is None:
        path = DEFAULT_DESIGN
    p = Path(path)
    if not p.exists() and p.suffix == "" and len(p.parts) == 1:
        shipped = designs_folder() / f"{p.name}.toml"
        if shipped.is_file():
            p = shipped
        else:
            names = ", ".join(shipped_designs())
            raise RequestError(f"design {str(path)!r} is neither a file nor a shipped design ({names})")
    return Design.from_toml(p)


def shipped_designs() -> dict[str, str]:
    """The designs shipped with the tool.

    Returns
    -------
    dict
        {name: description}; give a name to :func:`load_design` or ``--design``.

    Examples
    --------
    >>> import wheel_squeal as ws
    >>> "table1" in ws.shipped_designs()
    True
    """
    from geometry import DesignError

    out = {}
    for f in sorted(designs_folder().glob("*.toml")):
        try:
            out[f.stem] = Design.from_toml(f).description
        except DesignError:  # a broken shipped design is a bug the tests catch
            out[f.stem] = ""
    return out


# --------------------------------------------------------------------------------------
# the reduced model: modal parameters, contact, operating point, simulation
# --------------------------------------------------------------------------------------
def modal_dof(mode: Mode, design: Design) -> ModalDOF:
    """The FE mode as the reduced model's degree of freedom at the contact point: its
    lateral modal mass, stiffness and damping (m, k, c) with its damping ratio (the
    design's ``[squeal.damping]`` for it, else ``modal_damping_ratio``), its nodal
    diameters (a pair, on a turning wheel) and how it moves the contact normally
    (``reduced.ModalDOF.from_components``: a mode that moves it only normally takes its
    normal modal mass)."""
    return _modal_dof(mode, design.damping)


#: The modal degrees of freedom a process keeps (a mode at a contact and a damping table
#: give the same one whichever curve, friction state or design asks)
MODAL_DOFS_KEPT = 16384


@functools.lru_cache(maxsize=MODAL_DOFS_KEPT)
def _modal_dof(mode: Mode, damping: Damping) -> ModalDOF:
    from reduced import ModalDOF

    phi_t, phi_n = mode.contact_components
    if phi_t == 0.0 and phi_n == 0.0:
        raise RequestError(
            f"mode {mode.index} ({mode.label()}) has a node at the contact point: "
            "it cannot be excited there; pick another mode"
        )
    zeta = damping.of_mode(mode)[0]
    if phi_n == 0.0:  # the paper's lateral mode, its modal mass as the FE gives it
        return ModalDOF.from_damping_ratio(mode.modal_mass, mode.modal_stiffness, zeta, mode.nodal_diameters)
    lateral_mass = mode.modal_mass if math.isfinite(mode.modal_mass) else None
    return ModalDOF.from_components(mode.frequency_hz, zeta, phi_t, phi_n, mode.nodal_diameters, lateral_mass)


def hertz_of(design: Design) -> HertzContact:
    """The Hertz contact (``reduced.HertzContact``) of the design's wheel on its
    counter-body at its contact point: the wheel's radius of curvature along rolling is
    r / cos(angle) there (``contact.frames.ContactFrame``), across it the tread's crown;
    the counter-body's are its section's ``contact_radii`` (where a curving put the
    contact, its :class:`~wheel_squeal.design.ContactSite` gives the relative curvature
    across)."""
    from reduced import hertz_contact

    frame = design.contact_frame
    along, across = design.counter_body.contact_radii()
    crown = frame.crown_radius_m
    if design.contact_site is not None:  # the curving's relative curvature holds the rail's
        crown, along, across = design.contact_site.relative_transverse_radius_m, math.inf, math.inf
    return hertz_contact(
        frame.rolling_curvature_radius_m,
        crown,
        along,
        across,
        design.wheel.youngs_modulus,
        design.wheel.poissons_ratio,
        design.contact.normal_load,
    )


def contact_law(
    design: Design, c22: float | str | None = None, friction_law: str | None = None
) -> ContactLaw:
    """Creep-law parameters of the design's wheel on its roller (Hertz + Eq. 3, 6).

    ``c22``: None for the design's value (Table 1: 3.14), a number, or ``"kalker"``.
    ``friction_law``: None for the design's ([contact] friction_law), or a name of
    ``contact.creep.FRICTION_LAWS``.
    """
    from contact.creep import friction_law_named
    from reduced import ContactLaw

    if isinstance(c22, str):
        if c22.lower() != "kalker":
            raise RequestError(f"c22 must be a number or 'kalker', got {c22!r}")
        c22 = "kalker"
    elif c22 is not None and not (math.isfinite(c22) and C22_RANGE[0] <= c22 <= C22_RANGE[1]):
        raise RequestError(
            f"c22 must be 'kalker' or a creep coefficient from {C22_RANGE[0]:g} to {C22_RANGE[1]:g} "
            f"(Kalker's range; 3.14 in the paper), got {c22:g}"
        )
    hertz = hertz_of(design)
    c = design.contact
    c22 = c.c22 if c22 is None else c22
    law = c.friction_law if friction_law is None else friction_law
    try:
        friction_law_named(law)
    except ValueError as e:
        raise RequestError(str(e)) from None
    relaxation = (c.relaxation_length or hertz.semi_axis_a_m) if c.transient_creep else 0.0
    return ContactLaw.from_hertz(
        hertz,
        friction_coefficient=c.friction_coefficient,
        c22=c22,
        friction_law=law,
        normal=c.normal_contact == "hertz",
        relaxation_length_m=relaxation,
    )


def operating_point(
    design: Design,
    *,
    rpm: float | None = None,
    rolling_speed_m_s: float | None = None,
    crabbing_velocity_m_s: float | None = None,
    angle_of_attack_rad: float | None = None,
) -> OperatingPoint:
    """The operating point of ``design``'s wheel.

    Parameters
    ----------
    design : Design
        Its contact radius turns a wheel speed into the rolling speed.
    rpm : float, optional
        The wheel speed [rev/min] (default 800, the paper's Fig. 6).
    rolling_speed_m_s : float, optional
        The rolling speed V0 at the contact [m/s], instead of ``rpm``.
    crabbing_velocity_m_s : float, optional
        The crabbing velocity Vc [m/s] (default 0.39).
    angle_of_attack_rad : float, optional
        The angle of attack [rad], instead of the crabbing velocity (Vc = angle V0).

    Returns
    -------
    reduced.OperatingPoint

    Examples
    --------
    >>> import wheel_squeal as ws
    >>> op = ws.operating_point(ws.load_design(), rpm=800, crabbing_velocity_m_s=0.39)
    >>> round(op.rolling_speed_m_s, 2), round(op.creepage, 4)
    (17.84, 0.0219)
    """
    from reduced import OperatingPoint

    if rpm is not None and rolling_speed_m_s is not None:
        raise RequestError("give rpm or rolling_speed_m_s, not both")
    if crabbing_velocity_m_s is not None and angle_of_attack_rad is not None:
        raise RequestError("give crabbing_velocity_m_s or angle_of_attack_rad, not both")
    for name, v in (("rpm", rpm), ("rolling_speed_m_s", rolling_speed_m_s)):
        if v is not None and not (math.isfinite(v) and v > 0):
            raise RequestError(f"{name} must be positive, got {v:g}")
    for name, v in (
        ("crabbing_velocity_m_s", crabbing_velocity_m_s),
        ("angle_of_attack_rad", angle_of_attack_rad),
    ):
        if v is not None and not math.isfinite(v):
            raise RequestError(f"{name} must be finite, got {v}")
    v0 = (
        rolling_speed_m_s
        if rolling_speed_m_s is not None
        else rpm_to_speed(DEFAULT_RPM if rpm is None else rpm, design.rolling_radius)
    )
    if angle_of_attack_rad is not None:
        return OperatingPoint.from_angle_of_attack(v0, angle_of_attack_rad)
    vc = DEFAULT_CRAB_VELOCITY_M_S if crabbing_velocity_m_s is None else crabbing_velocity_m_s
    return OperatingPoint(v0, vc)
