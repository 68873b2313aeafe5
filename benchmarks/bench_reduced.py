"""Benchmark of the reduced squeal model (run: .venv/bin/python benchmarks/bench_reduced.py).

Prints, in one run:
* numba compile/cache-load time of the kernels (first calls), reported separately;
* the Fig. 6 case (m 3.1 kg, c 42 N s/m, k 1.6e8 N/m, mu 0.3, 800 RPM, Vc 0.39 m/s,
  0.6 s from rest): median seconds with solve_ivp (DOP853, rtol 1e-8) and with the
  production path (numba RK4), their ratio and the limit-cycle amplitude difference;
* the same case with a pure-numpy RK4 (no numba) to show whether numba earns its place;
* a 50 x 3 sweep (Vc 0..0.5 m/s x 400/600/800 RPM, 0.6 s each): median seconds,
  the numpy-vectorised RK4 over the 150 cases for comparison, and the max error of
  the harmonic-balance predictor where the time domain saturates (1.6 s runs).
"""

from __future__ import annotations

import math
import statistics
import sys
import time
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))

import numpy as np  # noqa: E402


def rk4_numpy_batch(m, c, k, laws, h, n_steps):
    """The non-compiled baseline: pure-numpy RK4, vectorised over cases (rows of
    ``laws``, as ``reduced.model.law_vector`` packs them), one mode per case, from rest.
    Written here, independently of the package's kernels. Returns the contact velocity
    history (n_steps+1, n_cases)."""
    W, mus, K, s1, s2, V0, Vc = (laws[:, i] for i in range(7))

    def force(v):
        zeta = (Vc + v) / V0
        a = np.abs(zeta)
        zp = a * K
        poly = np.where(zp < 3.0, zp * (1.0 - zp / 3.0 + zp * zp / 27.0), 1.0)
        s = a * V0
        inv = np.divide(1.0, s, out=np.full_like(s, np.inf), where=s > 0)
        f = 1.0 - 0.5 * np.exp(-s1 * inv) - 0.5 * np.exp(-s2 * inv)
        return -np.sign(zeta) * mus * poly * f * W

    def rhs(y, u):
        return u, (force(u) - c * u - k * y) / m

    y = np.zeros(laws.shape[0])
    u = np.zeros(laws.shape[0])
    out = np.empty((n_steps + 1, laws.shape[0]))
    out[0] = u
    for j in range(1, n_steps + 1):
        a1, b1 = rhs(y, u)
        a2, b2 = rhs(y + 0.5 * h * a1, u + 0.5 * h * b1)
        a3, b3 = rhs(y + 0.5 * h * a2, u + 0.5 * h * b2)
        a4, b4 = rhs(y + h * a3, u + h * b3)
        y = y + h / 6.0 * (a1 + 2 * a2 + 2 * a3 + a4)
        u = u + h / 6.0 * (b1 + 2 * b2 + 2 * b3 + b4)
        out[j] = u
    return out


def median_time(fn, repeat: int) -> tuple[float, object]:
    times, out = [], None
    for _ in range(repeat):
        t0 = time.perf_counter()
        out = fn()
        times.append(time.perf_counter() - t0)
    return statistics.median(times), out


def main() -> None:
    t0 = time.perf_counter()
    import reduced as r
    from reduced.model import choose_time_step, law_vector

    t_import = time.perf_counter() - t0

    law = r.ContactLaw.from_hertz(r.hertz_contact(0.213, 0.300, 0.085, 0.040, 175e9, 0.28, 1000.0), 0.3)
    mode = r.ModalDOF(3.1, 1.6e8, 42.0)
    op = r.OperatingPoint.from_rpm(800, 0.213, 0.39)
    speeds = np.array([400.0, 600.0, 800.0]) * 2 * math.pi / 60 * 0.213
    vcs = np.linspace(0.0, 0.5, 50)

    t0 = time.perf_counter()
    r.simulate(mode, law, op, 0.01)
    r.limit_cycle(r.simulate(mode, law, op, 0.01))
    t_first_sim = time.perf_counter() - t0
    t0 = time.perf_counter()
    r.sweep(mode, law, [0.39], [speeds[2]], 0.01)
    t_first_sweep = time.perf_counter() - t0
    print(
        f"import reduced: {t_import:.2f} s; first simulate+limit_cycle (numba compile or cache load): "
        f"{t_first_sim:.2f} s; first sweep (parallel kernel): {t_first_sweep:.2f} s"
    )

    t_ref, ref = median_time(lambda: r.simulate_reference(mode, law, op, 0.6, method="DOP853", rtol=1e-8), 3)
    t_prod, prod = median_time(lambda: r.simulate(mode, law, op, 0.6), 15)
    a_ref = r.limit_cycle(ref).velocity_amplitude_m_s
    a_prod = r.limit_cycle(prod).velocity_amplitude_m_s
    print(
        f"Fig. 6 case, 0.6 s simulated: solve_ivp DOP853 rtol 1e-8: {t_ref:.3f} s (median of 3); "
        f"production numba RK4 (48 steps/period, incl. Q, P post-processing): {t_prod * 1e3:.1f} ms "
        "(median of 15)"
    )
    print(
        f"  speed-up: {t_ref / t_prod:.0f}x; amplitude ref {a_ref:.6f} m/s, production {a_prod:.6f} m/s, "
        f"difference {abs(a_prod / a_ref - 1) * 100:.4f} %"
    )

    # pure-numpy RK4 (same step, same scheme) for the single case and for the whole grid
    h = choose_time_step(mode, law, op)
    n = int(math.ceil(0.6 / h))
    one = law_vector(law, op)[None, :]
    t_np1, v_np = median_time(lambda: rk4_numpy_batch(3.1, 42.0, 1.6e8, one, 0.6 / n, n), 1)
    tail = v_np[int(0.9 * n) :, 0]
    print(
        f"  numpy RK4 (no numba), same case: {t_np1:.2f} s ({t_np1 / t_prod:.0f}x slower than numba), "
        f"amplitude {0.5 * (tail.max() - tail.min()):.6f} m/s (raw samples)"
    )

    t_sweep, res = median_time(lambda: r.sweep(mode, law, vcs, speeds, 0.6), 5)
    print(
        f"sweep 50 x 3 (Vc x speed), 0.6 s each, numba prange: {t_sweep:.2f} s (median of 5); "
        f"{int(res.squeal.sum())} of 150 cases squeal"
    )
    laws = np.array([law_vector(law, r.OperatingPoint(v0, vc)) for vc in vcs for v0 in speeds])
    t_np, _ = median_time(lambda: rk4_numpy_batch(3.1, 42.0, 1.6e8, laws, 0.6 / n, n), 1)
    print(f"  numpy RK4 vectorised over the 150 cases (no cycle reduction): {t_np:.2f} s")

    long = r.sweep(mode, law, vcs, speeds, 1.6)
    errs = []
    for i, vc in enumerate(vcs):
        for j, v0 in enumerate(speeds):
            if long.saturated[i, j]:
                p = r.predict_limit_cycle(mode, law, r.OperatingPoint(v0, vc))
                errs.append(abs(p.velocity_amplitude_m_s / long.velocity_amplitude_m_s[i, j] - 1))
    t_pred, _ = median_time(lambda: r.predict_limit_cycle(mode, law, op), 5)
    print(
        f"predictor vs time domain (1.6 s runs) over {len(errs)} saturated cases of 150: "
        f"max error {max(errs) * 100:.3f} %, {t_pred * 1e3:.1f} ms per prediction"
    )
    h1 = r.hertz_contact(0.213, 0.300, 0.085, 0.040, 175e9, 0.28, 1000.0)
    print(
        f"Hertz: a = {h1.semi_axis_a_m * 1e3:.4f} mm (Table 1: 0.853), b = {h1.semi_axis_b_m * 1e3:.4f} mm "
        f"(0.594), a/b = {h1.a_over_b:.3f}; Kalker C22(a/b, nu 0.28) = {r.kalker_c22(h1.a_over_b, 0.28):.3f} "
        f"(paper uses 3.14); saturation creepage {law.saturation_creepage:.5f}"
    )


if __name__ == "__main__":
    main()
