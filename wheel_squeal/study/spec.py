"""A study specification (TOML) and the cases it makes.

::

    name = "smoke"
    base = "../designs/table1.toml"     # relative to the spec; default: the Table 1 wheel
    fidelity = "fast"                   # FE preset of every design
    fmax = 3000.0                       # modes up to [Hz]
    compute = ["stability", "limit_cycle", "sound"]

    [grid]                              # a grid over design parameters ([wheel], [material], ...)
    web_thickness = [0.012, 0.015]
    rim_depth = { start = 0.030, stop = 0.036, num = 4 }
    wear = { start = 0.0, stop = 0.005, num = 6, add = { rolling_radius = -1.0, rim_depth = -1.0 } }

    [samples]                           # or random samples (a tolerance study)
    n = 100
    seed = 1
    rim_depth = { normal = [0.0335, 0.0005] }        # mean, standard deviation
    web_thickness = { uniform = [0.0145, 0.0155] }   # low, high

    [operating]
    crab_velocity = [0.1, 0.3, 0.5]     # m/s
    rpm = [400, 800]

A plain entry sets the design field; ``add`` makes a named dimension whose value times
each coefficient is added to those fields of the base (wear: the rolling radius and the
rim depth shrink together). Every key is checked; unknown keys are errors.
"""

from __future__ import annotations

import hashlib
import itertools
import json
import math
import re
from dataclasses import dataclass
from pathlib import Path
from typing import Any, cast

import numpy as np

from geometry import SECTIONS, DesignError
from geometry.files import check_label, read_toml

from ..design import FIELDS, Design
from ..presets import DEFAULT_CRAB_VELOCITY_M_S, DEFAULT_DESIGN, DEFAULT_RPM, FIDELITIES
from ..runtime.request_errors import RequestError
from ..types import FidelityName
from .task import RESULT_FIELDS

__all__ = ["COMPUTE", "Case", "Dimension", "StudySpec", "load_spec"]

#: What a study may compute per design (modes are always computed).
COMPUTE = ("stability", "limit_cycle", "sound")
_TOP = {"name", "description", "base", "fidelity", "fmax", "compute", "grid", "samples", "operating"}
_DESIGN_FIELDS = set(FIELDS)
#: Most points of one axis, designs of one study, and operating points per design:
#: refused before anything is made (a typo like num = 1e9 must not allocate first).
MAX_AXIS_POINTS = 100_000
MAX_CASES = 1_000_000
MAX_OPERATING_POINTS = 10_000
#: The names of the results' own variables and coordinates (:mod:`.dataset`): no
#: dimension may take one.
RESERVED_NAMES = frozenset(
    {"sample", "crab_velocity", "rpm", "status", "reason", "mass_kg", "modes", "squeal_mode", *RESULT_FIELDS}
)
_NAME = re.compile(r"[A-Za-z_][A-Za-z0-9_]*")


@dataclass(frozen=True)
class Dimension:
    """One varied quantity: ``name``; ``values`` (a grid axis; empty for samples);
    ``add`` ((field, coefficient), ...) for an offset dimension, empty when the value
    sets the field ``name`` itself."""

    name: str
    values: tuple[float, ...] = ()
    add: tuple[tuple[str, float], ...] = ()
    distribution: tuple[str, float, float] | None = None  # samples: (normal|uniform, a, b)


@dataclass(frozen=True)
class Case:
    """One design of a study: its position (index per dimension, or the sample number),
    the values of the varied quantities and the design changes they make."""

    index: tuple[int, ...]
    values: tuple[float, ...]
    changes: tuple[tuple[str, float], ...]


@dataclass(frozen=True)
class StudySpec:
    name: str
    description: str
    base: Design
    fidelity: FidelityName
    fmax_hz: float
    compute: tuple[str, ...]
    dimensions: tuple[Dimension, ...]
    samples: int  # 0 for a grid study
    seed: int
    crabbing_velocities_m_s: tuple[float, ...]
    rpm: tuple[float, ...]
    source: str = ""  # the spec's text, for provenance

    @property
    def kind(self) -> str:
        return "samples" if self.samples else "grid"

    @property
    def n_cases(self) -> int:
        """The number of designs (without making them)."""
        return self.samples or math.prod(len(d.values) for d in self.dimensions)

    @property
    def n_points(self) -> int:
        """The number of operating points per design."""
        return len(self.crabbing_velocities_m_s) * len(self.rpm)

    def cases(self) -> list[Case]:
        """Every design of the study, in a fixed order (grid: C order over the
        dimensions; samples: by sample number, drawn with ``seed``)."""
        out = []
        if self.samples:
            rng = np.random.default_rng(self.seed)
            draws = []
            for d in self.dimensions:  # one stream, dimension after dimension: reproducible
                assert d.distribution is not None  # a sampled study's dimensions have one
                kind, a, b = d.distribution
                draws.append(
                    rng.normal(a, b, self.samples) if kind == "normal" else rng.uniform(a, b, self.samples)
                )
            for s in range(self.samples):
                values = tuple(float(x[s]) for x in draws)
                out.append(Case((s,), values, self._changes(values)))
            return out
        for idx in itertools.product(*(range(len(d.values)) for d in self.dimensions)):
            values = tuple(d.values[i] for d, i in zip(self.dimensions, idx))
            out.append(Case(tuple(idx), values, self._changes(values)))
        return out

    def _changes(self, values: tuple[float, ...]) -> tuple[tuple[str, float], ...]:
        """Plain dimensions set their field; ``add`` dimensions then add their offsets."""
        sets: dict[str, float] = {}
        offsets: dict[str, float] = {}
        for d, v in zip(self.dimensions, values):
            if not d.add:
                sets[d.name] = float(v)
            for f, c in d.add:
                offsets[f] = offsets.get(f, 0.0) + c * float(v)
        fields_ = set(sets) | set(offsets)
        return tuple(
            sorted(
                (f, (sets[f] if f in sets else float(self.base.get(f))) + offsets.get(f, 0.0))
                for f in fields_
            )
        )

    def digest(self) -> str:
        """What the results depend on (not the name or description), 16 hex chars."""
        payload = {
            "base": self.base.content_hash(),
            "fidelity": self.fidelity,
            "fmax": self.fmax_hz,
            "compute": self.compute,
            "vc": self.crabbing_velocities_m_s,
            "rpm": self.rpm,
        }
        return hashlib.sha256(json.dumps(payload, sort_keys=True).encode()).hexdigest()[:16]


def _num(v: Any, what: str, src: str) -> float:
    if isinstance(v, bool) or not isinstance(v, int | float) or not math.isfinite(v):
        raise RequestError(f"{src}: {what} must be a finite number, got {v!r}")
    return float(v)


def _axis(v: Any, what: str, src: str) -> tuple[float, ...]:
    """A list of numbers or {start, stop, num}."""
    if isinstance(v, list):
        if not v:
            raise RequestError(f"{src}: {what} is empty")
        return tuple(_num(x, what, src) for x in v)
    if isinstance(v, dict) and {"start", "stop", "num"} <= set(v):
        extra = set(v) - {"start", "stop", "num"}
        if extra:
            raise RequestError(
                f"{src}: {what}: unknown key(s) {sorted(extra)}; an axis is {{start, stop, num}}"
            )
        n = v["num"]
        if isinstance(n, bool) or not isinstance(n, int) or not 1 <= n <= MAX_AXIS_POINTS:
            raise RequestError(
                f"{src}: {what}: num must be an integer from 1 to {MAX_AXIS_POINTS}, got {n!r}"
            )
        a, b = _num(v["start"], what, src), _num(v["stop"], what, src)
        return tuple(float(x) for x in np.linspace(a, b, n))
    raise RequestError(f"{src}: {what} must be a list of numbers or {{start, stop, num}}")


def _add(v: Any, what: str, src: str) -> tuple[tuple[str, float], ...]:
    if not isinstance(v, dict) or not v:
        raise RequestError(f"{src}: {what}: add must be a table of design field = coefficient")
    for k in v:
        if k not in _DESIGN_FIELDS:
            raise RequestError(f"{src}: {what}: add: {k!r} is not a design parameter")
    return tuple(sorted((k, _num(c, f"{what}.add.{k}", src)) for k, c in v.items()))


def _check_name(name: str, where: str, src: str) -> None:
    """A dimension's name becomes a coordinate of the results: a plain identifier that
    is not one of theirs."""
    if not _NAME.fullmatch(name):
        raise RequestError(
            f"{src}: {where} {name!r}: a name is letters, digits and _ (not starting with a digit)"
        )
    if name in RESERVED_NAMES or name.startswith("design_"):
        raise RequestError(
            f"{src}: {where} {name!r} is a name the results use ({', '.join(sorted(RESERVED_NAMES))}, "
            "design_*): choose another"
        )


def _grid(table: Any, src: str) -> tuple[Dimension, ...]:
    if not isinstance(table, dict) or not table:
        raise RequestError(f"{src}: [grid] must be a table of parameters")
    dims = []
    for name, v in table.items():
        _check_name(name, "[grid]", src)
        add: tuple[tuple[str, float], ...] = ()
        if isinstance(v, dict) and "add" in v:
            add = _add(v["add"], name, src)
            v = {k: x for k, x in v.items() if k != "add"}
            extra = set(v) - {"start", "stop", "num", "values"}
            if extra:
                raise RequestError(f"{src}: [grid] {name}: unknown key(s) {sorted(extra)}")
            v = v["values"] if "values" in v else v
        elif name not in _DESIGN_FIELDS:
            raise RequestError(
                f"{src}: [grid] {name!r} is not a design parameter (give add = {{...}} for a combined one)"
            )
        dims.append(Dimension(name, _axis(v, f"[grid] {name}", src), add))
    return tuple(dims)


def _samples(table: Any, src: str) -> tuple[int, int, tuple[Dimension, ...]]:
    if not isinstance(table, dict):
        raise RequestError(f"{src}: [samples] must be a table")
    n, seed = table.get("n"), table.get("seed", 0)
    if isinstance(n, bool) or not isinstance(n, int) or not 1 <= n <= 1_000_000:
        raise RequestError(f"{src}: [samples] n must be an integer from 1 to 1000000, got {n!r}")
    if isinstance(seed, bool) or not isinstance(seed, int) or seed < 0:
        raise RequestError(f"{src}: [samples] seed must be a non-negative integer, got {seed!r}")
    dims = []
    for name, v in table.items():
        if name in ("n", "seed"):
            continue
        _check_name(name, "[samples]", src)
        ok = (
            isinstance(v, dict)
            and len(set(v) & {"normal", "uniform"}) == 1
            and set(v) <= {"normal", "uniform", "add"}
        )
        if not ok:
            raise RequestError(
                f"{src}: [samples] {name} must be {{normal = [mean, std]}} or {{uniform = [low, high]}}"
            )
        kind = "normal" if "normal" in v else "uniform"
        pair = v[kind]
        if not (isinstance(pair, list) and len(pair) == 2):
            raise RequestError(f"{src}: [samples] {name}: {kind} takes two numbers")
        a, b = (_num(x, f"[samples] {name}", src) for x in pair)
        if (kind == "normal" and b < 0) or (kind == "uniform" and b < a):
            raise RequestError(f"{src}: [samples] {name}: {kind} = [{a:g}, {b:g}] is not a distribution")
        add = _add(v["add"], name, src) if "add" in v else ()
        if not add and name not in _DESIGN_FIELDS:
            raise RequestError(f"{src}: [samples] {name!r} is not a design parameter")
        dims.append(Dimension(name, (), add, (kind, a, b)))
    if not dims:
        raise RequestError(f"{src}: [samples] varies nothing")
    return n, seed, tuple(dims)


def load_spec(path: str | Path) -> StudySpec:
    """Read and check a study specification (see the module docstring)."""
    path = Path(path)
    src = str(path)
    text, data = read_toml(path, "study spec", RequestError)
    unknown = set(data) - _TOP
    if unknown:
        raise RequestError(f"{src}: unknown key(s) {sorted(unknown)}; allowed: {', '.join(sorted(_TOP))}")
    if "base" in data and not isinstance(data["base"], str):
        raise RequestError(f"{src}: base must be a design file's path (a string), got {data['base']!r}")
    base_path = Path(data["base"]) if "base" in data else DEFAULT_DESIGN
    if not base_path.is_absolute() and "base" in data:
        base_path = path.parent / base_path
    try:
        base = Design.from_toml(base_path)
    except DesignError as exc:
        raise RequestError(f"{src}: base design: {exc}") from None
    fidelity = data.get("fidelity", "fast")
    if fidelity not in FIDELITIES:
        raise RequestError(f"{src}: fidelity must be one of {', '.join(FIDELITIES)}, got {fidelity!r}")
    fmax = _num(data.get("fmax", 3000.0), "fmax", src)
    if fmax <= 0:
        raise RequestError(f"{src}: fmax must be positive")
    compute = data.get("compute", list(COMPUTE))
    if not isinstance(compute, list) or not set(compute) <= set(COMPUTE):
        raise RequestError(f"{src}: compute must be a list from {', '.join(COMPUTE)}")
    compute = tuple(c for c in COMPUTE if c in compute)
    if ("limit_cycle" in compute or "sound" in compute) and "stability" not in compute:
        compute = ("stability",) + compute  # the limit cycle is the fastest mode's
    if "sound" in compute and "limit_cycle" not in compute:
        raise RequestError(f"{src}: sound needs limit_cycle (the level scales with the amplitude)")
    if ("grid" in data) == ("samples" in data):
        raise RequestError(f"{src}: give either [grid] or [samples]")
    if "grid" in data:
        n, seed, dims = 0, 0, _grid(data["grid"], src)
    else:
        n, seed, dims = _samples(data["samples"], src)
    if base.wheel.is_outline:  # an outline's [wheel] values follow from its points
        varied = {d.name for d in dims if not d.add} | {f for d in dims for f, _ in d.add}
        fixed = sorted(varied & set(SECTIONS["wheel"]))
        if fixed:
            raise RequestError(
                f"{src}: the base design {base.name!r} is an outline: {', '.join(fixed)} cannot be varied "
                "(vary material, contact or damping, or give a parametric base)"
            )
    absent = sorted({f for d in dims for f, _ in d.add if base.get(f) is None})
    if absent:
        raise RequestError(
            f"{src}: add offsets {', '.join(absent)}, which the base design {base.name!r} does not set "
            "(give the field's values in [grid] instead)"
        )
    op = data.get("operating", {})
    if not isinstance(op, dict) or set(op) - {"crab_velocity", "rpm"}:
        raise RequestError(f"{src}: [operating] takes crab_velocity and rpm")
    vcs = _axis(op.get("crab_velocity", [DEFAULT_CRAB_VELOCITY_M_S]), "[operating] crab_velocity", src)
    rpms = _axis(op.get("rpm", [DEFAULT_RPM]), "[operating] rpm", src)
    if min(rpms) <= 0:
        raise RequestError(f"{src}: [operating] rpm must be positive")
    n_cases = n if n else math.prod(len(d.values) for d in dims)
    if n_cases > MAX_CASES:
        raise RequestError(f"{src}: {n_cases:,} designs is more than a study takes ({MAX_CASES:,})")
    if len(vcs) * len(rpms) > MAX_OPERATING_POINTS:
        raise RequestError(
            f"{src}: {len(vcs):,} x {len(rpms):,} operating points is more than a study takes "
            f"({MAX_OPERATING_POINTS:,} per design)"
        )
    name = check_label(data.get("name", path.stem), f"{src}: the study's name", RequestError)
    return StudySpec(
        name=name,
        description=str(data.get("description", "")),
        base=base,
        fidelity=cast(FidelityName, fidelity),  # one of FIDELITIES: checked above
        fmax_hz=fmax,
        compute=compute,
        dimensions=dims,
        samples=n,
        seed=seed,
        crabbing_velocities_m_s=vcs,
        rpm=rpms,
        source=text,
    )
