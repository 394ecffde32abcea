"""The explorer's background threads, stopped together (no viser here).

:class:`Workers` starts the daemon threads of one explorer page (a run, its status ticker, a warm-up, the Track and
Wheel tabs' computations, a replay) and, on :meth:`Workers.close`, says that the page is closed
(:attr:`Workers.closed`: loops end at their next check, nothing is drawn any more) and joins every one of them, so
that no thread of a closed page updates it or outlives the explorer.
"""

from __future__ import annotations

import threading
from collections.abc import Callable

__all__ = ["Workers"]


class Workers:
    """Daemon threads started by name and joined together on :meth:`close`."""

    def __init__(self) -> None:
        self.closed = threading.Event()
        self._lock = threading.Lock()
        self._threads: set[threading.Thread] = set()

    def start(self, target: Callable, *args, name: str) -> threading.Thread | None:
        """``target(*args)`` in a new daemon thread named ``name``; None once closed (nothing is started)."""
        with self._lock:
            if self.closed.is_set():
                return None
            thread = threading.Thread(target=self._run, args=(target, args), daemon=True, name=name)
            self._threads.add(thread)
            thread.start()
        return thread

    def _run(self, target: Callable, args: tuple) -> None:
        try:
            target(*args)
        finally:
            with self._lock:
                self._threads.discard(threading.current_thread())

    def alive(self) -> list[threading.Thread]:
        """The threads still running."""
        with self._lock:
            return [thread for thread in self._threads if thread.is_alive()]

    def close(self, timeout: float | None = None) -> bool:
        """Mark closed and join every thread (the calling one aside) within ``timeout`` s each (None: until it
        ends); True if all have ended."""
        self.closed.set()
        current = threading.current_thread()
        for thread in self.alive():
            if thread is not current:
                thread.join(timeout)
        return not [thread for thread in self.alive() if thread is not current]
