"""A study's kept process pool (``core.study.execution._pool``) is kept per disk cache folder: its workers read the
folder from the environment when they start, so a process that changes ``WHEELRAIL_CACHE_DIR`` between studies gets
new workers, not ones that read and write the old folder."""

from __future__ import annotations

from wheelrail.core.study import execution


class _FakePool:
    """Stands in for ProcessPoolExecutor: no process is started."""

    def __init__(self, **kwargs) -> None:
        self.kwargs = kwargs

    def shutdown(self, wait=True, cancel_futures=False) -> None:
        pass


def test_a_new_cache_folder_gets_new_workers(monkeypatch, tmp_path):
    monkeypatch.setattr(execution, "ProcessPoolExecutor", _FakePool)
    monkeypatch.setattr(execution, "_POOLS", {})
    monkeypatch.setenv("WHEELRAIL_CACHE_DIR", str(tmp_path / "one"))
    first = execution._pool(2)
    assert execution._pool(2) is first  # kept for the next study on the same folder
    monkeypatch.setenv("WHEELRAIL_CACHE_DIR", str(tmp_path / "two"))
    second = execution._pool(2)
    assert second is not first
    execution._stop_pool(2, second)
    assert second not in execution._POOLS.values() and first in execution._POOLS.values()
