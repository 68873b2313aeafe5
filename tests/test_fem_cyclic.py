"""The cyclic 3-D P2 solver (fem.cyclic) and its mesh (geometry.revolve.revolve_profile).

Three independent checks of the numbers:
- exactness of the reduction: on the same small cyclic mesh, the full 3-D problem
  (fem.solid: whole-wheel assembly, one large eigen-solve, its own labeller and pair
  combination) gives the same frequencies and contact modal masses to round-off;
- the axisymmetric-harmonic solver on the same profile mesh: the two differ only in the
  circumferential discretisation (exact Fourier vs P2 over N sectors);
- the axisymmetric solver on a finer profile (the issue's 0.5 % / 2 % criterion).
The converged ladders live in benchmarks/bench_modes.py.
"""

from __future__ import annotations

import math
import types
import warnings

import numpy as np
import pytest
from conftest import DESIGNS, load_wheel as load_design

from fem.axisym import solve_axisymmetric
from fem.cyclic import default_sectors, solve_cyclic
from fem.modes import ResolutionWarning
from fem.solid import solve_solid
from geometry.gmsh_mesh import mesh_profile
from geometry.mesh import DEFAULT_ELEMENTS_THROUGH_WEB
from geometry.profile import revolved_volume
from geometry.revolve import revolve_profile
from geometry.simplex import inverted as _inverted
from geometry.wheel_design import WheelDesign

TABLE1 = load_design(DESIGNS / "table1.toml")


def key(m):
    return (m.nodal_diameters, m.nodal_circles, m.family)


def by_key(ms, fmax=math.inf):
    return {key(m): m for m in ms.modes if m.frequency_hz < fmax}


@pytest.fixture(scope="module")
def profile1():
    return mesh_profile(TABLE1, elements_through_web=1, order=2)


@pytest.fixture(scope="module")
def profile2():
    return mesh_profile(TABLE1, elements_through_web=2, order=2)


# -- the mesh ---------------------------------------------------------------------------
def test_revolved_mesh_volume_and_validity(profile1):
    """Curved P2 sectors: volume error O(Delta^4) (measured -9.5e-7 at N = 48, -1.1e-5 at
    N = 24); no element inverted; every node used; contact and bore nodes in place."""
    m = revolve_profile(profile1, 48)
    assert abs(m.volume() / revolved_volume(TABLE1) - 1) < 3e-6
    assert not _inverted(m.points, m.tetra, 3, 2).any()
    assert np.unique(m.tetra).size == m.n_nodes
    assert np.allclose(m.points[m.contact_node], [TABLE1.rolling_radius, 0, 0], atol=1e-15)
    r = np.hypot(m.points[m.bore_nodes, 0], m.points[m.bore_nodes, 1])
    assert np.allclose(r, TABLE1.bore_radius, rtol=1e-12)
    assert m.n_sectors == 48 and len(m.tetra) == 48 * 3 * len(profile1.triangles)


@pytest.mark.parametrize("n", [7, 12])
def test_revolved_mesh_is_cyclic(profile1, n):
    """Sector s + 1 is sector s rotated by 2 pi / N, node for node: the premise of the
    Bloch reduction."""
    m = revolve_profile(profile1, n)
    per = len(m.tetra) // n
    d = 2 * math.pi / n
    R = np.array([[math.cos(d), -math.sin(d), 0], [math.sin(d), math.cos(d), 0], [0, 0, 1]])
    for s in (0, n - 1):
        a = m.points[m.tetra[s * per : (s + 1) * per]]
        b = m.points[m.tetra[((s + 1) % n) * per : ((s + 1) % n + 1) * per]]
        assert np.abs(a @ R.T - b).max() < 1e-14 * TABLE1.rolling_radius


def test_layout_face_is_the_profile(profile1):
    m = revolve_profile(profile1, 12)
    L = m.sector_layout()
    as_set = lambda t: {tuple(sorted(row)) for row in np.asarray(t).tolist()}  # noqa: E731
    assert as_set(L.face_triangles) == as_set(profile1.triangles)
    xyz = m.points[L.owned[: len(profile1.points)]]
    assert np.abs(xyz[:, [0, 2]] - profile1.points).max() < 1e-15
    assert np.all(xyz[:, 1] == 0.0)


@pytest.mark.parametrize("bad", [2, 0, -4, 3.5, True, "12"])
def test_revolve_rejects_bad_sector_counts(profile1, bad):
    with pytest.raises(ValueError, match="n_sectors"):
        revolve_profile(profile1, bad)


def test_cyclic_needs_a_cyclic_mesh():
    with pytest.raises(ValueError, match="revolve_profile"):
        solve_cyclic(TABLE1, types.SimpleNamespace(n_sectors=0))


def test_default_sectors():
    assert default_sectors(TABLE1, 0.015) == 48  # 2 pi R1 / (2 h) = 44.6 -> 48
    assert default_sectors(TABLE1, 0.0075) == 92
    assert default_sectors(TABLE1, 0.0075) % 4 == 0


# -- exactness: cyclic reduction == full 3-D problem on the same mesh --------------------
@pytest.fixture(scope="module")
def cyclic_24(profile1):
    # 24 sectors: fem.solid's labeller takes a DFT over the node angles (48 distinct
    # angles here) up to n = 40; with 16 sectors (32 angles) n = 0 aliases onto n = 32
    m = revolve_profile(profile1, 24)
    return m, solve_cyclic(TABLE1, m, fmax_hz=3000.0)


@pytest.fixture(scope="module")
def same_mesh_pair(cyclic_24):
    """The cyclic solve and the full 3-D solve of the same mesh."""
    m, cyc = cyclic_24
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", RuntimeWarning)
        full = solve_solid(TABLE1, m, order=2, fmax_hz=3000.0)
    return m, cyc, full


@pytest.mark.slow
def test_cyclic_equals_full_3d_solve(same_mesh_pair):
    """Block-circulant reduction is exact: same eigenvalues (1e-8 relative: the Lanczos
    tolerance is 1e-10), same labels, same pair-combined contact modal masses (1e-6)."""
    m, cyc, full = same_mesh_pair
    assert cyc.dofs == full.dofs
    assert [key(a) for a in cyc.modes] == [key(b) for b in full.modes]
    fc = np.array([a.frequency_hz for a in cyc.modes])
    ff = np.array([b.frequency_hz for b in full.modes])
    np.testing.assert_allclose(fc, ff, rtol=1e-8)
    for a, b in zip(cyc.modes, full.modes):
        if math.isinf(a.modal_mass) or math.isinf(b.modal_mass):
            assert math.isinf(a.modal_mass) and math.isinf(b.modal_mass), (a, b)
        else:
            assert a.modal_mass == pytest.approx(b.modal_mass, rel=1e-6)


def test_cyclic_shapes_match_contact_values(cyclic_24):
    m, cyc = cyclic_24
    for mode, shape in zip(cyc.modes, cyc.shapes):
        assert shape.shape == (len(mode.contact_lateral), m.n_vertices, 3)
        if mode.modal_mass < math.inf:
            np.testing.assert_allclose(shape[:, m.contact_node, 2], mode.contact_lateral, rtol=1e-12)


def test_pair_modal_mass_is_rotation_invariant(cyclic_24):
    """Rotating a pair (phi_a, phi_b) -> (c a + s b, -s a + c b) leaves the contact modal
    mass unchanged to round-off, while a single member varies."""
    _, cyc = cyclic_24
    mode = next(a for a in cyc.modes if key(a) == (3, 0, "axial"))
    pa, pb = mode.contact_lateral
    masses, single = [], []
    for ang in np.linspace(0, math.pi, 7):
        c, s = math.cos(ang), math.sin(ang)
        qa, qb = c * pa + s * pb, -s * pa + c * pb
        masses.append(1.0 / (qa**2 + qb**2))
        single.append(1.0 / qa**2 if qa else math.inf)
    assert np.ptp(masses) <= 1e-12 * masses[0]
    assert max(single) > 2 * min(single)


# -- against the axisymmetric solver ---------------------------------------------------
def test_cyclic_converges_to_axisym_on_the_same_profile(profile2):
    """Same profile discretisation, only the circumferential one differs (P2 over N
    sectors vs exact Fourier): the difference is small and falls with N like Delta^4
    (measured max +3.1e-3 at N = 48, +3.1e-4 at 96, +5.6e-5 at 192; (3,0) modal mass
    -7e-4, -1.1e-4)."""
    ax = by_key(solve_axisymmetric(TABLE1, profile2, curved=True, fmax_hz=3100.0), 3000)
    errs = []
    for n in (48, 96):
        cy = by_key(solve_cyclic(TABLE1, revolve_profile(profile2, n), fmax_hz=3100.0), 3000)
        assert sorted(cy) == sorted(ax)
        rel = [cy[k].frequency_hz / ax[k].frequency_hz - 1 for k in ax]
        assert min(rel) > -1e-5  # the sector P2 discretisation is stiffer: from above
        errs.append(max(rel))
        m = cy[(3, 0, "axial")].modal_mass / ax[(3, 0, "axial")].modal_mass - 1
        assert abs(m) < 2e-3
    assert errs[1] < 5e-4
    assert errs[1] < errs[0] / 6  # Delta^4 would be 16x; measured 10x


@pytest.mark.slow
def test_cyclic_agrees_with_converged_axisym(profile2):
    """The issue's criterion at CI size: every mode below 3 kHz within 0.5 %, the (3,0)
    axial contact modal mass within 2 % (measured 0.16 % / 0.04 %, bench_modes.py)."""
    ref = by_key(
        solve_axisymmetric(
            TABLE1, mesh_profile(TABLE1, elements_through_web=6, order=2), curved=True, fmax_hz=3100.0
        ),
        3000,
    )
    cy = by_key(solve_cyclic(TABLE1, revolve_profile(profile2, 96), fmax_hz=3100.0), 3000)
    assert sorted(cy) == sorted(ref)
    for k, m in ref.items():
        assert cy[k].frequency_hz == pytest.approx(m.frequency_hz, rel=5e-3), k
    k30 = (3, 0, "axial")
    assert cy[k30].modal_mass == pytest.approx(ref[k30].modal_mass, rel=2e-2)


def test_cyclic_free_free_matches_axisym(profile1):
    """Free-free: the two rigid modes at p = 0 and two rigid pairs at p = 1 are dropped;
    the elastic modes are the axisymmetric solver's on the same profile."""
    ax = solve_axisymmetric(TABLE1, profile1, curved=True, fmax_hz=3000.0, boundary="free")
    cy = solve_cyclic(TABLE1, revolve_profile(profile1, 96), fmax_hz=3000.0, boundary="free")
    a, c = by_key(ax), by_key(cy)
    common = set(a) & set(c)
    assert len(common) >= len(a) - 1  # a mode may straddle fmax
    assert min(m.frequency_hz for m in cy.modes) > 100.0  # no rigid mode left
    for k in common:
        assert c[k].frequency_hz == pytest.approx(a[k].frequency_hz, rel=1e-3), k


@pytest.mark.slow
def test_cyclic_dished_wheel_contact_masses():
    """A dished web (web_offset != 0, not mirror-symmetric): in-plane modes couple to the
    axial contact displacement; both solvers give the same finite modal masses
    (measured within 2.9e-4 in frequency and 2.1e-4 in modal mass at N = 96)."""
    d = load_design(DESIGNS / "dished_web.toml")
    prof = mesh_profile(d, elements_through_web=2, order=2)
    ax = by_key(solve_axisymmetric(d, prof, curved=True, fmax_hz=3000.0))
    cy = by_key(solve_cyclic(d, revolve_profile(prof, 96), fmax_hz=3000.0))
    assert set(cy) == set(ax)
    for k in ax:
        assert cy[k].frequency_hz == pytest.approx(ax[k].frequency_hz, rel=1e-3), k
        assert math.isfinite(cy[k].modal_mass) == math.isfinite(ax[k].modal_mass), k
        if math.isfinite(ax[k].modal_mass):
            assert cy[k].modal_mass == pytest.approx(ax[k].modal_mass, rel=2e-3), k


def test_cyclic_k_lowest_and_band_agree(profile1):
    m = revolve_profile(profile1, 48)
    band = solve_cyclic(TABLE1, m, fmax_hz=3000.0)
    low = solve_cyclic(TABLE1, m, k=5, fmax_hz=None)
    assert [key(a) for a in low.modes] == [key(a) for a in band.modes[:5]]
    np.testing.assert_allclose(
        [a.frequency_hz for a in low.modes], [a.frequency_hz for a in band.modes[:5]], rtol=1e-9
    )


def test_too_few_sectors_warns(profile1):
    """An 8-sector mesh represents n <= 4 only: modes in the band at p = 4 alias."""
    with pytest.warns(ResolutionWarning, match="sectors"):
        solve_cyclic(TABLE1, revolve_profile(profile1, 8), fmax_hz=5000.0)


def test_the_default_sector_count_gives_the_lowest_modes_in_order():
    d = WheelDesign()
    profile = mesh_profile(d, elements_through_web=DEFAULT_ELEMENTS_THROUGH_WEB[3], order=2)
    ms = solve_cyclic(d, revolve_profile(profile, default_sectors(d, profile.size)), fmax_hz=1500.0)
    assert ms.solver == "3d-cyclic-p2"
    assert ms.points.shape[0] == ms.cells["tetra"].max() + 1
    assert [m.nodal_diameters for m in ms.modes][:3] == [1, 0, 2]
