"""The golden record: what a fixed set of requests prints and writes, so that a rebuild of
the code under them can show that no number and no file changed.

``python tests/golden.py`` runs the requests in a fresh stage cache and writes
``tests/golden_record.json``; ``tests/test_golden.py`` runs them again and compares every
file and every line printed with :func:`differences`.

What is compared, per request: the exit status, standard output and every file written.
Text (stdout, CSV, JSON, TOML, HTML, GeoJSON) is split into its words and its numbers: the
words must be the same exactly, each number the same to a relative 1e-9. An image (a PNG, or
one embedded in report.html) is compared by its pixels; a WAV by its samples; NetCDF and VTU
by every variable's values. Arrays longer than :data:`MAX_LISTED` are compared by a
fingerprint (sums, sums of absolute values and of squares over 32 blocks, extremes, 32
evenly spaced samples, compared to 1e-9) and a digest of every value to six significant
digits, rather than value by value, so that the record stays small: one value of a long
array moved by more than about 1e-6 changes the digest.

Masked, because they are not results: wall times (``[12.3 s]``, ``timings_s``), the date a
file was written, the hash of the code that wrote it (a report's ``code``, a dataset's
``code_version``: new with every commit), the folders of the run (the output folder, the
cache, the repository), and the cache's own hit and miss lists (which stage was computed
depends on the cache's layout, not on the physics). Standard error is progress and is not compared.
"""

from __future__ import annotations

import argparse
import base64
import gzip
import hashlib
import io
import json
import math
import os
import re
import subprocess
import sys
import tempfile
from collections.abc import Callable, Iterator
from pathlib import Path
from typing import Any

ROOT = Path(__file__).resolve().parents[1]
RECORD = Path(__file__).resolve().parent / "golden_record.json.gz"

#: Relative tolerance of every number: the rebuild moves code, not arithmetic, so the
#: numbers should be the same bit for bit; 1e-9 leaves room for a sum taken in another order
#: (1e-16 relative per operation) and none for a change of the physics.
REL_TOL = 1e-9
#: Arrays up to this length are kept value by value; longer ones by their fingerprint.
MAX_LISTED = 4000
BLOCKS = 32

#: (name, arguments after ``pipeline.py``): the requests the issue fixes. ``{inputs}`` is the
#: folder the generated inputs are written to, ``{out}`` the request's own result folder.
REQUESTS: tuple[tuple[str, tuple[str, ...]], ...] = (
    ("run_table1", ("run",)),
    # 40 km/h at the contact, 11.111 m/s; the angle of attack a 2.5 m wheelbase takes in a
    # 150 m curve, 2.5 / (2 x 150) rad
    (
        "stability_920_track",
        ("stability", "--design", "railway_920_track", "--speed", "11.1111", "--angle-of-attack", "0.00833"),
    ),
    (
        "run_920_track",
        ("run", "--design", "railway_920_track", "--speed", "11.1111", "--angle-of-attack", "0.00833"),
    ),
    ("curve", ("curve", "--design", "railway_920_track", "--radius", "150,300,1000", "--train-speed", "40")),
    (
        "line",
        ("line", "--design", "railway_920_track", "--line", "{inputs}/line20.csv", "--crs", "EPSG:25832"),
    ),
    ("study_stability", ("study", "{inputs}/smoke_stability.toml")),
    ("sound", ("sound",)),
    ("track", ("track", "--design", "railway_920_track")),
)

_RADII = (
    150,
    180,
    200,
    250,
    280,
    300,
    320,
    350,
    400,
    450,
    500,
    550,
    600,
    700,
    800,
    1000,
    1500,
    2000,
    3000,
    10000,
)
_SPEEDS = (40, 40, 40, 50, 50, 40, 60, 60, 60, 70, 70, 70, 80, 80, 80, 80, 100, 100, 120, 120)
_CANTS = (0, 20, 40, 60, 80, 100, 100, 120, 80, 60, 100, 80, 60, 40, 40, 20, 0, 0, 0, 0)


def write_inputs(folder: Path) -> None:
    """The line of 20 curves (with their ends' coordinates) and the stability-only copy of
    studies/smoke.toml."""
    rows = ["id,radius_m,length_m,cant_mm,train_speed_km_h,x0,y0,x1,y1"]
    x = y = 0.0
    for i, (radius, speed, cant) in enumerate(zip(_RADII, _SPEEDS, _CANTS, strict=True)):
        length = 150.0 + 10.0 * i
        x1, y1 = x + length * math.cos(0.2 * i), y + length * math.sin(0.2 * i)
        rows.append(f"c{i:02d},{radius},{length:g},{cant},{speed},{x:.1f},{y:.1f},{x1:.1f},{y1:.1f}")
        x, y = x1, y1
    (folder / "line20.csv").write_text("\n".join(rows) + "\n")
    smoke = (ROOT / "studies" / "smoke.toml").read_text()
    smoke = re.sub(r"(?m)^compute = .*$", 'compute = ["stability"]', smoke)
    smoke = re.sub(r'(?m)^base = ".*"$', f"base = {json.dumps(str(ROOT / 'designs' / 'table1.toml'))}", smoke)
    (folder / "smoke_stability.toml").write_text(smoke)


def run_requests(work: Path, progress: Callable[[str], None] = lambda s: None) -> dict[str, Any]:
    """Run every request in ``work`` (inputs, results and one fresh cache below it) and
    return the record: per request its exit status, its stdout and its files' contents."""
    inputs, cache = work / "inputs", work / "cache"
    inputs.mkdir(parents=True)
    write_inputs(inputs)
    # one thread per library: a reduction split over threads may round differently from one
    # run to the next, and the record is made and checked wherever the tests run
    threads = dict.fromkeys(
        ("OMP_NUM_THREADS", "OPENBLAS_NUM_THREADS", "MKL_NUM_THREADS", "NUMBA_NUM_THREADS"), "1"
    )
    env = dict(os.environ, WHEEL_SQUEAL_CACHE=str(cache), **threads)
    record: dict[str, Any] = {}
    for name, args in REQUESTS:
        out = work / "results" / name
        argv = [a.format(inputs=inputs) for a in args] + ["--out", str(out)]
        progress(f"golden: {name}: pipeline.py {' '.join(args)}")
        r = subprocess.run(
            [sys.executable, str(ROOT / "pipeline.py"), *argv],
            capture_output=True,
            text=True,
            cwd=ROOT,
            env=env,
            check=False,
        )
        folders = {str(out): "<OUT>", str(cache): "<CACHE>", str(inputs): "<INPUTS>", str(ROOT): "<REPO>"}
        record[name] = {
            "argv": list(args),
            "returncode": r.returncode,
            "stdout": text_content(r.stdout, folders),
            "files": {
                str(p.relative_to(out)): file_content(p, folders)
                for p in sorted(out.rglob("*"))
                if p.is_file() and p.name != ".wheel-squeal-result"  # the marker: the date it was written
            },
        }
        if r.returncode != 0:
            record[name]["stderr"] = r.stderr[-2000:]
    return record


# --- contents ------------------------------------------------------------------------------

_NUMBER = re.compile(
    r"(?<![A-Za-z_])[-+]?(?:\d+\.\d*|\.\d+|\d+)(?:[eE][-+]?\d+)?|\b(?:nan|NaN|inf|Infinity)\b"
)
_IMAGE = re.compile(r"data:image/(png|gif|jpeg);base64,([A-Za-z0-9+/=]+)")
_MASKS: tuple[tuple[re.Pattern[str], str], ...] = (
    (re.compile(r"\[\s*\d+(?:\.\d+)?\s*s\]"), "[<WALL TIME>]"),  # stdout's closing wall time
    # a report's provenance: the hash of the code that wrote it, new with every commit
    (re.compile(r'(code</td><td class="text">)[0-9a-f]{8,}'), r"\1<CODE>"),
    (re.compile(r"\d{4}-\d{2}-\d{2}[T ]\d{2}:\d{2}(?::\d{2}(?:\.\d+)?)?(?:[+-]\d{2}:?\d{2}|Z)?"), "<DATE>"),
)
#: JSON keys whose values are not results (see the module's docstring).
MASKED_KEYS = frozenset({"timings_s", "cache", "written", "wall_time_s", "elapsed_s", "code_version"})


def _mask(text: str, folders: dict[str, str]) -> str:
    for folder, token in sorted(folders.items(), key=lambda kv: -len(kv[0])):
        text = text.replace(folder, token)
    for pattern, token in _MASKS:
        text = pattern.sub(token, text)
    return text


def _image_digest(data: bytes) -> str:
    from PIL import Image

    with Image.open(io.BytesIO(data)) as image:
        frames = []
        for index in range(getattr(image, "n_frames", 1)):
            image.seek(index)
            frames.append(image.convert("RGBA").tobytes())
        return (
            f"{image.size[0]}x{image.size[1]}x{len(frames)}:" + hashlib.sha256(b"".join(frames)).hexdigest()
        )


def text_content(text: str, folders: dict[str, str]) -> dict[str, Any]:
    """Words and numbers of a text: the words (numbers replaced by ``#``, embedded images by
    their pixels' digest) and the numbers in order."""
    text = _IMAGE.sub(lambda m: "<image " + _image_digest(base64.b64decode(m.group(2))) + ">", text)
    text = _mask(text, folders)
    numbers = [float(m.group(0)) for m in _NUMBER.finditer(text)]
    words = _NUMBER.sub("#", text)
    content: dict[str, Any] = {"kind": "text", "numbers": array_content(numbers)}
    if len(words) <= 200_000:
        content["words"] = words
    else:
        content["words_sha256"] = hashlib.sha256(words.encode()).hexdigest()
        content["words_head"] = words[:2000]
    return content


def array_content(values: Any) -> dict[str, Any]:
    """An array's values (up to :data:`MAX_LISTED`) or its fingerprint."""
    import numpy as np

    a = np.asarray(values)
    if a.dtype.kind in "USO":
        flat = [str(v) for v in a.ravel()]
        return {"shape": list(a.shape), "text": flat if len(flat) <= MAX_LISTED else _sha("\n".join(flat))}
    if a.dtype.kind == "c":
        return {"real": array_content(a.real), "imag": array_content(a.imag)}
    if a.dtype.kind == "M" or a.dtype.kind == "m":
        a = a.astype("int64")
    x = a.astype(float).ravel()
    content: dict[str, Any] = {"shape": list(a.shape)}
    if x.size <= MAX_LISTED:
        content["values"] = [_number(v) for v in x]
        return content
    finite = np.isfinite(x)
    y = np.where(finite, x, 0.0)
    with np.errstate(over="ignore"):  # a fill value squared is inf, and is kept as such
        return _fingerprinted(content, x, y, finite)


def _fingerprinted(content: dict[str, Any], x: Any, y: Any, finite: Any) -> dict[str, Any]:
    import numpy as np

    blocks = np.array_split(np.abs(y), BLOCKS)
    content["fingerprint"] = {
        "not_finite": int((~finite).sum()),
        "sum": _number(y.sum()),
        "sum_abs_blocks": [_number(b.sum()) for b in blocks],
        "sum_squares_blocks": [_number((b * b).sum()) for b in blocks],
        "min": _number(y.min()),
        "max": _number(y.max()),
        "samples": [_number(v) for v in x[np.linspace(0, x.size - 1, BLOCKS).astype(int)]],
        # every value to six significant digits: one value moved by more than about 1e-6
        # changes it, which block sums over thousands of values cannot show at 1e-9
        "digest_6_digits": hashlib.sha256(np.char.mod("%.5e", x).tobytes()).hexdigest(),
    }
    return content


def _number(v: Any) -> float | str:
    v = float(v)
    return v if math.isfinite(v) else repr(v)


def _sha(text: str) -> str:
    return hashlib.sha256(text.encode()).hexdigest()


def file_content(path: Path, folders: dict[str, str]) -> dict[str, Any]:
    """A written file's content by its kind."""
    suffix = path.suffix.lower()
    if suffix in (".png", ".gif"):
        return {"kind": "image", "pixels": _image_digest(path.read_bytes())}
    if suffix == ".wav":
        from scipy.io import wavfile

        rate, samples = wavfile.read(path)
        return {
            "kind": "wav",
            "rate_hz": rate,
            "dtype": str(samples.dtype),
            "samples": array_content(samples),
        }
    if suffix == ".nc":
        return {"kind": "netcdf", **_netcdf(path, folders)}
    if suffix == ".vtu":
        return {"kind": "vtu", **_vtu(path)}
    if suffix in (".json", ".geojson"):
        data = _drop_masked(json.loads(path.read_text()))
        return text_content(json.dumps(data, indent=1), folders)
    return text_content(path.read_text(), folders)


def _drop_masked(data: Any) -> Any:
    if isinstance(data, dict):
        return {k: "<MASKED>" if k in MASKED_KEYS else _drop_masked(v) for k, v in data.items()}
    if isinstance(data, list):
        return [_drop_masked(v) for v in data]
    return data


def _netcdf(path: Path, folders: dict[str, str]) -> dict[str, Any]:
    import xarray as xr

    with xr.open_dataset(path) as ds:
        ds.load()
        return {
            "attrs": text_content(json.dumps(_drop_masked(_plain(ds.attrs)), sort_keys=True), folders),
            "variables": {
                str(name): {
                    "dims": list(var.dims),
                    "attrs": text_content(
                        json.dumps(_drop_masked(_plain(var.attrs)), sort_keys=True), folders
                    ),
                    "values": array_content(var.values),
                }
                for name, var in sorted({**ds.coords, **ds.data_vars}.items(), key=lambda kv: str(kv[0]))
            },
        }


def _plain(attrs: Any) -> Any:
    import numpy as np

    return {k: (v.tolist() if isinstance(v, np.ndarray | np.generic) else v) for k, v in attrs.items()}


def _vtu(path: Path) -> dict[str, Any]:
    import meshio

    mesh = meshio.read(path)
    return {
        "points": array_content(mesh.points),
        "cells": [{"type": c.type, "data": array_content(c.data)} for c in mesh.cells],
        "point_data": {k: array_content(v) for k, v in sorted(mesh.point_data.items())},
        "cell_data": {k: [array_content(b) for b in v] for k, v in sorted(mesh.cell_data.items())},
    }


# --- comparison ----------------------------------------------------------------------------


def differences(expected: Any, actual: Any, where: str = "") -> Iterator[str]:
    """Every place where ``actual`` differs from the ``expected`` record: a word, a number
    beyond :data:`REL_TOL`, a file or a key missing or added."""
    if isinstance(expected, dict) and isinstance(actual, dict):
        for key in sorted(set(expected) | set(actual)):
            if key not in actual:
                yield f"{where}/{key}: missing"
            elif key not in expected:
                yield f"{where}/{key}: not in the record"
            elif key == "words" and expected[key] != actual[key]:
                yield f"{where}/words: {_first_difference(expected[key], actual[key])}"
            else:
                yield from differences(expected[key], actual[key], f"{where}/{key}")
    elif isinstance(expected, list) and isinstance(actual, list):
        if len(expected) != len(actual):
            yield f"{where}: {len(actual)} entries, the record has {len(expected)}"
        else:
            for i, (e, a) in enumerate(zip(expected, actual, strict=True)):
                yield from differences(e, a, f"{where}[{i}]")
    elif isinstance(expected, float) and isinstance(actual, float | int) and not isinstance(actual, bool):
        if not math.isclose(expected, actual, rel_tol=REL_TOL, abs_tol=0.0):
            yield f"{where}: {actual!r}, the record has {expected!r}"
    elif expected != actual:
        yield f"{where}: {str(actual)[:200]!r}, the record has {str(expected)[:200]!r}"


def _first_difference(expected: str, actual: str) -> str:
    i = next((k for k, (a, b) in enumerate(zip(expected, actual)) if a != b), min(len(expected), len(actual)))
    around = slice(max(0, i - 60), i + 60)
    return f"from character {i}: {actual[around]!r}, the record has {expected[around]!r}"


def load_record(path: Path = RECORD) -> dict[str, Any]:
    with gzip.open(path, "rt") as f:
        return json.load(f)


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--out", type=Path, default=RECORD, help=f"the record (default {RECORD.name})")
    parser.add_argument("--check", action="store_true", help="compare with the record instead of writing it")
    args = parser.parse_args(argv)
    with tempfile.TemporaryDirectory(prefix="golden-") as tmp:
        record = run_requests(Path(tmp), progress=lambda s: print(s, file=sys.stderr))
    if args.check:
        found = list(differences(load_record(args.out), record))
        print("\n".join(found) or "the golden record holds")
        return 1 if found else 0
    with gzip.GzipFile(args.out, "wb", mtime=0) as f:  # mtime 0: the same record, the same bytes
        f.write(json.dumps(record, indent=1, sort_keys=True).encode())
    print(f"{args.out}: {len(record)} requests, {sum(len(r['files']) for r in record.values())} files")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
