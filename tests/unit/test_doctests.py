"""The documented examples run: the *Examples* sections of the public API's docstrings are executed as doctests
(the API reference of the documentation site shows them)."""

import doctest
import importlib

import pytest

# module -> the functions and classes whose docstrings must carry an Examples section
DOCUMENTED = {
    "wheelrail.core.interaction": ["prepare_run", "simulate"],
    "wheelrail.core.parameters": ["ContactParameters"],
    "wheelrail.core.spectra": ["third_octave_bands", "force_spectrum", "shortest_spectrum_run", "mean_level",
                               "contact_filter"],
}


@pytest.mark.parametrize("module_name", sorted(DOCUMENTED))
def test_docstring_examples_run(module_name):
    module = importlib.import_module(module_name)
    for name in DOCUMENTED[module_name]:
        doc = getattr(module, name).__doc__
        assert ">>> " in doc.partition("\n    Examples\n    --------\n")[2], f"{name} has no Examples section"
    finder = doctest.DocTestFinder()
    runner = doctest.DocTestRunner(optionflags=doctest.ELLIPSIS | doctest.NORMALIZE_WHITESPACE)
    tests = [test for test in finder.find(module, module_name) if test.examples]
    for test in tests:
        runner.run(test)
    results = runner.summarize(verbose=False)
    assert results.failed == 0
    # every listed function's examples were found and run (a renamed function cannot pass with nothing run)
    ran = {test.name.rsplit(".", 1)[-1] for test in tests}
    assert set(DOCUMENTED[module_name]) <= ran
    assert results.attempted >= 2 * len(DOCUMENTED[module_name])

