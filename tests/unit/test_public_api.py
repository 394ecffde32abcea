"""The curated namespace ``wheelrail``: the names scripts import from the top, each the object its module
defines, loaded on first use so that ``import wheelrail`` stays cheap (PEP 562)."""

import importlib
import subprocess
import sys

import pytest

import wheelrail

PUBLIC = {
    "simulate": "wheelrail.core.engine.prepare",
    "prepare_run": "wheelrail.core.engine.prepare",
    "ModelParameters": "wheelrail.core.parameters",
    "ContactParameters": "wheelrail.core.parameters",
    "force_spectrum": "wheelrail.core.spectra.force",
    "contact_filter": "wheelrail.core.spectra.levels",
    "run_study": "wheelrail.core.study.runner",
    "run_noise": "wheelrail.core.noise.run_noise",
    "WheelrailError": "wheelrail.core.errors",
}


@pytest.mark.parametrize("name", sorted(PUBLIC))
def test_each_public_name_is_the_object_its_module_defines(name):
    value = getattr(wheelrail, name)
    assert value is getattr(importlib.import_module(PUBLIC[name]), name)
    assert value.__module__ == PUBLIC[name]  # defined there, not a copy or a wrapper


def test_the_namespace_lists_exactly_the_curated_names():
    assert set(wheelrail.__all__) == {*PUBLIC, "__version__"}
    assert set(dir(wheelrail)) == set(wheelrail.__all__)
    with pytest.raises(AttributeError, match="no attribute 'simulat'"):
        wheelrail.simulat  # noqa: B018 (a misspelt name fails as for any module)


def test_star_import_gives_the_curated_names():
    namespace: dict = {}
    exec("from wheelrail import *", namespace)
    assert set(PUBLIC) <= set(namespace)


def test_import_wheelrail_loads_no_numerical_library():
    # in a fresh interpreter (this one has them loaded already): the top-level import, then one lazy name whose
    # module needs numpy only, to show the probe sees a load when there is one
    probe = (
        "import sys, wheelrail\n"
        "heavy = ('numpy', 'scipy', 'numba', 'matplotlib', 'wheelrail.core.engine.prepare')\n"
        "print(sorted(m for m in sys.modules if m.split('.')[0] in heavy or m in heavy))\n"
        "wheelrail.WheelrailError\n"
        "print('numpy' in sys.modules, 'numba' in sys.modules)\n"
        "wheelrail.force_spectrum\n"
        "print('numpy' in sys.modules)\n"
    )
    out = subprocess.run([sys.executable, "-c", probe], capture_output=True, text=True, check=True).stdout
    assert out.splitlines() == ["[]", "False False", "True"]
