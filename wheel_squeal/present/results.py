"""What a command writes into its result folder, from its records: the files of a
limit cycle, of a squeal's sound and of a run, each queued on the plot process
(:mod:`wheel_squeal.plotting`) where it is a figure. The formats are the other
presenters' (:mod:`.figures`, :mod:`.files`, :mod:`.summary`, :mod:`.html`)."""

from __future__ import annotations

from pathlib import Path
from typing import TYPE_CHECKING

from ..plotting import PlotWorkers
from .figures import plot_times, write_mode_growth_plot, write_shares_plot
from .sound_figures import write_sound_plot, write_spectrum_plot
from .time_history import TIMESERIES_BYTES
from .vtu_and_wav import write_pressure_vtu, write_squeal_wav

if TYPE_CHECKING:
    from ..chain import Analysis
    from ..simulation import Simulation
    from ..squeal_sound import SquealSound

__all__ = ["write_remedy_toml", "write_run_files", "write_simulation_files", "write_sound_files"]


def write_remedy_toml(directory: Path, a: Analysis) -> None:
    """remedy.toml: the verdict's remedy as the ``[squeal.damping]`` table to paste into
    the design (nothing where it does not squeal or no remedy was asked for)."""
    from geometry.files import write_atomic

    from ..presets import rpm_to_speed
    from ..verdict_remedy import remedy_toml

    remedy = a.verdict.remedy
    if remedy is None or not remedy["paste"]:
        return
    op = a.operating_point
    rpm = op.rolling_speed_m_s / rpm_to_speed(1.0, a.design.rolling_radius)
    where = f"V0 = {op.rolling_speed_m_s:.4g} m/s ({rpm:.0f} RPM), Vc = {op.crabbing_velocity_m_s:.4g} m/s"
    write_atomic(directory / "remedy.toml", remedy_toml(a.design, remedy, where))


def write_simulation_files(
    directory: Path, sim: Simulation, plots: PlotWorkers, record_bytes: float = TIMESERIES_BYTES
) -> None:
    """``timeseries.csv`` (at most ``record_bytes``) and the Fig. 4, 6-10 counterparts
    (PNG) of a simulation, queued on ``plots``, one job per file."""
    from .time_history import TIME_HISTORY_FIGURES, write_time_history_plots, write_timeseries_csv

    plots.submit(write_timeseries_csv, sim.history, directory, "timeseries.csv", record_bytes)
    for figure in TIME_HISTORY_FIGURES:
        plots.submit(write_time_history_plots, sim.history, directory, plot_times(sim), (figure,))


def write_sound_files(
    directory: Path,
    sound: SquealSound,
    plots: PlotWorkers | None = None,
    simulation: Simulation | None = None,
) -> None:
    """sound_field.png and pressure.vtu, and with the run's record (``simulation``)
    spectrum.png and squeal.wav (silence is no sound file); the figures queued on
    ``plots`` when given."""
    jobs: list = [
        (write_sound_plot, "sound_field.png", (sound,)),
        (write_pressure_vtu, "pressure.vtu", (sound,)),
    ]
    if simulation is not None and sound.signal is not None:
        if sound.audible:
            write_squeal_wav(directory / "squeal.wav", sound)
        jobs.append((write_spectrum_plot, "spectrum.png", (simulation, sound)))
    for fn, name, args in jobs:
        if plots is not None:
            plots.submit(fn, directory / name, *args)
        else:
            fn(directory / name, *args)


def write_run_files(
    directory: Path, a: Analysis, plots: PlotWorkers, record_bytes: float = TIMESERIES_BYTES
) -> None:
    """What ``run`` writes beside its summary, report and mode views: the limit cycle's
    record and figures, the squeal's sound, the modes that grew together (multimode.png)
    and every mode's growth rate (growth.png)."""
    write_remedy_toml(directory, a)
    o = a.outcome
    if o is not None and o.simulation is not None:
        write_simulation_files(directory, o.simulation, plots, record_bytes)
    heard = a.verdict.outcome
    if heard is not None and heard.sound is not None:
        write_sound_files(directory, heard.sound, plots, heard.simulation)
    for outcome in (a.verdict.pick, a.verdict.named):
        if outcome is not None and outcome.shares is not None and outcome.simulation is not None:
            plots.submit(write_shares_plot, directory / "multimode.png", outcome)
            break
    plots.submit(
        write_mode_growth_plot, directory / "growth.png", a.rows, o.mode.index if o is not None else None
    )
