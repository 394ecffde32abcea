"""The default blueprint written into a recording, checked against the recording itself: every view's origin and
contents name entities the file holds, and those carry only archetypes that view type draws.

The rule it checks is the viewer's (rerun 0.41): a 2D-kind visualizer (images, LineStrips2D) in a 3D view needs
a pinhole parent and a 3D-kind one (Mesh3D, LineStrips3D) in a 2D view a pinhole at its root, else the view shows
an error badge on the entity (re_view_spatial's ``process_archetype``); a time series view draws ``Scalars``
(styled by ``SeriesLines``), a bar chart view one ``BarChart``, a text document view one ``TextDocument``.
"""

from __future__ import annotations

from collections import defaultdict

import numpy as np
import pytest
from rerun.chunk import RrdReader
from test_recording import synthetic_result

from wheelrail.core.recording import record_result
from wheelrail.core.roughness import load_roughness

DRAWN = {  # view class -> archetypes it draws (data) and the ones that only style them
    "2D": {"DepthImage", "Image", "EncodedImage", "SegmentationImage", "LineStrips2D", "Points2D", "Boxes2D"},
    "3D": {"Mesh3D", "LineStrips3D", "Points3D", "Boxes3D", "Ellipsoids3D", "Arrows3D"},
    "TimeSeries": {"Scalars"},
    "BarChart": {"BarChart"},
    "TextDocument": {"TextDocument"},
}
STYLE = {"TimeSeries": {"SeriesLines", "SeriesPoints"}}
# recorded only when the sink is given the roughness set (the command line always gives it); a query that matches
# nothing draws nothing and shows no badge, so its absence is no problem as long as the view shows something
OPTIONAL = {"roughness/lines"}


def _archetypes(path) -> dict[str, set[str]]:
    """Entity path (no leading '/') -> the archetypes logged there."""
    found: dict[str, set[str]] = defaultdict(set)
    for chunk in RrdReader(path).stream():
        names = chunk.to_record_batch().schema.names
        found[chunk.entity_path.lstrip("/")] |= {name.split(":")[0] for name in names if ":" in name}
    return found


def _views(path) -> list[dict]:
    """The views of the file's blueprint: class, origin and content queries."""
    reader = RrdReader(path)
    (blueprint,) = reader.blueprints()
    views: dict[str, dict] = defaultdict(dict)
    for chunk in reader.stream(store=blueprint):
        batch = chunk.to_record_batch()
        entity = chunk.entity_path
        if "ViewBlueprint:class_identifier" in batch.schema.names:
            views[entity]["class"] = batch.column("ViewBlueprint:class_identifier").to_pylist()[-1][0]
            views[entity]["origin"] = batch.column("ViewBlueprint:space_origin").to_pylist()[-1][0].strip("/")
            views[entity]["name"] = batch.column("ViewBlueprint:display_name").to_pylist()[-1][0]
        if "ViewContents:query" in batch.schema.names:
            views[entity.rsplit("/", 1)[0]]["queries"] = batch.column("ViewContents:query").to_pylist()[-1]
    return list(views.values())


def _matches(query: str, origin: str, entities) -> list[str]:
    pattern = query.replace("$origin", origin).strip("/")
    if pattern.endswith("/**") or pattern == "**":
        base = pattern[:-3].rstrip("/") if pattern != "**" else ""
        return [e for e in entities if not base or e == base or e.startswith(base + "/")]
    return [e for e in entities if e == pattern]


def check_blueprint(path) -> list[str]:
    """Every problem the viewer would show for the file's blueprint (empty: none)."""
    archetypes = _archetypes(path)
    problems = []
    for view in _views(path):
        kind, drawn, name = view["class"], DRAWN[view["class"]], view["name"]
        shown = []
        for query in view.get("queries", ["$origin/**"]):
            matched = _matches(query, view["origin"], archetypes)
            if not matched and query.strip("/") not in OPTIONAL:
                problems.append(f"{name}: {query} names no entity of the recording")
            for entity in matched:
                wrong = archetypes[entity] - drawn - STYLE.get(kind, set())
                if wrong:
                    problems.append(f"{name}: {entity} carries {sorted(wrong)}, which a {kind} view cannot draw")
                shown += [entity] if archetypes[entity] & drawn else []
        if not shown:
            problems.append(f"{name}: shows nothing")
    return problems


def _bars(path, entity: str) -> tuple[np.ndarray, np.ndarray]:
    for chunk in RrdReader(path).stream():
        if chunk.entity_path == "/" + entity:
            batch = chunk.to_record_batch()
            abscissa = np.array(batch.column("BarChart:abscissa")[0].as_py()[0]["buffer"]).view(np.float64)
            widths = np.asarray(batch.column("BarChart:widths")[0].as_py(), dtype=float)
            return abscissa, widths
    raise AssertionError(f"no {entity}")


@pytest.mark.parametrize("model", ["3d", "hertz"])
def test_every_view_of_the_blueprint_shows_what_the_recording_holds(tmp_path, model):
    path = record_result(synthetic_result(model=model), tmp_path / "r.rrd", roughness=load_roughness("corrugated-rail"))
    assert check_blueprint(path) == []
    classes = sorted(view["class"] for view in _views(path))
    spatial = ["2D", "3D"] if model == "3d" else []  # a run without pressure maps has no pressure views
    assert classes == sorted(["BarChart", "TextDocument", *spatial, *["TimeSeries"] * 5])
    # the bars are drawn side by side over the bands, not as slivers on a frequency axis (width 1 by default)
    abscissa, widths = _bars(path, "spectra/force")
    assert len(abscissa) == 23 and np.all(np.diff(abscissa) > 0)
    assert widths.sum() >= 0.8 * (abscissa[-1] - abscissa[0])


def test_the_check_sees_a_circle_in_both_kinds(tmp_path):
    """The check fails a file whose one entity holds LineStrips2D and LineStrips3D under both spatial views (the
    earlier layout of the Hertz circle): the check can fail."""
    import rerun as rr
    import rerun.blueprint as rrb

    path = tmp_path / "mixed.rrd"
    stream = rr.RecordingStream("check", recording_id="mixed")
    blueprint = rrb.Blueprint(rrb.Spatial2DView(origin="c", contents=["$origin/**"], name="Mixed"))
    stream.save(str(path), default_blueprint=blueprint)
    stream.log("c/circle", rr.LineStrips2D([[(0, 0), (1, 1)]]), static=True)
    stream.log("c/circle", rr.LineStrips3D([[(0, 0, 0), (1, 1, 0)]]), static=True)
    stream.flush()
    stream.disconnect()
    assert check_blueprint(path) == ["Mixed: c/circle carries ['LineStrips3D'], which a 2D view cannot draw"]
