"""Baseline of the simulate benchmark: the paper's Fig. 6 as a plain SciPy script.

The Table 1 mode (3.1 kg, 1.6e8 N/m, 42 N s/m) at 800 RPM and Vc = 0.39 m/s, from rest
for 0.6 s, integrated with solve_ivp (DOP853, rtol 1e-8: the accuracy the production
RK4 matches) on a right-hand side written in Python, sampled at 64 points per period,
and the velocity history drawn with pyplot, as a user without this tool would write it.
Usage: python fig6_solve_ivp.py OUT.png
"""

import math
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
from scipy.integrate import solve_ivp  # noqa: E402

m, k, c = 3.1, 1.6e8, 42.0
W, mu_s, V0, Vc = 1000.0, 0.3, 800 * 2 * math.pi / 60 * 0.213, 0.39
G, a, b, C22 = 175e9 / (2 * 1.28), 0.8534e-3, 0.5945e-3, 3.14  # Table 1 and its Hertz ellipse
K = G * a * b * C22 / (mu_s * W)


def mu(zeta: float) -> float:
    zp = abs(zeta) * K
    poly = zp - zp**2 / 3 + zp**3 / 27 if zp < 3 else 1.0
    s = abs(zeta) * V0
    falling = 1 - 0.5 * math.exp(-0.138 / s) - 0.5 * math.exp(-6.9 / s) if s > 0 else 1.0
    return math.copysign(mu_s * poly * falling, zeta)


def rhs(_t, x):
    y, v = x
    return [v, (-mu((Vc + v) / V0) * W - c * v - k * y) / m]


f0 = math.sqrt(k / m) / (2 * math.pi)
t = np.linspace(0.0, 0.6, int(0.6 * f0 * 64) + 1)
sol = solve_ivp(rhs, (0.0, 0.6), [0.0, 0.0], method="DOP853", t_eval=t, rtol=1e-8, atol=[1e-14, 1e-10])
v = sol.y[1]
fig, ax = plt.subplots(figsize=(7, 4))
ax.plot(sol.t, v, lw=0.4)
ax.set(xlabel="time (s)", ylabel="lateral vibration velocity y' (m/s)", title="Fig. 6")
fig.savefig(sys.argv[1] if len(sys.argv) > 1 else "fig6.png", dpi=110)
print(f"amplitude at 0.6 s: {0.5 * (v[-200:].max() - v[-200:].min()):.4f} m/s")
