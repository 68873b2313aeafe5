"""Calibration: design parameters fitted to measured modal data."""

from __future__ import annotations

import math
import tempfile
from collections.abc import Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np

from geometry import DesignError

from .api import compute_modes, load_design, pick_mode
from .design import FIELDS, Design
from .presets import fidelity_for
from .runtime.progress import Progress
from .runtime.request_errors import RequestError
from .types import FidelityName

__all__ = ["CALIBRATED_MARK", "Calibration", "calibrate", "calibrated_design_path"]

#: Words in the description of every design calibrate writes (it may replace those).
CALIBRATED_MARK = " calibrated to f = "


@dataclass
class Calibration:
    """The fitted design, the fitted values of the free parameters, the selected mode's
    frequency [Hz] and contact modal mass [kg] there, the residuals and the number of
    evaluations."""

    design: Design
    free: dict[str, float]
    frequency_hz: float
    modal_mass_kg: float
    residual: dict[str, float]
    evaluations: int


def calibrate(
    design: Design,
    free: Sequence[str],
    target_frequency_hz: float | None,
    target_modal_mass_kg: float | None,
    fidelity: FidelityName = "fast",
    mode: str | None = None,
    frequency_uncertainty: float = 0.01,
    modal_mass_uncertainty: float = 0.10,
    progress: Progress | None = None,
) -> Calibration:
    """Weighted least-squares fit of the free design parameters to measured modal data.

    Residuals are relative errors of the selected mode (default: the squeal mode the
    design names, else the (3, 0) axial mode, computed with the ``fidelity`` preset)
    divided by the relative standard uncertainty of each measurement:
    ``(f / f_target - 1) / frequency_uncertainty`` and
    ``(m / m_target - 1) / modal_mass_uncertainty``. The defaults (1 % on a measured
    frequency, 10 % on a modal mass curve-fitted from a receptance) say that a modal
    test pins the frequency far better than the modal mass; equal values give the plain
    unweighted fit.
    """
    for name, u in (
        ("frequency_uncertainty", frequency_uncertainty),
        ("modal_mass_uncertainty", modal_mass_uncertainty),
    ):
        if not (math.isfinite(u) and u > 0):
            raise RequestError(f"{name} must be a positive relative uncertainty, got {u:g}")
    from scipy.optimize import least_squares

    check_request(free, target_frequency_hz, target_modal_mass_kg)
    progress = progress or Progress(quiet=True)
    fid = fidelity_for(fidelity)
    mode = mode or design.squeal.mode or "default"
    x0 = np.array([design.get(k) for k in free], dtype=float)
    scale = np.where(x0 != 0, np.abs(x0), design.wheel.web_thickness)
    evaluations = 0

    def evaluate(x: np.ndarray) -> Any:
        d = design.replace(**dict(zip(free, map(float, x))))
        ms = compute_modes(d, fid)
        m, _ = pick_mode(ms, mode)
        return d, m

    def residuals(x: np.ndarray) -> np.ndarray:
        nonlocal evaluations
        evaluations += 1
        try:
            d, m = evaluate(x)
        except DesignError:
            return np.full(2, 10.0)  # outside the valid design space
        r = [
            (m.frequency_hz / target_frequency_hz - 1) / frequency_uncertainty
            if target_frequency_hz
            else 0.0,
            (m.modal_mass / target_modal_mass_kg - 1) / modal_mass_uncertainty
            if target_modal_mass_kg
            else 0.0,
        ]
        progress.say(
            "calibrate: "
            + ", ".join(f"{k} = {v:.6g}" for k, v in zip(free, x))
            + f" -> f = {m.frequency_hz:.1f} Hz, m = {m.modal_mass:.3f} kg"
        )
        return np.array(r)

    lower, upper = x0 - 0.9 * scale, x0 + 3.0 * scale
    # Re-meshing makes the objective piecewise smooth at the 1e-4 level: a finite
    # difference step of 1 % of the parameter keeps derivatives meaningful.
    sol = least_squares(
        residuals, x0, bounds=(lower, upper), x_scale=scale, diff_step=1e-2, xtol=1e-4, ftol=1e-6
    )
    d, m = evaluate(sol.x)
    res = {}
    if target_frequency_hz:
        res["frequency_relative"] = m.frequency_hz / target_frequency_hz - 1
    if target_modal_mass_kg:
        res["modal_mass_relative"] = m.modal_mass / target_modal_mass_kg - 1
    res["weighted_rms"] = float(
        np.sqrt(np.mean(np.square(sol.fun[[bool(target_frequency_hz), bool(target_modal_mass_kg)]])))
    )
    return Calibration(d, dict(zip(free, map(float, sol.x))), m.frequency_hz, m.modal_mass, res, evaluations)


def check_request(
    free: Sequence[str], target_frequency_hz: float | None, target_modal_mass_kg: float | None
) -> None:
    """Refuse (:class:`RequestError`) free parameters that are not design parameters and
    missing or non-positive targets: before anything is written."""
    allowed = list(FIELDS)
    for name in free:
        if name not in allowed:
            raise RequestError(
                f"free parameter {name!r} is not a design parameter; choose from {', '.join(allowed)}"
            )
    if target_frequency_hz is None and target_modal_mass_kg is None:
        raise RequestError("give a target frequency and/or a target modal mass")
    for name, v in (
        ("target_frequency_hz", target_frequency_hz),
        ("target_modal_mass_kg", target_modal_mass_kg),
    ):
        if v is not None and not (math.isfinite(v) and v > 0):
            raise RequestError(f"{name} must be positive, got {v:g}")


def calibrated_design_path(out: Path, name: str) -> Path:
    """Where calibrate writes its design: ``out`` itself (a .toml) or ``out/NAME.toml``.
    An existing file there is replaced only if calibrate wrote it; the folder must take
    files (checked before the fit runs)."""
    path = out if out.suffix == ".toml" else out / f"{name}.toml"
    if path.exists():
        try:
            ours = CALIBRATED_MARK in load_design(path).description
        except DesignError:
            ours = False
        if not ours:
            raise RequestError(
                f"{path} exists and is not a design written by calibrate: "
                "choose another path (nothing was written)"
            )
    try:
        path.parent.mkdir(parents=True, exist_ok=True)
        with tempfile.TemporaryFile(dir=path.parent):
            pass
    except OSError as exc:
        raise RequestError(f"{out} cannot be written ({exc.strerror})") from None
    return path
