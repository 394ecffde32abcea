"""The tests' persistent cache (tests/conftest.py) is keyed by the code of every module that writes cache
entries, so that no test reads an entry an older version of that code computed."""

import importlib.util
import re
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]


def _conftest():
    spec = importlib.util.spec_from_file_location("tests_conftest", ROOT / "tests" / "conftest.py")
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def test_every_module_that_writes_cache_entries_keys_the_tests_cache():
    conftest = _conftest()
    covered = {path for pattern in conftest.CACHED_CODE for path in ROOT.glob(pattern)}
    writers = {
        path
        for folder in ("core", "explorer", "package")
        for path in (ROOT / folder).rglob("*.py")
        if path.name != "cache.py" and re.search(r"\bsave_entry(_behind)?\(", path.read_text(encoding="utf-8"))
    }
    assert writers, "no module writes cache entries: the search is wrong"
    assert writers <= covered, sorted(str(p.relative_to(ROOT)) for p in writers - covered)


def test_the_folder_changes_with_the_code(tmp_path, monkeypatch):
    conftest = _conftest()
    monkeypatch.setattr(conftest, "ROOT", tmp_path)
    (tmp_path / "core" / "track").mkdir(parents=True)
    source = tmp_path / "core" / "track" / "stationary.py"
    source.write_text("A = 1\n")
    before = conftest.code_hash()
    assert conftest.code_hash() == before
    source.write_text("A = 2\n")
    assert conftest.code_hash() != before


def test_other_code_versions_are_removed_but_the_last_used(tmp_path, monkeypatch):
    import os

    conftest = _conftest()
    monkeypatch.setenv("WHEELRAIL_TEST_CACHE_DIR", str(tmp_path))
    for age, name in enumerate(("old", "older", "newest")[::-1]):
        (tmp_path / name).mkdir()
        os.utime(tmp_path / name, (1e9 - age * 1e6, 1e9 - age * 1e6))
    folder = conftest._test_cache_folder()
    assert folder.parent == tmp_path and folder.name == conftest.code_hash()
    assert sorted(p.name for p in tmp_path.iterdir()) == sorted([folder.name, "newest"])
