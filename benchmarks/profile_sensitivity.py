"""How the rig wheel's squeal mode moves with its cross-section: hub, taper, conical
web, fillets, a curved web; Table 1 as the reference.

For each variant: the mass, the (3,0) axial frequency and contact modal mass, and the
lowest (1,0) axial one, at the accurate preset (axisymmetric P2, converged to about
0.01 %, tests/test_outline.py). Prints a Markdown table (the README's "Any wheel"
section).

    .venv/bin/python benchmarks/profile_sensitivity.py
"""

from __future__ import annotations

import sys
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))

import wheel_squeal as ws  # noqa: E402
from geometry import wheel_mass  # noqa: E402


def variants() -> list[tuple[str, object]]:
    t1 = ws.load_design(ROOT / "designs" / "table1.toml")
    return [
        ("Table 1 (flat 15 mm web)", t1),
        ("hub 40 mm wide to r = 65 mm", t1.replace(hub_radius=0.065, hub_width=0.040)),
        ("  + fillets 5 mm (designs/hubbed.toml)", ws.load_design(ROOT / "designs" / "hubbed.toml")),
        ("taper 18 -> 12 mm (hub end -> rim end)", t1.replace(web_thickness=0.018, web_thickness_rim=0.012)),
        ("taper 12 -> 18 mm", t1.replace(web_thickness=0.012, web_thickness_rim=0.018)),
        ("conical web, rim end 4 mm off centre", t1.replace(web_offset_rim=0.004)),
        ("fillets 5 mm at the rim only", t1.replace(fillet_rim=0.005)),
        (
            "curved tapered web + hub (designs/curved_web.toml)",
            ws.load_design(ROOT / "designs" / "curved_web.toml"),
        ),
    ]


def main() -> None:
    rows = []
    ref = None
    for label, d in variants():
        t = time.perf_counter()
        ms = ws.compute_modes(d, "accurate", fmax_hz=3000.0)
        by = {(m.nodal_diameters, m.nodal_circles, m.family): m for m in ms.modes}
        m30, m10 = by[(3, 0, "axial")], by[(1, 0, "axial")]
        if ref is None:
            ref = m30
        rows.append(
            f"| {label} | {wheel_mass(d):.2f} | {m30.frequency_hz:.1f} | "
            f"{100 * (m30.frequency_hz / ref.frequency_hz - 1):+.1f} % | {m30.modal_mass:.3f} | "
            f"{100 * (m30.modal_mass / ref.modal_mass - 1):+.1f} % | {m10.frequency_hz:.1f} | "
            f"{time.perf_counter() - t:.2f} s |"
        )
    head = ["rig wheel", "mass [kg]", "(3,0) f [Hz]", "vs Table 1", "(3,0) m [kg]", "vs Table 1"]
    head += ["(1,0) f [Hz]"]
    print("| " + " | ".join(head + ["solve"]) + " |")
    print("|---|---|---|---|---|---|---|---|")
    print("\n".join(rows))


if __name__ == "__main__":
    main()
