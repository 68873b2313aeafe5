"""Kernels of the exponential integrator, written once in plain Python: run interpreted or
compiled by numba (:mod:`reduced._engine`), with the same IEEE operations in both forms.

Every linear part of the model is a block of two states s = (s0, s1) driven by one
input u (a force [N]): a wheel mode's coordinate (q, q') with m q'' + c q' + k q = u, a
counter-body's pair of poles (q, q') with q'' + a1 q' + a0 q = u, or a counter-body's
first-order term (x, unused). Over a step h in which the input varies linearly from u0 to
u1, a block advances exactly:

    s(t + h) = Phi s(t) + Ga u0 + Gb (u1 - u0)

(``phi``, ``ga``, ``gb``, made once per step size by :mod:`reduced.stepping`), so that its
own frequency and damping, however high or stiff, set no step. The blocks meet only at
the contact. A block's input is its participation p(t) = cos(w t + phase) (1 without
rotation) times ``in_q`` Q + ``in_n`` dN (Q: the lateral force on the wheel the modes
feel; dN = N - W: the normal force beyond the load); it moves the contact by p(t) times
``out_td`` . s laterally and ``out_nd`` . s normally, at p(t) ``out_tv`` . s laterally
(the counter-body's terms with the opposite sign: the contact sees the wheel relative
to it). At the end of each step the contact forces solve, with the blocks' response to
them within the step, the contact's laws (Newton's method, safeguarded):

    Q_s = -mu((Vc + v)/V0) N,   N = W (1 + (u_n - u_n0)/delta0)^(3/2) (0 apart)

and, with transient creep, Q = alpha Q(t) + beta0 Q_s(t) + beta1 Q_s(t + h) (the lag's
own exact step), else Q = Q_s. The record keeps every ``store_every``-th step's contact
quantities and, in a ring, the blocks' states of the last ``tail`` stored samples.

Contact parameters come as :mod:`reduced._kernels`' ``law`` vector.
"""

from __future__ import annotations

import math

import numpy as np

from ._kernels import (
    LAW_D0,
    LAW_K,
    LAW_MUS,
    LAW_S1,
    LAW_S2,
    LAW_UN0,
    LAW_V0,
    LAW_VC,
    LAW_W,
    LAW_W1,
    LAW_W2,
    adhesion,
)

__all__ = ["adhesion_slope", "contact_forces", "exp_integrate"]

#: Newton's method on the contact forces stops when a step changes them by less than this
#: fraction of the load, and gives up (status 2) after this many iterations (halving the
#: bracket of 2 mu_s N to the tolerance takes about 40)
FORCE_TOLERANCE, MAX_NEWTON = 1e-11, 100
#: The columns of a stored sample: time, lateral displacement and velocity of the contact
#: (the wheel's relative to the counter-body's), lateral force, normal force, normal
#: approach, the counter-body's lateral velocity, power into the wheel's modes
COLUMNS = 8


def adhesion_slope(v, law):
    """d mu / d v [s/m] at contact velocity v [m/s]: (d mu / d zeta) / V0, even in zeta."""
    V0 = law[LAW_V0]
    zeta = (law[LAW_VC] + v) / V0
    a = abs(zeta)
    k = law[LAW_K]
    zp = a * k
    if zp < 3.0:
        poly = zp * (1.0 - zp / 3.0 + zp * zp / 27.0)
        dpoly = 1.0 - 2.0 * zp / 3.0 + zp * zp / 9.0
    else:
        poly = 1.0
        dpoly = 0.0
    s = a * V0
    if s > 0.0:
        e1 = math.exp(-law[LAW_S1] / s)
        e2 = math.exp(-law[LAW_S2] / s)
        f = 1.0 - law[LAW_W1] * e1 - law[LAW_W2] * e2
        df = -law[LAW_W1] * e1 * law[LAW_S1] / (s * s) - law[LAW_W2] * e2 * law[LAW_S2] / (s * s)
    else:
        f = 1.0
        df = 0.0
    return law[LAW_MUS] * (dpoly * k * f + poly * df * V0) / V0


def _hertz(un, law):
    """(N, dN/du_n) at the normal approach un: W (1 + d / delta0)^(3/2), 0 apart."""
    d0 = law[LAW_D0]
    if math.isinf(d0):
        return law[LAW_W], 0.0
    x = 1.0 + (un - law[LAW_UN0]) / d0
    if x <= 0.0:
        return 0.0, 0.0
    r = math.sqrt(x)
    return law[LAW_W] * x * r, 1.5 * law[LAW_W] * r / d0


def _safeguarded(x, step, r, lo, hi):
    """Newton's step from ``x`` kept within the bracket [lo, hi] of an increasing
    residual, which ``r`` (the residual at x) narrows; halfway where the step leaves it.
    Returns (the next x, lo, hi)."""
    if r > 0.0:
        hi = x
    else:
        lo = x
    nxt = x + step
    if not (lo < nxt < hi):
        nxt = 0.5 * (lo + hi)
    return nxt, lo, hi


def _normal_force(qd, un_free, gnq, gnn, dn_guess, law):
    """dN = N - W [N] meeting the Hertz law at the step's end for the lateral force ``qd``
    the blocks feel: the root of dN + W - N_hertz(un_free + gnq qd + gnn dN), increasing
    in dN (gnn <= 0: a larger normal force pushes the bodies apart), by Newton's method
    kept within a bracket; and its derivative in qd. 0 with a constant normal load."""
    if math.isinf(law[LAW_D0]):
        return 0.0, 0.0
    W = law[LAW_W]
    lo = -W  # no normal force: the residual is -N_hertz <= 0 there
    hi = W
    base = un_free + gnq * qd
    for _ in range(80):  # the residual is positive at hi
        if hi + W - _hertz(base + gnn * hi, law)[0] > 0.0:
            break
        hi *= 2.0
    dn = min(max(dn_guess, lo), hi)
    slope = 1.0
    for _ in range(MAX_NEWTON):
        nh, dnh = _hertz(base + gnn * dn, law)
        r = dn + W - nh
        slope = 1.0 - dnh * gnn
        step = -r / slope
        if abs(step) <= FORCE_TOLERANCE * W:
            dn = dn + step
            break
        dn, lo, hi = _safeguarded(dn, step, r, lo, hi)
    nh, dnh = _hertz(base + gnn * dn, law)
    slope = 1.0 - dnh * gnn
    return dn, dnh * gnq / slope


def _lateral_residual(qs, dn0, v_free, un_free, gvq, gvn, gnq, gnn, qd_free, beta1, law):
    """(Q_s + mu(v) N, its derivative in Q_s with dN following, dN) for the steady force
    ``qs`` (:func:`contact_forces`)."""
    qd = qd_free + beta1 * qs
    dn, ddn = _normal_force(qd, un_free, gnq, gnn, dn0, law)
    v = v_free + gvq * qd + gvn * dn
    n = law[LAW_W] + dn
    mu = adhesion(v, law)
    dv = beta1 * (gvq + gvn * ddn)
    return qs + mu * n, 1.0 + n * adhesion_slope(v, law) * dv + mu * ddn * beta1, dn


def contact_forces(v_free, un_free, gvq, gvn, gnq, gnn, qd_free, beta1, qs_guess, dn_guess, law):
    """The steady lateral force Q_s and dN = N - W [N] at the end of a step: the roots of

        Q_s + mu(v) N = 0,   dN + W - N_hertz(u_n) = 0,
        v = v_free + gvq Qd + gvn dN,  u_n = un_free + gnq Qd + gnn dN,  Qd = qd_free + beta1 Q_s

    dN follows Q_s (:func:`_normal_force`); Q_s is found by Newton's method within a
    bracket where the residual changes sign (|Q_s| <= mu_s N: one exists), halving it
    where Newton's step leaves it. Returns (Q_s, dN, iterations; -1: not converged)."""
    W = law[LAW_W]
    mus = law[LAW_MUS]
    dn = dn_guess
    # a bracket: |Q_s| <= mu_s N, N as large as the normal force there
    bound = mus * (W + abs(dn_guess)) * 1.01 + 1e-12 * W
    bracketed = False
    for _ in range(80):
        r_lo, _d, dn = _lateral_residual(-bound, dn, v_free, un_free, gvq, gvn, gnq, gnn, qd_free, beta1, law)
        r_hi, _d, dn = _lateral_residual(bound, dn, v_free, un_free, gvq, gvn, gnq, gnn, qd_free, beta1, law)
        if r_lo <= 0.0 <= r_hi:
            bracketed = True
            break
        bound *= 2.0
    if not bracketed:
        return qs_guess, dn_guess, -1
    lo = -bound
    hi = bound
    qs = min(max(qs_guess, lo), hi)
    dn = dn_guess
    for it in range(MAX_NEWTON):
        r, dr, dn = _lateral_residual(qs, dn, v_free, un_free, gvq, gvn, gnq, gnn, qd_free, beta1, law)
        step = -r / dr if dr != 0.0 else 0.0
        if abs(step) <= FORCE_TOLERANCE * W and dr != 0.0:
            return qs + step, dn, it + 1
        qs, lo, hi = _safeguarded(qs, step, r, lo, hi)
        if hi - lo <= FORCE_TOLERANCE * W:
            return qs, dn, it + 1
    return qs, dn, -1


def exp_integrate(
    s,
    phi,
    ga,
    gb,
    in_q,
    in_n,
    w,
    phase,
    out_td,
    out_tv,
    out_nd,
    c_wheel,
    law,
    lag,
    t0,
    q_d,
    q_s,
    d_n,
    h,
    n_steps,
    store_every,
    out,
    tail_every,
    tail_s,
    tail_t,
    tail_at,
    row0,
):
    """Advance the blocks ``s`` (n, 2) by ``n_steps`` steps of ``h`` [s] from time ``t0``
    with the contact forces at t0 (``q_d``: the lateral force the blocks feel, ``q_s``:
    its steady value, ``d_n``: N - W), in place (module docstring); ``lag`` = (alpha,
    beta0, beta1) of the creep force's lag over a step ((0, 0, 1): none). Every
    ``store_every``-th step writes a sample to ``out`` (rows from ``row0``), every
    ``tail_every``-th the states to the ring ``tail_s`` (its time to ``tail_t``) at
    ``tail_at``. ``c_wheel``: the blocks' viscous damping [N s/m] for the power into the
    wheel's modes (0 for the counter-body's).

    Returns (status: 0 ok, 1 non-finite, 2 the contact's forces not found; steps done;
    rows written; the ring's next position; q_d, q_s, d_n at the end; the most Newton
    iterations a step took)."""
    n = s.shape[0]
    alpha = lag[0]
    beta0 = lag[1]
    beta1 = lag[2]
    p0 = np.empty(n)
    p1 = np.empty(n)
    u0 = np.empty(n)
    free = np.empty((n, 2))
    row = row0
    status = 0
    worst = 0
    step = 0
    for i in range(n):
        p0[i] = math.cos(w[i] * t0 + phase[i])
    for step in range(1, n_steps + 1):
        t1 = t0 + step * h
        v_free = 0.0
        un_free = 0.0
        gvq = 0.0
        gvn = 0.0
        gnq = 0.0
        gnn = 0.0
        for i in range(n):
            p1[i] = math.cos(w[i] * t1 + phase[i])
            u0[i] = p0[i] * (in_q[i] * q_d + in_n[i] * d_n)
            a0 = phi[i, 0, 0] * s[i, 0] + phi[i, 0, 1] * s[i, 1] + (ga[i, 0] - gb[i, 0]) * u0[i]
            a1 = phi[i, 1, 0] * s[i, 0] + phi[i, 1, 1] * s[i, 1] + (ga[i, 1] - gb[i, 1]) * u0[i]
            free[i, 0] = a0
            free[i, 1] = a1
            v_free += p1[i] * (out_tv[i, 0] * a0 + out_tv[i, 1] * a1)
            un_free += p1[i] * (out_nd[i, 0] * a0 + out_nd[i, 1] * a1)
            tv = p1[i] * p1[i] * (out_tv[i, 0] * gb[i, 0] + out_tv[i, 1] * gb[i, 1])
            tn = p1[i] * p1[i] * (out_nd[i, 0] * gb[i, 0] + out_nd[i, 1] * gb[i, 1])
            gvq += tv * in_q[i]
            gvn += tv * in_n[i]
            gnq += tn * in_q[i]
            gnn += tn * in_n[i]
        qd_free = alpha * q_d + beta0 * q_s
        q_s, d_n, its = contact_forces(v_free, un_free, gvq, gvn, gnq, gnn, qd_free, beta1, q_s, d_n, law)
        if its < 0:
            status = 2
            break
        if its > worst:
            worst = its
        q_d = qd_free + beta1 * q_s
        y = 0.0
        v = 0.0
        un = 0.0
        vb = 0.0
        damp = 0.0
        energy = 0.0
        for i in range(n):
            u1 = p1[i] * (in_q[i] * q_d + in_n[i] * d_n)
            s[i, 0] = free[i, 0] + gb[i, 0] * u1
            s[i, 1] = free[i, 1] + gb[i, 1] * u1
            lat = p1[i] * (out_tv[i, 0] * s[i, 0] + out_tv[i, 1] * s[i, 1])
            y += p1[i] * (out_td[i, 0] * s[i, 0] + out_td[i, 1] * s[i, 1])
            v += lat
            un += p1[i] * (out_nd[i, 0] * s[i, 0] + out_nd[i, 1] * s[i, 1])
            if c_wheel[i] == 0.0 and in_q[i] < 0.0:
                vb -= lat  # the counter-body's own lateral velocity
            damp += c_wheel[i] * s[i, 1] * s[i, 1]
            energy += s[i, 0] * s[i, 0] + s[i, 1] * s[i, 1]
            p0[i] = p1[i]
        if not math.isfinite(energy):
            status = 1
            break
        if step % store_every == 0 and row < out.shape[0]:
            out[row, 0] = t1
            out[row, 1] = y
            out[row, 2] = v
            out[row, 3] = q_d
            out[row, 4] = law[LAW_W] + d_n
            out[row, 5] = un
            out[row, 6] = vb
            out[row, 7] = q_d * (v + vb) - damp
            row += 1
        if tail_s.shape[0] > 0 and step % tail_every == 0:
            for i in range(n):
                tail_s[tail_at, i, 0] = s[i, 0]
                tail_s[tail_at, i, 1] = s[i, 1]
            tail_t[tail_at] = t1
            tail_at += 1
            if tail_at == tail_s.shape[0]:
                tail_at = 0
    done = step if status == 0 else step - 1
    return status, done, row - row0, tail_at, q_d, q_s, d_n, worst
