"""Docstrings and comments say what the code does and how, never how fast it ran on one machine on one day, nor
what it did before: timings belong in ``docs/benchmarks.md`` with the script that prints them, history in
``CHANGELOG.md``. The patterns are precise on purpose: the physics and the program's own order of events use
"before" too (the step before, before contact, before the run), and those are what and how."""

import ast
import io
import re
import tokenize
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[2]
SCANNED = ("core", "cli", "explorer", "package")

# A measurement: a number with a time unit per step or per call, seconds of CPU or of wall time, a speed-up or
# slow-down factor, a throughput, the machine's load while measuring, what something took or costs in seconds.
# A time alone is physics (a 10 us step, a 50 ms truncation, 7.2 ms at 0.5 km/h) and passes.
TIMING = re.compile(
    r"\d\s?(?:ns|us|µs|ms|s|min) (?:a|per|each)\b"  # "~4 us a step", "3.6 us per pressure image", "1 us each"
    r"|\d\s?(?:ms|s|min|h) (?:of )?(?:CPU|wall)\b"  # "16 s of CPU", "43.2 s wall"
    r"|\d(?:\.\d+)?\s?x (?:faster|slower|the (?:CPU|wall) time)\b|\b\d+ times (?:faster|slower)\b"  # "2x faster"
    r"|\b(?:is|was|ran|runs) (?:\w+ )?(?:faster|slower)\b"  # "ran slower", "is much faster"
    r"|\d\s?[GMk]B/s\b|\bload(?: average)? \d[\d.]*(?:-\d[\d.]*)?(?![\d./]|\s?k?N\b)"  # "0.49 GB/s", "load 1.1"
    r"|\b(?:takes?|took|costs?) (?:about |some |~|only )?\d[\d.,-]*\s?(?:ns|us|µs|ms|s|min)\b"  # "took 0.8 s"
    r"|\bcompiled? (?:\S+ ){0,3}in (?:about |~)?\d[\d.,-]*\s?(?:ms|s|min)\b",  # "numba compiled those in 3.2 s"
    re.IGNORECASE,
)

# History: what the code did or cost before a change, or what an earlier version was.
HISTORY = re.compile(
    r"\bpreviously\b|\bformerly\b|\bused to be\b|\bnowadays\b"
    r"|\b(?:the )?(?:previous|earlier|older|old) (?:version|commit|code|release|implementation)s?\b"
    r"|\bbefore (?:this|that|the) (?:change|commit|version|fix|rewrite|refactor)\b"
    r"|\b(?:was|were) (?:about |~)?\d[\d.,-]*\s?(?:x|s|ms|%)"  # "was 1.15-1.24x", "was 0.3 s"
    r"|\bbefore\s*(?=[.;,)]|:\s|$)",  # "as every run did before;", "(682 s ... before)": "before" with no object
    re.IGNORECASE,
)

# Physics and the program's order of events: "before" with no object that means "the preceding one", not "an
# earlier version". Each names what comes before in the run, not in the code's history.
PRECEDING = re.compile(
    r"(?:\b(?:the|a|one|each|every) (?:step|lag|sample|position|element|frame|call|block|row|column|value|one|entry|"
    r"notice|band|line|bay|iteration|point|contact|wheel|run)|\bat rest) before\s*(?=[.;,)]|:\s|$)",
    re.IGNORECASE,
)


def _texts(source: str):
    """(line, text) of every docstring (a string standing as a statement: a module's, a class's, a function's, an
    attribute's after its assignment) and of every block of consecutive comment lines, whitespace collapsed."""
    for node in ast.walk(ast.parse(source)):
        if isinstance(node, ast.Expr) and isinstance(node.value, ast.Constant) and isinstance(node.value.value, str):
            yield node.lineno, " ".join(node.value.value.split())
    block, start, last = [], 0, -2
    for token in tokenize.generate_tokens(io.StringIO(source).readline):
        if token.type != tokenize.COMMENT:
            continue
        line = token.start[0]
        if line != last + 1 and block:
            yield start, " ".join(" ".join(block).split())
            block = []
        if not block:
            start = line
        block.append(token.string.lstrip("#"))
        last = line
    if block:
        yield start, " ".join(" ".join(block).split())


def offences(source: str) -> list[tuple[int, str]]:
    """(line, phrase) of each timing or piece of history in ``source``'s docstrings and comments."""
    found = []
    for line, text in _texts(source):
        found += [(line, match.group(0)) for match in TIMING.finditer(text)]
        allowed = {match.end() for match in PRECEDING.finditer(text)}
        found += [
            (line, text[max(0, match.start() - 30) : match.end() + 1].strip())
            for match in HISTORY.finditer(text)
            if match.end() not in allowed
        ]
    return found


@pytest.mark.parametrize(
    "text",
    [
        '"""Building a StepState costs ~4 us a step."""',
        '"""A fill with the steady state; the history is filled with P, as every run did before."""',
        '"""A track costs about 16 s of CPU, about 8 s on 2 free cores."""',
        "# the method: 2x faster than np.all at 576 elements",
        '"""The run-in: 1.9-3.8x its record (was 1.15-1.24x)."""',
        "# importing every command took 0.8 s before anything ran",
        "# with 8 it did not: the integration took 1.8x the CPU time",
        '"""Loops, not slice assignments: numba compiled those in 3.2 s."""',
        '"""The loop ran 20 times slower on subnormal numbers."""',
        '"""It reads the table from disk (previously it was rebuilt)."""',
        '"""The same array as before."""',
    ],
)
def test_the_patterns_find_timings_and_history(text):
    assert offences(text)


@pytest.mark.parametrize(
    "text",
    [
        '"""The force of the step before; the history before the first step is filled with P."""',
        '"""The response to a unit force at step 0 only, the track at rest before. Wheel load 25/50/100 kN."""',
        '"""Every step, or those done before :meth:`result`, at a load of 65 kN."""',
        '"""Checked here, before the run; comment lines are allowed only before the header."""',
        '"""The pressure before contact is zero; seconds before the first axle reaches the microphone."""',
        '"""A run-in of 0.5 ms at 100 km/h; steps of 7.2 ms at 0.5 km/h; the 50 ms truncation."""',
        '"""Its error decays before the record. It falls slower than (ka)^-3 at short wavelength."""',
        '"""One notice on the page, replacing the one before."""',
        "# samples on each side of a wheel's seam used to estimate the closure jump",
    ],
)
def test_the_patterns_pass_physics_and_the_order_of_events(text):
    assert offences(text) == []


def test_no_docstring_or_comment_carries_a_timing_or_history():
    scanned, offenders = 0, []
    for folder in SCANNED:
        for path in sorted((ROOT / folder).rglob("*.py")):
            relative = path.relative_to(ROOT).as_posix()
            scanned += 1
            for line, phrase in offences(path.read_text(encoding="utf-8")):
                offenders.append(f"{relative}:{line}: {phrase}")
    assert scanned > 100  # the scan reads the package's modules (a wrong folder finds none)
    assert offenders == []
