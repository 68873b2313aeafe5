"""The sound of a mode: the ``sound`` command, and the sound stage ``run`` and
``sweep --sound`` share."""

from __future__ import annotations

from pathlib import Path

from .. import api
from ..design import Design
from ..levels import SquealSound, tone_sound
from ..outputs import result_folder, write_json
from ..plotting import PlotWorkers
from ..progress import Progress
from ..sound import Listener, air_for, check_velocity_amplitude, microphone_for, mode_sound
from ..sound_files import (
    sound_text,
    write_pressure_vtu,
    write_sound_plot,
    write_spectrum_plot,
    write_squeal_wav,
)
from ..stability import choose_mode
from .common import budget_of, cache_of, design_of, modes_of, out_of

__all__ = ["cmd_sound", "listener_of", "write_sound_files"]


def listener_of(args, design: Design) -> Listener:
    """The command's ``--microphone``, ``--air-density`` and ``--sound-speed``, checked
    before any work (:func:`wheel_squeal.sound.microphone_for`, ``air_for``)."""
    return Listener(microphone_for(design, args.microphone), air_for(args.air_density, args.sound_speed))


def write_sound_files(
    directory: Path, sound: SquealSound, plots: PlotWorkers | None = None, simulation=None
) -> None:
    """sound_field.png and pressure.vtu, and with the run's record (``simulation``)
    spectrum.png and squeal.wav (the plots queued on ``plots`` when given)."""
    jobs: list = [
        (write_sound_plot, "sound_field.png", (sound,)),
        (write_pressure_vtu, "pressure.vtu", (sound,)),
    ]
    if simulation is not None and sound.signal is not None:
        if sound.audible:  # silence is no sound file
            write_squeal_wav(directory / "squeal.wav", sound)
        jobs.append((write_spectrum_plot, "spectrum.png", (simulation, sound)))
    for fn, name, args in jobs:
        if plots is not None:
            plots.submit(fn, directory / name, *args)
        else:
            fn(directory / name, *args)


def cmd_sound(args) -> int:
    design = design_of(args)
    progress = Progress(args.quiet)
    listener = listener_of(args, design)
    check_velocity_amplitude(args.velocity_amplitude)
    out = out_of(args, design.name)
    with result_folder(out, "sound") as tmp:
        cache = cache_of(args)
        fid, ms = modes_of(args, design, progress, cache)
        mode, why, _ = choose_mode(
            design, ms, args.mode, api.contact_law(design), api.operating_point(design)
        )
        f = args.frequency or mode.frequency_hz
        with progress.stage(f"sound of mode {mode.index} ({mode.label()}) at {f:.1f} Hz"):
            tone = mode_sound(
                design,
                ms,
                mode,
                f,
                args.velocity_amplitude,
                listener=listener,
                fidelity=args.fidelity,
                fmax_hz=args.fmax,
                cache=cache,
                budget=budget_of(args),
            )
        sound = tone_sound(tone)
        write_sound_files(tmp, sound)
        zeta = design.damping_ratio_of(mode)
        write_json(
            tmp / "summary.json",
            {
                "design": design.name,
                "fidelity": fid.name,
                "mode": {**mode.to_dict(zeta), "why": why},
                "sound": sound.summary(),
                "timings_s": progress.timings,
            },
        )
    print(f"{design.name}: mode {mode.index} {mode.label()} ({why}), {mode.frequency_hz:.1f} Hz")
    print(sound_text(sound.summary()))
    print(f"-> {out}")
    return 0
