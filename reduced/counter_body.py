"""The counter-body at the contact: what the wheel rolls on, as a linear system in series
with the contact.

The contact feels the wheel's motion relative to the counter-body's: the normal approach
is the wheel's normal displacement minus the counter-body's, the slip velocity the
wheel's lateral velocity minus the counter-body's, and the counter-body takes the
opposite of the force the wheel takes (along the normal +N - W beyond the static load,
laterally -Q). Its receptance at the contact, per direction, is a sum of terms
(:class:`BodyModel`):

- a first-order term r / (s - p), p < 0 (a spring and damper in series with the others,
  a relaxation);
- a second-order term (b1 s + b0) / (s^2 + a1 s + a0), a pair of poles: a modal degree
  of freedom (b1 = 0, b0 = 1/m: a mass, spring and damper) or a pair of a fitted
  receptance (``track.fit``) whose residues are complex.

The sum of the terms' leading coefficients (b1 of the pairs, r of the first-order terms)
is zero in each direction: the receptance falls as 1/s^2 at high frequency, like a mass,
and the counter-body's velocity answers a force through its states only (no
instantaneous velocity), which the linear stability and the time domain both take.

The paper's roller is rigid and fixed (no terms). A roller with measured modes is
:class:`ModalRoller`; a rail's receptance is fitted by ``track.fit`` and given here by
:meth:`BodyModel.from_rational`.
"""

from __future__ import annotations

import functools
import math
from collections.abc import Sequence
from dataclasses import dataclass, field
from typing import Protocol

import numpy as np

__all__ = [
    "LATERAL",
    "NORMAL",
    "BodyModel",
    "CounterBody",
    "ModalCounterBody",
    "ModalRoller",
    "RigidCounterBody",
    "counter_body",
]

#: The directions a counter-body's term acts along: the contact normal and the lateral tangent
NORMAL, LATERAL = 0, 1
#: The largest feedthrough (the sum of the leading coefficients relative to their size)
#: a body may have: beyond it its velocity would answer a force at once
MAX_FEEDTHROUGH = 1e-9


@dataclass(frozen=True, eq=False)
class BodyModel:
    """A counter-body's receptance at the contact as a sum of first- and second-order
    terms (module docstring), arrays of one entry per term.

    Attributes
    ----------
    order : numpy.ndarray
        1 or 2.
    direction : numpy.ndarray
        :data:`NORMAL` (0) or :data:`LATERAL` (1).
    a0, a1 : numpy.ndarray
        The denominator s^2 + a1 s + a0 of a pair [1/s^2, 1/s]; of a first-order term,
        s + a1 (its pole p = -a1 < 0; a0 = 0).
    b0, b1 : numpy.ndarray
        The numerator b1 s + b0 of a pair [m/N /s^2, m/N /s]; of a first-order term b0 = r
        [m/N /s] (b1 = 0).
    name : str
        What it is, in words ("the rail", "the roller").
    """

    order: np.ndarray
    direction: np.ndarray
    a0: np.ndarray
    a1: np.ndarray
    b0: np.ndarray
    b1: np.ndarray
    name: str = "the counter-body"
    _hash: int = field(default=0, repr=False)

    def __post_init__(self) -> None:
        n = len(self.order)
        for k in ("direction", "a0", "a1", "b0", "b1"):
            if len(getattr(self, k)) != n:
                raise ValueError(f"BodyModel.{k}: one value per term ({n})")
        if n and not (np.all(self.a1 > 0) and np.all(self.a0[self.order == 2] > 0)):
            raise ValueError("BodyModel: every term must be stable (a1 > 0, a0 > 0)")
        for d in (NORMAL, LATERAL):
            lead = self.leading(d)
            scale = float(np.abs(self.b1).sum() + np.abs(self.b0[self.order == 1]).sum()) or 1.0
            if abs(lead) > MAX_FEEDTHROUGH * scale:
                raise ValueError(
                    f"BodyModel: the {('normal', 'lateral')[d]} terms' leading coefficients sum to "
                    f"{lead:.3g}, not 0: its velocity would answer a force at once"
                )
        digest = (
            self.order.tobytes(),
            self.direction.tobytes(),
            self.a0.tobytes(),
            self.a1.tobytes(),
            self.b0.tobytes(),
            self.b1.tobytes(),
        )
        object.__setattr__(self, "_hash", hash(digest))

    def __hash__(self) -> int:
        return self._hash

    def __eq__(self, other: object) -> bool:
        return isinstance(other, BodyModel) and self._hash == other._hash and self.name == other.name

    # -- making one -------------------------------------------------------------------
    @classmethod
    def empty(cls, name: str = "the counter-body") -> BodyModel:
        """A rigid, fixed counter-body: no terms."""
        z = np.zeros(0)
        return cls(np.zeros(0, dtype=np.int64), np.zeros(0, dtype=np.int64), z, z, z, z, name)

    @classmethod
    def from_modes(
        cls, modes: Sequence[tuple[int, float, float, float]], name: str = "the counter-body"
    ) -> BodyModel:
        """Modal degrees of freedom: each (direction, frequency [Hz], damping ratio [-],
        modal mass at the contact [kg]), a mass, spring and damper along its direction:
        1 / (m (s^2 + 2 zeta w s + w^2))."""
        if not modes:
            return cls.empty(name)
        d, f, z, m = (np.array(col, float) for col in zip(*modes))
        w = 2 * math.pi * f
        n = len(f)
        return cls(
            np.full(n, 2, dtype=np.int64), d.astype(np.int64), w * w, 2 * z * w, 1.0 / m, np.zeros(n), name
        )

    @classmethod
    def from_rational(
        cls,
        by_direction: Sequence[tuple[int, np.ndarray, np.ndarray]],
        name: str = "the counter-body",
    ) -> BodyModel:
        """A fitted receptance per direction: (direction, poles [1/s] (a real pole, or one
        of each pair with Im > 0), residues [m/N /s] (complex for a pair)), its terms
        r/(s - p) + conj(r)/(s - conj(p)) = (2 Re r s - 2 Re(r conj p)) / (s^2 - 2 Re p s + |p|^2)."""
        order, direction, a0, a1, b0, b1 = [], [], [], [], [], []
        for d, poles, residues in by_direction:
            for p, r in zip(np.asarray(poles, complex), np.asarray(residues, complex)):
                direction.append(d)
                if p.imag == 0.0:
                    order.append(1)
                    a0.append(0.0)
                    a1.append(-p.real)
                    b0.append(r.real)
                    b1.append(0.0)
                else:
                    order.append(2)
                    a0.append(abs(p) ** 2)
                    a1.append(-2 * p.real)
                    b0.append(-2 * (r * np.conj(p)).real)
                    b1.append(2 * r.real)
        return cls(
            np.array(order, dtype=np.int64),
            np.array(direction, dtype=np.int64),
            np.array(a0, float),
            np.array(a1, float),
            np.array(b0, float),
            np.array(b1, float),
            name,
        )

    # -- what it is ---------------------------------------------------------------------
    @property
    def terms(self) -> int:
        return len(self.order)

    @property
    def states(self) -> int:
        """The states of its time domain and linear stability (two per pair, one per
        first-order term)."""
        return int(self.order.sum())

    def leading(self, direction: int) -> float:
        """The sum of the leading coefficients of the terms along ``direction`` (0 by
        construction: no feedthrough)."""
        along = self.direction == direction
        return float(self.b1[along].sum() + self.b0[along & (self.order == 1)].sum())

    def receptance(self, s: complex | np.ndarray, direction: int) -> np.ndarray:
        """Its receptance along ``direction`` [m/N] at the complex frequency ``s`` [1/s]
        (s = i omega on the frequency axis)."""
        s = np.asarray(s, complex)[..., None]
        along = self.direction == direction
        pair = along & (self.order == 2)
        first = along & (self.order == 1)
        out = ((self.b1[pair] * s + self.b0[pair]) / (s * s + self.a1[pair] * s + self.a0[pair])).sum(axis=-1)
        return out + (self.b0[first] / (s + self.a1[first])).sum(axis=-1)

    def state_space(self) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
        """(A, B, C, Cv): x' = A x + B f with f = (the force on it along the normal, along
        the lateral tangent) [N]; its displacement at the contact u = C x and velocity
        u' = Cv x (Cv = C A: no feedthrough), each (normal, lateral). A pair's states are
        (q, q') with q'' + a1 q' + a0 q = f, u = b0 q + b1 q'; a first-order term's x' = -a1 x + f,
        u = b0 x. Made once (every eigen-solve of a curve map asks for them): read-only."""
        return self._state_space

    @functools.cached_property
    def _state_space(self) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
        n = self.states
        A, B, C = np.zeros((n, n)), np.zeros((n, 2)), np.zeros((2, n))
        i = 0
        for k in range(self.terms):
            d = int(self.direction[k])
            if self.order[k] == 2:
                A[i, i + 1] = 1.0
                A[i + 1, i], A[i + 1, i + 1] = -self.a0[k], -self.a1[k]
                B[i + 1, d] = 1.0
                C[d, i], C[d, i + 1] = self.b0[k], self.b1[k]
                i += 2
            else:
                A[i, i] = -self.a1[k]
                B[i, d] = 1.0
                C[d, i] = self.b0[k]
                i += 1
        parts = (A, B, C, C @ A)
        for a in parts:
            a.setflags(write=False)
        return parts

    def energy_weights(self) -> np.ndarray:
        """Per state, the weight of its square in the counter-body's vibration energy (for
        energy shares): a pair's |b0| (q'^2 + a0 q^2), as a mass 1/b0 moving the contact by
        b0 q would hold; a first-order term's |b0| a1 x^2. Made once: read-only."""
        return self._energy_weights

    @functools.cached_property
    def _energy_weights(self) -> np.ndarray:
        w = np.zeros(self.states)
        i = 0
        for k in range(self.terms):
            if self.order[k] == 2:
                w[i], w[i + 1] = abs(self.b0[k]) * self.a0[k], abs(self.b0[k])
                i += 2
            else:
                w[i] = abs(self.b0[k]) * self.a1[k]
                i += 1
        w.setflags(write=False)
        return w

    def static_state(self, force_n: np.ndarray) -> np.ndarray:
        """Its states at rest under a steady ``force_n`` (normal, lateral) [N]: 0 = A x + B f."""
        if self.states == 0:
            return np.zeros(0)
        A, B, _, _ = self.state_space()
        return np.linalg.solve(A, -B @ np.asarray(force_n, float))


class CounterBody(Protocol):
    """What the wheel rolls on, seen at the contact."""

    def model(self) -> BodyModel:
        """Its receptance at the contact (:class:`BodyModel`; no terms: rigid)."""
        ...


@dataclass(frozen=True)
class RigidCounterBody:
    """Rigid and fixed: the paper's assumption."""

    def model(self) -> BodyModel:
        return BodyModel.empty("the rigid counter-body")


@dataclass(frozen=True)
class ModalRoller:
    """A roller with one mode along the contact normal and/or one along the lateral
    tangent: each (frequency [Hz], damping ratio [-], modal mass at the contact [kg]),
    None where it is rigid."""

    normal: tuple[float, float, float] | None = None
    lateral: tuple[float, float, float] | None = None

    def model(self) -> BodyModel:
        modes = [(d, *m) for d, m in ((NORMAL, self.normal), (LATERAL, self.lateral)) if m is not None]
        return BodyModel.from_modes(modes, "the roller")


@dataclass(frozen=True)
class ModalCounterBody:
    """A counter-body whose receptance along each direction is a sum of modal terms: per
    direction a tuple of (frequency [Hz], damping ratio [-], modal mass at the contact
    [kg])."""

    normal: tuple[tuple[float, float, float], ...] = ()
    lateral: tuple[tuple[float, float, float], ...] = ()

    def model(self) -> BodyModel:
        modes = [(NORMAL, *m) for m in self.normal] + [(LATERAL, *m) for m in self.lateral]
        return BodyModel.from_modes(modes)


def counter_body(
    normal: tuple[float, float, float] | None = None, lateral: tuple[float, float, float] | None = None
) -> BodyModel:
    """The model of a roller with the given modes (none given: rigid)."""
    return ModalRoller(normal, lateral).model()
