"""The closed vocabularies of the tool, one ``Literal`` alias each, in one place: the
words of the glossary (``docs/glossary.md``) as the code spells them. The physics'
own vocabularies live with the physics and are re-exported here."""

from __future__ import annotations

from typing import Literal

from reduced.stability import Mechanism

__all__ = [
    "AmplitudeMethod",
    "FidelityName",
    "Mechanism",
    "NormalContact",
    "SolverName",
    "Stage",
    "Wave",
]

#: How a mode is seen from the (fixed) contact: standing (the paper's model), or on a
#: turning wheel the backward or forward travelling wave of a pair.
Wave = Literal["standing", "backward", "forward"]
#: How the normal force follows the contact's normal motion.
NormalContact = Literal["hertz", "constant"]
#: The modal solvers of ``fem.solvers.SOLVERS``.
SolverName = Literal["axisym", "3d", "3d-tet"]
#: The FE presets of ``wheel_squeal.presets.FIDELITIES``.
FidelityName = Literal["fast", "balanced", "accurate"]
#: The stages of the chain, in order; a request stops after one of them.
Stage = Literal["stability", "limit_cycle", "sound"]
#: How the chain finds a squeal's amplitude: the harmonic balance of its squeal mode
#: (``reduced.predict_limit_cycle``, fast) or the time domain from rest.
AmplitudeMethod = Literal["harmonic balance", "time domain"]
