"""Convergence study (convergence.py): a small ladder converges, the CSV is complete,
the Pareto front and the child-process measurement behave. Runs in a few seconds."""

from __future__ import annotations

import math
import mmap

import pytest

import wheel_squeal as ws
import wheel_squeal.convergence as cv


@pytest.fixture(scope="module")
def ladder():
    design = ws.load_design()
    rungs = [cv.FERung("axisym-P2", 4, reference=True)] + [cv.FERung("axisym-P2", e) for e in (1, 2, 3)]
    rows, modes = cv.fe_ladder(design, rungs, isolate=False)
    cv.fill_errors(rows, rows[0])
    cv.mark_pareto(rows)
    return rows, modes


@pytest.mark.slow  # four FE solves and squeal runs
def test_frequency_error_decreases_with_refinement(ladder):
    rows, _ = ladder
    errs = [abs(r["frequency_rel_error"]) for r in rows[1:]]  # 1, 2, 3 per web
    assert errs[0] > errs[1] > errs[2] > 0
    # P2 on the Table 1 wheel: one element across the web is already within 0.2 %
    assert errs[0] < 2e-3
    assert all(abs(r["modal_mass_rel_error"]) < 1e-3 for r in rows[1:])
    # the same mode everywhere, and the squeal model ran for every rung
    assert {r["mode"] for r in rows} == {"(3,0) axial"}
    assert all(0.3 < r["amplitude_m_s"] < 0.39 and r["time_to_saturation_s"] > 0 for r in rows)
    assert all(abs(r["amplitude_rel_error"]) < 1e-3 for r in rows[1:])


@pytest.mark.slow
def test_csv_has_the_columns(ladder, tmp_path):
    rows, _ = ladder
    path = tmp_path / "convergence.csv"
    cv.write_csv(rows, path)
    header = path.read_text().splitlines()[0].split(",")
    # what the presets are chosen from: each quantity beside its error against the finest rung
    quantities = ("frequency_hz", "modal_mass_kg", "amplitude_m_s", "time_to_saturation_s")
    errors = (
        "frequency_rel_error",
        "modal_mass_rel_error",
        "amplitude_rel_error",
        "time_to_saturation_rel_error",
    )
    for col in ("study", "method", "parameter", "dofs", "seconds", "peak_memory_mb", *quantities, *errors):
        assert col in header
    back = cv.read_csv(path)
    assert len(back) == len(rows)
    assert back[0]["reference"] and back[0]["frequency_rel_error"] == 0.0
    assert math.isclose(back[1]["frequency_hz"], rows[1]["frequency_hz"], rel_tol=1e-15)
    presets = cv.choose_presets(back)
    assert presets["fast"]["method"] == "axisym-P2"  # 1 per web meets the fast aim
    assert "| fast |" in cv.presets_table(presets)


def test_pareto_front():
    pts = [(1.0, 1e-2), (2.0, 1e-3), (3.0, 5e-3), (0.5, 1e-1), (4.0, 1e-3), (2.0, float("nan"))]
    assert cv.pareto_front(pts) == [3, 0, 1]


def _touch_64_mb() -> float:
    """64 MB of fresh pages, every one written: resident whatever the allocator kept from
    earlier work in this process (an arena's freed pages would not show as growth)."""
    import mmap

    block = mmap.mmap(-1, 64 * 2**20)
    for offset in range(0, len(block), mmap.PAGESIZE):
        block[offset] = 1
    total = float(sum(block[:: mmap.PAGESIZE]))
    block.close()
    return total


def test_measure_in_child_reports_memory_and_errors():
    out, seconds, mb = cv.measure(_touch_64_mb)
    assert out == 64 * 2**20 / mmap.PAGESIZE and seconds > 0
    if cv.fork_available():
        assert 40 < mb < 400
        with pytest.raises(RuntimeError, match="ZeroDivisionError"):
            cv.measure(lambda: 1 / 0)
