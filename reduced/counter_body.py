"""The counter-body at the contact: what the wheel rolls on, as degrees of freedom in
series with the contact.

The contact feels the wheel's motion relative to the counter-body's: the normal
approach is the wheel's normal displacement minus the counter-body's, the slip
velocity the wheel's lateral velocity minus the counter-body's. A counter-body mode
along one direction is therefore a ``reduced.ModalDOF`` with gain -1 in that direction
(0 in the other); the normal force and the lateral force act on it with the opposite
sign to the wheel's. The paper's roller is rigid and fixed (no degrees of freedom). A
counter-body is anything with ``dofs()``: a roller's measured modes (:class:`ModalRoller`)
now, a rail's receptance (fitted by modes) later.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Protocol

from .model import ModalDOF

__all__ = ["CounterBody", "ModalCounterBody", "ModalRoller", "RigidCounterBody", "counter_body"]


class CounterBody(Protocol):
    """What the wheel rolls on, seen at the contact."""

    def dofs(self) -> list[ModalDOF]:
        """Its degrees of freedom at the contact (gains -1: relative motion)."""
        ...


@dataclass(frozen=True)
class RigidCounterBody:
    """Rigid and fixed: the paper's assumption."""

    def dofs(self) -> list[ModalDOF]:
        return []


@dataclass(frozen=True)
class ModalRoller:
    """A roller with one mode along the contact normal and/or one along the lateral
    tangent: each (frequency [Hz], damping ratio [-], modal mass at the contact [kg]),
    None where it is rigid."""

    normal: tuple[float, float, float] | None = None
    lateral: tuple[float, float, float] | None = None

    def dofs(self) -> list[ModalDOF]:
        out = []
        if self.normal is not None:
            f, zeta, m = self.normal
            out.append(ModalDOF.from_frequency(m, f, zeta, 0, lateral=0.0, normal=-1.0))
        if self.lateral is not None:
            f, zeta, m = self.lateral
            out.append(ModalDOF.from_frequency(m, f, zeta, 0, lateral=-1.0, normal=0.0))
        return out


@dataclass(frozen=True)
class ModalCounterBody:
    """A counter-body whose receptance along each direction is a sum of modal terms (a
    rail's, fitted: ``track.fit``): per direction a tuple of (frequency [Hz], damping
    ratio [-], modal mass at the contact [kg]), each term one degree of freedom."""

    normal: tuple[tuple[float, float, float], ...] = ()
    lateral: tuple[tuple[float, float, float], ...] = ()

    def dofs(self) -> list[ModalDOF]:
        out = [ModalDOF.from_frequency(m, f, z, 0, lateral=0.0, normal=-1.0) for f, z, m in self.normal]
        return out + [
            ModalDOF.from_frequency(m, f, z, 0, lateral=-1.0, normal=0.0) for f, z, m in self.lateral
        ]


def counter_body(
    normal: tuple[float, float, float] | None = None, lateral: tuple[float, float, float] | None = None
) -> list[ModalDOF]:
    """The degrees of freedom of a roller with the given modes (none given: rigid)."""
    body: CounterBody = (
        RigidCounterBody() if normal is None and lateral is None else ModalRoller(normal, lateral)
    )
    return body.dofs()
