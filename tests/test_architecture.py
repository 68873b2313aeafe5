"""The layering promises, checked on the source: data flows one way, no import cycles,
no module uses another's private names, the entry point stays thin, and a command that
needs no FE imports none of the FE libraries."""

from __future__ import annotations

import ast
import re
import subprocess
import sys
from pathlib import Path

from conftest import PIPELINE, ROOT, TABLE1_MODE_ARGS

from wheel_squeal.runtime.provenance import CODE_PACKAGES

#: What each top-level package may import of the project (anything else is "upward").
ALLOWED = {
    "geometry": set(),
    "contact": {"geometry"},  # a contact's frame and profiles on the wheel's outline
    "reduced": {"contact"},
    "fem": {"geometry", "contact"},  # the modes read at a contact's frame
    "acoustics": {"geometry"},
    "track": {"geometry", "contact", "reduced"},  # a wheel's running surface; each contact's mechanics
    "designs": set(),
    "wheel_squeal": {"geometry", "contact", "fem", "reduced", "acoustics", "track", "designs"},
    "pipeline": {"wheel_squeal"},
}
PACKAGES = (*CODE_PACKAGES, "designs")


def _modules() -> dict[str, Path]:
    out = {"pipeline": PIPELINE}
    for pkg in PACKAGES:
        for f in sorted((ROOT / pkg).rglob("*.py")):
            parts = f.relative_to(ROOT).with_suffix("").parts
            name = ".".join(parts[:-1] if parts[-1] == "__init__" else parts)
            out[name] = f
    return out


def _imports(name: str, path: Path, modules: dict[str, Path]) -> list[tuple[str, list[str]]]:
    """(imported project module, names imported from it) for every import in the file,
    at module level or inside functions."""
    is_pkg = path.name == "__init__.py"
    out = []
    for node in ast.walk(ast.parse(path.read_text())):
        if isinstance(node, ast.Import):
            out += [(a.name, []) for a in node.names]
        elif isinstance(node, ast.ImportFrom):
            if node.level:
                base = name.split(".") if is_pkg else name.split(".")[:-1]
                base = base[: len(base) - node.level + 1]
                target = ".".join(base + ([node.module] if node.module else []))
            else:
                target = node.module or ""
            names = [a.name for a in node.names]
            out += [(f"{target}.{n}", []) for n in names if f"{target}.{n}" in modules]
            rest = [n for n in names if f"{target}.{n}" not in modules]
            if rest:
                out.append((target, rest))
    return [(t, n) for t, n in out if t.split(".")[0] in ALLOWED]


def _graph():
    modules = _modules()
    return modules, {name: _imports(name, path, modules) for name, path in modules.items()}


def test_no_upward_imports():
    _, graph = _graph()
    bad = [
        (m, t)
        for m, deps in graph.items()
        for t, _ in deps
        if t.split(".")[0] != m.split(".")[0] and t.split(".")[0] not in ALLOWED[m.split(".")[0]]
    ]
    assert bad == [], f"imports against the data flow: {bad}"


def test_no_import_cycles():
    modules, graph = _graph()
    edges = {
        m: {t if t in modules else t.rsplit(".", 1)[0] for t, _ in deps} & set(modules) - {m}
        for m, deps in graph.items()
    }
    state: dict[str, int] = {}

    def visit(m: str, path: list[str]) -> list[str] | None:
        state[m] = 1
        for t in sorted(edges[m]):
            if state.get(t) == 1:
                return path + [t]
            if t not in state and (cycle := visit(t, path + [t])):
                return cycle
        state[m] = 2
        return None

    for m in sorted(modules):
        if m not in state and (cycle := visit(m, [m])):
            raise AssertionError("import cycle: " + " -> ".join(cycle))


def test_no_module_uses_another_modules_private_names():
    _, graph = _graph()
    bad = [
        (m, t, n)
        for m, deps in graph.items()
        for t, names in deps
        for n in names
        if n.startswith("_") and t != m
    ]
    assert bad == [], f"private names used across modules: {bad}"


def test_the_entry_point_is_thin_and_the_app_modules_small():
    assert len(PIPELINE.read_text().splitlines()) < 40
    big = {
        f.name: n
        for f in (ROOT / "wheel_squeal").rglob("*.py")
        if (n := len(f.read_text().splitlines())) > 420
    }
    assert big == {}, f"application modules over ~400 lines: {big}"


#: The application layer's largest share of the production code's non-blank lines: what is
#: physics or writing belongs to the physics packages and the presenters
APP_SHARE = 0.48


def test_the_application_layer_stays_a_thin_share():
    def lines(pkg: str) -> int:
        return sum(
            sum(1 for line in f.read_text().splitlines() if line.strip()) for f in (ROOT / pkg).rglob("*.py")
        )

    counts = {pkg: lines(pkg) for pkg in CODE_PACKAGES}
    share = counts["wheel_squeal"] / sum(counts.values())
    assert share <= APP_SHARE, f"wheel_squeal/ is {share:.1%} of the production lines: {counts}"


def _imported_by(*args: str, cwd: Path = ROOT) -> set[str]:
    """The modules ``python -X importtime pipeline.py ARGS`` imports (the run must end
    with status 0)."""
    r = subprocess.run(
        [sys.executable, "-X", "importtime", str(PIPELINE), *args],
        capture_output=True,
        text=True,
        timeout=300,
        cwd=cwd,
    )
    assert r.returncode == 0, r.stderr[-2000:]
    return {line.split("|")[-1].strip() for line in r.stderr.splitlines() if line.startswith("import time:")}


FE_LIBRARIES = {"skfem", "gmsh", "meshio", "pyvista", "vtk"}


def test_simulate_without_fe_imports_no_fe_library(tmp_path):
    loaded = _imported_by(
        "simulate",
        *TABLE1_MODE_ARGS,
        "--out",
        str(tmp_path / "sim"),
        "--quiet",
    )
    top = {m.split(".")[0] for m in loaded}
    assert top & FE_LIBRARIES == set()
    assert "numba" not in top  # one short run is interpreted: the compiler's load would cost more
    assert "reduced._kernels" in loaded  # the check can fail: it sees what was imported


def test_help_imports_no_heavy_library():
    top = {m.split(".")[0] for m in _imported_by("--help")}
    assert top & (FE_LIBRARIES | {"scipy", "matplotlib", "numba"}) == set()
    assert "wheel_squeal" in top


#: The numerical functions of the physics packages that solve something (an eigen-problem,
#: an ODE, a radiation problem, a root): the application layer calls each on a whole list
#: of modes or grid of points, never once per mode or point inside its own loop.
SOLVERS = {
    "linear_stability",
    "growth_rates",
    "critical_damping_ratio",
    "critical_friction_slope",
    "stability_map",
    "mitigation",
    "simulate",
    "simulate_to_limit_cycle",
    "sweep",
    "sweep_points",
    "limit_cycle",
    "predict_limit_cycle",
    "modal_content",
    "solve_modes",
    "solve_axisymmetric",
    "radiate",
    "kirchhoff_pressure",
}
#: numpy's numerical analysis (linear algebra, transforms, fits, quadrature, interpolation)
NUMPY_ANALYSIS = {"linalg", "fft", "interp", "polyfit", "gradient", "trapezoid", "trapz", "convolve", "roots"}
#: The one exception, and why: calibration drives SciPy's least squares whose objective
#: is the whole FE chain (mesh, modes, labels), which only the application layer has.
NUMERICS_ALLOWED = {("wheel_squeal/calibration.py", "scipy.optimize")}


def _numerics(rel: str, source: str) -> list[str]:
    """What breaks the rule below in one module's source."""
    found = []
    for node in ast.walk(ast.parse(source)):
        if isinstance(node, ast.Import | ast.ImportFrom):
            mods = [a.name for a in node.names] if isinstance(node, ast.Import) else [node.module or ""]
            for m in mods:
                if m.split(".")[0] in ("scipy", "numba") and (rel, m) not in NUMERICS_ALLOWED:
                    found.append(f"{rel}:{node.lineno} imports {m}")
        elif (
            isinstance(node, ast.Attribute)
            and node.attr in NUMPY_ANALYSIS
            and isinstance(node.value, ast.Name)
            and node.value.id in ("np", "numpy")
        ):
            found.append(f"{rel}:{node.lineno} uses np.{node.attr}")
        elif isinstance(
            node, ast.For | ast.While | ast.ListComp | ast.SetComp | ast.DictComp | ast.GeneratorExp
        ):
            for call in ast.walk(node):
                if isinstance(call, ast.Call):
                    fn = call.func
                    name = fn.attr if isinstance(fn, ast.Attribute) else getattr(fn, "id", None)
                    if name in SOLVERS:
                        found.append(f"{rel}:{call.lineno} calls {name} in a loop")
    return sorted(set(found))


def test_the_application_layer_has_no_numerics_of_its_own():
    """wheel_squeal orchestrates: it imports no SciPy or numba, uses none of numpy's
    numerical analysis, and calls no solver of geometry/fem/reduced/acoustics inside a
    loop or comprehension (the loop over modes or grid points belongs to the solver)."""
    found = []
    for f in sorted((ROOT / "wheel_squeal").rglob("*.py")):
        found += _numerics(str(f.relative_to(ROOT)), f.read_text())
    assert not found, "\n".join(found)


def test_the_numerics_rule_finds_what_it_forbids():
    """Not vacuous: a per-mode loop around a solver, a comprehension over grid points,
    np.linalg and a SciPy import are each found."""
    src = (
        "import scipy.linalg\n"
        "for m in modes:\n    rates.append(reduced.growth_rates([m], d, g))\n"
        "out = [simulate(dof, c, op) for op in ops]\n"
        "w = np.linalg.eigvals(a)\n"
    )
    found = _numerics("wheel_squeal/x.py", src)
    assert [f.split(" ", 1)[1] for f in found] == [
        "imports scipy.linalg",
        "calls growth_rates in a loop",
        "calls simulate in a loop",
        "uses np.linalg",
    ]


def test_every_package_is_installed():
    """A non-editable install ships only the packages pyproject.toml lists: every folder
    of the five packages that holds an ``__init__.py`` is among them."""
    import tomllib

    listed = set(tomllib.loads((ROOT / "pyproject.toml").read_text())["tool"]["setuptools"]["packages"])
    found = {
        ".".join(init.parent.relative_to(ROOT).parts)
        for top in CODE_PACKAGES
        for init in (ROOT / top).rglob("__init__.py")
    }
    assert found <= listed, sorted(found - listed)


def test_no_api_message_names_a_command_line_flag():
    """The API speaks in its own words (``max_seconds``, ``fmax_hz``, ``remedy=False``);
    the command line turns the settings it has flags for into them (``cli.in_flags``).
    Every string outside the command line and the field reference (which names the
    commands that write each file), docstrings aside, is free of ``--flag``."""
    import ast
    import re

    flag = re.compile(r"(?<![\w-])--[a-z][a-z-]+")
    hits = []
    for top in CODE_PACKAGES:
        for path in (ROOT / top).rglob("*.py"):
            rel = path.relative_to(ROOT)
            if rel.parts[:2] == ("wheel_squeal", "cli") or rel.name in ("fields.py", "output_files.py"):
                continue
            tree = ast.parse(path.read_text())
            docstrings = {
                id(node.body[0].value)
                for node in ast.walk(tree)
                if isinstance(node, ast.Module | ast.ClassDef | ast.FunctionDef | ast.AsyncFunctionDef)
                and node.body
                and isinstance(node.body[0], ast.Expr)
                and isinstance(node.body[0].value, ast.Constant)
            }
            for node in ast.walk(tree):
                text = node.value if isinstance(node, ast.Constant) and id(node) not in docstrings else None
                if isinstance(text, str) and flag.search(text):
                    hits.append(f"{rel}:{node.lineno}: {text[:60]!r}")
    assert hits == [], hits


def test_every_package_of_the_tool_is_in_the_code_a_result_depends_on():
    """A study's cache key and a report's provenance hash CODE_PACKAGES: a package left out
    would let a change in it reuse stale cached cases."""
    tops = {p.name for p in ROOT.iterdir() if (p / "__init__.py").is_file()} - {"designs", "tests"}
    assert tops == set(CODE_PACKAGES)


def test_the_models_write_no_files_and_draw_no_figures():
    """The squeal model, the acoustics and the track compute and return records; the
    application's presenters write and draw them."""
    import re

    writes = re.compile(r"savefig|matplotlib|write_text|write_bytes|\.write\(|open\([^)]*['\"][wa]")
    found = {
        str(f.relative_to(ROOT)): m.group(0)
        for pkg in ("reduced", "acoustics", "track")
        for f in sorted((ROOT / pkg).rglob("*.py"))
        if (m := writes.search(f.read_text()))
    }
    assert found == {}


def test_the_architecture_page_lists_the_packages_in_the_tree():
    """docs/architecture.md's table of packages is the tree's: every package with code is
    listed once, nothing listed is missing, and the interfaces it names exist."""
    import re

    from reduced import FrictionLaw
    from track.design_sections import CounterBodySection

    page = (ROOT / "docs" / "architecture.md").read_text()
    table = page.split("<!-- packages -->")[1].split("<!-- /packages -->")[0]
    listed = re.findall(r"^\| `(\w+)/` \|", table, flags=re.M)
    in_tree = {p.parent.name for p in ROOT.glob("*/__init__.py")} - {"designs"}  # package data
    assert sorted(listed) == sorted(in_tree) == sorted(CODE_PACKAGES)
    for method in ("contact_radii", "model", "states", "model_seconds"):
        assert f"`{method}()`" in page and callable(getattr(CounterBodySection, method)), method
    assert "`contact.creep.FrictionLaw`" in page and callable(FrictionLaw.kernel_parameters)


#: What a presenter must not call: the pass-by's physics, the solvers and the chain (a
#: presenter writes the records it is given)
COMPUTES = {
    "passby",
    "passby_pressure",
    "bogie_sources",
    "loudest_passby_sound",
    "stability_table",
    "linear_stability",
    "analyse",
    "simulate",
    "solve_curving",
    "mode_sound",
}


def test_a_presenter_computes_no_pass_by_and_solves_nothing():
    modules = _modules()
    for name, path in modules.items():
        if not name.startswith("wheel_squeal.present"):
            continue
        imported = {n for _, names in _imports(name, path, modules) for n in names}
        assert not imported & COMPUTES, (name, sorted(imported & COMPUTES))


def test_no_file_name_is_in_two_packages():
    """A module's file name says which one it is, wherever it is read from (a traceback, a
    search, an editor's tab): no two modules of the tool share one (packages' __init__ aside)."""
    seen: dict[str, list[str]] = {}
    for pkg in CODE_PACKAGES:
        for f in (ROOT / pkg).rglob("*.py"):
            if f.name != "__init__.py":
                seen.setdefault(f.name, []).append(str(f.relative_to(ROOT)))
    assert {n: p for n, p in seen.items() if len(p) > 1} == {}


def test_every_vocabulary_is_used_in_a_signature_and_names_its_registry():
    """Each Literal alias of wheel_squeal.types is used outside its own module (an alias no
    signature takes is a word the code does not keep), and a closed vocabulary spells its
    registry's names (the presets', the solvers', the normal contacts')."""
    import typing

    import wheel_squeal.types as types
    from fem.solvers import SOLVERS
    from wheel_squeal.model_sections import NORMAL_CONTACTS
    from wheel_squeal.presets import FIDELITIES

    sources = "\n".join(
        f.read_text() for pkg in CODE_PACKAGES for f in (ROOT / pkg).rglob("*.py") if f.name != "types.py"
    )
    for name in types.__all__:
        assert re.search(rf"\b{name}\b", sources), f"{name} is used nowhere"
    assert set(typing.get_args(types.FidelityName)) == set(FIDELITIES)
    assert set(typing.get_args(types.SolverName)) == set(SOLVERS)
    assert set(typing.get_args(types.NormalContact)) == set(NORMAL_CONTACTS)


def test_making_the_run_s_objects_changes_no_process_setting(tmp_path):
    """A cache, a context, a budget and a progress made, the environment is as before:
    where the libraries keep their files is chosen by the command that runs
    (wheel_squeal.runtime.library_folders), not by an object's constructor."""
    import os

    import wheel_squeal as ws
    from wheel_squeal.runtime.budget import Budget
    from wheel_squeal.runtime.progress import Progress

    before = dict(os.environ)
    cache = ws.StageCache(tmp_path / "cache")
    ws.RunContext.of("fast", cache=cache)
    Budget.from_environment()
    Progress(quiet=True)
    assert dict(os.environ) == before


#: What the runtime may import of the physics: the one home of atomic files and of quoting
#: untrusted text, which the design file's reader needs below it
RUNTIME_MAY_IMPORT = {"geometry.files"}


def test_the_runtime_imports_no_domain_module():
    """wheel_squeal.runtime (cache, budget, progress, folders, stops, pools) runs any
    request: it imports nothing of the application outside itself and nothing of the
    physics but :data:`RUNTIME_MAY_IMPORT`."""
    modules = _modules()
    for name, path in modules.items():
        if not name.startswith("wheel_squeal.runtime"):
            continue
        for target, _ in _imports(name, path, modules):
            assert target.startswith("wheel_squeal.runtime") or target in RUNTIME_MAY_IMPORT, (name, target)
