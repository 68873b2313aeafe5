"""Which mode squeals: linear stability of every mode against its analytic limit and
against the time domain, multi-mode limit cycles, wheel rotation, mitigation, and the
``stability`` command.

The time-domain growth rates are fitted by the matrix-pencil method (poles of a sum of
damped sinusoids from uniform samples, no knowledge of the model) on runs started at
steady sliding with a 1e-8 m/s kick, so that the contact stays linear to about 1e-6:
an independent check of the eigenvalues of ``reduced.stability``.
"""

from __future__ import annotations

import json
import math
import warnings

import numpy as np
import pytest
from conftest import DESIGNS, run_cli

import reduced as r
import wheel_squeal as ws
from reduced.stability import friction_damping_ns_m, growth_rates
from wheel_squeal.decision import decide
from wheel_squeal.envelope import envelope, mitigation
from wheel_squeal.mode_stability import mode_dofs, named_mode, stability_table

TABLE1 = r.ModalDOF(3.1, 1.6e8, 42.0, nodal_diameters=3)
KICK_M_S = 1e-8


def _steady_force(law, op_fig6) -> float:
    return float(-r.adhesion_ratio(op_fig6.creepage, law, op_fig6.rolling_speed_m_s) * law.normal_load_n)


def _poles(t: np.ndarray, v: np.ndarray, order: int) -> np.ndarray:
    """The ``order`` poles (1/s) of v(t) by the matrix pencil, those with Im > 0."""
    rows = np.lib.stride_tricks.sliding_window_view(v, len(v) // 3 + 1)
    _, _, vh = np.linalg.svd(rows, full_matrices=False)
    basis = vh[:order].T
    z = np.linalg.eigvals(np.linalg.pinv(basis[:-1]) @ basis[1:])
    lam = np.log(z.astype(complex)) / (t[1] - t[0])
    return lam[lam.imag > 0]


def _kicked_run(modes, law, op_fig6, duration: float, wheel_speed: float = 0.0):
    """The contact velocity (t, v) of ``modes`` started at steady sliding plus a kick."""
    q0 = _steady_force(law, op_fig6)
    coords = r.model.coordinates(modes, wheel_speed)
    y0, u0 = np.zeros(len(coords.m)), np.full(len(coords.m), KICK_M_S)
    for i in range(len(coords.m)):
        w0 = math.sqrt(coords.k[i] / coords.m[i])
        zeta = coords.c[i] / (2 * math.sqrt(coords.k[i] * coords.m[i]))
        if coords.w[i] == 0.0:
            y0[i] = q0 / coords.k[i]
            continue
        # the forced travelling response p = a + i b to Q0 e^{-i n Omega t} (docs/theory.md, rotation)
        nw = coords.w[i]
        p = q0 / coords.m[i] / (w0**2 - nw**2 - 2j * zeta * w0 * nw)
        p_dot = -1j * nw * p
        first = coords.phase[i] == 0.0
        y0[i] = p.real if first else p.imag
        u0[i] += p_dot.real if first else p_dot.imag
    hist = r.simulate(modes, law, op_fig6, duration, (y0, u0), wheel_speed_rad_s=wheel_speed)
    f_top = max(md.frequency_hz for md in r.model.as_modes(modes)) + 100.0
    step = max(1, int(1.0 / (hist.t[1] * 4 * f_top)))  # 4 samples per period: no aliasing
    return hist.t[::step], hist.v[::step]


def _fitted_growth(modes, law, op_fig6, duration=0.4, wheel_speed=0.0) -> np.ndarray:
    t, v = _kicked_run(modes, law, op_fig6, duration, wheel_speed)
    n = len(r.model.coordinates(modes, wheel_speed).m)
    return _poles(t, v - v.mean(), 2 * n)


def _nearest(poles: np.ndarray, frequency_hz: float) -> complex:
    return poles[np.argmin(abs(poles.imag / (2 * math.pi) - frequency_hz))]


def _three_modes(f_pair: float = 1150.0):
    return [r.ModalDOF.from_frequency(m, f, 9.4e-4) for m, f in ((2.0, 300.0), (3.1, 1143.0), (2.6, f_pair))]


# --------------------------------------------------------------------------------------
# item 1: linear stability of every mode
# --------------------------------------------------------------------------------------
def test_single_mode_is_the_analytic_eigenvalue(law, op_fig6):
    g = friction_damping_ns_m(law, op_fig6)
    md = r.ModalDOF(3.1, 1.6e8, 42.0)
    s = r.linear_stability(md, law, op_fig6, bounds="all").modes[0]
    assert s.growth_rate_1_s == pytest.approx(-(md.damping_ns_m + g) / (2 * md.mass_kg), rel=1e-12)
    assert s.growth_rate_1_s == pytest.approx(8.63, abs=0.01)  # Table 1 at the Fig. 6 point
    assert s.critical_damping_ratio == pytest.approx(
        -g / (2 * math.sqrt(md.mass_kg * md.stiffness_n_m)), rel=1e-8
    )
    assert s.critical_friction_slope == pytest.approx(
        -md.damping_ns_m * op_fig6.rolling_speed_m_s / law.normal_load_n, rel=1e-8
    )
    assert r.largest_growth_rate(md, law, op_fig6) == pytest.approx(s.growth_rate_1_s, rel=1e-12)


def test_separated_modes_tend_to_the_single_mode_limit(law, op_fig6):
    """Far apart in frequency and weakly coupled (g / (m w) = 5e-5: heavy modes), each
    mode's growth is -(c_i + g) / (2 m_i) to 1e-6 of the friction term g / (2 m_i); at
    Table 1's masses the coupling (g / (m w) = 5e-3) moves it by about the square of
    that, 3e-5, no more."""
    g = friction_damping_ns_m(law, op_fig6)
    for mass, tol in ((300.0, 1e-6), (2.5, 1e-4)):
        modes = [r.ModalDOF.from_frequency(mass, f, 9.4e-4) for f in (300.0, 1143.0, 3000.0)]
        got = r.linear_stability(modes, law, op_fig6, bounds="all")
        for md, s in zip(modes, got.modes):
            limit = -(md.damping_ns_m + g) / (2 * md.mass_kg)
            assert s.growth_rate_1_s == pytest.approx(limit, rel=0, abs=tol * abs(g) / (2 * md.mass_kg))
            assert s.critical_damping_ratio == pytest.approx(
                -g / (2 * math.sqrt(md.mass_kg * md.stiffness_n_m)), rel=tol
            )


def test_close_pair_differs_from_the_separated_limit(law, op_fig6):
    g = friction_damping_ns_m(law, op_fig6)
    modes = _three_modes(1150.0)
    got = r.linear_stability(modes, law, op_fig6).modes
    limit = [-(md.damping_ns_m + g) / (2 * md.mass_kg) for md in modes]
    assert got[0].growth_rate_1_s == pytest.approx(limit[0], rel=1e-3)  # 300 Hz: apart
    for i in (1, 2):  # 7 Hz apart: the contact couples them by several per cent
        assert abs(got[i].growth_rate_1_s / limit[i] - 1) > 0.04
    # closer still, one of the pair's eigenvalues is stabilised and the other takes both
    # modes' shares: it grows for both (the growing eigenvalue a mode takes part in
    # speaks for it)
    closer = r.linear_stability(_three_modes(1148.0), law, op_fig6)
    pair = sorted(closer.eigenvalues[np.abs(closer.eigenvalues.imag / (2 * math.pi) - 1148.0) < 10].real)
    assert len(pair) == 2 and pair[0] < 0.5 * limit[1] and pair[1] > 1.4 * limit[2]
    assert closer.modes[1].growth_rate_1_s == closer.modes[2].growth_rate_1_s == pair[1]


@pytest.mark.parametrize("f_pair", [1150.0, 1160.0])
def test_growth_rates_match_a_time_domain_fit(law, op_fig6, f_pair):
    """Three modes, two of them close: the eigenvalues against the poles fitted to the
    contact velocity of the time-domain model, within 3 % (measured: 1e-4)."""
    modes = _three_modes(f_pair)
    res = r.linear_stability(modes, law, op_fig6)
    poles = _fitted_growth(modes, law, op_fig6)
    for s in res.modes:
        fitted = _nearest(poles, s.damped_frequency_hz)
        assert fitted.real == pytest.approx(s.growth_rate_1_s, rel=0.03)
        assert fitted.imag / (2 * math.pi) == pytest.approx(s.damped_frequency_hz, rel=1e-4)


@pytest.mark.parametrize("which", [0, pytest.param(1, marks=pytest.mark.slow)])
def test_critical_damping_is_where_the_time_domain_growth_changes_sign(law, op_fig6, which):
    """Bisection on the mode's damping ratio with the time domain alone: the growth of
    its pole changes sign within 2 % of the computed zeta_crit (a separated mode and
    one of the close pair)."""
    modes = _three_modes(1160.0)
    s = r.linear_stability(modes, law, op_fig6, bounds=[which]).modes[which]

    def growth(zeta: float) -> float:
        trial = list(modes)
        trial[which] = modes[which].with_damping_ratio(zeta)
        return _nearest(_fitted_growth(trial, law, op_fig6, duration=0.3), s.damped_frequency_hz).real

    lo, hi = 0.5 * s.critical_damping_ratio, 1.5 * s.critical_damping_ratio
    assert growth(lo) > 0 > growth(hi)
    while hi - lo > 0.005 * s.critical_damping_ratio:
        mid = 0.5 * (lo + hi)
        lo, hi = (mid, hi) if growth(mid) > 0 else (lo, mid)
    assert 0.5 * (lo + hi) == pytest.approx(s.critical_damping_ratio, rel=0.02)


def test_critical_friction_slope_stabilises(law, op_fig6):
    modes = _three_modes(1160.0)
    res = r.linear_stability(modes, law, op_fig6, bounds="all")
    scale = law.normal_load_n / op_fig6.rolling_speed_m_s
    damping = [md.damping_ns_m for md in modes]
    for i, s in enumerate(res.modes):
        assert s.critical_friction_slope < 0  # falling friction below it grows
        assert growth_rates(modes, damping, scale * s.critical_friction_slope * 1.02, 0.0)[i] > 0
        assert growth_rates(modes, damping, scale * s.critical_friction_slope * 0.98, 0.0)[i] < 0


# --------------------------------------------------------------------------------------
# item 2: several modes in the time domain
# --------------------------------------------------------------------------------------
def test_one_mode_in_the_n_mode_kernel_is_the_1dof_run(law, op_fig6):
    """The N-mode kernel with one coordinate gives the scalar kernel's numbers exactly."""
    from reduced import _engine
    from reduced.model import law_vector

    _kernels = _engine.compiled()
    md = r.ModalDOF(3.1, 1.6e8, 42.0)
    h, n = 1.0 / (48 * md.frequency_hz), 20000
    one_y, one_u = np.empty((n + 1, 1)), np.empty((n + 1, 1))
    many_y, many_u = np.empty((n + 1, 1)), np.empty((n + 1, 1))
    lv = law_vector(law, op_fig6)
    _kernels.integrate_store_1(0.0, 0.0, 3.1, 42.0, 1.6e8, lv, h, n, 1, one_y[:, 0], one_u[:, 0])
    z, one = np.zeros(1), np.ones(1)
    _kernels.integrate_store(
        z,
        z.copy(),
        3.1 * one,
        42.0 * one,
        1.6e8 * one,
        one,
        z,
        z,
        z,
        lv,
        h,
        n,
        1,
        many_y,
        many_u,
        np.empty(n + 1),
    )
    np.testing.assert_array_equal(one_y, many_y)
    np.testing.assert_array_equal(one_u, many_u)


@pytest.fixture(scope="module")
def table1_fe():
    design = ws.load_design()
    ms = ws.compute_modes(design, "fast")
    return design, ms, ws.contact_law(design), ws.operating_point(design)


def test_the_model_with_one_mode_is_that_mode_run_alone(table1_fe):
    """At most one mode together: the model's outcome is the fastest-growing mode's run,
    bit for bit the one ``simulate`` gives it."""
    design, ms, contact, op = table1_fe
    free = design.replace(squeal_mode="")
    a = ws.analyse(free, op=op, modes=ms, max_modes=1, stop_after="limit_cycle", remedy=False)
    rows = a.rows
    fastest = rows[a.stability.winner].mode
    alone = ws.simulate(ws.modal_dof(fastest, design), contact, op)
    assert a.verdict.pick.group == (fastest,) and a.verdict.pick.shares is None
    np.testing.assert_array_equal(a.verdict.pick.simulation.history.v, alone.history.v)
    assert a.verdict.pick.simulation.summary() == alone.summary()


def test_the_modes_that_grow_together_give_the_limit_cycle_to_the_fastest(table1_fe):
    """Every unstable FE mode of designs/table1.toml at the Fig. 6 point, from rest: the
    fastest-growing mode, (1,0) at 261 Hz, takes the limit cycle (winner takes all: it
    saturates the contact first, and the falling friction it leaves behind no longer
    feeds the others)."""
    design, ms, contact, op = table1_fe
    a = ws.analyse(design.replace(squeal_mode=""), op=op, modes=ms, stop_after="limit_cycle", remedy=False)
    unstable = [row for row in a.rows if row.stability.unstable]
    assert len(unstable) >= 4
    pick = a.verdict.pick
    assert len(pick.group) == len(unstable) and a.verdict.outcome is pick
    assert pick.label == "(1,0) axial" == a.decision.fastest.label()
    assert pick.energy_share > 0.95 and sum(pick.shares.values()) == pytest.approx(1.0)
    assert pick.tone_hz == pytest.approx(pick.mode.frequency_hz, rel=0.005)
    assert pick.saturated


def test_the_decision_takes_the_named_mode_else_the_model(table1_fe):
    design, ms, contact, op = table1_fe
    table = stability_table(design, ms, contact, op)
    d = decide(table, named_mode(design, ms))
    assert d.named.label() == "(3,0) axial" and "names" in d.named_by and d.named_group[0] == d.named
    free = decide(table, named_mode(design.replace(squeal_mode=""), ms))
    growth = {row.mode.index: row.stability.growth_rate_1_s for row in table.rows}
    assert free.named is None and free.fastest.index == max(growth, key=growth.get)
    assert {m.index for m in free.growing} == {i for i, g in growth.items() if g > 0}
    assert decide(table, named_mode(design, ms, "n=2")).named.label() == "(2,0) axial"


def test_measured_damping_moves_the_winner(table1_fe):
    """The paper's rig squealed in (3,0): with the damping the stability table says the
    lower modes need, (3,0) is the only unstable mode left."""
    design, ms, contact, op = table1_fe
    rows, _ = stability_table(design, ms, contact, op, bounds="all")
    damping = tuple(
        (
            f"n={row.mode.nodal_diameters},c={row.mode.nodal_circles}",
            1.05 * row.stability.critical_damping_ratio,
        )
        for row in rows
        if row.stability.unstable and row.mode.label() != "(3,0) axial"
    )
    damped = design.replace(squeal_mode="", mode_damping=damping)
    rows2, res2 = stability_table(damped, ms, contact, op)
    assert [row.mode.label() for row in rows2 if row.stability.unstable] == ["(3,0) axial"]
    assert rows2[res2.winner].mode.label() == "(3,0) axial"


# --------------------------------------------------------------------------------------
# the eigenvectors from the contact's low-rank coupling
# --------------------------------------------------------------------------------------
def _rail_like(repeated: bool) -> r.BodyModel:
    """A fitted-receptance-like counter-body: pairs along both directions and first-order
    terms, the normal ones twice at one pole with ``repeated`` (as relocation can leave)."""
    firsts = [
        (r.NORMAL, -40.0, 2e-9),
        (r.NORMAL, -40.0 if repeated else -70.0, 3e-9),
        (r.LATERAL, -25.0, 4e-9),
    ]
    pairs = [(r.NORMAL, 2 * math.pi * (-30 + 900j)), (r.LATERAL, 2 * math.pi * (-50 + 400j))]
    terms = []
    for d, pole in pairs:
        lead = -sum(res for dd, _, res in firsts if dd == d)  # no feedthrough: the leads sum to 0
        terms.append((d, [pole], [lead / 2 + 1e-9j]))
    terms += [(d, [complex(p)], [complex(res)]) for d, p, res in firsts]
    return r.BodyModel.from_rational(terms, "a rail-like body")


@pytest.mark.parametrize(
    "omega, tau, repeated",
    [(0.0, 0.0, False), (60.0, 2e-4, False), (0.0, 0.0, True)],
    ids=["rail-like", "rotation-and-lag", "repeated-pole"],
)
def test_the_eigenvectors_from_the_low_rank_coupling_are_lapack_s(omega, tau, repeated):
    from reduced import stability as s

    modes = [
        r.ModalDOF(
            3.1, 3.1 * (2 * math.pi * f) ** 2, 2.0 + f / 100, nodal_diameters=n, lateral=1.0, normal=nr
        )
        for f, n, nr in (
            (420.0, 2, 0.3),
            (1100.0, 0, 0.8),
            (1135.0, 3, -0.4),
            (2500.0, 4, 0.1),
            (3900.0, 0, 1.2),
        )
    ]
    damping = np.array([md.damping_ns_m for md in modes])
    linear = s.LinearContact(-60.0, 0.35, 8e8, tau)
    layout = s._blocks(modes, omega, _rail_like(repeated))
    with warnings.catch_warnings():
        warnings.simplefilter("error")  # an exactly singular shift is the method's, not the user's
        lam, vec = s._eigen_vectors(modes, damping, linear, omega, layout, low_rank=True)  # small: forced
    A = s._state_matrix(modes, damping, linear, omega, layout)
    ref_lam, ref_vec = np.linalg.eig(A)
    # the kept eigenvalues: LAPACK's with Im >= 0 less the lag's own (one more with the lag)
    assert len(lam) == int(np.sum(ref_lam.imag >= 0.0)) - (tau > 0)
    for j, x in enumerate(lam):
        k = int(np.argmin(np.abs(ref_lam - x)))
        # eigvals and eig take different paths through LAPACK: 1e-9 of the largest eigenvalue
        assert abs(ref_lam[k] - x) <= 1e-9 * np.max(np.abs(ref_lam))
        y = ref_vec[:, k]
        cosine = abs(np.vdot(vec[:, j], y)) / (np.linalg.norm(vec[:, j]) * np.linalg.norm(y))
        # parallel to LAPACK's to its own accuracy (simple eigenvalues: one direction each)
        assert cosine > 1 - 1e-8, (j, x, cosine)
    A0, U, V = s._state_parts(modes, damping, linear, omega, layout)
    secular = s._secular_vectors(A0, U, V, lam, s._state_blocks(layout, tau > 0))
    missed = s._backward_errors(A, secular, lam) > s.SECULAR_BACKWARD_ERROR
    # a repeated pole leaves an eigenvalue the contact does not move: inverse iteration's
    assert np.any(missed) == repeated


def test_a_rail_s_normal_terms_under_a_constant_normal_load_leave_the_vectors_to_lapack():
    """With no Hertz spring (k_H = 0: a constant normal load) no force reaches the rail's
    normal terms and they move none: each is an eigenvalue of its own that the low rank
    cannot give (10 inverse iterations on a line's contact, 5x LAPACK's time), so LAPACK's
    vectors are taken; with the spring every block is coupled and the low rank serves."""
    from reduced import stability as s

    modes = [r.ModalDOF(3.1, 3.1 * (2 * math.pi * f) ** 2, 5.0, normal=0.5) for f in (400.0, 1200.0)]
    damping = np.array([md.damping_ns_m for md in modes])
    layout = s._blocks(modes, 0.0, _rail_like(False))
    blocks = s._state_blocks(layout, False)
    for k_h, apart in ((0.0, True), (8e8, False)):
        _, U, V = s._state_parts(modes, damping, s.LinearContact(-60.0, 0.35, k_h), 0.0, layout)
        acting = np.any(U != 0.0, axis=0) & np.any(V != 0.0, axis=0)
        assert s._apart(U[:, acting], V[:, acting], blocks) == apart


@pytest.mark.parametrize("low_rank", [False, True], ids=["lapack", "low-rank"])
def test_a_point_where_nothing_grows_is_said_by_its_eigenvalues_alone(law, op_fig6, monkeypatch, low_rank):
    """Asked for no stable modes, the linear stability of a point where no eigenvalue
    grows is its eigenvalues alone (no rows: one LAPACK solve without vectors), the same
    eigenvalues as the whole solve's; where one grows, it is the whole solve, bit for bit
    (the eigenvalues it found reused by the low-rank vectors, or LAPACK's taken again)."""
    from reduced import stability as s

    monkeypatch.setattr(s, "LOW_RANK_STATES", 0 if low_rank else 10_000)
    modes = [
        r.ModalDOF(3.1, 3.1 * (2 * math.pi * f) ** 2, 4.0, lateral=1.0, normal=0.4) for f in (420.0, 1143.0)
    ]
    body = _rail_like(False)
    quiet = r.OperatingPoint(op_fig6.rolling_speed_m_s, 0.02)  # on the creep curve's rising side
    full = r.linear_stability(modes, law, quiet, body=body)
    lean = r.linear_stability(modes, law, quiet, body=body, stable_modes=False)
    assert max(m.growth_rate_1_s for m in full.modes) < 0.0
    assert lean.modes == () and lean.shares is None
    assert np.array_equal(np.sort_complex(lean.eigenvalues), np.sort_complex(full.eigenvalues))
    assert lean.growth_rate_1_s == pytest.approx(float(full.eigenvalues.real.max()), abs=0.0)
    grows = r.linear_stability(modes, law, op_fig6, body=body)
    assert grows.growth_rate_1_s > 0.0
    again = r.linear_stability(modes, law, op_fig6, body=body, stable_modes=False)
    assert again.modes == grows.modes and again.mechanisms == grows.mechanisms
    assert np.array_equal(again.eigenvalues, grows.eigenvalues) and np.array_equal(again.shares, grows.shares)


@pytest.mark.parametrize("omega, tau", [(0.0, 0.0), (60.0, 2e-4)], ids=["steady", "rotation-and-lag"])
@pytest.mark.parametrize("g", [0.0, -60.0], ids=["mode-coupling-limit", "whole"])
def test_blocks_that_feed_no_force_are_solved_apart_to_the_same_eigenvalues(omega, tau, g):
    """The eigenvalues of A0 + U V^T with the blocks that feed no force or take none solved
    apart (A block triangular: without the friction damping the rail-like body's lateral
    terms take a force and feed none) are LAPACK's of the whole matrix, to 1e-9 of the
    largest (two paths through LAPACK), each once."""
    from reduced import stability as s

    modes = [
        r.ModalDOF(3.1, 3.1 * (2 * math.pi * f) ** 2, 3.0, nodal_diameters=n, lateral=1.0, normal=nr)
        for f, n, nr in ((420.0, 2, 0.3), (1100.0, 0, 0.0), (2500.0, 3, 0.7))
    ]
    damping = np.array([md.damping_ns_m for md in modes])
    layout = s._blocks(modes, omega, _rail_like(False))
    A0, U, V = s._state_parts(modes, damping, s.LinearContact(g, 0.35, 8e8, tau), omega, layout)
    blocks = s._state_blocks(layout, tau > 0)
    feeds, takes = np.any(V != 0.0, axis=1), np.any(U != 0.0, axis=1)
    apart = sum(int(np.sum(~(np.any(feeds[b], axis=1) & np.any(takes[b], axis=1)))) for b in blocks)
    assert (apart > 0) == (g == 0.0)  # the limit's lateral terms (and the mode with no normal part)
    lam = s._triangular_eigenvalues(A0, U, V, blocks, tau)
    ref = s._eigen(A0 + U @ V.T, tau, vectors=False)[0]
    assert len(lam) == len(ref)
    scale = np.max(np.abs(ref))
    distance = np.abs(lam[:, None] - ref[None, :])
    assert np.max(distance.min(axis=1)) <= 1e-9 * scale and np.max(distance.min(axis=0)) <= 1e-9 * scale


def test_one_blas_thread_sets_each_library_to_one_and_back():
    """The model's dense eigen-solves run on one BLAS thread, each library set back after."""
    from reduced._numerics import _blas_pools, one_blas_thread

    pools = _blas_pools()
    assert pools, "numpy's BLAS is found"
    before = [c.num_threads for c in pools]
    with one_blas_thread():
        assert [c.num_threads for c in pools] == [1] * len(pools)
    assert [c.num_threads for c in pools] == before


# --------------------------------------------------------------------------------------
# item 4: wheel rotation
# --------------------------------------------------------------------------------------
def test_rotation_to_zero_is_the_paper_model(law, op_fig6):
    still = r.simulate(TABLE1, law, op_fig6, 0.3)
    exact_zero = r.simulate(TABLE1, law, op_fig6, 0.3, wheel_speed_rad_s=0.0)
    np.testing.assert_array_equal(still.v, exact_zero.v)
    slow = r.simulate(TABLE1, law, op_fig6, 0.3, wheel_speed_rad_s=1e-4)  # n Omega t <= 1e-4
    assert np.max(abs(slow.v - still.v)) < 1e-3 * np.max(abs(still.v))
    assert r.linear_stability(TABLE1, law, op_fig6, 1e-6).growth_rate_1_s == pytest.approx(
        r.linear_stability(TABLE1, law, op_fig6).growth_rate_1_s, rel=1e-4
    )


def test_rotating_growth_has_half_the_destabilising_term(law, op_fig6):
    """sigma = -zeta w0 - W mu' / (4 m V0) when n Omega >> sigma: each travelling wave
    carries twice the modal mass; the time-domain fit agrees within 5 % (Table 1's
    damping, where the halving leaves 0.93 1/s of 8.6, and without damping)."""
    omega = op_fig6.rolling_speed_m_s / 0.213
    g = friction_damping_ns_m(law, op_fig6)
    for md in (TABLE1, r.ModalDOF(3.1, 1.6e8, 0.0, nodal_diameters=3)):
        zeta, w0 = md.damping_ratio, md.angular_frequency_rad_s
        halved = -zeta * w0 - g / (4 * md.mass_kg)
        assert r.linear_stability(md, law, op_fig6, omega).growth_rate_1_s == pytest.approx(halved, rel=0.01)
        poles = _fitted_growth(md, law, op_fig6, duration=0.6, wheel_speed=omega)
        shift = 3 * omega / (2 * math.pi)
        for f in (md.frequency_hz - shift, md.frequency_hz + shift):  # both waves
            assert _nearest(poles, f).real == pytest.approx(halved, rel=0.05)
        assert halved < 0.6 * -(md.damping_ns_m + g) / (2 * md.mass_kg)  # not the still wheel's


def test_rotating_limit_cycle_tone(law, op_fig6):
    """A microphone at the contact hears the backward wave, f0 - n Omega / 2 pi, from
    rest: the constant contact force excites it more ((w0 + n Omega) / (w0 - n Omega)
    times the forward wave) and both grow alike, so it saturates the contact first.
    Started in the forward wave the run stays there, at f0 + n Omega / 2 pi."""
    md = r.ModalDOF(3.1, 1.6e8, 0.0, nodal_diameters=3)  # undamped: saturates in 1 s
    omega = op_fig6.rolling_speed_m_s / 0.213
    shift = 3 * omega / (2 * math.pi)
    hist, lc = r.simulate_to_limit_cycle(md, law, op_fig6, wheel_speed_rad_s=omega)
    assert lc.saturated
    content = r.modal_content(hist)
    assert content.peak_frequency_hz == pytest.approx(md.frequency_hz - shift, rel=0.005)
    assert lc.frequency_hz == pytest.approx(md.frequency_hz - shift, rel=0.005)
    forward = r.simulate(md, law, op_fig6, 1.5, ((0.0, 0.0), (0.0, 0.05)), wheel_speed_rad_s=omega)
    assert r.modal_content(forward).peak_frequency_hz == pytest.approx(md.frequency_hz + shift, rel=0.005)


# --------------------------------------------------------------------------------------
# item 5: mitigation over the envelope
# --------------------------------------------------------------------------------------
@pytest.mark.parametrize("rotation", [False, pytest.param(True, marks=pytest.mark.slow)])
def test_mitigation_damping_and_friction_slope_stop_squeal_everywhere(table1_fe, rotation):
    design, ms, contact, _ = table1_fe
    vcs, rpms = np.linspace(0.0, 0.6, 13), [400.0, 600.0, 800.0]
    mit = mitigation(design, ms, contact, vcs, rpms, rotation)
    assert envelope(design, ms, contact, vcs, rpms, rotation).growth_rate_1_s.max() > 0  # squeals now
    # a measured-damping key names (n, c): where an axial and an in-plane mode share one,
    # it must give the larger of their bounds
    zeta: dict[str, float] = {}
    for m, z in zip(mit.modes, mit.result.damping_ratio):
        key = f"n={m.nodal_diameters},c={m.nodal_circles}"
        zeta[key] = max(zeta.get(key, 0.0), float(z))
    damped = design.replace(mode_damping=tuple(zeta.items()))
    env = envelope(damped, ms, contact, vcs, rpms, rotation)
    assert env.growth_rate_1_s.max() <= 1e-6
    # each bound is tight: 3 % less damping on the (1,0) mode and it grows somewhere
    key = next(k for k, m in zip(zeta, mit.modes) if m.label() == "(1,0) axial")
    less = damped.replace(mode_damping=tuple({**zeta, key: 0.97 * zeta[key]}.items()))
    assert envelope(less, ms, contact, vcs, rpms, rotation).growth_rate_1_s.max() > 0
    # the friction slope: no mode grows at the required slope, one does 3 % steeper
    dofs = mode_dofs(mit.modes, design)
    for factor, grows in ((0.97, False), (1.03, True)):
        worst = -math.inf
        for rpm in rpms:
            v0 = ws.presets.rpm_to_speed(rpm, design.wheel.rolling_radius)
            g = contact.normal_load_n / v0 * factor * mit.result.friction_slope
            omega = v0 / design.wheel.rolling_radius if rotation else 0.0
            worst = max(worst, growth_rates(dofs, [d.damping_ns_m for d in dofs], g, omega).max())
        assert (worst > 0) == grows


# --------------------------------------------------------------------------------------
# item 6: the command
# --------------------------------------------------------------------------------------
@pytest.mark.slow
def test_stability_command(tmp_path):
    out = tmp_path / "st"
    r_ = run_cli(
        *"stability --fidelity fast --envelope --envelope-crab-velocity 0:0.6:7".split(),
        *("--out", str(out), "--cache-dir", str(tmp_path / "cache")),
    )
    assert r_.returncode == 0, r_.stderr
    s = json.loads((out / "summary.json").read_text())
    modes = s["modes"]
    assert set(
        "index frequency_hz modal_mass_kg growth_rate_1_s critical_damping_ratio unstable".split()
    ) <= set(modes[0])
    assert s["winner"] == max(modes, key=lambda m: m["growth_rate_1_s"])
    assert all(m["unstable"] == (m["growth_rate_1_s"] > 0) for m in modes)
    assert s["operating_point"]["rpm"] == pytest.approx(800.0)
    csv = (out / "stability.csv").read_text().splitlines()
    assert len(csv) == 1 + 7 * 3 and csv[0].startswith("crabbing_velocity_m_s,rpm,growth_rate_1_s")
    assert (out / "stability.png").stat().st_size > 10_000
    assert {"rotation_off", "rotation_on"} <= set(s["mitigation"])
    assert "<- leads" in r_.stdout and "zeta needed" in r_.stdout


@pytest.mark.slow
def test_run_with_rotation_and_multimode_reports_both(tmp_path):
    out = tmp_path / "run"
    r_ = run_cli(
        *("run", "--design", str(DESIGNS / "thin_web.toml")),
        *"--fidelity fast --rotation --multimode 3 --render none".split(),
        *("--out", str(out), "--cache-dir", str(tmp_path / "c")),
    )
    assert r_.returncode == 0, r_.stderr
    s = json.loads((out / "summary.json").read_text())
    assert s["rotation"] is True and len(s["decision"]["growing_modes"]) <= 3
    assert s["winner"] == max(s["stability"], key=lambda m: m["growth_rate_1_s"])
    assert s["verdict"]["mode"] in s["decision"]["growing_modes"]  # thin_web names no mode
    assert "grow together" in r_.stdout
