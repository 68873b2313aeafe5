"""Mode coupling in closed form: two undamped modes on the contact's normal spring.

With mass-normalised modal coordinates q and each mode's components at the contact,
``phi_t`` (lateral) and ``phi_n`` (normal), the linearised contact of
:class:`reduced.stability.LinearContact` adds to the modal stiffness diag(omega^2)

    k_H phi_n phi_n^T  +  mu0 k_H phi_t phi_n^T

(the normal spring, and the lateral force's share of the normal force's change). The
second term is not symmetric. For two modes without damping the motion is q ~ e^{lambda
t} with lambda^2 = -s, s an eigenvalue of that stiffness S: a pair grows exactly when s
is complex, ``(S11 - S22)^2 + 4 S12 S21 < 0``, which needs ``S12 S21 < 0`` (the modes'
normal and lateral components of suitable signs) and the two contact-stiffened
frequencies close together. This is the independent check of the eigen-solver of
:mod:`reduced.stability`, which holds both mechanisms, damping and rotation.
"""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np

from .model import ModalDOF

__all__ = ["coupling_stiffness", "two_mode_coalesces"]


def coupling_stiffness(
    modes: Sequence[ModalDOF], normal_stiffness_n_m: float, adhesion_ratio: float
) -> np.ndarray:
    """S = diag(omega^2) + k_H phi_n phi_n^T + mu0 k_H phi_t phi_n^T [1/s^2] of ``modes``
    in mass-normalised coordinates (``ModalDOF.components``)."""
    w2 = np.array([md.angular_frequency_rad_s**2 for md in modes])
    pt, pn = (np.array(x) for x in zip(*(md.components for md in modes)))
    return np.diag(w2) + normal_stiffness_n_m * (np.outer(pn, pn) + adhesion_ratio * np.outer(pt, pn))


def two_mode_coalesces(stiffness: np.ndarray) -> bool:
    """Whether two undamped modes with the (non-symmetric) stiffness matrix ``stiffness``
    form a growing pair: the eigenvalues of S are complex, ``(S11 - S22)^2 + 4 S12 S21 <
    0`` (which needs S12 S21 < 0)."""
    s = np.asarray(stiffness, float)
    return bool((s[0, 0] - s[1, 1]) ** 2 + 4.0 * s[0, 1] * s[1, 0] < 0.0)
