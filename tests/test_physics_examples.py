"""Every example in the physics packages' docstrings runs as written (doctest), as the
application's public ones do (``tests/test_api_docs.py``): an example that drifted from the
code is a defect."""

from __future__ import annotations

import doctest
import importlib
import pkgutil

import pytest

PHYSICS = ("geometry", "contact", "fem", "reduced", "acoustics", "track")


def _modules() -> list[str]:
    names = []
    for pkg in PHYSICS:
        names.append(pkg)
        path = importlib.import_module(pkg).__path__
        names += [f"{pkg}.{m.name}" for m in pkgutil.iter_modules(path)]
    return names


def _with_examples() -> list[str]:
    finder = doctest.DocTestFinder()
    return [n for n in _modules() if any(t.examples for t in finder.find(importlib.import_module(n)))]


@pytest.mark.parametrize("name", _with_examples())
def test_the_examples_run(name):
    module = importlib.import_module(name)
    runner = doctest.DocTestRunner(optionflags=doctest.ELLIPSIS | doctest.NORMALIZE_WHITESPACE)
    for test in doctest.DocTestFinder().find(module, name):
        if test.examples:
            runner.run(test)
    assert runner.tries > 0 and runner.failures == 0, f"{name}: {runner.failures} example(s) failed"


def _public_names() -> dict[str, list[tuple[str, object]]]:
    """Each physics package's public functions and classes (its modules' ``__all__``,
    defined there)."""
    import inspect

    out: dict[str, list[tuple[str, object]]] = {}
    for pkg in PHYSICS:
        names = out.setdefault(pkg, [])
        for m in pkgutil.iter_modules(importlib.import_module(pkg).__path__):
            if m.name.startswith("_"):
                continue
            module = importlib.import_module(f"{pkg}.{m.name}")
            for n in getattr(module, "__all__", []):
                obj = getattr(module, n, None)
                if (inspect.isfunction(obj) or inspect.isclass(obj)) and obj.__module__ == module.__name__:
                    names.append((f"{module.__name__}.{n}", obj))
    return out


def _numpydoc(obj: object) -> bool:
    """Its parameters, return value or attributes in numpydoc's sections and an example
    (an exception: the example)."""
    import inspect
    import re

    doc = "\n" + (inspect.getdoc(obj) or "")
    example = "\nExamples\n--------" in doc and ">>> " in doc
    if inspect.isclass(obj) and issubclass(obj, Exception):
        return example
    return example and bool(re.search(r"\n(Parameters|Returns|Attributes)\n-{3,}", doc))


#: The physics' public names with numpydoc and an example, at the least, per package: what
#: is documented stays documented (the target is every package at 90 %; the contact
#: package is there)
DOCUMENTED_AT_LEAST = {"geometry": 0, "contact": 29, "fem": 2, "reduced": 1, "acoustics": 0, "track": 1}


def test_the_physics_public_names_keep_their_numpydoc():
    counts = {pkg: sum(_numpydoc(obj) for _, obj in names) for pkg, names in _public_names().items()}
    assert all(counts[pkg] >= least for pkg, least in DOCUMENTED_AT_LEAST.items()), counts
    contact = [name for name, obj in _public_names()["contact"] if not _numpydoc(obj)]
    assert contact == [], contact
