"""The ``sound`` command: sound of one mode at a given contact velocity (no time domain)."""

from __future__ import annotations

import argparse

from ..outputs import write_json
from ..present.results import write_sound_files
from ..present.text import sound_text
from ..runtime.request_errors import RequestError
from ..runtime.result_folders import result_folder
from ..sound import check_velocity_amplitude, mode_sound
from ..squeal_sound import tone_sound
from .arguments import non_negative, positive
from .common import analysis_of, context_of, design_of, listener_of, out_of
from .options import add_common, add_fe, add_microphone

__all__ = ["add_parser", "run"]


def add_parser(sub: argparse._SubParsersAction) -> None:
    """The command\'s flags."""
    p = sub.add_parser("sound", help="sound of one mode at a given contact velocity (no time domain)")
    add_common(p)
    add_fe(p)
    p.add_argument(
        "--velocity-amplitude",
        type=non_negative,
        default=1.0,
        help="contact velocity amplitude [m/s] (peak; default 1)",
    )
    p.add_argument("--frequency", type=positive, help="frequency [Hz] (default: the mode's)")
    add_microphone(p)


def run(args: argparse.Namespace) -> int:
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
                design,
                a.modeset,
                mode,
                f,
                args.velocity_amplitude,
                listener=listener,
                fidelity=ctx.fidelity.name,
                fmax_hz=ctx.fmax_hz,
                cache=ctx.cache,
                budget=ctx.budget,
            )
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
