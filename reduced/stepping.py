"""The exponential integrator: the squeal model with every linear part advanced exactly
and the contact's forces solved at the end of each step (:mod:`reduced._exponential`).

The explicit RK4 of :func:`reduced.model.simulate_rk4` takes a step that resolves the highest
frequency and the stiffest damping the contact sees, and a counter-body's fitted terms
(a rail's reach several kHz, some heavily damped and light) would set it at microseconds.
Here each linear block (a wheel mode's coordinate, a counter-body's term) advances by its
exact transition over a step in which its force varies linearly (first-order hold), so
the step only has to follow the forces: a number of steps per period of the highest
*wheel* frequency integrated (:data:`STEPS_PER_PERIOD`); the counter-body's terms, however
fast, answer exactly to forces sampled at it. The contact's laws (the creep law, the Hertz
spring, the lag of transient creep) are met at each step's end by Newton's method, so a
contact far stiffer than the step (a low rolling speed) leaves it stable.

A run (:class:`ExponentialRun`) advances in chunks and keeps what the questions about it
need (module docstring of :mod:`reduced.model`): the contact's quantities every few steps
over the whole run (the cycles, the plots, timeseries.csv) and the states of every block
over its last :data:`TAIL_S` seconds at most (the modal energy shares and the counter-body's
part).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

from contact.creep import ContactLaw, adhesion_ratio

from . import _engine, _exponential
from .counter_body import LATERAL, NORMAL, BodyModel
from .model import (
    Coordinates,
    IntegrationError,
    ModalDOF,
    OperatingPoint,
    TimeHistory,
    coordinates,
    highest_frequency_hz,
    law_vector,
    max_contact_damping_ns_m,
)

__all__ = ["STEPS_PER_PERIOD", "TAIL_S", "ExponentialRun", "exponential_step_s"]

#: Steps per period of the highest wheel frequency integrated (measured: the limit cycle's
#: amplitude within 2e-3 of the converged one, its frequency within 1e-5; the convergence
#: study's rungs, ``benchmarks/bench_time_domain.py``)
STEPS_PER_PERIOD = 64
#: Samples the record keeps per period of the highest wheel frequency (cycles, plots)
SAMPLES_PER_PERIOD = 16
#: The record keeps every block's states over its last this many seconds at most
TAIL_S = 0.4


def exponential_step_s(
    modes: tuple[ModalDOF, ...],
    contact: ContactLaw,
    op: OperatingPoint,
    wheel_speed_rad_s: float = 0.0,
    steps_per_period: int = STEPS_PER_PERIOD,
) -> float:
    """The step [s]: :data:`STEPS_PER_PERIOD` per period of the highest frequency of the
    wheel's modes the contact sees (a turning pair's faster wave, the Hertz spring's
    stiffening), and at most the time in which the contact's steepest friction damping
    moves its lightest mode, m / (g_max a^2): within a step the force is taken linear in
    time, which a light mode stuck to the counter-body does not follow."""
    f = highest_frequency_hz(modes, wheel_speed_rad_s, contact.normal_stiffness_n_m)
    g = max_contact_damping_ns_m(contact, op)
    light = min((md.mass_kg / (g * md.lateral**2) for md in modes if md.lateral != 0.0), default=math.inf)
    return min(1.0 / (steps_per_period * f), light)


def _transition(a: np.ndarray, b: np.ndarray, h: float) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """(Phi, Ga, Gb) of the block x' = a x + b u over h with u linear in time:
    x(h) = Phi x(0) + Ga u(0) + Gb (u(h) - u(0)); from the exponential of the augmented
    matrix [[a, b, 0], [0, 0, 1/h], [0, 0, 0]] h."""
    from scipy.linalg import expm

    m = np.zeros((4, 4))
    m[:2, :2] = a * h
    m[:2, 2] = b * h
    m[2, 3] = 1.0
    e = expm(m)
    return e[:2, :2], e[:2, 2], e[:2, 3]


@dataclass(frozen=True, eq=False)
class _Blocks:
    """The linear blocks of the model (the wheel's coordinates, then the counter-body's
    terms) and how each meets the contact: the arrays of :func:`_exponential.exp_integrate`."""

    a: np.ndarray  # (n, 2, 2) the block's own dynamics
    b: np.ndarray  # (n, 2) its input's column
    in_q: np.ndarray
    in_n: np.ndarray
    w: np.ndarray
    phase: np.ndarray
    out_td: np.ndarray
    out_tv: np.ndarray
    out_nd: np.ndarray
    c_wheel: np.ndarray
    wheel: int  # the first ``wheel`` blocks are the wheel's coordinates
    body_index: np.ndarray  # per counter-body state: (block, slot)

    @property
    def n(self) -> int:
        return len(self.in_q)


def _blocks(coords: Coordinates, body: BodyModel | None) -> _Blocks:
    nw = len(coords.m)
    nb = 0 if body is None else body.terms
    n = nw + nb
    a, b = np.zeros((n, 2, 2)), np.zeros((n, 2))
    in_q, in_n = np.zeros(n), np.zeros(n)
    w, phase = np.zeros(n), np.zeros(n)
    out_td, out_tv, out_nd = np.zeros((n, 2)), np.zeros((n, 2)), np.zeros((n, 2))
    c_wheel = np.zeros(n)
    for i in range(nw):
        m, c, k = coords.m[i], coords.c[i], coords.k[i]
        a[i] = [[0.0, 1.0], [-k / m, -c / m]]
        b[i] = [0.0, 1.0 / m]
        in_q[i], in_n[i] = coords.a[i], -coords.b[i]
        w[i], phase[i] = coords.w[i], coords.phase[i]
        out_td[i], out_tv[i], out_nd[i] = [coords.a[i], 0.0], [0.0, coords.a[i]], [coords.b[i], 0.0]
        c_wheel[i] = c
    index = []
    for j in range(nb):
        assert body is not None
        i = nw + j
        a0, a1, b0, b1 = body.a0[j], body.a1[j], body.b0[j], body.b1[j]
        lateral = body.direction[j] == LATERAL
        in_q[i], in_n[i] = (-1.0, 0.0) if lateral else (0.0, 1.0)
        if body.order[j] == 2:
            a[i] = [[0.0, 1.0], [-a0, -a1]]
            b[i] = [0.0, 1.0]
            disp, vel = [b0, b1], [-a0 * b1, b0 - a1 * b1]  # u = b0 q + b1 q', u' less its feedthrough
            index += [(i, 0), (i, 1)]
        else:
            a[i] = [[-a1, 0.0], [0.0, -1.0]]  # the second state unused (decays from 0)
            b[i] = [1.0, 0.0]
            disp, vel = [b0, 0.0], [-a1 * b0, 0.0]
            index.append((i, 0))
        # the contact sees the wheel relative to the counter-body: its motion with a minus
        if lateral:
            out_td[i], out_tv[i] = -np.array(disp), -np.array(vel)
        else:
            out_nd[i] = -np.array(disp)
    return _Blocks(
        a, b, in_q, in_n, w, phase, out_td, out_tv, out_nd, c_wheel, nw, np.array(index, dtype=np.int64)
    )


@dataclass
class ExponentialRun:
    """A run of the squeal model by the exponential integrator, advanced in chunks
    (:meth:`advance`) and read as a :class:`~reduced.model.TimeHistory` (:meth:`history`).

    Parameters
    ----------
    modes : tuple of ModalDOF
        The wheel's modes seen at the contact.
    contact, op : the contact's law and the operating point.
    wheel_speed_rad_s : Omega (0: no rotation).
    body : BodyModel or None
        The counter-body in series with the contact.
    initial_state : (y0, v0) per wheel coordinate, or None (rest).
    preload_body : bool
        The counter-body starts in its static deflection under the steady creep force (a
        track, loaded long before the squeal starts), else at rest at zero.
    max_duration_s : float
        The longest the run may be advanced to (the record's size).
    steps_per_period : int
        :data:`STEPS_PER_PERIOD`.
    """

    modes: tuple[ModalDOF, ...]
    contact: ContactLaw
    op: OperatingPoint
    wheel_speed_rad_s: float = 0.0
    body: BodyModel | None = None
    initial_state: tuple[np.ndarray, np.ndarray] | None = None
    preload_body: bool = False
    max_duration_s: float = 4.8
    steps_per_period: int = STEPS_PER_PERIOD
    t: float = field(default=0.0, init=False)

    def __post_init__(self) -> None:
        self.coords = coordinates(self.modes, self.wheel_speed_rad_s)
        body = self.body if self.body is not None and self.body.terms else None
        self.body = body
        self.blocks = _blocks(self.coords, body)
        self.law = law_vector(self.contact, self.op, self.modes)
        self.h = exponential_step_s(
            self.modes, self.contact, self.op, self.wheel_speed_rad_s, self.steps_per_period
        )
        tau = self.contact.relaxation_time_s(self.op.rolling_speed_m_s)
        self.lag = self._lag(tau)
        f_top = highest_frequency_hz(self.modes, self.wheel_speed_rad_s, self.contact.normal_stiffness_n_m)
        self.store_every = max(1, int(self.steps_per_period // SAMPLES_PER_PERIOD))
        per_second = 1.0 / (self.h * self.store_every)
        self.capacity = int(math.ceil(self.max_duration_s * per_second)) + 2
        self.out = np.empty((self.capacity, _exponential.COLUMNS))
        self.rows = 0
        self.tail_every = self.store_every
        n_tail = int(math.ceil(min(TAIL_S, self.max_duration_s) * per_second)) + 1
        self.tail_s = np.zeros((n_tail, self.blocks.n, 2))
        self.tail_t = np.full(n_tail, np.nan)
        self.tail_at = 0
        self.f_top = f_top
        phi, ga, gb = zip(
            *(_transition(self.blocks.a[i], self.blocks.b[i], self.h) for i in range(self.blocks.n))
        )
        self.phi = np.array(phi).reshape(self.blocks.n, 2, 2)
        self.ga = np.array(ga).reshape(self.blocks.n, 2)
        self.gb = np.array(gb).reshape(self.blocks.n, 2)
        self.s = self._start()
        self.q_s, self.d_n = self._start_forces()
        self.q_d = self.q_s
        self.newton_max = 0

    # -- the start -----------------------------------------------------------------------
    def _lag(self, tau: float) -> np.ndarray:
        """(alpha, beta0, beta1): the lagged force over a step, tau Q' = Q_s - Q, with Q_s
        linear in the step: exact."""
        if tau <= 0.0:
            return np.array([0.0, 0.0, 1.0])
        x = self.h / tau
        alpha = math.exp(-x)
        beta1 = 1.0 - (1.0 - alpha) / x
        beta0 = (1.0 - alpha) / x - alpha
        return np.array([alpha, beta0, beta1])

    def _start(self) -> np.ndarray:
        s = np.zeros((self.blocks.n, 2))
        nw = self.blocks.wheel
        if self.initial_state is not None:
            y0, v0 = self.initial_state
            s[:nw, 0], s[:nw, 1] = np.asarray(y0, float)[:nw], np.asarray(v0, float)[:nw]
        if self.preload_body and self.body is not None:
            q0 = -float(adhesion_ratio(self.op.creepage, self.contact, self.op.rolling_speed_m_s))
            q0 *= self.contact.normal_load_n
            x = self.body.static_state(np.array([0.0, -q0]))  # it takes -Q laterally
            for k, (i, slot) in enumerate(self.blocks.body_index):
                s[i, slot] = x[k]
        return s

    def _start_forces(self) -> tuple[float, float]:
        """The contact's forces at the start (the state as it is, no step)."""
        b = self.blocks
        p = np.cos(b.w * self.t + b.phase)
        v = float((p * (b.out_tv * self.s).sum(axis=1)).sum())
        un = float((p * (b.out_nd * self.s).sum(axis=1)).sum())
        guess = -float(adhesion_ratio(self.op.creepage, self.contact, self.op.rolling_speed_m_s))
        q, dn, its = _exponential.contact_forces(
            v, un, 0.0, 0.0, 0.0, 0.0, 0.0, 1.0, guess * self.contact.normal_load_n, 0.0, self.law
        )
        if its < 0:
            raise IntegrationError("the contact's forces at the start of the run were not found")
        return q, dn

    # -- advancing -------------------------------------------------------------------------
    def advance(self, seconds: float) -> None:
        """Integrate ``seconds`` more (at most to ``max_duration_s``)."""
        steps = int(round(min(seconds, self.max_duration_s - self.t + 1e-12) / self.h))
        if steps <= 0:
            return
        kernels = _engine.integration_kernels(steps * self.blocks.n, scalar=False)
        b = self.blocks
        status, done, rows, self.tail_at, q_d, q_s, d_n, worst = kernels.exp_integrate(
            self.s,
            self.phi,
            self.ga,
            self.gb,
            b.in_q,
            b.in_n,
            b.w,
            b.phase,
            b.out_td,
            b.out_tv,
            b.out_nd,
            b.c_wheel,
            self.law,
            self.lag,
            self.t,
            self.q_d,
            self.q_s,
            self.d_n,
            self.h,
            steps,
            self.store_every,
            self.out,
            self.tail_every,
            self.tail_s,
            self.tail_t,
            self.tail_at,
            self.rows,
        )
        self.q_d, self.q_s, self.d_n = float(q_d), float(q_s), float(d_n)
        self.rows += int(rows)
        self.newton_max = max(self.newton_max, int(worst))
        self.t += int(done) * self.h
        if status == 1:
            raise IntegrationError(f"the state became non-finite at t = {self.t:.4g} s")
        if status == 2:
            raise IntegrationError(
                f"the contact's forces were not found at t = {self.t:.4g} s (step {self.h:.3g} s)"
            )

    # -- the record ------------------------------------------------------------------------
    def history(self) -> TimeHistory:
        """The record so far (:class:`~reduced.model.TimeHistory`): the contact's
        quantities over the whole run, the blocks' states over its tail."""
        rows = self.out[: self.rows]
        t, y, v, q, n_force, un, vb, power = (rows[:, k].copy() for k in range(_exponential.COLUMNS))
        order = np.argsort(self.tail_t[np.isfinite(self.tail_t)], kind="stable")
        kept = np.flatnonzero(np.isfinite(self.tail_t))[order]
        t_tail = self.tail_t[kept]
        states = self.tail_s[kept]
        nw = self.blocks.wheel
        body_states = None
        if self.body is not None:
            body_states = np.array([states[:, i, slot] for i, slot in self.blocks.body_index]).T
        zeta = (self.op.crabbing_velocity_m_s + v) / self.op.rolling_speed_m_s
        hertz = any(md.normal != 0.0 for md in self.modes) or (
            self.body is not None and bool(np.any(self.body.direction == NORMAL))
        )
        return TimeHistory(
            t=t,
            y=y,
            v=v,
            y_modes=states[:, :nw, 0],
            v_modes=states[:, :nw, 1],
            creepage=zeta,
            Q=q,
            P=power,
            modes=self.modes,
            contact=self.contact,
            operating_point=self.op,
            step_s=self.h,
            method="exponential",
            wheel_speed_rad_s=float(self.wheel_speed_rad_s),
            coordinates=self.coords,
            u_n=un if hertz else np.zeros(len(t)),
            N=n_force,
            t_modes=t_tail,
            v_body=vb if self.body is not None else None,
            body=self.body,
            body_states=body_states,
        )
