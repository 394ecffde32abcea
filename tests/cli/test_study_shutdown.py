"""A study's worker processes end with the process that runs the study: kill -9 and SIGTERM of a real process, with
the process pool and with forked workers.

The study process is a small script whose two runs never finish: with the pool their roughness source unpickles by
blocking forever, forked the run itself blocks, so each worker is busy inside its task, deterministically, however
fast the machine is.
The test then follows the processes' states in /proc (polling with a generous deadline, no fixed sleep).
"""

import os
import signal
import subprocess
import sys
import time
from pathlib import Path

import pytest

pytestmark = [
    pytest.mark.skipif(not Path("/proc/self/stat").exists(), reason="reads process states from /proc"),
    pytest.mark.slow,
]  # real study processes: seconds each

DEADLINE_S = 120.0  # interpreter start and imports of 3 processes on a loaded 2-core machine; usually ~5 s

SCRIPT = """
import sys
import threading

from wheelrail.core.study import RunSpec, execute


def _block():
    threading.Event().wait()  # a worker unpickling its task stays here until its process ends


class Blocker:
    def __reduce__(self):
        return (_block, ())


if __name__ == "__main__":
    specs = [RunSpec(source=Blocker(), set_label="blocked", set_digest="0" * 64, model="hertz", line=line)
             for line in (0, 1)]
    try:
        execute(specs, cache=sys.argv[1], workers=2, progress=False, backend="processes")
    except KeyboardInterrupt as error:
        print(f"stopped by {type(error).__name__}", file=sys.stderr)
        sys.exit(130)
"""


def _state(pid: int) -> str | None:
    """The process's state letter, or None when it is gone."""
    try:
        return Path(f"/proc/{pid}/stat").read_text().rsplit(")", 1)[1].split()[0]
    except (OSError, IndexError):
        return None


def _alive(pid: int) -> bool:
    return _state(pid) not in (None, "Z", "X")  # a zombie has ended: only its exit status is left


def _children(parent: int) -> dict[int, str]:
    """Processes whose parent is ``parent``: pid -> command line."""
    found = {}
    for entry in os.listdir("/proc"):
        if not entry.isdigit():
            continue
        try:
            ppid = int(Path(f"/proc/{entry}/stat").read_text().rsplit(")", 1)[1].split()[1])
            cmdline = Path(f"/proc/{entry}/cmdline").read_bytes().replace(b"\0", b" ").decode(errors="replace")
        except (OSError, IndexError, ValueError):
            continue
        if ppid == parent:
            found[int(entry)] = cmdline
    return found


def _wait_until(condition, what: str) -> None:
    end = time.monotonic() + DEADLINE_S
    while not condition():
        if time.monotonic() > end:
            pytest.fail(f"not {what} after {DEADLINE_S:g} s")
        time.sleep(0.05)


FORK_SCRIPT = """
import sys
import threading

from wheelrail.core.study import RunSpec, execute, specs, threads


def blocked(spec, cancel=None):
    if cancel is not None:  # the study's process's own share: stops when the study does, as a run at its next chunk
        cancel.wait()
        raise specs.RunCancelled(spec.label())
    threading.Event().wait()  # a forked worker stays here until its process ends


if __name__ == "__main__":
    specs.compute_run = blocked  # what the forked workers (and the study's own thread) call
    threads.read_once = list
    runs = [RunSpec(source="sinter-wheel-1", set_label="blocked", set_digest="0" * 64, model="hertz", line=line)
            for line in (0, 1)]
    try:
        execute(runs, cache=sys.argv[1], workers=2, progress=False, backend="fork")
    except KeyboardInterrupt as error:
        print(f"stopped by {type(error).__name__}", file=sys.stderr)
        sys.exit(130)
"""


@pytest.fixture(params=["processes", "fork"])
def study_process(tmp_path, request):
    """The blocked study, once its workers run: with the process pool two spawned workers and the resource tracker,
    forked one child (the study's process the other worker): (process, their pids)."""
    script = tmp_path / "blocked_study.py"
    script.write_text(SCRIPT if request.param == "processes" else FORK_SCRIPT)
    command = [sys.executable, str(script), str(tmp_path / "runs")]
    # a session of its own: Ctrl-C reaches the study's process group only (test_ctrl_c_...)
    process = subprocess.Popen(command, stderr=subprocess.PIPE, text=True, start_new_session=True)
    helpers: dict[int, str] = {}

    def started() -> bool:
        helpers.update(_children(process.pid))
        if process.poll() is not None:
            pytest.fail(f"the study process ended early: {process.stderr.read()}")
        if request.param == "fork":
            return len(helpers) == 1
        workers = [pid for pid, cmd in helpers.items() if "spawn_main" in cmd]
        trackers = [pid for pid, cmd in helpers.items() if "resource_tracker" in cmd]
        return len(workers) == 2 and len(trackers) == 1

    try:
        _wait_until(started, "two workers and a resource tracker started")
        yield process, sorted(helpers)
    finally:
        for pid in [process.pid, *helpers]:  # only what this test started, should it have failed
            if _alive(pid):
                os.kill(pid, signal.SIGKILL)
        process.wait()
        process.stderr.close()


def test_workers_and_tracker_end_after_kill_9(study_process):
    process, helpers = study_process
    process.kill()
    assert process.wait() == -signal.SIGKILL
    _wait_until(lambda: not any(_alive(pid) for pid in helpers), "every worker and the tracker ended")


def test_sigterm_stops_the_study_like_ctrl_c(study_process):
    process, helpers = study_process
    process.terminate()
    try:
        code = process.wait(timeout=DEADLINE_S)
    except subprocess.TimeoutExpired:
        pytest.fail(f"the study did not stop within {DEADLINE_S:g} s of SIGTERM")
    assert code == 130 and "stopped by StudyTerminated" in process.stderr.read()
    _wait_until(lambda: not any(_alive(pid) for pid in helpers), "every worker and the tracker ended")


def test_ctrl_c_to_the_process_group_stops_forked_workers(study_process, request):
    # a terminal's Ctrl-C is SIGINT to the whole foreground group: the forked children ignore it, the study's
    # process stops them and exits as interrupted
    if request.node.callspec.params["study_process"] != "fork":
        pytest.skip("the process pool's spawned workers are covered by the SIGTERM and kill -9 tests")
    process, helpers = study_process
    os.killpg(process.pid, signal.SIGINT)
    try:
        code = process.wait(timeout=DEADLINE_S)
    except subprocess.TimeoutExpired:
        pytest.fail(f"the study did not stop within {DEADLINE_S:g} s of Ctrl-C")
    assert code == 130 and "stopped by KeyboardInterrupt" in process.stderr.read()
    _wait_until(lambda: not any(_alive(pid) for pid in helpers), "every forked worker ended")
