"""Extremes of the geometry and of the eigen solver: each case either
gives finite, sensible modes, or a clear error, or a warning that names the problem.

Warnings are ``fem.modes`` classes: ``FidelityWarning`` (base) with ``LockingWarning``
(P1 elements) and ``ResolutionWarning`` (mesh too coarse for the web or for the band),
and ``EmptyBandWarning`` (no mode in the band: empty ModeSet). Every solve here is the
axisymmetric one on a coarse profile mesh (P2, ``elements_through_web=1``: the ``fast``
preset) unless the case is about the mesh; one 3-D solve (free-free, coarse) checks the
rigid-mode count and the pair detection on a 2 m wheel.

Figures quoted in the tolerances were measured on these machines (the constants of
``fem.fidelity`` quote them too).
"""

from __future__ import annotations

import math
import warnings

import numpy as np
import pytest
from conftest import load_wheel as load_design

from fem.axisym import assemble_harmonic, solve_axisymmetric
from fem.eigen import solve_eigen
from fem.fidelity import LOCKING_NU, RESOLUTION_ELEMENTS, shortest_wavelength
from fem.meshes import to_skfem_mesh
from fem.modes import (
    CONTACT_NODE_RTOL,
    FAMILIES,
    EmptyBandWarning,
    FidelityWarning,
    LockingWarning,
    ModeSelection,
    ResolutionWarning,
    clean_contact,
    select_mode,
)
from fem.rules import RIGID_TOL
from geometry.gmsh_mesh import mesh_profile
from geometry.wheel_design import DesignError, WheelDesign

#: the Table 1 wheel with the 0.030 m starting rim depth: the values below were measured on it
T1 = WheelDesign(rim_depth=0.030)
SAG = T1.crown_radius - math.sqrt(T1.crown_radius**2 - (T1.rim_width / 2) ** 2)
FAST_MESH = dict(elements_through_web=1)  # the fast preset's mesh
FAST_SHAPES = dict(n_theta=8)  # small shapes
FAST = FAST_MESH | FAST_SHAPES


def labels(ms):
    return [m.label() for m in ms.modes]


def find(modes, n, family="axial", circles=0):
    hits = [m for m in modes if (m.nodal_diameters, m.family, m.nodal_circles) == (n, family, circles)]
    assert hits, f"no ({n},{circles}) {family} mode among {[m.label() for m in modes]}"
    return hits[0]


def quiet_solve(design, mesh=None, *, elements_through_web=None, size=None, **kw):
    """Mesh (unless given a mesh) and solve; fail on any FidelityWarning / EmptyBandWarning."""
    if mesh is None:
        order = 2 if kw.get("curved") else 1
        mesh = mesh_profile(design, size=size, elements_through_web=elements_through_web, order=order)
    with warnings.catch_warnings():
        warnings.simplefilter("error", FidelityWarning)
        warnings.simplefilter("error", EmptyBandWarning)
        return solve_axisymmetric(design, mesh, **kw)


def assert_sane(ms, fmax=None):
    """Finite positive ascending frequencies, known families, modal mass > 0 (inf for
    a contact node); axial modes have a finite contact mass, non-axial modes of a
    symmetric wheel have a node at the contact (inf)."""
    assert ms.modes, "no modes"
    f = np.array([m.frequency_hz for m in ms.modes])
    assert np.all(np.isfinite(f)) and np.all(f > 0) and np.all(np.diff(f) >= 0)
    if fmax is not None:
        assert f[-1] <= fmax
    for m, sh in zip(ms.modes, ms.shapes):
        assert m.family in FAMILIES
        assert m.nodal_diameters >= 0 and m.nodal_circles >= 0
        assert m.multiplicity == (1 if m.nodal_diameters == 0 else 2)
        assert np.all(np.isfinite(sh))
        assert m.modal_mass > 0
        if m.family == "axial":
            assert math.isfinite(m.modal_mass)
    return f


@pytest.fixture(scope="module")
def table1_fast():
    return quiet_solve(T1, fmax_hz=5000.0, **FAST)


# =====================================================================================
# geometry
# =====================================================================================
@pytest.mark.slow
def test_thin_web_2mm(table1_fast):
    """A 2 mm web (Table 1: 15 mm) is a floppy membrane between bore and rim: the rim
    rocks on it as a nearly rigid ring, so the (1,0) and (0,0) modes drop to tens of
    Hz, and the higher-n web modes barely move the rim (large contact masses). The
    mesh follows the web (size = web thickness), so it stays resolved: no warning; and
    a finer mesh changes the frequencies by less than 0.3 % (measured 0.2 %)."""
    d = T1.replace(web_thickness=0.002)
    ms = quiet_solve(d, fmax_hz=800.0, **FAST)
    f = assert_sane(ms, 800.0)
    assert labels(ms)[:2] == ["(1,0) axial", "(0,0) axial"]
    assert 5.0 < f[0] < 50.0  # measured 17.8 Hz
    for n in (1, 2):
        assert find(ms.modes, n).frequency_hz < find(table1_fast.modes, n).frequency_hz
    # (3,0) is a web mode now: the rim barely moves, the contact mass is large
    assert find(ms.modes, 3).modal_mass > 30 * find(table1_fast.modes, 3).modal_mass
    fine = quiet_solve(d, fmax_hz=800.0, elements_through_web=2, n_theta=8)
    assert labels(fine) == labels(ms)
    np.testing.assert_allclose([m.frequency_hz for m in fine.modes], f, rtol=3e-3)


def test_web_as_thick_as_the_rim(table1_fast):
    """web_thickness = rim_width (allowed, the limit): a crowned thick plate; stiffer
    than Table 1 in every axial family, same mode order at the bottom."""
    d = T1.replace(web_thickness=T1.rim_width)
    ms = quiet_solve(d, fmax_hz=5000.0, **FAST)
    assert_sane(ms, 5000.0)
    assert labels(ms)[:3] == ["(1,0) axial", "(0,0) axial", "(2,0) axial"]
    for n in (0, 1, 2, 3):
        assert find(ms.modes, n).frequency_hz > find(table1_fast.modes, n).frequency_hz
    with pytest.raises(DesignError, match="web_thickness must not exceed rim_width"):
        T1.replace(web_thickness=T1.rim_width * 1.001)


@pytest.mark.parametrize("depth", [1.05 * SAG, SAG + 1e-10], ids=["1.05_sagitta", "sagitta+0.1nm"])
def test_rim_depth_near_the_crown_sagitta(depth, table1_fast):
    """Rim depth just above the sagitta of the crown (0.28 mm): the rim is a sliver
    (14 um, resp. 0.1 nm, at the faces), the wheel a crowned plate. It meshes (local
    refinement, snapping) and solves; the two depths give the same modes (0.1 %:
    measured 0.02 %), lighter (smaller contact mass) than Table 1's 30 mm rim. At
    or below the sagitta the design is invalid."""
    d = T1.replace(rim_depth=depth)
    ms = quiet_solve(d, fmax_hz=5000.0, **FAST)
    assert_sane(ms, 5000.0)
    ref = quiet_solve(T1.replace(rim_depth=1.05 * SAG), fmax_hz=5000.0, **FAST)
    assert labels(ms) == labels(ref)
    np.testing.assert_allclose(
        [m.frequency_hz for m in ms.modes], [m.frequency_hz for m in ref.modes], rtol=1e-3
    )
    assert find(ms.modes, 3).modal_mass < find(table1_fast.modes, 3).modal_mass
    with pytest.raises(DesignError, match="rim_depth too small for the crown"):
        T1.replace(rim_depth=SAG * 0.99)


@pytest.mark.parametrize("gap", [1e-3, 1e-7], ids=["1mm", "0.1um_below_snap"])
def test_bore_close_to_the_rim(gap):
    """Bore 1 mm (and 0.1 um, less than the mesher's snapping length) inside the rim:
    a short clamped ring. Its lowest modes are axial (n, 0) modes near 10-11 kHz,
    nearly equal across n (the clamp, not the ring's bending, dominates). With the
    default band (5 kHz) nothing is left: empty ModeSet and EmptyBandWarning naming
    the lowest frequency."""
    d = T1.replace(bore_radius=T1.rim_inner_radius - gap)
    ms = quiet_solve(d, fmax_hz=None, k=4, **FAST)
    f = assert_sane(ms)
    assert [(m.nodal_diameters, m.family) for m in ms.modes] == [(n, "axial") for n in range(4)]
    assert 8e3 < f[0] < 1.3e4 and f[-1] / f[0] < 1.1  # measured 9.9-11.0 kHz, spread 5 %
    with pytest.warns(EmptyBandWarning, match=r"at or below fmax_hz = 5000 Hz") as rec:
        empty = solve_axisymmetric(d, mesh_profile(d, **FAST_MESH, order=1), fmax_hz=5000.0, **FAST_SHAPES)
    assert empty.modes == [] and empty.shapes == []
    assert _lowest(rec) == pytest.approx(f[0], rel=1e-3)  # 4 significant figures


@pytest.mark.parametrize("radius", [0.020, 2.0], ids=["R20mm", "R2m"])
def test_very_small_and_very_large_wheels(radius, table1_fast):
    """Table 1 scaled as a whole to a 20 mm and a 2 m rolling radius (every length,
    same elements through the web). Elastodynamics has no length scale, gmsh meshes in
    units of the rolling radius, so the scaled wheel has f / s and m s^3 (measured to
    1e-12; 1e-6 asked), the same labels, and the band fmax / s gives the same modes.
    The fidelity checks are scale-free too: no warning either way."""
    s = radius / T1.rolling_radius
    d = T1.scaled(s)
    ms = quiet_solve(d, fmax_hz=5000.0 / s, **FAST)
    assert_sane(ms)
    assert labels(ms) == labels(table1_fast)
    for a, b in zip(ms.modes, table1_fast.modes):
        assert a.frequency_hz * s == pytest.approx(b.frequency_hz, rel=1e-6)
        if math.isfinite(b.modal_mass):
            assert a.modal_mass == pytest.approx(b.modal_mass * s**3, rel=1e-6)
        else:
            assert a.modal_mass == math.inf


@pytest.mark.slow
def test_nu_near_half_p2_is_sane_and_p1_warns():
    """nu = 0.49: P2 (the axisymmetric path of every preset) does not lock: coarse (1
    per web) vs fine (4 per web) within 2.5 % on every mode below 5 kHz (measured 1.8 %
    against 6 per web) and 0.5 % on (3,0) (0.24 %); the frequencies move little from
    nu = 0.28 (the (3,0) mode -2 %). P1 at nu > 0.45 gives LockingWarning (volumetric);
    at nu = 0.499 P1 with 8 per web is +18 % on (3,0) (+47 % on the worst mode), P2
    coarse 0.4 %."""
    d = T1.replace(poissons_ratio=0.49)
    coarse = quiet_solve(d, fmax_hz=5000.0, **FAST)
    fine = quiet_solve(d, fmax_hz=5000.0, elements_through_web=4, n_theta=8)
    assert_sane(coarse, 5000.0)
    assert labels(coarse) == labels(fine)
    fc = np.array([m.frequency_hz for m in coarse.modes])
    ff = np.array([m.frequency_hz for m in fine.modes])
    assert np.all(fc >= ff * (1 - 1e-9))  # conforming: coarse is above
    assert np.max(fc / ff - 1) < 0.025
    assert find(coarse.modes, 3).frequency_hz == pytest.approx(find(fine.modes, 3).frequency_hz, rel=5e-3)
    assert find(fine.modes, 3).frequency_hz == pytest.approx(1114.0 * 0.98, rel=0.01)

    d = T1.replace(poissons_ratio=0.499)
    with pytest.warns(LockingWarning, match=r"nu = 0\.499 > 0\.45 .*volumetric locking"):
        p1 = solve_axisymmetric(
            d, mesh_profile(d, elements_through_web=8, order=1), order=1, fmax_hz=None, k=6, n_theta=8
        )
    p2 = quiet_solve(d, fmax_hz=None, k=6, **FAST)
    f1, f2 = find(p1.modes, 3).frequency_hz, find(p2.modes, 3).frequency_hz
    assert f1 > 1.1 * f2  # locked (measured +18 %)
    assert f2 == pytest.approx(1090.6, rel=0.01)  # 6-per-web P2 reference, measured


def test_locking_threshold_is_on_nu_and_order():
    """The volumetric warning depends on nu and the element order only: P1 at
    nu = LOCKING_NU with 8 per web is quiet, just above it warns; P2 never."""
    quiet_solve(
        T1.replace(poissons_ratio=LOCKING_NU), order=1, fmax_hz=None, k=2, elements_through_web=8, n_theta=8
    )
    with pytest.warns(LockingWarning, match="volumetric"):
        solve_axisymmetric(
            T1.replace(poissons_ratio=LOCKING_NU + 0.01),
            mesh_profile(T1.replace(poissons_ratio=LOCKING_NU + 0.01), elements_through_web=8, order=1),
            order=1,
            fmax_hz=None,
            k=2,
            n_theta=8,
        )
    quiet_solve(T1.replace(poissons_ratio=0.4999), fmax_hz=None, k=2, **FAST)


def test_meshes_too_coarse_for_the_web():
    """Element size above the web thickness (fewer than one element through it) gives
    ResolutionWarning naming the web; the result stays usable (gmsh cannot put fewer
    elements than the outline needs: 15 triangles at any size above 14 x the web),
    measured 1.4 % error at 2 x, 9.4 % at 20 x. P1 with fewer than 8 elements through
    the web gives LockingWarning (bending). The fast preset (P2, 1 per web) is quiet."""
    ref = quiet_solve(T1, fmax_hz=3000.0, elements_through_web=4, n_theta=8)
    fr = {m.label(): m.frequency_hz for m in ref.modes}
    for mult, tol in ((2.0, 0.02), (20.0, 0.12)):
        with pytest.warns(ResolutionWarning) as rec:
            ms = solve_axisymmetric(
                T1, mesh_profile(T1, size=mult * T1.web_thickness, order=1), fmax_hz=3000.0, n_theta=8
            )
        msgs = [str(w.message) for w in rec]
        assert any("exceeds the web thickness 15 mm" in m for m in msgs), msgs
        # at 20 x (300 mm elements) the 3 kHz wavelength is not resolved either
        assert any("does not resolve" in m for m in msgs) == (mult > 10), msgs
        assert_sane(ms, 3000.0)
        # a mode just below the band edge may be pushed out of it by the error
        assert set(labels(ms)) <= set(fr)
        assert {k for k, f in fr.items() if f < 3000.0 / (1 + tol)} <= set(labels(ms))
        for m in ms.modes:
            assert m.frequency_hz / fr[m.label()] - 1 == pytest.approx(0.0, abs=tol)
    with pytest.warns(LockingWarning, match="2 elements through the 15 mm web lock in bending"):
        solve_axisymmetric(
            T1, mesh_profile(T1, elements_through_web=2, order=1), order=1, fmax_hz=None, k=4, n_theta=8
        )
    # exactly one element through the web (ProfileMesh.size == web thickness): quiet
    quiet_solve(T1, mesh_profile(T1, elements_through_web=1, order=1), fmax_hz=5000.0, n_theta=8)


# =====================================================================================
# the eigen solver
# =====================================================================================
@pytest.mark.parametrize("s", [1.0, 0.02 / 0.213, 2.0 / 0.213], ids=["table1", "R20mm", "R2m"])
def test_free_free_rigid_modes_axisym(s):
    """Free-free: the rigid motions are the (U, V) problem's axial translation and the
    W problem's spin at n = 0, two at n = 1 (translation, tilt), none at n >= 2. They
    come out many decades below the recognition threshold RIGID_TOL * f_ref, and the
    first elastic mode many decades above it, at every scale (f_ref scales as 1 / s):
    recognised and dropped, leaving (2,0) axial first. Rigid f / f_ref measured
    <= 1e-6 (threshold 1e-3), first elastic 0.098."""
    d = T1.scaled(s)
    ms = quiet_solve(d, boundary="free", fmax_hz=None, k=3, **FAST)
    assert_sane(ms)
    assert labels(ms)[0] == "(2,0) axial"
    f_ref = math.sqrt(d.shear_modulus / d.density) / (2 * math.pi * d.rolling_radius)
    assert ms.modes[0].frequency_hz > 30 * RIGID_TOL * f_ref
    model = assemble_harmonic(
        d, to_skfem_mesh(mesh_profile(d, elements_through_web=1, order=1)), boundary="free"
    )
    sigma = -((2 * math.pi * 0.05 * f_ref) ** 2)
    comp = model.comp
    problems = [
        ("n=0 (U,V)", 0, model.free[comp[model.free] != 2], 1),
        ("n=0 W", 0, model.free[comp[model.free] == 2], 1),
        ("n=1", 1, None, 2),
        ("n=2", 2, None, 0),
    ]
    for name, n, dofs, expected in problems:
        K, M = model.matrices(n, dofs)
        f = solve_eigen(K, M, k=4, sigma=sigma).frequencies_hz / f_ref
        rigid = f < RIGID_TOL
        assert np.count_nonzero(rigid) == expected, (name, f)
        assert np.all(f[rigid] < 1e-5) and np.all(f[~rigid] > 30 * RIGID_TOL), (name, f)


@pytest.mark.slow
def test_free_free_3d_large_wheel_rigid_modes_and_pairs():
    """3-D, free-free, the 2 m wheel (coarse P2 mesh, 1 Hz rigid threshold and 10 Hz
    shift are absolute in fem.solid): exactly six rigid modes recognised and dropped
    (solve_solid raises otherwise), the first elastic mode is the (2,0) axial pair
    (multiplicity 2: the pair detection), at the axisymmetric frequency within 1 %
    (measured 0.46 %)."""
    import fem.solid as solid
    from geometry.gmsh_mesh import mesh_wheel

    s = 2.0 / T1.rolling_radius
    d = T1.scaled(s)
    ms = solid.solve_solid(
        d, mesh_wheel(d, size=0.04 * s, order=2), order=2, boundary="free", fmax_hz=None, k=1
    )
    first = ms.modes[0]
    assert first.label() == "(2,0) axial" and first.multiplicity == 2
    ax = quiet_solve(d, boundary="free", fmax_hz=None, k=1, **FAST)
    assert first.frequency_hz == pytest.approx(ax.modes[0].frequency_hz, rel=0.01)


def test_repeated_frequencies_are_one_mode_with_two_members(table1_fast):
    """Axisymmetric: a degenerate pair is exact by construction (the cos and sin
    members solve the same 2-D problem): one Mode, two members, the sin member's
    contact value 0 (a nodal diameter through the contact), its shape the cos member's
    turned by 90 deg / n. Close modes of different harmonics stay separate modes: the
    (1,0) circumferential and (2,1) axial lie 0.2 % apart here."""
    ms = table1_fast
    th = np.unique(np.round(np.arctan2(ms.points[:, 1], ms.points[:, 0]), 12))
    for m, sh in zip(ms.modes, ms.shapes):
        if m.nodal_diameters == 0:
            continue
        assert m.contact_lateral[1] == 0.0 and sh.shape[0] == 2
        # members M-orthogonal: <cos n t, sin n t> over the ring is 0 for every node
        ang = np.arctan2(ms.points[:, 1], ms.points[:, 0])
        n = m.nodal_diameters
        with np.errstate(invalid="ignore", divide="ignore"):
            uz_cos = sh[0, :, 2] / np.cos(n * ang)
            uz_sin = sh[1, :, 2] / np.sin(n * ang)
        ok = (np.abs(np.cos(n * ang)) > 0.3) & (np.abs(np.sin(n * ang)) > 0.3)
        if ok.sum() > 10:  # same V(r, z) behind both members
            np.testing.assert_allclose(uz_cos[ok], uz_sin[ok], rtol=1e-9, atol=1e-12 * np.abs(sh).max())
    assert len(th) == 8
    a, b = find(ms.modes, 1, "circumferential"), find(ms.modes, 2, "axial", 1)
    assert abs(a.frequency_hz / b.frequency_hz - 1) < 5e-3 and a.index != b.index


@pytest.mark.parametrize("boundary", ["clamped", "free"])
def test_band_with_no_modes(boundary):
    """fmax_hz = 10 Hz: nothing in the band. Choice: an empty ModeSet (it is a valid
    answer; a sweep over designs goes on) plus an EmptyBandWarning naming the band and
    the lowest natural frequency; select_mode then raises a LookupError that says the
    set is empty and to raise fmax (the pipeline turns it into a one-line error)."""
    with pytest.warns(
        EmptyBandWarning,
        match=rf"no natural frequency at or below fmax_hz = 10 Hz \({boundary} wheel .*raise fmax_hz",
    ) as rec:
        ms = solve_axisymmetric(
            T1, mesh_profile(T1, **FAST_MESH, order=1), fmax_hz=10.0, boundary=boundary, **FAST_SHAPES
        )
    # the lowest mode: clamped (1,0) axial 263.7 Hz, free (2,0) axial (measured 431 Hz)
    ref = quiet_solve(T1, fmax_hz=None, k=1, boundary=boundary, **FAST).modes[0]
    assert _lowest(rec) == pytest.approx(ref.frequency_hz, rel=1e-3)
    assert ms.modes == [] and ms.shapes == [] and ms.dofs > 0
    with pytest.raises(LookupError, match="mode set is empty .*raise .*fmax"):
        select_mode(ms.modes)
    with pytest.raises(LookupError, match="empty"):
        select_mode(ms.modes, ModeSelection.parse("f=1100"))


def test_fmax_beyond_the_mesh_resolution_warns():
    """The wavelength criterion (fem.fidelity.RESOLUTION_ELEMENTS: 6 P2 elements per
    shortest wavelength, the smaller of the web's bending and the shear wavelength,
    about 1 % frequency error): 50 kHz on the fast mesh (15 mm elements; 52 mm web
    bending wavelength, 3.5 elements) warns; 5 kHz on the default mesh (7.5 mm; 164 mm,
    22 elements) does not, nor 5 kHz on the fast mesh (11 elements). With only ``k``
    the check uses the highest mode found. The criterion is scale-free."""
    assert shortest_wavelength(T1, 5e4) == pytest.approx(0.0518, rel=0.01)
    assert shortest_wavelength(T1, 5e3) == pytest.approx(0.164, rel=0.01)
    with pytest.warns(ResolutionWarning, match=r"does not resolve 5e\+04 Hz.*fewer than 6"):
        solve_axisymmetric(T1, mesh_profile(T1, **FAST_MESH, order=1), fmax_hz=5e4, n_max=0, **FAST_SHAPES)
    quiet_solve(T1, fmax_hz=5000.0, n_theta=8)  # default mesh (2 per web)
    quiet_solve(T1, fmax_hz=5000.0, **FAST)
    s = 0.02 / T1.rolling_radius
    with pytest.warns(ResolutionWarning):
        solve_axisymmetric(
            T1.scaled(s),
            mesh_profile(T1.scaled(s), **FAST_MESH, order=1),
            fmax_hz=5e4 / s,
            n_max=0,
            **FAST_SHAPES,
        )
    # k only: 20 lowest of n = 0 reach about 35 kHz on the fast mesh -> warns after
    with pytest.warns(ResolutionWarning, match="does not resolve"):
        solve_axisymmetric(
            T1, mesh_profile(T1, **FAST_MESH, order=1), fmax_hz=None, k=20, n_max=0, **FAST_SHAPES
        )
    assert RESOLUTION_ELEMENTS[2] * T1.web_thickness / 2 < shortest_wavelength(T1, 5000.0)


# =====================================================================================
# contact modal mass of in-plane modes
# =====================================================================================
def test_in_plane_modes_have_a_contact_node(table1_fast):
    """Table 1 is mirror-symmetric: its in-plane (radial, circumferential) modes have
    V = 0 on z = 0, so the contact is a node and the modal mass is inf (was 1e10-1e11
    kg from the mesh's asymmetry). The n = 0 torsion mode in particular."""
    ms = table1_fast
    tors = find(ms.modes, 0, "circumferential")
    assert tors.contact_lateral == (0.0,) and tors.modal_mass == math.inf
    in_plane = [m for m in ms.modes if m.family != "axial"]
    assert len(in_plane) >= 3
    for m in in_plane:
        assert m.modal_mass == math.inf, m
        assert m.to_dict(9.4e-4)["modal_mass_kg"] is None
    # also on a coarse, thick-web mesh, where the spurious V was 1 % of the peak
    d = load_design(str(_designs() / "thick_web.toml"))
    ms2 = quiet_solve(d, fmax_hz=5000.0, **FAST)
    assert all(m.modal_mass == math.inf for m in ms2.modes if m.family != "axial")
    assert all(math.isfinite(m.modal_mass) for m in ms2.modes if m.family == "axial")


def test_dished_wheel_keeps_its_in_plane_coupling():
    """A dished wheel (web offset 4 mm) couples in-plane and axial motion for real:
    its (1,0) circumferential mode keeps a finite contact mass (about 200 kg)."""
    d = load_design(str(_designs() / "dished_web.toml"))
    ms = quiet_solve(d, fmax_hz=3000.0, **FAST)
    m = find(ms.modes, 1, "circumferential")
    assert 50.0 < m.modal_mass < 1000.0


def test_clean_contact_floor():
    assert CONTACT_NODE_RTOL == 1e-6
    assert clean_contact(1e-7, 1.0) == 0.0
    assert clean_contact(-1e-6, 1.0) == 0.0
    assert clean_contact(2e-6, 1.0) == 2e-6
    assert clean_contact(-0.3, 0.5) == -0.3
    assert clean_contact(0.0, 0.0) == 0.0


def _lowest(record) -> float:
    """The lowest frequency quoted by the (single) EmptyBandWarning in ``record``."""
    import re

    msgs = [str(w.message) for w in record if issubclass(w.category, EmptyBandWarning)]
    assert len(msgs) == 1, msgs
    return float(re.search(r"the lowest is ([0-9.e+-]+) Hz", msgs[0]).group(1))


def _designs():
    from pathlib import Path

    return Path(__file__).resolve().parents[1] / "designs"
