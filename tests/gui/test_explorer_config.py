"""Only physical inputs in the explorer (no server): the page's fields accept core's ranges and word core's
errors with their own labels and units (explorer/config.py)."""

from __future__ import annotations

import pytest

from wheelrail.core.errors import WheelrailError
from wheelrail.core.inputs.declared import by_key
from wheelrail.core.inputs.ranges import ACCEPTED
from wheelrail.core.parameters import MAX_SPEED_KMH, MIN_SPEED_KMH
from wheelrail.core.roughness import load_roughness
from wheelrail.explorer.config import accepted_text, page_message, read_config

RAIL = load_roughness("corrugated-rail")
WHEEL = load_roughness("sinter-wheel-1")
FIELDS = {"line": "0", "model": "hertz", "speed_kmh": "100", "preload_kn": "65", "length_m": "1"}


def _page_error(**changes) -> str:
    geometry_mm = changes.pop("geometry_mm", {})
    wheel = changes.pop("wheel", None)
    with pytest.raises(WheelrailError) as info:
        read_config(
            RAIL,
            "corrugated-rail",
            **{**FIELDS, **changes, **geometry_mm},
            wheel=wheel,
            wheel_label=None if wheel is None else "sinter-wheel-1",
        )
    message = page_message(info.value)
    assert "\n" not in message and "--" not in message and "ContactParameters" not in message
    return message


def test_the_fields_offer_cores_ranges():
    assert by_key("preload").in_shown() == (ACCEPTED["preload"].minimum / 1e3, ACCEPTED["preload"].maximum / 1e3)
    assert by_key("preload").in_shown() == (1.0, 500.0)
    assert (MIN_SPEED_KMH, MAX_SPEED_KMH) == (5.0, 400.0)
    assert [accepted_text(key) for key in ("speed", "preload", "wheel_radius", "rail_crown_radius")] == [
        "5 to 400 km/h",
        "1 to 500 kN",
        "100 to 1250 mm",
        "50 to 5000 mm",
    ]
    assert accepted_text("wheel_transverse_radius") == "at least 50 mm in magnitude"


@pytest.mark.parametrize(
    ("changes", "start"),
    [
        ({"preload_kn": "5000"}, "Preload 5000 kN is outside the accepted 1 to 500 kN ("),
        ({"preload_kn": "0.1"}, "Preload 0.1 kN is outside the accepted 1 to 500 kN ("),
        ({"speed_kmh": "401"}, "Speed 401 km/h is outside the accepted 5 to 400 km/h ("),
        ({"speed_kmh": "4"}, "Speed 4 km/h is outside the accepted 5 to 400 km/h ("),
        (
            {"geometry_mm": {"wheel_radius_mm": "0.001"}},
            "Wheel radius 0.001 mm is outside the accepted 100 to 1250 mm (",
        ),
        ({"geometry_mm": {"wheel_radius_mm": "1e6"}}, "Wheel radius 1e+06 mm is outside the accepted 100 to 1250 mm ("),
        (
            {"geometry_mm": {"rail_crown_radius_mm": "0.001"}},
            "Rail crown radius 0.001 mm is outside the accepted 50 to 5000 mm (",
        ),
        (
            {"geometry_mm": {"rail_crown_radius_mm": "300", "wheel_transverse_radius_mm": "-300.5"}},
            "Wheel tread radius across -300.5 mm: the Hertz patch at the preload would be 0.148 m wide across the rail",
        ),
        (
            {"wheel": WHEEL},
            "Wheel radius 390 mm: the wheel set sinter-wheel-1 is 2.9 m round (a wheel of radius 0.4615 m)",
        ),
        ({"length_m": "9"}, "Run length 9 m is outside the accepted 0.572 to 7.959 m (on corrugated-rail at 100 km/h"),
    ],
)
def test_an_unphysical_input_is_worded_with_the_fields_label(changes, start):
    assert _page_error(**changes).startswith(start)


def test_an_upload_is_named_in_its_messages_never_its_temporary_path():
    from wheelrail.explorer.uploads import read_upload

    with pytest.raises(WheelrailError) as info:
        read_upload("C:\\data\\bad.csv", b"# kind: rail\nx_m,y_mm=0\n0,abc\n", 10_000)
    message = str(info.value)
    assert message.startswith("upload 'bad.csv', line 3: height") and "wheelrail-upload-" not in message, message


def test_the_wheel_sets_own_radius_runs():
    config = read_config(
        RAIL,
        "corrugated-rail",
        **FIELDS,
        wheel_radius_mm="461.5",
        wheel=WHEEL,
        wheel_label="sinter-wheel-1",
    )
    assert config.wheel_set_label == "sinter-wheel-1" and config.contact().radius_along == 0.4615


def test_a_line_the_wheel_set_does_not_cover_is_worded_by_the_page():
    # wheel and rail are paired by lateral position (core's run_lines): a wheel set narrowed to its lines -2..2
    # (-4 .. 4 mm) covers the rail's lines -4..4 (1 mm apart), and the page offers and names only those
    from wheelrail.core.parameters import ContactParameters
    from wheelrail.explorer.config import offered_lines

    narrow = WHEEL.with_heights(
        WHEEL.heights[[WHEEL.row_of_line(n) for n in range(-2, 3)]],
        y=WHEEL.y[[WHEEL.row_of_line(n) for n in range(-2, 3)]],
    )
    own = {"wheel_radius_mm": "461.5"}
    assert offered_lines(RAIL, "hertz", ContactParameters(wheel_radius=0.4615), narrow) == tuple(range(-4, 5))
    with pytest.raises(WheelrailError) as info:
        read_config(RAIL, "corrugated-rail", **{**FIELDS, "line": "5", **own}, wheel=narrow, wheel_label="narrow-wheel")
    message = page_message(info.value)
    assert message == (
        "Line 5 of corrugated-rail lies where narrow-wheel has no data across the rail (wheel and "
        "rail are paired by position); choose a line from -4 to 4"
    )
    assert (
        read_config(
            RAIL, "corrugated-rail", **{**FIELDS, "line": "4", **own}, wheel=narrow, wheel_label="narrow-wheel"
        ).line
        == 4
    )


def test_a_one_line_set_offers_no_3d_line_and_says_how_wide_a_set_must_be():
    one = RAIL.with_heights(RAIL.heights[[RAIL.row_of_line(0)]], y=RAIL.y[[RAIL.row_of_line(0)]])
    from wheelrail.core.parameters import ContactParameters
    from wheelrail.explorer.config import offered_lines

    assert offered_lines(one, "3d", ContactParameters()) == ()  # was an internal resampling error
    assert offered_lines(one, "hertz", ContactParameters()) == (0,)
    with pytest.raises(WheelrailError) as info:
        read_config(one, "one-line", **{**FIELDS, "model": "3d"})
    assert "3d needs data 14 mm across around its line" in page_message(info.value)


@pytest.mark.parametrize("typed", ["inf", "nan", "1e999", "-inf"])
def test_a_speed_that_is_no_finite_number_is_worded_not_raised(typed):
    # typed in the Speed field these raised an OverflowError in a server callback
    with pytest.raises(WheelrailError) as info:
        read_config(RAIL, "corrugated-rail", **{**FIELDS, "speed_kmh": typed})
    assert page_message(info.value) == f"Speed '{typed}': not a number"


def test_the_noise_tab_says_what_the_cnossos_superstructure_term_is():
    # the Noise tab printed "superstructure 15.6 dB(A)" with no word on what it is: now its source, equation,
    # table and size against the track term (core.noise.cnossos: L_W,0,sup with Table G-3c, 0 dB in every band)
    from types import SimpleNamespace

    from wheelrail.core.noise.cnossos import superstructure_transfer
    from wheelrail.explorer.noise_tab import NOISE_NOTE, superstructure_words

    assert not superstructure_transfer().any()  # the one tabulated transfer: 0 dB in every band, as the words say
    words = superstructure_words(SimpleNamespace(superstructure_dba=15.6, track_dba=101.2))
    assert "*superstructure* term, 15.6 dB(A)" in words
    assert "L_W,0,sup = L_R,TOT + L_H,veh,sup + 10 lg N_a" in words and "eq. 2.3.10" in words
    assert "0 dB in every band (Table G-3c)" in words and "85.6 dB below the track term" in words
    assert "superstructure term" in NOISE_NOTE


def test_the_help_tab_says_that_each_browser_tab_is_its_own_session():
    # each client gets its own form and results (viser's per-client GUI): the page says so, and what is shared
    from wheelrail.explorer.help_tab import help_text

    text = help_text()
    assert "**Each browser tab its own session**: every tab open on this explorer has its own form, runs" in text
    assert "One shared session" not in text and "closing a tab stops its run" in text


def test_a_plots_title_names_the_track_in_cores_words():
    """The plots' titles (``RunConfig.title_label``): the case, then the paper's track or the track inputs that
    differ from it, each once (core's ``describe_track``)."""
    from wheelrail.explorer.config import RunConfig

    paper = RunConfig("corrugated-rail", 0, "hertz", 0.6)
    assert paper.title_label() == "corrugated-rail, line 0, 100 km/h, 65 kN, 0.6 m; the paper's track"
    soft = RunConfig("corrugated-rail", 0, "hertz", 0.6, inputs=(("wheel_radius", 0.46), ("pad_stiffness", 60e6)))
    assert soft.title_label() == (
        "corrugated-rail, line 0, 100 km/h, 65 kN, 0.6 m, wheel radius 460 mm; the track with pad stiffness 60 MN/m "
        "(else the paper's)"
    )


def _session(**changes) -> bytes:
    import json

    session = {
        "wheelrail_session": 1,
        "set": "corrugated-rail",
        "wheel_set": "none",
        "model": "hertz",
        "line": "0",
        "length_m": "1",
        "inputs": {"speed_kmh": "100"},
    }
    session.update(changes)
    return json.dumps({k: v for k, v in session.items() if v is not None}).encode()


def _session_error(content: bytes) -> str:
    from wheelrail.explorer.config import read_session, session_config

    with pytest.raises(WheelrailError) as info:
        session = read_session(content, ("corrugated-rail",), ("none", "sinter-wheel-1"))
        session_config(session, RAIL)
    text = str(info.value)
    assert "\n" not in text and "Error" not in text and text.startswith(("session file", "not a wheelrail")), text
    return text


@pytest.mark.parametrize(
    ("content", "fragment"),
    [
        (b"[" * 100_000 + b"]" * 100_000, "nested too deeply"),
        (b'{"wheelrail_session": 1, "x": ' + b"[" * 100_000 + b"]" * 100_000 + b"}", "nested too deeply"),
        (_session(length_m="-1"), "Run length -1 m is outside the accepted"),
        (_session(length_m="1e308"), "Run length 1e+308 m is outside the accepted"),
        (_session(length_m="nan"), "Run length"),
        (_session(length_m="0.1"), "Run length 0.1 m is outside the accepted"),
        (_session(line="99"), "Line 99 is not in corrugated-rail"),
        (_session(line="one"), "Line must be a whole number"),
        (_session(inputs={"speed_kmh": "1e308"}), "Speed"),
        (_session(inputs={"pad_stiffness_mn_m": "-5"}), "Pad stiffness"),
        (_session(colour="red"), "unknown setting(s) 'colour'"),
        (_session(length_m=None), "session file: no length_m"),
        (_session(inputs={"speed": "100"}), "unknown inputs speed"),
        (_session(model="banana"), "unknown contact model 'banana'"),
        (_session(line=0), "the settings must be text"),
        (b"\xff\xfe", "not a wheelrail session file"),
        (b"", "not a wheelrail session file"),
    ],
    ids=lambda v: v[:24].decode("utf-8", "replace") if isinstance(v, bytes) else v,
)
def test_a_session_file_is_checked_whole_before_any_field_is_set(content, fragment):
    # a value out of range is refused, not brought into range without a word (a length of -1 used to load as the
    # 0.572 m minimum, 1e308 as the set's 7.959 m); an unknown key is named; deep nesting is one line
    assert fragment in _session_error(content)


def test_a_good_session_reads_to_its_run():
    from wheelrail.explorer.config import read_session, session_config

    session = read_session(_session(length_m="1.5", line="2"), ("corrugated-rail",), ("none",))
    config = session_config(session, RAIL)
    assert config.length == 1.5 and config.line == 2 and config.model == "hertz"
