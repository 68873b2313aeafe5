"""A new counter-body kind is one section class and one physics class.

A block on a spring under the contact (a stand-in for any counter-body with a normal
mode) is written here as a ``CounterBodySection`` subclass whose ``model()`` is its
receptance at the contact (``reduced.BodyModel``), registered by its kind, and nothing
else: a design file with
``[counter_body] kind = "block"`` then loads, writes and hashes, and the chain's
stability sees its degree of freedom. The check that it is wired through, not merely
accepted: the block's eigenvalues are the roller's with the same normal mode (the same
physics by another door), and differ from the rigid counter-body's.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, replace
from typing import ClassVar

import numpy as np
import pytest
from conftest import COUPLED_PAIR_TOML

import wheel_squeal as ws
from geometry import DesignError
from geometry.schema import spec
from reduced import NORMAL, BodyModel
from track import design_sections as sections
from wheel_squeal.chain import ChainOptions


@dataclass(frozen=True)
class Block(sections.CounterBodySection):
    """The section: its fields, its surface at the contact, its physics, its labels."""

    KIND: ClassVar[str] = "block"

    mass_kg: float = spec(5.0, "kg", "the block's mass")
    stiffness_n_m: float = spec(2.0e8, "N/m", "the spring under it")
    damping_ratio: float = spec(0.02, "", "its damping ratio")
    radius: float = spec(0.085, "m", "its surface's radius along rolling", length=True)
    crown_radius: float = spec(0.040, "m", "its surface's radius across", length=True)

    def __post_init__(self) -> None:
        for name in ("mass_kg", "stiffness_n_m", "radius", "crown_radius"):
            if not getattr(self, name) > 0:
                raise DesignError(f"[counter_body] {name} must be positive")

    def contact_radii(self) -> tuple[float, float]:
        return self.radius, self.crown_radius

    def model(self) -> BodyModel:
        """The physics: a mass on a spring and dashpot under the contact, along its normal."""
        f_hz = math.sqrt(self.stiffness_n_m / self.mass_kg) / (2 * math.pi)
        return BodyModel.from_modes([(NORMAL, f_hz, self.damping_ratio, self.mass_kg)], "the block")


@pytest.fixture
def block_kind(monkeypatch):
    monkeypatch.setitem(sections.COUNTER_BODIES, "block", Block)


def _eigenvalues(design, modes) -> np.ndarray:
    op = ws.operating_point(design, rpm=800.0, crabbing_velocity_m_s=0.39)
    a = ws.analyse(design, op=op, modes=modes, options=ChainOptions(stop_after="stability", remedy=False))
    return np.sort_complex(np.asarray(a.table.result.eigenvalues))


def _block_design(tmp_path):
    """(the coupled pair's modes, table1 on a rigid roller, the same on the block)."""
    pair = tmp_path / "pair.toml"
    pair.write_text(COUPLED_PAIR_TOML)
    modes = ws.load_modal_model(pair)
    base = ws.load_design("table1").replace(friction_law="constant", squeal_mode="")
    text = base.to_toml().replace('kind = "roller"', "").split("[counter_body]")
    head, tail = text[0], text[1].split("\n[", 1)
    body = '[counter_body]\nkind = "block"\nmass_kg = 5.0\nstiffness_n_m = 2.0e8\ndamping_ratio = 0.02\n'
    path = tmp_path / "block.toml"
    path.write_text(head + body + ("\n[" + tail[1] if len(tail) > 1 else ""))
    return modes, base, ws.load_design(path)


def test_a_new_kind_loads_writes_hashes_and_reaches_the_stability(block_kind, tmp_path):
    modes, base, design = _block_design(tmp_path)
    assert isinstance(design.counter_body, Block) and design.counter_body.stiffness_n_m == 2.0e8
    again = tmp_path / "again.toml"
    again.write_text(design.to_toml())
    assert ws.load_design(again) == design  # written and read back the same
    assert design.content_hash() != base.content_hash()
    assert design.counter_body.summary()["kind"] == "block"
    with pytest.raises(DesignError, match="mass_kg must be positive"):
        design.replace(mass_kg=-1.0)

    # the same normal mode as a roller's modal degree of freedom (on a surface of the
    # roller's radii): the same eigenvalues
    f_hz = math.sqrt(2.0e8 / 5.0) / (2 * math.pi)
    roller = base.replace(normal_frequency_hz=f_hz, normal_damping_ratio=0.02, normal_modal_mass_kg=5.0)
    with_block, with_roller, rigid = (_eigenvalues(d, modes) for d in (design, roller, base))
    assert len(with_block) == len(with_roller) == len(rigid) + 1  # one more pair (Im >= 0 kept)
    # the two doors build the same matrices: equal to the round-off of a 6x6 eigen-solve
    assert np.allclose(with_block, with_roller, rtol=1e-9), (with_block, with_roller)
    # and the block matters: the pair's fastest growth moves by more than 0.1 %
    fastest = [float(np.max(ev.real)) for ev in (with_block, rigid)]
    assert abs(fastest[0] - fastest[1]) > 1e-3 * abs(fastest[1]), fastest


def test_what_a_new_kind_adds_reaches_the_verdict_by_its_model_not_its_kind(block_kind, tmp_path):
    """The verdict says how much a counter-body's own degrees of freedom add to the fastest
    growth rate whatever its kind: the block's effect is the fastest eigenvalue with it
    less the one with it rigid (the rigid roller's, the same contact), named by its model;
    a rigid counter-body has none."""
    modes, base, design = _block_design(tmp_path)
    op = ws.operating_point(design, rpm=800.0, crabbing_velocity_m_s=0.39)
    options = ChainOptions(stop_after="stability", remedy=False)
    verdict = ws.analyse(design, op=op, modes=modes, options=options).verdict
    fastest = [float(np.max(_eigenvalues(d, modes).real)) for d in (design, base)]
    # the same two eigen-solves by two paths: equal to their round-off
    assert verdict.counter_body_effect_1_s == pytest.approx(fastest[0] - fastest[1], rel=1e-9, abs=1e-9)
    assert "the block " in verdict.reason and "on a rigid block" in verdict.reason
    assert ws.analyse(base, op=op, modes=modes, options=options).verdict.counter_body_effect_1_s is None


def test_an_older_roller_section_is_the_roller_kind(tmp_path):
    """Files written before the counter-body had kinds say ``[roller]``: the same design,
    the same hash; both sections in one file is refused."""
    new = ws.load_design("table1").to_toml()
    assert '[counter_body]\nkind = "roller"' in new
    old = new.replace('[counter_body]\nkind = "roller"', "[roller]")
    (tmp_path / "old.toml").write_text(old)
    (tmp_path / "new.toml").write_text(new)
    a, b = ws.load_design(tmp_path / "old.toml"), ws.load_design(tmp_path / "new.toml")
    assert a == b and a.content_hash() == b.content_hash() == ws.load_design("table1").content_hash()
    (tmp_path / "both.toml").write_text(new + "\n[roller]\nrolling_radius = 0.085\n")
    with pytest.raises(DesignError, match="not both"):
        ws.load_design(tmp_path / "both.toml")


def test_a_verdict_without_the_counter_body_s_effect_is_otherwise_the_same(block_kind, tmp_path):
    """``counter_body_effect=False`` (a line's verdicts) leaves out the rigid counter-body's
    eigen-solve and its words and nothing else: the same verdict, field by field."""
    modes, _, design = _block_design(tmp_path)
    op = ws.operating_point(design, rpm=800.0, crabbing_velocity_m_s=0.39)
    options = ChainOptions(stop_after="stability", remedy=False)
    full = ws.analyse(design, op=op, modes=modes, options=options).verdict
    without = replace(options, counter_body_effect=False)
    plain = ws.analyse(design, op=op, modes=modes, options=without).verdict
    assert full.counter_body_effect_1_s is not None and plain.counter_body_effect_1_s is None
    assert full.reason.startswith(plain.reason) and "on a rigid block" not in plain.reason
    assert replace(full, reason=plain.reason, counter_body_effect_1_s=None) == plain
