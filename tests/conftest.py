"""Shared test set-up: every test uses a private Green's-function cache, never the user's."""

import pytest


@pytest.fixture(autouse=True, scope="session")
def _private_cache(tmp_path_factory):
    import os

    path = tmp_path_factory.mktemp("wheelrail-cache")
    old = os.environ.get("WHEELRAIL_CACHE_DIR")
    os.environ["WHEELRAIL_CACHE_DIR"] = str(path)
    yield path
    if old is None:
        os.environ.pop("WHEELRAIL_CACHE_DIR", None)
    else:
        os.environ["WHEELRAIL_CACHE_DIR"] = old
