"""The public API's contract: every name of ``wheel_squeal.__all__`` has a numpydoc
docstring (its sections, units where it takes or gives quantities) with an Examples
block, and every example runs as written (doctest)."""

from __future__ import annotations

import doctest
import inspect

import pytest

import wheel_squeal as ws


def _kind(obj: object) -> str:
    return "class" if inspect.isclass(obj) else "function"


@pytest.mark.parametrize("name", ws.__all__)
def test_every_public_name_has_a_numpydoc_docstring(name):
    obj = getattr(ws, name)
    doc = inspect.getdoc(obj) or ""
    assert "Examples\n--------" in doc and ">>> " in doc, name
    if _kind(obj) == "function":
        params = [p for p in inspect.signature(obj).parameters.values() if p.name not in ("self",)]
        if params:
            assert "Parameters\n----------" in doc, name
        assert "Returns\n-------" in doc, name
    elif not issubclass(obj, Exception):
        assert "Attributes\n----------" in doc, name


#: Examples that solve a wheel's modes and its steady curving (the curve's: about 6 s)
SLOW_EXAMPLES = {"curve"}


@pytest.mark.parametrize(
    "name", [pytest.param(n, marks=pytest.mark.slow) if n in SLOW_EXAMPLES else n for n in ws.__all__]
)
def test_every_public_example_runs(name):
    """The examples solve small models (one given mode, or the fast preset below
    1.5 kHz): a few hundredths of a second each, 3 s in all."""
    obj = getattr(ws, name)
    finder = doctest.DocTestFinder(recurse=False)
    runner = doctest.DocTestRunner(optionflags=doctest.ELLIPSIS | doctest.NORMALIZE_WHITESPACE)
    tests = finder.find(obj, name, globs={})
    assert tests, name
    for test in tests:
        runner.run(test)
    assert runner.failures == 0, f"{name}: {runner.failures} example(s) failed (run with -s to see them)"
