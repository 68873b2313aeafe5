"""The sound of a mode at a given contact velocity: the ``sound`` command (the mode the
chain's decision names at the operating point, unless ``--mode`` names one), and the
listener every command with a microphone reads."""

from __future__ import annotations

import argparse

from ..errors import RequestError
from ..levels import tone_sound
from ..outputs import result_folder, write_json
from ..present.results import write_sound_files
from ..present.text import sound_text
from ..sound import check_velocity_amplitude, mode_sound
from .common import analysis_of, context_of, design_of, listener_of, out_of

__all__ = ["cmd_curve", "cmd_sound", "cmd_track"]


def cmd_sound(args: argparse.Namespace) -> int:
    design = design_of(args)
    listener = listener_of(args, design)
    check_velocity_amplitude(args.velocity_amplitude)
    out = out_of(args, design.name)
    ctx = context_of(args)
    with result_folder(out, "sound") as tmp:
        a = analysis_of(args, design, stop_after="stability", remedy=False)
        o = a.verdict.outcome or a.verdict.named or a.verdict.pick
        if o is None:
            raise RequestError(f"{design.name}: no mode grows at this operating point; name one with --mode")
        mode, why = o.mode, a.verdict.reason
        f = args.frequency or mode.frequency_hz
        with ctx.progress.stage(f"sound of mode {mode.index} ({mode.label()}) at {f:.1f} Hz"):
            tone = mode_sound(
                design, a.modeset, mode, f, args.velocity_amplitude, listener=listener,
                fidelity=ctx.fidelity.name, fmax_hz=ctx.fmax_hz, cache=ctx.cache, budget=ctx.budget,
            )  # fmt: skip
        sound = tone_sound(tone)
        write_sound_files(tmp, sound)
        zeta = design.damping_ratio_of(mode)
        write_json(
            tmp / "summary.json",
            {
                "design": design.name,
                "fidelity": ctx.fidelity.name,
                "mode": {**mode.to_dict(zeta), "why": why},
                "sound": sound.summary(),
                "timings_s": ctx.progress.timings,
            },
        )
    print(f"{design.name}: mode {mode.index} {mode.label()} ({why}), {mode.frequency_hz:.1f} Hz")
    print(sound_text(sound.summary()))
    print(f"-> {out}")
    return 0


def cmd_track(args: argparse.Namespace) -> int:
    """receptance.csv, receptance.png and summary.json of the rail the design rolls on."""
    from ..present.track import track_text, write_receptance_csv, write_receptance_plot
    from ..track import track_receptances

    design = design_of(args)
    out = out_of(args, design.name)
    ctx = context_of(args)
    with result_folder(out, "track") as tmp:
        with ctx.progress.stage(f"the rail's receptances at {args.points} frequencies"):
            t = track_receptances(design, args.fmin, args.fmax, args.points)
        write_receptance_csv(tmp / "receptance.csv", t)
        write_receptance_plot(tmp / "receptance.png", t)
        write_json(tmp / "summary.json", {"design": design.name, **t.summary()})
    print(track_text(t))
    print(f"-> {out}")
    return 0


def cmd_curve(args: argparse.Namespace) -> int:
    """curve.csv and summary.json: each wheel of the bogie at each radius and speed."""
    from track.curving import Bogie

    from ..curve import curve
    from ..fields import columns_of
    from ..outputs import write_csv
    from ..present.text import curve_table

    design = design_of(args)
    try:
        bogie = Bogie(args.wheelbase, args.bogie)
    except ValueError as exc:
        raise RequestError(str(exc)) from None
    if min(args.radius) <= 0 or min(args.train_speed) <= 0:
        raise RequestError("--radius and --train-speed take positive values")
    out = out_of(args, design.name)
    ctx = context_of(args)
    with result_folder(out, "curve") as tmp:
        n = len(args.radius) * len(args.train_speed)
        with ctx.progress.stage(f"{n} curves x 4 wheels"):
            cases = curve(
                design, args.radius, args.train_speed, bogie,
                stop_after="sound" if args.sound else "stability",
                context=ctx, ground_reflection=args.ground_reflection,
            )  # fmt: skip
        rows = [c.to_record() for c in cases]
        write_csv(tmp / "curve.csv", rows, columns_of("curve.csv"))
        write_json(
            tmp / "summary.json",
            {"design": design.name, "wheelbase_m": args.wheelbase, "bogie": args.bogie,
             "cases": [{**r, "verdict": c.analysis.verdict.to_dict()} for r, c in zip(rows, cases)]},
        )  # fmt: skip
    print(curve_table(rows))
    print(f"-> {out}")
    return 0
