"""Design files: the wheel and the squeal model's sections (roller, contact, damping,
squeal), every key checked, round trips, one default, and the flat field names that
studies and calibration vary."""

from __future__ import annotations

import math
import tomllib
from pathlib import Path

import pytest

import wheel_squeal as ws
from geometry import SECTIONS, DesignError, WheelDesign
from geometry.wheel_design import OPTIONAL_FIELDS
from wheel_squeal.design import FIELDS, Design

ROOT = Path(__file__).resolve().parents[1]
DESIGN_FILES = sorted((ROOT / "designs").glob("*.toml"))


def test_design_files_exist_and_are_complete():
    names = {p.stem for p in DESIGN_FILES}
    assert {"table1", "thin_web", "thick_web", "deep_rim", "dished_web", "annular_plate"} <= names
    for path in DESIGN_FILES:
        data = tomllib.loads(path.read_text())
        assert data["name"] == path.stem
        assert len(data["description"]) > 40, path
        for section, keys in SECTIONS.items():  # every key explicit (optional shape keys may be left out)
            if section == "wheel" and "profile" in data:
                assert section not in data, path  # an outline design has no [wheel]
                continue
            assert set(keys) - set(OPTIONAL_FIELDS) <= set(data[section]) <= set(keys), (path, section)
        for section in ("counter_body", "contact", "damping"):
            assert section in data, (path, section)
        assert data["counter_body"]["kind"] in ("roller", "track"), path


def test_table1_file_is_the_default_design():
    # One default: Design() and designs/table1.toml are the same, Table 1 with the rim
    # depth calibrated to the Table 1 modal data (README: Calibration). The file also
    # names the mode the rig was seen to squeal in (an observation, not a Table 1 value).
    d = ws.load_design(ROOT / "designs" / "table1.toml")
    assert d.squeal.mode == "n=3,c=0" and Design().squeal.mode == ""
    assert d.replace(squeal_mode="").content_hash() == Design().content_hash()
    assert Design().content_hash() == ws.load_design(None).replace(squeal_mode="").content_hash()
    assert d.wheel.content_hash("structure") == WheelDesign().content_hash("structure") == "5aa0dca4eacae795"
    assert (d.counter_body.rolling_radius, d.counter_body.crown_radius) == (0.085, 0.040)
    assert (d.contact.normal_load, d.contact.c22, d.contact.friction_coefficient) == (1000.0, 3.14, 0.3)
    assert d.damping.modal_damping_ratio == 9.4e-4


@pytest.mark.parametrize("path", DESIGN_FILES, ids=lambda p: p.stem)
def test_design_toml_round_trip(path, tmp_path):
    d = ws.load_design(path)
    (tmp_path / "copy.toml").write_text(d.to_toml())
    again = ws.load_design(tmp_path / "copy.toml")
    assert again == d
    assert again.content_hash() == d.content_hash()


def test_flat_names_reach_every_section():
    d = Design()
    changed = d.replace(
        rim_depth=0.03, roller_rolling_radius=0.1, normal_load=1500.0, modal_damping_ratio=2e-3
    )
    assert changed.wheel.rim_depth == 0.03 and changed.counter_body.rolling_radius == 0.1
    assert changed.contact.normal_load == 1500.0 and changed.damping.modal_damping_ratio == 2e-3
    assert all(changed.get(n) == getattr(getattr(changed, p), a) for n, (p, a) in FIELDS.items())
    with pytest.raises(DesignError, match="not a design parameter"):
        d.replace(rim_deep=0.03)


INVALID = [
    ({"roller_rolling_radius": 0.0}, "rolling_radius"),
    ({"roller_rolling_radius": 85.0}, "millimetres"),
    ({"roller_crown_radius": -1.0}, "crown_radius"),
    ({"normal_load": math.inf}, "normal_load"),
    ({"c22": 0.0}, "c22"),
    ({"friction_coefficient": -0.3}, "friction_coefficient"),
    ({"modal_damping_ratio": 1.5}, "modal_damping_ratio"),
]


@pytest.mark.parametrize("changes,param", INVALID, ids=[repr(c) for c, _ in INVALID])
def test_invalid_sections_name_the_parameter(changes, param):
    with pytest.raises(DesignError, match=param):
        Design().replace(**changes)


def _toml(**sections) -> str:
    lines = ['name = "t"']
    for section, items in sections.items():
        lines.append(f"[{section}]")
        lines += [f"{k} = {v}" for k, v in items.items()]
    return "\n".join(lines) + "\n"


@pytest.mark.parametrize(
    "text,param",
    [
        (_toml(wheel={"rolling_radiu": 0.2}), "rolling_radiu"),  # typo
        (_toml(wheel={"bore_radius": '"0.03"'}), "bore_radius"),  # string
        (_toml(wheel={"web_thickness": "true"}), "web_thickness"),  # bool
        (_toml(material={"poissons_ratio": 0.6}), "poissons_ratio"),
        (_toml(roller={"rolling_radius": -1.0}), "rolling_radius"),
        (_toml(contact={"mu": 0.3}), "mu"),
        (_toml(whel={"rim_width": 0.02}), "whel"),  # unknown section
        ('name = "t"\nrim_width = 0.02\n', "rim_width"),  # key outside its section
        ('name = "t"\n[wheel]\nrim_width = [0.02]\n', "rim_width"),
        ('name = "t"\n[wheel\n', "not valid TOML"),
        ('name = "t"\n[squeal]\nmode = "n=x"\n', "mode"),
        ('name = "t"\n[squeal]\ncolour = "red"\n', "colour"),
    ],
)
def test_invalid_toml_names_the_parameter(tmp_path, text, param):
    path = tmp_path / "bad.toml"
    path.write_text(text)
    with pytest.raises(DesignError, match=param):
        ws.load_design(path)


def test_missing_design_file(tmp_path):
    with pytest.raises(DesignError, match="not found"):
        ws.load_design(tmp_path / "nope.toml")


def test_damping_by_family_falls_back_from_the_mode_to_its_family_to_the_common_ratio(tmp_path):
    """[squeal.damping] may give a ratio per mode ("n=N,c=C"), per family with its
    direction ("n>=2,axial"), per family ("n=0", "n=1", "n>=2") and for all the rest
    (modal_damping_ratio); each mode takes the narrowest that names it, and says which;
    the family keys survive a round trip through the file and are written one way."""
    import dataclasses
    from types import SimpleNamespace

    from wheel_squeal.model_sections import Damping, mode_key

    assert mode_key("n >= 2, axial") == "n>=2,axial" and mode_key("n = 0") == "n=0"
    damping = Damping(
        modal_damping_ratio=1e-3,
        by_mode=tuple(sorted({"n=3,c=0": 5e-5, "n>=2,axial": 1e-4, "n>=2": 2e-4, "n=1": 3e-3}.items())),
    )
    assert damping.source(3, 0, "axial") == (5e-5, "n=3,c=0")
    assert damping.source(2, 0, "axial") == (1e-4, "n>=2,axial")
    assert damping.source(2, 0, "radial") == (2e-4, "n>=2")
    assert damping.source(1, 0, "axial") == (3e-3, "n=1")
    assert damping.source(0, 0, "axial") == (1e-3, "modal_damping_ratio")
    design = dataclasses.replace(ws.load_design("railway_920"), damping=damping)
    mode = SimpleNamespace(name=None, damping_ratio=None, nodal_diameters=4, nodal_circles=1, family="axial")
    assert design.damping_source(mode) == (1e-4, "n>=2,axial")  # type: ignore[arg-type]
    measured = SimpleNamespace(
        name=None, damping_ratio=7e-4, nodal_diameters=4, nodal_circles=1, family="axial"
    )
    assert design.damping_source(measured) == (7e-4, "measured")  # type: ignore[arg-type]
    path = tmp_path / "family.toml"
    path.write_text(design.to_toml())
    assert ws.load_design(path).damping == damping
