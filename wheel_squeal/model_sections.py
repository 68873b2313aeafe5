"""The squeal model's sections of a design file, each a section of the one schema
(``geometry.schema.Fields``: fields with unit, default and check, the same mapping in and
out, TOML lines and hash): [counter_body] (what the wheel rolls on, one class per kind:
:data:`COUNTER_BODIES`), [contact] (load, friction, where and how the wheel touches it,
:class:`Contact`), [damping] (:class:`Damping`) and [squeal] (what the rig showed,
:class:`Squeal`). Every value is checked on construction, with a one-line
``geometry.DesignError`` naming it.

The sections of what the wheel runs on, [counter_body] and [vehicle], are the track
package's (``track.design_sections``), re-exported here.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import TYPE_CHECKING, ClassVar, get_args

from contact.creep import TABLE1_C22, friction_law_named
from contact.profiles import STANDARD_WHEELS
from geometry import DesignError
from geometry.schema import Fields, spec
from track.design_sections import (
    COUNTER_BODIES,
    ROLLER_MODAL,
    ROLLER_RANGES,
    CounterBodySection,
    Roller,
    Track,
    VehicleSection,
    check_positive,
    counter_body_from_file,
)

from .types import NormalContact

if TYPE_CHECKING:
    from fem.modes import Mode

__all__ = [
    "C22_RANGE",
    "COUNTER_BODIES",
    "CounterBodySection",
    "DAMPING_KEYS",
    "DEFAULT_FRICTION_LAW",
    "FRICTION_RANGE",
    "MAX_RELAXATION_LENGTH_M",
    "NORMAL_CONTACTS",
    "ROLLER_MODAL",
    "ROLLER_RANGES",
    "Contact",
    "Damping",
    "Roller",
    "Squeal",
    "Track",
    "VehicleSection",
    "counter_body_from_file",
    "FAMILY_KEYS",
    "family_keys",
    "mode_key",
]


#: The longest label a [squeal.damping] key may be (a modal model's mode label)
MAX_DAMPING_LABEL_CHARS = 80


#: The mode families a ``[squeal.damping]`` key may name (:func:`family_keys`): by nodal
#: diameters (the n = 0 and n = 1 modes couple to the axle, n >= 2 do not), and each
#: optionally by its direction at the tread
FAMILY_KEYS = tuple(f"{n}{d}" for n in ("n=0", "n=1", "n>=2") for d in ("", ",axial", ",radial"))
#: The keys a ``[squeal.damping]`` table accepts, in words (every error about one names them)
DAMPING_KEYS = (
    'a mode "n=N,c=C" (nodal diameters, circles), a family "n=0", "n=1" or "n>=2" (each optionally '
    'with ",axial" or ",radial") or a modal model\'s mode label'
)
#: The friction coefficients a wheel on a rail or a roller may have: a friction modifier
#: or a lubricant lowers it to 0.05-0.3, clean dry steel reaches 0.6-0.8
FRICTION_RANGE = (1e-3, 1.0)


def family_keys(nodal_diameters: int, family: str) -> tuple[str, str]:
    """The two family keys a mode answers to, the narrower first: ("n>=2,axial", "n>=2")."""
    n = "n=0" if nodal_diameters == 0 else "n=1" if nodal_diameters == 1 else "n>=2"
    return f"{n},{family}", n


def mode_key(label: str, source: str = "design") -> str:
    """A ``[squeal.damping]`` key written the one way: ``n=N,c=C`` for an FE mode named by
    nodal diameters and circles (``"n = 01, c = 0"`` is ``"n=1,c=0"``; the grammar is
    ``fem.modes.ModeSelection``'s), a family of :data:`FAMILY_KEYS` (``"n >= 2, axial"``
    is ``"n>=2,axial"``), or a modal model's mode label as it is."""
    from fem.modes import ModeSelection

    text = str(label)
    if text.replace(" ", "") in FAMILY_KEYS:
        return text.replace(" ", "")
    if "=" not in text:
        if text.strip() and text.isprintable() and len(text) <= MAX_DAMPING_LABEL_CHARS:
            return text
        raise DesignError(
            f"{source}: [squeal.damping] key {ascii(text[:40])}: the keys are {DAMPING_KEYS} (printable, at "
            f"most {MAX_DAMPING_LABEL_CHARS} characters)"
        )
    try:
        sel = ModeSelection.parse(text)
    except ValueError:
        sel = None
    if sel is None or sel.nodal_diameters is None or "c" not in text.replace(" ", ""):
        raise DesignError(f"{source}: [squeal.damping] key {label!r}: the keys are {DAMPING_KEYS}")
    return f"n={sel.nodal_diameters},c={sel.nodal_circles}"


# --------------------------------------------------------------------------------------
# the contact, the damping, what the rig showed
# --------------------------------------------------------------------------------------
#: The paper's friction law, the default of every design
DEFAULT_FRICTION_LAW = "falling"
#: How the normal force follows the contact's normal motion: "hertz" (the nonlinear
#: Hertz spring, the default) or "constant" (the paper's fixed normal load)
NORMAL_CONTACTS: tuple[str, ...] = get_args(NormalContact)
#: The plausible range of the creep coefficient C22 (Kalker's table spans about 2 to 10
#: for ellipses of axis ratio 0.1 to 10) and the longest relaxation length [m].
C22_RANGE = (0.1, 100.0)
MAX_RELAXATION_LENGTH_M = 1.0


@dataclass(frozen=True)
class Contact(Fields):
    """The contact of the wheel on its counter-body (module docstring; each field's
    meaning is its ``spec``)."""

    TABLE: ClassVar[str] = "contact"

    # a twin-disc rig's hundreds of newtons to a heavy-haul wheel's 150 kN, with room for
    # a curve's load transfer; 1e12 N is a unit slip
    normal_load: float = spec(1000.0, "N", "the normal load W", flat="normal_load", plausible=(1.0, 5e5))
    c22: float = spec(TABLE1_C22, "", "Kalker's lateral creep coefficient C22 (the paper's 3.14)", flat="c22")
    friction_coefficient: float = spec(
        0.3, "", "the friction coefficient mu_s = mu_0", flat="friction_coefficient", plausible=FRICTION_RANGE
    )
    flange_friction_coefficient: float | None = spec(
        None,
        "",
        "the friction coefficient where the flange touches (none: the rail head's; a lubricated gauge face "
        "about 0.1)",
        flat="flange_friction_coefficient",
        when_set=True,
        plausible=FRICTION_RANGE,
    )
    friction_law: str = spec(
        DEFAULT_FRICTION_LAW,
        "-",
        "a name of contact.creep.FRICTION_LAWS: falling (the paper's) or constant",
        when_set=True,
    )
    wheel_profile: str = spec(
        "outline",
        "-",
        "the transverse profile the wheel touches the rail with in a curve: outline (the design's own "
        "running surface) or S1002 (EN 13715)",
        when_set=True,
    )
    contact_angle: float = spec(
        0.0, "rad", "where on the tread the contact lies (0: the apex)", flat="contact_angle", when_set=True
    )
    normal_contact: NormalContact = spec(
        "hertz",
        "-",
        "hertz (the normal force follows the normal motion) or constant (fixed load)",
        when_set=True,
    )
    transient_creep: bool = spec(False, "-", "the creep force lags its steady value by L / V0", when_set=True)
    relaxation_length: float = spec(
        0.0,
        "m",
        "L of the transient creep (0: the Hertz semi-axis a along rolling)",
        flat="relaxation_length",
        when_set=True,
    )

    def __post_init__(self) -> None:
        for name in ("normal_load", "c22", "friction_coefficient"):
            check_positive("contact", name, getattr(self, name))
        if not C22_RANGE[0] <= self.c22 <= C22_RANGE[1]:
            raise DesignError(
                f"[contact] c22 = {self.c22:g} is outside the range of Kalker's creep coefficients "
                f"({C22_RANGE[0]:g} to {C22_RANGE[1]:g}; 3.14 in the paper)"
            )
        if self.flange_friction_coefficient is not None:
            check_positive("contact", "flange_friction_coefficient", self.flange_friction_coefficient)
        self.check_plausible()
        try:
            friction_law_named(self.friction_law)
        except ValueError as e:
            raise DesignError(f"[contact] {e}") from None
        if self.wheel_profile not in ("outline", *STANDARD_WHEELS):
            raise DesignError(
                f"[contact] wheel_profile must be 'outline' or one of {', '.join(STANDARD_WHEELS)}, "
                f"got {self.wheel_profile!r}"
            )
        if self.normal_contact not in NORMAL_CONTACTS:
            raise DesignError(
                f"[contact] normal_contact must be one of {', '.join(map(repr, NORMAL_CONTACTS))}, "
                f"got {self.normal_contact!r}"
            )
        if isinstance(self.contact_angle, bool) or not math.isfinite(self.contact_angle):
            raise DesignError(f"[contact] contact_angle must be an angle in rad, got {self.contact_angle!r}")
        if abs(self.contact_angle) > 0.5 * math.pi:
            raise DesignError(
                f"[contact] contact_angle = {self.contact_angle:g} is over pi/2: it is in rad "
                f"(write {math.radians(self.contact_angle):.4g} for {self.contact_angle:g} deg)"
            )
        if not isinstance(self.transient_creep, bool):
            raise DesignError(
                f"[contact] transient_creep must be true or false, got {self.transient_creep!r}"
            )
        if self.relaxation_length != 0.0:
            check_positive("contact", "relaxation_length", self.relaxation_length)
            if self.relaxation_length > MAX_RELAXATION_LENGTH_M:
                raise DesignError(
                    f"[contact] relaxation_length = {self.relaxation_length:g} m: the creep force builds up "
                    f"over about a contact length (a few mm), at most {MAX_RELAXATION_LENGTH_M:g} m"
                )
            if not self.transient_creep:
                raise DesignError("[contact] relaxation_length needs transient_creep = true")


@dataclass(frozen=True)
class Damping(Fields):
    """The modes' viscous damping: ``modal_damping_ratio`` [-] for every mode without a
    measured one; ``by_mode`` the measured ratios ((key, ratio), ...), sorted (the file's
    ``[squeal.damping]``; a key is "n=N,c=C" for an FE mode or a modal model's label)."""

    TABLE: ClassVar[str] = "damping"

    modal_damping_ratio: float = spec(
        9.4e-4, "", "the modal damping ratio of every mode without its own", flat="modal_damping_ratio"
    )
    by_mode: tuple[tuple[str, float], ...] = field(default=())

    def __post_init__(self) -> None:
        for name, ratio in (("modal_damping_ratio", self.modal_damping_ratio), *self.by_mode):
            if isinstance(ratio, bool) or not isinstance(ratio, int | float) or not 0.0 <= ratio < 1.0:
                raise DesignError(f"damping ratio {name} = {ratio!r}: a modal damping ratio in [0, 1)")
        keys = [k for k, _ in self.by_mode]
        for k in keys:
            if mode_key(k) != k:
                raise DesignError(f'[squeal.damping] key {k!r}: write it "{mode_key(k)}"')
        if len(set(keys)) != len(keys):
            raise DesignError("[squeal.damping] names a mode twice")

    def hash_payload(self) -> dict[str, str]:
        return {**super().hash_payload(), "by_mode": repr(self.by_mode)}

    def ratio(self, nodal_diameters: int, nodal_circles: int, family: str = "axial") -> float:
        """The (n, c) mode's damping ratio (:meth:`source`)."""
        return self.source(nodal_diameters, nodal_circles, family)[0]

    def source(self, nodal_diameters: int, nodal_circles: int, family: str = "axial") -> tuple[float, str]:
        """The (n, c) mode's damping ratio and the key it comes from: its own ("n=N,c=C"),
        else its family's with its direction ("n>=2,axial"), else its family's ("n>=2"),
        else the common one ("modal_damping_ratio")."""
        table = dict(self.by_mode)
        for key in (f"n={nodal_diameters},c={nodal_circles}", *family_keys(nodal_diameters, family)):
            if key in table:
                return table[key], key
        return self.modal_damping_ratio, "modal_damping_ratio"

    def labelled(self, label: str) -> float | None:
        """The ratio ``[squeal.damping]`` gives a mode by its label (None: none)."""
        return dict(self.by_mode).get(label)

    def of_mode(self, mode: Mode) -> tuple[float, str]:
        """A mode's damping ratio and where it comes from: this table's for its label (a
        modal model's mode: a remedy pasted in overrides the modal test), else its own (a
        modal test's: "measured"), else this table's for its (n, c) or its family, or
        ``modal_damping_ratio`` (:meth:`source`)."""
        by_label = self.labelled(mode.name) if mode.name else None
        if by_label is not None:
            return by_label, mode.name
        if mode.damping_ratio is not None:
            return mode.damping_ratio, "measured"
        return self.source(mode.nodal_diameters, mode.nodal_circles, mode.family)


@dataclass(frozen=True)
class Squeal(Fields):
    """What the rig showed: ``mode``, the mode seen to squeal (``n=3,c=0``, an index or
    ``f=HZ``; "" for none). A named mode is an override (:mod:`wheel_squeal.verdict`)."""

    TABLE: ClassVar[str] = "squeal"

    mode: str = spec("", "-", "the mode the rig was seen to squeal in (an override of the model's pick)")

    def __post_init__(self) -> None:
        if not isinstance(self.mode, str):
            raise DesignError(f'[squeal] mode must be a string like "n=3,c=0", got {self.mode!r}')
        if self.mode:
            from fem.modes import ModeSelection

            try:
                ModeSelection.parse(self.mode)
            except ValueError:
                raise DesignError(f"[squeal] mode {self.mode!r}: use n=N[,c=C], an index or f=HZ") from None
