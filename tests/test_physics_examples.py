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
