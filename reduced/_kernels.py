"""Fixed-step RK4 kernels for the modal squeal model, written once in plain Python.

:mod:`reduced._engine` runs them either as they are (interpreted: no start-up cost,
slow per step) or as their numba-compiled twins (fast per step, after a one-off load of
the compiler and its on-disk cache). The kernels use only IEEE float arithmetic,
``math`` and element access, in the same order in both forms, so both give the same
bits; ``prange`` is the compiled twin's parallel loop and a plain ``range`` here.

State: modal displacements y_i (m) and velocities u_i (m/s) of N modal coordinates
that share the contact point, each seen there with a participation
p_i(t) = cos(w_i t + phase_i) and moving the contact a_i y_i along the lateral
tangent and b_i y_i along the normal: lateral contact velocity v = sum_i p_i a_i u_i,
normal approach u_n = sum_i p_i b_i y_i, normal force N = W (1 + u_n/delta0)^(3/2)
(0 once the surfaces separate), lateral force Q = -mu((Vc + v)/V0) N, and
m_i y_i'' + c_i y_i' + k_i y_i = p_i (a_i Q - b_i (N - W)). With transient creep the
force the modes feel lags the steady Q: tau Q_l' = Q - Q_l. Without rotation every
w_i and phase_i is 0 and p_i = 1 exactly; with a_i = 1, b_i = 0 and no lag this is the
paper's N-mode model, and the same IEEE operations give its bits. On a wheel turning
at Omega, a pair of n nodal diameters is two coordinates with w = n Omega and phases 0
and pi/2 (p = cos(n Omega t) and -sin(n Omega t), docs/theory.md, rotation).

Contact parameters are passed as a float64 vector ``law``::

    law = [W, mu_s, K = G a b C22/(mu_0 W), s1, s2, V0, Vc, delta0, tau, u_n0]

(delta0 infinite: constant normal load; tau 0: steady creep; u_n0 the static normal
approach under the steady creep force, from which the Hertz spring is measured: the
rig's load keeps the mean normal force at W). Every kernel also
integrates the power balance, dE/dt = Q v - sum c_i u_i^2 with E = sum (m_i u_i^2 +
k_i y_i^2)/2 plus the Hertz spring's energy, with the RK4 weights: a mismatch between
the energy change and the integrated power flags a step too large for the dynamics.
"""

from __future__ import annotations

import math

import numpy as np

LAW_W, LAW_MUS, LAW_K, LAW_S1, LAW_S2, LAW_V0, LAW_VC, LAW_D0, LAW_TAU, LAW_UN0, LAW_W1, LAW_W2 = range(12)

prange = range


def adhesion(v, law):
    """mu((Vc + v)/V0), the signed adhesion ratio at contact velocity v in m/s (Eq. 3, 4, 6)."""
    V0 = law[LAW_V0]
    zeta = (law[LAW_VC] + v) / V0
    a = abs(zeta)
    zp = a * law[LAW_K]
    if zp < 3.0:
        poly = zp * (1.0 - zp / 3.0 + zp * zp / 27.0)
    else:
        poly = 1.0
    s = a * V0
    if s > 0.0:
        f = 1.0 - law[LAW_W1] * math.exp(-law[LAW_S1] / s) - law[LAW_W2] * math.exp(-law[LAW_S2] / s)
    else:
        f = 1.0
    mu = law[LAW_MUS] * poly * f
    if zeta < 0.0:
        mu = -mu
    return mu


def lateral_force(v, law):
    """Q(v) = -mu((Vc + v)/V0) W in N for contact velocity v in m/s (Eq. 2-4, 6)."""
    return -adhesion(v, law) * law[LAW_W]


def normal_force(un, law):
    """N = W (1 + (u_n - u_n0)/delta0)^(3/2) in N at a normal approach u_n in m; 0 once
    the surfaces separate; W exactly at u_n = u_n0 or delta0 infinite."""
    x = 1.0 + (un - law[LAW_UN0]) / law[LAW_D0]
    if x <= 0.0:
        return 0.0
    return law[LAW_W] * (x * math.sqrt(x))


def hertz_energy(un, law):
    """The Hertz spring's energy above the static state, int_u_n0^u_n (N - W) du, in J
    (0 with a constant normal load)."""
    d0 = law[LAW_D0]
    if math.isinf(d0):
        return 0.0
    d = un - law[LAW_UN0]
    x = 1.0 + d / d0
    if x < 0.0:
        x = 0.0
    return law[LAW_W] * (0.4 * d0 * (x * x * math.sqrt(x) - 1.0) - d)


def _contact(y, u, p, a, b):
    """(v, u_n): the lateral contact velocity and the normal approach."""
    v = 0.0
    un = 0.0
    for i in range(y.shape[0]):
        v += p[i] * a[i] * u[i]
        un += p[i] * b[i] * y[i]
    return v, un


def steady_force(y, u, p, a, b, law):
    """The steady lateral force Q = -mu N at the state (y, u) [N]."""
    v, un = _contact(y, u, p, a, b)
    return -adhesion(v, law) * normal_force(un, law)


def _participation(w, phase, t, p):
    """p_i = cos(w_i t + phase_i); exactly 1 where w_i = phase_i = 0."""
    for i in range(w.shape[0]):
        p[i] = math.cos(w[i] * t + phase[i])


def _deriv(y, u, ql, p, m, c, k, a, b, law, dy, du):
    """The state's rates into (dy, du); returns (power Q v - sum c u^2 [W], |Q v| [W],
    the lagged force's rate [N/s])."""
    n = y.shape[0]
    v, un = _contact(y, u, p, a, b)
    nf = normal_force(un, law)
    qs = -adhesion(v, law) * nf
    tau = law[LAW_TAU]
    if tau > 0.0:
        q = ql
        dq = (qs - ql) / tau
    else:
        q = qs
        dq = 0.0
    dn = nf - law[LAW_W]
    power = q * v
    for i in range(n):
        dy[i] = u[i]
        du[i] = (p[i] * a[i] * q - p[i] * b[i] * dn - c[i] * u[i] - k[i] * y[i]) / m[i]
        power -= c[i] * u[i] * u[i]
    return power, abs(q * v), dq


def _rk4_step(y, u, ql, m, c, k, a, b, w, phase, law, t, h, scratch):
    """Advance (y, u) in place by one RK4 step h (s) from time t (s); return the RK4
    estimate of the energy input  int P dt  and  int |Q v| dt  over the step (J), and
    the lagged force at its end (N)."""
    n = y.shape[0]
    ky1, ku1, ky2, ku2 = scratch[0], scratch[1], scratch[2], scratch[3]
    ky3, ku3, ky4, ku4 = scratch[4], scratch[5], scratch[6], scratch[7]
    yt, ut, p0, ph, p1 = scratch[8], scratch[9], scratch[10], scratch[11], scratch[12]
    _participation(w, phase, t, p0)
    _participation(w, phase, t + 0.5 * h, ph)
    _participation(w, phase, t + h, p1)
    e1, r1, g1 = _deriv(y, u, ql, p0, m, c, k, a, b, law, ky1, ku1)
    for i in range(n):
        yt[i] = y[i] + 0.5 * h * ky1[i]
        ut[i] = u[i] + 0.5 * h * ku1[i]
    e2, r2, g2 = _deriv(yt, ut, ql + 0.5 * h * g1, ph, m, c, k, a, b, law, ky2, ku2)
    for i in range(n):
        yt[i] = y[i] + 0.5 * h * ky2[i]
        ut[i] = u[i] + 0.5 * h * ku2[i]
    e3, r3, g3 = _deriv(yt, ut, ql + 0.5 * h * g2, ph, m, c, k, a, b, law, ky3, ku3)
    for i in range(n):
        yt[i] = y[i] + h * ky3[i]
        ut[i] = u[i] + h * ku3[i]
    e4, r4, g4 = _deriv(yt, ut, ql + h * g3, p1, m, c, k, a, b, law, ky4, ku4)
    for i in range(n):
        y[i] += h / 6.0 * (ky1[i] + 2.0 * ky2[i] + 2.0 * ky3[i] + ky4[i])
        u[i] += h / 6.0 * (ku1[i] + 2.0 * ku2[i] + 2.0 * ku3[i] + ku4[i])
    work = h / 6.0 * (e1 + 2.0 * e2 + 2.0 * e3 + e4)
    absqv = h / 6.0 * (r1 + 2.0 * r2 + 2.0 * r3 + r4)
    return work, absqv, ql + h / 6.0 * (g1 + 2.0 * g2 + 2.0 * g3 + g4)


def _rk4_step_1(y, u, m, c, k, law, h):
    """Single-mode RK4 step on scalars (2.4x faster than the array version).
    Returns (y, u, int P dt, int |Q v| dt) over the step (J)."""
    a1 = u
    q1 = lateral_force(a1, law)
    b1 = (q1 - c * a1 - k * y) / m
    a2 = u + 0.5 * h * b1
    q2 = lateral_force(a2, law)
    b2 = (q2 - c * a2 - k * (y + 0.5 * h * a1)) / m
    a3 = u + 0.5 * h * b2
    q3 = lateral_force(a3, law)
    b3 = (q3 - c * a3 - k * (y + 0.5 * h * a2)) / m
    a4 = u + h * b3
    q4 = lateral_force(a4, law)
    b4 = (q4 - c * a4 - k * (y + h * a3)) / m
    work = (
        h
        / 6.0
        * ((q1 - c * a1) * a1 + 2.0 * (q2 - c * a2) * a2 + 2.0 * (q3 - c * a3) * a3 + (q4 - c * a4) * a4)
    )
    absqv = h / 6.0 * (abs(q1 * a1) + 2.0 * abs(q2 * a2) + 2.0 * abs(q3 * a3) + abs(q4 * a4))
    return (
        y + h / 6.0 * (a1 + 2.0 * a2 + 2.0 * a3 + a4),
        u + h / 6.0 * (b1 + 2.0 * b2 + 2.0 * b3 + b4),
        work,
        absqv,
    )


def integrate_store_1(y0, u0, m, c, k, law, h, n_steps, store_every, out_y, out_u):
    """Single-mode version of integrate_store (scalars m, c, k, y0, u0; out_y, out_u 1-D)."""
    y = y0
    u = u0
    e0 = 0.5 * (m * u * u + k * y * y)
    emax = e0
    work = 0.0
    out_y[0] = y
    out_u[0] = u
    row = 1
    status = 0
    step = 0
    for step in range(1, n_steps + 1):
        y, u, w, _wq = _rk4_step_1(y, u, m, c, k, law, h)
        work += w
        e = 0.5 * (m * u * u + k * y * y)
        if not math.isfinite(e):
            status = 1
            break
        if e > emax:
            emax = e
        if step % store_every == 0 and row < len(out_y):
            out_y[row] = y
            out_u[row] = u
            row += 1
    e_end = 0.5 * (m * u * u + k * y * y)
    return status, abs(e_end - e0 - work), emax, work, step


def _energy(y, u, m, k):
    e = 0.0
    for i in range(y.shape[0]):
        e += 0.5 * (m[i] * u[i] * u[i] + k[i] * y[i] * y[i])
    return e


def _total_energy(y, u, m, k, a, b, w, phase, law, t, p):
    """The modes' energy plus the Hertz spring's at time t (p: scratch for the
    participations) [J]."""
    e = _energy(y, u, m, k)
    if math.isinf(law[LAW_D0]):
        return e
    _participation(w, phase, t, p)
    _v, un = _contact(y, u, p, a, b)
    return e + hertz_energy(un, law)


def integrate_store(y0, u0, m, c, k, a, b, w, phase, law, h, n_steps, store_every, out_y, out_u, out_q):
    """Integrate n_steps RK4 steps of size h (s) from (y0, u0) at t = 0, storing every
    ``store_every``-th state (row 0 = initial state) into out_y, out_u (n_out, N) and
    the lateral force the modes feel into out_q (n_out,); participations cos(w t +
    phase) and contact gains a, b (see the module docstring). With transient creep the
    lagged force starts at its steady value (without a lag out_q holds that first
    value only: the steady force follows from the stored state).

    Returns (status, energy_mismatch_J, max_energy_J, work_in_J, steps_done):
    status 0 = ok, 1 = non-finite state. energy_mismatch = |E_end - E_0 - int P dt|.
    """
    n = y0.shape[0]
    y = y0.copy()
    u = u0.copy()
    scratch = np.zeros((14, n))
    pe = scratch[13]
    _participation(w, phase, 0.0, pe)
    ql = steady_force(y, u, pe, a, b, law)
    e0 = _total_energy(y, u, m, k, a, b, w, phase, law, 0.0, pe)
    emax = e0
    work = 0.0
    out_y[0, :] = y
    out_u[0, :] = u
    out_q[0] = ql
    row = 1
    status = 0
    step = 0
    for step in range(1, n_steps + 1):
        dw, _wq, ql_end = _rk4_step(y, u, ql, m, c, k, a, b, w, phase, law, (step - 1) * h, h, scratch)
        work += dw
        e = _total_energy(y, u, m, k, a, b, w, phase, law, step * h, pe)
        if law[LAW_TAU] > 0.0:
            ql = ql_end
        if not math.isfinite(e):
            status = 1
            break
        if e > emax:
            emax = e
        if step % store_every == 0 and row < out_y.shape[0]:
            out_y[row, :] = y
            out_u[row, :] = u
            out_q[row] = ql
            row += 1
    e_end = _total_energy(y, u, m, k, a, b, w, phase, law, step * h, pe)
    return status, abs(e_end - e0 - work), emax, work, step


def extract_cycles(t, v, cum_p, cum_qv, out_start, out_amp, out_period, out_power, out_absqv):
    """Split a contact-velocity record v(t) into cycles between upward zero
    crossings (linearly interpolated). ``cum_p`` and ``cum_qv`` are the running
    integrals of P and |Q v| (J) at the samples. Per cycle: start time (s),
    velocity amplitude = (max - min)/2 with parabolic refinement of the sampled
    extrema (m/s), period (s), mean power P (W), mean |Q v| (W). Returns the number
    of cycles written (at most the length of the output arrays)."""
    n = len(t)
    cap = len(out_start)
    nc = 0
    have_start = False
    t_start = 0.0
    ep_start = 0.0
    eq_start = 0.0
    vmax = -np.inf
    vmin = np.inf
    for j in range(1, n):
        if v[j - 1] < 0.0 and v[j] >= 0.0:
            frac = -v[j - 1] / (v[j] - v[j - 1])
            tc = t[j - 1] + frac * (t[j] - t[j - 1])
            ep = cum_p[j - 1] + frac * (cum_p[j] - cum_p[j - 1])
            eq = cum_qv[j - 1] + frac * (cum_qv[j] - cum_qv[j - 1])
            if have_start and nc < cap:
                per = tc - t_start
                out_start[nc] = t_start
                out_amp[nc] = 0.5 * (vmax - vmin)
                out_period[nc] = per
                out_power[nc] = (ep - ep_start) / per
                out_absqv[nc] = (eq - eq_start) / per
                nc += 1
            have_start = True
            t_start = tc
            ep_start = ep
            eq_start = eq
            vmax = -np.inf
            vmin = np.inf
        # local extremum at j-1, refined by the parabola through j-2, j-1, j
        if j >= 2:
            a0 = v[j - 2]
            a1 = v[j - 1]
            a2 = v[j]
            curv = a0 - 2.0 * a1 + a2
            if a1 >= a0 and a1 >= a2:
                peak = a1 - (a2 - a0) * (a2 - a0) / (8.0 * curv) if curv < 0.0 else a1
                if peak > vmax:
                    vmax = peak
            if a1 <= a0 and a1 <= a2:
                trough = a1 - (a2 - a0) * (a2 - a0) / (8.0 * curv) if curv > 0.0 else a1
                if trough < vmin:
                    vmin = trough
    return nc


def sweep_kernel(
    m,
    c,
    k,
    a,
    b,
    laws,
    h_per_case,
    n_steps_per_case,
    cap,
    out_start,
    out_amp,
    out_period,
    out_power,
    out_absqv,
    out_ncycles,
    out_status,
    out_mismatch,
    out_emax,
):
    """Run every case (row of ``laws``) from rest in parallel (prange) and reduce
    each time history to its cycles (see extract_cycles) without keeping it.
    The power integrals use the RK4 stage values (no extra force evaluation)."""
    n_cases = laws.shape[0]
    n = m.shape[0]
    for ic in prange(n_cases):
        law = laws[ic]
        h = h_per_case[ic]
        ns = n_steps_per_case[ic]
        y = np.zeros(n)
        u = np.zeros(n)
        scratch = np.zeros((14, n))
        still = np.zeros(n)  # no rotation: participation 1
        ones = np.ones(n)
        scalar = n == 1 and a[0] == 1.0 and b[0] == 0.0 and law[LAW_TAU] == 0.0
        ql = steady_force(y, u, ones, a, b, law)
        t = np.empty(ns + 1)
        v = np.empty(ns + 1)
        cp = np.empty(ns + 1)
        cq = np.empty(ns + 1)
        t[0] = 0.0
        v[0] = 0.0
        cp[0] = 0.0
        cq[0] = 0.0
        emax = 0.0
        status = 0
        last = ns
        y1 = 0.0
        u1 = 0.0
        for step in range(1, ns + 1):
            if scalar:
                y1, u1, w, wq = _rk4_step_1(y1, u1, m[0], c[0], k[0], law, h)
                e = 0.5 * (m[0] * u1 * u1 + k[0] * y1 * y1)
                vv = u1
            else:
                w, wq, ql_end = _rk4_step(y, u, ql, m, c, k, a, b, still, still, law, 0.0, h, scratch)
                if law[LAW_TAU] > 0.0:
                    ql = ql_end
                e = _total_energy(y, u, m, k, a, b, still, still, law, 0.0, scratch[13])
                vv, _un = _contact(y, u, ones, a, b)
            if not math.isfinite(e):
                status = 1
                last = step - 1
                break
            if e > emax:
                emax = e
            t[step] = step * h
            v[step] = vv
            cp[step] = cp[step - 1] + w
            cq[step] = cq[step - 1] + wq
        if scalar:
            e_end = 0.5 * (m[0] * u1 * u1 + k[0] * y1 * y1)
        else:
            e_end = _total_energy(y, u, m, k, a, b, still, still, law, 0.0, scratch[13])
        out_status[ic] = status
        out_emax[ic] = emax
        out_mismatch[ic] = abs(e_end - cp[last]) if status == 0 else np.inf
        out_ncycles[ic] = extract_cycles(
            t[: last + 1],
            v[: last + 1],
            cp[: last + 1],
            cq[: last + 1],
            out_start[ic],
            out_amp[ic],
            out_period[ic],
            out_power[ic],
            out_absqv[ic],
        )
