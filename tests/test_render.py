"""Off-screen mode-shape rendering (fem/render.py) on a synthetic revolved wheel.

The mode set is built here with numpy (a web + rim profile revolved into wedge cells,
analytic shapes), so these tests do not depend on the FE solvers.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from fem.modes import Mode, ModeSet

# Table 1-like proportions [m]
R_BORE, R_RIM, R_OUT = 0.0325, 0.183, 0.213
WEB_T, RIM_W = 0.015, 0.026


def _revolve(profile_pts: np.ndarray, tris: np.ndarray, n_theta: int):
    """Revolve a triangulated (r, z) profile about z into wedge cells (VTK order)."""
    th = np.linspace(0.0, 2 * np.pi, n_theta, endpoint=False)
    r, z = profile_pts[:, 0], profile_pts[:, 1]
    npp = len(profile_pts)
    pts = np.empty((n_theta * npp, 3))
    for k, t in enumerate(th):
        pts[k * npp : (k + 1) * npp] = np.column_stack([r * np.cos(t), r * np.sin(t), z])
    wedges = []
    for k in range(n_theta):
        a, b = k * npp, ((k + 1) % n_theta) * npp
        wedges.append(np.hstack([tris + a, tris + b]))
    return pts, np.vstack(wedges)


def _profile(nr_web=8, nr_rim=3, nz_web=2, nz_rim=4):
    """Web + rim cross-section as structured quads split into triangles."""
    pts, index = [], {}

    def node(r, z):
        key = (round(r, 9), round(z, 9))
        if key not in index:
            index[key] = len(pts)
            pts.append(key)
        return index[key]

    tris = []

    def block(r0, r1, z0, z1, nr, nz):
        rs, zs = np.linspace(r0, r1, nr + 1), np.linspace(z0, z1, nz + 1)
        for i in range(nr):
            for j in range(nz):
                a, b = node(rs[i], zs[j]), node(rs[i + 1], zs[j])
                c, d = node(rs[i + 1], zs[j + 1]), node(rs[i], zs[j + 1])
                tris.extend([(a, b, c), (a, c, d)])

    block(R_BORE, R_RIM, -WEB_T / 2, WEB_T / 2, nr_web, nz_web)
    # rim: split in z so its nodes at +-WEB_T/2 match the web's
    zr = [-RIM_W / 2, -WEB_T / 2, WEB_T / 2, RIM_W / 2]
    for z0, z1, nz in zip(zr[:-1], zr[1:], (1, nz_web, 1)):
        block(R_RIM, R_OUT, z0, z1, nr_rim, nz)
    return np.array(pts), np.array(tris)


def synthetic_modeset(n_theta: int = 72) -> ModeSet:
    """Analytic shapes: axial n = 0, 2, 3 (pair for n >= 1, rotated by the 'solver'),
    an axial (2, 1) with a nodal circle, and a radial in-plane n = 2 pair."""
    prof, tris = _profile()
    pts, wedges = _revolve(prof, tris, n_theta)
    x, y, z = pts.T
    r, th = np.hypot(x, y), np.arctan2(y, x)
    s = (r - R_BORE) / (R_OUT - R_BORE)
    er = np.column_stack([np.cos(th), np.sin(th), np.zeros_like(th)])
    ez = np.tile([0.0, 0.0, 1.0], (len(pts), 1))

    def axial(n, phase, circle=False):
        w = s**2 * ((s - 0.55) if circle else 1.0)
        return (w * np.cos(n * (th - phase)))[:, None] * ez

    def radial(n, phase):
        return (s**2 * np.cos(n * (th - phase)))[:, None] * er

    contact = int(np.argmin(np.linalg.norm(pts - [R_OUT, 0, 0], axis=1)))
    specs = [
        # (f, n, c, family, member shapes)
        (310.0, 0, 0, "axial", [axial(0, 0.0)]),
        (520.0, 2, 0, "axial", [axial(2, 0.3), axial(2, 0.3 + np.pi / 4)]),
        (1143.0, 3, 0, "axial", [axial(3, 0.2), axial(3, 0.2 + np.pi / 6)]),
        (2100.0, 2, 1, "axial", [axial(2, 0.0, True), axial(2, np.pi / 4, True)]),
        (2600.0, 2, 0, "radial", [radial(2, 0.1), radial(2, 0.1 + np.pi / 4)]),
    ]
    modes, shapes = [], []
    for i, (f, n, c, fam, members) in enumerate(specs):
        S = np.stack(members) * 0.05  # "mass-normalised" scale [m / sqrt(kg)]
        shapes.append(S)
        modes.append(Mode(i, f, n, c, fam, tuple(float(m[contact, 2]) for m in S)))
    return ModeSet(
        modes=modes, points=pts, cells={"wedge": wedges}, shapes=shapes, solver="synthetic", dofs=3 * len(pts)
    )


@pytest.fixture(scope="module")
def modeset() -> ModeSet:
    return synthetic_modeset()


# --------------------------------------------------------------------------- helpers
def _wheel_fraction(img: np.ndarray) -> float:
    """Fraction of pixels differing from the (white) background, ignoring the text
    bands at the top (title) and bottom (scalar bar, footnote)."""
    h = img.shape[0]
    body = img[int(0.08 * h) : int(0.82 * h)].astype(int)
    return float(np.mean(np.abs(body - 255).sum(axis=2) > 30))


@pytest.fixture(autouse=True)
def no_display(monkeypatch):
    """Rendering must not need a display: CI has none."""
    monkeypatch.delenv("DISPLAY", raising=False)
    monkeypatch.delenv("WAYLAND_DISPLAY", raising=False)


# ----------------------------------------------------------------------------- tests
def test_contact_aligned_pair_is_rotation_invariant(modeset):
    from fem.render import contact_point_index, mode_shape

    k = contact_point_index(modeset)
    assert np.allclose(modeset.points[k], [R_OUT, 0, 0])
    for i, mode in enumerate(modeset.modes):
        u = mode_shape(modeset, i)
        if mode.family == "axial":
            # the drawn shape carries the whole contact response: u_z^2 = 1 / m
            assert u[k, 2] > 0
            assert u[k, 2] ** 2 == pytest.approx(1.0 / mode.modal_mass, rel=1e-9)
        else:  # in-plane: aligned on the whole contact displacement vector
            d = np.asarray(modeset.shapes[i])[:, k, :]
            assert np.linalg.norm(u[k]) == pytest.approx(np.linalg.norm(d), rel=1e-9)
    # rotating the pair (as another solver might) does not change the drawn shape
    i = 2
    c, s = math.cos(0.7), math.sin(0.7)
    a, b = modeset.shapes[i]
    rotated = ModeSet(
        modeset.modes,
        modeset.points,
        modeset.cells,
        [*modeset.shapes[:i], np.stack([c * a + s * b, -s * a + c * b]), *modeset.shapes[i + 1 :]],
        "synthetic",
        modeset.dofs,
    )
    assert np.allclose(mode_shape(rotated, i), mode_shape(modeset, i), atol=1e-12)
    # the analytic n = 3 shape aligned to the contact: u_z ~ cos(3 theta) at the rim
    th = np.arctan2(modeset.points[:, 1], modeset.points[:, 0])
    rim = np.hypot(modeset.points[:, 0], modeset.points[:, 1]) > R_OUT - 1e-9
    u = mode_shape(modeset, i)[rim, 2]
    assert np.allclose(u / u.max(), np.cos(3 * th[rim]), atol=1e-9)


@pytest.mark.slow  # an off-screen render (about 2 s)
def test_render_mode_png(modeset, tmp_path):
    from PIL import Image

    from fem.render import render_mode

    path = tmp_path / "m.png"
    img = render_mode(modeset, 2, path, window_size=(800, 600))
    assert img.shape == (600, 800, 3) and img.dtype == np.uint8
    png = np.asarray(Image.open(path).convert("RGB"))
    assert png.shape == (600, 800, 3)
    assert np.array_equal(png, np.asarray(img))
    frac = _wheel_fraction(png)
    assert 0.15 < frac < 0.85, frac
    # the colour map is used (not a flat grey wheel) and the contact marker is red
    assert len(np.unique(png.reshape(-1, 3), axis=0)) > 500
    red = (png[..., 0] > 150) & (png[..., 1] < 60) & (png[..., 2] < 60)
    assert red.sum() > 50
    # notebook display
    assert img._repr_png_()[:8] == b"\x89PNG\r\n\x1a\n"


@pytest.mark.slow
def test_different_modes_give_different_images(modeset):
    from fem.render import render_mode

    size = (480, 360)
    imgs = [np.asarray(render_mode(modeset, i, window_size=size), dtype=float) for i in (0, 2, 4)]
    again = np.asarray(render_mode(modeset, 2, window_size=size), dtype=float)
    assert np.abs(again - imgs[1]).mean() < 0.5  # deterministic
    for a, b in [(0, 1), (1, 2), (0, 2)]:
        diff = np.abs(imgs[a] - imgs[b]).mean()
        assert diff > 8.0, (a, b, diff)
    # other views work and differ from the oblique one
    front = np.asarray(render_mode(modeset, 2, window_size=size, camera="front"), dtype=float)
    assert np.abs(front - imgs[1]).mean() > 8.0
    assert 0.15 < _wheel_fraction(front.astype(np.uint8)) < 0.85


@pytest.mark.slow
def test_render_modes_png_and_gif(modeset, tmp_path):
    from PIL import Image

    from fem.render import render_modes

    paths = render_modes(
        modeset,
        tmp_path / "out",
        indices=[2],
        gif=True,
        frames=8,
        window_size=(480, 360),
        gif_window_size=(320, 240),
    )
    assert [p.name for p in paths] == ["mode_02_n3_c0_axial.png", "mode_02_n3_c0_axial.gif"]
    assert Image.open(paths[0]).size == (480, 360)
    gif = Image.open(paths[1])
    assert gif.size == (320, 240) and gif.n_frames == 8
    frames = []
    for k in (0, 4):
        gif.seek(k)
        frames.append(np.asarray(gif.convert("RGB"), dtype=float))
    assert np.abs(frames[0] - frames[1]).mean() > 2.0  # it moves
    assert not list((tmp_path / "out").glob(".*"))  # no temp files left


def test_vtu_round_trip(modeset, tmp_path):
    import meshio

    from fem.render import mode_array_name, mode_shape, to_pyvista, write_modes_vtu

    grid = to_pyvista(modeset)
    assert grid.n_points == len(modeset.points) and grid.n_cells == len(modeset.cells["wedge"])
    name = mode_array_name(modeset, 2)
    assert name == "mode_02_n3_c0_axial_1143Hz"
    assert np.allclose(grid.point_data[name + "_mag"], np.linalg.norm(mode_shape(modeset, 2), axis=1))
    assert np.all(grid.compute_cell_sizes()["Volume"] > 0)  # wedge ordering as VTK expects

    path = write_modes_vtu(modeset, tmp_path / "modes.vtu")
    assert not list(tmp_path.glob(".*"))
    mesh = meshio.read(path)
    assert np.allclose(mesh.points, modeset.points)
    assert np.array_equal(mesh.cells_dict["wedge"], modeset.cells["wedge"])
    expected = {mode_array_name(modeset, i) for i in range(len(modeset.modes))}
    expected |= {mode_array_name(modeset, i) + "_b" for i in range(1, len(modeset.modes))}
    assert set(mesh.point_data) == expected
    for i in range(len(modeset.modes)):
        assert np.allclose(mesh.point_data[mode_array_name(modeset, i)], mode_shape(modeset, i))
    # the pair (primary, partner) spans the same space as the solver's members
    a, b = mesh.point_data[name], mesh.point_data[name + "_b"]
    S = modeset.shapes[2].reshape(2, -1)
    P = np.stack([a.ravel(), b.ravel()])
    assert np.allclose(P @ P.T, S @ S.T)
    assert np.allclose(np.ravel(mesh.field_data["frequency_hz"]), [m.frequency_hz for m in modeset.modes])
    assert np.array_equal(np.ravel(mesh.field_data["nodal_diameters"]), [0, 2, 3, 2, 2])


def test_tetra_cells(modeset):
    """The 3-D solver's corner-node tetra meshes render too."""
    from fem.render import render_mode

    w = modeset.cells["wedge"]
    # each wedge -> 3 tets (consistent split is not needed for a picture)
    tets = np.vstack([w[:, [0, 1, 2, 3]], w[:, [1, 2, 3, 4]], w[:, [2, 3, 4, 5]]])
    ms = ModeSet(modeset.modes, modeset.points, {"tetra": tets}, modeset.shapes, "x", 0)
    img = render_mode(ms, 2, window_size=(400, 300), show_nodal_lines=False)
    assert 0.15 < _wheel_fraction(np.asarray(img)) < 0.85


def test_real_table1_mode(tmp_path):
    """The axisymmetric solver's Table 1 mode set renders (if that solver is present)."""
    import fem.axisym as axisym
    from fem.render import contact_point_index, mode_shape, render_mode
    from geometry.gmsh_mesh import mesh_profile
    from geometry.wheel_design import WheelDesign

    ms = axisym.solve_axisymmetric(WheelDesign(), mesh_profile(WheelDesign(), order=1), fmax_hz=1500.0)
    i = next(j for j, m in enumerate(ms.modes) if m.nodal_diameters == 3 and m.family == "axial")
    k = contact_point_index(ms)
    assert mode_shape(ms, i)[k, 2] ** 2 == pytest.approx(1 / ms.modes[i].modal_mass, rel=1e-6)
    img = render_mode(ms, i, tmp_path / "n3.png", window_size=(640, 480))
    assert 0.15 < _wheel_fraction(np.asarray(img)) < 0.85
