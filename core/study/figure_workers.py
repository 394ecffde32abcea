"""A study's figures drawn on two processes: the study's process and a forked copy of it
(:func:`~wheelrail.core.study.forked.forked_call`, where :func:`~wheelrail.core.study.forked.fork_refusal` allows it).

Several figures are shared out whole (the most panels first, each to the process with fewer panels so far). One
figure of two or more rows of panels is cut between two rows: its layout is worked out once, in the study's process
before the fork (the layout engine's ``execute``, then no engine: laid out on both sides at the same cost, but twice
the CPU), the child draws the panels below the cut and the study's process those above it (each with the other's
panels hidden), and the two halves of the pixel buffer are put together and written as matplotlib writes a PNG
(``matplotlib.image.imsave``).
The cut lies in the middle of the gap between the two rows' tight boxes (titles, tick and axis labels, legends
included), at least ``_MARGIN`` pixels from each, so that no pixel is drawn by both halves: the file is byte for byte
the one ``savefig`` writes. A figure of one row, or whose rows leave no such gap, is drawn whole in the study's
process.
"""

from __future__ import annotations

import io

import numpy as np

__all__ = ["png_files"]

_MARGIN = 2.0  # px, the least distance from the cut to anything drawn (a line's antialiased edge spreads one pixel)


def _png(figure, dpi: float) -> bytes:
    """The figure as ``savefig`` writes it."""
    handle = io.BytesIO()
    figure.savefig(handle, format="png", dpi=dpi)
    return handle.getvalue()


def png_files(figures: dict, dpi: float, workers: int = 1) -> dict[str, bytes]:
    """Each figure's PNG (``figure.savefig(format="png", dpi=dpi)``'s bytes) by file name, drawn on two processes
    where ``workers`` is two or more and the study's process may fork, else here one after the other."""
    from wheelrail.core.study.forked import fork_refusal, forked_call

    names = list(figures)
    if workers < 2 or not names or fork_refusal() is not None:
        return {name: _png(figures[name], dpi) for name in names}
    if len(names) >= 2:
        theirs = _shared_out(figures)
        with forked_call(lambda: {name: _png(figures[name], dpi) for name in theirs}) as result:
            mine = {name: _png(figures[name], dpi) for name in names if name not in theirs}
            drawn = {**mine, **result()}
        return {name: drawn[name] for name in names}
    figure = figures[names[0]]
    cut = _cut(figure, dpi)  # laid out once, here: the child inherits the layout
    if cut is None:
        return {names[0]: _png(figure, dpi)}
    row, above, below = cut
    with forked_call(lambda: _drawn(figure, above)[row:].copy()) as result:
        upper = _drawn(figure, below)[:row]
        return {names[0]: _encoded(np.vstack([upper, result()]), dpi)}


def _shared_out(figures: dict) -> set[str]:
    """The figures the child draws: the most panels first, each to the process with fewer panels so far."""
    load, theirs = [0, 0], set()
    for name in sorted(figures, key=lambda name: -len(figures[name].axes)):
        side = int(load[1] < load[0])
        load[side] += len(figures[name].axes)
        if side:
            theirs.add(name)
    return theirs


def _cut(figure, dpi: float):
    """Lay the figure out at ``dpi`` (once; no layout engine after it) and find the pixel row between two rows of
    panels, the middle pair: ``(row from the top, the artists above it, the axes below it)`` (the figure's own texts
    and legends, its title, above), or None (one row; no gap)."""
    if len({ax.get_position().y0 for ax in figure.axes}) < 2:
        return None  # one row (nothing laid out: savefig does it)
    figure.dpi = dpi
    engine = figure.get_layout_engine()
    if engine is not None:
        engine.execute(figure)
        figure.set_layout_engine("none")
    bottoms = sorted({round(ax.get_position().y0, 9) for ax in figure.axes}, reverse=True)
    if len(bottoms) < 2:
        return None
    lowest_above = bottoms[len(bottoms) // 2 - 1]
    above = [ax for ax in figure.axes if round(ax.get_position().y0, 9) >= lowest_above]
    below = [ax for ax in figure.axes if ax not in above]
    above += [*figure.texts, *figure.legends]
    renderer = figure.canvas.get_renderer()
    top_of_below = max(ax.get_tightbbox(renderer).y1 for ax in _beside_cut(below, top=True))
    bottom_of_above = min(
        artist.get_tightbbox(renderer).y0
        for artist in [
            *_beside_cut([ax for ax in above if ax in figure.axes], top=False),
            *figure.texts,
            *figure.legends,
        ]
        if artist.get_visible()
    )
    if bottom_of_above - top_of_below < 2 * _MARGIN + 1:
        return None
    return int(round(figure.bbox.height - (bottom_of_above + top_of_below) / 2)), above, below


def _beside_cut(axes: list, top: bool) -> list:
    """The axes of ``axes`` that reach into the band of its row nearest the cut (``top``: the highest row, below the
    cut; else the lowest, above it), by their laid-out positions: the rows further away lie in bands of their own
    (a layout engine keeps rows apart, their tick labels and titles included), so their tight boxes, the costly
    part of the cut, are not worked out."""
    positions = [ax.get_position() for ax in axes]
    if top:
        edge = max(position.y0 for position in positions)
        return [ax for ax, position in zip(axes, positions, strict=True) if position.y1 > edge]
    edge = min(position.y1 for position in positions)
    return [ax for ax, position in zip(axes, positions, strict=True) if position.y0 < edge]


def _drawn(figure, hidden) -> np.ndarray:
    """The figure's pixels (RGBA rows from the top) drawn with the artists ``hidden`` not drawn."""
    for artist in hidden:
        artist.set_visible(False)
    figure.canvas.draw()
    return np.asarray(figure.canvas.buffer_rgba())


def _encoded(pixels: np.ndarray, dpi: float) -> bytes:
    """RGBA rows as a PNG, as ``savefig`` encodes the canvas (``backend_agg``'s ``print_png``)."""
    import matplotlib.image

    handle = io.BytesIO()
    matplotlib.image.imsave(handle, pixels, format="png", origin="upper", dpi=dpi)
    return handle.getvalue()
