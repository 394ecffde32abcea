"""Rerun component columns built straight from numpy blocks, for ``send_columns``.

The archetypes' ``columns()`` helpers (``rr.Scalars.columns``, ``rr.DepthImage.columns``, ``rr.Mesh3D.columns``)
convert their input through several numpy copies and Python loops over the rows, the main cost of recording a
block of pressure images or surface meshes (``benchmarks/recording.py`` times both). Here the same arrow arrays
are made over the block's own buffers (no copy): the component descriptor and the arrow type of each column are
taken once from the archetype itself (:func:`templates`), so what is sent is what the archetype would send
(``tests/recording/test_recording.py`` compares the two arrays).

A block handed over here must not be written again afterwards: rerun keeps a reference to its buffers until the
chunk is encoded, so the sink allocates a new block for each send.
"""

from __future__ import annotations

import functools

import numpy as np

from wheelrail.core.recording.schema import rerun_module

__all__ = ["ArrowBatch", "blob_column", "colour_column", "position_column", "scalar_column", "templates"]


class ArrowBatch:
    """A prebuilt ``pyarrow.Array`` as a rerun component batch (rerun's ``ComponentBatchLike`` protocol)."""

    def __init__(self, array) -> None:
        self.array = array

    def as_arrow_array(self):
        """The array, as it is (rerun's ``ComponentBatchLike.as_arrow_array``)."""
        return self.array


@functools.cache
def templates() -> dict:
    """Per column kind, (component descriptor, arrow type of one row's values) as the archetypes make them."""
    rr = rerun_module()

    def first(columns) -> tuple:
        column = next(iter(columns))
        return column.component_descriptor(), column.as_arrow_array().type.value_type

    return {
        "scalars": first(rr.Scalars.columns(scalars=np.zeros(1))),
        "buffer": first(rr.DepthImage.columns(buffer=np.zeros((1, 4), np.uint8))),
        "positions": first(rr.Mesh3D.columns(vertex_positions=np.zeros((1, 3), np.float32))),
        "colours": first(rr.Mesh3D.columns(vertex_colors=np.zeros(1, np.uint32))),
    }


def _flat(kind, values: np.ndarray):
    """A primitive arrow array over the contiguous buffer of ``values`` (no copy)."""
    import pyarrow as pa

    return pa.Array.from_buffers(kind, values.size, [None, pa.py_buffer(values)])


def _column(descriptor, values, per_row: int, rows: int):
    """A column of ``rows`` rows of ``per_row`` values each."""
    offsets = np.arange(rows + 1, dtype=np.int32) * np.int32(per_row)
    return rerun_module().ComponentColumn(descriptor, ArrowBatch(values), offsets=offsets)


def scalar_column(values: np.ndarray):
    """``Scalars`` column: one row per step of ``values`` (steps,) or (steps, series), float64."""
    descriptor, kind = templates()["scalars"]
    values = np.ascontiguousarray(values, dtype=np.float64)
    rows = len(values)
    per_row = values.size // rows if rows else 1
    return _column(descriptor, _flat(kind, values.reshape(-1)), per_row, rows)


def blob_column(images: np.ndarray):
    """``DepthImage`` buffer column: one blob (the raw bytes of one image) per row of ``images`` (n, ...)."""
    import pyarrow as pa

    descriptor, kind = templates()["buffer"]
    images = np.ascontiguousarray(images)
    rows = len(images)
    size = images[0].nbytes if rows else 0
    inner = _flat(pa.uint8(), images.reshape(-1).view(np.uint8))
    blobs = pa.ListArray.from_arrays(pa.array(np.arange(rows + 1, dtype=np.int32) * np.int32(size)), inner, type=kind)
    return _column(descriptor, blobs, 1, rows)


def position_column(vertices: np.ndarray):
    """``Mesh3D`` vertex positions column: one mesh of vertices (n, vertices, 3) float32 per row."""
    import pyarrow as pa

    descriptor, kind = templates()["positions"]
    vertices = np.ascontiguousarray(vertices, dtype=np.float32)
    rows, per_row = vertices.shape[:2]
    points = pa.FixedSizeListArray.from_arrays(_flat(pa.float32(), vertices.reshape(-1)), type=kind)
    return _column(descriptor, points, per_row, rows)


def colour_column(colours: np.ndarray):
    """``Mesh3D`` vertex colours column: packed 0xRRGGBBAA (n, vertices) uint32, one mesh per row."""
    descriptor, kind = templates()["colours"]
    colours = np.ascontiguousarray(colours, dtype=np.uint32)
    rows, per_row = colours.shape[:2]
    return _column(descriptor, _flat(kind, colours.reshape(-1)), per_row, rows)
