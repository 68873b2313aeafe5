"""The squeal model's sections of a design file, each a small dataclass of its own:
[roller] (the counter-body, :class:`Roller`), [contact] (load, friction, where and how
the wheel touches it, :class:`Contact`), [damping] (:class:`Damping`) and [squeal] (what
the rig showed, :class:`Squeal`). Every value is checked on construction, with a
one-line :class:`~wheel_squeal.errors.RequestError` naming it.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

from geometry.design import MAX_LENGTH_M
from reduced.creep import FRICTION_LAWS, TABLE1_C22

from .errors import RequestError

__all__ = [
    "CONTACT_NUMBERS",
    "CONTACT_OPTIONAL_NUMBERS",
    "DEFAULT_FRICTION_LAW",
    "NORMAL_CONTACTS",
    "ROLLER_MODAL",
    "Contact",
    "Damping",
    "Roller",
    "Squeal",
    "mode_key",
]


def mode_key(label: str, source: str = "design") -> str:
    """``n=N,c=C`` of a mode named by nodal diameters and circles, written the one way
    (``"n = 01, c = 0"`` is ``"n=1,c=0"``); the grammar is ``fem.modes.ModeSelection``'s."""
    from fem.modes import ModeSelection

    try:
        sel = ModeSelection.parse(str(label))
    except ValueError:
        sel = None
    if sel is None or sel.nodal_diameters is None or "c" not in str(label).replace(" ", ""):
        raise RequestError(
            f'{source}: [squeal.damping] key {label!r}: use "n=N,c=C" (nodal diameters, circles)'
        )
    return f"n={sel.nodal_diameters},c={sel.nodal_circles}"


def _positive(owner: str, name: str, value: float, *, length: bool = False) -> None:
    if (
        isinstance(value, bool)
        or not isinstance(value, int | float)
        or not math.isfinite(value)
        or value <= 0
    ):
        raise RequestError(f"[{owner}] {name} must be a positive number, got {value!r}")
    if length and value > MAX_LENGTH_M:
        raise RequestError(
            f"[{owner}] {name} = {value:g} m is longer than any wheel ({MAX_LENGTH_M:g} m): "
            f"it looks like millimetres; write {value / 1000:g}"
        )


#: The counter-body's modal degrees of freedom: per direction at the contact, its
#: frequency [Hz], damping ratio [-] and modal mass [kg] (all three, or none: rigid).
ROLLER_MODAL = ("frequency_hz", "damping_ratio", "modal_mass_kg")
#: Plausible ranges (low, high, unit) of a counter-body mode's frequency and modal mass:
#: outside them a value is a typing error (and would overflow the model).
ROLLER_RANGES = {"frequency_hz": (0.1, 1e6, "Hz"), "modal_mass_kg": (1e-6, 1e6, "kg")}


@dataclass(frozen=True)
class Roller:
    """The counter-body: the upper wheel of the rig. rolling_radius: R2 [m];
    crown_radius: its transverse radius R2t [m]. Rigid and fixed unless a direction
    gives its modal degree of freedom at the contact: ``normal_frequency_hz``,
    ``normal_damping_ratio``, ``normal_modal_mass_kg`` (along the contact normal) and
    the same three ``lateral_`` ones (along the lateral tangent), in series with the
    contact."""

    rolling_radius: float = 0.085
    crown_radius: float = 0.040
    normal_frequency_hz: float | None = None
    normal_damping_ratio: float | None = None
    normal_modal_mass_kg: float | None = None
    lateral_frequency_hz: float | None = None
    lateral_damping_ratio: float | None = None
    lateral_modal_mass_kg: float | None = None

    def __post_init__(self) -> None:
        _positive("roller", "rolling_radius", self.rolling_radius, length=True)
        _positive("roller", "crown_radius", self.crown_radius)
        for direction in ("normal", "lateral"):
            given = [k for k in ROLLER_MODAL if getattr(self, f"{direction}_{k}") is not None]
            if given and len(given) < len(ROLLER_MODAL):
                missing = [f"{direction}_{k}" for k in ROLLER_MODAL if k not in given]
                raise RequestError(
                    f"[roller] a {direction} modal degree of freedom needs {', '.join(missing)} too "
                    "(frequency, damping ratio and modal mass; none of them: rigid)"
                )
            for k in given:
                value = getattr(self, f"{direction}_{k}")
                if k == "damping_ratio":
                    if isinstance(value, bool) or not 0.0 <= value < 1.0:
                        raise RequestError(f"[roller] {direction}_{k} = {value!r}: a damping ratio in [0, 1)")
                    continue
                _positive("roller", f"{direction}_{k}", value)
                low, high, unit = ROLLER_RANGES[k]
                if not low <= value <= high:
                    raise RequestError(
                        f"[roller] {direction}_{k} = {value:g} {unit} is outside the plausible range "
                        f"of a counter-body's mode ({low:g} to {high:g} {unit})"
                    )

    def modal(self, direction: str) -> tuple[float, float, float] | None:
        """(frequency [Hz], damping ratio, modal mass [kg]) of the roller's modal degree
        of freedom along ``direction`` ("normal" or "lateral"), None where it is rigid."""
        values = tuple(getattr(self, f"{direction}_{k}") for k in ROLLER_MODAL)
        return None if values[0] is None else values


#: The paper's friction law, the default of every design
DEFAULT_FRICTION_LAW = "falling"
#: How the normal force follows the contact's normal motion: "hertz" (the nonlinear
#: Hertz spring, the default) or "constant" (the paper's fixed normal load)
NORMAL_CONTACTS = ("hertz", "constant")
#: The numeric fields of [contact] (a design parameter each, see :data:`FIELDS`)
CONTACT_NUMBERS = ("normal_load", "c22", "friction_coefficient")
#: The plausible range of the creep coefficient C22 (Kalker's table spans about 2 to 10
#: for ellipses of axis ratio 0.1 to 10) and the longest relaxation length [m].
C22_RANGE = (0.1, 100.0)
MAX_RELAXATION_LENGTH_M = 1.0
#: The optional numeric fields of [contact], written and hashed only when set
CONTACT_OPTIONAL_NUMBERS = ("contact_angle", "relaxation_length")


@dataclass(frozen=True)
class Contact:
    """The contact of the wheel on the roller. normal_load: W [N]; c22: Kalker's creep
    coefficient C22 [-] (the paper's 3.14); friction_coefficient: mu_s = mu_0 [-];
    friction_law: a name of ``reduced.FRICTION_LAWS`` ("falling", the paper's, or
    "constant": no falling friction); contact_angle: where on the tread the contact
    lies [rad] (``geometry.contact``: 0 the apex); normal_contact: "hertz" or
    "constant" (:data:`NORMAL_CONTACTS`); transient_creep: the creep force lags its
    steady value by L / V0 (False: the paper's steady law), with the relaxation length
    L = relaxation_length [m] (0: the Hertz semi-axis a along rolling)."""

    normal_load: float = 1000.0
    c22: float = TABLE1_C22
    friction_coefficient: float = 0.3
    friction_law: str = DEFAULT_FRICTION_LAW
    contact_angle: float = 0.0
    normal_contact: str = "hertz"
    transient_creep: bool = False
    relaxation_length: float = 0.0

    def __post_init__(self) -> None:
        for name in CONTACT_NUMBERS:
            _positive("contact", name, getattr(self, name))
        if not C22_RANGE[0] <= self.c22 <= C22_RANGE[1]:
            raise RequestError(
                f"[contact] c22 = {self.c22:g} is outside the range of Kalker's creep coefficients "
                f"({C22_RANGE[0]:g} to {C22_RANGE[1]:g}; 3.14 in the paper)"
            )
        if self.friction_law not in FRICTION_LAWS:
            raise RequestError(
                f"[contact] friction_law must be one of {', '.join(map(repr, FRICTION_LAWS))}, "
                f"got {self.friction_law!r}"
            )
        if self.normal_contact not in NORMAL_CONTACTS:
            raise RequestError(
                f"[contact] normal_contact must be one of {', '.join(map(repr, NORMAL_CONTACTS))}, "
                f"got {self.normal_contact!r}"
            )
        if isinstance(self.contact_angle, bool) or not math.isfinite(self.contact_angle):
            raise RequestError(f"[contact] contact_angle must be an angle in rad, got {self.contact_angle!r}")
        if abs(self.contact_angle) > 0.5 * math.pi:
            raise RequestError(
                f"[contact] contact_angle = {self.contact_angle:g} is over pi/2: it is in rad "
                f"(write {math.radians(self.contact_angle):.4g} for {self.contact_angle:g} deg)"
            )
        if not isinstance(self.transient_creep, bool):
            raise RequestError(
                f"[contact] transient_creep must be true or false, got {self.transient_creep!r}"
            )
        if self.relaxation_length != 0.0:
            _positive("contact", "relaxation_length", self.relaxation_length)
            if self.relaxation_length > MAX_RELAXATION_LENGTH_M:
                raise RequestError(
                    f"[contact] relaxation_length = {self.relaxation_length:g} m: the creep force builds up "
                    f"over about a contact length (a few mm), at most {MAX_RELAXATION_LENGTH_M:g} m"
                )
            if not self.transient_creep:
                raise RequestError("[contact] relaxation_length needs transient_creep = true")


@dataclass(frozen=True)
class Damping:
    """The modes' viscous damping: ``modal_damping_ratio`` [-] for every mode without a
    measured one, ``by_mode`` the measured ratios (("n=N,c=C", ratio), ...), sorted."""

    modal_damping_ratio: float = 9.4e-4
    by_mode: tuple[tuple[str, float], ...] = ()

    def __post_init__(self) -> None:
        for name, ratio in (("modal_damping_ratio", self.modal_damping_ratio), *self.by_mode):
            if isinstance(ratio, bool) or not isinstance(ratio, int | float) or not 0.0 <= ratio < 1.0:
                raise RequestError(f"damping ratio {name} = {ratio!r}: a modal damping ratio in [0, 1)")
        keys = [k for k, _ in self.by_mode]
        for k in keys:
            if mode_key(k) != k:
                raise RequestError(f'[squeal.damping] key {k!r}: use "n=N,c=C" (nodal diameters, circles)')
        if len(set(keys)) != len(keys):
            raise RequestError("[squeal.damping] names a mode twice")

    def ratio(self, nodal_diameters: int, nodal_circles: int) -> float:
        """The (n, c) mode's damping ratio: its measured one, else the common one."""
        return dict(self.by_mode).get(f"n={nodal_diameters},c={nodal_circles}", self.modal_damping_ratio)


@dataclass(frozen=True)
class Squeal:
    """What the rig showed: ``mode``, the mode seen to squeal (``n=3,c=0``, an index or
    ``f=HZ``; "" for none). A named mode is an override (:mod:`wheel_squeal.verdict`)."""

    mode: str = ""

    def __post_init__(self) -> None:
        if not isinstance(self.mode, str):
            raise RequestError(f'[squeal] mode must be a string like "n=3,c=0", got {self.mode!r}')
        if self.mode:
            from fem.modes import ModeSelection

            try:
                ModeSelection.parse(self.mode)
            except ValueError:
                raise RequestError(f"[squeal] mode {self.mode!r}: use n=N[,c=C], an index or f=HZ") from None
