"""Reduced (modal) curve-squeal model of Liu & Meehan (CM2015).

Hertz contact -> creep law (Eq. 3, 6) -> modes at the contact point driven by the
lateral creep force (Eq. 1, 2, 4, 5) and, where they move the contact normally, by the
Hertz normal force; the counter-body's receptance in series (``reduced.counter_body``)
-> linear stability of every mode, with the mechanism of each growing eigenvalue
(falling friction or mode coupling) -> time integration (fixed-step RK4, interpreted
while a process's runs are few and short, numba-compiled otherwise; the exponential
integrator where a counter-body's terms or a stiff contact would set RK4's step:
``reduced.stepping``; solve_ivp reference), optionally on a turning wheel (each pair two
travelling waves) -> limit-cycle metrics, the mode that carries the cycle,
harmonic-balance predictor, grid sweeps, the record's summaries. Knows nothing of meshes: modes enter
as (mass, stiffness, damping, nodal diameters) at the contact.
All quantities are SI (m, s, kg, N, Pa, W, Hz).
"""

from contact.creep import (
    FRICTION_LAWS,
    ConstantFriction,
    ContactLaw,
    FallingFriction,
    FrictionLaw,
    adhesion_ratio,
    adhesion_ratio_slope,
    falling_friction_factor,
)
from contact.hertz import HertzContact, hertz_contact, kalker_c22

from ._engine import CompiledCodeNotKept, load_compiled_kernels
from .counter_body import (
    LATERAL,
    NORMAL,
    BodyModel,
    CounterBody,
    ModalCounterBody,
    ModalRoller,
    RigidCounterBody,
    counter_body,
)
from .coupling import coupling_stiffness, two_mode_coalesces
from .integrate import METHODS, choose_method, simulate
from .limit_cycle import Cycles, LimitCycle, cycles, limit_cycle
from .modal_content import ModalContent, modal_content
from .model import (
    Integration,
    IntegrationError,
    ModalDOF,
    OperatingPoint,
    TimeHistory,
    choose_time_step,
    simulate_reference,
)
from .predictor import (
    LimitCyclePrediction,
    equivalent_mode,
    harmonic_contact_velocities,
    harmonic_distortion,
    mean_power_per_cycle,
    predict_limit_cycle,
)
from .saturate import longest_record_s, simulate_to_limit_cycle
from .stability import (
    LinearContact,
    Mitigation,
    ModeStability,
    StabilityMap,
    StabilityResult,
    critical_damping_ratio,
    critical_friction_slope,
    friction_damping_ns_m,
    largest_growth_rate,
    linear_stability,
    mitigation,
    stability_map,
)
from .summaries import summary_dicts, timeseries_table
from .sweep import SweepResult, sweep

__all__ = [
    "HertzContact",
    "hertz_contact",
    "kalker_c22",
    "ContactLaw",
    "BodyModel",
    "LATERAL",
    "NORMAL",
    "CounterBody",
    "ModalCounterBody",
    "ModalRoller",
    "RigidCounterBody",
    "counter_body",
    "coupling_stiffness",
    "two_mode_coalesces",
    "LinearContact",
    "FRICTION_LAWS",
    "ConstantFriction",
    "FallingFriction",
    "FrictionLaw",
    "adhesion_ratio",
    "adhesion_ratio_slope",
    "falling_friction_factor",
    "ModalDOF",
    "OperatingPoint",
    "TimeHistory",
    "IntegrationError",
    "choose_time_step",
    "Integration",
    "METHODS",
    "choose_method",
    "simulate",
    "simulate_reference",
    "CompiledCodeNotKept",
    "load_compiled_kernels",
    "Cycles",
    "LimitCycle",
    "cycles",
    "limit_cycle",
    "LimitCyclePrediction",
    "mean_power_per_cycle",
    "harmonic_contact_velocities",
    "predict_limit_cycle",
    "equivalent_mode",
    "harmonic_distortion",
    "SweepResult",
    "sweep",
    "longest_record_s",
    "simulate_to_limit_cycle",
    "ModalContent",
    "modal_content",
    "ModeStability",
    "StabilityResult",
    "friction_damping_ns_m",
    "linear_stability",
    "largest_growth_rate",
    "critical_damping_ratio",
    "critical_friction_slope",
    "StabilityMap",
    "stability_map",
    "Mitigation",
    "mitigation",
    "summary_dicts",
    "timeseries_table",
]
