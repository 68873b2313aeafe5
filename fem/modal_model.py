"""A modal model without FE: what a modal test of the wheel gives, as a TOML file of one
``[[mode]]`` table per mode::

    [[mode]]
    frequency_hz = 1143.0       # natural frequency [Hz]
    damping_ratio = 9.4e-4      # modal damping ratio [-]
    lateral = 0.568             # mass-normalised shape at the contact along t [1/sqrt(kg)]
    normal = 0.0                # ... along the contact normal n [1/sqrt(kg)]
    nodal_diameters = 3         # optional (0): a pair on a turning wheel
    label = "(3,0) measured"    # optional

Table 1's mode is ``lateral = 1/sqrt(3.1)``, ``normal = 0``. The modes stand in for the
FE modes of ``stability``, ``simulate`` and ``run``: the design still gives the contact
(load, radii, material, friction, angle, roller), and each mode's own damping ratio
replaces the design's. A modal model has no shapes, so nothing is radiated or drawn.
"""

from __future__ import annotations

import math
import warnings
from pathlib import Path
from typing import Any

import numpy as np

from geometry import DesignError
from geometry.files import read_toml

from .modes import Mode, ModeSet

__all__ = ["MODAL_MODEL_SOLVER", "explicit_modes", "load_modal_model", "modal_modes"]

#: The ``solver`` of a mode set read from a modal model
MODAL_MODEL_SOLVER = "modal-model"
_KEYS = {"frequency_hz", "damping_ratio", "lateral", "normal", "nodal_diameters", "label"}
_REQUIRED = ("frequency_hz", "damping_ratio", "lateral", "normal")
#: The plausible range of a mode's frequency [Hz] and of a mass-normalised shape's value
#: at the contact [1/sqrt(kg)] (a modal mass from 1 mg to 1000 t): outside them a value is
#: a typing error, and would overflow the model.
FREQUENCY_RANGE_HZ = (0.1, 1e6)
COMPONENT_RANGE = (1e-3 / 1000**0.5, 1e3)
#: The longest label of a mode
MAX_LABEL_CHARS = 80
#: The most modes a modal model holds (its linear stability is a dense eigen-solve of
#: twice as many states: 10,000 modes take hours and 7.7 GB).
MAX_MODES = 10_000


def _number(where: str, key: str, value: Any) -> float:
    if isinstance(value, bool) or not isinstance(value, int | float) or not math.isfinite(value):
        raise DesignError(f"{where}: {key} must be a finite number, got {value!r}")
    return float(value)


def _mass(component: float) -> float:
    """The modal mass 1/phi^2 [kg] of a mass-normalised shape's value phi [1/sqrt(kg)]."""
    return math.inf if abs(component) < 1e-150 else component**-2


def _mode(i: int, table: Any, source: str) -> Mode:
    where = f"{source}: [[mode]] {i + 1}"
    if not isinstance(table, dict):
        raise DesignError(f"{where} must be a table")
    unknown = sorted(set(table) - _KEYS)
    if unknown:
        raise DesignError(f"{where}: unknown key {unknown[0]!r}; allowed: {', '.join(sorted(_KEYS))}")
    missing = [k for k in _REQUIRED if k not in table]
    if missing:
        raise DesignError(f"{where} needs {', '.join(missing)}")
    f, zeta, t, n = (_number(where, k, table[k]) for k in _REQUIRED)
    if not FREQUENCY_RANGE_HZ[0] <= f <= FREQUENCY_RANGE_HZ[1]:
        raise DesignError(
            f"{where}: frequency_hz = {f:g} is outside the range of a wheel's modes "
            f"({FREQUENCY_RANGE_HZ[0]:g} to {FREQUENCY_RANGE_HZ[1]:g} Hz)"
        )
    for key, phi in (("lateral", t), ("normal", n)):
        if phi != 0.0 and not COMPONENT_RANGE[0] <= abs(phi) <= COMPONENT_RANGE[1]:
            raise DesignError(
                f"{where}: {key} = {phi:g} 1/sqrt(kg) means a modal mass of {_mass(phi):.3g} kg at the "
                f"contact, outside {1 / COMPONENT_RANGE[1] ** 2:g} to {1 / COMPONENT_RANGE[0] ** 2:g} kg "
                "(give 0 for a mode that does not move the contact that way)"
            )
    if not 0.0 <= zeta < 1.0:
        raise DesignError(f"{where}: damping_ratio = {zeta:g}: a modal damping ratio in [0, 1)")
    if t == 0.0 and n == 0.0:
        raise DesignError(f"{where}: lateral and normal are both 0: the contact does not see this mode")
    nd = table.get("nodal_diameters", 0)
    if isinstance(nd, bool) or not isinstance(nd, int) or nd < 0:
        raise DesignError(f"{where}: nodal_diameters must be a whole number >= 0, got {nd!r}")
    label = table.get("label", "")
    if not isinstance(label, str):
        raise DesignError(f"{where}: label must be a string, got {label!r}")
    if not label.isprintable() or len(label) > MAX_LABEL_CHARS:
        raise DesignError(
            f"{where}: label {ascii(label[:40])} must be printable text (no control characters) of at most "
            f"{MAX_LABEL_CHARS} characters: it is printed on the terminal and in the report"
        )
    members = 1 if nd == 0 else 2  # a pair: its second member has a node at the contact
    lateral, normal = (t,) + (0.0,) * (members - 1), (n,) + (0.0,) * (members - 1)
    return Mode(i, f, nd, 0, "measured", lateral, normal, label or f"mode {i + 1} ({f:.1f} Hz)", zeta)


def modal_modes(modes: list[Mode]) -> ModeSet:
    """Measured or given modes (no shapes) as a ``fem.ModeSet`` of solver
    :data:`MODAL_MODEL_SOLVER`, in the order given."""
    return ModeSet(
        modes, np.zeros((0, 3)), {}, [np.zeros((m.multiplicity, 0, 3)) for m in modes], MODAL_MODEL_SOLVER, 0
    )


def explicit_modes(
    mass_kg: float, stiffness_n_m: float, damping_ns_m: float, nodal_diameters: int = 0
) -> ModeSet:
    """One mode given by its modal parameters at the contact, as a mode set the chain
    takes like any other.

    Parameters
    ----------
    mass_kg : float
        Its modal mass at the contact (lateral) [kg].
    stiffness_n_m : float
        Its modal stiffness [N/m].
    damping_ns_m : float
        Its modal damping [N s/m] (below critical).
    nodal_diameters : int
        A pair on a turning wheel when >= 1.

    Returns
    -------
    fem.ModeSet

    Raises
    ------
    DesignError
        A value that is not positive (damping: negative) or over critical damping.

    Examples
    --------
    >>> from fem import modal_model as mm
    >>> m = mm.explicit_modes(3.1, 1.6e8, 42).modes[0]
    >>> round(m.frequency_hz, 1), round(m.modal_mass, 6)
    (1143.4, 3.1)
    """
    for name, v, zero_ok in (
        ("mass_kg", mass_kg, False),
        ("stiffness_n_m", stiffness_n_m, False),
        ("damping_ns_m", damping_ns_m, True),
    ):
        if not (math.isfinite(v) and (v > 0 or (zero_ok and v == 0))):
            raise DesignError(f"{name} must be {'non-negative' if zero_ok else 'positive'}, got {v:g}")
    if nodal_diameters < 0:
        raise DesignError(f"nodal diameters must be 0 or more, got {nodal_diameters}")
    f = math.sqrt(stiffness_n_m / mass_kg) / (2 * math.pi)
    zeta = damping_ns_m / (2 * math.sqrt(stiffness_n_m * mass_kg))
    if not zeta < 1.0:
        raise DesignError(
            f"damping_ns_m = {damping_ns_m:g} is over critical damping "
            f"({2 * math.sqrt(stiffness_n_m * mass_kg):.4g} N s/m)"
        )
    members = 1 if nodal_diameters == 0 else 2
    phi = (1.0 / math.sqrt(mass_kg),) + (0.0,) * (members - 1)
    zero = (0.0,) * members
    label = f"the given mode ({f:.1f} Hz)"
    return modal_modes([Mode(0, f, int(nodal_diameters), 0, "measured", phi, zero, label, zeta)])


def load_modal_model(path: str | Path, fmax_hz: float | None = None) -> ModeSet:
    r"""The modes of a modal-model file (one ``[[mode]]`` table each: frequency_hz,
    damping_ratio, lateral and normal components at the contact [1/sqrt(kg)], optional
    nodal_diameters and label), in frequency order.

    Parameters
    ----------
    path : str or Path
    fmax_hz : float, optional
        Keep the modes up to this frequency [Hz] (the band, as for the FE modes).

    Returns
    -------
    fem.ModeSet
        No shapes; its ``solver`` is :data:`MODAL_MODEL_SOLVER`.

    Raises
    ------
    DesignError
        A bad file, in one line naming the problem.

    Examples
    --------
    >>> import tempfile, pathlib
    >>> from fem import modal_model as mm
    >>> path = pathlib.Path(tempfile.mkdtemp()) / "rig.toml"
    >>> text = "[[mode]]\nfrequency_hz = 1143.0\ndamping_ratio = 9.4e-4\nlateral = 0.568\nnormal = 0.0\n"
    >>> _ = path.write_text(text)
    >>> [m.label() for m in mm.load_modal_model(path).modes]
    ['mode 1 (1143.0 Hz)']
    """
    source = str(path)
    _, data = read_toml(path, "modal model", DesignError)
    unknown = sorted(set(data) - {"mode"})
    if unknown:
        raise DesignError(f"{source}: unknown key or table {unknown[0]!r}; a modal model is [[mode]] tables")
    tables = data.get("mode")
    if not isinstance(tables, list) or not tables:
        raise DesignError(
            f"{source}: no [[mode]] table: give one per mode (frequency_hz, damping_ratio, ...)"
        )
    if len(tables) > MAX_MODES:
        raise DesignError(f"{source}: {len(tables):,} modes, more than a modal model takes ({MAX_MODES:,})")
    modes = sorted((_mode(i, t, source) for i, t in enumerate(tables)), key=lambda m: m.frequency_hz)
    if fmax_hz is not None:
        band = [m for m in modes if m.frequency_hz <= fmax_hz]
        if not band:
            raise DesignError(
                f"{source}: no mode up to fmax = {fmax_hz:g} Hz "
                f"(the lowest is {modes[0].frequency_hz:.6g} Hz)"
            )
        if len(band) < len(modes):
            warnings.warn(
                f"{source}: {len(modes) - len(band)} of {len(modes)} modes lie above fmax = {fmax_hz:g} Hz "
                "and are left out",
                stacklevel=2,
            )
        modes = band
    modes = [
        Mode(
            k,
            m.frequency_hz,
            m.nodal_diameters,
            0,
            m.family,
            m.contact_lateral,
            m.contact_normal,
            m.name,
            m.damping_ratio,
        )
        for k, m in enumerate(modes)
    ]
    labels = [m.name for m in modes]
    if len(set(labels)) != len(labels):
        raise DesignError(f"{source}: two modes have the same label; give each its own")
    return modal_modes(modes)
