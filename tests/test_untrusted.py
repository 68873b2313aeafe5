"""What a cache entry, a line file, an id or an option holds is untrusted input: it is
checked whole before it is used, and nothing a run writes lands outside its result folder
and its cache (docs/guide/safety.md)."""

from __future__ import annotations

import json
import os
import stat
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest
from conftest import COUPLED_PAIR_TOML, ROOT, run_cli

from wheel_squeal.result_cache import TEXT, restore_result
from wheel_squeal.runtime.stage_cache import StageCache


def _bytes(text: str) -> np.ndarray:
    return np.frombuffer(text.encode(), np.uint8)


# -- the cache: every name, type and shape of an entry checked before use ------------------
@pytest.mark.parametrize(
    "name",
    [
        "../../../../../tmp/PWNED",
        "/tmp/PWNED",
        "sub/PWNED",
        "..",
        ".hidden",
        "a\\b",
        "x\x1b]0;t\x07",
        "a\u202ecsv",
    ],
)
def test_a_kept_result_with_a_file_name_beyond_its_folder_is_corrupt(tmp_path, name):
    """A result entry planted in a shared cache (``StageCache.store``, as the docs allow)
    whose file name leaves the result folder: a corrupt entry (one warning, recomputed),
    and nothing written anywhere."""
    seen: list[str] = []
    cache = StageCache(tmp_path / "cache", warn=seen.append)
    key = {"stage": "result", "request": 1}
    cache.store(
        "result", key, {"summary.json": _bytes("{}"), name: _bytes("x"), TEXT: _bytes("VERDICT: ok\n")}
    )
    folder = tmp_path / "a" / "b" / "c" / "d" / "e" / "out"
    folder.mkdir(parents=True)
    assert restore_result(cache, key, folder, {}) is None
    assert len(seen) == 1 and "corrupt" in seen[0] and "\x1b" not in seen[0] and "\u202e" not in seen[0]
    assert [p for p in tmp_path.rglob("*") if p.is_file() and "cache" not in p.parts] == []
    assert not Path("/tmp/PWNED").exists()  # (the absolute name's own target)


@pytest.mark.parametrize("text", ["x\nVERDICT\x1b[2J: forged", "\u202eno squeal", "\xff\xfe"])
def test_a_kept_result_whose_printed_text_holds_control_characters_is_corrupt(tmp_path, text):
    seen: list[str] = []
    cache = StageCache(tmp_path / "cache", warn=seen.append)
    data = np.frombuffer(text.encode("latin-1") if text == "\xff\xfe" else text.encode(), np.uint8)
    cache.store("result", {"k": 1}, {"summary.json": _bytes("{}"), TEXT: data})
    assert restore_result(cache, {"k": 1}, tmp_path, {}) is None
    assert len(seen) == 1 and "corrupt" in seen[0]


def test_a_kept_result_as_it_was_kept_is_restored(tmp_path):
    """The check refuses only what is not a result: a plain one comes back whole."""
    cache = StageCache(tmp_path / "cache", warn=pytest.fail)
    files = {"summary.json": _bytes('{"a": 1}'), "timeseries.csv": _bytes("t,v\n0,1\n")}
    cache.store("result", {"k": 1}, {**files, TEXT: _bytes("VERDICT: squeals\n  why: it grows\n")})
    out = tmp_path / "out"
    out.mkdir()
    assert restore_result(cache, {"k": 1}, out, {"total": 0.1}) == "VERDICT: squeals\n  why: it grows\n"
    assert (out / "timeseries.csv").read_text() == "t,v\n0,1\n"
    assert json.loads((out / "summary.json").read_text())["a"] == 1


@pytest.mark.slow  # two runs of the command line (about 4 s)
def test_a_planted_result_in_a_shared_cache_writes_nothing_outside_out(tmp_path):
    """The probe's attack end to end: a run's own result entry rewritten with a file named
    ``../../../../../<somewhere>/PWNED``; the next run warns once, recomputes, exits 0."""
    mode = tmp_path / "mode.toml"
    mode.write_text(
        "[[mode]]\nfrequency_hz = 1143.4\ndamping_ratio = 9.4e-4\nlateral = 0.568\nnormal = 0.0\n"
    )
    cache_dir, out = tmp_path / "shared", tmp_path / "deep" / "er" / "out"
    args = ("run", "--modal-model", mode, "--quiet", "--cache-dir", cache_dir, "--out", out)
    assert run_cli(*args).returncode == 0
    (entry,) = (cache_dir / "result").iterdir()
    cache = StageCache(cache_dir)
    meta = json.loads(str(np.load(entry)["__meta__"]))
    arrays = cache.load("result", meta["key"])
    target = tmp_path / "PWNED"
    hostile = os.path.relpath(target, out)  # the same depth as the probe's: out of the folder
    cache.store("result", meta["key"], {**arrays, hostile: _bytes("x")})
    r = run_cli(*args)
    assert r.returncode == 0, r.stderr
    assert [ln for ln in r.stderr.splitlines() if ln.startswith("warning:")] == [
        ln for ln in r.stderr.splitlines() if "corrupt" in ln
    ]
    assert "corrupt" in r.stderr and "VERDICT" in r.stdout
    assert not target.exists()


def _mesh_arrays() -> dict[str, np.ndarray]:
    from geometry import WheelDesign
    from geometry.gmsh_mesh import mesh_profile

    return mesh_profile(WheelDesign(), size=0.02).to_arrays()


@pytest.mark.parametrize(
    ("change", "word"),
    [
        (lambda a: a.update(triangles=a["triangles"] + 10**6), "indexes beyond"),
        (lambda a: a.update(triangles=a["triangles"][:, :2]), "shape"),
        (lambda a: a.update(points=np.full_like(a["points"], np.nan)), "not finite"),
        (lambda a: a.update(points=a["points"].astype(str)), "kind"),
        (lambda a: a.update(contact_node=np.array(-1)), "indexes beyond"),
        (lambda a: a.pop("bore_nodes"), "bore_nodes"),
    ],
    ids=["index out of range", "cells cut", "NaN points", "text points", "negative node", "missing"],
)
def test_a_stored_mesh_that_is_not_a_mesh_is_refused_before_use(change, word):
    from geometry.mesh import ProfileMesh

    arrays = _mesh_arrays()
    ProfileMesh.from_arrays(dict(arrays))  # as stored: accepted
    change(arrays)
    with pytest.raises((ValueError, KeyError), match=word):
        ProfileMesh.from_arrays(arrays)


def test_a_corrupt_mesh_entry_is_recomputed_with_one_warning(tmp_path, capsys):
    """The read check runs inside the cache's load: a failing record is a corrupt entry."""
    from geometry.mesh import ProfileMesh

    seen: list[str] = []
    cache = StageCache(tmp_path / "c", warn=seen.append)
    arrays = _mesh_arrays()
    arrays["triangles"] = arrays["triangles"] + 10**6
    cache.store("mesh2d", {"k": 1}, arrays)
    from wheel_squeal.runtime.stage_cache import CacheMiss

    with pytest.raises(CacheMiss):
        cache.load("mesh2d", {"k": 1}, ProfileMesh.from_arrays)
    assert len(seen) == 1 and "corrupt" in seen[0] and "indexes beyond" in seen[0]
    assert cache.misses == ["mesh2d"]


@pytest.mark.parametrize("kind", ["fifo", "link", "folder", "huge"])
def test_an_entry_that_is_not_a_regular_file_is_never_opened(tmp_path, kind):
    """A FIFO in place of an entry would block the run until its budget; a link could
    point anywhere; a sparse file of 100 GB would fill the memory: each a corrupt entry
    at once (opened without blocking or following, checked, then read)."""
    seen: list[str] = []
    cache = StageCache(tmp_path / "c", warn=seen.append)
    cache.store("modes", {"k": 0}, {"a": np.ones(2)})  # the stage folder exists
    path = cache.path("modes", {"k": 1})
    if kind == "fifo":
        os.mkfifo(path)
    elif kind == "link":
        (tmp_path / "elsewhere.npz").write_bytes(cache.path("modes", {"k": 0}).read_bytes())
        path.symlink_to(tmp_path / "elsewhere.npz")
    elif kind == "folder":
        path.mkdir()
    else:
        with open(path, "wb") as f:
            f.truncate(100 * 2**30)
    from wheel_squeal.runtime.stage_cache import CacheMiss

    with pytest.raises(CacheMiss):
        cache.load("modes", {"k": 1})
    assert len(seen) == 1 and "corrupt" in seen[0], seen


def test_a_stored_mode_set_that_does_not_match_its_mesh_is_refused():
    from fem.modes import Mode, ModeSet

    mode = Mode(0, 100.0, 2, 0, "axial", (0.5,))
    points = np.zeros((4, 3))
    good = ModeSet([mode], points, {"tetra": np.array([[0, 1, 2, 3]])}, [np.zeros((1, 4, 3))], "3d", 12)
    ModeSet.from_arrays(good.to_arrays())
    for name, value in [
        ("cells_tetra", np.array([[0, 1, 2, 9]])),
        ("shape_0", np.zeros((1, 5, 3))),
        ("shape_0", np.full((1, 4, 3), np.inf)),
    ]:
        arrays = {**good.to_arrays(), name: value}
        with pytest.raises(ValueError):
            ModeSet.from_arrays(arrays)
    bad_meta = good.to_arrays()
    meta = json.loads(str(bad_meta["meta"]))
    meta["modes"][0]["family"] = "\x1b[31m"
    with pytest.raises(ValueError):
        ModeSet.from_arrays({**bad_meta, "meta": np.array(json.dumps(meta))})


# -- a full cache never fails a run --------------------------------------------------------
def _mount_tmpfs(folder: Path, size: str) -> bool:
    folder.mkdir()
    if os.geteuid() != 0:
        return False
    return (
        subprocess.run(["mount", "-t", "tmpfs", "-o", f"size={size}", "tmpfs", str(folder)]).returncode == 0
    )


@pytest.mark.slow  # a fresh process compiles the kernels into the full cache (about 15 s)
def test_a_run_on_a_full_cache_exits_0_with_one_warning(tmp_path):
    """numba's compiled kernels, kept in the cache, go through its one warn-and-go-on path:
    a cache on a full disk (a 64 kB file system) gives one warning and the verdict."""
    full = tmp_path / "full"
    if not _mount_tmpfs(full, "64k"):  # the marker fits, the compiled kernels do not
        pytest.skip("a full file system needs a tmpfs mount, which needs root")
    try:
        pair = tmp_path / "pair.toml"
        pair.write_text(COUPLED_PAIR_TOML)
        r = run_cli(
            "run", "--modal-model", pair, "--quiet", "--cache-dir", full / "c", "--out", tmp_path / "out",
            env={"NUMBA_CACHE_DIR": None},
        )  # fmt: skip
        assert r.returncode == 0, r.stderr
        warnings = [ln for ln in r.stderr.splitlines() if ln.strip()]
        assert len(warnings) == 1 and "cannot be written" in warnings[0], r.stderr
        assert "VERDICT: squeals" in r.stdout
    finally:
        subprocess.run(["umount", str(full)])


# -- nothing written outside --out and the cache -------------------------------------------
def _home(tmp_path: Path) -> dict[str, str | None]:
    """An environment whose home, XDG and temporary folders are in ``tmp_path`` and in
    which the libraries' own folders are the tool's to choose."""
    home = tmp_path / "home"
    for sub in ("", "tmp", "cache", "config", "data"):
        (home / sub).mkdir(exist_ok=True)
    return {
        "HOME": str(home),
        "TMPDIR": str(home / "tmp"),
        "XDG_CACHE_HOME": str(home / "cache"),
        "XDG_CONFIG_HOME": str(home / "config"),
        "XDG_DATA_HOME": str(home / "data"),
        "NUMBA_CACHE_DIR": None,
        "MPLCONFIGDIR": None,
        "MESA_SHADER_CACHE_DIR": None,
    }


def _written(folder: Path) -> list[str]:
    return sorted(str(p.relative_to(folder)) for p in folder.rglob("*") if not p.is_dir())


def _numba_files_in_the_package() -> set[str]:
    return {str(p) for p in (ROOT / "reduced").rglob("*.nb[ic]")}


@pytest.mark.slow  # a mesh, the modes and two rendered views in a fresh process (about 7 s)
def test_a_mesh_and_a_rendering_write_nothing_outside_out_and_the_cache(tmp_path):
    env = _home(tmp_path)
    fltk = Path("/etc/fltk/fltk.org/fltk.prefs")
    fltk_before = fltk.exists()
    r = run_cli(
        "render", "--design", "table1", "--modes", "0", "--quiet",
        "--cache-dir", tmp_path / "cache", "--out", tmp_path / "out", env=env,
    )  # fmt: skip
    assert r.returncode == 0, r.stderr
    assert _written(tmp_path / "home") == []  # no ~/.fltk, ~/.cache/mesa_shader_cache, matplotlib
    assert fltk.exists() == fltk_before
    assert (tmp_path / "cache" / "libraries" / "mesa").is_dir()
    assert _written(tmp_path / "out") == [".wheel-squeal-result", "mode_00_n1_c0_axial.png"]


@pytest.mark.slow  # the squeal model's kernels compiled in a fresh process (about 11 s)
def test_a_run_without_cache_keeps_the_compiled_kernels_in_a_removed_temporary_folder(tmp_path):
    env = _home(tmp_path)
    before = _numba_files_in_the_package()
    pair = tmp_path / "pair.toml"
    pair.write_text(COUPLED_PAIR_TOML)
    r = run_cli("run", "--modal-model", pair, "--quiet", "--no-cache", "--out", tmp_path / "out", env=env)
    assert r.returncode == 0, r.stderr
    assert _numba_files_in_the_package() == before  # never beside the installed package
    assert _written(tmp_path / "home") == []  # the temporary folder (in TMPDIR) is removed
    assert "report.html" in _written(tmp_path / "out")


def test_the_libraries_folders_are_the_caches_or_one_temporary_folder(tmp_path, monkeypatch):
    from wheel_squeal.runtime.library_folders import LIBRARY_FOLDERS, keep_library_files

    for _module, variable, _name in LIBRARY_FOLDERS.values():
        monkeypatch.delenv(variable, raising=False)
    monkeypatch.delitem(sys.modules, "vtkmodules", raising=False)  # as in a fresh process
    chosen = keep_library_files(StageCache(tmp_path / "c"))
    assert chosen.temporary is None
    assert chosen.folders["mesa"] == tmp_path / "c" / "libraries" / "mesa"
    assert os.environ["MESA_SHADER_CACHE_DIR"] == str(tmp_path / "c" / "libraries" / "mesa")
    monkeypatch.delenv("MESA_SHADER_CACHE_DIR")
    chosen = keep_library_files(StageCache(tmp_path / "c", enabled=False))
    assert chosen.temporary is not None and chosen.folders["mesa"].parent == chosen.temporary
    chosen.remove()
    assert not os.path.lexists(os.environ["MESA_SHADER_CACHE_DIR"])
    assert stat.S_ISDIR(os.lstat(tmp_path / "c" / "libraries").st_mode)


# -- a line's files and options validated whole, before the work ---------------------------
HEADER = "id,radius_m,length_m,cant_mm,train_speed_km_h,wkt\n"
LINE = ("line", "--design", "railway_920_track", "--quiet")


def _line_refused(tmp_path: Path, text: str | bytes, *more: str, word: str) -> str:
    """``line`` on a LINE.csv of ``text``: one line naming ``word``, exit 2, no folder."""
    from conftest import one_line_error, run_here

    path = tmp_path / "line.csv"
    path.write_bytes(text if isinstance(text, bytes) else text.encode())
    out = tmp_path / "deep" / "out"
    r = run_here(*LINE, "--line", path, "--out", out, *more)
    assert r.returncode == 2, (r.returncode, r.stderr)
    line = one_line_error(r)
    assert word in line, line
    assert not (tmp_path / "deep").exists()  # no parent folder left either
    return line


@pytest.mark.parametrize(
    ("text", "word"),
    [
        (HEADER.replace("\n", "\r") + "a,300,100,0,40,\r" * 3, "--max-seconds"),  # counted: 3 rows
        (
            HEADER + 'a,300,100,0,40,"LINESTRING (' + ", ".join(f"{i} 0" for i in range(30_000)) + ')"\n',
            "cell",
        ),
        (HEADER + 'a,300,100,0,40,"LINESTRING (0 0, nan 1)"\n', "finite"),
        (HEADER + 'a,300,100,0,40,"LINESTRING (0 0, 1e400 1)"\n', "finite"),
        (HEADER + 'a,300,100,0,40,"LINESTRING (0 0)"\n', "two or more"),
        ("id,radius_m,length_m,cant_mm,train_speed_km_h,radius_m\na,300,100,0,40,500\n", "named twice"),
        (HEADER + "a,300,100,0,40,,7\n", "7 cells"),
        ("id,radius_m,length_m,cant_mm,train_speed_km_h,x0,y0,x1,y1\na,300,100,0,40,1,2,,\n", "go together"),
        (HEADER + '"x\nVERDICT: no squeal anywhere",300,100,0,40,\n', "printable"),
        (HEADER + "\x1b]0;x\x07,300,100,0,40,\n", "printable"),
        (HEADER + "a\u202eb,300,100,0,40,\n", "printable"),
        (HEADER + "a,300,100,1e300,40,\n", "cant"),
        (HEADER + "a,300,100,nan,40,\n", "finite"),
        (HEADER + "a,300,100,0,1e-9,\n", "train speed"),
    ],
    ids=[
        "CR newlines",
        "cell over the field limit",
        "NaN coordinate",
        "1e400 coordinate",
        "one-point LineString",
        "repeated column",
        "extra cell",
        "partial coordinates",
        "newline in an id",
        "escape sequence in an id",
        "bidi in an id",
        "cant 1e300",
        "cant nan",
        "creeping train",
    ],
)
def test_a_line_file_that_is_not_a_line_is_refused_with_its_row(tmp_path, text, word):
    more = ("--max-seconds", "1") if word == "--max-seconds" else ()
    line = _line_refused(tmp_path, text, *more, word=word)
    assert "\x1b" not in line and "\u202e" not in line and "VERDICT" not in line.split(":", 1)[0]
    assert "or raise" not in line or not line.split("; ")[-1].startswith(", or")


def test_a_line_file_with_a_byte_order_mark_is_read(tmp_path):
    from track.alignment import read_line

    path = tmp_path / "line.csv"
    path.write_text("\ufeff" + HEADER.replace("\n", "\r\n") + "R1,300,100,0,40,\r\n", encoding="utf-8")
    (curve,) = read_line(path)
    assert (curve.id, curve.radius_m) == ("R1", 300.0)
    path.write_text(HEADER.replace("\n", "\r") + "R1,300,100,0,40,\rR2,400,100,0,40,\r")
    assert [c.id for c in read_line(path)] == ["R1", "R2"]


@pytest.mark.parametrize(
    ("traffic", "word"),
    [
        ("line = 5\n", "is a table"),
        ("[line]\nfriction_weights = [1e308, 1e308, 1e308, 1e308]\n", "finite sum"),
        ("[line]\nfriction_weights = [inf, 1.0, 1.0, 1.0]\n", "finite"),
        ("[line]\nfriction_weights = [-1.0, 1.0, 1.0, 1.0]\n", "0 or more"),
    ],
    ids=["line = 5", "overflowing weights", "infinite weight", "negative weight"],
)
def test_a_traffic_file_that_is_not_one_is_refused(tmp_path, traffic, word):
    (tmp_path / "traffic.toml").write_text(traffic)
    _line_refused(
        tmp_path, HEADER + "a,300,100,0,40,\n", "--traffic", str(tmp_path / "traffic.toml"), word=word
    )


@pytest.mark.parametrize(
    ("crs", "word"),
    [
        ("not a crs", "pyproj knows"),
        ("EPSG:999999", "pyproj knows"),
        ("<b>EPSG</b>", "pyproj knows"),
        ("\x1b]0;x\x07", "a coordinate system's name"),
        ("EPSG:4326", "not projected"),
    ],
)
def test_a_crs_that_is_not_a_projected_one_is_refused(tmp_path, crs, word):
    line = _line_refused(
        tmp_path, HEADER + 'a,300,100,0,40,"LINESTRING (0 0, 1 1)"\n', "--crs", crs, word=word
    )
    assert "\x1b" not in line


def test_a_named_crs_is_written_as_its_authority_names_it():
    from wheel_squeal.cli.line_command import projected_crs

    assert projected_crs("EPSG:25832") == "EPSG:25832"
    assert projected_crs("epsg:2154") == "EPSG:2154"


@pytest.mark.slow  # 2 million positions parsed before the count passes its bound (about 6 s)
def test_a_line_whose_geojson_would_be_over_the_file_limit_is_refused_before_the_work(tmp_path):
    """The probe's 63.7 MiB LINE.csv of long WKT wrote a 255.6 MB line.geojson at 2.17 GB:
    its positions are counted before they are parsed (``track.alignment.MAX_LINE_POSITIONS``,
    which keeps the file within its limit; line.geojson's own price is checked too)."""
    cell = '"LINESTRING (' + ",".join(["0 0"] * 32_000) + ')"'  # each cell within the csv limit
    rows = "".join(f"c{i},300,100,0,40,{cell}\n" for i in range(520))
    assert len(cell) < 131_072 and len(HEADER + rows) < 64 * 2**20  # within the file limit
    _line_refused(tmp_path, HEADER + rows, "--max-seconds", "1000000", word="positions")
    from wheel_squeal.present.line_files import geojson_bytes

    assert geojson_bytes([]) == 0


def test_the_geojson_price_bounds_what_is_written():
    """The price is at least the file: positions at their repr, every property at the
    longest a number or an id takes (here all at the longest float repr)."""
    from track.alignment import LineCurve
    from wheel_squeal.present.line_files import geojson_bytes, line_columns

    curves = [
        LineCurve(f"c{i}", 300.0, 100.0, 0.0, 40.0, ((1e5 + i / 3, 2e5), (1.0, -i / 7))) for i in range(50)
    ]
    feature = {
        "type": "Feature",
        "geometry": {"type": "LineString", "coordinates": [[1e5 + 1 / 3, 2e5], [1.0, -1 / 7]]},
        "properties": {name: -1.2345678901234567e-300 for name in line_columns()},
    }
    written = json.dumps({"type": "FeatureCollection", "features": [feature] * len(curves)})
    assert len(written) <= geojson_bytes(curves) <= 3 * len(written)  # a bound, not a guess


@pytest.mark.parametrize("kind", ["fifo", "folder", "huge"])
def test_a_line_argument_that_is_not_a_file_is_named_so_in_seconds(tmp_path, kind):
    """A FIFO would block, a folder is no line, a 20 GiB sparse file was counted line by
    line for 32 s before its size was checked: each refused from its ``stat``."""
    import time

    from conftest import one_line_error, run_here

    path = tmp_path / "line.csv"
    if kind == "fifo":
        os.mkfifo(path)
    elif kind == "folder":
        path.mkdir()
    else:
        with open(path, "wb") as f:
            f.truncate(20 * 2**30)
    t0 = time.perf_counter()
    r = run_here(*LINE, "--line", path, "--out", tmp_path / "out")
    assert r.returncode == 2, r.stderr
    line = one_line_error(r)
    assert {"fifo": "pipe", "folder": "a folder", "huge": "MiB"}[kind] in line, line
    assert time.perf_counter() - t0 < 5.0  # the bound: seconds, whatever its size


def test_a_mode_argument_naming_a_huge_file_is_not_read(tmp_path):
    """``run --mode <a 2 GiB file>`` read the file whole to hash it into the result's key:
    only the parser's file arguments are hashed, and only regular files within the size
    read."""
    from wheel_squeal.result_cache import result_key

    huge = tmp_path / "huge"
    with open(huge, "wb") as f:
        f.truncate(2 * 2**30)
    key = result_key("run", {"mode": str(huge), "design": huge, "modal_model": None}, "h")
    assert key["arguments"]["mode"] == str(huge) and key["arguments"]["design"] == str(huge)
    small = tmp_path / "small.toml"
    small.write_text("x = 1\n")
    assert result_key("run", {"design": small}, "h")["arguments"]["design"]["sha256"]


def test_formula_ids_are_neutralised_in_every_csv(tmp_path):
    from wheel_squeal.outputs import write_csv

    rows = [{"id": v, "x": 1.5} for v in ('=HYPERLINK("http://x")', "+A1", "-A", "@SUM(A1)", "-12.5", "R1")]
    write_csv(tmp_path / "t.csv", rows, ["id", "x"])
    cells = [ln.split(",")[0] for ln in (tmp_path / "t.csv").read_text().splitlines()[1:]]
    assert cells == ['"\'=HYPERLINK(""http://x"")"', "'+A1", "'-A", "'@SUM(A1)", "-12.5", "R1"]


def test_out_and_the_cache_apart_is_checked_before_the_work(tmp_path):
    from conftest import one_line_error, run_here

    for out in (tmp_path / "c", tmp_path / "c" / "in", tmp_path):
        r = run_here("line", "--design", "railway_920_track", "--line", tmp_path / "none.csv",
                     "--cache-dir", tmp_path / "c", "--out", out)  # fmt: skip
        assert r.returncode == 2
        assert "cache folder" in one_line_error(r) or "line not found" in one_line_error(r)
    r = run_here("curve", "--design", "railway_920_track", "--radius", "300", "--train-speed", "40",
                 "--cache-dir", tmp_path / "c", "--out", tmp_path / "c" / "in")  # fmt: skip
    assert r.returncode == 2 and "lies inside the cache folder" in one_line_error(r)


def test_a_grid_radius_tighter_than_a_curve_keeps_the_curves_own():
    from wheel_squeal.line import LineSpec

    spec = LineSpec(radius_step=0.5)
    assert spec.grid_radius_m(52.0) == 52.0  # the grid's 44.4 m is no curve
    assert spec.grid_radius_m(140.0) == 150.0


@pytest.mark.parametrize(
    ("cant", "word"), [("nan", "--cant"), ("inf", "--cant"), ("1e300", "200 mm"), ("-400", "200 mm")]
)
def test_a_curve_cant_that_is_not_a_track_s_is_refused_in_one_line(tmp_path, cant, word):
    """``curve --cant nan`` was a traceback in the contact table; 1e300 a 150-digit speed."""
    from conftest import one_line_error, run_here

    args = ("curve", "--design", "railway_920_track", "--quiet", "--radius", "300", "--train-speed", "40")
    r = run_here(*args, f"--cant={cant}", "--out", tmp_path / "a" / "out")
    assert r.returncode == 2, r.stderr
    line = one_line_error(r)
    assert word in line and len(line) < 200, line
    assert not (tmp_path / "a").exists()


def test_a_refusal_without_a_remedy_of_its_own_names_only_the_setting():
    from wheel_squeal.runtime.budget import or_raise

    assert or_raise("", "max_seconds", "ENV") == "raise max_seconds (ENV)"
    assert or_raise("ask for less", "max_seconds", "ENV") == "ask for less, or raise max_seconds (ENV)"
