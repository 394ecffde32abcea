"""Explorer responsiveness: time from pressing Run to the first frame, and the live patch's frame rate.

Run: python3 benchmarks/explorer.py [--repeats 5] [--length-m 7.9] [--browser]

Server side (always): an ExplorerApp on a free port and the session of one tab of it opened without a browser
(a HeadlessTab); Run is pressed programmatically (the function the button's callback calls); "first frame" is the
moment the first step's patch has been handed to viser for sending (timed around the session's frame listener).
After a warm-up run, so the Green's functions are cached and numba's compiled code is loaded, as for a user's
second run. Frame rate: frames drawn per second of a 3D run on the corrugated rail (the explorer draws at most 20
per second), and the run's steps/s with the explorer drawing, to compare with benchmarks/interaction.py.

--browser (needs /usr/bin/chromium and playwright): the same press in a headless Chromium page (its own session),
timed in the page from the click to the moment the page's scene holds a new patch (received, before WebGL draws
it; headless Chromium renders WebGL in software, slowly, so the figure is pessimistic).
Target: press Run to first frame < 1 s.

--first-run: a user's very first run, the default one (3d, 3 m of the corrugated rail at 100 km/h), in a
fresh process with empty caches (a new Green's-function cache folder and a new numba cache folder): the
time of each preparation step the page announces, until the first frame and until the run is done; Run
pressed at once, then (another fresh process) pressed after the background warm-up that ``wheelrail
explore`` starts has finished.
"""

from __future__ import annotations

import argparse
import os
import statistics
import time
from pathlib import Path

from wheelrail.core.engine.history import default_run_in_length


def _new_session(explorer, open_tab):
    """``open_tab()`` (a HeadlessTab or a page connecting), then the session the explorer built for it."""
    known = set(explorer.sessions)
    tab = open_tab()
    assert explorer.wait_for(lambda: set(explorer.sessions) - known, 120), "no session for the new tab"
    return tab, explorer.sessions[max(set(explorer.sessions) - known)]


def _headless(explorer):
    from wheelrail.explorer.headless import HeadlessTab

    return _new_session(explorer, lambda: HeadlessTab(explorer.port))


def _press(app, model: str, length: float) -> tuple[float, float, int, int, float]:
    app.form.model_dropdown.value = model
    app.form.length_text.value = f"{length:g}"
    first = []
    draw = type(app).frame  # the benchmark times the listener's first frame (the app keeps no timer)

    def timed(state, view):
        draw(app, state, view)
        if not first:
            first.append(time.perf_counter())

    app.frame = timed
    start, cpu = time.perf_counter(), time.process_time()
    try:
        assert app.start_run(), app.page.last_error
        app.controller.wait()
    finally:
        del app.frame
    elapsed = time.perf_counter() - start
    _press.cpu = time.process_time() - cpu  # the whole process: the run's thread, viser's, the page's
    if app.page.last_error:
        raise SystemExit(app.page.last_error)
    return first[0] - start, elapsed, app.scene.frames_drawn, app.replay.entry.result.n_steps, start


def server_side(app, repeats: int, length: float) -> None:
    _press(app, "3d", 0.6)  # warm-up: Green's functions at this speed, compiled code
    _press(app, "hertz", 0.6)
    print("press Run -> first frame drawn (server side, warm), median of", repeats)
    for model in ("3d", "2d", "hertz"):
        firsts = [_press(app, model, 1.0)[0] for _ in range(repeats)]
        print(
            f"  {model:6s} {statistics.median(firsts) * 1e3:7.0f} ms   (min {min(firsts) * 1e3:.0f}, "
            f"max {max(firsts) * 1e3:.0f} ms; includes the run-in, {default_run_in_length() * 1e3:.0f} steps)"
        )
    first, elapsed, frames, steps, _ = _press(app, "3d", length)
    live = elapsed - first
    print(
        f"3d live patch, {length:g} m corrugated rail at 100 km/h: {frames} frames in {live:.2f} s after the first "
        f"= {frames / live:.1f} frames/s (cap 20); run incl. preparation and run-in {elapsed:.2f} s, "
        f"{steps / elapsed:.0f} steps/s overall, {steps / live:.0f} steps/s after the first frame; CPU of the "
        f"process {_press.cpu:.2f} s = {steps / _press.cpu:.0f} steps per CPU second overall "
        f"(load average {os.getloadavg()[0]:.1f}; target 27 778 steps/s)"
    )


PRESS_AND_WAIT = """async () => {
    const tree = window.__viserSceneTree;
    // a new update message brings a new vertex array (a repeated run ends on the same numbers)
    const before = tree.getState()['/contact/heatmap'].message.props._data;
    const button = [...document.querySelectorAll('button')].find(b => b.textContent.trim() === 'Run');
    const t0 = performance.now();
    button.click();
    while (performance.now() - t0 < 60000) {
        await new Promise(r => requestAnimationFrame(r));
        const now = tree.getState()['/contact/heatmap'].message.props._data;
        if (now !== before) return performance.now() - t0;
    }
    return -1;
}"""


COUNT_PATCHES = """async () => {
    // frames reaching the page: distinct heat-map updates the page's scene receives during one run
    const tree = window.__viserSceneTree;
    const data = () => tree.getState()['/contact/heatmap'].message.props._data;
    let last = data();
    const button = [...document.querySelectorAll('button')].find(b => b.textContent.trim() === 'Run');
    const t0 = performance.now();
    button.click();
    let first = -1, latest = -1, frames = 0;
    while (performance.now() - t0 < 120000) {
        await new Promise(r => requestAnimationFrame(r));
        const now = data();
        if (now !== last) {
            last = now; frames += 1; latest = performance.now();
            if (first < 0) first = latest;
        } else if (latest > 0 && performance.now() - latest > 2000) {
            break;  // nothing new for 2 s: the run has ended
        }
    }
    return [frames, first - t0, latest - t0];
}"""


def browser_frames(page, app, length: float) -> None:
    app.form.length_text.value = f"{length:g}"
    frames, first, latest = page.evaluate(COUNT_PATCHES)
    app.controller.wait()
    rate = (frames - 1) / ((latest - first) / 1e3) if frames > 1 and latest > first else float("nan")
    print(
        f"3d live patch in the page (headless Chromium, software WebGL), {length:g} m: {frames} patches reached "
        f"the page over {(latest - first) / 1e3:.2f} s = {rate:.1f} frames/s"
    )


def browser_side(explorer, repeats: int) -> None:
    from playwright.sync_api import sync_playwright

    args = [
        "--disable-background-networking",
        "--disable-component-update",
        "--disable-sync",
        "--no-sandbox",
        "--disable-gpu",
    ]
    with sync_playwright() as p:
        browser = p.chromium.launch(executable_path="/usr/bin/chromium", args=args)
        page = browser.new_page(viewport={"width": 1200, "height": 800})
        _, app = _new_session(explorer, lambda: page.goto(f"http://127.0.0.1:{explorer.port}"))
        page.get_by_role("button", name="Run", exact=True).wait_for(timeout=90_000)
        app.form.model_dropdown.value = "3d"
        app.form.length_text.value = "1"
        time.sleep(5.0)
        times = []
        for _ in range(repeats):
            ms = page.evaluate(PRESS_AND_WAIT)
            app.controller.wait()
            times.append(ms)
            time.sleep(1.0)
        for length in (3.0, 7.9):
            browser_frames(page, app, length)
        browser.close()
    print(
        f"press Run in the page -> new patch in the page (headless Chromium, software WebGL): median "
        f"{statistics.median(times):.0f} ms (min {min(times):.0f}, max {max(times):.0f} ms) of {repeats}"
    )


def first_run(warm_up: bool) -> None:
    """In this process (its caches empty): the default Run, with the time each status line appeared; with
    ``warm_up``, pressed once the app's background warm-up has finished."""
    from wheelrail.explorer.app import ExplorerApp

    start = time.perf_counter()
    explorer = ExplorerApp(port=0, warm_up=warm_up)  # a port the system chooses (explorer.port: the one bound)
    if warm_up:  # as `wheelrail explore` starts it
        explorer.warmed_up.wait()
        print(
            f"background warm-up (as `wheelrail explore` starts it): {time.perf_counter() - start:.1f} s "
            "from the app's start"
        )
    tab, app = _headless(explorer)
    said, first = [], []
    status, draw = app.status, type(app).frame

    def timed_status(text):
        status(text)
        if not said or not text.startswith(said[-1][1].split(" ...")[0]):
            said.append((time.perf_counter(), text))

    def timed_frame(state, view):
        draw(app, state, view)
        if not first:
            first.append(time.perf_counter())

    app.status, app.frame = timed_status, timed_frame
    try:
        start = time.perf_counter()
        assert app.start_run(), app.page.last_error
        app.controller.wait()
        done = time.perf_counter()
    finally:
        explorer.close()
        tab.close()
    for when, text in said:
        print(f"  {when - start:6.1f} s  {text.split(' ...')[0]}")
    when = "after the warm-up" if warm_up else "at once"
    print(
        f"first run (empty caches), Run pressed {when}: first frame after {first[0] - start:.1f} s, done after "
        f"{done - start:.1f} s"
    )


def first_run_in_a_fresh_process() -> None:
    import os
    import subprocess
    import sys
    import tempfile

    for flag in ("--first-run-here", "--first-run-here-warm"):
        with tempfile.TemporaryDirectory(prefix="wheelrail-first-run-") as folder:
            env = {
                **os.environ,
                "WHEELRAIL_CACHE_DIR": str(Path(folder) / "track"),
                "NUMBA_CACHE_DIR": str(Path(folder) / "numba"),
            }
            subprocess.run([sys.executable, __file__, flag], env=env, check=True)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--repeats", type=int, default=5)
    parser.add_argument("--length-m", type=float, default=7.9)
    parser.add_argument("--browser", action="store_true", help="also time the press in headless Chromium")
    parser.add_argument("--first-run", action="store_true", help="only a first run with empty caches")
    parser.add_argument("--first-run-here", action="store_true", help=argparse.SUPPRESS)
    parser.add_argument("--first-run-here-warm", action="store_true", help=argparse.SUPPRESS)
    args = parser.parse_args()
    if args.first_run:
        first_run_in_a_fresh_process()
        return
    if args.first_run_here or args.first_run_here_warm:
        first_run(warm_up=args.first_run_here_warm)
        return
    from wheelrail.explorer.app import ExplorerApp

    explorer = ExplorerApp(port=0)  # a port the system chooses (explorer.port: the one bound)
    tab, app = _headless(explorer)
    try:
        server_side(app, args.repeats, args.length_m)
        if args.browser:
            browser_side(explorer, args.repeats)
    finally:
        explorer.close()
        tab.close()


if __name__ == "__main__":
    main()
